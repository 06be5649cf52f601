"""Release: a robot leaves the structure (the one way it happens) and the two release actions.

* :func:`release` gives the robot its new mode, clears its structure roles (``struct_index``
  0, line/layer/opposite -1: what :mod:`swarm_sim.state` says a free robot has) and sends it
  off around ``away`` (rad) for ``DISPERSE_S`` seconds before it walks again.
* :func:`release_front` (building): the front row leaves onto the target ground
  (``mode TARGET``; on a tapering arch the first of them join the far foot instead);
  the structure slides back one length in its own frame and waits ``release_clear_s``.
* :func:`release_rear` (retreating): the rear row leaves onto the initial ground
  (``mode RETREAT``) and the structure waits ``release_clear_s``.
"""

from __future__ import annotations

import math

import numpy as np

from swarm_sim.behaviour import structure as S
from swarm_sim.behaviour import taper as T
from swarm_sim.engine.tick import Tick
from swarm_sim.faults import DRIVE
from swarm_sim.state import OPEN, Mode, evolve

DISPERSE_S = 2.0  # released robots drive straight away from the structure this long
_RECRUIT, _TARGET, _RETREAT = int(Mode.RECRUIT), int(Mode.TARGET), int(Mode.RETREAT)


def release(tk: Tick, r: int, away: float, new_mode: int) -> None:
    """Robot ``r`` leaves the structure in ``new_mode`` and disperses around heading ``away``
    (a robot that cannot drive is pushed clear instead: :func:`push_clear`)."""
    tk.mode[r] = new_mode
    tk.sidx[r], tk.sline[r], tk.slayer[r], tk.sopp[r] = 0, -1, -1, -1
    u = tk.rng.random(2)
    tk.goal[r] = away + (1 if u[0] < 0.5 else -1) * (0.35 + 0.7 * u[1])
    tk.run_left[r] = 0.0
    tk.disp[r] = DISPERSE_S
    if tk.is_failed(r, DRIVE):
        tk.disp[r] = 0.0
        push_clear(tk, r, away)


def push_clear(tk: Tick, r: int, away: float) -> None:
    """A released robot that cannot drive is pushed out of the structure's way: along ``away``
    (the direction it leaves in: ahead onto the target ground, back onto the initial ground)
    by one robot length, or more when a robot pushed before stands there, else sideways out of
    the structure's lane (modelled as its new pose once the release's pause ``release_clear_s``
    is over, not as a simulated push). It stays put, with an event, when nowhere is clear."""
    p, world = tk.p, tk.world
    L = p.robot_length_cm
    st = tk.st
    lane = (st.lines if st is not None else 1) * p.robot_width_cm
    x0, y0 = float(tk.x[r]), float(tk.y[r])
    ux, uy = math.cos(away), math.sin(away)
    others = np.ones(tk.x.shape[0], dtype=bool)
    others[r] = False
    gap = min(L, p.robot_width_cm) - 1e-6
    tries = [(x0 + j * L * ux, y0 + j * L * uy) for j in range(1, 5)]
    tries += [(x0 - k * lane * uy * sgn, y0 + k * lane * ux * sgn) for k in (1, 2) for sgn in (1, -1)]
    for cx, cy in tries:
        if not world.pose_ok1(cx, cy, away):
            continue
        d2 = (tk.x[others] - cx) ** 2 + (tk.y[others] - cy) ** 2
        if d2.size and d2.min() < gap * gap:
            continue
        tk.x[r], tk.y[r], tk.h[r] = cx, cy, away
        tk.ev("pushed_clear", r, x_cm=round(cx, 6), y_cm=round(cy, 6))
        return
    tk.ev("not_cleared", r, x_cm=round(x0, 6), y_cm=round(y0, 6))


def release_front(tk: Tick, g: T.ShellGeometry | None) -> None:
    st, p = tk.st, tk.p
    L, W = p.robot_length_cm, p.robot_width_cm
    k = S.row_size(st)
    row = [r for r in st.members[:k] if r != OPEN]
    # the row leaves from where the structure stands now (this step's move included)
    fslots = np.flatnonzero(np.asarray(st.members[:k]) != OPEN)
    tk.x[row], tk.y[row], _ = S.member_poses(st, L, W, fslots)
    far_cols = T.next_fill_group(st.shell, g, T.FAR) if g is not None else ()
    to_far = row[:len(far_cols)]
    ahead = math.atan2(st.dir_y, st.dir_x)
    for r in row[len(to_far):]:
        release(tk, r, ahead, _TARGET)  # turns there through the walk (the edge reflex guards the body)
    for r in to_far:  # Table 5.1 O-roles: a released core robot joins the far foot
        tk.mode[r] = _RECRUIT
        tk.sidx[r], tk.sline[r], tk.slayer[r], tk.sopp[r] = 0, -1, -1, 1
    members = st.members[k:]
    st = evolve(st, members=members, front_s_cm=st.front_s_cm - L, action="wait",
                 wait_until_s=tk.t + p.release_clear_s, progress_s=tk.t)
    if to_far:
        st = evolve(st, job=tuple(to_far), job_cols=tuple(far_cols[:len(to_far)]), job_kind="fill_far",
                     job_stage="drive", job_until_s=0.0, job_best_cm=(math.inf,) * len(to_far),
                     job_progress_s=(tk.t,) * len(to_far))
    tk.st = st
    tk.ev("release_front", row[0], n_left=len(members), robots=list(row), to_far_foot=list(to_far))


def release_rear(tk: Tick) -> None:
    st = tk.st
    k = S.row_size(st)
    cut = len(st.members) % k or k
    row = [r for r in st.members[-cut:] if r != OPEN]
    members = st.members[:-cut]
    back = math.atan2(-st.dir_y, -st.dir_x)
    for r in row:
        release(tk, r, back, _RETREAT)
    tk.st = evolve(st, members=members, action="wait", wait_until_s=tk.t + tk.p.release_clear_s,
                    progress_s=tk.t)
    tk.ev("release_rear", row[0], n_left=len(members), robots=list(row))
