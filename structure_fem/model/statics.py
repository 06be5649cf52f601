"""The exudyn model of a docked-robot structure and its static solution (SI units).

:func:`solve` is a function of typed inputs -> :class:`StaticResult`:

* each planar body (robots merged as :mod:`structure_fem.model.structures` explains)
  is an ``ObjectRigidBody2D`` at its centre of mass with the robots' summed
  mass and pitch inertia Iyy from ``robot_properties.json``;
* a coupling whose faces touch (the CuBot's front-rear coupling, every layer's twist-lock) is,
  with ``ConnectorSet.hinge == "emergent"`` (the default), built from its parts by :mod:`structure_fem.model.hinge`: tension rows with their play
  and compression-only face contacts, so its hinge and rotational play emerge. Otherwise
  (``"lumped"``, and the couplings whose faces do not touch)
  each coupling is a *penalty* connector, because Lagrange-multiplier joints
  stop converging once rotations grow (toolchain notes): an
  ``ObjectConnectorCartesianSpringDamper`` for the pin (axial stiffness in
  x and z) plus an ``ObjectConnectorCoordinateSpringDamper`` between the two
  bodies' rotations with the smooth dead-band moment
  (:func:`structure_fem.model.connectors.dead_band_moment`) as its user function.
  The smoothing ``e`` is chosen so a joint carrying one body's weight moment
  ``m g L`` sits within 1 % of the play of the sharp band edge, and a weak
  linear spring (at most 1 % of ``m g L`` at the band edge) gives an unloaded
  joint inside its play a defined angle (without it, redundant couplings in
  large arches leave the Jacobian singular). The formula is compiled to an
  exudyn symbolic user function (C++; identical results, ~20 % faster tables);
* each ledge support is a one-sided spring ``f_z = k_c min(dz, 0)``, smoothed
  over ``CONTACT_SMOOTHING_M``, where the robot touches the ground: at each wheel and caster
  contact over the ledge (``ground_contacts`` of the robot record, at their depth below the
  underside; :mod:`structure_fem.model.contacts`), or under a bottom corner for a robot without
  contacts (Python user function; ``k_c`` per contact point and robot); one bilateral horizontal
  spring at the rearmost support fixes the rigid-body x drift (gravity has no x part);
* a pier (:class:`structure_fem.model.structures.Pier`, ``Config.piers``) is a point node at the
  centre of its top (``NodePoint2D`` + ``ObjectMassPoint2D``, no gravity on it: the pier's own
  weight goes to the floor) held to the ground by a bilateral spring of the pier's vertical
  stiffness (the column is elastic both ways); the structure rests on that node through the
  same one-sided contact springs as on a ledge, so the pier can only push up. The top does not
  tilt (one node, no rotation) and its horizontal spring only fixes the node (the contacts are
  frictionless: no horizontal force reaches the pier);
* gravity is ramped over load steps by the static solver; the solver
  settings are the ones the toolchain notes found to matter. While the load is
  small every joint slides through its play, where its tangent stiffness is only
  the weak in-band spring (~1e-4 of the coupling's): a plain ramp then lets Newton
  swing the joints far past the sharp band edges, and it cycled (``fem table
  --clearance-mm 40``, robot mass x0.5, play x4 on the CuBot). So the dead bands
  start smoothed over 10x their half-width and relax to the model's smoothing as
  the load factor reaches 1 (:class:`SolverOptions`): the returned state is an
  equilibrium of the model itself (the same as the plain ramp's wherever both
  converge, to 1e-7 in the tests; near tipping, balanced on the ledge edge with
  the rear unloaded, the play admits more than one and the path can pick another).

``flexible=True`` (the table's default, :mod:`structure_fem.model.bodies`) adds each robot's own
bending compliance ``L / (E I)`` (printed material modulus, the printed shell's section cut
from the CAD, ``RobotProperties.body_second_moment_m4``) in series with the couplings, half a robot on each
side of every front-rear joint: a lumped beam whose curvature sits at the
joints, exact for the joints' moment when the robots are short compared with
the span, enough to show (as Eq. 7.1 suggests) whether body bending matters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from cubot_cad.properties import RobotProperties
from structure_fem.errors import InputError, SolverFailure
from structure_fem.model.connectors import SMOOTHING, ConnectorSet, band_force, dead_band_moment
from structure_fem.model.hinge import add_links, along_factor, emergent
from structure_fem.model.structures import (
    GRAVITY,
    Layout,
    Pier,
    Structure,
    gravity_moments,
    layout,
    tipping_edge,
    tipping_factor,
)

#: Ledge contact stiffness per support point (N/m): stiff against the couplings, not ill-conditioned.
CONTACT_N_PER_M = 2.0e6
#: Smoothing length of the one-sided contact (m): f = k/2 (dz - sqrt(dz^2 + e^2)), i.e. k min(dz, 0)
#: to within k e / 2 (10 mN at 2e6 N/m); a sharp min() makes Newton cycle between contact sets.
CONTACT_SMOOTHING_M = 1e-8


@dataclass(frozen=True)
class Config:
    """One static configuration: which structure, how long, where over which void."""

    structure: Structure
    rows: int
    rows_over: float
    void_widths: float
    phase: str = "cantilever"
    #: Supports hold in both directions (a clamped root, as in a bench test), not one-sided.
    clamped: bool = False
    #: Intermediate supports (:class:`~structure_fem.model.structures.Pier`), in order from the near edge.
    piers: tuple[Pier, ...] = ()
    #: The rearmost support holds both ways (the rest stay one-sided): the solve
    #: :func:`solve_uncached` falls back on when the free structure finds no equilibrium, to tell
    #: a structure that tips (the anchor has to pull it down) from a solver that failed.
    anchored: bool = False
    #: A vertical load (N, downward) hung at the front end of the front body's underside: the
    #: weights of a coupling bench test (:mod:`structure_fem.analysis.bench_test`); 0 in every table.
    tip_load_n: float = 0.0

    def describe(self, robot: str = "") -> str:
        who = f"{robot} " if robot else ""
        on = f", {self.tip_load_n:g} N hung at the tip" if self.tip_load_n else ""
        if self.piers:
            on += ", piers at " + ", ".join(f"{p.at_widths:g}" + (f" ({p.robots} robots)" if p.robots else "")
                                           for p in self.piers)
        return (f"{who}{self.structure.name} {self.rows} rows, {self.rows_over:g} over a "
                f"{self.void_widths:g}-wide void ({self.phase}{on})")


@dataclass(frozen=True)
class SolverOptions:
    """Static solver settings (see the module docstring and ``docs/structure_fem.md``).

    ``smoothing_start`` / ``smoothing_power``: smoothing continuation of the dead bands. At
    load factor ``t`` (the static solver's load-step time, 0 -> 1) every dead band is smoothed
    over ``e(t) = e + (smoothing_start * h - e) (1 - t)^smoothing_power`` instead of the model's
    ``e``: while gravity is small, and the joints slide through their play, the band is a smooth
    softening spring; by ``t`` of about 0.3 it is the model's band, and at ``t = 1`` exactly
    (the reported solution) it is ``e``. ``smoothing_start = 0`` switches it off.
    """

    load_steps: int = 8
    absolute_tolerance: float = 1e-6
    relative_tolerance: float = 1e-6
    max_iterations: int = 40
    contact_n_per_m: float = CONTACT_N_PER_M
    smoothing_start: float = 10.0
    smoothing_power: int = 20


@dataclass(frozen=True)
class StaticResult:
    """Deflected shape and derived facts of one configuration (SI units, z up).

    ``com_m``: (n, 2) deflected centres of mass; ``rotation_rad``: (n,) body
    pitch (positive nose up); ``underside_m``: (n, 2, 2) deflected bottom
    rear/front corners per body; ``tip_deflection_m``: how far the front-most
    bottom corner dropped (positive down); ``joint_rotation_rad``: relative
    rotation of each front-rear coupling (front minus rear); ``reactions_n``:
    vertical force at each support; ``tipping_factor``: restoring / overturning
    gravity moment about the tipping line (inf when nothing overhangs): the front-most
    wheel / caster contact on the near ledge (the near edge for a robot without contacts),
    or, when the structure rests on a pier, the front-most support point on it
    (:func:`structure_fem.model.structures.tipping_edge`); ``pier_compression_m``: how far each pier's top
    went down (positive: compressed).
    """

    config: Config
    layout: Layout
    com_m: np.ndarray
    rotation_rad: np.ndarray
    underside_m: np.ndarray
    tip_deflection_m: float
    max_deflection_m: float
    joint_rotation_rad: np.ndarray
    reactions_n: np.ndarray
    tipping_factor: float
    robots: int
    pier_compression_m: tuple[float, ...] = ()
    #: How hard (N) the rearmost support had to pull the structure down for it to stand: > 0 only
    #: when the free structure has no equilibrium and tips (:func:`_anchored`).
    anchor_pull_n: float = 0.0

    @property
    def tip_deflection_mm(self) -> float:
        return 1e3 * self.tip_deflection_m

    @property
    def pier_loads_n(self) -> tuple[float, ...]:
        """The vertical force each pier carries (the sum of its contacts' reactions)."""
        out = [0.0] * len(self.layout.piers)
        for f, sp in zip(self.reactions_n, self.layout.supports, strict=True):
            if sp.pier is not None:
                out[sp.pier] += float(f)
        return tuple(out)

    @property
    def tipping_edge_m(self) -> float:
        """x of the line the tipping factor is taken about (0: the near edge)."""
        return tipping_edge(self.layout)

    @property
    def total_weight_n(self) -> float:
        return GRAVITY * sum(b.mass_kg for b in self.layout.bodies)


def _flexible(conn: ConnectorSet, robot: RobotProperties) -> ConnectorSet:
    """Add half a robot's bending compliance on each side of every front-rear joint
    (:func:`structure_fem.model.bodies.with_body_bending`: the CAD's section, one home for ``E I``)."""
    from structure_fem.model.bodies import with_body_bending

    return with_body_bending(conn, robot)


def solve(config: Config, robot: RobotProperties, conn: ConnectorSet | None = None,
          flexible: bool = False, options: SolverOptions = SolverOptions()) -> StaticResult:
    """Build the exudyn system for ``config`` and solve it statically (:func:`solve_uncached`),
    through the solve cache (:mod:`structure_fem.solve_cache`: the result or the failure, by a
    hash of the inputs and of the model's code; ``VOIDCROSS_SOLVE_CACHE=0`` turns it off)."""
    from structure_fem.solve_cache import cached_solve

    if conn is None:
        conn = ConnectorSet.from_robot(robot)
    return cached_solve(solve_uncached, SolverFailure, config, robot, conn, flexible, options)


def solve_uncached(config: Config, robot: RobotProperties, conn: ConnectorSet | None = None,
                   flexible: bool = False, options: SolverOptions = SolverOptions()) -> StaticResult:
    """Build the exudyn system for ``config`` and solve it statically.

    The first run ramps gravity with the dead-band smoothing continuation of
    ``options`` (:class:`SolverOptions`). A failed run is retried with 4x the
    load steps and a 100x looser relative tolerance (very stiff pins leave a
    round-off floor), then without the continuation (the plain gravity ramp)
    with the given, 4x and 1/4 the load steps, then the continuation from a 3x wider and a 3x
    narrower start and with a faster relaxation: near tipping, where the structure
    balances on the ledge edge, the adaptive step control stalls on one path and
    not another. A solution with a body turned past 90 degrees (upside down over
    the edge, not a state the structure can reach) is not accepted. If all fail,
    raises :class:`SolverFailure` naming the configuration.
    """
    if conn is None:
        conn = ConnectorSet.from_robot(robot)
    if flexible:
        conn = _flexible(conn, robot)
    loose = 100 * options.relative_tolerance  # stiff pins (1e8 N/m) put a round-off floor near 1e-8
    plain = replace(options, smoothing_start=0.0)
    n = options.load_steps
    attempts = (options, replace(options, load_steps=4 * n, relative_tolerance=loose),
                plain, replace(plain, load_steps=4 * n, relative_tolerance=loose),
                replace(plain, load_steps=max(2, n // 4), relative_tolerance=loose))
    if options.smoothing_start > 0:  # the continuation along other paths: wider / narrower, faster relaxing
        attempts += (replace(options, smoothing_start=3.0 * options.smoothing_start, load_steps=4 * n,
                             relative_tolerance=loose),
                     replace(options, smoothing_start=options.smoothing_start / 3.0, load_steps=4 * n,
                             relative_tolerance=loose),
                     replace(options, smoothing_power=max(1, options.smoothing_power // 2), load_steps=8 * n,
                             relative_tolerance=loose))
    last: SolverFailure | None = None
    for opt in attempts:
        try:
            return _solve_once(config, robot, conn, opt)
        except SolverFailure as exc:
            last = exc
    anchored = _anchored(config, robot, conn, options)
    if anchored is not None:
        return anchored
    tried = ", ".join(f"{o.load_steps}{'' if o.smoothing_start else ' plain'}"
                      + (f" (smoothing {o.smoothing_start:g}x/{o.smoothing_power})"
                         if o.smoothing_start and (o.smoothing_start, o.smoothing_power) !=
                         (options.smoothing_start, options.smoothing_power) else "") for o in attempts[1:])
    raise SolverFailure(f"{last} (also retried with {tried} load steps)")


def _anchored(config: Config, robot: RobotProperties, conn: ConnectorSet,
              options: SolverOptions) -> StaticResult | None:
    """The free structure found no equilibrium: solve it again with its rearmost support
    holding both ways. If that support then pushes (or carries nothing), the anchored state is
    an equilibrium of the free structure too (every one-sided contact in compression): it is
    returned as the solution. If it has to pull the structure down, the free structure has no
    equilibrium: it tips about its front-most support, and the state is returned with its
    tipping factor set to the restoring over the overturning moment with the anchor's pull taken
    out of the restoring side (below 1; ``anchor_pull_n`` says by how much it pulled). None when
    the anchored solve fails too (or the structure is clamped, or not a cantilever)."""
    if config.clamped or config.anchored or config.phase != "cantilever":
        return None
    cfg = replace(config, anchored=True)
    n = options.load_steps
    for opt in (options, replace(options, load_steps=4 * n, relative_tolerance=100 * options.relative_tolerance)):
        try:
            res = _solve_once(cfg, robot, conn, opt)
        except SolverFailure:
            continue
        lay = res.layout
        rear = min(range(len(lay.supports)), key=lambda i: lay.supports[i].point_m[0])
        pull = max(0.0, -float(res.reactions_n[rear]))
        if pull <= ANCHOR_PULL_TOLERANCE * res.total_weight_n:
            return replace(res, config=config)
        edge = tipping_edge(lay)
        arm = edge - float(lay.supports[rear].point_m[0])  # > 0: the anchor is behind the edge
        restoring, overturning = gravity_moments(lay.bodies, res.com_m[:, 0], edge)
        tf = max(0.0, restoring - pull * arm) / overturning if overturning > 0 else 0.0
        return replace(res, config=config, tipping_factor=min(tf, res.tipping_factor), anchor_pull_n=pull)
    return None


#: An anchored rear pulling less than this fraction of the structure's weight counts as carrying
#: nothing (the contact's smoothing leaves a residual of millinewtons).
ANCHOR_PULL_TOLERANCE = 1e-4


#: A converged state with a body turned further than this (rad) is spurious: upside down.
MAX_BODY_ROTATION_RAD = 0.5 * math.pi
#: ... or with two coupled bodies turned further than this (rad) relative to each other. A coupling
#: turns by its play (10-15 mrad on the CuBot's front-rear pins) plus elastic milliradians; half a
#: radian would stretch a pin 26.5 mm above the underside by 13 mm, tearing it out, and the
#: penalty contacts (written for small relative turns) no longer keep the bodies apart. Found on
#: the emergent hinge: a line one row short of standing "converged" to bodies turned +-90 deg,
#: jack-knifed over the edge, with a tipping factor of 1.9 (tests/structure_fem/test_never_crash.py).
MAX_JOINT_ROTATION_RAD = 0.5


#: Compile the dead-band user functions to exudyn symbolic (C++) functions: same formula,
#: no Python call per Newton evaluation (a large arch calls it millions of times).
SYMBOLIC = True


def _dead_band_uf(mbs, h: float, e: float, k_reg: float, keep: list, e0: float = 0.0, power: int = 20):
    """The coupling's moment: smooth dead band of half-width ``h`` + ``k_reg`` u, smoothed over
    ``e`` at load factor ``t = 1``; with ``e0 > e`` the smoothing starts at ``e0`` and relaxes to
    ``e`` as ``e + (e0 - e) (1 - t)^power`` (see :class:`SolverOptions`)."""
    ramp = e0 > e

    def py(mbs_, t, item, u, v, k, d, off):
        ee = e + (e0 - e) * max(0.0, 1.0 - t) ** power if ramp else e
        return dead_band_moment(u, k, h, ee) + k_reg * u

    if not SYMBOLIC:
        return py
    import exudyn as exu
    from exudyn.advancedUtilities import CreateSymbolicUserFunction

    esym = exu.symbolic

    def sym(mbs_, t, item, u, v, k, d, off):
        # t <= 1 in the static solver (the load factor is clamped to the load-step duration 1)
        ee = e + (e0 - e) * esym.pow(1.0 - t, power) if ramp else e
        a = u - h
        b = u + h
        return 0.5 * k * (a + esym.sqrt(a * a + ee * ee)) + 0.5 * k * (b - esym.sqrt(b * b + ee * ee)) + k_reg * u

    f = CreateSymbolicUserFunction(mbs, sym, "springForceUserFunction",
                                   itemTypeName="ObjectConnectorCoordinateSpringDamper")
    keep.append(f)
    return f


def _band_uf_cartesian(mbs, bands, keep: list, start: float = 0.0, power: int = 20):
    """The pin / rail / key spring with translational play: per in-plane axis (x, z) a spring
    free over ``[-closing, opening]`` (:func:`structure_fem.model.connectors.band_force`) + ``k_reg u``.
    ``bands``: ``((closing, opening, e, k_reg), (closing, opening, e, k_reg))`` for x and z; the
    stiffnesses are the connector's ``stiffness[0]``, ``stiffness[1]``. With ``start > 0`` each
    band's smoothing starts at ``start x`` its widest play and relaxes to ``e`` as the load
    factor reaches 1 (the same continuation as the pitch dead bands, :class:`SolverOptions`)."""

    def e_at(t, e, gap, pw):
        e0 = start * gap
        if e0 <= e:
            return e
        return e + (e0 - e) * pw(1.0 - t)

    def py(mbs_, t, item, u, v, k, d, off):
        out = [0.0, 0.0, 0.0]
        for i, (c, o, e, kr) in enumerate(bands):
            ee = e_at(t, e, max(c, o), lambda x: max(0.0, x) ** power)
            out[i] = band_force(u[i], k[i], c, o, ee) + kr * u[i]
        return out

    if not SYMBOLIC:
        return py
    import exudyn as exu
    from exudyn.advancedUtilities import CreateSymbolicUserFunction

    esym = exu.symbolic

    def sym(mbs_, t, item, u, v, k, d, off):
        out = []
        for i, (c, o, e, kr) in enumerate(bands):
            x = u[i]
            if c <= 0 and o <= 0:
                out.append(k[i] * x)
                continue
            ee = e_at(t, e, max(c, o), lambda y: esym.pow(y, power))
            a = x - o
            b = x + c
            f0 = 0.5 * k[i] * (-o + esym.sqrt(o * o + ee * ee)) + 0.5 * k[i] * (c - esym.sqrt(c * c + ee * ee))
            out.append(0.5 * k[i] * (a + esym.sqrt(a * a + ee * ee)) + 0.5 * k[i] * (b - esym.sqrt(b * b + ee * ee))
                       - f0 + kr * x)
        return [out[0], out[1], 0.0]

    f = CreateSymbolicUserFunction(mbs, sym, "springForceUserFunction",
                                   itemTypeName="ObjectConnectorCartesianSpringDamper")
    keep.append(f)
    return f


def _ground_contact_uf(mbs, eps: float, keep: list):
    """The one-sided ground / pier contact: ``k_x u_x`` along x and ``0.5 k_z (z - sqrt(z^2 +
    eps^2))`` along z (it pushes up only, smoothed over ``eps``). Symbolic (C++) under
    ``SYMBOLIC``: exudyn differentiates a user-function connector numerically, so a table called
    the Python form millions of times (measured on the 40 mm / x2 mass / x4 play table: 5.0 M calls,
    the solves 55 s -> see docs/development.md)."""

    def py(mbs_, t, item, u, v, k, d, off):
        z = u[1]
        return [k[0] * u[0], 0.5 * k[1] * (z - math.sqrt(z * z + eps * eps)), 0.0]

    if not SYMBOLIC:
        return py
    import exudyn as exu
    from exudyn.advancedUtilities import CreateSymbolicUserFunction

    esym = exu.symbolic

    def sym(mbs_, t, item, u, v, k, d, off):
        z = u[1]
        return [k[0] * u[0], 0.5 * k[1] * (z - esym.sqrt(z * z + eps * eps)), 0.0]

    f = CreateSymbolicUserFunction(mbs, sym, "springForceUserFunction",
                                   itemTypeName="ObjectConnectorCartesianSpringDamper")
    keep.append(f)
    return f


def translational_bands(joint, count: int, force_scale_n: float) -> tuple[tuple[float, float, float, float], ...]:
    """``(closing, opening, e, k_reg)`` along x and z of a coupling (``count`` in parallel):
    the smoothing ``e`` keeps a coupling carrying ``force_scale_n`` (one body's weight) or more
    within 1 % of the play of the sharp band edge (``e^2 k / (4 F)``), at most a tenth of the
    play; the weak spring ``k_reg`` (at most 1 % of that force at the edge of the play, 1e-3 of
    the coupling) gives a coupling inside its play a defined position."""
    out = []
    for (c, o), k in ((joint.play_x, joint.axial_n_per_m * count), (joint.play_z, joint.k_z * count)):
        gap = max(c, o)
        if gap <= 0:
            out.append((0.0, 0.0, 0.0, 0.0))
            continue
        e = min(SMOOTHING * gap, math.sqrt(0.04 * force_scale_n * gap / k))
        out.append((c, o, e, min(1e-3 * k, 0.01 * force_scale_n / gap)))
    return tuple(out)


#: bodies from which the static solve factorises with Eigen's sparse LU instead of exudyn's dense
#: one: measured on the 14 slowest solves of a 40 mm table (26-66 nodes), sparse took 9.8 s where
#: dense took 17.7 s, every tip equal to 1e-15 m; at 26 nodes it is already 10 % faster (the
#: earlier threshold, 60, left the 58-node arches dense at twice the cost)
SPARSE_FROM_BODIES = 16


def dead_band_parameters(body_mass_kg: float, length_m: float, k: float, h: float) -> tuple[float, float]:
    """``(e, k_reg)`` of a pitch dead band of half-width ``h`` and stiffness ``k`` next to a body
    of ``body_mass_kg``: a joint carrying ``m g L`` sits inside the smooth band edge by about
    ``e^2 k / (4 M)``, kept below 1 % of the play; the weak linear spring ``k_reg`` gives an
    unloaded joint inside its play a defined angle, carrying at most 1 % of ``m g L`` at the band
    edge (used by :mod:`structure_fem.model.dynamics` too)."""
    m0 = body_mass_kg * GRAVITY * length_m
    return min(SMOOTHING * h, math.sqrt(0.04 * m0 * h / k)), min(1e-3 * k, 0.01 * m0 / h)


def _solve_once(config: Config, robot: RobotProperties, conn: ConnectorSet, options: SolverOptions) -> StaticResult:
    import exudyn as exu
    from exudyn.itemInterface import (
        LoadMassProportional,
        MarkerBodyMass,
        MarkerBodyPosition,
        MarkerNodeCoordinate,
        MarkerNodePosition,
        NodePoint2D,
        NodeRigidBody2D,
        ObjectConnectorCartesianSpringDamper,
        ObjectConnectorCoordinateSpringDamper,
        ObjectGround,
        ObjectMassPoint2D,
        ObjectRigidBody2D,
    )

    lay = layout(config.structure, robot, conn, config.rows, config.rows_over, config.void_widths, config.phase,
                 config.piers)
    exu.config.printToConsole = False
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    nodes, objs = [], []
    for b in lay.bodies:
        cx, cz = b.com_m
        n = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[cx, cz, 0.0], initialCoordinates=[0, 0, 0]))
        o = mbs.AddObject(ObjectRigidBody2D(mass=b.mass_kg, inertia=b.inertia_kg_m2, nodeNumber=n))
        m = mbs.AddMarker(MarkerBodyMass(bodyNumber=o))
        mbs.AddLoad(LoadMassProportional(markerNumber=m, loadVector=[0.0, -GRAVITY, 0.0]))
        nodes.append(n)
        objs.append(o)

    def local(i: int, p: tuple[float, float]) -> list[float]:
        cx, cz = lay.bodies[i].com_m
        return [p[0] - cx, p[1] - cz, 0.0]

    if config.tip_load_n:
        from exudyn.itemInterface import LoadForceVector

        fb = lay.bodies[lay.front_body]
        mt = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[lay.front_body],
                                              localPosition=local(lay.front_body, (fb.x_m + lay.length_m / 2, fb.z_m))))
        mbs.AddLoad(LoadForceVector(markerNumber=mt, loadVector=[0.0, -float(config.tip_load_n), 0.0]))

    keep: list = []  # symbolic user functions must outlive the solve
    for c in lay.couplings:
        if emergent(c, lay.hinge):  # tension rows + face contacts: the hinge emerges (structure_fem.model.hinge)
            add_links(mbs, keep, objs, lay, c, options.contact_n_per_m, start=options.smoothing_start,
                      power=options.smoothing_power, symbolic=SYMBOLIC)
            continue
        ma = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[c.a], localPosition=local(c.a, c.point_m)))
        mb = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[c.b], localPosition=local(c.b, c.point_m)))
        ka = c.joint.axial_n_per_m * c.count * along_factor(c, lay.hinge)
        kz = c.joint.k_z * c.count
        extra = {}
        if c.joint.has_translational_play:
            bands = translational_bands(c.joint, c.count, lay.bodies[c.a].mass_kg * GRAVITY)
            extra["springForceUserFunction"] = _band_uf_cartesian(mbs, bands, keep, options.smoothing_start,
                                                                  options.smoothing_power)
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[ma, mb], stiffness=[ka, kz, 0.0],
                                                           damping=[0.0, 0.0, 0.0], **extra))
        ra = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[c.a], coordinate=2))
        rb = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[c.b], coordinate=2))
        kr = c.joint.rotational_nm_per_rad * c.count
        h = c.joint.backlash_rad
        if h > 0:
            # A joint carrying M sits inside the smooth band edge by about e^2 k / (4 M): keep that
            # below 1 % of the play for moments of one body's weight m g L or more.
            e, k_reg = dead_band_parameters(lay.bodies[c.a].mass_kg, lay.length_m, kr, h)

            uf = _dead_band_uf(mbs, h, e, k_reg, keep, options.smoothing_start * h,
                               options.smoothing_power)
            mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=[ra, rb], stiffness=kr,
                                                                springForceUserFunction=uf))
        else:
            mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=[ra, rb], stiffness=kr))

    kc = options.contact_n_per_m

    eps = CONTACT_SMOOTHING_M

    contact = _ground_contact_uf(mbs, eps, keep)

    # Piers: a node at the centre of each pier's top on a bilateral spring of the pier's stiffness
    # (added after every body's node: the first 3 n coordinates stay the bodies').
    pier_markers, pier_x = [], []
    for k in range(len(lay.piers)):
        p = lay.piers[k]
        x0, x1 = lay.pier_range_m(k)
        xc = 0.5 * (x0 + x1)
        pn = mbs.AddNode(NodePoint2D(referenceCoordinates=[xc, 0.0], initialCoordinates=[0.0, 0.0]))
        # no load on it: the pier's own weight goes to the floor; the mass only enters the stabiliser
        mbs.AddObject(ObjectMassPoint2D(mass=max(p.mass_kg, 1e-3), nodeNumber=pn))
        mp = mbs.AddMarker(MarkerNodePosition(nodeNumber=pn))
        mg = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[xc, 0.0, 0.0]))
        kp = p.stiffness_n_per_m
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mg, mp], stiffness=[kp, kp, 0.0],
                                                           damping=[0.0, 0.0, 0.0]))
        pier_markers.append(mp)
        pier_x.append(xc)

    rearmost = min(range(len(lay.supports)), key=lambda i: lay.supports[i].point_m[0]) if lay.supports else -1
    for i, s in enumerate(lay.supports):
        if s.pier is None:
            mg = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[s.point_m[0], s.point_m[1], 0.0]))
            offset = [0.0, 0.0, 0.0]
        else:  # the contact is measured from the pier's (moving) top
            mg = pier_markers[s.pier]
            offset = [s.point_m[0] - pier_x[s.pier], s.point_m[1], 0.0]
        mbd = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[s.body], localPosition=local(s.body, s.point_m)))
        kz = kc * lay.bodies[s.body].count  # contact stiffness per robot standing on the ledge
        kx = kz if (i == rearmost or config.clamped) else 0.0
        bilateral = config.clamped or (config.anchored and i == rearmost)
        extra = {} if bilateral else {"springForceUserFunction": contact}
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mg, mbd], stiffness=[kx, kz, 0.0],
                                                           damping=[0.0, 0.0, 0.0], offset=offset, **extra))
    mbs.Assemble()

    ss = exu.SimulationSettings()
    ss.solution.file.write = False
    ss.solution.sensors.active = False
    ss.solution.file.writeInitialValues = False
    st = ss.staticSolver
    st.verboseMode = 0
    st.numberOfLoadSteps = options.load_steps
    st.stabilizerODE2term = 1.0
    st.minimumStepSize = 1e-3
    st.adaptiveStep = True
    st.newton.adaptInitialResidual = False
    st.newton.absoluteTolerance = options.absolute_tolerance
    st.newton.relativeTolerance = options.relative_tolerance
    st.newton.maxIterations = options.max_iterations
    ss.linearSolver.solverType = (exu.LinearSolverType.EXUdense if len(nodes) < SPARSE_FROM_BODIES
                                  else exu.LinearSolverType.EigenSparse)

    what = config.describe(robot.name)
    try:
        ok = mbs.SolveStatic(ss)
    except Exception as exc:  # exu.SolverError and friends
        raise SolverFailure(f"static solve failed for {what}: {exc}") from exc
    q = np.asarray(mbs.systemData.GetODE2Coordinates(), dtype=float)
    if ok is False or not np.all(np.isfinite(q)):
        raise SolverFailure(f"static solve did not converge for {what}")
    nb = 3 * len(lay.bodies)
    phi = q[:nb].reshape(-1, 3)[:, 2]
    turn = float(np.max(np.abs(phi))) if nb else 0.0
    if turn > MAX_BODY_ROTATION_RAD:
        raise SolverFailure(f"static solve for {what} reached a spurious state (a body turned {turn:.3g} rad)")
    opened = max((abs(float(phi[cp.b] - phi[cp.a])) for cp in lay.couplings), default=0.0)
    if opened > MAX_JOINT_ROTATION_RAD:
        raise SolverFailure(f"static solve for {what} reached a spurious state (a coupling turned {opened:.3g} rad)")
    return _result(config, lay, q, robot, kc)


