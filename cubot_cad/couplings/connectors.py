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
is whatever the geometry gives (``cubot_cad.checks.docking`` measures it by moving one
robot until first contact): zero when the pins are shorter than the latch
depth (CuBot), ``protrusion - depth`` when they are longer (the Cube Robot's
1.7 mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from cubot_cad.couplings.preload import WedgeLatch
from cubot_cad.part import (
    DEFAULT_CLEARANCE_MM,
    MIN_WALL_MM,
    NOZZLE_MM,
    Mate,
    Part,
    at_least,
    at_most,
    check_clearance,
    check_lengths,
    need,
)

PIN_ANGLES_DEG = (90.0, 210.0, 330.0)
#: In the nominal model the locked blade's slot edge must overlap the pin's shoulder
#: (pin radius - slot half-width = (pin - groove) / 2 - clearance) by at least half an
#: extrusion width; as printed the overlap is larger (the over-extrusion the clearance
#: compensates narrows the slot and fattens the pin).
MIN_LATCH_OVERLAP_MM = NOZZLE_MM / 2


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
    #: Lead-ins (45 deg) that let a misaligned pin find its hole: a chamfer on the pin tip (radial = axial
    #: size) and a countersink on the pin holes' mouths in the latch-side wall. Together with the clearance
    #: they set the lateral capture (``capture_estimate_mm``); 0 = no lead-in (sharp edges).
    pin_chamfer_mm: float = 0.6
    hole_chamfer_mm: float = 0.8
    #: The pins print lying down (layers along the axis, so the pull at the groove neck runs along
    #: them, not across): on a flat along the whole pin, at most ``pin_flat_max_mm`` deep, and never
    #: so deep that the locked blade's slot overlaps the flattened shoulder by less than
    #: :data:`MIN_LATCH_OVERLAP_MM` (``pin_flat_mm``: 0.4 mm at the default clearance, 0.1 at 0.5).
    pin_flat_max_mm: float = 0.4
    #: The blade's drive: a ``drive_shaft_mm`` D-shaft (flat ``drive_flat_mm`` across, i.e. 1 mm deep)
    #: from the latch servo's coupler through the rear plate's bearing hole (round, shaft + 2 clearances)
    #: into the blade's D bore (the D offset by the clearance): the flat turns the blade.
    drive_shaft_mm: float = 5.0
    drive_flat_mm: float = 4.0
    #: Screws through the block stack into the wall (nut behind): clearance holes from the fastener table.
    screw_size: str = "M3"
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    #: The wedge latch (:mod:`cubot_cad.couplings.preload`): a cone on the groove's tip side and tapered
    #: blade slots that draw the pins in and preload the faces (no free play). None: the clearance latch
    #: (flat blade in a flat groove, ``2 clearance_mm`` of tension play), the thesis's drawing.
    wedge: WedgeLatch | None = None

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        if self.wedge is not None:
            need(isinstance(self.wedge, WedgeLatch), f"wedge must be a WedgeLatch or None, got {self.wedge!r}")
        check_lengths(self, ("wall_mm", "plate_mm", "pin_diameter_mm", "groove_diameter_mm", "head_shoulder_mm",
                             "head_mm", "head_wall_mm", "blade_mm", "pocket_depth_mm", "pin_circle_mm", "block_mm",
                             "blade_radius_mm", "pin_flat_max_mm"), ("pin_chamfer_mm", "hole_chamfer_mm"))
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
        # (the slot at a fraction f of the turn lies f*th off its vertex and is slot_half_width_mm(f) wide)
        wall_slot = min(inr - self.pin_circle_mm * math.cos(math.radians(60) - th * k / 16) - self.slot_half_width_mm(k / 16)
                        for k in range(17))
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
        need(at_least(self.pin_flat_mm, 0.1),
             f"clearance_mm {c:g} leaves the grooved pins no flat to print lying on (pin_diameter_mm "
             f"{self.pin_diameter_mm:g}, groove_diameter_mm {self.groove_diameter_mm:g}: the latch overlap "
             f"{self.latch_overlap_mm:.2f} mm must exceed {MIN_LATCH_OVERLAP_MM:g} mm by at least 0.1 mm)")
        need(at_most(self.pin_chamfer_mm, self.pin_diameter_mm / 2 - 1.0),
             f"pin_chamfer_mm {self.pin_chamfer_mm:g} leaves the {self.pin_diameter_mm:g} mm pin a tip face under 2 mm")
        from cubot_cad.hardware.fasteners import thread as _thread

        head = _thread(self.screw_size).countersunk_head_diameter_mm
        need(head is not None,
             f"screw_size {self.screw_size!r}: the block screws are ISO 10642 countersunk, which starts at M3")
        from cubot_cad.hardware.fasteners import clearance_hole_mm as _hole

        sink = (head + NOZZLE_MM - _hole(self.screw_size)) / 2  # 90 deg: depth = radial step
        need(at_most(sink, self.wall_mm - MIN_WALL_MM / 2),
             f"wall_mm {self.wall_mm:g} is too thin for the {self.screw_size} countersunk block screws "
             f"({sink:.2f} mm deep)")
        need(at_most(self.hole_chamfer_mm, self.wall_mm / 2),
             f"hole_chamfer_mm {self.hole_chamfer_mm:g} countersinks more than half the {self.wall_mm:g} mm wall")
        need(self.drive_shaft_mm / 2 < self.drive_flat_mm < self.drive_shaft_mm - 0.2,
             f"drive_flat_mm {self.drive_flat_mm:g} must lie between the radius and the diameter (less 0.2 mm) "
             f"of the {self.drive_shaft_mm:g} mm drive shaft")
        need(at_least(self.pin_circle_mm - self.pin_diameter_mm / 2 - c - self.drive_shaft_mm / 2 - c, MIN_WALL_MM),
             f"drive_shaft_mm {self.drive_shaft_mm:g} leaves no wall to the pin holes (pin_circle_mm {self.pin_circle_mm:g})")
        from cubot_cad.hardware.fasteners import thread

        thread(self.screw_size)
        if self.pin_protrusion_mm is not None:
            check_lengths(self, ("pin_protrusion_mm",))
            need(at_least(self.pin_protrusion_mm, self.blade_end_mm + 1.0),
                 f"pin_protrusion_mm {self.pin_protrusion_mm:g} does not reach past the latch blade "
                 f"(needs >= {self.blade_end_mm + 1.0:g} mm)")
        tip_len = self.protrusion_mm - (self.design_gap_mm + self.wall_mm + 2 * self.plate_mm + self.separation_mm)
        need(at_most(self.pin_chamfer_mm, tip_len - 0.5),
             f"pin_chamfer_mm {self.pin_chamfer_mm:g} is longer than the pin's {tip_len:.2f} mm tip beyond its groove "
             "allows (keep 0.5 mm of full diameter)")
        if self.wedge is not None:  # after the plain checks: a bad pin or groove is named as such first
            self.wedge.validate(self)

    # -- derived ------------------------------------------------------------
    @property
    def screw_hole_mm(self) -> float:
        """Diameter of the block's screw holes: ISO 273 medium clearance for ``screw_size``."""
        from cubot_cad.hardware.fasteners import clearance_hole_mm

        return clearance_hole_mm(self.screw_size)

    @property
    def pin_stack_mm(self) -> float:
        """What the block screws clamp on the pin side: wall + plates d, c, b, a."""
        return self.wall_mm + 3 * self.plate_mm + self.locking_plate_mm

    @property
    def latch_stack_mm(self) -> float:
        """What the block screws clamp on the latch side: wall + plates a, b, c, e."""
        return self.wall_mm + 2 * self.plate_mm + self.separation_mm + self.rear_plate_mm

    @property
    def capture_estimate_mm(self) -> float:
        """Lateral offset the lead-ins are sized to take up: clearance + pin chamfer + hole countersink
        (the docking model measures the real capture, :mod:`cubot_cad.checks.capture`)."""
        return self.clearance_mm + self.pin_chamfer_mm + self.hole_chamfer_mm

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
    def pin_flat_mm(self) -> float:
        """Depth of the flat the pins print lying on (below their radius): ``pin_flat_max_mm``, less
        where the locked blade's overlap over the flattened shoulder would fall under
        :data:`MIN_LATCH_OVERLAP_MM`."""
        return max(0.0, min(self.pin_flat_max_mm, self.latch_overlap_mm - MIN_LATCH_OVERLAP_MM))

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

    def slot_half_width_mm(self, f: float) -> float:
        """Half-width of a blade slot a fraction ``f`` of the turn from its open end (0) to its locking
        end (1): constant for the clearance latch, tapering for the wedge latch."""
        if self.wedge is None:
            return self.slot_width_mm / 2
        return self.wedge.half_width_mm(self, f)

    @property
    def pin_draw_mm(self) -> float:
        """How far a locked latch draws the pins out of their robot (mm): the head's axial clearance for
        the wedge latch (the head then bears on the front of its counterbore), 0 for the clearance latch."""
        return 0.0 if self.wedge is None else self.clearance_mm

    @property
    def locked_turn_deg(self) -> float:
        """The blade's turn when locked on a nominal print (deg): the full turn for the clearance latch;
        for the wedge latch where the slot's edges meet the cone of pins drawn in by :attr:`pin_draw_mm`
        (the servo stalls there; the rest of the turn is the reach kept for looser prints)."""
        if self.wedge is None:
            return self.blade_turn_deg
        w = self.wedge
        h_c = w.lock_half_width_mm(self) + (w.take_up_mm(self) - self.pin_draw_mm) * w.tan_cone
        return self.blade_turn_deg * w.turn_fraction(self, h_c)

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

    @property
    def screw_countersink_mm(self) -> float:
        """Diameter of the 90 deg countersinks in the docking face for the block screws: the ISO 10642
        head plus half a nozzle width each side (the heads sit flush, the faces still touch; a fixed
        allowance for a bought part, not the print clearance of two printed parts)."""
        from cubot_cad.hardware.fasteners import thread

        return thread(self.screw_size).countersunk_head_diameter_mm + NOZZLE_MM

    @property
    def drive_play_deg(self) -> float:
        """Angular play of the D-shaft in the blade's bore (the flat's corners reach the bore's flat)."""
        r = self.drive_shaft_mm / 2
        d = self.drive_flat_mm - r
        h = math.sqrt(r * r - d * d)
        # d cos t + h sin t = d + c  ->  t = asin((d + c) / rho) - atan2(d, h)
        rho = math.hypot(d, h)
        return math.degrees(math.asin(min(1.0, (d + self.clearance_mm) / rho)) - math.atan2(d, h))

    def d_profile(self, x0: float, length: float, offset_mm: float = 0.0):
        """The drive shaft's D cross-section along +x from ``x0`` (set frame, on the block axis), grown by
        ``offset_mm`` on every side: the shaft itself (0) or the blade's bore (the clearance). The flat
        faces +y before the blade turns."""
        from cubot_cad.shapes import X, box, cyl

        r = self.drive_shaft_mm / 2 + offset_mm
        flat = self.drive_flat_mm - self.drive_shaft_mm / 2 + offset_mm
        return cyl(r, length, (x0, 0, 0), X).intersect(box(x0 - 1, x0 + length + 1, -r - 1, flat, -r - 1, r + 1))

    def _wall_common(self) -> list:
        from cubot_cad.shapes import X, box, cone, cyl

        w = self.wall_mm
        out = [box(-w - 0.1, 0.1, y - a / 2, y + a / 2, z - b / 2, z + b / 2) for y, z, a, b in self.ir_windows()]
        r, R = self.screw_hole_mm / 2, self.screw_countersink_mm / 2
        for y, z in self.screw_positions():
            out.append(cyl(r, w + 0.2, (-w - 0.1, y, z), X))
            out.append(cone(R + 0.1, r, R - r + 0.1, (0.1, y, z), (-1.0, 0.0, 0.0)))  # countersunk head, flush
        return out

    def pin_wall_cutters(self) -> list:
        """Cutters for the wall in front of a pin block (set frame, outer face at x = 0): plain pin holes
        (the pins come out here), IR windows, screw holes."""
        from cubot_cad.shapes import X, cyl

        w = self.wall_mm
        return [cyl(self.pin_diameter_mm / 2 + self.clearance_mm, w + 0.2, (-w - 0.1, y, z), X)
                for y, z in self.pin_positions()] + self._wall_common()

    def latch_wall_cutters(self) -> list:
        """Cutters for the wall in front of a latch block (set frame, outer face at x = 0): pin holes with a
        45 deg countersink ``hole_chamfer_mm`` deep on the outer face (the lead-in a docking pin meets
        first), IR windows, screw holes."""
        from cubot_cad.shapes import X, cone, cyl

        w, r, h = self.wall_mm, self.pin_diameter_mm / 2 + self.clearance_mm, self.hole_chamfer_mm
        out = []
        for y, z in self.pin_positions():
            out.append(cyl(r, w + 0.2, (-w - 0.1, y, z), X))
            if h > 0:  # from 0.1 mm outside the face (a clean cut) to h deep
                out.append(cone(r + h + 0.1, r, h + 0.1, (0.1, y, z), (-1.0, 0.0, 0.0)))
        return out + self._wall_common()

    def wall_cutters(self, side: str) -> list:
        """The wall cutters for a ``"pin"`` or a ``"latch"`` block (see the two methods)."""
        if side == "pin":
            return self.pin_wall_cutters()
        if side == "latch":
            return self.latch_wall_cutters()
        raise ValueError(f"side {side!r} is not pin or latch")


# --- the block plates: one class, the variants in a table (as cq_warehouse does for fasteners) -------
#
# Grooved-pin set (thesis Fig. 6.2): a locking plate, b pin-locking plate, c IR PCB plate, d locking
# plate, e three grooved pins. Engagement-latch set (Fig. 6.3): a locking plate, b IR PCB plate,
# c separation plate, d triangular blade, e locking plate. The plates are one kind of part: a square
# ``block_mm`` plate between two set-frame x planes with the four block screws' holes (ISO 273 from the
# fastener table, :attr:`FrontRearSpec.screw_hole_mm`), optionally the pin holes and the IR windows, and
# at most a few features of its own; :data:`PLATES` lists them.

#: Lay a plate on one of its square faces (its x axis vertical).
_FLAT_X: tuple = (((0.0, 1.0, 0.0), 90.0),)


def _span_front(s: FrontRearSpec) -> tuple[float, float]:
    return (-s.wall_mm - s.plate_mm, -s.wall_mm)  # right behind the robot wall


def _span_ir(s: FrontRearSpec) -> tuple[float, float]:
    return (-s.wall_mm - 2 * s.plate_mm, -s.wall_mm - s.plate_mm)


def _span_pin_locking(s: FrontRearSpec) -> tuple[float, float]:
    return (s.head_x_mm, s.head_x_mm + s.locking_plate_mm)


def _span_pin_rear(s: FrontRearSpec) -> tuple[float, float]:
    return (s.head_x_mm - s.plate_mm, s.head_x_mm)


def _span_separation(s: FrontRearSpec) -> tuple[float, float]:
    x1 = -s.wall_mm - 2 * s.plate_mm
    return (x1 - s.separation_mm, x1)


def _span_latch_rear(s: FrontRearSpec) -> tuple[float, float]:
    x1 = -s.blade_end_mm
    return (x1 - s.rear_plate_mm, x1)


def _counterbores(s: FrontRearSpec, x0: float, x1: float) -> list:
    """The pin heads' counterbores (head + clearance wide, head + clearance deep from the back face)."""
    from cubot_cad.shapes import X, cyl

    return [cyl(s.head_diameter_mm / 2 + s.clearance_mm, s.head_mm + s.clearance_mm + 0.1, (x0 - 0.1, y, z), X)
            for y, z in s.pin_positions()]


def _blade_cavity(s: FrontRearSpec, x0: float, x1: float) -> list:
    """The round cavity the blade turns in and the blade's lever slot."""
    from cubot_cad.shapes import X, box, cyl

    cav = cyl(s.blade_radius_mm + s.clearance_mm, s.separation_mm + 0.2, (x0 - 0.1, 0, 0), X)
    slot = box(x0 - 0.1, x1 + 0.1, -3.0, 3.0, -s.block_mm, 0)
    return [cav, slot]


def _pin_pockets(s: FrontRearSpec, x0: float, x1: float) -> list:
    """The blind pockets that stop the pin tips (the latch depth) and the drive shaft's bearing hole."""
    from cubot_cad.shapes import X, cyl

    r = s.pin_diameter_mm / 2 + s.clearance_mm
    pockets = [cyl(r, s.pocket_depth_mm + 0.1, (x1 - s.pocket_depth_mm, y, z), X) for y, z in s.pin_positions()]
    shaft = cyl(s.drive_shaft_mm / 2 + s.clearance_mm, s.rear_plate_mm + 0.2, (x0 - 0.1, 0, 0), X)  # bearing
    return pockets + [shaft]


@dataclass(frozen=True)
class PlateKind:
    """One variant of :class:`BlockPlate`: its file stem, what it is, where it lies in the set frame
    (``span``: spec -> (x0, x1), mm), which of the common holes it has, its own ``features`` (spec, x0,
    x1 -> cutters), how it prints and its mating points (name -> spec -> set-frame x of a +x-facing mate)."""

    name: str
    description: str
    span: object
    pin_holes: bool = True
    windows: bool = False
    features: tuple = ()
    print_rotation: tuple = _FLAT_X
    print_orientation: str = ""
    mates: tuple = ()


#: The plates of both block sets, by file stem. Two pairs share their geometry (the sets' front and IR
#: plates) and stay two printed parts each: they go on different blocks and carry different boards.
PLATES: dict[str, PlateKind] = {k.name: k for k in (
    PlateKind("pinset_d_front_locking_plate", "grooved-pin set (d): locking plate against the wall, pin holes",
              _span_front),
    PlateKind("pinset_c_ir_pcb_plate", "grooved-pin set (c): carrier of the IR receiver PCB", _span_ir, windows=True),
    # front face (toward the wall, plain pin holes: the larger face) on the bed, the counterbores open upward
    # (their shoulders face up: no bridge); about +y by -90 deg, as it was, put the counterbores on the bed
    PlateKind("pinset_b_pin_locking_plate", "grooved-pin set (b): holds the pin heads in counterbores",
              _span_pin_locking, features=(_counterbores,), print_rotation=(((0.0, 1.0, 0.0), 90.0),),
              print_orientation="front face (plain pin holes, the larger face) on the bed, counterbores up"),
    PlateKind("pinset_a_rear_locking_plate", "grooved-pin set (a): closes the stack behind the pin heads",
              _span_pin_rear, pin_holes=False),
    PlateKind("latchset_a_front_locking_plate", "latch set (a): locking plate against the wall, pin holes",
              _span_front),
    PlateKind("latchset_b_ir_pcb_plate", "latch set (b): carrier of the IR transmitter PCB", _span_ir, windows=True),
    PlateKind("latchset_c_separation_plate", "latch set (c): blade cavity and the triangular-blade lever slot",
              _span_separation, pin_holes=False, features=(_blade_cavity,)),
    PlateKind("latchset_e_rear_locking_plate", "latch set (e): pin pockets (latch depth) and the servo shaft hole",
              _span_latch_rear, pin_holes=False, features=(_pin_pockets,),
              print_rotation=(((0.0, 1.0, 0.0), -90.0),), print_orientation="back face down, the pin pockets open up",
              mates=(("pocket_bottom", lambda s: -s.latch_depth_mm),)),
)}


@dataclass(frozen=True)
class BlockPlate(Part):
    """A plate of a connector block (set frame): the :data:`PLATES` row ``kind`` built from ``spec``."""

    kind: str = "pinset_d_front_locking_plate"
    spec: FrontRearSpec = FrontRearSpec()

    def validate(self) -> None:
        need(self.kind in PLATES, f"BlockPlate.kind {self.kind!r} is not one of {', '.join(PLATES)}")

    @property
    def row(self) -> PlateKind:
        return PLATES[self.kind]

    # the per-variant class attributes of a Part, from the table
    @property
    def name(self) -> str:  # type: ignore[override]
        return self.row.name

    @property
    def description(self) -> str:  # type: ignore[override]
        return self.row.description

    @property
    def print_rotation(self):  # type: ignore[override]
        return self.row.print_rotation

    @property
    def print_orientation(self) -> str:  # type: ignore[override]
        return self.row.print_orientation

    @property
    def span_mm(self) -> tuple[float, float]:
        """(x0, x1) of the plate in the set frame, mm."""
        return self.row.span(self.spec)

    def build(self):
        from cubot_cad.shapes import X, box, cut_all, cyl

        s, k = self.spec, self.row
        x0, x1 = self.span_mm
        h = s.block_mm / 2
        base = box(x0, x1, -h, h, -h, h)
        cut = [cyl(s.screw_hole_mm / 2, x1 - x0 + 0.2, (x0 - 0.1, y, z), X) for y, z in s.screw_positions()]
        if k.pin_holes:
            r = s.pin_diameter_mm / 2 + s.clearance_mm
            cut += [cyl(r, x1 - x0 + 0.2, (x0 - 0.1, y, z), X) for y, z in s.pin_positions()]
        if k.windows:
            cut += [box(x0 - 0.1, x1 + 0.1, y - a / 2, y + a / 2, z - b / 2, z + b / 2)
                    for y, z, a, b in s.ir_windows()]
        for feature in k.features:
            cut += feature(s, x0, x1)
        return cut_all(base, cut)

    @property
    def mates(self):
        return {n: Mate((x(self.spec), 0, 0), (1, 0, 0)) for n, x in self.row.mates}


def _plate_of(kind: str):
    """A constructor of one :data:`PLATES` variant (``PinLockingPlate(spec=s)``, as before the table)."""

    def make(spec: FrontRearSpec = FrontRearSpec(), **kw) -> BlockPlate:
        return BlockPlate(kind=kind, spec=spec, **kw)

    make.__doc__ = f"The {kind} plate: ``BlockPlate(kind={kind!r}, spec=...)``."
    return make


PinFrontPlate = _plate_of("pinset_d_front_locking_plate")
PinIrPlate = _plate_of("pinset_c_ir_pcb_plate")
PinLockingPlate = _plate_of("pinset_b_pin_locking_plate")
PinRearPlate = _plate_of("pinset_a_rear_locking_plate")
LatchFrontPlate = _plate_of("latchset_a_front_locking_plate")
LatchIrPlate = _plate_of("latchset_b_ir_pcb_plate")
LatchSeparationPlate = _plate_of("latchset_c_separation_plate")
LatchRearPlate = _plate_of("latchset_e_rear_locking_plate")


@dataclass(frozen=True)
class GroovedPin(Part):
    """(e) One grooved pin (three per block), axis +x at y = z = 0 of the set frame."""

    spec: FrontRearSpec = FrontRearSpec()
    name: ClassVar[str] = "pinset_e_grooved_pin"
    description: ClassVar[str] = "grooved-pin set (e): grooved pin, three per block, printed lying on its flat"
    #: The mounting frame already lays it down: axis along x, the flat (``FrontRearSpec.pin_flat_mm``) at -z.
    print_rotation: ClassVar = ()
    print_orientation: ClassVar[str] = ("lying on its flat, axis horizontal: the layers run along the pin, so the "
                                        "pull at the groove neck runs along them, not across (standing, the neck "
                                        "was a stack of 3.4 mm discs)")
    infill_percent: ClassVar[int] = 100

    @property
    def groove_mm(self) -> tuple[float, float]:
        """x-range of the groove in the set frame (aligned with the latch blade when docked)."""
        s = self.spec
        if s.wedge is not None:
            g0, x_s, _x_e = s.wedge.groove_x_mm(s)
            return (g0, x_s)
        g0 = s.design_gap_mm + s.wall_mm + 2 * s.plate_mm
        return (g0, g0 + s.separation_mm)

    def build(self):
        from cubot_cad.shapes import X, box, cone, cyl, fuse_all

        s = self.spec
        x_head = s.head_x_mm
        r, rg = s.pin_diameter_mm / 2, s.groove_diameter_mm / 2
        g0, g1 = self.groove_mm
        tip = s.protrusion_mm
        ch = s.pin_chamfer_mm
        parts = [cyl(s.head_diameter_mm / 2, s.head_mm, (x_head, 0, 0), X),
                 cyl(r, g0 - x_head - s.head_mm, (x_head + s.head_mm, 0, 0), X),
                 cyl(rg, g1 - g0, (g0, 0, 0), X)]
        if s.wedge is not None:  # the groove's tip side: the cone the wedge slots draw the pin by
            _g0, x_s, x_e = s.wedge.groove_x_mm(s)
            parts += [cone(rg, r, x_e - x_s, (x_s, 0, 0), X), cyl(r, tip - x_e - ch, (x_e, 0, 0), X)]
        else:
            parts.append(cyl(r, tip - g1 - ch, (g1, 0, 0), X))
        if ch > 0:  # the lead-in: a 45 deg chamfer on the tip
            parts.append(cone(r, r - ch, ch, (tip - ch, 0, 0), X))
        pin = fuse_all(parts)
        f = s.pin_flat_mm
        if f <= 0:
            return pin
        # the flat it prints on, along the whole pin (head included) at -z
        R = s.head_diameter_mm / 2 + 1.0
        return pin.cut(box(x_head - 1.0, tip + 1.0, -R, R, -R, -(r - f)))

    @property
    def mates(self):
        return {"tip": Mate((self.spec.protrusion_mm, 0, 0), (1, 0, 0))}



@dataclass(frozen=True)
class TriangularBlade(Part):
    """(d) Triangular blade with three keyhole arc slots; turning it by
    ``blade_turn_deg`` moves the narrow ends of the slots into the pin grooves."""

    spec: FrontRearSpec = FrontRearSpec()
    locked: bool = False
    name: ClassVar[str] = "latchset_d_triangular_blade"
    description: ClassVar[str] = ("latch set (d): triangular blade on a 5 mm D-shaft, turned by a micro servo to "
                                  "lock the pins")
    print_rotation: ClassVar = _FLAT_X

    def build(self):
        from cubot_cad.shapes import X, cut_all, cyl, fuse_all, prism, rotated

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
            if s.wedge is not None:  # the tapered slot: open end at a1 (the entry), locking end at a0
                n = 24
                fs = sorted(set([k / n for k in range(n + 1)] + list(s.wedge.profile_breaks(s))))
                ang = [a1 + (a0 - a1) * f for f in fs]
                hw = [s.slot_half_width_mm(f) for f in fs]
                outer = [((r + h) * math.cos(g), (r + h) * math.sin(g)) for h, g in zip(hw, ang, strict=True)]
                inner = [((r - h) * math.cos(g), (r - h) * math.sin(g)) for h, g in zip(hw, ang, strict=True)]
                cutters.append(prism(outer + inner[::-1], "YZ", x0 - 0.1, t))
                cutters.append(cyl(hw[-1], t, (x0 - 0.1, r * math.cos(a0), r * math.sin(a0)), X))
                cutters.append(cyl(s.pin_diameter_mm / 2 + c, t, (x0 - 0.1, r * math.cos(a1), r * math.sin(a1)), X))
                continue
            R = 3 * r
            wedges.append(prism([(0, 0), (R * math.cos(a0), R * math.sin(a0)),
                                 (R * math.cos((a0 + a1) / 2) * 1.2, R * math.sin((a0 + a1) / 2) * 1.2),
                                 (R * math.cos(a1), R * math.sin(a1))], "YZ", x0 - 0.1, t))
            cutters.append(cyl(w / 2, t, (x0 - 0.1, r * math.cos(a0), r * math.sin(a0)), X))
            cutters.append(cyl(s.pin_diameter_mm / 2 + c, t, (x0 - 0.1, r * math.cos(a1), r * math.sin(a1)), X))
        if wedges:
            cutters.append(ring.intersect(fuse_all(wedges)))
        cutters.append(s.d_profile(x0 - 0.1, t, c))  # the D bore the drive shaft turns the blade by
        shape = cut_all(blade, cutters)
        if self.locked:
            shape = rotated(shape, X, s.locked_turn_deg)
        return shape


#: The plates of each block, from the robot wall inward.
PIN_SET_PLATES = ("pinset_d_front_locking_plate", "pinset_c_ir_pcb_plate", "pinset_b_pin_locking_plate",
                  "pinset_a_rear_locking_plate")
LATCH_SET_PLATES = ("latchset_a_front_locking_plate", "latchset_b_ir_pcb_plate", "latchset_c_separation_plate",
                    "latchset_e_rear_locking_plate")


def pin_set_parts(spec: FrontRearSpec) -> list[tuple[Part, list[tuple[float, float, float]]]]:
    """The five parts of one grooved-pin block with their offsets in the set frame."""
    plates: list = [(BlockPlate(kind=k, spec=spec), [(0, 0, 0)]) for k in PIN_SET_PLATES]
    return plates + [(GroovedPin(spec=spec), [(0, y, z) for y, z in spec.pin_positions()])]


def latch_set_parts(spec: FrontRearSpec, locked: bool = False) -> list[tuple[Part, list[tuple[float, float, float]]]]:
    """The five parts of one latch block (blade locked or open) in the set frame: the blade turns between
    the separation plate (c) and the rear plate (e)."""
    plates: list = [(BlockPlate(kind=k, spec=spec), [(0, 0, 0)]) for k in LATCH_SET_PLATES]
    return plates[:3] + [(TriangularBlade(spec=spec, locked=locked), [(0, 0, 0)])] + plates[3:]


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
    #: Lead-ins at both ends (45 deg), so that a robot sliding in alongside finds the dovetail: the
    #: groove's outline grows by ``groove_flare_mm`` (normal to every face, floor included) toward each
    #: end face; the tongue's outline shrinks by ``tongue_taper_mm`` toward its ends; the mating faces'
    #: end edges (male plate face, female mouth face) are chamfered ``end_chamfer_mm``. 0 = sharp ends.
    #: The flare and the taper run over ``flare_length_mm`` / ``taper_length_mm`` (2.5 x their size:
    #: 22 deg to the rail axis), not 45 deg, because a dovetail flank (26.6 deg from the plate face)
    #: turns only sin 26.6 = 0.45 of a sideways give into its normal; the end chamfers are 45 deg.
    groove_flare_mm: float = 1.0
    flare_length_mm: float = 2.5
    tongue_taper_mm: float = 0.6
    taper_length_mm: float = 1.5
    end_chamfer_mm: float = 0.8
    #: Each half is screwed to the robot's side wall by two ISO 10642 countersunk screws on the rail's
    #: axis (z = 0) at x = +-``screw_x_mm``, into heat-set inserts in bosses inside the body: through the
    #: male's tongue and plate (head in the tongue's tip face), through the female's groove floor (head in
    #: the floor). Each head sits ``screw_recess_mm`` below the face it is sunk in, so the mating half
    #: slides over it (its sliding faces never reach below those faces).
    screw_size: str = "M3"
    screw_x_mm: float = 28.0
    screw_recess_mm: float = 0.2
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        check_lengths(self, ("length_mm", "height_mm", "plate_mm", "tongue_mm", "tongue_root_mm", "tongue_tip_mm",
                             "ir_hole_mm", "ir_inset_mm", "screw_x_mm", "screw_recess_mm", "flare_length_mm",
                             "taper_length_mm"), ("groove_flare_mm", "tongue_taper_mm", "end_chamfer_mm"))
        from cubot_cad.hardware.fasteners import thread

        head = thread(self.screw_size).countersunk_head_diameter_mm
        need(head is not None,
             f"RailSpec.screw_size {self.screw_size!r}: the rail screws are ISO 10642 countersunk, which starts at M3")
        sink_r = self.screw_countersink_mm / 2
        need(at_least(self.tongue_tip_mm / 2 - sink_r, MIN_WALL_MM / 2)
             and at_least(self.tongue_root_mm / 2 - self.screw_hole_mm / 2, MIN_WALL_MM),
             f"tongue_tip_mm {self.tongue_tip_mm:g} / tongue_root_mm {self.tongue_root_mm:g}: the tongue is too narrow "
             f"for the {self.screw_size} countersunk rail screws ({self.screw_countersink_mm:g} mm countersink)")
        need(at_least(self.tongue_mm + self.plate_mm - self.screw_sink_depth_mm - self.screw_recess_mm, MIN_WALL_MM),
             f"tongue_mm {self.tongue_mm:g}: the male rail's countersunk screw heads leave under {MIN_WALL_MM:g} mm")
        floor = self.plate_mm - self.clearance_mm  # the female's groove floor
        need(at_least(floor - self.screw_sink_depth_mm - self.screw_recess_mm, NOZZLE_MM),
             f"RailSpec.plate_mm {self.plate_mm:g} leaves the female's {floor:g} mm groove floor too thin for the "
             f"{self.screw_size} countersunk screw heads ({self.screw_sink_depth_mm:g} mm deep, recessed "
             f"{self.screw_recess_mm:g} mm; clearance_mm {self.clearance_mm:g})")
        ends = self.length_mm / 2 - max(self.flare_length_mm, self.taper_length_mm) - MIN_WALL_MM
        need(at_most(self.screw_x_mm + sink_r, ends),
             f"RailSpec.screw_x_mm {self.screw_x_mm:g} puts the rail screws into the rail's end lead-ins")
        need(at_least(self.screw_x_mm - sink_r, MIN_WALL_MM),
             f"RailSpec.screw_x_mm {self.screw_x_mm:g} puts the two rail screws' countersinks into each other")
        need(self.flare_length_mm <= self.ir_inset_mm - self.ir_hole_mm / 2 - MIN_WALL_MM
             and self.taper_length_mm <= self.length_mm / 4,
             f"flare_length_mm {self.flare_length_mm:g} / taper_length_mm {self.taper_length_mm:g} reach the IR holes")
        need(at_least(self.plate_mm - self.clearance_mm - self.groove_flare_mm, MIN_WALL_MM),
             f"groove_flare_mm {self.groove_flare_mm:g} leaves the groove floor at the rail's ends thinner than "
             f"{MIN_WALL_MM:g} mm (plate_mm {self.plate_mm:g}, clearance_mm {self.clearance_mm:g})")
        need(at_most(self.tongue_taper_mm, self.tongue_mm / 2),
             f"tongue_taper_mm {self.tongue_taper_mm:g} is more than half the {self.tongue_mm:g} mm tongue")
        need(at_most(self.end_chamfer_mm, self.plate_mm / 2),
             f"end_chamfer_mm {self.end_chamfer_mm:g} is more than half the {self.plate_mm:g} mm plate")
        need(at_least(self.ir_inset_mm - self.ir_hole_mm / 2, self.end_chamfer_mm + MIN_WALL_MM),
             f"ir_inset_mm {self.ir_inset_mm:g} puts the IR holes into the rail's end lead-ins")
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
    def screw_hole_mm(self) -> float:
        """The rail screws' holes: ISO 273 medium clearance for ``screw_size``."""
        from cubot_cad.hardware.fasteners import clearance_hole_mm

        return clearance_hole_mm(self.screw_size)

    @property
    def screw_countersink_mm(self) -> float:
        """Diameter of the 90 deg countersinks at the face: the ISO 10642 head plus half a nozzle width
        each side (as the connector blocks' countersinks)."""
        from cubot_cad.hardware.fasteners import thread

        return thread(self.screw_size).countersunk_head_diameter_mm + NOZZLE_MM

    @property
    def screw_sink_depth_mm(self) -> float:
        """Depth of a 90 deg countersink (= its radial step) below the face it is sunk in."""
        return (self.screw_countersink_mm - self.screw_hole_mm) / 2

    def screw_xs_mm(self) -> tuple[float, float]:
        """x of the two screws of each half (rail frame; the female, turned 180 deg, has them at the
        same robot x: they are symmetric)."""
        return (-self.screw_x_mm, self.screw_x_mm)

    @property
    def male_screw_face_mm(self) -> float:
        """Rail-frame y of the face the male's screw heads are sunk in (its tongue's tip face)."""
        return self.plate_mm + self.tongue_mm

    @property
    def female_screw_face_mm(self) -> float:
        """Rail-frame y of the face the female's screw heads are sunk in (its groove floor)."""
        return self.female_mm - self.groove_depth_mm

    def screw_grip_mm(self, male: bool) -> float:
        """From a screw head's top (``screw_recess_mm`` below its face) to the rail's back face (on the
        wall, where the insert begins): what the screw clamps."""
        return (self.male_screw_face_mm if male else self.female_screw_face_mm) - self.screw_recess_mm

    def screw_cutters(self, face_y_mm: float) -> list:
        """Cutters (rail frame) of the two screw holes from the back face (y = 0) to ``face_y_mm``: the
        clearance hole, the countersink ``screw_recess_mm`` below the face and a counterbore of the
        countersink's diameter from there through the face (the recess)."""
        from cubot_cad.shapes import Y, cone, cyl

        r, R = self.screw_hole_mm / 2, self.screw_countersink_mm / 2
        seat = face_y_mm - self.screw_recess_mm  # the head's top
        out = []
        for x in self.screw_xs_mm():
            out.append(cyl(r, face_y_mm + 0.2, (x, -0.1, 0.0), Y))
            out.append(cone(R, r, R - r, (x, seat, 0.0), (0.0, -1.0, 0.0)))
            out.append(cyl(R, self.screw_recess_mm + 0.1, (x, seat - 0.001, 0.0), Y))
        return out

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

    def groove_half_width_mm(self, depth_mm: float, extra_mm: float = 0.0) -> float:
        """Half-width of the groove ``depth_mm`` behind its mouth: the tongue's half-width at that
        depth plus the flank offset (the flank is parallel to the tongue's); ``extra_mm`` offsets the
        flank further (the end flare)."""
        return (self.tongue_root_mm / 2 + (self.clearance_mm + extra_mm) * math.sqrt(1 + self.flank_slope ** 2)
                + depth_mm * self.flank_slope)

    def groove_outline(self, female_mm: float, extra_mm: float = 0.0) -> list[tuple[float, float]]:
        """(y, z) of the groove in the female's frame (mouth face at y = ``female_mm``), from 0.5 mm
        outside the mouth to the floor, offset by ``extra_mm`` beyond the clearance on every face."""
        out, deep = -0.5 - extra_mm, self.groove_depth_mm + extra_mm
        wo, wd = self.groove_half_width_mm(out, extra_mm), self.groove_half_width_mm(deep, extra_mm)
        t = female_mm
        return [(t - out, -wo), (t - deep, -wd), (t - deep, wd), (t - out, wo)]

    def tongue_outline(self, inset_mm: float = 0.0) -> list[tuple[float, float]]:
        """(y, z) of the tongue in the male's frame (plate face at y = ``plate_mm``), starting 0.01 mm
        inside the plate (a clean fuse), shrunk by ``inset_mm`` on the flanks and the tip (the end taper)."""
        p, k = self.plate_mm, self.flank_slope
        n = inset_mm * math.sqrt(1 + k ** 2)
        a = self.tongue_root_mm / 2 - 0.01 * k - n
        depth = self.tongue_mm - inset_mm
        b = self.tongue_root_mm / 2 + depth * k - n
        return [(p - 0.01, -a), (p + depth, -b), (p + depth, b), (p - 0.01, a)]

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
    description: ClassVar[str] = ("side rail, left half: dovetail tongue, two countersunk M3 screws through the "
                                  "tongue into the body's inserts")
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 90.0),)

    def build(self):
        from cubot_cad.shapes import Y, box, cut_all, cyl, fuse_all, loft_x, prism

        s = self.spec
        L, H, p = s.length_mm, s.height_mm, s.plate_mm
        plate = box(-L / 2, L / 2, 0, p, -H / 2, H / 2)
        e = s.end_chamfer_mm
        if e > 0:  # the plate face's end edges chamfered 45 deg (the lead-in for a robot coming in too close)
            plate = cut_all(plate, [prism([(sx * (L / 2 + 0.01), p - e - 0.01), (sx * (L / 2 + 0.01), p + 0.01),
                                           (sx * (L / 2 - e - 0.02), p + 0.01)], "XY", -H / 2 - 1, H + 2)
                                    for sx in (-1, 1)])
        g = s.tongue_taper_mm
        lt = s.taper_length_mm if g > 0 else 0.0
        tongue = [prism(s.tongue_outline(), "YZ", -L / 2 + lt, L - 2 * lt)]
        if g > 0:  # the tongue's ends taper (g over taper_length_mm)
            tongue += [loft_x(s.tongue_outline(g), -L / 2, s.tongue_outline(), -L / 2 + lt + 0.001),
                       loft_x(s.tongue_outline(), L / 2 - lt - 0.001, s.tongue_outline(g), L / 2)]
        body = fuse_all([plate] + tongue)
        holes = [cyl(s.ir_hole_mm / 2, p + 0.2, (x, -0.1, z), Y) for x, z in s.ir_points()]
        return cut_all(body, holes + s.screw_cutters(s.male_screw_face_mm))

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
    description: ClassVar[str] = ("side rail, right half: dovetail groove, printed groove up, two countersunk M3 "
                                  "screws through the groove floor into the body's inserts")
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 90.0),)

    def build(self):
        from cubot_cad.shapes import Y, box, cut_all, cyl, loft_x, prism

        s = self.spec
        L, H, t = s.length_mm, s.height_mm, s.female_mm
        plate = box(-L / 2, L / 2, 0, t, -H / 2, H / 2)
        # the groove's outline: the tongue offset by the clearance, drawn from 0.5 mm outside the
        # mouth (a clean cut through the mouth face) to the floor; y = t - depth
        groove = [prism(s.groove_outline(t), "YZ", -L / 2 - 1, L + 2)]
        f = s.groove_flare_mm
        if f > 0:  # the groove flares toward both end faces (f over flare_length_mm; 0.1 mm beyond them)
            lf = s.flare_length_mm
            big = s.groove_outline(t, f * (1 + 0.1 / lf))
            groove += [loft_x(big, -L / 2 - 0.1, s.groove_outline(t), -L / 2 + lf),
                       loft_x(s.groove_outline(t), L / 2 - lf, big, L / 2 + 0.1)]
        e = s.end_chamfer_mm
        if e > 0:  # the mouth face's end edges chamfered 45 deg
            groove += [prism([(sx * (L / 2 + 0.01), t - e - 0.01), (sx * (L / 2 + 0.01), t + 0.01),
                              (sx * (L / 2 - e - 0.02), t + 0.01)], "XY", -H / 2 - 1, H + 2) for sx in (-1, 1)]
        holes = [cyl(s.ir_hole_mm / 2, t + 0.2, (x, -0.1, z), Y) for x, z in s.ir_points()]
        return cut_all(plate, groove + holes + s.screw_cutters(s.female_screw_face_mm))


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
    #: Lead-ins (45 deg): a chamfer round the bottom edges of the key head and round the top edges of
    #: the cross hole in the collar roof; 0 = sharp edges.
    key_chamfer_mm: float = 0.8
    hole_chamfer_mm: float = 0.8
    #: Bore along the key for the IR transmitter that guides the upper robot (a 3 mm LED + 0.1 mm).
    ir_bore_mm: float = 3.2
    #: Screws of the pier deck's key flange and of the cover (into the body's corner bosses).
    screw_size: str = "M3"
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        check_lengths(self, ("arm_width_mm", "arm_length_mm", "head_mm", "roof_mm", "key_protrusion_mm", "flange_mm",
                             "flange_size_mm", "collar_wall_mm", "cover_mm", "lip_mm", "stand_mm",
                             "ground_clearance_mm"), ("key_chamfer_mm", "hole_chamfer_mm"))
        from cubot_cad.hardware.fasteners import thread

        thread(self.screw_size)
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
        need(at_most(self.key_chamfer_mm, min(self.head_mm / 2, self.arm_width_mm / 2 - 1.0)),
             f"key_chamfer_mm {self.key_chamfer_mm:g} is more than half the {self.head_mm:g} mm key head")
        need(at_most(self.hole_chamfer_mm, self.roof_mm / 2),
             f"hole_chamfer_mm {self.hole_chamfer_mm:g} is more than half the {self.roof_mm:g} mm collar roof")

    @property
    def screw_hole_mm(self) -> float:
        """ISO 273 medium clearance hole for ``screw_size`` (flange and cover screws)."""
        from cubot_cad.hardware.fasteners import clearance_hole_mm

        return clearance_hole_mm(self.screw_size)

    @property
    def capture_estimate_mm(self) -> float:
        """Lateral offset the lead-ins are sized for: clearance + key chamfer + hole chamfer."""
        return self.clearance_mm + self.key_chamfer_mm + self.hole_chamfer_mm

    def flange_screw_points(self) -> list[tuple[float, float]]:
        """(x, y) of the flanged key's four screws (:class:`CrossKey`, the pier deck's; key frame, before
        any turn)."""
        f = self.flange_size_mm / 2 - 4
        return [(x, y) for x in (-f, f) for y in (-f, f)]

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
    from cubot_cad.shapes import box

    return box(-L / 2, L / 2, -w / 2, w / 2, z0, z0 + h).fuse(box(-w / 2, w / 2, -L / 2, L / 2, z0, z0 + h))


