"""Hobby micro servos and their horns as data (mm, g): the drive of the CuBot's twist-lock
(:mod:`cubot_cad.couplings.twist`), like :mod:`cubot_cad.hardware.fasteners` for screws.

A part that takes a servo asks this table for the servo's case, mounting tabs, output spline and
the horn supplied with it, instead of repeating literals; the bill of materials names the servo
from the same row.

Sources of the numbers (per row):

* TowerPro SG90 and MG90S, nominal data from the maker's product pages and datasheets
  (towerpro.com.tw: SG90 "9 g, stall torque 1.8 kgf.cm (4.8 V), 0.1 s/60 deg, 22.2 x 11.8 x 31 mm";
  MG90S "13.4 g, stall torque 1.8 kgf.cm (4.8 V), 2.2 kgf.cm (6 V), 0.10 s/60 deg (4.8 V),
  22.8 x 12.2 x 28.5 mm", metal gears): mass, stall torque, speed;
* the case, tab and spline dimensions are measurements of the two servos in Brad Kartchner's
  OpenSCAD servo library (github.com/kartchnb/openscad-servo-library, ``servos/sg90_clone.scad``
  and ``servos/mg90s_clone.scad``: "aft height" = case bottom to the tabs, "wing height" = tab
  thickness, "fore height" = tabs to the spline-side face, "axle height" = spline protrusion,
  "axle offset" = spline axis from the near end of the case, hole offsets from the case centre);
  they agree with the nominal sizes above within 0.5 mm (the nominal heights include the spline);
* the horn is the double-arm ("I") horn of the 20-tooth spline both servos have, from the same
  author's servo horn library (github.com/kartchnb/servohorn_lib, ``servohorns/20t.scad`` and
  ``servohorns/20t/i.scad``: centre cap 6.92 mm, arms 1.43 mm thick, 3.73 mm overall, socket 4.60 mm
  x 2.00 mm deep, arms 16.5 mm from the centre with a 4 mm rounded end, 1.5 mm holes every 2 mm from
  5 mm out).

The horn is the one that comes with the servo (its spline fits by construction); the twist-lock
screws it to the key with two M2 screws through its innermost arm holes, drilled out to the
ISO 273 medium clearance (2.4 mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cubot_cad.errors import InputError

#: 1 kgf.cm in N.m (standard gravity 9.80665 m/s^2).
KGF_CM_NM = 9.80665e-2


@dataclass(frozen=True)
class Horn:
    """A servo horn (mm). Frame used by the stand-ins: the arms' flat face on z = 0, the centre cap
    rising to ``height_mm``, the splined socket open at the cap's top."""

    name: str
    spline: str
    hub_diameter_mm: float
    arm_mm: float
    height_mm: float
    socket_diameter_mm: float
    socket_depth_mm: float
    arm_length_mm: float
    arm_end_diameter_mm: float
    hole_radii_mm: tuple[float, ...]
    hole_mm: float
    arms: int = 2
    #: The screws that fasten something to the horn through its arm holes (drilled to their clearance).
    screw_size: str = "M2"

    def arm_width_mm(self, r: float) -> float:
        """Width of an arm at radius ``r`` (straight taper from the cap to the end circle)."""
        r_end = self.arm_length_mm - self.arm_end_diameter_mm / 2
        t = min(max(r / r_end, 0.0), 1.0)
        return self.hub_diameter_mm + (self.arm_end_diameter_mm - self.hub_diameter_mm) * t


