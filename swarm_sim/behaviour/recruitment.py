"""Recruitment: calling free robots to the structure's rear and bringing them in to dock.

* **Who is called.** For each open rear slot, the free robot (``mode == EXPLORE``) with the
  shortest *path* to the slot's approach point (:mod:`swarm_sim.engine.navigation`: walls,
  obstacles, the void and the structure's robots are in the way), never one that already
  failed to reach this dock (``Structure.passed_over``, cleared by the next dock). A robot
  with no path is never called. A row is recruited whole (Ch. 5.4, assumption 5).
* **The approach.** The recruit follows its path to the approach point, up to
  :data:`STAGE_BACK_L` robot lengths straight behind the dock point (nearer when an
  obstacle or a wall is in the way; beside it when an obstacle sits right behind it, see
  :func:`approach_point`), turns towards the dock point and drives straight in (the IR-guided docking of Ch. 3, as an exact placement).
  The thesis's assumption 13 (Ch. 4.4: obstacles met while the structure moves are
  ignored, it cannot be steered) is honoured explicitly: the structure, its dock points
  and the last straight drive in are checked against the walls and the void only
  (:attr:`World.without_obstacles`); everything before it avoids the obstacles.
* **Hand-over.** A recruit whose remaining path has not shortened by half a grid cell for
  ``recruit_stall_s`` is released (it walks again) and the next closest free robot is
  called for its slot. When no free robot is left that can be called, the recruitment is
  called off and the structure retreats (``why = "stalled"``; :mod:`swarm_sim.behaviour.retreat`).
"""

from __future__ import annotations

import math

import numpy as np

from swarm_sim.behaviour import structure as S
from swarm_sim.behaviour.retreat import start_retreat
from swarm_sim.engine.motion import drive_along, goto
from swarm_sim.engine.navigation import (
    _FIELDS,
    CostField,
    cost_field,
    disc_clear,
    footprint_mask,
    nav_grid,
)
from swarm_sim.engine.tick import Tick
from swarm_sim.engine.world import World
from swarm_sim.faults import DRIVE, TOTAL
from swarm_sim.params import Params
from swarm_sim.state import OPEN, Mode, Structure, evolve

_EXPLORE, _RECRUIT, _MEMBER = int(Mode.EXPLORE), int(Mode.RECRUIT), int(Mode.MEMBER)

#: the approach starts at most this many robot lengths straight behind the dock point
STAGE_BACK_L = 2.0


_APPROACH: dict = {}


def approach_point(world: World, dock_x: float, dock_y: float, dir_x: float, dir_y: float,
                   L: float) -> tuple[float, float]:
    """Where a recruit turns onto the structure's axis: the farthest point up to
    ``STAGE_BACK_L`` lengths behind the dock point where it can turn on the spot (clear of
    walls, obstacles, the void and of the structure's rear robot one length ahead of the
    dock point) and from which the straight drive in is clear (cm). Nearer points, where
    turning grazes the rear robot, only when there is none; the dock point itself last."""
    key = (id(world), dock_x, dock_y, dir_x, dir_y, L)
    hit = _APPROACH.get(key)
    if hit is not None and hit[0] is world:
        return hit[1]
    if len(_APPROACH) > 4096:
        _APPROACH.clear()
    out = _approach_point(world, dock_x, dock_y, dir_x, dir_y, L)
    _APPROACH[key] = (world, out)
    return out


def _segment_ok(world: World, ax: float, ay: float, bx: float, by: float) -> bool:
    """The straight drive from (ax, ay) to (bx, by), heading along it, keeps off walls and void."""
    r = math.hypot(bx - ax, by - ay)
    if r < 1e-9:
        return world.pose_ok1(bx, by, 0.0)
    h = math.atan2(by - ay, bx - ax)
    n = max(2, int(r) + 1)
    return all(world.pose_ok1(ax + (bx - ax) * k / n, ay + (by - ay) * k / n, h) for k in range(n + 1))


