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
def test_derived_widest_void_crossed_by_the_rule_minimum_with_three_switches():
    """Derived record's widest structure (8 widths): 544 robots, line -> 4x2 -> 6x3 -> 8x4 (~1 min)."""
    r = run_scenario("large-void-8", 544, 8, 1, limits="derived")
    assert r.success and r.robots_lost == 0 and r.robots_delivered == 544, r.to_dict()
    assert [(s["level"], s["n_g"]) for s in r.switches] == [
        ("arch-4x2-staggered", 4), ("arch-6x3-staggered", 6), ("arch-8x4-staggered", 7)]
