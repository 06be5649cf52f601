"""Spans with intermediate supports: a structure crossing a void over piers of failed robots (SI).

A **pier** is a column of ``k`` failed robots stacked with the top-down (twist-key) coupling,
standing on the void floor, one robot length wide along the void, its top at the ledge height
(the void depth that makes ``k`` robots reach the ledge is the scenario's, not ours). The swarm
advances its structure as a cantilever from the near ledge to that structure's own threshold
``s`` (the first span, robot widths), a pier is built just beyond its front (near face at
``s``, far face at ``s + 1``), the structure rolls onto the pier top and goes on as a
continuous beam over it, its overhang beyond the pier's far face growing one row at a time
until it reaches the far ledge; a second pier may follow in the same way.

**Pier stiffness** (:func:`pier_stiffness`), ``k`` robots in series, top to floor::

    1 / K_k = k H / (E A) + (k - 1) / k_key

* ``E``: the printed material's modulus, ``youngs_modulus_pa`` of the robot properties record;
* ``A = f L W``: the load-bearing cross-section of one robot body, its footprint ``L x W``
  (``length_m``, ``width_m``) times its fill fraction ``f = min(1, m / (rho L W H))`` (``mass_kg``,
  ``density_kg_m3``, ``height_m``): the printed walls smeared over the footprint, as the
  ``--flexible`` body bending uses it (:func:`structure_fem.model.statics._flexible`). The record's mass
  includes the non-printed parts (motors, battery), so this is an upper bound on the walls'
  section; it does not matter: one body (about 1e8 N/m for the CuBot) is some 200x stiffer
  than one key;
* ``H``: the robot's height (``height_m``), the length in compression;
* ``k_key``: the top twist-lock's vertical stiffness (``top_twist`` connector, ``k_z``: its
  four key arms' vertical bending, hand formula in the record), one per
  interface between two stacked robots, ``k - 1`` of them. In compression the upper robot
  stands on the cover (the pull-out play is tension-only), so the key is in series with the body.

The ledge-like contact between the structure and the pier top (``model.CONTACT_N_PER_M`` per
wheel / caster contact, one-sided: a pier only pushes) is in series with ``K_k`` in the model.

**Model**: the existing exudyn planar model (:func:`structure_fem.model.statics.solve`) with
``Config.piers``: each pier top is a node on a spring ``K_k`` to the floor, the structure rests
on it through one-sided contacts at the robots' wheels and casters that are over it (bottom
corners for a robot without contacts; see :mod:`structure_fem.model.statics` and
:mod:`structure_fem.model.contacts`). The tipping factor is taken about the last support: the
front-most contact on the front-most pier the structure rests on (its far face for a flat
underside), 12 mm short of the far face for the CuBot's front caster.

**Thresholds per span** (:func:`derive`). For ``k = 1..4``, with the first span at the
structure's own cantilever threshold: the widest overhang ``o`` beyond the pier's far face
(whole rows) for which, with the fewest rows behind the far face that keep the structure
standing (solved tipping factor about the far face above the required one; at least one row
on the near ledge), the tip stays within the clearance: the same two criteria as the
cantilever thresholds (:mod:`structure_fem.analysis.study`). Then a second pier of the same height at
the first overhang's limit (near face at ``s + 1 + o1``) and the widest overhang beyond it.

**Counting rule** beyond the last support, in the form of the ledge rule: ``rows behind the
last support's far face >= ratio * rows beyond it + margin``. Rigid bodies of a uniform
structure give a tipping factor of ``(R_b / o)^2`` about the far face, so ``ratio = 1``
(as for the near ledge) and the margin is the smallest that keeps every overhang up to the
derived ones standing, rigidly about the front-most contact at or behind the far face
(:func:`support_edge`: a setback ``s`` lowers the factor to ``(R_b^2 a / 2 - s R_b) / (o^2 a / 2
+ s o)``) and in the solved states (:func:`derive` says which set it).

**Check**: every state of each crossing with the rule's counts (the first span's cantilever
steps with the structure's own rule, the front row on each pier, each overhang step beyond it,
and the front landed on the far ledge) is solved; a cantilever or overhang state must stand
and keep its tip within the clearance (the landed state is reported). Robots move in whole
rows; partial rows over a pier edge are not checked.

Not modelled: the pier's sideways and rocking stability, its buckling (a stack of ``k``
robots joined by one soft twist key each: 47 N m/rad on the CuBot), the lowering of the failed
robots into the void, and any dynamics (robots rolling onto the pier, impact).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from cubot_cad.properties import RobotProperties
from structure_fem.analysis.study import MAX_EXTRA_ROWS, NonConvergence, StudyInputs
from structure_fem.errors import InputError, SolverFailure
from structure_fem.limits import MAX_ARCH_HIGH, PierRule, StructureLevel
from structure_fem.model.connectors import ConnectorSet
from structure_fem.model.statics import CONTACT_N_PER_M, Config, StaticResult, solve
from structure_fem.model.structures import Pier, Structure, layout, rigid_tipping, tipping_factor

#: The tallest pier the rule covers: the thesis stacks robots at most 4 high (its arches,
#: Ch. 5.5.2; ``limits.MAX_ARCH_HIGH``).
MAX_PIER_ROBOTS = MAX_ARCH_HIGH
#: A pier is one robot length wide along the void (a single column of robots).
PIER_WIDTH_WIDTHS = 1
#: Overhang rows tried beyond a pier before the search stops (the overhang is a cantilever of
#: the same couplings: it cannot beat the ledge cantilever by much).
MAX_OVERHANG = 30
#: The structure the rule is derived for by default (the issue asks for the line).
LINE = Structure("line")


@dataclass(frozen=True)
class PierStiffness:
    """Vertical stiffness of a pier of ``robots`` robots (N/m) and its parts."""

    robots: int
    body_n_per_m: float
    key_n_per_m: float | None
    n_per_m: float

    @property
    def formula(self) -> str:
        key = "" if self.key_n_per_m is None else f" + {self.robots - 1} / {self.key_n_per_m:.4g}"
        return f"1 / K = {self.robots} / {self.body_n_per_m:.4g}{key} -> K = {self.n_per_m:.4g} N/m"


def body_stiffness(robot: RobotProperties) -> float:
    """One robot body in compression, ``E f L W / H`` (N/m; see the module docstring)."""
    fill = min(1.0, robot.mass_kg / (robot.density_kg_m3 * robot.length_m * robot.width_m * robot.height_m))
    return robot.youngs_modulus_pa * fill * robot.length_m * robot.width_m / robot.height_m


def pier_stiffness(robot: RobotProperties, conn: ConnectorSet, robots: int) -> PierStiffness:
    """``1 / K = k H / (E A) + (k - 1) / k_key`` for ``robots = k`` stacked robots."""
    if isinstance(robots, bool) or not isinstance(robots, int) or robots < 1:
        raise InputError(f"a pier is made of an integer >= 1 of robots, got {robots!r}")
    kb = body_stiffness(robot)
    if robots == 1:
        return PierStiffness(1, kb, None, kb)
    if conn.top_twist is None:
        raise InputError(f"robot {robot.name!r} has no top_twist connector to stack {robots} robots into a pier")
    kk = conn.top_twist.k_z  # vertical: the key arms (the horizontal stiffness is the key stem's)
    return PierStiffness(robots, kb, kk, 1.0 / (robots / kb + (robots - 1) / kk))


def robot_pier(robot: RobotProperties, conn: ConnectorSet, robots: int, at_widths: float,
               stiffness_scale: float = 1.0) -> Pier:
    """A pier of ``robots`` stacked robots with its near face at ``at_widths`` (``stiffness_scale``
    multiplies its stiffness: studies only)."""
    k = pier_stiffness(robot, conn, robots).n_per_m * stiffness_scale
    return Pier(at_widths, k, PIER_WIDTH_WIDTHS, robots, robots * robot.mass_kg)


# --------------------------------------------------------------------------- one configuration

@dataclass(frozen=True)
class PierSolution:
    """One solved configuration over piers (``fem piers``): the static result and what it means."""

    result: StaticResult
    void_widths: float
    stiffness: tuple[PierStiffness, ...]
    clearance_m: float
    required_tipping: float

    @property
    def passes(self) -> bool:
        r = self.result
        standing = r.tipping_factor > self.required_tipping * (1 + 1e-6)
        return standing and r.tip_deflection_m <= self.clearance_m

    def to_dict(self) -> dict:
        r = self.result
        lay = r.layout
        sup = []
        for f, sp in zip(r.reactions_n, lay.supports, strict=True):
            where = sp.ledge if sp.pier is None else f"pier {sp.pier + 1}"
            sup.append({"support": where, "x_m": sp.point_m[0], "body_row": lay.bodies[sp.body].row,
                        "reaction_n": float(f)})
        tf = r.tipping_factor
        return {
            "structure": r.config.structure.name, "rows": r.config.rows, "rows_over": r.config.rows_over,
            "void_widths": self.void_widths, "robots": r.robots, "weight_n": r.total_weight_n,
            "tip_deflection_mm": r.tip_deflection_mm, "max_deflection_mm": r.max_deflection_m * 1e3,
            "clearance_mm": self.clearance_m * 1e3,
            "tipping_factor": tf if math.isfinite(tf) else None, "tipping_edge_m": r.tipping_edge_m,
            "passes": self.passes,
            "piers": [{"at_widths": p.at_widths, "robots": p.robots, "stiffness_n_per_m": p.stiffness_n_per_m,
                       "stiffness_formula": s.formula, "load_n": load, "compression_mm": c * 1e3}
                      for p, s, load, c in zip(lay.piers, self.stiffness, r.pier_loads_n, r.pier_compression_m,
                                               strict=True)],
            "support_reactions": sup, "support_reactions_sum_n": float(r.reactions_n.sum()),
        }


def _rigid_tipping(s: Structure, inp: StudyInputs, cfg: Config) -> float:
    """Tipping factor of the undeformed layout, about the edge the solved one would use."""
    lay = layout(s, inp.robot, inp.connectors, cfg.rows, cfg.rows_over, cfg.void_widths, cfg.phase, cfg.piers)
    return rigid_tipping(lay)


def solve_piers(inp: StudyInputs, void_widths: float, at_widths: tuple[float, ...], robots: int,
                structure: Structure = LINE, rows: int | None = None,
                rows_over: float | None = None) -> PierSolution:
    """Solve ``structure`` over a ``void_widths``-wide void with piers of ``robots`` robots whose
    near faces are at ``at_widths`` (robot widths from the near edge). ``rows_over`` (default:
    the void width, the front at the far edge: the longest overhang); ``rows`` (default: the
    fewest that keep it standing, at least one on the near ledge). :class:`InputError` for bad
    positions, :class:`SolverFailure` if no row count converges and stands."""
    over = float(void_widths) if rows_over is None else float(rows_over)
    piers = tuple(robot_pier(inp.robot, inp.connectors, robots, float(a)) for a in at_widths)
    stiff = tuple(pier_stiffness(inp.robot, inp.connectors, robots) for _ in piers)
    if rows is not None:
        cfg = Config(structure, rows, over, void_widths, piers=piers)
        return PierSolution(solve(cfg, inp.robot, inp.connectors, inp.flexible), void_widths, stiff,
                            inp.clearance_m, inp.required_tipping)
    need = inp.required_tipping * (1 + 1e-6)
    n = math.floor(over + 1e-9) + 1  # at least one row on the near ledge
    last: StaticResult | None = None
    reason = ""
    for _ in range(MAX_EXTRA_ROWS + 40):
        cfg = Config(structure, n, over, void_widths, piers=piers)
        if _rigid_tipping(structure, inp, cfg) > need:
            try:
                last = solve(cfg, inp.robot, inp.connectors, inp.flexible)
            except SolverFailure as exc:
                reason = str(exc)
                n += 1
                continue
            if last.tipping_factor > need:
                break
        n += 1
    if last is None:
        raise SolverFailure(f"{structure.name} over piers at {list(at_widths)}: no row count converged ({reason})")
    return PierSolution(last, void_widths, stiff, inp.clearance_m, inp.required_tipping)


# --------------------------------------------------------------------------- the derivation

@dataclass(frozen=True)
class PierStudy:
    """Typed inputs of the pier derivation.

    ``first_span``: the structure's own level from the limits (its ``max_span_widths`` is the
    first span, its ``ground_ratio`` / ``ground_margin`` the counting rule of the cantilever
    steps before the pier); ``max_pier_robots``: pier heights ``1..max_pier_robots`` (the
    record uses 4); ``pier_stiffness_scale`` multiplies every pier's stiffness (studies only).
    """

    inputs: StudyInputs
    first_span: StructureLevel
    max_pier_robots: int = MAX_PIER_ROBOTS
    pier_stiffness_scale: float = 1.0
    max_overhang: int = MAX_OVERHANG

    def __post_init__(self) -> None:
        if not (isinstance(self.max_pier_robots, int) and 1 <= self.max_pier_robots <= MAX_PIER_ROBOTS):
            raise InputError(f"max_pier_robots={self.max_pier_robots!r} outside 1..{MAX_PIER_ROBOTS}")
        if not (math.isfinite(self.pier_stiffness_scale) and self.pier_stiffness_scale > 0):
            raise InputError(f"pier stiffness scale must be > 0, got {self.pier_stiffness_scale!r}")
        if self.first_span.tapered:
            raise InputError(f"{self.first_span.name}: piers under a tapering arch are not modelled")

    @property
    def structure(self) -> Structure:
        lv = self.first_span
        arrangement = "staggered" if lv.name.endswith("-staggered") else "aligned"
        return Structure(lv.kind, lv.lines, lv.layers, arrangement)

    @property
    def span(self) -> int:
        return self.first_span.max_span_widths

    def pier(self, robots: int, at_widths: float) -> Pier:
        return robot_pier(self.inputs.robot, self.inputs.connectors, robots, at_widths, self.pier_stiffness_scale)


@dataclass(frozen=True)
class CrossingState:
    """One state of a crossing: ``rows`` rows, the front ``rows_over`` past the near edge;
    ``rows_behind`` / ``rows_beyond`` the last support's far face (for the first span: the rows
    on the near ledge and over the void); ``passes``: stands and its tip is within the clearance
    (landed: converged)."""

    what: str
    rows: int
    rows_over: int
    rows_behind: int
    rows_beyond: int
    tip_mm: float | None
    max_deflection_mm: float | None
    tipping_factor: float | None
    pier_compression_mm: tuple[float, ...]
    passes: bool
    note: str = ""


@dataclass(frozen=True)
class Overhang:
    """The overhang search beyond one pier: per overhang ``o`` the fewest rows behind the far
    face that stand (``rows_behind``), the tip and tipping factor there; ``widest`` the last ``o``
    within the clearance (0: none)."""

    pier_face_widths: int
    widest: int
    rows_behind: tuple[int, ...]
    floor: int
    tip_mm: tuple[float, ...]
    tipping: tuple[float, ...]
    stopped: str


@dataclass(frozen=True)
class PierCrossing:
    """Everything derived for piers of ``robots`` robots: the overhang beyond one pier and beyond
    a second one at its limit, and every state of both crossings at the rule's counts."""

    robots: int
    stiffness: PierStiffness
    one: Overhang
    two: Overhang | None
    states_one: tuple[CrossingState, ...]
    states_two: tuple[CrossingState, ...]

    @property
    def overhang(self) -> int:
        return self.one.widest

    @property
    def overhang_two(self) -> int:
        return 0 if self.two is None else self.two.widest


