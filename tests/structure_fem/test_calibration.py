"""The platform-bolt calibration under both readings of "five connected platforms" (issue 12,
deliverable 7): each fitted, each reproducing the 5 mm when fed back, reported side by side, and
the report saying plainly that the CuBot's couplings do not come from it."""

from __future__ import annotations

import pytest

pytest.importorskip("exudyn")

from structure_fem.analysis.calibration import (  # noqa: E402
    CROSSING_READING,
    HELD_READING,
    MEASURED_TIP_M,
    READINGS,
    calibrate,
    platform_from,
    platform_tip_m,
)


@pytest.fixture(scope="module")
def cal():
    return calibrate()


def test_both_readings_are_fitted_and_differ(cal):
    assert [r.reading.name for r in cal.readings] == ["held", "crossing"] == [r.name for r in READINGS]
    held, crossing = cal.reading("held"), cal.reading("crossing")
    # the set-ups differ: 1 clamped + 4 over, against 3 resting on the ground + 2 over a 2-wide void
    assert HELD_READING.set_up() == {"platforms": 5, "held": 1, "on_the_ground": 1, "over": 4,
                                     "supports": "clamped (held on the bench)"}
    cfg = CROSSING_READING.config(5)
    assert (cfg.rows, cfg.rows_over, cfg.void_widths, cfg.clamped) == (5, 2, 2, False)
    # fewer joints over the void (and a shorter lever) need a much softer bolt for the same 5 mm
    assert crossing.stiffness_nm_per_rad < 0.5 * held.stiffness_nm_per_rad
    assert cal.to_dict()["readings_stiffness_ratio"] == pytest.approx(
        held.stiffness_nm_per_rad / crossing.stiffness_nm_per_rad, rel=1e-3)
    # the primary (top-level) fit is the held reading
    assert cal.stiffness_nm_per_rad == held.stiffness_nm_per_rad


@pytest.mark.parametrize("name", ["held", "crossing"])
def test_each_fit_reproduces_five_mm_when_fed_back(cal, name):
    fit = cal.reading(name)
    plat = platform_from(None)
    k = fit.stiffness_nm_per_rad
    assert platform_tip_m(plat, 5, k, 0.0, fit.reading) == pytest.approx(MEASURED_TIP_M, rel=1e-3)
    assert fit.refit_tip_m == pytest.approx(MEASURED_TIP_M, rel=1e-3)
    # and it is the fit that does it: the other reading's bolt does not give 5 mm in this set-up
    other = cal.reading("crossing" if name == "held" else "held").stiffness_nm_per_rad
    assert abs(platform_tip_m(plat, 5, other, 0.0, fit.reading) - MEASURED_TIP_M) > 0.5 * MEASURED_TIP_M
    # every family point reproduces 5 mm too, and more backlash needs a stiffer spring
    for _b, _kk, _t3, _t4, t5 in fit.family:
        assert t5 == pytest.approx(MEASURED_TIP_M, rel=1e-3)
    ks = [row[1] for row in fit.family]
    assert len(ks) >= 3 and ks == sorted(ks)
    assert fit.tips_m[3] <= fit.tips_m[4] * (1 + 1e-6) < 0.5 * fit.tips_m[5]  # "slightly" for three and four


def test_calibrate_reports_both_readings_and_where_the_robot_connectors_come_from(cli):
    res = cli("fem", "calibrate", "--json")
    assert res.code == 0, res.err
    out = res.json()
    assert [r["reading"] for r in out["readings"]] == ["held", "crossing"]
    assert all(r["refit_tip5_mm"] == pytest.approx(5.0, abs=5e-3) for r in out["readings"])
    assert out["readings"][0]["bolt_stiffness_nm_per_rad"] != out["readings"][1]["bolt_stiffness_nm_per_rad"]
    assert "do not come from this bolt fit" in out["robot_connectors"]
    assert "finite-element" in out["robot_connectors"]
    text = cli("fem", "calibrate")
    assert text.code == 0, text.err
    assert "reading held" in text.out and "reading crossing" in text.out
    assert "do not come from this bolt fit" in text.out
