"""One simulation step: ``step(state, params, world, rng) -> state`` (inputs are not mutated).

A step is the sequence :data:`PHASES` (dt = ``params.dt_s``), each a function of the step's
working copy (:class:`swarm_sim.engine.tick.Tick`):

0. :func:`~swarm_sim.faults.fail`: the faults due by the end of the step happen (runs with
   faults only; what the swarm then senses and does is :mod:`swarm_sim.behaviour.detection`);
1. :func:`detect_seed` (search phase): an initial explorer whose ground sensor sees the
   void becomes the seed (ties: the one nearest the void) and the ``void found``
   broadcast stops others from seeding;
2. :func:`walk_free`: free robots walk (vectorised over the walking modes, :mod:`swarm_sim.behaviour.explore`);
3. :func:`move_structure`: the structure's current action moves (align, wait, advance/back,
   the recruits' approach: :mod:`swarm_sim.behaviour.recruitment`) and a foot round under way
   advances (:mod:`swarm_sim.behaviour.feet`);
4. :func:`decide`: an idle structure takes the first matching row of its decision table
   (:mod:`swarm_sim.behaviour.structure`, :mod:`swarm_sim.behaviour.taper`) and does it through :data:`ACTIONS`;
5. :func:`watch`: the watchdog (a structure that cannot proceed retreats) and the
   dissolution (:mod:`swarm_sim.behaviour.retreat`); members are placed where the structure stands;
6. :func:`finish`: the target check, the post-retreat wander clock and the time-limit guard.
"""

from __future__ import annotations

import math

import numpy as np

from swarm_sim.behaviour import detection as DT
from swarm_sim.behaviour import feet
from swarm_sim.behaviour import piers as PR
from swarm_sim.behaviour import recruitment as RC
from swarm_sim.behaviour import release as RL
from swarm_sim.behaviour import retreat as RT
from swarm_sim.behaviour import structure as S
from swarm_sim.behaviour import taper as T
from swarm_sim.behaviour.explore import walk
from swarm_sim.engine.tick import Tick
from swarm_sim.engine.world import wrap

from .faults import DRIVE, SENSOR, fail
from .params import at_level, level_params
from .state import OPEN, WALKING_MODES, Mode, Phase, Structure, SwarmState, evolve

_EXPLORE, _SEED, _MEMBER = int(Mode.EXPLORE), int(Mode.SEED), int(Mode.MEMBER)
_TARGET, _STOPPED, _PIER = int(Mode.TARGET), int(Mode.STOPPED), int(Mode.PIER)
_P_SEARCH, _P_BUILD, _P_DELIVERED = int(Phase.SEARCH), int(Phase.BUILD), int(Phase.DELIVERED)
_P_WANDER, _P_SUCCESS, _P_RETREATED, _P_TIMEOUT = (int(Phase.WANDER), int(Phase.SUCCESS), int(Phase.RETREATED),
                                                   int(Phase.TIMEOUT))
_P_STRANDED = int(Phase.STRANDED)
EPS_MOVE = 1e-9
ENDED = (_P_SUCCESS, _P_RETREATED, _P_TIMEOUT, _P_STRANDED)
WALKING_LUT = np.zeros(len(Mode), dtype=bool)
WALKING_LUT[list(WALKING_MODES)] = True


# ---------------------------------------------------------------------------- 1. seed

def detect_seed(tk: Tick) -> None:
    if tk.phase != _P_SEARCH:
        return
    p, world = tk.p, tk.world
    able = tk.mode == _EXPLORE
    if tk.fault is not None:
        able &= tk.fault == 0  # a robot knows its own failure: a failed one never seeds
    cand = np.flatnonzero(able)
    if not cand.size:
        return
    see = world.void_ahead(tk.x[cand], tk.y[cand], tk.h[cand])
    if not see.any():
        return
    hits = cand[see]
    seed = int(hits[np.argmax(tk.x[hits])])
    tk.mode[seed] = _SEED
    tk.sidx[seed] = 1
    tk.st = Structure(members=(seed,), origin_x_cm=world.x0_cm, origin_y_cm=float(tk.y[seed]),
                      dir_x=1.0, dir_y=0.0, front_s_cm=0.0, action="align",
                      lines=2 if p.taper_block_rows else p.lines,
                      layers=1 if p.taper_block_rows else p.layers,
                      lateral_sign=1.0 if tk.y[seed] < 0.5 * world.h_cm else -1.0, progress_s=tk.t)
    tk.phase, tk.phase_since, tk.seed_robot = _P_BUILD, tk.t, seed
    tk.ev("seed", seed, x_cm=float(tk.x[seed]), y_cm=float(tk.y[seed]))


