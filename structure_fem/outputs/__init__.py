"""What structure_fem writes: the table and limits.json, plots, the run cache, the docs' generated blocks.
May import every other structure_fem sub-package; nothing in structure_fem imports it.
"""
