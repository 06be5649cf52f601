"""Piers of failed robots lengthen the line's span (issue 16; the thesis's future work 4)."""

import dataclasses

import pytest

from structure_fem.limits import load_limits
from swarm_sim.behaviour.rule import robots_per_pier
from swarm_sim.errors import InputError
from swarm_sim.params import load_preset, with_overrides
from swarm_sim.resolve import with_limits
from swarm_sim.runner import resolve_params, run_scenario, simulate


def pier_params(width=6, robots=20, limits=None, **ov):
    lim = limits or load_limits("derived")
    p = with_overrides(load_preset("pier"), dict(robots=robots, void_width=width, **ov)).validate()
    return with_limits(p, lim)


def test_a_pier_needs_the_robots_whose_stack_reaches_the_ledge_within_the_clearance():
    # standing 9 cm, pitch 9 cm, clearance 1.5 cm: tops at 9, 18, 27 cm
    assert robots_per_pier(18.0, 9.0, 9.0, 1.5) == 2
    assert robots_per_pier(19.4, 9.0, 9.0, 1.5) == 2          # 1.4 cm short: the line sags onto it
    assert robots_per_pier(20.0, 9.0, 9.0, 1.5) == 0          # 2 cm short, 7 cm too tall: no stack fits
    assert robots_per_pier(27.0, 9.0, 9.0, 1.5) == 3
    assert robots_per_pier(27.0, 9.0, 9.0, 1.5, deck_cm=1.0) == 0  # the deck makes 3 too tall, 2 too short
    assert robots_per_pier(19.0, 9.0, 9.0, 1.5, deck_cm=1.0) == 2
    assert robots_per_pier(0.0, 9.0, 9.0, 1.5) == 0           # no depth given: no pier


def test_the_pier_preset_crosses_a_void_wider_than_the_derived_line_with_the_line_and_its_pier():
    lim = load_limits("derived")
    line = next(lv for lv in lim.levels if lv.kind == "line")
    p = pier_params()
    assert p.void_width > line.max_span_widths and p.level_name == "line" and p.pier_robots >= 1
    res = run_scenario("pier", p.robots, p.void_width, 1, check_invariants=True)
    assert res.success and res.end_reason == "crossed"
    assert res.robots_in_piers == p.pier_robots and res.robots_lost == 0 and not res.violations
    kinds = [k for _t, k, _r, _d in res.events]
    assert "pier_complete" in kinds and kinds.index("pier_complete") < kinds.index("far_ledge")
    assert res.levels_used == ["line"]
    pier = res.to_dict()["piers"]
    assert len(pier) == 1 and pier[0]["complete"] and len(pier[0]["robots"]) == p.pier_robots
    assert {f["robot"] for f in res.faults} >= set(pier[0]["robots"])  # built of failed robots


def test_a_pier_is_built_only_of_robots_the_swarm_found_to_have_failed():
    res = run_scenario("pier", 20, 6, 2, check_invariants=True)
    known = {}
    for t, kind, r, d in res.events:
        if kind == "fault_detected":
            known.setdefault(r, t)
        if kind == "pier_fetch":
            assert d["failed"] in known and known[d["failed"]] <= t


@pytest.mark.parametrize("why", ["no depth", "thesis limits"])
def test_the_same_swarm_without_a_pier_retreats_at_the_span(why):
    kw = {"void_depth_cm": 0.0} if why == "no depth" else {"limits": "thesis"}
    res = run_scenario("pier", 20, 6, 1, check_invariants=True, **kw)
    assert not res.success and res.end_reason == "retreated-span" and res.robots_in_piers == 0
    assert res.robots_lost == 0


def test_the_widest_void_is_the_records_first_span_pier_and_overhang():
    lim = load_limits("derived")
    k = pier_params().pier_robots
    widest = lim.piers.max_void_for(k)
    assert run_scenario("pier", 24, widest, 1, check_invariants=True).success
    res = run_scenario("pier", 24, widest + 1, 1, check_invariants=True)
    # beyond it: a second pier (if the record allows one there) or a retreat, never a fall
    assert res.robots_lost == 0 and not res.violations


