"""Piers of failed robots (issue 16, structure_fem part): spans with intermediate supports.

What the spec asks and these tests hold: a pier lets the line overhang farther than without it;
a stiffer pier never gives less overhang; more robots in a pier make a softer pier; a pier only
pushes; the rule moves when the inputs move; bad ``--piers`` is exit 2 naming the value; the
record round-trips, old records without ``piers`` load, the thesis preset has none.
"""

from __future__ import annotations

import dataclasses
import json
import math

import pytest

pytest.importorskip("exudyn")

from structure_fem.analysis.piers import (  # noqa: E402
    PierStudy,
    body_stiffness,
    derive,
    own_level,
    pier_stiffness,
    robot_pier,
    solve_piers,
)
from structure_fem.analysis.study import StudyInputs, min_rows  # noqa: E402
from structure_fem.errors import InputError  # noqa: E402
from structure_fem.limits import PierRule, StructureLimits, load_limits, thesis_limits  # noqa: E402
from structure_fem.model.statics import Config, solve  # noqa: E402
from structure_fem.model.structures import Pier, Structure, layout  # noqa: E402
from structure_fem.outputs.runs import RunOptions, make_inputs, with_piers  # noqa: E402

LINE = Structure("line")


@pytest.fixture(scope="module")
def inp() -> StudyInputs:
    """The packaged CuBot as `fem table` uses it (FE front-rear coupling, the CAD's play)."""
    return make_inputs(RunOptions())[0]


@pytest.fixture(scope="module")
def first_span(inp):
    return own_level(inp)


@pytest.fixture(scope="module")
def base(inp, first_span):
    """The pier derivation for piers of 1 and 2 robots (one and two piers, every state checked)."""
    return derive(PierStudy(inp, first_span, max_pier_robots=2))


def test_pier_stiffness_is_the_stack_in_series_and_more_robots_are_softer(inp):
    r, key = inp.robot, inp.connectors.top_twist.k_z  # vertical: the key arms (horizontal: its stem)
    fill = r.mass_kg / (r.density_kg_m3 * r.length_m * r.width_m * r.height_m)
    kb = r.youngs_modulus_pa * fill * r.length_m * r.width_m / r.height_m
    assert body_stiffness(r) == pytest.approx(kb, rel=1e-12)
    ks = [pier_stiffness(r, inp.connectors, k).n_per_m for k in (1, 2, 3, 4)]
    for k, v in zip((1, 2, 3, 4), ks, strict=True):
        assert 1 / v == pytest.approx(k / kb + (k - 1) / key, rel=1e-12)
    assert all(a > b for a, b in zip(ks, ks[1:], strict=False))  # more robots: softer
    soft = inp.connectors.scaled(0.5, 1.0)  # softer keys: softer piers of 2+, a pier of 1 has no key
    assert pier_stiffness(r, soft, 1).n_per_m == ks[0]
    assert pier_stiffness(r, soft, 3).n_per_m < ks[2]
    with pytest.raises(InputError, match="no top_twist"):
        pier_stiffness(r, dataclasses.replace(inp.connectors, top_twist=None), 2)


def test_supports_sit_only_under_bodies_over_the_pier(inp):
    p = robot_pier(inp.robot, inp.connectors, 1, 3.0)
    lay = layout(LINE, inp.robot, inp.connectors, 8, 7, 7, piers=(p,))
    on = [(lay.bodies[s.body].row, s.point_m[0]) for s in lay.supports if s.pier == 0]
    # the body over [3, 4] rests on its wheels and casters (the CuBot's: 12, 50 and 88 mm behind its front
    # face, structure_fem.model.contacts); its neighbours only touch the pier's faces with their bodies
    assert [row for row, _ in on] == [3, 3, 3] and [x for _, x in on] == pytest.approx([0.312, 0.35, 0.388])
    half = layout(LINE, inp.robot, inp.connectors, 8, 7, 7, piers=(dataclasses.replace(p, at_widths=2.5),))
    assert sorted(lay_row for lay_row in (half.bodies[s.body].row for s in half.supports if s.pier == 0)) == \
        [3, 4]  # straddling two bodies: each rests on the contact strictly over its half (the others at the faces)
    for bad, word in (((dataclasses.replace(p, at_widths=6.5),), "beyond"),
                      ((p, dataclasses.replace(p, at_widths=3.5)), "overlaps")):
        with pytest.raises(InputError, match=word):
            layout(LINE, inp.robot, inp.connectors, 8, 7, 7, piers=bad)
    with pytest.raises(InputError, match="inside the void"):
        Pier(-1.0, 1e5)


