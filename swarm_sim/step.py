"""One simulation step: ``step(state, params, world, rng) -> state`` (inputs are not mutated).

Order within a step (dt = ``params.dt_s``):
1. seed detection (search phase): an initial explorer whose ground sensor sees the
   void becomes the seed (ties: the one nearest the void) and the ``void found``
   broadcast stops others from seeding;
2. free robots walk (vectorised over the walking modes, :mod:`swarm_sim.explore`);
3. the structure acts (:mod:`swarm_sim.structure`): align, decide, move, recruit, release;
4. the target check, the post-retreat wander clock and the timeout.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from . import structure as S
from . import taper as T
from .explore import walk
from .params import Params, at_level
from .state import OPEN, WALKING_MODES, Mode, Phase, Structure, SwarmState
from .world import World, wrap

_EXPLORE = int(Mode.EXPLORE)
_SEED = int(Mode.SEED)
_RECRUIT = int(Mode.RECRUIT)
_MEMBER = int(Mode.MEMBER)
_TARGET = int(Mode.TARGET)
_RETREAT = int(Mode.RETREAT)
_STOPPED = int(Mode.STOPPED)
_P_SEARCH = int(Phase.SEARCH)
_P_BUILD = int(Phase.BUILD)
_P_DELIVERED = int(Phase.DELIVERED)
_P_WANDER = int(Phase.WANDER)
_P_SUCCESS = int(Phase.SUCCESS)
_P_RETREATED = int(Phase.RETREATED)
_P_TIMEOUT = int(Phase.TIMEOUT)
EPS_MOVE = 1e-9
DISPERSE_S = 2.0  # released robots drive straight away from the structure this long
ENDED = (_P_SUCCESS, _P_RETREATED, _P_TIMEOUT)
WALKING_LUT = np.zeros(len(Mode), dtype=bool)
WALKING_LUT[list(WALKING_MODES)] = True


def _goto(x, y, h, tx, ty, p: Params, world: World, final_heading: float | None = None,
          align_h: float | None = None):
    """Drive one robot one step towards (tx, ty): turn (limited), then drive; stays off hazards."""
    dist = p.speed_cm_s * p.dt_s
    dx, dy = tx - x, ty - y
    r = math.hypot(dx, dy)
    if r < 1e-9:
        if final_heading is None:
            return x, y, h, True
        d = float(wrap(np.array(final_heading - h)))
        nh = h + max(-p.turn_max_rad, min(p.turn_max_rad, d))
        return x, y, nh, abs(d) <= p.turn_max_rad
    want = math.atan2(dy, dx)
    d = float(wrap(np.array(want - h)))
    nh = h + max(-p.turn_max_rad, min(p.turn_max_rad, d))
    if abs(d) > p.turn_max_rad + 1e-12:
        if world.pose_ok1(x, y, nh):
            return x, y, nh, False
        return _slide_off(x, y, h, dist, world)
    step = min(dist, r)
    # straight at the goal, else skirt an obstacle/edge at 45 or 90 degrees
    for off in (0.0, math.pi / 4, -math.pi / 4, math.pi / 2, -math.pi / 2):
        a = want + off
        nx, ny = x + step * math.cos(a), y + step * math.sin(a)
        if world.pose_ok1(nx, ny, a):
            return nx, ny, a, False
    if world.pose_ok1(x, y, want):
        return x, y, want, False
    # cramped (wall or edge too close to turn): creep towards the goal keeping the heading,
    # standing for the small forward/back shuffles a differential drive makes
    headings = [h]
    if align_h is not None:
        da = float(wrap(np.array(align_h - h)))
        headings.insert(0, h + max(-p.turn_max_rad, min(p.turn_max_rad, da)))
    for hh in headings:
        nx, ny = x + step * dx / r, y + step * dy / r
        if world.pose_ok1(nx, ny, hh):
            return nx, ny, hh, False
        if world.pose_ok1(x, y, hh) and hh != h:
            return x, y, hh, False
    return _slide_off(x, y, h, dist, world)


def _slide_off(x, y, h, dist, world: World):
    """Edge reflex: too close to the void to turn: back away from the edge one step."""
    mid = 0.5 * (world.x0_cm + world.x1_cm)
    sx = x - dist if x < mid else x + dist
    if world.pose_ok1(sx, y, h):
        return sx, y, h, False
    return x, y, h, False


def _geometry(st: Structure, p: Params) -> T.ShellGeometry | None:
    """The shell geometry of a tapered level (None for the other structures)."""
    lp = S.level_params(p, st)
    if not lp.taper_block_rows:
        return None
    return T.shell_geometry(lp.layers, lp.taper_block_rows, p.void_width)


def _place_members(arr, st: Structure, p: Params):
    x, y, h, idx, sline, slayer, sopp = arr
    if st.members:
        ids, m = S.occupied(st)
        mx, my, mh = S.member_poses(st, p.robot_length_cm, p.robot_width_cm, m)
        x[ids], y[ids], h[ids] = mx, my, mh
        k = S.row_size(st)
        if k == 1:
            idx[ids] = m + 1
            sline[ids] = 0
            slayer[ids] = 0
        else:
            idx[ids] = m // k + 1
            sline[ids] = (m % k) % st.lines
            slayer[ids] = (m % k) // st.lines
        sopp[ids] = 0
    if st.shell:
        g = _geometry(st, p)
        sh = np.asarray(st.shell, dtype=np.int64)
        slots = np.flatnonzero(sh != OPEN)
        if slots.size:
            ids = sh[slots]
            x[ids], y[ids] = T.slot_xy(st, g, p.robot_length_cm, p.robot_width_cm, slots)
            h[ids] = math.atan2(st.dir_y, st.dir_x)
            idx[ids] = g.pos[slots] + 1
            sline[ids] = g.q[slots]
            slayer[ids] = g.z[slots]
            sopp[ids] = g.foot[slots]


def _release(r: int, away: float, mode, sidx, sline, slayer, sopp, goal, run_left, disp, rng, new_mode: int):
    """A robot leaves the structure and walks off (``away``: heading it disperses around)."""
    mode[r] = new_mode
    sidx[r], sline[r], slayer[r], sopp[r] = 0, -1, -1, -1
    u = rng.random(2)
    goal[r] = away + (1 if u[0] < 0.5 else -1) * (0.35 + 0.7 * u[1])
    run_left[r] = 0.0
    disp[r] = DISPERSE_S


def _foot_job(st: Structure, p: Params, t: float, x, y, h, mode, sidx, sline, slayer, sopp, goal, run_left,
              disp, rng, world: World, ev) -> Structure:
    """Advance the foot job (fill or dissolve a group of shell columns, one robot per column)."""
    g = _geometry(st, p)
    L, W = p.robot_length_cm, p.robot_width_cm
    dir_h = math.atan2(st.dir_y, st.dir_x)
    if st.job_stage == "drive":
        arrived = True
        for r, c in zip(st.job, st.job_cols, strict=True):
            tx, ty = T.staging_xy(st, g, L, W, c)
            rx, ry, rh = float(x[r]), float(y[r]), float(h[r])
            if rx == tx and ry == ty and rh == dir_h:
                continue
            arrived = False
            nx, ny, nh, done = _goto(rx, ry, rh, tx, ty, p, world, final_heading=dir_h, align_h=dir_h)
            if done and math.hypot(nx - tx, ny - ty) < 1e-9:
                nx, ny, nh = tx, ty, dir_h
            x[r], y[r], h[r] = nx, ny, nh
        if arrived:
            zmax = max(int(g.col_z[c]) for c in st.job_cols)
            st = replace(st, job_stage="climb", job_until_s=t + zmax * p.climb_s_per_layer + L / p.speed_cm_s)
        return st
    if t + 1e-9 < st.job_until_s:
        return st
    shell = list(st.shell)
    if st.job_kind.startswith("fill"):
        for r, c in zip(st.job, st.job_cols, strict=True):
            T.fill_column(shell, g, c, r)
            mode[r] = _MEMBER
        ev(st.job_kind, st.job[0], robots=list(st.job), columns=list(st.job_cols))
    else:
        near = st.job_kind == "unfill_near"
        new_mode = (_RETREAT if st.retreating else _EXPLORE) if near else _TARGET
        away = dir_h + (math.pi if near else 0.0)
        for c in st.job_cols:
            r = T.pop_column(shell, g, c)
            x[r], y[r] = T.staging_xy(st, g, L, W, c)
            h[r] = dir_h + (math.pi if near else 0.0)
            _release(r, away, mode, sidx, sline, slayer, sopp, goal, run_left, disp, rng, new_mode)
            if new_mode == _EXPLORE:
                disp[r] = 0.0
        ev(st.job_kind, st.job[0], robots=list(st.job), columns=list(st.job_cols))
    return replace(st, shell=tuple(shell), job=(), job_cols=(), job_kind="", job_stage="", job_until_s=0.0)


def step(state: SwarmState, p: Params, world: World, rng: np.random.Generator,
         use_numba: bool | None = None) -> SwarmState:
    if state.phase in ENDED:
        return state
    t = state.t_s + p.dt_s
    mode = state.mode.copy()
    sidx = state.struct_index.copy()
    sline = state.struct_line.copy()
    slayer = state.struct_layer.copy()
    sopp = (state.struct_opposite.copy() if state.struct_opposite is not None
            else np.full(state.n, -1, dtype=np.int8))
    disp = state.disperse_left_s.copy()
    st = state.structure
    new = state
    events: list = []

    def ev(kind, robot=-1, **data):
        events.append((round(t, 6), kind, int(robot), data))

    phase, phase_since = state.phase, state.phase_since_s
    seed_robot, seed_pos = state.seed_robot, state.seed_position

    # 1. seed detection
    if phase == _P_SEARCH:
        cand = np.flatnonzero(mode == _EXPLORE)
        if cand.size:
            sees = world.void_ahead(state.x_cm[cand], state.y_cm[cand], state.heading_rad[cand])
            if sees.any():
                c = cand[sees]
                seed = int(c[np.argmax(state.x_cm[c])])
                mode[seed] = _SEED
                sidx[seed] = 1
                st = Structure(members=(seed,), origin_x_cm=world.x0_cm, origin_y_cm=float(state.y_cm[seed]),
                               dir_x=1.0, dir_y=0.0, front_s_cm=0.0, action="align",
                               lines=2 if p.taper_block_rows else p.lines,
                               layers=1 if p.taper_block_rows else p.layers,
                               lateral_sign=1.0 if state.y_cm[seed] < 0.5 * world.h_cm else -1.0)
                phase, phase_since, seed_robot = _P_BUILD, t, seed
                ev("seed", seed, x_cm=float(state.x_cm[seed]), y_cm=float(state.y_cm[seed]))

    # 2. walkers
    walking = WALKING_LUT[mode]
    if phase != _P_SEARCH and p.case in ("A", "B"):
        walking &= mode != _EXPLORE  # cases A, B: free robots stop once the void is found (Ch. 4.5)
    walkers = np.flatnonzero(walking)
    x, y, h, goal, run_left = walk(state.x_cm, state.y_cm, state.heading_rad, state.goal_heading_rad,
                                   state.run_left_cm, walkers, disp[walkers] > 0, world, p, rng, use_numba)
    disp = np.maximum(disp - p.dt_s, 0.0)

    # 3. the structure
    if st is not None and phase == _P_BUILD:
        L = p.robot_length_cm
        dist = p.speed_cm_s * p.dt_s
        if st.action == "align":
            s0 = st.members[0]
            dir_h = math.atan2(st.dir_y, st.dir_x)
            hx, hy, hh = float(x[s0]), float(y[s0]), float(h[s0])
            d = float(wrap(np.array(dir_h - hh)))
            if abs(d) > 1e-9:
                nh = hh + max(-p.turn_max_rad, min(p.turn_max_rad, d))
                if world.pose_ok1(hx, hy, nh):
                    h[s0] = nh
                else:  # too close to the edge to turn: back away from it first
                    x[s0] = hx - dist * st.dir_x
                    y[s0] = hy - dist * st.dir_y
            else:
                h[s0] = dir_h
                gap = (world.x0_cm - 0.5 * L) - hx  # distance to the aligned pose
                if gap > dist:
                    x[s0] = hx + dist
                else:
                    st = replace(st, origin_y_cm=hy, front_s_cm=0.0, action="idle")
                    mode[s0] = _MEMBER
                    seed_pos = (round(world.x0_cm - 0.5 * L, 6), round(hy, 6))
                    ev("aligned", s0, x_cm=seed_pos[0], y_cm=seed_pos[1])
        elif st.action == "wait":
            if t >= st.wait_until_s:
                st = replace(st, action="idle")
        elif st.action in ("advance", "back"):
            sgn = 1.0 if st.action == "advance" else -1.0
            f = st.front_s_cm + sgn * dist
            if (f - st.goal_s_cm) * sgn >= -EPS_MOVE:
                f = st.goal_s_cm
                st = replace(st, front_s_cm=f, action="idle")
            else:
                st = replace(st, front_s_cm=f)
            if not st.landed and st.front_s_cm + world.detect_cm >= p.void_width_cm - 1e-6:
                st = replace(st, landed=True)
                ev("far_ledge", st.members[0], front_s_cm=round(st.front_s_cm, 6))
        elif st.action == "recruit":
            dir_h = math.atan2(st.dir_y, st.dir_x)
            arrived_all = True
            for r, slot in zip(st.recruits, st.recruit_slots, strict=True):
                dxp, dyp, _, _ = S.slot_pose(st, slot, L, p.robot_width_cm)
                stage_back = min(2 * L, max(0.0, (dxp - world.body_radius_cm - 0.5) * st.dir_x
                                            if st.dir_x > 0 else 2 * L))
                wxp, wyp = dxp - stage_back * st.dir_x, dyp - stage_back * st.dir_y
                rx, ry, rh = float(x[r]), float(y[r]), float(h[r])
                if rx == dxp and ry == dyp and rh == dir_h:
                    continue
                arrived_all = False
                on_axis = abs((ry - dyp) * st.dir_x - (rx - dxp) * st.dir_y) < 1e-6 and \
                    (dxp - rx) * st.dir_x + (dyp - ry) * st.dir_y >= -1e-6
                if not on_axis:
                    nx, ny, nh, _ = _goto(rx, ry, rh, wxp, wyp, p, world, align_h=dir_h)
                else:
                    nx, ny, nh, arrived = _goto(rx, ry, rh, dxp, dyp, p, world, final_heading=dir_h, align_h=dir_h)
                    if arrived and math.hypot(nx - dxp, ny - dyp) < 1e-9:
                        nx, ny, nh = dxp, dyp, dir_h
                x[r], y[r], h[r] = nx, ny, nh
            if arrived_all:
                if S.filling(st):
                    # a new line/layer grows from the rear: its robots slide forward one row
                    # along the core and the recruit takes the rear slot (kinematic)
                    members = list(st.members)
                    k = S.row_size(st)
                    for r, slot in zip(st.recruits, st.recruit_slots, strict=True):
                        col = members[slot % k::k]
                        members[slot % k::k] = col[1:] + [r]
                    members = tuple(members)
                else:
                    members = st.members + st.recruits
                for r in st.recruits:
                    mode[r] = _MEMBER
                ev("dock", st.recruits[0], index=len(members), robots=list(st.recruits))
                st = replace(st, members=members, recruits=(), recruit_slots=(), action="idle")
            elif t - st.recruit_since_s > p.recruit_timeout_s:
                for r in st.recruits:
                    mode[r] = _EXPLORE
                ev("recruit_timeout", st.recruits[0], robots=list(st.recruits))
                st = replace(st, recruits=(), recruit_slots=(), action="idle")
        if st.job and st.action != "align":
            st = _foot_job(st, p, t, x, y, h, mode, sidx, sline, slayer, sopp, goal, run_left, disp, rng, world, ev)
        if st.action == "idle":
            free = np.flatnonzero(mode == _EXPLORE)
            k = S.row_size(st)
            if S.filling(st):
                # after a switch: one robot for each new line/layer, docking at the rear row
                rear = (S.all_rows(st) - 1) * k
                slot_ids = [rear + q for q in S.open_columns(st)]
                enough = free.size >= 1
            else:
                n_slots = k - len(st.members) % k if len(st.members) % k else k
                slot_ids = [len(st.members) + q for q in range(n_slots)]
                enough = free.size >= n_slots
            slots = [S.slot_pose(st, q, L, p.robot_width_cm) for q in slot_ids]
            dock_ok = all(world.pose_ok1(sx_, sy_, 0.0) for sx_, sy_, _, _ in slots)
            # a row is recruited whole (assumption 5 of Ch. 5.4: several robots at once)
            g = _geometry(st, p)
            if g is not None:
                if not st.shell:
                    st = replace(st, shell=T.empty_shell(g))
                if st.job and (st.retreating or not st.landed):
                    action, sit = "hold", None  # the tables' first row, without computing the rest
                else:
                    action, sit = T.decide(st, S.level_params(p, st), g, int(free.size), enough, dock_ok)
            else:
                action, sit = S.decide(st, p, enough, dock_ok)
            if action == "release_front":
                row = [r for r in st.members[:k] if r != OPEN]
                # the row leaves from where the structure stands now (this step's move included)
                fslots = np.flatnonzero(np.asarray(st.members[:k]) != OPEN)
                x[row], y[row], _ = S.member_poses(st, L, p.robot_width_cm, fslots)
                members = st.members[k:]
                far_cols = T.next_fill_group(st.shell, g, T.FAR) if g is not None else ()
                to_far = row[:len(far_cols)]
                for fr in row[len(to_far):]:
                    # turns there through the walk (the edge reflex guards the body)
                    _release(fr, math.atan2(st.dir_y, st.dir_x), mode, sidx, sline, slayer, sopp, goal, run_left,
                             disp, rng, _TARGET)
                for fr in to_far:  # Table 5.1 O-roles: a released core robot joins the far foot
                    mode[fr] = _RECRUIT
                    sidx[fr], sline[fr], slayer[fr], sopp[fr] = 0, -1, -1, 1
                st = replace(st, members=members, front_s_cm=st.front_s_cm - L, action="wait",
                             wait_until_s=t + p.release_clear_s)
                if to_far:
                    st = replace(st, job=tuple(to_far), job_cols=tuple(far_cols[:len(to_far)]), job_kind="fill_far",
                                 job_stage="drive", job_until_s=0.0)
                ev("release_front", row[0], n_left=len(members), robots=list(row), to_far_foot=list(to_far))
            elif action == "hold":
                pass
            elif action in ("fill_near", "unfill_near", "dissolve_far"):
                if action == "fill_near":
                    cols = T.next_fill_group(st.shell, g, T.NEAR)[:free.size]
                    chosen: list[int] = []
                    pool = list(free)
                    for c in cols:  # the closest free robot to each column's staging point
                        sx_, sy_ = T.staging_xy(st, g, L, p.robot_width_cm, c)
                        d2 = (x[pool] - sx_) ** 2 + (y[pool] - sy_) ** 2
                        chosen.append(int(pool.pop(int(np.argmin(d2)))))
                    for r in chosen:
                        mode[r] = _RECRUIT
                    st = replace(st, job=tuple(chosen), job_cols=tuple(cols), job_kind=action, job_stage="drive")
                else:
                    cols = T.next_unfill_group(st.shell, g, T.NEAR if action == "unfill_near" else T.FAR)
                    prev = list(st.shell)
                    robots = tuple(T.pop_column(prev, g, c) for c in cols)
                    zmax = max(int(g.col_z[c]) for c in cols)
                    st = replace(st, job=robots, job_cols=tuple(cols), job_kind=action, job_stage="climb",
                                 job_until_s=t + zmax * p.climb_s_per_layer + L / p.speed_cm_s)
                ev(action + "_start", st.job[0], robots=list(st.job), columns=list(st.job_cols))
            elif action == "release_rear":
                cut = len(st.members) % k or k
                row = [r for r in st.members[-cut:] if r != OPEN]
                members = st.members[:-cut]
                for rr in row:
                    mode[rr] = _RETREAT
                    sidx[rr], sline[rr], slayer[rr] = 0, -1, -1
                    u = rng.random(2)
                    ang = math.atan2(-st.dir_y, -st.dir_x) + (1 if u[0] < 0.5 else -1) * (0.35 + 0.7 * u[1])
                    goal[rr] = ang
                    run_left[rr] = 0.0
                    disp[rr] = DISPERSE_S
                st = replace(st, members=members, action="wait", wait_until_s=t + p.release_clear_s)
                ev("release_rear", row[0], n_left=len(members), robots=list(row))
            elif action == "advance":
                st = replace(st, action="advance", goal_s_cm=st.front_s_cm + L)
                ev("advance", st.members[0], n_p=sit.counts.n_p, n_g=sit.counts.n_g, n_o=sit.counts.n_o)
            elif action == "back":
                st = replace(st, action="back", goal_s_cm=st.front_s_cm - L)
            elif action == "recruit":
                chosen: list[int] = []
                pool = list(free)
                for sx_, sy_, _, _ in slots[:len(pool)]:  # closest free robot to each slot
                    d2 = (x[pool] - sx_) ** 2 + (y[pool] - sy_) ** 2
                    chosen.append(int(pool.pop(int(np.argmin(d2)))))
                for r in chosen:
                    mode[r] = _RECRUIT
                st = replace(st, action="recruit", recruits=tuple(chosen), recruit_slots=tuple(slot_ids[:len(chosen)]),
                             recruit_since_s=t)
                ev("recruit", chosen[0], n=len(st.members), robots=chosen)
            elif action == "switch":
                nxt = st.level + 1
                pl = at_level(p, nxt)
                if pl.taper_block_rows:
                    # a tapering arch: the core is (or becomes) two lines; the feet are shell data
                    g_new = T.shell_geometry(pl.layers, pl.taper_block_rows, p.void_width)
                    shell = T.remap_shell(st.shell, g, g_new) if (g is not None and st.shell) else T.empty_shell(g_new)
                    members = st.members if st.lines == 2 and st.layers == 1 else S.widened(st, 2, 1)
                    _, sy = T.slot_xy(st, g_new, L, p.robot_width_cm, np.arange(g_new.n))
                    hw = 0.5 * p.robot_width_cm
                    if sy.min() - hw < -1e-6 or sy.max() + hw > world.h_cm + 1e-6:
                        # the feet would stick out of the arena beside this core line: give up
                        st = replace(st, retreating=True)
                        ev("retreat", st.members[0], n=len(st.members), n_p=sit.counts.n_p, n_g=sit.counts.n_g,
                           free=int(free.size), why="no_room_for_the_feet")
                    else:
                        st = replace(st, members=members, lines=2, layers=1, level=nxt, shell=shell)
                else:
                    st = replace(st, members=S.widened(st, pl.lines, pl.layers), lines=pl.lines, layers=pl.layers,
                                 level=nxt)
                if not st.retreating:
                    ev("switch", st.members[0], level=pl.level_name, lines=pl.lines, layers=pl.layers,
                       n_p=sit.counts.n_p, n_g=sit.counts.n_g, rows=S.all_rows(st))
            elif action == "retreat":
                st = replace(st, retreating=True)
                ev("retreat", st.members[0] if st.members else -1,
                   n=len(st.members), n_p=sit.counts.n_p, n_g=sit.counts.n_g, free=int(free.size),
                   why="span" if sit.span_blocked and not sit.filling else "no_free_robot")
        if st.action in ("wait", "idle") and not st.members and not st.job and all(r == OPEN for r in st.shell):
            # the structure is gone
            if st.retreating:
                phase, phase_since = _P_WANDER, t
                ev("dissolved", retreated=True)
                m = (mode == _EXPLORE) | (mode == _RECRUIT)
                mode[m] = _RETREAT
            else:
                phase, phase_since = _P_DELIVERED, t
                ev("dissolved", retreated=False)
            st = None
        if st is not None and st.action != "align":
            _place_members((x, y, h, sidx, sline, slayer, sopp), st, p)

    # 4. target, wander clock, timeout
    target_finder = state.target_finder
    if phase in (_P_BUILD, _P_DELIVERED) and target_finder < 0:
        tg = np.flatnonzero(mode == _TARGET)
        if tg.size:
            d2 = (x[tg] - world.target_x_cm) ** 2 + (y[tg] - world.target_y_cm) ** 2
            hit = d2 <= world.target_found_cm ** 2
            if hit.any():
                target_finder = int(tg[hit][np.argmin(d2[hit])])
                ev("target_found", target_finder)
    # the run succeeds once the target is found (finish_delivery: and the structure has
    # delivered everyone and dissolved, so the disassembly time is measured)
    if target_finder >= 0 and phase in (_P_BUILD, _P_DELIVERED) and (
            not p.finish_delivery or phase == _P_DELIVERED):
        phase, phase_since = _P_SUCCESS, t
        mode[WALKING_LUT[mode]] = _STOPPED
    if phase == _P_WANDER and t - phase_since >= p.wander_after_retreat_s - 1e-9:
        phase, phase_since = _P_RETREATED, t
        mode[:] = _STOPPED
        ev("stopped")
    if phase not in ENDED and t >= p.max_time_s - 1e-9:
        phase, phase_since = _P_TIMEOUT, t
        ev("timeout")

    new = replace(state, x_cm=x, y_cm=y, heading_rad=h, goal_heading_rad=goal, run_left_cm=run_left,
                  mode=mode, struct_index=sidx, struct_line=sline, struct_layer=slayer, struct_opposite=sopp,
                  disperse_left_s=disp, t_s=t, step=state.step + 1,
                  phase=int(phase), phase_since_s=phase_since, structure=st, seed_robot=seed_robot,
                  seed_position=seed_pos, target_finder=target_finder,
                  events=state.events + tuple(events) if events else state.events)
    return new

