"""`Robot`: a parametric robot = placed printable parts + non-printed components.

Robot frame (mm here, SI in the exported record): x forward (front connector
side), y left, z up; origin at the centre of the footprint on the underside.

Mass properties combine the printed parts (OCC volume, centre of mass and
inertia of every placed solid at the chosen material density) with the
robot's table of non-printed components (:mod:`cubot_cad.hardware.components`), each a
box, cylinder or sphere of assumed mass at an assumed position.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass
from functools import cached_property
from typing import ClassVar

import numpy as np

from cubot_cad.errors import InputError
from cubot_cad.hardware.components import Component
from cubot_cad.part import Part, material

#: Colour (rgb 0-1) of the printed parts by :attr:`Placed.role` (a ``_side`` suffix is ignored), so
#: the connectors stand out from the grey body in the STEP assemblies and GLB models.
ROLE_COLOURS: dict[str, tuple[float, float, float]] = {
    "body": (0.85, 0.85, 0.80), "structure": (0.85, 0.85, 0.80), "cover": (0.72, 0.76, 0.82),
    "pin": (0.95, 0.42, 0.08), "pinset": (0.98, 0.68, 0.30),
    "blade": (0.10, 0.40, 0.85), "latchset": (0.45, 0.65, 0.95),
    "rail": (0.20, 0.65, 0.35), "cross_key": (0.60, 0.30, 0.75), "locking_key": (0.85, 0.30, 0.60),
    "key_bearing": (0.40, 0.20, 0.55),
    "caster_seat": (0.55, 0.55, 0.50),
    "ring": (0.95, 0.42, 0.08), "housing": (0.10, 0.40, 0.85), "finger": (0.90, 0.75, 0.10),
}


def role_colour(role: str) -> tuple[float, float, float]:
    return ROLE_COLOURS.get(role.removesuffix("_side"), ROLE_COLOURS["body"])


@dataclass(frozen=True)
class Placed:
    """A printable part placed in the robot frame; ``role`` tags it for docking."""

    part: Part
    loc: object  # cq.Location
    role: str = "structure"

    @cached_property
    def shape(self):
        return self.part.solid.moved(self.loc)


@dataclass(frozen=True)
class MassProperties:
    """Whole-robot mass properties (SI): kg, m (robot frame), kg m^2 about the COM."""

    mass_kg: float
    printed_mass_kg: float
    com_m: tuple[float, float, float]
    inertia_kg_m2: tuple[float, float, float, float, float, float]


def _shape_inertia(shape, density_kg_m3: float):
    """(mass kg, com m (3,), inertia about com kg m^2 (3x3)) of an OCC solid in mm."""
    import cadquery as cq

    vol_m3 = shape.Volume() * 1e-9
    m = vol_m3 * density_kg_m3
    c = cq.Shape.centerOfMass(shape)
    J = np.array(cq.Shape.matrixOfInertia(shape)) * 1e-15 * density_kg_m3  # mm^5 -> m^5
    return m, np.array([c.x, c.y, c.z]) * 1e-3, J


def combine(items) -> tuple[float, np.ndarray, np.ndarray]:
    """Combine (mass, com, inertia-about-own-com) triples by the parallel-axis theorem."""
    M = sum(m for m, _, _ in items)
    com = sum(m * c for m, c, _ in items) / M
    J = np.zeros((3, 3))
    for m, c, Ji in items:
        d = c - com
        J += Ji + m * (np.dot(d, d) * np.eye(3) - np.outer(d, d))
    return M, com, J


class Robot:
    """Base class of the robot models. Subclasses are frozen dataclasses of named
    dimensions and implement :meth:`build_placed` and :meth:`components`."""

    name: ClassVar[str] = "robot"
    title: ClassVar[str] = ""

    # -- subclass API ---------------------------------------------------------
    def build_placed(self) -> list[Placed]:
        raise NotImplementedError

    def components(self) -> list[Component]:
        return []

    def drive_parts(self) -> list[tuple[str, str, str, int]]:
        """Bought drive parts that are not in the mass table: (item, description, size, count)."""
        return []

    def hardware(self, placed: list | None = None) -> list:
        """Stand-ins of bought drive hardware that is neither a printed part nor a component (screws,
        horns: :class:`~cubot_cad.couplings.twist.Hardware`, robot frame) for the parts as ``placed``."""
        return []

    def fasteners(self) -> list:
        """Bought screws, nuts and inserts (:class:`~cubot_cad.hardware.fasteners.FastenerUse`), sized from the
        fastener table and the thickness each one clamps."""
        return []

    @property
    def envelope_mm(self) -> tuple[float, float, float]:
        raise NotImplementedError

    def connector_properties(self, youngs_modulus_pa: float) -> tuple:
        raise NotImplementedError

    # -- derived ----------------------------------------------------------------
    @cached_property
    def placed(self) -> list[Placed]:
        return self.build_placed()

    def printable_parts(self) -> list[tuple[Part, int]]:
        """Distinct printable parts and how many of each the robot needs."""
        counts: OrderedDict[Part, int] = OrderedDict()
        for p in self.placed:
            counts[p.part] = counts.get(p.part, 0) + 1
        return list(counts.items())

    def shapes(self, roles: tuple[str, ...] | None = None) -> list:
        return [p.shape for p in self.placed if roles is None or p.role in roles]

    def component_solids(self, ground_only: bool = False) -> list:
        out = []
        for comp in self.components():
            if ground_only and not comp.ground_contact:
                continue
            out += comp.solids()
        return out

    def bbox_mm(self, include_components: bool = False):
        """Bounding box of the placed printed parts (and stand-ins) in the robot frame."""
        import cadquery as cq

        shapes = self.shapes() + (self.component_solids() if include_components else [])
        from cubot_cad.shapes import tight_bbox

        return tight_bbox(cq.Compound.makeCompound(shapes))

    @cached_property
    def wheel_exposed_mm(self) -> float:
        """How far the drive wheels reach below the underside (z = 0), measured on the wheel solids."""
        wheels = [s for c in self.components() if c.role == "wheel" for s in c.solids()]
        if not wheels:
            return 0.0
        from cubot_cad.shapes import tight_bbox

        return -min(tight_bbox(s)[2] for s in wheels)

    @cached_property
    def caster_exposed_mm(self) -> float:
        """How far the caster balls protrude below their seats, measured on the solids."""
        balls = [s for c in self.components() if c.role == "caster" for s in c.solids()]
        seats = [p.shape for p in self.placed if p.role == "caster_seat"]
        if not balls or not seats:
            return 0.0
        from cubot_cad.shapes import tight_bbox

        return min(tight_bbox(s)[2] for s in seats) - min(tight_bbox(b)[2] for b in balls)

    def mass_properties(self, material_name: str = "abs", printed_fraction: dict | None = None) -> MassProperties:
        """Mass, COM and inertia of the printed parts (the solid model at the material's density)
        plus the component table. ``printed_fraction``: part name -> printed / solid mass (the
        slicer's grams at the part's print settings over the solid model's, :func:`printed_fractions`);
        each such part's density is scaled by it (its mass distributed as the solid's: an
        assumption, the shell of a print is denser than its infill)."""
        rho = material(material_name)["density_kg_m3"]
        frac = printed_fraction or {}
        for name, f in frac.items():
            if not (isinstance(f, (int, float)) and math.isfinite(f) and 0 < f <= 1.5):
                raise InputError(f"printed_fraction[{name!r}] = {f!r} must be a number in (0, 1.5]")
        printed = [_shape_inertia(p.shape, rho * frac.get(p.part.name, 1.0)) for p in self.placed]
        others = [item for comp in self.components() for item in comp.mass_items()]
        mp, _, _ = combine(printed)
        M, com, J = combine(printed + others)
        return MassProperties(
            mass_kg=float(M), printed_mass_kg=float(mp), com_m=tuple(float(v) for v in com),
            inertia_kg_m2=(float(J[0, 0]), float(J[1, 1]), float(J[2, 2]),
                           float(J[0, 1]), float(J[0, 2]), float(J[1, 2])))

    def robot_properties(self, material_name: str = "abs", source: str = "cubot_cad",
                         printed_fraction: dict | None = None):
        from cubot_cad.properties import RobotProperties

        mat = material(material_name)
        mp = self.mass_properties(material_name, printed_fraction)
        L, W, H = self.envelope_mm
        return RobotProperties(
            name=self.name, length_m=L / 1000, width_m=W / 1000, height_m=H / 1000,
            mass_kg=mp.mass_kg, com_m=mp.com_m, inertia_kg_m2=mp.inertia_kg_m2,
            wheel_exposed_height_m=self.wheel_exposed_mm / 1000,
            caster_exposed_height_m=self.caster_exposed_mm / 1000,
            material=material_name.upper(), density_kg_m3=mat["density_kg_m3"],
            youngs_modulus_pa=mat["youngs_modulus_pa"],
            connectors=tuple(self.connector_properties(mat["youngs_modulus_pa"])),
            source=source)

    def assembly(self, include_components: bool = True, name: str | None = None, placed: list | None = None,
                 fresh: bool = False):
        """A cq.Assembly of the robot: printed parts coloured by role (:data:`ROLE_COLOURS`: body
        grey, pins orange, latches blue, rails green, keys purple, ...), stand-ins in their own colours.

        ``placed`` replaces :attr:`placed` (e.g. ``build_placed(blades_locked=True)``); ``fresh``
        copies every solid without its triangulation, so a mesh written from the assembly (GLB)
        is made at the writer's tolerance and not at whatever finer one the shapes already carry."""
        import cadquery as cq

        assy = cq.Assembly(name=name or self.name)
        seen: dict[str, int] = {}
        copies: dict = {}  # one copy per distinct part: its instances share one mesh
        for p in (self.placed if placed is None else placed):
            k = seen[p.part.name] = seen.get(p.part.name, 0) + 1
            solid = p.part.solid
            if fresh:
                solid = copies[p.part] if p.part in copies else copies.setdefault(p.part, solid.copy(False))
            assy.add(solid, name=f"{p.part.name}_{k}", loc=p.loc, color=cq.Color(*role_colour(p.role)))
        if include_components:
            for comp in self.components():
                for i, s in enumerate(comp.solids()):
                    assy.add(s, name=f"{comp.key}_{i + 1}", color=cq.Color(*comp.colour))
            for h in self.hardware(self.placed if placed is None else placed):
                assy.add(h.shape, name=h.label, color=cq.Color(*h.colour))
        return assy
