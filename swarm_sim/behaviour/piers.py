"""Piers: failed robots stacked in the void so the line spans farther (the thesis's future
work 4, Ch. 7.2; issue 16).

The void has a depth (``void_depth_cm``, preset ``void.depth_cm``; 0: unknown or too deep, no
piers: the thesis's voids have vertical sides). A pier is a column of ``k`` robots standing
on the void's floor, stacked with the top-down (twist-key) coupling, one robot length wide
along the structure's axis. Its top is at ``standing + (k - 1) * pitch`` (the limits record's
pier block, from the CAD's stack geometry); a depth is pier-able when some ``k`` puts the top
within the record's clearance below the ledge (the line's wheels roll onto it after a sag of
at most the clearance) and not above it (:func:`robots_per_pier`).

**When.** A line whose next advance would exceed its span (``span_blocked``) and that knows
``k`` failed robots standing on the initial side (:mod:`swarm_sim.behaviour.detection`: only robots the
swarm detected, never read from their flags) builds a pier just beyond its front: the site is
``[front_s, front_s + L]`` past the near edge, where the record's rule was derived
(``first_span_widths``). Without a pier rule (the ``thesis`` limits: the thesis has none), a
depth that takes no pier, or too few known failed robots, the table goes on as before
(switch or retreat).

**How (modelled as timed moves, not simulated mechanisms).** One robot at a time: a healthy
free robot (the carrier, called like a recruit: the closest by path that answers) drives to
the failed robot (``fetch``); from there the failed robot moves with it, as if carried, along
the carrier's real path to the structure's rear dock point (``tow``); both climb onto the
structure (``climb_s_per_layer``), ride along its top to the front (``carry``, at
``speed_cm_s``), the failed robot is lowered onto the pier (``lower``: ``climb_s_per_layer``
per robot height of descent), and the carrier rides back and comes down at the rear, free
again (``return``). How a CuBot pushes, lifts or lowers another is not modelled; the cad
package checks the stack itself (``cubot_cad.piers.pier``).

**Then.** Once the pier has its ``k`` robots its top is a support: the counting rule and the
span are taken from the pier's far face (rows behind it >= ``pier_ground_ratio`` x rows
beyond it + ``pier_ground_margin``, at most ``overhang_widths[k - 1]`` rows beyond it:
:func:`rule_frame`). Robots in piers stay there (``Mode.PIER``), are reported as
``robots_in_piers`` and are never lost.
"""

from __future__ import annotations

import math

import numpy as np

from swarm_sim.behaviour.rule import complete_piers as complete
from swarm_sim.behaviour.rule import move_ok, robots_per_pier, rule_frame, stable_at  # noqa: F401  (the rule's home)
from swarm_sim.engine.navigation import cost_field, nav_grid
from swarm_sim.engine.tick import Tick
from swarm_sim.faults import DRIVE, SENSOR, TOTAL
from swarm_sim.state import Mode, evolve

_EXPLORE, _RECRUIT, _PIER = int(Mode.EXPLORE), int(Mode.RECRUIT), int(Mode.PIER)
STAGES = ("fetch", "tow", "climb", "carry", "lower", "return")


def call_for_material(tk: Tick) -> None:
    """The structure's call for pier material: every free robot on the initial side that knows
    it failed (it cannot drive or cannot see) and can still communicate answers; a totally
    failed robot cannot (it is material only if the swarm found it otherwise)."""
    if tk.fault is None:
        return
    ans = (tk.mode == _EXPLORE) & (tk.x < tk.world.x0_cm) & ((tk.fault & (DRIVE | SENSOR)) != 0) & \
        ((tk.fault & TOTAL) == 0) & ~tk.known
    for r in np.flatnonzero(ans):
        tk.detect(int(r), "answered_pier_call")


def known_failed_free(tk: Tick) -> np.ndarray:
    """Failed robots the swarm knows of, standing free on the initial side (pier material)."""
    if tk.known is None:
        return np.zeros(0, dtype=np.int64)
    ok = tk.known & (tk.mode == _EXPLORE) & (tk.x < tk.world.x0_cm)
    return np.flatnonzero(ok)


def ready(tk: Tick) -> bool:
    """Could the structure start (or go on with) a pier now?"""
    st, p = tk.st, tk.p
    if not p.pier_robots or st.landed or st.retreating or st.lines * st.layers != 1:
        return False
    if st.piers and st.piers[-1][1] < p.pier_robots:
        needed = p.pier_robots - st.piers[-1][1]  # the pier under way goes on
    elif len(st.piers) >= p.pier_max:
        return False
    else:
        L = p.robot_length_cm
        site = st.front_s_cm
        if site + L > p.void_width_cm + 1e-6:
            return False  # the pier would stand on the far ledge (against its wall is fine)
        needed = p.pier_robots  # a pier is started only when the swarm knows enough material
    return known_failed_free(tk).size >= needed and _carrier_pool(tk).size > 0


