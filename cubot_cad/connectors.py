"""Connector parts (mm): the grooved-pin set, the engagement-latch set, the side
rail halves, the twist-and-lock cross key / cover / locking key, caster seats.

Thesis Ch. 6.3.1.1 and 6.3.3.1 (Fig. 6.2, 6.3, 6.8-6.10).

Frames. A front-rear connector set is drawn in its *set frame*: origin at the
centre of the block on the robot's outer face, +x pointing out of the robot,
plates stacked at x < 0 behind the robot wall (``wall_mm`` thick). The pin set
goes on the front, the latch set (rotated 180 deg about z) on the rear. Both
are generated from one :class:`FrontRearSpec`, so holes always match pins:
every hole, slot and pocket is its mating feature plus ``clearance_mm`` per side.

Docked gap. Pins protrude ``pin_protrusion_mm`` beyond the face; the latch
stack's pocket bottom lies ``latch_depth_mm`` behind the face. The docked gap
is whatever the geometry gives (``cubot_cad.docking`` measures it by moving one
robot until first contact): zero when the pins are shorter than the latch
depth (CuBot), ``protrusion - depth`` when they are longer (the Cube Robot's
1.7 mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from .part import (
    DEFAULT_CLEARANCE_MM,
    MIN_WALL_MM,
    NOZZLE_MM,
    Mate,
    Part,
    at_least,
    at_most,
    check_clearance,
    need,
)

PIN_ANGLES_DEG = (90.0, 210.0, 330.0)
#: In the nominal model the locked blade's slot edge must overlap the pin's shoulder
#: (pin radius - slot half-width = (pin - groove) / 2 - clearance) by at least half an
#: extrusion width; as printed the overlap is larger (the over-extrusion the clearance
#: compensates narrows the slot and fattens the pin).
MIN_LATCH_OVERLAP_MM = NOZZLE_MM / 2


def _pos_ok(name: str, value: float) -> None:
    need(isinstance(value, (int, float)) and math.isfinite(value) and value > 0,
         f"{name} must be a positive length in mm, got {value!r}")


@dataclass(frozen=True)
class FrontRearSpec:
    """Dimensions of one grooved-pin block and its matching latch block (mm, deg)."""

    wall_mm: float = 2.4
    plate_mm: float = 3.0
    pin_diameter_mm: float = 5.0
    groove_diameter_mm: float = 3.4
    #: Radial overlap of the pin head over its hole (pin + 2 clearances): the shoulder that takes
    #: the pull. Constant, so the head grows with the clearance (7.5 mm at the default 0.2 mm).
    head_shoulder_mm: float = 1.05
    head_mm: float = 1.8
    #: Pin-locking plate (b) left in front of the head's counterbore (head + clearance deep):
    #: constant, so plate (b) thickens with the clearance (``plate_mm`` at the default 0.2 mm).
    head_wall_mm: float = 1.0
    blade_mm: float = 2.4
    pocket_depth_mm: float = 3.0
    pin_circle_mm: float = 7.0
    block_mm: float = 36.0
    blade_radius_mm: float = 16.0
    blade_turn_deg: float = 15.0
    #: Pin length beyond the robot face; None = latch depth less one clearance (zero-gap fit).
    pin_protrusion_mm: float | None = None
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        for n in ("wall_mm", "plate_mm", "pin_diameter_mm", "groove_diameter_mm", "head_shoulder_mm",
                  "head_mm", "head_wall_mm", "blade_mm", "pocket_depth_mm", "pin_circle_mm", "block_mm",
                  "blade_radius_mm"):
            _pos_ok(n, getattr(self, n))
        c = self.clearance_mm
        for n in ("wall_mm", "plate_mm", "blade_mm", "head_shoulder_mm", "head_mm", "head_wall_mm"):
            need(at_least(getattr(self, n), MIN_WALL_MM),
                 f"{n} = {getattr(self, n):g} mm is thinner than two nozzle widths ({MIN_WALL_MM:g} mm)")
        need(at_most(self.groove_diameter_mm, self.pin_diameter_mm - MIN_WALL_MM),
             f"groove_diameter_mm {self.groove_diameter_mm:g} must be at least {MIN_WALL_MM:g} mm smaller "
             f"than pin_diameter_mm {self.pin_diameter_mm:g}")
        need(at_least(self.groove_diameter_mm, 2.0), f"groove_diameter_mm {self.groove_diameter_mm:g} < 2 mm would snap")
        need(at_least(self.latch_overlap_mm, MIN_LATCH_OVERLAP_MM),
             f"clearance_mm {c:g} leaves the latch blade's slot ({self.slot_width_mm:g} mm) overlapping the "
             f"{self.pin_diameter_mm:g} mm pin by {self.latch_overlap_mm:.2f} mm (< {MIN_LATCH_OVERLAP_MM:g} mm): "
             "the blade would not hold the pin (groove_diameter_mm, pin_diameter_mm)")
        spacing = self.pin_circle_mm * math.sqrt(3)
        need(at_least(spacing, self.head_diameter_mm + 2 * c + MIN_WALL_MM),
             f"pin_circle_mm {self.pin_circle_mm:g} puts the {self.head_diameter_mm:g} mm pin heads' counterbores "
             f"closer than a printable wall (clearance_mm {c:g})")
        need(5.0 <= self.blade_turn_deg <= 45.0, f"blade_turn_deg {self.blade_turn_deg:g} must be in 5..45")
        # The arc slots and entry holes must leave a printable wall to the triangle's edges
        # (perpendicular distance from a point at radius rho, angle a off a vertex: R/2 - rho cos(60 - a)).
        inr = self.blade_radius_mm / 2
        th = math.radians(self.blade_turn_deg)
        wall_slot = inr - self.pin_circle_mm * math.cos(math.radians(60) - th) - self.slot_width_mm / 2
        wall_entry = inr - self.pin_circle_mm * math.cos(math.radians(60)) - self.pin_diameter_mm / 2 - c
        need(at_least(min(wall_slot, wall_entry), MIN_WALL_MM),
             f"blade_radius_mm {self.blade_radius_mm:g} is too small for pin_circle_mm {self.pin_circle_mm:g} "
             f"and blade_turn_deg {self.blade_turn_deg:g}: the slots leave a {min(wall_slot, wall_entry):.2f} mm "
             f"wall to the blade's edge (< {MIN_WALL_MM:g} mm)")
        need(at_least(self.blade_radius_mm, self.pin_circle_mm + self.pin_diameter_mm / 2 + c + MIN_WALL_MM),
             f"blade_radius_mm {self.blade_radius_mm:g} does not cover the pin holes")
        need(at_least(self.block_mm / 2, self.blade_radius_mm + c + MIN_WALL_MM),
             f"block_mm {self.block_mm:g} is too small for the blade cavity (blade_radius_mm {self.blade_radius_mm:g})")
        need(at_least(self.block_mm / 2, self.pin_circle_mm + self.head_diameter_mm / 2 + c + MIN_WALL_MM),
             f"block_mm {self.block_mm:g} is too small for pin_circle_mm {self.pin_circle_mm:g}")
        if self.pin_protrusion_mm is not None:
            _pos_ok("pin_protrusion_mm", self.pin_protrusion_mm)
            need(at_least(self.pin_protrusion_mm, self.blade_end_mm + 1.0),
                 f"pin_protrusion_mm {self.pin_protrusion_mm:g} does not reach past the latch blade "
                 f"(needs >= {self.blade_end_mm + 1.0:g} mm)")

    # -- derived ------------------------------------------------------------
    @property
    def head_diameter_mm(self) -> float:
        """Pin head diameter: the pin hole (pin + 2 clearances) plus the shoulder on each side."""
        return self.pin_diameter_mm + 2 * (self.clearance_mm + self.head_shoulder_mm)

    @property
    def locking_plate_mm(self) -> float:
        """Pin-locking plate (b) thickness: head, its axial clearance and the wall in front of it."""
        return self.head_mm + self.clearance_mm + self.head_wall_mm

    @property
    def head_x_mm(self) -> float:
        """Set-frame x of the pin head's back face = the back face of plate (b) (front of plate (a))."""
        return -self.wall_mm - 2 * self.plate_mm - self.locking_plate_mm

    @property
    def latch_overlap_mm(self) -> float:
        """How far the locked blade's slot edge overlaps the pin's shoulder (nominal model)."""
        return (self.pin_diameter_mm - self.slot_width_mm) / 2

    @property
    def separation_mm(self) -> float:
        """Separation plate (and pin groove) width: blade plus a clearance each side."""
        return self.blade_mm + 2 * self.clearance_mm

    @property
    def slot_width_mm(self) -> float:
        return self.groove_diameter_mm + 2 * self.clearance_mm

    @property
    def blade_end_mm(self) -> float:
        """Depth behind the latch face where the separation plate ends."""
        return self.wall_mm + 2 * self.plate_mm + self.separation_mm

    @property
    def latch_depth_mm(self) -> float:
        """Depth of the pin pockets' bottom behind the latch face."""
        return self.blade_end_mm + self.pocket_depth_mm

    @property
    def protrusion_mm(self) -> float:
        if self.pin_protrusion_mm is not None:
            return float(self.pin_protrusion_mm)
        return self.latch_depth_mm - self.clearance_mm

    @property
    def design_gap_mm(self) -> float:
        """Where the pin's designer puts the groove: the gap at which the tip meets the pocket bottom."""
        return max(0.0, self.protrusion_mm - self.latch_depth_mm)

    @property
    def rear_plate_mm(self) -> float:
        return self.pocket_depth_mm + 1.6

    def pin_positions(self) -> list[tuple[float, float]]:
        """(y, z) of the three pins in the block, mm."""
        r = self.pin_circle_mm
        return [(r * math.cos(math.radians(a)), r * math.sin(math.radians(a))) for a in PIN_ANGLES_DEG]

    def ir_windows(self) -> list[tuple[float, float, float, float]]:
        """(y, z, width, height) of the two IR sensor windows of a block."""
        h = self.block_mm / 2
        return [(-h * 0.5, -h * 0.72, 4.0, 3.0), (h * 0.5, -h * 0.72, 4.0, 3.0)]

    def screw_positions(self) -> list[tuple[float, float]]:
        s = self.block_mm / 2 - 3.5
        return [(sy * s, sz * s) for sy in (-1, 1) for sz in (-1, 1)]

    def wall_cutters(self, kind: str = "pin") -> list:
        """Cutters for the robot wall behind which a block sits (set frame): pin holes, IR windows, screws."""
        from .shapes import X, box, cyl

        w = self.wall_mm
        out = [cyl(self.pin_diameter_mm / 2 + self.clearance_mm, w + 0.2, (-w - 0.1, y, z), X)
               for y, z in self.pin_positions()]
        out += [box(-w - 0.1, 0.1, y - a / 2, y + a / 2, z - b / 2, z + b / 2) for y, z, a, b in self.ir_windows()]
        out += [cyl(1.7, w + 0.2, (-w - 0.1, y, z), X) for y, z in self.screw_positions()]
        return out