def test_the_crossing_moves_with_the_records_overhang():
    """The record's overhang cut to 1: the pier (one width, right after the first span f) carries
    the line to f + 2, and a void one wider is a retreat at the span."""
    lim = load_limits("derived")
    f = lim.piers.first_span_widths
    short = dataclasses.replace(lim, piers=dataclasses.replace(
        lim.piers, overhang_widths=(1,) * 4, overhang_widths_two_piers=(0,) * 4,
        max_void_widths=(f + 2,) * 4))
    wide = pier_params(f + 3, limits=short)
    assert wide.pier_overhang_widths == 1
    _, res = simulate(wide, 1, check=True)
    assert res.end_reason == "retreated-span" and res.robots_lost == 0 and not res.violations
    _, res_in = simulate(pier_params(f + 2, limits=short), 1, check=True)
    assert res_in.success and res_in.robots_in_piers >= 1


def _first_span_two(lim):
    """The record with the line's span cut to 2 and the pier rule of a 2-wide first span (what the
    emergent hinge's mechanics derived on 2026-12-04: line 2, one pier of 2 robots at 2 carrying it
    3 further, to 6); the 4 x 2 arch takes over from 3 so the levels still tile the widths."""
    levels, span = [], lim.level_for(1).max_span_widths
    for lv in lim.levels:
        if lv.kind == "line":
            lv = dataclasses.replace(lv, max_span_widths=2, min_robots=lv.min_robots[:2])
        elif lv.min_span_widths == span + 1 and span > 2:  # the next level takes over the widths cut
            lv = dataclasses.replace(lv, min_span_widths=3, min_robots=(lv.min_robots[0],) * (span - 2) + lv.min_robots)
        levels.append(lv)
    piers = dataclasses.replace(lim.piers, first_span_widths=2, overhang_widths=(3,) * 4,
                                overhang_widths_two_piers=(3,) * 4, max_void_widths=(6,) * 4)
    return dataclasses.replace(lim, levels=tuple(levels), piers=piers)


def test_a_two_wide_first_span_crosses_on_its_pier_without_leaving_the_near_ledge():
    """First span 2: the pier stands at 2 widths, right beyond a line of 5 (4 on the ground, 1
    over). Advancing onto it, the line used to walk its rear off the near ledge (the rule beyond
    the pier still held), where no recruit can dock, and retreat 3 rows short. Before landing an
    advance now keeps the rear row on the initial ground (as the pier rule's derivation does in
    every state), so the line recruits as it goes and crosses."""
    lim = _first_span_two(load_limits("derived"))
    p = pier_params(6, limits=lim)
    assert p.pier_robots == 2 and p.pier_overhang_widths == 3 and p.level_name == "line"
    world, res = simulate(p, 1, check=True)
    assert res.success and res.end_reason == "crossed", res.end_reason
    assert res.robots_in_piers == 2 and res.robots_lost == 0 and not res.violations
    kinds = [k for _t, k, _r, _d in res.events]
    landed = kinds.index("far_ledge")
    assert "recruit" in kinds[kinds.index("pier_complete"):landed]  # it recruits over the pier
    assert "retreat" not in kinds


def test_too_few_failed_robots_start_no_pier():
    res = run_scenario("pier", 20, 6, 1, faults="0@0:drive", check_invariants=True)
    assert res.end_reason == "retreated-span" and res.robots_in_piers == 0


def test_a_bad_depth_is_refused():
    with pytest.raises(InputError, match="void_depth_cm"):
        resolve_params("pier", 20, 6, void_depth_cm=-1.0)


def test_a_void_one_width_past_the_line_takes_a_pier_against_the_far_wall():
    lim = load_limits("derived")
    line = next(lv for lv in lim.levels if lv.kind == "line")
    res = run_scenario("pier", 24, line.max_span_widths + 1, 1, check_invariants=True)
    assert res.success and res.robots_in_piers >= 1 and res.robots_lost == 0


def test_a_carrier_whose_drive_fails_says_so_and_another_brings_the_robot():
    # 22 robots: four lose their drive, and the derived rule's wider first span (the wedge latch's
    # line) needs more of the rest than 20 leave
    base = run_scenario("pier", 22, 6, 1)
    fetch = next(e for e in base.events if e[1] == "pier_fetch")
    c, t = fetch[2], fetch[0] + 1.0
    res = run_scenario("pier", 22, 6, 1, faults=f"0@0:drive,1@0:drive,2@0:drive,{c}@{t}:drive", check_invariants=True)
    abort = [e for e in res.events if e[1] == "pier_aborted"]
    assert abort and abort[0][2] == c
    assert any(e[1] == "fault_detected" and e[2] == c and e[3]["how"] == "reports_cannot_drive" for e in res.events)
    later = [e for e in res.events if e[1] == "pier_fetch" and e[0] > abort[0][0]]
    assert later and all(e[2] != c for e in later)
    assert res.success and res.robots_in_piers == 2 and res.robots_lost == 0