def _carrier_pool(tk: Tick) -> np.ndarray:
    free = (tk.mode == _EXPLORE) & (tk.x < tk.world.x0_cm)
    if tk.known is not None:
        free &= ~tk.known
    if tk.st is not None and tk.st.passed_over:
        free[list(tk.st.passed_over)] = False
    return np.flatnonzero(free)


def _field_to(tk: Tick, x: float, y: float):
    return cost_field(tk.world, x, y)


def start(tk: Tick) -> None:
    """The decision ``pier``: the nearest known failed robot is to be fetched by the closest
    carrier that answers (a new pier at the front when none is under way)."""
    from swarm_sim.behaviour.recruitment import answering

    st, p = tk.st, tk.p
    if not st.piers or st.piers[-1][1] >= p.pier_robots:
        st = evolve(st, piers=st.piers + ((st.front_s_cm, 0),))
        tk.ev("pier_site", st.members[0], s_cm=round(st.front_s_cm, 6), robots_needed=p.pier_robots)
    failed = known_failed_free(tk)
    # the failed robot nearest the structure's rear
    rx, ry = _rear_point(st, p)
    f = int(failed[np.argmin((tk.x[failed] - rx) ** 2 + (tk.y[failed] - ry) ** 2)])
    gx, gy = _pickup_point(tk, f)
    chosen = answering(tk, [_field_to(tk, gx, gy)], list(_carrier_pool(tk)))
    if not chosen:
        tk.st = st
        return
    c = chosen[0]
    tk.mode[c] = _RECRUIT
    tk.mode[f] = _RECRUIT  # it is being moved (by the carrier)
    tk.st = evolve(st, action="pier", pier_job=(c, f), pier_stage="fetch", pier_goal=(gx, gy),
                    pier_best_cm=math.inf, pier_progress_s=tk.t, progress_s=tk.t)
    tk.ev("pier_fetch", c, failed=f)


def _rear_point(st, p) -> tuple[float, float]:
    from swarm_sim.behaviour import structure as S

    n = len(st.members)
    x, y, _, _ = S.slot_pose(st, n, p.robot_length_cm, p.robot_width_cm)
    return x, y


def _pickup_point(tk: Tick, f: int) -> tuple[float, float]:
    """Where the carrier couples to the failed robot: the free spot one length from it on the
    structure's side (else any side)."""
    L = tk.p.robot_length_cm
    fx, fy = float(tk.x[f]), float(tk.y[f])
    rx, ry = _rear_point(tk.st, tk.p)
    base = math.atan2(ry - fy, rx - fx)
    for off in (0.0, 0.8, -0.8, 1.6, -1.6, math.pi):
        a = base + off
        gx, gy = fx + L * math.cos(a), fy + L * math.sin(a)
        if tk.world.pose_ok1(gx, gy, a):
            return gx, gy
    return fx, fy


