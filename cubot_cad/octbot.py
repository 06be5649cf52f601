"""OctBot (thesis Ch. 6.3.2): octagonal prism <= 100 x 100 x 30 mm (without connectors),
differential drive, two adjustable ball casters, ring-and-capture coupling.

Rear: a ring (a short tube with an inner lip) on a mounting plate. Front: the
capturer housing (worm-screw bore) with three fingers at 90/210/330 deg; the
fingers pass the lip closed, open behind it and pull the ring against the
housing. The docked gap (face to face) is ``docked_gap_mm`` (thesis: it cannot
be less than 40 mm because of the proximity sensors' reading range); the
housing length follows from it and the ring's geometry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import ClassVar

from . import couplings
from .components import Component
from .connectors import CasterSeat
from .cubot import check_dims
from .part import DEFAULT_CLEARANCE_MM, MIN_WALL_MM, Part, at_least, at_most, check_clearance, need
from .robot import Placed, Robot

MIN_SENSOR_GAP_MM = 40.0


@dataclass(frozen=True)
class RingSpec:
    """Ring and capturer dimensions (mm). Ring frame: x = 0 on the robot's rear face, +x outward."""

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
        from .fasteners import thread

        thread(self.screw_size)
        check_dims(self, ("plate_mm", "lip_mm", "lip_radius_mm", "tube_wall_mm", "finger_mm", "hook_mm",
                          "hook_overlap_mm", "finger_travel_mm", "centre_z_mm"))
        for n in ("plate_mm", "lip_mm", "tube_wall_mm", "finger_mm", "hook_mm"):
            need(at_least(getattr(self, n), MIN_WALL_MM), f"{n} {getattr(self, n):g} is thinner than {MIN_WALL_MM:g} mm")
        need(at_least(self.finger_travel_mm, self.hook_overlap_mm + self.clearance_mm),
             f"finger_travel_mm {self.finger_travel_mm:g} cannot pull the hooks ({self.hook_overlap_mm:g} mm) "
             "back through the lip")
        need(at_least(self.finger_radius_mm - self.finger_mm / 2 - self.finger_travel_mm, 0.5),
             f"lip_radius_mm {self.lip_radius_mm:g} is too small for three {self.finger_mm:g} mm fingers that close "
             f"by {self.finger_travel_mm:g} mm")

    @property
    def finger_radius_mm(self) -> float:
        """Radius of the finger bars' centres when open (touching the lip less a clearance)."""
        return self.lip_radius_mm - self.clearance_mm - self.finger_mm / 2

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

    def build(self):
        from .shapes import X, box, cone, cut_all, cyl

        s = self.spec
        zc = s.centre_z_mm
        h = s.plate_half_mm
        plate = box(0, s.plate_mm, -h, h, zc - min(h, zc - 0.5), zc + min(h, 30 - zc))
        tube = cyl(s.outer_radius_mm, s.ring_length_mm - s.plate_mm + 0.01, (s.plate_mm - 0.005, 0, zc), X)
        body = plate.fuse(tube).clean()
        bore = cyl(s.undercut_radius_mm, s.undercut_mm + 0.01, (s.plate_mm, 0, zc), X)
        lip = cyl(s.lip_radius_mm, s.lip_mm + 0.2, (s.plate_mm + s.undercut_mm - 0.1, 0, zc), X)
        cut = [bore, lip]
        ch = s.lip_chamfer_mm
        if ch > 0:  # the lead-in: a 45 deg cone on the lip's mouth
            cut.append(cone(s.lip_radius_mm + ch + 0.1, s.lip_radius_mm, ch + 0.1, (s.ring_length_mm + 0.1, 0, zc),
                            (-1.0, 0.0, 0.0)))
        from .fasteners import clearance_hole_mm

        r_screw = clearance_hole_mm(s.screw_size) / 2
        screws = [cyl(r_screw, s.plate_mm + 0.2, (-0.1, y, zc), X) for y in s.mount_ys_mm]
        return cut_all(body, cut + screws)


