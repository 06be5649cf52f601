"""The robot body's bending section, cut from the CAD (issue 12, flexible bodies).

`structure_fem` treats each robot between its front and rear couplings as a beam bending in
the structure's vertical plane (x along the structure, z up). What it needs from the CAD is the
body's flexural rigidity ``E I(x)`` along x. A thin-walled printed shell is far softer than its
envelope: the CuBot body (2.4 mm walls and floor, open under the cover) has ``I`` of about
2.7e5 mm^4 at mid-length, while the envelope box scaled by the robot's fill fraction (what the
model used before) gives about 1.9e6 mm^4, seven times stiffer.

:func:`body_section` cuts the printed parts of the given roles (default ``"body"``) with planes
``x = const`` at the mid-points of ``stations`` equal slices of the body's length, and takes each
cut face's second moment of area about the horizontal axis (y) through its own centroid,
``I(x) = integral z'^2 dA`` (OpenCascade ``BRepGProp.SurfaceProperties``: exact for the faces,
no mesh). Several parts cut at one station (the Cube Robot's three tiers) are added as separate
beams, each about its own centroid: they are screwed together, not bonded, so no composite
action is counted (the lower bound). Parts screwed *to* the body (cover, connector blocks,
rails) are left out for the same reason (conservative).

The result is the compliance the lumped beam needs, ``integral dx / I(x)`` over the length
(mid-point rule), and the effective ``I_eff = L / integral dx / I``: the uniform section with
the same end rotation under a uniform moment. A station with no material (a slot through the
whole body) has no bending stiffness there, and is refused (the body would be two parts).

**Coupling zones.** A robot whose coupling is cut into its body (the test platform's lap joint:
the front tab and the rear recess are the plate's own material, half its thickness) names those
x-intervals in ``coupling_zones_mm``: they belong to the coupling's model, whose FE
(:mod:`structure_fem.couplings.platform_bolt_fe`) already counts them as the joint's compliance
*beyond a continuous plate*, so the body's section is taken over the rest only (stations whose
mid-point lies in a zone are skipped, ``I_eff`` over the kept length). Cutting them into the body
too counted the joint twice: the platform's record said 205 mm^4 (a 2.9 mm plate) where the FE's
plate, and the part, are 5 mm (1042 mm^4). One geometry for both.

Shear deformation of the walls is not in it: for the CuBot (webs 2 x 2.4 x 72 mm, G = E / 2.7)
a robot carrying 20 N of shear deflects 7 um in shear, well below a micrometre-scale
contribution to millimetre tips (stated, not modelled).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cubot_cad.errors import InputError

#: Cut stations along the body's length (mid-points of equal slices). 40 resolves the 2.4 mm
#: end walls of a 100 mm body within one station (a finer cut changes I_eff by < 1 %: the test).
DEFAULT_STATIONS = 40


@dataclass(frozen=True)
class BodySection:
    """The bending section of a robot body along its length (mm, mm^2, mm^4)."""

    roles: tuple[str, ...]
    parts: tuple[str, ...]
    stations: int
    length_mm: float
    #: Smallest I(x) over the stations, and where (x in the robot frame, mm).
    min_second_moment_mm4: float
    min_at_x_mm: float
    #: L / integral dx / I(x): the uniform section with the same bending compliance.
    effective_second_moment_mm4: float
    #: The mean cut area (mm^2), for reference.
    mean_area_mm2: float
    #: x-intervals (robot frame, mm) left to the couplings' own models (module docstring).
    coupling_zones_mm: tuple[tuple[float, float], ...] = ()
    #: Stations cut (``stations`` less those in a coupling zone).
    kept_stations: int = 0

    @property
    def effective_second_moment_m4(self) -> float:
        return self.effective_second_moment_mm4 * 1e-12

    @property
    def source(self) -> str:
        zones = ""
        if self.coupling_zones_mm:
            zones = (f" ({self.kept_stations} kept: the coupling's own zones x = " + ", ".join(f"{a:.4g}..{b:.4g}" for a, b in self.coupling_zones_mm)
                     + " mm left to its model, which counts them)")
        return (f"cubot_cad.section: the printed {', '.join(self.parts)} cut by planes x = const at {self.stations} "
                f"stations over {self.length_mm:g} mm{zones}, I(x) = integral z'^2 dA about each cut's own centroid "
                f"(OpenCascade surface properties; parts screwed together added without composite action; "
                f"cover, connector blocks and rails left out), I_eff = L / integral dx / I(x) = "
                f"{self.effective_second_moment_mm4:.4g} mm^4 (min {self.min_second_moment_mm4:.4g} mm^4 at "
                f"x = {self.min_at_x_mm:.3g} mm)")


def _cut(shape, x_mm: float, span_mm: float):
    """(area mm^2, I about the cut's centroidal y axis mm^4) of ``shape`` cut by the plane x = x_mm."""
    import cadquery as cq
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    plane = cq.Face.makePlane(span_mm, span_mm, basePnt=cq.Vector(x_mm, 0, 0), dir=cq.Vector(1, 0, 0))
    face = shape.intersect(plane)
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face.wrapped, props)
    area = props.Mass()
    if area <= 0:
        return 0.0, 0.0
    # about the centroid; in a plane x = const, I_yy = integral (x'^2 + z'^2) dA = integral z'^2 dA
    return float(area), float(props.MatrixOfInertia().Value(2, 2))


