"""Cube Robot (thesis Ch. 6.3.1): <= 120 mm cube in three printed tiers.

* wheel block (bottom): four wheels in an Ackermann layout (front pair steered,
  wider wells for the steering sweep);
* connector cuboid (middle): grooved-pin blocks front AND right, latch blocks
  rear AND left (two blocks per side);
* sensor cylinder (top): 16 IR proximity windows, 8 light-sensor windows.

Its pins are the thesis's design: ``pin_protrusion_mm`` longer than the latch
depth, so two docked Cube Robots stop with a gap (the thesis measured 1.7 mm)
that comes out of the geometry (:mod:`cubot_cad.docking` measures it).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import ClassVar

from . import couplings
from .components import Component
from .connectors import FrontRearSpec, latch_set_parts, pin_set_parts
from .cubot import check_dims
from .part import DEFAULT_CLEARANCE_MM, MIN_WALL_MM, Part, at_most, check_clearance, need
from .robot import Placed, Robot

ENVELOPE_MM = 120.0
#: Thesis pins: 1.7 mm longer than the latch stack is deep (Ch. 6.3.1.3).
THESIS_PIN_OVERRUN_MM = 1.7


@dataclass(frozen=True)
class WheelBlock(Part):
    size_mm: float = 120.0
    height_mm: float = 30.0
    wall_mm: float = 2.4
    floor_mm: float = 3.0
    wheel_radius_mm: float = 20.0
    wheel_width_mm: float = 10.0
    wheel_x_mm: float = 35.0
    wheel_y_mm: float = 48.0
    steer_deg: float = 30.0
    name: ClassVar[str] = "cube_wheel_block"
    description: ClassVar[str] = "Cube Robot tier 1: wheel block, four wheel wells (Ackermann, front steered)"
    support: ClassVar[str] = "overhangs at the wheel wells (the slicer places supports there, issue 15)"

    def build(self):
        import math

        from .shapes import box, cut_all

        S, H, w, f = self.size_mm / 2, self.height_mm, self.wall_mm, self.floor_mm
        shell = box(-S, S, -S, S, 0, H).cut(box(-S + w, S - w, -S + w, S - w, f, H + 1))
        cut = []
        r = self.wheel_radius_mm + 1.5
        a = self.wheel_width_mm / 2 + 1.5
        for x in (-self.wheel_x_mm, self.wheel_x_mm):
            sweep = 0.0
            if x > 0:  # steered: the well covers the wheel turned by steer_deg
                t = math.radians(self.steer_deg)
                sweep = r * math.sin(t) + a * math.cos(t) - a
            for y in (-self.wheel_y_mm, self.wheel_y_mm):
                cut.append(box(x - r - sweep / 2, x + r + sweep / 2, y - a - sweep, y + a + sweep,
                               -1, self.wheel_radius_mm - 5.0))
        return cut_all(shell, cut)


@dataclass(frozen=True)
class ConnectorCuboid(Part):
    size_mm: float = 120.0
    height_mm: float = 50.0
    z0_mm: float = 30.0
    wall_mm: float = 2.4
    floor_mm: float = 3.0
    block_offset_mm: float = 22.0
    fr: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "cube_connector_cuboid"
    description: ClassVar[str] = "Cube Robot tier 2: connector cuboid, pin holes front/right, latch holes rear/left"

    def build(self):
        from .shapes import box, cut_all, location

        S, w, f = self.size_mm / 2, self.wall_mm, self.floor_mm
        z0, z1 = self.z0_mm, self.z0_mm + self.height_mm
        shell = box(-S, S, -S, S, z0, z1).cut(box(-S + w, S - w, -S + w, S - w, z0 + f, z1 + 1))
        zb = (z0 + z1) / 2
        cut = []
        # pins front (0 deg) and right (-90 = 270 deg), latches rear (180 deg) and left (90 deg)
        for rot, side in ((0, "pin"), (90, "latch"), (180, "latch"), (270, "pin")):
            for o in (-self.block_offset_mm, self.block_offset_mm):
                loc = location((0, 0, zb), rot) * location((S, o, 0))
                cut += [t.moved(loc) for t in self.fr.wall_cutters(side)]
        cut.append(box(-10, 10, -10, 10, z0 - 1, z0 + f + 1))  # wiring to the wheel block
        return cut_all(shell, cut)


@dataclass(frozen=True)
class SensorCylinder(Part):
    diameter_mm: float = 116.0
    height_mm: float = 40.0
    z0_mm: float = 80.0
    wall_mm: float = 2.4
    floor_mm: float = 3.0
    name: ClassVar[str] = "cube_sensor_cylinder"
    description: ClassVar[str] = "Cube Robot tier 3: sensor cylinder, 16 IR proximity and 8 light-sensor windows"

    def build(self):
        from .shapes import Z, box, cut_all, cyl, rotated

        R, z0 = self.diameter_mm / 2, self.z0_mm
        body = cyl(R, self.height_mm, (0, 0, z0), Z).cut(
            cyl(R - self.wall_mm, self.height_mm, (0, 0, z0 + self.floor_mm), Z))
        cut = [rotated(box(R - 5, R + 1, -2.5, 2.5, z0 + 12, z0 + 17), Z, 22.5 * k) for k in range(16)]
        cut += [rotated(box(R - 5, R + 1, -3, 3, z0 + 26, z0 + 32), Z, 45 * k + 11.25) for k in range(8)]
        cut.append(cyl(8.0, self.floor_mm + 2, (0, 0, z0 - 1), Z))
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
    wheel_y_mm: float = 48.0
    block_offset_mm: float = 22.0
    pin_overrun_mm: float = THESIS_PIN_OVERRUN_MM
    #: The grooved pins and their neck (:class:`~cubot_cad.connectors.FrontRearSpec`), mm.
    pin_diameter_mm: float = 5.0
    groove_diameter_mm: float = 3.4
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    name: ClassVar[str] = "cube-robot"
    title: ClassVar[str] = "Cube Robot"

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        check_dims(self, ("size_mm", "wheel_block_mm", "cuboid_mm", "sensor_mm", "wall_mm", "wheel_radius_mm",
                          "wheel_width_mm", "wheel_exposed_mm", "wheel_x_mm", "wheel_y_mm", "block_offset_mm",
                          "pin_diameter_mm", "groove_diameter_mm"))
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

    @property
    def height_mm(self) -> float:
        return self.wheel_block_mm + self.cuboid_mm + self.sensor_mm

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
        from .shapes import location

        S = self.size_mm / 2
        out = [Placed(WheelBlock(size_mm=self.size_mm, height_mm=self.wheel_block_mm, wall_mm=self.wall_mm,
                                 wheel_radius_mm=self.wheel_radius_mm, wheel_width_mm=self.wheel_width_mm,
                                 wheel_x_mm=self.wheel_x_mm, wheel_y_mm=self.wheel_y_mm), location(), "body"),
               Placed(ConnectorCuboid(size_mm=self.size_mm, height_mm=self.cuboid_mm, z0_mm=self.wheel_block_mm,
                                      wall_mm=self.wall_mm, block_offset_mm=self.block_offset_mm, fr=self.fr_spec),
                      location(), "body"),
               Placed(SensorCylinder(diameter_mm=self.size_mm - 4, height_mm=self.sensor_mm,
                                     z0_mm=self.wheel_block_mm + self.cuboid_mm, wall_mm=self.wall_mm),
                      location(), "body")]
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

    def drive_parts(self) -> list[tuple[str, str, str, int]]:
        fr = self.fr_spec
        length = fr.rear_plate_mm + fr.separation_mm + 6.0  # through the bearing and the blade, into the coupler
        return [("latch_shaft", "steel D-shaft (0.5 mm flat) with a coupler onto the latch servo's output",
                 f"diameter {fr.drive_shaft_mm:g} x {length:.0f} mm, {fr.drive_flat_mm:g} mm across the flat",
                 4)]

    def fasteners(self) -> list:
        from .fasteners import bolted

        fr, n = self.fr_spec, self.name
        return (bolted(n, fr.screw_size, fr.pin_stack_mm, 4 * 4, "grooved-pin blocks (front, right)", nut=True,
                       kind="ISO 10642")
                + bolted(n, fr.screw_size, fr.latch_stack_mm, 4 * 4, "latch blocks (rear, left)", nut=True,
                         kind="ISO 10642"))

    def pin_heights_mm(self) -> list[float]:
        return [self.block_z_mm + z for _ in (0, 1) for _y, z in self.fr_spec.pin_positions()]

    def components(self) -> list[Component]:
        axle = self.wheel_radius_mm - self.wheel_exposed_mm
        x, y = self.wheel_x_mm, self.wheel_y_mm
        zt = self.wheel_block_mm + self.cuboid_mm
        S, stack = self.size_mm / 2, self.fr_spec.latch_stack_mm
        return [
            Component("wheel", f"wheel, {2 * self.wheel_radius_mm:g} mm (front pair steered)", 10.0,
                      ((x, -y, axle), (x, y, axle), (-x, -y, axle), (-x, y, axle)),
                      (2 * self.wheel_radius_mm, self.wheel_width_mm), "cyl_y", "wheel", (0.1, 0.1, 0.1)),
            Component("drive_motor", "geared DC motor, rear axle", 25.0, ((-x, -20.0, 14.0), (-x, 20.0, 14.0)),
                      (20.0, 30.0, 20.0), "box", "motor", (0.3, 0.3, 0.3)),
            Component("steering_servo", "micro servo for the Ackermann linkage", 9.0, ((x, 0.0, 14.0),),
                      (23.0, 12.0, 22.0), "box", "motor", (0.3, 0.3, 0.3)),
            Component("battery", "2S LiPo 7.4 V 1000 mAh", 55.0, ((0.0, 0.0, self.wheel_block_mm + 12.0),),
                      (70.0, 35.0, 18.0), "box", "power", (0.8, 0.5, 0.1)),
            # a micro servo (18 x 12 x 16 mm case, output 4 mm from one end) behind each latch block, coaxial
            # with its drive shaft, 0.3 mm behind the stack: the rear ones reach out from the axis, the left
            # ones toward the middle, so the two in each rear-left corner miss each other and the battery
            Component("latch_servo", "micro servo per latch block (rear)", 4.3,
                      tuple((-S + stack + 0.3 + 6.0, sy * (self.block_offset_mm + 5.0), self.block_z_mm)
                            for sy in (-1, 1)),
                      (12.0, 18.0, 16.0), "box", "motor", (0.3, 0.3, 0.3)),
            Component("latch_servo_left", "micro servo per latch block (left)", 4.3,
                      tuple((sx * (self.block_offset_mm - 4.0), S - stack - 0.3 - 6.0, self.block_z_mm)
                            for sx in (-1, 1)),
                      (18.0, 12.0, 16.0), "box", "motor", (0.3, 0.3, 0.3)),
            Component("main_board", "controller + RFID + accelerometer", 25.0, ((0.0, 0.0, zt + 10.0),),
                      (70.0, 70.0, 10.0)),
            # a board square inside the sensor cylinder (corners 1.9 mm off its wall), over the main board
            Component("sensor_ring", "16 IR proximity, 8 light sensors, 8x3 colour LEDs", 30.0,
                      ((0.0, 0.0, zt + 15.0 + 0.3 + 10.0),), (76.0, 76.0, 20.0)),
            Component("ground_sensor", "ground (void) sensor", 1.0,
                      ((self.size_mm / 2 - 8, 0.0, 5.0), (self.size_mm / 2 - 8, -30.0, 5.0), (self.size_mm / 2 - 8, 30.0, 5.0)),
                      (6.0, 10.0, 4.0)),
            Component("fasteners", "M3 screws and nuts", 25.0, ((0.0, 0.0, 60.0),), (100.0, 100.0, 100.0),
                      "box", "hardware", (0.6, 0.6, 0.6), lump=True),
        ]

    def connector_properties(self, youngs_modulus_pa: float, gaps_mm: dict | None = None) -> tuple:
        fr = self.fr_spec
        gap = (gaps_mm or {}).get("front_rear", fr.design_gap_mm)
        return (couplings.front_rear(fr, self.pin_heights_mm(), gap, youngs_modulus_pa, self.block_z_mm),)
