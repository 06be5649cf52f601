"""The emergent hinge (issue 12, item 2): couplings whose faces touch are tension rows with their
play plus compression-only face contacts; the joint's pitch play is not an input."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from cubot_cad.errors import InputError
from cubot_cad.properties import default_properties
from structure_fem.model import hinge
from structure_fem.model.connectors import ConnectorSet, Joint


def _cubot():
    from structure_fem.couplings.connector_sources import resolve

    rec = next(r for r in default_properties().robots if r.name == "cubot")
    return resolve(rec)[0]


def _clearance(conn):
    """The same couplings with the thesis's clearance latch: 2 x 0.2 mm of tension play, no preload
    (the packaged CuBot has the wedge latch since issue 38)."""
    fr = conn.front_rear
    return replace(conn, front_rear=replace(fr, play_x=(0.0, 4e-4), backlash_rad=4e-4 / max(fr.levers_m), preload_n=0.0))


def test_the_cad_gives_every_pin_its_lever_about_the_hinge():
    fr = next(r for r in default_properties().robots if r.name == "cubot").connector("front_rear")
    assert sorted(fr.pin_levers_m) == pytest.approx([0.0265] * 4 + [0.037] * 2)
    # the record's pitch play is the tension play over the highest pin: the same CAD numbers
    assert fr.backlash_rad == pytest.approx(fr.play_of("tension").play_m / max(fr.pin_levers_m))


def test_two_pin_rows_have_the_joints_axial_and_rotational_stiffness_exactly():
    j = ConnectorSet.from_robot(_cubot()).front_rear
    rs = hinge.rows(j)
    assert [a for a, _ in rs] == pytest.approx([0.0265, 0.037])
    assert sum(k for _, k in rs) == pytest.approx(j.axial_n_per_m, rel=1e-12)
    assert sum(k * a * a for a, k in rs) == pytest.approx(j.rotational_nm_per_rad, rel=1e-12)
    assert all(k > 0 for _, k in rs)


def test_without_pin_levers_one_equivalent_row_keeps_both_stiffnesses():
    j = Joint("front_rear", 1000.0, 1.0e6)
    ((a, k),) = hinge.rows(j)
    assert k == pytest.approx(1.0e6) and k * a * a == pytest.approx(1000.0)
    # a fit that would need a negative row falls back to it as well
    j2 = Joint("front_rear", 5000.0, 1.0e6, levers_m=(0.02, 0.03))
    assert len(hinge.rows(j2)) == 1


def test_an_unknown_hinge_model_is_refused():
    j = Joint("front_rear", 1000.0, 1.0e6)
    with pytest.raises(InputError, match="hinge model 'bogus'"):
        ConnectorSet(j, hinge="bogus")


def test_one_sided_axes_bear_only_on_their_side():
    row = hinge._row(1.0e6, 4e-4, 3.6)
    assert abs(hinge.axis_force(row, 2e-4)) < 0.02 * 3.6  # inside the play: the weak spring + smoothing
    assert hinge.axis_force(row, 1e-3) == pytest.approx(1.0e6 * 6e-4, rel=0.01)
    assert hinge.axis_force(row, -1e-3) < 0  # the weak in-play spring only
    assert abs(hinge.axis_force(row, -1e-3)) < 0.05 * 3.6
    c = hinge._contact(1.0e8, 4e-4, 3.6)
    assert hinge.axis_force(c, -1e-4) == pytest.approx(-1.0e4, rel=0.01)
    assert abs(hinge.axis_force(c, 4e-4)) < 0.02 * 3.6  # a separated face: k e^2 / 4 u


exudyn = pytest.importorskip("exudyn")

from structure_fem.model.statics import Config, solve_uncached  # noqa: E402
from structure_fem.model.structures import Structure  # noqa: E402


def _line(conn, robot, w=2, **kw):
    return solve_uncached(Config(Structure("line"), 2 * w + 1, w, w), robot, conn, **kw)


def test_a_hogging_joint_turns_about_its_bottom_edge_by_the_play_over_the_top_pin():
    """With stiff pins the root joint's rotation is the tension play over the upper pins' lever
    (37 mm), which is not an input: the record's dead band is ignored by this model."""
    robot = _cubot()
    conn = replace(_clearance(ConnectorSet.from_robot(robot)).scaled(stiffness=20), hinge="emergent")
    r = _line(conn, robot)
    play = conn.front_rear.play_x[1]
    root = float(abs(r.joint_rotation_rad).max())
    assert root == pytest.approx(play / 0.037, rel=0.05)
    odd = replace(conn, front_rear=replace(conn.front_rear, backlash_rad=0.2))
    assert _line(odd, robot).tip_deflection_m == pytest.approx(r.tip_deflection_m, rel=1e-9)
    lumped = replace(odd, hinge="lumped")
    assert _line(lumped, robot).tip_deflection_m > 3 * r.tip_deflection_m  # that model uses it


def test_the_hinge_moves_with_the_cads_pins_and_play():
    robot = _cubot()
    conn = replace(_clearance(ConnectorSet.from_robot(robot)), hinge="emergent")
    base = _line(conn, robot, w=3).tip_deflection_m
    # the same pins 20 % higher: every lever and so the rotational stiffness (k a^2) grow
    fr = conn.front_rear
    higher = replace(conn, front_rear=replace(fr, levers_m=tuple(1.2 * a for a in fr.levers_m),
                                              rotational_nm_per_rad=1.44 * fr.rotational_nm_per_rad))
    assert _line(higher, robot, w=3).tip_deflection_m < 0.9 * base  # longer levers: less play rotation
    tight = conn.scaled(backlash=0.5)
    assert _line(tight, robot, w=3).tip_deflection_m < base
    no_play = conn.scaled(backlash=0.0)
    assert _line(no_play, robot, w=3).tip_deflection_m < 0.3 * base


