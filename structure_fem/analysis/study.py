"""Launch-sequence studies, derived thresholds, minimal counts and the selection table.

Everything here is computed from a robot record and its connectors every
time; nothing is looked up.

Launch sequence of a structure ``R`` rows long over a void ``w`` robot widths
wide (all ``R`` rows joined, as when the whole swarm has been recruited):
cantilever with ``g = 1..w`` rows past the near edge (``R - g`` on the
ground), then bridged (front on the far ledge, rows split between the
ledges), then released row by row at the front; the last phase (the rear
leaving the near ledge, held by the rows on the far ledge) mirrors the
launch. The largest tip deflection is at ``g = w`` (the front just reaching
the far ledge) and the smallest tipping factor too.

* Minimal rows ``R_min(w)``: the fewest rows whose solved tipping factor at
  ``g = w`` exceeds ``required_tipping`` (default 1: the structure stands).
* Threshold of a structure: the widest ``w`` (from 1 upwards, without gaps)
  whose tip deflection at ``g = w`` with ``R_min(w)`` rows is <= the climb
  clearance.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import numpy as np

from cubot_cad.properties import RobotProperties
from structure_fem.errors import InputError, SolverFailure
from structure_fem.limits import StructureLevel, StructureLimits
from structure_fem.model.connectors import ConnectorSet
from structure_fem.model.contacts import ground_support
from structure_fem.model.statics import Config, StaticResult, solve
from structure_fem.model.structures import Structure, layout, rigid_tipping

MAX_WIDTH = 30
CLEARANCE_CHOICES = ("wheel", "caster")


@dataclass(frozen=True)
class StudyInputs:
    """Physical inputs of a study (SI); ``clearance_m``: the step the deflected front can still climb."""

    robot: RobotProperties
    connectors: ConnectorSet
    clearance_m: float
    required_tipping: float = 1.0
    flexible: bool = False
    max_width: int = MAX_WIDTH
    #: Threshold criterion static tip + dynamic overshoot <= clearance (structure_fem.model.dynamics).
    dynamic: bool = False
    #: First-mode damping ratio of the launch transients (structure_fem.model.dynamics.DEFAULT_DAMPING_RATIO).
    damping_ratio: float = 0.02

    def __post_init__(self) -> None:
        if not (math.isfinite(self.clearance_m) and self.clearance_m > 0):
            raise InputError(f"clearance must be > 0 mm, got {self.clearance_m * 1e3:g} mm")
        if not (math.isfinite(self.required_tipping) and self.required_tipping >= 1.0):
            raise InputError(f"required tipping factor must be >= 1, got {self.required_tipping}")
        if not (isinstance(self.max_width, int) and 1 <= self.max_width <= 100):
            raise InputError(f"max width must be an integer in 1..100, got {self.max_width!r}")
        if not (math.isfinite(self.damping_ratio) and 0 <= self.damping_ratio < 1):
            raise InputError(f"damping ratio must be in [0, 1), got {self.damping_ratio!r}")

    @classmethod
    def for_robot(cls, robot: RobotProperties, clearance_mm: float | None = None,
                  stiffness_scale: float = 1.0, backlash_scale: float = 1.0, mass_scale: float = 1.0,
                  **kw) -> StudyInputs:
        """Defaults: the robot's own connectors, clearance = its exposed main-wheel height."""
        for name, v in (("stiffness scale", stiffness_scale), ("mass scale", mass_scale)):
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"{name} must be > 0, got {v!r}")
        if mass_scale != 1.0:
            robot = robot.with_mass_scaled(mass_scale)
        conn = ConnectorSet.from_robot(robot).scaled(stiffness_scale, backlash_scale)
        if clearance_mm is None:
            clearance_m = robot.wheel_exposed_height_m
        else:
            if not (isinstance(clearance_mm, (int, float)) and math.isfinite(clearance_mm) and clearance_mm > 0):
                raise InputError(f"clearance must be > 0 mm, got {clearance_mm!r}")
            clearance_m = clearance_mm / 1e3
        return cls(robot, conn, clearance_m, **kw)

    def provenance(self) -> dict[str, float]:
        """Every numeric input of the derivation (SI), named ``<connector>_<quantity>`` for the
        couplings; :meth:`input_provenance` says where each connector's values come from."""
        out = {"mass_kg": self.robot.mass_kg, "length_m": self.robot.length_m, "height_m": self.robot.height_m,
               "clearance_m": self.clearance_m, "required_tipping": self.required_tipping}
        g = ground_support(self.robot)
        out["front_contact_setback_m"] = g.setback_m(self.robot.length_m)
        for name, j in self._joints():
            out[f"{name}_nm_per_rad"] = j.rotational_nm_per_rad
            out[f"{name}_axial_n_per_m"] = j.axial_n_per_m
            out[f"{name}_shear_n_per_m"] = j.k_z
            out[f"{name}_backlash_rad"] = j.backlash_rad
            out[f"{name}_play_x_closing_m"], out[f"{name}_play_x_opening_m"] = j.play_x
            out[f"{name}_play_z_closing_m"], out[f"{name}_play_z_opening_m"] = j.play_z
            out[f"{name}_height_m"] = j.height_m
        if self.flexible:
            from structure_fem.model.bodies import body_bending

            b = body_bending(self.robot)
            out["body_youngs_modulus_pa"] = b.youngs_modulus_pa
            out["body_second_moment_m4"] = b.second_moment_m4
        if self.dynamic:
            out["damping_ratio"] = self.damping_ratio
        return out

    def _joints(self):
        c = self.connectors
        return [(n, getattr(c, n)) for n in ("front_rear", "side_rail", "top_twist") if getattr(c, n) is not None]

    def input_provenance(self) -> dict[str, str]:
        """Per connector: where its stiffness comes from (``hand formula: ...``, ``fe: ...``,
        ``measured: ...``) and that its play is the CAD's clearances per feature; the robot's
        mass properties from the record's source."""
        g = ground_support(self.robot)
        out = {"robot": self.robot.source,
               "ground_contacts": f"{g.kind} (ledge and pier supports, tipping line): {g.source}"}
        for name, j in self._joints():
            out[name] = j.provenance or "hand formula (legacy record)"
            out[f"{name}_play"] = ("CAD clearances per feature (robot_properties.json play)"
                                   if j.has_translational_play else
                                   "pitch backlash only (no per-feature play in the record)")
        if self.flexible:
            from structure_fem.model.bodies import body_bending

            out["bodies"] = (f"flexible: E = the record's youngs_modulus_pa ({self.robot.material}), I = "
                             f"{body_bending(self.robot).source}")
        else:
            out["bodies"] = "rigid (only the couplings bend)"
        if self.dynamic:
            out["damping_ratio"] = ("assumption: first-mode damping ratio of the launch transients (printed ABS/PLA "
                                    "loss factor 0.01-0.05 plus joint friction; structure_fem.dynamics)")
        return out


