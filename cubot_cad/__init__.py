"""cubot_cad: parametric CadQuery models of CuBot, OctBot, Cube Robot, the test
platform and their connectors (millimetres), printable exports and the
`RobotProperties` record (SI) that `structure_fem` reads.

Importing this package does not import cadquery; the CAD modules do.
"""

from .errors import InputError
from .properties import (
    ConnectorProperties,
    RobotProperties,
    RobotPropertiesFile,
    default_properties,
    load_properties,
)

__all__ = [
    "ConnectorProperties",
    "InputError",
    "RobotProperties",
    "RobotPropertiesFile",
    "default_properties",
    "load_properties",
]
