"""Issue 6: the structure widens during the build (Ch. 5.5.2), driven by the limits record.

The robots do not know the void width: the structure starts as the record's first level
and switches to the next one when the front has not found the far ledge and one more
advance would exceed the current level's span. Change the record and the switch moves.
"""

from __future__ import annotations

import pytest

from structure_fem.limits import StructureLevel, StructureLimits
from swarm_sim.behaviour.structure import open_columns, widened
from swarm_sim.runner import construction_times, resolve_params, run_scenario
from swarm_sim.state import OPEN, Structure


def limits_file(path, levels):
    StructureLimits("derived", "cubot", 15.0, tuple(levels), notes="test").save(path)
    return str(path)


def level(name, kind, lines, layers, lo, hi, ratio=1.0, margin=1):
    rows = lambda w: w + int(ratio * w + margin + 0.999999)  # noqa: E731
    return StructureLevel(name, kind, lines, layers, lo, hi, ratio, margin,
                          tuple(rows(w) * lines * layers for w in range(lo, hi + 1)))


def line_then_two(tmp_path, line_span):
    return limits_file(tmp_path / f"s{line_span}.json",
                       [level("line", "line", 1, 1, 1, line_span),
                        level("two_line", "two_line", 2, 1, line_span + 1, 5)])


def switches(r):
    return [d for _, k, _, d in r.events if k == "switch"]


def test_widening_keeps_every_robot_in_its_row_line_and_layer():
    st = Structure(members=(7, 8, 9), origin_x_cm=0, origin_y_cm=0, dir_x=1, dir_y=0, front_s_cm=0)
    w = widened(st, 2, 1)
    assert w == (7, OPEN, 8, OPEN, 9, OPEN)
    two = Structure(members=w, origin_x_cm=0, origin_y_cm=0, dir_x=1, dir_y=0, front_s_cm=0, lines=2)
    assert open_columns(two) == [1]
    arch = widened(Structure(members=(1, 2, 3, 4), origin_x_cm=0, origin_y_cm=0, dir_x=1, dir_y=0,
                             front_s_cm=0, lines=2), 3, 2)
    assert arch[:6] == (1, 2, OPEN, OPEN, OPEN, OPEN) and arch[6:8] == (3, 4) and len(arch) == 12


@pytest.mark.parametrize("line_span", [2, 3])
def test_the_switch_happens_where_the_record_says_and_moves_with_it(tmp_path, line_span):
    f = line_then_two(tmp_path, line_span)
    p = resolve_params("case-d", 30, 4, f, structure="switch")
    assert p.level_name == "line" and p.lines == 1  # starts as the first level: the width is unknown
    r = run_scenario("case-d", 30, 4, 1, limits=f, structure="switch", finish_delivery=True,
                     check_invariants=True)
    assert r.success and r.robots_lost == 0 and r.robots_delivered == 30, r.to_dict()
    sw = switches(r)
    assert len(sw) == 1 and sw[0]["level"] == "two_line" and sw[0]["n_g"] == line_span
    assert r.levels_used == ["line", "two_line"] and r.switches[0]["n_g"] == line_span
    # the right line was recruited beside the core before the structure moved on
    docks = [(t, d) for t, k, _, d in r.events if k == "dock"]
    t_sw = [t for t, k, _, _ in r.events if k == "switch"][0]
    after = [len(d["robots"]) for t, d in docks if t > t_sw]
    assert after[:sw[0]["rows"]] == [1] * sw[0]["rows"]  # one open column, filled row by row
    assert set(after[sw[0]["rows"]:]) == {2}              # then whole rows of two


def test_a_void_within_the_first_level_never_switches(tmp_path):
    r = run_scenario("case-d", 9, 2, 1, limits=line_then_two(tmp_path, 2), structure="switch",
                     check_invariants=True)
    assert r.success and not switches(r) and r.levels_used == ["line"]


def test_too_few_robots_to_widen_retreat_with_none_lost(tmp_path):
    f = line_then_two(tmp_path, 2)
    r = run_scenario("case-d", 8, 4, 1, limits=f, structure="switch", check_invariants=True)
    assert r.retreated and r.robots_lost == 0 and r.robots_on_initial_side == 8
    assert len(switches(r)) == 1  # it tried: widened, ran out of robots while filling, retreated


def test_the_rule_minimum_counts_the_rows_widened_at_each_switch(tmp_path):
    f = line_then_two(tmp_path, 2)
    # line at its span 2: 2 + (2 + 1) = 5 rows; two lines at 4: 4 + 5 = 9 rows of 2 = 18
    assert resolve_params("case-d", 30, 4, f, structure="switch").min_robots_rule == 18
    assert resolve_params("case-d", 30, 2, f, structure="switch").min_robots_rule == 5


def test_thesis_large_void_70_robots_cross_six_widths_switching_at_five():
    r = run_scenario("large-void", 70, 6, 3, limits="thesis")
    assert r.success and r.robots_lost == 0 and r.robots_delivered == 70, r.to_dict()
    assert [(s["level"], s["n_g"]) for s in r.switches] == [("two_line", 5)]
    d = r.to_dict()
    assert d["assembly"] > 0 and d["disassembly"] > 0 and d["seed_edge_cm"] == r.seed_position[1]
    assert d["levels_used"] == ["line", "two_line"]


def test_construction_times_from_the_event_log():
    ev = ((1.0, "seed", 0, {}), (2.0, "aligned", 0, {}), (10.0, "release_front", 0, {}),
          (12.0, "dock", 5, {}), (20.0, "dissolved", -1, {}))
    assert construction_times(ev) == {"assembly": 8.0, "disassembly": 8.0}
    ev = ((1.0, "seed", 0, {}), (2.0, "aligned", 0, {}), (7.0, "retreat", 0, {}), (9.5, "dissolved", -1, {}))
    assert construction_times(ev) == {"assembly": 5.0, "disassembly": 2.5}
    assert construction_times(((1.0, "seed", 0, {}),)) == {"assembly": None, "disassembly": None}


def test_derived_limits_first_switch_happens_where_the_record_says_and_the_rule_count_is_exact():
    """Packaged derived record: the first level spans s widths, so on a void of s + 1 widths the
    structure widens to the next level at n_g = s, and the swarm size the rule demands (read from
    the resolved parameters, which compute it from the record) crosses while one robot fewer retreats.
    Nothing here is a hard-coded number: regenerate limits.json and the test follows."""
    from structure_fem.limits import load_limits

    lim = load_limits("derived")
    first, second = lim.levels[0], lim.levels[1]
    w = first.max_span_widths + 1
    kw = dict(limits="derived", arena_w_cm=800.0, arena_h_cm=400.0, target_x_cm=750.0, target_y_cm=200.0)
    need = resolve_params("large-void", 10, w, **kw).min_robots_rule
    assert need >= second.lines * second.layers * (w + 1)
    ok = run_scenario("large-void", need, w, 1, **kw)
    assert ok.success and ok.robots_lost == 0 and ok.robots_delivered == need, ok.to_dict()
    assert ok.min_robots_rule == need
    assert [(s["level"], s["n_g"]) for s in ok.switches] == [(second.name, first.max_span_widths)]
    fail = run_scenario("large-void", need - 1, w, 1, **kw)
    assert fail.retreated and fail.robots_lost == 0 and fail.robots_on_initial_side == need - 1


def test_switch_mode_rejects_a_void_wider_than_the_widest_level_before_the_run(tmp_path):
    from swarm_sim.errors import InputError

    with pytest.raises(InputError, match="wider than the widest structure"):
        resolve_params("case-d", 50, 6, line_then_two(tmp_path, 2), structure="switch")
