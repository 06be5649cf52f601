"""The latch blades' drive (mm): a servo from the table (:mod:`cubot_cad.servos`) behind each latch
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
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

from .part import DEFAULT_CLEARANCE_MM, MIN_WALL_MM, at_least, check_clearance, need

#: How far the blade's D-shaft sticks out of the latch stack's last plate into the coupler, mm.
SHAFT_INTO_COUPLER_MM = 6.0
#: The coupler's end stands this far off the latch stack's last plate (it must not rub on it), mm.
COUPLER_GAP_MM = 0.3
#: Between the D-shaft's end and the spline's end inside the coupler, mm.
COUPLER_INNER_GAP_MM = 1.0
#: The tab screws' thread into the frame's tap holes, mm (the twist servo's bosses take 5 mm; the
#: frame is a plate, 3 mm of M2 thread is 7.5 pitches).
TAB_THREAD_MM = 3.0


@dataclass(frozen=True)
class LatchDriveSpec:
    """The latch servos and their mounting frames (mm)."""

    servo: str = "SG90"
    case_up: bool = True
    frame_mm: float = 5.0
    frame_margin_mm: float = 2.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm)
        from .cubot import check_dims

        check_dims(self, ("frame_mm", "frame_margin_mm"))
        self.servo_row  # noqa: B018 (an unknown servo is refused here)
        need(at_least(self.frame_margin_mm, MIN_WALL_MM),
             f"LatchDriveSpec.frame_margin_mm {self.frame_margin_mm:g} leaves under {MIN_WALL_MM:g} mm of frame beside "
             "the servo's case")
        need(at_least(self.frame_mm - self.tab_tap_depth_mm(), MIN_WALL_MM / 2),
             f"LatchDriveSpec.frame_mm {self.frame_mm:g} is thinner than the {self.tab_tap_depth_mm():.2f} mm tab-screw "
             "tap holes")

    @cached_property
    def servo_row(self):
        from .servos import servo

        return servo(self.servo)

    @property
    def coupler_mm(self) -> float:
        """The coupler's length: the shaft's engagement, the spline's, and the gap between them."""
        return SHAFT_INTO_COUPLER_MM + self.servo_row.spline_mm + COUPLER_INNER_GAP_MM

    def face_x_mm(self, stack_end_x_mm: float) -> float:
        """x of the servo's output face for a latch stack ending at ``stack_end_x_mm`` (robot frame)."""
        return stack_end_x_mm + COUPLER_GAP_MM + self.coupler_mm

    def case_mm(self, stack_end_x_mm: float, y: float, z: float) -> tuple[float, float, float, float, float, float]:
        """The servo case's box (x0, x1, y0, y1, z0, z1) for the block centred at (``y``, ``z``)."""
        sv = self.servo_row
        xf = self.face_x_mm(stack_end_x_mm)
        z0 = z - sv.axle_from_end_mm if self.case_up else z + sv.axle_from_end_mm - sv.case_length_mm
        return (xf, xf + sv.case_height_mm, y - sv.case_width_mm / 2, y + sv.case_width_mm / 2, z0,
                z0 + sv.case_length_mm)

    def tabs_mm(self, stack_end_x_mm: float, y: float, z: float) -> tuple[float, float, float, float, float, float]:
        """The tabs' box (x0, x1, y0, y1, z0, z1)."""
        sv = self.servo_row
        x0, _x1, y0, y1, z0, z1 = self.case_mm(stack_end_x_mm, y, z)
        zc = (z0 + z1) / 2
        xt = x0 + sv.tab_from_face_mm
        return (xt, xt + sv.tab_mm, y0, y1, zc - sv.tab_length_mm / 2, zc + sv.tab_length_mm / 2)

    def tab_hole_zs_mm(self, z: float) -> tuple[float, float]:
        """z of the two tab holes for a block centred at height ``z`` (the servo's axle there)."""
        sv = self.servo_row
        return tuple(z - d if self.case_up else z + d for d in sv.hole_offsets_mm())

    def frame_box_mm(self, stack_end_x_mm: float, y: float, z: float, floor_mm: float):
        """The frame plate (x0, x1, y0, y1, z0, z1): behind the tabs, from 0.01 mm into the floor to the
        tabs' top."""
        _tx0, tx1, _y0, _y1, _tz0, tz1 = self.tabs_mm(stack_end_x_mm, y, z)
        a = self.servo_row.case_width_mm / 2 + self.clearance_mm + self.frame_margin_mm
        return (tx1, tx1 + self.frame_mm, y - a, y + a, floor_mm - 0.01, tz1)

    def frame_window_mm(self, stack_end_x_mm: float, y: float, z: float):
        """The window the case passes through (its box plus the clearance)."""
        c = self.clearance_mm
        x0, x1, y0, y1, z0, z1 = self.case_mm(stack_end_x_mm, y, z)
        return (x0, x1 + 1.0, y0 - c, y1 + c, z0 - c, z1 + c)

    # -- fasteners -----------------------------------------------------------------------
    def tab_screws(self, robot: str, count: int) -> list:
        """The tab screws: ISO 4762 through a tab into a tap hole in the frame, :data:`TAB_THREAD_MM` of
        thread (two per servo)."""
        from .fasteners import bolted

        sv = self.servo_row
        return bolted(robot, sv.screw_size, sv.tab_mm, 2 * count,
                      f"{sv.name} latch servos' tabs onto the body's latch-servo frames", thread_mm=TAB_THREAD_MM)[:1]

    def tab_tap_depth_mm(self) -> float:
        return self.tab_screws("-", 1)[0].length_mm - self.servo_row.tab_mm + 0.5

    # -- the body's frames ---------------------------------------------------------------
    def frames(self, stack_end_x_mm: float, blocks_yz, floor_mm: float, keep_out=()) -> list:
        """The frame plates with their windows and tap holes, one per block (robot frame), to fuse into
        the body; ``keep_out``: solids cut from them (the twist horn's swept volume)."""
        from .fasteners import tap_hole_mm
        from .shapes import X, box, cut_all, cyl

        out = []
        tap = tap_hole_mm(self.servo_row.screw_size) / 2
        depth = self.tab_tap_depth_mm()
        for y, z in blocks_yz:
            plate = box(*self.frame_box_mm(stack_end_x_mm, y, z, floor_mm))
            x0 = plate.BoundingBox().xmin
            holes = [cyl(tap, depth + 0.1, (x0 - 0.1, y, zt), X) for zt in self.tab_hole_zs_mm(z)]
            out.append(cut_all(plate, [box(*self.frame_window_mm(stack_end_x_mm, y, z))] + holes + list(keep_out)))
        return out

    def check_frames(self, stack_end_x_mm: float, blocks_yz, floor_mm: float) -> None:
        """The tap holes keep a wall to the window and the frame's top; the case clears the floor."""
        from .fasteners import tap_hole_mm

        tap = tap_hole_mm(self.servo_row.screw_size)
        for y, z in blocks_yz:
            _x0, _x1, _y0, _y1, wz0, wz1 = self.frame_window_mm(stack_end_x_mm, y, z)
            lo, hi = sorted(self.tab_hole_zs_mm(z))
            top = self.frame_box_mm(stack_end_x_mm, y, z, floor_mm)[5]
            need(at_least(wz0 - lo - tap / 2, MIN_WALL_MM / 2) and at_least(hi - wz1 - tap / 2, MIN_WALL_MM / 2)
                 and at_least(top - hi - tap / 2, MIN_WALL_MM / 2),
                 f"LatchDriveSpec.servo {self.servo!r}: its tab holes leave no frame round them")
            need(at_least(wz0 - floor_mm, MIN_WALL_MM),
                 f"block_z_mm {z:g}: the {self.servo} latch servo's case ({self.servo_row.axle_from_end_mm:g} mm below "
                 f"its axle) reaches the floor")

    # -- the bought parts ----------------------------------------------------------------
    def component(self, stack_end_x_mm: float, blocks_yz):
        """The latch servos as one component (a servo stand-in per block)."""
        from .twist import ServoStandIn

        sv = self.servo_row
        centres = []
        for y, z in blocks_yz:
            x0, x1, y0, y1, z0, z1 = self.case_mm(stack_end_x_mm, y, z)
            centres.append(((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2))
        return ServoStandIn("latch_servo", sv.describe("driving a latch blade through its D-shaft"), sv.mass_g,
                            tuple(centres), (sv.case_height_mm, sv.case_width_mm, sv.case_length_mm), "box", "motor",
                            (0.3, 0.3, 0.3), servo_model=sv.name, output="-x" if self.case_up else "-x down")

    def drive_parts(self, shaft_mm: float, flat_mm: float, shaft_length_mm: float, count: int) -> list:
        """The D-shafts and the couplers (bought), as :meth:`Robot.drive_parts` rows."""
        sv = self.servo_row
        return [("latch_shaft", "steel D-shaft (0.5 mm flat) from the latch blade into the coupler",
                 f"diameter {shaft_mm:g} x {shaft_length_mm:.0f} mm, {flat_mm:g} mm across the flat", count),
                ("latch_coupler", f"shaft coupler: {shaft_mm:g} mm D-bore (set screw on the flat) to the {sv.name}'s "
                 f"{sv.horn.spline} spline", f"{self.coupler_mm:.1f} mm long, {SHAFT_INTO_COUPLER_MM:g} mm on the shaft",
                 count)]

