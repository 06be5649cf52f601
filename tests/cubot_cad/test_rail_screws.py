"""The side rails are screwed to the body: ISO 10642 countersunk M3 screws (holes from the fastener
table) through each half into heat-set inserts in bosses inside the side walls; the heads are sunk
below the faces the other half slides on, so the docked pair and the slide-in path stay free."""

from __future__ import annotations

import numpy as np
import pytest


def _m(shape):
    from cubot_cad.checks.docking import to_manifold

    return to_manifold(shape)


def _union(shapes):
    from cubot_cad.checks.docking import union

    return union([_m(s) for s in shapes])


def test_rail_holes_come_from_the_fastener_table(robots):
    from collections import Counter

    from cubot_cad.hardware.fasteners import clearance_hole_mm, thread

    r = robots["cubot"]
    rs = r.rail_spec
    for p in r.placed:
        if p.role != "rail":
            continue
        radii = Counter(round(e.radius(), 4) for e in p.part.solid.Edges() if e.geomType() == "CIRCLE")
        assert radii[round(clearance_hole_mm("M3") / 2, 4)] >= 2, p.part.name  # one circle per hole at least
        assert radii[round((thread("M3").countersunk_head_diameter_mm + 0.4) / 2, 4)] >= 2, p.part.name
    assert rs.screw_hole_mm == clearance_hole_mm(rs.screw_size)


def test_screws_clear_their_own_robot_and_reach_the_inserts(robots):
    import cadquery as cq

    from cubot_cad.checks.docking import intersection_volume
    from cubot_cad.hardware.fasteners import thread
    from cubot_cad.shapes import tight_bbox

    r = robots["cubot"]
    screws = r.rail_screws()
    assert len(screws) == 4
    parts = _union([p.shape for p in r.placed])
    for s in screws:
        assert intersection_volume(_m(s.shape), parts) < 1e-3, s.label
    t = thread("M3")
    body, yc, W = r.body, r.y_centre_mm, r.body_width_mm
    for x, y, z, side in body.rail_screw_points():
        # the insert hole through the wall (into the boss) is open; the boss round it is solid
        inside = y - side * t.insert_hole_depth_mm / 2
        assert not body.solid.isInside(cq.Vector(x, inside, z))
        assert body.solid.isInside(cq.Vector(x, inside, z + body.rail_boss_mm / 2 - 0.4))
        assert body.solid.isInside(cq.Vector(x, y - side * (r.wall_mm + body.rail_boss_extent_mm - 0.2), z + 2.5))
    for s in screws:  # each screw's tip is at least half an insert length past the wall's outer face
        b = tight_bbox(s.shape)
        if "_male_" in s.label:
            assert yc + W / 2 - b[1] >= t.insert_length_mm / 2
        else:
            assert b[4] - (yc - W / 2) >= t.insert_length_mm / 2


def test_heads_are_recessed_below_the_sliding_faces(robots):
    from cubot_cad.shapes import tight_bbox

    r = robots["cubot"]
    rs, yc, W = r.rail_spec, r.y_centre_mm, r.body_width_mm
    male_face = yc + W / 2 + rs.plate_mm + rs.tongue_mm               # the tongue's tip face (left)
    female_floor = yc - W / 2 - (rs.female_mm - rs.groove_depth_mm)   # the groove floor (right)
    rails = {p.part.name: p.shape for p in r.placed if p.role == "rail"}
    assert tight_bbox(rails["rail_male_left"])[4] == pytest.approx(male_face, abs=1e-6)
    for s in r.rail_screws():
        b = tight_bbox(s.shape)
        if "_male_" in s.label:
            assert b[4] <= male_face - rs.screw_recess_mm + 1e-6, s.label
        else:
            assert b[1] >= female_floor + rs.screw_recess_mm - 1e-6, s.label


