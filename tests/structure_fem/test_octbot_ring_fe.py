"""FE of the OctBot's ring-and-capture coupling (issue 12, deliverable 1: the last coupling still a
hand formula): a finger's bar against closed forms, the FE following the CAD, resolve() finding the
packaged result by the hash of geometry + material + mesh, the play from the CAD's clearances.

Kept fast: a coarse mesh (h 1.2 mm in the fingers, 2 mm in the lip: ~7 s a coupling) where a solve is
needed, the packaged result otherwise; the packaged cold solve and the mesh refinement are ``bench``."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

from cubot_cad.properties import default_properties  # noqa: E402
from cubot_cad.robots.octbot import OctBot, RingSpec  # noqa: E402
from structure_fem.couplings import connector_sources as cs  # noqa: E402
from structure_fem.couplings import octbot_ring_fe as orf  # noqa: E402
from structure_fem.couplings.connector_fe import Material  # noqa: E402
from structure_fem.errors import InputError  # noqa: E402

ABS = Material.from_cubot_cad("abs")
COARSE = orf.RingMesh(1.2, 2.0, 3.0)


@pytest.fixture(scope="module")
def octbot():
    return default_properties().get("octbot")


@pytest.fixture(scope="module")
def coarse():
    return orf.compute_octbot_ring(orf.OctRingGeometry.from_octbot(), ABS, COARSE)


def test_a_finger_bar_is_an_axial_bar_and_a_timoshenko_cantilever():
    """The fingers' bar section (3 mm square, outer face rounded to the lip's bore less the clearance)
    by the coupling's own mesh and solver: pulled, ``E A / L``; pushed sideways at its end,
    ``L^3 / 3 E I + L / kappa G A`` (kappa 5/6, rectangle), each within 5 %, over the hand formula's
    13.5 mm finger. The FE's section area is the box less the two rounded corners (closed form)."""
    g = orf.OctRingGeometry.from_octbot()
    E, nu, L = ABS.E_pa, ABS.poisson, 13.5
    a, R = g.finger_mm / 2, g.bar_round_mm
    # area outside the disc of radius R of the box's outer strip [r - a, r + a]: int (r + a - sqrt(R^2 - y^2)) dy
    ys = np.linspace(-a, a, 20001)
    cut = np.clip(g.finger_radius_mm + a - np.sqrt(R ** 2 - ys ** 2), 0.0, None)
    area_mm2 = (2 * a) ** 2 - float(np.sum((cut[1:] + cut[:-1]) / 2 * np.diff(ys)))
    k_ax, A, inertia = orf.finger_bar_fe(g, L, E, nu, COARSE, "axial")
    assert A == pytest.approx(area_mm2 * 1e-6, rel=0.01)
    assert k_ax == pytest.approx(E * A / (L * 1e-3), rel=0.05)
    k_b, _A, _I = orf.finger_bar_fe(g, L, E, nu, COARSE, "bending")
    G, Lm = E / (2 * (1 + nu)), L * 1e-3
    assert k_b == pytest.approx(1.0 / (Lm ** 3 / (3 * E * inertia) + Lm / (5 / 6 * G * A)), rel=0.05)
    assert inertia < (2 * a) ** 4 / 12 * 1e-12  # the rounding takes a little off the square's
    with pytest.raises(InputError, match="load must be"):
        orf.finger_bar_fe(g, L, E, nu, COARSE, "twist")