def candidate_structures(conn: ConnectorSet, narrow: bool = False) -> list[Structure]:
    """Line; two lines aligned and (sliding rail) staggered; arches 2L wide x L high, L = 2..4
    (the thesis's cross-section, Fig. 5.3). ``narrow`` adds 2-wide arches of the same heights:
    in-plane they bend about as much with far fewer robots, but their sideways stability is
    outside a planar model, so they are reported, never given a band."""
    out = [Structure("line")]
    if conn.side_rail is not None:
        out += [Structure("two_line", 2, 1, "aligned"), Structure("two_line", 2, 1, "staggered")]
        if conn.top_twist is not None:
            out += [Structure("arch", 2 * k, k, "staggered") for k in (2, 3, 4)]
            if narrow:
                out += [Structure("arch", 2, k, "staggered") for k in (2, 3, 4)]
    return out


def _rigid_tipping(s: Structure, inp: StudyInputs, rows: int, w: int) -> float:
    """Tipping factor of the undeformed ``rows``-row layout about its tipping line (the front-most
    near-ledge contact, :func:`structure_fem.model.structures.tipping_edge`)."""
    return rigid_tipping(layout(s, inp.robot, inp.connectors, rows, w, w))


@dataclass(frozen=True)
class NonConvergence:
    """A static solve that did not converge and what the study made of it (never silent).

    ``structure`` and ``width`` (robot widths) name the case, ``what`` the configuration
    (e.g. "longest cantilever"), ``counted_as`` the consequence (e.g. "counted as failing"),
    ``reason`` the solver's message (:class:`~structure_fem.errors.SolverFailure`)."""

    structure: str
    width: int
    what: str
    counted_as: str
    reason: str

    def warning(self, context: str = "") -> str:
        """One ``warning: ...`` line for stderr."""
        ctx = f" ({context})" if context else ""
        return (f"warning: {self.structure} at void width {self.width}{ctx}: {self.what} did not converge, "
                f"{self.counted_as}: {self.reason}")

    def to_dict(self) -> dict:
        return {"structure": self.structure, "width": self.width, "what": self.what, "converged": False,
                "counted_as": self.counted_as, "reason": self.reason}


#: Row counts tried above the rigid minimum before a width counts as failing (not standing).
MAX_EXTRA_ROWS = 20


