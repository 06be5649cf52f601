"""Scenario parameters: presets are TOML data files, flattened into one frozen record.

Units are in the names: centimetres (``_cm``), seconds (``_s``), radians (``_rad``).
A preset (``swarm_sim/presets/<name>.toml``, or a path to a TOML file) gives every
value; ``run_scenario(..., **overrides)`` may replace any field by its flat name
(``arena_w_cm=800``). Every value is validated; bad input raises :class:`InputError`
naming the value.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field, fields, replace
from functools import lru_cache
from importlib import resources
from pathlib import Path

from .errors import InputError

CASES = ("A", "B", "C", "D")
STARTS = ("fixed", "random")
WALKS = ("levy", "random")
SHAPES = ("square", "octagon")
STRUCTURES = ("line", "auto", "switch")

#: TOML "section.key" -> flat Params field.
TOML_KEYS = {
    "scenario.case": "case", "scenario.start": "start", "scenario.robots": "robots",
    "scenario.void_width": "void_width", "scenario.case_margin": "case_margin",
    "scenario.structure": "structure",
    "arena.width_cm": "arena_w_cm", "arena.height_cm": "arena_h_cm",
    "void.left_x_cm": "void_left_x_cm", "void.depth_cm": "void_depth_cm",
    "robot.length_cm": "robot_length_cm", "robot.width_cm": "robot_width_cm",
    "robot.wheel_base_cm": "wheel_base_cm", "robot.wheel_radius_cm": "wheel_radius_cm",
    "robot.wheel_width_cm": "wheel_width_cm", "robot.shape": "shape",
    "robot.speed_cm_s": "speed_cm_s", "robot.turn_max_rad": "turn_max_rad",
    "robot.climb_s_per_layer": "climb_s_per_layer",
    "sensors.void_detect_cm": "void_detect_cm", "sensors.avoid_cm": "avoid_cm",
    "target.x_cm": "target_x_cm", "target.y_cm": "target_y_cm",
    "target.radius_cm": "target_radius_cm", "target.found_cm": "target_found_cm",
    "exploration.walk": "walk", "exploration.levy_mu": "levy_mu",
    "exploration.levy_min_cm": "levy_min_cm", "exploration.levy_max_cm": "levy_max_cm",
    "exploration.random_turn_prob": "random_turn_prob",
    "exploration.random_turn_rad": "random_turn_rad",
    "sim.dt_s": "dt_s", "sim.max_time_s": "max_time_s",
    "sim.wander_after_retreat_s": "wander_after_retreat_s", "sim.finish_delivery": "finish_delivery",
    "behaviour.recruit_stall_s": "recruit_stall_s", "behaviour.stall_s": "stall_s",
    "behaviour.heartbeat_s": "heartbeat_s", "behaviour.heartbeat_misses": "heartbeat_misses",
}


@dataclass(frozen=True)
class Params:
    """Everything one run needs. Void and target geometry: the void is a vertical band
    ``void_left_x_cm .. void_left_x_cm + void_width * robot_length_cm`` spanning the arena
    height; the robots start on its left (initial side), the target is on its right."""

    preset: str = "custom"
    case: str = "D"
    start: str = "random"
    robots: int = 9
    void_width: int = 3
    case_margin: int = 0
    structure: str = "line"  # line: the small-void single line (Ch. 4); auto: the limits' level for the void
    arena_w_cm: float = 500.0
    arena_h_cm: float = 300.0
    void_left_x_cm: float | None = None  # None: void centred
    #: ledge to floor (cm); 0: not given (the thesis's voids: vertical sides, no floor in reach),
    #: then no pier can be built (swarm_sim.behaviour.piers)
    void_depth_cm: float = 0.0
    robot_length_cm: float = 10.0
    robot_width_cm: float = 10.0
    wheel_base_cm: float = 7.0
    wheel_radius_cm: float = 2.1
    wheel_width_cm: float = 0.1
    shape: str = "square"
    speed_cm_s: float = 13.89
    turn_max_rad: float = math.pi / 2
    void_detect_cm: float = 5.0
    avoid_cm: float = 15.0
    target_x_cm: float = 475.0
    target_y_cm: float = 150.0
    target_radius_cm: float = 5.0
    target_found_cm: float = 5.0
    obstacles: tuple[tuple[float, float, float], ...] = ()
    walk: str = "levy"
    levy_mu: float = 2.0
    levy_min_cm: float = 5.0
    levy_max_cm: float = 300.0
    random_turn_prob: float = 0.1
    random_turn_rad: float = 0.3
    dt_s: float = 0.01
    max_time_s: float = 1500.0
    wander_after_retreat_s: float = 5.0
    finish_delivery: bool = False  # success waits for the structure to dissolve (large voids: Fig. 5.13)
    # behaviour timing of the structure (not in the thesis; small, documented)
    release_clear_s: float = 1.0
    #: a recruit whose remaining path has not shortened by half a grid cell for this long is
    #: released and the next closest free robot is called (swarm_sim.behaviour.recruitment)
    recruit_stall_s: float = 20.0
    #: a building structure that has not docked, moved, released, switched or seen a robot
    #: come closer for this long retreats (swarm_sim.behaviour.retreat.watchdog)
    stall_s: float = 120.0
    launch_min_robots: int = 3
    #: tapering arch: seconds a robot takes to climb (or come down) one layer onto a foot
    #: column; our assumption, the thesis does not say how robots get up
    climb_s_per_layer: float = 2.0
    #: robots that fail mid-task (swarm_sim.faults): the spec in its command-line form
    #: (``drive:0.5/h,3@120:total``; "" = none), from ``--faults`` or the preset's ``[faults]``
    faults: str = ""
    #: structure members and the seed broadcast a heartbeat every ``heartbeat_s``; a robot whose
    #: heartbeat is missed ``heartbeat_misses`` times running is known to have failed (our
    #: assumption: the thesis's robots broadcast, it does not give a rate)
    heartbeat_s: float = 1.0
    heartbeat_misses: int = 3
    # resolved from the limits record (filled by with_limits)
    limits_source: str = "unresolved"
    ground_ratio: float = 2.0
    ground_margin: int = 0
    max_span_widths: int = 5
    min_robots_rule: int = 0
    record_min_robots: int = 0
    level_name: str = "line"
    lines: int = 1
    layers: int = 1
    #: the level's taper block B (rows) when it is a tapering arch, else 0
    taper_block_rows: int = 0
    #: structure = "switch": every level of the record, in order, as (name, lines, layers,
    #: ground_ratio, ground_margin incl. case margin, max_span_widths, taper_block_rows or 0)
    switch_levels: tuple = ()
    #: piers (swarm_sim.behaviour.piers; from the limits record's pier rule, 0 / () when it has none or
    #: this void's depth takes no pier): robots per pier, piers allowed, the rule beyond a pier
    pier_robots: int = 0
    pier_max: int = 0
    pier_ground_ratio: float = 1.0
    pier_ground_margin: int = 1
    pier_overhang_widths: int = 0
    extra: dict = field(default_factory=dict, compare=False)

    # ------------------------------------------------------------------ derived geometry
    @property
    def void_width_cm(self) -> float:
        return self.void_width * self.robot_length_cm

    @property
    def void_x0_cm(self) -> float:
        if self.void_width <= 0:
            return math.inf
        if self.void_left_x_cm is not None:
            return float(self.void_left_x_cm)
        return 0.5 * (self.arena_w_cm - self.void_width_cm)

    @property
    def void_x1_cm(self) -> float:
        return self.void_x0_cm + self.void_width_cm if self.void_width > 0 else math.inf

    @property
    def rule(self) -> tuple[float, int, int]:
        """(ground_ratio, ground_margin, max_span_widths): the arguments of :func:`swarm_sim.behaviour.rule.stable`."""
        return self.ground_ratio, self.ground_margin, self.max_span_widths

    @property
    def steps_per_s(self) -> float:
        return 1.0 / self.dt_s

    def validate(self) -> Params:
        def req(cond: bool, msg: str) -> None:
            if not cond:
                raise InputError(msg)

        def pos(name: str) -> None:
            v = getattr(self, name)
            req(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0,
                f"{name} must be a positive number, got {v!r}")

        req(self.case in CASES, f"case {self.case!r} is not one of {', '.join(CASES)}")
        req(self.start in STARTS, f"start {self.start!r} is not one of {', '.join(STARTS)}")
        req(self.walk in WALKS, f"walk {self.walk!r} is not one of {', '.join(WALKS)}")
        req(self.shape in SHAPES, f"shape {self.shape!r} is not one of {', '.join(SHAPES)}")
        req(self.structure in STRUCTURES, f"structure {self.structure!r} is not one of {', '.join(STRUCTURES)}")
        req(isinstance(self.robots, int) and not isinstance(self.robots, bool) and self.robots >= 1,
            f"robots must be a positive integer, got {self.robots!r}")
        req(isinstance(self.void_width, int) and not isinstance(self.void_width, bool)
            and self.void_width >= 1, f"void_width must be a positive integer (robot widths), got {self.void_width!r}")
        req(isinstance(self.case_margin, int) and self.case_margin >= 0,
            f"case_margin must be an integer >= 0, got {self.case_margin!r}")
        for name in ("arena_w_cm", "arena_h_cm", "robot_length_cm", "robot_width_cm", "wheel_base_cm",
                     "wheel_radius_cm", "wheel_width_cm", "speed_cm_s", "turn_max_rad", "void_detect_cm",
                     "avoid_cm", "target_radius_cm", "target_found_cm", "levy_min_cm", "levy_max_cm",
                     "random_turn_rad", "dt_s", "max_time_s", "levy_mu", "recruit_stall_s", "stall_s"):
            pos(name)
        req(isinstance(self.climb_s_per_layer, float) and math.isfinite(self.climb_s_per_layer)
            and self.climb_s_per_layer >= 0,
            f"climb_s_per_layer must be a number >= 0 (seconds), got {self.climb_s_per_layer!r}")
        pos("heartbeat_s")
        req(isinstance(self.void_depth_cm, float) and math.isfinite(self.void_depth_cm) and self.void_depth_cm >= 0,
            f"void_depth_cm must be a number >= 0 (0: not given), got {self.void_depth_cm!r}")
        req(isinstance(self.heartbeat_misses, int) and not isinstance(self.heartbeat_misses, bool)
            and 1 <= self.heartbeat_misses <= 100,
            f"heartbeat_misses must be an integer in 1..100, got {self.heartbeat_misses!r}")
        req(isinstance(self.faults, str), f"faults must be a spec string, got {self.faults!r}")
        from .faults import parse_faults

        parse_faults(self.faults).check_robots(self.robots)
        req(self.wander_after_retreat_s >= 0, f"wander_after_retreat_s must be >= 0, got {self.wander_after_retreat_s}")
        req(0 <= self.random_turn_prob <= 1, f"random_turn_prob must be in 0..1, got {self.random_turn_prob}")
        req(self.levy_max_cm >= self.levy_min_cm,
            f"levy_max_cm {self.levy_max_cm} is below levy_min_cm {self.levy_min_cm}")
        req(self.dt_s <= 0.1, f"dt_s {self.dt_s} is too coarse (> 0.1 s)")
        L = self.robot_length_cm
        req(self.void_width_cm < self.arena_w_cm,
            f"void_width {self.void_width} ({self.void_width_cm:g} cm) is wider than the arena "
            f"({self.arena_w_cm:g} cm)")
        x0, x1 = self.void_x0_cm, self.void_x1_cm
        req(x0 >= 3 * L, f"void at x={x0:g} cm leaves less than 3 robot lengths of initial ground")
        req(x1 <= self.arena_w_cm - 2 * L,
            f"void_width {self.void_width}: the void ends at x={x1:g} cm, leaving less than 2 robot "
            f"lengths of target ground in a {self.arena_w_cm:g} cm arena")
        tx, ty = self.target_x_cm, self.target_y_cm
        req(0 <= tx <= self.arena_w_cm and 0 <= ty <= self.arena_h_cm,
            f"target ({tx:g}, {ty:g}) cm is outside the {self.arena_w_cm:g} x {self.arena_h_cm:g} cm arena")
        req(tx - self.target_radius_cm > x1 or tx + self.target_radius_cm < x0,
            f"target x={tx:g} cm is inside (or touching) the void {x0:g}..{x1:g} cm")
        req(tx > x1, f"target x={tx:g} cm is on the initial side of the void (x < {x0:g} cm)")
        for i, ob in enumerate(self.obstacles):
            req(len(ob) == 3 and all(isinstance(v, (int, float)) and math.isfinite(v) for v in ob) and ob[2] > 0,
                f"obstacle {i} must be (x_cm, y_cm, r_cm) with r > 0, got {ob!r}")
            # a walker turns away from an obstacle ahead within avoid_cm of its rim, so its centre
            # never comes closer than r + avoid_cm: a target inside that disc is never found
            reach = ob[2] + self.avoid_cm
            gap = math.hypot(tx - ob[0], ty - ob[1])
            req(gap >= reach,
                f"target ({tx:g}, {ty:g}) cm is {gap:.1f} cm from obstacle {i} at ({ob[0]:g}, {ob[1]:g}) cm: "
                f"free robots keep r + avoid_cm = {reach:g} cm from its centre, so the target can never be found")
        # the swarm must fit on the initial ground at the start
        free_area = (x0 - 2 * L) * (self.arena_h_cm - 2 * L)
        req(self.robots * (2 * L) ** 2 <= max(free_area, 0) * 0.9,
            f"robots={self.robots} do not fit on the {x0:g} x {self.arena_h_cm:g} cm initial side")
        return self


def _flatten(doc: dict, source: str) -> dict:
    flat: dict = {}
    for section, body in doc.items():
        if section == "obstacles":
            if not isinstance(body, list):
                raise InputError(f"{source}: [[obstacles]] must be an array of tables")
            obs = []
            for i, ob in enumerate(body):
                try:
                    obs.append((float(ob["x_cm"]), float(ob["y_cm"]), float(ob.get("r_cm", 5.0))))
                except (KeyError, TypeError, ValueError) as exc:
                    raise InputError(f"{source}: obstacle {i} needs numeric x_cm, y_cm (r_cm): {exc}") from None
            flat["obstacles"] = tuple(obs)
            continue
        if not isinstance(body, dict):
            raise InputError(f"{source}: top-level key {section!r} is not a [section]")
        if section == "faults":
            from .faults import from_table

            spec = from_table(body, f"{source}: [faults]")
            flat["faults"] = "" if spec.empty else spec.describe()
            continue
        for key, value in body.items():
            name = TOML_KEYS.get(f"{section}.{key}")
            if name is None:
                raise InputError(f"{source}: unknown setting {section}.{key}")
            flat[name] = value
    return flat


def preset_names() -> list[str]:
    d = resources.files("swarm_sim") / "presets"
    return sorted(p.name[:-5] for p in d.iterdir() if p.name.endswith(".toml"))


def load_preset(preset: str) -> Params:
    """A named preset (``case-d``) or a path to a TOML file -> validated-later Params."""
    if not isinstance(preset, str) or not preset:
        raise InputError(f"preset must be a name or a TOML path, got {preset!r}")
    path = Path(preset)
    if preset.endswith(".toml") or path.exists():
        if not path.is_file():
            raise InputError(f"preset file {preset} does not exist")
        text, source, name = path.read_bytes(), str(path), path.stem
    else:
        res = resources.files("swarm_sim") / "presets" / f"{preset}.toml"
        if not res.is_file():
            raise InputError(f"unknown preset {preset!r} (known: {', '.join(preset_names())})")
        text, source, name = res.read_bytes(), f"preset {preset}", preset
    try:
        doc = tomllib.loads(text.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"{source}: malformed TOML: {exc}") from None
    flat = _flatten(doc, source)
    return with_overrides(Params(preset=name), flat, source)


def with_overrides(params: Params, overrides: dict, source: str = "override") -> Params:
    names = {f.name for f in fields(Params)} - {"extra", "limits_source", "ground_ratio", "ground_margin",
                                                "max_span_widths", "min_robots_rule", "record_min_robots",
                                                "level_name", "lines", "layers",
                                                "switch_levels", "taper_block_rows", "pier_robots", "pier_max",
                                                "pier_ground_ratio", "pier_ground_margin",
                                                "pier_overhang_widths"}
    clean = {}
    for k, v in overrides.items():
        if k not in names:
            raise InputError(f"{source}: unknown parameter {k!r}")
        ref = getattr(params, k)
        if isinstance(ref, float) and isinstance(v, int) and not isinstance(v, bool):
            v = float(v)
        if k == "obstacles":
            v = tuple(tuple(float(c) for c in ob) for ob in v)
        elif ref is not None and k != "void_left_x_cm" and type(v) is not type(ref):
            raise InputError(f"{source}: {k} must be {type(ref).__name__}, got {v!r}")
        from .tunables import check

        check(k, v, source)
        clean[k] = v
    return replace(params, **clean)


@lru_cache(maxsize=64)
def at_level(params: Params, i: int) -> Params:
    """``params`` with the rule and cross-section of switch level ``i`` (``structure = "switch"``)."""
    name, lines, layers, ratio, margin, span, taper = params.switch_levels[i]
    return replace(params, level_name=name, lines=lines, layers=layers, ground_ratio=ratio,
                   ground_margin=margin, max_span_widths=span, taper_block_rows=taper)


def level_params(p: Params, st) -> Params:
    """The rule in force for structure ``st``: its switch level's (``structure = "switch"``), else ``p``."""
    return at_level(p, st.level) if p.switch_levels else p
