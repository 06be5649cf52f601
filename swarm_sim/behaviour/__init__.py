"""The bridge algorithms as named phases: explore, recruit, release, retreat, detection, the counting rule.
May import the core and swarm_sim.engine.
"""
