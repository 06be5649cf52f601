"""CuBot (thesis Ch. 6.3.3): a cuboid robot <= 100 x 100 x 85 mm with three couplings.

* front: two grooved-pin blocks (three pins in a triangle each); rear: two
  engagement-latch blocks (triangular blade); docked front-to-rear with zero gap;
* left: male dovetail rail, right: female rail (two CuBots slide side by side);
* top: cover with the cross-hole collar and the locking key; underneath: the
  twist key (twist and lock, clockwise), which turns on a shaft through the floor in a bearing
  ring screwed under it, driven by a micro servo inside the body (:mod:`cubot_cad.couplings.twist`);
* two drive wheels (radius 21 mm, 70 mm apart), two 10 mm ball casters (held by a
  0.3 mm undercut, 2.8 mm exposed), windows for 8 IR pairs and the two bottom-front edge detectors.

Envelope: length x width x height excludes only what enters a docked
neighbour (pins, dovetail tongue); the body, rails, cover, collar and locking
key lie inside it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import ClassVar

from cubot_cad.couplings import compliance as couplings
from cubot_cad.couplings.connectors import (
    CasterSeat,
    Cover,
    FrontRearSpec,
    LockingKey,
    RailFemale,
    RailMale,
    RailSpec,
    TopTwistSpec,
    latch_set_parts,
    pin_set_parts,
)
from cubot_cad.couplings.latch_drive import SHAFT_INTO_COUPLER_MM, LatchDriveSpec
from cubot_cad.couplings.preload import WedgeLatch
from cubot_cad.couplings.twist import (
    STANDIN_GAP_MM,
    KeyBearing,
    TwistDriveSpec,
    TwistKey,
    servo_component,
)
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

ENVELOPE_MM = (100.0, 100.0, 85.0)
#: The CuBot's front-rear couplings (:attr:`CuBot.front_rear_coupling`).
FRONT_REAR_COUPLINGS = ("wedge", "clearance")
#: The drive motors' stand-in (x, y, z mm) and how far its centre sits above the wheel axle: an N20
#: gearmotor, 12 x 10 mm, 9 mm gearbox + 15 mm can = 24 mm along the axle (its 3 mm D-shaft goes into
#: the wheel's hub). A 26 mm motor with a bracket does not fit beside the twist key's 13.4 mm shaft
#: with the 70 mm wheel base: that leaves 31 - 6.7 = 24.3 mm from the shaft to a wheel's inner face.
MOTOR_SIZE_MM = (12.0, 24.0, 10.0)
MOTOR_ABOVE_AXLE_MM = 4.0
#: Gap (mm) of the drive motor stand-in to its wheel and to the twist key's shaft (they fit with this).
MOTOR_GAP_MM = 0.15
#: Side of the square bosses that hold the rail screws' inserts inside the side walls (mm).
RAIL_BOSS_MM = 8.0
#: The wheel slots in the floor are the wheel plus this much all round (mm).
WHEEL_SLOT_MARGIN_MM = 1.5


@dataclass(frozen=True)
class CuBotBody(Part):
    """Hollow printable body (open top, closed by the cover), robot frame."""

    length_mm: float = 100.0
    width_mm: float = 90.0
    height_mm: float = 71.8
    y_centre_mm: float = 2.0
    wall_mm: float = 2.4
    floor_mm: float = 3.0
    wheel_radius_mm: float = 21.0
    wheel_width_mm: float = 8.0
    wheel_base_mm: float = 70.0
    caster_x_mm: float = 38.0
    block_y_mm: float = 22.0
    block_z_mm: float = 30.0
    rail_z_mm: float = 26.0
    #: The cover's four screws sit this far in from its edges, each over a corner boss of the body that
    #: holds an M3 heat-set insert (boss ``boss_mm`` square in the inner corner, ``boss_depth_mm`` of
    #: full section under the wall top, then a 45 deg underside so it prints without support).
    cover_screw_inset_mm: float = 5.0
    boss_mm: float = 9.0
    boss_depth_mm: float = 8.0
    #: The side rails' screws (:class:`RailSpec`) go into M3 heat-set inserts in the side walls, each in a
    #: boss ``rail_boss_mm`` square inside the wall (as deep as the insert hole plus a
    #: :data:`MIN_WALL_MM` floor, less the wall; a 45 deg underside so it prints without support).
    rail_boss_mm: float = RAIL_BOSS_MM
    fr: FrontRearSpec = FrontRearSpec()
    rail: RailSpec = RailSpec()
    top: TopTwistSpec = TopTwistSpec()
    #: The twist-lock drive: the key's shaft hole and the bearing ring's screw holes in the floor, and
    #: the two servo bosses (``drive.boss_mm`` square, up to the servo's tabs, an M2 tap hole each; the
    #: one beside the key's shaft is cut round it with the clearance).
    drive: TwistDriveSpec = TwistDriveSpec()
    #: The latch servos' frames (:mod:`cubot_cad.couplings.latch_drive`): a plate behind each latch servo's tabs,
    #: from the floor up, with a window for its case and M2 tap holes for its tab screws.
    latch: LatchDriveSpec = LatchDriveSpec()
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    name: ClassVar[str] = "cubot_body"
    description: ClassVar[str] = ("CuBot body: hollow shell, pin/latch holes, rail IR holes, rail insert bosses, 8 IR windows, "
                                  "edge-detector windows, wheel slots, caster screw holes, twist-key shaft hole, "
                                  "key-bearing screw holes, two twist-servo bosses, two latch-servo frames")

    def validate(self) -> None:
        from cubot_cad.hardware.fasteners import thread

        self.wall_check("wall_mm", self.wall_mm)
        self.wall_check("floor_mm", self.floor_mm)
        ins = thread(self.top.screw_size)
        inset = self.cover_screw_inset_mm
        need(at_least(inset - ins.insert_hole_mm / 2, MIN_WALL_MM),
             f"CuBotBody.cover_screw_inset_mm {inset:g} puts the {ins.insert_hole_mm:g} mm insert holes closer "
             f"than {MIN_WALL_MM:g} mm to the outer wall")
        need(at_least(self.boss_mm + self.wall_mm - inset - ins.insert_hole_mm / 2, MIN_WALL_MM),
             f"CuBotBody.boss_mm {self.boss_mm:g} leaves under {MIN_WALL_MM:g} mm of boss round the insert holes")
        need(at_least(self.boss_depth_mm, ins.insert_hole_depth_mm + MIN_WALL_MM),
             f"CuBotBody.boss_depth_mm {self.boss_depth_mm:g} is shallower than the {ins.insert_hole_depth_mm:g} mm "
             f"insert hole plus a {MIN_WALL_MM:g} mm floor")
        ri = thread(self.rail.screw_size)
        need(at_least(self.rail_boss_mm / 2 - ri.insert_hole_mm / 2, MIN_WALL_MM),
             f"CuBotBody.rail_boss_mm {self.rail_boss_mm:g} leaves under {MIN_WALL_MM:g} mm of boss round the "
             f"{ri.insert_hole_mm:g} mm rail inserts")
        d = self.drive
        tap = thread(d.servo_row.screw_size).tap_drill_mm / 2
        near, _far = d.boss_xs_mm()
        need(at_least(near - tap - self.servo_boss_inner_mm, MIN_WALL_MM),
             f"TwistDriveSpec.shaft_diameter_mm {d.shaft_diameter_mm:g}: the {d.servo} servo's near boss keeps under "
             f"{MIN_WALL_MM:g} mm round its tap hole beside the key's shaft")
        need(at_least(d.tab_z_mm - self.floor_mm, d.tab_tap_depth_mm() + MIN_WALL_MM),
             f"TwistDriveSpec.hub_top_mm {d.hub_top_mm:g}: the servo bosses are shorter than their tap holes")
        self.latch.check_frames(self.latch_stack_end_mm, self.latch_blocks_yz_mm, self.floor_mm)

    def horn_sweep(self):
        """The twist servo's horn swept through a turn (a cylinder about the key's axis, its arms' reach
        and height plus :data:`~cubot_cad.couplings.twist.STANDIN_GAP_MM`), kept free of the latch-servo frames."""
        from cubot_cad.shapes import Z, cyl

        d, g = self.drive, STANDIN_GAP_MM
        return cyl(d.horn.arm_length_mm + g, d.horn.height_mm + 2 * g, (0.0, self.y_centre_mm, d.hub_top_mm - g), Z)

    @property
    def latch_stack_end_mm(self) -> float:
        """x where the rear latch stacks (wall + plates a, b, c, e) end inside the body."""
        return -self.length_mm / 2 + self.fr.latch_stack_mm

    @property
    def latch_blocks_yz_mm(self) -> list[tuple[float, float]]:
        """(y, z) of the rear latch blocks' centres (their D-shafts' axes)."""
        yc = self.y_centre_mm
        return [(yc - self.block_y_mm, self.block_z_mm), (yc + self.block_y_mm, self.block_z_mm)]

    @property
    def servo_boss_inner_mm(self) -> float:
        """How far from the key's axis the near servo boss ends (the turning shaft + the clearance)."""
        return self.drive.shaft_diameter_mm / 2 + self.clearance_mm

    def _servo_bosses(self):
        """The twist servo's two bosses: from the floor to the tabs' underside at the tab holes, the near
        one cut flat :attr:`servo_boss_inner_mm` from the key's axis (clear of its turning shaft)."""
        from cubot_cad.shapes import box

        d, f, yc = self.drive, self.floor_mm, self.y_centre_mm
        a, z1 = d.boss_mm / 2, d.tab_z_mm
        near, far = d.boss_xs_mm()
        return [box(max(near - a, self.servo_boss_inner_mm), near + a, yc - a, yc + a, f - 0.01, z1),
                box(far - a, min(far + a, -self.servo_boss_inner_mm), yc - a, yc + a, f - 0.01, z1)]

    def cover_screw_points(self) -> list[tuple[float, float]]:
        """(x, y) of the cover screws (robot frame): over the corner bosses."""
        a, b = self.length_mm / 2 - self.cover_screw_inset_mm, self.width_mm / 2 - self.cover_screw_inset_mm
        return [(x, self.y_centre_mm + y) for x in (-a, a) for y in (-b, b)]

    @property
    def rail_boss_extent_mm(self) -> float:
        """How far the rail bosses reach in from the side walls' inner faces (0: the wall holds the insert)."""
        from cubot_cad.hardware.fasteners import thread

        return max(0.0, thread(self.rail.screw_size).insert_hole_depth_mm + MIN_WALL_MM - self.wall_mm)

    def rail_screw_points(self) -> list[tuple[float, float, float, int]]:
        """(x, y, z, side) of the rail screws' inserts at the side walls' outer faces (robot frame); side
        +1 = left (male rail), -1 = right (female)."""
        yc, W = self.y_centre_mm, self.width_mm
        return [(x, yc + side * W / 2, self.rail_z_mm, side) for side in (1, -1) for x in self.rail.screw_xs_mm()]

    def _rail_bosses(self):
        """The rail inserts' bosses on the side walls' inner faces, with a 45 deg underside."""
        from cubot_cad.shapes import prism

        e, a, w = self.rail_boss_extent_mm, self.rail_boss_mm / 2, self.wall_mm
        if e <= 0:
            return []
        out = []
        for x, y, z, side in self.rail_screw_points():
            yi = y - side * (w - 0.01)  # 0.01 mm into the wall: a clean fuse
            ye = y - side * (w + e)
            outline = [(yi, z - a - e), (ye, z - a), (ye, z + a), (yi, z + a)]
            out.append(prism(outline, "YZ", x - a, 2 * a))
        return out

    def _bosses(self):
        """The four corner bosses (clipped to the hollow, fused to the walls)."""
        from cubot_cad.shapes import box, frustum

        L, W, H, w = self.length_mm, self.width_mm, self.height_mm, self.wall_mm
        yc, B = self.y_centre_mm, self.boss_mm
        zb = H - self.boss_depth_mm
        inner = box(-L / 2 + w, L / 2 - w, yc - W / 2 + w, yc + W / 2 - w, zb - B - 1, H)
        out = []
        for sx in (-1, 1):
            for sy in (-1, 1):
                cx, cy = sx * (L / 2 - w), yc + sy * (W / 2 - w)
                solid = box(cx - B, cx + B, cy - B, cy + B, zb, H).fuse(
                    frustum((0.05, 0.05), (B + 0.01, B + 0.01), zb - B + 0.04, zb + 0.01, (cx, cy)))
                out.append(solid.intersect(inner))
        return out

    def build(self):
        from cubot_cad.hardware.fasteners import thread
        from cubot_cad.shapes import Y, Z, box, cut_all, cyl, fuse_all

        L, W, H, w, f = self.length_mm, self.width_mm, self.height_mm, self.wall_mm, self.floor_mm
        yc = self.y_centre_mm
        y0, y1 = yc - W / 2, yc + W / 2
        shell = box(-L / 2, L / 2, y0, y1, 0, H).cut(box(-L / 2 + w, L / 2 - w, y0 + w, y1 - w, f, H + 1))
        frames = self.latch.frames(self.latch_stack_end_mm, self.latch_blocks_yz_mm, f, [self.horn_sweep()])
        shell = fuse_all([shell] + self._bosses() + self._servo_bosses() + self._rail_bosses() + frames)
        ins = thread(self.top.screw_size)
        cut = [cyl(ins.insert_hole_mm / 2, ins.insert_hole_depth_mm + 0.1, (x, y, H - ins.insert_hole_depth_mm), Z)
               for x, y in self.cover_screw_points()]
        ri = thread(self.rail.screw_size)  # the rail screws' inserts, pressed in from outside
        cut += [cyl(ri.insert_hole_mm / 2, ri.insert_hole_depth_mm + 0.1, (x, y + side * 0.1, z), (0.0, -side, 0.0))
                for x, y, z, side in self.rail_screw_points()]
        fr = self.fr
        for yb in (yc - self.block_y_mm, yc + self.block_y_mm):
            for sgn in (1, -1):  # front pin blocks, rear latch blocks (patterns are symmetric in y)
                for t in fr.wall_cutters("pin" if sgn > 0 else "latch"):
                    t = t.moved(_loc((sgn * L / 2, yb, self.block_z_mm), 0 if sgn > 0 else 180))
                    cut.append(t)
        # rail IR holes through the side walls
        for x, z in self.rail.ir_points():
            cut.append(cyl(self.rail.ir_hole_mm / 2, W + 2, (x, y0 - 1, self.rail_z_mm + z), Y))
        # 8 IR LED/photodiode pair windows, two per face, near the top
        zi = H - 10.0
        for d in (-25.0, 25.0):
            cut.append(box(-L / 2 - 1, -L / 2 + w + 1, yc + d - 5, yc + d + 5, zi - 2.5, zi + 2.5))
            cut.append(box(L / 2 - w - 1, L / 2 + 1, yc + d - 5, yc + d + 5, zi - 2.5, zi + 2.5))
            cut.append(box(d - 5, d + 5, y0 - 1, y0 + w + 1, zi - 2.5, zi + 2.5))
            cut.append(box(d - 5, d + 5, y1 - w - 1, y1 + 1, zi - 2.5, zi + 2.5))
        # floor: wheel slots, edge detectors, key shaft + bearing screws, caster screws; servo boss tap holes
        r = self.wheel_radius_mm + WHEEL_SLOT_MARGIN_MM
        for yw in (yc - self.wheel_base_mm / 2, yc + self.wheel_base_mm / 2):  # centred on the body
            a = self.wheel_width_mm / 2 + WHEEL_SLOT_MARGIN_MM
            cut.append(box(-r, r, yw - a, yw + a, -1, f + 1))
        xe = L / 2 - w - 6
        for ye in (yc - 30, yc + 30):
            cut.append(box(xe - 3, xe + 3, ye - 2, ye + 2, -1, f + 1))
        d = self.drive
        cut.append(cyl(self.servo_boss_inner_mm, f + 2, (0, yc, -1), Z))  # the twist key's shaft
        from cubot_cad.hardware.fasteners import clearance_hole_mm, tap_hole_mm

        ring_r = clearance_hole_mm(d.screw_size) / 2
        cut += [cyl(ring_r, f + 2, (x, yc + y, -1), Z) for x, y in d.ring_screw_points()]
        hole_r = self.top.screw_hole_mm / 2
        cut += [cyl(hole_r, f + 2, (x, 0, -1), Z) for x in (-self.caster_x_mm, self.caster_x_mm)]
        tap, depth = tap_hole_mm(d.servo_row.screw_size) / 2, d.tab_tap_depth_mm()
        cut += [cyl(tap, depth + 0.1, (x, yc, d.tab_z_mm - depth), Z) for x in d.boss_xs_mm()]
        return cut_all(shell, cut)


