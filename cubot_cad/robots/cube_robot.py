"""Cube Robot (thesis Ch. 6.3.1): <= 120 mm cube in three printed tiers.

* wheel block (bottom): four wheels in an Ackermann layout (front pair steered);
  each wheel's well in the floor is the plan footprint the wheel sweeps over its steering
  range (:func:`swept_half_extents_mm`) plus :data:`WELL_MARGIN_MM`, and the track is derived
  so a wheel at full lock keeps :data:`WHEEL_GAP_MM` to the inner walls (inside the 120 mm cube);
* connector cuboid (middle): grooved-pin blocks front AND right, latch blocks
  rear AND left (two blocks per side);
* sensor cylinder (top): 16 IR proximity windows, 8 light-sensor windows, standing on a square
  base plate.

The tiers locate and fasten (:class:`TierJoint`): the cuboid sits on the wheel block's walls,
located by four tabs (on ribs inside the wheel block's walls, mid-side) in slots through its floor,
and is screwed down through its floor into heat-set inserts in the wheel block's corner bosses; the
sensor tier's base plate sits inside a lip (the outer part of the cuboid's walls, raised) and is
screwed at its corners into inserts in the cuboid's top corner bosses. Every boss and rib hangs
from the walls on a 45 deg underside (no support).

Its pins are the thesis's design: ``pin_protrusion_mm`` longer than the latch
depth, so two docked Cube Robots stop with a gap (the thesis measured 1.7 mm)
that comes out of the geometry (:mod:`cubot_cad.checks.docking` measures it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import ClassVar

from cubot_cad.couplings import compliance as couplings
from cubot_cad.couplings.connectors import FrontRearSpec, latch_set_parts, pin_set_parts
from cubot_cad.couplings.latch_drive import SHAFT_INTO_COUPLER_MM, LatchDriveSpec
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

ENVELOPE_MM = 120.0
#: A wheel (at any steering angle) keeps this gap to the tier's inner walls (mm).
WHEEL_GAP_MM = 1.0
#: A wheel's well in the floor is its swept plan footprint plus this much all round (mm).
WELL_MARGIN_MM = 0.8
#: Thesis pins: 1.7 mm longer than the latch stack is deep (Ch. 6.3.1.3).
THESIS_PIN_OVERRUN_MM = 1.7
#: The 2S 1000 mAh LiPo's stand-in (mm; x, y, z as it lies in the wheel block).
BATTERY_MM = (35.0, 70.0, 18.0)


def swept_half_extents_mm(radius_mm: float, width_mm: float, steer_deg: float) -> tuple[float, float]:
    """Half extents (along x, along y; mm) of the plan footprint of a wheel (``radius_mm``, ``width_mm``,
    axle along y) that turns about the vertical through its centre from ``-steer_deg`` to ``+steer_deg``.

    The footprint at angle t is a 2r x w rectangle turned by t: its x half extent r cos t + (w/2) sin t
    peaks at t = atan(w / 2r) (the diagonal, if inside the range), its y half extent r sin t + (w/2) cos t
    grows with |t| up to the full lock."""
    r, a, t = radius_mm, width_mm / 2, math.radians(steer_deg)
    hx = math.hypot(r, a) if math.atan2(a, r) <= t else r * math.cos(t) + a * math.sin(t)
    return hx, r * math.sin(t) + a * math.cos(t)


@dataclass(frozen=True)
class TierJoint:
    """How a tier locates and fastens on the one below it (mm; tier frame: z up, x/y from the centre).

    ``screw_size``: the screws (ISO 4762) go down through clearance holes in the upper tier into
    heat-set inserts in ``boss_mm`` square corner bosses of the lower tier, the holes ``screw_inset_mm``
    from the outer faces; each boss is ``boss_depth_mm`` of full section under the top, then a 45 deg
    underside. Tabs (``tab_width_mm`` across the side, ``tab_length_mm`` along it) rise ``tab_mm`` from
    ribs on the lower tier's inner wall faces (``rib_depth_mm`` full section, then 45 deg) into slots
    through the upper tier's floor that are the tab plus ``clearance_mm`` all round: the upper tier
    cannot slide further than the clearance. ``tab_mm == 0`` leaves the tabs out (a lip locates instead)."""

    screw_size: str = "M3"
    screw_inset_mm: float = 6.0
    boss_mm: float = 9.0
    boss_depth_mm: float = 8.0
    tab_mm: float = 2.0
    tab_width_mm: float = 2.5
    tab_length_mm: float = 16.0
    rib_depth_mm: float = 2.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        from cubot_cad.hardware.fasteners import thread
        from cubot_cad.part import check_lengths

        check_clearance(self.clearance_mm, "TierJoint.clearance_mm")
        check_lengths(self, ("screw_inset_mm", "boss_mm", "boss_depth_mm", "tab_width_mm", "tab_length_mm",
                             "rib_depth_mm"), ("tab_mm",), "TierJoint.")
        ins = thread(self.screw_size)
        need(at_least(self.screw_inset_mm - ins.insert_hole_mm / 2, MIN_WALL_MM),
             f"TierJoint.screw_inset_mm {self.screw_inset_mm:g} puts the {ins.insert_hole_mm:g} mm insert holes "
             f"closer than {MIN_WALL_MM:g} mm to the outer wall")
        need(at_least(self.boss_depth_mm, ins.insert_hole_depth_mm + MIN_WALL_MM),
             f"TierJoint.boss_depth_mm {self.boss_depth_mm:g} is shallower than the {ins.insert_hole_depth_mm:g} mm "
             f"insert hole plus a {MIN_WALL_MM:g} mm floor")
        need(at_least(self.tab_width_mm, MIN_WALL_MM),
             f"TierJoint.tab_width_mm {self.tab_width_mm:g} is thinner than {MIN_WALL_MM:g} mm")

    def check_walls(self, wall_mm: float, floor_mm: float | None = None) -> None:
        """The bosses keep material round their inserts in a tier of ``wall_mm`` walls and the screw heads
        clear the walls; the tabs fit in the upper tier's ``floor_mm`` floor (where given)."""
        from cubot_cad.hardware.fasteners import thread

        ins = thread(self.screw_size)
        need(at_least(self.boss_mm + wall_mm - self.screw_inset_mm - ins.insert_hole_mm / 2, MIN_WALL_MM),
             f"TierJoint.boss_mm {self.boss_mm:g} leaves under {MIN_WALL_MM:g} mm of boss round the insert holes")
        need(at_least(self.screw_inset_mm - ins.shcs_head_diameter_mm / 2, wall_mm + self.clearance_mm),
             f"TierJoint.screw_inset_mm {self.screw_inset_mm:g} puts the {ins.shcs_head_diameter_mm:g} mm screw heads "
             f"into the {wall_mm:g} mm walls (keep the clearance {self.clearance_mm:g} mm)")
        if floor_mm is not None:
            need(at_most(self.tab_mm, floor_mm),
                 f"TierJoint.tab_mm {self.tab_mm:g} is taller than the {floor_mm:g} mm floor its slots go through")

    def screw_points(self, half_mm: float) -> list[tuple[float, float]]:
        """(x, y) of the four screws in a tier ``2 * half_mm`` square."""
        a = half_mm - self.screw_inset_mm
        return [(sx * a, sy * a) for sx in (-1, 1) for sy in (-1, 1)]

    def bosses(self, half_mm: float, wall_mm: float, z_top: float) -> list:
        """The four corner bosses under ``z_top`` (the CuBot's cover bosses: a box and a 45 deg pyramid,
        clipped to the hollow)."""
        from cubot_cad.shapes import box, frustum

        hi, B = half_mm - wall_mm, self.boss_mm
        zb = z_top - self.boss_depth_mm
        inner = box(-hi, hi, -hi, hi, zb - B - 1, z_top)
        out = []
        for sx in (-1, 1):
            for sy in (-1, 1):
                cx, cy = sx * hi, sy * hi
                solid = box(cx - B, cx + B, cy - B, cy + B, zb, z_top).fuse(
                    frustum((0.05, 0.05), (B + 0.01, B + 0.01), zb - B + 0.04, zb + 0.01, (cx, cy)))
                out.append(solid.intersect(inner))
        return out

    def insert_holes(self, half_mm: float, z_top: float) -> list:
        from cubot_cad.hardware.fasteners import thread
        from cubot_cad.shapes import Z, cyl

        ins = thread(self.screw_size)
        return [cyl(ins.insert_hole_mm / 2, ins.insert_hole_depth_mm + 0.1, (x, y, z_top - ins.insert_hole_depth_mm), Z)
                for x, y in self.screw_points(half_mm)]

    def clearance_holes(self, half_mm: float, z0: float, depth_mm: float) -> list:
        from cubot_cad.hardware.fasteners import clearance_hole_mm
        from cubot_cad.shapes import Z, cyl

        r = clearance_hole_mm(self.screw_size) / 2
        return [cyl(r, depth_mm + 2, (x, y, z0 - 1), Z) for x, y in self.screw_points(half_mm)]

    def _per_side(self, shape) -> list:
        from cubot_cad.shapes import Z, rotated

        return [rotated(shape, Z, 90 * k) for k in range(4)]

    def ribs_and_tabs(self, half_mm: float, wall_mm: float, z_top: float) -> list:
        """The ribs on the four inner wall faces (mid-side) and the tabs on them, rising ``tab_mm``
        above ``z_top``; a tab's outer face is ``clearance_mm`` in from the wall's inner face."""
        from cubot_cad.shapes import box, prism

        if self.tab_mm <= 0:
            return []
        hi, t, c, h = half_mm - wall_mm, self.tab_width_mm, self.clearance_mm, self.tab_length_mm / 2
        x0, x1 = hi - c - t, hi + 0.01  # the rib: from the tab's inner face into the wall (a clean fuse)
        zr = z_top - self.rib_depth_mm
        rib = prism([(x1, zr - (x1 - x0)), (x1, z_top), (x0, z_top), (x0, zr)], "XZ", -h, 2 * h)
        tab = box(hi - c - t, hi - c, -h, h, z_top - 0.01, z_top + self.tab_mm)
        return self._per_side(rib) + self._per_side(tab)

    def slots(self, half_mm: float, wall_mm: float, z0: float, depth_mm: float) -> list:
        """The slots through the upper tier's floor (from ``z0``, ``depth_mm`` thick): each tab plus
        the clearance all round."""
        from cubot_cad.shapes import box

        if self.tab_mm <= 0:
            return []
        hi, t, c, h = half_mm - wall_mm, self.tab_width_mm, self.clearance_mm, self.tab_length_mm / 2
        return self._per_side(box(hi - 2 * c - t, hi, -h - c, h + c, z0 - 1, z0 + depth_mm + 1))


