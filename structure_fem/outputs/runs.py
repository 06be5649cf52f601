"""What `voidcross fem table` / `fem study` and the pipeline stage run: inputs -> files.

Everything is recomputed from the robot record each call; the packaged
``structure_fem/data/limits.json`` is :func:`packaged_limits` written to disk
(a test regenerates it and fails if it no longer matches).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from pathlib import Path

from cubot_cad.properties import RobotProperties, RobotPropertiesFile, load_properties
from structure_fem.analysis.calibration import Calibration, calibrate, calibrated_connectors
from structure_fem.analysis.study import (
    Derivation,
    NonConvergence,
    StudyInputs,
    derive,
    limits_from,
    table,
    tapered_arches,
)
from structure_fem.errors import InputError, SolverFailure
from structure_fem.limits import StructureLimits
from structure_fem.model.connectors import ConnectorSet
from structure_fem.model.statics import Config, solve
from structure_fem.outputs.outputs import (
    summary,
    table_csv,
    table_markdown,
    tapered_csv,
    tapered_markdown,
    write_text_atomic,
)

#: ``fe``: finite-element results where one applies to the record's geometry (cached or packaged,
#: :mod:`structure_fem.couplings.connector_sources`), the record's hand formula elsewhere; ``properties``:
#: the record's hand formulas only; ``calibrated``: those scaled by the platform bolt fit.
CONNECTOR_SOURCES = ("fe", "properties", "calibrated")
#: ``auto``: derive the pier rule (:mod:`structure_fem.analysis.piers`) into limits.json; ``none``: leave it out.
PIER_CHOICES = ("auto", "none")
Progress = Callable[[Iterable, str, int], Iterable]


@dataclass(frozen=True)
class RunOptions:
    """CLI-level knobs; ``None`` clearance = the robot's exposed main-wheel height."""

    properties: str | None = None
    robot: str = "cubot"
    clearance_mm: float | None = None
    caster: bool = False
    connectors: str = "fe"
    #: A measured-coupling JSON (``connector_sources.load_measured``): replaces those connectors.
    measured: str | None = None
    stiffness_scale: float = 1.0
    backlash_scale: float = 1.0
    mass_scale: float = 1.0
    required_tipping: float = 1.0
    #: The robots bend with their printed shell's section (structure_fem.model.bodies; the default);
    #: False: rigid bodies, only the couplings are compliant (``--rigid``).
    flexible: bool = True
    calibration_backlash: float | None = None
    max_width: int = 30
    #: Derive the pier (multi-span) rule into the limits (``auto``) or not (``none``).
    piers: str = "auto"
    #: Threshold criterion static tip + launch-transient overshoot <= clearance (the default;
    #: :mod:`structure_fem.model.dynamics`, exudyn time integration at the threshold, 1-120 s per structure
    #: cold, cached by input hash in :mod:`structure_fem.model.dynamics_cache`); False: static tip <= clearance.
    dynamic: bool = True
    #: First-mode damping ratio of the launch transients (an assumption: dynamics.DEFAULT_DAMPING_RATIO).
    damping_ratio: float = 0.02
    #: ``fem study``: the sensitivity grid by the table's criterion too (each grid point's launch
    #: transients, all of them side by side; ~72 more integrations, tens of minutes cold); False
    #: (the default): the grid by the static tip, labelled so.
    sensitivity_dynamic: bool = False
    #: How couplings whose faces touch are modelled (:data:`structure_fem.model.hinge.HINGES`; ``--hinge``).
    hinge: str = "emergent"
    #: Latin-hypercube samples of the thresholds' uncertainty band (:mod:`structure_fem.analysis.band`;
    #: ``--band [N]``); 0: no band.
    band_samples: int = 0
    #: With a band: which thresholds the table and limits.json use (:data:`structure_fem.analysis.band.PICKS`).
    pick: str = "p5"
    #: ``fem table``: each structure's range over plausible inputs (:mod:`structure_fem.analysis.margins`:
    #: print clearance 0.1 / 0.4 mm, printed modulus, solid parts, the worst case; about half of a
    #: cold table's solves); False (``--no-ranges``): margins and what sets them without the range.
    ranges: bool = True

    def __post_init__(self) -> None:
        from structure_fem.model.hinge import HINGES

        if self.hinge not in HINGES:
            raise InputError(f"--hinge {self.hinge!r} is not one of {', '.join(HINGES)}")
        if self.connectors not in CONNECTOR_SOURCES:
            raise InputError(f"--connectors {self.connectors!r} is not one of {', '.join(CONNECTOR_SOURCES)}")
        if self.piers not in PIER_CHOICES:
            raise InputError(f"--piers {self.piers!r} is not one of {', '.join(PIER_CHOICES)}")
        from structure_fem.analysis.band import PICKS

        if isinstance(self.band_samples, bool) or not isinstance(self.band_samples, int) or not (
                self.band_samples == 0 or 4 <= self.band_samples <= 1000):
            raise InputError(f"--band {self.band_samples!r}: give 4 to 1000 samples (or leave --band out)")
        if self.pick not in PICKS:
            raise InputError(f"--pick {self.pick!r} is not one of {', '.join(PICKS)}")