def _approach_point(world: World, dock_x: float, dock_y: float, dir_x: float, dir_y: float,
                    L: float) -> tuple[float, float]:
    free = world.without_obstacles  # docking is part of the structure: assumption 13
    steps = 32
    b_clear = world.body_radius_cm + 0.5 * world.length_cm - L  # turning clears the rear robot
    near = []
    for i in range(steps, 0, -1):  # straight behind the dock, farthest first
        b = STAGE_BACK_L * L * i / steps
        ax, ay = dock_x - b * dir_x, dock_y - b * dir_y
        if disc_clear(world, ax, ay) and _segment_ok(free, ax, ay, dock_x, dock_y):
            if b >= b_clear:
                return ax, ay
            near.append((ax, ay))
    if near:
        return near[0]
    # an obstacle sits behind the dock: turn where the ground is clear beside it, nearest first,
    # behind the dock before beside it (never ahead: the structure is there), then drive in
    back = math.atan2(-dir_y, -dir_x)
    for rad in (0.5 * L, L, 1.5 * L, 2 * L, 2.5 * L, 3 * L):
        for off in (0.0, 0.5, -0.5, 1.0, -1.0, 1.4, -1.4):
            a = back + off
            ax, ay = dock_x + rad * math.cos(a), dock_y + rad * math.sin(a)
            if disc_clear(world, ax, ay) and _segment_ok(free, ax, ay, dock_x, dock_y):
                return ax, ay
    return dock_x, dock_y


def footprint(st: Structure, p: Params, world: World):
    """The structure's core robots as closed grid cells (a function computing the mask, for
    :func:`~swarm_sim.engine.navigation.cost_field`) and a key naming them (for its cache)."""
    _, slots = S.occupied(st)
    mx, my, _ = S.member_poses(st, p.robot_length_cm, p.robot_width_cm, slots)
    mx, my = np.atleast_1d(mx), np.atleast_1d(my)
    key = np.round(np.stack([mx, my]), 3).tobytes()
    # a robot's centre stays a body's size away from a member's (they would touch)
    reach = 0.5 * (p.robot_length_cm + p.robot_width_cm) - 0.5
    return (lambda: footprint_mask(nav_grid(world), mx, my, reach, reach)), key


_SLOT_FIELDS: dict = {}


def slot_field(st: Structure, p: Params, world: World, slot: int) -> tuple[CostField, float, float]:
    """The cost field towards slot ``slot``'s approach point, and the dock point (cm)."""
    key = (id(world), st.members, st.front_s_cm, st.origin_x_cm, st.origin_y_cm, st.dir_x, st.dir_y, st.lines,
           st.layers, st.lateral_sign, slot, p.robot_length_cm, p.robot_width_cm)
    hit = _SLOT_FIELDS.get(key)
    if hit is not None and hit[0] is world:
        return hit[1]
    if len(_SLOT_FIELDS) > 256:
        _SLOT_FIELDS.clear()
    out = _slot_field(st, p, world, slot)
    _SLOT_FIELDS[key] = (world, out)
    return out


def forget_fields() -> None:
    """Forget every cost field made so far (the slot fields here and
    :mod:`swarm_sim.engine.navigation`'s cache): the next run computes each field it asks for. A
    benchmark calls this before each timed run so no run finds another's fields."""
    _SLOT_FIELDS.clear()
    _FIELDS.clear()


def _slot_field(st: Structure, p: Params, world: World, slot: int) -> tuple[CostField, float, float]:
    dx, dy, _, _ = S.slot_pose(st, slot, p.robot_length_cm, p.robot_width_cm)
    ax, ay = approach_point(world, dx, dy, st.dir_x, st.dir_y, p.robot_length_cm)
    mask, key = footprint(st, p, world)
    return cost_field(world, ax, ay, mask, key), dx, dy