@dataclass(frozen=True)
class WheelBlock(Part):
    """Cube Robot tier 1 (robot frame, mm): a ``size_mm`` square hollow block, ``height_mm`` tall.

    Four wheels (``wheel_radius_mm`` x ``wheel_width_mm``, axles along y) at x = +-``wheel_x_mm``,
    y = +-``wheel_y_mm``; the front pair (x > 0) steers +-``steer_deg`` about the vertical through the
    wheel's centre. Each wheel's well through the floor is the footprint it sweeps
    (:func:`swept_half_extents_mm`) plus :data:`WELL_MARGIN_MM`; :meth:`validate` refuses a layout in
    which a wheel at full lock comes nearer than :data:`WHEEL_GAP_MM` to the inner walls. ``joint``: the
    corner bosses (inserts for the cuboid's screws) and the locating tabs on top (:class:`TierJoint`)."""

    size_mm: float = 120.0
    height_mm: float = 30.0
    wall_mm: float = 2.4
    floor_mm: float = 3.0
    wheel_radius_mm: float = 20.0
    wheel_width_mm: float = 10.0
    wheel_x_mm: float = 35.0
    wheel_y_mm: float = 41.5
    steer_deg: float = 30.0
    joint: TierJoint = TierJoint()
    name: ClassVar[str] = "cube_wheel_block"
    description: ClassVar[str] = ("Cube Robot tier 1: wheel block, four wheel wells (Ackermann, front steered), "
                                  "corner insert bosses, locating tabs")

    def validate(self) -> None:
        self.wall_check("wall_mm", self.wall_mm)
        self.wall_check("floor_mm", self.floor_mm)
        need(isinstance(self.steer_deg, (int, float)) and not isinstance(self.steer_deg, bool)
             and 0 <= self.steer_deg < 90, f"WheelBlock.steer_deg must be in 0-90 deg, got {self.steer_deg!r}")
        need(abs(self.joint.clearance_mm - self.clearance_mm) < 1e-12,
             f"WheelBlock.joint.clearance_mm {self.joint.clearance_mm:g} differs from clearance_mm {self.clearance_mm:g}")
        self.joint.check_walls(self.wall_mm)
        hi = self.size_mm / 2 - self.wall_mm
        hx, hy = swept_half_extents_mm(self.wheel_radius_mm, self.wheel_width_mm, self.steer_deg)
        r = self.wheel_radius_mm
        need(at_most(self.wheel_y_mm + hy + WHEEL_GAP_MM, hi),
             f"wheel_y_mm {self.wheel_y_mm:g}: the front wheels turned {self.steer_deg:g} deg reach "
             f"{self.wheel_y_mm + hy:.2f} mm from the middle, past the inner walls less {WHEEL_GAP_MM:g} mm "
             f"({hi - WHEEL_GAP_MM:.2f} mm; size_mm {self.size_mm:g}, wall_mm {self.wall_mm:g}): "
             f"wheel_y_mm <= {hi - WHEEL_GAP_MM - hy:.2f}")
        need(at_least(self.wheel_y_mm - hy - WELL_MARGIN_MM, WHEEL_GAP_MM),
             f"wheel_y_mm {self.wheel_y_mm:g}: the left and right front wells ({self.steer_deg:g} deg lock) meet "
             f"in the middle")
        need(at_most(self.wheel_x_mm + hx + WHEEL_GAP_MM, hi),
             f"wheel_x_mm {self.wheel_x_mm:g}: the front wheels turned {self.steer_deg:g} deg reach "
             f"{self.wheel_x_mm + hx:.2f} mm forward, past the inner wall less {WHEEL_GAP_MM:g} mm "
             f"({hi - WHEEL_GAP_MM:.2f} mm): wheel_x_mm <= {hi - WHEEL_GAP_MM - hx:.2f}")
        need(at_least(self.wheel_x_mm - hx - WELL_MARGIN_MM, -self.wheel_x_mm + r + WELL_MARGIN_MM + WHEEL_GAP_MM),
             f"wheel_x_mm {self.wheel_x_mm:g}: the front and rear wheel wells meet")
        rib = self.joint.tab_length_mm / 2 + WHEEL_GAP_MM  # the ribs are mid-side, this far either way
        need(at_least(min(self.wheel_x_mm - hx, self.wheel_x_mm - r), rib) and at_least(self.wheel_y_mm - hy, rib),
             f"wheel_x_mm {self.wheel_x_mm:g}, wheel_y_mm {self.wheel_y_mm:g}: the wheels reach the locating ribs "
             f"(mid-side, {self.joint.tab_length_mm:g} mm long)")

    def wheel_centres_mm(self) -> list[tuple[float, float, bool]]:
        """(x, y, steered) of the four wheels' centres in plan."""
        return [(x, y, x > 0) for x in (-self.wheel_x_mm, self.wheel_x_mm) for y in (-self.wheel_y_mm, self.wheel_y_mm)]

    def build(self):
        from cubot_cad.shapes import box, cut_all, fuse_all

        S, H, w, f = self.size_mm / 2, self.height_mm, self.wall_mm, self.floor_mm
        j = self.joint
        shell = box(-S, S, -S, S, 0, H).cut(box(-S + w, S - w, -S + w, S - w, f, H + 1))
        shell = fuse_all([shell] + j.bosses(S, w, H) + j.ribs_and_tabs(S, w, H))
        cut = j.insert_holes(S, H)
        m = WELL_MARGIN_MM
        for x, y, steered in self.wheel_centres_mm():
            hx, hy = swept_half_extents_mm(self.wheel_radius_mm, self.wheel_width_mm,
                                           self.steer_deg if steered else 0.0)
            cut.append(box(x - hx - m, x + hx + m, y - hy - m, y + hy + m, -1, f + 1))
        return cut_all(shell, cut)


