"""The compiled engine: a numba fast-forward kernel that advances a run many steps at once
while only *continuous* things happen, bit-identical to the reference :func:`swarm_sim.step.step`.

:func:`fast_forward` looks at a state and, when its situation is one the kernel knows, runs
:func:`_kernel` for up to ``S`` steps. Each kernel step is the reference step's
arithmetic (same float operations, same order):

* free robots walk: :func:`swarm_sim.behaviour.explore._walk_kernel` itself, on the kernel's own Verlet
  list (:func:`swarm_sim.engine.grid.verlet_update` with a :data:`KERNEL_SKIN_CM` skin, rebuilt when a
  bound on how far robots can have moved says so; exact whatever its history), with the step's
  random numbers (the reference's ``rng.random((4, k))`` from the generator's own PCG64
  state, :mod:`swarm_sim.engine.pcg64`: only the few the walk reads are computed, by jump-ahead
  from the step's start, and the commit jumps the stream past the step, so the numbers and
  the stream's end are numpy's) and the walkers' cos/sin of heading kept between steps
  (recomputed only for a robot that turned);
* the dispersal clocks count down;
* the seed's alignment (turn, back off, creep to the edge), the structure's ``wait``, its
  ``advance``/``back`` slide with the members placed at
  their slots, or ``recruit``: every recruit drives along its cost-field path
  (:func:`_goto`, :func:`_slide_off`, :func:`_drive_along`, :func:`_pose_ok1`,
  :func:`_waypoint`, :func:`_cost_at` are njit ports of :mod:`swarm_sim.engine.motion`,
  :class:`swarm_sim.engine.world.World` and :class:`swarm_sim.engine.navigation.CostField`) with the
  progress/stall bookkeeping;
* the watchdog clock, the target check, the post-retreat wander clock, the time limit and
  the lost-robot check (and, with ``check=True``, the per-robot invariants).

A step in which anything *discrete* would happen (the seed is seen, a wait or slide ends,
the far ledge is seen, a recruit docks or stalls, the watchdog fires, a target is found, a
robot would be lost, an invariant could break, the time limit, ...) is computed into
temporaries, not committed, and the kernel returns; the caller (``runner.simulate``) then
runs that one step with the reference ``step()``, which takes the kernel's walk of that step
(``step(walked=...)``) when the kernel stopped after the walk phase. Threshold tests whose arithmetic is not
literally the reference's (numpy vs scalar) stop *conservatively* (a small margin): a
stop costs one reference step, never a difference. The uncommitted step's draws are
undone (its stream words restored), so the generator is left where the reference would
leave it; a generator whose bit generator is not PCG64 gets reference steps only.

Three functions differ between Python and numba and are handled explicitly:
``math.hypot`` (CPython computes its own correctly rounded norm, numba calls libm:
:func:`_py_hypot` is CPython's ``vector_norm`` for two numbers), ``x ** 2`` on a Python
float (libm ``pow``, not ``x * x``: :func:`_pose_ok1` calls ``math.pow`` with a run-time
exponent so LLVM cannot fold it) and ``np.hypot`` (libm, the same as numba's ``math.hypot``).

Tapering arches (:mod:`swarm_sim.behaviour.taper`): the feet's robots stand at their slots (carried);
a foot round's robots drive to their staging points and climb (a timer) beside the core's
action, as :func:`swarm_sim.behaviour.feet.advance_job` does; an idle tapered structure whose decision
is ``hold`` (:func:`_holds`) holds until the round changes stage.

What is not fast-forwarded (always reference steps): idle steps that decide anything but
``hold`` (decisions), the steps in which a round starts, changes stage or ends, octagonal
robots, runs with ``use_numba=False``, ``on_step`` callbacks, piers, and with ``check=True``
the structure's slides (the rule would have to be re-counted), tapering arches, the seed's
alignment and any step after an invariant violation.
"""

from __future__ import annotations

import math
import time

import numpy as np

from swarm_sim.behaviour.recruitment import slot_field
from swarm_sim.engine import pcg64
from swarm_sim.engine.borrow import address
from swarm_sim.engine.grid import HAVE_NUMBA, numba, workspace
from swarm_sim.engine.navigation import _HOPS, BLOCKED

from .state import OPEN, WALKING_MODES, Mode, Phase, evolve

_EXPLORE, _TARGET = int(Mode.EXPLORE), int(Mode.TARGET)
_P_SEARCH, _P_BUILD, _P_DELIVERED, _P_WANDER = (int(Phase.SEARCH), int(Phase.BUILD), int(Phase.DELIVERED),
                                                int(Phase.WANDER))
_ENDED = (int(Phase.SUCCESS), int(Phase.RETREATED), int(Phase.TIMEOUT), int(Phase.STRANDED))
_WALKING_LUT = np.zeros(len(Mode), dtype=bool)
_WALKING_LUT[list(WALKING_MODES)] = True

# structure kinds the kernel knows
K_NONE, K_WAIT, K_SLIDE, K_RECRUIT, K_ALIGN, K_HOLD = 0, 1, 2, 3, 4, 5
# a tapering arch's foot round (``Structure.job``) under way beside the structure's action
J_NONE, J_DRIVE, J_CLIMB = 0, 1, 2
#: why the kernel stopped (index into STOP_REASONS)
STOP_REASONS = ("batch", "seed", "verlet_grow", "wait_over", "slide_end", "far_ledge", "dock", "stalled_recruit",
                "watchdog", "target", "wander_over", "time_limit", "lost", "invariant", "aligned", "job_stage",
                "field")
R_BATCH, R_SEED, R_GROW, R_WAIT, R_SLIDE_END, R_LEDGE, R_DOCK, R_RSTALL, R_WATCH, R_TARGET, R_WANDER, R_TIME, \
    R_LOST, R_INV, R_ALIGNED, R_JOB, R_FIELD = range(len(STOP_REASONS))

#: conservative margin (cm) for threshold tests whose reference is numpy arithmetic (~200 ulps of a
#: 3000 cm coordinate: far above a last-bit difference, far below the 1e-9 cm the edge tests allow)
_MARGIN = 1e-10
_MAX_BATCH = 16384  # steps per kernel call at most (it returns earlier when anything discrete happens)
#: the kernel's Verlet skin (cm). Its list is rebuilt after at most ``KERNEL_SKIN_CM / 2`` cm of
#: walking (see ``_kernel``: a bound, not a pass over every robot each step); a wider skin than
#: the walk's (grid.SKIN_CM, 3 cm) means fewer rebuilds for a few more listed pairs. Measured on
#: large-void recruiting stretches (ns per kernel step, 64-68 walkers): 3 cm 2,190, 10 cm 2,060;
#: any skin gives the same runs (the list only has to hold every pair closer than ``avoid``).
KERNEL_SKIN_CM = 10.0

AVAILABLE = HAVE_NUMBA

