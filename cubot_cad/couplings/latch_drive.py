"""The latch blades' drive (mm): a servo from the table (:mod:`cubot_cad.hardware.servos`) behind each latch
block, its output coaxial with the blade's D-shaft and coupled to it, held by its tabs on a printed
frame that stands on the floor as part of the body.

Layout (robot frame; a rear latch block at x = -L/2 with its centre at (y_b, z_b)):

* the latch stack (wall + plates a, b, c, e) ends at ``x_s = -L/2 + latch_stack_mm``;
* the D-shaft sticks :data:`SHAFT_INTO_COUPLER_MM` out of plate e into a coupler whose other end takes
  the servo's output spline; the coupler is that engagement + the spline + 1 mm between the two,
  :data:`COUPLER_GAP_MM` off plate e (:meth:`LatchDriveSpec.coupler_mm`);
* the servo's output face is at ``x_f = x_s + COUPLER_GAP_MM + coupler_mm``, the output pointing -x
  on the block's axis; the case extends +x from it with its length downward (the axle at the case's
  upper end: the boards above stay low) where the case then clears the drive motors and the twist
  servo's horn under it, else upward (``case_up``; the CuBot chooses, :attr:`CuBot.latch_spec`), so
  its tabs lie in a y-z plane;
* the frame: a plate ``frame_mm`` thick right behind the tabs (their +x side) from the floor to the
  tabs' top, ``frame_margin_mm`` wider than the case on each side, with a window for the case (plus
  the clearance) and an M2 tap hole at each tab hole (the screws go in from the output side, reached
  from the open top before the cover goes on).

The servo is a row of the servo table: its mass, case and tabs come from there, and the bill of
materials names it. The coupler (a 5 mm D-bore to the servo's spline) is a bought part.

**Geared drive.** Where a servo cannot sit on its blade's axis (two coaxial servos meet in a corner
of the Cube Robot, whose latch blocks sit on two adjacent faces), it sits beside it, its output
parallel to the shaft one gear centre distance away along the face (``servo_y`` of the block's
place), and a 1:1 pair of stock spur gears (:mod:`cubot_cad.hardware.gears`) carries the turn: one with a hub
on the blade's D-shaft (set screw on the flat), one screwed to the servo's horn (its arms cut
short, :func:`horn_trim_mm`), both in the plane :data:`COUPLER_GAP_MM` past the block's screw
ends and nuts (``proud_mm`` beyond the stack's last plate). The servo's output face is then that gap + the
gear's face + the horn's stack (:meth:`LatchDriveSpec.horn_stack_mm`) behind the stack; the blade
turns the other way from the servo (the controller reverses it). Frame and tabs are as above.

A block's place is ``(y, z)`` (coaxial) or ``(y, z, servo_y)`` (the servo's axis at ``servo_y``;
geared where it differs from ``y``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

from cubot_cad.hardware.components import Component
from cubot_cad.part import DEFAULT_CLEARANCE_MM, MIN_WALL_MM, at_least, check_clearance, need

#: How far the blade's D-shaft sticks out of the latch stack's last plate into the coupler, mm.
SHAFT_INTO_COUPLER_MM = 6.0
#: The coupler's end stands this far off the latch stack's last plate (it must not rub on it), mm.
COUPLER_GAP_MM = 0.3
#: Between the D-shaft's end and the spline's end inside the coupler, mm.
COUPLER_INNER_GAP_MM = 1.0
#: A gear's stand-in is its pitch cylinder less this much in radius (mm; see :class:`GearStandIn`).
STANDIN_PITCH_INSET_MM = 0.02
#: The tab screws' thread into the frame's tap holes, mm (the twist servo's bosses take 5 mm; the
#: frame is a plate, 3 mm of M2 thread is 7.5 pitches).
TAB_THREAD_MM = 3.0


@dataclass(frozen=True)
class LatchDriveSpec:
    """The latch servos and their mounting frames (mm)."""

    servo: str = "SG90"
    case_up: bool = True
    #: A geared drive's pair (:mod:`cubot_cad.hardware.gears`): on the blade's D-shaft (hubbed) / on the servo's horn.
    blade_gear: str = "M0.5 z48 hub"
    servo_gear: str = "M0.5 z48"
    #: How far the latch block's screw ends and nuts stand proud of the stack's last plate (mm): a
    #: geared drive's gears turn :data:`COUPLER_GAP_MM` past them (the robot sets it from its screws).
    proud_mm: float = 0.0
    frame_mm: float = 5.0
    frame_margin_mm: float = 2.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm)
        from cubot_cad.part import check_dims

        check_dims(self, ("frame_mm", "frame_margin_mm"))
        need(isinstance(self.proud_mm, (int, float)) and self.proud_mm >= 0,
             f"LatchDriveSpec.proud_mm must be >= 0, got {self.proud_mm!r}")
        self.servo_row  # noqa: B018 (an unknown servo is refused here)
        self.gear_offset_mm  # noqa: B018 (unknown or non-meshing gears are refused here)
        need(at_least(self.frame_margin_mm, MIN_WALL_MM),
             f"LatchDriveSpec.frame_margin_mm {self.frame_margin_mm:g} leaves under {MIN_WALL_MM:g} mm of frame beside "
             "the servo's case")
        need(at_least(self.frame_mm - self.tab_tap_depth_mm(), MIN_WALL_MM / 2),
             f"LatchDriveSpec.frame_mm {self.frame_mm:g} is thinner than the {self.tab_tap_depth_mm():.2f} mm tab-screw "
             "tap holes")

    @cached_property
    def servo_row(self):
        from cubot_cad.hardware.servos import servo

        return servo(self.servo)

    @cached_property
    def gears(self):
        """(blade gear, servo gear) rows of the gear table."""
        from cubot_cad.hardware.gears import gear

        return gear(self.blade_gear), gear(self.servo_gear)

    @property
    def gear_offset_mm(self) -> float:
        """A geared servo's axis from its blade's: the pair's centre distance."""
        from cubot_cad.hardware.gears import mesh_centre_distance_mm

        return mesh_centre_distance_mm(*self.gears)

    @property
    def horn_stack_mm(self) -> float:
        """From the servo's output face to the horn's flat arm face (the spline's protrusion less the horn
        socket's depth, plus the horn's height): where the servo gear is screwed on."""
        sv = self.servo_row
        return sv.spline_mm - sv.horn.socket_depth_mm + sv.horn.height_mm

    @staticmethod
    def place(block) -> tuple[float, float, bool]:
        """``(servo_y, z, geared)`` of a block's place ``(y, z)`` or ``(y, z, servo_y)``."""
        y, z = block[0], block[1]
        sy = block[2] if len(block) > 2 else y
        return sy, z, abs(sy - y) > 1e-9

    def check_places(self, blocks) -> None:
        """A geared servo sits exactly one gear centre distance from its blade."""
        for b in blocks:
            if len(b) > 2 and abs(b[2] - b[0]) > 1e-9:
                need(abs(abs(b[2] - b[0]) - self.gear_offset_mm) < 1e-6,
                     f"latch servo at {b[2]:g} mm: {abs(b[2] - b[0]):g} mm from its blade's axis at {b[0]:g} mm, "
                     f"not the {self.blade_gear} / {self.servo_gear} pair's {self.gear_offset_mm:g} mm")

    @property
    def coupler_mm(self) -> float:
        """The coupler's length: the shaft's engagement, the spline's, and the gap between them."""
        return SHAFT_INTO_COUPLER_MM + self.servo_row.spline_mm + COUPLER_INNER_GAP_MM

    def face_x_mm(self, stack_end_x_mm: float, geared: bool = False) -> float:
        """x of the servo's output face for a latch stack ending at ``stack_end_x_mm`` (robot frame): a
        coupler's length behind it, or (``geared``) the gear's face and the horn's stack."""
        if geared:
            return self.gear_plane_x_mm(stack_end_x_mm) + self.gears[1].face_mm + self.horn_stack_mm
        return stack_end_x_mm + COUPLER_GAP_MM + self.coupler_mm

    def gear_plane_x_mm(self, stack_end_x_mm: float) -> float:
        """x of a geared drive's gears' stack-side faces: :data:`COUPLER_GAP_MM` past the block's screw
        ends and nuts (``proud_mm``)."""
        return stack_end_x_mm + self.proud_mm + COUPLER_GAP_MM

    def case_mm(self, stack_end_x_mm: float, y: float, z: float,
                geared: bool = False) -> tuple[float, float, float, float, float, float]:
        """The servo case's box (x0, x1, y0, y1, z0, z1) for the servo's axis at (``y``, ``z``)."""
        sv = self.servo_row
        xf = self.face_x_mm(stack_end_x_mm, geared)
        z0 = z - sv.axle_from_end_mm if self.case_up else z + sv.axle_from_end_mm - sv.case_length_mm
        return (xf, xf + sv.case_height_mm, y - sv.case_width_mm / 2, y + sv.case_width_mm / 2, z0,
                z0 + sv.case_length_mm)

    def tabs_mm(self, stack_end_x_mm: float, y: float, z: float,
                geared: bool = False) -> tuple[float, float, float, float, float, float]:
        """The tabs' box (x0, x1, y0, y1, z0, z1)."""
        sv = self.servo_row
        x0, _x1, y0, y1, z0, z1 = self.case_mm(stack_end_x_mm, y, z, geared)
        zc = (z0 + z1) / 2
        xt = x0 + sv.tab_from_face_mm
        return (xt, xt + sv.tab_mm, y0, y1, zc - sv.tab_length_mm / 2, zc + sv.tab_length_mm / 2)

    def tab_hole_zs_mm(self, z: float) -> tuple[float, float]:
        """z of the two tab holes for a block centred at height ``z`` (the servo's axle there)."""
        sv = self.servo_row
        return tuple(z - d if self.case_up else z + d for d in sv.hole_offsets_mm())

    def frame_box_mm(self, stack_end_x_mm: float, y: float, z: float, floor_mm: float, geared: bool = False):
        """The frame plate (x0, x1, y0, y1, z0, z1): behind the tabs, from 0.01 mm into the floor to the
        tabs' top."""
        _tx0, tx1, _y0, _y1, _tz0, tz1 = self.tabs_mm(stack_end_x_mm, y, z, geared)
        a = self.servo_row.case_width_mm / 2 + self.clearance_mm + self.frame_margin_mm
        return (tx1, tx1 + self.frame_mm, y - a, y + a, floor_mm - 0.01, tz1)

    def frame_window_mm(self, stack_end_x_mm: float, y: float, z: float, geared: bool = False):
        """The window the case passes through (its box plus the clearance)."""
        c = self.clearance_mm
        x0, x1, y0, y1, z0, z1 = self.case_mm(stack_end_x_mm, y, z, geared)
        return (x0, x1 + 1.0, y0 - c, y1 + c, z0 - c, z1 + c)

    # -- fasteners -----------------------------------------------------------------------
    def tab_screws(self, robot: str, count: int) -> list:
        """The tab screws: ISO 4762 through a tab into a tap hole in the frame, :data:`TAB_THREAD_MM` of
        thread (two per servo)."""
        from cubot_cad.hardware.fasteners import bolted

        sv = self.servo_row
        return bolted(robot, sv.screw_size, sv.tab_mm, 2 * count,
                      f"{sv.name} latch servos' tabs onto the body's latch-servo frames", thread_mm=TAB_THREAD_MM)[:1]

    def tab_tap_depth_mm(self) -> float:
        return self.tab_screws("-", 1)[0].length_mm - self.servo_row.tab_mm + 0.5

    # -- the body's frames ---------------------------------------------------------------
    def frames(self, stack_end_x_mm: float, blocks_yz, floor_mm: float, keep_out=()) -> list:
        """The frame plates with their windows and tap holes, one per block's servo (robot frame, a rear
        face), to fuse into the body; ``keep_out``: solids cut from them (the twist horn's swept volume)."""
        from cubot_cad.hardware.fasteners import tap_hole_mm
        from cubot_cad.shapes import X, box, cut_all, cyl

        out = []
        tap = tap_hole_mm(self.servo_row.screw_size) / 2
        depth = self.tab_tap_depth_mm()
        for y, z, geared in map(self.place, blocks_yz):
            plate = box(*self.frame_box_mm(stack_end_x_mm, y, z, floor_mm, geared))
            x0 = plate.BoundingBox().xmin
            holes = [cyl(tap, depth + 0.1, (x0 - 0.1, y, zt), X) for zt in self.tab_hole_zs_mm(z)]
            out.append(cut_all(plate, [box(*self.frame_window_mm(stack_end_x_mm, y, z, geared))] + holes
                               + list(keep_out)))
        return out

    def check_frames(self, stack_end_x_mm: float, blocks_yz, floor_mm: float) -> None:
        """The tap holes keep a wall to the window and the frame's top; the case clears the floor; a
        geared servo sits one gear centre distance from its blade."""
        from cubot_cad.hardware.fasteners import tap_hole_mm

        self.check_places(blocks_yz)
        tap = tap_hole_mm(self.servo_row.screw_size)
        for y, z, geared in map(self.place, blocks_yz):
            _x0, _x1, _y0, _y1, wz0, wz1 = self.frame_window_mm(stack_end_x_mm, y, z, geared)
            lo, hi = sorted(self.tab_hole_zs_mm(z))
            top = self.frame_box_mm(stack_end_x_mm, y, z, floor_mm, geared)[5]
            need(at_least(wz0 - lo - tap / 2, MIN_WALL_MM / 2) and at_least(hi - wz1 - tap / 2, MIN_WALL_MM / 2)
                 and at_least(top - hi - tap / 2, MIN_WALL_MM / 2),
                 f"LatchDriveSpec.servo {self.servo!r}: its tab holes leave no frame round them")
            need(at_least(wz0 - floor_mm, MIN_WALL_MM),
                 f"block_z_mm {z:g}: the {self.servo} latch servo's case ({self.servo_row.axle_from_end_mm:g} mm below "
                 f"its axle) reaches the floor")

    # -- the bought parts ----------------------------------------------------------------
    def component(self, stack_end_x_mm: float, blocks_yz, key: str = "latch_servo", yaw_deg: float = 0.0):
        """The latch servos as one component (a servo stand-in per block), built on a rear face and
        turned ``yaw_deg`` about the robot's vertical axis (a multiple of 90)."""
        from cubot_cad.couplings.twist import ServoStandIn
        from cubot_cad.shapes import yaw_box

        sv = self.servo_row
        centres = []
        for y, z, geared in map(self.place, blocks_yz):
            x0, x1, y0, y1, z0, z1 = yaw_box(self.case_mm(stack_end_x_mm, y, z, geared), yaw_deg)
            centres.append(((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2))
        size = (sv.case_height_mm, sv.case_width_mm, sv.case_length_mm)
        if round(yaw_deg / 90) % 2:
            size = (size[1], size[0], size[2])
        return ServoStandIn(key, sv.describe("driving a latch blade through its D-shaft"), sv.mass_g,
                            tuple(centres), size, "box", "motor", (0.3, 0.3, 0.3), servo_model=sv.name,
                            output="-x" if self.case_up else "-x down", yaw_deg=yaw_deg)

    def gear_components(self, stack_end_x_mm: float, blocks_yz, key: str = "latch_gear", yaw_deg: float = 0.0) -> list:
        """The geared blocks' gear pairs (none when every servo is coaxial): the hubbed gear on each such
        blade's D-shaft and the plain one screwed to its servo's horn, both in the plane
        :meth:`gear_plane_x_mm`, turned like :meth:`component`."""
        geared = [(b[0], self.place(b)) for b in blocks_yz if self.place(b)[2]]
        if not geared:
            return []
        bg, sg = self.gears
        from cubot_cad.shapes import yaw_point

        xc = self.gear_plane_x_mm(stack_end_x_mm) + bg.face_mm / 2
        return [GearStandIn(f"{key}_blade", bg.describe("on a latch blade's D-shaft, set screw on the flat, hub inward"),
                            bg.mass_g, tuple(yaw_point((xc, y, z), yaw_deg) for y, (_sy, z, _g) in geared), (bg.pitch_diameter_mm, bg.face_mm),
                            "cyl_y" if round(yaw_deg / 90) % 2 else "cyl_x", "motor", (0.85, 0.85, 0.8), gear_name=bg.name, yaw_deg=yaw_deg),
                GearStandIn(f"{key}_servo", sg.describe("screwed to the geared latch servo's horn (two M2)"),
                            sg.mass_g, tuple(yaw_point((xc, sy, z), yaw_deg) for _y, (sy, z, _g) in geared), (sg.pitch_diameter_mm, sg.face_mm),
                            "cyl_y" if round(yaw_deg / 90) % 2 else "cyl_x", "motor", (0.85, 0.85, 0.8), gear_name=sg.name, yaw_deg=yaw_deg,
                            horn_stack_mm=self.horn_stack_mm, servo_model=self.servo)]

    def gear_screws(self, robot: str, count: int) -> list:
        """Two M2 per servo gear, through the gear into its horn's innermost arm holes (cut into the
        horn's plastic as the servo's own screws are; the arms cut off :func:`horn_trim_mm` from the
        centre)."""
        from cubot_cad.hardware.fasteners import bolted

        sv = self.servo_row
        return bolted(robot, sv.horn.screw_size, self.gears[1].face_mm, 2 * count,
                      f"latch servo gears onto their {sv.name} horns", thread_mm=sv.horn.arm_mm)[:1]

    def drive_parts(self, shaft_mm: float, flat_mm: float, shaft_length_mm: float, count: int,
                    geared: int = 0) -> list:
        """The D-shafts and the couplers (bought), as :meth:`Robot.drive_parts` rows: ``count`` blocks, of
        which ``geared`` drive through a gear pair (their shafts reach through the blade gear and its hub
        instead of into a coupler)."""
        sv = self.servo_row
        rows = []
        if count - geared:
            rows += [("latch_shaft", "steel D-shaft (0.5 mm flat) from the latch blade into the coupler",
                      f"diameter {shaft_mm:g} x {shaft_length_mm:.0f} mm, {flat_mm:g} mm across the flat", count - geared),
                     ("latch_coupler", f"shaft coupler: {shaft_mm:g} mm D-bore (set screw on the flat) to the {sv.name}'s "
                      f"{sv.horn.spline} spline", f"{self.coupler_mm:.1f} mm long, {SHAFT_INTO_COUPLER_MM:g} mm on the shaft",
                      count - geared)]
        if geared:
            bg = self.gears[0]
            length = shaft_length_mm - SHAFT_INTO_COUPLER_MM + self.proud_mm + COUPLER_GAP_MM + bg.face_mm + bg.hub_mm
            rows.append(("latch_shaft_geared", "steel D-shaft (0.5 mm flat) from the latch blade through its gear's hub",
                         f"diameter {shaft_mm:g} x {length:.0f} mm, {flat_mm:g} mm across the flat", geared))
        return rows


def horn_trim_mm(horn) -> float:
    """A geared servo's horn has its arms cut this far from the centre (mm): 2 mm past the innermost
    holes, which take the screws into the gear (whole arms would sweep into the neighbouring block's
    coupler)."""
    return horn.hole_radii_mm[0] + 2.0


@dataclass(frozen=True)
class GearStandIn(Component):
    """A gear of a geared latch drive as a component: mass and inertia of a disc (``size_mm`` = pitch
    diameter, face; ``kind`` ``cyl_x`` as built on a rear face), one per position (the disc's centre,
    robot frame; built on a rear face and turned ``yaw_deg`` about the vertical axis). Stand-in solid:
    the pitch cylinder less :data:`STANDIN_PITCH_INSET_MM` (two meshing gears' pitch cylinders touch
    along a line; tessellated, exactly tangent ones would overlap), the hub of a hubbed
    gear (on the side away from the stack), and on a servo's gear (``horn_stack_mm`` > 0) the horn
    between it and the servo: its cap and the disc its arms sweep, cut to :func:`horn_trim_mm`."""

    gear_name: str = ""
    yaw_deg: float = 0.0
    horn_stack_mm: float = 0.0
    servo_model: str = "SG90"

    def solids(self):
        from cubot_cad.hardware.gears import gear
        from cubot_cad.hardware.servos import servo
        from cubot_cad.shapes import X, Z, cyl, rotated, yaw_point

        g = gear(self.gear_name)
        out = []
        for p in self.positions_mm:
            x, y, z = yaw_point(p, -self.yaw_deg)
            x -= g.face_mm / 2
            s = cyl(g.pitch_diameter_mm / 2 - STANDIN_PITCH_INSET_MM, g.face_mm, (x, y, z), X)
            if g.hub_mm > 0:
                s = s.fuse(cyl(g.hub_diameter_mm / 2, g.hub_mm + 0.01, (x + g.face_mm - 0.01, y, z), X))
            if self.horn_stack_mm > 0:
                h = servo(self.servo_model).horn
                xa = x + g.face_mm  # the horn's flat arm face on the gear
                s = s.fuse(cyl(horn_trim_mm(h), h.arm_mm, (xa, y, z), X)).fuse(
                    cyl(h.hub_diameter_mm / 2, h.height_mm, (xa, y, z), X))
            out.append(rotated(s.clean(), Z, self.yaw_deg) if self.yaw_deg else s.clean())
        return out
