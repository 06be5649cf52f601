"""Single-source Dijkstra on a fixed grid graph, compiled, giving scipy's answer bit for bit.

:func:`swarm_sim.engine.navigation.cost_field` asks ``scipy.sparse.csgraph.dijkstra(graph,
directed=False, indices=goal, return_predecessors=True, limit=BLOCKED)`` for every recruit
call; building the sparse matrix and its transpose costs more than the search. Here the
graph is the grid itself (:func:`grid_graph`, once per grid): per cell a bit mask of the
8-neighbour directions it has an edge in, and one length per direction, so a scan reads no
edge lists (the CSR form this replaced cost ~300 ns per cell reached on the 100,000-cell
large-void grid, mostly cache misses in its index arrays); the closed cells are a mask (an
edge into one weighs 1e9 in navigation, beyond the search's limit, so it is skipped).

The search is scipy's (``_shortest_path.pyx``, SciPy 1.11+): a priority queue (here a 4-ary heap) of
``(-distance, vertex)`` pairs (a max-heap: shortest distance first, ties to the larger
vertex index), a popped entry skipped when its vertex's distance has since decreased, each
of its neighbours (scipy: its CSR row, then its transpose's row) updated when ``d + w <=
limit`` and strictly shorter. That order is a total order on the entries, so the result
depends neither on the heap's implementation nor on the order a vertex's distinct
neighbours are scanned in; the same float additions give the same distances and the same
predecessors. ``tests/swarm_sim/test_compiled_engine.py``
compares it with scipy on random fields.
"""

from __future__ import annotations

import numpy as np

from swarm_sim.engine.grid import HAVE_NUMBA, numba

NULL_IDX = -9999  # scipy's "no predecessor"


#: The 8 neighbour directions (di, dj) of a grid cell; bit k of a cell's edge mask is direction k.
DIRECTIONS = ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (-1, 1), (1, -1))


def grid_graph(ei: np.ndarray, ej: np.ndarray, ew: np.ndarray, nx: int, ny: int):
    """The grid's edge list (ei[e], ej[e], length ew[e]; each pair once, between 8-neighbours) as
    the search uses it: per cell a bit mask of the directions (:data:`DIRECTIONS`) it has an edge
    in, the cell-index offset of each direction and the edge length of each direction (cm; every
    edge of a direction has the same length, checked)."""
    n = nx * ny
    mask = np.zeros(n, np.uint8)
    dw = np.full(8, np.nan)
    di = ej % nx - ei % nx
    dj = ej // nx - ei // nx
    for k, (a, b) in enumerate(DIRECTIONS):
        sel = (di == a) & (dj == b)
        back = (di == -a) & (dj == -b)
        if sel.any() or back.any():
            w = np.concatenate([ew[sel], ew[back]])
            if not np.all(w == w[0]):
                raise ValueError(f"grid edges of direction {(a, b)} differ in length")
            dw[k] = w[0]
        mask[ei[sel]] |= np.uint8(1 << k)  # a -> b in direction k
        kb = DIRECTIONS.index((-a, -b))
        mask[ej[sel]] |= np.uint8(1 << kb)  # and b -> a in the opposite one
    if ((di == 0) & (dj == 0)).any() or (np.abs(di) > 1).any() or (np.abs(dj) > 1).any():
        raise ValueError("grid edges must join distinct 8-neighbours")
    off = np.array([b * nx + a for a, b in DIRECTIONS], np.int64)
    return mask, off, np.nan_to_num(dw, nan=np.inf)


