"""Robots that fail mid-task: the fault model (the thesis's future work, Ch. 7.2 item 4).

A fault is ``(robot, t_s, mode)``: from simulated time ``t_s`` on, robot ``robot`` has
failed in ``mode``:

* ``drive``: cannot move on its own; it still docks passively and can be pushed or carried;
* ``sensor``: cannot see the edge or the target (its ground and target sensors are dead);
* ``total``: no motion and no communication at all.

Faults come from a :class:`FaultSpec`: per-mode *rates* (failures per robot per hour of
simulated time, a Poisson process per robot and mode, so the first failure of a robot in a
mode is exponential with that rate) and/or an explicit *schedule* of faults. The spec is
given on the command line as ``--faults drive:0.5/h,sensor:0.2/h`` (rates per hour ``/h``,
per minute ``/min`` or per second ``/s``) and/or ``--faults 3@120:drive,7@300.5:total``
(robot @ time in s : mode), or in a preset's ``[faults]`` table (``drive_per_h = 0.5``,
``schedule = [[3, 120.0, "drive"], ...]``).

:func:`draw_schedule` turns a spec into the run's :class:`FaultSchedule` (a struct of
arrays sorted by time, then robot). The draw uses its own random stream, derived from the
run's seed and :data:`FAULT_STREAM`, so switching faults on never changes the fault-free
part of a run and a fault-free spec draws nothing: the same seed gives the same run with or
without this module.

Faults never heal and they accumulate: a robot's disabled functions are the union of the
effects (:data:`EFFECT`) of its faults so far (``drive`` then ``sensor`` is both; ``total``
is everything). :meth:`FaultSchedule.state_at` gives each robot's flags at a time.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError

#: the failure modes, in the order of their bit in the per-robot fault flags
MODES = ("drive", "sensor", "total")
DRIVE, SENSOR, TOTAL = 1, 2, 4
BIT = {"drive": DRIVE, "sensor": SENSOR, "total": TOTAL}
#: what each mode disables (a total failure is everything)
EFFECT = {DRIVE: DRIVE, SENSOR: SENSOR, TOTAL: DRIVE | SENSOR | TOTAL}
#: the fault draw's own random stream: ``default_rng([seed, FAULT_STREAM])``
FAULT_STREAM = 0xFA17
#: rates above this (per robot per hour) are not a fault model but a broken swarm
MAX_RATE_PER_H = 3600.0
_PER_H = {"h": 1.0, "min": 60.0, "s": 3600.0}
_RATE = re.compile(r"^(?P<mode>[a-z]+):(?P<rate>[^/]+)/(?P<unit>h|min|s)$")
_EVENT = re.compile(r"^(?P<robot>[^@]+)@(?P<t>[^:]+):(?P<mode>[a-z]+)$")


@dataclass(frozen=True)
class Fault:
    robot: int
    t_s: float
    mode: str


@dataclass(frozen=True)
class FaultSpec:
    """Rates (failures per robot per hour, per mode) and explicit faults."""

    rates_per_h: dict = field(default_factory=dict)
    schedule: tuple[Fault, ...] = ()

    def __post_init__(self) -> None:
        for mode, rate in self.rates_per_h.items():
            _mode(mode, "rate")
            if not (isinstance(rate, (int, float)) and math.isfinite(rate) and 0 <= rate <= MAX_RATE_PER_H):
                raise InputError(f"fault rate {mode}:{rate!r}/h must be a number in 0..{MAX_RATE_PER_H:g} per hour")
        for f in self.schedule:
            _mode(f.mode, "scheduled fault")
            if not (isinstance(f.robot, int) and f.robot >= 0):
                raise InputError(f"scheduled fault robot {f.robot!r} must be an integer >= 0")
            if not (isinstance(f.t_s, (int, float)) and math.isfinite(f.t_s) and f.t_s >= 0):
                raise InputError(f"scheduled fault time {f.t_s!r} s must be a finite number >= 0")

    @property
    def empty(self) -> bool:
        return not self.schedule and not any(r > 0 for r in self.rates_per_h.values())

    def describe(self) -> str:
        parts = [f"{m}:{r:.15g}/h" for m, r in self.rates_per_h.items() if r > 0]
        parts += [f"{f.robot}@{f.t_s:.15g}:{f.mode}" for f in self.schedule]
        return ",".join(parts) or "none"

    def check_robots(self, robots: int) -> None:
        """Every scheduled robot exists in a swarm of ``robots``."""
        bad = [f for f in self.schedule if f.robot >= robots]
        if bad:
            raise InputError(f"scheduled fault {bad[0].robot}@{bad[0].t_s:g}:{bad[0].mode}: there is no robot "
                             f"{bad[0].robot} in a swarm of {robots} (robots are numbered 0..{robots - 1})")


def _mode(mode: str, what: str) -> str:
    if mode not in MODES:
        raise InputError(f"{what} mode {mode!r} is not one of {', '.join(MODES)}")
    return mode


def _number(text: str, what: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"{what} {text!r} is not a number") from None
    if not math.isfinite(v):
        raise InputError(f"{what} {text!r} is not a finite number")
    return v


def parse_faults(text: str) -> FaultSpec:
    """``drive:0.5/h,sensor:0.2/h`` and/or ``3@120:drive,7@300.5:total`` -> :class:`FaultSpec`
    (``none`` or an empty string: no faults). Each bad item raises one :class:`InputError`
    naming it."""
    text = (text or "").strip()
    if text in ("", "none"):
        return FaultSpec()
    rates: dict = {}
    sched: list[Fault] = []
    for item in (s.strip() for s in text.split(",")):
        if not item:
            raise InputError(f"--faults {text!r}: an empty item (two commas or a trailing comma)")
        m = _RATE.match(item)
        if m:
            mode = _mode(m["mode"], f"--faults item {item!r}:")
            if mode in rates:
                raise InputError(f"--faults {text!r}: the rate of {mode!r} is given twice")
            rates[mode] = _number(m["rate"], f"--faults item {item!r}: rate") * _PER_H[m["unit"]]
            continue
        m = _EVENT.match(item)
        if m:
            r = _number(m["robot"], f"--faults item {item!r}: robot")
            if r != int(r):
                raise InputError(f"--faults item {item!r}: robot {m['robot']!r} is not an integer")
            sched.append(Fault(int(r), _number(m["t"], f"--faults item {item!r}: time"),
                               _mode(m["mode"], f"--faults item {item!r}:")))
            continue
        raise InputError(f"--faults item {item!r} is neither MODE:RATE/h (e.g. drive:0.5/h) nor ROBOT@T:MODE "
                         f"(e.g. 3@120:drive); modes: {', '.join(MODES)}")
    return FaultSpec(rates, tuple(sched))


def from_table(table: dict, where: str = "[faults]") -> FaultSpec:
    """A preset's ``[faults]`` table: ``<mode>_per_h = rate`` and ``schedule = [[robot, t_s, mode], ...]``."""
    rates: dict = {}
    sched: list[Fault] = []
    for key, v in table.items():
        if key == "schedule":
            if not isinstance(v, list):
                raise InputError(f"{where}.schedule must be a list of [robot, t_s, mode], got {v!r}")
            for e in v:
                if not (isinstance(e, list) and len(e) == 3 and isinstance(e[0], int) and not isinstance(e[0], bool)
                        and isinstance(e[1], (int, float)) and isinstance(e[2], str)):
                    raise InputError(f"{where}.schedule entry {e!r} must be [robot, t_s, mode]")
                sched.append(Fault(e[0], float(e[1]), e[2]))
        elif key.endswith("_per_h"):
            mode = _mode(key[:-len("_per_h")], f"{where}.{key}:")
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise InputError(f"{where}.{key} must be a number (failures per robot per hour), got {v!r}")
            rates[mode] = float(v)
        else:
            raise InputError(f"{where}: unknown key {key!r} (use <mode>_per_h or schedule; modes: {', '.join(MODES)})")
    return FaultSpec(rates, tuple(sched))