def min_rows(s: Structure, w: int, inp: StudyInputs,
             failures: list[NonConvergence] | None = None) -> tuple[int, StaticResult]:
    """Fewest rows whose solved tipping factor at the longest cantilever exceeds the requirement.

    A row count whose solve does not converge counts as not standing and the next one is tried;
    if one stands, one entry in ``failures`` says which counts were skipped. If none of them
    stands, :class:`SolverFailure` (the width then counts as failing)."""
    need = inp.required_tipping * (1 + 1e-6)  # "exceeds": a factor of 1 + rounding is not standing
    rows = w + 1
    while _rigid_tipping(s, inp, rows, w) <= need:
        rows += 1
    skipped: list[int] = []
    reason = ""
    for _ in range(MAX_EXTRA_ROWS):
        try:
            res = solve(Config(s, rows, w, w), inp.robot, inp.connectors, inp.flexible)
        except SolverFailure as exc:
            skipped.append(rows)
            reason = reason or str(exc)
            rows += 1
            continue
        if res.tipping_factor > need:
            if skipped and failures is not None:
                failures.append(NonConvergence(
                    s.name, w, f"longest cantilever with {', '.join(map(str, skipped))} rows",
                    f"counted as not standing, {rows} rows used", reason))
            return rows, res
        rows += 1
    if skipped:
        raise SolverFailure(f"{s.name}: no converged solve keeps a {w}-wide cantilever standing with up to "
                            f"{rows - 1} rows ({len(skipped)} did not converge; first: {reason})")
    raise SolverFailure(f"{s.name}: no row count up to {rows - 1} keeps a {w}-wide cantilever standing")


def table_rows(structure: Structure, void_width: int | float, props: RobotProperties,
               connectors: ConnectorSet | None = None, flexible: bool = False) -> int:
    """The table's rows at ``void_width``: the fewest that keep the longest cantilever standing
    (:func:`min_rows`; the clearance does not enter)."""
    conn = ConnectorSet.from_robot(props) if connectors is None else connectors
    inp = StudyInputs(props, conn, props.wheel_exposed_height_m or 0.015, flexible=flexible)
    w = int(void_width) if float(void_width).is_integer() else void_width
    return min_rows(structure, w, inp)[0]


@dataclass
class Curve:
    """A structure's tip deflection and tipping factor at its longest cantilever, per void width
    (only the widths the threshold search or the table needed, sorted)."""

    structure: Structure
    widths: list[int] = field(default_factory=list)
    tip_mm: list[float] = field(default_factory=list)
    tipping: list[float] = field(default_factory=list)
    rows: list[int] = field(default_factory=list)
    robots: list[int] = field(default_factory=list)
    threshold: int = 0
    #: Solves that did not converge (the widths among them count as failing: not in ``widths``).
    failures: list[NonConvergence] = field(default_factory=list)
    #: The static threshold (tip <= clearance) when ``threshold`` is the dynamic one (None: static study).
    static_threshold: int | None = None
    #: Dynamic allowance (mm, structure_fem.model.dynamics.dynamic_allowance_m) per width where it was computed.
    allowance_mm: dict[int, float] = field(default_factory=dict)

    def index(self, w: int, inp: StudyInputs | None = None) -> int:
        """Index of width ``w``, solving it first (minimal rows, longest cantilever) if missing;
        :class:`SolverFailure` if that does not converge."""
        if w in self.widths:
            return self.widths.index(w)
        if inp is None:
            raise KeyError(f"{self.structure.name}: width {w} not solved")
        rows, res = min_rows(self.structure, w, inp, self.failures)
        i = bisect.bisect(self.widths, w)
        for name, v in (("widths", w), ("tip_mm", res.tip_deflection_mm), ("tipping", res.tipping_factor),
                        ("rows", rows), ("robots", res.robots)):
            getattr(self, name).insert(i, v)
        return i


#: Widths solved one by one before the threshold search starts doubling.
DENSE_WIDTHS = 8


def structure_curve(s: Structure, inp: StudyInputs, extra: int = 1, tick: Callable[[], None] | None = None,
                    dynamic: bool | None = None) -> Curve:
    """The threshold of ``s``: widths 1..8 one by one, then doubling, then bisection.

    The tip deflection at the longest cantilever grows with the void width (more
    overhang, same couplings), which the search relies on; ``extra`` widths past
    the first failing one are added for the plots (a solver failure there only
    ends the curve: those configurations are already out of bounds).

    A width whose solve does not converge counts as failing (the last resort: the solver
    settings of :mod:`structure_fem.model.statics` converge on every shipped record); it is kept
    in ``Curve.failures`` and reported, never dropped silently.

    ``dynamic`` (default ``inp.dynamic``): step down to the dynamic threshold here; ``False``
    leaves the static one (:func:`apply_dynamic` steps many curves down at once).
    """
    c = Curve(s)
    clear = inp.clearance_m * 1e3

    def passes(w: int) -> bool:
        try:
            i = c.index(w, inp)
        except SolverFailure as exc:
            c.failures.append(NonConvergence(s.name, w, "longest cantilever", "counted as failing", str(exc)))
            return False
        finally:
            if tick:
                tick()
        return c.tip_mm[i] <= clear

    lo, hi, w = 0, None, 1
    while w <= inp.max_width:
        if not passes(w):
            hi = w
            break
        lo = w
        if w == inp.max_width:
            break
        w = w + 1 if w < DENSE_WIDTHS else min(2 * w, inp.max_width)
    if hi is not None:
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if passes(mid):
                lo = mid
            else:
                hi = mid
        for e in range(1, extra + 1):
            if hi + e > inp.max_width or hi + e - 1 not in c.widths:
                break
            try:
                c.index(hi + e, inp)
            except SolverFailure as exc:
                c.failures.append(NonConvergence(s.name, hi + e, "longest cantilever (past the threshold, "
                                                 "for the plots)", "left out of the plots", str(exc)))
                break
    c.threshold = lo
    if inp.dynamic if dynamic is None else dynamic:
        apply_dynamic([(c, inp)])
    return c