def test_the_geometry_is_the_cad_and_its_play_the_cad_clearances():
    g = orf.OctRingGeometry.from_octbot()
    bot = OctBot()
    s = bot.ring_spec
    assert g.finger_angles_deg == s.FINGER_ANGLES_DEG and g.docked_gap_mm == bot.docked_gap_mm
    # docked: the lip's face on the retainer's front, the hooks one clearance behind the lip as drawn
    assert g.lip_face_x_mm == pytest.approx(bot.housing_mm)
    assert g.tip_x_mm - g.hook_mm - g.lip_inner_x_mm == pytest.approx(s.clearance_mm)
    assert g.retainer_x_mm[0] - g.shoulder_end_x_mm == pytest.approx(s.clearance_mm)
    assert g.lip_inner_x_mm + g.undercut_mm + g.plate_mm == pytest.approx(g.docked_gap_mm)
    assert g.hinge_z_mm == -s.outer_radius_mm
    (play,) = g.play()  # hook to lip and shoulders to retainer, in series
    assert play["feature"] == "tension" and play["axis"] == "x" and play["sense"] == "tension"
    assert play["play_m"] == pytest.approx(2 * s.clearance_mm * 1e-3)
    # another print clearance or finger is another geometry: another key; so is another mesh
    keys = {orf.input_hash(orf.OctRingGeometry.from_octbot(b), ABS, orf.RingMesh())
            for b in (OctBot(), OctBot(clearance_mm=0.3), OctBot(ring=RingSpec(finger_mm=3.5)))}
    assert len(keys) == 3
    assert orf.input_hash(g, ABS, orf.RingMesh()) != orf.input_hash(g, ABS, COARSE)
    with pytest.raises(InputError, match="hooks do not reach"):
        replace(g, hook_top_mm=12.0).check()
    with pytest.raises(InputError, match="retainer's slots"):
        replace(g, retainer_slot_half_mm=3.0).check()
    with pytest.raises(InputError, match=r"OctRingGeometry\.lip_mm must be > 0"):
        replace(g, lip_mm=-1.0).check()
    with pytest.raises(InputError, match=r"RingMesh\.finger_size_mm"):
        orf.build_finger_side_mesh(g, orf.RingMesh(0.0))


def test_the_coarse_fe_joint(coarse, octbot):
    """Reciprocity and the fingers' symmetry, the hinge and arms, the two sides in series, and the
    coarse mesh within 10 % of the packaged (default mesh) result."""
    g = orf.OctRingGeometry.from_octbot()
    for side in (coarse.finger_side, coarse.ring_side):
        C = np.array(side["flexibility_m_per_n"])
        assert side["asymmetry"] < 1e-6
        d = np.diag(C)
        assert np.ptp(d) < 0.05 * d.mean()  # three alike fingers (the retainer and plate are not round)
        assert np.all(np.abs(C - np.diag(d)) < 0.05 * d.mean())  # loading one finger hardly moves the others
    # the arms: the bearing patches (hook beyond the lip's bore) above the ring's bottom edge
    rad = [r * 1e3 for r in coarse.ring_side["patch_radius_m"]]
    assert all(g.lip_radius_mm < r < g.hook_top_mm for r in rad)
    arms = [a * 1e3 for a in coarse.lever_arms_m]
    for arm, r, ang in zip(arms, rad, g.finger_angles_deg, strict=True):
        assert arm == pytest.approx(g.outer_radius_mm + r * math.cos(math.radians(ang)), rel=1e-9)
    assert coarse.hinge_z_m == pytest.approx((g.centre_z_mm - g.outer_radius_mm) * 1e-3)
    # in series: softer than either side; pitch = a^T K a with K of the summed flexibility
    K = np.linalg.inv(np.array(coarse.finger_side["flexibility_m_per_n"]) + np.array(coarse.ring_side["flexibility_m_per_n"]))
    a = np.array(coarse.lever_arms_m)
    assert coarse.rotational_stiffness_nm_per_rad == pytest.approx(float(a @ K @ a), rel=1e-12)
    assert coarse.axial_stiffness_n_per_m == pytest.approx(float(K.sum()), rel=1e-12)
    assert coarse.axial_stiffness_n_per_m < min(coarse.finger_side["axial_n_per_m"], coarse.ring_side["axial_n_per_m"])
    assert coarse.backlash_rad == pytest.approx(2 * g.clearance_mm / max(arms))
    assert math.isnan(coarse.shear_stiffness_n_per_m)
    assert coarse.provenance.startswith("fe: scikit-fem P2 tetra, gmsh h=1.2 mm in the fingers / 2 mm in the lip")
    fe, _ = cs.fe_octbot_ring_for(octbot)
    assert coarse.rotational_stiffness_nm_per_rad == pytest.approx(fe.rotational_stiffness_nm_per_rad, rel=0.10)
    assert coarse.axial_stiffness_n_per_m == pytest.approx(fe.axial_stiffness_n_per_m, rel=0.10)


