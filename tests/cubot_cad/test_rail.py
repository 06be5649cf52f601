"""The side rail's dovetail: the female groove is the tongue offset by the clearance (a uniform
gap along each flank, mouth to tip), and the female half prints groove up."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cubot_cad.part import MAX_CLEARANCE_MM, MIN_CLEARANCE_MM


def _docked_rails(c):
    """Male and female halves of one rail, docked (rail frame of the male)."""
    from cubot_cad.couplings.connectors import RailFemale, RailMale, RailSpec
    from cubot_cad.shapes import location

    s = RailSpec(clearance_mm=c)
    male = RailMale(spec=s).solid
    # the female turned 180 deg about z (as CuBot mounts it), its mouth face on the male's plate face
    female = RailFemale(spec=s).solid.moved(location((0, s.plate_mm + s.female_mm, 0), 180))
    return s, male, female


def _on_tongue_flank(s, male, depth, side=1.0):
    """A point on the male tongue's flank ``depth`` mm out from its root, checked on the solid."""
    import cadquery as cq

    slope = (s.tongue_tip_mm - s.tongue_root_mm) / 2 / s.tongue_mm
    y, z = s.plate_mm + depth, side * (s.tongue_root_mm / 2 + depth * slope)
    n = np.array([0.0, -slope, side]) / math.hypot(slope, 1.0)  # outward normal of that flank
    on = cq.Vertex.makeVertex(0.0, y, z)
    off = cq.Vertex.makeVertex(0.0, y + 0.05 * n[1], z + 0.05 * n[2])
    assert male.distance(on) < 1e-6 and male.distance(off) == pytest.approx(0.05, abs=1e-6), \
        "the probe is not on the tongue's flank"
    return on


@pytest.mark.parametrize("c", (MIN_CLEARANCE_MM, 0.2, MAX_CLEARANCE_MM))
def test_groove_flanks_are_parallel_to_the_tongue_flanks_at_the_clearance(c):
    """Measured on the docked solids: the gap from the tongue's flank to the groove is the clearance
    at the mouth and at the tip, on both flanks (it was 0.66 mm at the mouth and 0.15 mm at the tip:
    the groove's flanks were 20.4 deg against the tongue's 26.6 deg); the tip is the clearance off
    the groove floor; nothing overlaps."""
    import cadquery as cq

    s, male, female = _docked_rails(c)
    for side in (1.0, -1.0):
        mouth = female.distance(_on_tongue_flank(s, male, 0.25, side))
        middle = female.distance(_on_tongue_flank(s, male, s.tongue_mm / 2, side))
        tip = female.distance(_on_tongue_flank(s, male, s.tongue_mm - 0.25, side))
        assert (mouth, middle, tip) == pytest.approx((c, c, c), abs=1e-4), (side, mouth, middle, tip)
    tip_face = cq.Vertex.makeVertex(0.0, s.plate_mm + s.tongue_mm, 0.0)
    assert male.distance(tip_face) < 1e-6
    assert female.distance(tip_face) == pytest.approx(c, abs=1e-4)
    assert male.intersect(female).Volume() == pytest.approx(0.0, abs=1e-9)


def test_the_docked_pair_slides_apart_only_by_the_flank_play(pairs):
    """A uniform flank gap c lets the rails be pulled apart by c / sin(flank angle) before both
    flanks catch together (0.447 mm at 0.2 mm)."""
    from cubot_cad.couplings.connectors import RailSpec

    s = RailSpec()
    slope = (s.tongue_tip_mm - s.tongue_root_mm) / 2 / s.tongue_mm
    expected = s.clearance_mm * math.hypot(1.0, slope) / slope
    assert pairs["cubot-side-rail"].play_mm == pytest.approx(expected, abs=0.01)


def _manifold(path):
    import manifold3d as m3d
    import trimesh

    mesh = trimesh.load(path, force="mesh")
    return m3d.Manifold(m3d.Mesh(vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
                                 tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))