def advance(tk: Tick) -> None:
    """The ``pier`` action, one step."""
    from swarm_sim.behaviour import structure as S
    from swarm_sim.behaviour.recruitment import slot_field
    from swarm_sim.engine.motion import drive_along

    st, p, world = tk.st, tk.p, tk.world
    c, f = st.pier_job
    L = p.robot_length_cm
    stage = st.pier_stage
    if stage in ("fetch", "tow"):
        if stage == "fetch":
            field = _field_to(tk, *st.pier_goal)
            gx, gy = st.pier_goal
            final_h = math.atan2(float(tk.y[f]) - gy, float(tk.x[f]) - gx)  # facing the failed robot
        else:
            field = slot_field(st, p, world, len(st.members))[0]
            final_h = math.atan2(st.dir_y, st.dir_x)
        rx, ry, rh = float(tk.x[c]), float(tk.y[c]), float(tk.h[c])
        arrived = False
        if tk.is_failed(c, DRIVE) and not tk.is_failed(c, TOTAL):
            tk.detect(c, "reports_cannot_drive")  # the carrier's own drive failed: it says so
            abort(tk, "the carrier's drive failed")
            return
        if tk.is_failed(c, DRIVE):  # silent and still: found when it makes no progress
            nx, ny, nh = rx, ry, rh
        else:
            nx, ny, nh, arrived = drive_along(field, rx, ry, rh, p, world, final_heading=final_h)
        tk.x[c], tk.y[c], tk.h[c] = nx, ny, nh
        if stage == "tow":
            tk.x[f], tk.y[f], tk.h[f] = nx, ny, nh  # the failed robot moves with its carrier
        left = field.cost_at(nx, ny)
        best, since = st.pier_best_cm, st.pier_progress_s
        if left < best - 0.5 * nav_grid(world).cell_cm:
            best, since = left, tk.t
            tk.progress()
        if arrived:
            if stage == "fetch":
                tk.st = evolve(tk.st, pier_stage="tow", pier_best_cm=math.inf, pier_progress_s=tk.t)
            else:
                n_rows = len(st.members)
                ride = (n_rows * L + max(st.front_s_cm, 0.0)) / p.speed_cm_s
                tk.st = evolve(tk.st, pier_stage="carry", pier_until_s=tk.t + p.climb_s_per_layer + ride,
                                progress_s=tk.t)
                tk.ev("pier_carry", c, failed=f)
            return
        if tk.t - since > p.recruit_stall_s:
            abort(tk, "the carrier made no progress")
            return
        tk.st = evolve(tk.st, pier_best_cm=best, pier_progress_s=since)
        return
    # on the structure: the pair rides along its axis (drawn on top of the members)
    dir_h = math.atan2(st.dir_y, st.dir_x)
    rear_x, rear_y = _rear_point(st, p)
    fx_, fy_, _, _ = S.slot_pose(st, 0, L, p.robot_width_cm)
    if stage == "carry":
        left = max(st.pier_until_s - tk.t, 0.0)
        total = max(st.pier_until_s - st.pier_progress_s, 1e-9)
        u = 1.0 - left / total
        for r in (c, f):
            tk.x[r], tk.y[r], tk.h[r] = rear_x + u * (fx_ - rear_x), rear_y + u * (fy_ - rear_y), dir_h
        if left <= 0:
            s_pier, k = st.piers[-1]
            tk.st = evolve(tk.st, pier_stage="lower", pier_progress_s=tk.t,
                            pier_until_s=tk.t + p.climb_s_per_layer * max(1, p.pier_robots - k), progress_s=tk.t)
        return
    if stage == "lower":
        if tk.t + 1e-9 < st.pier_until_s:
            return
        s_pier, k = st.piers[-1]
        px = st.origin_x_cm + (s_pier + 0.5 * L) * st.dir_x
        py = st.origin_y_cm + (s_pier + 0.5 * L) * st.dir_y
        tk.x[f], tk.y[f], tk.h[f] = px, py, dir_h
        tk.mode[f] = _PIER
        tk.sidx[f], tk.sline[f], tk.slayer[f], tk.sopp[f] = 0, -1, -(k + 1), -1
        piers = st.piers[:-1] + ((s_pier, k + 1),)
        ride = (len(st.members) * L + max(st.front_s_cm, 0.0)) / p.speed_cm_s
        tk.st = evolve(tk.st, piers=piers, pier_members=st.pier_members + (f,), pier_stage="return",
                        pier_progress_s=tk.t, pier_until_s=tk.t + ride + p.climb_s_per_layer, progress_s=tk.t)
        tk.ev("pier_lowered", f, pier=len(piers) - 1, robots=k + 1, needed=p.pier_robots)
        if k + 1 >= p.pier_robots:
            tk.ev("pier_complete", f, pier=len(piers) - 1, s_cm=round(s_pier, 6), robots=k + 1)
        return
    if stage == "return":
        left = max(st.pier_until_s - tk.t, 0.0)
        total = max(st.pier_until_s - st.pier_progress_s, 1e-9)
        u = left / total
        tk.x[c], tk.y[c], tk.h[c] = rear_x + u * (fx_ - rear_x), rear_y + u * (fy_ - rear_y), dir_h + math.pi
        if left <= 0:
            from swarm_sim.behaviour.release import release

            release(tk, c, dir_h + math.pi, _EXPLORE)
            tk.disp[c] = 0.0
            tk.st = evolve(tk.st, action="idle", pier_job=(), pier_stage="", progress_s=tk.t)
            tk.ev("pier_carrier_back", c)


def abort(tk: Tick, why: str) -> None:
    """The round is called off (its robots are on the ground: fetch or tow): both are free
    again where they stand; the failed one is still known."""
    st = tk.st
    c, f = st.pier_job
    tk.mode[c] = _EXPLORE
    tk.mode[f] = _EXPLORE
    tk.st = evolve(st, action="idle", pier_job=(), pier_stage="", passed_over=st.passed_over + (c,))
    tk.ev("pier_aborted", c, failed=f, why=why)


def carried(st) -> list[int]:
    """Robots a pier round holds on the structure (they are over the void only on its top)."""
    if not st.pier_job or st.pier_stage in ("fetch", "tow"):
        return []
    c, f = st.pier_job
    return [c] if st.pier_stage == "return" else [c, f]


__all__ = ["STAGES", "abort", "advance", "carried", "complete", "known_failed_free", "ready", "robots_per_pier",
           "move_ok", "rule_frame", "stable_at", "start"]