def body_section(robot, roles: tuple[str, ...] = ("body",), stations: int = DEFAULT_STATIONS) -> BodySection:
    """The bending section of ``robot``'s printed parts with ``roles`` (module docstring)."""
    if isinstance(stations, bool) or not isinstance(stations, int) or stations < 4:
        raise InputError(f"section stations must be an integer >= 4, got {stations!r}")
    placed = [p for p in robot.placed if p.role in roles]
    if not placed:
        raise InputError(f"{robot.name} has no printed part with role {', '.join(roles)} to take a bending section of")
    shapes = [p.shape for p in placed]
    from cubot_cad.shapes import tight_bbox

    boxes = [tight_bbox(s) for s in shapes]
    x0 = min(b[0] for b in boxes)
    x1 = max(b[3] for b in boxes)
    span = 4.0 * max(abs(v) for b in boxes for v in b) + 10.0  # a plane larger than any cut
    zones = tuple((float(a), float(b)) for a, b in getattr(robot, "coupling_zones_mm", ()))
    for a, b in zones:
        if not (math.isfinite(a) and math.isfinite(b) and a < b):
            raise InputError(f"{robot.name}: coupling zone {a!r}..{b!r} mm is not an interval")
    dx = (x1 - x0) / stations
    xs = [x0 + (k + 0.5) * dx for k in range(stations)]
    xs = [x for x in xs if not any(a < x < b for a, b in zones)]
    if len(xs) < 4:
        raise InputError(f"{robot.name}: its coupling zones leave {len(xs)} of {stations} section stations")
    length = len(xs) * dx
    compliance = 0.0  # integral dx / I, mm^-3
    i_min, x_min, area_sum = math.inf, x0, 0.0
    for x in xs:
        cuts = [_cut(s, x, span) for s in shapes]
        area = sum(a for a, _ in cuts)
        i_x = sum(i for _, i in cuts)
        if not i_x > 0:
            raise InputError(f"{robot.name}: the {', '.join(roles)} parts have no material at x = {x:.3g} mm "
                             "(nothing carries bending there)")
        compliance += dx / i_x
        area_sum += area
        if i_x < i_min:
            i_min, x_min = i_x, x
    return BodySection(roles=tuple(roles), parts=tuple(dict.fromkeys(p.part.name for p in placed)),
                       stations=stations, length_mm=float(length), min_second_moment_mm4=float(i_min),
                       min_at_x_mm=float(x_min), effective_second_moment_mm4=float(length / compliance),
                       mean_area_mm2=float(area_sum / len(xs)), coupling_zones_mm=zones,
                       kept_stations=len(xs))


def body_section_fields(robot, stations: int = DEFAULT_STATIONS) -> dict:
    """``{"body_second_moment_m4": ..., "body_second_moment_source": ...}`` for a parametric
    :class:`cubot_cad.robots.base.Robot`, to ``dataclasses.replace`` into its
    :class:`cubot_cad.properties.RobotProperties` when the record is written (empty when the
    robot has no part with the ``body`` role)."""
    if not any(p.role == "body" for p in robot.placed):
        return {}
    sec = body_section(robot, stations=stations)
    return {"body_second_moment_m4": sec.effective_second_moment_m4, "body_second_moment_source": sec.source}