def load_file(opts: RunOptions) -> RobotPropertiesFile:
    if opts.properties is not None and not Path(opts.properties).exists():
        raise InputError(f"--properties {opts.properties}: file not found")
    return load_properties(opts.properties)


def make_inputs(opts: RunOptions, props: RobotPropertiesFile | None = None,
                cal: Calibration | None = None) -> tuple[StudyInputs, dict]:
    """Study inputs and the calibration record (fitted bolt, how the robot's connectors follow)."""
    from structure_fem.couplings.connector_sources import resolve

    props = load_file(opts) if props is None else props
    record: RobotProperties = props.get(opts.robot)
    robot, sources = resolve(record, "fe" if opts.connectors == "fe" else "properties", measured=opts.measured)
    clearance = opts.clearance_mm
    if opts.caster:
        if clearance is not None:
            raise InputError("give either --clearance-mm or --caster, not both")
        clearance = robot.caster_exposed_height_m * 1e3
        if clearance <= 0:
            raise InputError(f"robot {robot.name!r} has no exposed caster height for --caster")
    inp = StudyInputs.for_robot(robot, clearance, opts.stiffness_scale, opts.backlash_scale, opts.mass_scale,
                                required_tipping=opts.required_tipping, flexible=opts.flexible,
                                max_width=opts.max_width, dynamic=opts.dynamic, damping_ratio=opts.damping_ratio)
    inp = replace(inp, connectors=replace(inp.connectors, hinge=opts.hinge))
    if cal is None:
        cal = calibrate(props, opts.calibration_backlash)
    # The calibration scales the record's hand estimates (it says how far off they were).
    cal_conn = calibrated_connectors(ConnectorSet.from_robot(record).scaled(opts.stiffness_scale,
                                                                           opts.backlash_scale), cal)
    cal_conn = replace(cal_conn, hinge=opts.hinge)
    if opts.connectors == "calibrated":
        inp = replace(inp, connectors=cal_conn)
    info = cal.to_dict()
    info["robot_connectors_source"] = opts.connectors
    info["connector_sources"] = sources
    info["robot_connectors"] = inp.connectors.to_dict()
    info["calibrated_alternative"] = {
        "rule": "robot stiffness x (fitted / estimated platform bolt stiffness)",
        "connectors": cal_conn.to_dict() if opts.connectors != "calibrated" else None,
    }
    return inp, info


