"""The CuBot's twist-lock drive (issue 15, item 1): the cross key turns on a shaft, driven by a
servo inside the body, in a fixed bearing ring screwed under the floor.

What turns and what does not (key frame: origin on the key axis in the plane of the robot's
underside, z up, x and y as the robot's; the key's cross arms lie along x and y when it is open):

* the **twist key** (:class:`TwistKey`, printed, turns): the cross head of the top-down coupling
  (:class:`~cubot_cad.couplings.connectors.TopTwistSpec`, unchanged: same arms, chamfer and height), a stem,
  a round **thrust disc** just under the floor, and a round **shaft** up through the floor to the
  **hub face** at ``hub_top_mm`` above the underside. The servo horn is screwed to the hub face with
  two M2 screws into tap holes; the IR transmitter's bore runs along the axis and its wires leave
  through a slot in the hub face (under the horn, between its arms);
* the **key bearing** (:class:`KeyBearing`, printed, fixed): a ring under the floor, screwed to it
  with four ISO 10642 countersunk screws (heads flush with its underside, nuts inside the body).
  Its pocket holds the disc: the disc's top bears on the floor when the key is pushed up, its
  underside on the ring's lip when the key is pulled down (a robot lifted off the one it docked on).
  The lip's bore is the key's cross plus the clearance, so the ring slides on over the head;
* the **servo** (a :mod:`cubot_cad.hardware.servos` row, bought, fixed): upside down over the key, its output
  spline on the key axis in the horn's socket, its case towards the rear (-x); its two tabs are
  screwed (M2) onto two bosses rising from the body's floor (:class:`~cubot_cad.robots.cubot.CuBotBody`);
* the **horn** (bought with the servo, turns), its two screws and the servo's output spline turn
  with the key. The horn's arms point along ``horn_open_deg`` when the key is open, so over the
  key's free travel (``travel_deg``, clockwise) they never come near the servo bosses (which lie
  along the servo, at 0 and 180 deg).

Nothing fixed is ever part of the turning set, so the ring's screws always stay in their holes
(the old one-piece key was screwed to the floor by its flange, and the docking model turned the
flange with its screws). Heights, named in :class:`TwistDriveSpec`, are chosen so that:

* the hub face is above the drive motors (their stand-ins end 15 mm above the underside): the
  horn turns over them;
* the ring's underside stays above the lower robot's locking-key lip when docked (stand 15 mm,
  collar and lip 10.2 mm above the lower cover);
* the servo's spline ends ``spline_gap_mm`` beyond the key's axial play short of the horn socket's
  bottom: the key's axial loads go through the disc and the ring, not the servo.

:func:`turning_torque_nm` estimates what the servo must give to turn the key under a tension load;
:func:`hardware` gives the bought parts' stand-ins (servo excepted, a component) for the motion
checks, the docking and pier checks and the assemblies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from cubot_cad.couplings.connectors import TopTwistSpec, _cross, _cross_taper
from cubot_cad.errors import InputError
from cubot_cad.hardware.components import Component
from cubot_cad.part import (
    DEFAULT_CLEARANCE_MM,
    MIN_WALL_MM,
    NOZZLE_MM,
    Part,
    at_least,
    at_most,
    check_clearance,
    need,
)

#: Gap (mm) kept between a bought part's stand-in and what it sits beside (stand-ins are not toleranced).
STANDIN_GAP_MM = 0.3
#: Friction coefficient of printed ABS/PLA on itself (as :data:`cubot_cad.checks.capture.FRICTION`).
FRICTION = 0.5
#: Least radial land (mm) of the thrust disc on the ring's lip, beyond the corners of the lip's cross bore.
MIN_LAND_MM = 2.0
#: Screw shanks are modelled this much under their hole (mm): a shank in its tap hole is the thread's core.
SHANK_UNDERSIZE_MM = 0.05


@dataclass(frozen=True)
class TwistDriveSpec:
    """Dimensions of the twist-lock drive (mm, deg); see the module docstring."""

    servo: str = "SG90"
    #: The key's shaft through the floor; its top is the hub face the horn is screwed to, ``hub_top_mm``
    #: above the underside (a :class:`~cubot_cad.robots.cubot.CuBot` sets it to its drive motors' top +
    #: :data:`STANDIN_GAP_MM` unless given a drive spec).
    shaft_diameter_mm: float = 13.4
    hub_top_mm: float = 15.3
    #: The thrust disc under the floor and the bearing ring round it.
    disc_diameter_mm: float = 20.0
    disc_mm: float = 1.5
    ring_lip_mm: float = 1.5
    ring_diameter_mm: float = 39.0
    ring_screw_radius_mm: float = 15.0
    #: The ring's four screws at +-angle and 180 +- angle from +x (clear of the cross bore's arms).
    ring_screw_angle_deg: float = 40.0
    #: The horn's arms (key frame) when the key is open, and the clockwise travel the drive is laid out for.
    horn_open_deg: float = 135.0
    travel_deg: float = 90.0
    #: The IR transmitter's wires: a slot in the hub face from the bore to the rim.
    wire_slot_mm: float = 1.6
    wire_slot_depth_mm: float = 1.2
    wire_slot_deg: float = 45.0
    #: Width of the servo bosses (across the servo) in the body.
    boss_mm: float = 4.6
    #: The spline's end is this much beyond the key's axial play short of the horn socket's bottom.
    spline_gap_mm: float = 0.1
    #: The ring's screws (ISO 10642 countersunk, nuts inside).
    screw_size: str = "M3"
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "TwistDriveSpec.clearance_mm")
        from cubot_cad.hardware.fasteners import thread
        from cubot_cad.hardware.servos import servo

        sv = servo(self.servo)
        thread(self.screw_size)
        thread(sv.horn.screw_size)
        thread(sv.screw_size)
        for n in ("shaft_diameter_mm", "hub_top_mm", "disc_diameter_mm", "disc_mm", "ring_lip_mm",
                  "ring_diameter_mm", "ring_screw_radius_mm", "wire_slot_mm", "wire_slot_depth_mm", "boss_mm",
                  "spline_gap_mm"):
            v = getattr(self, n)
            need(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0,
                 f"TwistDriveSpec.{n} must be a positive length in mm, got {v!r}")
        for n in ("ring_screw_angle_deg", "horn_open_deg", "travel_deg", "wire_slot_deg"):
            v = getattr(self, n)
            need(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v),
                 f"TwistDriveSpec.{n} must be an angle in degrees, got {v!r}")
        for n in ("disc_mm", "ring_lip_mm", "boss_mm"):
            need(at_least(getattr(self, n), MIN_WALL_MM),
                 f"TwistDriveSpec.{n} {getattr(self, n):g} is thinner than two nozzle widths ({MIN_WALL_MM:g} mm)")
        need(0 < self.travel_deg <= 180, f"TwistDriveSpec.travel_deg {self.travel_deg:g} must be in (0, 180]")
        h = sv.horn
        r_tap = thread(h.screw_size).tap_drill_mm / 2
        need(at_least(self.shaft_diameter_mm / 2, h.hole_radii_mm[0] + r_tap + MIN_WALL_MM),
             f"TwistDriveSpec.shaft_diameter_mm {self.shaft_diameter_mm:g} leaves under {MIN_WALL_MM:g} mm round "
             f"the horn screws' tap holes ({h.hole_radii_mm[0]:g} mm from the axis)")
        need(at_least(self.disc_diameter_mm / 2, self.shaft_diameter_mm / 2 + self.clearance_mm + MIN_LAND_MM),
             f"TwistDriveSpec.disc_diameter_mm {self.disc_diameter_mm:g} overlaps the floor round the "
             f"{self.shaft_diameter_mm:g} mm shaft's hole by under {MIN_LAND_MM:g} mm")
        need(at_most(self.wire_slot_depth_mm, self.hub_top_mm / 2),
             f"TwistDriveSpec.wire_slot_depth_mm {self.wire_slot_depth_mm:g} cuts more than half the key's shaft")
        # the slot between the horn's screws: at least a wall from their tap holes
        gap = min(_point_line_gap(h.hole_radii_mm[0], self.horn_open_deg + k * 180.0, self.wire_slot_deg)
                  for k in (0, 1))
        need(at_least(gap - r_tap - self.wire_slot_mm / 2, MIN_WALL_MM),
             f"TwistDriveSpec.wire_slot_deg {self.wire_slot_deg:g} runs the wire slot within {MIN_WALL_MM:g} mm of "
             f"the horn screws' tap holes (horn_open_deg {self.horn_open_deg:g})")
        R_cs = self.countersink_mm / 2
        need(at_least(self.ring_diameter_mm / 2, self.ring_screw_radius_mm + R_cs + MIN_WALL_MM),
             f"TwistDriveSpec.ring_diameter_mm {self.ring_diameter_mm:g} leaves under {MIN_WALL_MM:g} mm outside "
             f"the ring screws' countersinks (radius {self.ring_screw_radius_mm:g} mm)")
        need(at_least(self.ring_screw_radius_mm - R_cs, self.disc_diameter_mm / 2 + self.clearance_mm + MIN_WALL_MM),
             f"TwistDriveSpec.ring_screw_radius_mm {self.ring_screw_radius_mm:g} puts the countersinks within "
             f"{MIN_WALL_MM:g} mm of the disc's pocket")
        need(at_least(self.countersink_depth_mm, 0.0) and at_most(self.countersink_depth_mm, self.ring_mm - 0.5),
             f"TwistDriveSpec.ring_lip_mm {self.ring_lip_mm:g}: the ring ({self.ring_mm:g} mm) is too thin for "
             f"the {self.screw_size} countersunk heads")

    # -- the servo and horn ----------------------------------------------------------------
    @property
    def servo_row(self):
        from cubot_cad.hardware.servos import servo

        return servo(self.servo)

    @property
    def horn(self):
        return self.servo_row.horn

    # -- derived heights (key frame, z above the underside) -------------------------------
    @property
    def ring_mm(self) -> float:
        """The ring's thickness: the pocket (disc + the key's axial play) and the lip."""
        return self.disc_mm + self.clearance_mm + self.ring_lip_mm

    @property
    def disc_z_mm(self) -> tuple[float, float]:
        """(bottom, top) of the disc: resting on the lip, the key's axial play below the floor."""
        c = self.clearance_mm
        return (-(c + self.disc_mm), -c)

    @property
    def horn_top_mm(self) -> float:
        """Top of the horn's centre cap (the socket's mouth)."""
        return self.hub_top_mm + self.horn.height_mm

    @property
    def spline_end_gap_mm(self) -> float:
        """Axial gap between the spline's end and the horn socket's bottom (the key's play + the gap)."""
        return self.clearance_mm + self.spline_gap_mm

    @property
    def case_face_mm(self) -> float:
        """The servo case's spline-side face (it faces down)."""
        sv = self.servo_row
        return self.horn_top_mm - self.horn.socket_depth_mm + self.spline_end_gap_mm + sv.spline_mm

    @property
    def spline_engagement_mm(self) -> float:
        return self.horn.socket_depth_mm - self.spline_end_gap_mm

    @property
    def tab_z_mm(self) -> float:
        """The underside of the servo's tabs = the tops of the servo bosses."""
        return self.case_face_mm + self.servo_row.tab_from_face_mm

    @property
    def servo_top_mm(self) -> float:
        """The servo case's far end (its highest point)."""
        return self.case_face_mm + self.servo_row.case_height_mm

    # -- derived plan positions (key frame) -----------------------------------------------
    def boss_xs_mm(self) -> tuple[float, float]:
        """x of the servo's tab holes = the bosses' tap holes (near hole > 0, far hole < 0)."""
        return self.servo_row.hole_offsets_mm()

    def ring_screw_points(self) -> list[tuple[float, float]]:
        r, a = self.ring_screw_radius_mm, math.radians(self.ring_screw_angle_deg)
        return [(sx * r * math.cos(a), sy * r * math.sin(a)) for sx in (1, -1) for sy in (1, -1)]

    def horn_screw_points(self, turn_deg: float = 0.0) -> list[tuple[float, float]]:
        """The horn screws (its innermost holes), key frame, turned clockwise by ``turn_deg``."""
        r = self.horn.hole_radii_mm[0]
        return [(r * math.cos(math.radians(a)), r * math.sin(math.radians(a)))
                for a in (self.horn_open_deg - turn_deg, self.horn_open_deg - turn_deg + 180.0)]

    @property
    def countersink_mm(self) -> float:
        """The ring's 90 deg countersinks: the ISO 10642 head + half a nozzle each side (as the blocks')."""
        from cubot_cad.hardware.fasteners import thread

        head = thread(self.screw_size).countersunk_head_diameter_mm
        need(head is not None, f"TwistDriveSpec.screw_size {self.screw_size!r} has no ISO 10642 head in the table")
        return head + NOZZLE_MM

    @property
    def countersink_depth_mm(self) -> float:
        from cubot_cad.hardware.fasteners import clearance_hole_mm

        return (self.countersink_mm - clearance_hole_mm(self.screw_size)) / 2

    # -- screws (lengths from the table) --------------------------------------------------
    def horn_screw(self):
        """The two horn screws: ISO 4762 through the horn's arm into tap holes in the hub face, at least
        3 mm of thread."""
        from cubot_cad.hardware.fasteners import bolted

        return bolted("cubot", self.horn.screw_size, self.horn.arm_mm, 2,
                      "servo horn to the twist key's hub face (horn holes drilled to 2.4 mm)", thread_mm=3.0)[0]

    def horn_tap_depth_mm(self) -> float:
        return self.horn_screw().length_mm - self.horn.arm_mm + 0.5

    def tab_screw(self):
        """The two servo tab screws: ISO 4762 through a tab into a tap hole in a boss, 5 mm of thread."""
        from cubot_cad.hardware.fasteners import bolted

        sv = self.servo_row
        return bolted("cubot", sv.screw_size, sv.tab_mm, 2, f"{sv.name} tabs onto the body's servo bosses",
                      thread_mm=5.0)[0]

    def tab_tap_depth_mm(self) -> float:
        return self.tab_screw().length_mm - self.servo_row.tab_mm + 0.5

    def ring_screws(self, floor_mm: float):
        """The ring's four ISO 10642 screws (flush in its underside) through the floor, nuts inside."""
        from cubot_cad.hardware.fasteners import bolted

        return bolted("cubot", self.screw_size, self.ring_mm + floor_mm, 4,
                      "key bearing ring under the floor (heads flush, nuts inside)", nut=True, kind="ISO 10642")

    # -- the horn against the servo bosses ---------------------------------------------------
    def horn_boss_margin_deg(self, boss_inner_mm: float) -> float:
        """Least angle (deg) between the horn's arm edges and the near servo boss's side faces (at the
        boss's inner radius ``boss_inner_mm``) over the key's travel; the bosses lie at 0 and 180 deg."""
        h = self.horn
        half_arm = math.degrees(math.atan2(h.arm_width_mm(boss_inner_mm) / 2, boss_inner_mm))
        half_boss = math.degrees(math.atan2(self.boss_mm / 2, boss_inner_mm))
        worst = 180.0
        for k in range(721):
            a = (self.horn_open_deg - self.travel_deg * k / 720) % 180.0  # the arms, modulo the other arm
            worst = min(worst, a, 180.0 - a)
        return worst - half_arm - half_boss


