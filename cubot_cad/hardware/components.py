"""Non-printed components (motors, wheels, battery, boards, fasteners).

Each robot lists its bought components with an *assumed* mass and position
(robot frame, mm; see docs/cubot_cad.md for the table and the reasoning). A
component is modelled as a homogeneous box, a cylinder along y (wheels,
motors) or a sphere (caster balls) for its inertia, and as a simple solid
stand-in in the STEP assembly. Wheels and caster balls are also used to land
a robot on another one (top-down docking) and to measure exposed heights.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cubot_cad.errors import InputError


@dataclass(frozen=True)
class Component:
    """``count`` identical items, one per entry of ``positions_mm``.

    ``kind``: ``box`` (size = x, y, z), ``cyl_x`` / ``cyl_y`` (size = diameter, width along x / y), ``cyl_z``
    (size = diameter, length along z), ``sphere`` (size = diameter). Masses in grams.

    ``lump``: a mass spread through the robot (screws, wires), modelled as a homogeneous box for the
    mass properties only: it has no stand-in solid (:meth:`solids` is empty), so it is neither drawn
    nor checked for room (every other component's stand-in must overlap nothing).
    """

    key: str
    description: str
    unit_mass_g: float
    positions_mm: tuple[tuple[float, float, float], ...]
    size_mm: tuple[float, ...]
    kind: str = "box"
    role: str = "electronics"
    colour: tuple[float, float, float] = (0.2, 0.4, 0.8)
    lump: bool = False

    def __post_init__(self) -> None:
        if not (self.unit_mass_g > 0):
            raise InputError(f"component {self.key}: unit_mass_g must be > 0, got {self.unit_mass_g}")
        if self.kind not in ("box", "cyl_x", "cyl_y", "cyl_z", "sphere"):
            raise InputError(f"component {self.key}: unknown kind {self.kind!r}")
        if not self.positions_mm:
            raise InputError(f"component {self.key}: no positions")

    @property
    def count(self) -> int:
        return len(self.positions_mm)

    @property
    def ground_contact(self) -> bool:
        return self.role in ("wheel", "caster")

    def _own_inertia(self, m: float) -> np.ndarray:
        s = np.array(self.size_mm, dtype=float) * 1e-3
        if self.kind == "box":
            a, b, c = s
            return m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
        if self.kind in ("cyl_x", "cyl_y", "cyl_z"):
            r, h = s[0] / 2, s[1]
            i_perp = m * (3 * r * r + h * h) / 12
            if self.kind == "cyl_z":
                return np.diag([i_perp, i_perp, m * r * r / 2])
            if self.kind == "cyl_x":
                return np.diag([m * r * r / 2, i_perp, i_perp])
            return np.diag([i_perp, m * r * r / 2, i_perp])
        r = s[0] / 2
        return np.eye(3) * (2 / 5) * m * r * r

    def mass_items(self):
        """(mass kg, com m, inertia kg m^2 about own com) per item."""
        m = self.unit_mass_g * 1e-3
        return [(m, np.array(p, dtype=float) * 1e-3, self._own_inertia(m)) for p in self.positions_mm]

    def solids(self):
        """Stand-in solids (mm) for assemblies, renders and ground contact (none for a ``lump``)."""
        from cubot_cad.shapes import X, Y, Z, box, cyl, sphere

        out = []
        if self.lump:
            return out
        for x, y, z in self.positions_mm:
            if self.kind == "box":
                a, b, c = self.size_mm
                out.append(box(x - a / 2, x + a / 2, y - b / 2, y + b / 2, z - c / 2, z + c / 2))
            elif self.kind == "cyl_x":
                d, w = self.size_mm[:2]
                out.append(cyl(d / 2, w, (x - w / 2, y, z), X))
            elif self.kind == "cyl_y":
                d, w = self.size_mm[:2]
                out.append(cyl(d / 2, w, (x, y - w / 2, z), Y))
            elif self.kind == "cyl_z":
                d, h = self.size_mm[:2]
                out.append(cyl(d / 2, h, (x, y, z - h / 2), Z))
            else:
                out.append(sphere(self.size_mm[0] / 2, (x, y, z)))
        return out


def component_table(components: list[Component]) -> list[dict]:
    """Rows for the manifest and the docs: what, how many, assumed mass, where."""
    return [{"component": c.key, "description": c.description, "count": c.count,
             "unit_mass_g": c.unit_mass_g, "total_mass_g": round(c.unit_mass_g * c.count, 3),
             "positions_mm": [list(p) for p in c.positions_mm], "model": c.kind, "size_mm": list(c.size_mm)}
            for c in components]
