"""`StructureLimits`: the record `structure_fem` hands to `swarm_sim`.

For each structure the swarm can build (single line, two lines side by side,
layered arch levels) it states the widest void it may span, in robot widths,
and the robot-count rule that keeps it from tipping while it is launched.

Two sources live side by side and are never blurred:

* ``derived`` (the default): computed by `structure_fem` from the robots'
  mass properties and connector compliance (``voidcross fem table`` writes
  ``limits.json``; the packaged copy is ``structure_fem/data/limits.json``).
* ``thesis``: the thesis's own limits (switch every 5 widths up to 30, its
  counting rules 3 n_g / 6 n_g and the arch counts of Ch. 5.5.2), built by
  :func:`thesis_limits` so its experiments can be reproduced exactly.

This module imports neither exudyn nor cadquery: `swarm_sim` reads it.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from cubot_cad.jsonrecord import check_schema, from_dict, read_json, to_jsonable, write_json_atomic

from .errors import InputError

SCHEMA_VERSION = 1
KINDS = ("line", "two_line", "arch")
MAX_ARCH_WIDE = 8
MAX_ARCH_HIGH = 4


def _req(cond: bool, msg: str) -> None:
    if not cond:
        raise InputError(msg)


@dataclass(frozen=True)
class StructureLevel:
    """One structure and the band of void widths it is used for.

    ``lines`` robots side by side in the core, ``layers`` robots high at the
    thickest section (1 for line / two-line). While the structure is a
    cantilever (front not yet on the far ledge) each advance must keep
    ``rows on the initial ground >= ground_ratio * rows over the void +
    ground_margin``; the thesis's rule for cases B-D is ratio 2, margin 0
    (n_p = 2 n_g before landing, n_p = n_g = n_o once bridged).
    ``min_robots`` lists the minimum swarm size for each void width in
    ``min_span_widths..max_span_widths``.

    ``taper_block_rows`` (arches only): ``None`` means every row has the full
    ``lines x layers`` section (what `structure_fem` derives and validates).
    An integer ``B`` makes the thesis's tapering arch (Ch. 5.5.2, Fig.
    5.2-5.3): a moving core of two lines, and a static foot at each ledge
    whose half cross-section grows in blocks of ``B`` rows, 1, 2, .., k
    (k = ``layers``) towards the ledge and shrinks k-1, .., 2 over the void
    (:func:`taper_half_level`). Then ``lines`` must be ``2 * layers`` and the
    counting rule counts robots, not rows (the rows differ in size; the
    thesis: "the number of robots at each initial and target zones is larger
    than the number of robots over the void").
    """

    name: str
    kind: str
    lines: int
    layers: int
    min_span_widths: int
    max_span_widths: int
    ground_ratio: float
    ground_margin: int
    min_robots: tuple[int, ...]
    #: Mechanics at the band's widest void (None in the thesis preset, which had no model).
    max_deflection_mm: float | None = None
    min_tipping_factor: float | None = None
    taper_block_rows: int | None = None
    #: The launch transients' overshoot at the band's widest void (mm; the threshold criterion is
    #: max_deflection_mm + dynamic_allowance_mm <= clearance). None: a static derivation / thesis.
    dynamic_allowance_mm: float | None = None

    def __post_init__(self) -> None:
        _req(self.kind in KINDS, f"structure kind {self.kind!r} is not one of {', '.join(KINDS)}")
        _req(1 <= self.lines <= MAX_ARCH_WIDE,
             f"structure {self.name!r}: lines={self.lines} outside 1..{MAX_ARCH_WIDE}")
        _req(1 <= self.layers <= MAX_ARCH_HIGH,
             f"structure {self.name!r}: layers={self.layers} outside 1..{MAX_ARCH_HIGH}")
        _req(1 <= self.min_span_widths <= self.max_span_widths,
             f"structure {self.name!r}: span {self.min_span_widths}..{self.max_span_widths} is empty or non-positive")
        _req(math.isfinite(self.ground_ratio) and self.ground_ratio > 0,
             f"structure {self.name!r}: ground_ratio must be > 0, got {self.ground_ratio}")
        _req(self.ground_margin >= 0, f"structure {self.name!r}: ground_margin must be >= 0")
        n = self.max_span_widths - self.min_span_widths + 1
        _req(len(self.min_robots) == n,
             f"structure {self.name!r}: min_robots has {len(self.min_robots)} entries for {n} widths")
        _req(all(isinstance(k, int) and k >= 2 for k in self.min_robots),
             f"structure {self.name!r}: min_robots must be integers >= 2, got {self.min_robots}")
        for name in ("max_deflection_mm", "min_tipping_factor", "dynamic_allowance_mm"):
            v = getattr(self, name)
            _req(v is None or math.isfinite(v), f"structure {self.name!r}: {name} is not finite ({v})")
        _req(self.dynamic_allowance_mm is None or self.dynamic_allowance_mm >= 0,
             f"structure {self.name!r}: dynamic_allowance_mm must be >= 0, got {self.dynamic_allowance_mm}")
        if self.taper_block_rows is not None:
            _req(self.kind == "arch", f"structure {self.name!r}: only an arch can taper (kind {self.kind!r})")
            _req(isinstance(self.taper_block_rows, int) and 1 <= self.taper_block_rows <= 50,
                 f"structure {self.name!r}: taper_block_rows={self.taper_block_rows!r} outside 1..50")
            _req(self.lines == 2 * self.layers,
                 f"structure {self.name!r}: a tapering arch is 2k wide and k high, got "
                 f"{self.lines} x {self.layers}")

    @property
    def tapered(self) -> bool:
        return self.taper_block_rows is not None

    def robots_for(self, width: int) -> int:
        _req(self.min_span_widths <= width <= self.max_span_widths,
             f"void width {width} is outside structure {self.name!r} ({self.min_span_widths}..{self.max_span_widths})")
        return self.min_robots[width - self.min_span_widths]


@dataclass(frozen=True)
class PierRule:
    """Crossing a void over intermediate supports: piers of failed robots stacked with the
    top-down coupling, standing on the void floor with their top at the ledge height
    (derived by :mod:`structure_fem.analysis.piers`; the thesis has no such rule).

    The structure ``structure`` (a level name of the record) advances as a cantilever from the
    near ledge to ``first_span_widths`` (that level's own threshold, its own counting rule), a
    pier ``pier_width_widths`` robot lengths wide is built just beyond its front (its near face
    at ``first_span_widths`` from the near edge), the structure rolls onto it and continues as a
    continuous beam; beyond the pier's far face it may overhang ``overhang_widths[k - 1]`` rows
    for a pier of ``k`` robots (0: no overhang is safe), then it reaches the far ledge (widest
    void crossed with one pier: ``max_void_widths[k - 1] = first_span + pier_width + overhang``).
    A second pier at the first overhang's limit allows ``overhang_widths_two_piers[k - 1]``
    beyond it. While something overhangs the last support, every advance must keep
    ``rows behind the last support's far face >= ground_ratio * rows beyond it + ground_margin``.
    ``pier_stiffness_n_per_m[k - 1]``: the vertical stiffness of a pier of ``k`` robots;
    ``max_deflection_mm`` / ``min_tipping_factor``: the largest tip and the smallest tipping
    factor (about the last support) over every state of the crossings checked at these counts.
    """

    structure: str
    first_span_widths: int
    pier_width_widths: int
    overhang_widths: tuple[int, ...]
    overhang_widths_two_piers: tuple[int, ...]
    ground_ratio: float
    ground_margin: int
    max_void_widths: tuple[int, ...]
    pier_stiffness_n_per_m: tuple[float, ...]
    max_deflection_mm: float
    min_tipping_factor: float
    notes: str = ""
    #: the pier's stack geometry, copied from the robot properties record (cubot_cad.piers.pier;
    #: None when the record has none): floor to the top cover of one robot standing on its
    #: wheels, top cover to top cover of stacked robots, and the printed deck the line rolls
    #: over on the top robot (cubot_cad.piers.deck). The simulator turns a void's depth into robots
    #: per pier with them (swarm_sim.behaviour.piers.robots_per_pier).
    standing_height_m: float | None = None
    stack_pitch_m: float | None = None
    deck_height_m: float | None = None

    def __post_init__(self) -> None:
        _req(self.first_span_widths >= 1, f"piers: first_span_widths must be >= 1, got {self.first_span_widths}")
        _req(self.pier_width_widths >= 1, f"piers: pier_width_widths must be >= 1, got {self.pier_width_widths}")
        n = len(self.overhang_widths)
        _req(n >= 1, "piers: overhang_widths lists no pier height")
        for name in ("overhang_widths_two_piers", "max_void_widths", "pier_stiffness_n_per_m"):
            _req(len(getattr(self, name)) == n,
                 f"piers: {name} has {len(getattr(self, name))} entries for {n} pier heights")
        _req(all(isinstance(o, int) and o >= 0 for o in self.overhang_widths + self.overhang_widths_two_piers),
             f"piers: overhangs must be integers >= 0, got {self.overhang_widths} / {self.overhang_widths_two_piers}")
        want = tuple(self.first_span_widths + self.pier_width_widths + o for o in self.overhang_widths)
        _req(self.max_void_widths == want,
             f"piers: max_void_widths {self.max_void_widths} is not first span + pier width + overhang {want}")
        _req(all(math.isfinite(k) and k > 0 for k in self.pier_stiffness_n_per_m),
             f"piers: pier stiffness must be > 0, got {self.pier_stiffness_n_per_m}")
        _req(math.isfinite(self.ground_ratio) and self.ground_ratio > 0,
             f"piers: ground_ratio must be > 0, got {self.ground_ratio}")
        _req(self.ground_margin >= 0, f"piers: ground_margin must be >= 0, got {self.ground_margin}")
        for name in ("max_deflection_mm", "min_tipping_factor"):
            _req(math.isfinite(getattr(self, name)), f"piers: {name} is not finite ({getattr(self, name)})")

    @property
    def max_pier_robots(self) -> int:
        """The tallest pier the rule covers (robots stacked)."""
        return len(self.overhang_widths)

    def _k(self, robots: int) -> int:
        _req(isinstance(robots, int) and 1 <= robots <= self.max_pier_robots,
             f"a pier of {robots!r} robots is outside the rule's 1..{self.max_pier_robots}")
        return robots - 1

    def overhang_for(self, robots: int, second: bool = False) -> int:
        """Rows that may overhang the far face of a pier of ``robots`` robots (``second``: of
        the second pier)."""
        return (self.overhang_widths_two_piers if second else self.overhang_widths)[self._k(robots)]

    def max_void_for(self, robots: int) -> int:
        """The widest void (robot widths) crossed over one pier of ``robots`` robots."""
        return self.max_void_widths[self._k(robots)]

    def min_rows_behind(self, rows_beyond: int) -> int:
        """Fewest rows behind the last support's far face with ``rows_beyond`` rows past it."""
        _req(isinstance(rows_beyond, int) and rows_beyond >= 0, f"rows beyond must be >= 0, got {rows_beyond!r}")
        return math.ceil(self.ground_ratio * rows_beyond - 1e-9) + self.ground_margin


@dataclass(frozen=True)
class StructureLimits:
    """Which structure spans which void, and the counting rules, for one robot model.

    ``piers`` (optional, :class:`PierRule`): the multi-span rule over piers of failed robots;
    ``None`` when it was not derived (and in records written before it existed).
    """

    source: str
    robot: str
    clearance_mm: float
    levels: tuple[StructureLevel, ...]
    notes: str = ""
    #: Inputs that produced a derived record (stiffness, masses, ...), for provenance.
    inputs: dict[str, float] = field(default_factory=dict)
    #: Where each input comes from (per connector: "hand formula: ...", "fe: ...", "measured: ...").
    input_provenance: dict[str, str] = field(default_factory=dict)
    #: Crossing over piers (``None``: not derived; the thesis has no pier rule).
    piers: PierRule | None = None
    schema_version: int = SCHEMA_VERSION

    def __post_init__(self) -> None:
        _req(self.schema_version == SCHEMA_VERSION,
             f"limits schema_version {self.schema_version} is not {SCHEMA_VERSION}")
        _req(len(self.levels) > 0, "limits list no structure")
        _req(math.isfinite(self.clearance_mm) and self.clearance_mm > 0,
             f"clearance_mm must be > 0, got {self.clearance_mm}")
        expected = 1
        for lvl in self.levels:
            _req(lvl.min_span_widths == expected,
                 f"structure {lvl.name!r} starts at width {lvl.min_span_widths}, expected {expected} "
                 "(levels must tile the widths without gaps)")
            expected = lvl.max_span_widths + 1
        names = [lvl.name for lvl in self.levels]
        _req(len(set(names)) == len(names), f"duplicate structure names {names}")
        if self.piers is not None:
            _req(self.piers.structure in names,
                 f"piers: structure {self.piers.structure!r} is not a level of these limits ({', '.join(names)})")
            lvl = self.levels[names.index(self.piers.structure)]
            _req(self.piers.first_span_widths == lvl.max_span_widths,
                 f"piers: first_span_widths {self.piers.first_span_widths} is not {lvl.name!r}'s own threshold "
                 f"{lvl.max_span_widths}")

    @property
    def max_span_widths(self) -> int:
        """The widest void (robot widths) any structure here can cross."""
        return self.levels[-1].max_span_widths

    def level_for(self, width: int) -> StructureLevel:
        """The structure used for a void ``width`` robot widths wide."""
        _req(isinstance(width, int) and width >= 1, f"void width must be a positive integer, got {width!r}")
        for lvl in self.levels:
            if width <= lvl.max_span_widths:
                return lvl
        raise InputError(
            f"void width {width} is wider than the widest structure in the {self.source} limits "
            f"({self.max_span_widths} robot widths)")

    def min_robots(self, width: int) -> int:
        return self.level_for(width).robots_for(width)

    def thresholds(self) -> dict:
        """``{"line", "two_line", "arch", "arch_levels"}``: widest span of each structure kind."""
        out: dict = {"line": 0, "two_line": 0, "arch": 0, "arch_levels": []}
        arches = [lvl.max_span_widths for lvl in self.levels if lvl.kind == "arch"]
        for lvl in self.levels:
            if lvl.kind in ("line", "two_line"):
                out[lvl.kind] = lvl.max_span_widths
        if arches:
            out["arch"] = arches[0]
            out["arch_levels"] = arches[1:]
        return out

    def to_dict(self) -> dict:
        d = to_jsonable(self)
        return {"schema_version": d.pop("schema_version"), **d}

    @classmethod
    def from_dict(cls, data: object, what: str = "limits") -> StructureLimits:
        check_schema(data, SCHEMA_VERSION, what)
        return from_dict(cls, data, what)

    def save(self, path: str | os.PathLike) -> Path:
        return write_json_atomic(path, self.to_dict())

    @classmethod
    def load(cls, path: str | os.PathLike) -> StructureLimits:
        return cls.from_dict(read_json(path), str(path))


# --------------------------------------------------------------------------- thesis preset

# --------------------------------------------------------------------------- tapering arch geometry

def taper_half_level(layers: int, block_rows: int, row: int, void_rows: int, far_foot: bool = True) -> int:
    """Half-level ``j`` of the tapering arch's row occupying ``[row, row + 1)`` robot
    lengths past the near edge (negative rows on the initial ground); its cross-section
    is ``2j`` robots wide and ``j`` high (``2 j^2`` robots; ``j = 1`` is the bare core
    of two lines).

    On each ground the foot has blocks of ``block_rows`` rows with ``j = k, k-1, .., 1``
    going away from the edge (k = ``layers``; the core goes on behind it with ``j = 1``);
    over the void the section shrinks ``k-1, .., 2`` from each ledge and the middle is
    the bare core. ``far_foot=False``: before the far foot is built (the structure has
    not landed) the far half is bare core. Thesis Ch. 5.5.2 (c)-(f): e.g. k = 3, 5-row
    blocks, 15 widths: initial / over / target = 28a / 18a / 28a (a = 5 robots).
    """
    k, b = layers, block_rows
    if row < 0:                      # initial ground
        return max(1, k - (-row - 1) // b)
    if row >= void_rows:             # target ground
        return max(1, k - (row - void_rows) // b) if far_foot else 1
    d_near = row
    d_far = void_rows - 1 - row
    j = max(1, k - 1 - d_near // b)
    if far_foot:
        j = max(j, k - 1 - d_far // b)
    return j


def tapered_arch_robots(layers: int, block_rows: int, void_rows: int, far_foot: bool = True) -> dict[str, int]:
    """Robots of the complete tapering arch over ``void_rows``: ``{"initial", "over", "target", "total"}``.

    Each ground holds the ``layers`` foot blocks (the last one the bare core); with
    ``far_foot=False`` the target side holds nothing yet (the structure before landing).
    """
    ground = layers * block_rows
    sec = lambda r: 2 * taper_half_level(layers, block_rows, r, void_rows, far_foot) ** 2  # noqa: E731
    initial = sum(sec(r) for r in range(-ground, 0))
    over = sum(sec(r) for r in range(void_rows))
    target = sum(sec(r) for r in range(void_rows, void_rows + ground)) if far_foot else 0
    return {"initial": initial, "over": over, "target": target, "total": initial + over + target}


#: Rows per block "a" of the thesis's arch counts (Ch. 5.5.2): a block of five rows,
#: one robot per row per half cross-section level.
THESIS_ROWS_PER_BLOCK = 5
#: (name, widest span, layers) of the thesis's arch levels, Ch. 5.5.2 (c)-(f). Their counts
#: come from :func:`tapered_arch_robots` (a test checks them against the thesis's 28a/18a/28a,
#: 28a/20a/28a, 60a/54a/60a and 60a/56a/60a).
THESIS_ARCHES = (
    ("arch-15", 15, 3),
    ("arch-20", 20, 3),
    ("arch-25", 25, 4),
    ("arch-30", 30, 4),
)


def thesis_limits(robot: str = "cubot") -> StructureLimits:
    """The thesis's own limits: line to 5 widths (N = 3 n_g), two lines to 10
    (N = 2 x 3 n_g), tapering arches to 15/20/25/30 with the Ch. 5.5.2 counts
    (complete arch, both feet; robots on each ground > robots over the void,
    i.e. ratio 1 and margin 1 counted in robots), clearance 15 mm.

    Case A's stricter rule (n_p, n_o >= n_g + 1, N = 3 n_g + 2) is a scenario
    margin applied by the simulator on top of these.

    ``piers`` is ``None``: the thesis names failed robots as piers only as future work
    (Ch. 7.2) and gives no rule for them, so this preset has none.
    """
    levels = [
        StructureLevel("line", "line", 1, 1, 1, 5, 2.0, 0, tuple(3 * w for w in range(1, 6))),
        StructureLevel("two_line", "two_line", 2, 1, 6, 10, 2.0, 0, tuple(6 * w for w in range(6, 11))),
    ]
    lo = 11
    b = THESIS_ROWS_PER_BLOCK
    for name, hi, layers in THESIS_ARCHES:
        counts = tuple(tapered_arch_robots(layers, b, w)["total"] for w in range(lo, hi + 1))
        levels.append(StructureLevel(name, "arch", 2 * layers, layers, lo, hi, 1.0, 1, counts,
                                     taper_block_rows=b))
        lo = hi + 1
    return StructureLimits(
        source="thesis", robot=robot, clearance_mm=15.0, levels=tuple(levels),
        notes="Thesis Ch. 5.5.2 / 6.5.2: structure switched every 5 robot widths on the "
              "1 mm-per-platform extrapolation; counts 3 n_g, 6 n_g and 28a/18a/28a ... (a = 5 rows).")


def packaged_limits_path() -> Path:
    """``structure_fem/data/limits.json``: the derived limits shipped with the package."""
    return Path(str(resources.files("structure_fem") / "data" / "limits.json"))


def load_limits(spec: str | os.PathLike = "derived") -> StructureLimits:
    """``"derived"`` (packaged output of structure_fem), ``"thesis"``, or a path to a limits.json."""
    if spec == "thesis":
        return thesis_limits()
    if spec == "derived":
        path = packaged_limits_path()
        if not path.exists():
            raise InputError(
                f"derived limits not found at {path}: run `voidcross fem table` to derive them")
        return StructureLimits.load(path)
    p = Path(spec)
    if not p.exists():
        raise InputError(f"--limits {spec!s}: not 'derived', 'thesis' or an existing limits.json file")
    return StructureLimits.load(p)