@dataclass
class PierDerivation:
    study: PierStudy
    rule: PierRule
    crossings: list[PierCrossing]
    failures: list[NonConvergence] = field(default_factory=list)
    margin_source: str = ""

    def to_dict(self) -> dict:
        from cubot_cad.jsonrecord import to_jsonable

        out = {"rule": to_jsonable(self.rule), "margin_source": self.margin_source, "crossings": [],
               "not_converged": [f.to_dict() for f in self.failures]}
        for c in self.crossings:
            out["crossings"].append({
                "robots": c.robots, "stiffness_n_per_m": c.stiffness.n_per_m, "stiffness_formula": c.stiffness.formula,
                "overhang": to_jsonable(c.one), "overhang_second_pier": to_jsonable(c.two),
                "states_one_pier": to_jsonable(c.states_one), "states_two_piers": to_jsonable(c.states_two)})
        return out


class _Solver:
    """Solves of one derivation, with the non-converged ones recorded (never silent)."""

    def __init__(self, study: PierStudy, failures: list[NonConvergence]):
        self.study = study
        self.inp = study.inputs
        self.failures = failures
        self.need = self.inp.required_tipping * (1 + 1e-6)

    def run(self, cfg: Config, what: str, counted: str) -> StaticResult | None:
        try:
            return solve(cfg, self.inp.robot, self.inp.connectors, self.inp.flexible)
        except SolverFailure as exc:
            self.failures.append(NonConvergence(cfg.structure.name, int(round(cfg.void_widths)), what, counted,
                                                str(exc)))
            return None

    def rigid(self, cfg: Config) -> float:
        return _rigid_tipping(cfg.structure, self.inp, cfg)

    def overhang(self, piers: tuple[Pier, ...], robots: int) -> Overhang:
        """Widest overhang beyond the far face of the last of ``piers`` (whole rows)."""
        s = self.study.structure
        face = round(piers[-1].at_widths + piers[-1].width_widths)
        floor = face + 1  # the rows up to the far face + one row on the near ledge
        rows_b, tips, tfs = [], [], []
        stopped = f"search stopped at {self.study.max_overhang} rows"
        for o in range(1, self.study.max_overhang + 1):
            void = face + o
            got = None
            for rb in range(floor, floor + MAX_EXTRA_ROWS):
                cfg = Config(s, rb + o, void, void, piers=piers)
                if self.rigid(cfg) <= self.need:
                    continue
                res = self.run(cfg, f"{o} rows beyond a pier of {robots} robots at {piers[-1].at_widths:g}",
                               "counted as not standing")
                if res is not None and res.tipping_factor > self.need:
                    got = (rb, res)
                    break
            if got is None:
                stopped = f"no row count up to {floor + MAX_EXTRA_ROWS - 1} behind keeps {o} rows beyond standing"
                break
            rb, res = got
            rows_b.append(rb)
            tips.append(res.tip_deflection_mm)
            tfs.append(res.tipping_factor)
            if res.tip_deflection_m > self.inp.clearance_m:
                stopped = f"{o} rows beyond: tip {res.tip_deflection_mm:.2f} mm > clearance"
                break
        # the tip grows with the overhang: the widest is the count before the first failure
        widest = next((i for i, t in enumerate(tips) if t > self.inp.clearance_m * 1e3), len(tips))
        return Overhang(face, widest, tuple(rows_b), floor, tuple(tips), tuple(tfs), stopped)

    def state(self, what: str, cfg: Config, behind: int, beyond: int, landed: bool = False) -> CrossingState:
        res = self.run(cfg, what, "counted as failing the crossing")
        if res is None:
            return CrossingState(what, cfg.rows, int(cfg.rows_over), behind, beyond, None, None, None, (), False,
                                 "did not converge")
        tf = res.tipping_factor
        ok = True if landed else (tf > self.need and res.tip_deflection_m <= self.inp.clearance_m)
        return CrossingState(what, cfg.rows, int(cfg.rows_over), behind, beyond, round(res.tip_deflection_mm, 4),
                             round(res.max_deflection_m * 1e3, 4), round(tf, 4) if math.isfinite(tf) else None,
                             tuple(round(c * 1e3, 5) + 0.0 for c in res.pier_compression_m), ok)


