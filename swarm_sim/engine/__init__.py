"""The world and how robots move in it: grid, navigation cost fields, motion, the tick and its random streams.
May import the swarm_sim core (errors, state, params, faults) only.
"""