def _point_line_gap(r: float, point_deg: float, line_deg: float) -> float:
    """Distance from the point at radius ``r``, angle ``point_deg`` to the ray from the origin along
    ``line_deg`` (a slot from the axis outward)."""
    d = math.radians(point_deg - line_deg)
    along = r * math.cos(d)
    return abs(r * math.sin(d)) if along > 0 else r


@dataclass(frozen=True)
class TwistKey(Part):
    """The turning cross key on its shaft (key frame, open)."""

    spec: TopTwistSpec = TopTwistSpec()
    drive: TwistDriveSpec = TwistDriveSpec()
    name: ClassVar[str] = "twist_key"
    description: ClassVar[str] = ("twist-and-lock: cross key on a shaft through the floor, thrust disc under it, "
                                  "hub face for the servo horn (2 M2 tap holes), IR transmitter bore and wire slot")
    support: ClassVar[str] = ("the thrust disc overhangs the stem by 6 mm (support under the disc; the cross head "
                              "prints on the bed)")
    infill_percent: ClassVar[int] = 100

    def validate(self) -> None:
        s, d = self.spec, self.drive
        need(abs(s.clearance_mm - self.clearance_mm) < 1e-12 and abs(d.clearance_mm - self.clearance_mm) < 1e-12,
             f"TwistKey: spec, drive and part clearances differ ({s.clearance_mm:g}, {d.clearance_mm:g}, "
             f"{self.clearance_mm:g})")
        head_top = s.key_protrusion_mm - s.head_mm  # below the underside
        need(at_least(head_top - d.ring_mm, MIN_WALL_MM),
             f"TwistDriveSpec: the {d.ring_mm:g} mm bearing ring reaches down to the key head "
             f"({head_top:g} mm under the robot)")
        need(at_least(d.disc_diameter_mm / 2, math.sqrt(2) * (s.arm_width_mm / 2 + s.clearance_mm) + MIN_LAND_MM),
             f"TwistDriveSpec.disc_diameter_mm {d.disc_diameter_mm:g} rests on the ring's lip by under "
             f"{MIN_LAND_MM:g} mm beyond the corners of its cross bore")
        need(at_least(d.shaft_diameter_mm / 2, s.ir_bore_mm / 2 + MIN_WALL_MM + d.wire_slot_mm / 2),
             f"TwistDriveSpec.shaft_diameter_mm {d.shaft_diameter_mm:g} is too thin for the IR bore")
        need(at_least(d.hub_top_mm - d.horn_tap_depth_mm(), 0.0) and d.hub_top_mm > 0,
             f"TwistDriveSpec.hub_top_mm {d.hub_top_mm:g} is shorter than the horn screws' tap holes")

    def build(self):
        from cubot_cad.hardware.fasteners import tap_hole_mm
        from cubot_cad.shapes import Z, box, cut_all, cyl, fuse_all, rotated

        s, d = self.spec, self.drive
        zt = -s.key_protrusion_mm
        ch, w, L = s.key_chamfer_mm, s.arm_width_mm, s.arm_length_mm
        head = [_cross(w, L, zt + ch, s.head_mm - ch)]
        if ch > 0:  # the lead-in: the head's bottom edges chamfered 45 deg (as CrossKey)
            head.append(_cross_taper(w - 2 * ch, L - 2 * ch, zt, w, L, zt + ch + 0.001))
        z0, z1 = d.disc_z_mm
        stem = cyl(w / 2, z0 - (zt + s.head_mm) + 0.01, (0, 0, zt + s.head_mm - 0.005), Z)
        disc = cyl(d.disc_diameter_mm / 2, z1 - z0, (0, 0, z0), Z)
        shaft = cyl(d.shaft_diameter_mm / 2, d.hub_top_mm - z1 + 0.005, (0, 0, z1 - 0.005), Z)
        key = fuse_all(head + [stem, disc, shaft])
        top = d.hub_top_mm
        cut = [cyl(s.ir_bore_mm / 2, top - zt + 0.2, (0, 0, zt - 0.1), Z)]  # the IR transmitter's bore
        r_tap, depth = tap_hole_mm(d.horn.screw_size) / 2, d.horn_tap_depth_mm()
        cut += [cyl(r_tap, depth + 0.1, (x, y, top - depth), Z) for x, y in d.horn_screw_points()]
        slot = box(0.0, d.shaft_diameter_mm / 2 + 0.5, -d.wire_slot_mm / 2, d.wire_slot_mm / 2,
                   top - d.wire_slot_depth_mm, top + 0.1)
        cut.append(rotated(slot, Z, d.wire_slot_deg))  # the IR wires leave the bore under the horn
        return cut_all(key, cut)


