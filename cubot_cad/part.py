"""The `Part` base class and the shared print settings (all lengths in millimetres).

A part is a frozen dataclass whose fields are its named dimensions (``*_mm``,
``*_deg``) with defaults; ``__post_init__`` validates them and raises
:class:`~cubot_cad.errors.InputError` naming the bad parameter. The solid is
built lazily (OCC is slow) in the part's *mounting frame* (where the robot
places it) and cached; :meth:`Part.printable` returns it turned flat for
printing (largest planar face on the bed, ``z >= 0``).

Derived facts every part exposes: ``volume_mm3``, ``bbox_mm``, ``com_mm``,
``inertia_mm5`` (inertia / density about the COM), and ``mates``: named
mating points with an outward normal, in the mounting frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import cached_property
from typing import Any, ClassVar

from .errors import InputError

#: Default printing assumptions: one clearance for every mating pair (per
#: side: a hole is ``pin + 2 * clearance``), nozzle width (thinnest wall is two
#: nozzle widths), and the bed (Prusa MK3-class, 250 x 210 x 210 mm).
DEFAULT_CLEARANCE_MM = 0.2
NOZZLE_MM = 0.4
MIN_WALL_MM = 2 * NOZZLE_MM
BED_MM = (250.0, 210.0, 210.0)

#: The range of print clearance (per side) every robot is built and docked with.
#:
#: Minimum 0.1 mm: common FDM fit tables put the tightest fit that still assembles
#: (a press/tight fit) at about 0.05-0.15 mm per side, because a well-tuned FDM
#: printer holds about +-0.1..0.2 mm and holes print undersize (general FDM
#: practice, not a measurement of ours; a maker with a calibrated printer can
#: measure a test coupling and choose within the range).
#: Below it the parts would not go together, and the CAD model cannot show it
#: either: at 0 the pins' and holes' coincident walls tessellate into each other
#: (CuBot front-rear docked 5 mm short with 12 mm^3 of interference).
MIN_CLEARANCE_MM = 0.1
#: Maximum 0.5 mm: the loose end of the same FDM tables (0.3-0.5 mm per side),
#: and as far as the thesis's connector dimensions go (1 mm, advertised before,
#: cannot be built with them). Just above it: OctBot's fingers travel 2.5 mm,
#: exactly the 2 mm hook overlap plus 0.5 mm, so they no longer clear the ring's
#: lip; from 0.55 mm the latch blade's arc slots (pin groove + 2 clearances wide)
#: leave less than two nozzle widths to the blade's edge (16 mm blade, 7 mm pin
#: circle); adjacent Cube Robot blocks collide above 0.8 mm; at 0.8 mm the slot is
#: as wide as the 5 mm pin, so the blade would hold nothing; and the widened
#: dovetail groove reaches the rail's IR holes from about 0.87 mm (24 mm rail).
MAX_CLEARANCE_MM = 0.5
#: Comparisons of derived lengths (sums of mm values) use this tolerance, so that
#: a limit met exactly (3 - 1.8 - 0.4 = 0.7999999999999998 against 0.8) passes.
#: 1e-6 mm is far below any printable feature and far above float rounding.
LENGTH_TOL_MM = 1e-6

#: Print settings every part shares (0.4 mm nozzle): layer height, perimeters, top/bottom layers.
PRINT_DEFAULTS = {"nozzle_mm": NOZZLE_MM, "layer_mm": 0.2, "perimeters": 3, "top_bottom_layers": 5}

#: Printing materials: density in kg/m^3 and Young's modulus in Pa (typical FDM values).
MATERIALS: dict[str, dict[str, float]] = {
    "abs": {"density_kg_m3": 1040.0, "youngs_modulus_pa": 2.2e9},
    "pla": {"density_kg_m3": 1240.0, "youngs_modulus_pa": 3.5e9},
}


def material(name: str) -> dict[str, float]:
    """The material record for ``name`` (``abs`` or ``pla``); :class:`InputError` otherwise."""
    key = str(name).lower()
    if key not in MATERIALS:
        raise InputError(f"--material {name!r} is not one of {', '.join(MATERIALS)}")
    return MATERIALS[key]


def clearance_range_text() -> str:
    """The advertised clearance range, as CLI help and error messages print it."""
    return f"{MIN_CLEARANCE_MM:g}-{MAX_CLEARANCE_MM:g} mm"


def check_clearance(clearance_mm: float, where: str = "clearance_mm") -> float:
    """Validate the print clearance per side: ``MIN_CLEARANCE_MM <= c <= MAX_CLEARANCE_MM``
    (within :data:`LENGTH_TOL_MM`); :class:`InputError` naming ``where`` and the value otherwise."""
    if not isinstance(clearance_mm, (int, float)) or isinstance(clearance_mm, bool) \
            or not math.isfinite(clearance_mm):
        raise InputError(f"{where} must be a number, got {clearance_mm!r}")
    if clearance_mm < MIN_CLEARANCE_MM - LENGTH_TOL_MM:
        raise InputError(f"{where} {clearance_mm:g} mm is below the printable minimum {MIN_CLEARANCE_MM:g} mm "
                         f"per side (FDM parts need a clearance to go together; range {clearance_range_text()})")
    if clearance_mm > MAX_CLEARANCE_MM + LENGTH_TOL_MM:
        raise InputError(f"{where} {clearance_mm:g} mm is above the maximum {MAX_CLEARANCE_MM:g} mm per side "
                         f"(the thesis's connectors cannot be built looser: OctBot's fingers would not clear "
                         f"the ring's lip, the latch blade's slots would break its edge; "
                         f"range {clearance_range_text()})")
    return float(clearance_mm)


def at_least(value: float, limit: float) -> bool:
    """``value >= limit`` for derived lengths, within :data:`LENGTH_TOL_MM`."""
    return value >= limit - LENGTH_TOL_MM


def at_most(value: float, limit: float) -> bool:
    """``value <= limit`` for derived lengths, within :data:`LENGTH_TOL_MM`."""
    return value <= limit + LENGTH_TOL_MM


def is_length(value, zero_ok: bool = False) -> bool:
    """``value`` is a finite number (not a bool) > 0, or >= 0 with ``zero_ok``."""
    return (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
            and (value >= 0 if zero_ok else value > 0))


def check_lengths(obj, positive: tuple[str, ...] = (), zero_ok: tuple[str, ...] = (), prefix: str = "") -> None:
    """The one length check every part and spec shares: each field in ``positive`` is a length > 0 mm,
    each in ``zero_ok`` a length >= 0 mm (0 = the feature left out); :class:`InputError` naming the field
    (``prefix`` + name) and the value otherwise."""
    for n in positive:
        v = getattr(obj, n)
        if not is_length(v):
            raise InputError(f"{prefix}{n} must be a positive length in mm, got {v!r}")
    for n in zero_ok:
        v = getattr(obj, n)
        if not is_length(v, zero_ok=True):
            raise InputError(f"{prefix}{n} must be a length >= 0 mm (0 = left out), got {v!r}")


def need(cond: bool, message: str) -> None:
    """Raise :class:`InputError` with ``message`` unless ``cond``."""
    if not cond:
        raise InputError(message)


@dataclass(frozen=True)
class Mate:
    """A mating feature: a point and an outward unit normal (mm, mounting frame)."""

    point: tuple[float, float, float]
    normal: tuple[float, float, float]


@dataclass(frozen=True)
class Part:
    """Base class: subclasses add dimension fields and implement :meth:`build`."""

    clearance_mm: float = DEFAULT_CLEARANCE_MM

    #: File stem of the exported part and how many a robot needs.
    name: ClassVar[str] = "part"
    description: ClassVar[str] = ""
    #: Rotations (axis, degrees) applied in order to lay the part flat for printing.
    print_rotation: ClassVar[tuple[tuple[tuple[float, float, float], float], ...]] = ()
    #: Print settings recorded per part in the manifest (:meth:`print_settings`): infill, and why the
    #: part needs supports as oriented ("" = it prints without).
    infill_percent: ClassVar[int] = 25
    support: ClassVar[str] = ""
    #: How ``print_rotation`` lays the part on the bed and why, recorded in the manifest ("" = its
    #: largest flat face down, the default choice).
    print_orientation: ClassVar[str] = ""
    #: ``*_mm`` fields that may be 0 (a feature left out), not only positive.
    ZERO_OK: ClassVar[tuple[str, ...]] = ()

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, f"{type(self).__name__}.clearance_mm")
        lengths = [f.name for f in fields(self) if f.name.endswith("_mm") and f.name != "clearance_mm"]
        check_lengths(self, tuple(n for n in lengths if n not in self.ZERO_OK),
                      tuple(n for n in lengths if n in self.ZERO_OK), f"{type(self).__name__}.")
        self.validate()

    # -- subclass API -----------------------------------------------------
    def validate(self) -> None:
        """Extra checks of impossible combinations (raise InputError naming the parameter)."""

    def build(self) -> Any:  # -> cq.Workplane | cq.Shape
        raise NotImplementedError

    @property
    def mates(self) -> dict[str, Mate]:
        return {}

    # -- derived facts ----------------------------------------------------
    def wall_check(self, pname: str, value: float) -> None:
        """A wall (``pname`` = ``value`` mm) must be at least two nozzle widths thick."""
        need(at_least(value, MIN_WALL_MM),
             f"{type(self).__name__}.{pname} = {value:g} mm is thinner than two nozzle widths ({MIN_WALL_MM:g} mm)")

    @cached_property
    def solid(self):
        """The part's single solid (cq.Shape) in its mounting frame, mm."""
        import cadquery as cq

        obj = self.build()
        shape = obj.val() if isinstance(obj, cq.Workplane) else obj
        if isinstance(obj, cq.Workplane) and len(obj.vals()) > 1:
            shape = cq.Compound.makeCompound(obj.vals())
        solids = shape.Solids()
        if len(solids) != 1:
            raise RuntimeError(f"{self.name}: geometry has {len(solids)} solids, expected one")
        return solids[0].clean()

    @cached_property
    def volume_mm3(self) -> float:
        return float(self.solid.Volume())

    @cached_property
    def bbox_mm(self) -> tuple[float, float, float, float, float, float]:
        from .shapes import tight_bbox

        return tight_bbox(self.solid)

    @property
    def size_mm(self) -> tuple[float, float, float]:
        b = self.bbox_mm
        return (b[3] - b[0], b[4] - b[1], b[5] - b[2])

    @cached_property
    def com_mm(self) -> tuple[float, float, float]:
        import cadquery as cq

        c = cq.Shape.centerOfMass(self.solid)
        return (c.x, c.y, c.z)

    @cached_property
    def inertia_mm5(self):
        """Inertia tensor / density about the COM (mm^5), as a 3x3 list."""
        import cadquery as cq

        return cq.Shape.matrixOfInertia(self.solid)

    @cached_property
    def printable(self):
        """The solid laid flat for printing: rotated per ``print_rotation``, centred on xy, min z = 0."""
        import cadquery as cq

        s = self.solid
        for axis, deg in self.print_rotation:
            s = s.rotate(cq.Vector(0, 0, 0), cq.Vector(*axis), deg)
        from .shapes import tight_bbox

        x0, y0, z0, x1, y1, _ = tight_bbox(s)
        return s.translate(cq.Vector(-(x0 + x1) / 2, -(y0 + y1) / 2, -z0))

    def print_settings(self) -> dict:
        """Per-part print settings for the manifest (the shared ones: :data:`PRINT_DEFAULTS`)."""
        return {**PRINT_DEFAULTS, "infill_percent": self.infill_percent, "supports": bool(self.support),
                "support_reason": self.support or None,
                "orientation": self.print_orientation or "largest flat face on the bed",
                "print_rotation": [{"axis": list(axis), "deg": deg} for axis, deg in self.print_rotation]}

    def params(self) -> dict[str, float]:
        """The part's named dimensions."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


def check_dims(obj, names: tuple[str, ...]) -> None:
    for n in names:
        v = getattr(obj, n)
        need(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0,
             f"{type(obj).__name__}.{n} must be a positive length in mm, got {v!r}")
