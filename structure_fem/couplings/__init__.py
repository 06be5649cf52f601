"""Finite-element models of the couplings (scikit-fem/gmsh solids) and where each connector's stiffness comes from.
May import the structure_fem core (errors, limits, solve_cache) and cubot_cad records.
"""