class _Plate(Part):
    """A square block plate lying in the set frame between x0 and x1."""

    def _plate(self, spec: FrontRearSpec, x0: float, x1: float, pin_holes: bool = True,
               windows: bool = False, extra: list | None = None):
        from .shapes import X, box, cut_all, cyl

        h = spec.block_mm / 2
        base = box(x0, x1, -h, h, -h, h)
        cut = [cyl(1.7, x1 - x0 + 0.2, (x0 - 0.1, y, z), X) for y, z in spec.screw_positions()]
        if pin_holes:
            r = spec.pin_diameter_mm / 2 + spec.clearance_mm
            cut += [cyl(r, x1 - x0 + 0.2, (x0 - 0.1, y, z), X) for y, z in spec.pin_positions()]
        if windows:
            cut += [box(x0 - 0.1, x1 + 0.1, y - a / 2, y + a / 2, z - b / 2, z + b / 2)
                    for y, z, a, b in spec.ir_windows()]
        cut += extra or []
        return cut_all(base, cut)


# --- grooved-pin set (thesis Fig. 6.2: a locking plate, b pin-locking plate,
#     c IR PCB plate, d locking plate, e three grooved pins) --------------------

_FLAT_X: tuple = (((0.0, 1.0, 0.0), 90.0),)


