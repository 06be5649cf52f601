"""Flexible bodies (issue 12, deliverable 3): the robots bend with the CAD's section.

The record carries the printed shell's effective second moment of area
(``body_second_moment_m4``, cut from the CAD by ``cubot_cad.checks.section``); the table's model
lumps ``L / (E I)`` at the front-rear joints. These tests pin what that must do.
"""

from dataclasses import replace

import pytest

from cubot_cad.errors import InputError as CadInputError
from structure_fem.model.bodies import LEGACY_SOURCE, body_bending, with_body_bending
from structure_fem.model.connectors import ConnectorSet
from structure_fem.model.statics import Config, SolverOptions, solve
from structure_fem.model.structures import Structure

#: The CuBot shell's I_eff as the CAD cuts it (tests/cubot_cad/test_section.py measures 3.39e5 mm^4).
CUBOT_I_M4 = 3.39e-7


def _with_section(robot, i_m4=CUBOT_I_M4):
    return replace(robot, body_second_moment_m4=i_m4, body_second_moment_source="test: the CuBot shell's I_eff")


def test_the_record_section_is_used_and_the_legacy_box_says_it_is_legacy(make_robot):
    old = make_robot()
    assert body_bending(old).source == LEGACY_SOURCE
    new = _with_section(old)
    b = body_bending(new)
    assert b.second_moment_m4 == CUBOT_I_M4 and b.source.startswith("test:")
    assert b.flexural_rigidity_n_m2 == pytest.approx(2.2e9 * CUBOT_I_M4)
    # the thin-walled shell is much softer than the filled envelope box
    assert body_bending(old).second_moment_m4 > 3 * b.second_moment_m4


def test_body_compliance_is_in_series_with_the_front_rear_joint(make_robot):
    robot = _with_section(make_robot(k=500.0))
    conn = ConnectorSet.from_robot(robot)
    k = with_body_bending(conn, robot).front_rear.rotational_nm_per_rad
    expected = 1.0 / (1.0 / 500.0 + robot.length_m / (robot.youngs_modulus_pa * CUBOT_I_M4))
    assert k == pytest.approx(expected, rel=1e-12)
    # a stiffer section gives a stiffer joint
    k2 = with_body_bending(conn, _with_section(robot, 2 * CUBOT_I_M4)).front_rear.rotational_nm_per_rad
    assert k < k2 < 500.0


@pytest.mark.parametrize("bad", [0.0, -1e-7, float("nan")])
def test_a_record_with_a_bad_section_is_refused(make_robot, bad):
    with pytest.raises(CadInputError, match="body_second_moment_m4"):
        _with_section(make_robot(), bad)


def test_a_section_without_its_source_is_refused(make_robot):
    with pytest.raises(CadInputError, match="body_second_moment_source"):
        replace(make_robot(), body_second_moment_m4=CUBOT_I_M4)


@pytest.mark.parametrize("k", [200.0, 2.0e4, "cubot"])
def test_flexible_tends_to_rigid_as_the_modulus_grows(make_robot, k):
    """Same couplings, same geometry: the bodies' modulus x10^4 leaves only the couplings. Test
    robots (joints as springs, the lumped hinge: a 200 N m/rad joint with 1e9 N/m pins has no
    pin rows to speak of) and the packaged CuBot with the emergent hinge."""
    if k == "cubot":
        from cubot_cad.properties import default_properties

        robot = default_properties().get("cubot")
        conn = replace(ConnectorSet.from_robot(robot), hinge="emergent")
    else:
        robot = _with_section(make_robot(k=k, k_ax=1e9))
        conn = replace(ConnectorSet.from_robot(robot), hinge="lumped")
    cfg = Config(Structure("line"), 6, 5, 5, clamped=True)
    opts = SolverOptions(contact_n_per_m=1e9)
    rigid = solve(cfg, robot, conn, options=opts).tip_deflection_m
    flex = solve(cfg, robot, conn, flexible=True, options=opts).tip_deflection_m
    stiff = replace(robot, youngs_modulus_pa=robot.youngs_modulus_pa * 1e4)
    flex_stiff = solve(cfg, stiff, conn, flexible=True, options=opts).tip_deflection_m
    assert flex > rigid
    assert flex_stiff == pytest.approx(rigid, rel=1e-3)
    assert abs(flex_stiff - rigid) < abs(flex - rigid) / 100


@pytest.mark.parametrize("k, within", [(200.0, 0.05), (1000.0, 0.10)])
def test_lumped_bodies_against_exudyn_ancf_beams_at_cubot_like_joints(make_robot, k, within):
    """At couplings as stiff as the CuBot's (FE: about 1.1e3 N m/rad front-rear) the table's
    lumped bodies are within 10 % of robots as exudyn ANCF cable elements with the same E I
    (clamped line of 3 and 5, no play), and on the safe side."""
    from structure_fem.model.beams import flexible_line_tip

    robot = _with_section(make_robot(k=k, k_ax=1e9))
    conn = replace(ConnectorSet.from_robot(robot), hinge="lumped")  # joints as springs: the bodies are the subject
    opts = SolverOptions(contact_n_per_m=1e9)
    for n in (3, 5):
        cfg = Config(Structure("line"), n + 1, n, n, clamped=True)
        beam = flexible_line_tip(robot, k, n)
        lumped = solve(cfg, robot, conn, flexible=True, options=opts).tip_deflection_m
        rigid = solve(cfg, robot, conn, options=opts).tip_deflection_m
        assert rigid < beam <= lumped <= (1 + within) * beam


def test_lumped_bodies_overcount_the_body_share_as_the_closed_form_says(make_robot):
    """With joints 20x stiffer than the CuBot's the bodies dominate, and the lumping shows its
    one simplification: every joint, the edge one too, takes a whole robot's compliance
    ``L / E I`` (half a robot on each side) at the joint's moment. For a uniformly loaded
    cantilever of n robots the bodies' share of the tip is then ``w L^4 / (2 E I) sum m^3``
    against the beam's ``w (n L)^4 / (8 E I)``: a ratio ``(n + 1)^2 / n^2`` (n = 3: 1.78,
    n = 5: 1.44). The model's ratio (lumped - rigid) / (ANCF - rigid) matches it within 10 %."""
    from structure_fem.model.beams import flexible_line_tip

    k = 2.0e4
    robot = _with_section(make_robot(k=k, k_ax=1e9))
    conn = replace(ConnectorSet.from_robot(robot), hinge="lumped")  # joints as springs: the bodies are the subject
    opts = SolverOptions(contact_n_per_m=1e9)
    for n in (3, 5):
        cfg = Config(Structure("line"), n + 1, n, n, clamped=True)
        beam = flexible_line_tip(robot, k, n)
        lumped = solve(cfg, robot, conn, flexible=True, options=opts).tip_deflection_m
        rigid = solve(cfg, robot, conn, options=opts).tip_deflection_m
        share = (lumped - rigid) / (beam - rigid)
        assert share == pytest.approx((n + 1) ** 2 / n ** 2, rel=0.10), (n, share)
