"""Derived thresholds: what must hold when inputs move, the counting rules, the packaged limits."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

pytest.importorskip("exudyn")

from structure_fem.analysis.calibration import (  # noqa: E402
    MEASURED_TIP_M,
    calibrate,
    platform_from,
    platform_tip_m,
)
from structure_fem.analysis.study import StudyInputs, derive, limits_from  # noqa: E402
from structure_fem.limits import load_limits, packaged_limits_path  # noqa: E402
from structure_fem.model.structures import GRAVITY  # noqa: E402
from structure_fem.outputs.runs import packaged_limits  # noqa: E402


def _th(d) -> dict:
    return d.thresholds()["per_structure"]


#: A test robot with the old hand-estimate couplings (soft, so thresholds are small and fast to find).
BASE = dict(mass=0.3, k=200.0, k_ax=2e5, backlash=0.002)
MAXW = 12


@pytest.fixture(scope="module")
def base_robot(make_robot):
    return make_robot(**BASE)


@pytest.fixture(scope="module")
def base(base_robot):
    return derive(StudyInputs.for_robot(base_robot, max_width=MAXW), extra=0)


def _never_below(a: dict, b: dict) -> None:
    for name, t in a.items():
        assert b[name] >= t, f"{name}: {t} -> {b[name]}"


def test_stiffer_connectors_never_shrink_a_threshold(base, base_robot):
    stiff = derive(StudyInputs.for_robot(base_robot, stiffness_scale=2.0, max_width=MAXW), extra=0)
    _never_below(_th(base), _th(stiff))
    assert stiff.curve("line").tip_mm[0] < base.curve("line").tip_mm[0]


def test_larger_clearance_never_shrinks_a_threshold(base, base_robot):
    wide = derive(StudyInputs.for_robot(base_robot, clearance_mm=base.inputs.clearance_m * 1e3 * 2,
                                        max_width=MAXW), extra=0)
    _never_below(_th(base), _th(wide))
    assert sum(_th(wide).values()) > sum(_th(base).values())


def test_heavier_robots_never_grow_a_threshold(base, base_robot):
    heavy = derive(StudyInputs.for_robot(base_robot, mass_scale=2.0, max_width=MAXW), extra=0)
    _never_below(_th(heavy), _th(base))
    assert heavy.curve("line").tip_mm[0] > base.curve("line").tip_mm[0]


def test_threshold_is_the_widest_void_within_clearance(base):
    """Checked densely: every width up to the threshold passes, the next one fails."""
    from structure_fem.analysis.study import structure_curve

    clear = base.inputs.clearance_m * 1e3
    for c in base.curves:
        t = c.threshold
        for w in range(1, t + 2):
            c.index(w, base.inputs)
        assert all(c.tip_mm[c.index(w)] <= clear for w in range(1, t + 1))
        assert c.tip_mm[c.index(t + 1)] > clear
    # The doubling/bisection search agrees with a width-by-width scan (monotone tip vs width).
    tall = structure_curve(base.curves[-1].structure, replace(base.inputs, clearance_m=0.03), extra=0)
    scan = [tall.index(w, base.inputs) for w in range(1, tall.threshold + 2)]
    assert all(tall.tip_mm[i] <= 30 for i in scan[:-1]) and tall.tip_mm[scan[-1]] > 30


def test_limits_tile_widths_and_counts_stand(base):
    lim = limits_from(base)
    assert lim.source == "derived"
    assert lim.levels[0].min_span_widths == 1
    assert lim.max_span_widths == base.max_span
    for lvl in lim.levels:
        c = base.curve(lvl.name)
        for w in range(lvl.min_span_widths, lvl.max_span_widths + 1):
            assert lvl.robots_for(w) == c.robots[c.index(w)]
            assert c.tipping[c.index(w)] > 1.0


def test_minimal_line_count_beats_the_thesis_rule_and_one_less_would_tip(base):
    """Thesis: N = 3 n_g (n_p = 2 n_g while launching). Tipping about the edge only needs n_p > n_g:
    a uniform line's rigid factor is (n_p / n_g)^2, so N_min = 2 w + 1 when the centre of mass is
    central; the solved factor of one row less must not exceed 1."""
    from structure_fem.model.statics import Config, solve

    c = base.curve("line")
    robot = base.inputs.robot
    from structure_fem.errors import SolverFailure

    for w in c.widths[:4]:
        rows = c.rows[c.widths.index(w)]
        assert rows <= 3 * w
        try:  # one row less either has no static equilibrium (it tips) or a factor <= 1
            fewer = solve(Config(c.structure, rows - 1, w, w), robot, base.inputs.connectors)
        except SolverFailure:
            continue
        assert fewer.tipping_factor <= 1.0 + 1e-6


def test_aligned_two_lines_add_nothing_over_one_line(base):
    one, two = base.curve("line"), base.curve("two_line-aligned")
    assert two.threshold == one.threshold
    assert [two.tip_mm[two.index(w, base.inputs)] for w in (1, 2, 3)] == pytest.approx(
        [one.tip_mm[one.index(w, base.inputs)] for w in (1, 2, 3)], rel=1e-6)


def test_packaged_limits_json_is_regenerated_from_the_packaged_properties():
    """Fails when robot_properties.json or the model changed: run `python -m structure_fem.outputs.runs`."""
    fresh = packaged_limits()
    shipped = json.loads(packaged_limits_path().read_text())
    assert json.loads(json.dumps(fresh.to_dict())) == shipped, (
        "structure_fem/data/limits.json is stale: regenerate with `python -m structure_fem.outputs.runs`")
    assert load_limits("derived").source == "derived"


def test_calibration_reproduces_the_measurement_and_the_closed_form():
    """Stiffness-only fit: five platforms, one held, four overhang joints. As in the rigid-link
    chain test (n = 4): tip = m g a^2 / (2 k) (n (n + 1) / 2)^2 + pin slip m g n (n + 1) / (2 k_ax)
    + the held platform's contact springs k_c, so k = m g a^2 100 / (2 (5 mm - slip - clamp))."""
    from structure_fem.model.connectors import ConnectorSet
    from structure_fem.model.statics import CONTACT_N_PER_M

    cal = calibrate()
    plat = platform_from(None)
    assert platform_tip_m(plat, 5, cal.stiffness_nm_per_rad, 0.0) == pytest.approx(MEASURED_TIP_M, rel=1e-3)
    n, mg, a, kc = 4, plat.mass_kg * GRAVITY, plat.length_m, CONTACT_N_PER_M
    k_ax = ConnectorSet.from_robot(plat).front_rear.axial_n_per_m
    f_front, f_rear = n * mg + mg / 2 + mg * n * n / 2, mg / 2 - mg * n * n / 2
    rest = mg * n * (n + 1) / (2 * k_ax) + (f_front + n * (f_front - f_rear)) / kc
    k_closed = mg * a ** 2 * 100 / (2 * (MEASURED_TIP_M - rest))
    assert cal.stiffness_nm_per_rad == pytest.approx(k_closed, rel=0.01)
    assert cal.tips_m[3] < cal.tips_m[4] < 0.5 * cal.tips_m[5]  # "slightly" for three and four
    ks = [row[1] for row in cal.family]
    assert ks == sorted(ks)  # more backlash needs a stiffer spring to give the same 5 mm
    heavier = replace(plat, mass_kg=plat.mass_kg * 2)
    assert platform_tip_m(heavier, 5, cal.stiffness_nm_per_rad, 0.0) == pytest.approx(2 * MEASURED_TIP_M, rel=0.02)