@dataclass(frozen=True)
class KeyBearing(Part):
    """The fixed bearing ring under the floor (key frame; its top face on the floor's underside)."""

    spec: TopTwistSpec = TopTwistSpec()
    drive: TwistDriveSpec = TwistDriveSpec()
    name: ClassVar[str] = "key_bearing"
    description: ClassVar[str] = ("twist-and-lock: bearing ring under the floor holding the key's thrust disc "
                                  "(cross-shaped lip bore, four M3 countersunk screws, never turns)")

    def validate(self) -> None:
        s, d = self.spec, self.drive
        c = s.clearance_mm
        corner = math.hypot(s.arm_length_mm / 2 + c, s.arm_width_mm / 2 + c)
        need(at_least(d.ring_diameter_mm / 2 - corner, MIN_WALL_MM),
             f"TwistDriveSpec.ring_diameter_mm {d.ring_diameter_mm:g} leaves under {MIN_WALL_MM:g} mm round the "
             f"ends of the lip's cross bore")
        a = math.radians(d.ring_screw_angle_deg)
        r = d.ring_screw_radius_mm
        to_arm = min(r * abs(math.sin(a)), r * abs(math.cos(a))) - (s.arm_width_mm / 2 + c)
        need(at_least(to_arm - d.countersink_mm / 2, MIN_WALL_MM),
             f"TwistDriveSpec.ring_screw_angle_deg {d.ring_screw_angle_deg:g} puts the ring screws' countersinks "
             f"within {MIN_WALL_MM:g} mm of the lip's cross bore")

    def build(self):
        from cubot_cad.hardware.fasteners import clearance_hole_mm
        from cubot_cad.shapes import Z, cone, cut_all, cyl

        s, d = self.spec, self.drive
        c, t = s.clearance_mm, d.ring_mm
        ring = cyl(d.ring_diameter_mm / 2, t, (0, 0, -t), Z)
        cut = [_cross(s.arm_width_mm + 2 * c, s.arm_length_mm + 2 * c, -t - 0.1, t + 0.2)]  # the head passes
        z0, _ = d.disc_z_mm
        cut.append(cyl(d.disc_diameter_mm / 2 + c, -z0 + 0.1, (0, 0, z0), Z))  # the disc's pocket
        r, R = clearance_hole_mm(d.screw_size) / 2, d.countersink_mm / 2
        for x, y in d.ring_screw_points():
            cut.append(cyl(r, t + 0.2, (x, y, -t - 0.1), Z))
            cut.append(cone(R + 0.1, r, R - r + 0.1, (x, y, -t - 0.1), Z))  # countersunk heads, flush
        return cut_all(ring, cut)