@dataclass(frozen=True)
class PinFrontPlate(_Plate):
    """(d) Front locking plate of the pin set, right behind the robot wall."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "pinset_d_front_locking_plate"
    description: ClassVar[str] = "grooved-pin set (d): locking plate against the wall, pin holes"
    print_rotation: ClassVar = _FLAT_X

    def build(self):
        s = self.spec
        return self._plate(s, -s.wall_mm - s.plate_mm, -s.wall_mm)


@dataclass(frozen=True)
class PinIrPlate(_Plate):
    """(c) IR PCB plate of the pin set: pin holes and two receiver windows."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "pinset_c_ir_pcb_plate"
    description: ClassVar[str] = "grooved-pin set (c): carrier of the IR receiver PCB"
    print_rotation: ClassVar = _FLAT_X

    def build(self):
        s = self.spec
        return self._plate(s, -s.wall_mm - 2 * s.plate_mm, -s.wall_mm - s.plate_mm, windows=True)


@dataclass(frozen=True)
class PinLockingPlate(_Plate):
    """(b) Pin-locking plate: pin holes with counterbores that capture the pin heads."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "pinset_b_pin_locking_plate"
    description: ClassVar[str] = "grooved-pin set (b): holds the pin heads in counterbores"
    print_rotation: ClassVar = (((0.0, 1.0, 0.0), -90.0),)

    def build(self):
        from .shapes import X, cyl

        s = self.spec
        x0 = s.head_x_mm
        cb = [cyl(s.head_diameter_mm / 2 + s.clearance_mm, s.head_mm + s.clearance_mm + 0.1, (x0 - 0.1, y, z), X)
              for y, z in s.pin_positions()]
        return self._plate(s, x0, x0 + s.locking_plate_mm, extra=cb)


@dataclass(frozen=True)
class PinRearPlate(_Plate):
    """(a) Rear locking plate: solid behind the pin heads, screws only."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "pinset_a_rear_locking_plate"
    description: ClassVar[str] = "grooved-pin set (a): closes the stack behind the pin heads"
    print_rotation: ClassVar = _FLAT_X

    def build(self):
        s = self.spec
        x0 = s.head_x_mm - s.plate_mm
        return self._plate(s, x0, x0 + s.plate_mm, pin_holes=False)


