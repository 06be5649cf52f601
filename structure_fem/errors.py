"""structure_fem errors: bad input (exit 2) and solver failures that name the configuration."""

from __future__ import annotations

from cubot_cad.errors import InputError as _BaseInputError


class InputError(_BaseInputError):
    """Bad structure description, properties or limits value."""


class SolverFailure(RuntimeError):
    """The static solver did not converge; the message names the configuration."""
