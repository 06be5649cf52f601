"""OctBot (thesis Ch. 6.3.2): octagonal prism <= 100 x 100 x 30 mm (without connectors),
differential drive, two adjustable ball casters, ring-and-capture coupling.

Rear: a ring (a short tube with an inner lip) on a mounting plate. Front: the
capturer housing with three fingers at 90/210/330 deg; the fingers pass the lip
closed (retracted), open (spread) behind it and pull the ring against the
housing. They are driven like a scroll chuck: a cam disc behind them (three
spiral slots, one peg per finger) turned by a worm on an N20 gearmotor in a
pocket of the housing; :meth:`RingSpec.finger_offset_mm` maps the disc angle to
the fingers' radial position, ``OctBot.build_placed(disc_deg=...)`` places them. The docked gap (face to face) is ``docked_gap_mm`` (thesis: it cannot
be less than 40 mm because of the proximity sensors' reading range); the
housing length follows from it and the ring's geometry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import ClassVar

from cubot_cad.couplings import compliance as couplings
from cubot_cad.couplings.connectors import CasterSeat
from cubot_cad.hardware.components import Component
from cubot_cad.part import (
    DEFAULT_CLEARANCE_MM,
    MIN_WALL_MM,
    Part,
    at_least,
    at_most,
    check_clearance,
    check_dims,
    need,
)
from cubot_cad.robots.base import Placed, Robot

MIN_SENSOR_GAP_MM = 40.0


@dataclass(frozen=True)
class RingSpec:
    """Ring and capturer dimensions (mm). Ring frame: x = 0 on the robot's rear face, +x outward."""

    #: The three fingers' angles about the capture axis (0 = +z, turning about +x), deg.
    FINGER_ANGLES_DEG: ClassVar[tuple[float, float, float]] = (0.0, 120.0, 240.0)

    plate_mm: float = 3.0
    lip_mm: float = 3.0
    lip_radius_mm: float = 8.0
    tube_wall_mm: float = 2.0
    finger_mm: float = 3.0
    hook_mm: float = 2.5
    hook_overlap_mm: float = 2.0
    finger_travel_mm: float = 2.5
    centre_z_mm: float = 16.0
    #: Lead-ins (45 deg): a cone on the mouth of the ring's lip and a chamfer on the hooks' leading
    #: outer edges, so that closed fingers arriving off-centre are steered through the lip. 0 = none.
    lip_chamfer_mm: float = 1.0
    hook_chamfer_mm: float = 0.8
    screw_size: str = "M3"
    #: The finger drive (a scroll-chuck-like cam disc turned by a worm): the pegs' radius on the
    #: fingers' tails, the cam disc's thickness and radius, the disc turn from retracted to spread
    #: (deg), and the worm's pitch radius and length (mm).
    peg_radius_mm: float = 1.0
    cam_disc_mm: float = 3.0
    cam_radius_mm: float = 9.0
    cam_turn_deg: float = 60.0
    worm_radius_mm: float = 3.0
    worm_length_mm: float = 8.0
    #: The finger retainer (:class:`FingerRetainer`): a plate ``retainer_mm`` thick over the housing's
    #: front whose slots pass the fingers' bars and hooks but not the shoulders (``shoulder_mm`` wider
    #: each side) on the fingers' tails, so a finger cannot be pulled out along +x and, its peg held in
    #: the cam disc, the disc cannot lift out of its open slot. Two countersunk ``retainer_screw_size``
    #: screws at ``retainer_screw_radius_mm`` from the capture axis (between the fingers, at 60 and
    #: 300 deg) go into heat-set inserts in the housing's front face.
    retainer_mm: float = 2.4
    shoulder_mm: float = 1.0
    retainer_screw_size: str = "M2"
    retainer_screw_radius_mm: float = 11.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm)
        for n in ("lip_chamfer_mm", "hook_chamfer_mm"):
            v = getattr(self, n)
            need(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v >= 0,
                 f"{n} must be a length >= 0 mm (0 = no lead-in), got {v!r}")
        need(at_most(self.lip_chamfer_mm, self.lip_mm / 2),
             f"lip_chamfer_mm {self.lip_chamfer_mm:g} is more than half the {self.lip_mm:g} mm lip")
        need(at_most(self.hook_chamfer_mm, self.hook_mm - MIN_WALL_MM),
             f"hook_chamfer_mm {self.hook_chamfer_mm:g} leaves the {self.hook_mm:g} mm hook under {MIN_WALL_MM:g} mm")
        from cubot_cad.hardware.fasteners import thread

        thread(self.screw_size)
        check_dims(self, ("plate_mm", "lip_mm", "lip_radius_mm", "tube_wall_mm", "finger_mm", "hook_mm",
                          "hook_overlap_mm", "finger_travel_mm", "centre_z_mm"))
        for n in ("plate_mm", "lip_mm", "tube_wall_mm", "finger_mm", "hook_mm"):
            need(at_least(getattr(self, n), MIN_WALL_MM), f"{n} {getattr(self, n):g} is thinner than {MIN_WALL_MM:g} mm")
        need(at_least(self.finger_travel_mm, self.hook_overlap_mm + self.clearance_mm),
             f"finger_travel_mm {self.finger_travel_mm:g} cannot pull the hooks ({self.hook_overlap_mm:g} mm) "
             "back through the lip")
        check_dims(self, ("peg_radius_mm", "cam_disc_mm", "cam_radius_mm", "cam_turn_deg", "worm_radius_mm",
                          "worm_length_mm"))
        need(at_least(self.cam_disc_mm, 2 * MIN_WALL_MM), f"cam_disc_mm {self.cam_disc_mm:g} is too thin")
        need(at_most(self.peg_radius_mm, self.finger_mm / 2), f"peg_radius_mm {self.peg_radius_mm:g} is wider than "
             f"the {self.finger_mm:g} mm finger")
        need(at_least(self.cam_radius_mm - self.finger_radius_mm - self.cam_slot_half_mm, MIN_WALL_MM),
             f"cam_radius_mm {self.cam_radius_mm:g} leaves under {MIN_WALL_MM:g} mm outside the cam slots")
        need(at_least(self.finger_radius_mm - self.finger_travel_mm - self.cam_slot_half_mm, MIN_WALL_MM),
             f"finger_travel_mm {self.finger_travel_mm:g}: the cam slots reach the disc's centre")
        # three slots, each spanning cam_turn_deg plus its end caps, must leave webs between them
        caps = math.degrees(self.cam_slot_half_mm / self.finger_radius_mm
                            + self.cam_slot_half_mm / (self.finger_radius_mm - self.finger_travel_mm))
        need(self.cam_turn_deg + caps + 10.0 <= 120.0,
             f"cam_turn_deg {self.cam_turn_deg:g}: the three cam slots overlap (at most {110.0 - caps:.0f} deg)")
        need(at_least(self.finger_radius_mm - self.finger_mm / 2 - self.finger_travel_mm, 0.5),
             f"lip_radius_mm {self.lip_radius_mm:g} is too small for three {self.finger_mm:g} mm fingers that close "
             f"by {self.finger_travel_mm:g} mm")
        self._check_retainer()

    def _check_retainer(self) -> None:
        from cubot_cad.hardware.fasteners import countersunk_head_mm

        check_dims(self, ("retainer_mm", "shoulder_mm", "retainer_screw_radius_mm"))
        dk, k, _std = countersunk_head_mm(self.retainer_screw_size)
        need(at_least(self.retainer_mm - k, MIN_WALL_MM),
             f"retainer_mm {self.retainer_mm:g} leaves under {MIN_WALL_MM:g} mm under the {self.retainer_screw_size} "
             f"countersunk heads ({k:g} mm)")
        need(at_least(self.shoulder_mm - self.clearance_mm, 0.5),
             f"shoulder_mm {self.shoulder_mm:g}: the fingers' shoulders overlap the retainer's slots by under 0.5 mm "
             f"at the {self.clearance_mm:g} mm clearance")
        # the screws sit between the fingers: clear of the retainer's slots (which pass the hooks) by a wall
        rho, half = self.retainer_screw_radius_mm, self.finger_mm / 2 + self.clearance_mm
        off = rho * math.sin(math.radians(60.0)) - half - (dk / 2 + self.clearance_mm)
        need(at_least(off, MIN_WALL_MM),
             f"retainer_screw_radius_mm {rho:g} puts the {self.retainer_screw_size} screw heads into the finger slots")

    @property
    def retainer_slot_radii_mm(self) -> tuple[float, float]:
        """Radial extent of the retainer's finger slots (from the capture axis), mm: from the bars' inner
        faces fully retracted to the hooks' tops fully spread, each less/plus the clearance (the plate
        goes on over the hooks at any disc angle)."""
        r0 = self.finger_radius_mm - self.finger_mm / 2 - self.finger_travel_mm - self.clearance_mm
        return (r0, self.lip_radius_mm + self.hook_overlap_mm + self.clearance_mm)

    @property
    def retainer_screw_points_mm(self) -> tuple[tuple[float, float], ...]:
        """(y, z about the capture axis) of the retainer's two screws: at 60 and 300 deg (the fingers'
        angles turned by half their spacing; 0 deg = +z, as the fingers), mm."""
        rho = self.retainer_screw_radius_mm
        return tuple((-rho * math.sin(math.radians(a)), rho * math.cos(math.radians(a))) for a in (60.0, 300.0))

    @property
    def finger_radius_mm(self) -> float:
        """Radius of the finger bars' centres when open (touching the lip less a clearance)."""
        return self.lip_radius_mm - self.clearance_mm - self.finger_mm / 2

    @property
    def cam_slot_half_mm(self) -> float:
        """Half width of the cam disc's slots: the peg's radius plus the clearance, mm."""
        return self.peg_radius_mm + self.clearance_mm

    def finger_offset_mm(self, disc_deg: float) -> float:
        """Radial offset of every finger from its spread (holding) position for the cam disc turned by
        ``disc_deg`` (0 = retracted, ``cam_turn_deg`` = spread; linear: an Archimedean cam), mm:
        ``-finger_travel_mm`` at 0, 0 at ``cam_turn_deg``."""
        need(-1e-9 <= disc_deg <= self.cam_turn_deg + 1e-9,
             f"disc_deg {disc_deg:g} is outside the cam's 0-{self.cam_turn_deg:g} deg")
        return -self.finger_travel_mm * (1.0 - disc_deg / self.cam_turn_deg)

    def peg_radius_at_mm(self, disc_deg: float) -> float:
        """Distance of the pegs' axes from the capture axis at ``disc_deg``, mm."""
        return self.finger_radius_mm + self.finger_offset_mm(disc_deg)

    @property
    def undercut_radius_mm(self) -> float:
        return self.lip_radius_mm + self.hook_overlap_mm + self.clearance_mm + 0.8

    @property
    def outer_radius_mm(self) -> float:
        return self.undercut_radius_mm + self.tube_wall_mm

    @property
    def undercut_mm(self) -> float:
        return self.hook_mm + 2 * self.clearance_mm + 1.0

    @property
    def plate_half_mm(self) -> float:
        """Half the ring's mounting plate's width (y), mm."""
        return self.outer_radius_mm + 2.5

    @property
    def mount_ys_mm(self) -> tuple[float, float]:
        """y of the two M-screws that hold the ring plate to the rear wall and the capturer housing to the
        front wall (the body's wall holes are at the same y, at ``centre_z_mm``), mm: 3.5 mm in from the
        plate's edges."""
        y = self.plate_half_mm - 3.5
        return (-y, y)

    @property
    def ring_length_mm(self) -> float:
        """From the rear face to the lip's outer face."""
        return self.plate_mm + self.undercut_mm + self.lip_mm


