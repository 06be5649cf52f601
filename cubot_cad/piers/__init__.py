"""Piers: robots stacked top-down in a void and the printed deck the line rolls over.
May import everything below outputs (core, hardware, couplings, robots, checks).
"""