def _loc(xyz, rot_z=0.0):
    from cubot_cad.shapes import location

    return location(xyz, rot_z)


@dataclass(frozen=True)
class CuBot(Robot):
    """Parametric CuBot; every dimension in mm with the thesis's value as default."""

    length_mm: float = 100.0
    width_mm: float = 100.0
    height_mm: float = 85.0
    wall_mm: float = 2.4
    floor_mm: float = 3.0
    wheel_radius_mm: float = 21.0
    wheel_width_mm: float = 8.0
    wheel_base_mm: float = 70.0
    wheel_exposed_mm: float = 15.0
    caster_ball_mm: float = 10.0
    caster_x_mm: float = 38.0
    block_y_mm: float = 22.0
    block_z_mm: float = 30.0
    rail_z_mm: float = 26.0
    #: The grooved pins (front) and their neck (the latch blade's slots, rear): :class:`FrontRearSpec`.
    pin_diameter_mm: float = 5.0
    groove_diameter_mm: float = 3.4
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    #: The front-rear coupling (:data:`FRONT_REAR_COUPLINGS`): ``"wedge"`` (the default since issue 38: the
    #: wedge latch of :mod:`cubot_cad.couplings.preload`, no free play) or ``"clearance"`` (the thesis's
    #: flat blade in a flat groove, 2 x the clearance of tension play; ``--set front_rear_coupling=clearance``).
    front_rear_coupling: str = "wedge"
    fr: FrontRearSpec | None = field(default=None)
    rail: RailSpec | None = field(default=None)
    top: TopTwistSpec | None = field(default=None)
    drive: TwistDriveSpec | None = field(default=None)
    latch: LatchDriveSpec | None = field(default=None)

    name: ClassVar[str] = "cubot"
    title: ClassVar[str] = "CuBot"

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        need(self.front_rear_coupling in FRONT_REAR_COUPLINGS,
             f"front_rear_coupling {self.front_rear_coupling!r} is not one of {', '.join(FRONT_REAR_COUPLINGS)}")
        check_dims(self, ("length_mm", "width_mm", "height_mm", "wall_mm", "floor_mm", "wheel_radius_mm",
                          "wheel_width_mm", "wheel_base_mm", "wheel_exposed_mm", "caster_ball_mm",
                          "caster_x_mm", "block_y_mm", "block_z_mm", "rail_z_mm", "pin_diameter_mm",
                          "groove_diameter_mm"))
        for n, lim in zip(("length_mm", "width_mm", "height_mm"), ENVELOPE_MM, strict=True):
            need(getattr(self, n) <= lim,
                 f"{n} {getattr(self, n):g} is outside the CuBot envelope "
                 f"{ENVELOPE_MM[0]:g} x {ENVELOPE_MM[1]:g} x {ENVELOPE_MM[2]:g} mm")
        need(self.wall_mm >= MIN_WALL_MM, f"wall_mm {self.wall_mm:g} is thinner than two nozzle widths ({MIN_WALL_MM:g} mm)")
        need(self.floor_mm >= MIN_WALL_MM, f"floor_mm {self.floor_mm:g} is thinner than two nozzle widths ({MIN_WALL_MM:g} mm)")
        fr, rail, top, drive = self.fr_spec, self.rail_spec, self.top_spec, self.drive_spec
        for spec, nm in ((fr, "fr"), (rail, "rail"), (top, "top"), (drive, "drive"), (self.latch_spec, "latch")):
            need(abs(spec.clearance_mm - self.clearance_mm) < 1e-12,
                 f"{nm}.clearance_mm {spec.clearance_mm:g} differs from clearance_mm {self.clearance_mm:g} "
                 "(one print clearance for every mating pair)")
        for n in ("wall_mm", "pin_diameter_mm", "groove_diameter_mm"):
            need(abs(getattr(fr, n) - getattr(self, n)) < 1e-12,
                 f"fr.{n} {getattr(fr, n):g} must equal {n} {getattr(self, n):g}")
        W_b = self.body_width_mm
        need(W_b >= 40, f"width_mm {self.width_mm:g} leaves a {W_b:g} mm body between the rails")
        H_b = self.body_height_mm
        half = fr.block_mm / 2
        need(self.block_z_mm - half >= self.floor_mm and self.block_z_mm + half <= H_b - 15,
             f"block_z_mm {self.block_z_mm:g} puts the {fr.block_mm:g} mm connector blocks outside the walls "
             f"(body height {H_b:g} mm)")
        need(self.block_y_mm + half <= W_b / 2 - self.wall_mm and self.block_y_mm >= half,
             f"block_y_mm {self.block_y_mm:g}: the {fr.block_mm:g} mm blocks do not fit side by side "
             f"inside the {W_b:g} mm body")
        need(self.wheel_exposed_mm < self.wheel_radius_mm,
             f"wheel_exposed_mm {self.wheel_exposed_mm:g} must be less than wheel_radius_mm {self.wheel_radius_mm:g}")
        # the wheels are centred on the body (not on the robot's footprint, which includes the thicker
        # female rail): each wheel slot keeps this much of the floor to the inner face of its side wall
        left = W_b / 2 - self.wall_mm - (self.wheel_base_mm / 2 + self.wheel_width_mm / 2 + WHEEL_SLOT_MARGIN_MM)
        need(at_least(left, 0.0),
             f"wheel_base_mm {self.wheel_base_mm:g} with wall_mm {self.wall_mm:g} puts the wheel slots "
             f"{-left:.2f} mm into the side walls (body {W_b:g} mm wide): reduce wheel_base_mm to "
             f"{self.wheel_base_mm + 2 * left:g} or wall_mm to {self.wall_mm + left:g}")
        need(at_least(self.length_mm / 2 - fr.latch_depth_mm - fr.rear_plate_mm, self.wheel_radius_mm + 1.5),
             f"wheel_radius_mm {self.wheel_radius_mm:g} collides with the connector stacks (length_mm {self.length_mm:g})")
        need(self.rail_z_mm - rail.height_mm / 2 >= 0 and self.rail_z_mm + rail.height_mm / 2 <= H_b - 15,
             f"rail_z_mm {self.rail_z_mm:g} puts the {rail.height_mm:g} mm rails outside the side walls")
        need(rail.length_mm <= self.length_mm, f"rail.length_mm {rail.length_mm:g} exceeds length_mm {self.length_mm:g}")
        self._check_rail_bosses()
        need(H_b >= 40, f"height_mm {self.height_mm:g} leaves only {H_b:g} mm of body under the cover/collar")
        CasterSeat(ball_diameter_mm=self.caster_ball_mm, wheel_exposed_mm=self.wheel_exposed_mm,
                   clearance_mm=self.clearance_mm)  # validates the caster against the wheels
        self._check_twist_drive()

    def _check_rail_bosses(self) -> None:
        """The rail screws' bosses inside the side walls clear the wheels, the connector stacks at the
        front and rear, and the rail IR holes through the body."""
        body, rail = self.body, self.rail_spec
        a, x = body.rail_boss_mm / 2, rail.screw_x_mm
        fr = self.fr_spec
        stack = min(self.length_mm / 2 - fr.pin_stack_mm, self.length_mm / 2 - fr.latch_stack_mm)
        need(at_most(x + a, stack - STANDIN_GAP_MM),
             f"rail.screw_x_mm {x:g}: the rail screws' bosses ({body.rail_boss_mm:g} mm) reach the connector stacks "
             f"(from x = +-{stack:g} mm)")
        inner = self.body_width_mm / 2 - self.wall_mm - body.rail_boss_extent_mm  # boss face, from the body's centre
        wheel_out = self.wheel_base_mm / 2 + self.wheel_width_mm / 2
        need(at_least(inner - wheel_out, STANDIN_GAP_MM) or at_least(x - a, self.wheel_radius_mm + STANDIN_GAP_MM),
             f"rail.screw_x_mm {x:g}: the rail screws' bosses reach the wheels (radius {self.wheel_radius_mm:g} mm)")
        ir = min(abs(px) for px, _z in rail.ir_points()) - rail.ir_hole_mm / 2
        need(at_most(x + a, ir - MIN_WALL_MM / 2),
             f"rail.screw_x_mm {x:g}: the rail screws' bosses reach the rail IR holes")

    def _check_twist_drive(self) -> None:
        """The twist-lock drive fits the robot: the horn turns over the drive motors, the servo and the
        boards above it stay under the cover, the bearing ring under the floor clears the lower robot's
        locking key when docked, the battery fits in front of the horn, the horn misses the servo bosses."""
        d, top = self.drive_spec, self.top_spec
        comps = {c.key: c for c in self._component_list()}
        m = comps["drive_motor"]
        motor_top = max(p[2] for p in m.positions_mm) + m.size_mm[2] / 2
        need(at_least(d.hub_top_mm, motor_top + STANDIN_GAP_MM),
             f"TwistDriveSpec.hub_top_mm {d.hub_top_mm:g} puts the servo horn into the drive motors (they reach "
             f"{motor_top:g} mm; keep {STANDIN_GAP_MM:g} mm)")
        z = comps["zigbee"]
        z_top = z.positions_mm[0][2] + z.size_mm[2] / 2
        need(at_most(z_top, self.body_height_mm - STANDIN_GAP_MM),
             f"TwistDriveSpec: the {d.servo} twist servo ({d.servo_top_mm:.2f} mm high) or the latch servos' tabs "
             f"(block_z_mm {self.block_z_mm:g}) leave no room for the main board and the ZigBee module under the cover "
             f"(hub_top_mm {d.hub_top_mm:g})")
        lip_under = top.stand_mm - top.collar_mm - top.lip_mm  # the lower robot's locking-key lip, below us
        need(at_most(d.ring_mm, lip_under - top.clearance_mm),
             f"TwistDriveSpec: the {d.ring_mm:g} mm bearing ring under the floor reaches the lower robot's locking "
             f"key ({lip_under:g} mm below when docked; ring_lip_mm {d.ring_lip_mm:g}, disc_mm {d.disc_mm:g})")
        b = comps["battery"]
        bx1 = b.positions_mm[0][0] + b.size_mm[0] / 2
        need(at_most(bx1, self.length_mm / 2 - self.fr_spec.pin_stack_mm - STANDIN_GAP_MM),
             f"TwistDriveSpec: the servo horn ({d.horn.arm_length_mm:g} mm) pushes the battery into the front "
             f"connector stacks")
        # (the 60 mm battery fits between the default wheels with 0.7 mm to spare; a narrower wheel base
        # is allowed, its stand-in then overlaps the wheels as the stand-ins did before: a stand-in, not a part)
        margin = d.horn_boss_margin_deg(self.body.servo_boss_inner_mm)
        need(margin > math.degrees(math.atan2(STANDIN_GAP_MM, self.body.servo_boss_inner_mm)),
             f"TwistDriveSpec.horn_open_deg {d.horn_open_deg:g}: over travel_deg {d.travel_deg:g} the horn comes "
             f"within {margin:.1f} deg of the servo bosses")

    # -- derived dimensions ---------------------------------------------------------
    @cached_property
    def fr_spec(self) -> FrontRearSpec:
        return self.fr or FrontRearSpec(wall_mm=self.wall_mm, pin_diameter_mm=self.pin_diameter_mm,
                                        groove_diameter_mm=self.groove_diameter_mm, clearance_mm=self.clearance_mm,
                                        wedge=WedgeLatch() if self.front_rear_coupling == "wedge" else None)

    @cached_property
    def rail_spec(self) -> RailSpec:
        """The side rails; by default their screws at x = +-28 mm, or nearer the middle where a thick
        wall deepens the connector stacks so far that the screws' bosses would reach them."""
        if self.rail:
            return self.rail
        fr = self.fr_spec
        stack = self.length_mm / 2 - max(fr.pin_stack_mm, fr.latch_stack_mm)
        x = min(RailSpec.screw_x_mm, stack - STANDIN_GAP_MM - RAIL_BOSS_MM / 2)
        return RailSpec(clearance_mm=self.clearance_mm, screw_x_mm=x)

    @cached_property
    def top_spec(self) -> TopTwistSpec:
        return self.top or TopTwistSpec(stand_mm=self.wheel_exposed_mm, clearance_mm=self.clearance_mm)

    @cached_property
    def latch_spec(self) -> LatchDriveSpec:
        """The latch servos (default: the servo table's SG90) and their frames: the case hangs down from
        the axle where it then stays :data:`STANDIN_GAP_MM` above the drive motors and the twist horn
        (the boards above stay low), else it stands up."""
        if self.latch:
            return self.latch
        down = LatchDriveSpec(clearance_mm=self.clearance_mm, case_up=False)
        above = max(self.motor_top_mm, self.drive_spec.hub_top_mm + self.drive_spec.horn.height_mm) + STANDIN_GAP_MM
        fits = (down.case_mm(0.0, 0.0, self.block_z_mm)[4] >= above  # the tabs stand clear of both, beside them
                and down.tabs_mm(0.0, 0.0, self.block_z_mm)[4] >= self.floor_mm + MIN_WALL_MM)
        return down if fits else LatchDriveSpec(clearance_mm=self.clearance_mm)

    @cached_property
    def drive_spec(self) -> TwistDriveSpec:
        """The twist drive; by default its hub face (the horn's seat) just above the drive motors."""
        return self.drive or TwistDriveSpec(hub_top_mm=self.motor_top_mm + STANDIN_GAP_MM,
                                            clearance_mm=self.clearance_mm)

    @property
    def motor_top_mm(self) -> float:
        """Top of the drive motors' stand-ins (N20 + bracket, 10 mm tall, centred 4 mm above the axle)."""
        return self.wheel_radius_mm - self.wheel_exposed_mm + MOTOR_ABOVE_AXLE_MM + MOTOR_SIZE_MM[2] / 2

    @property
    def key_axis_mm(self) -> tuple[float, float]:
        """(x, y) of the twist key's axis (the cover's collar and the cross hole are on it)."""
        return (0.0, self.y_centre_mm)

    @cached_property
    def twist_key(self) -> TwistKey:
        return TwistKey(spec=self.top_spec, drive=self.drive_spec, clearance_mm=self.clearance_mm)

    @cached_property
    def key_bearing(self) -> KeyBearing:
        return KeyBearing(spec=self.top_spec, drive=self.drive_spec, clearance_mm=self.clearance_mm)

    @property
    def body_width_mm(self) -> float:
        return self.width_mm - self.rail_spec.plate_mm - self.rail_spec.female_mm

    @property
    def y_centre_mm(self) -> float:
        """Body centre in y (the female rail is thicker, so the body sits off-centre)."""
        return (self.rail_spec.female_mm - self.rail_spec.plate_mm) / 2

    @property
    def body_height_mm(self) -> float:
        return self.height_mm - self.top_spec.top_mm

    @property
    def envelope_mm(self):
        return (self.length_mm, self.width_mm, self.height_mm)

    @property
    def block_ys_mm(self) -> tuple[float, float]:
        return (self.y_centre_mm - self.block_y_mm, self.y_centre_mm + self.block_y_mm)

    @cached_property
    def body(self) -> CuBotBody:
        return CuBotBody(length_mm=self.length_mm, width_mm=self.body_width_mm, height_mm=self.body_height_mm,
                         y_centre_mm=self.y_centre_mm, wall_mm=self.wall_mm, floor_mm=self.floor_mm,
                         wheel_radius_mm=self.wheel_radius_mm, wheel_width_mm=self.wheel_width_mm,
                         wheel_base_mm=self.wheel_base_mm, caster_x_mm=self.caster_x_mm,
                         block_y_mm=self.block_y_mm, block_z_mm=self.block_z_mm, rail_z_mm=self.rail_z_mm,
                         fr=self.fr_spec, rail=self.rail_spec, top=self.top_spec, drive=self.drive_spec,
                         latch=self.latch_spec, clearance_mm=self.clearance_mm)

    def key_turn_deg(self, key_turned: bool) -> float:
        """Clockwise turn of the twist key: 0 open (aligned with a cross hole), ``twist_deg`` locked."""
        return self.top_spec.twist_deg if key_turned else 0.0

    def key_placed(self, turn_deg: float = 0.0) -> Placed:
        """The twist key turned ``turn_deg`` clockwise (seen from above) about its axis."""
        from cubot_cad.shapes import location

        x, y = self.key_axis_mm
        return Placed(self.twist_key, location((x, y, 0), -turn_deg), "cross_key")

    def build_placed(self, blades_locked: bool = False, key_turned: bool = False,
                     with_locking_key: bool = True, key_turn_deg: float | None = None) -> list[Placed]:
        """The printed parts placed; ``key_turn_deg`` (clockwise) overrides ``key_turned``."""
        from cubot_cad.shapes import location

        L = self.length_mm
        out = [Placed(self.body, location(), "body")]
        for yb in self.block_ys_mm:
            for part, offs in pin_set_parts(self.fr_spec):
                for o in offs:
                    role = "pin" if part.name.endswith("pin") else "pinset"
                    # a locked wedge latch has drawn the pins out by the head's clearance (they bear on it)
                    dx = self.fr_spec.pin_draw_mm if (blades_locked and role == "pin") else 0.0
                    out.append(Placed(part, location((L / 2 + o[0] + dx, yb + o[1], self.block_z_mm + o[2])), role))
            for part, _offs in latch_set_parts(self.fr_spec, locked=blades_locked):
                role = "blade" if "blade" in part.name else "latchset"
                out.append(Placed(part, location((-L / 2, yb, self.block_z_mm), 180), role))
        yc, W_b = self.y_centre_mm, self.body_width_mm
        out.append(Placed(RailMale(spec=self.rail_spec), location((0, yc + W_b / 2, self.rail_z_mm)), "rail"))
        out.append(Placed(RailFemale(spec=self.rail_spec), location((0, yc - W_b / 2, self.rail_z_mm), 180), "rail"))
        H_b = self.body_height_mm
        out.append(Placed(Cover(spec=self.top_spec, length_mm=L, width_mm=W_b,
                                screw_inset_mm=self.body.cover_screw_inset_mm), location((0, yc, H_b)), "cover"))
        if with_locking_key:
            out.append(Placed(LockingKey(spec=self.top_spec), location((0, yc, H_b)), "locking_key"))
        turn = self.key_turn_deg(key_turned) if key_turn_deg is None else float(key_turn_deg)
        out.append(self.key_placed(turn))
        out.append(Placed(self.key_bearing, location((*self.key_axis_mm, 0)), "key_bearing"))
        seat = CasterSeat(ball_diameter_mm=self.caster_ball_mm, wheel_exposed_mm=self.wheel_exposed_mm,
                          clearance_mm=self.clearance_mm)
        for x in (-self.caster_x_mm, self.caster_x_mm):
            out.append(Placed(seat, location((x, 0, 0)), "caster_seat"))
        return out

    def drive_parts(self) -> list[tuple[str, str, str, int]]:
        fr = self.fr_spec
        length = fr.rear_plate_mm + fr.separation_mm + SHAFT_INTO_COUPLER_MM  # through bearing and blade, into the coupler
        h, d = self.drive_spec.horn, self.drive_spec
        return self.latch_spec.drive_parts(fr.drive_shaft_mm, fr.drive_flat_mm, length, len(self.block_ys_mm)) + [
                ("twist_horn", f"{h.name} supplied with the {d.servo} (its spline fits), screwed to the twist key's "
                 f"hub face; drill its innermost arm holes ({h.hole_radii_mm[0]:g} mm from the centre) to 2.4 mm",
                 f"{2 * h.arm_length_mm:g} mm tip to tip, {h.height_mm:g} mm thick, {h.spline} spline", 1)]

    def hardware(self, placed: list | None = None) -> list:
        """Stand-ins of the twist drive's bought parts (horn, screws, nuts, spline; the servo is a
        component), robot frame, the turning ones at the key's turn in ``placed`` (default: open)."""
        from cubot_cad.couplings.twist import hardware
        from cubot_cad.shapes import location

        turn = 0.0
        if placed is not None:
            key = next((p for p in placed if p.role == "cross_key"), None)
            if key is not None:
                from cubot_cad.shapes import loc_matrix

                m = loc_matrix(key.loc)
                turn = -math.degrees(math.atan2(m[1, 0], m[0, 0]))
        x, y = self.key_axis_mm
        loc = location((x, y, 0))
        return ([replace(h, shape=h.shape.moved(loc)) for h in hardware(self.top_spec, self.drive_spec, self.floor_mm, turn)]
                + self.rail_screws())

    def rail_screws(self) -> list:
        """Stand-ins of the side rails' countersunk screws (robot frame): head in the male's tongue tip
        face / the female's groove floor, ``screw_recess_mm`` below it, shank through the rail and into the
        insert in the side wall (shank at the clearance hole less :data:`~cubot_cad.couplings.twist.SHANK_UNDERSIZE_MM`)."""
        from cubot_cad.couplings.twist import SHANK_UNDERSIZE_MM, Hardware
        from cubot_cad.hardware.fasteners import thread
        from cubot_cad.shapes import cone, cyl, fuse_all

        rs = self.rail_spec
        t = thread(rs.screw_size)
        R, k = t.countersunk_head_diameter_mm / 2, t.countersunk_head_height_mm
        r = min(t.nominal_mm / 2, rs.screw_hole_mm / 2 - SHANK_UNDERSIZE_MM)
        yc, W_b, z = self.y_centre_mm, self.body_width_mm, self.rail_z_mm
        out = []
        for male, side in ((True, 1.0), (False, -1.0)):
            length = self.rail_screw_use(male)[0].length_mm
            y_top = yc + side * (W_b / 2 + rs.screw_grip_mm(male))  # the head's top (robot frame)
            axis = (0.0, -side, 0.0)  # into the robot
            for i, x in enumerate(rs.screw_xs_mm()):
                head = cone(R, R - k, k, (x, y_top, z), axis)
                shank = cyl(r, length - k + 0.01, (x, y_top - side * (k - 0.005), z), axis)
                label = f"rail_{'male' if male else 'female'}_screw_{i + 1}"
                out.append(Hardware(label, "screw", fuse_all([head, shank]), False))
        return out

    def rail_screw_use(self, male: bool) -> list:
        """The screws (and inserts) of one rail half: ISO 10642 countersunk (its length includes the head)
        clamping the rail from the head's top to the wall, into an insert in the wall."""
        from cubot_cad.hardware.fasteners import bolted

        rs = self.rail_spec
        half = "male rail (left): through the tongue" if male else "female rail (right): through the groove floor"
        return bolted(self.name, rs.screw_size, rs.screw_grip_mm(male), len(rs.screw_xs_mm()),
                      f"{half} into the side wall's inserts", insert=True, kind="ISO 10642")

    def fasteners(self) -> list:
        from cubot_cad.hardware.fasteners import bolted

        fr, top, n = self.fr_spec, self.top_spec, self.name
        blocks = len(self.block_ys_mm)
        return (bolted(n, fr.screw_size, fr.pin_stack_mm, 4 * blocks, "grooved-pin blocks: wall + plates d, c, b, a",
                       nut=True, kind="ISO 10642")
                + bolted(n, fr.screw_size, fr.latch_stack_mm, 4 * blocks, "latch blocks: wall + plates a, b, c, e",
                         nut=True, kind="ISO 10642")
                + bolted(n, top.screw_size, top.cover_mm, 4, "cover into the body's corner bosses", insert=True)
                + self.rail_screw_use(True) + self.rail_screw_use(False)
                + self.drive_spec.ring_screws(self.floor_mm)
                + [self.drive_spec.horn_screw(), self.drive_spec.tab_screw()]
                + self.latch_spec.tab_screws(n, blocks)
                + bolted(n, "M3", self.floor_mm, 2, "caster seats (screw from inside into the seat's tap hole)",
                         thread_mm=3.0))

    def pin_heights_mm(self) -> list[float]:
        return [self.block_z_mm + z for _ in self.block_ys_mm for _y, z in self.fr_spec.pin_positions()]

    def components(self) -> list[Component]:
        return self._component_list()

    def _component_list(self) -> list[Component]:
        """The component table. The twist servo hangs over the key (:mod:`cubot_cad.couplings.twist`); the battery
        stands on its long edge in front of the servo horn's sweep, between the wheels; the main board and
        the ZigBee module lie above the servo (at least :data:`~cubot_cad.couplings.twist.STANDIN_GAP_MM` apart)."""
        yc, H_b, L = self.y_centre_mm, self.body_height_mm, self.length_mm
        drv = self.drive_spec
        body = self.body
        latch_top = max(self.latch_spec.tabs_mm(body.latch_stack_end_mm, y, z)[5] for y, z in body.latch_blocks_yz_mm)
        board_z = max(H_b - 22.0, drv.servo_top_mm + STANDIN_GAP_MM + 4.0, latch_top + STANDIN_GAP_MM + 4.0)
        zigbee_z = max(H_b - 14.0, board_z + 4.0 + STANDIN_GAP_MM + 2.5)
        near, _far = drv.boss_xs_mm()
        bat_x0 = max(drv.horn.arm_length_mm, near + drv.boss_mm / 2) + STANDIN_GAP_MM
        axle = self.wheel_radius_mm - self.wheel_exposed_mm
        wb = self.wheel_base_mm / 2
        motor_y = wb - self.wheel_width_mm / 2 - MOTOR_GAP_MM - MOTOR_SIZE_MM[1] / 2  # gearbox face at the wheel
        ball_z = -self.wheel_exposed_mm + self.caster_ball_mm / 2
        zi = H_b - 10
        # the IR pair boards (4 mm thick) stand behind their windows, STANDIN_GAP_MM off the walls' inner faces
        t = self.wall_mm + STANDIN_GAP_MM + 2.0
        ir = [(L / 2 - t, yc + d, zi) for d in (-25, 25)] + [(-L / 2 + t, yc + d, zi) for d in (-25, 25)]
        ir_side = [(d, yc - self.body_width_mm / 2 + t, zi) for d in (-25, 25)] + \
                  [(d, yc + self.body_width_mm / 2 - t, zi) for d in (-25, 25)]
        return [
            Component("drive_motor", "micro metal gearmotor (N20: 12 x 10 x 24 mm, 3 mm D-shaft) with clip", 12.0,
                      ((0.0, yc - motor_y, axle + MOTOR_ABOVE_AXLE_MM), (0.0, yc + motor_y, axle + MOTOR_ABOVE_AXLE_MM)),
                      MOTOR_SIZE_MM, "box", "motor", (0.3, 0.3, 0.3)),
            Component("wheel", f"drive wheel, {2 * self.wheel_radius_mm:g} mm, rubber tyre", 8.0,
                      ((0.0, yc - wb, axle), (0.0, yc + wb, axle)), (2 * self.wheel_radius_mm, self.wheel_width_mm),
                      "cyl_y", "wheel", (0.1, 0.1, 0.1)),
            Component("caster_ball", f"steel ball, {self.caster_ball_mm:g} mm", 4.1,
                      ((-self.caster_x_mm, 0.0, ball_z), (self.caster_x_mm, 0.0, ball_z)),
                      (self.caster_ball_mm,), "sphere", "caster", (0.7, 0.7, 0.75)),
            Component("battery", "2S LiPo 7.4 V 800 mAh (60 x 30 x 15 mm, standing on its long edge)", 45.0,
                      ((bat_x0 + 7.5, yc, self.floor_mm + STANDIN_GAP_MM + 15.0),),
                      (15.0, 60.0, 30.0), "box", "power", (0.8, 0.5, 0.1)),
            Component("main_board", "ARM Cortex-M3 controller + motor drivers + CAN", 15.0,
                      ((0.0, yc, board_z),), (60.0, 50.0, 8.0), "box"),
            Component("zigbee", "ZigBee module (XBee class)", 4.0, ((20.0, yc, zigbee_z),), (25.0, 25.0, 5.0)),
            Component("ir_pair_board", "IR LED + photodiode pair board (front and rear walls)", 1.5, tuple(ir),
                      (4.0, 12.0, 8.0)),
            Component("ir_pair_board_side", "IR LED + photodiode pair board (side walls)", 1.5, tuple(ir_side),
                      (12.0, 4.0, 8.0)),
            self.latch_spec.component(body.latch_stack_end_mm, body.latch_blocks_yz_mm),
            servo_component(drv, self.key_axis_mm),
            Component("edge_detector", "IR reflective edge detector (bottom front)", 1.0,
                      ((L / 2 - self.wall_mm - 6, yc - 30, self.floor_mm + 3), (L / 2 - self.wall_mm - 6, yc + 30, self.floor_mm + 3)),
                      (6.0, 10.0, 4.0)),
            Component("fasteners", "M3 screws and nuts (about 30)", 15.0, ((0.0, yc, H_b / 2),), (80.0, 80.0, 60.0),
                      "box", "hardware", (0.6, 0.6, 0.6), lump=True),
            Component("wiring", "wires and connectors", 10.0, ((0.0, yc, H_b / 2),), (60.0, 60.0, 40.0),
                      "box", "hardware", (0.9, 0.2, 0.2), lump=True),
        ]

    def latch_servo_torque(self) -> tuple[float, str]:
        """The latch servo's stall torque on each blade (N m; the 1:1 gears of a geared drive pass it on)
        and the sentence naming it (the servo table's datasheet row)."""
        from cubot_cad.hardware.servos import servo

        sv = servo(self.latch_spec.servo)
        return sv.stall_torque_nm, f"{sv.maker} {sv.name} ({sv.stall_torque_kgf_cm:g} kgf cm at 4.8 V, datasheet)"

    def connector_properties(self, youngs_modulus_pa: float, gaps_mm: dict | None = None) -> tuple:
        gaps = gaps_mm or {}
        fr = self.fr_spec
        return (
            couplings.front_rear(fr, self.pin_heights_mm(), gaps.get("front_rear", fr.design_gap_mm),
                                 youngs_modulus_pa, self.block_z_mm, *self.latch_servo_torque()),
            couplings.side_rail(self.rail_spec, youngs_modulus_pa, self.rail_z_mm),
            couplings.top_twist(self.top_spec, youngs_modulus_pa, self.body_height_mm + self.top_spec.cover_mm,
                                gaps.get("top_twist", self.top_spec.stand_mm)),
        )