def hand_formula_warnings(info: dict, robot: str) -> list[str]:
    """One ``warning: ...`` line per coupling whose FE result was asked for (``--connectors fe``) but
    does not exist for the record's geometry, so the table runs on the record's hand formula (issue
    38, item 2: a CAD export at another clearance used to fall back silently)."""
    if info.get("robot_connectors_source") != "fe":
        return []
    return [f"warning: {robot} {kind}: no FE result applies, the table uses the record's hand formula ({note[len('record (hand formula): '):]})"
            for kind, note in sorted(info.get("connector_sources", {}).items())
            if note.startswith("record (hand formula)")]


def _alt_thresholds(inp: StudyInputs, info: dict, opts: RunOptions) -> list[tuple[str, NonConvergence]]:
    """Thresholds with the other connector source, for the calibration report; returns its
    non-converged solves with their context."""
    # static criterion: the alternative shows what the connector source moves; its launch
    # transients would double a cold table's integration time for a side report
    alt_opts = replace(opts, connectors="calibrated" if opts.connectors != "calibrated" else "properties",
                       dynamic=False)
    alt_inp, _ = make_inputs(alt_opts)
    alt = derive(alt_inp, extra=0)
    th = alt.thresholds()
    info["calibrated_alternative"]["thresholds_with_" + alt_opts.connectors + "_connectors"] = {
        k: th[k] for k in ("line", "two_line", "arch", "arch_levels")}
    info["calibrated_alternative"]["criterion"] = "static (tip <= clearance, no launch transients)"
    return [(f"{alt_opts.connectors} connectors alternative", f) for f in alt.failures]


def pier_derivation(inp: StudyInputs, limits: StructureLimits | None, opts: RunOptions):
    """The pier derivation (:func:`structure_fem.analysis.piers.derive`) for the limits' line level, or
    ``(None, why)`` when there is none to derive (``--piers none``, no limits, no line level)."""
    from structure_fem.analysis.piers import MAX_PIER_ROBOTS, PierStudy, derive

    if opts.piers == "none":
        return None, "not derived (--piers none)"
    if limits is None:
        return None, "not derived: there is no limits record"
    line = next((lvl for lvl in limits.levels if lvl.kind == "line"), None)
    if line is None:
        return None, "not derived: the limits have no line level (the line crosses no void)"
    # without a top-down coupling robots cannot be stacked: a pier is one robot
    k = MAX_PIER_ROBOTS if inp.connectors.top_twist is not None else 1
    return derive(PierStudy(inp, line, max_pier_robots=k)), ""


def with_piers(limits: StructureLimits | None, inp: StudyInputs, opts: RunOptions):
    """``(limits with the pier rule, derivation or None, why not)``."""
    d, why = pier_derivation(inp, limits, opts)
    if d is None:
        return limits, None, why
    return replace(limits, piers=d.rule), d, ""


def not_converged(failures: Iterable[tuple[str, NonConvergence]]) -> dict:
    """``{"not_converged": [...], "warnings": [...]}`` for a summary: every solve that did not
    converge (with its context and what it was counted as) and one ``warning: ...`` line each."""
    items, lines = [], []
    for context, f in failures:
        items.append({**f.to_dict(), "context": context})
        lines.append(f.warning(context))
    return {"not_converged": items, "warnings": lines}


def structure_reports(d: Derivation, ranges: bool = True, progress: Progress | None = None) -> list[dict]:
    """Per structure: threshold, margin, what sets it, bodies, range (:mod:`structure_fem.analysis.margins`);
    the range only for the thesis-shaped structures (the narrow arches are reported, not banded)."""
    from structure_fem.analysis.margins import report

    narrow = [c.structure.name for c in d.curves
              if c.structure.kind == "arch" and c.structure.lines < 2 * c.structure.layers]
    wide = report(d, ranges, [c.structure.name for c in d.curves if c.structure.name not in narrow], progress)
    return wide + report(d, False, narrow)