if HAVE_NUMBA:
    from swarm_sim.behaviour.explore import _walk_kernel, _wrap
    from swarm_sim.engine.borrow import bool_at, borrowed, float64_at, int64_at
    from swarm_sim.engine.grid import verlet_update
    from swarm_sim.engine.navigation import _cell_ij, _near
    from swarm_sim.engine.pcg64 import jump as pcg_jump

    @numba.njit(cache=True, inline="always")
    def _two_prod(x, y):  # pragma: no cover - compiled
        """x * y as an exact (hi, lo) pair (Dekker / Veltkamp split)."""
        z = x * y
        c = 134217729.0 * x
        hx = c - (c - x)
        tx = x - hx
        c = 134217729.0 * y
        hy = c - (c - y)
        ty = y - hy
        zz = ((hx * hy - z) + hx * ty + tx * hy) + tx * ty
        return z, zz

    @numba.njit(cache=True)
    def _py_hypot(a, b):  # pragma: no cover - compiled
        """CPython 3.8+'s ``math.hypot(a, b)`` bit for bit (``vector_norm`` of Modules/mathmodule.c;
        numba's math.hypot is libm's, which differs in the last bit for ~0.2 % of inputs)."""
        a = abs(a)
        b = abs(b)
        if math.isnan(a) or math.isnan(b):
            return math.inf if (math.isinf(a) or math.isinf(b)) else math.nan
        mx = a if a > b else b
        if math.isinf(mx) or mx == 0.0:
            return mx
        _, e = math.frexp(mx)
        if e < -1023:  # subnormal inputs (never in the simulator): scale up first
            return 2.2250738585072014e-308 * _py_hypot(a / 2.2250738585072014e-308, b / 2.2250738585072014e-308)
        scale = math.ldexp(1.0, -e)
        csum = 1.0
        frac1 = 0.0
        frac2 = 0.0
        for v in (a, b):
            v *= scale
            hi, lo = _two_prod(v, v)
            s = csum + hi
            slo = (csum - s) + hi
            csum = s
            frac1 += lo
            frac2 += slo
        h = math.sqrt(csum - 1.0 + (frac1 + frac2))
        hi, lo = _two_prod(-h, h)
        s = csum + hi
        slo = (csum - s) + hi
        csum = s
        frac1 += lo
        frac2 += slo
        v = csum - 1.0 + (frac1 + frac2)
        h += v / (2.0 * h)
        return h / scale

    @numba.njit(cache=True, inline="always")
    def _hypot_below(a, b, lim):  # pragma: no cover - compiled
        """``_py_hypot(a, b) < lim`` (lim > 0), computing the correctly rounded norm only when
        ``a * a + b * b`` (within a few ulps of the norm's square) is within 1e-6 of ``lim ** 2``;
        NaN and overflow fall through to the exact test."""
        s2 = a * a + b * b
        l2 = lim * lim
        if s2 < l2 * (1.0 - 1e-6):
            return True
        if s2 > l2 * (1.0 + 1e-6) and s2 < 1e300:
            return False
        return _py_hypot(a, b) < lim

    @numba.njit(cache=True)
    def _pose_ok1(x, y, h, hl, hw, W, H, x0, x1, obs, r, two):  # pragma: no cover - compiled
        """:meth:`World.pose_ok1` for the square body (``two`` = 2.0 at run time: Python's
        ``v ** 2`` is libm's pow, which LLVM would fold into ``v * v`` for a constant)."""
        return _pose_ok_cs(x, y, math.cos(h), math.sin(h), hl, hw, W, H, x0, x1, obs, r, two)

    @numba.njit(cache=True)
    def _pose_ok_cs(x, y, c, s, hl, hw, W, H, x0, x1, obs, r, two):  # pragma: no cover - compiled
        """:func:`_pose_ok1` given the heading's cos and sin (a caller that has them)."""
        c = abs(c)
        s = abs(s)
        ex = hl * c + hw * s
        ey = hl * s + hw * c
        if x - ex < 0 or x + ex > W or y - ey < 0 or y + ey > H:
            return False
        if x + ex > x0 + 1e-9 and x - ex < x1 - 1e-9:
            return False
        for k in range(obs.shape[0]):
            if not (math.pow(x - obs[k, 0], two) + math.pow(y - obs[k, 1], two) > math.pow(obs[k, 2] + r, two)):
                return False
        return True

    @numba.njit(cache=True, inline="always")
    def _field_views(addr, row, cells):  # pragma: no cover - compiled
        """A cost field's cost, next-cell and closed arrays where they lie, from row ``row`` of its
        address table (:func:`_field_table`): borrowed views of ``cells`` entries each."""
        return (numba.carray(float64_at(addr[row, 0]), cells), numba.carray(int64_at(addr[row, 1]), cells),
                numba.carray(bool_at(addr[row, 2]), cells))

    @numba.njit(cache=True, inline="always")
    def _moved_beyond(x, y, xref, yref, ids, h2):  # pragma: no cover - compiled
        """Any of the robots ``ids`` farther than ``sqrt(h2)`` cm from where the neighbour list
        was built (grid.verlet_update's test, for these robots only)."""
        for q in range(ids.shape[0]):
            i = ids[q]
            dx_ = x[i] - xref[i]
            dy_ = y[i] - yref[i]
            if dx_ * dx_ + dy_ * dy_ > h2:
                return True
        return False

    @numba.njit(cache=True, inline="always")
    def _clip(d, tm):  # pragma: no cover - compiled
        """Python's ``max(-tm, min(tm, d))``."""
        v = d if d < tm else tm
        return v if v > -tm else -tm

    @numba.njit(cache=True)
    def _slide_off(x, y, h, dist, hl, hw, W, H, x0, x1, obs, r, two):  # pragma: no cover - compiled
        """:func:`swarm_sim.engine.motion.slide_off`."""
        mid = 0.5 * (x0 + x1)
        sx = x - dist if x < mid else x + dist
        if _pose_ok1(sx, y, h, hl, hw, W, H, x0, x1, obs, r, two):
            return sx, y, h, False
        return x, y, h, False

    @numba.njit(cache=True)
    def _goto(x, y, h, tx, ty, has_final, final_h, has_align, align_h, dist, tm,
              hl, hw, W, H, x0, x1, obs, r, two):  # pragma: no cover - compiled
        """:func:`swarm_sim.engine.motion.goto` (``final_heading``/``align_h`` None <=> ``has_*`` False)."""
        dx = tx - x
        dy = ty - y
        # the norm is needed exactly only when it is small (the arrival test, the last step) or in
        # the rare fallback below; when it clearly exceeds dist, min(dist, rr) is dist
        s2 = dx * dx + dy * dy
        far = s2 > dist * dist * (1.0 + 1e-6) and s2 > 1e-18 * (1.0 + 1e-6) and s2 < 1e300
        rr = dist if far else _py_hypot(dx, dy)
        if not far and rr < 1e-9:
            if not has_final:
                return x, y, h, True
            d = _wrap(final_h - h)
            nh = h + _clip(d, tm)
            return x, y, nh, abs(d) <= tm
        want = math.atan2(dy, dx)
        d = _wrap(want - h)
        nh = h + _clip(d, tm)
        if abs(d) > tm + 1e-12:
            if _pose_ok1(x, y, nh, hl, hw, W, H, x0, x1, obs, r, two):
                return x, y, nh, False
            return _slide_off(x, y, h, dist, hl, hw, W, H, x0, x1, obs, r, two)
        step = dist if (far or dist < rr) else rr  # Python's min(dist, r)
        for off in (0.0, math.pi / 4, -math.pi / 4, math.pi / 2, -math.pi / 2):
            a = want + off
            ca = math.cos(a)
            sa = math.sin(a)
            nx = x + step * ca
            ny = y + step * sa
            if _pose_ok_cs(nx, ny, ca, sa, hl, hw, W, H, x0, x1, obs, r, two):
                return nx, ny, a, False
        if _pose_ok1(x, y, want, hl, hw, W, H, x0, x1, obs, r, two):
            return x, y, want, False
        n_h = 1
        h_first = h
        if has_align:
            n_h = 2
            h_first = h + _clip(_wrap(align_h - h), tm)
        if far:
            rr = _py_hypot(dx, dy)
        for q in range(n_h):
            hh = h_first if q == 0 else h
            nx = x + step * dx / rr
            ny = y + step * dy / rr
            if _pose_ok1(nx, ny, hh, hl, hw, W, H, x0, x1, obs, r, two):
                return nx, ny, hh, False
            if _pose_ok1(x, y, hh, hl, hw, W, H, x0, x1, obs, r, two) and hh != h:
                return x, y, hh, False
        return _slide_off(x, y, h, dist, hl, hw, W, H, x0, x1, obs, r, two)

    @numba.njit(cache=True)
    def _cost_at(x, y, cost, closed, cell, gnx, gny, window, gcx, gcy, blocked):  # pragma: no cover
        """:meth:`CostField.cost_at`."""
        i, j = _cell_ij(x, y, cell, gnx, gny)
        c = j * gnx + i
        v = cost[c]
        if v < blocked:
            return v + _py_hypot(x - gcx[c], y - gcy[c])
        if not closed[c]:
            return math.inf
        best, _ = _near(x, y, cost, cell, gnx, gny, window, gcx, gcy, blocked)
        return best

    @numba.njit(cache=True)
    def _waypoint(x, y, cost, nxt, closed, goal_cell, gx, gy, cell, gnx, gny, window, gcx, gcy, blocked,
                  hops):  # pragma: no cover - compiled
        """:meth:`CostField.waypoint`: (found, wx, wy, read); found False is ``None``; ``read``: the
        cost the answer rests on (final when below the field's front, :meth:`CostField.known`)."""
        i, j = _cell_ij(x, y, cell, gnx, gny)
        c = j * gnx + i
        v = cost[c]
        if v >= blocked:
            if not closed[c]:
                return False, 0.0, 0.0, v
            best, c = _near(x, y, cost, cell, gnx, gny, window, gcx, gcy, blocked)
            if c < 0:
                return False, 0.0, 0.0, best
            return True, gcx[c], gcy[c], best
        for _ in range(hops):
            if c == goal_cell:
                return True, gx, gy, v
            c = nxt[c]
            if c < 0:
                return True, gx, gy, v
        if c == goal_cell:
            return True, gx, gy, v
        return True, gcx[c], gcy[c], v

    @numba.njit(cache=True)
    def _drive_along(x, y, h, final_h, align_h, cost, nxt, closed, goal_cell, gx, gy, cell, gnx, gny, window,
                     gcx, gcy, blocked, hops, dist, tm, hl, hw, W, H, x0, x1, obs, r, two):  # pragma: no cover
        """:func:`swarm_sim.engine.motion.drive_along` (``align_h`` given, as the recruits call it), and
        the field's value it read (``-inf``: none; :func:`_waypoint`)."""
        if _hypot_below(x - gx, y - gy, 1e-9):
            _, _, nh, done = _goto(gx, gy, h, gx, gy, True, final_h, False, 0.0, dist, tm,
                                   hl, hw, W, H, x0, x1, obs, r, two)
            if done:
                return gx, gy, final_h, True, -math.inf
            return gx, gy, nh, False, -math.inf
        found, wx, wy, read = _waypoint(x, y, cost, nxt, closed, goal_cell, gx, gy, cell, gnx, gny, window, gcx, gcy,
                                  blocked, hops)
        if not found:
            wx = gx
            wy = gy
        at_goal = wx == gx and wy == gy
        nx, ny, nh, _ = _goto(x, y, h, wx, wy, False, 0.0, at_goal, align_h, dist, tm,
                              hl, hw, W, H, x0, x1, obs, r, two)
        if at_goal and _hypot_below(nx - gx, ny - gy, 1e-9):
            nx = gx
            ny = gy
        return nx, ny, nh, False, read

    @numba.njit(cache=True)
    def _final(read, front, x, y, closed, cell, gnx, gny, window):  # pragma: no cover - compiled
        """The field's value read for a robot at (x, y) is final (:meth:`CostField.final`):
        below the field's ``front`` (inf once complete), or the robot stands in a closed cell
        with no open cell in its window (no path however far the search goes)."""
        if read < front or front == math.inf:
            return True
        i, j = _cell_ij(x, y, cell, gnx, gny)
        if not closed[j * gnx + i]:
            return False
        for jj in range(max(0, j - window), min(gny, j + window + 1)):
            for ii in range(max(0, i - window), min(gnx, i + window + 1)):
                if not closed[jj * gnx + ii]:
                    return False
        return True

    @numba.njit(cache=True)
    def _kernel(n_steps, t, dt, x, y, h, goal, run_left, disp, mode, carried, walkers, rw, jt, ws_k, ws_counts,
                ws_fill, ws_bucket, ws_items, ws_sx, ws_sy, nbr_start, nbr_idx, xref, yref, valid,
                wf, obs, obs_none, levy, flags, kind, sf, mem_ids, mem_slots, rec_ids, rec_f, rec_final,
                f_addr, f_goal_cell, f_row, grid_i, gcx, gcy, job, job_ids, job_f, j_addr, j_goal_cell,
                j_row, walked):  # pragma: no cover - compiled
        """Up to ``n_steps`` whole steps; returns (steps committed, stop reason, t, front_s, progress_s).

        ``wf``: world/walk floats (see :func:`fast_forward`); ``flags``: (search phase, target
        check, check invariants, retreating, landed, phase WANDER); ``sf``: structure floats;
        ``rec_f`` (R, 7): per recruit dock x, y, goal x, y, best, since, -; ``rec_final`` (R,).
        ``job``: the foot round's stage (J_NONE, J_DRIVE, J_CLIMB), ``sf[20]`` its climb's end (s);
        ``job_f`` (J, 4): per round robot staging x, y, best, since (:func:`swarm_sim.behaviour.feet.advance_job`).
        ``walked`` (5, n): written when a step is computed but not committed after its walk (every
        stop but ``seed`` and ``verlet_grow``): x, y, heading, goal heading and run left after that
        step's walk, for the reference step to take instead of walking again."""
        # the arrays passed on to compiled calls every step (the walk, the recruits' drive) as borrowed
        # views: no reference counts per call (swarm_sim.engine.borrow; the caller holds the arrays)
        x, y, h, goal, run_left, walkers, rw, jt, nbr_start, nbr_idx, obs, obs_none = (
            borrowed(x), borrowed(y), borrowed(h), borrowed(goal), borrowed(run_left), borrowed(walkers),
            borrowed(rw), borrowed(jt), borrowed(nbr_start), borrowed(nbr_idx), borrowed(obs), borrowed(obs_none))
        gcx, gcy, f_addr, j_addr = borrowed(gcx), borrowed(gcy), borrowed(f_addr), borrowed(j_addr)
        n = x.shape[0]
        k = walkers.shape[0]
        hl, hw, W, H, x0, x1, r, detect, avoid, dist, turn_max, mu, lmin, lmax, p_turn, turn_rad = (
            wf[0], wf[1], wf[2], wf[3], wf[4], wf[5], wf[6], wf[7], wf[8], wf[9], wf[10], wf[11], wf[12],
            wf[13], wf[14], wf[15])
        tgx, tgy, tfound2, max_time, phase_since, wander_s, stall_s, two = (
            wf[16], wf[17], wf[18], wf[19], wf[20], wf[21], wf[22], wf[23])
        x0w = x0 if x0 < 1e300 else math.inf
        x1w = x1 if x1 < 1e300 else math.inf
        search, target_check, check, retreating, landed, wander = (flags[0], flags[1], flags[2], flags[3],
                                                                   flags[4], flags[5])
        wait_until, front, goal_s, sgn, speed, void_cm, L, Wr, ox, oy, ddx, ddy, lat_sign, mem_h, progress, \
            recruit_stall, half_cell, dir_h, cell, blocked = (
                sf[0], sf[1], sf[2], sf[3], sf[4], sf[5], sf[6], sf[7], sf[8], sf[9], sf[10], sf[11], sf[12],
                sf[13], sf[14], sf[15], sf[16], sf[17], sf[18], sf[19])
        k_row, lines, gnx, gny, window, hops = grid_i[0], grid_i[1], grid_i[2], grid_i[3], grid_i[4], grid_i[5]
        cells = gnx * gny
        nr = rec_ids.shape[0]
        nj = job_ids.shape[0]
        job_until = sf[20]
        jbest = np.empty(nj)
        jsince = np.empty(nj)
        bx = np.empty(n)
        by = np.empty(n)
        bh = np.empty(n)
        bg = np.empty(n)
        br = np.empty(n)
        straight = np.zeros(k, np.bool_)
        nbest = np.empty(nr)
        nsince = np.empty(nr)
        nfinal = np.zeros(nr, np.bool_)
        # per recruit, constant while the kernel runs: the heading of its approach (from the
        # field's goal point to its dock) and that leg's length
        rec_in_h = np.empty(nr)
        rec_tail = np.empty(nr)
        for q in range(nr):
            dxp = rec_f[q, 0]
            dyp = rec_f[q, 1]
            ax = rec_f[q, 2]
            ay = rec_f[q, 3]
            rec_in_h[q] = dir_h if _hypot_below(dxp - ax, dyp - ay, 1e-9) else math.atan2(dyp - ay, dxp - ax)
            rec_tail[q] = _py_hypot(ax - dxp, ay - dyp)
        # cos/sin of each walker's heading, kept by the walk (this call's only: a step that is not
        # committed ends the call)
        hc = np.empty(n)
        hs = np.empty(n)
        is_walker = np.zeros(n, np.bool_)
        for q in range(k):
            hc[walkers[q]] = math.cos(h[walkers[q]])
            hs[walkers[q]] = math.sin(h[walkers[q]])
            is_walker[walkers[q]] = True
        no_u = np.empty((0, 0))
        # the walk's own arrays as borrowed views (the arguments are borrowed above)
        vstraight, vno_u, vbx, vby, vhc, vhs = (borrowed(straight), borrowed(no_u), borrowed(bx), borrowed(by),
                                                 borrowed(hc), borrowed(hs))
        # The neighbour list's validity (grid.verlet_update: no robot has moved more than half the
        # skin since its rebuild) without a pass over every robot each step: ``moved`` bounds how far
        # the walkers and the robots standing still have moved since the rebuild (the farthest any
        # robot was at this call's start, plus one walk step per committed step: a walker moves at
        # most ``dist``, forward or by a fallback); the robots the kernel drives (the seed aligning,
        # a sliding structure's members, recruits, a foot round's robots) are tested exactly.
        skin = KERNEL_SKIN_CM
        half_skin = 0.5 * skin
        half_skin2 = half_skin * half_skin
        walk_len = dist * (1.0 + 1e-9) + 1e-9  # a walk step's length, with room for its rounding
        moved = 0.0
        if k and valid[0] == 1:
            m2 = 0.0
            for i in range(n):
                dx_ = x[i] - xref[i]
                dy_ = y[i] - yref[i]
                d2 = dx_ * dx_ + dy_ * dy_
                if d2 > m2:
                    m2 = d2
            moved = math.sqrt(m2)
        q4 = 0.5 * hw  # = 0.25 * width (World.void_ahead), exactly
        sense = hl + q4 + detect + 1.0  # no ground sensor reaches farther from the centre (cm)
        for j in range(n_steps):
            tn = t + dt
            # 1. detect_seed (search phase): an explorer's ground sensor sees the void
            if search and x0 < 1e300:
                for i in range(n):
                    if mode[i] != _EXPLORE or x[i] + sense < x0 - _MARGIN or x[i] - sense > x1 + _MARGIN:
                        continue  # (no sensor reaches the void band from here)
                    c = math.cos(h[i])
                    s = math.sin(h[i])
                    reach = detect * c
                    for lat in (0.0, q4, -q4):
                        px = x[i] + hl * c - lat * s
                        lo = min(px, px + reach)
                        hi = max(px, px + reach)
                        if hi > x0 - _MARGIN and lo < x1 + _MARGIN:
                            return j, R_SEED, t, front, progress
            # 2. walk_free (uncommitted until the end of the step)
            for i in range(n):
                bx[i] = x[i]
                by[i] = y[i]
                bh[i] = h[i]
                bg[i] = goal[i]
                br[i] = run_left[i]
            if k:
                # the list's validity (above); verlet_update is called only for a rebuild
                stale = valid[0] != 1 or moved > half_skin
                if not stale:
                    if kind == K_ALIGN:
                        stale = _moved_beyond(bx, by, xref, yref, mem_ids[:1], half_skin2)
                    elif kind == K_SLIDE:
                        stale = _moved_beyond(bx, by, xref, yref, mem_ids, half_skin2)
                    elif kind == K_RECRUIT:
                        stale = _moved_beyond(bx, by, xref, yref, rec_ids, half_skin2)
                    if job == J_DRIVE and not stale:
                        stale = _moved_beyond(bx, by, xref, yref, job_ids, half_skin2)
                if stale:
                    valid[0] = 0  # rebuilt now
                    moved = 0.0
                    if verlet_update(bx, by, avoid + skin, skin, ws_k, ws_counts, ws_fill, ws_bucket, ws_items,
                                     ws_sx, ws_sy, nbr_start, nbr_idx, xref, yref, valid) == -1:
                        return j, R_GROW, t, front, progress
                for q in range(k):
                    straight[q] = disp[walkers[q]] > 0
                # the step's 4 x k uniforms are the generator's own stream from ``rw``: the walk
                # computes the few it reads (jump table ``jt``); the commit jumps the stream past them
                _walk_kernel(x, y, h, goal, run_left, walkers, vstraight, vno_u, True, hl, hw, W, H, x0, x1, obs, r,
                             detect, avoid, dist, turn_max, levy, mu, lmin, lmax, p_turn, turn_rad, vbx, vby,
                             nbr_start, nbr_idx, rw, jt, vhc, vhs)
            stop = R_BATCH
            nfront = front
            nprogress = progress
            # 3. move_structure
            if kind == K_WAIT:
                if tn >= wait_until:
                    stop = R_WAIT
            elif kind == K_SLIDE:
                f = front + sgn * speed * dt
                if (f - goal_s) * sgn >= -1e-9:
                    stop = R_SLIDE_END
                else:
                    nfront = f
                    if not landed and nfront + detect >= void_cm - 1e-6:
                        stop = R_LEDGE
            elif kind == K_ALIGN:  # step._align: the seed turns perpendicular to the edge, creeps to it
                s0 = mem_ids[0]
                hx = x[s0]
                hy = y[s0]
                hh = h[s0]
                d = _wrap(dir_h - hh)
                if abs(d) > 1e-9:
                    nh = hh + _clip(d, turn_max)
                    if _pose_ok1(hx, hy, nh, hl, hw, W, H, x0w, x1w, obs, r, two):
                        h[s0] = nh
                    else:  # too close to the edge to turn: back away from it first
                        x[s0] = hx - dist * ddx
                        y[s0] = hy - dist * ddy
                else:
                    h[s0] = dir_h
                    if (x0 - 0.5 * L) - hx > dist:
                        x[s0] = hx + dist
                    else:
                        stop = R_ALIGNED
            elif kind == K_RECRUIT:
                arrived_all = True
                for q in range(nr):
                    ri = rec_ids[q]
                    dxp = rec_f[q, 0]
                    dyp = rec_f[q, 1]
                    rx = x[ri]
                    ry = y[ri]
                    rh = h[ri]
                    nbest[q] = rec_f[q, 4]
                    nsince[q] = rec_f[q, 5]
                    nfinal[q] = rec_final[q]
                    if rx == dxp and ry == dyp and rh == dir_h:
                        continue
                    arrived_all = False
                    if rec_final[q]:
                        nx, ny, nh, arrived = _goto(rx, ry, rh, dxp, dyp, True, dir_h, True, dir_h, dist, turn_max,
                                                    hl, hw, W, H, x0w, x1w, obs_none, r, two)
                        if arrived and _hypot_below(nx - dxp, ny - dyp, 1e-9):
                            nx = dxp
                            ny = dyp
                            nh = dir_h
                        left = _py_hypot(nx - dxp, ny - dyp)
                    else:
                        ax = rec_f[q, 2]
                        ay = rec_f[q, 3]
                        in_h = rec_in_h[q]
                        fc, fx, fz = _field_views(f_addr, f_row[q], cells)
                        nx, ny, nh, fin, read = _drive_along(rx, ry, rh, in_h, in_h, fc, fx, fz, f_goal_cell[q],
                                                             ax, ay, cell, gnx, gny, window, gcx, gcy, blocked,
                                                             hops, dist, turn_max, hl, hw, W, H, x0w, x1w, obs, r,
                                                             two)
                        nfinal[q] = fin
                        here = _cost_at(nx, ny, fc, fz, cell, gnx, gny, window, gcx, gcy, blocked)
                        if not (_final(read, rec_f[q, 6], rx, ry, fz, cell, gnx, gny, window)
                                and _final(here, rec_f[q, 6], nx, ny, fz, cell, gnx, gny, window)):
                            stop = R_FIELD  # the field is not settled this far yet (fast_forward settles it)
                        left = here + rec_tail[q]
                    x[ri] = nx  # undone from the snapshot if the step is not committed
                    y[ri] = ny
                    h[ri] = nh
                    if left < nbest[q] - half_cell:
                        nbest[q] = left
                        nsince[q] = tn
                        nprogress = tn
                    elif tn - nsince[q] > recruit_stall:
                        stop = R_RSTALL
                if arrived_all:
                    stop = R_DOCK
            # 3b. the foot round (feet.advance_job): robots drive to their staging points, or climb
            if job == J_DRIVE:
                j_arrived = True
                for q in range(nj):
                    ri = job_ids[q]
                    jgx = job_f[q, 0]
                    jgy = job_f[q, 1]
                    jbest[q] = job_f[q, 2]
                    jsince[q] = job_f[q, 3]
                    if x[ri] == jgx and y[ri] == jgy and h[ri] == dir_h:
                        continue
                    j_arrived = False
                    ox_ = x[ri]
                    oy_ = y[ri]
                    fc, fx, fz = _field_views(j_addr, j_row[q], cells)
                    nx, ny, nh, _, read = _drive_along(x[ri], y[ri], h[ri], dir_h, dir_h, fc, fx, fz, j_goal_cell[q],
                                                       jgx, jgy, cell, gnx, gny, window, gcx, gcy, blocked, hops, dist,
                                                       turn_max, hl, hw, W, H, x0w, x1w, obs, r, two)
                    x[ri] = nx  # undone from the snapshot if the step is not committed
                    y[ri] = ny
                    h[ri] = nh
                    left = _cost_at(nx, ny, fc, fz, cell, gnx, gny, window, gcx, gcy, blocked)
                    if stop == R_BATCH and not (
                            _final(read, job_f[q, 4], ox_, oy_, fz, cell, gnx, gny, window)
                            and _final(left, job_f[q, 4], nx, ny, fz, cell, gnx, gny, window)):
                        stop = R_FIELD
                    if left < jbest[q] - half_cell:
                        jbest[q] = left
                        jsince[q] = tn
                        nprogress = tn
                if j_arrived and stop == R_BATCH:
                    stop = R_JOB  # all at their staging points: the climb starts (a reference step)
            elif job == J_CLIMB:
                if not (tn + 1e-9 < job_until) and stop == R_BATCH:
                    stop = R_JOB
            # 5. watch: the watchdog
            if stop == R_BATCH and kind != K_NONE and kind != K_ALIGN and not retreating and \
                    not (tn - nprogress <= stall_s):
                stop = R_WATCH
            # 6. finish: target, wander, time limit
            if stop == R_BATCH and target_check:
                for i in range(n):
                    if mode[i] == _TARGET:
                        d2 = (x[i] - tgx) * (x[i] - tgx) + (y[i] - tgy) * (y[i] - tgy)
                        if d2 <= tfound2 * (1.0 + 1e-9) + _MARGIN:
                            stop = R_TARGET
                            break
            if stop == R_BATCH and wander and tn - phase_since >= wander_s - 1e-9:
                stop = R_WANDER
            if stop == R_BATCH and tn >= max_time - 1e-9:
                stop = R_TIME
            # the lost-robot check (runner) and, with check, the per-robot invariants
            if stop == R_BATCH:
                for i in range(n):
                    if carried[i]:
                        continue
                    xi = x[i]
                    yi = y[i]
                    if (xi + r < x0 - _MARGIN or xi - r > x1 + _MARGIN) and (
                            not check or (xi - r > _MARGIN and xi + r < W - _MARGIN and yi - r > _MARGIN
                                          and yi + r < H - _MARGIN and math.isfinite(xi) and math.isfinite(yi))):
                        continue  # the body (within r of its centre) is far from the void and the walls
                    c = abs(math.cos(h[i]))
                    s = abs(math.sin(h[i]))
                    ex = hl * c + hw * s
                    if xi + ex > x0 + 1e-9 - _MARGIN and xi - ex < x1 - 1e-9 + _MARGIN:
                        stop = R_LOST
                        break
                    if check:
                        ey = hl * s + hw * c
                        if not (math.isfinite(xi) and math.isfinite(yi)) or xi - ex < -1e-6 + _MARGIN or \
                                xi + ex > W + 1e-6 - _MARGIN or yi - ey < -1e-6 + _MARGIN or \
                                yi + ey > H + 1e-6 - _MARGIN:
                            stop = R_INV
                            break
            if stop != R_BATCH:  # not committed: the reference step does this one. Its walk is
                # handed over (``walked``: the walkers as walked, every other robot as it stood; the
                # robots the kernel drives are never walkers) and the state is left before the step
                # (the stream words ``rw`` move only at the commit: the caller jumps them)
                for i in range(n):
                    w = is_walker[i]
                    walked[0, i] = x[i] if w else bx[i]
                    walked[1, i] = y[i] if w else by[i]
                    walked[2, i] = h[i] if w else bh[i]
                    walked[3, i] = goal[i] if w else bg[i]
                    walked[4, i] = run_left[i] if w else br[i]
                for i in range(n):
                    x[i] = bx[i]
                    y[i] = by[i]
                    h[i] = bh[i]
                    goal[i] = bg[i]
                    run_left[i] = br[i]
                return j, stop, t, front, progress
            # commit
            if k:
                pcg_jump(rw, jt, 4 * k)
            for i in range(n):
                v = disp[i] - dt
                disp[i] = v if v > 0.0 else 0.0
            if kind == K_SLIDE:
                front = nfront
                for q in range(mem_ids.shape[0]):
                    mi = mem_ids[q]
                    m = mem_slots[q]
                    if k_row == 1:
                        s_ = front - (m + 0.5) * L
                        x[mi] = ox + s_ * ddx
                        y[mi] = oy + s_ * ddy
                    else:
                        s_ = front - (m // k_row + 0.5) * L
                        lat = ((m % k_row) % lines) * Wr * lat_sign
                        x[mi] = ox + s_ * ddx - lat * ddy
                        y[mi] = oy + s_ * ddy + lat * ddx
                    h[mi] = mem_h
            elif kind == K_RECRUIT:
                for q in range(nr):
                    rec_f[q, 4] = nbest[q]
                    rec_f[q, 5] = nsince[q]
                    rec_final[q] = nfinal[q]
            if job == J_DRIVE:
                for q in range(nj):
                    job_f[q, 2] = jbest[q]
                    job_f[q, 3] = jsince[q]
            progress = nprogress
            t = tn
            moved += walk_len
        return n_steps, R_BATCH, t, front, progress


def _drop_stale_cache() -> None:
    """numba's cache (``cache=True``) checks only the source file of the cached function, not the
    njit functions it calls in other modules (``explore._walk_kernel``, ``grid.verlet_update``,
    ``pcg64.jump``, ``navigation._near``, the ``borrow`` intrinsics, and the walk's
    ``pcg64.draw_at``): after an edit there this module's and ``explore``'s cached kernels would
    keep the old code. So their cache files are dropped (and
    recompiled on first use) whenever those sources change."""
    import hashlib
    import os

    from swarm_sim.behaviour import explore
    from swarm_sim.engine import borrow, grid, navigation, pcg64

    path = getattr(getattr(_kernel, "_cache", None), "_cache_path", None)
    if not path or not os.path.isdir(path):
        return
    digest = hashlib.sha1()
    for mod in (borrow, explore, grid, navigation, pcg64):
        with open(mod.__file__, "rb") as fh:
            digest.update(fh.read())
    stamp = os.path.join(path, "compiled.deps-sha1")
    try:
        with open(stamp, encoding="ascii") as fh:
            if fh.read().strip() == digest.hexdigest():
                return
    except OSError:
        pass
    try:
        for name in os.listdir(path):
            if name.startswith(("compiled.", "explore.")) and name.endswith((".nbi", ".nbc")):
                os.remove(os.path.join(path, name))
        with open(stamp, "w", encoding="ascii") as fh:
            fh.write(digest.hexdigest())
    except OSError:  # a read-only or shared cache: numba still works (and recompiles if it must)
        pass


if HAVE_NUMBA:
    _drop_stale_cache()


def _kind(state, p, world, check: bool) -> int | None:
    """The structure kind the kernel can advance in this state, or None (reference step)."""
    st = state.structure
    if st is None:
        return K_NONE if state.phase in (_P_SEARCH, _P_DELIVERED, _P_WANDER) else None
    if state.phase != _P_BUILD or st.piers:
        return None
    if st.shell or st.job or (p.switch_levels[st.level][6] if p.switch_levels else p.taper_block_rows):
        # a tapering arch: its feet stand still unless a round is under way (the kernel drives
        # a round's robots and times its climb); with check the reference checks every step
        if check or st.action == "align" or (st.job and st.job_stage not in ("drive", "climb")):
            return None
        if st.action == "idle":
            return K_HOLD if _holds(state, p, world) else None
    if st.action == "align":
        return K_ALIGN if (st.members and not check) else None
    if st.action == "wait":
        return K_WAIT if st.members else None
    if st.action in ("advance", "back"):
        return None if check else K_SLIDE
    if st.action == "recruit" and st.recruits:
        return K_RECRUIT
    return None


def _holds(state, p, world) -> bool:
    """An idle tapered structure whose decision is ``hold`` (a foot round under way, or landed
    with nothing to do): it decides ``hold`` again every step until something discrete
    happens, since nothing its decision reads changes in a kernel step (the structure, the
    free robots' modes, the world)."""
    from swarm_sim.behaviour import feet
    from swarm_sim.behaviour.recruitment import free_robots

    from .step import choose

    st = state.structure
    g = feet.geometry(st, p)
    if g is None or not st.shell:
        return False  # the reference's decide sets the empty shell first
    if not (st.members or st.job or any(r != OPEN for r in st.shell)):
        return False  # the structure dissolves in this step
    free = free_robots(state.mode, st, state.fault_known)
    return choose(st, p, world, g, int(free.size))[0] == "hold"


_CONTEXTS: dict = {}


def _context(p, world) -> tuple:
    """What a run's kernel calls share (cached per (params, world) objects): the world/walk
    floats (``wf``; index 20, the phase start, is set per call), the navigation grid and an
    empty obstacle table."""
    key = (id(p), id(world))
    hit = _CONTEXTS.get(key)
    if hit is not None and hit[0] is p and hit[1] is world:
        return hit[2]
    from swarm_sim.engine.navigation import nav_grid

    x0 = world.x0_cm if np.isfinite(world.x0_cm) else 1e308
    x1 = world.x1_cm if np.isfinite(world.x1_cm) else 1e308
    wf = np.array([0.5 * world.length_cm, 0.5 * world.width_cm, world.w_cm, world.h_cm, x0, x1,
                   world.body_radius_cm, world.detect_cm, world.avoid_cm, p.speed_cm_s * p.dt_s, p.turn_max_rad,
                   p.levy_mu, p.levy_min_cm, p.levy_max_cm, p.random_turn_prob, p.random_turn_rad,
                   world.target_x_cm, world.target_y_cm, world.target_found_cm ** 2, p.max_time_s,
                   0.0, p.wander_after_retreat_s, p.stall_s, 2.0])
    out = (wf, nav_grid(world), np.zeros((0, 3)))
    if len(_CONTEXTS) > 16:
        _CONTEXTS.clear()
    _CONTEXTS[key] = (p, world, out)
    return out


def _field_table(fields: list) -> tuple:
    """The cost fields for the kernel, read where they lie: per field the data addresses of its
    cost, next-cell and closed arrays (``(F, 3)`` int64: :func:`swarm_sim.engine.borrow.address`), the
    goal cell of each and its row. A field settled further (``CostField.extend``) is settled in
    place, so the kernel sees it at once; the caller keeps ``fields`` (and so the arrays) alive
    while the kernel runs. (Before, the fields were copied into one stacked array per call:
    ~2 ms for eight 100,000-cell fields on the large void.)"""
    addr = np.array([(address(f.cost, np.float64), address(f.nxt, np.int64), address(f.closed, np.bool_))
                     for f in fields], dtype=np.int64).reshape(len(fields), 3)
    goal = np.array([f.goal_cell for f in fields], dtype=np.int64)
    return addr, goal, np.arange(len(fields), dtype=np.int64)


def fast_forward(state, p, world, rng: np.random.Generator, check: bool = False, max_steps: int | None = None,
                 stats: dict | None = None):
    """Advance ``state`` by as many whole reference-identical steps as the kernel can (0 when it
    cannot do the next one); returns (new state, steps advanced, walked). The caller runs the
    next step with :func:`swarm_sim.step.step`, passing ``walked`` on: when not None it is that
    step's walk, already computed by the kernel (x, y, heading, goal heading, run left; the
    generator already past its draws), so the reference step does not walk again. ``stats``
    (optional dict) counts kernel calls, steps, stop reasons and the CPU seconds spent inside
    the kernel (``kernel_cpu_s``)."""
    if not AVAILABLE or world.shape != "square" or state.phase in _ENDED or not pcg64.supported(rng):
        return state, 0, None
    kind = _kind(state, p, world, check)
    if kind is None:
        return state, 0, None
    st = state.structure
    n = state.n
    mode = state.mode
    walking = _WALKING_LUT[mode]
    if state.phase != _P_SEARCH and p.case in ("A", "B"):
        walking &= mode != _EXPLORE
    walkers = np.flatnonzero(walking).astype(np.int64)
    k = walkers.size
    carried = np.zeros(n, dtype=np.bool_)
    mem_ids = np.zeros(0, np.int64)
    mem_slots = np.zeros(0, np.int64)
    if st is not None:
        mem = np.asarray(st.members, dtype=np.int64)
        mem_slots = np.flatnonzero(mem != OPEN).astype(np.int64)
        mem_ids = mem[mem_slots]
        carried[mem_ids] = True
    L, Wr = p.robot_length_cm, p.robot_width_cm
    wf0, grid, obs_none = _context(p, world)
    wf = wf0.copy()
    wf[20] = state.phase_since_s
    target_check = state.phase in (_P_BUILD, _P_DELIVERED) and state.target_finder < 0
    if state.target_finder >= 0 and state.phase in (_P_BUILD, _P_DELIVERED) and (
            not p.finish_delivery or state.phase == _P_DELIVERED):
        return state, 0  # the run succeeds in the next step
    flags = np.array([state.phase == _P_SEARCH, target_check, check, bool(st is not None and st.retreating),
                      bool(st is not None and st.landed), state.phase == _P_WANDER], dtype=np.bool_)
    rec_ids = np.zeros(0, np.int64)
    rec_f = np.zeros((0, 7))
    rec_final = np.zeros(0, np.bool_)
    f_addr = np.zeros((0, 3), np.int64)
    f_goal = np.zeros(0, np.int64)
    f_row = np.zeros(0, np.int64)
    sf = np.zeros(21)
    job = J_NONE
    job_ids = np.zeros(0, np.int64)
    job_f = np.zeros((0, 5))
    j_addr, j_goal, j_row = f_addr, f_goal, f_row
    jfields: list = []
    if st is not None:
        dir_h = math.atan2(st.dir_y, st.dir_x)
        k_row = st.lines * st.layers
        mem_h = dir_h if k_row == 1 else float(np.arctan2(st.dir_y, st.dir_x))
        sgn = 1.0 if st.action == "advance" else -1.0
        sf[:20] = (st.wait_until_s, st.front_s_cm, st.goal_s_cm, sgn, p.speed_cm_s, p.void_width_cm, L, Wr,
                 st.origin_x_cm, st.origin_y_cm, st.dir_x, st.dir_y, st.lateral_sign, mem_h, st.progress_s,
                 p.recruit_stall_s, 0.5 * grid.cell_cm, dir_h, grid.cell_cm, BLOCKED)
        grid_i = np.array([k_row, st.lines, grid.nx, grid.ny, grid.window, _HOPS], dtype=np.int64)
        if kind == K_RECRUIT:
            fields = [slot_field(st, p, world, slot) for slot in st.recruit_slots]
            rec_ids = np.asarray(st.recruits, dtype=np.int64)
            rec_f = np.array([[dxp, dyp, f.goal_x, f.goal_y, b, s_, f.front] for (f, dxp, dyp), b, s_ in
                              zip(fields, st.recruit_best_cm, st.recruit_progress_s, strict=True)], dtype=np.float64)
            rec_final = np.asarray(st.recruit_final, dtype=np.bool_)
            f_addr, f_goal, f_row = _field_table([f for f, _, _ in fields])
            if carried[rec_ids].any():
                return state, 0, None
        if st.shell:  # the feet's robots stand at their slots (carried by the structure)
            sh = np.asarray(st.shell, dtype=np.int64)
            carried[sh[sh != OPEN]] = True
        if st.job:
            from swarm_sim.behaviour import feet
            from swarm_sim.behaviour import taper as T
            from swarm_sim.engine.navigation import cost_field

            if st.job_stage == "drive":
                g = feet.geometry(st, p)
                job = J_DRIVE
                jfields = [cost_field(world, *T.staging_xy(st, g, L, Wr, c)) for c in st.job_cols]
                job_ids = np.asarray(st.job, dtype=np.int64)
                job_f = np.array([[f.goal_x, f.goal_y, b, s_, f.front] for f, b, s_ in
                                  zip(jfields, st.job_best_cm, st.job_progress_s, strict=True)], dtype=np.float64)
                j_addr, j_goal, j_row = _field_table(jfields)
                if carried[job_ids].any():
                    return state, 0, None
            else:
                job = J_CLIMB
                sf[20] = st.job_until_s
    else:
        grid_i = np.array([1, 1, grid.nx, grid.ny, grid.window, _HOPS], dtype=np.int64)
    ws = workspace(n, "kernel")
    x, y, h = state.x_cm.copy(), state.y_cm.copy(), state.heading_rad.copy()
    goal, run_left, disp = state.goal_heading_rad.copy(), state.run_left_cm.copy(), state.disperse_left_s.copy()
    t, front, progress = state.t_s, sf[1], sf[14]
    total = 0
    limit = max_steps if max_steps is not None else 1 << 62
    reason = R_BATCH
    rw = pcg64.words(rng)  # the kernel draws the walk's uniforms from the stream itself
    jt = np.empty((4 * k, 4), np.uint64)  # a step's 4 x k draws, by jump-ahead (pcg64.jump_table)
    pcg64.jump_table(rw, 4 * k, jt)
    walked = np.empty((5, n))
    while total < limit:
        S = int(min(_MAX_BATCH, limit - total))
        t_cpu = time.process_time() if stats is not None else 0.0
        j, reason, t, front, progress = _kernel(
            S, t, p.dt_s, x, y, h, goal, run_left, disp, mode, carried, walkers, rw, jt, *ws[:7], *ws[7:], wf,
            world.obstacles, obs_none, p.walk == "levy", flags, kind, sf, mem_ids, mem_slots, rec_ids,
            rec_f, rec_final, f_addr, f_goal, f_row, grid_i, grid.cx, grid.cy, job, job_ids, job_f, j_addr, j_goal,
            j_row, walked)
        total += j
        if stats is not None:
            stats["kernel_cpu_s"] = stats.get("kernel_cpu_s", 0.0) + time.process_time() - t_cpu
            stats["kernel_calls"] = stats.get("kernel_calls", 0) + 1
            why = STOP_REASONS[reason]
            stops = stats.setdefault("stops", {})
            stops[why] = stops.get(why, 0) + 1
        if reason == R_FIELD:  # a recruit or foot robot reached cells its field has not settled yet
            if kind == K_RECRUIT:  # (settled in place: the kernel reads the fields where they lie)
                for f, _, _ in fields:
                    f.extend(f.front)
                rec_f[:, 6] = [f.front for f, _, _ in fields]
            if job == J_DRIVE:
                for f in jfields:
                    f.extend(f.front)
                job_f[:, 4] = [f.front for f in jfields]
        elif reason == R_GROW:  # more close pairs than the list has room for: grow it, go on
            ws[8] = np.empty(2 * ws[8].shape[0], np.int64)
        elif reason != R_BATCH:
            break
        sf[1], sf[14] = front, progress
    if stats is not None:
        stats["kernel_steps"] = stats.get("kernel_steps", 0) + total
    out = None
    if reason not in (R_BATCH, R_SEED, R_GROW):  # the step after the last committed one, walked
        out = (walked[0], walked[1], walked[2], walked[3], walked[4])
        if k:  # its walk's draws are taken: the reference step does not draw them again
            pcg_jump(rw, jt, 4 * k)
    if total or out is not None:
        pcg64.store(rng, rw)
    if total == 0:
        return state, 0, out
    new_st = st
    if st is not None:
        if kind == K_SLIDE:
            new_st = evolve(st, front_s_cm=float(front))
        elif kind == K_RECRUIT:
            best = tuple(float(v) for v in rec_f[:, 4])
            since = tuple(float(v) for v in rec_f[:, 5])
            final = tuple(bool(v) for v in rec_final)
            if (best, since, final) != (st.recruit_best_cm, st.recruit_progress_s, st.recruit_final):
                new_st = evolve(st, recruit_best_cm=best, recruit_progress_s=since, recruit_final=final)
        if job == J_DRIVE:
            best = tuple(float(v) for v in job_f[:, 2])
            since = tuple(float(v) for v in job_f[:, 3])
            if (best, since) != (st.job_best_cm, st.job_progress_s):
                new_st = evolve(new_st, job_best_cm=best, job_progress_s=since)
        if float(progress) != new_st.progress_s:
            new_st = evolve(new_st, progress_s=float(progress))
    new = evolve(state, x_cm=x, y_cm=y, heading_rad=h, goal_heading_rad=goal, run_left_cm=run_left,
                  disperse_left_s=disp, t_s=float(t), step=state.step + total, structure=new_st)
    return new, total, out


__all__ = ["AVAILABLE", "STOP_REASONS", "fast_forward"]
