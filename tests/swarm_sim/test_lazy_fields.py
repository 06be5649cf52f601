"""Cost fields are settled lazily (swarm_sim.engine.navigation.CostField): every answer is the one the
whole Dijkstra search gives, and whole runs are the runs with whole fields, bit for bit."""

import math

import numpy as np
import pytest

from swarm_sim.engine import navigation as N
from swarm_sim.engine.grid import HAVE_NUMBA
from swarm_sim.engine.world import World
from swarm_sim.runner import resolve_params, simulate

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="lazy fields are the compiled search's (numba)")


@pytest.fixture
def eager(monkeypatch):
    def set_(on: bool) -> None:
        monkeypatch.setattr(N, "EAGER", on)
        N._FIELDS.clear()
    yield set_
    N._FIELDS.clear()


def _worlds():
    posts = tuple((120.0, y, 6.0) for y in np.arange(0.0, 200.0, 10.0))  # a fence, open at the top
    return [World.from_params(resolve_params("case-d", 9, 3, "thesis")),
            World.from_params(resolve_params("case-d", 9, 3, "thesis", obstacles=posts)),
            World.from_params(resolve_params("large-void", 70, 8, "thesis"))]  # the arena, any record


@pytest.mark.parametrize("wi", range(3))
def test_every_query_of_a_lazy_field_is_the_whole_fields_answer(eager, wi):
    world = _worlds()[wi]
    g = N.nav_grid(world)
    rng = np.random.default_rng(wi)
    goals = [(float(g.cx[c]), float(g.cy[c])) for c in rng.choice(np.flatnonzero(g.free), 3, replace=False)]
    goals.append((float(g.cx[np.flatnonzero(~g.free)[0]]), float(g.cy[np.flatnonzero(~g.free)[0]])))
    # groups of 7: across the arena, and clustered within a few cells (where the within-cell
    # offset decides which robot is nearest)
    cx, cy = rng.uniform(0, world.w_cm, 30), rng.uniform(0, world.h_cm, 30)
    xs = np.concatenate([rng.uniform(0, world.w_cm, 63)] + [a + rng.uniform(-2, 2, 7) * g.cell_cm for a in cx])
    ys = np.concatenate([rng.uniform(0, world.h_cm, 63)] + [b + rng.uniform(-2, 2, 7) * g.cell_cm for b in cy])
    xs, ys = np.clip(xs, 0, world.w_cm), np.clip(ys, 0, world.h_cm)
    partial = 0
    for gx, gy in goals:
        eager(True)
        whole = N.cost_field(world, gx, gy)
        want = ([whole.cost_at(a, b) for a, b in zip(xs, ys, strict=True)],
                [whole.waypoint(a, b) for a, b in zip(xs, ys, strict=True)])
        want_near = [whole.nearest(xs[k:k + 7], ys[k:k + 7]) for k in range(0, len(xs), 7)]
        want_costs = whole.path_costs(xs, ys)
        eager(False)
        lazy = N.cost_field(world, gx, gy)
        assert lazy.search is not None or not np.isfinite(whole.cost).sum() > 1
        first = lazy.nearest(xs[-7:], ys[-7:])  # one cluster: settled no farther than it needs
        partial += lazy.search is not None and lazy.front < np.max(whole.cost[np.isfinite(whole.cost)])
        assert first == want_near[-1]
        got_near = [lazy.nearest(xs[k:k + 7], ys[k:k + 7]) for k in range(0, len(xs), 7)]
        assert got_near == want_near
        got = ([lazy.cost_at(a, b) for a, b in zip(xs, ys, strict=True)],
               [lazy.waypoint(a, b) for a, b in zip(xs, ys, strict=True)])
        assert got == want
        assert np.array_equal(lazy.path_costs(xs, ys), want_costs)
        # what it settled is the whole search's, cell for cell and predecessor for predecessor
        done = lazy.cost < lazy.front
        assert np.array_equal(lazy.cost[done], whole.cost[done]) and np.array_equal(lazy.nxt[done], whole.nxt[done])
        lazy.settle(math.inf)
        assert lazy.search is None and np.array_equal(lazy.cost, whole.cost) and np.array_equal(lazy.nxt, whole.nxt)
    assert partial  # the nearest robot was found before the whole field was settled