def _result(config: Config, lay: Layout, q: np.ndarray, robot: RobotProperties, kc: float) -> StaticResult:
    n = len(lay.bodies)
    qp = q[3 * n:].reshape(-1, 2)  # pier tops (x, z)
    q = q[:3 * n].reshape(n, 3)
    ref = np.array([b.com_m for b in lay.bodies])
    com = ref + q[:, :2]
    phi = q[:, 2]
    c, s = np.cos(phi), np.sin(phi)
    L = lay.length_m
    under = np.zeros((n, 2, 2))
    for i, b in enumerate(lay.bodies):
        for j, dx in enumerate((-L / 2, L / 2)):
            lx, lz = dx - b.com_local_m[0], -b.com_local_m[1]
            under[i, j] = (com[i, 0] + c[i] * lx - s[i] * lz, com[i, 1] + s[i] * lx + c[i] * lz)
    base_z = np.array([b.z_m for b in lay.bodies])
    drop = base_z[:, None] - under[:, :, 1]
    tip = float(drop[lay.front_body, 1])
    jr = np.array([phi[cp.b] - phi[cp.a] for cp in lay.couplings if cp.role == "front_rear"])
    reac = []
    rearmost = min(range(len(lay.supports)), key=lambda i: lay.supports[i].point_m[0]) if lay.supports else -1
    for k, sp in enumerate(lay.supports):
        b = lay.bodies[sp.body]
        lx = sp.point_m[0] - b.com_m[0]
        lz = sp.point_m[1] - b.com_m[1]
        i = sp.body
        z = com[i, 1] + s[i] * lx + c[i] * lz
        dz = z - sp.point_m[1] - (qp[sp.pier, 1] if sp.pier is not None else 0.0)
        e = CONTACT_SMOOTHING_M
        bilateral = config.clamped or (config.anchored and k == rearmost)
        reac.append(-kc * b.count * (dz if bilateral else 0.5 * (dz - math.sqrt(dz * dz + e * e))))
    tf = tipping_factor(lay.bodies, com[:, 0], tipping_edge(lay)) if config.phase == "cantilever" else math.inf
    result = StaticResult(config, lay, com, phi, under, tip, float(drop.max()), jr, np.array(reac), tf,
                          sum(b.count for b in lay.bodies), tuple(float(-z) for z in qp[:, 1]))
    if not (math.isfinite(result.tip_deflection_m) and np.all(np.isfinite(under))):
        raise InputError(f"non-finite result for {config.describe(robot.name)}")
    return result
