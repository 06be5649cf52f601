"""Path planning on the static map: an occupancy grid and cost-to-go fields (cm).

A robot called to the structure (a recruit, a foot-column robot) does not only steer
locally: it follows the shortest path on a grid of the arena whose free cells are the
places where its whole body can turn on the spot (the circumscribed disc of radius
:attr:`World.body_radius_cm` clears the walls, the obstacles, the void and the
structure's own robots). One Dijkstra search from the goal (``scipy.sparse.csgraph``)
gives every cell its path length to the goal and the next cell towards it, so:

* choosing "the closest free robot" means the shortest *path*, not the straight line
  (a robot behind an obstacle, or on the wrong side of the structure, is farther);
* a robot with no path (``inf``) is never called;
* following the path is a table look-up per step (:func:`waypoint`).

Cell size is a third of the robot's smaller side (see :data:`MAX_CELLS`). The grid of a world is built once
(:func:`nav_grid`, cached); a field is cached by its goal cell and the structure's
footprint, so the robots recruited for one row share the work, and by its contents (goal
point and closed cells), so a later recruitment that closes the same cells under another
name reuses the search already settled (:mod:`swarm_sim.engine.field_cache`).

A field is settled lazily (:class:`CostField`): the search from the goal stops as soon as the
question asked (which free robot is nearest, where this robot drives next) has its final
answer, and resumes when a robot asks beyond what is settled. The search pops cells in one
fixed order, so every answer is the one the whole search gives (``EAGER`` settles each field
whole, for the tests that compare); on the large-void arena a recruit call settles about a
quarter of the 100,000 cells instead of all the reachable half.

The moving structure itself ignores obstacles (the thesis's assumption 13, Ch. 4.4):
only the robots that drive to it plan around them.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from swarm_sim.engine.dijkstra import dijkstra_start, grid_graph
from swarm_sim.engine.field_cache import FieldCache, contents_key
from swarm_sim.engine.grid import HAVE_NUMBA
from swarm_sim.engine.world import World

if HAVE_NUMBA:
    from swarm_sim.engine.dijkstra import dijkstra_resume
    from swarm_sim.engine.grid import numba

    @numba.njit(cache=True, inline="always")
    def _floor_div(x, c):  # pragma: no cover - compiled
        """Python's ``x // c`` (numba's float floor division, CPython's fmod-based algorithm, costs
        ~12 ns; this ~2): ``floor(x / c)`` unless the rounded quotient is a whole number, where the
        true quotient may lie just below it, and then the exact algorithm. (A rounded quotient that
        is not whole has the true one's floor: a whole number between them would be nearer the
        true quotient than the rounding.)"""
        q = x / c
        f = math.floor(q)
        if f != q:
            return f
        return x // c

    @numba.njit(cache=True, inline="always")
    def _cell_ij(x, y, cell, gnx, gny):  # pragma: no cover - compiled
        i = min(gnx - 1, max(0, int(_floor_div(x, cell))))
        j = min(gny - 1, max(0, int(_floor_div(y, cell))))
        return i, j

    @numba.njit(cache=True)
    def _near(x, y, cost, cell, gnx, gny, window, gcx, gcy, blocked):  # pragma: no cover - compiled
        """:meth:`CostField._near` compiled, the same answer (np.hypot is libm's hypot, as numba's
        math.hypot; the window in the same order, the first of equal minima): (best, cell)."""
        i, j = _cell_ij(x, y, cell, gnx, gny)
        j0 = max(0, j - window)
        j1 = min(gny, j + window + 1)
        i0 = max(0, i - window)
        i1 = min(gnx, i + window + 1)
        best = math.inf
        bi = -1
        for jj in range(j0, j1):
            for ii in range(i0, i1):
                c = jj * gnx + ii
                v = cost[c]
                if v < blocked:
                    v = v + math.hypot(x - gcx[c], y - gcy[c])
                    if v < best:
                        best = v
                        bi = c
        if bi < 0:
            return math.inf, -1
        return best, bi

#: settle every cost field whole when it is made (the search as it was before it became lazy:
#: the tests run both ways and compare)
EAGER = False

#: edges into a blocked cell get this weight; a cost above :data:`BLOCKED` is "no path"
_BLOCK_W = 1e9
BLOCKED = 1e8
_HOPS = 3  # the waypoint is this many cells ahead on the path
#: the grid's cells are a third of the robot's smaller side, coarser only in arenas that
#: would need more cells than this (the large-void arenas, which have no obstacles)
MAX_CELLS = 100_000


@dataclass(frozen=True, eq=False)
class NavGrid:
    """Occupancy grid of a world: ``ny x nx`` cells of ``cell_cm``, flattened row-major."""

    cell_cm: float
    nx: int
    ny: int
    clearance_cm: float
    free: np.ndarray        # bool (ny*nx,): static free cells (walls, obstacles, void)
    cx: np.ndarray          # cell centres (cm), (ny*nx,)
    cy: np.ndarray
    ei: np.ndarray          # undirected edges between 8-neighbours, both ends static-free
    ej: np.ndarray
    ew: np.ndarray          # edge length (cm)
    window: int = 3         # cells searched around a robot standing in a closed cell

    def cell(self, x: float, y: float) -> int:
        i = min(self.nx - 1, max(0, int(x // self.cell_cm)))
        j = min(self.ny - 1, max(0, int(y // self.cell_cm)))
        return j * self.nx + i

    def cells(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        i = np.clip((np.asarray(x) // self.cell_cm).astype(np.int64), 0, self.nx - 1)
        j = np.clip((np.asarray(y) // self.cell_cm).astype(np.int64), 0, self.ny - 1)
        return j * self.nx + i


_GRIDS: OrderedDict = OrderedDict()
#: the cost fields made so far, by name and by contents (64 named, LRU)
_FIELDS = FieldCache(64)


def _world_key(world: World) -> tuple:
    return (world.w_cm, world.h_cm, world.x0_cm, world.x1_cm, world.length_cm, world.width_cm, world.shape,
            world.obstacles.tobytes())


def _clear_of_world(world: World, x: np.ndarray, y: np.ndarray, r: float) -> np.ndarray:
    """A disc of radius ``r`` (cm) at (x, y) clears the walls, the void and the obstacles."""
    ok = (x - r >= 0) & (x + r <= world.w_cm) & (y - r >= 0) & (y + r <= world.h_cm)
    if math.isfinite(world.x0_cm):
        ok &= ~((x + r > world.x0_cm + 1e-9) & (x - r < world.x1_cm - 1e-9))
    for ox, oy, orad in world.obstacles:
        ok &= (x - ox) ** 2 + (y - oy) ** 2 > (orad + r) ** 2
    return ok


def disc_clear(world: World, x: float, y: float) -> bool:
    """A robot at (x, y) can turn on the spot without touching a wall, the void or an obstacle."""
    return bool(_clear_of_world(world, np.array([x]), np.array([y]), world.body_radius_cm)[0])


def nav_grid(world: World) -> NavGrid:
    """The world's grid (built once per world geometry)."""
    key = _world_key(world)
    g = _GRIDS.get(key)
    if g is not None:
        _GRIDS.move_to_end(key)
        return g
    cell = max(min(world.length_cm, world.width_cm) / 3.0, math.sqrt(world.w_cm * world.h_cm / MAX_CELLS))
    nx, ny = max(1, math.ceil(world.w_cm / cell)), max(1, math.ceil(world.h_cm / cell))
    jj, ii = np.divmod(np.arange(nx * ny), nx)
    cx, cy = (ii + 0.5) * cell, (jj + 0.5) * cell
    r = world.body_radius_cm
    free = _clear_of_world(world, cx, cy, r)
    idx = np.arange(nx * ny).reshape(ny, nx)
    f2 = free.reshape(ny, nx)
    ei, ej, ew = [], [], []
    for dy, dx, w in ((0, 1, 1.0), (1, 0, 1.0), (1, 1, math.sqrt(2)), (1, -1, math.sqrt(2))):
        xa, xb = max(0, -dx), nx - max(0, dx)
        a, b = idx[0:ny - dy, xa:xb], idx[dy:ny, xa + dx:xb + dx]
        m = f2[0:ny - dy, xa:xb] & f2[dy:ny, xa + dx:xb + dx]
        if dx and dy:  # no diagonal through a blocked corner
            m &= f2[0:ny - dy, xa + dx:xb + dx] & f2[dy:ny, xa:xb]
        ei.append(a[m])
        ej.append(b[m])
        ew.append(np.full(int(m.sum()), w * cell))
    window = math.ceil((world.length_cm + world.width_cm) / cell) + 2
    g = NavGrid(cell, nx, ny, r, free, cx, cy, np.concatenate(ei), np.concatenate(ej), np.concatenate(ew), window)
    _GRIDS[key] = g
    while len(_GRIDS) > 8:
        _GRIDS.popitem(last=False)
    return g


