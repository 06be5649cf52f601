"""The thesis's tapering arch (Ch. 5.5.2 (c)-(f)): a two-line core sliding through a static foot
at each ledge. Small custom records (blocks of B = 2 rows, k = 2 layers, narrow voids) keep the
runs short; the thesis's own numbers are checked on the geometry."""

from __future__ import annotations

import numpy as np
import pytest

from structure_fem.limits import (
    taper_half_level,
    tapered_arch_robots,
)
from swarm_sim.behaviour import taper as T
from swarm_sim.errors import InputError
from swarm_sim.runner import resolve_params, run_scenario, simulate
from swarm_sim.state import OPEN, Mode

V = 4  # void width (robot widths) of the simulated cases


def params(limits, robots, width=V, **kw):
    return resolve_params("case-d", robots, width, limits, 900.0, structure="switch", finish_delivery=True, **kw)


def shell_by_zone(st, g):
    """Shell robots per row and (initial, over, target) counts."""
    sh = np.asarray(st.shell)
    rows = g.row[sh != OPEN]
    per_row = {int(r): int(c) for r, c in zip(*np.unique(rows, return_counts=True), strict=True)}
    return per_row, (int((rows < 0).sum()), int(((rows >= 0) & (rows < g.V)).sum()), int((rows >= g.V).sum()))


class Watch:
    """on_step probe: the near foot when it is first complete, the whole arch when the far foot
    is first complete, and whether a shell robot ever moved while its slot stayed the same."""

    def __init__(self, g):
        self.g, self.near = g, None
        self.near_core = None
        self.full = None
        self.moved = 0
        self.prev = None

    def __call__(self, s):
        st = s.structure
        if st is None or not st.shell:
            self.prev = None
            return
        sh = np.asarray(st.shell)
        near = self.g.foot == T.NEAR
        if self.near is None and (sh[near] != OPEN).all() and not st.landed:
            self.near = shell_by_zone(st, self.g)
        if self.full is None and (sh != OPEN).all():
            self.full = shell_by_zone(st, self.g)
        if self.prev is not None:
            psh, px, py = self.prev
            same = (sh == psh) & (sh != OPEN)
            ids = sh[same]
            self.moved += int(((s.x_cm[ids] != px[ids]) | (s.y_cm[ids] != py[ids])).sum())
        self.prev = (sh.copy(), s.x_cm.copy(), s.y_cm.copy())


@pytest.fixture(scope="module")
def lim(tmp_path_factory, tapering_record):
    return tapering_record(tmp_path_factory.mktemp("taper") / "limits.json")


@pytest.fixture(scope="module")
def runs(lim):
    """(state, result, watch) for the rule minimum (every invariant checked each step), one robot
    fewer, and the complete arch (lost robots counted by the cheap per-step check)."""
    g = T.shell_geometry(2, 2, V)
    out = {}
    p = params(lim, 10)
    for name, n in (("min", p.min_robots_rule), ("below", p.min_robots_rule - 1), ("full", p.record_min_robots)):
        w = Watch(g)
        state, res = simulate(params(lim, n), 1, check=name == "min", on_step=w)
        out[name] = (state, res, w)
    return out


def test_thesis_geometry_near_foot_is_140_initial_60_over_at_15_widths():
    k, B, W = 3, 5, 15
    g = T.shell_geometry(k, B, W)
    # a complete near foot plus the core (k B rows on the ground, the whole void) is the thesis's 28a / 12a
    shell = tuple(0 if f == T.NEAR else OPEN for f in g.foot)
    sp, sg, so = T.shell_counts(shell, g)
    assert (sp + 2 * k * B, sg + 2 * W, so) == (140, 60, 0)
    assert tapered_arch_robots(k, B, W, far_foot=False) == {"initial": 140, "over": 60, "target": 0, "total": 200}
    # every row's section is 2 j^2 robots (the core's two plus the shell)
    rows = g.row[g.foot == T.NEAR]
    for r in range(-k * B, W):
        assert 2 + int((rows == r).sum()) == 2 * taper_half_level(k, B, r, W, far_foot=False) ** 2
    # both feet: the thesis's complete arch 28a / 18a / 28a
    s_all = T.shell_counts(tuple(0 for _ in g.foot), g)
    assert (s_all[0] + 2 * k * B, s_all[1] + 2 * W, s_all[2] + 2 * k * B) == (140, 90, 140)


def test_thesis_preset_reports_the_rule_minimum_and_the_record_count():
    p = resolve_params("large-void-15", 370, 15, "thesis")
    assert (p.min_robots_rule, p.record_min_robots) == (200, 370)
    p30 = resolve_params("large-void-30", 880, 30, "thesis")
    assert p30.record_min_robots == 880 and p30.min_robots_rule < 880
    with pytest.raises(InputError, match="wider than the widest"):
        resolve_params("large-void-30", 880, 30, "derived")


