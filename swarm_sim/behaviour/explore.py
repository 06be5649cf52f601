"""Exploration walk of free robots, vectorised over a mask of walking robots.

Per step each walker: (1) senses hazards: void ahead of a ground sensor, a wall
or obstacle within ``avoid_cm`` ahead, another robot within ``avoid_cm`` in its
front half-plane (grid query); (2) picks a heading goal: on a hazard a random
turn of 90..180 deg away (kept, not redrawn, while the hazard lasts and the turn is under
way and not refused by the reflex), else the walk (Levy walk: straight runs whose length
follows a power law ``p(l) ~ l^-mu`` on ``[levy_min_cm, levy_max_cm]`` followed by a
uniform random turn; random walk: a turn of ``+-random_turn_rad`` with probability
``random_turn_prob`` per step); (3) turns towards the goal by at most
``turn_max_rad`` per step and drives ``speed_cm_s * dt_s`` once aligned; (4) the
body/edge reflex keeps the body off the void, inside the walls and off obstacles:
a pose that would violate that is replaced by the first safe one of: drive without
turning, turn without driving, slide away from the void edge, stand still.
"""

from __future__ import annotations

import math

import numpy as np

from swarm_sim.engine.grid import HAVE_NUMBA, blocked_ahead, neighbour_list, numba

if HAVE_NUMBA:
    from swarm_sim.engine.pcg64 import draw_at
from swarm_sim.engine.world import World, wrap
from swarm_sim.params import Params

AVOIDING = -1.0  # run_left_cm marker: the robot turned away from a hazard on its last step


def levy_lengths(u: np.ndarray, p: Params) -> np.ndarray:
    """Inverse-CDF sample of a power law with exponent ``levy_mu`` (cm)."""
    a = p.levy_mu - 1.0
    if abs(a) < 1e-9:
        lo, hi = np.log(p.levy_min_cm), np.log(p.levy_max_cm)
        return np.exp(lo + u * (hi - lo))
    lo, hi = p.levy_min_cm ** -a, p.levy_max_cm ** -a
    return (lo + u * (hi - lo)) ** (-1.0 / a)


def _walk_numpy(x, y, h, goal, run_left, walkers, straight, blocked, u, world: World, p: Params):
    """Reference (numpy) version of the walk; the numba kernel mirrors it line by line."""
    wx, wy, wh = x[walkers], y[walkers], h[walkers]
    wg, wr = goal[walkers], run_left[walkers]
    hazard = world.void_ahead(wx, wy, wh) | world.wall_ahead(wx, wy, wh) | (blocked & ~straight)
    dist = p.speed_cm_s * p.dt_s
    side = np.where(u[0] < 0.5, -1.0, 1.0)
    # an avoidance turn still under way (hazard last step too, goal not reached) is finished,
    # not redrawn: redrawing every step let the 90-deg clipped turn cycle a lattice of headings
    keep = hazard & (wr < 0) & (np.abs(wrap(wg - wh)) > 1e-9)
    wg = np.where(hazard & ~keep, wh + side * (0.5 * np.pi + 0.5 * np.pi * u[1]), wg)
    wr = np.where(hazard, AVOIDING, np.where(wr < 0, 0.0, wr))
    calm = ~hazard & ~straight
    if p.walk == "levy":
        wr = np.where(calm, wr - dist, wr)
        need = calm & (wr <= 0)
        wg = np.where(need, wh + np.pi * (2 * u[2] - 1), wg)
        wr = np.where(need, levy_lengths(u[3], p), wr)
    else:
        turn = np.where(u[2] < p.random_turn_prob, np.where(u[3] < 0.5, -1.0, 1.0) * p.random_turn_rad, 0.0)
        wg = np.where(calm, wg + turn, wg)
    d = wrap(wg - wh)
    dh = np.clip(d, -p.turn_max_rad, p.turn_max_rad)
    nh_ = wrap(wh + dh)
    aligned = np.abs(d - dh) < 1e-9
    step = np.where(aligned & ~hazard, dist, 0.0)
    nx, ny = wx + step * np.cos(nh_), wy + step * np.sin(nh_)
    ok = world.pose_ok(nx, ny, nh_)
    if not ok.all():
        bad = ~ok
        bx, by, bh = wx[bad], wy[bad], wh[bad]
        ax, ay = bx + dist * np.cos(bh), by + dist * np.sin(bh)      # 1) drive, no turn
        ok1 = world.pose_ok(ax, ay, bh)
        ok2 = world.pose_ok(bx, by, nh_[bad])                          # 2) turn, no drive
        mid = 0.5 * (world.x0_cm + world.x1_cm) if np.isfinite(world.x0_cm) else np.inf
        sx = bx + np.where(bx < mid, -dist, dist)                      # 3) slide off the edge
        ok3 = world.pose_ok(sx, by, bh)
        nx[bad] = np.where(ok1, ax, np.where(ok2, bx, np.where(ok3, sx, bx)))
        ny[bad] = np.where(ok1, ay, by)
        nh_[bad] = np.where(ok1, bh, np.where(ok2, nh_[bad], bh))
        wr[bad] = np.where(ok2 & ~ok1, wr[bad], np.where(wr[bad] < 0, 0.0, wr[bad]))  # turn refused: redraw next
    x[walkers], y[walkers], h[walkers] = nx, ny, nh_
    goal[walkers], run_left[walkers] = wg, wr