@pytest.mark.parametrize("preset,n,w,limits,seed", [
    ("case-d", 9, 3, "thesis", 1000), ("case-a", 8, 2, "thesis", 1001), ("case-d", 50, 5, "thesis", 1000),
])
def test_runs_with_lazy_fields_are_the_runs_with_whole_fields(eager, preset, n, w, limits, seed):
    """The reference engine on whole fields (as before fields were lazy) against both engines on
    lazy ones; the compiled engine stops where a recruit reaches cells not settled yet."""
    p = resolve_params(preset, n, w, limits)
    runs = {}
    stops = {}
    for on, engine in ((True, "reference"), (False, "reference"), (False, "compiled")):
        eager(on)
        st: dict = {}
        _, r = simulate(p, seed, engine=engine, stats=st)
        d = r.to_dict(events=True)
        d.pop("wall_s")
        runs[(on, engine)] = d
        stops[(on, engine)] = st.get("stops", {})
    assert runs[(False, "reference")] == runs[(True, "reference")]
    assert runs[(False, "compiled")] == runs[(True, "reference")]
    if preset == "case-d" and n == 50:  # a recruit drove beyond its field's front: settled, resumed
        assert stops[(False, "compiled")].get("field", 0) >= 1


@pytest.mark.parametrize("wi", range(3))
def test_the_compiled_window_search_is_the_numpy_ones_answer(monkeypatch, wi):
    """CostField._near (best open cell round a robot standing where the grid is closed) is
    compiled when numba is there: the same value and cell as the numpy window, at walls, at the
    fence's posts, at the arena's corners and anywhere."""
    world = _worlds()[wi]
    g = N.nav_grid(world)
    field = N.cost_field(world, float(g.cx[np.flatnonzero(g.free)[len(g.cx) // 3]]),
                         float(g.cy[np.flatnonzero(g.free)[len(g.cx) // 3]]))
    field.settle(math.inf)
    rng = np.random.default_rng(7 + wi)
    closed = np.flatnonzero(field.closed)
    pts = [(float(g.cx[c]) + rng.uniform(-1, 1), float(g.cy[c]) + rng.uniform(-1, 1))
           for c in rng.choice(closed, 60)]
    pts += [(rng.uniform(0, world.w_cm), rng.uniform(0, world.h_cm)) for _ in range(40)]
    pts += [(0.0, 0.0), (world.w_cm, world.h_cm), (world.w_cm - 1e-9, 0.5)]
    compiled = [field._near(x, y) for x, y in pts]
    monkeypatch.setattr(N, "HAVE_NUMBA", False)
    assert compiled == [field._near(x, y) for x, y in pts]
    assert any(c < math.inf for c, _ in compiled)


def test_the_compiled_floor_division_is_pythons_even_where_the_quotient_rounds_to_a_whole_number():
    """navigation._floor_div (the compiled cell lookup's x // cell) against Python's // on the
    cases that matter: multiples of the cell and their neighbours one ulp away, where x / c
    rounds to a whole number but the true quotient is just below it, negatives and zero."""
    import numba

    from swarm_sim.engine.navigation import _floor_div

    @numba.njit
    def fdiv(xs, c, out):
        for i in range(xs.shape[0]):
            out[i] = _floor_div(xs[i], c)

    rng = np.random.default_rng(4)
    for c in (4.47213595499958, 3.3333333333333335, 10.0, 0.1, 7.3):
        k = np.arange(-50, 3000).astype(float)
        base = k * c
        xs = np.concatenate([base, np.nextafter(base, -np.inf), np.nextafter(base, np.inf),
                             rng.uniform(-100, 3000 * c, 5000), [0.0, -0.0, 1e-300, -1e-300]])
        out = np.empty_like(xs)
        fdiv(xs, c, out)
        want = np.array([x // c for x in xs.tolist()])
        assert np.array_equal(out, want)
        assert (np.floor(xs / c) != want).any() or c == 10.0  # the cases where floor(x / c) is wrong occur
