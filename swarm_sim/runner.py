"""Run one scenario: ``run_scenario(preset, robots, void_width, seed, ...) -> RunResult``.

This is the contract the Monte-Carlo sweeps (``swarm_sim.sweeps``) call from worker
processes: a module-level function of plain arguments, returning a record whose
``to_dict()`` is JSON-able. Same arguments, same result (seeded ``numpy`` Generator).
"""

from __future__ import annotations

import math
import re
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from swarm_sim.behaviour.retreat import end_reason
from swarm_sim.engine.world import World
from swarm_sim.params import Params, load_preset, with_overrides
from swarm_sim.resolve import with_limits

from .errors import InputError, InvariantViolation
from .invariants import lost_robots, violations
from .state import Mode, Phase, SwarmState, new_state
from .step import ENDED, step

_OVER = re.compile(r"robot (\d+) .*over the void")


@dataclass
class RunResult:
    preset: str
    robots: int
    void_width: int
    seed: int
    limits_source: str
    success: bool
    retreated: bool
    timed_out: bool
    robots_lost: int
    times: dict
    seed_robot: int | None
    seed_position: list | None
    target_finder: int | None
    min_robots_rule: int
    robots_delivered: int
    robots_on_initial_side: int
    steps: int
    wall_s: float
    violations: list = field(default_factory=list)
    events: list = field(default_factory=list)
    #: structure levels the run built, first to last (switches during the build, Ch. 5.5.2)
    levels_used: list = field(default_factory=list)
    #: one entry per switch: {"t_s", "level", "lines", "layers", "n_g", "rows"}
    switches: list = field(default_factory=list)
    #: the seed's aligned position along the edge (y, cm; Fig. 5.10)
    seed_edge_cm: float | None = None
    #: Fig. 5.13: {"assembly": s, "disassembly": s} (see :func:`construction_times`)
    construction: dict = field(default_factory=dict)
    #: the limits record's own robot count for this void (thesis: the complete arch)
    record_min_robots: int = 0
    #: how the run ended: crossed | retreated-no-robots | retreated-span | retreated-stalled |
    #: retreated-blocked | retreated-no-room | timeout (swarm_sim.behaviour.retreat.end_reason)
    end_reason: str | None = None
    #: recruits released because they made no progress, and the robot called instead (-1: none)
    hand_overs: int = 0
    #: faults (swarm_sim.faults): the spec, and per fault {robot, t_s, mode, doing, detected_s,
    #: how, delay_s} (detected_s/how/delay_s null while the swarm never found out)
    faults_spec: str = ""
    faults: list = field(default_factory=list)
    #: failed robots built into piers (never counted as lost)
    robots_in_piers: int = 0

    def to_dict(self, events: bool = False) -> dict:
        d = {k: getattr(self, k) for k in (
            "success", "retreated", "timed_out", "robots_lost", "times", "seed_robot", "seed_position",
            "target_finder", "preset", "robots", "void_width", "seed", "limits_source", "min_robots_rule",
            "record_min_robots", "robots_delivered", "robots_on_initial_side", "steps", "wall_s", "violations",
            "levels_used", "switches", "seed_edge_cm", "end_reason", "hand_overs", "faults_spec", "faults",
            "robots_in_piers")}
        d["piers"] = pier_records(self.events)
        d["robots_failed"] = len({f["robot"] for f in self.faults})
        d["robots_detected"] = len({f["robot"] for f in self.faults if f["detected_s"] is not None})
        delays = [f["delay_s"] for f in self.faults if f["delay_s"] is not None]
        d["max_detection_delay_s"] = max(delays) if delays else None
        d["switches"] = [dict(x) for x in self.switches]
        d["assembly"] = self.construction.get("assembly")
        d["disassembly"] = self.construction.get("disassembly")
        d["times"] = dict(self.times)
        if events:
            d["events"] = [{"t_s": t, "kind": k, "robot": r, **data} for t, k, r, data in self.events]
        return d


# ---------------------------------------------------------------------------- set-up