if HAVE_NUMBA:

    @numba.njit(cache=True, inline="always")
    def _ok_box(x, y, c, s, sq, hl, hw, W, H, x0, x1, r):  # pragma: no cover - compiled
        """pose_ok for one robot, given cos/sin of its heading, without the obstacles (scalars
        only: an inlined helper that takes an array pays its reference count on every call)."""
        c = abs(c)
        s = abs(s)
        if sq:
            ex = hl * c + hw * s
            ey = hl * s + hw * c
        else:
            ex = r
            ey = r
        if x - ex < 0 or x + ex > W or y - ey < 0 or y + ey > H:
            return False
        if x + ex > x0 + 1e-9 and x - ex < x1 - 1e-9:
            return False
        return True

    @numba.njit(cache=True)
    def _clear_of(x, y, obs, r):  # pragma: no cover - compiled
        """No obstacle of ``obs`` (rows x, y, radius) within ``r`` of (x, y)."""
        for k in range(obs.shape[0]):
            if (x - obs[k, 0]) ** 2 + (y - obs[k, 1]) ** 2 <= (obs[k, 2] + r) ** 2:
                return False
        return True

    @numba.njit(cache=True, inline="always")
    def _wrap(a):  # pragma: no cover - compiled
        if -math.pi <= a < math.pi:  # same as world.wrap, bit for bit
            return a
        return (a + math.pi) % (2 * math.pi) - math.pi

    @numba.njit(cache=True, error_model="numpy")
    def _walk_kernel(x, y, h, goal, run_left, walkers, straight, u, sq, hl, hw, W, H, x0, x1,
                     obs, r, detect, avoid, dist, turn_max, levy, mu, lmin, lmax, p_turn,
                     turn_rad, snap_x, snap_y, nbr_start, nbr_idx, rw, jt, hc, hs):  # pragma: no cover - compiled
        """One walk step of ``walkers`` in place (the numba twin of :func:`_walk_numpy`).

        ``snap_x``, ``snap_y``: positions before anyone moves (the neighbour list was built
        from them). The step's ``4 x k`` uniforms are ``u``, or, with a non-empty jump table
        ``jt`` (the compiled engine), only the ones read are computed from the stream words
        ``rw`` (the caller then jumps the stream past the step). ``hc``, ``hs`` (length n, or
        empty): cos and sin of every walker's heading, read instead of recomputed and kept
        up to date (the compiled engine's steps; a heading changes on few steps).

        No helper that takes an array is called per walker: numba reference-counts an array
        passed to an inlined helper on every call (two atomic operations each), which measured
        ~5 % of the exploration bench and ~10 % of the compiled engine's large-void step; the
        neighbour test and the draws are written out here, and the obstacle test
        (:func:`_clear_of`) is called only when the world has obstacles."""
        r2 = avoid * avoid
        q = 0.5 * hw
        a = mu - 1.0
        mid = 0.5 * (x0 + x1)
        sense = hl + q + detect + 1.0
        kw = walkers.shape[0]
        cached = hc.shape[0] > 0
        lazy = jt.shape[0] > 0
        nobs = obs.shape[0]
        for k in range(kw):  # index order: the per-robot arrays stream through cache
            i = walkers[k]
            wx = x[i]
            wy = y[i]
            wh = h[i]
            if cached:
                c = hc[i]
                s = hs[i]
            else:
                c = math.cos(wh)
                s = math.sin(wh)
            hz = False
            # the ground sensors reach at most hl + q + detect from the centre (|cos|, |sin| <= 1;
            # 1 cm more for rounding): a walker farther from the void band skips their test
            if x0 < 1e300 and wx + sense > x0 and wx - sense < x1:
                reach = detect * c
                for lat in (0.0, q, -q):
                    px = wx + hl * c - lat * s
                    lo = min(px, px + reach)
                    hi = max(px, px + reach)
                    if hi > x0 and lo < x1:
                        hz = True
            px = wx + avoid * c
            py = wy + avoid * s
            if px < 0 or px > W or py < 0 or py > H:
                hz = True
            for o in range(nobs):
                dx = obs[o, 0] - wx
                dy = obs[o, 1] - wy
                if dx * dx + dy * dy < (obs[o, 2] + avoid) ** 2 and dx * c + dy * s > 0:
                    hz = True
            if not hz and not straight[k]:
                for m in range(nbr_start[i], nbr_start[i + 1]):  # a listed neighbour ahead, within avoid
                    j = nbr_idx[m]
                    ddx = snap_x[j] - wx
                    ddy = snap_y[j] - wy
                    if ddx * ddx + ddy * ddy < r2 and ddx * c + ddy * s > 0:
                        hz = True
                        break
            g = goal[i]
            rl = run_left[i]
            if rl < 0 and not hz:
                rl = 0.0
            if hz:
                if not (rl < 0 and abs(_wrap(g - wh)) > 1e-9):  # see _walk_numpy: keep
                    side = -1.0 if (draw_at(rw, jt, 0 * kw + k) if lazy else u[0, k]) < 0.5 else 1.0
                    g = wh + side * (0.5 * math.pi + 0.5 * math.pi * (draw_at(rw, jt, 1 * kw + k) if lazy else u[1, k]))
                rl = AVOIDING
            elif not straight[k]:
                if levy:
                    rl -= dist
                    if rl <= 0:
                        g = wh + math.pi * (2 * (draw_at(rw, jt, 2 * kw + k) if lazy else u[2, k]) - 1)
                        u3 = (draw_at(rw, jt, 3 * kw + k) if lazy else u[3, k])
                        if abs(a) < 1e-9:
                            rl = math.exp(math.log(lmin) + u3 * (math.log(lmax) - math.log(lmin)))
                        else:
                            lo_ = lmin ** -a
                            hi_ = lmax ** -a
                            rl = (lo_ + u3 * (hi_ - lo_)) ** (-1.0 / a)
                elif (draw_at(rw, jt, 2 * kw + k) if lazy else u[2, k]) < p_turn:
                    g = g + (-1.0 if (draw_at(rw, jt, 3 * kw + k) if lazy else u[3, k]) < 0.5 else 1.0) * turn_rad
            d = _wrap(g - wh)
            dh = min(max(d, -turn_max), turn_max)
            if dh == 0.0:  # no turn this step (the common case): reuse the heading's cos/sin
                nh = wh
                cn = c
                sn = s
            else:
                nh = _wrap(wh + dh)
                cn = math.cos(nh)
                sn = math.sin(nh)
            st = dist if (abs(d - dh) < 1e-9 and not hz) else 0.0
            nx = wx + st * cn
            ny = wy + st * sn
            if not (_ok_box(nx, ny, cn, sn, sq, hl, hw, W, H, x0, x1, r) and (nobs == 0 or _clear_of(nx, ny, obs, r))):
                ax = wx + dist * c
                ay = wy + dist * s
                sx = wx - dist if wx < mid else wx + dist
                turned = False
                if (_ok_box(ax, ay, c, s, sq, hl, hw, W, H, x0, x1, r) and (nobs == 0 or _clear_of(ax, ay, obs, r))):
                    nx, ny, nh = ax, ay, wh
                elif (_ok_box(wx, wy, cn, sn, sq, hl, hw, W, H, x0, x1, r) and (nobs == 0 or _clear_of(wx, wy, obs, r))):
                    nx, ny = wx, wy
                    turned = True
                elif (_ok_box(sx, wy, c, s, sq, hl, hw, W, H, x0, x1, r) and (nobs == 0 or _clear_of(sx, wy, obs, r))):
                    nx, ny, nh = sx, wy, wh
                else:
                    nx, ny, nh = wx, wy, wh
                if not turned:
                    cn = c
                    sn = s
                    if rl < 0:  # turn refused: redraw the avoidance goal next step
                        rl = 0.0
            if cached:
                hc[i] = cn
                hs[i] = sn
            x[i] = nx
            y[i] = ny
            h[i] = nh
            goal[i] = g
            run_left[i] = rl