@dataclass(frozen=True, eq=False)
class FaultSchedule:
    """The faults of one run, sorted by time then robot: a struct of arrays."""

    robot: np.ndarray   # int64
    t_s: np.ndarray     # float64, simulated seconds
    bits: np.ndarray    # int8, DRIVE / SENSOR / TOTAL

    def __len__(self) -> int:
        return int(self.robot.size)

    def state_at(self, t_s: float, robots: int) -> np.ndarray:
        """Each robot's disabled functions at time ``t_s`` (int8 flags: the OR of the
        :data:`EFFECT` of every fault with time <= ``t_s``)."""
        flags = np.zeros(robots, dtype=np.int8)
        k = int(np.searchsorted(self.t_s, t_s, side="right"))
        for r, b in zip(self.robot[:k], self.bits[:k], strict=True):
            flags[r] |= EFFECT[int(b)]
        return flags

    def events(self) -> list[tuple]:
        """``(t_s, "fault", robot, {"mode": ...})`` per fault, the event log's form."""
        names = {v: k for k, v in BIT.items()}
        return [(round(float(t), 6), "fault", int(r), {"mode": names[int(b)]})
                for r, t, b in zip(self.robot, self.t_s, self.bits, strict=True)]


def draw_schedule(spec: FaultSpec, robots: int, max_time_s: float, seed: int) -> FaultSchedule:
    """The run's faults: the spec's schedule plus, per robot and mode with a rate, the first
    failure of a Poisson process of that rate if it falls before ``max_time_s``. Drawn from
    the stream ``default_rng([seed, FAULT_STREAM])`` only when some rate is > 0."""
    if robots < 1:
        raise InputError(f"robots must be >= 1, got {robots}")
    spec.check_robots(robots)
    rs, ts, bs = [], [], []
    for f in spec.schedule:
        if f.t_s <= max_time_s:
            rs.append(f.robot)
            ts.append(f.t_s)
            bs.append(BIT[f.mode])
    active = [(m, spec.rates_per_h[m]) for m in MODES if spec.rates_per_h.get(m, 0) > 0]
    if active:
        rng = np.random.default_rng([int(seed) & 0xFFFFFFFFFFFFFFFF, FAULT_STREAM])
        for mode, rate in active:  # one exponential per robot per mode, in mode then robot order
            t = rng.exponential(3600.0 / rate, robots)
            hit = np.flatnonzero(t <= max_time_s)
            rs += hit.tolist()
            ts += t[hit].tolist()
            bs += [BIT[mode]] * hit.size
    robot = np.array(rs, dtype=np.int64)
    t_s = np.array(ts, dtype=float)
    bits = np.array(bs, dtype=np.int8)
    order = np.lexsort((robot, t_s))
    return FaultSchedule(robot[order], t_s[order], bits[order])