def resolve_params(preset: str, robots: int, void_width: int, limits: str = "derived",
                   max_time_s: float | None = None, **overrides) -> Params:
    """Preset + overrides + limits -> validated :class:`Params`."""
    from structure_fem.limits import load_limits

    for name, v in (("robots", robots), ("void_width", void_width)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise InputError(f"{name} must be an integer, got {v!r}")
    p = load_preset(preset)
    ov = dict(overrides)
    ov["robots"] = int(robots)
    ov["void_width"] = int(void_width)
    if max_time_s is not None:
        ov["max_time_s"] = float(max_time_s)
    p = with_overrides(p, ov).validate()
    return with_limits(p, load_limits(limits))


def initial_poses(p: Params, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fixed starts (cases A-C: a grid on the initial side, facing the void, ids rising towards
    it) or random non-overlapping starts with random headings (case D)."""
    L = p.robot_length_cm
    x0 = p.void_x0_cm
    n = p.robots
    if p.start == "fixed":
        pitch = 2.5 * L
        rows = max(1, min(n, int((p.arena_h_cm - 2 * L) // pitch)))
        cols = math.ceil(n / rows)
        # the last column (highest ids) stands 5 robot lengths before the void, the rest behind it
        last = min(x0 - 2 * L, max(x0 - 5 * L, 1.5 * L + pitch * (cols - 1)))
        xs = last - pitch * np.arange(cols)[::-1]
        if xs[0] < 1.5 * L:
            raise InputError(f"robots={n} do not fit in the fixed start grid left of the void")
        ys0 = 0.5 * p.arena_h_cm - 0.5 * pitch * (rows - 1)
        k = np.arange(n)
        x = xs[k // rows]
        y = ys0 + pitch * (k % rows)
        h = np.zeros(n)
        ok = World.from_params(p).pose_ok(x, y, h)
        if not ok.all():  # an obstacle sits on the grid: shift those robots sideways
            for i in np.flatnonzero(~ok):
                for dy in (pitch / 2, -pitch / 2, pitch, -pitch):
                    if World.from_params(p).pose_ok(x[i:i + 1], y[i:i + 1] + dy, h[i:i + 1])[0]:
                        y[i] += dy
                        break
        return x.astype(float), y.astype(float), h
    world = World.from_params(p)
    r = world.body_radius_cm
    xs, ys = [], []
    lo_x, hi_x, lo_y, hi_y = r, x0 - 2 * L, r, p.arena_h_cm - r
    tries = 0
    while len(xs) < n:
        tries += 1
        if tries > 200 * n + 1000:
            raise InputError(f"robots={n} could not be placed without overlap on the initial side")
        cx, cy = rng.uniform(lo_x, hi_x), rng.uniform(lo_y, hi_y)
        if xs:
            d2 = (np.array(xs) - cx) ** 2 + (np.array(ys) - cy) ** 2
            if d2.min() < (2 * r) ** 2:
                continue
        if not world.pose_ok(np.array([cx]), np.array([cy]), np.array([0.0]))[0]:
            continue
        xs.append(cx)
        ys.append(cy)
    return np.array(xs), np.array(ys), rng.uniform(-np.pi, np.pi, n)


def init_state(p: Params, rng: np.random.Generator) -> SwarmState:
    x, y, h = initial_poses(p, rng)
    return new_state(x, y, h)


def with_faults(s: SwarmState, p: Params, seed: int) -> SwarmState:
    """``s`` carrying the run's fault schedule when ``p.faults`` has any (drawn from the run
    seed's own fault stream: :func:`swarm_sim.faults.draw_schedule`)."""
    from dataclasses import replace

    from .faults import draw_schedule, init_arrays, parse_faults

    if p.faults:
        spec = parse_faults(p.faults)
        sch, flags, t_s, known = init_arrays(draw_schedule(spec, p.robots, p.max_time_s, seed), p.robots)
        if sch is not None:
            s = replace(s, fault_schedule=sch, fault_flags=flags, fault_t_s=t_s, fault_known=known)
    return s


def pier_records(events) -> list[dict]:
    """Per pier the run built (swarm_sim.behaviour.piers): where (its near face, cm past the near edge),
    the robots stacked in it (lowest first), how many it needed and whether it was completed."""
    out: list[dict] = []
    for t, kind, r, d in events:
        if kind == "pier_site":
            out.append({"s_cm": d["s_cm"], "robots": [], "needed": d["robots_needed"], "complete": False,
                        "started_s": t})
        elif kind == "pier_lowered" and out:
            out[d["pier"]]["robots"].append(r)
        elif kind == "pier_complete" and out:
            out[d["pier"]]["complete"], out[d["pier"]]["complete_s"] = True, t
    return out


def fault_records(events) -> list[dict]:
    """Per fault (first fault of each robot and mode): when, what the robot was doing, and when
    and how the swarm detected the robot's failure (from the event log)."""
    found = {}
    for t, kind, r, d in events:
        if kind == "fault_detected" and r not in found:
            found[r] = (t, d["how"], d["delay_s"])
    out = []
    for t, kind, r, d in events:
        if kind == "fault":
            det = found.get(r)
            out.append({"robot": r, "t_s": t, "mode": d["mode"], "doing": d["doing"],
                        "detected_s": det[0] if det else None, "how": det[1] if det else None,
                        "delay_s": det[2] if det else None})
    return out


# ---------------------------------------------------------------------------- metrics

def times_from_events(events: tuple, t_end: float, phase: int) -> dict:
    """T_s, T_a, T_o, T_d, T_b, T_t (s) from the event log; null for a phase a run that
    timed out never finished, 0 for a phase the run's outcome skips (thesis tables)."""
    first = {}
    for t, kind, _r, _d in events:
        first.setdefault(kind, t)
    ts = first.get("seed")
    out = {k: None for k in ("Ts", "Ta", "To", "Td", "Tb", "Tt")}
    out["Tt"] = round(t_end, 6) if phase != Phase.TIMEOUT else None
    if ts is None:
        return out
    out["Ts"] = ts
    t_found, t_retreat, t_dissolved, t_stop = (first.get(k) for k in ("target_found", "retreat", "dissolved", "stopped"))
    if phase == Phase.SUCCESS:
        end_a = min(v for v in (t_dissolved, t_found) if v is not None)
        out.update(Ta=end_a - ts, To=(t_found - t_dissolved) if t_dissolved is not None and t_dissolved < t_found else 0.0,
                   Td=0.0, Tb=0.0)
    elif t_retreat is not None:
        out["Ta"] = t_retreat - ts
        if t_dissolved is not None:
            out["Td"] = t_dissolved - t_retreat
            out["To"] = 0.0
            if t_stop is not None:
                out["Tb"] = t_stop - t_dissolved
    elif t_dissolved is not None:
        out["Ta"] = t_dissolved - ts
    return {k: (round(v, 6) if v is not None else None) for k, v in out.items()}


def construction_times(events: tuple, phase: int | None = None) -> dict:
    """Fig. 5.13's two construction times (s; null when the run never reached them).

    ``assembly``: from the seed aligned at the edge until the structure is built and
    delivers (its first front release); for a run that retreats, until the retreat
    decision. ``disassembly``: from the last robot joining (no free robot left on the
    initial side) until the structure has dissolved on the target side; for a retreat,
    from the retreat decision until dissolved (= T_d).
    """
    first, last = {}, {}
    for t, kind, _r, _d in events:
        first.setdefault(kind, t)
        last[kind] = t
    out = {"assembly": None, "disassembly": None}
    t_al = first.get("aligned")
    if t_al is None:
        return out
    t_rel, t_ret, t_dis = first.get("release_front"), first.get("retreat"), first.get("dissolved")
    if t_ret is not None:
        out["assembly"] = t_ret - t_al
        if t_dis is not None:
            out["disassembly"] = t_dis - t_ret
    elif t_rel is not None:
        out["assembly"] = t_rel - t_al
        if t_dis is not None:
            out["disassembly"] = t_dis - max(last.get("dock", t_rel), t_rel)
    return {k: (round(v, 6) if v is not None else None) for k, v in out.items()}


# ---------------------------------------------------------------------------- run

#: the engines :func:`simulate` knows: ``compiled`` (swarm_sim.compiled's fast-forward kernel
#: between reference steps, bit-identical) and ``reference`` (every step by swarm_sim.step)
ENGINES = ("compiled", "reference")


#: environment variable naming the default engine (``voidcross sweep --engine`` sets it for its workers)
ENGINE_ENV = "SWARM_SIM_ENGINE"


def default_engine() -> str:
    """``$SWARM_SIM_ENGINE`` when set, else ``compiled`` when numba is importable, else ``reference``."""
    import os

    from .compiled import AVAILABLE

    env = os.environ.get(ENGINE_ENV)
    if env in ENGINES and (env == "reference" or AVAILABLE):
        return env
    return "compiled" if AVAILABLE else "reference"


def resolve_engine(engine: str | None) -> str:
    """``None`` -> :func:`default_engine`; an unknown name (or ``compiled`` without numba) is an
    :class:`InputError`."""
    if engine is None:
        return default_engine()
    if engine not in ENGINES:
        raise InputError(f"engine must be one of {', '.join(ENGINES)}, got {engine!r}")
    from .compiled import AVAILABLE

    if engine == "compiled" and not AVAILABLE:
        raise InputError("engine 'compiled' needs numba, which is not installed (use engine='reference')")
    return engine


def simulate(p: Params, seed: int, check: bool = False, on_step: Callable | None = None,
             use_numba: bool | None = None, until: str | None = None, engine: str | None = None,
             stats: dict | None = None) -> tuple[SwarmState, RunResult]:
    """Run to the end (target found, retreat finished, or ``max_time_s``); ``until="seed"``
    stops once the seed is chosen and aligned (seed statistics depend on nothing later).

    ``engine``: ``compiled`` (default when numba is importable) or ``reference``; both give
    the same run bit for bit. The compiled engine fast-forwards the steps in which only
    continuous things happen (:mod:`swarm_sim.compiled`) and runs every other step with the
    reference :func:`~swarm_sim.step.step`; with ``on_step`` or ``use_numba=False`` every step
    is a reference step. ``check=True`` checks the invariants after every step either way (the
    kernel checks the per-robot ones itself and leaves steps that could change the structure's
    to the reference). ``stats``: a dict to receive ``reference_steps``, ``kernel_steps``,
    ``kernel_calls`` and the kernel's stop reasons."""
    if until not in (None, "seed"):
        raise InputError(f"until must be None or 'seed', got {until!r}")
    engine = resolve_engine(engine)
    rng = np.random.default_rng(seed)
    world = World.from_params(p)
    state = with_faults(init_state(p, rng), p, int(seed))
    # the kernel knows no faults: a run with faults is fast-forwarded only until just before its
    # first fault, then it is reference steps (the same result either way)
    fast = engine == "compiled" and on_step is None and use_numba is not False
    sch = state.fault_schedule
    if fast:
        from .compiled import fast_forward
    ref_steps = 0
    last_ok = True
    lost: set[int] = set()
    viol: list[str] = []
    t0 = time.perf_counter()
    if on_step is not None:
        on_step(state)
    while state.phase not in ENDED:
        walked = None  # the next step's walk, when the kernel stopped after computing it
        if fast and last_ok:
            if sch is None:
                state, _, walked = fast_forward(state, p, world, rng, check, stats=stats)
            elif state.fault_next == 0 and len(sch):
                # every kernel step ends before the first fault's time (one step of margin)
                room = int(math.floor((float(sch.t_s[0]) - state.t_s) / p.dt_s)) - 2
                if room > 0:
                    state, _, walked = fast_forward(state, p, world, rng, check, max_steps=room, stats=stats)
        state = step(state, p, world, rng, use_numba, walked=walked)
        ref_steps += 1
        if check:
            v = violations(state, p, world, p.robots)
            last_ok = not v
            if v:
                viol.extend(v[:5])
                lost.update(int(m.group(1)) for m in map(_OVER.search, v) if m)
                if len(viol) > 50:
                    break
        else:
            lost.update(int(i) for i in lost_robots(state, world))
        if on_step is not None:
            on_step(state)
        if until == "seed" and state.seed_position is not None:
            break
    wall = time.perf_counter() - t0
    if stats is not None:
        stats["engine"] = engine
        stats["reference_steps"] = stats.get("reference_steps", 0) + ref_steps
        stats.setdefault("kernel_steps", 0)
    times = times_from_events(state.events, state.t_s, state.phase)
    side = world.side_of(state.x_cm)
    res = RunResult(
        preset=p.preset, robots=p.robots, void_width=p.void_width, seed=int(seed), limits_source=p.limits_source,
        success=state.phase == Phase.SUCCESS, retreated=state.phase == Phase.RETREATED,
        timed_out=state.phase == Phase.TIMEOUT, robots_lost=len(lost), times=times,
        seed_robot=state.seed_robot if state.seed_robot >= 0 else None,
        seed_position=list(state.seed_position) if state.seed_position is not None else None,
        target_finder=state.target_finder if state.target_finder >= 0 else None,
        min_robots_rule=p.min_robots_rule, robots_delivered=int((side > 0).sum()),
        robots_on_initial_side=int((side < 0).sum()), steps=state.step, wall_s=round(wall, 4),
        violations=viol, events=list(state.events),
        levels_used=_levels_used(p, state.events), switches=[
            {"t_s": t, "level": d["level"], "lines": d["lines"], "layers": d["layers"], "n_g": d["n_g"],
             "rows": d["rows"]} for t, k, _r, d in state.events if k == "switch"],
        seed_edge_cm=float(state.seed_position[1]) if state.seed_position is not None else None,
        construction=construction_times(state.events, state.phase), record_min_robots=p.record_min_robots,
        end_reason=end_reason(state.events, state.phase),
        hand_overs=sum(1 for _t, k, _r, _d in state.events if k == "hand_over"), faults_spec=p.faults,
        robots_in_piers=int((state.mode == Mode.PIER).sum()),
        faults=fault_records(state.events))
    return state, res


def _levels_used(p: Params, events) -> list:
    if not p.switch_levels:
        return [p.level_name] if any(k == "aligned" for _t, k, _r, _d in events) else []
    used = [p.switch_levels[0][0]] if any(k == "aligned" for _t, k, _r, _d in events) else []
    return used + [d["level"] for _t, k, _r, d in events if k == "switch"]


def run_scenario(preset: str, robots: int, void_width: int, seed: int, limits: str = "derived",
                 max_time_s: float | None = None, engine: str | None = None, **overrides) -> RunResult:
    """One run. ``preset``: a preset name (``case-d``) or TOML path; ``robots``: swarm size;
    ``void_width``: robot widths; ``seed``: RNG seed; ``limits``: ``derived`` | ``thesis`` |
    path to limits.json; ``max_time_s``: simulated-time cap; ``engine``: ``compiled`` | ``reference``
    (default: compiled when numba is importable; the same result either way); ``overrides``: any flat
    :class:`Params` field (``arena_w_cm=800``) plus ``check_invariants=True`` (raise
    :class:`InvariantViolation` on the first broken invariant) and ``until="seed"`` (stop
    once the seed is chosen).
    Raises :class:`InputError` on bad input."""
    check = bool(overrides.pop("check_invariants", False))
    until = overrides.pop("until", None)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}")
    engine = resolve_engine(engine)
    p = resolve_params(preset, robots, void_width, limits, max_time_s, **overrides)
    _, res = simulate(p, int(seed), check=check, until=until, engine=engine)
    if check and res.violations:
        raise InvariantViolation(res.violations[0])
    return res


__all__ = ["ENGINES", "ENGINE_ENV", "RunResult", "default_engine", "init_state", "resolve_engine", "resolve_params", "run_scenario",
           "simulate"]
