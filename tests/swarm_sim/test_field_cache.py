"""Cost fields shared by contents (swarm_sim.engine.field_cache): runs with the by-contents table are the
runs without it, event for event, and the table is used (it answers recruitments that closed
the same cells under another name)."""

import numpy as np
import pytest

from structure_fem.limits import load_limits
from swarm_sim.engine import navigation as N
from swarm_sim.engine.field_cache import FieldCache, contents_key
from swarm_sim.engine.world import World
from swarm_sim.runner import resolve_params, simulate


def _run(monkeypatch, cache: FieldCache, preset, n, w, limits, seed, engine):
    monkeypatch.setattr(N, "_FIELDS", cache)
    p = resolve_params(preset, n, w, limits)
    _, r = simulate(p, seed, engine=engine)
    d = r.to_dict(events=True)
    d.pop("wall_s")
    return d


@pytest.mark.parametrize("preset,n,w,limits,seed,engine", [
    ("case-d", 9, 3, "thesis", 1000, "compiled"),
    ("case-d", 9, 3, "thesis", 1001, "reference"),
    ("case-d", 8, 3, "thesis", 1000, "compiled"),    # too few robots: a retreat
    ("case-a", 8, 2, "thesis", 1001, "compiled"),
    ("case-d", 50, 5, "thesis", 1000, "compiled"),
    # the widest void the derived record spans: a switch of structure, then a retreat (70 robots)
    ("large-void", 70, load_limits("derived").max_span_widths, "derived", 1001, "compiled"),
])
def test_runs_sharing_fields_by_contents_are_the_runs_without(monkeypatch, preset, n, w, limits, seed, engine):
    off = FieldCache(64, share=False)
    want = _run(monkeypatch, off, preset, n, w, limits, seed, engine)
    on = FieldCache(64)
    got = _run(monkeypatch, on, preset, n, w, limits, seed, engine)
    assert got == want
    assert on.hits["contents"] >= 1, on.hits  # the table answered, so the runs tested it
    assert on.hits["built"] + on.hits["contents"] == off.hits["built"]  # every reuse is a search saved
    if preset == "large-void":
        assert {"switch", "retreat"} <= {e["kind"] for e in got["events"]}


def test_a_field_is_shared_only_when_every_closed_cell_and_the_goal_point_agree(monkeypatch):
    world = World.from_params(resolve_params("case-d", 9, 3, "thesis"))
    g = N.nav_grid(world)
    monkeypatch.setattr(N, "_FIELDS", FieldCache(64))
    c = int(np.flatnonzero(g.free)[len(np.flatnonzero(g.free)) // 2])
    gx, gy = float(g.cx[c]), float(g.cy[c])
    mask = np.zeros(g.nx * g.ny, dtype=bool)
    mask[np.flatnonzero(g.free)[:50]] = True
    a = N.cost_field(world, gx, gy, mask.copy(), b"a")
    assert N.cost_field(world, gx, gy, lambda: mask.copy(), b"b") is a  # another name, the same cells
    other = mask.copy()
    other[np.flatnonzero(g.free & ~mask)[0]] = True  # one more closed cell
    assert N.cost_field(world, gx, gy, other, b"c") is not a
    assert N.cost_field(world, gx + 1e-9, gy, mask.copy(), b"d") is not a  # the goal point moved
    # the key names the cells exactly (a bit per cell, its length too)
    k1 = contents_key(("w",), c, gx, gy, mask)
    assert k1 == contents_key(("w",), c, gx, gy, mask.copy())
    assert k1 != contents_key(("w",), c, gx, gy, other)
    assert contents_key(("w",), c, gx, gy, np.zeros(9, bool)) != contents_key(("w",), c, gx, gy, np.zeros(10, bool))


def test_the_tables_are_bounded_and_clear_forgets_both(monkeypatch):
    world = World.from_params(resolve_params("case-d", 9, 3, "thesis"))
    g = N.nav_grid(world)
    cache = FieldCache(4)
    monkeypatch.setattr(N, "_FIELDS", cache)
    cells = np.flatnonzero(g.free)[::97][:10]
    for c in cells:
        N.cost_field(world, float(g.cx[c]), float(g.cy[c]))
    assert len(cache) == 4 and len(cache._contents) == 2
    cache.clear()
    assert len(cache) == 0 and len(cache._contents) == 0
    c = cells[-1]
    built = cache.hits["built"]
    N.cost_field(world, float(g.cx[c]), float(g.cy[c]))
    assert cache.hits["built"] == built + 1