def apply_dynamic(pairs: list[tuple[Curve, StudyInputs]], progress: Callable[[Iterable, str, int], Iterable]
                  | None = None, workers: int | None = None, label: str = "launch transients") -> None:
    """Turn each curve's static threshold into the dynamic one under its inputs
    (:func:`dynamic_threshold`). The launch transients at every curve's static threshold are
    integrated first, side by side in ``workers`` processes
    (:func:`structure_fem.model.dynamics_cache.prefill`); the step-down then finds them cached. A width
    whose static solve fails here is left to the step-down (which counts it as failing)."""
    from structure_fem.model.dynamics_cache import Job, prefill

    jobs = []
    for c, inp in pairs:
        if c.threshold >= 1:
            try:
                i = c.index(c.threshold, inp)
            except SolverFailure:
                continue
            jobs.append(Job(c.structure, c.threshold, c.rows[i], inp.robot, inp.connectors, inp.flexible,
                            inp.damping_ratio))
    prefill(jobs, workers, progress=progress, label=label)
    for c, inp in pairs:
        c.static_threshold = c.threshold
        c.threshold = dynamic_threshold(c, inp)


def dynamic_threshold(c: Curve, inp: StudyInputs) -> int:
    """Step down from the static threshold ``c.threshold`` to the widest width whose static tip +
    dynamic allowance (the larger overshoot of the support-loss and docking transients,
    :func:`structure_fem.model.dynamics.dynamic_allowance_m`, through :mod:`structure_fem.model.dynamics_cache`)
    stays within the clearance. A transient that does not converge counts as failing (one
    ``NonConvergence``), as a static solve does."""
    from structure_fem.model.dynamics_cache import allowance_m

    clear = inp.clearance_m * 1e3
    w = c.threshold
    while w >= 1:
        i = c.index(w, inp)
        try:
            res = solve(Config(c.structure, c.rows[i], w, w), inp.robot, inp.connectors, inp.flexible)
            a = 1e3 * allowance_m(c.structure, w, inp.robot, inp.damping_ratio, rows=c.rows[i],
                                  connectors=inp.connectors, flexible=inp.flexible, static=res)
        except SolverFailure as exc:
            c.failures.append(NonConvergence(c.structure.name, w, "launch transient", "counted as failing", str(exc)))
            w -= 1
            continue
        c.allowance_mm[w] = a
        if c.tip_mm[i] + a <= clear:
            return w
        w -= 1
    return 0


@dataclass
class Derivation:
    inputs: StudyInputs
    curves: list[Curve]
    levels: list[tuple[Structure, int, int]]  # (structure, first width, last width)
    #: Non-converged solves outside the threshold search (table launch steps, tapering arches, plots).
    other_failures: list[NonConvergence] = field(default_factory=list)

    def curve(self, name: str) -> Curve:
        return next(c for c in self.curves if c.structure.name == name)

    @property
    def failures(self) -> list[NonConvergence]:
        """Every solve of this derivation that did not converge, and what was made of it."""
        return [f for c in self.curves for f in c.failures] + list(self.other_failures)

    def thresholds(self) -> dict:
        """Each kind's own widest crossing: ``line``, best ``two_line``, first ``arch``, wider ``arch_levels``."""
        by = {c.structure.name: c.threshold for c in self.curves}
        two = [c.threshold for c in self.curves if c.structure.kind == "two_line"]
        arches = [c.threshold for c in self.curves
                  if c.structure.kind == "arch" and c.structure.lines >= 2 * c.structure.layers]
        return {"line": by.get("line", 0), "two_line": max(two, default=0),
                "arch": arches[0] if arches else 0, "arch_levels": arches[1:],
                "per_structure": by}

    @property
    def max_span(self) -> int:
        return self.levels[-1][2] if self.levels else 0


