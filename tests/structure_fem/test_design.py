"""Inverse design (`voidcross fem design`): the factor found is the boundary of spanning the void."""

from __future__ import annotations

import pytest

pytest.importorskip("exudyn")

from structure_fem.analysis import design as D  # noqa: E402
from structure_fem.outputs.runs import RunOptions, make_inputs  # noqa: E402


@pytest.fixture(scope="module")
def dyn():
    """The table's default inputs: the dynamic criterion (static tip + launch allowance)."""
    return make_inputs(RunOptions())[0]


@pytest.fixture(scope="module")
def inp(dyn):
    """The same with the static criterion (``--static``)."""
    from dataclasses import replace

    return replace(dyn, dynamic=False)


@pytest.fixture(scope="module")
def loose(inp):
    """The static inputs with the thesis's clearance latch (0.4 mm of tension play: the line at 5
    widths is set by it; the wedge latch of the packaged CuBot has none)."""
    from dataclasses import replace

    from .conftest import clearance_latch

    return replace(inp, connectors=clearance_latch(inp.connectors))


def test_the_wedge_latch_already_spans_what_the_clearance_latch_needs_less_play_for(inp, loose):
    assert D.design(inp, "line", 5, ("play",))["results"][0]["spans_now"] is True
    assert D.design(loose, "line", 5, ("play",))["results"][0]["spans_now"] is False


def test_the_play_factor_is_where_the_line_just_spans_the_void(loose):
    inp = loose
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


def test_with_the_launch_transients_the_boundary_asks_for_less_play(dyn, inp):
    """Under the table's dynamic criterion the play factor is the boundary of static tip + launch
    allowance <= clearance, on the passing side of the static one (the allowance is >= 0): passing at
    the factor, failing at the bracket's other end, both recomputed here."""
    s = D.structure_named(dyn, "line")
    w = 5
    res = D.design(dyn, "line", w, ("play",))
    assert res["dynamic"] is True and "allowance" in res["criterion"]
    (r,) = res["results"]
    (st,) = D.design(inp, "line", w, ("play",))["results"]
    assert r["static_factor"] == pytest.approx(st["factor"])
    assert 0 < r["factor"] < r["static_factor"]
    clear = dyn.clearance_m * 1e3
    t, a = D.dynamic_tip_mm(s, w, D.scaled_inputs(dyn, "play", r["factor"]))
    assert t + a <= clear and a == pytest.approx(r["allowance_mm"]) and a > 0
    lo, hi = r["bracket"]
    assert lo == r["factor"] and hi > lo
    t2, a2 = D.dynamic_tip_mm(s, w, D.scaled_inputs(dyn, "play", hi))
    assert t2 + a2 > clear
    assert r["values"]["front_rear_tension_play_mm"] == pytest.approx(
        1e3 * dyn.connectors.front_rear.play_x[1] * r["factor"])
    assert "static criterion alone" in D.describe(res)


def test_a_void_the_structure_spans_already_reports_how_much_it_could_lose(inp):
    (r,) = D.design(inp, "line", 2, ("stiffness",))["results"]
    assert r["spans_now"] is True and r["factor"] < 1  # softer couplings would still do
    s = D.structure_named(inp, "line")
    assert D.tip_mm(s, 2, D.scaled_inputs(inp, "stiffness", r["factor"])) <= inp.clearance_m * 1e3


def test_a_parameter_that_cannot_do_it_alone_says_so(loose):
    """With the clearance latch the line's droop at 5 widths is play: no stiffness makes it span (the
    tip only tends to the play's own droop)."""
    (r,) = D.design(loose, "line", 5, ("stiffness",))["results"]
    assert r["factor"] is None and "does not span 5 by stiffness alone" in r["note"]
    assert "does not span" in D.describe(D.design(loose, "line", 5, ("stiffness",)))


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
    assert out["structure"] == "line" and out["void_width"] == 4 and out["dynamic"] is True
    assert [r["parameter"] for r in out["results"]] == ["play"]
    assert out["results"][0]["factor"] <= out["results"][0]["static_factor"]
    res = cli("fem", "design", "--void-width", "4", "--structure", "line", "--vary", "play", "--static", "--json")
    assert res.code == 0, res.err
    assert res.json()["dynamic"] is False and "static_factor" not in res.json()["results"][0]
