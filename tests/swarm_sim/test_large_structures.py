"""Issue 6 (part): structures with several lines / layers, chosen by the limits record.

Rows of ``lines x layers`` robots are recruited whole, advanced together and released
together; the rule counts rows. Which structure is built comes from ``limits.json``.
"""

from __future__ import annotations

import pytest

from structure_fem.limits import StructureLevel, StructureLimits
from swarm_sim.errors import InputError
from swarm_sim.runner import resolve_params, run_scenario


def limits_file(path, levels):
    StructureLimits("derived", "cubot", 15.0, tuple(levels), notes="test").save(path)
    return str(path)


def level(name, kind, lines, layers, lo, hi, ratio=2.0, margin=0):
    rows = lambda w: w + int(ratio * w + margin + 0.999999)  # noqa: E731
    return StructureLevel(name, kind, lines, layers, lo, hi, ratio, margin,
                          tuple(rows(w) * lines * layers for w in range(lo, hi + 1)))


@pytest.fixture
def two_line_from_2(tmp_path):
    return limits_file(tmp_path / "l.json", [level("line", "line", 1, 1, 1, 1),
                                             level("two_line", "two_line", 2, 1, 2, 4)])


def test_the_record_picks_the_structure_and_its_switch_moves_with_it(tmp_path, two_line_from_2):
    p1 = resolve_params("case-d", 3, 1, two_line_from_2, structure="auto")
    p2 = resolve_params("case-d", 12, 2, two_line_from_2, structure="auto")
    assert (p1.level_name, p1.lines) == ("line", 1) and (p2.level_name, p2.lines) == ("two_line", 2)
    later = limits_file(tmp_path / "m.json", [level("line", "line", 1, 1, 1, 2),
                                              level("two_line", "two_line", 2, 1, 3, 4)])
    assert resolve_params("case-d", 12, 2, later, structure="auto").level_name == "line"
    assert p2.min_robots_rule == p2.record_min_robots == 12


def test_two_lines_cross_with_the_rule_count_and_retreat_below_it(two_line_from_2):
    ok = run_scenario("case-d", 12, 2, 1, limits=two_line_from_2, structure="auto", check_invariants=True)
    assert ok.success and ok.robots_lost == 0 and ok.robots_delivered == 12, ok.to_dict()
    docks = [d for _, k, _, d in ok.events if k == "dock"]
    assert all(len(d["robots"]) == 2 for d in docks[1:]) and len(docks[0]["robots"]) == 1  # seed row filled
    fail = run_scenario("case-d", 11, 2, 1, limits=two_line_from_2, structure="auto", check_invariants=True)
    assert fail.retreated and fail.robots_lost == 0 and fail.robots_on_initial_side == 11


def test_layered_rows_are_recruited_and_released_whole(tmp_path):
    f = limits_file(tmp_path / "a.json", [level("line", "line", 1, 1, 1, 1),
                                          level("arch", "arch", 2, 2, 2, 3)])
    r = run_scenario("case-d", 24, 2, 2, limits=f, structure="auto", check_invariants=True)
    assert r.success and r.robots_lost == 0, r.to_dict()
    released = [d["robots"] for _, k, _, d in r.events if k == "release_front"]
    assert all(len(x) == 4 for x in released) and sum(map(len, released)) == 24


def test_void_wider_than_the_widest_structure_is_rejected_before_the_run(two_line_from_2):
    with pytest.raises(InputError, match="wider than the widest structure"):
        run_scenario("case-d", 50, 5, 1, limits=two_line_from_2, structure="auto")
