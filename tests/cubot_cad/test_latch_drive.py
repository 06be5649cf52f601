"""The CuBot's latch servos are real rows of the servo table, mounted and coupled: each one's output
is coaxial with its latch blade's D-shaft, a coupler's length behind the latch stack; its tabs rest on
a frame that stands on the body's floor (tap holes under the tab holes, a window round the case with
the clearance), and the bill of materials names the servo, the coupler and the tab screws. Checked by
moving the servo against the body (manifold3d volumes, mm^3, as the other mechanism tests)."""

from __future__ import annotations

import pytest

FREE_MM3 = 1e-3


def _m(shape):
    from cubot_cad.checks.docking import to_manifold

    return to_manifold(shape)


def _iv(a, b) -> float:
    from cubot_cad.checks.docking import intersection_volume

    return intersection_volume(a, b)


@pytest.fixture(scope="module")
def cubot():
    from cubot_cad.robots.cubot import CuBot

    return CuBot()


@pytest.fixture(scope="module")
def body(cubot):
    return _m(cubot.body.build())


def _servos(cubot):
    return next(c for c in cubot.components() if c.key == "latch_servo")


def test_each_latch_servo_is_the_tables_row_on_its_blades_axis(cubot):
    from cubot_cad.couplings.latch_drive import COUPLER_GAP_MM, SHAFT_INTO_COUPLER_MM
    from cubot_cad.hardware.servos import servo

    comp = _servos(cubot)
    sv = servo("SG90")
    assert comp.servo_model == "SG90" and comp.unit_mass_g == sv.mass_g and comp.count == 2
    assert "TowerPro SG90" in comp.description
    fr = cubot.fr_spec
    stack_end = -cubot.length_mm / 2 + fr.latch_stack_mm
    want_face = stack_end + COUPLER_GAP_MM + SHAFT_INTO_COUPLER_MM + sv.spline_mm + 1.0
    axles = sorted(comp.axles_mm(), key=lambda a: a[1])
    assert [v for _x, y, z in axles for v in (y, z)] == pytest.approx(
        [v for y in cubot.block_ys_mm for v in (y, cubot.block_z_mm)])
    assert all(x == pytest.approx(want_face) for x, _y, _z in axles)
    # the stand-in solid: its case starts at the face and its tab holes sit over the frame's tap holes
    for solid, (x, _y, z) in zip(comp.solids(), comp.axles_mm(), strict=True):
        bb = solid.BoundingBox()
        assert bb.xmin == pytest.approx(x, abs=1e-6) and bb.xmax == pytest.approx(x + sv.case_height_mm, abs=1e-6)
        assert bb.zmin == pytest.approx(z - sv.tab_length_mm / 2 + sv.case_length_mm / 2 - sv.axle_from_end_mm, abs=1e-6)


def test_the_tabs_rest_on_the_frame_and_the_case_passes_its_window(cubot, body):
    """At rest the servo touches nothing; pushed 0.1 mm along +x its tabs run into the frame (it holds
    them); moved by the clearance less 0.02 mm sideways or up and down the case still clears its
    window, by the clearance + 0.1 mm it touches the frame."""
    c = cubot.clearance_mm
    for solid in _servos(cubot).solids():
        assert _iv(body, _m(solid)) <= FREE_MM3
        assert _iv(body, _m(solid.translate((0.1, 0, 0)))) > 0.1
        for d in ((0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)):
            near = solid.translate(tuple(v * (c - 0.02) for v in d))
            # the tabs overhang the window in z; only the case's sides are checked sideways
            if d[2] == 0:
                assert _iv(body, _m(near)) <= FREE_MM3, d
                assert _iv(body, _m(solid.translate(tuple(v * (c + 0.1) for v in d)))) > FREE_MM3, d


