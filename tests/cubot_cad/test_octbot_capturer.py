"""OctBot capturer housing: it fastens to the body's front wall (screws from the fastener table into
heat-set inserts, on the same points as the wall's holes and the ring's), and it is one printable body
without closed cavities; its worm gearmotor slides into a pocket open at the side and its cam disc drops
into a slot open at the top (the drive's motion: ``test_octbot_drive.py``)."""

from __future__ import annotations

import pytest


def _vol(a, b) -> float:
    return a.intersect(b).Volume()


@pytest.mark.parametrize("c", (0.1, 0.2, 0.5))
def test_housing_screws_go_through_the_front_wall_into_inserts_in_the_housing(c):
    """Each front-wall hole has an open insert hole behind it in the housing's back face, with a full
    ring of material round it, and the ring plate's holes sit on the rear wall's at every clearance
    (one home for the points: before, the wall's were a literal 12 mm and the ring's moved with it)."""
    from cubot_cad.hardware.fasteners import clearance_hole_mm, thread
    from cubot_cad.robots.octbot import OctBot
    from cubot_cad.shapes import X, cyl

    r = OctBot(clearance_mm=c)
    rs, h = r.ring_spec, r.across_flats_mm / 2
    housing = next(p for p in r.placed if p.role == "housing")
    ring = next(p for p in r.placed if p.role == "ring")
    body = r.body.solid
    ins = thread(rs.screw_size)
    pts = housing.part.insert_points_mm()
    assert len(pts) == 2 and [y for y, _ in pts] == list(rs.mount_ys_mm)
    hole_r = clearance_hole_mm(rs.screw_size) / 2 - 0.05
    for y, z in pts:
        wall = cyl(hole_r, r.wall_mm, (h - r.wall_mm, y, z), X)
        assert _vol(body, wall) == pytest.approx(0.0, abs=1e-6), (y, z)  # the wall's hole is there
        d = ins.insert_hole_depth_mm
        hole = cyl(ins.insert_hole_mm / 2 - 0.05, d - 0.1, (h + 0.05, y, z), X)
        assert _vol(housing.shape, hole) == pytest.approx(0.0, abs=1e-6), (y, z)
        ring_ = cyl(ins.insert_hole_mm / 2 + MIN_RING_MM, d, (h, y, z), X).cut(
            cyl(ins.insert_hole_mm / 2 + 0.05, d, (h, y, z), X))
        assert _vol(housing.shape, ring_) == pytest.approx(ring_.Volume(), rel=1e-3), (y, z)
        # the ring's plate on the rear wall: its hole on the wall's
        back = cyl(hole_r, r.wall_mm + rs.plate_mm, (-h - rs.plate_mm, y, z), X)
        assert _vol(body, back) == pytest.approx(0.0, abs=1e-6) and _vol(ring.shape, back) == pytest.approx(0.0, abs=1e-6)
    # the BOM: two screws into two inserts, long enough to engage half the insert, not past it
    uses = [u for u in r.fasteners() if u.where.startswith("capturer housing")]
    screw = next(u for u in uses if u.kind == "ISO 4762")
    assert {u.kind for u in uses} == {"ISO 4762", "insert"} and all(u.count == 2 for u in uses)
    assert ins.insert_length_mm / 2 <= screw.length_mm - r.wall_mm <= ins.insert_hole_depth_mm


#: Material (mm) the housing keeps round each insert hole (two nozzle widths).
MIN_RING_MM = 0.8


def test_housing_screw_heads_clear_the_stand_ins_inside_the_body(robots):
    from cubot_cad.checks.docking import intersection_volume, to_manifold
    from cubot_cad.hardware.fasteners import thread
    from cubot_cad.shapes import cyl

    r = robots["octbot"]
    t = thread(r.ring_spec.screw_size)
    inner = r.across_flats_mm / 2 - r.wall_mm
    housing = next(p.part for p in r.placed if p.role == "housing")
    heads = [to_manifold(cyl(t.shcs_head_diameter_mm / 2, t.shcs_head_height_mm, (inner - 0.01, y, z), (-1.0, 0.0, 0.0)))
             for y, z in housing.insert_points_mm()]
    comps = [to_manifold(s) for c in r.components() for s in c.solids()]
    assert all(intersection_volume(hd, m) < 1e-3 for hd in heads for m in comps)


def test_the_housing_is_one_body_without_closed_cavities(robots):
    """One solid with one shell: a cavity closed all round would be a second (inner) shell."""
    housing = next(p.part for p in robots["octbot"].placed if p.role == "housing")
    assert len(housing.solid.Solids()) == 1 and len(housing.solid.Shells()) == 1
    assert housing.solid.isValid()


def _slide_free(fixed, moving, direction, distance, steps=12) -> list[float]:
    """Interference (mm^3) of ``moving`` with ``fixed`` at ``steps`` + 1 points along a straight path."""
    from cubot_cad.checks.docking import intersection_volume

    return [intersection_volume(fixed, moving.translate(tuple(distance * k / steps * d for d in direction)))
            for k in range(steps + 1)]


def test_the_worm_motor_slides_into_its_pocket_from_the_side_and_the_disc_drops_in_from_the_top(robots):
    """Assembly paths: the N20 worm gearmotor with its worm goes in along -y through the pocket's open
    side, the cam disc straight down into its slot, each without touching the housing; the motor is a
    named stand-in with its mass, in the pocket with the clearance all round."""
    from cubot_cad.checks.docking import manifold_of, to_manifold, union

    r = robots["octbot"]
    housing = next(p for p in r.placed if p.role == "housing")
    hm = manifold_of(housing)
    comps = {c.key: c for c in r.components()}
    motor, worm = comps["worm_motor"], comps["worm"]
    assert "N20" in motor.description and motor.unit_mass_g == 10.0 and motor.count == 1
    assert motor.size_mm == (12.0, 24.0, 10.0) and worm.kind == "cyl_y"
    drive = union([to_manifold(s) for s in motor.solids() + worm.solids()])
    y1 = housing.part.extent_mm[1]
    assert max(_slide_free(hm, drive, (0.0, 1.0, 0.0), y1 - housing.part.worm_y_mm[0] + 1.0)) < 1e-3
    disc = manifold_of(next(p for p in r.placed if p.role == "cam_disc"))
    top = housing.part.extent_mm[3]
    rise = top - (r.ring_spec.centre_z_mm - r.ring_spec.cam_radius_mm) + 1.0
    assert max(_slide_free(hm, disc, (0.0, 0.0, 1.0), rise)) < 1e-3
    # (the fingers go in from the front afterwards, pegs into the disc's slots)
    finger = manifold_of(next(p for p in r.placed if p.role == "finger"))
    assert max(_slide_free(hm, finger, (1.0, 0.0, 0.0), 15.0)) < 1e-3
    # and the pocket holds the motor: pushed 0.5 mm up, down, forward or back it meets the housing
    from cubot_cad.checks.docking import intersection_volume

    m = to_manifold(motor.solids()[0])
    for d in ((0, 0, 0.5), (0, 0, -0.5), (0.5, 0, 0), (-0.5, 0, 0)):
        assert intersection_volume(hm, m.translate(d)) > 0.1, d