def footprint_mask(grid: NavGrid, cx: np.ndarray, cy: np.ndarray, half_x: float, half_y: float) -> np.ndarray:
    """Cells whose centre is within ``half_x`` / ``half_y`` (cm) of a robot standing at (cx, cy)
    (the structure's members; the caller adds the moving robot's own half size)."""
    blocked = np.zeros(grid.nx * grid.ny, dtype=bool)
    if len(cx) == 0:
        return blocked
    b2 = blocked.reshape(grid.ny, grid.nx)
    rx, ry = half_x, half_y
    c = grid.cell_cm
    # the structure's robots stand in rows and lines: merge them into runs of a rectangle each
    i0 = np.clip(np.floor((np.asarray(cx) - rx) / c - 0.5).astype(np.int64) + 1, 0, grid.nx)
    i1 = np.clip(np.ceil((np.asarray(cx) + rx) / c - 0.5).astype(np.int64), 0, grid.nx)
    j0 = np.clip(np.floor((np.asarray(cy) - ry) / c - 0.5).astype(np.int64) + 1, 0, grid.ny)
    j1 = np.clip(np.ceil((np.asarray(cy) + ry) / c - 0.5).astype(np.int64), 0, grid.ny)
    for box in set(zip(i0.tolist(), i1.tolist(), j0.tolist(), j1.tolist(), strict=True)):
        a, b, d, e = box
        b2[d:e, a:b] = True
    return blocked