def run_table(out: str | Path, opts: RunOptions = RunOptions(), docs_dir: str | Path | None = None,
              progress: Progress | None = None, alternative: bool = True, plots: bool = True,
              ranges: bool = True) -> dict:
    """Derive, write selection_table.{md,csv}, limits.json (+ plots); return the JSON summary.

    The table also evaluates the thesis's tapering arches under our mechanics
    (:func:`structure_fem.analysis.study.tapered_arches`; the derived limits do not depend on it) and,
    with ``plots``, draws them beside the derived uniform arches (``thesis_tapering_arches.png``,
    copied to ``docs_dir/img/`` with ``docs_dir``).

    Solves that do not converge never abort the run: they count as failing (a width) or are
    left out (a launch step, a plot) and are listed in the summary's ``not_converged`` with a
    ``warnings`` line each. When no structure crosses even a 1-wide void there is no
    limits record: ``limits.json`` is not written and ``warnings`` says so.
    """
    out = Path(out)
    inp, info = make_inputs(opts)  # bad input fails here, before anything is created
    ahead = prefetch_tapered(inp)
    try:
        return _run_table(out, opts, inp, info, docs_dir, progress, alternative, plots, ranges, ahead)
    finally:
        if ahead is not None and ahead.is_alive():
            ahead.terminate()
        if ahead is not None:
            ahead.join()


def prefetch_tapered(inp: StudyInputs):
    """Start solving the thesis's tapering arches (:func:`tapered_arches`) in a second process while
    this one derives, and return it (None where it would not help).

    The tapering arches are the table's longest sequential part (the 8 x 4 arch's widest voids:
    2.5 of a cold table's 6 minutes), and they depend only on the inputs, not on the derivation.
    The second process's static solves land in the solve cache
    (:mod:`structure_fem.solve_cache`); when the table reaches the tapering arches it reads them, or
    waits on the claim of the one being solved, so the rows are the same, bit for bit, as solved
    here. Nothing is started when the solve cache is off or cannot be written (the work would be
    lost), when one worker is asked for (``VOIDCROSS_TRANSIENT_WORKERS=1``), inside a pool's worker,
    or when the robot cannot build the tapering arches. The process writes nothing but the cache."""
    import multiprocessing as mp

    from structure_fem import solve_cache
    from structure_fem.analysis.study import tapered_not_applicable
    from structure_fem.model.dynamics_cache import process_context, workers_default

    if (workers_default() < 2 or mp.current_process().daemon or not solve_cache.writable()
            or tapered_not_applicable(inp.connectors, inp.robot.name)):
        return None
    p = process_context().Process(target=_tapered_ahead, args=(inp,), daemon=True, name="voidcross-tapered-arches")
    p.start()
    return p


def _tapered_ahead(inp: StudyInputs) -> None:
    """:func:`prefetch_tapered`'s process: the tapering arches on an empty derivation (their rows are
    thrown away; their solves stay in the cache). A failure here is the table's to meet and report."""
    try:
        tapered_arches(Derivation(inp, [], []))
    except BaseException:  # noqa: BLE001 - the table solves (and reports) whatever is missing itself
        pass