def _cross_taper(w0: float, L0: float, z0: float, w1: float, L1: float, z1: float):
    """A cross whose arms taper from ``w0`` x ``L0`` at ``z0`` to ``w1`` x ``L1`` at ``z1`` (a chamfered
    edge of a cross: two rectangular frusta)."""
    from cubot_cad.shapes import frustum

    a = frustum((L0 / 2, w0 / 2), (L1 / 2, w1 / 2), z0, z1)
    b = frustum((w0 / 2, L0 / 2), (w1 / 2, L1 / 2), z0, z1)
    return a.fuse(b).clean()


@dataclass(frozen=True)
class CrossKey(Part):
    """Fixed cross key on a square flange (frame: z = 0 at the flange's top face, key below): the
    pier deck's key (:mod:`cubot_cad.piers.deck`), screwed under the deck, which turns as a whole. A
    robot's key turns on a shaft instead (:class:`cubot_cad.couplings.twist.TwistKey`, same head)."""

    spec: TopTwistSpec = TopTwistSpec()
    turned: bool = False
    name: ClassVar[str] = "cross_key"
    description: ClassVar[str] = "twist-and-lock: flanged cross key (the pier deck's), IR transmitter bore"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 180.0),)
    support: ClassVar[str] = "the cross head's arms overhang the stem by 10 mm (support under the arms)"

    def build(self):
        from cubot_cad.shapes import Z, box, cut_all, cyl, fuse_all, rotated

        s = self.spec
        f = s.flange_size_mm / 2
        zt = -s.key_protrusion_mm
        flange = box(-f, f, -f, f, -s.flange_mm, 0)
        stem = cyl(s.arm_width_mm / 2, s.key_protrusion_mm - s.flange_mm - s.head_mm + 0.01,
                   (0, 0, zt + s.head_mm - 0.005), Z)
        ch, w, L = s.key_chamfer_mm, s.arm_width_mm, s.arm_length_mm
        head = [_cross(w, L, zt + ch, s.head_mm - ch)]
        if ch > 0:  # the lead-in: the head's bottom edges chamfered 45 deg
            head.append(_cross_taper(w - 2 * ch, L - 2 * ch, zt, w, L, zt + ch + 0.001))
        k = fuse_all([flange, stem] + head)
        holes = [cyl(s.screw_hole_mm / 2, s.flange_mm + 0.2, (x, y, -s.flange_mm - 0.1), Z)
                 for x, y in s.flange_screw_points()]
        holes.append(cyl(s.ir_bore_mm / 2, s.key_protrusion_mm + 0.2, (0, 0, zt - 0.1), Z))  # IR transmitter
        k = cut_all(k, holes)
        return rotated(k, Z, -s.twist_deg) if self.turned else k  # clockwise seen from above