_U_CACHE: dict = {}
# the reference walk draws its uniforms into ``u`` and computes every cos/sin (no jump table, no cache)
_NO_WORDS = np.zeros(4, np.uint64)
_NO_TABLE = np.zeros((0, 4), np.uint64)
_NO_CACHE = np.zeros(0)


def walk(x, y, h, goal, run_left, walkers, straight, world: World, p: Params, rng: np.random.Generator,
         use_numba: bool | None = None):
    """Advance ``walkers`` (int index array) by one step; ``straight`` (bool over walkers)
    marks dispersing robots that keep their heading goal and ignore other robots.
    Returns new (x, y, h, goal, run_left) full arrays. Both back-ends consume the same
    random numbers, so a seed gives the same run with or without numba."""
    px, py = x, y  # inputs are never mutated: they are the pre-step snapshot
    x, y, h, goal, run_left = x.copy(), y.copy(), h.copy(), goal.copy(), run_left.copy()
    k = walkers.size
    if k == 0:
        return x, y, h, goal, run_left
    if use_numba is None:
        use_numba = HAVE_NUMBA
    if k >= 4096:  # reuse a buffer: fresh large arrays every step cost page faults
        u = _U_CACHE.get(k)
        if u is None:
            _U_CACHE.clear()
            u = _U_CACHE[k] = np.empty((4, k))
        rng.random(out=u)
    else:
        u = rng.random((4, k))
    if use_numba and HAVE_NUMBA and world.shape == "square":
        _walk_kernel(x, y, h, goal, run_left, walkers.astype(np.int64), straight, u,
                     True, 0.5 * world.length_cm, 0.5 * world.width_cm, world.w_cm, world.h_cm,
                     world.x0_cm if np.isfinite(world.x0_cm) else 1e308,
                     world.x1_cm if np.isfinite(world.x1_cm) else 1e308,
                     world.obstacles, world.body_radius_cm, world.detect_cm, world.avoid_cm,
                     p.speed_cm_s * p.dt_s, p.turn_max_rad, p.walk == "levy", p.levy_mu,
                     p.levy_min_cm, p.levy_max_cm, p.random_turn_prob, p.random_turn_rad,
                     px, py, *neighbour_list(px, py, p.avoid_cm)[7:9], _NO_WORDS, _NO_TABLE, _NO_CACHE, _NO_CACHE)
    else:
        q = walkers[~straight]
        blocked = blocked_ahead(x, y, h, q, p.avoid_cm, use_numba)[walkers] if q.size else np.zeros(k, bool)
        _walk_numpy(x, y, h, goal, run_left, walkers, straight, blocked, u, world, p)
    return x, y, h, goal, run_left
