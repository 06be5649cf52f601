"""Inverse design (`voidcross fem design`): the factor found is the boundary of spanning the void."""

from __future__ import annotations

import pytest

pytest.importorskip("exudyn")

from structure_fem import design as D  # noqa: E402
from structure_fem.runs import RunOptions, make_inputs  # noqa: E402


@pytest.fixture(scope="module")
def inp():
    return make_inputs(RunOptions())[0]


def test_the_play_factor_is_where_the_line_just_spans_the_void(inp):
    s = D.structure_named(inp, "line")
    w = 5
    res = D.design(inp, "line", w, ("play",))
    (r,) = res["results"]
    assert r["spans_now"] is False and 0 < r["factor"] < 1
    clear = inp.clearance_m * 1e3
    assert D.tip_mm(s, w, D.scaled_inputs(inp, "play", r["factor"])) <= clear
    assert D.tip_mm(s, w, D.scaled_inputs(inp, "play", r["factor"] * 1.05)) > clear
    assert r["values"]["front_rear_tension_play_mm"] == pytest.approx(
        1e3 * inp.connectors.front_rear.play_x[1] * r["factor"])


def test_a_void_the_structure_spans_already_reports_how_much_it_could_lose(inp):
    (r,) = D.design(inp, "line", 2, ("stiffness",))["results"]
    assert r["spans_now"] is True and r["factor"] < 1  # softer couplings would still do
    s = D.structure_named(inp, "line")
    assert D.tip_mm(s, 2, D.scaled_inputs(inp, "stiffness", r["factor"])) <= inp.clearance_m * 1e3


def test_a_parameter_that_cannot_do_it_alone_says_so(inp):
    """The line's droop at 5 widths is play: no stiffness makes it span (the tip only tends to
    the play's own droop)."""
    (r,) = D.design(inp, "line", 5, ("stiffness",))["results"]
    assert r["factor"] is None and "does not span 5 by stiffness alone" in r["note"]
    assert "does not span" in D.describe(D.design(inp, "line", 5, ("stiffness",)))


@pytest.mark.parametrize("argv,word", [
    (("--void-width", "0", "--structure", "line"), "--void-width 0"),
    (("--void-width", "40", "--structure", "line"), "--void-width 40"),
    (("--void-width", "3", "--structure", "tower"), "'tower'"),
    (("--void-width", "3", "--structure", "line", "--vary", "colour"), "--vary 'colour'"),
])
def test_bad_design_input_is_one_error_line_exit_2(cli, argv, word):
    res = cli("fem", "design", *argv)
    assert res.code == 2, res.err
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:") and word in res.error_lines[0]


def test_design_cli_prints_each_parameter(cli):
    res = cli("fem", "design", "--void-width", "4", "--structure", "line", "--vary", "play", "--json")
    assert res.code == 0, res.err
    out = res.json()
    assert out["structure"] == "line" and out["void_width"] == 4
    assert [r["parameter"] for r in out["results"]] == ["play"]
