"""structure_fem errors: bad input (exit 2) and solver failures that name the configuration.

``InputError`` is the one class of the whole chain (:class:`cubot_cad.errors.InputError`),
re-exported here so ``structure_fem`` code and users import it from their own package."""

from __future__ import annotations

from cubot_cad.errors import InputError


class SolverFailure(RuntimeError):
    """The static solver did not converge; the message names the configuration."""


__all__ = ["InputError", "SolverFailure"]
