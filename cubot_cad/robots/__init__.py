"""The robots (CuBot, OctBot, Cube Robot, the test platform) built from parts and couplings, and the registry by name.
May import the core, hardware and couplings.
"""
