"""The robot registry: every robot model by its command-line name, built once per
(name, clearance, settings). Below the export layer, so docking, piers and slicing build robots
without importing the exporter."""

from __future__ import annotations

from functools import lru_cache

from cubot_cad.errors import InputError
from cubot_cad.part import DEFAULT_CLEARANCE_MM, check_clearance

ROBOT_NAMES = ("cubot", "octbot", "cube-robot", "platform")


def make_robot(name: str, clearance_mm: float = DEFAULT_CLEARANCE_MM, settings: tuple = ()):
    """The robot model ``name`` with the given print clearance and ``settings`` (``--set``: (name,
    value) pairs, :mod:`cubot_cad.settings`; those the robot has no field for are ignored), a shared
    instance: parts build once.

    The robot's own validation (its dataclass and every part and connector spec it derives) accepts
    or refuses the values; a refusal names ``--set NAME=VALUE`` (or ``--clearance-mm``), the values a
    user set, rather than a connector dimension the command line cannot reach."""
    from cubot_cad.settings import for_robot, parse_settings, settings_text

    check_clearance(clearance_mm, "--clearance-mm")
    if name not in ROBOT_NAMES:
        raise InputError(f"--robot {name!r} is not one of {', '.join(ROBOT_NAMES)}, all")
    settings = tuple((k, v) for k, v in parse_settings(settings) if k != "clearance_mm")
    mine = tuple(sorted(for_robot(settings, name).items()))
    try:
        return _make_robot(name, float(clearance_mm), mine)
    except InputError as exc:
        what = f"--set {settings_text(mine)}" if mine else f"--clearance-mm {clearance_mm:g}"
        if mine and abs(clearance_mm - DEFAULT_CLEARANCE_MM) > 1e-12:
            what += f" (--clearance-mm {clearance_mm:g})"
        raise InputError(f"{what}: the {name} cannot be built with it ({exc})") from None


@lru_cache(maxsize=32)
def _make_robot(name: str, clearance_mm: float, settings: tuple = ()):
    kw = dict(settings)
    if name == "cubot":
        from cubot_cad.robots.cubot import CuBot

        r = CuBot(clearance_mm=clearance_mm, **kw)
    elif name == "octbot":
        from cubot_cad.robots.octbot import OctBot

        r = OctBot(clearance_mm=clearance_mm, **kw)
    elif name == "cube-robot":
        from cubot_cad.robots.cube_robot import CubeRobot

        r = CubeRobot(clearance_mm=clearance_mm, **kw)
    elif name == "platform":
        from cubot_cad.robots.platform import TestPlatform

        r = TestPlatform(clearance_mm=clearance_mm, **kw)
    else:
        raise InputError(f"--robot {name!r} is not one of {', '.join(ROBOT_NAMES)}, all")
    if settings:
        # every part the robot places validates its dimensions when it is made (the solids are built
        # later): a value the geometry refuses is refused here, before anything is written
        r.placed  # noqa: B018
        r.components()
    return r


def parse_robots(value: str) -> tuple[str, ...]:
    items = [v.strip() for v in str(value).split(",") if v.strip()]
    if not items:
        raise InputError("--robot is empty")
    if items == ["all"]:
        return ROBOT_NAMES
    for v in items:
        if v not in ROBOT_NAMES:
            raise InputError(f"--robot {v!r} is not one of {', '.join(ROBOT_NAMES)}, all")
    return tuple(dict.fromkeys(items))