def _rows_behind(ratio: float, margin: int, beyond: int, floor: int) -> int:
    return max(floor, math.ceil(ratio * beyond - 1e-9) + margin)


def _crossing_states(sv: _Solver, piers: tuple[Pier, ...], overhangs: tuple[int, ...], ratio: float,
                     margin: int, first: bool = True) -> tuple[CrossingState, ...]:
    """Every state of the crossing over ``piers`` (overhang ``overhangs[j]`` beyond pier ``j``;
    the last pier's overhang ends at the far ledge) at the rule's counts; ``first``: include the
    first span's cantilever steps and the states up to the last pier (else only those beyond
    the second-to-last pier's overhang)."""
    study = sv.study
    s, span = study.structure, study.span
    lv = study.first_span
    face_last = round(piers[-1].at_widths + piers[-1].width_widths)
    void = face_last + overhangs[-1]
    out: list[CrossingState] = []
    if first:
        for g in range(1, span + 1):
            n_p = max(1, math.ceil(lv.ground_ratio * g - 1e-9) + lv.ground_margin)
            out.append(sv.state(f"cantilever, {g} rows over the void", Config(s, n_p + g, g, void, piers=piers),
                                n_p, g))
    for j, p in enumerate(piers):
        if not first and j < len(piers) - 1:
            continue
        face = round(p.at_widths + p.width_widths)
        floor = face + 1
        for o in range(0, overhangs[j] + 1):
            rb = _rows_behind(ratio, margin, o, floor)
            what = (f"front row on pier {j + 1}" if o == 0 else f"{o} rows beyond pier {j + 1}")
            out.append(sv.state(what, Config(s, rb + o, face + o, void, piers=piers), rb, o))
    o = overhangs[-1]
    rb = _rows_behind(ratio, margin, o, face_last + 1)
    out.append(sv.state("landed: front row on the far ledge",
                        Config(s, rb + o + 1, void + 1, void, "bridged", piers=piers), rb, o, landed=True))
    return tuple(out)


