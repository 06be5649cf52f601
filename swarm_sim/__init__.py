"""swarm_sim: vectorised 2D swarm simulator of the bridge-launching algorithms.

Needs only numpy/scipy/matplotlib; never imports cadquery or exudyn.
Units are in parameter names: centimetres (``_cm``), seconds (``_s``).
"""

from .errors import InputError, InvariantViolation

__all__ = ["InputError", "InvariantViolation"]
