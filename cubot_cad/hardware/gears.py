"""Spur gears as data (mm, g): the bought gear pairs that carry a latch servo's turn to a blade whose
axis the servo cannot sit on (:mod:`cubot_cad.couplings.latch_drive`), like :mod:`cubot_cad.hardware.fasteners` for
screws and :mod:`cubot_cad.hardware.servos` for servos.

Sources of the numbers:

* tooth proportions: ISO 53:1998 basic rack (addendum 1.00 m, dedendum 1.25 m), so the tip diameter
  is m (z + 2) and the root diameter m (z - 2.5); the module is a first-choice value of ISO 54:1996
  (0.5 mm); two equal gears mesh at the pitch diameter m z apart (1:1, no profile shift);
* material: acetal (POM) copolymer, density 1.41 g/cm^3 (Celanese Hostaform C 9021 datasheet,
  ISO 1183), the usual material of stock small-module gears;
* face width, bore and hub are the stock sizes ordered (a plain 5 mm bore opened to the blade's
  D-shaft with an M3 set screw in the hub; the servo's gear plain, drilled for the horn's screws).

The mass counts the body to the root circle, half the ring of teeth between root and tip, and the
hub, less the bore (teeth are about half solid at the pitch circle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cubot_cad.errors import InputError

#: POM copolymer density, g/mm^3 (source: module docstring).
POM_DENSITY_G_MM3 = 1.41e-3


@dataclass(frozen=True)
class SpurGear:
    """A stock spur gear (mm): ``module_mm``, ``teeth``, ``face_mm`` wide, ``bore_mm`` through it, a hub
    ``hub_diameter_mm`` x ``hub_mm`` on one side (``hub_mm`` 0: none)."""

    name: str
    module_mm: float
    teeth: int
    face_mm: float
    bore_mm: float
    hub_diameter_mm: float = 0.0
    hub_mm: float = 0.0
    material: str = "POM"

    @property
    def pitch_diameter_mm(self) -> float:
        return self.module_mm * self.teeth

    @property
    def tip_diameter_mm(self) -> float:
        return self.module_mm * (self.teeth + 2)

    @property
    def root_diameter_mm(self) -> float:
        return self.module_mm * (self.teeth - 2.5)

    @property
    def mass_g(self) -> float:
        rr, rt = self.root_diameter_mm / 2, self.tip_diameter_mm / 2
        body = math.pi * (rr * rr + 0.5 * (rt * rt - rr * rr)) * self.face_mm
        hub = math.pi * (self.hub_diameter_mm / 2) ** 2 * self.hub_mm
        bore = math.pi * (self.bore_mm / 2) ** 2 * (self.face_mm + self.hub_mm)
        return (body + hub - bore) * POM_DENSITY_G_MM3

    def describe(self, duty: str) -> str:
        hub = f", hub {self.hub_diameter_mm:g} x {self.hub_mm:g} mm" if self.hub_mm > 0 else ""
        return (f"spur gear module {self.module_mm:g}, {self.teeth} teeth ({self.pitch_diameter_mm:g} mm pitch, "
                f"{self.tip_diameter_mm:g} mm tip), {self.face_mm:g} mm face, {self.bore_mm:g} mm bore{hub}, "
                f"{self.material}: {duty}")


def mesh_centre_distance_mm(a: SpurGear, b: SpurGear) -> float:
    """Where two gears of one module mesh (the pitch circles touch); :class:`InputError` otherwise."""
    if abs(a.module_mm - b.module_mm) > 1e-12:
        raise InputError(f"gears {a.name!r} (module {a.module_mm:g}) and {b.name!r} (module {b.module_mm:g}) "
                         "do not mesh")
    return (a.pitch_diameter_mm + b.pitch_diameter_mm) / 2


#: Tooth counts of the stock module-0.5 pairs offered (smallest first): 20, 22, 24, 26 mm apart.
STOCK_TEETH = (40, 44, 48, 52)

#: Stock gears (source: module docstring): per tooth count a hubbed one (for a D-shaft) and a plain one.
GEARS: dict[str, SpurGear] = {
    **{f"M0.5 z{z} hub": SpurGear(f"M0.5 z{z} hub", 0.5, z, 4.0, 5.0, hub_diameter_mm=10.0, hub_mm=4.0)
       for z in STOCK_TEETH},
    **{f"M0.5 z{z}": SpurGear(f"M0.5 z{z}", 0.5, z, 4.0, 5.0) for z in STOCK_TEETH},
}

#: The 1:1 pairs (hubbed, plain) in order of size.
STOCK_PAIRS: tuple[tuple[str, str], ...] = tuple((f"M0.5 z{z} hub", f"M0.5 z{z}") for z in STOCK_TEETH)


def gear(name: str) -> SpurGear:
    """The table row ``name``; :class:`InputError` otherwise."""
    if name not in GEARS:
        raise InputError(f"gear {name!r} is not one of {', '.join(GEARS)}")
    return GEARS[name]