@dataclass(frozen=True)
class OctRing(Part):
    spec: RingSpec = RingSpec()
    name: ClassVar[str] = "octbot_ring"
    description: ClassVar[str] = "OctBot rear ring: mounting plate, tube with undercut and lip"
    support: ClassVar[str] = "the lip overhangs the undercut inside the tube (support in the bore)"
    print_rotation: ClassVar = (((0.0, 1.0, 0.0), -90.0),)

    @property
    def plate_z_mm(self) -> tuple[float, float]:
        """z range of the mounting plate (robot frame: the underside at 0, the 30 mm body's top at 30),
        ``plate_half_mm`` about the ring's centre where the body allows, mm."""
        s = self.spec
        zc, h = s.centre_z_mm, s.plate_half_mm
        return (zc - min(h, zc - 0.5), zc + min(h, 30 - zc))

    def build(self):
        from cubot_cad.shapes import X, box, cone, cut_all, cyl

        s = self.spec
        zc = s.centre_z_mm
        h = s.plate_half_mm
        plate = box(0, s.plate_mm, -h, h, *self.plate_z_mm)
        tube = cyl(s.outer_radius_mm, s.ring_length_mm - s.plate_mm + 0.01, (s.plate_mm - 0.005, 0, zc), X)
        body = plate.fuse(tube).clean()
        bore = cyl(s.undercut_radius_mm, s.undercut_mm + 0.01, (s.plate_mm, 0, zc), X)
        lip = cyl(s.lip_radius_mm, s.lip_mm + 0.2, (s.plate_mm + s.undercut_mm - 0.1, 0, zc), X)
        cut = [bore, lip]
        ch = s.lip_chamfer_mm
        if ch > 0:  # the lead-in: a 45 deg cone on the lip's mouth
            cut.append(cone(s.lip_radius_mm + ch + 0.1, s.lip_radius_mm, ch + 0.1, (s.ring_length_mm + 0.1, 0, zc),
                            (-1.0, 0.0, 0.0)))
        from cubot_cad.hardware.fasteners import clearance_hole_mm

        r_screw = clearance_hole_mm(s.screw_size) / 2
        screws = [cyl(r_screw, s.plate_mm + 0.2, (-0.1, y, zc), X) for y in s.mount_ys_mm]
        return cut_all(body, cut + screws)