# ---------------------------------------------------------------------------- 2. walk

def walk_free(tk: Tick) -> None:
    p = tk.p
    if tk.walked is not None:  # the compiled engine's kernel already walked this step (the same walk)
        tk.x, tk.y, tk.h, tk.goal, tk.run_left = tk.walked
    else:
        walking = WALKING_LUT[tk.mode]
        if tk.phase != _P_SEARCH and p.case in ("A", "B"):
            walking &= tk.mode != _EXPLORE  # cases A, B: free robots stop once the void is found (Ch. 4.5)
        if tk.fault is not None:
            walking &= ~tk.failed(DRIVE | SENSOR)  # fail-safe: a robot that cannot drive or see stops
        walkers = np.flatnonzero(walking)
        tk.x, tk.y, tk.h, tk.goal, tk.run_left = walk(tk.x, tk.y, tk.h, tk.goal, tk.run_left, walkers,
                                                      tk.disp[walkers] > 0, tk.world, p, tk.rng, tk.use_numba)
    tk.disp = np.maximum(tk.disp - p.dt_s, 0.0)


# ---------------------------------------------------------------------------- 3. structure moves

def _align(tk: Tick) -> None:
    """The seed turns perpendicular to the edge and creeps up to it."""
    st, p, world = tk.st, tk.p, tk.world
    dist = p.speed_cm_s * p.dt_s
    s0 = st.members[0]
    if tk.is_failed(s0, DRIVE):
        return  # it cannot align (swarm_sim.behaviour.detection.seed_failed)
    dir_h = math.atan2(st.dir_y, st.dir_x)
    hx, hy, hh = float(tk.x[s0]), float(tk.y[s0]), float(tk.h[s0])
    d = float(wrap(np.array(dir_h - hh)))
    if abs(d) > 1e-9:
        nh = hh + max(-p.turn_max_rad, min(p.turn_max_rad, d))
        if world.pose_ok1(hx, hy, nh):
            tk.h[s0] = nh
        else:  # too close to the edge to turn: back away from it first
            tk.x[s0] = hx - dist * st.dir_x
            tk.y[s0] = hy - dist * st.dir_y
        return
    tk.h[s0] = dir_h
    gap = (world.x0_cm - 0.5 * p.robot_length_cm) - hx  # distance to the aligned pose
    if gap > dist:
        tk.x[s0] = hx + dist
        return
    tk.st = evolve(st, origin_y_cm=hy, front_s_cm=0.0, action="idle", progress_s=tk.t)
    tk.mode[s0] = _MEMBER
    tk.seed_pos = (round(world.x0_cm - 0.5 * p.robot_length_cm, 6), round(hy, 6))
    tk.ev("aligned", s0, x_cm=tk.seed_pos[0], y_cm=tk.seed_pos[1])


def _wait(tk: Tick) -> None:
    if tk.t >= tk.st.wait_until_s:
        tk.st = evolve(tk.st, action="idle")


def _slide(tk: Tick) -> None:
    """``advance`` / ``back``: the whole structure moves one length (it ignores obstacles:
    the thesis's assumption 13)."""
    st, p = tk.st, tk.p
    if tk.fault is not None and not DT.drivers(tk):
        return  # no member can drive: the structure stands (its watchdog decides)
    sgn = 1.0 if st.action == "advance" else -1.0
    f = st.front_s_cm + sgn * p.speed_cm_s * p.dt_s
    if (f - st.goal_s_cm) * sgn >= -EPS_MOVE:
        st = evolve(st, front_s_cm=st.goal_s_cm, action="idle", progress_s=tk.t)
    else:
        st = evolve(st, front_s_cm=f)
    if not st.landed and st.front_s_cm + tk.world.detect_cm >= p.void_width_cm - 1e-6 and DT.front_sees(tk):
        st = evolve(st, landed=True)
        tk.ev("far_ledge", st.members[0], front_s_cm=round(st.front_s_cm, 6))
    tk.st = st