def support_edge(lay, face_m: float) -> float:
    """The line a structure tips about when it rests on a support whose far face is at ``face_m``:
    the front-most ground contact of a layer-0 body at or behind that face (the face itself for
    a robot without contacts: a flat underside tips about the face)."""
    g = lay.ground
    if g is None or g.kind != "contacts":
        return face_m
    xs = [b.x_m + cx for b in lay.bodies if b.layer == 0 for cx, _ in g.points if b.x_m + cx <= face_m + 1e-9]
    return max(xs) if xs else face_m


def _rigid_margin(sv: _Solver, overhangs: list[int], ratio: float) -> int:
    """Smallest margin with which every overhang ``o`` in ``overhangs`` stands rigidly about the
    last support's far face when the rows behind it are ``ratio * o + margin`` (whatever the
    geometry's floor)."""
    s = sv.study.structure
    for m in range(0, 4 * (max(overhangs, default=0) + 2)):
        ok = True
        for o in overhangs:
            rb = max(1, math.ceil(ratio * o - 1e-9) + m)
            n = rb + o
            lay = layout(s, sv.inp.robot, sv.inp.connectors, n, n - 1, n)  # one row on the ledge
            face = lay.bodies[lay.front_body].x_m + lay.length_m / 2 - o * lay.pitch_m
            edge = support_edge(lay, face)
            if tipping_factor(lay.bodies, [b.com_m[0] for b in lay.bodies], edge) <= sv.need:
                ok = False
                break
        if ok:
            return m
    raise SolverFailure("no margin keeps the overhangs standing rigidly")  # pragma: no cover


