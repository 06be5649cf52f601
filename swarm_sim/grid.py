"""Neighbour queries through a uniform grid (cell = query radius): O(N), never N x N.

:func:`blocked_ahead` answers, for each querying robot, "is another robot's centre
within ``radius_cm`` and in my front half-plane?". A numba kernel (counting sort
into cells, then a 3 x 3 cell scan) is used when numba is installed; otherwise a
vectorised numpy version (sort + searchsorted pair generation) gives identical results.
"""

from __future__ import annotations

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

    @numba.njit(cache=True)
    def _blocked_kernel(x, y, h, query, radius, out):  # pragma: no cover - compiled
        n = x.shape[0]
        x0 = x.min()
        y0 = y.min()
        nx = int((x.max() - x0) / radius) + 3
        ny = int((y.max() - y0) / radius) + 3
        ncell = nx * ny
        counts = np.zeros(ncell + 1, np.int64)
        cell = np.empty(n, np.int64)
        for i in range(n):
            c = (int((x[i] - x0) / radius) + 1) * ny + int((y[i] - y0) / radius) + 1
            cell[i] = c
            counts[c + 1] += 1
        for c in range(ncell):
            counts[c + 1] += counts[c]
        fill = counts[:-1].copy()
        items = np.empty(n, np.int64)
        for i in range(n):
            items[fill[cell[i]]] = i
            fill[cell[i]] += 1
        r2 = radius * radius
        for qi in range(query.shape[0]):
            i = query[qi]
            ci = cell[i]
            ch = np.cos(h[i])
            sh = np.sin(h[i])
            found = False
            for dx in range(-1, 2):
                for dy in range(-1, 2):
                    c = ci + dx * ny + dy
                    for k in range(counts[c], counts[c + 1]):
                        j = items[k]
                        if j == i:
                            continue
                        ddx = x[j] - x[i]
                        ddy = y[j] - y[i]
                        if ddx * ddx + ddy * ddy < r2 and ddx * ch + ddy * sh > 0:
                            found = True
                            break
                    if found:
                        break
                if found:
                    break
            out[i] = found


def blocked_ahead(x, y, h, query, radius, use_numba: bool | None = None):
    """Bool per robot (False for robots not in ``query``)."""
    if use_numba is None:
        use_numba = HAVE_NUMBA
    if use_numba and HAVE_NUMBA and x.shape[0] >= 2 and query.size:
        out = np.zeros(x.shape[0], dtype=np.bool_)
        _blocked_kernel(x, y, h, query.astype(np.int64), float(radius), out)
        return out
    return blocked_ahead_numpy(x, y, h, query, radius)
