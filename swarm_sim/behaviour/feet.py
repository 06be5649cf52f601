"""The tapering arch's feet (:mod:`swarm_sim.behaviour.taper`): rounds that fill or dissolve a group of
shell columns, one robot per column.

A round (``Structure.job``) has two stages. ``drive``: each robot follows its planned path
(:mod:`swarm_sim.engine.navigation`, walls, obstacles and the void in the way) to the staging
point one row behind its column and turns to the structure's heading. ``climb``: a timed
kinematic stage (``climb_s_per_layer`` per layer plus one length of travel; the thesis does
not say how robots get up) after which the column slides and the robot takes its slot
(:func:`swarm_sim.behaviour.taper.fill_column`), or the column's rear robot steps off
(:func:`swarm_sim.behaviour.taper.pop_column`). The feet's own robots are not in the way of the
planner: they stand beside the staging points the robots drive to.
"""

from __future__ import annotations

import math

from swarm_sim.behaviour import taper as T
from swarm_sim.behaviour.recruitment import answering, candidates
from swarm_sim.behaviour.release import release
from swarm_sim.behaviour.retreat import start_retreat
from swarm_sim.engine.motion import drive_along
from swarm_sim.engine.navigation import cost_field, nav_grid
from swarm_sim.engine.tick import Tick
from swarm_sim.faults import DRIVE
from swarm_sim.params import level_params
from swarm_sim.state import Mode, Structure, evolve

_EXPLORE, _RECRUIT, _MEMBER = int(Mode.EXPLORE), int(Mode.RECRUIT), int(Mode.MEMBER)
_TARGET, _RETREAT = int(Mode.TARGET), int(Mode.RETREAT)


def geometry(st: Structure, p) -> T.ShellGeometry | None:
    """The shell geometry of a tapered level (None for the other structures)."""
    lp = level_params(p, st)
    if not lp.taper_block_rows:
        return None
    return T.shell_geometry(lp.layers, lp.taper_block_rows, p.void_width)


def _staging_field(tk: Tick, g: T.ShellGeometry, c: int):
    sx, sy = T.staging_xy(tk.st, g, tk.p.robot_length_cm, tk.p.robot_width_cm, c)
    return cost_field(tk.world, sx, sy)


def start_fill_near(tk: Tick, g: T.ShellGeometry) -> None:
    """Call the closest free robots (by path) to the next group of near-foot columns."""
    free = candidates(tk)
    cols = T.next_fill_group(tk.st.shell, g, T.NEAR)[:free.size]
    known = int(tk.known.sum()) if tk.known is not None else 0
    chosen = answering(tk, [_staging_field(tk, g, c) for c in cols], list(free))
    if not chosen:
        if tk.known is not None and int(tk.known.sum()) > known:
            return  # those called answered that they failed: decide again, knowing it
        start_retreat(tk, "stalled")
        return
    cols = cols[:len(chosen)]
    tk.mode[chosen] = _RECRUIT
    tk.st = evolve(tk.st, job=tuple(chosen), job_cols=tuple(cols), job_kind="fill_near", job_stage="drive",
                    job_best_cm=(math.inf,) * len(chosen), job_progress_s=(tk.t,) * len(chosen), progress_s=tk.t)
    tk.ev("fill_near_start", chosen[0], robots=list(chosen), columns=list(cols))


def start_unfill(tk: Tick, g: T.ShellGeometry, kind: str) -> None:
    """``unfill_near`` / ``dissolve_far``: the next group of columns gives up its rear robots."""
    st, p = tk.st, tk.p
    cols = T.next_unfill_group(st.shell, g, T.NEAR if kind == "unfill_near" else T.FAR)
    prev = list(st.shell)
    robots = tuple(T.pop_column(prev, g, c) for c in cols)
    zmax = max(int(g.col_z[c]) for c in cols)
    tk.st = evolve(st, job=robots, job_cols=tuple(cols), job_kind=kind, job_stage="climb",
                    job_until_s=tk.t + zmax * p.climb_s_per_layer + p.robot_length_cm / p.speed_cm_s,
                    progress_s=tk.t)
    tk.ev(kind + "_start", robots[0], robots=list(robots), columns=list(cols))


def advance_job(tk: Tick) -> None:
    """One step of the round under way."""
    st, p = tk.st, tk.p
    g = geometry(st, p)
    L, W = p.robot_length_cm, p.robot_width_cm
    dir_h = math.atan2(st.dir_y, st.dir_x)
    if st.job_stage == "drive":
        arrived = True
        best, since = list(st.job_best_cm), list(st.job_progress_s)
        half_cell = 0.5 * nav_grid(tk.world).cell_cm
        for i, (r, c) in enumerate(zip(st.job, st.job_cols, strict=True)):
            field = _staging_field(tk, g, c)
            rx, ry, rh = float(tk.x[r]), float(tk.y[r]), float(tk.h[r])
            if rx == field.goal_x and ry == field.goal_y and rh == dir_h:
                continue
            arrived = False
            if tk.is_failed(r, DRIVE):
                continue  # it cannot come: the round stalls and the watchdog calls it off
            nx, ny, nh, _ = drive_along(field, rx, ry, rh, p, tk.world, final_heading=dir_h, align_h=dir_h)
            tk.x[r], tk.y[r], tk.h[r] = nx, ny, nh
            left = field.cost_at(nx, ny)
            if left < best[i] - half_cell:
                best[i], since[i] = left, tk.t
                tk.progress()
        tk.st = evolve(tk.st, job_best_cm=tuple(best), job_progress_s=tuple(since))
        if arrived:
            zmax = max(int(g.col_z[c]) for c in st.job_cols)
            tk.st = evolve(tk.st, job_stage="climb", job_until_s=tk.t + zmax * p.climb_s_per_layer + L / p.speed_cm_s)
        return
    if tk.t + 1e-9 < st.job_until_s:
        return
    shell = list(st.shell)
    if st.job_kind.startswith("fill"):
        for r, c in zip(st.job, st.job_cols, strict=True):
            T.fill_column(shell, g, c, r)
            tk.mode[r] = _MEMBER
    else:
        near = st.job_kind == "unfill_near"
        new_mode = (_RETREAT if st.retreating else _EXPLORE) if near else _TARGET
        away = dir_h + (math.pi if near else 0.0)
        for c in st.job_cols:
            r = T.pop_column(shell, g, c)
            tk.x[r], tk.y[r] = T.staging_xy(st, g, L, W, c)
            tk.h[r] = dir_h + (math.pi if near else 0.0)
            release(tk, r, away, new_mode)
            if new_mode == _EXPLORE:
                tk.disp[r] = 0.0
    tk.ev(st.job_kind, st.job[0], robots=list(st.job), columns=list(st.job_cols))
    tk.st = evolve(tk.st, shell=tuple(shell), job=(), job_cols=(), job_kind="", job_stage="", job_until_s=0.0,
                    job_best_cm=(), job_progress_s=(), progress_s=tk.t)


def abort_job(tk: Tick) -> None:
    """A round whose robots cannot reach their columns is called off: near-foot robots walk
    again on the initial side, far-foot robots on the target side."""
    st = tk.st
    for r in st.job:
        tk.mode[r] = _TARGET if tk.sopp[r] == 1 else _EXPLORE
        tk.sopp[r] = -1
    tk.ev("job_aborted", st.job[0], kind=st.job_kind, robots=list(st.job))
    tk.st = evolve(st, job=(), job_cols=(), job_kind="", job_stage="", job_until_s=0.0, job_best_cm=(),
                    job_progress_s=())