def _run_table(out: Path, opts: RunOptions, inp: StudyInputs, info: dict, docs_dir, progress, alternative: bool,
               plots: bool, ranges: bool, ahead) -> dict:
    d = derive(inp, progress, narrow=True)
    band_record = None
    if opts.band_samples:
        from structure_fem.analysis.band import apply_pick, band

        b = band(d, opts.band_samples, progress=progress)
        nominal = apply_pick(d, b, opts.pick)
        band_record = {"pick": opts.pick, "nominal_thresholds": nominal, **b.to_dict()}
    limits = limits_from(d) if d.levels else None
    if limits is not None and band_record is not None:
        limits = replace(limits, notes=limits.notes + " " + band_note(band_record))
    limits, piers, piers_why = with_piers(limits, inp, opts)
    rows = table(d, progress)
    tapered = tapered_arches(d, progress=progress)
    if ahead is not None:
        ahead.join()  # it solved the same arches: done, or about to be
    alt_failures = _alt_thresholds(inp, info, opts) if alternative else []
    info["body_bending"] = body_bending(d)
    structures = structure_reports(d, ranges and opts.ranges, progress)
    out.mkdir(parents=True, exist_ok=True)
    files: dict[str, str] = {}
    if plots and tapered:
        from structure_fem.outputs.plots import tapered_plot

        files["tapered_plot"] = str(tapered_plot(d, tapered, out / TAPERED_PLOT))
        if docs_dir is not None:
            files["docs_tapered_plot"] = str(tapered_plot(d, tapered, Path(docs_dir) / "img" / TAPERED_PLOT))
    link = TAPERED_PLOT if plots and tapered else None
    from structure_fem.analysis.margins import markdown as margins_markdown
    from structure_fem.outputs.outputs import piers_markdown

    sect = margins_markdown(structures) + piers_markdown(piers, piers_why)
    sect = band_markdown(band_record, BAND_PLOT if plots else None) + sect
    md = table_markdown(rows, d, limits, info, tapered_markdown(tapered, d, link)) + "\n" + sect
    files.update({
        "markdown": str(write_text_atomic(out / "selection_table.md", md)),
        "csv": str(write_text_atomic(out / "selection_table.csv", table_csv(rows))),
        "tapered_csv": str(write_text_atomic(out / "thesis_tapering_arches.csv", tapered_csv(tapered))),
    })
    stale = False
    if limits is not None:
        files["limits"] = str(limits.save(out / "limits.json"))
    elif (out / "limits.json").exists():  # an older record must not sit beside this table
        (out / "limits.json").unlink()
        stale = True
    if docs_dir is not None:
        docs_md = table_markdown(rows, d, limits, info,
                                 tapered_markdown(tapered, d, f"img/{TAPERED_PLOT}" if link else None)) + "\n" + sect
        files["docs_markdown"] = str(write_text_atomic(Path(docs_dir) / "structure_fem_table.md", docs_md))
    if plots:
        files.update(write_plots(out, d))
        if band_record is not None:
            from structure_fem.outputs.plots import band_plot

            files["band_plot"] = str(band_plot(band_record, out / BAND_PLOT))
    res = summary(d, limits, info, files, rows, tapered)
    res["structures"] = structures
    if band_record is not None:
        res["band"] = band_record
    res["piers"] = piers.to_dict() if piers is not None else {"rule": None, "why": piers_why}
    pier_failures = [("pier rule", f) for f in piers.failures] if piers is not None else []
    res.update(not_converged([("", f) for f in d.failures] + alt_failures + pier_failures))
    hand = hand_formula_warnings(info, opts.robot)
    res["warnings"][:0] = hand
    res["hand_formula_connectors"] = [w.split()[2].rstrip(":") for w in hand]
    if limits is None:
        res["warnings"].append(f"warning: {no_crossing(d)}; limits.json not written"
                               + (f" (the older {out / 'limits.json'} was removed)" if stale else ""))
    return res


def band_note(band: dict) -> str:
    """One sentence for limits.json's notes: which thresholds it holds and the band behind them."""
    per = band["per_structure"]
    return (f"Thresholds picked at {band['pick']} of an uncertainty band ({len(band['samples'])} Latin-hypercube "
            f"samples over {', '.join(f['name'] for f in band['factors'])}): "
            + ", ".join(f"{s} {v['p5']} / {v['p50']} / {v['p95']} (p5 / p50 / p95; nominal {v['nominal']})"
                        for s, v in per.items()) + ".")


#: File name of the band plot (beside the table, with --band).
BAND_PLOT = "threshold_band.png"