if HAVE_NUMBA:

    @numba.njit(cache=True, inline="always")
    def _before(d1, i1, d2, i2):  # pragma: no cover - compiled
        """Entry 1 pops before entry 2 (scipy: max of (-d, i))."""
        return d1 < d2 or (d1 == d2 and i1 > i2)

    @numba.njit(cache=True)
    def dijkstra_resume(source, closed, emask, off, dw, limit, extra_j, extra_w, dist, pred, hd, hi, size,
                        until):  # pragma: no cover - compiled
        """Continue a search (the heap ``hd``/``hi`` of ``size`` entries, ``dist``/``pred`` so far)
        while the heap's top distance is ``<= until``; returns (size, hd, hi), the heap arrays
        grown (doubled) when a scan needs room. Stopping and resuming pops exactly the entries one
        uninterrupted run pops, in the same order: every cell whose distance is below the new top
        (``hd[0]``) is final, the rest are at least that far.

        The graph is the grid's (:func:`grid_graph`): ``emask[v]`` the directions v has an edge
        in, ``off``/``dw`` each direction's index offset and length. An edge into a closed cell
        weighs ``ew + 1e9`` in navigation, more than any limit used: it is never relaxed.
        ``extra_j``/``extra_w``: edges from the source to these cells (lengths in cm) added to
        the graph: the goal in a cell the static grid calls blocked joins its open neighbours
        (it has no grid edges then). scipy scans a vertex's edges in its own order; the order
        of a vertex's distinct neighbours changes nothing (each is relaxed once from it, and the
        heap pops by the total order of (distance, index)), so the result is scipy's."""
        while size and hd[0] <= until:
            vd = hd[0]
            v = hi[0]
            size -= 1
            if size:  # pop: the last entry sifts down from the root
                ld = hd[size]
                li = hi[size]
                k = 0
                while True:
                    c = 4 * k + 1
                    if c >= size:
                        break
                    b = c
                    bd = hd[c]
                    bi = hi[c]
                    for q in range(c + 1, min(c + 4, size)):
                        if _before(hd[q], hi[q], bd, bi):
                            b = q
                            bd = hd[q]
                            bi = hi[q]
                    if _before(bd, bi, ld, li):
                        hd[k] = bd
                        hi[k] = bi
                        k = b
                    else:
                        break
                hd[k] = ld
                hi[k] = li
            if dist[v] < vd:
                continue
            need = size + 8 + extra_j.shape[0]
            if need > hd.shape[0]:
                cap = max(2 * hd.shape[0], need)
                nd = np.empty(cap)
                ni = np.empty(cap, np.int64)
                nd[:size] = hd[:size]
                ni[:size] = hi[:size]
                hd = nd
                hi = ni
            # its grid edges (directions 0..7), and the source its extra edges (8..); written out in
            # the loop, not through a helper: measured 2.3x faster (a full large-void field 17 -> 7.3 ms)
            m = emask[v]
            ne = extra_j.shape[0] if v == source else 0
            for q in range(8 + ne):
                if q < 8:
                    if not m & (1 << q):
                        continue
                    j = v + off[q]
                    w = dw[q]
                else:
                    j = extra_j[q - 8]
                    w = extra_w[q - 8]
                if closed[j]:
                    continue
                nv = vd + w
                if nv <= limit and dist[j] > nv:  # strictly shorter: push (sift up in the 4-ary heap)
                    dist[j] = nv
                    pred[j] = v
                    k = size
                    size += 1
                    while k > 0:
                        par = (k - 1) >> 2
                        if _before(nv, j, hd[par], hi[par]):
                            hd[k] = hd[par]
                            hi[k] = hi[par]
                            k = par
                        else:
                            break
                    hd[k] = nv
                    hi[k] = j
        return size, hd, hi

    @numba.njit(cache=True)
    def dijkstra_grid(n, source, closed, emask, off, dw, limit, extra_j, extra_w):  # pragma: no cover - compiled
        """(dist, pred) from ``source`` over the edges between open cells (``closed[source]`` is
        False), the whole search at once; arguments as :func:`dijkstra_resume`'s."""
        dist = np.full(n, np.inf)
        pred = np.full(n, NULL_IDX, np.int64)
        hd = np.empty(256)
        hi = np.empty(256, np.int64)
        dist[source] = 0.0
        hd[0] = 0.0
        hi[0] = source
        dijkstra_resume(source, closed, emask, off, dw, limit, extra_j, extra_w, dist, pred, hd, hi, 1, np.inf)
        return dist, pred


def dijkstra_start(n: int, source: int, capacity: int = 256):
    """A search's arrays before its first pop: ``dist``/``pred`` over ``n`` cells, the heap
    (``capacity`` entries, grown as needed) holding the source at distance 0 (size 1)."""
    dist = np.full(n, np.inf)
    pred = np.full(n, NULL_IDX, np.int64)
    hd = np.empty(capacity)
    hi = np.empty(capacity, np.int64)
    dist[source] = 0.0
    hd[0] = 0.0
    hi[0] = source
    return dist, pred, hd, hi


__all__ = ["DIRECTIONS", "NULL_IDX", "dijkstra_start", "grid_graph"] + (["dijkstra_grid", "dijkstra_resume"] if HAVE_NUMBA else [])