@dataclass(frozen=True)
class GroovedPin(Part):
    """(e) One grooved pin (three per block), axis +x at y = z = 0 of the set frame."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "pinset_e_grooved_pin"
    description: ClassVar[str] = "grooved-pin set (e): grooved pin, three per block, printed standing on its head"
    print_rotation: ClassVar = (((0.0, 1.0, 0.0), -90.0),)

    @property
    def groove_mm(self) -> tuple[float, float]:
        """x-range of the groove in the set frame (aligned with the latch blade when docked)."""
        s = self.spec
        g0 = s.design_gap_mm + s.wall_mm + 2 * s.plate_mm
        return (g0, g0 + s.separation_mm)

    def build(self):
        from .shapes import X, cyl, fuse_all

        s = self.spec
        x_head = s.head_x_mm
        r, rg = s.pin_diameter_mm / 2, s.groove_diameter_mm / 2
        g0, g1 = self.groove_mm
        tip = s.protrusion_mm
        parts = [cyl(s.head_diameter_mm / 2, s.head_mm, (x_head, 0, 0), X),
                 cyl(r, g0 - x_head - s.head_mm, (x_head + s.head_mm, 0, 0), X),
                 cyl(rg, g1 - g0, (g0, 0, 0), X),
                 cyl(r, tip - g1, (g1, 0, 0), X)]
        return fuse_all(parts)

    @property
    def mates(self):
        return {"tip": Mate((self.spec.protrusion_mm, 0, 0), (1, 0, 0))}


# --- engagement-latch set (thesis Fig. 6.3: a locking plate, b IR PCB plate,
#     c separation plate, d triangular blade, e locking plate) ---------------

@dataclass(frozen=True)
class LatchFrontPlate(_Plate):
    """(a) Front locking plate of the latch set, right behind the robot wall."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "latchset_a_front_locking_plate"
    description: ClassVar[str] = "latch set (a): locking plate against the wall, pin holes"
    print_rotation: ClassVar = _FLAT_X

    def build(self):
        s = self.spec
        return self._plate(s, -s.wall_mm - s.plate_mm, -s.wall_mm)


@dataclass(frozen=True)
class LatchIrPlate(_Plate):
    """(b) IR PCB plate of the latch set: pin holes and two transmitter windows."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "latchset_b_ir_pcb_plate"
    description: ClassVar[str] = "latch set (b): carrier of the IR transmitter PCB"
    print_rotation: ClassVar = _FLAT_X

    def build(self):
        s = self.spec
        return self._plate(s, -s.wall_mm - 2 * s.plate_mm, -s.wall_mm - s.plate_mm, windows=True)


@dataclass(frozen=True)
class LatchSeparationPlate(_Plate):
    """(c) Separation plate: the round cavity the blade turns in, and the blade's lever slot."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "latchset_c_separation_plate"
    description: ClassVar[str] = "latch set (c): blade cavity and the triangular-blade lever slot"
    print_rotation: ClassVar = _FLAT_X

    def build(self):
        from .shapes import X, box, cyl

        s = self.spec
        x1 = -s.wall_mm - 2 * s.plate_mm
        x0 = x1 - s.separation_mm
        cav = cyl(s.blade_radius_mm + s.clearance_mm, s.separation_mm + 0.2, (x0 - 0.1, 0, 0), X)
        slot = box(x0 - 0.1, x1 + 0.1, -3.0, 3.0, -s.block_mm, 0)
        return self._plate(s, x0, x1, pin_holes=False, extra=[cav, slot])


@dataclass(frozen=True)
class TriangularBlade(Part):
    """(d) Triangular blade with three keyhole arc slots; turning it by
    ``blade_turn_deg`` moves the narrow ends of the slots into the pin grooves."""

    spec: FrontRearSpec = FrontRearSpec()
    locked: bool = False
    name: ClassVar[str] = "latchset_d_triangular_blade"
    description: ClassVar[str] = "latch set (d): triangular blade, turned by a micro servo to lock the pins"
    print_rotation: ClassVar = _FLAT_X

    def build(self):
        from .shapes import X, cut_all, cyl, fuse_all, prism, rotated

        s = self.spec
        c = s.clearance_mm
        x1 = -s.wall_mm - 2 * s.plate_mm - c
        x0 = x1 - s.blade_mm
        t = s.blade_mm + 0.2
        rb = s.blade_radius_mm
        tri = [(rb * math.cos(math.radians(a)), rb * math.sin(math.radians(a))) for a in PIN_ANGLES_DEG]
        blade = prism(tri, "YZ", x0, s.blade_mm)
        r, w = s.pin_circle_mm, s.slot_width_mm
        ring = cyl(r + w / 2, t, (x0 - 0.1, 0, 0), X).cut(cyl(r - w / 2, t, (x0 - 0.1, 0, 0), X))
        wedges, cutters = [], []
        th = s.blade_turn_deg
        for a in PIN_ANGLES_DEG:
            a0, a1 = math.radians(a - th), math.radians(a)
            R = 3 * r
            wedges.append(prism([(0, 0), (R * math.cos(a0), R * math.sin(a0)),
                                 (R * math.cos((a0 + a1) / 2) * 1.2, R * math.sin((a0 + a1) / 2) * 1.2),
                                 (R * math.cos(a1), R * math.sin(a1))], "YZ", x0 - 0.1, t))
            cutters.append(cyl(w / 2, t, (x0 - 0.1, r * math.cos(a0), r * math.sin(a0)), X))
            cutters.append(cyl(s.pin_diameter_mm / 2 + c, t, (x0 - 0.1, r * math.cos(a1), r * math.sin(a1)), X))
        cutters.append(ring.intersect(fuse_all(wedges)))
        cutters.append(cyl(2.5 + c, t, (x0 - 0.1, 0, 0), X))  # servo hub
        shape = cut_all(blade, cutters)
        if self.locked:
            shape = rotated(shape, X, th)
        return shape