def derive(study: PierStudy) -> PierDerivation:
    """The pier rule of ``study`` (see the module docstring): overhangs per pier height, with
    one and two piers, the counting rule beyond the last support, and the check of every state."""
    failures: list[NonConvergence] = []
    sv = _Solver(study, failures)
    inp = study.inputs
    span = study.span
    ks = range(1, study.max_pier_robots + 1)
    ones: dict[int, Overhang] = {}
    twos: dict[int, Overhang | None] = {}
    for k in ks:
        p1 = study.pier(k, float(span))
        ones[k] = sv.overhang((p1,), k)
        o1 = ones[k].widest
        if o1 >= 1:
            p2 = study.pier(k, float(span + PIER_WIDTH_WIDTHS + o1))
            twos[k] = sv.overhang((p1, p2), k)
        else:
            twos[k] = None
    ratio = 1.0  # rigid uniform structure: factor (R_b / o)^2 about the far face
    searched = [ov for ov in list(ones.values()) + [t for t in twos.values() if t is not None]]
    overhangs = sorted({o for ov in searched for o in range(1, ov.widest + 1)})
    m_rigid = _rigid_margin(sv, overhangs, ratio)
    solved = [(rb - math.ceil(ratio * (i + 1) - 1e-9)) for ov in searched
              for i, rb in enumerate(ov.rows_behind[:ov.widest]) if rb > ov.floor]
    m_solved = max(solved, default=None)
    margin = m_rigid if m_solved is None else max(m_rigid, m_solved)
    if m_solved is None:
        source = (f"rigid: the fewest rows behind that stand about the far face for every derived overhang "
                  f"(1..{max(overhangs, default=0)}); in every solved overhang state the geometry's floor (the rows "
                  f"up to the pier's far face + one on the near ledge) already exceeds it, so the solves never "
                  f"needed more rows than the floor")
    else:
        source = (f"max of rigid ({m_rigid}) and solved ({m_solved}: rows behind the fewest standing minus the "
                  f"rows beyond, where more than the floor were needed)")

    crossings: list[PierCrossing] = []
    for k in ks:
        p1 = study.pier(k, float(span))
        o1 = ones[k].widest
        if o1 < 1:
            crossings.append(PierCrossing(k, pier_stiffness(inp.robot, inp.connectors, k), ones[k], None, (), ()))
            continue
        st1 = _crossing_states(sv, (p1,), (o1,), ratio, margin)
        bad = [st for st in st1 if not st.passes]
        if bad:  # the rule's counts do not hold every state: keep the overhang that does
            o_ok = _kept_overhang(st1, 1)
            ones[k] = replace(ones[k], widest=o_ok, stopped=ones[k].stopped + f"; checked at the rule's counts: "
                              f"{bad[0].what} fails")
            twos[k] = None
            crossings.append(PierCrossing(k, pier_stiffness(inp.robot, inp.connectors, k), ones[k], None, st1, ()))
            continue
        two = twos[k]
        st2: tuple[CrossingState, ...] = ()
        if two is not None and two.widest >= 1:
            p2 = study.pier(k, float(span + PIER_WIDTH_WIDTHS + o1))
            st2 = _crossing_states(sv, (p1, p2), (o1, two.widest), ratio, margin, first=False)
            bad2 = [st for st in st2 if not st.passes]
            if bad2:
                twos[k] = two = replace(two, widest=_kept_overhang(st2, 2), stopped=two.stopped + f"; checked at the rule's counts: "
                                        f"{bad2[0].what} fails")
        crossings.append(PierCrossing(k, pier_stiffness(inp.robot, inp.connectors, k), ones[k], two, st1, st2))

    states = [st for c in crossings for st in c.states_one + c.states_two if not st.what.startswith("landed")]
    tips = [st.tip_mm for st in states if st.tip_mm is not None]
    tfs = [st.tipping_factor for st in states if st.tipping_factor is not None]
    o_one = tuple(c.overhang for c in crossings)
    o_two = tuple(c.overhang_two for c in crossings)
    stiff = tuple(round(c.stiffness.n_per_m * study.pier_stiffness_scale, 6) for c in crossings)
    voids = tuple(span + PIER_WIDTH_WIDTHS + o for o in o_one)
    notes = _notes(study, crossings, margin, source, failures, voids)
    rule = PierRule(structure=study.first_span.name, first_span_widths=span, pier_width_widths=PIER_WIDTH_WIDTHS,
                    overhang_widths=o_one, overhang_widths_two_piers=o_two, ground_ratio=ratio, ground_margin=margin,
                    max_void_widths=voids, pier_stiffness_n_per_m=stiff,
                    max_deflection_mm=round(max(tips, default=0.0), 3),
                    min_tipping_factor=round(min(tfs, default=math.inf), 4) if tfs else 0.0, notes=notes,
                    standing_height_m=getattr(study.inputs.robot, "standing_height_m", None),
                    stack_pitch_m=getattr(study.inputs.robot, "stack_pitch_m", None),
                    deck_height_m=getattr(study.inputs.robot, "deck_height_m", None))
    return PierDerivation(study, rule, crossings, failures, source)