def band_markdown(band: dict | None, plot: str | None = None) -> str:
    """The table's "Uncertainty band" section (empty without a band)."""
    if band is None:
        return ""
    rows = ["## Uncertainty band", "", band["method"] + ".", "",
            f"The table and limits.json use **{band['pick']}**"
            + (" (what 95 % of printed robots span)" if band["pick"] == "p5" else "") + ".", "",
            "| structure | nominal (as drawn) | p5 | p50 | p95 |", "|---|---:|---:|---:|---:|"]
    rows += [f"| {s} | {v['nominal']} | {v['p5']} | {v['p50']} | {v['p95']} |" for s, v in band["per_structure"].items()]
    if plot:
        rows += ["", f"![uncertainty band of the thresholds]({plot})"]
    rows += ["", "Inputs:", ""] + [f"- {f['name']}: {f['distribution']} on {f['applies_to']} ({f['source']})"
                                   for f in band["factors"]]
    return "\n".join(rows) + "\n\n"


def no_crossing(d: Derivation) -> str:
    """What it means when no structure crosses even a 1-wide void (valid input, no limits record)."""
    return (f"no structure keeps the tip deflection of even a 1-wide void within the "
            f"{d.inputs.clearance_m * 1e3:g} mm clearance for robot {d.inputs.robot.name!r}")


#: File name of the tapering-arch plot (in the output directory, and under docs/img with --docs).
TAPERED_PLOT = "thesis_tapering_arches.png"


def body_bending(d: Derivation) -> dict:
    """How much the robots' own bending (``--flexible``) adds to the line's tip at its threshold
    (``converged: false`` and the reason, instead of the numbers, if a solve does not converge)."""
    line = d.curve("line")
    w = max(line.threshold, 1)
    try:
        cfg = Config(line.structure, line.rows[line.index(w, d.inputs)], w, w)
        rigid = solve(cfg, d.inputs.robot, d.inputs.connectors).tip_deflection_m
        flex = solve(cfg, d.inputs.robot, d.inputs.connectors, flexible=True).tip_deflection_m
    except SolverFailure as exc:
        d.other_failures.append(NonConvergence(line.structure.name, w, "body-bending check (rigid vs flexible)",
                                               "left out of the calibration report", str(exc)))
        return {"line_width": w, "converged": False, "reason": str(exc)}
    return {"line_width": w, "rigid_tip_mm": round(rigid * 1e3, 4), "flexible_tip_mm": round(flex * 1e3, 4),
            "increase_percent": round(100 * (flex / rigid - 1), 2)}


def write_plots(out: Path, d: Derivation) -> dict[str, str]:
    """Deflection vs width and side views; a side view whose solve does not converge is left out
    (and listed in ``d.other_failures``)."""
    from structure_fem.outputs.plots import deflection_plot, side_view

    def view(s, rows: int, w: int, name: str) -> None:
        try:
            res = solve(Config(s, rows, w, w), d.inputs.robot, d.inputs.connectors, d.inputs.flexible)
        except SolverFailure as exc:
            d.other_failures.append(NonConvergence(s.name, w, f"side view ({name})", "plot left out", str(exc)))
            return
        files[name.removesuffix(".png")] = str(side_view(res, out / name, d.inputs.robot.height_m))

    files = {"deflection_plot": str(deflection_plot(d, out / "deflection_vs_width.png"))}
    if d.levels:
        s, lo, hi = d.levels[-1]
        c = d.curve(s.name)
        view(s, c.rows[c.widths.index(hi)], hi, "side_view.png")
    line = d.curve("line")
    if line.widths:
        w = line.threshold + 1 if line.threshold + 1 in line.widths else line.widths[-1]
        view(line.structure, line.rows[line.widths.index(w)], w, "side_view_line.png")
    return files


#: (parameter, unit, values): the sensitivity study's grid (one factor at a time).
SENSITIVITY = (
    ("connector stiffness", "x record", (0.5, 0.71, 1.0, 1.41, 2.0)),
    ("backlash", "x record", (0.0, 1.0, 2.0, 4.0)),
    ("robot mass", "x record", (0.5, 1.0, 2.0)),
    ("clearance", "mm", (3.3, 7.5, 15.0, 20.0)),
)