#: The worm gearmotor (N20: 12 x 10 x 24 mm gearbox and motor; x, z, y in the housing) and the length
#: of bare shaft between its gearbox face and the worm, mm.
WORM_MOTOR_MM = (12.0, 10.0, 24.0)
WORM_SHAFT_GAP_MM = 3.5


def cam_slot_outline(spec: RingSpec, finger_deg: float, samples: int = 61) -> list[tuple[float, float]]:
    """(y, z) outline of the cam disc's slot for the finger at ``finger_deg`` (0 = +z; the disc frame:
    capture axis at y = z = 0, the disc at rest).

    With the disc turned by theta (0 .. ``cam_turn_deg``, positive about +x), the finger's peg, held on
    its radial line by the housing's slot, sits at radius :meth:`RingSpec.peg_radius_at_mm` (theta);
    in the disc's frame that point is at angle ``finger_deg - theta``. The slot is that curve (an
    Archimedean spiral) swept by a circle of the peg's radius plus the clearance, with round ends."""
    a0 = math.radians(finger_deg)
    T = math.radians(spec.cam_turn_deg)
    k = spec.finger_travel_mm / T
    w = spec.cam_slot_half_mm
    left, right, ends = [], [], []
    for i in range(samples):
        th = T * i / (samples - 1)
        rho = spec.finger_radius_mm - spec.finger_travel_mm + k * th
        psi = a0 - th
        u = (-math.sin(psi), math.cos(psi))
        v = (math.cos(psi), math.sin(psi))
        p = (rho * u[0], rho * u[1])
        t = (k * u[0] + rho * v[0], k * u[1] + rho * v[1])
        n = math.hypot(*t)
        t = (t[0] / n, t[1] / n)
        nn = (-t[1], t[0])
        left.append((p[0] + w * nn[0], p[1] + w * nn[1]))
        right.append((p[0] - w * nn[0], p[1] - w * nn[1]))
        ends.append((p, math.atan2(t[1], t[0])))
    out = list(left)

    def cap(p, ang0):
        return [(p[0] + w * math.cos(ang0 - math.pi * j / 12), p[1] + w * math.sin(ang0 - math.pi * j / 12))
                for j in range(1, 12)]

    (p1, g1), (p0, g0) = ends[-1], ends[0]
    out += cap(p1, g1 + math.pi / 2)  # round the end (+tangent side)
    out += list(reversed(right))
    out += cap(p0, g0 - math.pi / 2)  # round the start (-tangent side)
    # (the caps' 15 deg chords cut under 1 % of w into the round ends: 0.01 mm at the defaults)
    return out