def test_a_pier_lets_the_line_overhang_farther_than_no_pier(inp, first_span, base):
    s = first_span.max_span_widths
    o = base.rule.overhang_for(1)
    assert o >= 1 and base.rule.max_void_for(1) == s + 1 + o > s
    w = s + 1 + o  # the widest void over one pier: without it the line cannot reach the far ledge
    _rows, alone = min_rows(LINE, w, inp)
    assert alone.tip_deflection_m > inp.clearance_m
    over = solve_piers(inp, w, (float(s),), 1)
    assert over.passes and over.result.tip_deflection_m <= inp.clearance_m < alone.tip_deflection_m
    # and the solve is the one it reports: every support's reaction sums to the weight
    assert over.result.reactions_n.sum() == pytest.approx(over.result.total_weight_n, rel=1e-6)
    assert over.result.pier_loads_n[0] > 0 and over.result.pier_compression_m[0] > 0


def test_every_state_of_the_crossing_passes_at_the_rule_counts(inp, base):
    rule = base.rule
    for c in base.crossings:
        states = c.states_one + c.states_two
        assert states and all(st.passes for st in states), [st for st in states if not st.passes]
        for st in states:
            if "beyond pier" in st.what and not st.what.startswith("landed"):
                assert st.rows_behind >= rule.min_rows_behind(st.rows_beyond)
                assert st.tipping_factor > inp.required_tipping and st.tip_mm <= inp.clearance_m * 1e3
        # one row more beyond the pier is past the clearance (or does not stand): the overhang is the widest
        assert len(c.one.tip_mm) > c.overhang and c.one.tip_mm[c.overhang] > inp.clearance_m * 1e3
    assert rule.max_deflection_mm <= inp.clearance_m * 1e3 and rule.min_tipping_factor > 1


def test_the_counting_rule_is_the_smallest_that_stands(inp, base):
    """Rows behind = o + margin stands rigidly about the far face for every derived overhang; one
    row fewer does not for some (the rule is not padded)."""
    from structure_fem.model.structures import tipping_factor

    rule = base.rule
    top = max(rule.overhang_widths)

    def rigid(rb: int, o: int) -> float:
        n = rb + o
        lay = layout(LINE, inp.robot, inp.connectors, n, n - 1, n)
        edge = lay.bodies[lay.front_body].x_m + lay.length_m / 2 - o * lay.pitch_m
        return tipping_factor(lay.bodies, [b.com_m[0] for b in lay.bodies], edge)

    assert all(rigid(rule.min_rows_behind(o), o) > 1 for o in range(1, top + 1))
    assert any(rigid(rule.min_rows_behind(o) - 1, o) <= 1 for o in range(1, top + 1))


def test_piers_only_push(inp, clearance_latch):
    """A pier under a part of the line that the overhang lifts carries nothing there (the line
    leaves its top); the same configuration with two-sided supports would pull it down. (With the
    clearance latch's play, whose open joints let the line leave the pier at these positions.)"""
    inp = dataclasses.replace(inp, connectors=clearance_latch(inp.connectors))
    # (with the supports at the wheels and casters: piers at 0.5 and 2.5, 6 rows over; the corner
    # supports used 0.5 and 3.0 with 7 over, where the contacts' pier 1 is no longer pulled down)
    piers = (robot_pier(inp.robot, inp.connectors, 1, 0.5), robot_pier(inp.robot, inp.connectors, 1, 2.5))
    cfg = Config(LINE, 7, 6, 6, piers=piers)
    one_sided = solve(cfg, inp.robot, inp.connectors)
    two_sided = solve(dataclasses.replace(cfg, clamped=True), inp.robot, inp.connectors)
    on_a = [i for i, s in enumerate(one_sided.layout.supports) if s.pier == 0]
    assert min(two_sided.reactions_n[i] for i in on_a) < -0.1  # a two-sided pier would hold the line down
    assert min(one_sided.reactions_n[i] for i in on_a) >= 0.0
    assert any(one_sided.reactions_n[i] < 1e-3 for i in on_a)  # lifted off there
    assert one_sided.reactions_n.sum() == pytest.approx(one_sided.total_weight_n, rel=1e-6)


