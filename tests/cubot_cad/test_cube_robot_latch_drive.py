"""The Cube Robot's four latch blades each have a servo of the servo table, mounted on a frame of the
connector cuboid and coupled to the blade: coaxial where the servo fits on the blade's axis, and
through a 1:1 pair of stock spur gears for the one left-face block whose coaxial servo would meet the
rear face's servo in the rear-left corner. Checked by moving the stand-ins against the cuboid and each
other (manifold3d volumes, mm^3, as the other mechanism tests)."""

from __future__ import annotations

import math

import pytest

from cubot_cad.checks.docking import intersection_volume as _iv
from cubot_cad.checks.docking import to_manifold as _m

#: A stand-in "touches nothing" below this intersection volume (mm^3).
FREE_MM3 = 1e-3


@pytest.fixture(scope="module")
def robot():
    from cubot_cad.robots.cube_robot import CubeRobot

    return CubeRobot()


@pytest.fixture(scope="module")
def cuboid(robot):
    return _m(robot.cuboid.build())


def _comps(robot) -> dict:
    return {c.key: c for c in robot.components()}


# the latch blades' axes (robot frame): rear face x = -S (y = +-offset), left face y = +S (x = +-offset)
def _blade_axes(robot):
    o, z = robot.block_offset_mm, robot.block_z_mm
    return {"latch_servo": [(y, z) for y in (o, -o)], "latch_servo_left": [(x, z) for x in (o, -o)]}


def test_four_table_servos_three_on_their_blades_axes_one_geared_beside_it(robot):
    from cubot_cad.couplings.latch_drive import COUPLER_GAP_MM
    from cubot_cad.hardware.servos import servo

    sv = servo("SG90")
    comps = _comps(robot)
    spec = robot.latch_spec
    S, end = robot.size_mm / 2, robot.fr_spec.latch_stack_mm
    coax_face = S - end - COUPLER_GAP_MM - spec.coupler_mm  # distance of a coaxial output face from the middle
    geared_face = S - end - spec.proud_mm - COUPLER_GAP_MM - spec.gears[1].face_mm - spec.horn_stack_mm
    assert spec.proud_mm == pytest.approx(robot.latch_screw_proud_mm) and spec.proud_mm > 2.4  # past the nuts
    assert coax_face == pytest.approx(S - end - 0.3 - 10.08) and geared_face < coax_face + 2
    rear, left = comps["latch_servo"], comps["latch_servo_left"]
    for c in (rear, left):
        assert c.servo_model == "SG90" and c.unit_mass_g == sv.mass_g and c.count == 2
        assert "TowerPro SG90" in c.description
    # rear face: outputs point -x, on the blades' axes
    assert [v for _x, y, z in sorted(rear.axles_mm(), key=lambda a: a[1]) for v in (y, z)] == pytest.approx(
        [v for yz in sorted(_blade_axes(robot)["latch_servo"]) for v in yz])
    assert all(x == pytest.approx(-coax_face) for x, _y, _z in rear.axles_mm())
    # left face: the block nearest the rear face (x < 0) is geared, its servo one centre distance towards
    # the face's middle; the other is coaxial
    axles = sorted(left.axles_mm())
    o = robot.block_offset_mm
    assert list(axles[0]) == pytest.approx([-o + spec.gear_offset_mm, geared_face, robot.block_z_mm])
    assert list(axles[1]) == pytest.approx([o, coax_face, robot.block_z_mm])
    assert robot.geared_latches == 1


def test_coaxial_the_corner_pair_would_meet(robot):
    """Why the gears: the left-face servo of the rear-left corner's block, put on its blade's axis, runs
    into the rear face's servo there (both cases hold the point where the two blades' axes cross)."""
    spec = robot.latch_spec
    x_end = robot.cuboid_stack_end_mm
    o, z = robot.block_offset_mm, robot.block_z_mm
    coax = spec.component(x_end, ((-o, z),), "coaxial", -90.0).solids()[0]
    rear = next(s for s, (_x, y, _z) in zip(_comps(robot)["latch_servo"].solids(),
                                             _comps(robot)["latch_servo"].axles_mm(), strict=True) if y > 0)
    assert _iv(_m(coax), _m(rear)) > 100.0