@dataclass(frozen=True)
class Cover(Part):
    """Top cover of the body with the cross-hole collar (frame: z = 0 at the wall tops)."""

    spec: TopTwistSpec = TopTwistSpec()
    length_mm: float = 100.0
    width_mm: float = 90.0
    #: Cover screws this far in from the cover's edges (over the body's corner bosses).
    screw_inset_mm: float = 5.0
    name: ClassVar[str] = "cover_cross_hole"
    description: ClassVar[str] = "twist-and-lock: body cover with the cross-shaped hole in a collar"
    support: ClassVar[str] = "the collar roof spans the 30 mm cavity round the cross hole (support inside the collar)"

    def validate(self) -> None:
        s = self.spec
        need(self.width_mm / 2 >= s.cavity_radius_mm + s.collar_wall_mm + 5,
             f"Cover.width_mm {self.width_mm:g} is too small for the collar")

    def build(self):
        from cubot_cad.shapes import Z, box, cut_all, cyl

        s = self.spec
        c = s.clearance_mm
        L, W, t = self.length_mm, self.width_mm, s.cover_mm
        plate = box(-L / 2, L / 2, -W / 2, W / 2, 0, t)
        R = s.cavity_radius_mm
        collar = cyl(R + s.collar_wall_mm, s.collar_mm + 0.01, (0, 0, t - 0.005), Z)
        body = plate.fuse(collar).clean()
        cav = cyl(R, t + s.roof_under_mm + 0.1, (0, 0, -0.1), Z)
        wh, Lh = s.arm_width_mm + 2 * c, s.arm_length_mm + 2 * c
        hole = [_cross(wh, Lh, t + s.roof_under_mm - 0.1, s.roof_mm + 0.2)]
        ch = s.hole_chamfer_mm
        if ch > 0:  # the lead-in: the cross hole's top edges chamfered 45 deg
            top = t + s.collar_mm
            hole.append(_cross_taper(wh, Lh, top - ch, wh + 2 * ch + 0.2, Lh + 2 * ch + 0.2, top + 0.1))
        screws = [cyl(s.screw_hole_mm / 2, t + 0.2, (x, y, -0.1), Z) for x, y in self.screw_points()]
        return cut_all(body, [cav] + hole + screws)

    def screw_points(self) -> list[tuple[float, float]]:
        """(x, y) of the four cover screws (cover frame = body frame centred on the body): over the
        body's corner bosses, ``screw_inset_mm`` in from the edges."""
        a, b = self.length_mm / 2 - self.screw_inset_mm, self.width_mm / 2 - self.screw_inset_mm
        return [(x, y) for x in (-a, a) for y in (-b, b)]