def derive(inp: StudyInputs, progress: Callable[[Iterable, str, int], Iterable] | None = None,
           extra: int = 1, narrow: bool = False) -> Derivation:
    """Curves of all candidate structures and the levels that tile 1..max span.

    A structure gets a band only if it crosses wider than every cheaper one
    before it (aligned two-line lines add no bending stiffness, so they get
    none when they equal the line)."""
    structs = candidate_structures(inp.connectors, narrow)
    for s in structs:
        s.check_connectors(inp.connectors, inp.robot.name)
    it = structs if progress is None else progress(structs, "fem structures", len(structs))
    curves = [structure_curve(s, inp, extra, dynamic=False) for s in it]
    if inp.dynamic:
        apply_dynamic([(c, inp) for c in curves], progress)
    return Derivation(inp, curves, levels_of(curves))


def levels_of(curves: list[Curve]) -> list[tuple[Structure, int, int]]:
    """The bands: each structure (in the cheaper-first order of the curves) that crosses wider than
    every one before it, from one past the previous band to its threshold."""
    levels = []
    covered = 0
    for c in curves:
        if c.structure.kind == "arch" and c.structure.lines < 2 * c.structure.layers:
            continue  # narrow arches: reported only
        if c.threshold > covered:
            levels.append((c.structure, covered + 1, c.threshold))
            covered = c.threshold
    return levels


def limits_from(d: Derivation, source: str = "derived") -> StructureLimits:
    """The `StructureLimits` record of a derivation (levels tile 1..max span without gaps)."""
    inp = d.inputs
    if not d.levels:
        raise InputError(
            f"no structure keeps the tip deflection of even a 1-wide void within the "
            f"{inp.clearance_m * 1e3:g} mm clearance for robot {inp.robot.name!r}")
    lv = []
    for s, lo, hi in d.levels:
        c = d.curve(s.name)
        for w in range(lo, hi + 1):
            c.index(w, inp)
        idx = [c.widths.index(w) for w in range(lo, hi + 1)]
        margins = [c.rows[i] - 2 * c.widths[i] for i in idx]
        lv.append(StructureLevel(
            name=s.name, kind=s.kind, lines=s.lines, layers=s.layers, min_span_widths=lo,
            max_span_widths=hi, ground_ratio=1.0, ground_margin=max(margins),
            min_robots=tuple(c.robots[i] for i in idx),
            max_deflection_mm=round(c.tip_mm[idx[-1]], 3), min_tipping_factor=round(min(c.tipping[i] for i in idx), 4),
            dynamic_allowance_mm=(round(c.allowance_mm[hi], 3) if hi in c.allowance_mm else None)))
    th = d.thresholds()
    def narrow(s: Structure) -> bool:
        return s.kind == "arch" and s.lines < 2 * s.layers

    skipped = [c.structure.name for c in d.curves
               if not narrow(c.structure) and all(c.structure != s for s, _, _ in d.levels)]
    narrows = [f"{c.structure.name} to {c.threshold} with {c.robots[c.widths.index(c.threshold)]} robots"
               for c in d.curves if narrow(c.structure) and c.threshold]
    failing = [f"{f.structure} at width {f.width}" for f in d.failures if f.counted_as == "counted as failing"]
    hinge = ("emergent hinges (tension rows with their play + compression-only face contacts where the faces "
             "touch, sliding side rails)" if inp.connectors.hinge == "emergent" else
             "lumped couplings (pitch dead band = tension play / highest pin, side rails as ties)")
    notes = (f"Derived by structure_fem (exudyn planar multibody, penalty couplings, {hinge}, "
             f"translational play per feature from the CAD clearances) for "
             f"{inp.robot.name}: clearance {inp.clearance_m * 1e3:g} mm, tipping factor > {inp.required_tipping:g}; "
             + ("flexible bodies (each robot bends with its printed shell's section from the CAD)" if inp.flexible
                else "rigid bodies")
             + ("; criterion static tip + launch-transient allowance (a row leaving the ledge, a recruit docking; "
                f"damping ratio {inp.damping_ratio:g}) <= clearance" if inp.dynamic else "; criterion static tip <= clearance")
             + ". "
             f"Own thresholds per structure: {th['per_structure']}"
             + ("" if not inp.dynamic else
                f" (static criterion alone: {dict((c.structure.name, c.static_threshold) for c in d.curves)})")
             + ". "
             f"Rows on the initial ground >= rows over the void + margin (n_p = n_g + margin) replaces the thesis's "
             f"n_p = 2 n_g. Widest void crossed: {d.max_span} robot widths"
             + (" (< 30: no structure up to 8 wide x 4 high keeps the tip within the clearance beyond it)"
                if d.max_span < MAX_WIDTH else "")
             + (f". No band (adds nothing over a cheaper structure): {', '.join(skipped)}" if skipped else "")
             + (f". Narrow 2-wide arches (fewer robots in-plane; not banded because their sideways stability "
                f"is outside a planar model): {'; '.join(narrows)}" if narrows else "")
             + (f". Static solves that did not converge, counted as failing: {'; '.join(failing)}" if failing else "")
             + ".")
    return StructureLimits(source=source, robot=inp.robot.name, clearance_mm=round(inp.clearance_m * 1e3, 6),
                           levels=tuple(lv), notes=notes, inputs=inp.provenance(),
                           input_provenance=inp.input_provenance())


