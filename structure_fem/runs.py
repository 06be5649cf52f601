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

from .calibration import Calibration, calibrate, calibrated_connectors
from .errors import InputError
from .limits import StructureLimits
from .model import Config, solve
from .outputs import (
    summary,
    table_csv,
    table_markdown,
    tapered_csv,
    tapered_markdown,
    write_text_atomic,
)
from .study import Derivation, StudyInputs, derive, limits_from, table, tapered_arches

CONNECTOR_SOURCES = ("properties", "calibrated")
Progress = Callable[[Iterable, str, int], Iterable]


@dataclass(frozen=True)
class RunOptions:
    """CLI-level knobs; ``None`` clearance = the robot's exposed main-wheel height."""

    properties: str | None = None
    robot: str = "cubot"
    clearance_mm: float | None = None
    caster: bool = False
    connectors: str = "properties"
    stiffness_scale: float = 1.0
    backlash_scale: float = 1.0
    mass_scale: float = 1.0
    required_tipping: float = 1.0
    flexible: bool = False
    calibration_backlash: float | None = None
    max_width: int = 30

    def __post_init__(self) -> None:
        if self.connectors not in CONNECTOR_SOURCES:
            raise InputError(f"--connectors {self.connectors!r} is not one of {', '.join(CONNECTOR_SOURCES)}")


def load_file(opts: RunOptions) -> RobotPropertiesFile:
    if opts.properties is not None and not Path(opts.properties).exists():
        raise InputError(f"--properties {opts.properties}: file not found")
    return load_properties(opts.properties)


def make_inputs(opts: RunOptions, props: RobotPropertiesFile | None = None,
                cal: Calibration | None = None) -> tuple[StudyInputs, dict]:
    """Study inputs and the calibration record (fitted bolt, how the robot's connectors follow)."""
    props = load_file(opts) if props is None else props
    robot: RobotProperties = props.get(opts.robot)
    clearance = opts.clearance_mm
    if opts.caster:
        if clearance is not None:
            raise InputError("give either --clearance-mm or --caster, not both")
        clearance = robot.caster_exposed_height_m * 1e3
        if clearance <= 0:
            raise InputError(f"robot {robot.name!r} has no exposed caster height for --caster")
    inp = StudyInputs.for_robot(robot, clearance, opts.stiffness_scale, opts.backlash_scale, opts.mass_scale,
                                required_tipping=opts.required_tipping, flexible=opts.flexible,
                                max_width=opts.max_width)
    if cal is None:
        cal = calibrate(props, opts.calibration_backlash)
    cal_conn = calibrated_connectors(inp.connectors, cal)
    if opts.connectors == "calibrated":
        inp = replace(inp, connectors=cal_conn)
    info = cal.to_dict()
    info["robot_connectors_source"] = opts.connectors
    info["robot_connectors"] = inp.connectors.to_dict()
    info["calibrated_alternative"] = {
        "rule": "robot stiffness x (fitted / estimated platform bolt stiffness)",
        "connectors": cal_conn.to_dict() if opts.connectors == "properties" else None,
    }
    return inp, info


def _alt_thresholds(inp: StudyInputs, info: dict, opts: RunOptions) -> None:
    """Thresholds with the other connector source, for the calibration report."""
    alt_opts = replace(opts, connectors="calibrated" if opts.connectors == "properties" else "properties")
    alt_inp, _ = make_inputs(alt_opts)
    th = derive(alt_inp, extra=0).thresholds()
    info["calibrated_alternative"]["thresholds_with_" + alt_opts.connectors + "_connectors"] = {
        k: th[k] for k in ("line", "two_line", "arch", "arch_levels")}


