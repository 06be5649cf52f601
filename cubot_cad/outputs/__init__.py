"""What the CAD writes: the export (STL/STEP/3MF/GLB, manifest, robot_properties.json), renders, exploded views, the BOM.
May import every other cubot_cad sub-package; nothing in cubot_cad imports it.
"""
