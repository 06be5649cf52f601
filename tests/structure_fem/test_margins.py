"""Margins, what sets a threshold (decomposition of the tip), and its range (issue 12, item 6)."""

from __future__ import annotations

import pytest

pytest.importorskip("exudyn")

from structure_fem.analysis import margins  # noqa: E402
from structure_fem.analysis.study import Derivation, structure_curve  # noqa: E402
from structure_fem.model.structures import Structure  # noqa: E402
from structure_fem.outputs.runs import RunOptions, make_inputs  # noqa: E402


@pytest.fixture(scope="module")
def line_report():
    inp, _ = make_inputs(RunOptions())
    c = structure_curve(Structure("line"), inp, extra=1)
    return margins.structure_report(Derivation(inp, [c], []), c)


def test_margin_is_non_negative_at_the_threshold_and_negative_one_width_beyond(line_report):
    r = line_report
    assert r["threshold"] >= 1
    assert r["margin_mm"] >= 0
    assert r["margin_beyond_mm"] < 0
    # the margin is what the clearance leaves after the static tip and the launch overshoot
    allow = r["dynamic_allowance_mm"] or 0.0
    assert r["margin_mm"] == pytest.approx(r["clearance_mm"] - r["tip_mm"] - allow, abs=1e-3)
    assert r["bodies"] == "flexible"  # the table's default (issue 12, deliverable 3)


def test_flexible_bodies_add_their_bending_and_say_where_it_comes_from(line_report):
    """The bodies' share is the flexible tip less the rigid-body tip of the same structure, and
    the record's section (cut from the CAD) is what they bend with."""
    d = line_report["decomposition"]
    assert 0 < d["rigid_bodies_tip_mm"] < line_report["tip_mm"]
    src = line_report["bodies_source"]
    assert src["second_moment_m4"] > 0 and src["source"].startswith("cubot_cad.section")


def test_the_decomposition_sums_to_the_tip_within_one_percent(line_report):
    d = line_report["decomposition"]
    assert d["support_mm"] + d["play_mm"] + d["elastic_mm"] == pytest.approx(d["sum_mm"], abs=2e-4)
    assert d["sum_mm"] == pytest.approx(d["tip_mm"], rel=0.01)
    assert d["play_mm"] > 0 and d["elastic_mm"] > 0
    # the counterfactual: without any play the tip is what the elastic joints and supports give
    assert 0 < d["without_play_tip_mm"] < d["tip_mm"]
    assert d["play_total_mm"] == pytest.approx(d["tip_mm"] - d["without_play_tip_mm"], abs=1e-3)


def test_the_wedge_latch_takes_the_play_out_of_the_line(line_report):
    """The clearance latch's 0.4 mm tension gap over a 37 mm lever made ~95 % of the line's tip play
    (issue 38); the wedge latch draws it shut: the joints' opening rotation (``play_mm``) is a small
    share of the tip. What play is left is the pins' vertical slip in their bores (2 x 0.2 mm per
    joint, kept because the model does not count on the preload's friction): where play still sets
    the line (44 % of the tip at 5 widths on the packaged record), it is that slip. Where the launch
    allowance took a width off the static threshold, that is what sets it, and the report says so."""
    d = line_report["decomposition"]
    assert 0 <= d["play_mm"] < 0.1 * d["tip_mm"]
    if line_report["threshold"] < line_report["static_threshold"]:
        assert line_report["set_by"] == "dynamic"
    elif line_report["set_by"] == "play":
        assert d["play_total_mm"] - d["play_mm"] > 0.9 * d["play_total_mm"]  # the slip, not the opening