@dataclass(frozen=True)
class ServoStandIn(Component):
    """A servo from :mod:`cubot_cad.hardware.servos` as a component: mass and inertia of its case (a box at
    each of ``positions_mm``), stand-in solid = case + tabs (with their holes), one per position.

    ``output`` says which way it is mounted: ``"-z"`` hangs upside down (the twist servo: the output
    spline points down from the case face, the case extends along -x from the axle; ``size_mm`` =
    case length, width, height); ``"-x"`` points its output at -x (a latch servo: the case extends +x
    from the face and upward from the axle, the tabs in a y-z plane; ``size_mm`` = case height, width,
    length); ``"-x down"`` the same with the case downward from the axle. ``yaw_deg`` (a multiple of
    90): the whole mounted servo turned about the robot's vertical axis through the origin (a latch
    servo on a side face); ``positions_mm`` and ``size_mm`` are then the turned case's."""

    servo_model: str = "SG90"
    output: str = "-z"
    yaw_deg: float = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.output not in ("-z", "-x", "-x down"):
            raise InputError(f"component {self.key}: servo output {self.output!r} is not -z, -x or '-x down'")

    def axles_mm(self) -> list[tuple[float, float, float]]:
        """Where each servo's output axis meets its case face (robot frame)."""
        from cubot_cad.shapes import yaw_point

        return [yaw_point(a, self.yaw_deg) for a in self._axles_unturned()]

    def _axles_unturned(self) -> list[tuple[float, float, float]]:
        from cubot_cad.hardware.servos import servo
        from cubot_cad.shapes import yaw_point

        sv = servo(self.servo_model)
        at = [yaw_point(p, -self.yaw_deg) for p in self.positions_mm]
        if self.output == "-z":
            return [(x + sv.axle_to_centre_mm, y, z - sv.case_height_mm / 2) for x, y, z in at]
        dz = -sv.axle_to_centre_mm if self.output == "-x" else sv.axle_to_centre_mm
        return [(x - sv.case_height_mm / 2, y, z + dz) for x, y, z in at]

    def solids(self):
        from cubot_cad.hardware.servos import servo
        from cubot_cad.shapes import X, Y, Z, box, cut_all, cyl, rotated

        sv = servo(self.servo_model)
        out = []
        for ax, ay, az in self._axles_unturned():
            near = ax + sv.axle_from_end_mm
            centre = ax - sv.axle_to_centre_mm
            W = sv.case_width_mm / 2
            case = box(near - sv.case_length_mm, near, ay - W, ay + W, az, az + sv.case_height_mm)
            zt = az + sv.tab_from_face_mm
            tabs = box(centre - sv.tab_length_mm / 2, centre + sv.tab_length_mm / 2, ay - W, ay + W, zt, zt + sv.tab_mm)
            holes = [cyl(sv.tab_hole_mm / 2, sv.tab_mm + 0.2, (ax + dx, ay, zt - 0.1), Z) for dx in sv.hole_offsets_mm()]
            solid = cut_all(case.fuse(tabs).clean(), holes)
            if self.output != "-z":  # built hanging (output -z, case along -x), turned +90 deg about y at the axle
                solid = rotated(solid, Y, 90.0, (ax, ay, az))
            if self.output == "-x down":  # and half a turn about its output axis (the case symmetric in y)
                solid = rotated(solid, X, 180.0, (ax, ay, az))
            out.append(rotated(solid, Z, self.yaw_deg) if self.yaw_deg else solid)
        return out


