"""The behaviour's tunables in one typed table (issue 39, deliverable 1): name, range, unit and
what each changes, for the fields of :class:`swarm_sim.params.Params` that set how the robots
behave (not the arena, the robot's body or the limits record). Both engines read these fields
from the same ``Params``; the defaults are the ``Params`` defaults (this module
imports nothing of the simulator: params imports it) (the thesis's values where it
gives one, else ours, say so in ``source``). ``--set NAME=VALUE`` and a preset's TOML outside a
range are one :class:`~swarm_sim.errors.InputError` naming the value and the range
(:func:`check`, called by :func:`swarm_sim.params.with_overrides`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import InputError

#: what a tunable is: ``robot`` (the body and its sensors: a faster robot is bought, not tuned;
#: ``voidcross optimise`` refuses these), ``search`` (how free robots explore), ``timing`` (waits
#: of the structure's behaviour), ``watchdog`` (when the swarm gives up on a stalled step)
KINDS = ("robot", "search", "timing", "watchdog")
_KIND = {"speed_cm_s": "robot", "void_detect_cm": "robot", "target_found_cm": "robot",
         "climb_s_per_layer": "robot", "avoid_cm": "search", "levy_mu": "search", "levy_min_cm": "search",
         "levy_max_cm": "search", "random_turn_prob": "search", "random_turn_rad": "search",
         "wander_after_retreat_s": "timing", "release_clear_s": "timing", "recruit_stall_s": "watchdog",
         "stall_s": "watchdog", "heartbeat_s": "watchdog", "heartbeat_misses": "watchdog"}


@dataclass(frozen=True)
class Tunable:
    name: str
    lo: float
    hi: float
    unit: str
    changes: str
    source: str

    @property
    def kind(self) -> str:
        """One of :data:`KINDS` (every tunable has one: a test checks)."""
        return _KIND[self.name]

    @property
    def integer(self) -> bool:
        """Whole numbers only (``heartbeat_misses``): both bounds are ints."""
        return isinstance(self.lo, int) and isinstance(self.hi, int)


TUNABLES: tuple[Tunable, ...] = (
    Tunable("speed_cm_s", 1.0, 50.0, "cm/s", "how fast every robot drives (free, recruited, in the structure)",
            "thesis Ch. 3.3/4.4 set-up (../shared/SPEC.md, Simulation setup): vmax 13.89 cm/s"),
    Tunable("void_detect_cm", 1.0, 20.0, "cm", "how far ahead a robot senses the void's edge",
            "thesis Ch. 3.3/4.4 set-up (../shared/SPEC.md, Simulation setup): 5 cm (6 cm for cases A/B)"),
    Tunable("avoid_cm", 2.0, 50.0, "cm", "distance at which a walker turns away from a robot, wall or obstacle",
            "thesis Ch. 3.3/4.4 set-up (../shared/SPEC.md, Simulation setup): 15 cm"),
    Tunable("target_found_cm", 1.0, 30.0, "cm", "distance at which a robot recognises the target",
            "thesis Ch. 3.3/4.4 set-up (../shared/SPEC.md, Simulation setup): 5 cm (15 cm in the large arena)"),
    Tunable("levy_mu", 1.1, 3.0, "-", "Levy walk exponent: smaller makes longer straight legs (search pattern)",
            "ours: the thesis names a Levy walk, not its exponent"),
    Tunable("levy_min_cm", 1.0, 50.0, "cm", "shortest leg of the Levy walk", "ours"),
    Tunable("levy_max_cm", 50.0, 1000.0, "cm", "longest leg of the Levy walk", "ours (1000 cm in the large arenas' presets)"),
    Tunable("random_turn_prob", 0.0, 1.0, "1/step", "chance per step that a random walker turns",
            "ours (random walk only)"),
    Tunable("random_turn_rad", 0.01, math.pi, "rad", "largest turn of a random walker", "ours (random walk only)"),
    Tunable("wander_after_retreat_s", 0.0, 60.0, "s", "how long robots wander after a failed crossing before they stop",
            "thesis Ch. 3.3/4.4 set-up (../shared/SPEC.md, Simulation setup): 5 s"),
    Tunable("release_clear_s", 0.1, 10.0, "s", "how long a released front robot drives clear before it is free",
            "ours (the thesis does not time it)"),
    Tunable("recruit_stall_s", 0.1, 200.0, "s", "a recruit making no progress this long is released and the next "
            "closest free robot called", "ours (watchdog)"),
    Tunable("stall_s", 10.0, 1000.0, "s", "a building structure with no progress this long retreats (watchdog)",
            "ours (watchdog)"),
    Tunable("climb_s_per_layer", 0.0, 30.0, "s", "time a robot takes to climb one layer onto a tapering foot",
            "ours (the thesis does not say)"),
    Tunable("heartbeat_s", 0.1, 10.0, "s", "heartbeat period of structure members and the seed (fault detection)",
            "ours (the thesis's robots broadcast; no rate)"),
    Tunable("heartbeat_misses", 1, 100, "beats", "missed heartbeats before a robot is known to have failed",
            "ours"),
)
BY_NAME = {t.name: t for t in TUNABLES}


def check(name: str, value, source: str = "--set") -> None:
    """One error line when ``value`` is outside ``name``'s range (other names: nothing to check)."""
    t = BY_NAME.get(name)
    if t is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        return
    if not (math.isfinite(value) and t.lo <= value <= t.hi):
        raise InputError(f"{source}: {name}={value!r} is outside its range {t.lo:g}..{t.hi:g} {t.unit} "
                         f"({t.changes}; `voidcross sim params` lists every tunable)")


def table(params) -> list[dict]:
    """The table as rows with the values of ``params`` (a :class:`~swarm_sim.params.Params`; its
    defaults for ``Params()``), for ``voidcross sim params --json`` and the docs."""
    return [{"name": t.name, "kind": t.kind, "default": getattr(params, t.name), "lo": t.lo, "hi": t.hi,
             "unit": t.unit, "changes": t.changes, "source": t.source} for t in TUNABLES]
