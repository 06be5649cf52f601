"""Print orientation: grooved pins lie down on a flat (layers along the pin), the pin-locking plate has
its larger face on the bed, every part as exported has z-min 0."""

from __future__ import annotations

import numpy as np
import pytest


def _planar_faces_at(shape, z, tol=1e-6):
    from cubot_cad.shapes import tight_bbox

    return [f for f in shape.Faces() if f.geomType() == "PLANE"
            and abs(tight_bbox(f)[2] - z) < tol and abs(tight_bbox(f)[5] - z) < tol]


def _pins(robots):
    from cubot_cad.couplings.connectors import GroovedPin

    return [(name, part) for name, r in robots.items() for part, _ in r.printable_parts() if isinstance(part, GroovedPin)]


def test_every_grooved_pin_prints_lying_down_on_its_flat(robots):
    from OCP.BRepAdaptor import BRepAdaptor_Surface

    from cubot_cad.mesh import mesh_of
    from cubot_cad.shapes import tight_bbox

    pins = _pins(robots)
    assert {n for n, _ in pins} == {"cubot", "cube-robot"}
    for name, pin in pins:
        s = pin.spec
        shape = pin.printable
        # every cylindrical and conical face's axis is horizontal
        axes = []
        for f in shape.Faces():
            if f.geomType() in ("CYLINDER", "CONE"):
                ad = BRepAdaptor_Surface(f.wrapped)
                ax = (ad.Cylinder() if f.geomType() == "CYLINDER" else ad.Cone()).Axis().Direction()
                axes.append((ax.X(), ax.Y(), ax.Z()))
        assert len(axes) >= 4, name
        assert all(abs(a[2]) < 1e-9 for a in axes), (name, axes)
        # as exported (the STL's mesh): the axis of least inertia lies within 1 deg of horizontal (the flat
        # shifts the head's and the shaft's centroids by different amounts: not exactly on the axis)
        mesh = mesh_of(shape)
        axis = mesh.principal_inertia_vectors[int(np.argmin(mesh.principal_inertia_components))]
        assert abs(axis[2]) < np.sin(np.radians(1.0)), (name, axis)
        x0, y0, z0, x1, y1, z1 = tight_bbox(shape)
        length = s.protrusion_mm - s.head_x_mm
        assert max(x1 - x0, y1 - y0) == pytest.approx(length, abs=1e-6), name
        assert z1 - z0 == pytest.approx(s.head_diameter_mm / 2 + s.pin_diameter_mm / 2 - s.pin_flat_mm, abs=1e-6)
        assert mesh.bounds[0][2] == pytest.approx(0.0, abs=1e-9)
        # it stands on its flat: a strip as long as the pin less its chamfer, at least 2 mm wide
        bottom = sum(f.Area() for f in _planar_faces_at(shape, 0.0))
        assert bottom >= 2.0 * (length - s.pin_chamfer_mm), (name, bottom)
        assert "lying" in pin.print_settings()["orientation"]


@pytest.mark.parametrize("c", (0.1, 0.2, 0.5))
def test_the_pin_flat_keeps_the_latch_overlap(c):
    """The flat is as deep as the locked blade's overlap over the flattened shoulder allows (>= the
    minimum overlap), 0.4 mm at most."""
    from cubot_cad.couplings.connectors import MIN_LATCH_OVERLAP_MM, FrontRearSpec

    s = FrontRearSpec(clearance_mm=c)
    assert 0.1 - 1e-9 <= s.pin_flat_mm <= 0.4
    assert s.pin_diameter_mm / 2 - s.pin_flat_mm - s.slot_width_mm / 2 >= MIN_LATCH_OVERLAP_MM - 1e-9
    assert s.pin_diameter_mm / 2 - s.pin_flat_mm > s.groove_diameter_mm / 2  # the groove is round all round


def test_pin_locking_plate_prints_larger_face_down_counterbores_up(robots):
    """``print_rotation`` about +y by +90 deg (it was -90: the counterbored back face on the bed, its
    shoulders printed as bridges)."""
    from cubot_cad.shapes import tight_bbox

    part = next(p for p, _ in robots["cubot"].printable_parts() if p.name == "pinset_b_pin_locking_plate")
    assert part.print_rotation == (((0.0, 1.0, 0.0), 90.0),)
    shape = part.printable
    b = tight_bbox(shape)
    assert b[2] == pytest.approx(0.0, abs=1e-9)
    assert b[5] == pytest.approx(part.spec.locking_plate_mm, abs=1e-6)
    planar = [f for f in shape.Faces() if f.geomType() == "PLANE"]
    largest = max(f.Area() for f in planar)
    down = _planar_faces_at(shape, 0.0)
    assert len(down) == 1 and down[0].Area() == pytest.approx(largest, rel=1e-9)
    up = _planar_faces_at(shape, b[5])
    assert len(up) == 1 and up[0].Area() < largest
    # the counterbores (head + clearance radius) open at the top face, none at the bottom
    s = part.spec
    rc = s.head_diameter_mm / 2 + s.clearance_mm

    def circles(face):
        return sum(1 for e in face.Edges() if e.geomType() == "CIRCLE" and abs(e.radius() - rc) < 1e-6)

    assert circles(up[0]) == 3 and circles(down[0]) == 0


def test_every_part_in_print_orientation_has_z_min_0(robots):
    """Every exported part (per robot and per pier), as laid on the bed and as meshed for its STL."""
    from cubot_cad.mesh import mesh_of
    from cubot_cad.piers.deck import pier_parts
    from cubot_cad.shapes import tight_bbox

    seen = 0
    for r in robots.values():
        for part, _ in list(r.printable_parts()) + list(pier_parts(r)):
            shape = part.printable
            assert tight_bbox(shape)[2] == pytest.approx(0.0, abs=1e-9), part.name
            assert mesh_of(shape).bounds[0][2] == pytest.approx(0.0, abs=1e-6), part.name
            seen += 1
    assert seen >= 36