# --------------------------------------------------------------------------- the selection table

def thesis_robots(w: int) -> int:
    from structure_fem.limits import thesis_limits
    return thesis_limits().min_robots(w)


@dataclass(frozen=True)
class TableRow:
    width: int
    band: str
    structure: str
    lines: int | None
    layers: int | None
    min_robots: int | None
    thesis_robots: int
    launch_initial: int | None
    launch_over: int | None
    launch_target: int | None
    bridged_initial: int | None
    bridged_over: int | None
    bridged_target: int | None
    max_deflection_mm: float | None
    bridged_deflection_mm: float | None
    margin_mm: float | None
    min_tipping_factor: float | None
    thesis_count_tipping: float | None
    case_a_count_tipping: float | None
    #: False when a launch step or the bridged state of this row did not converge (``note`` says which;
    #: the row's deflections and tipping then cover the converged states only).
    converged: bool = True
    note: str = ""


def _split(s: Structure, rows_initial: int, rows_over: int, rows_target: int) -> tuple[int, int, int]:
    """Robots on the initial ground / over the void / on the target ground (offset lines counted where their centres are)."""
    per = s.layers * sum(s.parity_counts)
    return rows_initial * per, rows_over * per, rows_target * per


#: What a launch step or bridged state of a table row that does not converge is counted as.
TABLE_ROW_FAILURE = "left out of the table row"

#: Launch sequences up to this width are solved at every step; wider ones at quarter points.
FULL_STEPPING = 6


def launch_steps(w: int) -> list[int]:
    """Cantilever steps g < w solved besides g = w (where tip and tipping are worst)."""
    if w <= FULL_STEPPING:
        return list(range(1, w))
    return sorted({1, *(math.ceil(w * f) for f in (0.25, 0.5, 0.75))} - {w})


def _row_solve(d: Derivation, cfg: Config, what: str, missing: list[str]) -> StaticResult | None:
    """A table row's extra solve; ``None`` (noted in ``missing`` and ``d.other_failures``) if it
    does not converge."""
    inp = d.inputs
    try:
        return solve(cfg, inp.robot, inp.connectors, inp.flexible)
    except SolverFailure as exc:
        missing.append(what)
        d.other_failures.append(NonConvergence(cfg.structure.name, int(cfg.void_widths), what, TABLE_ROW_FAILURE,
                                               str(exc)))
        return None


def table(d: Derivation, progress: Callable[[Iterable, str, int], Iterable] | None = None,
          step_launch: bool = True) -> list[TableRow]:
    """The selection table for w = 1..max width, stepping through each launch sequence."""
    inp = d.inputs
    rows_out = []
    widths = range(1, inp.max_width + 1)
    it = widths if progress is None else progress(widths, "fem table", len(widths))
    for w in it:
        trob = thesis_robots(w) if w <= 30 else 0
        band = next(((s, lo, hi) for s, lo, hi in d.levels if lo <= w <= hi), None)
        if band is None:
            rows_out.append(TableRow(w, "beyond", "none", None, None, None, trob, *([None] * 6), None, None, None,
                                     None, None, None))
            continue
        s, lo, hi = band
        c = d.curve(s.name)
        i = c.index(w, inp)
        R = c.rows[i]
        tips, tfs = [c.tip_mm[i]], [c.tipping[i]]
        missing: list[str] = []
        if step_launch:
            for g in launch_steps(w):
                res = _row_solve(d, Config(s, R, g, w), f"launch step with {g} rows over the void", missing)
                if res is not None:
                    tips.append(res.tip_deflection_mm)
                    tfs.append(res.tipping_factor)
        n_o = (R - w) // 2
        n_p = R - w - n_o
        bridged = _row_solve(d, Config(s, R, w + n_o, w, "bridged"), "bridged state", missing)
        # Thesis count on this structure: N = 3 n_g rows (n_p = 2 n_g at the longest cantilever).
        t_tip = _rigid_tipping(s, inp, 3 * w, w)
        a_tip = _rigid_tipping(s, inp, 3 * w + 2, w)  # case A: n_p, n_o >= n_g + 1
        li, lo_, lt = _split(s, R - w, w, 0)
        bi, bo, bt = _split(s, n_p, w, n_o)
        maxdef = max(tips)
        rows_out.append(TableRow(
            w, f"{lo}-{hi}", s.name, s.lines, s.layers, c.robots[i], trob, li, lo_, lt, bi, bo, bt,
            round(maxdef, 3), None if bridged is None else round(bridged.max_deflection_m * 1e3, 3),
            round(inp.clearance_m * 1e3 - maxdef, 3), round(min(tfs), 4), round(t_tip, 4), round(a_tip, 4),
            not missing, "did not converge: " + ", ".join(missing) if missing else ""))
    return rows_out