def test_a_stiffer_pier_never_gives_less_overhang(inp, first_span):
    scales = (0.003, 0.01, 0.03, 1.0)  # of a pier of 2 robots: 1.4e3 .. 4.7e5 N/m
    got = [derive(PierStudy(inp, first_span, max_pier_robots=2, pier_stiffness_scale=f)).rule for f in scales]
    over = [r.overhang_for(2) for r in got]
    assert all(a <= b for a, b in zip(over, over[1:], strict=False)), over
    assert over[0] < over[-1], over  # and the pier's stiffness does matter when it is soft enough
    assert [r.pier_stiffness_n_per_m[1] for r in got] == pytest.approx(
        [f * got[-1].pier_stiffness_n_per_m[1] for f in scales], rel=1e-6)


def test_the_rule_moves_when_the_inputs_move(inp, base):
    """Heavier robots press the pier further and droop more; softer keys make softer piers."""
    heavy_inp = StudyInputs.for_robot(inp.robot, inp.clearance_m * 1e3, mass_scale=2.0)
    heavy_inp = dataclasses.replace(heavy_inp, connectors=inp.connectors)
    heavy = derive(PierStudy(heavy_inp, own_level(heavy_inp), max_pier_robots=2))
    soft_inp = dataclasses.replace(inp, connectors=inp.connectors.scaled(0.5, 1.0))
    soft = derive(PierStudy(soft_inp, own_level(soft_inp), max_pier_robots=2))
    assert heavy.rule != base.rule and soft.rule != base.rule

    def beyond(d, k, o=None):  # the state o rows (default: the deepest overhang) beyond the first pier of k robots
        c = d.crossings[k - 1]
        o = c.overhang if o is None else o
        return next(st for st in c.states_one if st.what == f"{o} rows beyond pier 1")

    # heavier: never more overhang, and at the same state (the heavy rule's deepest, which the
    # base crossing also goes through) a deeper tip and a pier pressed twice as hard
    o = heavy.crossings[1].overhang
    assert heavy.rule.overhang_widths[1] <= base.rule.overhang_widths[1]
    assert beyond(heavy, 2).tip_mm > beyond(base, 2, o).tip_mm
    assert beyond(heavy, 2).pier_compression_mm[0] > 1.5 * beyond(base, 2, o).pier_compression_mm[0]
    assert soft.rule.pier_stiffness_n_per_m[1] == pytest.approx(0.5 * base.rule.pier_stiffness_n_per_m[1], rel=0.02)
    assert soft.rule.overhang_widths[1] <= base.rule.overhang_widths[1]
    assert beyond(soft, 2).tip_mm > beyond(base, 2, soft.crossings[1].overhang).tip_mm


def test_the_record_carries_the_rule_and_round_trips(tmp_path, base, first_span):
    derived = load_limits("derived")
    assert derived.piers is not None and derived.piers.structure == "line"
    assert derived.piers.first_span_widths == derived.level_for(1).max_span_widths
    assert len(derived.piers.overhang_widths) == 4
    assert derived.piers.max_void_widths == tuple(derived.piers.first_span_widths + 1 + o
                                                  for o in derived.piers.overhang_widths)
    assert StructureLimits.load(derived.save(tmp_path / "limits.json")) == derived
    # a record written before the field existed loads without it
    old = derived.to_dict()
    del old["piers"]
    (tmp_path / "old.json").write_text(json.dumps(old))
    assert StructureLimits.load(tmp_path / "old.json").piers is None
    assert StructureLimits.load(tmp_path / "old.json").levels == derived.levels
    # the thesis has no pier rule
    assert thesis_limits().piers is None and thesis_limits().to_dict()["piers"] is None