def test_the_exported_female_rail_prints_groove_up(export_dir):
    """The shipped STL: the back face lies on the bed, solid across the whole rail (no 12.6 x 80 mm
    bridge under the groove), and the groove opens at the top: sections above the groove floor are
    two lips with the groove between them, sections below it one plate."""
    from cubot_cad.couplings.connectors import RailSpec

    s = RailSpec()
    m = _manifold(export_dir / "cubot" / "rail_female_right.stl")
    x0, y0, z0, x1, y1, z1 = m.bounding_box()
    assert z0 == pytest.approx(0.0, abs=1e-4) and z1 == pytest.approx(s.female_mm, abs=1e-4)
    assert sorted((x1 - x0, y1 - y0)) == pytest.approx(sorted((s.length_mm, s.height_mm)), abs=1e-3)
    holes = 2 * math.pi * (s.ir_hole_mm / 2) ** 2
    floor = s.plate_mm - s.clearance_mm  # groove floor height above the bed
    # the sections away from the ends' lead-ins (the groove flares over flare_length_mm at each end)
    import manifold3d as m3d

    trim = max(s.flare_length_mm, s.end_chamfer_mm) + 0.5
    long_x = (x1 - x0) > (y1 - y0)
    lo = [x0 + trim, y0 - 1, -1] if long_x else [x0 - 1, y0 + trim, -1]
    hi = [x1 - trim, y1 + 1, z1 + 1] if long_x else [x1 + 1, y1 - trim, z1 + 1]
    m = m ^ m3d.Manifold.cube(tuple(h - low for h, low in zip(hi, lo, strict=True))).translate(tuple(lo))
    length = s.length_mm - 2 * trim

    def screws(z):  # the two rail screws' holes through the floor: clearance hole, countersink, recess
        d = floor - z  # below the groove floor
        r = s.screw_hole_mm / 2
        R = s.screw_countersink_mm / 2
        rr = R if d <= s.screw_recess_mm else max(r, R - (d - s.screw_recess_mm))
        return len(s.screw_xs_mm()) * math.pi * rr ** 2

    for z in (0.05, floor - 0.05):
        cs = m.slice(z)
        assert len(cs.decompose()) == 1, z
        assert cs.area() == pytest.approx(length * s.height_mm - holes - screws(z), rel=2e-3), z
    for depth in (0.05, s.tongue_mm / 2, s.groove_depth_mm - 0.05):  # below the top face
        z = s.female_mm - depth
        cs = m.slice(z)
        lips = cs.decompose()
        assert len(lips) == 2, z
        width = 2 * s.groove_half_width_mm(depth)  # the groove between the lips at that height
        assert cs.area() == pytest.approx(length * (s.height_mm - width) - holes, rel=2e-3), z
    # the groove widens downwards (a dovetail): narrowest at the top
    assert s.groove_half_width_mm(0) < s.groove_half_width_mm(s.groove_depth_mm)


def test_ir_holes_keep_a_wall_to_the_groove_across_the_range():
    """The groove widens with the clearance; the IR holes stay at the thesis position while it
    leaves two nozzle widths, and move out (not into the groove) beyond that."""
    from cubot_cad.couplings.connectors import RailSpec
    from cubot_cad.part import MIN_WALL_MM

    thesis_z = None
    for c in (MIN_CLEARANCE_MM, 0.2, 0.3, 0.4, MAX_CLEARANCE_MM):
        s = RailSpec(clearance_mm=c)
        (_, z), _ = s.ir_points()
        r = s.ir_hole_mm / 2
        wall_to_groove = -z - r - s.groove_half_width_mm(s.groove_depth_mm)
        wall_to_edge = s.height_mm / 2 - (-z + r)
        assert wall_to_groove >= MIN_WALL_MM - 1e-6 and wall_to_edge >= MIN_WALL_MM - 1e-6, c
        if c == 0.2:
            thesis_z = z
    assert thesis_z == pytest.approx(-(24.0 / 2 - 1.5 - 1.8))