# --------------------------------------------------------------------------- the thesis's tapering arches

@dataclass(frozen=True)
class TaperRow:
    """The thesis's tapering arch of one level at one void width, under our mechanics.

    ``tip_mm`` / ``tipping_factor``: the core front just reaching the far ledge (``g = w``),
    near foot only, ``k B`` core rows on the initial ground (the thesis's count);
    ``tip_mm`` is None when the arch tips there (rigid factor <= required) or the solver
    finds no equilibrium (``note`` says which). ``bridged_max_mm``: largest deflection of
    the complete arch on both feet. ``passes``: stands and ``tip_mm <= clearance``.
    ``uniform_*``: the derived band's structure at ``w`` (None beyond the derived span);
    ``same_section_*``: the uniform ``2k x k`` staggered arch at ``w`` where the derivation
    solved it (only up to just past its own threshold).
    """

    level: str
    width: int
    structure: str
    lines: int
    layers: int
    block_rows: int
    robots: int
    robots_before_landing: int
    tip_mm: float | None
    tipping_factor: float | None
    bridged_max_mm: float | None
    margin_mm: float | None
    passes: bool
    uniform_structure: str | None
    uniform_robots: int | None
    uniform_tip_mm: float | None
    same_section_structure: str
    same_section_robots: int | None
    same_section_tip_mm: float | None
    note: str = ""


def tapered_structure(lvl: StructureLevel) -> Structure:
    """The planar structure of a tapering `StructureLevel` (``taper_block_rows`` set)."""
    if not lvl.tapered:
        raise InputError(f"structure {lvl.name!r} does not taper (taper_block_rows is None)")
    return Structure("arch", lvl.lines, lvl.layers, "aligned", lvl.taper_block_rows)


#: A robot of a tapering arch turned further than this (rad, nose down) before landing: the arch
#: hangs into the void, collapsed (its front hundreds of mm below the ledge; with the packaged
#: record the thesis's 8 x 4 arch reaches it at 25 widths: tip 596 mm, a robot turned 0.53 rad).
#: Wider voids of the same arch only add overhang, so :func:`tapered_arches` reports them as
#: collapsed instead of solving them: their static solves did not converge and each cost minutes
#: of retries on a 470-robot model.
COLLAPSE_ROTATION_RAD = 0.5


def tapered_point(s: Structure, w: int, inp: StudyInputs, collapsed: tuple[int, float] | None = None) -> dict:
    """Tip and tipping factor at ``g = w`` before landing, largest deflection bridged (mm).

    ``collapsed`` = (width, rad): the same arch already hung a robot that far at that narrower width
    (:data:`COLLAPSE_ROTATION_RAD`): the state before landing is reported as collapsed, not solved.
    ``max_rotation_rad`` is the largest turn of a robot before landing (None when not solved)."""
    foot = s.foot_rows
    before = Config(s, foot + w, w, w)
    need = inp.required_tipping * (1 + 1e-6)
    out: dict = {"tip_mm": None, "tipping_factor": None, "bridged_max_mm": None, "note": "", "failures": [],
                 "max_rotation_rad": None}
    lay = layout(s, inp.robot, inp.connectors, before.rows, w, w)
    rigid = rigid_tipping(lay)
    out["tipping_factor"] = rigid
    if rigid <= need:
        out["note"] = f"tips before landing (rigid tipping factor {rigid:.3g})"
    elif collapsed is not None:
        out["note"] = (f"collapsed before landing: at {collapsed[0]} widths a robot of this arch already hung "
                       f"{collapsed[1]:.2f} rad nose down; a wider void only adds overhang (not solved)")
    else:
        try:
            res = solve(before, inp.robot, inp.connectors, inp.flexible)
            out["tip_mm"] = res.tip_deflection_mm
            out["tipping_factor"] = res.tipping_factor
            out["max_rotation_rad"] = float(np.max(np.abs(res.rotation_rad)))
        except SolverFailure as exc:
            out["note"] = "the static solve before landing did not converge (counted as not holding)"
            out["failures"].append(("before landing (core front at the far edge)", "counted as not holding",
                                    str(exc)))
    try:
        br = solve(Config(s, 2 * foot + w, w + foot, w, "bridged"), inp.robot, inp.connectors, inp.flexible)
        out["bridged_max_mm"] = br.max_deflection_m * 1e3
    except SolverFailure as exc:
        out["note"] = (out["note"] + "; " if out["note"] else "") + "the bridged static solve did not converge"
        out["failures"].append(("bridged on both feet", "bridged deflection left out", str(exc)))
    return out