def path_costs(field: CostField, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Path length (cm) of each robot to the field's goal (``inf``: no path)."""
    return field.path_costs(x, y)


def closest(fields: list[CostField], pool: list[int], x: np.ndarray, y: np.ndarray) -> list[int]:
    """For each field in turn, the robot of ``pool`` with the shortest path to its goal (each
    robot once); stops at the first field no remaining robot can reach."""
    pool = list(pool)
    chosen: list[int] = []
    for f in fields:
        if not pool:
            break
        i, _ = f.nearest(x[pool], y[pool])  # the argmin of path_costs, settling no farther than it needs
        if i < 0:
            break
        chosen.append(int(pool.pop(i)))
    return chosen


def candidates(tk: Tick) -> np.ndarray:
    """Free robots that may be called (not passed over for this dock, not known to have failed)."""
    return free_robots(tk.mode, tk.st, tk.known)


def free_robots(mode: np.ndarray, st: Structure | None, known: np.ndarray | None) -> np.ndarray:
    """:func:`candidates` from the state's arrays (``known``: robots known to have failed)."""
    free = mode == _EXPLORE
    if st is not None and st.passed_over:
        free[list(st.passed_over)] = False
    if known is not None:
        free &= ~known
    return np.flatnonzero(free)


def answering(tk: Tick, fields: list[CostField], pool: list[int]) -> list[int]:
    """:func:`closest`, then the call: a robot that does not answer (a total failure) or answers
    that it cannot drive (it knows from its own wheels) is known to have failed and the next
    closest is called instead."""
    pool = list(pool)
    while True:
        chosen = closest(fields, pool, tk.x, tk.y)
        bad = [r for r in chosen if tk.is_failed(r, DRIVE)]
        if not bad:
            return chosen
        for r in bad:
            tk.detect(r, "no_reply_to_call" if tk.is_failed(r, TOTAL) else "replied_cannot_drive")
            pool.remove(r)


def call(tk: Tick, slot_ids: list[int]) -> list[int]:
    """Call the closest free robots to ``slot_ids`` (fewer when fewer can reach them); the
    structure's action becomes ``recruit``."""
    st, p = tk.st, tk.p
    fields = [slot_field(st, p, tk.world, q)[0] for q in slot_ids]
    chosen = answering(tk, fields, list(candidates(tk)))
    if not chosen:
        return chosen
    tk.mode[chosen] = _RECRUIT
    n = len(chosen)
    tk.st = evolve(st, action="recruit", recruits=tuple(chosen), recruit_slots=tuple(slot_ids[:n]),
                    recruit_best_cm=(math.inf,) * n, recruit_progress_s=(tk.t,) * n,
                    recruit_final=(False,) * n)
    tk.ev("recruit", chosen[0], n=len(st.members), robots=chosen)
    return chosen


def approach(tk: Tick) -> None:
    """The ``recruit`` action, one step: every recruit drives towards its dock point (its path
    to the approach point, then straight in); a stalled one is handed over; when all have
    arrived they dock (:func:`dock`)."""
    st, p, world = tk.st, tk.p, tk.world
    dir_h = math.atan2(st.dir_y, st.dir_x)
    arrived_all = True
    best, since, final = list(st.recruit_best_cm), list(st.recruit_progress_s), list(st.recruit_final)
    stalled: list[int] = []
    half_cell = 0.5 * nav_grid(world).cell_cm
    for i, (r, slot) in enumerate(zip(st.recruits, st.recruit_slots, strict=True)):
        field, dxp, dyp = slot_field(st, p, world, slot)
        rx, ry, rh = float(tk.x[r]), float(tk.y[r]), float(tk.h[r])
        if rx == dxp and ry == dyp and rh == dir_h:
            continue
        arrived_all = False
        if tk.is_failed(r, TOTAL):  # silent and still: no motion when called (hand_over detects it)
            if tk.t - since[i] > p.recruit_stall_s:
                stalled.append(i)
            continue
        if tk.is_failed(r, DRIVE):  # its wheels stopped: it tells the structure at once
            tk.detect(r, "reports_cannot_drive")
            stalled.append(i)
            continue
        if final[i]:
            # the drive in is part of the structure, which ignores obstacles (assumption 13)
            nx, ny, nh, arrived = goto(rx, ry, rh, dxp, dyp, p, world.without_obstacles, final_heading=dir_h,
                                       align_h=dir_h)
            if arrived and math.hypot(nx - dxp, ny - dyp) < 1e-9:
                nx, ny, nh = dxp, dyp, dir_h
            left = math.hypot(nx - dxp, ny - dyp)
        else:
            ax, ay = field.goal_x, field.goal_y
            in_h = dir_h if math.hypot(dxp - ax, dyp - ay) < 1e-9 else math.atan2(dyp - ay, dxp - ax)
            nx, ny, nh, final[i] = drive_along(field, rx, ry, rh, p, world, final_heading=in_h, align_h=in_h)
            left = field.cost_at(nx, ny) + math.hypot(ax - dxp, ay - dyp)
        tk.x[r], tk.y[r], tk.h[r] = nx, ny, nh
        if left < best[i] - half_cell:
            best[i], since[i] = left, tk.t
            tk.progress()
        elif tk.t - since[i] > p.recruit_stall_s:
            stalled.append(i)
    best, since, final = tuple(best), tuple(since), tuple(final)
    if (best, since, final) != (st.recruit_best_cm, st.recruit_progress_s, st.recruit_final):
        tk.st = evolve(tk.st, recruit_best_cm=best, recruit_progress_s=since, recruit_final=final)
    if arrived_all:
        dock(tk)
        return
    for i in stalled:
        if not hand_over(tk, i):
            return


def dock(tk: Tick) -> None:
    """All recruits are at their dock points: they join the structure."""
    st = tk.st
    if S.filling(st):
        # a new line/layer grows from the rear: its robots slide forward one row along the
        # core and the recruit takes the rear slot (kinematic)
        members = list(st.members)
        k = S.row_size(st)
        for r, slot in zip(st.recruits, st.recruit_slots, strict=True):
            col = members[slot % k::k]
            members[slot % k::k] = col[1:] + [r]
        members = tuple(members)
    else:
        members = st.members + st.recruits
    tk.mode[list(st.recruits)] = _MEMBER
    tk.ev("dock", st.recruits[0], index=len(members), robots=list(st.recruits))
    tk.st = evolve(st, members=members, recruits=(), recruit_slots=(), recruit_best_cm=(), recruit_progress_s=(),
                    recruit_final=(), passed_over=(), action="idle", progress_s=tk.t)


def hand_over(tk: Tick, i: int) -> bool:
    """Recruit ``i`` made no progress: release it and call the next closest free robot for its
    slot. False (and the recruitment called off, the structure retreating) when none can come."""
    st = tk.st
    r, slot = st.recruits[i], st.recruit_slots[i]
    tk.mode[r] = _EXPLORE
    if tk.is_failed(r, TOTAL):  # no motion, and no answer when the structure asks (a stuck robot answers)
        tk.detect(r, "no_motion_when_called")
    tk.st = st = evolve(st, passed_over=st.passed_over + (r,))
    field = slot_field(st, tk.p, tk.world, slot)[0]
    pool = [int(c) for c in candidates(tk)]
    nxt = answering(tk, [field], pool)
    if not nxt:
        tk.ev("hand_over", r, slot=int(slot), to=-1)
        call_off(tk)
        start_retreat(tk, "stalled")
        return False
    n = nxt[0]
    tk.mode[n] = _RECRUIT
    rec, best, since, fin = (list(st.recruits), list(st.recruit_best_cm), list(st.recruit_progress_s),
                             list(st.recruit_final))
    rec[i], best[i], since[i], fin[i] = n, math.inf, tk.t, False
    tk.st = evolve(st, recruits=tuple(rec), recruit_best_cm=tuple(best), recruit_progress_s=tuple(since),
                    recruit_final=tuple(fin))
    tk.ev("hand_over", r, slot=int(slot), to=n)
    return True


def call_off(tk: Tick) -> None:
    """Every recruit under way goes back to exploring; the structure is idle again."""
    st = tk.st
    if st.recruits:
        tk.mode[list(st.recruits)] = _EXPLORE
    tk.st = evolve(st, recruits=(), recruit_slots=(), recruit_best_cm=(), recruit_progress_s=(), recruit_final=(),
                    action="idle" if st.action == "recruit" else st.action)


def open_slots(st: Structure) -> list[int]:
    """The rear slots the next recruitment fills: after a switch, the open slot of each new
    line/layer in the rear row; else the rest of the rear row (a whole row when it is full)."""
    k = S.row_size(st)
    if S.filling(st):
        rear = (S.all_rows(st) - 1) * k
        return [rear + q for q in S.open_columns(st)]
    n_slots = k - len(st.members) % k if len(st.members) % k else k
    return [len(st.members) + q for q in range(n_slots)]


__all__ = ["approach", "approach_point", "call", "call_off", "candidates", "closest", "dock", "forget_fields",
           "hand_over", "free_robots", "open_slots", "path_costs", "slot_field", "answering", "OPEN"]