def test_near_foot_once_built_has_the_section_taper_half_level_says(runs):
    g = T.shell_geometry(2, 2, V)
    per_row, zones = runs["min"][2].near
    for r in range(-4, V):
        j = taper_half_level(2, 2, r, V, far_foot=False)
        assert per_row.get(r, 0) == 2 * j * j - 2, r
    ref = tapered_arch_robots(2, 2, V, far_foot=False)
    assert (zones[0] + 2 * 4, zones[1] + 2 * V, zones[2]) == (ref["initial"], ref["over"], 0)
    assert g.n > 0


def test_far_foot_mirrors_the_near_one_and_shells_never_move_in_their_slot(runs):
    per_row, zones = runs["full"][2].full
    ref = tapered_arch_robots(2, 2, V)
    assert (zones[0] + 8, zones[1] + 2 * V, zones[2] + 8) == (ref["initial"], ref["over"], ref["target"])
    for r in range(V, V + 4):  # the mirror of the near foot's ground rows
        assert per_row.get(r, 0) == per_row.get(V - 1 - r, 0)
    for _state, _res, w in runs.values():
        assert w.moved == 0


def test_rule_minimum_crosses_with_everyone_delivered_and_one_fewer_retreats(runs):
    _s, ok, _w = runs["min"]
    assert ok.success and ok.robots_lost == 0 and ok.violations == []
    assert ok.robots_delivered == ok.robots and ok.robots_on_initial_side == 0
    assert ok.levels_used == ["line", "arch-t"]
    kinds = {e[1] for e in ok.events}
    assert {"fill_near", "fill_far", "unfill_near", "dissolve_far"} <= kinds
    assert ok.construction["assembly"] is not None and ok.construction["disassembly"] is not None
    _s, full, _w = runs["full"]
    assert full.success and full.robots_lost == 0 and full.robots_delivered == full.robots
    state, fail, _w = runs["below"]
    assert fail.retreated and fail.robots_lost == 0 and fail.violations == []
    assert fail.robots_on_initial_side == fail.robots
    assert (state.mode == Mode.STOPPED).all()


def test_block_rows_and_span_move_the_switch_and_the_counts(tmp_path, tapering_record):
    base = params(tapering_record(tmp_path / "a.json"), 10)
    longer_blocks = params(tapering_record(tmp_path / "b.json", B=3), 10)
    later_switch = params(tapering_record(tmp_path / "c.json", line_span=3), 10)
    assert longer_blocks.min_robots_rule > base.min_robots_rule
    assert longer_blocks.record_min_robots > base.record_min_robots
    assert later_switch.min_robots_rule != base.min_robots_rule
    r = run_scenario("case-d", later_switch.min_robots_rule, V, 1, limits=str(tmp_path / "c.json"),
                     structure="switch", finish_delivery=True, max_time_s=900.0)
    assert r.success and r.robots_lost == 0
    assert [s["n_g"] for s in r.switches] == [3]  # the line carried 3 rows over the void, not 2


def test_climb_time_must_be_a_non_negative_number(lim):
    with pytest.raises(InputError, match="climb_s_per_layer"):
        params(lim, 30, climb_s_per_layer=-1.0)


def test_an_arena_too_short_for_the_feet_is_rejected_before_the_run(lim):
    with pytest.raises(InputError, match="feet need 60 cm"):
        params(lim, 10, void_left_x_cm=40.0)


def test_cli_derived_limits_reject_30_widths_exit_2_and_thesis_reports_both_counts(cli):
    res = cli("sim", "run", "--preset", "large-void-30", "--void-width", "30")
    assert res.code == 2 and "wider than the widest" in res.error_lines[0]
    # both counts on the human line (a too-short run: stops at the seed's alignment time cap)
    res = cli("sim", "run", "--preset", "large-void-15", "--limits", "thesis", "--max-time", "1")
    assert "min robots 200 by the rule, 370 by the record" in res.out


def _derived_band() -> range:
    """6 widths up to the derived record's widest void (8 today; computed, so it follows the record)."""
    from structure_fem.limits import load_limits

    return range(min(6, load_limits("derived").max_span_widths), load_limits("derived").max_span_widths + 1)


@pytest.mark.parametrize("preset, band, limits", [("large-void", range(6, 11), "thesis"),
                                                  ("large-void-15", range(11, 16), "thesis"),
                                                  ("large-void-30", range(16, 31), "thesis"),
                                                  ("large-void-8", _derived_band(), "derived")])
def test_each_large_void_preset_holds_enough_robots_for_every_width_of_its_band(preset, band, limits):
    """Issue 6: presets for 11..30 widths with the robot counts the structures need, for the
    thesis's limits and for the derived ones (up to the derived record's widest void).

    The need is the simulator's rule minimum computed from the record's geometry, so a change of
    the rule or the taper that makes a preset too small fails here, not in a 20-minute run.
    """
    from swarm_sim.params import load_preset

    robots = load_preset(preset).robots
    for w in band:
        need = resolve_params(preset, robots, w, limits).min_robots_rule
        assert robots >= need, f"{preset}: {robots} robots, {w} widths need {need}"