def _r(v: float | None, nd: int) -> float | None:
    return None if v is None or not math.isfinite(v) else round(v, nd)


def tapered_not_applicable(conn: ConnectorSet, robot: str) -> str:
    """Why the thesis's tapering arches cannot be built with these couplings ("" if they can)."""
    missing = [name for name in ("side_rail", "top_twist") if getattr(conn, name) is None]
    return (f"robot {robot!r} has no {' or '.join(missing)} connector: the thesis's tapering arches "
            "(lines side by side, layers) cannot be built" if missing else "")


def tapered_arches(d: Derivation, thesis: StructureLimits | None = None,
                   progress: Callable[[Iterable, str, int], Iterable] | None = None) -> list[TaperRow]:
    """Every width of every tapering level of the thesis preset, with our connectors and robot
    record (``d.inputs``), beside the derived uniform arches at the same width where they exist.
    Reads the derivation's curves; solves nothing on them (the derived limits stay as they are).
    A robot without side rails and top twist-locks cannot build them: no rows
    (:func:`tapered_not_applicable` says why)."""
    from structure_fem.limits import thesis_limits

    inp = d.inputs
    if tapered_not_applicable(inp.connectors, inp.robot.name):
        return []
    thesis = thesis_limits(inp.robot.name) if thesis is None else thesis
    clear = inp.clearance_m * 1e3
    need = inp.required_tipping
    jobs = [(lvl, w) for lvl in thesis.levels if lvl.tapered
            for w in range(lvl.min_span_widths, lvl.max_span_widths + 1)]
    it = jobs if progress is None else progress(jobs, "thesis tapering arches", len(jobs))
    by_name = {c.structure.name: c for c in d.curves}
    out = []
    collapsed: dict[str, tuple[int, float]] = {}  # arch name -> (width, rad) where it first hung
    for lvl, w in it:
        s = tapered_structure(lvl)
        p = tapered_point(s, w, inp, collapsed.get(s.name))
        rot = p["max_rotation_rad"]
        if rot is not None and rot > COLLAPSE_ROTATION_RAD and s.name not in collapsed:
            collapsed[s.name] = (w, rot)
        d.other_failures.extend(NonConvergence(s.name, w, what, counted, reason)
                                for what, counted, reason in p["failures"])
        band = next(((u, lo, hi) for u, lo, hi in d.levels if lo <= w <= hi), None)
        u_name = u_rob = u_tip = None
        if band is not None:
            c = by_name[band[0].name]
            if w in c.widths:
                i = c.widths.index(w)
                u_name, u_rob, u_tip = c.structure.name, c.robots[i], _r(c.tip_mm[i], 3)
        same = Structure("arch", s.lines, s.layers, "staggered")
        c = by_name.get(same.name)
        s_rob = s_tip = None
        if c is not None and w in c.widths:
            i = c.widths.index(w)
            s_rob, s_tip = c.robots[i], _r(c.tip_mm[i], 3)
        tip = p["tip_mm"]
        stands = p["tipping_factor"] is not None and p["tipping_factor"] > need
        out.append(TaperRow(
            lvl.name, w, s.name, s.lines, s.layers, s.taper_block_rows, s.tapered_robots(w)["total"],
            s.tapered_robots(w, far_foot=False)["total"], _r(tip, 3), _r(p["tipping_factor"], 4),
            _r(p["bridged_max_mm"], 3), None if tip is None else round(clear - tip, 3),
            bool(stands and tip is not None and tip <= clear), u_name, u_rob, u_tip, same.name, s_rob, s_tip,
            p["note"]))
    return out


def tapered_verdict(rows: list[TaperRow], clearance_mm: float) -> dict:
    """One summary per thesis level and overall: widths passing, worst tip, largest bridged deflection."""
    levels = {}
    for r in rows:
        e = levels.setdefault(r.level, {"widths": [r.width, r.width], "passing_widths": [], "max_tip_mm": None,
                                        "min_tip_mm": None, "max_bridged_mm": None, "min_tipping_factor": None})
        e["widths"][1] = r.width
        if r.passes:
            e["passing_widths"].append(r.width)
        for key, v, f in (("max_tip_mm", r.tip_mm, max), ("min_tip_mm", r.tip_mm, min),
                          ("max_bridged_mm", r.bridged_max_mm, max), ("min_tipping_factor", r.tipping_factor, min)):
            if v is not None:
                e[key] = v if e[key] is None else f(e[key], v)
    passing = [r.width for r in rows if r.passes]
    return {"clearance_mm": clearance_mm, "levels": levels, "widths_evaluated": len(rows),
            "widths_passing": passing, "all_hold": bool(rows) and len(passing) == len(rows),
            "bridged_within_clearance": all(r.bridged_max_mm is not None and r.bridged_max_mm <= clearance_mm
                                            for r in rows)}
