"""Experiments on the simulator: the engine benchmark and the long soak runs.
May import every swarm_sim module; nothing below it imports it.
"""