@dataclass(frozen=True)
class ConnectorCuboid(Part):
    """Cube Robot tier 2 (robot frame, mm): from ``z0_mm`` to ``z0_mm + height_mm``.

    ``below``: how it sits on the wheel block (clearance holes and the tabs' slots through the floor);
    ``above``: the corner bosses with inserts for the sensor tier's screws; the outer ``lip_wall_mm`` of
    the walls rises ``lip_mm`` above the top, a lip round the sensor tier's base plate."""

    size_mm: float = 120.0
    height_mm: float = 50.0
    z0_mm: float = 30.0
    wall_mm: float = 2.4
    floor_mm: float = 3.0
    block_offset_mm: float = 22.0
    lip_mm: float = 2.0
    lip_wall_mm: float = 1.0
    fr: FrontRearSpec = FrontRearSpec()
    below: TierJoint = TierJoint()
    above: TierJoint = TierJoint(tab_mm=0.0)
    #: The latch servos' frames (:mod:`cubot_cad.couplings.latch_drive`), standing on the floor: ``latch`` and,
    #: per latch face, ``(yaw_deg, places)`` with the places in the rear face's frame
    #: (:meth:`CubeRobot.latch_places`); none by default.
    latch: LatchDriveSpec | None = None
    latch_places: tuple = ()
    name: ClassVar[str] = "cube_connector_cuboid"
    description: ClassVar[str] = ("Cube Robot tier 2: connector cuboid, pin holes front/right, latch holes rear/left, "
                                  "floor screw holes and tab slots, top corner insert bosses and lip, latch-servo frames")

    def validate(self) -> None:
        self.wall_check("wall_mm", self.wall_mm)
        self.wall_check("floor_mm", self.floor_mm)
        self.wall_check("lip_wall_mm", self.lip_wall_mm)
        need(at_least(self.wall_mm - self.lip_wall_mm - self.clearance_mm, MIN_WALL_MM),
             f"ConnectorCuboid.lip_wall_mm {self.lip_wall_mm:g} leaves under {MIN_WALL_MM:g} mm of the "
             f"{self.wall_mm:g} mm wall top for the sensor tier to bear on")
        for j in (self.below, self.above):
            need(abs(j.clearance_mm - self.clearance_mm) < 1e-12,
                 f"ConnectorCuboid: a joint's clearance_mm {j.clearance_mm:g} differs from clearance_mm "
                 f"{self.clearance_mm:g}")
        for j in (self.below, self.above):
            j.check_walls(self.wall_mm, self.floor_mm)
        if self.latch is not None:
            for _yaw, places in self.latch_places:
                self.latch.check_frames(self.latch_stack_end_mm, places, self.z0_mm + self.floor_mm)

    @property
    def top_mm(self) -> float:
        return self.z0_mm + self.height_mm

    @property
    def latch_stack_end_mm(self) -> float:
        """x where a rear face's latch stacks end inside the cuboid (the rear face's frame)."""
        return self.stack_end_mm(self.size_mm, self.fr)

    @staticmethod
    def stack_end_mm(size_mm: float, fr: FrontRearSpec) -> float:
        """:attr:`latch_stack_end_mm` of a cuboid ``size_mm`` wide with connector blocks ``fr``."""
        return -size_mm / 2 + fr.latch_stack_mm

    def latch_frames(self) -> list:
        """The latch servos' frames, turned onto their faces."""
        from cubot_cad.shapes import Z, rotated

        if self.latch is None:
            return []
        return [rotated(f, Z, yaw) if yaw else f for yaw, places in self.latch_places
                for f in self.latch.frames(self.latch_stack_end_mm, places, self.z0_mm + self.floor_mm)]

    def build(self):
        from cubot_cad.shapes import box, cut_all, fuse_all, location

        S, w, f = self.size_mm / 2, self.wall_mm, self.floor_mm
        z0, z1 = self.z0_mm, self.top_mm
        shell = box(-S, S, -S, S, z0, z1).cut(box(-S + w, S - w, -S + w, S - w, z0 + f, z1 + 1))
        li = S - self.lip_wall_mm
        lip = box(-S, S, -S, S, z1 - 0.01, z1 + self.lip_mm).cut(box(-li, li, -li, li, z1 - 1, z1 + self.lip_mm + 1))
        shell = fuse_all([shell, lip] + self.above.bosses(S, w, z1) + self.latch_frames())
        zb = (z0 + z1) / 2
        cut = self.above.insert_holes(S, z1) + self.below.clearance_holes(S, z0, f) + self.below.slots(S, w, z0, f)
        # pins front (0 deg) and right (-90 = 270 deg), latches rear (180 deg) and left (90 deg)
        for rot, side in ((0, "pin"), (90, "latch"), (180, "latch"), (270, "pin")):
            for o in (-self.block_offset_mm, self.block_offset_mm):
                loc = location((0, 0, zb), rot) * location((S, o, 0))
                cut += [t.moved(loc) for t in self.fr.wall_cutters(side)]
        cut.append(box(-10, 10, -10, 10, z0 - 1, z0 + f + 1))  # wiring to the wheel block
        return cut_all(shell, cut)


