"""Derived thresholds: what must hold when inputs move, the counting rules, the packaged limits."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

pytest.importorskip("exudyn")

from structure_fem.calibration import MEASURED_TIP_M, calibrate, platform_from, platform_tip_m  # noqa: E402
from structure_fem.limits import load_limits, packaged_limits_path  # noqa: E402
from structure_fem.runs import packaged_limits  # noqa: E402
from structure_fem.structures import GRAVITY  # noqa: E402
from structure_fem.study import StudyInputs, derive, limits_from  # noqa: E402


def _th(d) -> dict:
    return d.thresholds()["per_structure"]


@pytest.fixture(scope="session")
def base(cubot_session):
    return derive(StudyInputs.for_robot(cubot_session), extra=0)


@pytest.fixture(scope="session")
def cubot_session():
    from cubot_cad.properties import default_properties

    return default_properties().get("cubot")


def _never_below(a: dict, b: dict) -> None:
    for name, t in a.items():
        assert b[name] >= t, f"{name}: {t} -> {b[name]}"


def test_stiffer_connectors_never_shrink_a_threshold(base, cubot_session):
    stiff = derive(StudyInputs.for_robot(cubot_session, stiffness_scale=2.0), extra=0)
    _never_below(_th(base), _th(stiff))
    assert stiff.max_span > base.max_span or stiff.curve("line").tip_mm[0] < base.curve("line").tip_mm[0]


def test_larger_clearance_never_shrinks_a_threshold(base, cubot_session):
    wide = derive(StudyInputs.for_robot(cubot_session, clearance_mm=base.inputs.clearance_m * 1e3 * 2), extra=0)
    _never_below(_th(base), _th(wide))
    assert sum(_th(wide).values()) > sum(_th(base).values())


def test_heavier_robots_never_grow_a_threshold(base, cubot_session):
    heavy = derive(StudyInputs.for_robot(cubot_session, mass_scale=2.0), extra=0)
    _never_below(_th(heavy), _th(base))
    assert heavy.curve("line").tip_mm[0] > base.curve("line").tip_mm[0]


def test_threshold_is_the_widest_void_within_clearance(base):
    clear = base.inputs.clearance_m * 1e3
    for c in base.curves:
        t = c.threshold
        assert all(x <= clear for x in c.tip_mm[:t])
        if t < len(c.tip_mm):
            assert c.tip_mm[t] > clear


def test_limits_tile_widths_and_counts_stand(base):
    lim = limits_from(base)
    assert lim.source == "derived"
    assert lim.levels[0].min_span_widths == 1
    assert lim.max_span_widths == base.max_span
    for lvl in lim.levels:
        c = base.curve(lvl.name)
        for w in range(lvl.min_span_widths, lvl.max_span_widths + 1):
            assert lvl.robots_for(w) == c.robots[c.widths.index(w)]
            assert c.tipping[c.widths.index(w)] > 1.0


def test_minimal_line_count_beats_the_thesis_rule_and_one_less_would_tip(base):
    """Thesis: N = 3 n_g (n_p = 2 n_g while launching). Tipping about the edge only needs n_p > n_g:
    a uniform line's rigid factor is (n_p / n_g)^2, so N_min = 2 w + 1 when the centre of mass is
    central; the solved factor of one row less must not exceed 1."""
    from structure_fem.model import Config, solve

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
    assert base.curve("two_line-aligned").threshold == base.curve("line").threshold
    assert base.curve("two_line-aligned").tip_mm == pytest.approx(base.curve("line").tip_mm, rel=1e-6)


def test_packaged_limits_json_is_regenerated_from_the_packaged_properties():
    """Fails when robot_properties.json or the model changed: run `python -m structure_fem.runs`."""
    fresh = packaged_limits()
    shipped = json.loads(packaged_limits_path().read_text())
    assert json.loads(json.dumps(fresh.to_dict())) == shipped, (
        "structure_fem/data/limits.json is stale: regenerate with `python -m structure_fem.runs`")
    assert load_limits("derived").source == "derived"


def test_calibration_reproduces_the_measurement_and_the_closed_form():
    """Stiffness-only fit: five platforms, one held, four overhang joints. As in the rigid-link
    chain test (n = 4): tip = m g a^2 / (2 k) (n (n + 1) / 2)^2 + pin slip m g n (n + 1) / (2 k_ax)
    + the held platform's contact springs k_c, so k = m g a^2 100 / (2 (5 mm - slip - clamp))."""
    from structure_fem.connectors import ConnectorSet
    from structure_fem.model import CONTACT_N_PER_M

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