#: what each structure action does every step while it lasts (``idle`` decides, see :func:`decide`)
MOTIONS = {"align": _align, "wait": _wait, "advance": _slide, "back": _slide, "recruit": RC.approach,
           "pier": PR.advance, "idle": lambda tk: None}


def move_structure(tk: Tick) -> None:
    if tk.st is None or tk.phase != _P_BUILD:
        return
    MOTIONS[tk.st.action](tk)
    if tk.st.job and tk.st.action != "align":
        feet.advance_job(tk)


# ---------------------------------------------------------------------------- 4. decide and act

def _recruit(tk: Tick, ctx: dict) -> None:
    known = int(tk.known.sum()) if tk.known is not None else 0
    chosen = RC.call(tk, ctx["slots"])
    learnt = tk.known is not None and int(tk.known.sum()) > known
    if not chosen:  # free robots exist, none can reach the dock: the structure cannot proceed
        if learnt:
            return  # those called answered that they failed: decide again, knowing it
        RT.start_retreat(tk, "stalled", ctx["sit"].counts, ctx["free"])
    elif len(chosen) < len(ctx["slots"]) and not S.filling(tk.st):
        RC.call_off(tk)  # a row is recruited whole: it cannot be completed
        if learnt:
            return
        RT.start_retreat(tk, "stalled", ctx["sit"].counts, ctx["free"])


def _advance(tk: Tick, ctx: dict) -> None:
    st = tk.st
    tk.st = evolve(st, action="advance", goal_s_cm=st.front_s_cm + tk.p.robot_length_cm)
    c = ctx["sit"].counts
    tk.ev("advance", st.members[0], n_p=c.n_p, n_g=c.n_g, n_o=c.n_o)


def _back(tk: Tick, ctx: dict) -> None:
    tk.st = evolve(tk.st, action="back", goal_s_cm=tk.st.front_s_cm - tk.p.robot_length_cm)


def _switch(tk: Tick, ctx: dict) -> None:
    """Ch. 5.5.2: the far ledge is not found within this level's span: widen to the next."""
    st, p, world, g, sit = tk.st, tk.p, tk.world, ctx["g"], ctx["sit"]
    L, W = p.robot_length_cm, p.robot_width_cm
    nxt = st.level + 1
    pl = at_level(p, nxt)
    if pl.taper_block_rows:
        # a tapering arch: the core is (or becomes) two lines; the feet are shell data
        g_new = T.shell_geometry(pl.layers, pl.taper_block_rows, p.void_width)
        shell = T.remap_shell(st.shell, g, g_new) if (g is not None and st.shell) else T.empty_shell(g_new)
        members = st.members if st.lines == 2 and st.layers == 1 else S.widened(st, 2, 1)
        _, sy = T.slot_xy(st, g_new, L, W, np.arange(g_new.n))
        if sy.min() - 0.5 * W < -1e-6 or sy.max() + 0.5 * W > world.h_cm + 1e-6:
            # the feet would stick out of the arena beside this core line: give up
            RT.start_retreat(tk, "no_room_for_the_feet", sit.counts, ctx["free"])
            return
        tk.st = evolve(st, members=members, lines=2, layers=1, level=nxt, shell=shell, progress_s=tk.t)
    else:
        tk.st = evolve(st, members=S.widened(st, pl.lines, pl.layers), lines=pl.lines, layers=pl.layers,
                        level=nxt, progress_s=tk.t)
    tk.ev("switch", tk.st.members[0], level=pl.level_name, lines=pl.lines, layers=pl.layers,
          n_p=sit.counts.n_p, n_g=sit.counts.n_g, rows=S.all_rows(tk.st))


def _retreat(tk: Tick, ctx: dict) -> None:
    sit = ctx["sit"]
    if getattr(sit, "span_blocked", False) and not getattr(sit, "filling", False):
        why = "span"
    elif tk.st.passed_over and (tk.mode == _EXPLORE).any():
        why = "stalled"             # free robots are left, but none that can reach the dock
    elif ctx["free"] and not ctx["dock_ok"]:
        why = "dock_blocked"
    else:
        why = "no_free_robot"
    RT.start_retreat(tk, why, sit.counts, ctx["free"])