@dataclass(frozen=True)
class SensorCylinder(Part):
    """Cube Robot tier 3 (robot frame, mm): a cylinder (``diameter_mm``, ``wall_mm``) standing on a square
    base plate (``floor_mm`` thick) that fits inside the cuboid's lip (``size_mm`` less twice
    ``lip_wall_mm`` and the clearance) and is screwed at its corners into the cuboid's bosses (``joint``)."""

    diameter_mm: float = 116.0
    height_mm: float = 40.0
    z0_mm: float = 80.0
    wall_mm: float = 2.4
    floor_mm: float = 3.0
    size_mm: float = 120.0
    lip_wall_mm: float = 1.0
    joint: TierJoint = TierJoint(tab_mm=0.0)
    name: ClassVar[str] = "cube_sensor_cylinder"
    description: ClassVar[str] = ("Cube Robot tier 3: sensor cylinder on a square base plate (corner screw holes), "
                                  "16 IR proximity and 8 light-sensor windows")

    @property
    def plate_half_mm(self) -> float:
        """Half the base plate's side: inside the cuboid's lip by the clearance."""
        return self.size_mm / 2 - self.lip_wall_mm - self.clearance_mm

    def validate(self) -> None:
        self.wall_check("wall_mm", self.wall_mm)
        self.wall_check("floor_mm", self.floor_mm)
        need(at_most(self.diameter_mm / 2, self.plate_half_mm),
             f"SensorCylinder.diameter_mm {self.diameter_mm:g} overhangs its {2 * self.plate_half_mm:g} mm base plate")

    def build(self):
        from cubot_cad.shapes import Z, box, cut_all, cyl, rotated

        R, z0, f, P = self.diameter_mm / 2, self.z0_mm, self.floor_mm, self.plate_half_mm
        tube = cyl(R, self.height_mm - f + 0.01, (0, 0, z0 + f - 0.01), Z).cut(
            cyl(R - self.wall_mm, self.height_mm, (0, 0, z0 + f - 1), Z))
        body = box(-P, P, -P, P, z0, z0 + f).fuse(tube).clean()
        cut = [rotated(box(R - 5, R + 1, -2.5, 2.5, z0 + 12, z0 + 17), Z, 22.5 * k) for k in range(16)]
        cut += [rotated(box(R - 5, R + 1, -3, 3, z0 + 26, z0 + 32), Z, 45 * k + 11.25) for k in range(8)]
        cut.append(cyl(8.0, f + 2, (0, 0, z0 - 1), Z))
        cut += self.joint.clearance_holes(self.size_mm / 2, z0, f)
        return cut_all(body, cut)


