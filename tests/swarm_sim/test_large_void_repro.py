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
