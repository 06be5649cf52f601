"""Test platform (thesis Ch. 6.5.1): 100 x 100 x 5 mm ABS plate used in the deflection tests.

Coupling by a nut and bolt at a single point on the centre line: the front
tab (lower half of the plate) of one platform slides into the rear recess of
the next and one M3 bolt goes through both (lap joint, zero gap).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from cubot_cad.couplings import compliance as couplings
from cubot_cad.hardware.components import Component
from cubot_cad.part import (
    DEFAULT_CLEARANCE_MM,
    MIN_WALL_MM,
    Part,
    at_least,
    check_clearance,
    check_dims,
    need,
)
from cubot_cad.robots.base import Placed, Robot


@dataclass(frozen=True)
class PlatformPlate(Part):
    length_mm: float = 100.0
    width_mm: float = 100.0
    thickness_mm: float = 5.0
    tab_length_mm: float = 12.0
    tab_width_mm: float = 20.0
    bolt_mm: float = 3.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    name: ClassVar[str] = "test_platform"
    description: ClassVar[str] = "test platform: plate with front tab, rear recess and the M3 coupling holes"

    @property
    def bolt_size(self) -> str:
        """The ISO metric size of the bolt (``bolt_mm`` must be one of the fastener table's)."""
        return f"M{self.bolt_mm:g}"

    @property
    def bolt_hole_mm(self) -> float:
        """ISO 273 medium clearance hole for the bolt (from the fastener table)."""
        from cubot_cad.hardware.fasteners import clearance_hole_mm

        return clearance_hole_mm(self.bolt_size)

    def validate(self) -> None:
        from cubot_cad.hardware.fasteners import THREADS

        need(self.bolt_size in THREADS,
             f"PlatformPlate.bolt_mm {self.bolt_mm:g} is not a bolt of the fastener table ({', '.join(THREADS)})")
        c = self.clearance_mm
        need(at_least(self.thickness_mm / 2 - c, MIN_WALL_MM),
             f"thickness_mm {self.thickness_mm:g} leaves a lap joint half thinner than {MIN_WALL_MM:g} mm")
        need(at_least(self.tab_length_mm, self.bolt_hole_mm + 2 * MIN_WALL_MM + 2),
             f"tab_length_mm {self.tab_length_mm:g} is too short for the {self.bolt_mm:g} mm bolt hole")
        need(self.tab_width_mm <= self.width_mm - 4 * MIN_WALL_MM,
             f"tab_width_mm {self.tab_width_mm:g} must be narrower than width_mm {self.width_mm:g}")

    @property
    def half_mm(self) -> float:
        return self.thickness_mm / 2

    def build(self):
        from cubot_cad.shapes import Z, box, cut_all, cyl

        L, W, T, c = self.length_mm, self.width_mm, self.thickness_mm, self.clearance_mm
        tl, tw = self.tab_length_mm, self.tab_width_mm
        plate = box(-L / 2, L / 2, -W / 2, W / 2, 0, T)
        tab = box(L / 2 - 0.01, L / 2 + tl, -tw / 2, tw / 2, 0, self.half_mm)
        body = plate.fuse(tab).clean()
        recess = box(-L / 2 - 1, -L / 2 + tl + c, -tw / 2 - c, tw / 2 + c, -1, self.half_mm + c)
        r = self.bolt_hole_mm / 2
        holes = [cyl(r, T + 2, (L / 2 + tl / 2, 0, -1), Z), cyl(r, T + 2, (-L / 2 + tl / 2, 0, -1), Z)]
        return cut_all(body, [recess] + holes)


@dataclass(frozen=True)
class TestPlatform(Robot):
    __test__ = False  # not a pytest class

    length_mm: float = 100.0
    width_mm: float = 100.0
    thickness_mm: float = 5.0
    tab_length_mm: float = 12.0
    tab_width_mm: float = 20.0
    bolt_mm: float = 3.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM

    name: ClassVar[str] = "platform"
    title: ClassVar[str] = "test platform"

    def __post_init__(self) -> None:
        check_clearance(self.clearance_mm, "clearance_mm")
        check_dims(self, ("length_mm", "width_mm", "thickness_mm", "tab_length_mm", "tab_width_mm", "bolt_mm"))
        _ = self.plate  # validates the plate dimensions

    @property
    def plate(self) -> PlatformPlate:
        return PlatformPlate(length_mm=self.length_mm, width_mm=self.width_mm, thickness_mm=self.thickness_mm,
                             tab_length_mm=self.tab_length_mm, tab_width_mm=self.tab_width_mm,
                             bolt_mm=self.bolt_mm, clearance_mm=self.clearance_mm)

    @property
    def envelope_mm(self):
        return (self.length_mm, self.width_mm, self.thickness_mm)

    @property
    def coupling_zones_mm(self) -> tuple[tuple[float, float], ...]:
        """The lap joint's own material (robot frame, mm): the rear recess (to its end wall) and
        the front tab. Its FE (:mod:`structure_fem.couplings.platform_bolt_fe`) counts both as the
        joint's compliance beyond a continuous plate, so the body's bending section
        (:mod:`cubot_cad.checks.section`) leaves them out: the body is the 5 mm plate the FE's
        reference plate is."""
        L, tl, c = self.length_mm, self.tab_length_mm, self.clearance_mm
        return ((-L / 2, -L / 2 + tl + c), (L / 2, L / 2 + tl))

    @property
    def wheel_exposed_mm(self) -> float:  # no wheels: the plate itself is the step it can climb
        return self.thickness_mm

    def build_placed(self) -> list[Placed]:
        from cubot_cad.shapes import location

        return [Placed(self.plate, location(), "body")]

    def components(self) -> list[Component]:
        x = self.length_mm / 2 + self.tab_length_mm / 2
        return [Component("bolt_nut", f"{self.plate.bolt_size} x 10 ISO 4762 bolt with ISO 4032 nut (one per coupling)", 1.5,
                          ((x, 0.0, self.thickness_mm / 2),), (self.plate.bolt_mm, 10.0), "cyl_z", "hardware",
                          (0.6, 0.6, 0.6))]

    def fasteners(self) -> list:
        from cubot_cad.hardware.fasteners import bolted

        return bolted(self.name, self.plate.bolt_size, self.thickness_mm, 1, "lap joint to the next platform", nut=True)

    def connector_properties(self, youngs_modulus_pa: float, gaps_mm: dict | None = None) -> tuple:
        return (couplings.bolt(self.tab_width_mm, self.thickness_mm / 2, self.tab_length_mm, self.bolt_mm,
                               self.clearance_mm, youngs_modulus_pa, self.thickness_mm / 2),)
