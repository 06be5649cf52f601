"""swarm_sim: vectorised 2D swarm simulator of the bridge-launching algorithms.

Needs only numpy/scipy/matplotlib (numba optional); never imports cadquery or exudyn.
Units are in parameter names: centimetres (``_cm``), seconds (``_s``), radians (``_rad``).

Entry point: :func:`swarm_sim.runner.run_scenario` (also re-exported here).
"""

from .errors import InputError, InvariantViolation


def run_scenario(*args, **kwargs):
    """See :func:`swarm_sim.runner.run_scenario`."""
    from .runner import run_scenario as _run

    return _run(*args, **kwargs)


__all__ = ["InputError", "InvariantViolation", "run_scenario"]
