"""Bought hardware as data tables and stand-in solids: fasteners (ISO sizes), servos, gears, components.
May import the cubot_cad core modules (part, shapes, errors, ...) only.
"""