@dataclass(frozen=True)
class LatchRearPlate(_Plate):
    """(e) Rear locking plate: blind pockets that stop the pin tips (this sets the latch depth)."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "latchset_e_rear_locking_plate"
    description: ClassVar[str] = "latch set (e): pin pockets (latch depth) and the servo shaft hole"
    print_rotation: ClassVar = (((0.0, 1.0, 0.0), -90.0),)

    def build(self):
        from .shapes import X, cyl

        s = self.spec
        x1 = -s.blade_end_mm
        x0 = x1 - s.rear_plate_mm
        r = s.pin_diameter_mm / 2 + s.clearance_mm
        pockets = [cyl(r, s.pocket_depth_mm + 0.1, (x1 - s.pocket_depth_mm, y, z), X) for y, z in s.pin_positions()]
        shaft = cyl(2.5 + s.clearance_mm, s.rear_plate_mm + 0.2, (x0 - 0.1, 0, 0), X)
        return self._plate(s, x0, x1, pin_holes=False, extra=pockets + [shaft])

    @property
    def mates(self):
        return {"pocket_bottom": Mate((-self.spec.latch_depth_mm, 0, 0), (1, 0, 0))}


def pin_set_parts(spec: FrontRearSpec) -> list[tuple[Part, list[tuple[float, float, float]]]]:
    """The five parts of one grooved-pin block with their offsets in the set frame."""
    pin = GroovedPin(spec=spec)
    return [(PinFrontPlate(spec=spec), [(0, 0, 0)]), (PinIrPlate(spec=spec), [(0, 0, 0)]),
            (PinLockingPlate(spec=spec), [(0, 0, 0)]), (PinRearPlate(spec=spec), [(0, 0, 0)]),
            (pin, [(0, y, z) for y, z in spec.pin_positions()])]


def latch_set_parts(spec: FrontRearSpec, locked: bool = False) -> list[tuple[Part, list[tuple[float, float, float]]]]:
    """The five parts of one latch block (blade locked or open) in the set frame."""
    return [(LatchFrontPlate(spec=spec), [(0, 0, 0)]), (LatchIrPlate(spec=spec), [(0, 0, 0)]),
            (LatchSeparationPlate(spec=spec), [(0, 0, 0)]), (TriangularBlade(spec=spec, locked=locked), [(0, 0, 0)]),
            (LatchRearPlate(spec=spec), [(0, 0, 0)])]


# --- side rail (thesis Fig. 6.9) ------------------------------------------------

@dataclass(frozen=True)
class RailSpec:
    """Dovetail rail pair (mm). Rail frame: robot side face at y = 0, +y outward,
    rail centred on x = 0 and on z = 0 (the robot places it at its rail height).

    The female groove is the tongue's cross-section offset outward by
    ``clearance_mm`` normal to every face: flanks parallel to the tongue's flanks
    (a uniform gap from mouth to tip), floor ``clearance_mm`` beyond the tip.
    """

    length_mm: float = 80.0
    height_mm: float = 24.0
    plate_mm: float = 3.0
    tongue_mm: float = 4.0
    tongue_root_mm: float = 8.0
    tongue_tip_mm: float = 12.0
    ir_hole_mm: float = 3.0
    ir_inset_mm: float = 6.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        for n in ("length_mm", "height_mm", "plate_mm", "tongue_mm", "tongue_root_mm", "tongue_tip_mm",
                  "ir_hole_mm", "ir_inset_mm"):
            _pos_ok(n, getattr(self, n))
        need(at_least(self.plate_mm - self.clearance_mm, MIN_WALL_MM),
             f"plate_mm {self.plate_mm:g} leaves the groove floor thinner than {MIN_WALL_MM:g} mm "
             f"(clearance_mm {self.clearance_mm:g})")
        need(self.tongue_tip_mm > self.tongue_root_mm,
             f"tongue_tip_mm {self.tongue_tip_mm:g} must exceed tongue_root_mm {self.tongue_root_mm:g} (a dovetail)")
        need(at_least(self.tongue_root_mm, 2 * MIN_WALL_MM),
             f"tongue_root_mm {self.tongue_root_mm:g} is too thin to print")
        band = self.height_mm / 2 - self.groove_half_width_mm(self.groove_depth_mm)
        need(at_least(band, self.ir_hole_mm + 2 * MIN_WALL_MM),
             f"height_mm {self.height_mm:g} leaves {band:.2f} mm beside the dovetail groove for the "
             f"{self.ir_hole_mm:g} mm IR holes and their walls (clearance_mm {self.clearance_mm:g})")

    @property
    def female_mm(self) -> float:
        """Female half thickness: plate plus the groove depth."""
        return self.plate_mm + self.tongue_mm

    @property
    def flank_slope(self) -> float:
        """Widening of the tongue's half-width per mm of depth (tan of the flank angle, 26.6 deg)."""
        return (self.tongue_tip_mm - self.tongue_root_mm) / 2 / self.tongue_mm

    @property
    def flank_offset_mm(self) -> float:
        """Horizontal offset of a slanted flank that gives a normal clearance of ``clearance_mm``."""
        return self.clearance_mm * math.sqrt(1 + self.flank_slope ** 2)

    @property
    def groove_depth_mm(self) -> float:
        """Groove depth behind the female's mouth face: the tongue plus a clearance beyond its tip."""
        return self.tongue_mm + self.clearance_mm

    def groove_half_width_mm(self, depth_mm: float) -> float:
        """Half-width of the groove ``depth_mm`` behind its mouth: the tongue's half-width at that
        depth plus the flank offset (the flank is parallel to the tongue's)."""
        return self.tongue_root_mm / 2 + self.flank_offset_mm + depth_mm * self.flank_slope

    def ir_points(self) -> list[tuple[float, float]]:
        """(x, z) of the two IR holes at both ends, in the bottom half: the thesis position (hole
        edge 1.8 mm from the rail's edge) unless the groove, which widens with the clearance,
        comes closer than two nozzle widths; then the holes move out to keep that wall."""
        r = self.ir_hole_mm / 2
        z = max(self.height_mm / 2 - r - MIN_WALL_MM - 1.0,
                self.groove_half_width_mm(self.groove_depth_mm) + MIN_WALL_MM + r)
        dx = self.length_mm / 2 - self.ir_inset_mm
        return [(-dx, -z), (dx, -z)]