class _Search:
    """A Dijkstra search left part-way (:func:`swarm_sim.engine.dijkstra.dijkstra_resume`): its heap and
    the graph it runs on."""

    __slots__ = ("args", "hd", "hi", "size")

    def __init__(self, args: tuple, hd: np.ndarray, hi: np.ndarray) -> None:
        self.args, self.hd, self.hi, self.size = args, hd, hi, 1


@dataclass(frozen=True, eq=False)
class CostField:
    """Path length (cm) from every cell to the goal cell, and the next cell on that path.

    Computed lazily: the search from the goal stops once what was asked is known and resumes
    when a farther cell is asked for. A cell whose ``cost`` is below :attr:`front` is final (its
    path and every cell on it too); the others are at least :attr:`front` away. Every method
    answers exactly what the whole search would (its pops are the whole search's first ones, in
    order): it settles more cells first when the answer depends on one not yet final."""

    grid: NavGrid
    goal_x: float
    goal_y: float
    goal_cell: int
    cost: np.ndarray     # (cells,) cm; > BLOCKED: no path (for cells beyond the front: not yet known)
    nxt: np.ndarray      # (cells,) next cell towards the goal (-9999 at the goal / no path)
    closed: np.ndarray   # (cells,) bool: cells a turning robot cannot occupy
    search: _Search | None = None  # None: the search is complete

    @property
    def front(self) -> float:
        """Every cell costing less than this (cm) is final; ``inf`` once the search is complete."""
        s = self.search
        return math.inf if s is None else float(s.hd[0])

    def settle(self, until_cm: float) -> None:
        """Settle every cell whose cost is at most ``until_cm`` (``inf``: all)."""
        s = self.search
        if s is None or not s.size or s.hd[0] > until_cm:
            return
        s.size, s.hd, s.hi = dijkstra_resume(*s.args, self.cost, self.nxt, s.hd, s.hi, s.size, float(until_cm))
        if not s.size:
            object.__setattr__(self, "search", None)

    def extend(self, read: float) -> None:
        """Settle beyond a value read that was not yet final (``read``: the cost read, cm, or
        ``inf``), with a margin so a robot driving along the field does not ask again at once."""
        base = max(self.front, read if read < BLOCKED else 0.0)
        self.settle(base + max(20.0 * self.grid.cell_cm, 0.25 * base))

    def known(self, read: float) -> bool:
        """A value read from :attr:`cost` (or the best of a window of it) is final."""
        return self.search is None or read < self.front

    def final(self, read: float, x: float, y: float) -> bool:
        """:meth:`known`, or the robot at (x, y) stands in a closed cell with no open cell in its
        window (``inf``, however far the search goes)."""
        if self.known(read):
            return True
        g = self.grid
        return bool(self.closed[g.cell(x, y)] and self.closed[self._window(x, y)].all())

    def _window(self, x: float, y: float) -> np.ndarray:
        """The cells within :attr:`NavGrid.window` of (x, y)."""
        g = self.grid
        i, j = min(g.nx - 1, max(0, int(x // g.cell_cm))), min(g.ny - 1, max(0, int(y // g.cell_cm)))
        j0, j1, i0, i1 = max(0, j - g.window), min(g.ny, j + g.window + 1), max(0, i - g.window), \
            min(g.nx, i + g.window + 1)
        return (np.arange(j0, j1)[:, None] * g.nx + np.arange(i0, i1)[None, :]).ravel()

    def cost_at(self, x: float, y: float) -> float:
        """Path length (cm) from a robot at (x, y): its cell's, or (next to a wall) the best
        neighbouring cell's plus the step to it; ``inf`` when there is no path."""
        while True:
            c = self.grid.cell(x, y)
            v = float(self.cost[c])
            if v < BLOCKED and self.known(v):
                return v + math.hypot(x - self.grid.cx[c], y - self.grid.cy[c])
            if not self.closed[c]:
                if self.known(v):
                    return math.inf  # an open cell with no path: walled in
                self.extend(v)
                continue
            best, _ = self._near(x, y)
            if self.final(best, x, y):
                return best
            self.extend(best)

    def costs(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """:meth:`cost_at` for many robots."""
        return np.array([self.cost_at(float(a), float(b)) for a, b in zip(x, y, strict=True)])

    def nearest(self, x: np.ndarray, y: np.ndarray) -> tuple[int, float]:
        """Index of the robot at (x[i], y[i]) with the shortest path (the first of equals) and
        its path length (cm); (-1, inf) when none has a path. The same answer as the argmin of
        :meth:`path_costs`, settling only as far as the nearest robot needs."""
        if len(x) == 0:
            return -1, math.inf
        g = self.grid
        c = g.cells(x, y)
        walled = np.flatnonzero(self.closed[c])  # their own cell's cost is never set: they look round
        while True:
            front = self.front
            raw = self.cost[c]
            v = raw + np.hypot(x - g.cx[c], y - g.cy[c])
            final = raw < front  # a robot beyond the front is at least the front away
            for i in walled:  # final when the best of its window is below the front (cost_at's rule)
                v[i], _ = self._near(float(x[i]), float(y[i]))
                final[i] = self.final(v[i], float(x[i]), float(y[i]))
            if self.search is None:
                v = np.where(v >= BLOCKED, np.inf, v)
                i = int(np.argmin(v))
                return (i, float(v[i])) if np.isfinite(v[i]) else (-1, math.inf)
            vk = np.where(final, v, np.inf)
            i = int(np.argmin(vk))
            best = float(vk[i])
            if best < front:
                return i, best
            # just past the best final candidate; none yet: a little farther (the search's own
            # rings, so the settled area stays close to the nearest robot's)
            self.settle(best if best < BLOCKED else 1.25 * front + 4.0 * g.cell_cm)

    def path_costs(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Path length (cm) of each robot to the goal (``inf``: no path), all final."""
        if len(x) == 0:
            return np.zeros(0)
        g = self.grid
        c = g.cells(x, y)
        while True:
            raw = self.cost[c]
            open_unknown = ~self.closed[c] & (raw >= self.front)
            if self.search is None or not open_unknown.any():
                break
            self.extend(float(np.max(np.where(raw[open_unknown] < BLOCKED, raw[open_unknown], 0.0))))
        v = self.cost[c] + np.hypot(x - g.cx[c], y - g.cy[c])
        bad = (self.cost[c] >= BLOCKED) & self.closed[c]
        for i in np.flatnonzero(bad):
            v[i] = self.cost_at(float(x[i]), float(y[i]))
        return np.where(v >= BLOCKED, np.inf, v)

    def _near(self, x: float, y: float) -> tuple[float, int]:
        """Best open cell within :attr:`NavGrid.window` cells (path cost plus the straight step
        to it): for a robot standing where the grid is closed (by a wall, or among the
        structure's robots after stepping off a foot). The value is final when :meth:`known`.
        Compiled when numba is there (the same answer, ~30x cheaper: a recruitment asks it for
        every robot standing by a wall or the structure, each time the search goes further)."""
        g = self.grid
        if HAVE_NUMBA:
            return _near(x, y, self.cost, g.cell_cm, g.nx, g.ny, g.window, g.cx, g.cy, BLOCKED)
        idx = self._window(x, y)
        v = self.cost[idx]
        v = np.where(v < BLOCKED, v + np.hypot(x - g.cx[idx], y - g.cy[idx]), np.inf)
        k = int(np.argmin(v))
        return (float(v[k]), int(idx[k])) if np.isfinite(v[k]) else (math.inf, -1)

    def waypoint(self, x: float, y: float) -> tuple[float, float] | None:
        """Where a robot at (x, y) drives next: a cell a few hops ahead on its path, the goal
        point once the path reaches the goal cell, ``None`` when there is no path."""
        g = self.grid
        c = g.cell(x, y)
        while True:
            v = float(self.cost[c])
            if self.closed[c]:
                best, near = self._near(x, y)
                if not self.final(best, x, y):
                    self.extend(best)
                    continue
                return None if near < 0 else (float(g.cx[near]), float(g.cy[near]))
            if not self.known(v):
                self.extend(v)
                continue
            if v >= BLOCKED:
                return None
            break
        for _ in range(_HOPS):  # the path from a final cell is final
            if c == self.goal_cell:
                return self.goal_x, self.goal_y
            c = int(self.nxt[c])
            if c < 0:
                return self.goal_x, self.goal_y
        if c == self.goal_cell:
            return self.goal_x, self.goal_y
        return float(g.cx[c]), float(g.cy[c])


_GRAPHS: dict = {}


def _graph(grid: NavGrid) -> tuple:
    """The grid graph as the compiled search reads it (:func:`swarm_sim.engine.dijkstra.grid_graph`:
    per-cell direction masks, direction offsets and lengths), built once per grid."""
    hit = _GRAPHS.get(id(grid))
    if hit is not None and hit[0] is grid:
        return hit[1]
    out = grid_graph(grid.ei, grid.ej, grid.ew, grid.nx, grid.ny)
    if len(_GRAPHS) > 8:
        _GRAPHS.clear()
    _GRAPHS[id(grid)] = (grid, out)
    return out


def prepare(world: World) -> NavGrid:
    """Build (and cache for the process) what every cost field of this world geometry shares: its
    navigation grid and the grid's search graph. A run builds them on its first recruitment
    anyway; a benchmark builds them before it times anything, as it compiles the kernels."""
    grid = nav_grid(world)
    _graph(grid)
    return grid


def cost_field(world: World, goal_x: float, goal_y: float, blocked=None, blocked_key: bytes = b"") -> CostField:
    """The field towards (goal_x, goal_y) cm with ``blocked`` cells (the structure) closed:
    a bool mask over the cells, or a function returning it (called only when the field for
    ``blocked_key`` is not cached yet).

    The goal's own cell is always open (a staging point chosen by
    :func:`approach_point` may sit closer to a wall than the grid's clearance)."""
    grid = nav_grid(world)
    gc = grid.cell(goal_x, goal_y)
    wk = _world_key(world)
    key = (wk, gc, round(goal_x, 6), round(goal_y, 6), blocked_key)
    cache = _FIELDS
    f = cache.named(key)
    if f is not None:
        return f
    n = grid.nx * grid.ny
    closed = ~grid.free.copy()
    if callable(blocked):
        blocked = blocked()
    if blocked is not None:
        closed |= blocked
    closed[gc] = False
    ckey = contents_key(wk, gc, goal_x, goal_y, closed)
    f = cache.by_contents(ckey)
    if f is not None:  # the same cells closed under another name: the same field
        return cache.put(key, ckey, f, built=False)
    # the goal cell joins its open neighbours even when the static grid calls it blocked
    extra_j, extra_w = _goal_edges(grid, gc, closed)
    if HAVE_NUMBA:  # the same search compiled (swarm_sim.engine.dijkstra: scipy's answer bit for bit), lazily
        cost, pred, hd, hi = dijkstra_start(n, gc)
        search = _Search((gc, closed, *_graph(grid), BLOCKED, extra_j, extra_w), hd, hi)
        f = CostField(grid, float(goal_x), float(goal_y), gc, cost, pred, closed, search)
        if not EAGER:
            f.settle(0.0)
        else:
            f.settle(math.inf)
        return cache.put(key, ckey, f)
    w = grid.ew + _BLOCK_W * (closed[grid.ei] | closed[grid.ej])
    ei = np.concatenate([grid.ei, np.full(len(extra_j), gc, dtype=np.int64)])
    ej = np.concatenate([grid.ej, extra_j])
    ww = np.concatenate([w, extra_w])
    graph = csr_matrix((ww, (ei, ej)), shape=(n, n))
    cost, pred = dijkstra(graph, directed=False, indices=gc, return_predecessors=True, limit=BLOCKED)
    cost = np.where(np.isfinite(cost), cost, np.inf)
    return cache.put(key, ckey, CostField(grid, float(goal_x), float(goal_y), gc, cost, pred.astype(np.int64), closed))


def _goal_edges(grid: NavGrid, gc: int, closed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edges (target cells in increasing order, lengths in cm) joining a goal cell the static grid
    calls blocked to its open neighbours; none when the goal cell is free (its edges exist)."""
    if grid.free[gc]:
        return np.zeros(0, np.int64), np.zeros(0)
    gi, gj = gc % grid.nx, gc // grid.nx
    cells, lengths = [], []
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            ii, jj = gi + di, gj + dj
            if (di or dj) and 0 <= ii < grid.nx and 0 <= jj < grid.ny and not closed[jj * grid.nx + ii]:
                cells.append(jj * grid.nx + ii)
                lengths.append(math.hypot(di, dj) * grid.cell_cm)
    return np.array(cells, dtype=np.int64), np.array(lengths, dtype=float)