def _kept_overhang(states, pier: int) -> int:
    """The most rows beyond pier ``pier`` reached before the first state that fails."""
    kept = 0
    for st in states:
        if not st.passes:
            break
        if st.what.endswith(f"beyond pier {pier}"):
            kept = st.rows_beyond
    return kept


def _notes(study: PierStudy, crossings: list[PierCrossing], margin: int, source: str,
           failures: list[NonConvergence], voids: tuple[int, ...]) -> str:
    inp = study.inputs
    span = study.span
    rb = body_stiffness(inp.robot)
    key = inp.connectors.top_twist
    per = "; ".join(
        f"k={c.robots}: K={c.stiffness.n_per_m:.4g} N/m, overhang {c.overhang} beyond one pier "
        f"(tip {c.one.tip_mm[c.overhang - 1]:.2f} mm" + (f", next row {c.one.tip_mm[c.overhang]:.2f} mm"
                                                          if len(c.one.tip_mm) > c.overhang else "")
        + f"), {c.overhang_two} beyond a second pier at {span + PIER_WIDTH_WIDTHS + c.overhang}"
        if c.overhang >= 1 else f"k={c.robots}: K={c.stiffness.n_per_m:.4g} N/m, no safe overhang ({c.one.stopped})"
        for c in crossings)
    failing = [f"{f.what} ({f.counted_as})" for f in failures]
    scale = (f" Pier stiffness scaled x{study.pier_stiffness_scale:g} (study)." if study.pier_stiffness_scale != 1
             else "")
    return (
        f"Derived by structure_fem.piers (the exudyn planar model with each pier as an elastic, one-sided support) "
        f"for {inp.robot.name}, structure {study.first_span.name}, clearance {inp.clearance_m * 1e3:g} mm, tipping "
        f"factor about the last support > {inp.required_tipping:g}. First span = the structure's own cantilever "
        f"threshold {span} (its own rule: rows on the ground >= {study.first_span.ground_ratio:g} x rows over + "
        f"{study.first_span.ground_margin}); pier near face at {span}, far face at {span + PIER_WIDTH_WIDTHS}. "
        f"Pier stiffness 1/K = k H/(E A) + (k-1)/k_key: body E A/H = {rb:.4g} N/m (E = youngs_modulus_pa, A = "
        f"fill x L x W with fill = mass/(density L W H), H = height_m of the robot record), key k_key = "
        + (f"{key.k_z:.4g} N/m (top_twist vertical k_z: {key.provenance or 'record'})" if key else "none")
        + f", in series with the contacts ({CONTACT_N_PER_M:.3g} N/m per wheel / caster contact). Per pier height: {per}. "
        f"Overhang = widest rows past the pier's far face with the fewest rows behind that stand and the tip within "
        f"the clearance; the second pier (same height) stands at the first overhang's limit. Counting rule beyond "
        f"the last support: rows behind its far face >= 1 x rows beyond + {margin} (margin from {source}); at "
        f"least one row stays on the near ledge. Checked: every state of each crossing at these counts (the first "
        f"span's cantilever steps, the front row on each pier, every overhang step, the landed state reported). "
        f"Widest void with one pier: {list(voids)} robot widths (x{max(voids) / span:.3g} the structure's own "
        f"{span}).{scale} Not modelled: the pier's sideways/rocking stability and buckling, the lowering of the "
        f"failed robots, dynamics; whole-row steps only."
        + (f" Static solves that did not converge: {'; '.join(failing)}." if failing else ""))


