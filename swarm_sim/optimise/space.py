"""The search space: a chosen subset of the behaviour's tunables (:mod:`swarm_sim.tunables`),
mapped to the unit cube the optimiser works in.

A tunable whose range spans a decade or more (``hi / lo >= 10``, ``lo > 0``: waits, distances)
is searched on a log scale, the others linearly; whole-number tunables are rounded. Values
handed to the simulator are rounded to 6 significant digits so the same point always gives the
same run keys (the store's ``param_hash``), which is what makes a study resumable.
Tunables of kind ``robot`` (speed, sensor ranges, climbing time) are refused: a faster robot
is bought, not tuned, and a study that "wins" by driving faster has learnt nothing about rules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..params import Params
from ..tunables import BY_NAME, Tunable

#: the default subset (7 tunables): the search pattern, the turn-away distance, the release
#: wait and both watchdogs (what the thesis set once by hand and a rule can change)
DEFAULT_PARAMS = ("levy_mu", "levy_min_cm", "levy_max_cm", "avoid_cm", "release_clear_s",
                  "recruit_stall_s", "stall_s")


@dataclass(frozen=True)
class SearchSpace:
    names: tuple[str, ...] = DEFAULT_PARAMS

    def __post_init__(self):
        names = tuple(self.names)
        object.__setattr__(self, "names", names)
        if not names:
            raise InputError("--params is empty: name at least one tunable (`voidcross sim params` lists them)")
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise InputError(f"--params: {', '.join(dup)} given twice")
        for n in names:
            t = BY_NAME.get(n)
            if t is None:
                raise InputError(f"--params: {n!r} is not a tunable (`voidcross sim params` lists them)")
            if t.kind == "robot":
                raise InputError(f"--params: {n!r} is the robot's body or sensors (kind robot), not a rule: "
                                 "it is not tuned")

    @property
    def tunables(self) -> tuple[Tunable, ...]:
        return tuple(BY_NAME[n] for n in self.names)

    @property
    def dim(self) -> int:
        return len(self.names)

    @staticmethod
    def log_scale(t: Tunable) -> bool:
        return t.lo > 0 and t.hi / t.lo >= 10

    def _u(self, t: Tunable, v: float) -> float:
        if self.log_scale(t):
            return (math.log(v) - math.log(t.lo)) / (math.log(t.hi) - math.log(t.lo))
        return (v - t.lo) / (t.hi - t.lo)

    def _v(self, t: Tunable, u: float) -> float | int:
        u = min(1.0, max(0.0, float(u)))
        if self.log_scale(t):
            v = math.exp(math.log(t.lo) + u * (math.log(t.hi) - math.log(t.lo)))
        else:
            v = t.lo + u * (t.hi - t.lo)
        if t.integer:
            return int(round(v))
        return min(t.hi, max(t.lo, float(f"{v:.6g}")))

    def start(self, params: Params | None = None) -> np.ndarray:
        """The unit-cube point of ``params``' values (default: the simulator's defaults, the
        thesis's values where it gives one)."""
        p = params or Params()
        return np.array([self._u(t, getattr(p, t.name)) for t in self.tunables], dtype=float)

    def values(self, x) -> dict[str, float | int]:
        """``{name: value in its unit}`` for a unit-cube point ``x`` (clipped to the cube)."""
        x = np.asarray(x, dtype=float)
        if x.shape != (self.dim,):
            raise ValueError(f"point of shape {x.shape}, expected ({self.dim},)")
        return {t.name: self._v(t, u) for t, u in zip(self.tunables, x, strict=True)}
