"""Single-source Dijkstra on a fixed grid graph, compiled, giving scipy's answer bit for bit.

:func:`swarm_sim.navigation.cost_field` asks ``scipy.sparse.csgraph.dijkstra(graph,
directed=False, indices=goal, return_predecessors=True, limit=BLOCKED)`` for every recruit
call; building the sparse matrix and its transpose costs more than the search. Here the
graph's two CSR structures (the matrix and its transpose, as scipy builds them: rows
sorted by column) are computed once per grid (:func:`csr_pair`); the closed cells are a mask
(an edge into one weighs 1e9 in navigation, beyond the search's limit, so it is skipped).

The search is scipy's (``_shortest_path.pyx``, SciPy 1.11+): a priority queue (here a 4-ary heap) of
``(-distance, vertex)`` pairs (a max-heap: shortest distance first, ties to the larger
vertex index), a popped entry skipped when its vertex's distance has since decreased, each
vertex's CSR row scanned then its transpose's row, a neighbour updated when
``d + w <= limit`` and strictly shorter. That order is a total order on the entries, so the
result does not depend on the heap's implementation; the same float additions give the
same distances and the same predecessors. ``tests/swarm_sim/test_compiled_engine.py``
compares it with scipy on random fields.
"""

from __future__ import annotations

import numpy as np

from .grid import HAVE_NUMBA, numba

NULL_IDX = -9999  # scipy's "no predecessor"


def csr_pair(ei: np.ndarray, ej: np.ndarray, n: int):
    """For the edge list (ei[e], ej[e]) over ``n`` vertices (no duplicate pair): the CSR of the
    matrix (indptr, indices, edge order) and of its transpose, rows sorted by column."""
    order = np.lexsort((ej, ei))
    indptr = np.zeros(n + 1, np.int64)
    np.cumsum(np.bincount(ei, minlength=n), out=indptr[1:])
    order_t = np.lexsort((ei, ej))
    indptr_t = np.zeros(n + 1, np.int64)
    np.cumsum(np.bincount(ej, minlength=n), out=indptr_t[1:])
    return (indptr, ej[order].astype(np.int64), order.astype(np.int64),
            indptr_t, ei[order_t].astype(np.int64), order_t.astype(np.int64))


if HAVE_NUMBA:

    @numba.njit(cache=True, inline="always")
    def _before(d1, i1, d2, i2):  # pragma: no cover - compiled
        """Entry 1 pops before entry 2 (scipy: max of (-d, i))."""
        return d1 < d2 or (d1 == d2 and i1 > i2)

    @numba.njit(cache=True, inline="always")
    def _scan(v, vd, lo, hi_e, ix, wt, closed, limit, dist, pred, hd, hi, size):  # pragma: no cover - compiled
        """Relax the entries ``lo:hi_e`` of ``v``'s CSR row (pushing improved neighbours); returns
        the heap's new size (the heap has room for every push: at most one per directed edge). An
        edge into a closed cell weighs ``ew + 1e9`` in navigation, more than any limit used: it is
        never relaxed."""
        for e in range(lo, hi_e):
            j = ix[e]
            if closed[j]:
                continue
            nv = vd + wt[e]
            if nv <= limit and dist[j] > nv:
                dist[j] = nv
                pred[j] = v
                k = size  # push: sift up (a 4-ary heap)
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
        return size

    @numba.njit(cache=True)
    def dijkstra_resume(source, closed, indptr, indices, ew_csr, indptr_t, indices_t, ew_csr_t, limit, extra_j,
                        extra_w, dist, pred, hd, hi, size, until):  # pragma: no cover - compiled
        """Continue a search (the heap ``hd``/``hi`` of ``size`` entries, ``dist``/``pred`` so far)
        while the heap's top distance is ``<= until``; returns (size, hd, hi), the heap arrays
        grown (doubled) when a scan needs room. Stopping and resuming pops exactly the entries one
        uninterrupted run pops, in the same order: every cell whose distance is below the new top
        (``hd[0]``) is final, the rest are at least that far.

        Arguments as :func:`dijkstra_grid`'s; ``extra_j``/``extra_w``: edges from the source to
        these cells (sorted, lengths in cm) added to the graph: the goal in a cell the static grid
        calls blocked joins its open neighbours (its own CSR rows are empty then, so scipy, given
        the same edges in the matrix, scans exactly these first)."""
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
            need = size + indptr[v + 1] - indptr[v] + indptr_t[v + 1] - indptr_t[v] + extra_j.shape[0]
            if need > hd.shape[0]:
                cap = max(2 * hd.shape[0], need)
                nd = np.empty(cap)
                ni = np.empty(cap, np.int64)
                nd[:size] = hd[:size]
                ni[:size] = hi[:size]
                hd = nd
                hi = ni
            if v == source:
                size = _scan(v, vd, 0, extra_j.shape[0], extra_j, extra_w, closed, limit, dist, pred, hd, hi, size)
            size = _scan(v, vd, indptr[v], indptr[v + 1], indices, ew_csr, closed, limit, dist, pred, hd, hi, size)
            size = _scan(v, vd, indptr_t[v], indptr_t[v + 1], indices_t, ew_csr_t, closed, limit, dist, pred, hd,
                         hi, size)
        return size, hd, hi

    @numba.njit(cache=True)
    def dijkstra_grid(n, source, closed, indptr, indices, ew_csr, indptr_t, indices_t, ew_csr_t,
                      limit, extra_j, extra_w):  # pragma: no cover - compiled
        """(dist, pred) from ``source`` over the edges between open cells (``closed[source]`` is
        False), the whole search at once; ``ew_csr``/``ew_csr_t``: the edge lengths in each CSR's
        entry order; ``limit`` < the closed-edge weight (1e9); ``extra_j``/``extra_w`` as
        :func:`dijkstra_resume`'s."""
        dist = np.full(n, np.inf)
        pred = np.full(n, NULL_IDX, np.int64)
        hd = np.empty(256)
        hi = np.empty(256, np.int64)
        dist[source] = 0.0
        hd[0] = 0.0
        hi[0] = source
        dijkstra_resume(source, closed, indptr, indices, ew_csr, indptr_t, indices_t, ew_csr_t, limit, extra_j,
                        extra_w, dist, pred, hd, hi, 1, np.inf)
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


__all__ = ["NULL_IDX", "csr_pair", "dijkstra_start"] + (["dijkstra_grid", "dijkstra_resume"] if HAVE_NUMBA else [])