@dataclass(frozen=True)
class CapturerHousing(Part):
    """Front capturer housing (frame: x = 0 on the front face, +x outward; mm).

    It is screwed to the body's front wall from inside: two screws (``spec.screw_size``) through the
    wall's holes into heat-set inserts in the housing's back face, at :attr:`RingSpec.mount_ys_mm` and
    the ring's centre height.

    The finger drive: three radial slots in the front guide the fingers; behind them a slot across the
    housing, open at the top, takes the cam disc (:class:`CamDisc`: dropped in from above, it turns in
    the slot's round bottom on its rim); each finger's peg reaches back into one of the disc's three
    spiral slots. Under the disc a worm (on the shaft of an N20 gearmotor) turns the disc's rim: the
    motor lies along +y in a pocket open at the housing's +y side (it slides in, worm first, into the
    worm's bore under the disc). The worm and the disc's rim are represented by their pitch cylinders,
    ``spec.clearance_mm`` apart (the backlash): gear teeth are left out, their mesh is not modelled."""

    spec: RingSpec = RingSpec()
    length_mm: float = 29.0
    #: The housing's half width (y; 15.5 keeps 0.8 mm round the inserts at the loosest clearance; on +y
    #: it reaches the end of the worm motor's pocket) and half height (z about the ring's centre), mm.
    half_width_mm: float = 15.5
    half_height_mm: float = 12.0
    name: ClassVar[str] = "octbot_capturer_housing"
    description: ClassVar[str] = ("OctBot capturer housing: finger chambers, cam disc slot, worm bore and worm "
                                  "motor pocket, two mounting inserts, two retainer inserts")
    print_rotation: ClassVar = (((0.0, 1.0, 0.0), -90.0),)

    def validate(self) -> None:
        from cubot_cad.hardware.fasteners import thread

        need(self.length_mm >= 20.0, f"length_mm {self.length_mm:g}: the capturer housing needs >= 20 mm")
        ins = thread(self.spec.screw_size)
        y = max(abs(v) for v in self.spec.mount_ys_mm)
        need(at_least(self.half_width_mm - y - ins.insert_hole_mm / 2, MIN_WALL_MM),
             f"CapturerHousing.half_width_mm {self.half_width_mm:g} leaves under {MIN_WALL_MM:g} mm round the "
             f"{ins.insert_hole_mm:g} mm mounting inserts at y = +-{y:g} mm")
        # the inserts stay clear of the motor pocket and the cam slot (from x = 0) and the carrier bore
        x0 = min(self.motor_pocket_mm[0], self.cam_slot_x_mm[0])
        need(at_least(x0 - ins.insert_hole_depth_mm, MIN_WALL_MM)
             and at_least(y - ins.insert_hole_mm / 2 - self.carrier_bore_radius_mm, MIN_WALL_MM),
             f"CapturerHousing.length_mm {self.length_mm:g}: the mounting inserts reach the cam disc, the worm "
             "motor or the carrier bore")
        need(at_least(self.spec.centre_z_mm + self.half_height_mm - self.spec.centre_z_mm - self.spec.cam_radius_mm,
                      MIN_WALL_MM), "the cam disc does not fit under the housing's top")
        # the retainer's inserts stay clear of the cam slot behind them, the centre pocket and the housing's
        # edges, and the motor pocket keeps a wall in front of it
        s = self.spec
        ri = thread(s.retainer_screw_size).insert_hole_mm / 2
        need(at_least(self.front_mm - thread(s.retainer_screw_size).insert_hole_depth_mm - self.cam_slot_x_mm[1],
                      MIN_WALL_MM),
             f"RingSpec.retainer_mm {s.retainer_mm:g}: the retainer's inserts reach the cam disc's slot")
        y0, y1, z0, z1 = self.extent_mm
        for y, z in s.retainer_screw_points_mm:
            need(at_least(max(abs(y), abs(z)) - ri - self.CENTRE_POCKET_HALF_MM, MIN_WALL_MM)
                 and at_least(min(y - y0, y1 - y, s.centre_z_mm + z - z0, z1 - s.centre_z_mm - z) - ri, MIN_WALL_MM),
                 f"RingSpec.retainer_screw_radius_mm {s.retainer_screw_radius_mm:g}: the retainer's inserts leave "
                 f"under {MIN_WALL_MM:g} mm of wall")
        need(at_least(self.front_mm - self.motor_pocket_mm[1], MIN_WALL_MM),
             f"RingSpec.retainer_mm {s.retainer_mm:g} leaves under {MIN_WALL_MM:g} mm in front of the worm motor")

    #: Half size (y, z about the capture axis) of the pocket behind the finger slots, mm.
    CENTRE_POCKET_HALF_MM: ClassVar[float] = 6.0

    @property
    def front_mm(self) -> float:
        """x of the housing's own front face: the retainer plate (``spec.retainer_mm``) takes the rest."""
        return self.length_mm - self.spec.retainer_mm

    @property
    def chamber_x_mm(self) -> float:
        """x of the fingers' chambers' bottom (they run from there to the front face), mm."""
        return self.length_mm - 8.0

    @property
    def chamber_radii_mm(self) -> tuple[float, float]:
        """Radial extent of each finger's chamber (from the capture axis): from the bar's inner face
        fully retracted to its outer face spread, each less/plus the clearance, mm."""
        s = self.spec
        return (s.finger_radius_mm - s.finger_mm / 2 - s.finger_travel_mm - s.clearance_mm,
                s.finger_radius_mm + s.finger_mm / 2 + s.clearance_mm)

    @property
    def chamber_half_width_mm(self) -> float:
        """Half width of each finger's chamber: the shoulders plus the clearance, mm."""
        s = self.spec
        return s.finger_mm / 2 + s.shoulder_mm + s.clearance_mm

    #: Radius of the lightening bore on the axis behind the cam disc, mm.
    carrier_bore_radius_mm: ClassVar[float] = 5.0

    # -- the finger drive (housing frame, mm) -------------------------------------------------
    @property
    def cam_slot_x_mm(self) -> tuple[float, float]:
        """x range of the slot the cam disc turns in (the disc is ``clearance_mm`` off both faces)."""
        s = self.spec
        x1 = self.length_mm - 8.0
        return (x1 - s.cam_disc_mm - 2 * s.clearance_mm, x1)

    @property
    def cam_disc_x_mm(self) -> tuple[float, float]:
        x0, x1 = self.cam_slot_x_mm
        c = self.spec.clearance_mm
        return (x0 + c, x1 - c)

    @property
    def worm_axis_mm(self) -> tuple[float, float]:
        """(x, z) of the worm's axis (along y): under the disc, its pitch cylinder ``clearance_mm`` from
        the disc's rim."""
        s = self.spec
        x0, x1 = self.cam_disc_x_mm
        return ((x0 + x1) / 2, s.centre_z_mm - s.cam_radius_mm - s.clearance_mm - s.worm_radius_mm)

    @property
    def worm_y_mm(self) -> tuple[float, float]:
        """y range of the worm and the bare shaft behind it (to 0.3 mm off the gearbox face)."""
        return (-self.spec.worm_length_mm / 2, self.motor_y_mm[0] - 0.3)

    @property
    def motor_y_mm(self) -> tuple[float, float]:
        y0 = self.spec.worm_length_mm / 2 + WORM_SHAFT_GAP_MM
        return (y0, y0 + WORM_MOTOR_MM[2])

    @property
    def motor_box_mm(self) -> tuple[float, float, float, float, float, float]:
        """The worm gearmotor's box (x0, x1, y0, y1, z0, z1)."""
        xw, zw = self.worm_axis_mm
        a, b = WORM_MOTOR_MM[0] / 2, WORM_MOTOR_MM[1] / 2
        y0, y1 = self.motor_y_mm
        return (xw - a, xw + a, y0, y1, zw - b, zw + b)

    @property
    def motor_pocket_mm(self) -> tuple[float, float, float, float, float, float]:
        """The pocket: the motor's box plus the clearance, open at the housing's +y side."""
        c = self.spec.clearance_mm
        x0, x1, y0, y1, z0, z1 = self.motor_box_mm
        return (x0 - c, x1 + c, y0 - c, y1 + 1.0, z0 - c, z1 + c)

    @property
    def extent_mm(self) -> tuple[float, float, float, float]:
        """(y0, y1, z0, z1) of the housing's block."""
        zc = self.spec.centre_z_mm
        _, _, _, y1, z0, _ = self.motor_box_mm
        return (-self.half_width_mm, max(self.half_width_mm, y1), min(zc - self.half_height_mm, z0 - 1.6),
                zc + self.half_height_mm)

    def insert_points_mm(self) -> list[tuple[float, float]]:
        """(y, z) of the mounting inserts in the back face (housing frame)."""
        return [(y, self.spec.centre_z_mm) for y in self.spec.mount_ys_mm]

    def build(self):
        from cubot_cad.shapes import X, Y, box, cut_all, cyl, rotated

        s = self.spec
        zc = s.centre_z_mm
        Lh = self.length_mm
        from cubot_cad.hardware.fasteners import thread

        y0, y1, z0, z1 = self.extent_mm
        body = box(0, self.front_mm, y0, y1, z0, z1)
        cut = [cyl(self.carrier_bore_radius_mm, self.cam_slot_x_mm[0] - 3.0 + 0.01, (3.0, 0, zc), X)]
        ins = thread(s.screw_size)
        cut += [cyl(ins.insert_hole_mm / 2, ins.insert_hole_depth_mm + 0.1, (-0.1, y, z), X)
                for y, z in self.insert_points_mm()]
        # the fingers' chambers behind the retainer: as wide as their shoulders plus the clearance
        xf = self.front_mm
        r0, r1 = self.chamber_radii_mm
        a = self.chamber_half_width_mm
        for ang in s.FINGER_ANGLES_DEG:
            slot = box(self.chamber_x_mm, xf + 0.1, -a, a, r0, r1)
            cut.append(rotated(slot, X, ang).translate((0, 0, zc)))
        p = self.CENTRE_POCKET_HALF_MM
        cut.append(box(Lh - 8, xf + 0.1, -p, p, -p + zc, p + zc))
        # the retainer's inserts in the front face
        ri = thread(s.retainer_screw_size)
        cut += [cyl(ri.insert_hole_mm / 2, ri.insert_hole_depth_mm + 0.1, (xf + 0.1, y, zc + z), (-1.0, 0.0, 0.0))
                for y, z in s.retainer_screw_points_mm]
        # the cam disc's slot: round at the bottom (the disc turns on its rim), open at the top
        xs0, xs1 = self.cam_slot_x_mm
        rc = s.cam_radius_mm + s.clearance_mm
        cut.append(cyl(rc, xs1 - xs0, (xs0, 0, zc), X))
        cut.append(box(xs0, xs1, -rc, rc, zc, z1 + 0.1))
        # the worm's bore (blind at -y) and the motor's pocket (open at +y)
        xw, zw = self.worm_axis_mm
        wy0, _ = self.worm_y_mm
        yb0 = wy0 - s.clearance_mm
        cut.append(cyl(s.worm_radius_mm + s.clearance_mm, self.motor_y_mm[0] - yb0 + 0.01, (xw, yb0, zw), Y))
        px0, px1, py0, py1, pz0, pz1 = self.motor_pocket_mm
        cut.append(box(px0, px1, py0, max(py1, y1 + 0.1), pz0, pz1))
        return cut_all(body, cut)


