"""Checks made by moving the parts: docking, capture range, printability (slicing, walls), the body section.
May import the core, hardware, couplings and robots.
"""
