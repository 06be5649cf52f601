"""Where a robot stands on a ledge or a pier: its wheel and caster contacts (SI, robot frame).

The ledge and pier supports of the planar model (:mod:`structure_fem.model.structures`) sit where the
robot touches the ground. The robot properties record says where
(``RobotProperties.ground_contacts``, derived by `cubot_cad` from the wheel and caster positions
of the robot's component table, with ``ground_contacts_source``). For a record without them
(written before they existed) :func:`ground_support` falls back, in this order:

1. **the parametric robot of the same name** (``cubot``, ``octbot``, ``cube-robot``) at its
   default dimensions, accepted only if it reproduces the record's length and exposed wheel
   height (the lowest contact is ``-wheel_exposed_height_m`` below the underside); its source
   says that the contacts are the class defaults, not read from the record;
2. **the body's bottom corners** (``x = +-length_m / 2``, on the underside): a robot without
   wheels that lies flat (the test platform), or a record no parametric robot reproduces.

:class:`GroundSupport` says which was used (``kind``: ``"contacts"`` or ``"corners"``) and why
(``source``); the studies report it with their inputs.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from cubot_cad.properties import GroundContact, RobotProperties, ground_contacts_from_components

#: Parametric robot classes by record name (module, class) for records without contacts.
_CLASSES = {"cubot": ("cubot_cad.robots.cubot", "CuBot"), "octbot": ("cubot_cad.robots.octbot", "OctBot"),
            "cube-robot": ("cubot_cad.robots.cube_robot", "CubeRobot")}


@dataclass(frozen=True)
class GroundSupport:
    """The points a robot rests on (robot frame: x from the footprint centre, z below the
    underside, m), ``kind`` ``"contacts"`` (wheels / casters) or ``"corners"`` (its flat
    underside's ends), and where they come from."""

    kind: str
    points: tuple[tuple[float, float], ...]
    source: str

    @property
    def front_x_m(self) -> float:
        return max(x for x, _ in self.points)

    def setback_m(self, length_m: float) -> float:
        """How far the front-most point is behind the front face (m)."""
        return length_m / 2 - self.front_x_m


def corners(robot: RobotProperties, why: str) -> GroundSupport:
    L = robot.length_m
    return GroundSupport("corners", ((-L / 2, 0.0), (L / 2, 0.0)), f"body bottom corners ({why})")


def _from_record(contacts: tuple[GroundContact, ...], source: str) -> GroundSupport:
    return GroundSupport("contacts", tuple((c.x_m, c.z_m) for c in contacts), source)


@lru_cache(maxsize=64)
def _fallback(name: str, length_m: float, wheel_exposed_m: float) -> tuple[tuple[GroundContact, ...], str]:
    """Contacts of the parametric robot ``name`` at its defaults, or ``((), why not)``."""
    if name not in _CLASSES:
        return (), "the record has no ground_contacts and no parametric robot is named " + repr(name)
    import importlib

    mod, cls = _CLASSES[name]
    try:
        robot = getattr(importlib.import_module(mod), cls)()
    except Exception as exc:  # noqa: BLE001 - the CAD package cannot build its default: stay on corners
        return (), f"the record has no ground_contacts and the default {cls} cannot be built ({exc})"
    L = robot.envelope_mm[0]
    contacts = ground_contacts_from_components(robot.components(), L)
    if not contacts:
        return (), f"the record has no ground_contacts and the default {cls} has no wheels or casters"
    low = -min(c.z_m for c in contacts)
    if abs(L / 1e3 - length_m) > 1e-6 or abs(low - wheel_exposed_m) > 1e-4:
        return (), (f"the record has no ground_contacts and is not the default {cls} (length {length_m:g} m vs "
                    f"{L / 1e3:g}, wheel height {wheel_exposed_m:g} m vs {low:g})")
    what = ", ".join(f"{c.count} {c.feature}(s) at x = {c.x_m * 1e3:g} mm" for c in contacts)
    return contacts, (f"default parametric {cls} (cubot_cad component table: {what}): the record predates "
                      "ground_contacts; its length and exposed wheel height match the default, the contact "
                      "positions are the class defaults (re-export with `voidcross cad export` to read them "
                      "from the CAD)")


def ground_support(robot: RobotProperties) -> GroundSupport:
    """Where ``robot`` rests: the record's contacts, else the fallbacks of the module docstring."""
    if robot.ground_contacts:
        return _from_record(robot.ground_contacts, f"record: {robot.ground_contacts_source}")
    contacts, why = _fallback(robot.name, float(robot.length_m), float(robot.wheel_exposed_height_m))
    if contacts:
        return _from_record(contacts, why)
    return corners(robot, why)
