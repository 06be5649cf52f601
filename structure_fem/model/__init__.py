"""The exudyn multibody model: joints, structures, ground contacts, flexible bodies, statics and launch transients.
May import the core and structure_fem.couplings.
"""
