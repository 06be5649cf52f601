"""The dimensions a maker tunes from the command line (``voidcross cad ... --set NAME=VALUE``).

Each :class:`Setting` names one dimension (with its unit in the name, ``*_mm``) and the robots
whose dataclass field of that name it sets; a setting with ``choices`` (the front-rear latch)
takes one of its names instead. A dimension is not checked here beyond being a finite number: it goes into the robot's frozen dataclass, whose own validation (and that of
the parts and connector specs it derives) accepts or refuses it, and a refusal is reported
as one :class:`~cubot_cad.errors.InputError` naming ``--set NAME=VALUE``
(:func:`cubot_cad.outputs.export.make_robot`). ``clearance_mm`` is the print clearance per side, the
same value as ``--clearance-mm`` and validated the same way
(:func:`~cubot_cad.part.check_clearance`).

A robot that has no such dimension is built with its defaults; a setting that no selected robot
takes is refused (it would silently do nothing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import InputError


@dataclass(frozen=True)
class Setting:
    """One tunable dimension: ``name`` (the dataclass field, unit suffix included), what it is, and
    the robots (:data:`~cubot_cad.outputs.export.ROBOT_NAMES`) whose field of that name it sets."""

    name: str
    description: str
    robots: tuple[str, ...]
    #: A variant chosen by name instead of a dimension (e.g. the front-rear coupling): its values.
    choices: tuple[str, ...] | None = None

    @property
    def unit(self) -> str:
        return "one of " + ", ".join(self.choices) if self.choices else self.name.rsplit("_", 1)[-1]


def _fmt(v) -> str:
    return v if isinstance(v, str) else f"{v:g}"


#: What ``--set`` exposes: dimensions (in mm) and variants chosen by name (``choices``).
SETTINGS: dict[str, Setting] = {s.name: s for s in (
    Setting("clearance_mm", "print clearance per side on every mating pair (= --clearance-mm)",
            ("cubot", "octbot", "cube-robot", "platform")),
    Setting("wall_mm", "outer wall thickness of the body (the connector blocks are screwed to it)",
            ("cubot", "octbot", "cube-robot")),
    Setting("floor_mm", "floor thickness of the body", ("cubot", "octbot")),
    Setting("pin_diameter_mm", "diameter of the grooved pins (their holes are pin + 2 clearances)",
            ("cubot", "cube-robot")),
    Setting("groove_diameter_mm", "diameter of the grooved pins' neck (the latch blade's slots follow it)",
            ("cubot", "cube-robot")),
    Setting("wheel_base_mm", "distance between the drive wheels' mid-planes", ("cubot", "octbot")),
    Setting("front_rear_coupling", "the front-rear latch: wedge (no free play, the default) or clearance "
            "(the thesis's drawing, 2 clearances of tension play)", ("cubot",), ("wedge", "clearance")),
)}


def _names() -> str:
    return ", ".join(sorted(SETTINGS))


def parse_setting(text: str) -> tuple[str, float | str]:
    """``"NAME=VALUE"`` -> (name, value in mm, or the variant's name for a setting with choices);
    :class:`InputError` (naming the text) for an unknown name, a missing ``=``, a value that is not
    a finite number or not one of the choices."""
    raw = str(text)
    if "=" not in raw:
        raise InputError(f"--set {raw!r} is not NAME=VALUE (NAME one of {_names()})")
    name, value = (s.strip() for s in raw.split("=", 1))
    if name not in SETTINGS:
        raise InputError(f"--set {name}={value}: {name!r} is not a dimension the CLI sets (one of {_names()})")
    choices = SETTINGS[name].choices
    if choices:
        if value not in choices:
            raise InputError(f"--set {name}={value}: {value!r} is not one of {', '.join(choices)}")
        return name, value
    try:
        v = float(value)
    except ValueError:
        raise InputError(f"--set {name}={value}: {value!r} is not a number ({SETTINGS[name].unit})") from None
    if not math.isfinite(v):
        raise InputError(f"--set {name}={value}: {value!r} is not a finite number ({SETTINGS[name].unit})")
    return name, v


def parse_settings(items) -> tuple[tuple[str, float], ...]:
    """The ``--set`` items (strings ``NAME=VALUE``, or (name, value) pairs), parsed, as a sorted
    tuple of (name, value) (hashable: robots are cached by it). A name given twice with two values
    is refused; ``clearance_mm`` is not in the result (it is the clearance, see
    :func:`resolve_clearance`)."""
    out: dict[str, float] = {}
    for it in items or ():
        name, v = parse_setting(it) if isinstance(it, str) else parse_setting(f"{it[0]}={it[1]}")
        if name in out and out[name] != v:
            raise InputError(f"--set {name} is given twice ({_fmt(out[name])} and {_fmt(v)})")
        out[name] = v
    return tuple(sorted(out.items()))


def resolve_clearance(settings: tuple[tuple[str, float], ...], clearance_mm: float | None,
                      default_mm: float) -> tuple[float, tuple[tuple[str, float], ...]]:
    """(clearance, the other settings): ``--set clearance_mm=V`` and ``--clearance-mm`` are the same
    value (validated by :func:`~cubot_cad.part.check_clearance` under the name the user gave);
    both given and different is an :class:`InputError`; neither gives ``default_mm``."""
    from .part import check_clearance

    d = dict(settings)
    rest = tuple((k, v) for k, v in settings if k != "clearance_mm")
    if "clearance_mm" in d:
        c = check_clearance(d["clearance_mm"], "--set clearance_mm")
        if clearance_mm is not None and abs(float(clearance_mm) - c) > 1e-12:
            raise InputError(f"--set clearance_mm={c:g} contradicts --clearance-mm {clearance_mm:g} (give one)")
        return c, rest
    if clearance_mm is None:
        return default_mm, rest
    return check_clearance(clearance_mm, "--clearance-mm"), rest


def check_applicable(settings: tuple[tuple[str, float], ...], robots) -> None:
    """Refuse a setting none of ``robots`` takes (it would change nothing)."""
    robots = tuple(robots)
    for name, v in settings:
        s = SETTINGS[name]
        if not set(s.robots) & set(robots):
            raise InputError(f"--set {name}={_fmt(v)}: none of {', '.join(robots)} has {name} "
                             f"(it sets the {', '.join(s.robots)})")


def for_robot(settings: tuple[tuple[str, float], ...], robot: str) -> dict[str, float]:
    """The settings that apply to ``robot``, as dataclass keyword arguments."""
    return {k: v for k, v in settings if k != "clearance_mm" and robot in SETTINGS[k].robots}


def settings_text(settings) -> str:
    return ", ".join(f"{k}={_fmt(v)}" for k, v in settings)