@dataclass(frozen=True)
class LockingKey(Part):
    """Locking key: drops into one arm of the cross hole after the twist and blocks the
    key head from turning back (frame = cover frame)."""

    spec: TopTwistSpec = TopTwistSpec()
    name: ClassVar[str] = "locking_key"
    description: ClassVar[str] = "twist-and-lock: locking key that stops the turned cross key"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 180.0),)

    def build(self):
        from cubot_cad.shapes import box

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

    The ball is held by an undercut: the mouth of the socket (a sphere of the ball's
    radius plus the clearance) is ``undercut_mm`` per side narrower than the ball, so the
    ball snaps in and cannot fall out. That fixes how far it can protrude: the mouth lies
    sqrt((R + c)^2 - (R - u)^2) below the ball's centre, so a 10 mm ball shows 2.78 mm
    (28 %, against the thesis's third, which would leave an undercut of 0.09 mm, below
    what FDM holds). The seat height follows from the wheels' exposed height so that
    wheels and casters touch flat ground together.
    """

    ball_diameter_mm: float = 10.0
    wheel_exposed_mm: float = 15.0
    outer_diameter_mm: float = 14.0
    #: Radial overlap of the mouth over the ball (per side): what retains the ball.
    undercut_mm: float = 0.3
    #: Fixed by one screw through the floor into an ISO 2306 tap hole this deep in the seat's top
    #: (0: no hole, the seat is glued).
    screw_size: str = "M3"
    screw_depth_mm: float = 3.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    name: ClassVar[str] = "caster_seat"
    description: ClassVar[str] = "ball-caster seat (snap-in socket, 0.3 mm undercut), screwed under the floor"
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 180.0),)

    #: Least undercut FDM can hold (per side): below it the mouth prints as wide as the ball.
    MIN_UNDERCUT_MM: ClassVar[float] = 0.3
    ZERO_OK: ClassVar[tuple[str, ...]] = ("screw_depth_mm",)

    def validate(self) -> None:
        need(at_least(self.undercut_mm, self.MIN_UNDERCUT_MM),
             f"CasterSeat.undercut_mm {self.undercut_mm:g} is below {self.MIN_UNDERCUT_MM:g} mm: the ball would not be held")
        need(at_least(self.exposed_mm, 0.1 * self.ball_diameter_mm),
             f"CasterSeat.undercut_mm {self.undercut_mm:g} leaves the {self.ball_diameter_mm:g} mm ball only "
             f"{self.exposed_mm:.2f} mm below the seat")
        need(at_least(self.outer_diameter_mm, self.ball_diameter_mm + 2 * self.clearance_mm + 2 * MIN_WALL_MM),
             f"outer_diameter_mm {self.outer_diameter_mm:g} leaves no wall around the "
             f"{self.ball_diameter_mm:g} mm ball")
        from cubot_cad.hardware.fasteners import thread

        thread(self.screw_size)
        top = self.ball_centre_z_mm + self.ball_diameter_mm / 2 + self.clearance_mm
        need(at_most(top, -MIN_WALL_MM),
             f"ball_diameter_mm {self.ball_diameter_mm:g} is too large for wheel_exposed_mm "
             f"{self.wheel_exposed_mm:g}: the socket would break through the floor")
        need(self.screw_depth_mm <= 0 or at_most(top, -self.screw_depth_mm - MIN_WALL_MM),
             f"CasterSeat.screw_depth_mm {self.screw_depth_mm:g}: the tap hole would come within {MIN_WALL_MM:g} mm "
             f"of the ball socket")

    @property
    def mouth_below_centre_mm(self) -> float:
        """Depth of the socket's mouth below the ball's centre (where the socket is R - u wide)."""
        R, c, u = self.ball_diameter_mm / 2, self.clearance_mm, self.undercut_mm
        return math.sqrt(max((R + c) ** 2 - (R - u) ** 2, 0.0))

    @property
    def mouth_radius_mm(self) -> float:
        return self.ball_diameter_mm / 2 - self.undercut_mm

    @property
    def exposed_mm(self) -> float:
        return self.ball_diameter_mm / 2 - self.mouth_below_centre_mm

    @property
    def exposed_fraction(self) -> float:
        return self.exposed_mm / self.ball_diameter_mm

    @property
    def seat_height_mm(self) -> float:
        return self.wheel_exposed_mm - self.exposed_mm

    @property
    def ball_centre_z_mm(self) -> float:
        return -self.wheel_exposed_mm + self.ball_diameter_mm / 2

    def build(self):
        from cubot_cad.shapes import Z, cyl, sphere

        boss = cyl(self.outer_diameter_mm / 2, self.seat_height_mm, (0, 0, -self.seat_height_mm), Z)
        sock = sphere(self.ball_diameter_mm / 2 + self.clearance_mm, (0, 0, self.ball_centre_z_mm))
        from cubot_cad.hardware.fasteners import tap_hole_mm

        seat = boss.cut(sock)
        if self.screw_depth_mm <= 0:
            return seat
        # the M3 screw from inside the robot, through the floor, cuts its own thread in this tap hole
        return seat.cut(cyl(tap_hole_mm(self.screw_size) / 2, self.screw_depth_mm, (0, 0, -self.screw_depth_mm), Z))