@dataclass(frozen=True)
class RailMale(Part):
    """Left rail half: plate with a dovetail tongue (slides into a neighbour's right rail)."""

    spec: RailSpec = RailSpec()
    name: ClassVar[str] = "rail_male_left"
    description: ClassVar[str] = "side rail, left half: dovetail tongue"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 90.0),)

    def build(self):
        from .shapes import Y, box, cut_all, cyl, prism

        s = self.spec
        L, H, p = s.length_mm, s.height_mm, s.plate_mm
        plate = box(-L / 2, L / 2, 0, p, -H / 2, H / 2)
        # the tongue starts 0.01 mm inside the plate (a clean fuse) on the extension of its flanks
        a, b = s.tongue_root_mm / 2 - 0.01 * s.flank_slope, s.tongue_tip_mm / 2
        tongue = prism([(p - 0.01, -a), (p + s.tongue_mm, -b), (p + s.tongue_mm, b), (p - 0.01, a)],
                       "YZ", -L / 2, L)
        body = plate.fuse(tongue).clean()
        holes = [cyl(s.ir_hole_mm / 2, p + 0.2, (x, -0.1, z), Y) for x, z in s.ir_points()]
        return cut_all(body, holes)

    @property
    def mates(self):
        return {"face": Mate((0, self.spec.plate_mm, 0), (0, 1, 0))}


@dataclass(frozen=True)
class RailFemale(Part):
    """Right rail half: thicker plate with the dovetail groove (clearance on every face).

    Printed groove up (back face on the bed): the groove floor is then printed on
    solid layers and the flanks overhang only by the flank angle (26.6 deg from
    vertical); groove down, the floor would be a 12.6 x 80 mm bridge.
    """

    spec: RailSpec = RailSpec()
    name: ClassVar[str] = "rail_female_right"
    description: ClassVar[str] = "side rail, right half: dovetail groove, printed groove up"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 90.0),)

    def build(self):
        from .shapes import Y, box, cut_all, cyl, prism

        s = self.spec
        L, H, t = s.length_mm, s.height_mm, s.female_mm
        plate = box(-L / 2, L / 2, 0, t, -H / 2, H / 2)
        # the groove's outline: the tongue offset by the clearance, drawn from 0.5 mm outside the
        # mouth (a clean cut through the mouth face) to the floor; y = t - depth
        out, deep = -0.5, s.groove_depth_mm
        w_out, w_deep = s.groove_half_width_mm(out), s.groove_half_width_mm(deep)
        groove = prism([(t - out, -w_out), (t - deep, -w_deep), (t - deep, w_deep), (t - out, w_out)],
                       "YZ", -L / 2 - 1, L + 2)
        holes = [cyl(s.ir_hole_mm / 2, t + 0.2, (x, -0.1, z), Y) for x, z in s.ir_points()]
        return cut_all(plate, [groove] + holes)


# --- twist-and-lock top-down coupling (thesis Fig. 6.10) -----------------------