@dataclass(frozen=True)
class FingerRetainer(Part):
    """The plate over the capturer housing's front (housing frame, from ``housing.front_mm`` to the
    housing's length, mm): three radial slots as wide as the fingers' bars plus the clearance and long
    enough for their hooks (it goes on over the hooks, from the front, after the fingers), too narrow
    for the shoulders on the fingers' tails, which bear on its back face if a finger is pulled along
    +x; two countersunk screws (``spec.retainer_screw_size``, flush with the docking face) into the
    housing's inserts. The docked ring's face bears on its front."""

    spec: RingSpec = RingSpec()
    housing_mm: float = 29.0
    name: ClassVar[str] = "octbot_finger_retainer"
    description: ClassVar[str] = ("OctBot capturer finger retainer: front plate, slots pass the fingers' bars and "
                                  "hooks but not their shoulders, two countersunk screws")
    print_rotation: ClassVar = (((0.0, 1.0, 0.0), -90.0),)
    print_orientation: ClassVar[str] = "flat, back face down (the countersinks open upward)"

    @property
    def housing(self) -> CapturerHousing:
        return CapturerHousing(spec=self.spec, length_mm=self.housing_mm)

    def build(self):
        from cubot_cad.hardware.fasteners import clearance_hole_mm, countersunk_head_mm
        from cubot_cad.shapes import X, box, cone, cut_all, cyl, rotated

        s, hs = self.spec, self.housing
        zc, Lh, xf = s.centre_z_mm, self.housing_mm, hs.front_mm
        y0, y1, z0, z1 = hs.extent_mm
        plate = box(xf, Lh, y0, y1, z0, z1)
        r0, r1 = s.retainer_slot_radii_mm
        a = s.finger_mm / 2 + s.clearance_mm
        cut = [rotated(box(xf - 0.1, Lh + 0.1, -a, a, r0, r1), X, ang).translate((0, 0, zc)) for ang in s.FINGER_ANGLES_DEG]
        rc = clearance_hole_mm(s.retainer_screw_size) / 2
        R = countersunk_head_mm(s.retainer_screw_size)[0] / 2 + s.clearance_mm
        for y, z in s.retainer_screw_points_mm:
            cut.append(cyl(rc, Lh - xf + 0.2, (xf - 0.1, y, zc + z), X))
            cut.append(cone(R + 0.1, rc, R + 0.1 - rc, (Lh + 0.1, y, zc + z), (-1.0, 0.0, 0.0)))  # flush head
        return cut_all(plate, cut)


@dataclass(frozen=True)
class CamDisc(Part):
    """The finger drive's cam disc (frame: housing frame, capture axis at y = z = 0, at rest): a disc
    of ``spec.cam_radius_mm`` in the housing's cam slot with three spiral slots
    (:func:`cam_slot_outline`), one per finger peg; turning it by theta sets the fingers' radial
    offset :meth:`RingSpec.finger_offset_mm` (theta). Its rim is the worm wheel's pitch cylinder (the
    teeth are left out)."""

    spec: RingSpec = RingSpec()
    housing_mm: float = 29.0
    name: ClassVar[str] = "octbot_finger_cam_disc"
    description: ClassVar[str] = "OctBot capturer cam disc: three spiral slots drive the fingers' pegs, turned by the worm"
    print_rotation: ClassVar = (((0.0, 1.0, 0.0), -90.0),)
    print_orientation: ClassVar[str] = "flat on a face, the slots vertical"

    @property
    def x_mm(self) -> tuple[float, float]:
        return CapturerHousing(spec=self.spec, length_mm=self.housing_mm).cam_disc_x_mm

    def build(self):
        from cubot_cad.shapes import X, cut_all, cyl, prism

        s = self.spec
        x0, x1 = self.x_mm
        disc = cyl(s.cam_radius_mm, x1 - x0, (x0, 0, 0), X)
        slots = [prism(cam_slot_outline(s, ang), "YZ", x0 - 0.1, x1 - x0 + 0.2) for ang in s.FINGER_ANGLES_DEG]
        return cut_all(disc, slots)


