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


@pytest.fixture(scope="module")
def cad_cal():
    """The calibration of the packaged record's platform (the CAD's), as `fem calibrate` runs it."""
    from cubot_cad.properties import default_properties

    return calibrate(default_properties())


def test_the_platform_test_is_run_with_one_geometry_and_shown_beside_five_mm(cad_cal, cli):
    """Issue 38, deliverable 4: the record's body section is the CAD's 5 mm plate (the lap joint's
    tab and recess left to the bolt's FE, which counts them), the same plate the FE measures its
    joint against; the model run that way (flexible platforms + the FE's joint) agrees with the
    rigid platforms + the FE's whole pitch, and `fem calibrate` prints it beside the thesis's 5 mm."""
    cal = cad_cal
    fe = cal.fe
    assert fe["available"], fe
    g = fe["one_geometry"]
    assert g["record_body_second_moment_mm4"] == pytest.approx(100 * 5 ** 3 / 12, rel=1e-3)  # b t^3 / 12
    assert 1.0 <= g["fe_over_record"] < 1.0 / (1 - 0.35 ** 2)  # the FE's plate: the beam + at most the plate effect
    for r in fe["readings"]:
        assert r["model_tip5_mm"] == pytest.approx(r["fe_tip5_mm"], rel=0.03)  # one geometry, two ways
        tips = [r["model_tips_mm"][n] for n in ("3", "4", "5")]
        assert tips == sorted(tips) and r["model_tips_mm"]["5"] == r["model_tip5_mm"]
        assert r["model_contact_tip5_mm"] < r["model_tip5_mm"]  # the faces bearing stiffen it
    test = cal.to_dict()["platform_test"]
    assert test["thesis"] == {"3": "slight", "4": "slight", "5": 5.0}
    held, crossing = (next(r for r in test["readings"] if r["reading"] == n) for n in ("held", "crossing"))
    # the unstated set-up matters more than the bolt: the two readings bracket the measured 5 mm
    assert crossing["model_tips_mm"]["5"] < 5.0 < held["model_faces_bearing_tip5_mm"]
    text = cli("fem", "calibrate")
    assert text.code == 0 and text.out.startswith("the thesis's platform test")
    assert "against the thesis's slight / slight / 5 mm" in text.out.splitlines()[0]


def test_a_thinner_plate_in_the_record_deflects_the_model_more(cad_cal):
    from dataclasses import replace

    from cubot_cad.properties import default_properties
    from structure_fem.analysis.calibration import one_geometry

    cal = cad_cal
    plat = platform_from(default_properties())
    thin = replace(plat, body_second_moment_m4=plat.body_second_moment_m4 / 2)
    fe_k = cal.fe["joint_stiffness_nm_per_rad"]
    assert (platform_tip_m(thin, 5, fe_k, 0.0, HELD_READING, flexible=True)
            > platform_tip_m(plat, 5, fe_k, 0.0, HELD_READING, flexible=True))
    assert platform_tip_m(plat, 5, fe_k, 0.0, HELD_READING, flexible=True) > platform_tip_m(plat, 5, fe_k, 0.0, HELD_READING)

    class _FE:
        plate_pitch_stiffness_nm_per_rad = cal.fe["plate_pitch_stiffness_nm_per_rad"]

    assert one_geometry(thin, _FE)["fe_over_record"] == pytest.approx(2 * one_geometry(plat, _FE)["fe_over_record"], rel=1e-3)
