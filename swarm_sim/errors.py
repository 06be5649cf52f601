"""swarm_sim errors: bad scenario input (exit 2) and invariant violations.

``InputError`` is the one class of the whole chain (:class:`cubot_cad.errors.InputError`),
re-exported here; ``cubot_cad.errors`` imports nothing heavy (swarm_sim runs without cadquery)."""

from __future__ import annotations

from cubot_cad.errors import InputError


class InvariantViolation(AssertionError):
    """A simulation invariant broke (robot over the void unsupported, robot lost, count changed)."""


__all__ = ["InputError", "InvariantViolation"]
