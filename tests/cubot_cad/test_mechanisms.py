"""Mechanisms checked in the CAD by moving their parts: 0 interference where a part must move
freely, > 0 where it must hold (volumes from OCC booleans, mm^3)."""

from __future__ import annotations

import math

import pytest


def _vol(a, b) -> float:
    return a.intersect(b).Volume()


# --- the cover fastens to bosses in the body -----------------------------------------------

def test_cover_screws_go_into_inserts_in_corner_bosses(robots):
    """Each cover screw hole lies over a boss: under it the body holds the insert hole and a full
    ring of material around it (it was 0 mm^3: the screws sat over the hollow)."""
    from cubot_cad.hardware.fasteners import thread
    from cubot_cad.shapes import Z, cyl

    r = robots["cubot"]
    body = r.body
    cover = next(p for p in r.placed if p.role == "cover")
    ins = thread(r.top_spec.screw_size)
    H = body.height_mm
    pts = body.cover_screw_points()
    assert len(pts) == 4
    cover_pts = [(x, r.y_centre_mm + y) for x, y in cover.part.screw_points()]
    for a, b in zip(sorted(pts), sorted(cover_pts), strict=True):
        assert a == pytest.approx(b, abs=1e-9)
    for x, y in pts:
        hole = cyl(ins.insert_hole_mm / 2 - 0.05, ins.insert_hole_depth_mm - 0.1,
                   (x, y, H - ins.insert_hole_depth_mm + 0.05), Z)
        assert _vol(body.solid, hole) == pytest.approx(0.0, abs=1e-6)  # the insert hole is open
        ring_r0, ring_r1, depth = ins.insert_hole_mm / 2 + 0.05, ins.insert_hole_mm / 2 + 1.5, ins.insert_hole_depth_mm
        ring = cyl(ring_r1, depth, (x, y, H - depth), Z).cut(cyl(ring_r0, depth, (x, y, H - depth), Z))
        assert _vol(body.solid, ring) == pytest.approx(ring.Volume(), rel=1e-3)  # material all round
        # and the cover's hole is right above it
        probe = cyl(r.top_spec.screw_hole_mm / 2 - 0.05, r.top_spec.cover_mm, (x, y, H), Z)
        assert _vol(cover.shape, probe) == pytest.approx(0.0, abs=1e-6)


def test_corner_bosses_print_without_support(robots):
    """The bosses hang from the walls: their undersides slope at 45 deg (no face looks straight down
    inside the hollow above the floor)."""
    body = robots["cubot"].body
    H, w, B = body.height_mm, body.wall_mm, body.boss_mm
    ax, ay = body.length_mm / 2 - w, body.width_mm / 2 - w

    def near_boss(v):
        return abs(abs(v.x) - ax) < B + 0.5 and abs(abs(v.y - body.y_centre_mm) - ay) < B + 0.5 \
            and v.z > H - body.boss_depth_mm - B - 1

    faces = [fc for fc in body.solid.Faces() if near_boss(fc.Center())]
    assert sum(1 for fc in faces if -0.75 < fc.normalAt().z < -0.65) >= 8  # the 45 deg undersides
    # nothing faces straight down (but the 0.05 mm tips of the pyramids)
    down = [fc for fc in faces if fc.geomType() == "PLANE" and fc.normalAt().z < -0.99 and fc.Area() > 0.05]
    assert down == [], [fc.Center() for fc in down]


# --- caster balls are retained ----------------------------------------------------------------

@pytest.mark.parametrize("robot", ["cubot", "octbot"])
def test_caster_ball_turns_freely_and_cannot_drop_out(robots, robot):
    from cubot_cad.couplings.connectors import CasterSeat
    from cubot_cad.shapes import sphere

    r = robots[robot]
    seat = next(p.part for p in r.placed if p.role == "caster_seat")
    R = seat.ball_diameter_mm / 2
    assert seat.undercut_mm >= CasterSeat.MIN_UNDERCUT_MM
    assert R - seat.mouth_radius_mm == pytest.approx(seat.undercut_mm)

    def ball(dz=0.0, dy=0.0):
        return sphere(R, (0.0, dy, seat.ball_centre_z_mm - dz))

    assert _vol(seat.solid, ball()) == pytest.approx(0.0, abs=1e-6)  # at rest: free all round
    assert _vol(seat.solid, ball(dy=seat.clearance_mm * 0.9)) == pytest.approx(0.0, abs=1e-6)
    # pulled down (out of the mouth): free by its play (the clearance and the sphere's geometry, under
    # 0.6 mm), then it bears on the undercut and cannot go further
    assert _vol(seat.solid, ball(dz=seat.clearance_mm)) == pytest.approx(0.0, abs=1e-6)
    held = _vol(seat.solid, ball(dz=1.0))
    assert held > 0.1, held
    assert _vol(seat.solid, ball(dz=R / 2)) > 0.1  # still caught half a radius further
    # and it still touches the ground with the wheels
    assert r.caster_exposed_mm == pytest.approx(seat.exposed_mm, abs=1e-6)


