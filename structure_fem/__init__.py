"""structure_fem: exudyn multibody model of docked-robot structures (SI units)
that derives the structure-switch thresholds and the `StructureLimits` record.

Importing this package does not import exudyn; the model modules do.
"""

from .errors import InputError, SolverFailure
from .limits import StructureLevel, StructureLimits, load_limits, thesis_limits

__all__ = ["InputError", "SolverFailure", "StructureLevel", "StructureLimits", "load_limits", "thesis_limits"]
