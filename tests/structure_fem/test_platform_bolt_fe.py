"""FE of the test platform's bolted lap joint (issue 12, deliverable 1: "the test platform's bolt"):
the FE follows its inputs, resolve() finds it by the hash of geometry + material + mesh, and the
calibration report puts it beside the values fitted to the thesis's 5 mm.

Kept fast: a coarse mesh (h 3 mm at the joint, 10 mm in the plates: ~3 s a solve) where a solve is
needed, the packaged result otherwise; the packaged cold solve and the mesh refinement are ``bench``."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

from cubot_cad.properties import RobotPropertiesFile, default_properties, default_properties_path  # noqa: E402
from cubot_cad.robots.platform import TestPlatform  # noqa: E402
from structure_fem.couplings import connector_sources as cs  # noqa: E402
from structure_fem.couplings import platform_bolt_fe as pb  # noqa: E402
from structure_fem.couplings.connector_fe import Material  # noqa: E402
from structure_fem.couplings.fe_solid import Load, box_mesh, solve_linear_elastic  # noqa: E402
from structure_fem.errors import InputError  # noqa: E402

ABS = Material.from_cubot_cad("abs")
COARSE = pb.PlatformMesh(3.0, 10.0)


@pytest.fixture(scope="module")
def platform():
    return default_properties().get("platform")


def test_a_thicker_plate_gives_a_stiffer_joint():
    base = pb.compute_platform_bolt(pb.PlatformBoltGeometry.from_platform(), ABS, COARSE, with_contact=False)
    thick = pb.compute_platform_bolt(pb.PlatformBoltGeometry.from_platform(TestPlatform(thickness_mm=6.0)), ABS,
                                     COARSE, with_contact=False)
    assert thick.rotational_stiffness_nm_per_rad > 1.3 * base.rotational_stiffness_nm_per_rad
    assert thick.pitch_stiffness_nm_per_rad > 1.3 * base.pitch_stiffness_nm_per_rad
    assert thick.shear_stiffness_n_per_m > base.shear_stiffness_n_per_m
    assert thick.input_hash != base.input_hash
    # the joint is softer than the plates it joins, and the pitch is the two in series
    assert base.pitch_stiffness_nm_per_rad < base.rotational_stiffness_nm_per_rad
    assert base.pitch_stiffness_nm_per_rad < base.plate_pitch_stiffness_nm_per_rad
    # it acts between the abutting faces (x = 50 mm) and the bolt (56 mm)
    assert 0.050 < base.hinge_x_m < 0.056
    # reciprocity of the measured flexibility (vertical force <-> couple)
    f = base.inputs["flexibility_lap"]
    assert f["C_VM"] == pytest.approx(f["C_MV"], rel=1e-6)
    assert base.provenance.startswith("fe: scikit-fem P2 tetra, gmsh h=3 mm at the joint / 10 mm in the plates")
    assert np.isnan(base.contact_pitch_stiffness_nm_per_rad)  # not asked for
    # the coarse mesh is within 10 % of the packaged (h 1.5 mm) result
    fe, _ = cs.fe_platform_bolt_for(default_properties().get("platform"))
    assert base.rotational_stiffness_nm_per_rad == pytest.approx(fe.rotational_stiffness_nm_per_rad, rel=0.10)


def test_the_play_is_the_cad_clearance_hole_and_the_key_follows_the_geometry():
    g = pb.PlatformBoltGeometry.from_platform()
    assert g.hole_mm == 3.4 and g.bolt_mm == 3.0  # ISO 273 medium, M3
    (play,) = g.play()
    assert play["play_m"] == pytest.approx(0.4e-3) and play["axis"] == "x" and play["sense"] == "both"
    keys = {pb.input_hash(pb.PlatformBoltGeometry.from_platform(p), ABS, pb.PlatformMesh())
            for p in (TestPlatform(), TestPlatform(thickness_mm=6.0), TestPlatform(clearance_mm=0.3))}
    assert len(keys) == 3
    assert pb.input_hash(g, ABS, pb.PlatformMesh()) != pb.input_hash(g, ABS, COARSE)
    with pytest.raises(InputError, match="bolt hole"):
        replace(g, hole_mm=2.5).check()


def test_resolve_uses_the_packaged_fe_of_the_bolt_by_its_hash(platform, tmp_path, monkeypatch):
    robot, notes = cs.resolve(platform, "fe", cache_dir=tmp_path)
    bolt = robot.connector("bolt")
    fe, where = cs.fe_platform_bolt_for(platform, cache_dir=tmp_path)
    assert where.startswith("packaged") and notes["bolt"].startswith("fe (result found in the packaged")
    assert bolt.provenance.startswith("fe: ") and fe.input_hash[:16] in bolt.provenance
    assert bolt.rotational_stiffness_nm_per_rad == fe.rotational_stiffness_nm_per_rad
    assert bolt.axial_stiffness_n_per_m == fe.axial_stiffness_n_per_m
    assert bolt.shear_stiffness_n_per_m == fe.shear_stiffness_n_per_m
    assert bolt.backlash_rad == 0.0 and [p.feature for p in bolt.play] == ["bolt_slip"]
    assert bolt.play_of("bolt_slip").play_m == pytest.approx(0.4e-3)
    assert fe.input_hash == pb.input_hash(pb.PlatformBoltGeometry.from_platform(), ABS, pb.PlatformMesh())
    # the record mode keeps the hand formula
    assert cs.resolve(platform, "properties")[0].connector("bolt") == platform.connector("bolt")
    # an edited record: no FE applies, the hand formula stays and the note says why
    edited = platform.with_connector(replace(platform.connector("bolt"), rotational_stiffness_nm_per_rad=9.0))
    robot, notes = cs.resolve(edited, "fe", cache_dir=tmp_path)
    assert robot.connector("bolt").provenance.startswith("hand formula") and "not the parametric" in notes["bolt"]
    # neither packaged nor cached: the hand formula, and how to compute the FE
    monkeypatch.setattr(cs, "packaged_fe", lambda: [])
    robot, notes = cs.resolve(platform, "fe", cache_dir=tmp_path)
    assert robot.connector("bolt") == platform.connector("bolt")
    assert "no FE result for this platform bolt" in notes["bolt"]


def test_the_calibration_report_carries_the_fe_beside_both_fits(tmp_path):
    from structure_fem.analysis.calibration import calibrate
    from structure_fem.outputs.docs_blocks import _calibration

    cal = calibrate(RobotPropertiesFile.load(default_properties_path()), None, family_points=1,
                    cache_dir=tmp_path).to_dict()
    fe = cal["fe"]
    assert fe["available"] and fe["provenance"].startswith("fe: ")
    fitted = {r["reading"]: r["bolt_stiffness_nm_per_rad"] for r in cal["readings"]}
    assert [r["reading"] for r in fe["readings"]] == ["held", "crossing"]
    for r in fe["readings"]:
        assert r["fitted_nm_per_rad"] == pytest.approx(fitted[r["reading"]], rel=1e-6)
        assert r["fe_over_fitted"] == pytest.approx(fe["pitch_stiffness_nm_per_rad"] / r["fitted_nm_per_rad"],
                                                    rel=1e-3)
        assert r["fe_contact_over_fitted"] == pytest.approx(
            fe["contact_pitch_stiffness_nm_per_rad"] / r["fitted_nm_per_rad"], rel=1e-3)
        lo, hi = r["fe_over_fitted"], r["fe_contact_over_fitted"]
        assert lo < hi  # the faces-free FE is the softer end of the bracket
        assert r["fe_is"] == ("stiffer" if lo >= 1 else "softer" if hi <= 1 else "bracketing")
        # a softer FE predicts more than the measured 5 mm, a stiffer one less
        assert (r["fe_tip5_mm"] > 5.0) == (lo < 1) and (r["fe_contact_tip5_mm"] > 5.0) == (hi < 1)
        assert r["fe_contact_tip5_mm"] < r["fe_tip5_mm"]
        assert f"{r['reading']} reading: fitted" in cal["fe_statement"]
    assert "only check of the connector FE against a measurement" in cal["fe_statement"]
    assert "FE / fitted" in _calibration()


def test_a_record_the_fe_does_not_model_says_why_in_the_calibration():
    from structure_fem.analysis.calibration import calibrate

    cal = calibrate(None, None, family_points=1).to_dict()  # the thesis platform's stated numbers
    assert cal["fe"]["available"] is False and "the CAD cannot rebuild the record's bolt" in cal["fe"]["why"]
    assert cal["fe_statement"].startswith("No FE of the platform bolt applies")


def test_per_element_moduli_in_the_solver():
    """One modulus per element (the steel bolt in ABS plates): a constant array is the scalar, twice
    the modulus halves the displacement, a wrong length is an input error."""
    m = box_mesh(20.0, 4.0, 4.0, 4.0)
    tip = lambda x: np.abs(x[0] - 0.02) < 1e-9  # noqa: E731
    root = lambda x: np.abs(x[0]) < 1e-9  # noqa: E731
    n = m.t.shape[1]
    u = [solve_linear_elastic(m, e, nu, root, Load(tip, (0.0, 0.0, 1.0))).mean_displacement(tip)[2]
         for e, nu in ((2e9, 0.35), (np.full(n, 2e9), np.full(n, 0.35)), (np.full(n, 4e9), 0.35))]
    assert u[1] == pytest.approx(u[0], rel=1e-10) and u[2] == pytest.approx(u[0] / 2, rel=1e-10)
    with pytest.raises(InputError, match="one per element"):
        solve_linear_elastic(m, np.full(n - 1, 2e9), 0.35, root, Load(tip, (0.0, 0.0, 1.0)))


@pytest.mark.bench
def test_packaged_cold_solve_and_mesh_refinement(tmp_path):
    """The packaged result recomputed cold (~50-100 s) and one step finer (h 1.25 mm at the joint,
    faces free: ~3 min): under 5 % apart."""
    fe = pb.platform_bolt_fe(cache_dir=tmp_path)
    pkg, _ = cs.fe_platform_bolt_for(default_properties().get("platform"))
    assert fe.input_hash == pkg.input_hash
    assert fe.rotational_stiffness_nm_per_rad == pytest.approx(pkg.rotational_stiffness_nm_per_rad, rel=1e-6)
    assert fe.contact_pitch_stiffness_nm_per_rad == pytest.approx(pkg.contact_pitch_stiffness_nm_per_rad, rel=1e-6)
    fine = pb.compute_platform_bolt(pb.PlatformBoltGeometry.from_platform(), ABS, pb.PlatformMesh(1.25, 5.0),
                                    with_contact=False)
    for f in ("rotational_stiffness_nm_per_rad", "pitch_stiffness_nm_per_rad", "axial_stiffness_n_per_m",
              "shear_stiffness_n_per_m"):
        assert getattr(fine, f) == pytest.approx(getattr(fe, f), rel=0.05), f