@dataclass(frozen=True)
class Finger(Part):
    """One capturer finger (frame: housing frame, finger pointing +z before rotation), with the peg on
    its tail that runs in the cam disc's slot."""

    spec: RingSpec = RingSpec()
    housing_mm: float = 29.0
    name: ClassVar[str] = "octbot_finger"
    description: ClassVar[str] = ("OctBot capturer finger with hook, cam peg and the shoulders the retainer holds "
                                  "(three per robot)")
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 90.0),)

    @property
    def tip_x_mm(self) -> float:
        s = self.spec
        return self.housing_mm + s.lip_mm + s.clearance_mm + s.hook_mm

    @property
    def tail_x_mm(self) -> float:
        """x of the finger's tail (``clearance_mm`` off its chamber's bottom), mm."""
        return CapturerHousing(spec=self.spec, length_mm=self.housing_mm).chamber_x_mm + self.spec.clearance_mm

    @property
    def shoulder_end_x_mm(self) -> float:
        """x of the shoulders' front faces: ``clearance_mm`` short of the retainer's back face, mm."""
        s = self.spec
        return self.housing_mm - s.retainer_mm - s.clearance_mm

    @property
    def hook_top_mm(self) -> float:
        """Radial reach of the hook (from the capture axis): the lip's bore plus the overlap, mm."""
        return self.spec.lip_radius_mm + self.spec.hook_overlap_mm

    @property
    def peg_x_mm(self) -> tuple[float, float]:
        """x range of the peg: from 0.5 mm short of the disc's back face to the finger's tail."""
        s = self.spec
        d0, _ = CapturerHousing(spec=s, length_mm=self.housing_mm).cam_disc_x_mm
        return (d0 + 0.5, self.tail_x_mm)

    def build(self):
        from cubot_cad.shapes import X, box, cyl, prism

        s = self.spec
        r, a = s.finger_radius_mm, s.finger_mm / 2
        x0 = self.tail_x_mm
        xt = self.tip_x_mm
        # the bar's outer face is rounded to the lip's bore less the clearance: spread, its corners
        # (at sqrt((r + a)^2 + a^2)) would otherwise reach into the lip at small clearances
        bar = box(x0, xt, -a, a, r - a, r + a).intersect(
            cyl(s.lip_radius_mm - s.clearance_mm, xt - x0 + 2.0, (x0 - 1.0, 0, 0), X))
        zt = self.hook_top_mm
        hook = box(xt - s.hook_mm, xt, -a, a, r - a, zt)
        p0, p1 = self.peg_x_mm
        peg = cyl(s.peg_radius_mm, p1 - p0 + 0.5, (p0, 0, r), X)  # 0.5 mm into the bar: one body
        # the shoulders: the tail widened by shoulder_mm each side up to the clearance short of the retainer
        xs = self.shoulder_end_x_mm
        shoulder = box(x0, xs, -a - s.shoulder_mm, a + s.shoulder_mm, r - a, r + a).intersect(
            cyl(s.lip_radius_mm - s.clearance_mm, xs - x0 + 2.0, (x0 - 1.0, 0, 0), X))
        body = bar.fuse(hook, peg, shoulder).clean()
        ch = s.hook_chamfer_mm
        if ch > 0:  # the lead-in: the hook's leading outer edge chamfered 45 deg
            body = body.cut(prism([(xt + 0.01, zt - ch - 0.01), (xt + 0.01, zt + 0.01), (xt - ch - 0.01, zt + 0.01)],
                                  "XZ", -a - 0.1, 2 * a + 0.2))
        return body


@dataclass(frozen=True)
class OctBotBody(Part):
    across_flats_mm: float = 100.0
    height_mm: float = 30.0
    wall_mm: float = 2.0
    floor_mm: float = 2.4
    wheel_radius_mm: float = 16.0
    wheel_width_mm: float = 6.0
    wheel_base_mm: float = 70.0
    caster_x_mm: float = 36.0
    ring_centre_z_mm: float = 16.0
    #: The ring's and the capturer housing's two screws go through the rear and front walls at
    #: y = +-``mount_y_mm`` (:attr:`RingSpec.mount_ys_mm`), mm.
    mount_y_mm: float = 12.0
    screw_size: str = "M3"
    name: ClassVar[str] = "octbot_body"
    description: ClassVar[str] = "OctBot body: octagonal tray, wheel slots, IR windows, mounting holes"

    def validate(self) -> None:
        self.wall_check("wall_mm", self.wall_mm)
        self.wall_check("floor_mm", self.floor_mm)

    def build(self):
        from cubot_cad.hardware.fasteners import clearance_hole_mm
        from cubot_cad.shapes import X, Z, box, cut_all, cyl, prism, regular_polygon, rotated

        af, H, w = self.across_flats_mm, self.height_mm, self.wall_mm
        outer = prism(regular_polygon(8, af), "XY", 0, H)
        inner = prism(regular_polygon(8, af - 2 * w), "XY", self.floor_mm, H)
        body = outer.cut(inner)
        cut = []
        r = self.wheel_radius_mm + 1.5
        for yw in (-self.wheel_base_mm / 2, self.wheel_base_mm / 2):
            a = self.wheel_width_mm / 2 + 1.5
            cut.append(box(-r, r, yw - a, yw + a, -1, self.floor_mm + 1))
        r_screw = clearance_hole_mm(self.screw_size) / 2
        cut += [cyl(r_screw, self.floor_mm + 2, (x, 0, -1), Z) for x in (-self.caster_x_mm, self.caster_x_mm)]
        # 8 IR LED windows (one per face) and 4 photodiode windows (front, rear, sides)
        for k in range(8):
            win = box(af / 2 - w - 1, af / 2 + 1, -3, 3, 17, 21)
            cut.append(rotated(win, Z, 45 * k))
        for k in range(4):
            cut.append(rotated(box(af / 2 - w - 1, af / 2 + 1, 8, 12, 17, 21), Z, 90 * k))
        # ring/housing screw holes, colour sensor and edge detector windows in the floor
        zc = self.ring_centre_z_mm
        for x0 in (af / 2 - w - 1, -af / 2 - 1):
            cut += [cyl(r_screw, w + 2, (x0, y, zc), X) for y in (-self.mount_y_mm, self.mount_y_mm)]
        cut.append(box(20, 26, -4, 4, -1, self.floor_mm + 1))
        cut.append(box(af / 2 - w - 8, af / 2 - w - 3, -3, 3, -1, self.floor_mm + 1))
        return cut_all(body, cut)


