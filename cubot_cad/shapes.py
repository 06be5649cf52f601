"""Small solid-building helpers on top of OCC (via cadquery), millimetres.

Boxes are given by their extents, cylinders by base point and axis, prisms by a
2D outline extruded along an axis. Many cutters are fused into one compound and
cut in a single boolean: that is what keeps a full robot body near a second.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import cadquery as cq
import numpy as np

X = (1.0, 0.0, 0.0)
Y = (0.0, 1.0, 0.0)
Z = (0.0, 0.0, 1.0)


def box(x0: float, x1: float, y0: float, y1: float, z0: float, z1: float) -> cq.Solid:
    """Axis-aligned box between the given extents."""
    return cq.Solid.makeBox(x1 - x0, y1 - y0, z1 - z0, cq.Vector(x0, y0, z0))


def cyl(r: float, h: float, base: Sequence[float], axis: Sequence[float] = Z) -> cq.Solid:
    """Cylinder of radius ``r`` and length ``h`` from ``base`` along ``axis``."""
    return cq.Solid.makeCylinder(r, h, cq.Vector(*base), cq.Vector(*axis))


def sphere(r: float, centre: Sequence[float]) -> cq.Solid:
    return cq.Solid.makeSphere(r, cq.Vector(*centre), angleDegrees1=-90, angleDegrees2=90)


def prism(outline: Sequence[tuple[float, float]], plane: str, offset: float, depth: float) -> cq.Solid:
    """Extrude a closed 2D ``outline`` drawn in ``plane`` ("YZ", "XZ" or "XY") from
    ``offset`` along the plane normal by ``depth`` (may be negative)."""
    pts = []
    for u, v in outline:
        if plane == "YZ":
            pts.append(cq.Vector(offset, u, v))
        elif plane == "XZ":
            pts.append(cq.Vector(u, offset, v))
        else:
            pts.append(cq.Vector(u, v, offset))
    normal = {"YZ": X, "XZ": Y, "XY": Z}[plane]
    wire = cq.Wire.makePolygon(pts, close=True)
    return cq.Solid.extrudeLinear(wire, [], cq.Vector(*normal) * depth)


def regular_polygon(n: int, across_flats: float, flats_on_axes: bool = True) -> list[tuple[float, float]]:
    """Vertices of a regular ``n``-gon with the given across-flats size (flats facing the axes)."""
    rc = across_flats / 2 / math.cos(math.pi / n)
    start = math.pi / n if flats_on_axes else 0.0
    return [(rc * math.cos(start + 2 * math.pi * i / n), rc * math.sin(start + 2 * math.pi * i / n))
            for i in range(n)]


def cut_all(base: cq.Shape, cutters: Iterable[cq.Shape]) -> cq.Shape:
    tools = list(cutters)
    return base.cut(*tools) if tools else base


def fuse_all(shapes: Iterable[cq.Shape]) -> cq.Shape:
    items = list(shapes)
    if len(items) == 1:
        return items[0]
    return items[0].fuse(*items[1:]).clean()


def rotated(shape: cq.Shape, axis: Sequence[float], deg: float, centre: Sequence[float] = (0, 0, 0)) -> cq.Shape:
    c = cq.Vector(*centre)
    return shape.rotate(c, c + cq.Vector(*axis), deg)


def yaw_point(p: Sequence[float], deg: float) -> tuple[float, float, float]:
    """``p`` turned ``deg`` (a multiple of 90, exact) about the z axis through the origin."""
    k = round(deg / 90) % 4
    if abs(deg - 90 * round(deg / 90)) > 1e-9:
        raise ValueError(f"yaw {deg!r} deg is not a multiple of 90")
    x, y, z = p
    for _ in range(k):
        x, y = -y, x
    return (x, y, z)


def yaw_box(b: Sequence[float], deg: float) -> tuple[float, float, float, float, float, float]:
    """The axis-aligned box ``(x0, x1, y0, y1, z0, z1)`` turned ``deg`` (a multiple of 90) about z."""
    x0, x1, y0, y1, z0, z1 = b
    a = yaw_point((x0, y0, z0), deg)
    c = yaw_point((x1, y1, z1), deg)
    return (min(a[0], c[0]), max(a[0], c[0]), min(a[1], c[1]), max(a[1], c[1]), z0, z1)


def location(xyz: Sequence[float] = (0, 0, 0), rot_z_deg: float = 0.0, rot_x_deg: float = 0.0) -> cq.Location:
    """A placement: rotate about x, then about z, then translate by ``xyz``."""
    loc = cq.Location(cq.Vector(*xyz))
    if rot_z_deg:
        loc = loc * cq.Location(cq.Vector(0, 0, 0), cq.Vector(0, 0, 1), rot_z_deg)
    if rot_x_deg:
        loc = loc * cq.Location(cq.Vector(0, 0, 0), cq.Vector(1, 0, 0), rot_x_deg)
    return loc


def tight_bbox(shape) -> tuple[float, float, float, float, float, float]:
    """Exact (optimal) bounding box (xmin, ymin, zmin, xmax, ymax, zmax) of an OCC shape, mm.

    cadquery's ``BoundingBox`` is enlarged by tolerances (tenths of a mm on
    curved faces); measurements such as exposed heights need the true extent.
    """
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box_ = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape.wrapped, box_, False, False)
    return tuple(box_.Get())


def cone(r0: float, r1: float, h: float, base: Sequence[float], axis: Sequence[float] = Z) -> cq.Solid:
    """Truncated cone of radius ``r0`` at ``base`` and ``r1`` a length ``h`` along ``axis``
    (lead-ins: 45 deg chamfers and countersinks are cones with ``|r1 - r0| = h``)."""
    return cq.Solid.makeCone(r0, r1, h, cq.Vector(*base), cq.Vector(*axis))


def frustum(half0: tuple[float, float], half1: tuple[float, float], z0: float, z1: float,
            centre: tuple[float, float] = (0.0, 0.0)) -> cq.Solid:
    """A rectangular frustum along z: half-sizes (x, y) ``half0`` at ``z0`` and ``half1`` at ``z1``."""
    cx, cy = centre

    def rect(h, z):
        a, b = h
        return cq.Wire.makePolygon([cq.Vector(cx - a, cy - b, z), cq.Vector(cx + a, cy - b, z),
                                    cq.Vector(cx + a, cy + b, z), cq.Vector(cx - a, cy + b, z)], close=True)

    return cq.Solid.makeLoft([rect(half0, z0), rect(half1, z1)], True)


def loft_x(outline0: Sequence[tuple[float, float]], x0: float, outline1: Sequence[tuple[float, float]],
           x1: float) -> cq.Solid:
    """A ruled solid between two (y, z) polygons with the same number of vertices at ``x0`` and ``x1``."""
    w0 = cq.Wire.makePolygon([cq.Vector(x0, u, v) for u, v in outline0], close=True)
    w1 = cq.Wire.makePolygon([cq.Vector(x1, u, v) for u, v in outline1], close=True)
    return cq.Solid.makeLoft([w0, w1], True)


def convex_hull(points) -> list[tuple[float, float]]:
    """Counter-clockwise convex hull (Andrew's monotone chain)."""
    pts = sorted(set((float(x), float(y)) for x, y in points))
    if len(pts) < 3:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def loc_matrix(loc) -> np.ndarray:
    t = loc.wrapped.Transformation()
    return np.array([[t.Value(i, j) for j in range(1, 5)] for i in range(1, 4)])