def test_the_range_brackets_the_threshold_and_goes_the_physical_way(line_report):
    rg = line_report["range"]
    by = {v["inputs"]: v["threshold"] for v in rg["variants"]}
    t = line_report["threshold"]
    assert rg["min"] <= t <= rg["max"]
    assert by["print clearance 0.4 mm"] <= t <= by["print clearance 0.1 mm"]
    assert by["printed modulus x0.7"] <= t
    # the record is at its parts' recorded infill: solid parts (heavier) never widen the threshold,
    # and the worst case takes all three
    assert by[margins.SOLID_VARIANT] <= t
    worst = f"print clearance 0.4 mm, printed modulus x0.7 and {margins.SOLID_VARIANT}"
    assert by[worst] == rg["min"] <= by["print clearance 0.4 mm and printed modulus x0.7"]
    assert rg["record_print_clearance_mm"] == pytest.approx(0.2)


def test_the_range_uses_the_tables_criterion_with_each_variants_own_transients(line_report):
    """Issue 12, items 4 and 6: a variant's threshold is static tip + its own launch allowance
    <= clearance, as the table's: never above its static threshold, and at it the margin holds."""
    rg = line_report["range"]
    assert "launch allowance" in rg["criterion"]
    for v in rg["variants"]:
        assert v["threshold"] <= v["static_threshold"]
        if v["threshold"] >= 1:
            assert v["dynamic_allowance_mm"] > 0
    # the loose print's play makes the structure fall farther through its joints: a larger overshoot
    # at the same width (at a narrower one it can be smaller: fewer rows over the void fall)
    by = {v["inputs"]: v for v in rg["variants"]}
    loose, tight = by["print clearance 0.4 mm"], by["print clearance 0.1 mm"]
    assert loose["threshold"] <= tight["threshold"]
    if loose["threshold"] == tight["threshold"]:
        assert loose["dynamic_allowance_mm"] > tight["dynamic_allowance_mm"]


def test_the_infill_variant_is_the_records_solid_mass_and_moves_with_it():
    """The variant scales mass and inertia by the record's solid / as-sliced mass; a record without
    the field has no infill variant, and a heavier solid mass gives a heavier variant."""
    from dataclasses import replace

    inp, _ = make_inputs(RunOptions())
    r = inp.robot
    assert r.solid_print_mass_kg > r.mass_kg and "100 % infill" in r.solid_print_mass_source
    vs = dict(margins._variants(inp))
    solid = vs[margins.SOLID_VARIANT].robot
    assert solid.mass_kg == pytest.approx(r.solid_print_mass_kg)
    k = r.solid_print_mass_kg / r.mass_kg
    assert solid.inertia_kg_m2 == pytest.approx(tuple(i * k for i in r.inertia_kg_m2))
    bare = replace(inp, robot=replace(r, solid_print_mass_kg=None, solid_print_mass_source=None))
    assert margins.SOLID_VARIANT not in dict(margins._variants(bare))
    heavier = replace(inp, robot=replace(r, solid_print_mass_kg=2 * r.solid_print_mass_kg))
    assert dict(margins._variants(heavier))[margins.SOLID_VARIANT].robot.mass_kg == pytest.approx(
        2 * r.solid_print_mass_kg)


def test_markdown_flags_a_marginal_threshold(line_report):
    md = margins.markdown([line_report])
    (row,) = [ln for ln in md.splitlines() if ln.startswith("| line |")]
    assert ("**marginal**" in row) == line_report["marginal"]
    tight = dict(line_report, margin_mm=0.1, marginal=0.1 < margins.MARGINAL_FRACTION * 15.0)
    assert "| 0.10 **marginal** |" in margins.markdown([tight])
    assert f"below {100 * margins.MARGINAL_FRACTION:g} % of the clearance" in md


def test_a_threshold_at_the_widest_width_studied_is_marked_as_a_lower_bound(line_report):

    inp, _ = make_inputs(RunOptions(max_width=2, dynamic=False))
    c = structure_curve(Structure("line"), inp, extra=1)
    r = margins.structure_report(Derivation(inp, [c], []), c, ranges=False)
    assert r["threshold"] == 2 and r["capped_by_max_width"] and r["margin_beyond_mm"] is None
    assert line_report["capped_by_max_width"] is False
