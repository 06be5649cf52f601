"""Structure descriptions and their planar layout (SI units, no exudyn).

A :class:`Structure` is what the swarm builds: ``lines`` robots side by side,
``layers`` robots high, every row the same cross-section, joints of
neighbouring lines ``aligned`` or ``staggered`` by half a robot (the CuBot's
side rail slides, so a half offset is possible; the top twist-lock has one
centred key, so layers always stack aligned).

:func:`layout` turns a structure, a robot and a position over a void into the
planar bodies, couplings and ledge supports the model solves. A structure with
``taper_block_rows`` is the thesis's tapering arch (a two-line core through
static feet, Ch. 5.5.2): :func:`tapered_layout` places it row by row from
`limits.taper_half_level`, to be evaluated beside the derived uniform ones.

Why a planar (x-z) model is exact here: every robot, coupling and load
(gravity) is symmetric about the structure's vertical mid-plane along the
void, so there is no out-of-plane displacement, twist or roll to first and
to any order. Robots that sit at the same x in the same layer move
identically (same load per coupling: side-by-side aligned lines deflect like
one line) and are merged into one planar body carrying their summed mass,
inertia and coupling stiffness. Staggered lines are two planar bodies per row
(even lines at offset 0, odd lines shifted half a pitch back), coupled through
the side rails where they overlap. What a planar model cannot show (lateral
tipping, twist under an off-centre robot) is outside this package's claims.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cubot_cad.properties import RobotProperties
from structure_fem.errors import InputError
from structure_fem.limits import (
    KINDS,
    MAX_ARCH_HIGH,
    MAX_ARCH_WIDE,
    taper_half_level,
    tapered_arch_robots,
)
from structure_fem.model.connectors import ConnectorSet, Joint
from structure_fem.model.contacts import GroundSupport, ground_support

ARRANGEMENTS = ("aligned", "staggered")
PHASES = ("cantilever", "bridged")
GRAVITY = 9.81


@dataclass(frozen=True)
class Structure:
    """``lines`` side by side (1..8) x ``layers`` high (1..4); ``arrangement`` of the line joints.

    ``taper_block_rows`` (arches only, ``None`` = uniform): the thesis's tapering arch
    (Ch. 5.5.2), ``lines = 2 * layers`` at its thickest; row ``i``'s section is ``2j`` wide
    and ``j`` high with ``j = taper_half_level(layers, taper_block_rows, i, ...)``
    (see :func:`tapered_layout`). Its lines are aligned (each layer of a row is one body).
    """

    kind: str
    lines: int = 1
    layers: int = 1
    arrangement: str = "aligned"
    taper_block_rows: int | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise InputError(f"structure kind {self.kind!r} is not one of {', '.join(KINDS)}")
        if not (isinstance(self.lines, int) and 1 <= self.lines <= MAX_ARCH_WIDE):
            raise InputError(f"structure lines={self.lines!r} outside 1..{MAX_ARCH_WIDE} (at most 8 wide)")
        if not (isinstance(self.layers, int) and 1 <= self.layers <= MAX_ARCH_HIGH):
            raise InputError(f"structure layers={self.layers!r} outside 1..{MAX_ARCH_HIGH} (at most 4 high)")
        if self.arrangement not in ARRANGEMENTS:
            raise InputError(f"arrangement {self.arrangement!r} is not one of {', '.join(ARRANGEMENTS)}")
        if self.kind == "line" and (self.lines, self.layers) != (1, 1):
            raise InputError(f"a line structure is 1 x 1, got {self.lines} x {self.layers}")
        if self.kind == "two_line" and (self.lines, self.layers) != (2, 1):
            raise InputError(f"a two_line structure is 2 x 1, got {self.lines} x {self.layers}")
        if self.kind == "arch" and self.layers < 2:
            raise InputError(f"an arch has at least 2 layers, got {self.layers}")
        b = self.taper_block_rows
        if b is not None:
            if self.kind != "arch":
                raise InputError(f"only an arch can taper: structure kind {self.kind!r} with taper_block_rows={b!r}")
            if not (isinstance(b, int) and not isinstance(b, bool) and 1 <= b <= 50):
                raise InputError(f"taper_block_rows={b!r} outside 1..50 (rows per block of the tapering feet)")
            if self.lines != 2 * self.layers:
                raise InputError(f"a tapering arch is 2k wide and k high, got {self.lines} x {self.layers}")
            if self.arrangement != "aligned":
                raise InputError(f"a tapering arch's lines are aligned, got arrangement {self.arrangement!r}")

    @property
    def tapered(self) -> bool:
        return self.taper_block_rows is not None

    @property
    def foot_rows(self) -> int:
        """Rows of one tapering foot on its ground (``layers`` blocks; the last one bare core)."""
        if not self.tapered:
            raise InputError(f"structure {self.name} does not taper: it has no feet")
        return self.layers * self.taper_block_rows

    def tapered_robots(self, void_rows: int, far_foot: bool = True) -> dict[str, int]:
        """The thesis's count of the tapering arch over ``void_rows`` (see `limits.tapered_arch_robots`)."""
        if not self.tapered:
            raise InputError(f"structure {self.name} does not taper")
        return tapered_arch_robots(self.layers, self.taper_block_rows, void_rows, far_foot)

    @property
    def name(self) -> str:
        if self.tapered:
            return f"tapered-arch-{self.lines}x{self.layers}-b{self.taper_block_rows}"
        if self.kind == "line":
            return "line"
        tag = "" if self.lines == 1 else f"-{self.arrangement}"
        if self.kind == "two_line":
            return f"two_line{tag}"
        return f"arch-{self.lines}x{self.layers}{tag}"

    @property
    def parity_counts(self) -> tuple[int, int]:
        """Robots per row in the planar body groups (offset 0, offset half a pitch)."""
        if self.arrangement == "staggered" and self.lines > 1:
            return (self.lines + 1) // 2, self.lines // 2
        return self.lines, 0

    def robots(self, rows: int) -> int:
        """Robots in a structure ``rows`` long (offset lines have one robot fewer per line)."""
        if self.tapered:
            raise InputError(f"{self.name}: a tapering arch's count depends on the void, see tapered_robots")
        n0, n1 = self.parity_counts
        return self.layers * (rows * n0 + max(rows - 1, 0) * n1)

    def check_connectors(self, conn: ConnectorSet, robot: str) -> None:
        if self.lines > 1 and conn.side_rail is None:
            raise InputError(f"structure {self.name}: robot {robot!r} has no side_rail connector to join lines")
        if self.layers > 1 and conn.top_twist is None:
            raise InputError(f"structure {self.name}: robot {robot!r} has no top_twist connector to stack layers")