@dataclass(frozen=True)
class Servo:
    """A micro servo (mm, g). ``tab_from_face_mm``: from the spline-side face of the case to the tabs'
    face on that side; ``axle_from_end_mm``: from the output axis to the near end of the case."""

    name: str
    maker: str
    mass_g: float
    stall_torque_kgf_cm: float
    speed_s_per_60deg: float
    case_length_mm: float
    case_width_mm: float
    case_height_mm: float
    tab_length_mm: float
    tab_mm: float
    tab_from_face_mm: float
    axle_from_end_mm: float
    spline_diameter_mm: float
    spline_mm: float
    hole_spacing_mm: float
    tab_hole_mm: float
    horn: Horn
    gears: str = "plastic"
    #: The screws through the mounting tabs (the table's M2; the servo's own self-tapping screws fit too).
    screw_size: str = "M2"

    @property
    def stall_torque_nm(self) -> float:
        return self.stall_torque_kgf_cm * KGF_CM_NM

    @property
    def axle_to_centre_mm(self) -> float:
        """How far the case centre lies from the output axis, along the case."""
        return self.case_length_mm / 2 - self.axle_from_end_mm

    def hole_offsets_mm(self) -> tuple[float, float]:
        """The two tab holes along the case, from the output axis (near hole > 0, far hole < 0, with the
        case extending towards negative values)."""
        c = -self.axle_to_centre_mm
        return (c + self.hole_spacing_mm / 2, c - self.hole_spacing_mm / 2)

    def describe(self, duty: str) -> str:
        """The bill of materials' words for this servo doing ``duty``."""
        return (f"{self.maker} {self.name} micro servo ({self.gears} gears, {self.mass_g:g} g, stall "
                f"{self.stall_torque_kgf_cm:g} kgf cm at 4.8 V) {duty}")

    @property
    def description(self) -> str:
        return self.describe("turning the cross key")


#: The 20-tooth (Futaba-compatible micro) double-arm horn (source: module docstring).
HORN_20T_I = Horn(name="20T double-arm horn (I)", spline="20T", hub_diameter_mm=6.92, arm_mm=1.43, height_mm=3.73,
                  socket_diameter_mm=4.60, socket_depth_mm=2.00, arm_length_mm=16.5, arm_end_diameter_mm=4.0,
                  hole_radii_mm=(5.0, 7.0, 9.0, 11.0, 13.0, 15.0), hole_mm=1.5)

#: Micro servos (source: module docstring).
SERVOS: dict[str, Servo] = {
    "SG90": Servo(name="SG90", maker="TowerPro", mass_g=9.0, stall_torque_kgf_cm=1.8, speed_s_per_60deg=0.10,
                  case_length_mm=22.62, case_width_mm=12.38, case_height_mm=15.56 + 2.46 + 8.34,
                  tab_length_mm=32.38, tab_mm=2.46, tab_from_face_mm=8.34, axle_from_end_mm=6.19,
                  spline_diameter_mm=4.00, spline_mm=3.08, hole_spacing_mm=2 * 13.97, tab_hole_mm=2.60,
                  horn=HORN_20T_I),
    "MG90S": Servo(name="MG90S", maker="TowerPro", mass_g=13.4, stall_torque_kgf_cm=1.8, speed_s_per_60deg=0.10,
                   case_length_mm=22.92, case_width_mm=12.38, case_height_mm=18.31 + 2.53 + 7.62,
                   tab_length_mm=32.38, tab_mm=2.53, tab_from_face_mm=7.62, axle_from_end_mm=6.19,
                   spline_diameter_mm=4.70, spline_mm=4.00, hole_spacing_mm=2 * 14.16, tab_hole_mm=2.20,
                   horn=HORN_20T_I, gears="metal"),
}


def servo(name: str) -> Servo:
    """The table row ``name``; :class:`InputError` otherwise."""
    if name not in SERVOS:
        raise InputError(f"servo {name!r} is not one of {', '.join(SERVOS)}")
    return SERVOS[name]


def arm_outline(horn: Horn, angle_deg: float, segments: int = 48) -> list[tuple[float, float]]:
    """Plan outline (x, y, counter-clockwise) of one arm of ``horn`` pointing along ``angle_deg``: the
    convex hull of the centre cap's circle and the arm's rounded end."""
    from cubot_cad.shapes import convex_hull

    R, r = horn.hub_diameter_mm / 2, horn.arm_end_diameter_mm / 2
    d = horn.arm_length_mm - r
    a = math.radians(angle_deg)
    pts = []
    for i in range(segments):
        t = 2 * math.pi * i / segments
        pts.append((R * math.cos(t), R * math.sin(t)))
        pts.append((d * math.cos(a) + r * math.cos(t), d * math.sin(a) + r * math.sin(t)))
    return convex_hull(pts)