@dataclass(frozen=True)
class TopTwistSpec:
    """Cross key (under a robot), cover with cross-hole collar and locking key (on top), mm.

    ``stand_mm`` is how high an upper robot's underside stands above the cover
    (its wheels' exposed height): the key must reach down through the collar
    yet clear the ground by ``ground_clearance_mm`` while driving.
    """

    arm_width_mm: float = 8.0
    arm_length_mm: float = 28.0
    head_mm: float = 3.0
    roof_mm: float = 2.5
    key_protrusion_mm: float = 12.0
    flange_mm: float = 2.0
    flange_size_mm: float = 30.0
    collar_wall_mm: float = 2.4
    cover_mm: float = 3.0
    lip_mm: float = 1.5
    twist_deg: float = 45.0
    stand_mm: float = 15.0
    ground_clearance_mm: float = 2.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        for n in ("arm_width_mm", "arm_length_mm", "head_mm", "roof_mm", "key_protrusion_mm", "flange_mm",
                  "flange_size_mm", "collar_wall_mm", "cover_mm", "lip_mm", "stand_mm", "ground_clearance_mm"):
            _pos_ok(n, getattr(self, n))
        for n in ("head_mm", "roof_mm", "flange_mm", "collar_wall_mm", "cover_mm"):
            need(at_least(getattr(self, n), MIN_WALL_MM), f"{n} {getattr(self, n):g} is thinner than {MIN_WALL_MM:g} mm")
        need(at_most(self.key_protrusion_mm, self.stand_mm - self.ground_clearance_mm),
             f"key_protrusion_mm {self.key_protrusion_mm:g} would touch the ground: the wheels stand "
             f"{self.stand_mm:g} mm (keep {self.ground_clearance_mm:g} mm clear)")
        need(at_least(self.key_protrusion_mm, self.flange_mm + self.head_mm + self.roof_mm + 2 * self.clearance_mm),
             f"key_protrusion_mm {self.key_protrusion_mm:g} is too short to pass through the collar roof")
        need(self.arm_length_mm >= 2 * self.arm_width_mm + 4,
             f"arm_length_mm {self.arm_length_mm:g} leaves no cross arms beside arm_width_mm {self.arm_width_mm:g}")
        need(at_most(self.lock_x0_mm + 2.0, self.arm_length_mm / 2),
             f"arm_length_mm {self.arm_length_mm:g} leaves no room for the locking key")
        need(30.0 <= self.twist_deg <= 60.0, f"twist_deg {self.twist_deg:g} must be in 30..60")

    @property
    def head_z0_mm(self) -> float:
        """Key head bottom above the cover top when docked."""
        return self.stand_mm - self.key_protrusion_mm

    @property
    def roof_under_mm(self) -> float:
        return self.head_z0_mm + self.head_mm + self.clearance_mm

    @property
    def collar_mm(self) -> float:
        """Collar height above the cover plate."""
        return self.roof_under_mm + self.roof_mm

    @property
    def cavity_radius_mm(self) -> float:
        return self.arm_length_mm / 2 + 1.0

    @property
    def lock_x0_mm(self) -> float:
        """Inner end of the locking key along a hole arm (clears the turned head arms)."""
        a = self.arm_width_mm / 2
        return a + math.sqrt(2) * (a + self.clearance_mm) + self.clearance_mm

    @property
    def top_mm(self) -> float:
        """Height of cover + collar + locking-key lip above the body walls."""
        return self.cover_mm + self.collar_mm + self.lip_mm


def _cross(w: float, L: float, z0: float, h: float):
    from .shapes import box

    return box(-L / 2, L / 2, -w / 2, w / 2, z0, z0 + h).fuse(box(-w / 2, w / 2, -L / 2, L / 2, z0, z0 + h))


@dataclass(frozen=True)
class CrossKey(Part):
    """Cross key under a robot (frame: z = 0 at the robot's underside, key below)."""

    spec: TopTwistSpec = TopTwistSpec()
    turned: bool = False
    name: ClassVar[str] = "cross_key"
    description: ClassVar[str] = "twist-and-lock: cross key under the robot, IR transmitter bore"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 180.0),)

    def build(self):
        from .shapes import Z, box, cut_all, cyl, fuse_all, rotated

        s = self.spec
        f = s.flange_size_mm / 2
        zt = -s.key_protrusion_mm
        flange = box(-f, f, -f, f, -s.flange_mm, 0)
        stem = cyl(s.arm_width_mm / 2, s.key_protrusion_mm - s.flange_mm - s.head_mm + 0.01,
                   (0, 0, zt + s.head_mm - 0.005), Z)
        head = _cross(s.arm_width_mm, s.arm_length_mm, zt, s.head_mm)
        k = fuse_all([flange, stem, head])
        holes = [cyl(1.7, s.flange_mm + 0.2, (x, y, -s.flange_mm - 0.1), Z)
                 for x in (-f + 4, f - 4) for y in (-f + 4, f - 4)]
        holes.append(cyl(1.6, s.key_protrusion_mm + 0.2, (0, 0, zt - 0.1), Z))
        k = cut_all(k, holes)
        return rotated(k, Z, -s.twist_deg) if self.turned else k  # clockwise seen from above