@dataclass(frozen=True)
class Body:
    """One planar body: ``count`` robots merged; ``x_m``, ``z_m`` of the footprint centre underside."""

    layer: int
    parity: int
    row: int
    count: int
    x_m: float
    z_m: float
    mass_kg: float
    inertia_kg_m2: float
    com_local_m: tuple[float, float]

    @property
    def com_m(self) -> tuple[float, float]:
        return self.x_m + self.com_local_m[0], self.z_m + self.com_local_m[1]


@dataclass(frozen=True)
class Coupling:
    """A joint between bodies ``a`` and ``b`` at global point ``point_m``; ``count`` couplings in parallel."""

    a: int
    b: int
    point_m: tuple[float, float]
    joint: Joint
    count: int
    role: str  # "front_rear" | "side_rail" | "top_twist"


@dataclass(frozen=True)
class Support:
    """A one-sided support under body ``body`` at global point ``point_m``: on the ``"near"`` or
    ``"far"`` ledge, or (``ledge == "pier"``) on the top of pier number ``pier`` of the layout."""

    body: int
    point_m: tuple[float, float]
    ledge: str
    pier: int | None = None


@dataclass(frozen=True)
class Pier:
    """An elastic column standing on the void floor with its top at the ledge height (z = 0).

    ``at_widths``: its near face, in robot pitches from the near edge (x = 0); ``width_widths``:
    its width along the void in robot lengths (a stack of robots: 1); ``stiffness_n_per_m``: the
    vertical stiffness of the whole column, top to floor (``structure_fem.analysis.piers.pier_stiffness``
    for a stack of robots); ``robots``: how many robots it is made of (0: not a robot stack,
    informational); ``mass_kg``: its mass (carried by the floor; only the static solver's
    stabiliser sees it). The structure rests on its top through one-sided contacts like the
    ledge's, so a pier can only push up. Its top stays level and does not move along the void:
    the pier's rocking, sway and buckling are not modelled.
    """

    at_widths: float
    stiffness_n_per_m: float
    width_widths: float = 1.0
    robots: int = 0
    mass_kg: float = 0.0

    def __post_init__(self) -> None:
        for name in ("at_widths", "width_widths", "stiffness_n_per_m", "mass_kg"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise InputError(f"pier {name}={v!r} is not a finite number")
        if self.at_widths <= 0:
            raise InputError(f"pier at {self.at_widths:g} robot widths: a pier stands inside the void "
                             "(position > 0 from the near edge)")
        if self.width_widths <= 0:
            raise InputError(f"pier width {self.width_widths:g} robot widths must be > 0")
        if self.stiffness_n_per_m <= 0:
            raise InputError(f"pier stiffness {self.stiffness_n_per_m:g} N/m must be > 0")
        if self.mass_kg < 0:
            raise InputError(f"pier mass {self.mass_kg:g} kg must be >= 0")

    def x_range_m(self, pitch_m: float, length_m: float) -> tuple[float, float]:
        """Near and far face (m from the near edge)."""
        x0 = self.at_widths * pitch_m
        return x0, x0 + self.width_widths * length_m


def check_piers(piers: tuple[Pier, ...], void_widths: float, pitch_m: float, length_m: float) -> None:
    """Piers inside the void (far face short of the far edge), in order, not overlapping."""
    void = void_widths * pitch_m
    last = 0.0
    for i, p in enumerate(piers):
        if not isinstance(p, Pier):
            raise InputError(f"pier {i + 1}: expected a Pier, got {p!r}")
        x0, x1 = p.x_range_m(pitch_m, length_m)
        if x1 >= void - 1e-9:
            raise InputError(f"pier at {p.at_widths:g} robot widths ({p.width_widths:g} wide) reaches beyond the "
                             f"{void_widths:g}-wide void")
        if x0 < last - 1e-9:
            raise InputError(f"pier at {p.at_widths:g} robot widths overlaps the pier before it (or the piers "
                             "are not in order from the near edge)")
        last = x1


@dataclass(frozen=True)
class Layout:
    bodies: tuple[Body, ...]
    couplings: tuple[Coupling, ...]
    supports: tuple[Support, ...]
    front_body: int
    rear_body: int
    length_m: float
    pitch_m: float
    void_m: float
    #: Intermediate supports (:class:`Pier`), in order from the near edge.
    piers: tuple[Pier, ...] = ()
    #: Where the robots touch the ground (:class:`~structure_fem.model.contacts.GroundSupport`; None:
    #: body corners, as a layout built before contacts existed).
    ground: GroundSupport | None = None
    #: The robot's height (m): a layer's underside sits ``height_m`` above the one below, and a
    #: front-rear coupling's faces span it (the emergent hinge's top edge, :mod:`structure_fem.model.hinge`).
    height_m: float = 0.0
    #: How couplings whose faces touch are modelled (``ConnectorSet.hinge``).
    hinge: str = "emergent"

    def pier_range_m(self, i: int) -> tuple[float, float]:
        return self.piers[i].x_range_m(self.pitch_m, self.length_m)


def layout(structure: Structure, robot: RobotProperties, conn: ConnectorSet, rows: int,
           rows_over: float, void_widths: float, phase: str = "cantilever",
           piers: tuple[Pier, ...] = ()) -> Layout:
    """Place a ``rows``-long structure with its front face ``rows_over`` pitches past the
    near edge (x = 0) of a void ``void_widths`` robot lengths wide.

    ``phase="cantilever"``: only the near ledge (x <= 0) supports the structure
    (the front has not reached the far ledge; ``rows_over <= void_widths``);
    ``"bridged"``: bodies whose centre is beyond the far edge rest on it too.
    Supports sit where the robots touch the ground (:func:`structure_fem.model.contacts.ground_support`):
    at the wheel and caster contacts of layer-0 bodies that are over a ledge, at their depth
    below the underside (a contact exactly at the edge is leaving it as the structure advances,
    and does not count: the staggered line's wheels sit exactly at the edge at whole rows); for a robot without contacts (flat underside, e.g. the test platform) under the
    two bottom corners of every body whose centre is over a ledge, at the corners that are over
    that ledge.

    ``piers`` (:class:`Pier`, uniform structures only): a layer-0 body rests on a pier's top at
    each of its contacts over the top (a contact exactly at a face does not count, as at a ledge); without contacts, at both ends of the
    overlap of its underside with the top (both corners for a body right over a one-robot-wide
    pier; a body that only touches the pier's face at a corner does not rest on it).

    A tapering structure (``structure.tapered``) is placed by :func:`tapered_layout`.
    """
    if structure.tapered:
        if piers:
            raise InputError(f"{structure.name}: piers under a tapering arch are not modelled")
        return tapered_layout(structure, robot, conn, rows, rows_over, void_widths, phase)
    if not (isinstance(rows, int) and rows >= 1):
        raise InputError(f"rows must be an integer >= 1, got {rows!r}")
    if not (math.isfinite(void_widths) and void_widths > 0):
        raise InputError(f"void width must be > 0 robot widths, got {void_widths!r}")
    if phase not in PHASES:
        raise InputError(f"phase {phase!r} is not one of {', '.join(PHASES)}")
    if not (math.isfinite(rows_over) and 0 <= rows_over <= rows):
        raise InputError(f"rows_over={rows_over!r} outside 0..{rows}")
    structure.check_connectors(conn, robot.name)
    fr = conn.front_rear
    L, H = robot.length_m, robot.height_m
    pitch = L + fr.gap_m
    void = void_widths * pitch
    if phase == "cantilever" and rows_over > void_widths + 1e-9:
        raise InputError(f"cantilever with {rows_over} rows over a {void_widths}-wide void: front is past the far ledge")
    x_front = rows_over * pitch
    iyy = robot.inertia_kg_m2[1]
    com_local = (robot.com_m[0], robot.com_m[2])
    n0, n1 = structure.parity_counts

    bodies: list[Body] = []
    index: dict[tuple[int, int, int], int] = {}
    for k in range(structure.layers):
        for parity, n in ((0, n0), (1, n1)):
            if n == 0:
                continue
            nrows = rows if parity == 0 else rows - 1
            for j in range(nrows):
                xc = x_front - pitch * j - L / 2 - parity * pitch / 2
                index[(k, parity, j)] = len(bodies)
                bodies.append(Body(k, parity, j, n, xc, k * H, n * robot.mass_kg, n * iyy, com_local))

    couplings: list[Coupling] = []
    for (k, parity, j), a in index.items():
        n = n0 if parity == 0 else n1
        b = index.get((k, parity, j + 1))  # the row behind
        if b is not None:
            xj = bodies[a].x_m - L / 2 - fr.gap_m / 2
            couplings.append(Coupling(b, a, (xj, k * H + fr.height_m), fr, n, "front_rear"))
        up = index.get((k + 1, parity, j))
        if up is not None:
            tw = conn.top_twist
            couplings.append(Coupling(a, up, (bodies[a].x_m, (k + 1) * H), tw, n, "top_twist"))
        if parity == 1:
            rail = conn.side_rail
            pairs = structure.lines - 1  # neighbouring line pairs, each with a rail
            for jj in (j, j + 1):  # the offset body overlaps even-line rows j and j + 1
                c = index[(k, 0, jj)]
                xo = 0.5 * (bodies[a].x_m + bodies[c].x_m)
                couplings.append(Coupling(c, a, (xo, k * H + rail.height_m), rail, pairs, "side_rail"))

    piers = tuple(piers)
    check_piers(piers, void_widths, pitch, L)
    ground = ground_support(robot)
    supports = (_ledge_supports(bodies, L, void, phase, ground)
                + _pier_supports(bodies, L, pitch, piers, ground))
    if not any(s.ledge == "near" for s in supports):
        raise InputError(f"{structure.name}: no row of the {rows}-row structure rests on the near ledge "
                         f"with {rows_over} rows over the void")
    front = index[(0, 0, 0)]
    rear = index[(0, 0, rows - 1)]
    return Layout(tuple(bodies), tuple(couplings), tuple(supports), front, rear, L, pitch, void, piers, ground,
                  height_m=H, hinge=conn.hinge)


def _pier_supports(bodies: list[Body], L: float, pitch: float, piers: tuple[Pier, ...],
                   ground: GroundSupport | None = None) -> list[Support]:
    """Supports of layer-0 bodies on the pier tops: at the contacts strictly over a top,
    or, for a flat underside (``ground`` is None or corners), at both ends of the overlap of the
    underside with the top."""
    out: list[Support] = []
    tol = 1e-9
    contacts = ground is not None and ground.kind == "contacts"
    for k, p in enumerate(piers):
        x0, x1 = p.x_range_m(pitch, L)
        for i, bd in enumerate(bodies):
            if bd.layer != 0:
                continue
            if contacts:
                for cx, cz in ground.points:
                    x = bd.x_m + cx
                    if x0 + tol < x < x1 - tol:
                        out.append(Support(i, (x, cz), "pier", k))
                continue
            a, b = max(bd.x_m - L / 2, x0), min(bd.x_m + L / 2, x1)
            if b - a > tol:
                out += [Support(i, (a, 0.0), "pier", k), Support(i, (b, 0.0), "pier", k)]
    return out


def _ledge_supports(bodies: list[Body], L: float, void: float, phase: str,
                    ground: GroundSupport | None = None) -> list[Support]:
    """Ledge supports of layer-0 bodies: at their contacts strictly over a ledge (one exactly at
    the edge is leaving it), or, for a flat underside (``ground`` is None
    or corners), under the bottom corners (over a ledge) of bodies whose centre is over it."""
    supports: list[Support] = []
    tol = 1e-9
    if ground is not None and ground.kind == "contacts":
        for i, bd in enumerate(bodies):
            if bd.layer != 0:
                continue
            for cx, cz in ground.points:
                x = bd.x_m + cx
                if x < -tol:
                    supports.append(Support(i, (x, cz), "near"))
                elif phase == "bridged" and x > void + tol:
                    supports.append(Support(i, (x, cz), "far"))
        return supports
    for i, bd in enumerate(bodies):
        if bd.layer != 0:
            continue
        corners = (bd.x_m - L / 2, bd.x_m + L / 2)
        if bd.x_m < 0:
            for cx in corners:
                if cx <= tol:
                    supports.append(Support(i, (cx, 0.0), "near"))
        elif phase == "bridged" and bd.x_m > void:
            for cx in corners:
                if cx >= void - tol:
                    supports.append(Support(i, (cx, 0.0), "far"))
    return supports


def _whole(name: str, v: float) -> int:
    if not (isinstance(v, (int, float)) and math.isfinite(v) and float(v).is_integer()):
        raise InputError(f"a tapering arch needs a whole number of rows for {name}, got {v!r}")
    return int(v)


def tapered_layout(structure: Structure, robot: RobotProperties, conn: ConnectorSet, rows: int,
                   rows_over: float, void_widths: float, phase: str = "cantilever") -> Layout:
    """Planar layout of the thesis's tapering arch (Ch. 5.5.2): ``rows`` rows of the core, its
    front ``rows_over`` pitches past the near edge of a ``void_widths``-wide void (whole rows).

    Row ``i`` occupies ``[i, i + 1)`` pitches past the near edge (negative: initial ground);
    its half-level ``j = taper_half_level(k, B, i, w, far_foot=phase == "bridged")`` makes a
    section ``2j`` robots wide and ``j`` high (``j = 1``: the bare two-line core; behind the
    near foot the core is bare). Each (row, layer) is one planar body merging its ``2j``
    aligned robots (the mid-plane symmetry of the module docstring); front-rear couplings
    join consecutive rows of a layer, ``min(2 j_i, 2 j_{i+1})`` of them (robots with a
    neighbour in both rows); top twist-locks join a layer to the one above, one per robot of
    the upper layer; ledge supports as in :func:`layout`.

    ``"cantilever"`` (before landing): near foot only, the core front at ``g = rows_over <= w``
    and at least ``k B`` rows on the initial ground (the thesis keeps exactly ``k B``: its
    "28a" for k = 3). ``"bridged"``: both feet, the core front past the far foot
    (``rows_over >= w + k B``). Shell rows of a foot beyond the core front are not placed.
    """
    if phase not in PHASES:
        raise InputError(f"phase {phase!r} is not one of {', '.join(PHASES)}")
    if not (isinstance(rows, int) and rows >= 1):
        raise InputError(f"rows must be an integer >= 1, got {rows!r}")
    w = _whole("the void width", void_widths)
    g = _whole("rows over the void", rows_over)
    if w < 1:
        raise InputError(f"void width must be > 0 robot widths, got {void_widths!r}")
    structure.check_connectors(conn, robot.name)
    k, b = structure.layers, structure.taper_block_rows
    foot = structure.foot_rows
    if rows - g < foot:
        raise InputError(f"{structure.name}: the core must keep at least {foot} rows (k x B) on the initial "
                         f"ground, got {rows - g} ({rows} rows, {g} over the void)")
    if phase == "cantilever" and not 1 <= g <= w:
        raise InputError(f"{structure.name} before landing: core front {g} rows past the near edge is outside "
                         f"1..{w} (the void width)")
    if phase == "bridged" and g < w + foot:
        raise InputError(f"{structure.name} bridged: the core front must be past the far foot, "
                         f"rows_over >= {w + foot}, got {g}")
    fr = conn.front_rear
    L, H = robot.length_m, robot.height_m
    pitch = L + fr.gap_m
    void = w * pitch
    iyy = robot.inertia_kg_m2[1]
    com_local = (robot.com_m[0], robot.com_m[2])
    far = phase == "bridged"

    bodies: list[Body] = []
    index: dict[tuple[int, int], int] = {}  # (layer, row i) -> body
    half: dict[int, int] = {}
    for i in range(g - rows, g):
        j = taper_half_level(k, b, i, w, far_foot=far)
        half[i] = j
        xc = (i + 1) * pitch - L / 2
        for layer in range(j):
            index[(layer, i)] = len(bodies)
            n = 2 * j
            bodies.append(Body(layer, 0, g - 1 - i, n, xc, layer * H, n * robot.mass_kg, n * iyy, com_local))

    couplings: list[Coupling] = []
    for (layer, i), a in index.items():
        behind = index.get((layer, i - 1))
        if behind is not None:
            xj = bodies[a].x_m - L / 2 - fr.gap_m / 2
            n = 2 * min(half[i], half[i - 1])
            couplings.append(Coupling(behind, a, (xj, layer * H + fr.height_m), fr, n, "front_rear"))
        up = index.get((layer + 1, i))
        if up is not None:
            couplings.append(Coupling(a, up, (bodies[a].x_m, (layer + 1) * H), conn.top_twist, 2 * half[i],
                                      "top_twist"))

    ground = ground_support(robot)
    supports = _ledge_supports(bodies, L, void, phase, ground)
    if not any(s.ledge == "near" for s in supports):  # pragma: no cover - rows - g >= k B >= 1 rests
        raise InputError(f"{structure.name}: no row rests on the near ledge")
    return Layout(tuple(bodies), tuple(couplings), tuple(supports), index[(0, g - 1)], index[(0, g - rows)],
                  L, pitch, void, ground=ground, height_m=H, hinge=conn.hinge)


def tipping_edge(lay: Layout) -> float:
    """The line the structure tips about: its front-most support that is not on the far ledge,
    i.e. the front-most wheel / caster contact on the near ledge (the body corner at the edge,
    x = 0, for a robot without contacts), or, when the structure rests on a pier, the front-most
    contact on the last pier it is on (without contacts: that pier's far face)."""
    on_pier = [sp.point_m[0] for sp in lay.supports if sp.pier is not None]
    if on_pier:
        return max(on_pier)
    if lay.ground is None or lay.ground.kind != "contacts":
        return 0.0  # a flat underside tips about the ledge edge
    on = [sp.point_m[0] for sp in lay.supports if sp.ledge == "near"]
    return max(on) if on else 0.0


def rigid_tipping(lay: Layout) -> float:
    """The tipping factor of the undeformed layout about :func:`tipping_edge`."""
    return tipping_factor(lay.bodies, [b.com_m[0] for b in lay.bodies], tipping_edge(lay))


def _mass_moments(bodies: tuple[Body, ...], com_x: np.ndarray, edge_x: float) -> tuple[float, float]:
    """Mass moments (kg m) about ``edge_x``: (behind it, beyond it)."""
    m = np.array([b.mass_kg for b in bodies])
    arm = np.asarray(com_x) - edge_x
    return float(np.sum(m * np.clip(-arm, 0, None))), float(np.sum(m * np.clip(arm, 0, None)))


def gravity_moments(bodies: tuple[Body, ...], com_x: np.ndarray, edge_x: float = 0.0) -> tuple[float, float]:
    """Gravity moments (N m) about the tipping line ``edge_x``: (restoring, overturning), of the
    bodies whose centre of mass is behind it and of those beyond it."""
    back, over = _mass_moments(bodies, com_x, edge_x)
    return GRAVITY * back, GRAVITY * over


def tipping_factor(bodies: tuple[Body, ...], com_x: np.ndarray, edge_x: float = 0.0) -> float:
    """Restoring over overturning gravity moment about the tipping line ``edge_x`` (>1: stands;
    :func:`tipping_edge` says where it is: the front-most near-ledge contact).

    Bodies with their centre of mass behind the edge restore, those beyond it
    overturn (:func:`gravity_moments`). With nothing beyond the edge the factor is infinite,
    returned as ``math.inf`` (tables print it as "-", never NaN).
    """
    back, over = _mass_moments(bodies, com_x, edge_x)
    return math.inf if over <= 0 else back / over