def test_a_pier_rule_that_contradicts_itself_or_its_limits_is_rejected(base):
    rule = base.rule
    with pytest.raises(InputError, match="max_void_widths"):
        dataclasses.replace(rule, max_void_widths=tuple(v + 1 for v in rule.max_void_widths))
    with pytest.raises(InputError, match="entries"):
        dataclasses.replace(rule, pier_stiffness_n_per_m=rule.pier_stiffness_n_per_m[:1])
    derived = load_limits("derived")
    with pytest.raises(InputError, match="own threshold"):
        dataclasses.replace(derived, piers=dataclasses.replace(
            rule, first_span_widths=rule.first_span_widths + 1,
            max_void_widths=tuple(v + 1 for v in rule.max_void_widths)))
    with pytest.raises(InputError, match="not a level"):
        dataclasses.replace(derived, piers=dataclasses.replace(rule, structure="arch-9x9"))
    assert isinstance(rule, PierRule) and rule.min_rows_behind(3) == 3 + rule.ground_margin


def test_piers_none_leaves_the_rule_out(inp):
    derived = dataclasses.replace(load_limits("derived"), piers=None)
    lim, d, why = with_piers(derived, inp, RunOptions(piers="none"))
    assert lim.piers is None and d is None and "--piers none" in why
    with pytest.raises(InputError, match="--piers 'sometimes'"):
        RunOptions(piers="sometimes")


def test_fem_piers_reports_one_configuration(cli, tmp_path):
    png = tmp_path / "piers.png"
    res = cli("fem", "piers", "--void-width", "7", "--piers", "3", "--pier-robots", "2", "--json", "--plot", str(png))
    assert res.code == 0, res.err
    out = res.json()
    assert out["converged"] and out["structure"] == "line" and out["tipping_factor"] > 1
    assert out["tip_deflection_mm"] > 0 and out["support_reactions_sum_n"] == pytest.approx(out["weight_n"], rel=1e-6)
    (p,) = out["piers"]
    assert p["robots"] == 2 and p["load_n"] > 0 and p["compression_mm"] == pytest.approx(
        1e3 * p["load_n"] / p["stiffness_n_per_m"], rel=1e-3)
    assert {r["support"] for r in out["support_reactions"]} == {"near", "pier 1"}
    # about the front caster of the robot on the pier, 12 mm short of the pier's far face (0.4 m)
    assert out["tipping_edge_m"] == pytest.approx(0.4 - 0.012)
    assert png.stat().st_size > 0
    two = cli("fem", "piers", "--void-width", "9", "--piers", "3,6", "--pier-robots", "1", "--rows", "12")
    assert two.code == 0, two.err
    assert "pier 2 at 6" in two.out and math.isfinite(float(two.out.split("tip ")[1].split(" mm")[0]))


@pytest.mark.parametrize("value,word", [
    ("-1", "pier at -1 is not inside the void"),
    ("0", "pier at 0 is not inside the void"),
    ("6.5", "reaches beyond the 7-wide void"),
    ("9", "reaches beyond"),
    ("3,3.5", "pier at 3.5 overlaps the pier at 3"),
    ("5,3", "pier at 3 overlaps"),
    ("abc", "'abc' is not a number"),
    ("3,,5", "comma list"),
    ("nan", "not a finite number"),
])
def test_bad_piers_is_one_line_exit_2(cli, value, word):
    res = cli("fem", "piers", "--void-width", "7", "--piers", value)
    assert res.code == 2, res.err
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:")
    assert word in res.error_lines[0] and f"--piers {value!r}" in res.error_lines[0]


@pytest.mark.parametrize("argv,word", [
    (("fem", "piers", "--void-width", "7", "--piers", "3", "--pier-robots", "5"), "--pier-robots 5"),
    (("fem", "piers", "--void-width", "0", "--piers", "3"), "--void-width 0"),
    (("fem", "piers", "--void-width", "7", "--piers", "3", "--over", "8"), "--over 8"),
    (("fem", "table", "--piers", "sometimes"), "sometimes"),
])
def test_bad_pier_options_are_one_line_exit_2(cli, argv, word):
    res = cli(*argv)
    assert res.code == 2, res.err
    assert len(res.error_lines) == 1 and word in res.error_lines[0]