def servo_component(drive: TwistDriveSpec, axis_xy: tuple[float, float]) -> ServoStandIn:
    """The drive's servo as a component of the robot whose key axis is at ``axis_xy``."""
    sv = drive.servo_row
    x, y = axis_xy
    z = drive.case_face_mm
    centre = (x - sv.axle_to_centre_mm, y, z + sv.case_height_mm / 2)
    return ServoStandIn("twist_servo", sv.description, sv.mass_g, (centre,),
                        (sv.case_length_mm, sv.case_width_mm, sv.case_height_mm), "box", "motor", (0.3, 0.3, 0.3),
                        servo_model=sv.name)


@dataclass(frozen=True)
class Hardware:
    """A bought part's stand-in of the twist drive (key frame until placed): ``moves`` with the key or not."""

    label: str
    role: str
    shape: object
    moves: bool
    colour: tuple[float, float, float] = (0.6, 0.6, 0.6)


def _hex(af: float, h: float, xyz):
    from cubot_cad.shapes import prism, regular_polygon

    x, y, z = xyz
    return prism([(x + u, y + v) for u, v in regular_polygon(6, af)], "XY", z, h)


def hardware(spec: TopTwistSpec, drive: TwistDriveSpec, floor_mm: float, turn_deg: float = 0.0) -> list[Hardware]:
    """Stand-ins of the drive's bought parts (key frame), the turning ones at ``turn_deg`` clockwise:
    the horn, its two screws and the servo's output spline turn; the ring's four countersunk screws
    and nuts and the servo's two tab screws do not. Shanks are modelled at their hole less
    :data:`SHANK_UNDERSIZE_MM` (in a tap hole: the thread's core)."""
    from cubot_cad.hardware.fasteners import clearance_hole_mm, tap_hole_mm, thread
    from cubot_cad.hardware.servos import arm_outline
    from cubot_cad.shapes import Z, cone, cut_all, cyl, fuse_all, prism

    out: list[Hardware] = []
    # fixed: the ring's screws (heads flush in the ring's underside) and their nuts on the floor
    t3 = thread(drive.screw_size)
    t = drive.ring_mm
    ring_screw = drive.ring_screws(floor_mm)[0]
    r_shank = min(t3.nominal_mm / 2, clearance_hole_mm(drive.screw_size) / 2 - SHANK_UNDERSIZE_MM)
    R_head = t3.countersunk_head_diameter_mm / 2
    for i, (x, y) in enumerate(drive.ring_screw_points()):
        k = t3.countersunk_head_height_mm
        head = cone(R_head, R_head - k, k, (x, y, -t), Z)
        shank = cyl(r_shank, ring_screw.length_mm - k + 0.01, (x, y, -t + k - 0.005), Z)
        out.append(Hardware(f"key_bearing_screw_{i + 1}", "screw", fuse_all([head, shank]), False))
        out.append(Hardware(f"key_bearing_nut_{i + 1}", "screw",
                            _hex(t3.nut_flats_mm, t3.nut_height_mm, (x, y, floor_mm)).cut(
                                cyl(t3.nominal_mm / 2, t3.nut_height_mm + 0.2, (x, y, floor_mm - 0.1), Z)), False))
    # fixed: the servo's tab screws into the bosses
    sv = drive.servo_row
    t2 = thread(sv.screw_size)
    tab = drive.tab_screw()
    top = drive.tab_z_mm + sv.tab_mm
    for i, dx in enumerate(drive.boss_xs_mm()):
        head = cyl(t2.shcs_head_diameter_mm / 2, t2.shcs_head_height_mm, (dx, 0.0, top), Z)
        shank = cyl(tap_hole_mm(sv.screw_size) / 2 - SHANK_UNDERSIZE_MM, tab.length_mm + 0.01,
                    (dx, 0.0, top - tab.length_mm), Z)
        out.append(Hardware(f"servo_tab_screw_{i + 1}", "screw", fuse_all([head, shank]), False))
    # turning: the horn, its screws, the servo's output spline
    h = drive.horn
    z = drive.hub_top_mm
    arms = [prism(arm_outline(h, drive.horn_open_deg + 180.0 * k - turn_deg), "XY", z, h.arm_mm)
            for k in range(h.arms)]
    cap = cyl(h.hub_diameter_mm / 2, h.height_mm, (0, 0, z), Z)
    socket = cyl(h.socket_diameter_mm / 2, h.socket_depth_mm + 0.1, (0, 0, z + h.height_mm - h.socket_depth_mm), Z)
    horn = cut_all(fuse_all(arms + [cap]), [socket])
    out.append(Hardware("servo_horn", "horn", horn, True, (0.95, 0.95, 0.9)))
    ht = thread(h.screw_size)
    hs = drive.horn_screw()
    zt = z + h.arm_mm
    for i, (x, y) in enumerate(drive.horn_screw_points(turn_deg)):
        head = cyl(ht.shcs_head_diameter_mm / 2, ht.shcs_head_height_mm, (x, y, zt), Z)
        shank = cyl(tap_hole_mm(h.screw_size) / 2 - SHANK_UNDERSIZE_MM, hs.length_mm + 0.01,
                    (x, y, zt - hs.length_mm), Z)
        out.append(Hardware(f"horn_screw_{i + 1}", "screw", fuse_all([head, shank]), True))
    face = drive.case_face_mm
    spline = cyl(min(sv.spline_diameter_mm, h.socket_diameter_mm - 2 * SHANK_UNDERSIZE_MM) / 2, sv.spline_mm,
                 (0, 0, face - sv.spline_mm), Z)
    out.append(Hardware("servo_spline", "horn", spline, True, (0.95, 0.95, 0.9)))
    return out


def turning_torque_nm(spec: TopTwistSpec, drive: TwistDriveSpec, tension_n: float,
                      friction: float = FRICTION) -> float:
    """Torque (N m) to turn the key while it carries ``tension_n`` (N) pulling the robots apart: the
    head's arms rub on the collar roof's underside and the thrust disc on the ring's lip, each at the
    mean radius of its contact (uniform pressure: 2/3 (R^3 - r^3) / (R^2 - r^2)), with ``friction``.
    The shaft's radial friction and the servo's gears are left out."""
    c = spec.clearance_mm

    def mean_r(r0, r1):
        return 2 / 3 * (r1 ** 3 - r0 ** 3) / (r1 ** 2 - r0 ** 2)

    corner = math.sqrt(2) * (spec.arm_width_mm / 2 + c)  # the cross hole's centre square: no roof inside it
    r_head = mean_r(corner, spec.arm_length_mm / 2)
    r_disc = mean_r(corner, drive.disc_diameter_mm / 2)
    return friction * tension_n * (r_head + r_disc) * 1e-3
