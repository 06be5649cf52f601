"""Neighbour queries through a uniform grid (cell = query radius): O(N), never N x N.

:func:`blocked_ahead` answers, for each querying robot, "is another robot's centre
within ``radius_cm`` and in my front half-plane?". With numba the cells
are folded onto a power-of-two K x K table (K^2 >= 2N) and scanned 2 x 2, and the walk kernel
keeps a Verlet neighbour list built from them (:func:`neighbour_list`); otherwise a vectorised
numpy version (sort + searchsorted pair generation) gives identical results.
"""

from __future__ import annotations

import math

import numpy as np

try:  # optional acceleration
    import numba

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised only without numba
    numba = None
    HAVE_NUMBA = False


def _cells(x, y, radius):
    x0, y0 = x.min(), y.min()
    cx = ((x - x0) / radius).astype(np.int64)
    cy = ((y - y0) / radius).astype(np.int64)
    ny = int(cy.max()) + 3
    return cx + 1, cy + 1, ny


def blocked_ahead_numpy(x, y, h, query, radius):
    """numpy version: ``query`` is an int index array of the robots asking."""
    n = x.shape[0]
    out = np.zeros(n, dtype=bool)
    if n < 2 or query.size == 0:
        return out
    cx, cy, ny = _cells(x, y, radius)
    key = cx * ny + cy
    order = np.argsort(key, kind="stable")
    skey = key[order]
    qkey = key[query]
    c, s = np.cos(h[query]), np.sin(h[query])
    r2 = radius * radius
    hits = np.zeros(query.size, dtype=bool)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            nk = qkey + dx * ny + dy
            start = np.searchsorted(skey, nk, "left")
            end = np.searchsorted(skey, nk, "right")
            cnt = end - start
            tot = int(cnt.sum())
            if tot == 0:
                continue
            qi = np.repeat(np.arange(query.size), cnt)
            offs = np.arange(tot) - np.repeat(np.cumsum(cnt) - cnt, cnt)
            j = order[np.repeat(start, cnt) + offs]
            i = query[qi]
            ddx, ddy = x[j] - x[i], y[j] - y[i]
            hit = (j != i) & (ddx * ddx + ddy * ddy < r2) & (ddx * c[qi] + ddy * s[qi] > 0)
            if hit.any():
                hits[qi[hit]] = True
    out[query] = hits
    return out


if HAVE_NUMBA:

    @numba.njit(cache=True, error_model="numpy")
    def hash_build_into(x, y, radius, k, counts, fill, bucket, items, sx, sy):  # pragma: no cover
        """Robots binned over cells of side ``2 * radius`` folded onto a k x k table
        (k a power of two, k^2 >= 2N; cell (cx, cy) -> bucket (cx mod k, cy mod k)), written
        into caller-owned buffers (reused between steps: fresh half-megabyte arrays every
        step cost more in page faults than the binning itself). Memory and time are O(N)
        for any arena; folding only adds candidates, which the distance test rejects.
        sx/sy are the positions in bucket order (a snapshot: callers may move robots)."""
        n = x.shape[0]
        km = k - 1
        inv = 0.5 / radius
        counts[:] = 0
        for i in range(n):
            b = (np.int64(math.floor(x[i] * inv)) & km) * k + (np.int64(math.floor(y[i] * inv)) & km)
            bucket[i] = b
            counts[b + 1] += 1
        for b in range(k * k):
            counts[b + 1] += counts[b]
        fill[:] = counts[:-1]
        for i in range(n):
            f = fill[bucket[i]]
            items[f] = i
            sx[f] = x[i]
            sy[f] = y[i]
            fill[bucket[i]] += 1

    @numba.njit(cache=True, error_model="numpy")
    def hash_build(x, y, radius):  # pragma: no cover - compiled
        """:func:`hash_build_into` with fresh buffers: (counts, items, sx, sy, k)."""
        n = x.shape[0]
        k = 1
        while k * k < 2 * n:
            k *= 2
        counts = np.empty(k * k + 1, np.int64)
        fill = np.empty(k * k, np.int64)
        bucket = np.empty(n, np.int64)
        items = np.empty(n, np.int64)
        sx = np.empty(n)
        sy = np.empty(n)
        hash_build_into(x, y, radius, k, counts, fill, bucket, items, sx, sy)
        return counts, items, sx, sy, k

    @numba.njit(cache=True, inline="always")
    def hash_ahead(i, xi, yi, ch, sh, radius, counts, items, sx, sy, mask):  # pragma: no cover
        """Is another robot's centre within ``radius`` of (xi, yi) and ahead along (ch, sh)?
        Cells are ``2 * radius`` wide, so the disc touches only the 2 x 2 cells on the side
        of the point's cell it is nearest to."""
        inv = 0.5 / radius
        fx = xi * inv
        fy = yi * inv
        cx = np.int64(math.floor(fx))
        cy = np.int64(math.floor(fy))
        x_lo = cx - 1 if fx - cx < 0.5 else cx
        y_lo = cy - 1 if fy - cy < 0.5 else cy
        r2 = radius * radius
        for gx in range(x_lo, x_lo + 2):
            for gy in range(y_lo, y_lo + 2):
                b = (gx & (mask - 1)) * mask + (gy & (mask - 1))
                for k in range(counts[b], counts[b + 1]):
                    ddx = sx[k] - xi
                    ddy = sy[k] - yi
                    if items[k] != i and ddx * ddx + ddy * ddy < r2 and ddx * ch + ddy * sh > 0:
                        return True
        return False

    @numba.njit(cache=True)
    def _blocked_kernel(x, y, h, query, radius, out):  # pragma: no cover - compiled
        counts, items, sx, sy, mask = hash_build(x, y, radius)
        asks = np.zeros(x.shape[0], np.bool_)
        for qi in range(query.shape[0]):
            asks[query[qi]] = True
        for kk in range(items.shape[0]):  # bucket order: neighbouring queries share cache lines
            i = items[kk]
            if not asks[i]:
                continue
            out[i] = hash_ahead(i, x[i], y[i], math.cos(h[i]), math.sin(h[i]), radius,
                                counts, items, sx, sy, mask)
    @numba.njit(cache=True, error_model="numpy")
    def verlet_update(x, y, rc, skin, k, counts, fill, bucket, items, sx, sy, nbr_start, nbr_idx,
                      xref, yref, valid):  # pragma: no cover - compiled
        """Neighbour (Verlet) list as in JAX MD / MD codes: every pair closer than
        ``rc = radius + skin`` at the last rebuild, in CSR form (nbr_start, nbr_idx).
        While no robot has moved more than ``skin / 2`` since, the list still holds every
        pair within ``radius``, so queries stay exact. Returns -2 (list still valid), the
        number of entries after a rebuild, or -1 if ``nbr_idx`` is too small."""
        n = x.shape[0]
        h2 = 0.25 * skin * skin
        if valid[0] == 1:
            ok = True
            for i in range(n):
                dx = x[i] - xref[i]
                dy = y[i] - yref[i]
                if dx * dx + dy * dy > h2:
                    ok = False
                    break
            if ok:
                return -2
        valid[0] = 0
        hash_build_into(x, y, rc, k, counts, fill, bucket, items, sx, sy)
        km = k - 1
        inv = 0.5 / rc
        r2 = rc * rc
        cap = nbr_idx.shape[0]
        m = 0
        for i in range(n):
            nbr_start[i] = m
            xi = x[i]
            yi = y[i]
            fx = xi * inv
            fy = yi * inv
            cx = np.int64(math.floor(fx))
            cy = np.int64(math.floor(fy))
            x_lo = cx - 1 if fx - cx < 0.5 else cx
            y_lo = cy - 1 if fy - cy < 0.5 else cy
            for gx in range(x_lo, x_lo + 2):
                for gy in range(y_lo, y_lo + 2):
                    b = (gx & km) * k + (gy & km)
                    for kk in range(counts[b], counts[b + 1]):
                        j = items[kk]
                        if j != i:
                            ddx = sx[kk] - xi
                            ddy = sy[kk] - yi
                            if ddx * ddx + ddy * ddy < r2:
                                if m >= cap:
                                    return -1
                                nbr_idx[m] = j
                                m += 1
        nbr_start[n] = m
        for i in range(n):
            xref[i] = x[i]
            yref[i] = y[i]
        valid[0] = 1
        return m