def run_table(out: str | Path, opts: RunOptions = RunOptions(), docs_dir: str | Path | None = None,
              progress: Progress | None = None, alternative: bool = True, plots: bool = True) -> dict:
    """Derive, write selection_table.{md,csv}, limits.json (+ plots); return the JSON summary.

    The table also evaluates the thesis's tapering arches under our mechanics
    (:func:`structure_fem.study.tapered_arches`; the derived limits do not depend on it) and,
    with ``plots``, draws them beside the derived uniform arches (``thesis_tapering_arches.png``,
    copied to ``docs_dir/img/`` with ``docs_dir``).
    """
    out = Path(out)
    inp, info = make_inputs(opts)  # bad input fails here, before anything is created
    d = derive(inp, progress, narrow=True)
    limits = limits_from(d)
    rows = table(d, progress)
    tapered = tapered_arches(d, progress=progress)
    if alternative:
        _alt_thresholds(inp, info, opts)
    info["body_bending"] = body_bending(d)
    out.mkdir(parents=True, exist_ok=True)
    files: dict[str, str] = {}
    if plots:
        from .plots import tapered_plot

        files["tapered_plot"] = str(tapered_plot(d, tapered, out / TAPERED_PLOT))
        if docs_dir is not None:
            files["docs_tapered_plot"] = str(tapered_plot(d, tapered, Path(docs_dir) / "img" / TAPERED_PLOT))
    link = TAPERED_PLOT if plots else None
    md = table_markdown(rows, d, limits, info, tapered_markdown(tapered, d, link))
    files.update({
        "markdown": str(write_text_atomic(out / "selection_table.md", md)),
        "csv": str(write_text_atomic(out / "selection_table.csv", table_csv(rows))),
        "tapered_csv": str(write_text_atomic(out / "thesis_tapering_arches.csv", tapered_csv(tapered))),
        "limits": str(limits.save(out / "limits.json")),
    })
    if docs_dir is not None:
        docs_md = table_markdown(rows, d, limits, info,
                                 tapered_markdown(tapered, d, f"img/{TAPERED_PLOT}" if plots else None))
        files["docs_markdown"] = str(write_text_atomic(Path(docs_dir) / "structure_fem_table.md", docs_md))
    if plots:
        files.update(write_plots(out, d))
    return summary(d, limits, info, files, rows, tapered)


#: File name of the tapering-arch plot (in the output directory, and under docs/img with --docs).
TAPERED_PLOT = "thesis_tapering_arches.png"


def body_bending(d: Derivation) -> dict:
    """How much the robots' own bending (``--flexible``) adds to the line's tip at its threshold."""
    line = d.curve("line")
    w = max(line.threshold, 1)
    cfg = Config(line.structure, line.rows[line.index(w, d.inputs)], w, w)
    rigid = solve(cfg, d.inputs.robot, d.inputs.connectors).tip_deflection_m
    flex = solve(cfg, d.inputs.robot, d.inputs.connectors, flexible=True).tip_deflection_m
    return {"line_width": w, "rigid_tip_mm": round(rigid * 1e3, 4), "flexible_tip_mm": round(flex * 1e3, 4),
            "increase_percent": round(100 * (flex / rigid - 1), 2)}


def write_plots(out: Path, d: Derivation) -> dict[str, str]:
    from .plots import deflection_plot, side_view

    files = {"deflection_plot": str(deflection_plot(d, out / "deflection_vs_width.png"))}
    if d.levels:
        s, lo, hi = d.levels[-1]
        c = d.curve(s.name)
        res = solve(Config(s, c.rows[c.widths.index(hi)], hi, hi), d.inputs.robot, d.inputs.connectors,
                    d.inputs.flexible)
        files["side_view"] = str(side_view(res, out / "side_view.png", d.inputs.robot.height_m))
    line = d.curve("line")
    w = line.threshold + 1 if line.threshold + 1 in line.widths else line.widths[-1]
    res = solve(Config(line.structure, line.rows[line.widths.index(w)], w, w), d.inputs.robot,
                d.inputs.connectors, d.inputs.flexible)
    files["side_view_line"] = str(side_view(res, out / "side_view_line.png", d.inputs.robot.height_m))
    return files


#: (parameter, unit, values): the sensitivity study's grid (one factor at a time).
SENSITIVITY = (
    ("connector stiffness", "x record", (0.5, 0.71, 1.0, 1.41, 2.0)),
    ("backlash", "x record", (0.0, 1.0, 2.0, 4.0)),
    ("robot mass", "x record", (0.5, 1.0, 2.0)),
    ("clearance", "mm", (3.3, 7.5, 15.0, 20.0)),
)