def test_the_gear_pair_meshes_on_the_blade_and_the_servo_axes(robot):
    """Both gears of one module in one plane 0.3 mm past the latch block's screw ends, the hubbed one on
    the blade's axis and the plain one on the geared servo's output axis, their pitch circles touching:
    the two stand-ins touch nothing and overlap once moved 0.1 mm towards each other; the servo's horn
    fits between its gear and its face; the gears' tip circles clear every nut and screw end of the
    latch blocks."""
    from cubot_cad.couplings.latch_drive import COUPLER_GAP_MM
    from cubot_cad.hardware.gears import mesh_centre_distance_mm

    comps = _comps(robot)
    bg, sg = comps["latch_gear_blade"], comps["latch_gear_servo"]
    spec = robot.latch_spec
    g_b, g_s = spec.gears
    assert g_b.module_mm == g_s.module_mm and g_b.teeth == g_s.teeth  # 1:1
    (xb, yb, zb), = bg.positions_mm
    (xs, ys, zs), = sg.positions_mm
    servo_axle = min(comps["latch_servo_left"].axles_mm())
    S = robot.size_mm / 2
    assert [xb, zb] == pytest.approx([-robot.block_offset_mm, robot.block_z_mm])
    assert [xs, zs] == pytest.approx([servo_axle[0], servo_axle[2]])
    assert yb == pytest.approx(ys) == pytest.approx(
        S - robot.fr_spec.latch_stack_mm - spec.proud_mm - COUPLER_GAP_MM - g_b.face_mm / 2)
    assert math.dist((xb, zb), (xs, zs)) == pytest.approx(mesh_centre_distance_mm(g_b, g_s))
    # the servo's face is the gear's far face + the horn's stack
    assert servo_axle[1] == pytest.approx(ys - g_s.face_mm / 2 - spec.horn_stack_mm)
    a, b = _m(bg.solids()[0]), bg.solids()[0]
    s = sg.solids()[0]
    assert _iv(a, _m(s)) <= FREE_MM3
    assert _iv(_m(b.translate((0.1, 0, 0))), _m(s)) > 0.1
    assert _iv(_m(b), _m(s.translate((-0.1, 0, 0)))) > 0.1
    # the teeth (tip circles) against the latch blocks' nuts and screw ends
    from cubot_cad.shapes import cyl

    hw = [_m(h.shape) for h in robot.hardware()]
    assert len(hw) == 32
    for x in (xb, xs):
        tip = _m(cyl(g_b.tip_diameter_mm / 2, g_b.face_mm, (x, yb + g_b.face_mm / 2, zb), (0.0, -1.0, 0.0)))
        assert all(_iv(tip, h) <= FREE_MM3 for h in hw)


def test_the_tabs_rest_on_their_frames_and_the_cases_pass_their_windows(robot, cuboid):
    """At rest each servo touches nothing; pushed 0.1 mm away from its output (+x on the rear face, -y on
    the left) its tabs run into the frame; moved sideways by the clearance less 0.02 mm the case clears
    its window, by the clearance + 0.1 mm it touches the frame."""
    c = robot.clearance_mm
    comps = _comps(robot)
    for key, back, side in (("latch_servo", (1, 0, 0), (0, 1, 0)), ("latch_servo_left", (0, -1, 0), (1, 0, 0))):
        for solid in comps[key].solids():
            assert _iv(cuboid, _m(solid)) <= FREE_MM3, key
            assert _iv(cuboid, _m(solid.translate(tuple(0.1 * v for v in back)))) > 0.1, key
            for sgn in (1, -1):
                d = tuple(sgn * v for v in side)
                assert _iv(cuboid, _m(solid.translate(tuple(v * (c - 0.02) for v in d)))) <= FREE_MM3, (key, d)
                assert _iv(cuboid, _m(solid.translate(tuple(v * (c + 0.1) for v in d)))) > FREE_MM3, (key, d)


def test_the_frames_tap_holes_are_under_the_tab_holes(robot):
    """Each servo's two tab holes line up with two empty tap holes in its frame, with frame round them."""
    from cubot_cad.hardware.fasteners import tap_hole_mm
    from cubot_cad.shapes import X, Z, cyl, rotated, yaw_point

    spec, cub = robot.latch_spec, robot.cuboid
    solid = cub.build()
    depth = spec.tab_tap_depth_mm()
    tap = tap_hole_mm(spec.servo_row.screw_size) / 2
    floor = cub.z0_mm + cub.floor_mm
    n = 0
    for yaw, places in robot.latch_places:
        for place in places:
            y, z, geared = spec.place(place)
            x_frame = spec.frame_box_mm(cub.latch_stack_end_mm, y, z, floor, geared)[0]
            for zt in spec.tab_hole_zs_mm(z):
                hole = rotated(cyl(tap - 0.05, depth - 0.1, (x_frame, y, zt), X), Z, yaw)
                ring = rotated(cyl(tap + 0.6, depth - 0.1, (x_frame, y, zt), X).cut(
                    cyl(tap + 0.05, depth, (x_frame - 0.1, y, zt), X)), Z, yaw)
                assert solid.intersect(hole).Volume() == pytest.approx(0.0, abs=1e-6)
                assert solid.intersect(ring).Volume() == pytest.approx(ring.Volume(), rel=1e-3)
                n += 1
            assert yaw_point((x_frame, y, z), yaw)[2] == z
    assert n == 8