#: decision-table action -> what the structure does (``hold``: nothing this step)
ACTIONS = {
    "release_front": lambda tk, ctx: RL.release_front(tk, ctx["g"]),
    "release_rear": lambda tk, ctx: RL.release_rear(tk),
    "recruit": _recruit,
    "advance": _advance,
    "back": _back,
    "switch": _switch,
    "retreat": _retreat,
    "fill_near": lambda tk, ctx: feet.start_fill_near(tk, ctx["g"]),
    "unfill_near": lambda tk, ctx: feet.start_unfill(tk, ctx["g"], "unfill_near"),
    "dissolve_far": lambda tk, ctx: feet.start_unfill(tk, ctx["g"], "dissolve_far"),
    "pier": lambda tk, ctx: PR.start(tk),
    "hold": lambda tk, ctx: None,
}


def decide(tk: Tick) -> None:
    st, p = tk.st, tk.p
    if st is None or tk.phase != _P_BUILD or st.action != "idle":
        return
    if tk.fault is not None and not DT.can_decide(tk):
        return  # every member is silent (swarm_sim.behaviour.detection.watch ends it)
    g = feet.geometry(st, p)
    if g is not None and not st.shell:
        tk.st = st = evolve(st, shell=T.empty_shell(g))
    free = RC.candidates(tk)
    action, sit, ctx = choose(st, p, tk.world, g, int(free.size))
    if g is None and sit.span_blocked and p.pier_robots and not st.landed:
        PR.call_for_material(tk)  # the span is reached: can failed robots make a pier?
        if PR.ready(tk):
            action, sit = S.decide(st, level_params(p, st), ctx["enough"], ctx["dock_ok"], pier_ready=True)
    ctx["sit"] = sit
    ACTIONS[action](tk, ctx)


def choose(st: Structure, p, world, g, free: int) -> tuple[str, object, dict]:
    """The idle structure's decision (a pure function of the structure, the free robots'
    count and the world): (action, situation, the actions' context). ``g``: the level's shell
    geometry (None when it does not taper; the shell already set). The compiled engine asks
    it too, to know when an idle tapered structure only holds."""
    slot_ids = RC.open_slots(st)
    enough = free >= 1 if S.filling(st) else free >= len(slot_ids)
    L, W = p.robot_length_cm, p.robot_width_cm
    # the dock point is part of the structure: walls and void only (assumption 13)
    on_ground = world.without_obstacles.pose_ok1
    dock_ok = all(on_ground(sx, sy, 0.0) for sx, sy, _, _ in (S.slot_pose(st, q, L, W) for q in slot_ids))
    lp = level_params(p, st)
    if g is not None:
        if st.job and (st.retreating or not st.landed):
            action, sit = "hold", None  # the tables' first row, without computing the rest
        else:
            action, sit = T.decide(st, lp, g, free, enough, dock_ok)
    else:
        action, sit = S.decide(st, lp, enough, dock_ok)
    return action, sit, {"g": g, "sit": sit, "slots": slot_ids, "free": free, "dock_ok": dock_ok, "enough": enough}


# ---------------------------------------------------------------------------- 5. watch

def _place_members(tk: Tick) -> None:
    """Every member stands at its slot of the structure (the structure is rigid)."""
    st, p = tk.st, tk.p
    if st.members:
        ids, m = S.occupied(st)
        mx, my, mh = S.member_poses(st, p.robot_length_cm, p.robot_width_cm, m)
        tk.x[ids], tk.y[ids], tk.h[ids] = mx, my, mh
        k = S.row_size(st)
        if k == 1:
            tk.sidx[ids] = m + 1
            tk.sline[ids] = 0
            tk.slayer[ids] = 0
        else:
            tk.sidx[ids] = m // k + 1
            tk.sline[ids] = (m % k) % st.lines
            tk.slayer[ids] = (m % k) // st.lines
        tk.sopp[ids] = 0
    if st.shell:
        g = feet.geometry(st, p)
        sh = np.asarray(st.shell, dtype=np.int64)
        slots = np.flatnonzero(sh != OPEN)
        if slots.size:
            ids = sh[slots]
            tk.x[ids], tk.y[ids] = T.slot_xy(st, g, p.robot_length_cm, p.robot_width_cm, slots)
            tk.h[ids] = math.atan2(st.dir_y, st.dir_x)
            tk.sidx[ids] = g.pos[slots] + 1
            tk.sline[ids] = g.q[slots]
            tk.slayer[ids] = g.z[slots]
            tk.sopp[ids] = g.foot[slots]