def sensitivity(opts: RunOptions, progress: Progress | None = None, grid=SENSITIVITY) -> list[dict]:
    """Thresholds vs connector stiffness, backlash, robot mass and clearance (one factor at a time;
    identical input sets are derived once)."""
    props = load_file(opts)
    cal = calibrate(props, opts.calibration_backlash)
    jobs = [(p, u, v) for p, u, vals in grid for v in vals]
    it = jobs if progress is None else progress(jobs, "fem sensitivity", len(jobs))
    rows, cache = [], {}
    for p, u, v in it:
        o = {"connector stiffness": replace(opts, stiffness_scale=opts.stiffness_scale * v),
             "backlash": replace(opts, backlash_scale=opts.backlash_scale * v),
             "robot mass": replace(opts, mass_scale=opts.mass_scale * v),
             "clearance": replace(opts, clearance_mm=v, caster=False)}[p]
        inp, _ = make_inputs(o, props, cal)
        key = (inp.connectors, inp.robot, inp.clearance_m)
        if key not in cache:
            cache[key] = derive(inp, extra=0)
        d = cache[key]
        th = d.thresholds()
        rows.append({"parameter": p, "unit": u, "value": v, "line": th["line"], "two_line": th["two_line"],
                     "arch": th["arch"], "arch_levels": " ".join(map(str, th["arch_levels"])),
                     "max_span": d.max_span})
    return rows


def run_study(out: str | Path, opts: RunOptions = RunOptions(), progress: Progress | None = None,
              grid=SENSITIVITY) -> dict:
    """Deflection vs width plot, side views, sensitivity CSV + plot."""
    from .plots import sensitivity_plot

    out = Path(out)
    inp, info = make_inputs(opts)
    d = derive(inp, progress, extra=2)
    out.mkdir(parents=True, exist_ok=True)
    files = write_plots(out, d)
    curves = io.StringIO()
    w = csv.writer(curves, lineterminator="\n")
    w.writerow(["structure", "width", "tip_deflection_mm", "tipping_factor", "rows", "robots"])
    for c in d.curves:
        for i, wd in enumerate(c.widths):
            tf = c.tipping[i]
            w.writerow([c.structure.name, wd, f"{c.tip_mm[i]:.6g}", f"{tf:.6g}" if math.isfinite(tf) else "",
                        c.rows[i], c.robots[i]])
    files["curves_csv"] = str(write_text_atomic(out / "deflection_vs_width.csv", curves.getvalue()))
    sens = sensitivity(opts, progress, grid)
    buf = io.StringIO()
    sw = csv.DictWriter(buf, fieldnames=list(sens[0]), lineterminator="\n")
    sw.writeheader()
    sw.writerows(sens)
    files["sensitivity_csv"] = str(write_text_atomic(out / "sensitivity.csv", buf.getvalue()))
    files["sensitivity_plot"] = str(sensitivity_plot(sens, out / "sensitivity.png"))
    th = d.thresholds()
    return {"thresholds": {k: th[k] for k in ("line", "two_line", "arch", "arch_levels")},
            "thresholds_per_structure": th["per_structure"], "clearance_mm": inp.clearance_m * 1e3,
            "calibration": info, "sensitivity": sens, "files": files}


def packaged_limits(properties: str | None = None) -> StructureLimits:
    """The derived limits of the packaged robot properties (or ``properties``) with default options:
    what the shipped limits.json must hold."""
    inp, _ = make_inputs(RunOptions(properties=properties))
    return limits_from(derive(inp, narrow=True))


def write_packaged_limits(properties: str | None = None) -> Path:
    """Regenerate ``structure_fem/data/limits.json`` (``python -m structure_fem.runs [properties.json]``)."""
    from .limits import packaged_limits_path

    return packaged_limits(properties).save(packaged_limits_path())


if __name__ == "__main__":  # pragma: no cover
    import sys

    print(write_packaged_limits(sys.argv[1] if len(sys.argv) > 1 else None))