def test_the_bom_names_servos_gears_couplers_shafts_and_screws(robot):
    from cubot_cad.outputs.bom import bom_rows

    rows = {r["item"]: r for r in bom_rows(robot, 1040.0)}
    assert rows["latch_servo"]["quantity"] == 2 and rows["latch_servo_left"]["quantity"] == 2
    assert "TowerPro SG90" in rows["latch_servo_left"]["description"]
    assert rows["latch_coupler"]["quantity"] == 3 and rows["latch_shaft"]["quantity"] == 3
    assert rows["latch_shaft_geared"]["quantity"] == 1
    for key in ("latch_gear_blade", "latch_gear_servo"):
        assert rows[key]["quantity"] == 1 and "module 0.5, 48 teeth" in rows[key]["description"]
        assert 1.0 < rows[key]["unit_mass_g"] < 5.0
    screws = [(r["item"], r["quantity"]) for r in rows.values() if r["category"] == "fastener"
              and ("latch servos' tabs" in r["where"] or "gears onto" in r["where"])]
    assert screws == [("M2x6 ISO 4762", 10)]


def test_the_servos_and_gears_are_in_the_mass(robot):
    from cubot_cad.hardware.gears import gear

    comps = _comps(robot)
    keys = ("latch_servo", "latch_servo_left", "latch_gear_blade", "latch_gear_servo")
    assert sum(comps[k].unit_mass_g * comps[k].count for k in keys) == pytest.approx(
        4 * 9.0 + gear("M0.5 z48 hub").mass_g + gear("M0.5 z48").mass_g)
    items = {round(m * 1e3, 6) for c in (comps[k] for k in keys) for m, _p, _i in c.mass_items()}
    assert {9.0, round(gear("M0.5 z48").mass_g, 6)} <= items


@pytest.mark.parametrize("offset, teeth", [(20.0, 44), (23.0, 52)])
def test_other_block_offsets_take_the_stock_pair_that_fits(offset, teeth):
    """Blocks nearer or farther from the face centres: the robot takes the smallest stock gear pair with
    which the geared servo has room, and nothing of the latch drive overlaps anything (stand-ins, the
    cuboid)."""
    import itertools

    from cubot_cad.robots.cube_robot import CubeRobot

    r = CubeRobot(block_offset_mm=offset)
    assert r.latch_spec.gears[0].teeth == teeth
    (_y, _z, sy), = [p for p in r.latch_places[1][1] if len(p) > 2]
    assert abs(sy + offset) == pytest.approx(teeth * 0.5)
    latch = [_m(s) for c in r.latch_components() for s in c.solids()]
    rest = [_m(s) for c in r.components() if not c.key.startswith("latch") for s in c.solids()]
    rest += [_m(h.shape) for h in r.hardware()]
    body = _m(r.cuboid.build())
    assert all(_iv(a, b) <= FREE_MM3 for a, b in itertools.combinations(latch, 2))
    assert all(_iv(a, b) <= FREE_MM3 for a in latch for b in rest + [body])


def test_layouts_with_no_room_are_refused_naming_the_offset_and_the_servo():
    """Blocks 18 mm off the face centres: the geared servo would meet the other left-face servo's frame;
    the taller MG90S at 22 mm: the rear servo's case reaches the geared servo's frame."""
    from cubot_cad.couplings.latch_drive import LatchDriveSpec
    from cubot_cad.errors import InputError
    from cubot_cad.robots.cube_robot import CubeRobot

    with pytest.raises(InputError, match="block_offset_mm 18: the SG90 latch servos .* 20/22/24/26 mm"):
        CubeRobot(block_offset_mm=18.0)
    with pytest.raises(InputError, match="block_offset_mm 22: the MG90S latch servos"):
        CubeRobot(latch=LatchDriveSpec(servo="MG90S"))