def test_emergent_and_lumped_agree_where_they_should_and_the_emergent_joint_is_progressive():
    """The lumped dead band (tension play / highest pin) is where the emergent joint's first row
    bears; the emergent one then stiffens as the second row bears, so it turns at least as far."""
    robot = _cubot()
    conn = _clearance(ConnectorSet.from_robot(robot))
    em = _line(replace(conn, hinge="emergent"), robot, w=3, flexible=True).tip_deflection_m
    lu = _line(replace(conn, hinge="lumped"), robot, w=3, flexible=True).tip_deflection_m
    assert lu < em < 1.3 * lu


def test_a_layer_turns_on_the_one_below_only_by_lifting_its_key():
    """In an arch, with a stiff key, a layer's body turns relative to the body below by at most
    the key's pull-out play over its distance to the nearest wheel or caster contact it can pivot
    on (a contact right under the key, as the CuBot's wheels, only shifts the pivot to a caster)."""
    robot = _cubot()
    conn = replace(_clearance(ConnectorSet.from_robot(robot)).scaled(stiffness=20), hinge="emergent")
    st = Structure("arch", 4, 2)
    r = solve_uncached(Config(st, 7, 3, 3), robot, conn)
    lay = r.layout
    pull = conn.top_twist.play_z[1]
    nearest = min(abs(x) for x, _ in lay.ground.points if abs(x) > 1e-6)
    bound = pull / nearest
    turns = [abs(r.rotation_rad[c.b] - r.rotation_rad[c.a]) for c in lay.couplings if c.role == "top_twist"]
    assert turns and max(turns) <= 1.05 * bound
    lumped = solve_uncached(Config(st, 7, 3, 3), robot, replace(conn, hinge="lumped"))
    lturns = [abs(lumped.rotation_rad[c.b] - lumped.rotation_rad[c.a]) for c in lumped.layout.couplings
              if c.role == "top_twist"]
    assert max(lturns) > max(turns)  # the key's own dead band let the layers turn through each other


def test_a_side_rail_slides_along_the_lines_with_the_emergent_hinge():
    """The staggered two-line's rails carry no force along x: their axial stiffness does not
    change the tip (the lumped model used them as a tie)."""
    robot = _cubot()
    conn = replace(ConnectorSet.from_robot(robot), hinge="emergent")
    st = Structure("two_line", 2, 1, "staggered")
    cfg = Config(st, 7, 3, 3)
    base = solve_uncached(cfg, robot, conn).tip_deflection_m
    stiff = replace(conn, side_rail=replace(conn.side_rail, axial_n_per_m=conn.side_rail.axial_n_per_m * 10))
    assert solve_uncached(cfg, robot, stiff).tip_deflection_m == pytest.approx(base, rel=0.01)


def test_flexible_bodies_soften_the_rows_by_the_series_rule():
    from structure_fem.model.bodies import body_bending, with_body_bending

    robot = _cubot()
    conn = replace(ConnectorSet.from_robot(robot), hinge="emergent")
    flex = with_body_bending(conn, robot).front_rear
    k = 1 / (1 / conn.front_rear.rotational_nm_per_rad + body_bending(robot).compliance_rad_per_nm)
    assert sum(kk * a * a for a, kk in hinge.rows(flex)) == pytest.approx(k, rel=1e-9)
    assert math.isclose(flex.axial_n_per_m / conn.front_rear.axial_n_per_m, k / conn.front_rear.rotational_nm_per_rad)


# --- the wedge latch's preload (issue 38) ---------------------------------------------------


def test_a_preloaded_coupling_is_in_equilibrium_when_docked_and_its_rows_carry_the_preload():
    """At the docked position the pre-stretched rows pull with the preload and the two face edges
    push back with as much, with no net moment: the preload deforms nothing the tip sees."""
    robot = _cubot()
    j = ConnectorSet.from_robot(robot).front_rear
    assert j.preload_n > 0 and j.play_x == (0.0, 0.0)

    class _B:  # the layout the links read: two bodies on the ground, one robot tall
        z_m = 0.0

    class _Lay:
        bodies = (_B(), _B())
        height_m = robot.height_m

    class _C:
        role, a, b, count, point_m, joint = "front_rear", 0, 1, 1, (0.05, 0.03), j

    links = hinge.links(_C(), _Lay(), 3.6, 1e5)
    fx = [(lk, hinge.axis_force(lk.x, 0.0)) for lk in links]
    rows = [f for lk, f in fx if lk.feature.startswith("pin row")]
    faces = [f for lk, f in fx if lk.feature.startswith("faces")]
    assert sum(rows) == pytest.approx(j.preload_n, rel=1e-9)
    assert sum(faces) == pytest.approx(-j.preload_n, rel=1e-9)
    assert sum(f * lk.point_m[1] for lk, f in fx) == pytest.approx(0.0, abs=1e-9 * j.preload_n)


def test_the_wedge_latch_spans_what_the_clearance_latch_cannot_and_the_preload_moves_the_tip():
    robot = _cubot()
    conn = replace(ConnectorSet.from_robot(robot), hinge="emergent")
    wedge = _line(conn, robot, w=3).tip_deflection_m
    assert _line(_clearance(conn), robot, w=3).tip_deflection_m > 3 * wedge  # the play was the tip
    fr = conn.front_rear
    none = replace(conn, front_rear=replace(fr, preload_n=0.0))
    tight = replace(conn, front_rear=replace(fr, preload_n=20 * fr.preload_n))
    assert _line(tight, robot, w=3).tip_deflection_m < _line(none, robot, w=3).tip_deflection_m