def test_docked_side_rail_pair_screws_do_not_touch_the_other_robot(pairs, robots):
    """Docked: B (on A's left) has its female rail on A's male. 0 interference with the screws counted
    (the pair's own measurement includes them), and each robot's screw heads keep at least the print
    clearance plus the recess to the other robot's rail."""
    from cubot_cad.checks.docking import intersection_volume

    p = pairs["cubot-side-rail"]
    assert p.ok and p.interference_mm3 < 1e-3
    r = robots["cubot"]
    rs = r.rail_spec
    off = np.asarray(p.offset_mm)
    a_rails = _union([q.shape for q in r.placed if q.role == "rail"])
    b_rails = a_rails.translate(tuple(off))
    screws = [_m(s.shape) for s in r.rail_screws()]
    for m in screws:
        assert intersection_volume(m, b_rails) < 1e-3
        assert intersection_volume(m.translate(tuple(off)), a_rails) < 1e-3
    import manifold3d as m3d

    gaps = [m3d.Manifold.min_gap(m, b_rails, 5.0) for m in screws] + \
           [m3d.Manifold.min_gap(m.translate(tuple(off)), a_rails, 5.0) for m in screws]
    # the nearest: A's male screws under B's groove floor, B's female screws over A's tongue tip
    assert min(gaps) >= rs.clearance_mm + rs.screw_recess_mm - 0.03, gaps  # meshes within 0.02 mm


def test_sliding_in_along_the_rail_never_touches_a_screw(pairs, robots):
    """B slides in from behind along +x (the only way a dovetail goes together): at every 1 mm of the
    path, B's rails and screws against A's rails and screws: no interference."""
    from cubot_cad.checks.docking import intersection_volume

    r = robots["cubot"]
    p = pairs["cubot-side-rail"]
    off = np.asarray(p.offset_mm)
    a = _union([q.shape for q in r.placed if q.role == "rail"] + [s.shape for s in r.rail_screws()])
    b = a.translate(tuple(off))
    a_screws = _union([s.shape for s in r.rail_screws()])
    b_screws = a_screws.translate(tuple(off))
    L = r.rail_spec.length_mm
    hits = []
    for dx in np.arange(-(L + 1.0), 0.5, 1.0):
        bb, bs = b.translate((dx, 0, 0)), b_screws.translate((dx, 0, 0))
        v = intersection_volume(a_screws, bb) + intersection_volume(a, bs)
        if v > 1e-3:
            hits.append((dx, v))
    assert not hits
    # and the check sees a screw that stands proud: lift A's male screws by the recess + 0.4 mm
    proud = a_screws.translate((0, r.rail_spec.screw_recess_mm + r.rail_spec.clearance_mm + 0.4, 0))
    assert max(intersection_volume(proud, b.translate((dx, 0, 0))) for dx in (-40.0, -28.0, 0.0)) > 1e-3


def test_bom_lists_the_rail_screws_and_inserts(robots):
    from cubot_cad.outputs.bom import bom_rows

    r = robots["cubot"]
    rows = [x for x in bom_rows(r, 1040.0) if x["category"] == "fastener"]
    male = [x for x in rows if "male rail (left)" in x["where"]]
    female = [x for x in rows if "female rail (right)" in x["where"]]
    assert any(x["item"] == "M3x12 ISO 10642" for x in male), male
    assert any(x["item"] == "M3x8 ISO 10642" for x in female), female
    inserts = next(x for x in rows if x["item"] == "M3 insert")
    assert inserts["quantity"] == 4 + 4  # the cover's four and the rails' four
    uses = [u for u in r.fasteners() if "rail" in u.where and u.kind == "ISO 10642"]
    assert sum(u.count for u in uses) == 4
    # the screws are as long as the insert allows: head top to wall + at least half the insert
    from cubot_cad.hardware.fasteners import thread

    for u in uses:
        grip = r.rail_spec.screw_grip_mm("(left)" in u.where)
        assert grip + thread("M3").insert_length_mm / 2 <= u.length_mm <= grip + thread("M3").insert_length_mm


@pytest.mark.parametrize("c", (0.1, 0.5))
def test_rail_screws_build_over_the_clearance_range(c):
    from cubot_cad.robots.registry import make_robot

    r = make_robot("cubot", c)
    for p in r.placed:
        if p.role == "rail":
            assert p.part.solid.isValid()
    assert r.body.solid.isValid()