def test_a_thicker_finger_gives_a_stiffer_joint(coarse):
    thick = orf.compute_octbot_ring(orf.OctRingGeometry.from_octbot(OctBot(ring=RingSpec(finger_mm=3.5))), ABS, COARSE)
    assert thick.input_hash != coarse.input_hash
    assert thick.finger_side["per_finger_axial_n_per_m"] > 1.2 * coarse.finger_side["per_finger_axial_n_per_m"]
    assert thick.axial_stiffness_n_per_m > 1.2 * coarse.axial_stiffness_n_per_m
    assert thick.rotational_stiffness_nm_per_rad > 1.2 * coarse.rotational_stiffness_nm_per_rad


def test_resolve_uses_the_packaged_fe_of_the_ring_by_its_hash(octbot, tmp_path, monkeypatch):
    robot, notes = cs.resolve(octbot, "fe", cache_dir=tmp_path)
    ring = robot.connector("ring_capture")
    fe, where = cs.fe_octbot_ring_for(octbot, cache_dir=tmp_path)
    assert where.startswith("packaged") and notes["ring_capture"].startswith("fe (result found in the packaged")
    assert fe.input_hash == orf.input_hash(orf.OctRingGeometry.from_octbot(), ABS, orf.RingMesh())
    assert ring.provenance.startswith("fe: ") and fe.input_hash[:16] in ring.provenance
    assert ring.rotational_stiffness_nm_per_rad == fe.rotational_stiffness_nm_per_rad
    assert ring.axial_stiffness_n_per_m == fe.axial_stiffness_n_per_m
    rec = octbot.connector("ring_capture")
    assert ring.shear_stiffness_n_per_m == rec.shear_stiffness_n_per_m  # not modelled: the record's
    assert ring.gap_m == rec.gap_m and ring.height_m == rec.height_m
    # the play: the CAD's two clearances in series, and the dead band they give the top finger
    assert [p.feature for p in ring.play] == ["tension"]
    assert ring.play_of("tension").play_m == pytest.approx(2 * rec.play_of("tension").play_m)
    assert ring.backlash_rad == pytest.approx(ring.play_of("tension").play_m / fe.lever_arms_m[0])
    # the record mode keeps the hand formula
    assert cs.resolve(octbot, "properties")[0].connector("ring_capture") == rec
    # an edited record: no FE applies, the hand formula stays and the note says why
    edited = octbot.with_connector(replace(rec, rotational_stiffness_nm_per_rad=900.0))
    robot, notes = cs.resolve(edited, "fe", cache_dir=tmp_path)
    assert robot.connector("ring_capture").provenance.startswith("hand formula")
    assert "not the parametric OctBot" in notes["ring_capture"]
    # neither packaged nor cached: the hand formula, and how to compute the FE
    monkeypatch.setattr(cs, "packaged_fe", lambda: [])
    robot, notes = cs.resolve(octbot, "fe", cache_dir=tmp_path)
    assert robot.connector("ring_capture") == rec
    assert "no FE result for this OctBot ring" in notes["ring_capture"]


@pytest.mark.bench
def test_packaged_cold_solve_and_mesh_refinement(tmp_path, octbot):
    """The packaged result recomputed cold (~20 s) and one step finer (h 0.6 mm in the fingers, 0.8 mm
    in the lip: ~1-2 min): under 5 % apart."""
    fe = orf.octbot_ring_fe(cache_dir=tmp_path)
    pkg, _ = cs.fe_octbot_ring_for(octbot)
    assert fe.input_hash == pkg.input_hash and not fe.cache_hit
    assert fe.rotational_stiffness_nm_per_rad == pytest.approx(pkg.rotational_stiffness_nm_per_rad, rel=1e-6)
    assert fe.axial_stiffness_n_per_m == pytest.approx(pkg.axial_stiffness_n_per_m, rel=1e-6)
    fine = orf.compute_octbot_ring(orf.OctRingGeometry.from_octbot(), ABS, orf.RingMesh(0.6, 0.8, 3.0))
    for f in ("rotational_stiffness_nm_per_rad", "axial_stiffness_n_per_m", "per_finger_axial_n_per_m"):
        assert getattr(fine, f) == pytest.approx(getattr(fe, f), rel=0.05), f
        assert getattr(fine, f) < getattr(fe, f)  # refining softens (P2 converges from the stiff side)