def own_level(inp: StudyInputs, structure: Structure = LINE) -> StructureLevel:
    """``structure``'s own cantilever level under ``inp`` (threshold and counting rule, as
    :func:`structure_fem.analysis.study.limits_from` makes them): the first span of a pier study when no
    limits record is at hand. :class:`InputError` if it crosses no void."""
    from structure_fem.analysis.study import structure_curve

    c = structure_curve(structure, inp, extra=0)
    if c.threshold < 1:
        raise InputError(f"{structure.name} crosses no void within the {inp.clearance_m * 1e3:g} mm clearance: "
                         "there is no first span to put a pier after")
    idx = [c.index(w, inp) for w in range(1, c.threshold + 1)]
    return StructureLevel(structure.name, structure.kind, structure.lines, structure.layers, 1, c.threshold, 1.0,
                          max(c.rows[i] - 2 * c.widths[i] for i in idx), tuple(c.robots[i] for i in idx),
                          round(c.tip_mm[idx[-1]], 3), round(min(c.tipping[i] for i in idx), 4))


def pier_rule(inputs: StudyInputs, first_span: StructureLevel, **kw) -> PierRule:
    """Shortcut: the :class:`PierRule` of :func:`derive`."""
    return derive(PierStudy(inputs, first_span, **kw)).rule