@dataclass(frozen=True)
class CapturerHousing(Part):
    """Front capturer housing (frame: x = 0 on the front face, +x outward; mm).

    It is screwed to the body's front wall from inside: two screws (``spec.screw_size``) through the
    wall's holes into heat-set inserts in the housing's back face, at :attr:`RingSpec.mount_ys_mm` and
    the ring's centre height. (The finger drive, a worm on a motor in a pocket of the housing, is not
    built yet: issue 15.)"""

    spec: RingSpec = RingSpec()
    length_mm: float = 29.0
    #: The housing's half width (y; 15.5 keeps 0.8 mm round the inserts at the loosest clearance) and
    #: half height (z about the ring's centre), mm.
    half_width_mm: float = 15.5
    half_height_mm: float = 12.0
    name: ClassVar[str] = "octbot_capturer_housing"
    description: ClassVar[str] = "OctBot capturer housing: worm-screw bore, finger slots, two mounting inserts"
    print_rotation: ClassVar = (((0.0, 1.0, 0.0), -90.0),)

    def validate(self) -> None:
        from .fasteners import thread

        need(self.length_mm >= 20.0, f"length_mm {self.length_mm:g}: the worm-screw housing needs >= 20 mm")
        ins = thread(self.spec.screw_size)
        y = max(abs(v) for v in self.spec.mount_ys_mm)
        need(at_least(self.half_width_mm - y - ins.insert_hole_mm / 2, MIN_WALL_MM),
             f"CapturerHousing.half_width_mm {self.half_width_mm:g} leaves under {MIN_WALL_MM:g} mm round the "
             f"{ins.insert_hole_mm:g} mm mounting inserts at y = +-{y:g} mm")
        # the inserts stay clear of the worm-screw bore (across y at mid-length) and the carrier bore (on the axis)
        need(at_least(self.length_mm / 2 - self.worm_bore_radius_mm - ins.insert_hole_depth_mm, MIN_WALL_MM)
             and at_least(y - ins.insert_hole_mm / 2 - self.carrier_bore_radius_mm, MIN_WALL_MM),
             f"CapturerHousing.length_mm {self.length_mm:g}: the mounting inserts reach the worm or carrier bore")

    #: Radius of the worm wheel / finger carrier bore on the axis, mm.
    carrier_bore_radius_mm: ClassVar[float] = 5.0

    @property
    def worm_bore_radius_mm(self) -> float:
        """The worm screw's bore (across y at mid-length): a 6 mm worm plus the clearance, mm."""
        return 3.0 + self.spec.clearance_mm

    def insert_points_mm(self) -> list[tuple[float, float]]:
        """(y, z) of the mounting inserts in the back face (housing frame)."""
        return [(y, self.spec.centre_z_mm) for y in self.spec.mount_ys_mm]

    def build(self):
        from .shapes import X, Y, box, cut_all, cyl, rotated

        s = self.spec
        zc = s.centre_z_mm
        Lh = self.length_mm
        from .fasteners import thread

        hw, hh = self.half_width_mm, self.half_height_mm
        body = box(0, Lh, -hw, hw, zc - hh, zc + hh)
        cut = [cyl(self.worm_bore_radius_mm, 2 * hw + 1, (Lh / 2, -hw - 0.5, zc), Y),  # worm screw
               cyl(self.carrier_bore_radius_mm, Lh - 10, (3.0, 0, zc), X)]  # worm wheel / finger carrier
        ins = thread(s.screw_size)
        cut += [cyl(ins.insert_hole_mm / 2, ins.insert_hole_depth_mm + 0.1, (-0.1, y, z), X)
                for y, z in self.insert_points_mm()]
        r0 = s.finger_radius_mm - s.finger_mm / 2 - s.finger_travel_mm - s.clearance_mm
        r1 = s.finger_radius_mm + s.finger_mm / 2 + s.clearance_mm
        a = s.finger_mm / 2 + s.clearance_mm
        for ang in (0.0, 120.0, 240.0):
            slot = box(Lh - 8, Lh + 0.1, -a, a, r0, r1)
            cut.append(rotated(slot, X, ang).translate((0, 0, zc)))
        cut.append(box(Lh - 8, Lh - 3, -6, 6, -6 + zc, 6 + zc))
        return cut_all(body, cut)


@dataclass(frozen=True)
class Finger(Part):
    """One capturer finger (frame: housing frame, finger pointing +z before rotation)."""

    spec: RingSpec = RingSpec()
    housing_mm: float = 29.0
    name: ClassVar[str] = "octbot_finger"
    description: ClassVar[str] = "OctBot capturer finger with hook (three per robot)"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 90.0),)

    @property
    def tip_x_mm(self) -> float:
        s = self.spec
        return self.housing_mm + s.lip_mm + s.clearance_mm + s.hook_mm

    def build(self):
        from .shapes import box, prism

        s = self.spec
        r, a = s.finger_radius_mm, s.finger_mm / 2
        x0 = self.housing_mm - 8 + s.clearance_mm
        xt = self.tip_x_mm
        bar = box(x0, xt, -a, a, r - a, r + a)
        zt = s.lip_radius_mm + s.hook_overlap_mm
        hook = box(xt - s.hook_mm, xt, -a, a, r - a, zt)
        body = bar.fuse(hook).clean()
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
        from .fasteners import clearance_hole_mm
        from .shapes import X, Z, box, cut_all, cyl, prism, regular_polygon, rotated

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

    def build_placed(self, fingers_open: bool = False) -> list[Placed]:
        from .shapes import location

        h = self.across_flats_mm / 2
        rs = self.ring_spec
        out = [Placed(self.body, location(), "body"),
               Placed(OctRing(spec=rs), location((-h, 0, 0), 180), "ring"),
               Placed(CapturerHousing(spec=rs, length_mm=self.housing_mm), location((h, 0, 0)), "housing")]
        finger = Finger(spec=rs, housing_mm=self.housing_mm)
        shift = 0.0 if fingers_open else -rs.finger_travel_mm
        for ang in (0.0, 120.0, 240.0):
            loc = location((h, 0, rs.centre_z_mm)) * location((0, 0, 0), 0, ang) * location((0, 0, shift))
            out.append(Placed(finger, loc, "finger"))
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
        inner = h - self.wall_mm  # the flat walls' inner faces
        from .fasteners import thread

        head = thread(self.ring_spec.screw_size).shcs_head_height_mm  # the housing screws' heads on the front wall
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
            # in the body behind the front wall (and the housing screws' heads), its shaft through the wall
            # into the housing's worm bore
            Component("worm_motor", "micro gearmotor driving the capturer's worm screw (through the front wall)", 10.0,
                      ((inner - head - gap - 5.0, 0.0, self.ring_spec.centre_z_mm),), (10.0, 24.0, 10.0), "box",
                      "motor", (0.3, 0.3, 0.3)),
            Component("fasteners", "M2/M3 screws", 5.0, ((0.0, 0.0, self.height_mm / 2),), (60.0, 60.0, 20.0),
                      "box", "hardware", (0.6, 0.6, 0.6), lump=True),
        ]

    def fasteners(self) -> list:
        from .fasteners import bolted

        rs, n = self.ring_spec, self.name
        out = bolted(n, rs.screw_size, rs.plate_mm + self.wall_mm, 2, "ring plate to the rear wall", nut=True)
        out += bolted(n, rs.screw_size, self.wall_mm, len(rs.mount_ys_mm),
                      "capturer housing: from inside the body through the front wall into the housing's inserts",
                      insert=True)
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

