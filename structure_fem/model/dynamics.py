"""Launch dynamics: exudyn time integration of the two transients the thesis ignores (its
assumption 8), on the same planar model as the static table (SI units).

Events (``launch_transient(..., event=...)``), both from the static equilibrium of the table's
state (the longest cantilever, ``rows_over = void_width``, the table's minimal rows):

* ``"support_loss"``: a row's wheels leave the near ledge. Between two of the robot's ground
  contacts the pivot (the front-most contact on the ledge) moves on with the structure; when
  it passes the edge, the pivot jumps back to the next contact behind it at once and the
  overhang and its moment about the pivot rise in a step. The jump that ends in the table's
  state is the worst one of the cantilever (the largest overhang): the structure starts in
  static equilibrium on the table's supports *plus* the contact ahead of the table's pivot
  (the last one to leave the ledge; :func:`_support_ahead`: on the CuBot the next robot's
  rear caster, 24 mm ahead of the front caster the table's state rests on), that contact is
  removed at t = 0, and the structure swings down to the table's static state (the
  static tip after the event is :func:`structure_fem.model.statics.solve`'s; a test holds the
  transient's end to it within 1 %). ``contact_pitch`` overrides the jump (e.g. the 38 mm
  from a caster to the wheels).
* ``"docking"``: a recruit docks at the rear. A body of the recruit's mass (one row of the
  bottom layer: the robots of the rear bottom body, the thesis recruits a row whole, its
  assumption 5) arrives at the docking speed (:data:`DOCKING_SPEED_M_S`) and strikes the rear
  face at the front-rear coupling's height through a compression-only face contact of the
  coupling's axial stiffness; it is free along x (it rolls), held in z. The static state after
  the push is the one before it (the push is transient; the recruit's weight on the ground
  behind the rear only adds restoring moment), so the overshoot is the peak above it.

Model. The bodies, couplings (the emergent hinge's tension rows and face contacts,
:mod:`structure_fem.model.hinge`, built by the same function; dead bands and translational play of
the lumped couplings), ledge contacts and gravity are those of :mod:`structure_fem.model.statics` (same formulas, rebuilt here because the dynamic system
needs damping, initial conditions and a moved support; the static equilibrium the transient
starts from *is* :func:`structure_fem.model.statics.solve`'s, with all its retries). Damping is Rayleigh
damping proportional to the *tangent* stiffness of every spring (coupling, dead band, contact):
``C = beta K_t`` with ``beta = 2 zeta / omega_1`` so the first mode has the damping ratio
``zeta`` and a mode of frequency ``omega`` has ``zeta omega / omega_1`` (the stiff contact and
pin modes are strongly damped, as material damping does). Inside a play the tangent stiffness
is the weak in-band spring: a joint sliding through its play is undamped (no friction
modelled, the conservative choice). No mass-proportional term (it would damp the rigid
rotation about the ledge, which nothing in the structure resists).

Damping ratio (assumption): :data:`DEFAULT_DAMPING_RATIO` = 0.02. Printed ABS and PLA have a
loss factor (DMA ``tan delta`` at room temperature, well below the glass transition) of about
0.01-0.05, i.e. a material damping ratio ``zeta = tan delta / 2`` of 0.5-2.5 %; pinned and
latched joints add friction damping (structural joints are commonly quoted at 1-5 %). 2 % is
the modest end: it keeps the overshoot near the undamped bound (1 + exp(-pi zeta /
sqrt(1 - zeta^2)) = 1.94 for a suddenly applied load). It is an assumption, not a measurement;
the amplification's sensitivity to it is reported by the tests and the result.

First mode. A linearised eigen-solve (``ComputeODE2Eigenvalues``) of the undamped system at
the table's static equilibrium (the state the transient rings about). Unloaded joints inside their play and the
contact/pin modes give frequencies far from the structure's bending; the *first mode* is the
mode with the largest participation in the tip's static response (the gravity sag of the
table's state): the fundamental sway of the cantilever on its ledge contacts (measured with the
record's hand-formula connectors: 43 Hz for the 5-robot line at w = 2, 31 Hz at w = 3 (7
robots), 22 Hz at w = 5 (11 robots; the issue's "about 25 Hz"); with the table's FE connectors
(``fem table``'s inputs) 18.6 Hz for the line at its threshold w = 3, 10.7 / 12.7 / 14.7 Hz for
the 4x2 / 6x3 / 8x4 arches at theirs). A
slower mode that still moves the tip (at least a tenth of the first's participation; from
w = 4 the line's rear robot rocking in its unloaded joint's play, 9.5 Hz) sets a minimum run
length of 3 of its periods. The time step is ``T_1 / steps_per_period`` (>= 20, default 40)
and the run lasts
``periods`` first periods (default 8: the peak of a suddenly applied load is at half a
period); the docking contact (a fraction of a millisecond) is integrated with a step of a
twentieth of its duration first, then the rest with the ``T_1`` step. Integrator:
generalised-alpha, spectral radius :data:`SPECTRAL_RADIUS` (0.95: negligible numerical
damping at 40 steps per period, the single-mode peak within 0.1 % of the closed form, while
the under-resolved contact modes are damped). Below a damping ratio of 0.01 the joints'
impacts at the edges of their play need 160 steps per period (the default then). Step
convergence with play (line at w = 3, table inputs): the support loss's overshoot is 1.375 mm
at 40 steps per period, 1.16 / 1.17 / 1.20 / 1.19 mm at 80 / 160 / 320 / 640 (the default
errs on the safe side by 0.2 mm there; the two-line's is 4 % low); the docking's 0.52 mm
within 0.01 mm at all of them.

:func:`dynamic_allowance_m` is what the threshold criterion adds to the static tip:
``static tip + dynamic overshoot <= clearance``, the overshoot being the larger event's
``peak - static tip`` (the static tip after both events is the table's).

Measured finding: with the record's play the support loss's peak is set by the front rows
falling through their joints' play and being caught at the band edges; it hardly depends on
the damping ratio and not monotonically (line at w = 3, table inputs: overshoot 1.61 / 1.38 /
1.31 / 1.53 mm at zeta = 0.01 / 0.02 / 0.05 / 0.1; hand-formula record: peak 13.97 mm at 0.02,
13.88 mm at 0.3, static 12.57 mm).
Without play the structure is elastic and the amplification falls with damping as a
single mode's does (tests).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from cubot_cad.properties import RobotProperties
from structure_fem.errors import InputError, SolverFailure
from structure_fem.model.connectors import ConnectorSet
from structure_fem.model.hinge import add_links, along_factor, emergent
from structure_fem.model.statics import (
    CONTACT_N_PER_M,
    CONTACT_SMOOTHING_M,
    Config,
    StaticResult,
    dead_band_parameters,
    solve,
    translational_bands,
)
from structure_fem.model.structures import (
    GRAVITY,
    Layout,
    Structure,
    Support,
    tipping_factor,
)

#: Docking speed (m/s): swarm_sim drives a recruit straight into its dock point at the robot
#: speed ``swarm_sim.params.Params.speed_cm_s`` = 13.89 cm/s (the thesis's vmax; every shipped
#: preset, e.g. ``swarm_sim/presets/case-d.toml``, ``robot.speed_cm_s = 13.89``).
DOCKING_SPEED_M_S = 0.1389
#: Damping ratio of the first mode (assumption, see the module docstring).
DEFAULT_DAMPING_RATIO = 0.02
EVENTS = ("support_loss", "docking")
#: Generalised-alpha spectral radius at infinite frequency.
SPECTRAL_RADIUS = 0.95
DEFAULT_STEPS_PER_PERIOD = 40
DEFAULT_PERIODS = 8.0
MIN_STEPS_PER_PERIOD = 20
#: Below this damping ratio the joints' impacts at the edges of their play ring on and need a
#: finer step: LOW_DAMPING_STEPS_PER_PERIOD (measured: the line's peak converges to 0.5 % at
#: 160 steps per period for zeta = 0.005 and diverges at 40 undamped).
LOW_DAMPING = 0.01
LOW_DAMPING_STEPS_PER_PERIOD = 160
#: Contact pitch when the record has no ground contacts (m): half a robot (the issue's estimate).
FALLBACK_CONTACT_PITCH_FRACTION = 0.5
#: Modes whose participation in the tip's static response is below this fraction of the
#: largest are not the "first mode" (in-play joint modes, local contact modes).
PARTICIPATION_FRACTION = 0.1


@dataclass(frozen=True)
class TransientResult:
    """One launch transient (SI units; the tip is the front-most bottom corner's drop, positive
    down, as in :class:`structure_fem.model.statics.StaticResult`).

    ``tip_before_m``: static tip before the event (support loss: resting on the contact ahead;
    docking: the table's tip); ``static_tip_m``: static tip after it (the table's state for both
    events: :func:`structure_fem.model.statics.solve`'s tip); ``peak_tip_m``:
    the largest tip of the transient; ``overshoot_m = peak - static`` (after the event);
    ``amplification = peak / static``; ``increment_amplification = (peak - before) / (static -
    before)`` (the classical dynamic load factor of the step, 2 for an undamped sudden load;
    ``nan`` for the docking, which has no static increment); ``allowance_m = max(0, overshoot)``:
    what the threshold criterion adds to the table's static tip (:func:`dynamic_allowance_m`).
    ``first_mode_hz``: the structure's first (tip-participating) mode, linearised at the
    equilibrium before the event; ``lowest_mode_hz``: the lowest eigenfrequency of all (an
    unloaded joint in its play or the rigid rocking on the ledge can be lower).
    ``time_s``, ``tip_history_m``: the tip over time (event at t = 0).
    """

    event: str
    structure: str
    void_width: float
    rows: int
    damping_ratio: float
    first_mode_hz: float
    lowest_mode_hz: float
    tip_before_m: float
    static_tip_m: float
    peak_tip_m: float
    peak_time_s: float
    overshoot_m: float
    amplification: float
    increment_amplification: float
    allowance_m: float
    time_step_s: float
    end_time_s: float
    time_s: np.ndarray = field(repr=False)
    tip_history_m: np.ndarray = field(repr=False)
    rayleigh_beta_s: float = 0.0
    #: support loss: how far the pivot moved back (m); docking: 0
    pivot_shift_m: float = 0.0
    #: docking: recruit mass (kg) and speed (m/s); support loss: 0
    recruit_mass_kg: float = 0.0
    docking_speed_m_s: float = 0.0
    #: tipping factor about the (moved) front-most support after the event
    tipping_factor_after: float = math.inf
    #: the tip at the end of the run (m)
    final_tip_m: float = 0.0
    runtime_s: float = 0.0
    notes: str = ""
    #: rows past the near edge of the state the event ends in (the table's: ``void_width``)
    rows_over: float = math.nan

    @property
    def overshoot_mm(self) -> float:
        return 1e3 * self.overshoot_m

    @property
    def allowance_mm(self) -> float:
        return 1e3 * self.allowance_m

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in ("event", "structure", "void_width", "rows", "damping_ratio",
                                             "first_mode_hz", "lowest_mode_hz", "time_step_s", "end_time_s",
                                             "rayleigh_beta_s", "pivot_shift_m", "recruit_mass_kg",
                                             "docking_speed_m_s", "runtime_s", "notes", "rows_over")}
        for k in ("tip_before_m", "static_tip_m", "peak_tip_m", "overshoot_m", "allowance_m", "final_tip_m"):
            out[k.replace("_m", "_mm") if k.endswith("_m") else k] = 1e3 * getattr(self, k)
        for k in ("amplification", "increment_amplification", "tipping_factor_after", "peak_time_s"):
            v = getattr(self, k)
            out[k] = v if math.isfinite(v) else None
        return out


# --------------------------------------------------------------------------- inputs


def _check(name: str, v, lo: float | None = 0.0, strict: bool = True) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise InputError(f"{name} must be a finite number, got {v!r}")
    if lo is not None and (v <= lo if strict else v < lo):
        raise InputError(f"{name} must be {'>' if strict else '>='} {lo:g}, got {v!r}")
    return float(v)


# --------------------------------------------------------------------------- user functions


def _sym():
    import exudyn as exu
    return exu.symbolic


def _smooth_band(esym, x, k, c, o, e):
    """Force and tangent stiffness of a spring ``k`` free over ``[-c, o]`` (smoothed over ``e``),
    less its value at 0 (:func:`structure_fem.model.connectors.band_force`); symbolic."""
    a = x - o
    b = x + c
    ra = esym.sqrt(a * a + e * e)
    rb = esym.sqrt(b * b + e * e)
    f0 = 0.5 * k * (-o + math.sqrt(o * o + e * e)) + 0.5 * k * (c - math.sqrt(c * c + e * e))
    f = 0.5 * k * (a + ra) + 0.5 * k * (b - rb) - f0
    kt = 0.5 * k * (1.0 + a / ra) + 0.5 * k * (1.0 - b / rb)
    return f, kt


def _cartesian_uf(mbs, keep: list, axes, beta: float):
    """CartesianSpringDamper force per axis (x, z): ``axes[i] = (kind, k, c, o, e, k_reg)`` with
    kind ``"lin"`` (k u), ``"band"`` (play, :func:`_smooth_band` + k_reg u) or ``"contact"``
    (one-sided ``k/2 (u - sqrt(u^2 + e^2))``) plus ``beta k_t v`` (tangent-stiffness damping)."""
    import exudyn as exu  # noqa: F401
    from exudyn.advancedUtilities import CreateSymbolicUserFunction

    esym = _sym()

    def sym(mbs_, t, item, u, v, k, d, off):
        out = []
        for i, (kind, kk, c, o, e, kr) in enumerate(axes):
            x = u[i]
            if kind == "lin":
                f, kt = kk * x, kk
            elif kind == "band":
                f, kt = _smooth_band(esym, x, kk, c, o, e)
                f = f + kr * x
                kt = kt + kr
            else:  # contact, compression (u < 0) only
                r = esym.sqrt(x * x + e * e)
                f = 0.5 * kk * (x - r)
                kt = 0.5 * kk * (1.0 - x / r)
            out.append(f + beta * kt * v[i] if beta > 0 else f)
        return [out[0], out[1], 0.0]

    f = CreateSymbolicUserFunction(mbs, sym, "springForceUserFunction",
                                   itemTypeName="ObjectConnectorCartesianSpringDamper")
    keep.append(f)
    return f


def _dead_band_uf(mbs, keep: list, h: float, e: float, k_reg: float, beta: float):
    """Smooth pitch dead band (:func:`structure_fem.model.connectors.dead_band_moment`) + ``k_reg u``
    + ``beta k_t v``; symbolic."""
    from exudyn.advancedUtilities import CreateSymbolicUserFunction

    esym = _sym()

    def sym(mbs_, t, item, u, v, k, d, off):
        a = u - h
        b = u + h
        ra = esym.sqrt(a * a + e * e)
        rb = esym.sqrt(b * b + e * e)
        m = 0.5 * k * (a + ra) + 0.5 * k * (b - rb) + k_reg * u
        if beta <= 0:
            return m
        kt = 0.5 * k * (1.0 + a / ra) + 0.5 * k * (1.0 - b / rb) + k_reg
        return m + beta * kt * v

    f = CreateSymbolicUserFunction(mbs, sym, "springForceUserFunction",
                                   itemTypeName="ObjectConnectorCoordinateSpringDamper")
    keep.append(f)
    return f


# --------------------------------------------------------------------------- system


@dataclass
class _Recruit:
    mass_kg: float
    speed_m_s: float
    body: int  # the structure body it strikes
    point_m: tuple[float, float]  # the rear face point it strikes (global reference)
    k_contact: float


@dataclass
class _System:
    SC: object
    mbs: object
    keep: list
    n_bodies: int
    recruit_node: int | None = None


def _build(lay: Layout, supports: tuple[Support, ...], q0: np.ndarray, beta: float,
           kc: float = CONTACT_N_PER_M, recruit: _Recruit | None = None, clamped: bool = False) -> _System:
    """The exudyn system of ``lay`` resting on ``supports``, its bodies starting at ``q0``
    ((n, 3) displacements x, z, pitch from the reference), with tangent-stiffness Rayleigh
    damping ``beta``; the formulas of :func:`structure_fem.model.statics._solve_once`."""
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

    if lay.piers:
        raise InputError("launch transients over piers are not modelled")
    exu.config.printToConsole = False
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    nodes, objs = [], []
    for i, b in enumerate(lay.bodies):
        cx, cz = b.com_m
        n = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[cx, cz, 0.0], initialCoordinates=list(q0[i])))
        o = mbs.AddObject(ObjectRigidBody2D(mass=b.mass_kg, inertia=b.inertia_kg_m2, nodeNumber=n))
        m = mbs.AddMarker(MarkerBodyMass(bodyNumber=o))
        mbs.AddLoad(LoadMassProportional(markerNumber=m, loadVector=[0.0, -GRAVITY, 0.0]))
        nodes.append(n)
        objs.append(o)

    def local(i: int, p: tuple[float, float]) -> list[float]:
        cx, cz = lay.bodies[i].com_m
        return [p[0] - cx, p[1] - cz, 0.0]

    keep: list = []
    for c in lay.couplings:
        if emergent(c, lay.hinge):  # the static model's links (structure_fem.model.hinge), damped
            add_links(mbs, keep, objs, lay, c, kc, beta=beta)
            continue
        ma = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[c.a], localPosition=local(c.a, c.point_m)))
        mb = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[c.b], localPosition=local(c.b, c.point_m)))
        ka = c.joint.axial_n_per_m * c.count * along_factor(c, lay.hinge)
        kz = c.joint.k_z * c.count
        if c.joint.has_translational_play:
            bands = translational_bands(c.joint, c.count, lay.bodies[c.a].mass_kg * GRAVITY)
            axes = [("lin", k, 0.0, 0.0, 0.0, 0.0) if (cl <= 0 and op <= 0) else ("band", k, cl, op, e, kr)
                    for (cl, op, e, kr), k in zip(bands, (ka, kz), strict=True)]
            uf = _cartesian_uf(mbs, keep, axes, beta)
            mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[ma, mb], stiffness=[ka, kz, 0.0],
                                                               damping=[0.0, 0.0, 0.0], springForceUserFunction=uf))
        else:
            mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[ma, mb], stiffness=[ka, kz, 0.0],
                                                               damping=[beta * ka, beta * kz, 0.0]))
        ra = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[c.a], coordinate=2))
        rb = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[c.b], coordinate=2))
        kr = c.joint.rotational_nm_per_rad * c.count
        h = c.joint.backlash_rad
        if h > 0:  # the same smoothing and in-band spring as structure_fem.model.statics
            e, k_reg = dead_band_parameters(lay.bodies[c.a].mass_kg, lay.length_m, kr, h)
            uf = _dead_band_uf(mbs, keep, h, e, k_reg, beta)
            mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=[ra, rb], stiffness=kr,
                                                                springForceUserFunction=uf))
        else:
            mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=[ra, rb], stiffness=kr,
                                                                damping=beta * kr))

    eps = CONTACT_SMOOTHING_M
    rearmost = min(range(len(supports)), key=lambda i: supports[i].point_m[0]) if supports else -1
    for i, s in enumerate(supports):
        mg = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[s.point_m[0], s.point_m[1], 0.0]))
        mbd = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[s.body], localPosition=local(s.body, s.point_m)))
        kz = kc * lay.bodies[s.body].count
        kx = kz if (i == rearmost or clamped) else 0.0
        if clamped:
            mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mg, mbd], stiffness=[kx, kz, 0.0],
                                                               damping=[beta * kx, beta * kz, 0.0]))
            continue
        uf = _cartesian_uf(mbs, keep, [("lin", kx, 0, 0, 0, 0), ("contact", kz, 0, 0, eps, 0)], beta)
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mg, mbd], stiffness=[kx, kz, 0.0],
                                                           damping=[0.0, 0.0, 0.0], springForceUserFunction=uf))

    rn = None
    if recruit is not None:
        # the recruit: a mass point at the struck face, rolling (free in x), held in z by its wheels
        px, pz = recruit.point_m
        rn = mbs.AddNode(NodePoint2D(referenceCoordinates=[px, pz], initialCoordinates=[0.0, 0.0],
                                     initialVelocities=[recruit.speed_m_s, 0.0]))
        mbs.AddObject(ObjectMassPoint2D(mass=recruit.mass_kg, nodeNumber=rn))
        mr = mbs.AddMarker(MarkerNodePosition(nodeNumber=rn))
        mgz = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[px, pz, 0.0]))
        kzr = kc * max(1, round(recruit.mass_kg / lay.bodies[recruit.body].mass_kg * lay.bodies[recruit.body].count))
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mgz, mr], stiffness=[0.0, kzr, 0.0],
                                                           damping=[0.0, beta * kzr, 0.0]))
        mface = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[recruit.body],
                                                 localPosition=local(recruit.body, recruit.point_m)))
        kk = recruit.k_contact
        # face contact: u = x_face - x_recruit, compression (u < 0) only; frictionless (no z force)
        uf = _cartesian_uf(mbs, keep, [("contact", kk, 0, 0, eps, 0), ("lin", 0.0, 0, 0, 0, 0)], beta)
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mr, mface], stiffness=[kk, 0.0, 0.0],
                                                           damping=[0.0, 0.0, 0.0], springForceUserFunction=uf))
    mbs.Assemble()
    return _System(SC, mbs, keep, len(lay.bodies), rn)


def _settings(static: bool, n_bodies: int, h: float = 1e-3, t_end: float = 0.0, t_start: float = 0.0,
              load_steps: int = 8, ramp: bool = True):
    import exudyn as exu

    ss = exu.SimulationSettings()
    ss.solution.file.write = False
    ss.solution.sensors.active = False
    ss.solution.file.writeInitialValues = False
    ss.linearSolver.solverType = exu.LinearSolverType.EXUdense if n_bodies < 60 else exu.LinearSolverType.EigenSparse
    if static:
        st = ss.staticSolver
        st.verboseMode = 0
        # gravity ramped (a 1-step solve from a far state stalls on the contacts); ramp=False: one
        # full-load step from a state near equilibrium (after a dynamic relaxation)
        st.numberOfLoadSteps = load_steps if ramp else 1
        st.useLoadFactor = ramp
        st.stabilizerODE2term = 1.0 if ramp else 0.0
        st.adaptiveStep = True
        st.minimumStepSize = 1e-3
        st.newton.adaptInitialResidual = False
        st.newton.absoluteTolerance = 1e-6
        st.newton.relativeTolerance = 1e-6
        st.newton.maxIterations = 40
        return ss
    ti = ss.timeIntegration
    ti.verboseMode = 0
    ti.startTime = t_start
    ti.endTime = t_end
    ti.numberOfSteps = max(1, int(round((t_end - t_start) / h)))
    ti.generalizedAlpha.spectralRadius = SPECTRAL_RADIUS
    ti.generalizedAlpha.computeInitialAccelerations = True
    ti.adaptiveStep = True
    ti.minimumStepSize = 1e-3 * h
    ti.newton.useModifiedNewton = False
    ti.newton.adaptInitialResidual = False
    ti.newton.absoluteTolerance = 1e-6  # the line's peak equals the 1e-8 run's to 1e-4 mm, 2x faster
    ti.newton.relativeTolerance = 1e-6
    ti.newton.maxIterations = 25
    return ss


def _coords(sys_: _System) -> np.ndarray:
    return np.asarray(sys_.mbs.systemData.GetODE2Coordinates(), dtype=float)


def _static(sys_: _System, what: str, load_steps: int = 8, ramp: bool = True) -> np.ndarray:
    ss = _settings(True, sys_.n_bodies, load_steps=load_steps, ramp=ramp)
    try:
        ok = sys_.mbs.SolveStatic(ss)
    except Exception as exc:  # exu.SolverError and friends
        raise SolverFailure(f"static solve failed for {what}: {exc}") from exc
    q = _coords(sys_)
    if ok is False or not np.all(np.isfinite(q)):
        raise SolverFailure(f"static solve did not converge for {what}")
    return q


def _integrate(sys_: _System, h: float, t_end: float, what: str, t_start: float = 0.0,
               record: list | None = None) -> None:
    """Generalised-alpha from ``t_start`` to ``t_end`` with step ``h``; every step's ODE2
    coordinates are appended to ``record`` as ``(t, q)``."""
    import exudyn as exu

    mbs = sys_.mbs
    if record is not None:
        def post(mbs_, t):
            record.append((t, np.asarray(mbs_.systemData.GetODE2Coordinates(), dtype=float)))
            return True
        mbs.SetPreStepUserFunction(post)
    ss = _settings(False, sys_.n_bodies, h, t_end, t_start)
    try:
        ok = mbs.SolveDynamic(ss, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    except Exception as exc:
        raise SolverFailure(f"dynamic solve failed for {what}: {exc}") from exc
    if ok is False:
        raise SolverFailure(f"dynamic solve did not converge for {what}")
    if record is not None:
        record.append((t_end, _coords(sys_)))
        mbs.SetPreStepUserFunction(0)


def _continue_from_current(sys_: _System) -> None:
    """Make the current state the initial one (to continue integrating)."""
    import exudyn as exu

    sd = sys_.mbs.systemData
    sd.SetSystemState(sd.GetSystemState(exu.ConfigurationType.Current), configuration=exu.ConfigurationType.Initial)


# --------------------------------------------------------------------------- geometry


def _tip_row(lay: Layout) -> tuple[int, np.ndarray]:
    """The front body and the local offset (x, z) of its front bottom corner from its COM."""
    b = lay.bodies[lay.front_body]
    return lay.front_body, np.array([lay.length_m / 2 - b.com_local_m[0], -b.com_local_m[1]])


def tip_of(lay: Layout, q: np.ndarray) -> float:
    """Tip deflection (m, positive down) of the front bottom corner for coordinates ``q`` (the
    first 3 n entries are the bodies'); the formula of :func:`structure_fem.model.statics._result`."""
    i, (lx, lz) = _tip_row(lay)
    dx, dz, phi = q[3 * i:3 * i + 3]
    b = lay.bodies[i]
    cz = b.com_m[1] + dz
    z = cz + math.sin(phi) * lx + math.cos(phi) * lz
    return float(b.z_m - z)


def _tip_gradient(lay: Layout, q: np.ndarray) -> np.ndarray:
    """d tip / d q at ``q`` (the tip's linearisation, bodies' coordinates only)."""
    i, (lx, lz) = _tip_row(lay)
    g = np.zeros(3 * len(lay.bodies))
    phi = q[3 * i + 2]
    g[3 * i + 1] = -1.0
    g[3 * i + 2] = -(math.cos(phi) * lx - math.sin(phi) * lz)
    return g


def _q_from_static(res: StaticResult) -> np.ndarray:
    lay = res.layout
    ref = np.array([b.com_m for b in lay.bodies])
    q = np.zeros((len(lay.bodies), 3))
    q[:, :2] = np.asarray(res.com_m) - ref
    q[:, 2] = res.rotation_rad
    return q


@dataclass(frozen=True)
class Modes:
    """Linearised modes at an equilibrium: frequencies (Hz, ascending), the first (the mode with
    the largest participation in the tip's static sag: the cantilever's sway on its contacts)
    and the lowest one that still participates."""

    frequencies_hz: np.ndarray
    first_hz: float
    first_index: int
    participation: np.ndarray
    #: the lowest mode with at least PARTICIPATION_FRACTION of the first's participation
    lowest_participating_hz: float = math.nan


def modes(sys_: _System, lay: Layout, q: np.ndarray, shape: np.ndarray) -> Modes:
    """Eigen-solve of the undamped system at its initial state ``q`` (``ComputeODE2Eigenvalues``);
    the first mode is the one with the largest participation ``|g.phi_i| |phi_i^T M shape| /
    phi_i^T M phi_i`` in the tip (``g`` the tip's gradient); ``lowest_participating_hz`` the
    lowest reaching :data:`PARTICIPATION_FRACTION` of it (e.g. the rear robot rocking in its
    unloaded joint's play)."""
    from exudyn.solver import ComputeODE2Eigenvalues

    try:
        lam, vec = ComputeODE2Eigenvalues(sys_.mbs, useSparseSolver=False, useAbsoluteValues=True)
    except Exception as exc:
        raise SolverFailure(f"eigen-solve failed: {exc}") from exc
    lam = np.asarray(lam, dtype=float)
    vec = np.asarray(vec, dtype=float)
    nb = 3 * len(lay.bodies)
    masses = np.zeros(vec.shape[0])
    for i, b in enumerate(lay.bodies):
        masses[3 * i:3 * i + 3] = (b.mass_kg, b.mass_kg, b.inertia_kg_m2)
    g = np.zeros(vec.shape[0])
    g[:nb] = _tip_gradient(lay, q)
    s = np.zeros(vec.shape[0])
    s[:len(shape)] = shape
    mnorm = np.einsum("ij,i,ij->j", vec, masses, vec)
    mnorm[mnorm <= 0] = 1.0
    part = np.abs(g @ vec) * np.abs((vec * masses[:, None]).T @ s) / mnorm
    freq = np.sqrt(np.abs(lam)) / (2 * math.pi)
    order = np.argsort(freq)
    freq, part = freq[order], part[order]
    big = part.max() if part.size else 0.0
    if not big > 0:
        raise SolverFailure("eigen-solve: no mode moves the tip")
    idx = int(np.argmax(part))
    low = int(np.argmax(part >= PARTICIPATION_FRACTION * big))
    return Modes(freq, float(freq[idx]), idx, part, float(freq[low]))


# --------------------------------------------------------------------------- public API


def _ground_points(lay: Layout, props: RobotProperties) -> tuple[tuple[float, float], ...]:
    """The robot's ground contacts (robot frame x, z) the layout rests on."""
    g = getattr(lay, "ground", None)
    if g is None:
        try:
            from structure_fem.model.contacts import ground_support
            g = ground_support(props)
        except Exception:  # noqa: BLE001 - layouts without contacts rest on corners
            g = None
    if g is not None and getattr(g, "kind", "") == "contacts":
        return tuple(g.points)
    return ((-lay.length_m / 2, 0.0), (lay.length_m / 2, 0.0))


def _support_ahead(lay: Layout, props: RobotProperties, contact_pitch: float | None
                   ) -> tuple[tuple[Support, ...], float, str]:
    """The supports *before* the pivot jumps back to the table's front-most near-ledge support:
    the table's plus one at the next ground contact ahead of it (the last contact to leave the
    ledge), ``contact_pitch`` ahead if given. Returns ``(supports, shift, note)``."""
    near = [s for s in lay.supports if s.ledge == "near"]
    if not near:
        raise InputError("no near-ledge support")
    piv = max(near, key=lambda s: s.point_m[0])
    xp, zp = piv.point_m
    L = lay.length_m
    layer0 = [i for i, b in enumerate(lay.bodies) if b.layer == 0]
    if contact_pitch is None:
        pts = _ground_points(lay, props)
        cand = [(lay.bodies[i].x_m + cx, i) for i in layer0 for cx, _ in pts if lay.bodies[i].x_m + cx > xp + 1e-6]
        if not cand:
            raise InputError("no ground contact ahead of the pivot (nothing overhangs)")
        x_new, body = min(cand)
        src = "the robots' ground contacts: the last contact to leave the ledge, ahead of the table's pivot"
        corners = all(abs(abs(cx) - L / 2) < 1e-9 for cx, _ in pts)
        if corners:  # a flat underside pivots on the edge itself: no jump; use half a robot (issue's estimate)
            x_new = xp + FALLBACK_CONTACT_PITCH_FRACTION * L
            body = None
            src = "half a robot length (a flat underside: no ground contacts)"
    else:
        x_new, body = xp + contact_pitch, None
        src = "given"
    if body is None:
        cands = [i for i in layer0 if lay.bodies[i].x_m - L / 2 - 1e-9 <= x_new <= lay.bodies[i].x_m + L / 2 + 1e-9]
        if not cands:
            raise InputError(f"no body over the support point {x_new:g} m ahead of the pivot")
        body = min(cands, key=lambda i: lay.bodies[i].x_m)
    extra = Support(body, (x_new, zp), "near")
    shift = x_new - xp
    return (tuple(lay.supports) + (extra,), shift,
            f"pivot jumps back by {shift * 1e3:.1f} mm from x = {x_new * 1e3:.1f} mm to {xp * 1e3:.1f} mm "
            f"(contact pitch: {src})")


def _static_from(lay, supports, starts, what: str, h_relax: float, w1: float | None) -> tuple[np.ndarray, str]:
    """An equilibrium of ``lay`` on ``supports``: a static solve from each start in turn, then
    dynamic relaxation (critically damped integration) from the first start."""
    n = len(lay.bodies)
    for q0 in starts:
        try:
            return _static(_build(lay, supports, q0, 0.0), what, 8)[:3 * n].reshape(n, 3), ""
        except SolverFailure:
            continue
    if w1 is None:
        raise SolverFailure(f"static solve did not converge for {what}")
    # stiffness-proportional damping critical at the first mode: every overdamped mode decays at
    # about omega_1 / 2, i.e. by exp(-pi) per first period; 10 periods, then a static solve
    q = _relax(lay, supports, starts[0], 2.0 / w1, h_relax, 10 * 2 * math.pi / w1, what + " (relaxation)")
    return q[:3 * n].reshape(n, 3), "by dynamic relaxation"


def _relax(lay, supports, q0, beta_fast, h, t_end, what, recruit=None) -> np.ndarray:
    """Dynamic relaxation (heavily damped integration) to an equilibrium: the fallback of a
    static solve that does not converge from the transient's state."""
    sys_ = _build(lay, supports, q0, beta_fast, recruit=recruit)
    _integrate(sys_, h, t_end, what)
    q = _coords(sys_)
    for ramp in (False, True):
        try:
            return _static(_build(lay, supports, q[:3 * len(lay.bodies)].reshape(-1, 3), 0.0), what, ramp=ramp)
        except SolverFailure:
            continue
    return q


def launch_transient(structure: Structure, void_width: int | float, props: RobotProperties,
                     event: str = "support_loss", damping_ratio: float = DEFAULT_DAMPING_RATIO, *,
                     rows: int | None = None, connectors: ConnectorSet | None = None, flexible: bool = False,
                     docking_speed_m_s: float = DOCKING_SPEED_M_S, recruit_robots: int | None = None,
                     contact_pitch: float | None = None, steps_per_period: int | None = None,
                     periods: float = DEFAULT_PERIODS, static: StaticResult | None = None,
                     rows_over: float | None = None) -> TransientResult:
    """The launch transient ``event`` of ``structure`` at its longest cantilever over a
    ``void_width``-wide void (``rows_over = void_width``; ``rows``: the table's
    minimal rows, :func:`structure_fem.analysis.study.table_rows`, required unless ``static`` is given), from its static equilibrium
    (:func:`structure_fem.model.statics.solve`, or ``static`` if given); ``rows_over`` (default
    ``void_width``) places the front elsewhere (:func:`support_loss_family`).

    ``damping_ratio``: of the first mode (tangent-stiffness Rayleigh damping, module docstring);
    ``docking_speed_m_s`` and ``recruit_robots`` (default: the robots of the rear bottom body,
    one row of the bottom layer) for ``"docking"``; ``contact_pitch`` (m, default: the next
    ground contact ahead of the table's pivot, :func:`_support_ahead`) for ``"support_loss"``.
    Time step ``T_1 / steps_per_period`` (>= 20; default 40, 160 below a damping ratio of
    :data:`LOW_DAMPING`), run ``periods`` first periods. Raises :class:`SolverFailure` naming the case if a
    solve does not converge, :class:`InputError` on bad input.
    """
    t_wall = time.perf_counter()
    if event not in EVENTS:
        raise InputError(f"event {event!r} is not one of {', '.join(EVENTS)}")
    zeta = _check("damping ratio", damping_ratio, 0.0, strict=False)
    if zeta >= 1.0:
        raise InputError(f"damping ratio must be < 1 (underdamped), got {zeta!r}")
    if steps_per_period is None:
        steps_per_period = DEFAULT_STEPS_PER_PERIOD if zeta >= LOW_DAMPING else LOW_DAMPING_STEPS_PER_PERIOD
    if not (isinstance(steps_per_period, int) and steps_per_period >= MIN_STEPS_PER_PERIOD):
        raise InputError(f"steps per period must be an integer >= {MIN_STEPS_PER_PERIOD}, got {steps_per_period!r}")
    periods = _check("periods", periods, 0.0)
    _check("void width", void_width, 0.0)
    conn = ConnectorSet.from_robot(props) if connectors is None else connectors
    what = f"{props.name} {structure.name} over a {void_width:g}-wide void ({event})"

    if static is None:
        if rows is None:
            raise InputError(f"{what}: give the table's rows (rows=, structure_fem.analysis.study.table_rows) "
                             "or its solved state (static=)")
        g = void_width if rows_over is None else _check("rows over", rows_over, 0.0)
        static = solve(Config(structure, rows, g, void_width), props, conn, flexible)
    lay = static.layout
    rows = static.config.rows
    q_model = _q_from_static(static)

    # the table's equilibrium (after a support loss; before and after a docking push): the model's
    # solution is an equilibrium of this system too (the same equations)
    q_table = q_model
    notes = []
    shift = 0.0
    recruit = None
    if event == "support_loss":
        if contact_pitch is not None:
            _check("contact pitch", contact_pitch)
        supports_before, shift, note = _support_ahead(lay, props, contact_pitch)
        notes.append(note)
    else:
        supports_before = lay.supports
        v = _check("docking speed", docking_speed_m_s, 0.0, strict=False)
        rear = lay.rear_body
        b = lay.bodies[rear]
        count = b.count if recruit_robots is None else recruit_robots
        if isinstance(count, bool) or not (isinstance(count, int) and count >= 1):
            raise InputError(f"recruit robots must be an integer >= 1, got {recruit_robots!r}")
        fr = conn.front_rear
        point = (b.x_m - lay.length_m / 2 - fr.gap_m, b.z_m + fr.height_m)
        recruit = _Recruit(count * props.mass_kg, v, rear, point, fr.axial_n_per_m * count)
        notes.append(f"{count} robot(s) ({count * props.mass_kg:.3f} kg) at {v:.4f} m/s against the rear face at "
                     f"z = {fr.height_m * 1e3:.1f} mm (face contact {fr.axial_n_per_m * count:.3g} N/m)")

    # modes at the table's equilibrium (the structure the transient rings in), participation in its sag
    md = modes(_build(lay, lay.supports, q_table, 0.0), lay, q_table.ravel(), q_table.ravel())
    f1 = md.first_hz
    if not (math.isfinite(f1) and f1 > 0):
        raise SolverFailure(f"{what}: no first mode ({f1})")
    w1 = 2 * math.pi * f1
    beta = 2 * zeta / w1
    T1 = 1.0 / f1
    h = T1 / steps_per_period
    # several first periods, and at least 3 of the slowest mode that moves the tip
    t_end = max(periods * T1, 3.0 / md.lowest_participating_hz)

    if event == "support_loss":
        q_before, how = _static_from(lay, supports_before, (q_table,), what + ", before the event", h, w1)
        if how:
            notes.append(f"static state before the event {how}")
    else:
        q_before = q_table
    q_after = q_table
    tip_before = tip_of(lay, q_before.ravel())
    static_tip = tip_of(lay, q_after.ravel())

    record: list = []
    sysd = _build(lay, lay.supports, q_before, beta, recruit=recruit)
    if recruit is not None:
        mb = lay.bodies[recruit.body].mass_kg
        m_eff = recruit.mass_kg * mb / (recruit.mass_kg + mb)
        t_contact = math.pi * math.sqrt(m_eff / recruit.k_contact)
        t1 = min(t_end, max(4 * t_contact, 2 * h))
        _integrate(sysd, min(h, t_contact / 20), t1, what + ", contact", 0.0, record)
        if t1 < t_end:
            _continue_from_current(sysd)
            _integrate(sysd, h, t_end, what, t1, record)
    else:
        _integrate(sysd, h, t_end, what, 0.0, record)

    ts = np.array([t for t, _ in record])
    tips = np.array([tip_of(lay, q) for _, q in record])
    ts, idx = np.unique(ts, return_index=True)
    tips = tips[idx]
    k = int(np.argmax(tips))
    peak = float(tips[k])
    inc = static_tip - tip_before
    com_x = np.array([b.com_m[0] for b in lay.bodies]) + q_after[:, 0]
    edge = max(s.point_m[0] for s in lay.supports if s.ledge == "near")
    tf = tipping_factor(lay.bodies, com_x, edge)
    return TransientResult(
        event=event, structure=structure.name, void_width=float(void_width), rows=rows, damping_ratio=zeta,
        first_mode_hz=f1, lowest_mode_hz=float(md.frequencies_hz[0]), tip_before_m=tip_before,
        static_tip_m=static_tip, peak_tip_m=peak, peak_time_s=float(ts[k]), overshoot_m=peak - static_tip,
        amplification=peak / static_tip if static_tip > 0 else math.nan,
        increment_amplification=(peak - tip_before) / inc if abs(inc) > 1e-12 else math.nan,
        allowance_m=max(0.0, peak - static_tip), time_step_s=h, end_time_s=t_end, time_s=ts, tip_history_m=tips,
        rayleigh_beta_s=beta, pivot_shift_m=shift,
        recruit_mass_kg=recruit.mass_kg if recruit else 0.0, docking_speed_m_s=recruit.speed_m_s if recruit else 0.0,
        tipping_factor_after=tf, final_tip_m=float(tips[-1]), runtime_s=time.perf_counter() - t_wall,
        notes="; ".join(notes), rows_over=float(static.config.rows_over))


def support_loss_family(structure: Structure, void_width: int, props: RobotProperties,
                        damping_ratio: float = DEFAULT_DAMPING_RATIO, *, rows: int | None = None,
                        connectors: ConnectorSet | None = None, flexible: bool = False,
                        **kw) -> tuple[TransientResult, ...]:
    """Every pivot jump in the last robot pitch of the launch (rows over the void ``w - 1 .. w``,
    the table's rows): for each ground contact that leaves the edge there, the structure just
    after that contact passed the edge (``rows_over = w - x / pitch + 1e-4``, ``x`` the contact's
    position in the table's state) starting on it and dropping onto the next one behind. The
    table's state is the family's end (its jump is ``launch_transient``'s default event); the
    worst peak of the family is what a continuous advance meets. ``kw`` as
    :func:`launch_transient`."""
    conn = ConnectorSet.from_robot(props) if connectors is None else connectors
    if rows is None:
        raise InputError(f"{props.name} {structure.name} over a {void_width:g}-wide void (support_loss family): "
                         "give the table's rows (rows=, structure_fem.analysis.study.table_rows)")
    table = solve(Config(structure, rows, void_width, void_width), props, conn, flexible)
    lay = table.layout
    pts = _ground_points(lay, props)
    xs = sorted({round(lay.bodies[i].x_m + cx, 9) for i, b in enumerate(lay.bodies) if b.layer == 0
                 for cx, _ in pts})
    ahead = [x for x in xs if 1e-6 < x < lay.pitch_m - 1e-6]
    out = [launch_transient(structure, void_width, props, "support_loss", damping_ratio, connectors=conn,
                            flexible=flexible, static=table, **kw)]
    for x in ahead[1:]:  # the first one ahead is the table's own jump
        g = void_width - x / lay.pitch_m + 1e-4
        out.append(launch_transient(structure, void_width, props, "support_loss", damping_ratio, rows=rows,
                                    connectors=conn, flexible=flexible, rows_over=g, **kw))
    return tuple(out)


def dynamic_allowance_m(structure: Structure, void_width: int | float, props: RobotProperties,
                        damping_ratio: float = DEFAULT_DAMPING_RATIO, events: tuple[str, ...] = EVENTS,
                        family: bool = False, **kw) -> float:
    """What the threshold criterion adds to the table's static tip (m, >= 0): the largest
    ``peak - table's static tip`` over ``events`` (the static tip after both events is the
    table's), so ``static tip + allowance <= clearance`` keeps the transient's peak below the
    clearance. ``family=True``: the support loss's peak is the worst of
    :func:`support_loss_family` (every pivot jump of the last robot pitch; 3x the cost).
    ``kw`` as :func:`launch_transient` (``static=`` reuses the solved table state)."""
    out = 0.0
    for e in events:
        if e == "support_loss" and family:
            kw2 = {k: v for k, v in kw.items() if k != "static"}
            fam = support_loss_family(structure, int(void_width), props, damping_ratio, **kw2)
            table_tip = fam[0].static_tip_m
            out = max(out, max(r.peak_tip_m for r in fam) - table_tip)
        else:
            out = max(out, launch_transient(structure, void_width, props, e, damping_ratio, **kw).allowance_m)
    return out


# --------------------------------------------------------------------------- single degree of freedom


def sdof_step(mass_kg: float, stiffness_n_per_m: float, force_n: float, damping_ratio: float = 0.0,
              steps_per_period: int = DEFAULT_STEPS_PER_PERIOD, periods: float = 4.0) -> tuple[np.ndarray, np.ndarray]:
    """A mass on a spring (exudyn mass point and spring-damper, the same integrator, step rule and
    tangent-stiffness Rayleigh damping as :func:`launch_transient`) under a force applied
    suddenly at t = 0 from rest: ``(time_s, displacement_m)`` along the force. Closed form: the
    peak is ``(F / k) (1 + exp(-pi zeta / sqrt(1 - zeta^2)))``."""
    import exudyn as exu
    from exudyn.itemInterface import (
        LoadForceVector,
        MarkerBodyPosition,
        MarkerNodePosition,
        NodePoint2D,
        ObjectConnectorCartesianSpringDamper,
        ObjectGround,
        ObjectMassPoint2D,
    )

    m = _check("mass", mass_kg)
    k = _check("stiffness", stiffness_n_per_m)
    zeta = _check("damping ratio", damping_ratio, 0.0, strict=False)
    w = math.sqrt(k / m)
    beta = 2 * zeta / w
    exu.config.printToConsole = False
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    g = mbs.AddObject(ObjectGround())
    nd = mbs.AddNode(NodePoint2D(referenceCoordinates=[0.0, 0.0]))
    mbs.AddObject(ObjectMassPoint2D(mass=m, nodeNumber=nd))
    mn = mbs.AddMarker(MarkerNodePosition(nodeNumber=nd))
    mg = mbs.AddMarker(MarkerBodyPosition(bodyNumber=g, localPosition=[0.0, 0.0, 0.0]))
    keep: list = []
    uf = _cartesian_uf(mbs, keep, [("lin", k, 0, 0, 0, 0), ("lin", k, 0, 0, 0, 0)], beta)
    mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mg, mn], stiffness=[k, k, 0.0],
                                                       damping=[0.0, 0.0, 0.0], springForceUserFunction=uf))
    mbs.AddLoad(LoadForceVector(markerNumber=mn, loadVector=[0.0, -float(force_n), 0.0]))
    mbs.Assemble()
    sys_ = _System(SC, mbs, keep, 1)
    T = 2 * math.pi / w
    record: list = []
    _integrate(sys_, T / steps_per_period, periods * T, "single degree of freedom", 0.0, record)
    ts = np.array([t for t, _ in record])
    ts, idx = np.unique(ts, return_index=True)
    x = np.array([-q[1] for _, q in record])[idx] * math.copysign(1.0, force_n) if force_n else np.zeros(len(idx))
    return ts, x


def sdof_peak_factor(damping_ratio: float) -> float:
    """Closed-form peak / static of a suddenly applied load: ``1 + exp(-pi z / sqrt(1 - z^2))``."""
    z = damping_ratio
    return 1.0 + math.exp(-math.pi * z / math.sqrt(1.0 - z * z))


__all__ = ["DEFAULT_DAMPING_RATIO", "DOCKING_SPEED_M_S", "EVENTS", "Modes", "TransientResult",
           "dynamic_allowance_m", "launch_transient", "support_loss_family", "modes", "sdof_peak_factor", "sdof_step", "tip_of"]
