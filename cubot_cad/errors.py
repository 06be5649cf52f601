"""Error types shared along the dependency chain cubot_cad -> structure_fem -> swarm_sim.

`InputError` is the one exception that means "the user gave a bad value": the
`voidcross` CLI turns it into a single ``error: ...`` line and exit code 2.
Downstream packages subclass it so the chain of imports follows the data flow.
"""

from __future__ import annotations


class InputError(ValueError):
    """A bad user-supplied value (parameter, file, range). Message names the value."""


def require(condition: bool, message: str) -> None:
    """Raise :class:`InputError` with ``message`` unless ``condition`` holds."""
    if not condition:
        raise InputError(message)