@dataclass(frozen=True)
class OctBot(Robot):
    across_flats_mm: float = 100.0
    height_mm: float = 30.0
    wall_mm: float = 2.0
    floor_mm: float = 2.4
    wheel_radius_mm: float = 16.0
    wheel_width_mm: float = 6.0
    wheel_base_mm: float = 70.0
    wheel_exposed_mm: float = 8.0
    caster_ball_mm: float = 6.0
    caster_x_mm: float = 36.0
    docked_gap_mm: float = 40.0
    #: The 6 mm caster's seat leaves only 1.3-1.7 mm above its socket (by the clearance): no room for
    #: a screw, the seats are glued under the floor (0 = no tap hole).
    caster_screw_depth_mm: float = 0.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    ring: RingSpec | None = None

    name: ClassVar[str] = "octbot"
    title: ClassVar[str] = "OctBot"

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        check_dims(self, ("across_flats_mm", "height_mm", "wall_mm", "floor_mm", "wheel_radius_mm",
                          "wheel_width_mm", "wheel_base_mm", "wheel_exposed_mm", "caster_ball_mm",
                          "caster_x_mm", "docked_gap_mm"))
        need(self.across_flats_mm <= 100 and self.height_mm <= 30,
             f"across_flats_mm {self.across_flats_mm:g} x height_mm {self.height_mm:g} is outside the OctBot "
             "envelope 100 x 100 x 30 mm")
        need(self.docked_gap_mm >= MIN_SENSOR_GAP_MM,
             f"docked_gap_mm {self.docked_gap_mm:g} is below {MIN_SENSOR_GAP_MM:g} mm: the proximity sensors "
             "cannot guide the capturer closer (thesis Ch. 6.3.2.1)")
        need(self.wall_mm >= MIN_WALL_MM and self.floor_mm >= MIN_WALL_MM,
             f"wall_mm/floor_mm must be >= {MIN_WALL_MM:g} mm")
        rs = self.ring_spec
        need(abs(rs.clearance_mm - self.clearance_mm) < 1e-12,
             f"ring.clearance_mm {rs.clearance_mm:g} differs from clearance_mm {self.clearance_mm:g}")
        need(self.wheel_exposed_mm < self.wheel_radius_mm,
             f"wheel_exposed_mm {self.wheel_exposed_mm:g} must be less than wheel_radius_mm {self.wheel_radius_mm:g}")
        need(self.wheel_base_mm / 2 + self.wheel_width_mm / 2 + 1.5 <= self.across_flats_mm / 2 - self.wall_mm - 4,
             f"wheel_base_mm {self.wheel_base_mm:g} puts the wheels into the walls")
        CapturerHousing(spec=rs, length_mm=self.housing_mm)
        CasterSeat(ball_diameter_mm=self.caster_ball_mm, wheel_exposed_mm=self.wheel_exposed_mm,
                   outer_diameter_mm=self.caster_ball_mm + 4, screw_depth_mm=self.caster_screw_depth_mm,
                   clearance_mm=self.clearance_mm)

    @cached_property
    def ring_spec(self) -> RingSpec:
        return self.ring or RingSpec(clearance_mm=self.clearance_mm)

    @property
    def housing_mm(self) -> float:
        """Capturer housing length: what the docked gap leaves after the ring."""
        return self.docked_gap_mm - self.ring_spec.ring_length_mm

    @property
    def envelope_mm(self):
        return (self.across_flats_mm, self.across_flats_mm, self.height_mm)

    @cached_property
    def body(self) -> OctBotBody:
        return OctBotBody(across_flats_mm=self.across_flats_mm, height_mm=self.height_mm, wall_mm=self.wall_mm,
                          floor_mm=self.floor_mm, wheel_radius_mm=self.wheel_radius_mm,
                          wheel_width_mm=self.wheel_width_mm, wheel_base_mm=self.wheel_base_mm,
                          caster_x_mm=self.caster_x_mm, ring_centre_z_mm=self.ring_spec.centre_z_mm,
                          mount_y_mm=max(self.ring_spec.mount_ys_mm))

    @property
    def housing(self) -> CapturerHousing:
        return CapturerHousing(spec=self.ring_spec, length_mm=self.housing_mm)

    def finger_offset_mm(self, disc_deg: float) -> float:
        """The fingers' radial offset from spread (holding) for the cam disc at ``disc_deg``
        (:meth:`RingSpec.finger_offset_mm`: -finger_travel_mm retracted at 0 deg, 0 spread at
        ``ring_spec.cam_turn_deg``), mm."""
        return self.ring_spec.finger_offset_mm(disc_deg)

    def disc_deg_for(self, fingers_open: bool) -> float:
        """The cam disc's angle for the two end states: 0 = fingers retracted (they pass the ring's
        lip), ``cam_turn_deg`` = fingers spread behind the lip (``fingers_open``, the docked hold)."""
        return self.ring_spec.cam_turn_deg if fingers_open else 0.0

    def build_placed(self, fingers_open: bool = False, disc_deg: float | None = None) -> list[Placed]:
        """The parts as assembled. The capturer's cam disc is turned by ``disc_deg`` (0 ..
        ``ring_spec.cam_turn_deg``) and the fingers sit where it drives them; without ``disc_deg``,
        at the end ``fingers_open`` names (:meth:`disc_deg_for`)."""
        from cubot_cad.shapes import location

        h = self.across_flats_mm / 2
        rs = self.ring_spec
        deg = self.disc_deg_for(fingers_open) if disc_deg is None else float(disc_deg)
        shift = rs.finger_offset_mm(deg)
        out = [Placed(self.body, location(), "body"),
               Placed(OctRing(spec=rs), location((-h, 0, 0), 180), "ring"),
               Placed(self.housing, location((h, 0, 0)), "housing"),
               Placed(CamDisc(spec=rs, housing_mm=self.housing_mm), location((h, 0, rs.centre_z_mm), 0, deg),
                      "cam_disc")]
        finger = Finger(spec=rs, housing_mm=self.housing_mm)
        for ang in rs.FINGER_ANGLES_DEG:
            loc = location((h, 0, rs.centre_z_mm)) * location((0, 0, 0), 0, ang) * location((0, 0, shift))
            out.append(Placed(finger, loc, "finger"))
        out.append(Placed(FingerRetainer(spec=rs, housing_mm=self.housing_mm), location((h, 0, 0)), "retainer"))
        seat = CasterSeat(ball_diameter_mm=self.caster_ball_mm, wheel_exposed_mm=self.wheel_exposed_mm,
                          outer_diameter_mm=self.caster_ball_mm + 4, screw_depth_mm=self.caster_screw_depth_mm,
                   clearance_mm=self.clearance_mm)
        for x in (-self.caster_x_mm, self.caster_x_mm):
            out.append(Placed(seat, location((x, 0, 0)), "caster_seat"))
        return out

    def components(self) -> list[Component]:
        axle = self.wheel_radius_mm - self.wheel_exposed_mm
        wb = self.wheel_base_mm / 2
        ball_z = -self.wheel_exposed_mm + self.caster_ball_mm / 2
        h = self.across_flats_mm / 2
        gap = 0.3
        motor_y = wb - self.wheel_width_mm / 2 - gap - 12.0  # the gearbox face 0.3 mm from the wheel
        mb = self.housing.motor_box_mm
        xw, zw = self.housing.worm_axis_mm
        wy = self.housing.worm_y_mm
        return [
            Component("drive_motor", "micro metal gearmotor (N20: 12 x 10 x 24 mm)", 10.0,
                      ((0.0, -motor_y, axle + 4), (0.0, motor_y, axle + 4)), (12.0, 24.0, 10.0), "box", "motor",
                      (0.3, 0.3, 0.3)),
            Component("wheel", f"drive wheel, {2 * self.wheel_radius_mm:g} mm", 5.0,
                      ((0.0, -wb, axle), (0.0, wb, axle)), (2 * self.wheel_radius_mm, self.wheel_width_mm),
                      "cyl_y", "wheel", (0.1, 0.1, 0.1)),
            Component("caster_ball", f"steel ball, {self.caster_ball_mm:g} mm (adjustable caster)", 0.9,
                      ((-self.caster_x_mm, 0.0, ball_z), (self.caster_x_mm, 0.0, ball_z)),
                      (self.caster_ball_mm,), "sphere", "caster", (0.7, 0.7, 0.75)),
            # flat on the floor behind the drive motors, its 50 mm across the robot (between the wheels)
            Component("battery", "3.7 V 1200 mAh LiPo (thesis), 50 x 34 x 6 mm", 25.0,
                      ((-(6.0 + gap + 17.0), 0.0, self.floor_mm + gap + 3.0),),
                      (34.0, 50.0, 6.0), "box", "power", (0.8, 0.5, 0.1)),
            # under the open top, inside the octagon (a 66 mm square's corners stay inside its walls)
            Component("main_board", "ARM Cortex-M0 board with IMU, colour sensor, IR LEDs/photodiodes", 12.0,
                      ((0.0, 0.0, self.height_mm - 4.0),), (66.0, 66.0, 4.0)),
            # in the capturer housing's pocket (open at its +y side), along y under the cam disc
            Component("worm_motor", "N20 micro gearmotor (12 x 10 x 24 mm) turning the capturer's worm", 10.0,
                      ((h + (mb[0] + mb[1]) / 2, (mb[2] + mb[3]) / 2, (mb[4] + mb[5]) / 2),),
                      (mb[1] - mb[0], mb[3] - mb[2], mb[5] - mb[4]), "box", "motor", (0.3, 0.3, 0.3)),
            Component("worm", f"worm on the worm motor's shaft (pitch diameter {2 * self.ring_spec.worm_radius_mm:g} mm, "
                      "module 0.5, driving the cam disc's rim)", 1.0,
                      ((h + xw, (wy[0] + wy[1]) / 2, zw),), (2 * self.ring_spec.worm_radius_mm, wy[1] - wy[0]),
                      "cyl_y", "motor", (0.7, 0.6, 0.3)),
            Component("fasteners", "M2/M3 screws", 5.0, ((0.0, 0.0, self.height_mm / 2),), (60.0, 60.0, 20.0),
                      "box", "hardware", (0.6, 0.6, 0.6), lump=True),
        ]

    def fasteners(self) -> list:
        from cubot_cad.hardware.fasteners import bolted

        rs, n = self.ring_spec, self.name
        out = bolted(n, rs.screw_size, rs.plate_mm + self.wall_mm, 2, "ring plate to the rear wall", nut=True)
        out += bolted(n, rs.screw_size, self.wall_mm, len(rs.mount_ys_mm),
                      "capturer housing: from inside the body through the front wall into the housing's inserts",
                      insert=True)
        from cubot_cad.hardware.fasteners import countersunk_head_mm

        out += bolted(n, rs.retainer_screw_size, rs.retainer_mm, len(rs.retainer_screw_points_mm),
                      "finger retainer: flush through the plate into the housing's front inserts", insert=True,
                      kind=countersunk_head_mm(rs.retainer_screw_size)[2])
        if self.caster_screw_depth_mm > 0:
            out += bolted(n, rs.screw_size, self.floor_mm, 2, "caster seats (into the seat's tap hole)",
                          thread_mm=self.caster_screw_depth_mm)
        return out

    def connector_properties(self, youngs_modulus_pa: float, gaps_mm: dict | None = None) -> tuple:
        rs = self.ring_spec
        gap = (gaps_mm or {}).get("ring_capture", self.docked_gap_mm)
        finger_len = 8 + rs.lip_mm + rs.hook_mm
        return (couplings.ring_capture(rs.finger_mm ** 2, finger_len, rs.finger_radius_mm, rs.outer_radius_mm,
                                       rs.clearance_mm, gap, youngs_modulus_pa, rs.centre_z_mm),)

