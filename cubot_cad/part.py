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


def check_clearance(clearance_mm: float, where: str = "clearance_mm") -> float:
    """Validate the print clearance (0 <= c <= 1 mm)."""
    if not isinstance(clearance_mm, (int, float)) or not math.isfinite(clearance_mm):
        raise InputError(f"{where} must be a number, got {clearance_mm!r}")
    if clearance_mm < 0:
        raise InputError(f"{where} must be >= 0 mm, got {clearance_mm}")
    if clearance_mm > 1.0:
        raise InputError(f"{where} {clearance_mm} mm is larger than any FDM printer needs (max 1 mm)")
    return float(clearance_mm)


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

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, f"{type(self).__name__}.clearance_mm")
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name.endswith("_mm") and f.name != "clearance_mm":
                if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v) or v <= 0:
                    raise InputError(f"{type(self).__name__}.{f.name} must be a positive length in mm, got {v!r}")
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
        need(value >= MIN_WALL_MM - 1e-9,
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

    def params(self) -> dict[str, float]:
        """The part's named dimensions."""
        return {f.name: getattr(self, f.name) for f in fields(self)}