def sensitivity_dynamic(opts: RunOptions) -> bool:
    """The sensitivity grid uses the table's dynamic criterion (``--sensitivity-dynamic`` with the
    dynamic criterion), else the static tip."""
    return opts.dynamic and opts.sensitivity_dynamic


def sensitivity(opts: RunOptions, progress: Progress | None = None, grid=SENSITIVITY,
                failures: list[tuple[str, NonConvergence]] | None = None) -> list[dict]:
    """Thresholds vs connector stiffness, backlash, robot mass and clearance (one factor at a time;
    identical input sets are derived once). By default by the static tip: the grid shows how the
    inputs move the statics, and its launch transients (one per structure and grid point, 1-120 s
    each) would make a cold study tens of minutes long. With :func:`sensitivity_dynamic` by the
    table's criterion: every grid point's static thresholds first, then all their transients side
    by side (:func:`structure_fem.model.dynamics_cache.prefill`), then each steps down
    (:func:`structure_fem.analysis.study.apply_dynamic`). ``not_converged`` lists the widths whose solve
    did not converge (counted as failing); with ``failures`` their details are appended there,
    with the grid point as context."""
    from structure_fem.analysis.study import apply_dynamic, levels_of

    props = load_file(opts)
    cal = calibrate(props, opts.calibration_backlash)
    dyn = sensitivity_dynamic(opts)
    jobs = [(p, u, v) for p, u, vals in grid for v in vals]
    it = jobs if progress is None else progress(jobs, "fem sensitivity", len(jobs))
    points, cache = [], {}
    for p, u, v in it:
        o = {"connector stiffness": replace(opts, stiffness_scale=opts.stiffness_scale * v),
             "backlash": replace(opts, backlash_scale=opts.backlash_scale * v),
             "robot mass": replace(opts, mass_scale=opts.mass_scale * v),
             "clearance": replace(opts, clearance_mm=v, caster=False)}[p]
        inp, _ = make_inputs(replace(o, dynamic=dyn), props, cal)
        key = (inp.connectors, inp.robot, inp.clearance_m)
        fresh = key not in cache
        if fresh:
            cache[key] = (derive(replace(inp, dynamic=False), extra=0), inp)
        points.append((p, u, v, key, fresh))
    if dyn:  # every grid point's transients at its static thresholds at once, then the step-down
        apply_dynamic([(c, inp) for d, inp in cache.values() for c in d.curves], progress,
                      label="launch transients (sensitivity)")
        for d, inp in cache.values():
            d.inputs, d.levels = inp, levels_of(d.curves)
    rows = []
    for p, u, v, key, fresh in points:
        d = cache[key][0]
        th = d.thresholds()
        failing = [f"{f.structure} {f.width}" for f in d.failures if f.counted_as == "counted as failing"]
        rows.append({"parameter": p, "unit": u, "value": v, "line": th["line"], "two_line": th["two_line"],
                     "arch": th["arch"], "arch_levels": " ".join(map(str, th["arch_levels"])),
                     "max_span": d.max_span, "not_converged": "; ".join(failing)})
        if failures is not None and fresh:
            failures.extend((f"sensitivity: {p} {v:g} {u}", f) for f in d.failures)
    return rows


