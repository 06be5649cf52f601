"""Reproduce the thesis's small-void results (Ch. 4.7) with ``--limits thesis``.

Every run checks every invariant after every step (``check_invariants=True`` raises on
the first violation). Thresholds are read from the limits record, never typed in: for
cases C/D the record's line level gives N_min(w) (the thesis: 3w), case A adds its +2.
"""

from __future__ import annotations

import pytest

from structure_fem.limits import load_limits
from swarm_sim.runner import resolve_params, run_scenario, simulate

THESIS = load_limits("thesis")
SEEDS = {"case-c": 2, "case-d": 1}  # one seed per case keeps `make test` short; sweeps do 30


def n_min(width: int, margin: int = 0) -> int:
    return THESIS.level_for(width).robots_for(width) + margin


def test_thesis_record_is_the_3w_rule():
    assert [n_min(w) for w in range(1, 6)] == [3 * w for w in range(1, 6)]


@pytest.mark.parametrize("case", ["case-c", "case-d"])
@pytest.mark.parametrize("width", [1, 2, 3, 4, 5])
def test_cases_c_d_cross_with_n_min_and_retreat_with_one_less(case, width):
    need = n_min(width)
    ok = run_scenario(case, need, width, SEEDS[case], limits="thesis", check_invariants=True)
    assert ok.success and not ok.retreated, ok.to_dict()
    assert ok.robots_lost == 0 and ok.robots_delivered == need
    assert ok.target_finder is not None and ok.times["Td"] == 0.0
    if need - 1 >= 1:
        fail = run_scenario(case, need - 1, width, SEEDS[case], limits="thesis", check_invariants=True)
        assert fail.retreated and not fail.success, fail.to_dict()
        assert fail.robots_lost == 0 and fail.robots_on_initial_side == need - 1
        t = fail.times
        assert t["To"] == 0.0 and t["Td"] > 0 and t["Tb"] == pytest.approx(5.0, abs=0.02)
        assert t["Tt"] == pytest.approx(t["Ts"] + t["Ta"] + t["Td"] + t["Tb"], abs=1e-6)


@pytest.mark.parametrize("width", [1, 2])
def test_case_a_needs_3w_plus_2(width):
    need = n_min(width, margin=2)
    assert need == 3 * width + 2
    ok = run_scenario("case-a", need, width, 1, limits="thesis", check_invariants=True)
    assert ok.success and ok.robots_lost == 0, ok.to_dict()
    fail = run_scenario("case-a", need - 1, width, 1, limits="thesis", check_invariants=True)
    assert fail.retreated and fail.robots_lost == 0 and fail.robots_on_initial_side == need - 1


def test_many_robots_become_seeds_in_case_d():
    """30 case-D runs of 9 robots on a 3-wide void: at least 6 different seed robots
    (the seed depends only on the initial exploration, so each run stops at the seed)."""
    p = resolve_params("case-d", 9, 3, "thesis")
    seeds, positions = [], []
    for s in range(30):
        _, r = simulate(p, s, until="seed", check=True)
        assert r.seed_robot is not None and not r.violations
        seeds.append(r.seed_robot)
        positions.append(r.seed_position)
    assert len(set(seeds)) >= 6, seeds
    # seeds align on the edge: x = void edge - half a robot, y anywhere along it
    assert all(abs(x - (p.void_x0_cm - 5.0)) < 1e-6 for x, _ in positions)
    assert max(y for _, y in positions) - min(y for _, y in positions) > 100


def test_structure_timeline_follows_the_thesis_counts():
    """N = 3w on w = 2: launch with 3, front over the void held by 2 n_g on the ground,
    far ledge found with n_p = 2w, then released at the front one by one."""
    r = run_scenario("case-d", 6, 2, 1, limits="thesis", check_invariants=True)
    ev = r.events
    kinds = [k for _, k, _, _ in ev]
    first_adv = next(d for _, k, _, d in ev if k == "advance")
    assert first_adv["n_p"] + first_adv["n_g"] + first_adv["n_o"] == 3 and first_adv["n_g"] == 0
    assert kinds.index("far_ledge") > kinds.index("dock")
    assert kinds.count("dock") == 5 and kinds.count("release_front") == 6
    assert "retreat" not in kinds


def test_case_a_five_widths_needs_17_in_a_longer_arena():
    """Ch. 4.7: case A needs 17 robots for a 5-wide void. The 250 cm case-A arena cannot hold
    the 12-robot counterweight line, so the arena is lengthened (the thesis's own remark)."""
    need = n_min(5, margin=2)
    assert need == 17
    kw = {"arena_w_cm": 700.0, "target_x_cm": 680.0}
    ok = run_scenario("case-a", need, 5, 1, limits="thesis", check_invariants=True, **kw)
    assert ok.success and ok.robots_lost == 0, ok.to_dict()
    fail = run_scenario("case-a", need - 1, 5, 1, limits="thesis", check_invariants=True, **kw)
    assert fail.retreated and fail.robots_lost == 0 and fail.robots_on_initial_side == need - 1
