"""The limits record drives the simulator: change it and the crossing threshold moves."""

from __future__ import annotations

import json

import pytest

from structure_fem.limits import StructureLevel, StructureLimits, load_limits, packaged_limits_path
from swarm_sim.runner import run_scenario


def write_limits(path, ratio: float, margin: int, line_max: int):
    line_mins = tuple(int(w + (ratio * w + margin) + 0.999999) for w in range(1, line_max + 1))
    levels = [StructureLevel("line", "line", 1, 1, 1, line_max, ratio, margin, line_mins),
              StructureLevel("two_line", "two_line", 2, 1, line_max + 1, 10, ratio, margin,
                             tuple(100 for _ in range(line_max + 1, 11)))]
    StructureLimits("derived", "cubot", 15.0, tuple(levels), notes="test").save(path)
    return str(path)


def test_a_softer_rule_lets_fewer_robots_cross(tmp_path):
    f = write_limits(tmp_path / "soft.json", ratio=1.0, margin=0, line_max=5)
    # n_p >= n_g: 2w robots hold w over the void, so 4 robots cross 2 widths (thesis needs 6)
    ok = run_scenario("case-d", 4, 2, 1, limits=f, check_invariants=True)
    assert ok.success and ok.robots_lost == 0 and ok.min_robots_rule == 4
    fail = run_scenario("case-d", 3, 2, 1, limits=f, check_invariants=True)
    assert fail.retreated and fail.robots_lost == 0
    thesis = run_scenario("case-d", 4, 2, 1, limits="thesis", check_invariants=True)
    assert thesis.retreated


def test_a_void_wider_than_the_line_may_span_ends_in_a_safe_retreat(tmp_path):
    f = write_limits(tmp_path / "short.json", ratio=2.0, margin=0, line_max=2)
    r = run_scenario("case-d", 12, 3, 1, limits=f, check_invariants=True)
    assert r.retreated and r.robots_lost == 0 and r.robots_on_initial_side == 12
    why = [d.get("why") for _, k, _, d in r.events if k == "retreat"]
    assert why == ["span"]


@pytest.mark.skipif(not packaged_limits_path().exists(), reason="derived limits.json not produced yet")
def test_derived_limits_threshold_is_read_from_the_record():
    rec = load_limits("derived")
    line = next(lvl for lvl in rec.levels if lvl.kind == "line")
    w = 1
    need = line.robots_for(w)
    ok = run_scenario("case-d", need, w, 1, check_invariants=True)
    assert ok.success and ok.limits_source == "derived" and ok.robots_lost == 0
    fail = run_scenario("case-d", need - 1, w, 1, check_invariants=True)
    assert fail.retreated and fail.robots_lost == 0
    assert json.loads(packaged_limits_path().read_text())["source"] == "derived"