# --- the latch blade is driven and locks -------------------------------------------------------

def _latch_frame_pins(spec, pull_mm=0.0):
    """The docked neighbour's three pins in the latch set frame (it enters along -x), pulled back by
    ``pull_mm``."""
    import cadquery as cq

    from cubot_cad.couplings.connectors import GroovedPin

    pin = GroovedPin(spec=spec).solid.rotate(cq.Vector(0, 0, 0), cq.Vector(0, 0, 1), 180)
    return [pin.translate((pull_mm + spec.design_gap_mm, -y, z)) for y, z in spec.pin_positions()]


@pytest.mark.parametrize("robot", ["cubot", "cube-robot"])
def test_the_blade_turns_on_its_d_shaft_and_holds_the_pins_only_when_locked(robots, robot):
    import cadquery as cq

    from cubot_cad.couplings.connectors import LatchRearPlate, LatchSeparationPlate, TriangularBlade

    spec = robots[robot].fr_spec
    c = spec.clearance_mm
    x_blade = -spec.wall_mm - 2 * spec.plate_mm - c - spec.blade_mm
    shaft = spec.d_profile(x_blade - spec.rear_plate_mm - spec.pocket_depth_mm,
                           spec.rear_plate_mm + spec.separation_mm + 3, 0.0)
    open_blade = TriangularBlade(spec=spec).solid
    X = cq.Vector(1, 0, 0)
    o = cq.Vector(0, 0, 0)
    # the shaft drives the blade: free in its D bore within its play, then the flat bears on the bore
    play = spec.drive_play_deg
    assert 2.0 < play < 8.0, play
    assert _vol(open_blade, shaft) == pytest.approx(0.0, abs=1e-6)
    assert _vol(open_blade, shaft.rotate(o, X, 0.8 * play)) == pytest.approx(0.0, abs=1e-6)
    assert _vol(open_blade, shaft.rotate(o, X, play + 1.5)) > 0.01
    assert _vol(open_blade, shaft.rotate(o, X, -play - 1.5)) > 0.01
    # blade and shaft turn together through the whole travel inside the stack, touching nothing
    stack = [LatchSeparationPlate(spec=spec).solid, LatchRearPlate(spec=spec).solid]
    pins = _latch_frame_pins(spec, -spec.pin_draw_mm)  # a wedge latch draws them in as it turns
    for k in range(7):
        deg = spec.locked_turn_deg * k / 6
        b, sh = open_blade.rotate(o, X, deg), shaft.rotate(o, X, deg)
        for part in stack:
            assert _vol(part, b) == pytest.approx(0.0, abs=1e-6), deg
            assert _vol(part, sh) == pytest.approx(0.0, abs=1e-6), deg
        for p in pins:  # the docked pins sit in the grooves while the blade turns
            assert _vol(p, b) == pytest.approx(0.0, abs=1e-6), deg
    locked = TriangularBlade(spec=spec, locked=True).solid
    assert _vol(locked, shaft.rotate(o, X, spec.locked_turn_deg)) == pytest.approx(0.0, abs=1e-6)
    # pull the neighbour back by 0.5 mm: open, its pins come out freely; locked, the slots hold their shoulders
    pulled = _latch_frame_pins(spec, pull_mm=c + 0.3)
    assert sum(_vol(p, open_blade) for p in pulled) == pytest.approx(0.0, abs=1e-6)
    held = sum(_vol(p, locked) for p in pulled)
    assert held > (0.1 if spec.wedge is not None else 1.0), held  # a wedge holds by its cone
    assert math.isclose(spec.drive_flat_mm - spec.drive_shaft_mm / 2, 1.5)