@dataclass(frozen=True)
class CubeRobot(Robot):
    size_mm: float = 120.0
    wheel_block_mm: float = 30.0
    cuboid_mm: float = 50.0
    sensor_mm: float = 40.0
    wall_mm: float = 2.4
    wheel_radius_mm: float = 20.0
    wheel_width_mm: float = 10.0
    wheel_exposed_mm: float = 15.0
    wheel_x_mm: float = 35.0
    #: Half the track (mm); ``None``: as wide as the front wheels at full lock allow (they keep
    #: :data:`WHEEL_GAP_MM` to the inner walls), 42.27 mm at the defaults (it was 48: turned 30 deg the
    #: wheels cut 37.8 mm^3 into the block and stuck out of the 120 mm cube).
    wheel_y_mm: float | None = None
    #: Full lock of the steered front wheels either way (deg).
    steer_deg: float = 30.0
    block_offset_mm: float = 22.0
    pin_overrun_mm: float = THESIS_PIN_OVERRUN_MM
    #: The grooved pins and their neck (:class:`~cubot_cad.couplings.connectors.FrontRearSpec`), mm.
    pin_diameter_mm: float = 5.0
    groove_diameter_mm: float = 3.4
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    #: The latch servos (:mod:`cubot_cad.couplings.latch_drive`; default: the servo table's SG90, case up).
    latch: LatchDriveSpec | None = None

    name: ClassVar[str] = "cube-robot"
    title: ClassVar[str] = "Cube Robot"

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        check_dims(self, ("size_mm", "wheel_block_mm", "cuboid_mm", "sensor_mm", "wall_mm", "wheel_radius_mm",
                          "wheel_width_mm", "wheel_exposed_mm", "wheel_x_mm", "block_offset_mm",
                          "pin_diameter_mm", "groove_diameter_mm") + (() if self.wheel_y_mm is None else ("wheel_y_mm",)))
        need(self.pin_overrun_mm >= 0, f"pin_overrun_mm must be >= 0, got {self.pin_overrun_mm!r}")
        need(self.size_mm <= ENVELOPE_MM, f"size_mm {self.size_mm:g} is outside the Cube Robot envelope 120 mm")
        need(self.height_mm <= ENVELOPE_MM,
             f"wheel_block_mm + cuboid_mm + sensor_mm = {self.height_mm:g} mm exceeds the 120 mm cube")
        need(self.wall_mm >= MIN_WALL_MM, f"wall_mm {self.wall_mm:g} is thinner than {MIN_WALL_MM:g} mm")
        fr = self.fr_spec
        need(self.cuboid_mm >= fr.block_mm + 6, f"cuboid_mm {self.cuboid_mm:g} is lower than a connector block")
        need(at_most(self.block_offset_mm + fr.block_mm / 2, self.size_mm / 2 - fr.latch_depth_mm - fr.rear_plate_mm)
             and self.block_offset_mm >= fr.block_mm / 2,
             f"block_offset_mm {self.block_offset_mm:g}: blocks on adjacent faces would collide in the corners")
        need(self.wheel_exposed_mm < self.wheel_radius_mm,
             f"wheel_exposed_mm {self.wheel_exposed_mm:g} must be less than wheel_radius_mm {self.wheel_radius_mm:g}")
        need(self.wheel_radius_mm - self.wheel_exposed_mm + self.wheel_radius_mm + 2 <= self.wheel_block_mm,
             f"wheel_radius_mm {self.wheel_radius_mm:g} does not fit in wheel_block_mm {self.wheel_block_mm:g}")
        # the parts validate their own rules (wheels at full lock, bosses, lip, plate)
        self.wheel_block, self.cuboid, self.sensor_tier  # noqa: B018

    @property
    def height_mm(self) -> float:
        return self.wheel_block_mm + self.cuboid_mm + self.sensor_mm

    @property
    def track_half_mm(self) -> float:
        """Half the track (mm): ``wheel_y_mm``, or the widest at which the front wheels at full lock keep
        :data:`WHEEL_GAP_MM` to the wheel block's inner walls."""
        if self.wheel_y_mm is not None:
            return float(self.wheel_y_mm)
        _hx, hy = swept_half_extents_mm(self.wheel_radius_mm, self.wheel_width_mm, self.steer_deg)
        return self.size_mm / 2 - self.wall_mm - WHEEL_GAP_MM - hy

    @property
    def screw_inset_mm(self) -> float:
        """The tier screws' inset from the outer faces: :class:`TierJoint`'s, or more where a thick wall
        (and the clearance) would take the screw heads."""
        from cubot_cad.hardware.fasteners import thread

        head = thread(TierJoint.screw_size).shcs_head_diameter_mm / 2
        return max(TierJoint.screw_inset_mm, self.wall_mm + self.clearance_mm + head)

    @cached_property
    def joint(self) -> TierJoint:
        """Wheel block to cuboid: corner screws into inserts, tabs in floor slots."""
        return TierJoint(screw_inset_mm=self.screw_inset_mm, clearance_mm=self.clearance_mm)

    @cached_property
    def top_joint(self) -> TierJoint:
        """Cuboid to sensor tier: corner screws into inserts; the cuboid's lip locates the base plate."""
        return TierJoint(tab_mm=0.0, screw_inset_mm=self.screw_inset_mm, clearance_mm=self.clearance_mm)

    @cached_property
    def wheel_block(self) -> WheelBlock:
        return WheelBlock(size_mm=self.size_mm, height_mm=self.wheel_block_mm, wall_mm=self.wall_mm,
                          wheel_radius_mm=self.wheel_radius_mm, wheel_width_mm=self.wheel_width_mm,
                          wheel_x_mm=self.wheel_x_mm, wheel_y_mm=self.track_half_mm, steer_deg=self.steer_deg,
                          joint=self.joint, clearance_mm=self.clearance_mm)

    @cached_property
    def cuboid(self) -> ConnectorCuboid:
        return ConnectorCuboid(size_mm=self.size_mm, height_mm=self.cuboid_mm, z0_mm=self.wheel_block_mm,
                               wall_mm=self.wall_mm, block_offset_mm=self.block_offset_mm, fr=self.fr_spec,
                               below=self.joint, above=self.top_joint, clearance_mm=self.clearance_mm,
                               latch=self.latch_spec, latch_places=self.latch_places)

    @cached_property
    def latch_spec(self) -> LatchDriveSpec:
        """The latch servos: ``latch``, or the servo table's SG90 with its case up from the axle and the
        smallest stock gear pair (:data:`~cubot_cad.hardware.gears.STOCK_PAIRS`) with which a geared corner
        servo has room (:meth:`latch_places`)."""
        from dataclasses import replace

        proud = self.latch_screw_proud_mm
        if self.latch is not None:
            need(abs(self.latch.clearance_mm - self.clearance_mm) < 1e-12,
                 f"latch.clearance_mm {self.latch.clearance_mm:g} differs from clearance_mm {self.clearance_mm:g}")
            return replace(self.latch, proud_mm=proud)
        from cubot_cad.hardware.gears import STOCK_PAIRS

        specs = [LatchDriveSpec(clearance_mm=self.clearance_mm, blade_gear=b, servo_gear=s, proud_mm=proud)
                 for b, s in STOCK_PAIRS]
        return next((sp for sp in specs if self._latch_layout(sp)[1]), specs[len(specs) // 2])

    def _latch_block_screws(self) -> list:
        from cubot_cad.hardware.fasteners import bolted

        fr = self.fr_spec
        return bolted(self.name, fr.screw_size, fr.latch_stack_mm, 4 * 4, "latch blocks (rear, left)", nut=True,
                      kind="ISO 10642")

    @property
    def latch_screw_proud_mm(self) -> float:
        """How far the latch blocks' countersunk screws (their length includes the head, flush with the
        docking face) reach past the stack's last plate, through their nuts."""
        return self._latch_block_screws()[0].length_mm - self.fr_spec.latch_stack_mm

    def hardware(self, placed: list | None = None) -> list:
        """Stand-ins of the latch blocks' nuts and screw ends inside the cuboid (robot frame): what the
        latch servos' gears and couplers must clear."""
        from cubot_cad.couplings.twist import Hardware
        from cubot_cad.hardware.fasteners import thread
        from cubot_cad.shapes import X, Z, cyl, prism, regular_polygon, rotated

        fr = self.fr_spec
        t = thread(fr.screw_size)
        x0, zb, proud = self.cuboid_stack_end_mm, self.block_z_mm, self.latch_screw_proud_mm
        out = []
        for yaw, places in self.latch_places:
            for y, *_ in places:
                for dy, dz in fr.screw_positions():
                    yy, zz = y + dy, zb + dz
                    hexagon = regular_polygon(6, t.nut_flats_mm)
                    nut = prism(hexagon, "YZ", 0.0, t.nut_height_mm).translate((x0, yy, zz))
                    end = cyl(t.nominal_mm / 2, proud, (x0, yy, zz), X)
                    k = len(out) // 2 + 1
                    for label, shape in ((f"latch_block_nut_{k}", nut), (f"latch_block_screw_end_{k}", end)):
                        out.append(Hardware(label, "fastener", rotated(shape, Z, yaw) if yaw else shape, False))
        return out

    @cached_property
    def latch_places(self) -> tuple:
        """Per latch face ``(yaw_deg, places)``: the rear face (0) and the left face (the rear face turned
        -90 deg about the vertical axis), each block's place in the rear face's frame (``(y, z)``, or
        ``(y, z, servo_y)`` when geared; :mod:`cubot_cad.couplings.latch_drive`).

        A left-face servo whose case, coaxial with its blade, would meet a rear-face servo or frame (the
        two blocks nearest the rear-left corner) is geared instead: its axis moves one gear centre
        distance along the face towards the face's middle. If it still meets anything, the layout is
        refused."""
        from cubot_cad.hardware.gears import STOCK_PAIRS, gear

        spec = self.latch_spec
        places, ok = self._latch_layout(spec)
        tried = (f"{spec.gear_offset_mm:g} mm" if self.latch is not None else
                 "/".join(f"{gear(b).pitch_diameter_mm:g}" for b, _s in STOCK_PAIRS) + " mm (the stock pairs)")
        need(ok, f"block_offset_mm {self.block_offset_mm:g}: the {spec.servo} latch servos of the rear and left faces "
                 f"meet in the rear-left corner, coaxial or geared {tried} along the face")
        return places

    def _latch_layout(self, spec: LatchDriveSpec) -> tuple[tuple, bool]:
        """(:meth:`latch_places` with ``spec``, whether no servo case or frame meets another)."""
        from cubot_cad.shapes import yaw_box

        x_end, z = self.cuboid_stack_end_mm, self.block_z_mm
        floor = self.wheel_block_mm + ConnectorCuboid.floor_mm
        c = self.clearance_mm

        def boxes(place, yaw):
            y, zz, geared = spec.place(place)
            return [yaw_box(spec.case_mm(x_end, y, zz, geared), yaw),
                    yaw_box(spec.frame_box_mm(x_end, y, zz, floor, geared), yaw)]

        def meet(a, b):
            return all(a[2 * i] < b[2 * i + 1] + c and b[2 * i] < a[2 * i + 1] + c for i in range(3))

        o = self.block_offset_mm
        rear = tuple((y, z) for y in (o, -o))
        taken = [b for p in rear for b in boxes(p, 0.0)]
        left, ok = [], True
        for y in (o, -o):
            place = (y, z)
            if any(meet(a, b) for a in boxes(place, -90.0) for b in taken):
                place = (y, z, y - math.copysign(spec.gear_offset_mm, y))
                ok = ok and not any(meet(a, b) for a in boxes(place, -90.0) for b in taken)
            taken += boxes(place, -90.0)
            left.append(place)
        return ((0.0, rear), (-90.0, tuple(left))), ok

    @property
    def cuboid_stack_end_mm(self) -> float:
        """x where a rear face's latch stacks end inside the cuboid (the rear face's frame; the
        cuboid's own :attr:`ConnectorCuboid.latch_stack_end_mm`, known before the cuboid is built)."""
        return ConnectorCuboid.stack_end_mm(self.size_mm, self.fr_spec)

    @cached_property
    def sensor_tier(self) -> SensorCylinder:
        return SensorCylinder(diameter_mm=self.size_mm - 4, height_mm=self.sensor_mm,
                              z0_mm=self.wheel_block_mm + self.cuboid_mm, wall_mm=self.wall_mm, size_mm=self.size_mm,
                              lip_wall_mm=self.cuboid.lip_wall_mm, joint=self.top_joint,
                              clearance_mm=self.clearance_mm)

    @cached_property
    def fr_spec(self) -> FrontRearSpec:
        dims = {"wall_mm": self.wall_mm, "pin_diameter_mm": self.pin_diameter_mm,
                "groove_diameter_mm": self.groove_diameter_mm, "clearance_mm": self.clearance_mm}
        base = FrontRearSpec(**dims)
        if self.pin_overrun_mm <= 0:
            return base
        return FrontRearSpec(**dims, pin_protrusion_mm=base.latch_depth_mm + self.pin_overrun_mm)

    @property
    def envelope_mm(self):
        return (self.size_mm, self.size_mm, self.height_mm)

    @property
    def block_z_mm(self) -> float:
        return self.wheel_block_mm + self.cuboid_mm / 2

    def build_placed(self, blades_locked: bool = False) -> list[Placed]:
        from cubot_cad.shapes import location

        S = self.size_mm / 2
        out = [Placed(self.wheel_block, location(), "body"), Placed(self.cuboid, location(), "body"),
               Placed(self.sensor_tier, location(), "body")]
        zb = self.block_z_mm
        # pins front (0 deg) and right (-90 deg), latches rear (180 deg) and left (90 deg)
        for rot, kind in ((0, "pin"), (-90, "pin"), (180, "latch"), (90, "latch")):
            for o in (-self.block_offset_mm, self.block_offset_mm):
                face = location((0, 0, zb), rot) * location((S, o, 0))
                parts = pin_set_parts(self.fr_spec) if kind == "pin" else latch_set_parts(self.fr_spec, blades_locked)
                for part, offs in parts:
                    for off in offs:
                        role = ("pin" if part.name.endswith("pin") else "pinset") if kind == "pin" else \
                            ("blade" if "blade" in part.name else "latchset")
                        out.append(Placed(part, face * location(off), role + ("_side" if rot in (-90, 90) else "")))
        return out

    @property
    def geared_latches(self) -> int:
        return sum(self.latch_spec.place(p)[2] for _yaw, places in self.latch_places for p in places)

    def drive_parts(self) -> list[tuple[str, str, str, int]]:
        fr = self.fr_spec
        # through the bearing and the blade, into the coupler
        length = fr.rear_plate_mm + fr.separation_mm + SHAFT_INTO_COUPLER_MM
        blocks = sum(len(places) for _yaw, places in self.latch_places)
        return self.latch_spec.drive_parts(fr.drive_shaft_mm, fr.drive_flat_mm, length, blocks, self.geared_latches)

    def fasteners(self) -> list:
        from cubot_cad.hardware.fasteners import bolted

        fr, n = self.fr_spec, self.name
        return (bolted(n, fr.screw_size, fr.pin_stack_mm, 4 * 4, "grooved-pin blocks (front, right)", nut=True,
                       kind="ISO 10642")
                + self._latch_block_screws()
                + bolted(n, self.joint.screw_size, self.cuboid.floor_mm, len(self.joint.screw_points(self.size_mm / 2)),
                         "connector cuboid: down through its floor into the wheel block's corner bosses", insert=True)
                + bolted(n, self.top_joint.screw_size, self.sensor_tier.floor_mm,
                         len(self.top_joint.screw_points(self.size_mm / 2)),
                         "sensor tier: through its base plate's corners into the cuboid's top corner bosses",
                         insert=True)
                + self.latch_spec.tab_screws(n, sum(len(places) for _yaw, places in self.latch_places))
                + (self.latch_spec.gear_screws(n, self.geared_latches) if self.geared_latches else []))

    def pin_heights_mm(self) -> list[float]:
        return [self.block_z_mm + z for _ in (0, 1) for _y, z in self.fr_spec.pin_positions()]

    def components(self) -> list[Component]:
        axle = self.wheel_radius_mm - self.wheel_exposed_mm
        x, y = self.wheel_x_mm, self.track_half_mm
        zt = self.wheel_block_mm + self.cuboid_mm
        _hx, hy = swept_half_extents_mm(self.wheel_radius_mm, self.wheel_width_mm, self.steer_deg)
        ys = y - hy - WHEEL_GAP_MM - 5.0  # the 10 mm sensor's outer edge WHEEL_GAP_MM from the turned wheel
        return [
            Component("wheel", f"wheel, {2 * self.wheel_radius_mm:g} mm (front pair steered)", 10.0,
                      ((x, -y, axle), (x, y, axle), (-x, -y, axle), (-x, y, axle)),
                      (2 * self.wheel_radius_mm, self.wheel_width_mm), "cyl_y", "wheel", (0.1, 0.1, 0.1)),
            Component("drive_motor", "geared DC motor, rear axle", 25.0, ((-x, -20.0, 14.0), (-x, 20.0, 14.0)),
                      (20.0, 30.0, 20.0), "box", "motor", (0.3, 0.3, 0.3)),
            Component("steering_servo", "micro servo for the Ackermann linkage", 9.0, ((x, 0.0, 14.0),),
                      (23.0, 12.0, 22.0), "box", "motor", (0.3, 0.3, 0.3)),
            # in the wheel block, across it, between the drive motors and the steering servo (the cuboid
            # holds the four latch servos)
            Component("battery", "2S LiPo 7.4 V 1000 mAh", 55.0, (self.battery_centre_mm,),
                      BATTERY_MM, "box", "power", (0.8, 0.5, 0.1)),
            Component("main_board", "controller + RFID + accelerometer", 25.0, ((0.0, 0.0, zt + 10.0),),
                      (70.0, 70.0, 10.0)),
            # a board square inside the sensor cylinder (corners 1.9 mm off its wall), over the main board
            Component("sensor_ring", "16 IR proximity, 8 light sensors, 8x3 colour LEDs", 30.0,
                      ((0.0, 0.0, zt + 15.0 + 0.3 + 10.0),), (76.0, 76.0, 20.0)),
            # the outer two between the steering servo and the front wheels' swept footprint
            Component("ground_sensor", "ground (void) sensor", 1.0,
                      ((self.size_mm / 2 - 8, 0.0, 5.0), (self.size_mm / 2 - 8, -ys, 5.0), (self.size_mm / 2 - 8, ys, 5.0)),
                      (6.0, 10.0, 4.0)),
            Component("fasteners", "M3 screws and nuts", 25.0, ((0.0, 0.0, 60.0),), (100.0, 100.0, 100.0),
                      "box", "hardware", (0.6, 0.6, 0.6), lump=True),
        ] + self.latch_components()

    def latch_components(self) -> list[Component]:
        """The latch servos of the rear and left faces (stand-ins on their frames) and the geared
        blocks' gear pairs."""
        spec, x_end = self.latch_spec, self.cuboid_stack_end_mm
        (_r, rear), (yaw, left) = self.latch_places
        return ([spec.component(x_end, rear, "latch_servo"), spec.component(x_end, left, "latch_servo_left", yaw)]
                + spec.gear_components(x_end, rear, "latch_gear_rear") + spec.gear_components(x_end, left, "latch_gear", yaw))

    @property
    def battery_centre_mm(self) -> tuple[float, float, float]:
        """The battery (:data:`BATTERY_MM`, long side across) on the wheel block's floor, 1 mm in front
        of the drive motors."""
        return (-self.wheel_x_mm + 10.0 + 1.0 + BATTERY_MM[0] / 2, 0.0,
                self.wheel_block.floor_mm + 0.01 + BATTERY_MM[2] / 2)

    def connector_properties(self, youngs_modulus_pa: float, gaps_mm: dict | None = None) -> tuple:
        fr = self.fr_spec
        gap = (gaps_mm or {}).get("front_rear", fr.design_gap_mm)
        return (couplings.front_rear(fr, self.pin_heights_mm(), gap, youngs_modulus_pa, self.block_z_mm),)
