"""swarm_sim errors: bad scenario input (exit 2) and invariant violations."""

from __future__ import annotations

from structure_fem.errors import InputError as _BaseInputError


class InputError(_BaseInputError):
    """Bad preset, swarm size, void width, arena or TOML value."""


class InvariantViolation(AssertionError):
    """A simulation invariant broke (robot over the void unsupported, robot lost, count changed)."""