_WORKSPACES: dict = {}
SKIN_CM = 3.0  # Verlet skin: the list is rebuilt once some robot has moved SKIN_CM / 2


def workspace(n: int, owner: str = "walk") -> tuple:
    """Reusable buffers for ``n`` robots: grid (k, counts, fill, bucket, items, sx, sy) and
    Verlet list (nbr_start, nbr_idx, xref, yref, valid). Each ``owner`` has its own (a Verlet
    list is valid only under the skin it was built with: the compiled engine's kernel uses a
    wider one than the walk, :data:`swarm_sim.compiled.KERNEL_SKIN_CM`)."""
    ws = _WORKSPACES.get((n, owner))
    if ws is None:
        k = 1
        while k * k < 2 * n:
            k *= 2
        ws = [k, np.empty(k * k + 1, np.int64), np.empty(k * k, np.int64), np.empty(n, np.int64),
              np.empty(n, np.int64), np.empty(n), np.empty(n),
              np.empty(n + 1, np.int64), np.empty(4 * n + 64, np.int64), np.empty(n), np.empty(n),
              np.zeros(1, np.int64)]
        if len(_WORKSPACES) > 8:
            _WORKSPACES.clear()
        _WORKSPACES[(n, owner)] = ws
    return ws


def neighbour_list(x, y, radius: float) -> list:
    """Bring the cached Verlet list for these positions up to date (growing it if needed);
    returns the workspace list. Exactness does not depend on the cache's history: a list
    built from positions all within SKIN_CM / 2 of the current ones holds every close pair."""
    ws = workspace(x.shape[0])
    while True:
        m = verlet_update(x, y, radius + SKIN_CM, SKIN_CM, *ws[:7], *ws[7:])
        if m != -1:
            return ws
        ws[8] = np.empty(2 * ws[8].shape[0], np.int64)  # more close pairs than room: grow


def blocked_ahead(x, y, h, query, radius, use_numba: bool | None = None):
    """Bool per robot (False for robots not in ``query``)."""
    if use_numba is None:
        use_numba = HAVE_NUMBA
    if use_numba and HAVE_NUMBA and x.shape[0] >= 2 and query.size:
        out = np.zeros(x.shape[0], dtype=np.bool_)
        _blocked_kernel(x, y, h, query.astype(np.int64), float(radius), out)
        return out
    return blocked_ahead_numpy(x, y, h, query, radius)