def watch(tk: Tick, before: Structure | None = None) -> None:
    """``before``: the structure at the start of the step (unchanged: its members already
    stand at their slots, nothing else moves them)."""
    if tk.st is None or tk.phase != _P_BUILD:
        return
    if RT.stalled(tk):  # the structure cannot proceed: call off what is under way, retreat
        st = tk.st
        tk.ev("stalled", st.members[0] if st.members else -1, action=st.action, since_s=round(st.progress_s, 6))
        if st.recruits:
            RC.call_off(tk)
        if tk.st.job and tk.st.job_stage == "drive":
            feet.abort_job(tk)
        if tk.st.action in ("advance", "back", "wait"):
            tk.st = evolve(tk.st, action="idle")
        RT.start_retreat(tk, "stalled")
    if tk.fault is not None and tk.st is not None and tk.st.action != "align" and tk.st is not before:
        _place_members(tk)  # where the structure stands now, before the fault handling may end it
    DT.watch(tk)
    if tk.st is None or tk.phase != _P_BUILD:
        return
    RT.dissolved(tk)
    if tk.st is not None and tk.st.action != "align" and tk.st is not before:
        _place_members(tk)


# ---------------------------------------------------------------------------- 6. finish

def finish(tk: Tick) -> None:
    p, world, t = tk.p, tk.world, tk.t
    if tk.phase in (_P_BUILD, _P_DELIVERED) and tk.target_finder < 0:
        seeing = tk.mode == _TARGET
        if tk.fault is not None:
            seeing &= ~tk.failed(SENSOR)  # a blind robot cannot see the target
        tg = np.flatnonzero(seeing)
        if tg.size:
            d2 = (tk.x[tg] - world.target_x_cm) ** 2 + (tk.y[tg] - world.target_y_cm) ** 2
            hit = d2 <= world.target_found_cm ** 2
            if hit.any():
                tk.target_finder = int(tg[hit][np.argmin(d2[hit])])
                tk.ev("target_found", tk.target_finder)
    # the run succeeds once the target is found (finish_delivery: and the structure has
    # delivered everyone and dissolved, so the disassembly time is measured)
    if tk.target_finder >= 0 and tk.phase in (_P_BUILD, _P_DELIVERED) and (
            not p.finish_delivery or tk.phase == _P_DELIVERED):
        tk.phase, tk.phase_since = _P_SUCCESS, t
        tk.mode[WALKING_LUT[tk.mode]] = _STOPPED
    if tk.phase == _P_WANDER and t - tk.phase_since >= p.wander_after_retreat_s - 1e-9:
        tk.phase, tk.phase_since = _P_RETREATED, t
        tk.mode[tk.mode != _PIER] = _STOPPED  # robots in piers stay there
        tk.ev("stopped")
    if tk.fault is not None and tk.target_finder < 0:
        if tk.phase == _P_SEARCH and not DT.search_possible(tk):
            DT.strand(tk, "no robot left that can find the void")
        elif tk.phase == _P_DELIVERED and not DT.target_search_possible(tk):
            DT.strand(tk, "no robot left on the target side that can find the target")
    if tk.phase not in ENDED and t >= p.max_time_s - 1e-9:
        tk.phase, tk.phase_since = _P_TIMEOUT, t
        tk.ev("timeout")


#: the step, in order
PHASES = (fail, detect_seed, walk_free, move_structure, decide, watch, finish)


def step(state: SwarmState, p, world, rng: np.random.Generator, use_numba: bool | None = None,
         walked: tuple | None = None) -> SwarmState:
    """One step: every phase of :data:`PHASES` in order on a working copy (:class:`Tick`).
    ``walked``: this step's walk as :func:`swarm_sim.compiled.fast_forward` computed it (the
    kernel stopped after the walk phase of this step; the generator is already past its draws),
    taken instead of walking again."""
    if state.phase in ENDED:
        return state
    tk = Tick.of(state, p, world, rng, use_numba)
    tk.walked = walked
    for phase in PHASES:
        if phase is watch:
            watch(tk, state.structure)
        else:
            phase(tk)
    return tk.state(state)