def run_study(out: str | Path, opts: RunOptions = RunOptions(), progress: Progress | None = None,
              grid=SENSITIVITY) -> dict:
    """Deflection vs width plot, side views, sensitivity CSV + plot."""
    from structure_fem.outputs.plots import sensitivity_plot

    out = Path(out)
    inp, info = make_inputs(opts)
    d = derive(inp, progress, extra=2)
    band_record = None
    if opts.band_samples:  # reported beside the curves; the study picks nothing
        from structure_fem.analysis.band import band

        band_record = {"pick": "nominal", "nominal_thresholds": {c.structure.name: c.threshold for c in d.curves},
                       **band(d, opts.band_samples, progress=progress).to_dict()}
    out.mkdir(parents=True, exist_ok=True)
    files = write_plots(out, d)
    if band_record is not None:
        from structure_fem.outputs.plots import band_plot

        files["band_plot"] = str(band_plot(band_record, out / BAND_PLOT))
    curves = io.StringIO()
    w = csv.writer(curves, lineterminator="\n")
    w.writerow(["structure", "width", "tip_deflection_mm", "tipping_factor", "rows", "robots"])
    for c in d.curves:
        for i, wd in enumerate(c.widths):
            tf = c.tipping[i]
            w.writerow([c.structure.name, wd, f"{c.tip_mm[i]:.6g}", f"{tf:.6g}" if math.isfinite(tf) else "",
                        c.rows[i], c.robots[i]])
    files["curves_csv"] = str(write_text_atomic(out / "deflection_vs_width.csv", curves.getvalue()))
    sens_failures: list[tuple[str, NonConvergence]] = []
    sens = sensitivity(opts, progress, grid, sens_failures)
    buf = io.StringIO()
    sw = csv.DictWriter(buf, fieldnames=list(sens[0]), lineterminator="\n")
    sw.writeheader()
    sw.writerows(sens)
    files["sensitivity_csv"] = str(write_text_atomic(out / "sensitivity.csv", buf.getvalue()))
    files["sensitivity_plot"] = str(sensitivity_plot(sens, out / "sensitivity.png"))
    th = d.thresholds()
    return {"thresholds": {k: th[k] for k in ("line", "two_line", "arch", "arch_levels")},
            "thresholds_per_structure": th["per_structure"], "clearance_mm": inp.clearance_m * 1e3,
            "criterion": "static tip + launch allowance <= clearance" if inp.dynamic else "static tip <= clearance",
            "sensitivity_criterion": ("static tip + launch allowance <= clearance" if sensitivity_dynamic(opts)
                                      else "static tip <= clearance"),
            "calibration": info, "sensitivity": sens, "files": files,
            **({"band": band_record} if band_record is not None else {}),
            **not_converged([("", f) for f in d.failures] + sens_failures)}


def packaged_limits(properties: str | None = None) -> StructureLimits:
    """The derived limits of the packaged robot properties (or ``properties``) with default options:
    what the shipped limits.json must hold."""
    opts = RunOptions(properties=properties)
    inp, _ = make_inputs(opts)
    return with_piers(limits_from(derive(inp, narrow=True)), inp, opts)[0]


def write_packaged_limits(properties: str | None = None) -> Path:
    """Regenerate ``structure_fem/data/limits.json`` (``python -m structure_fem.outputs.runs [properties.json]``,
    which then also regenerates the packaged launch allowances: :func:`write_packaged_dynamics`)."""
    from structure_fem.limits import packaged_limits_path

    return packaged_limits(properties).save(packaged_limits_path())


def write_packaged_dynamics(properties: str | None = None) -> Path:
    """Regenerate ``structure_fem/data/dynamic_allowance.json``: the launch transients the
    default ``fem table`` (and the packaged limits) integrate for the packaged record, so a fresh
    clone's table is served from it (:mod:`structure_fem.model.dynamics_cache`)."""
    import tempfile

    from structure_fem.model import dynamics_cache

    packaged_limits(properties)
    with tempfile.TemporaryDirectory() as tmp:
        run_table(tmp, RunOptions(properties=properties), plots=False)
    return dynamics_cache.write_packaged()


if __name__ == "__main__":  # pragma: no cover
    import sys

    print(write_packaged_limits(sys.argv[1] if len(sys.argv) > 1 else None))
    print(write_packaged_dynamics(sys.argv[1] if len(sys.argv) > 1 else None))