@dataclass(frozen=True)
class Cover(Part):
    """Top cover of the body with the cross-hole collar (frame: z = 0 at the wall tops)."""

    spec: TopTwistSpec = TopTwistSpec()
    length_mm: float = 100.0
    width_mm: float = 90.0
    name: ClassVar[str] = "cover_cross_hole"
    description: ClassVar[str] = "twist-and-lock: body cover with the cross-shaped hole in a collar"

    def validate(self) -> None:
        s = self.spec
        need(self.width_mm / 2 >= s.cavity_radius_mm + s.collar_wall_mm + 5,
             f"Cover.width_mm {self.width_mm:g} is too small for the collar")

    def build(self):
        from .shapes import Z, box, cut_all, cyl

        s = self.spec
        c = s.clearance_mm
        L, W, t = self.length_mm, self.width_mm, s.cover_mm
        plate = box(-L / 2, L / 2, -W / 2, W / 2, 0, t)
        R = s.cavity_radius_mm
        collar = cyl(R + s.collar_wall_mm, s.collar_mm + 0.01, (0, 0, t - 0.005), Z)
        body = plate.fuse(collar).clean()
        cav = cyl(R, t + s.roof_under_mm + 0.1, (0, 0, -0.1), Z)
        hole = _cross(s.arm_width_mm + 2 * c, s.arm_length_mm + 2 * c, t + s.roof_under_mm - 0.1, s.roof_mm + 0.2)
        screws = [cyl(1.7, t + 0.2, (x, y, -0.1), Z) for x in (-L / 2 + 5, L / 2 - 5) for y in (-W / 2 + 5, W / 2 - 5)]
        return cut_all(body, [cav, hole] + screws)


@dataclass(frozen=True)
class LockingKey(Part):
    """Locking key: drops into one arm of the cross hole after the twist and blocks the
    key head from turning back (frame = cover frame)."""

    spec: TopTwistSpec = TopTwistSpec()
    name: ClassVar[str] = "locking_key"
    description: ClassVar[str] = "twist-and-lock: locking key that stops the turned cross key"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 180.0),)

    def build(self):
        from .shapes import box

        s = self.spec
        t = s.cover_mm
        x0, x1 = s.lock_x0_mm, s.arm_length_mm / 2
        a = s.arm_width_mm / 2
        top = t + s.collar_mm
        block = box(x0, x1, -a, a, t + s.head_z0_mm, top)
        lip = box(x0, x1 + 3.0, -a - 2.0, a + 2.0, top, top + s.lip_mm)
        return block.fuse(lip).clean()


@dataclass(frozen=True)
class CasterSeat(Part):
    """Snap-in seat for a ball caster under the floor (frame: z = 0 at the underside).

    The ball protrudes a third of its diameter below the seat (thesis: 10 mm
    casters, a third exposed); the seat height follows from the wheels' exposed
    height so that wheels and casters touch flat ground together.
    """

    ball_diameter_mm: float = 10.0
    wheel_exposed_mm: float = 15.0
    outer_diameter_mm: float = 14.0
    exposed_fraction: float = 1.0 / 3.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    name: ClassVar[str] = "caster_seat"
    description: ClassVar[str] = "ball-caster seat (snap-in socket), screwed under the floor"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 180.0),)

    def validate(self) -> None:
        need(0.1 <= self.exposed_fraction <= 0.45, f"exposed_fraction {self.exposed_fraction:g} must be in 0.1..0.45")
        need(at_least(self.outer_diameter_mm, self.ball_diameter_mm + 2 * self.clearance_mm + 2 * MIN_WALL_MM),
             f"outer_diameter_mm {self.outer_diameter_mm:g} leaves no wall around the "
             f"{self.ball_diameter_mm:g} mm ball")
        top = self.ball_centre_z_mm + self.ball_diameter_mm / 2 + self.clearance_mm
        need(at_most(top, -MIN_WALL_MM),
             f"ball_diameter_mm {self.ball_diameter_mm:g} is too large for wheel_exposed_mm "
             f"{self.wheel_exposed_mm:g}: the socket would break through the floor")

    @property
    def exposed_mm(self) -> float:
        return self.exposed_fraction * self.ball_diameter_mm

    @property
    def seat_height_mm(self) -> float:
        return self.wheel_exposed_mm - self.exposed_mm

    @property
    def ball_centre_z_mm(self) -> float:
        return -self.wheel_exposed_mm + self.ball_diameter_mm / 2

    def build(self):
        from .shapes import Z, cyl, sphere

        boss = cyl(self.outer_diameter_mm / 2, self.seat_height_mm, (0, 0, -self.seat_height_mm), Z)
        sock = sphere(self.ball_diameter_mm / 2 + self.clearance_mm, (0, 0, self.ball_centre_z_mm))
        return boss.cut(sock).cut(cyl(1.5, 3.0, (0, 0, -3.0), Z))