def test_the_tab_screws_find_tap_holes_and_the_coupler_has_room(cubot):
    from cubot_cad.hardware.fasteners import tap_hole_mm
    from cubot_cad.shapes import X, cyl

    spec = cubot.latch_spec
    body = cubot.body
    solid = body.build()
    depth = spec.tab_tap_depth_mm()
    tap = tap_hole_mm(spec.servo_row.screw_size) / 2
    for y, z in body.latch_blocks_yz_mm:
        x_frame = spec.frame_box_mm(body.latch_stack_end_mm, y, z, body.floor_mm)[0]
        for zt in spec.tab_hole_zs_mm(z):
            hole = cyl(tap - 0.05, depth - 0.1, (x_frame, y, zt), X)
            assert solid.intersect(hole).Volume() == pytest.approx(0.0, abs=1e-6)
            # and the frame is around it (the screw bites)
            ring = cyl(tap + 0.6, depth - 0.1, (x_frame, y, zt), X).cut(cyl(tap + 0.05, depth, (x_frame - 0.1, y, zt), X))
            assert solid.intersect(ring).Volume() == pytest.approx(ring.Volume(), rel=1e-3)
        # the coupler's cylinder (10 mm across) between the latch stack and the servo face is free of body
        x0 = body.latch_stack_end_mm
        x1 = spec.face_x_mm(x0)
        coupler = cyl(5.0, x1 - x0 - 0.02, (x0 + 0.01, y, z), X)
        assert solid.intersect(coupler).Volume() == pytest.approx(0.0, abs=1e-6)


def test_the_bom_names_the_servo_the_coupler_and_the_screws(cubot):
    from cubot_cad.outputs.bom import bom_rows

    rows = bom_rows(cubot, 1040.0)
    servo_row = next(r for r in rows if r["item"] == "latch_servo")
    assert "TowerPro SG90" in servo_row["description"] and servo_row["quantity"] == 2
    assert "20T spline" in servo_row["size"]
    coupler = next(r for r in rows if r["item"] == "latch_coupler")
    assert coupler["quantity"] == 2 and "D-bore" in coupler["description"]
    screws = [r for r in rows if r["category"] == "fastener" and "latch servos" in r["where"]]
    assert [(r["item"], r["quantity"]) for r in screws] == [("M2x6 ISO 4762", 4)]


def test_another_servo_row_moves_the_mass_and_an_unknown_one_is_refused():
    from cubot_cad.couplings.latch_drive import LatchDriveSpec
    from cubot_cad.errors import InputError
    from cubot_cad.robots.cubot import CuBot

    mg = CuBot(latch=LatchDriveSpec(servo="MG90S"))
    comp = next(c for c in mg.components() if c.key == "latch_servo")
    assert comp.unit_mass_g == 13.4 and "MG90S" in comp.description
    with pytest.raises(InputError, match="servo 'HS-55'"):
        LatchDriveSpec(servo="HS-55")
    with pytest.raises(InputError, match="frame_mm"):
        LatchDriveSpec(frame_mm=3.0)


def test_higher_blocks_hang_the_case_down_and_it_still_fits():
    """With the blocks 8 mm higher the case hangs down from the axle (it then clears the drive motors
    and the twist horn): its tab holes below/above swap, the tabs rest on the frame, and no stand-in
    overlaps a printed part or another stand-in."""
    from cubot_cad.robots.cubot import CuBot

    low, high = CuBot(), CuBot(block_z_mm=38.0)
    assert low.latch_spec.case_up and not high.latch_spec.case_up
    body = _m(high.body.build())
    comp = _servos(high)
    for solid, (_x, _y, z) in zip(comp.solids(), comp.axles_mm(), strict=True):
        bb = solid.BoundingBox()
        assert bb.zmax > z and bb.zmin < z - 10.0  # mostly below its axle
        assert _iv(body, _m(solid)) <= FREE_MM3
        assert _iv(body, _m(solid.translate((0.1, 0, 0)))) > 0.1
    others = [_m(p.shape) for p in high.placed if p.role != "body"] + \
        [_m(s) for c in high.components() if c.key != "latch_servo" for s in c.solids()]
    assert all(_iv(_m(s), o) <= FREE_MM3 for s in comp.solids() for o in others)
