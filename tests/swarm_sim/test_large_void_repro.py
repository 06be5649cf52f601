"""Thesis Ch. 5.6 reproduction (long: marked bench, excluded from ``make test``).

With ``--limits thesis`` 70 robots cross voids of 6..10 robot widths in every one of 10 seeded
runs, switching from the line to two lines at 5 robot widths over the void, none lost.
Same as ``voidcross sweep --preset large-void --robots 70 --void-width 6-10 --runs 10 --limits thesis``.
"""

from __future__ import annotations

import pytest

from swarm_sim.runner import run_scenario


@pytest.mark.bench
@pytest.mark.parametrize("width", [6, 7, 8, 9, 10])
def test_thesis_large_void_ten_runs_all_cross(width):
    for seed in range(10):
        r = run_scenario("large-void", 70, width, seed, limits="thesis")
        assert r.success and r.robots_lost == 0 and r.robots_delivered == 70, (seed, r.to_dict())
        assert [(s["level"], s["n_g"]) for s in r.switches] == [("two_line", 5)]


@pytest.mark.bench
def test_derived_widest_void_crossed_by_the_rule_minimum():
    """The derived record's widest void, crossed by the swarm size its rule demands, switching
    through every level on the way. Widths, levels and robot count all come from the packaged
    limits.json (regenerate it and this follows); the arena is sized for the swarm."""
    from structure_fem.limits import load_limits
    from swarm_sim.runner import resolve_params

    lim = load_limits("derived")
    w = lim.max_span_widths
    length_cm = 100.0 * w + 2000.0
    kw = dict(limits="derived", arena_w_cm=length_cm, arena_h_cm=1000.0,
              target_x_cm=length_cm - 50.0, target_y_cm=500.0, max_time_s=20000.0)
    need = resolve_params("large-void-8", 10, w, **kw).min_robots_rule
    r = run_scenario("large-void-8", need, w, 1, **kw)
    assert r.success and r.robots_lost == 0 and r.robots_delivered == need, r.to_dict()
    assert [s["level"] for s in r.switches] == [lvl.name for lvl in lim.levels[1:]]