def expected_failed_fraction(spec: FaultSpec, duration_s: float) -> float:
    """The fraction of a swarm that fails (in any mode) within ``duration_s`` of simulated
    time under the spec's rates: ``1 - exp(-sum(rates) * duration)``."""
    lam = sum(spec.rates_per_h.values()) / 3600.0
    return 1.0 - math.exp(-lam * max(duration_s, 0.0))


def rate_for_fraction(fraction: float, duration_s: float) -> float:
    """The rate (per robot per hour) at which ``fraction`` of a swarm fails within
    ``duration_s``: the inverse of :func:`expected_failed_fraction` for one mode."""
    if not (0 <= fraction < 1):
        raise InputError(f"failed fraction {fraction!r} must be in [0, 1)")
    if not (duration_s > 0 and math.isfinite(duration_s)):
        raise InputError(f"duration {duration_s!r} s must be > 0")
    return -math.log1p(-fraction) / duration_s * 3600.0


# ---------------------------------------------------------------------------- in the step

_MODE_OF_BITS = {v: k for k, v in BIT.items()}


def fail(tk) -> None:
    """The step's first phase: every fault due by the end of this step happens (the physics:
    ``tk.fault`` gains the mode's :data:`EFFECT`; no robot reads another's flags, see
    :mod:`swarm_sim.behaviour.detection`). Each new fault is one ``fault`` event naming the mode and
    what the robot was doing."""
    sch = tk.fault_schedule
    if sch is None:
        return
    k = tk.fault_next
    n = len(sch)
    while k < n and sch.t_s[k] <= tk.t + 1e-9:
        r, b = int(sch.robot[k]), int(sch.bits[k])
        k += 1
        new = tk.fault[r] | EFFECT[b]
        if new == tk.fault[r]:
            continue  # already lost everything this mode takes
        first = tk.fault[r] == 0
        tk.fault[r] = new
        if first:
            tk.fault_t[r] = tk.t
        from .state import Mode

        tk.ev("fault", r, mode=_MODE_OF_BITS[b], doing=Mode(int(tk.mode[r])).name.lower())
    tk.fault_next = k


def init_arrays(schedule: FaultSchedule | None, robots: int):
    """The fault fields of a run's first state: (schedule, flags, first-fault times, known) or
    all None when the run has no fault."""
    if schedule is None or len(schedule) == 0:
        return None, None, None, None
    return (schedule, np.zeros(robots, dtype=np.int8), np.full(robots, math.inf),
            np.zeros(robots, dtype=bool))


__all__ = ["BIT", "DRIVE", "EFFECT", "FAULT_STREAM", "MODES", "SENSOR", "TOTAL", "Fault", "FaultSchedule",
           "FaultSpec", "draw_schedule", "expected_failed_fraction", "fail", "from_table", "init_arrays", "parse_faults",
           "rate_for_fraction"]
