"""Writers for the selection table (Markdown, CSV), limits.json and the JSON summary.

Every file is written atomically (temporary file + rename) so a failed run
never leaves a half-written table next to a good one. Missing values (void
widths no structure crosses) are written as "-" in Markdown and empty in CSV,
never NaN.
"""

from __future__ import annotations

import csv
import io
import math
import os
from dataclasses import asdict
from pathlib import Path

from cubot_cad.atomic import write_text
from structure_fem.analysis.study import (
    TABLE_ROW_FAILURE,
    Derivation,
    TableRow,
    TaperRow,
    tapered_not_applicable,
    tapered_verdict,
)
from structure_fem.limits import StructureLimits, thesis_limits

COLUMNS = (
    ("width", "w"), ("band", "band"), ("structure", "structure"), ("lines", "lines"), ("layers", "layers"),
    ("min_robots", "min N"), ("thesis_robots", "thesis N"),
    ("launch_initial", "launch initial"), ("launch_over", "launch over"), ("launch_target", "launch target"),
    ("bridged_initial", "bridged initial"), ("bridged_over", "bridged over"), ("bridged_target", "bridged target"),
    ("max_deflection_mm", "max tip defl. mm"), ("bridged_deflection_mm", "bridged defl. mm"),
    ("margin_mm", "margin mm"), ("min_tipping_factor", "min tipping"), ("thesis_count_tipping", "tipping at thesis N"),
    ("case_a_count_tipping", "tipping at case A N"),
)


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    """Complete or not at all, world-readable (:mod:`cubot_cad.atomic`)."""
    return write_text(path, text)


def _cell(v, md: bool) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-" if md else ""
    if isinstance(v, float):
        return f"{v:.2f}" if md else f"{v:.6g}"
    return str(v)


def table_csv(rows: list[TableRow]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([k for k, _ in COLUMNS])
    for r in rows:
        d = asdict(r)
        w.writerow([_cell(d[k], md=False) for k, _ in COLUMNS])
    return buf.getvalue()


def thresholds_md(d: Derivation, limits: StructureLimits | None) -> str:
    th = d.thresholds()
    tt = thesis_limits().thresholds()
    lines = ["| structure | derived threshold (robot widths) | robots at it | thesis |", "|---|---|---|---|"]
    thesis_of = {"line": tt["line"], "two_line-aligned": tt["two_line"], "two_line-staggered": tt["two_line"]}
    arch_th = [tt["arch"], *tt["arch_levels"]]
    arch_names = [c.structure.name for c in d.curves
                  if c.structure.kind == "arch" and c.structure.lines >= 2 * c.structure.layers]
    for i, name in enumerate(arch_names):
        thesis_of[name] = arch_th[i] if i < len(arch_th) else "-"
    for name, t in th["per_structure"].items():
        used = any(s.name == name for s, _, _ in d.levels)
        c = d.curve(name)
        n = c.robots[c.widths.index(t)] if t else "-"
        lines.append(f"| {name}{'' if used else ' (no band)'} | {t} | {n} | {thesis_of.get(name, '-')} |")
    widest = d.max_span if limits is None else limits.max_span_widths
    lines.append(f"| widest void crossed | {widest} | - | {thesis_limits().max_span_widths} |")
    return "\n".join(lines)


TAPER_COLUMNS = (
    ("level", "thesis level"), ("width", "w"), ("robots", "N complete"), ("robots_before_landing", "N before landing"),
    ("tip_mm", "tip at g = w mm"), ("tipping_factor", "tipping at g = w"), ("bridged_max_mm", "bridged max mm"),
    ("margin_mm", "margin mm"), ("passes", "holds"), ("uniform_structure", "derived structure at w"),
    ("uniform_robots", "its N"), ("uniform_tip_mm", "its tip mm"), ("same_section_robots", "uniform 2k x k N"),
    ("same_section_tip_mm", "uniform 2k x k tip mm"),
)


def tapered_csv(rows: list[TaperRow]) -> str:
    """The tapering-arch evaluation, one row per (thesis level, width); every field of `TaperRow`."""
    buf = io.StringIO()
    fields = list(TaperRow.__dataclass_fields__)
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(fields)
    for r in rows:
        d = asdict(r)
        w.writerow([_cell(d[k], md=False) for k in fields])
    return buf.getvalue()


def tapered_markdown(rows: list[TaperRow], d: Derivation, plot: str | None = None) -> str:
    """The section "The thesis's tapering arches under our mechanics" (verdict, table, plot link)."""
    if not rows:
        return ""
    clear = d.inputs.clearance_m * 1e3
    v = tapered_verdict(rows, clear)
    per = []
    for name, e in v["levels"].items():
        lo, hi = e["widths"]
        tip = ("-" if e["min_tip_mm"] is None
               else f"tip {e['min_tip_mm']:.1f}..{e['max_tip_mm']:.1f} mm")
        br = "-" if e["max_bridged_mm"] is None else f"{e['max_bridged_mm']:.1f} mm"
        ok = ", ".join(map(str, e["passing_widths"])) or "none"
        per.append(f"{name} ({rows[[r.level for r in rows].index(name)].structure}, widths {lo}-{hi}): {tip}, "
                   f"bridged at most {br}, widths within the clearance: {ok}")
    verdict = ("hold at every width of their bands" if v["all_hold"] else
               f"hold at {len(v['widths_passing'])} of {v['widths_evaluated']} band widths"
               + (f" ({', '.join(map(str, v['widths_passing']))})" if v["widths_passing"] else ""))
    head = "| " + " | ".join(h for _, h in TAPER_COLUMNS) + " |"
    sep = "|" + "---|" * len(TAPER_COLUMNS)
    body = []
    for r in rows:
        dd = asdict(r)
        cells = [("yes" if dd[k] else "no") if k == "passes" else _cell(dd[k], md=True) for k, _ in TAPER_COLUMNS]
        body.append("| " + " | ".join(cells) + " |")
    notes = [f"{r.level} w = {r.width}: {r.note}" for r in rows if r.note]
    img = f"\n![tip deflection vs void width: thesis tapering arches vs derived uniform arches]({plot})\n" if plot else ""
    return (
        "## The thesis's tapering arches under our mechanics\n\n"
        "The thesis's own arches (Ch. 5.5.2, the `thesis` preset: a two-line core sliding through static "
        "feet whose section grows in blocks of 5 rows to 2k x k at each ledge and shrinks over the void) built "
        f"with this robot record and its connectors. Before landing: the near foot and the core, k x 5 core rows "
        f"on the initial ground (the thesis's count), core front at the far edge (g = w). Bridged: the complete "
        f"arch on both feet. Holds = stands (tipping > {d.inputs.required_tipping:g}) and tip <= the "
        f"{clear:g} mm clearance, the test the derived levels pass. Beside it, the derived band's structure at "
        f"the same width and the uniform 2k x k staggered arch, where the derivation solved them.\n\n"
        f"**Verdict: under our mechanics the thesis's tapering arches {verdict}.** "
        + "; ".join(per) + ".\n" + img + "\n" + head + "\n" + sep + "\n" + "\n".join(body) + "\n"
        + ("\nNotes: " + "; ".join(notes) + ".\n" if notes else ""))


def failures_markdown(rows: list[TableRow], d: Derivation) -> str:
    """Rows that are not fully converged and every solve that did not converge (empty if none)."""
    out = [f"w = {r.width}: {r.note}" for r in rows if not r.converged]
    out += [f"{f.structure} at width {f.width}: {f.what} ({f.counted_as})" for f in d.failures
            if f.counted_as != TABLE_ROW_FAILURE]
    return ("\nStatic solves that did not converge: " + "; ".join(out) + ".\n") if out else ""


def table_markdown(rows: list[TableRow], d: Derivation, limits: StructureLimits | None, calibration: dict | None,
                   tapered: str = "") -> str:
    inp = d.inputs
    head = "| " + " | ".join(h for _, h in COLUMNS) + " |"
    sep = "|" + "---|" * len(COLUMNS)
    body = []
    for r in rows:
        dd = asdict(r)
        body.append("| " + " | ".join(_cell(dd[k], md=True) for k, _ in COLUMNS) + " |")
    cal = ""
    if calibration:
        cal = (f"\nCalibration (test-platform bolt, thesis Ch. 6.5.2): stiffness "
               f"{calibration['bolt_stiffness_nm_per_rad']:.4g} N m/rad at backlash "
               f"{calibration['bolt_backlash_rad']:.4g} rad; predicted tips (mm) for 3/4/5 platforms: "
               f"{calibration['predicted_tip_mm']}.\n")
        fe = calibration.get("fe") or {}
        if fe.get("available"):
            cal += ("FE of the bolt (3D, from the CAD): whole pitch "
                    f"{fe['pitch_stiffness_nm_per_rad']:.4g} (faces free) to {fe['contact_pitch_stiffness_nm_per_rad']:.4g} "
                    "N m/rad (lower edge bearing); "
                    + "; ".join(f"{r['reading']} reading fitted {r['fitted_nm_per_rad']:.4g}: FE {r['fe_is']} "
                                f"(x{r['factor']})" for r in fe["readings"]) + ".\n")
    return (
        f"# Structure-selection table ({inp.robot.name}, derived)\n\n"
        f"Generated by `voidcross fem table` from the robot record ({inp.robot.source}). "
        f"Clearance {inp.clearance_m * 1e3:g} mm; a structure must stand with tipping factor > "
        f"{inp.required_tipping:g} at its longest cantilever. Robot counts: N total; launching = at the longest "
        f"cantilever (front at the far edge); bridged = rows split between the ledges. \"thesis N\" is the "
        f"thesis's count (3 n_g, 6 n_g, arch counts); \"tipping at thesis N\" is the rigid tipping factor "
        f"of this structure built with 3 n_g rows (n_p = 2 n_g), \"case A\" with 3 n_g + 2 rows.\n\n"
        f"## Thresholds\n\n{thresholds_md(d, limits)}\n{cal}\n"
        f"## Table\n\n{head}\n{sep}\n" + "\n".join(body) + "\n" + failures_markdown(rows, d) + "\n"
        f"Notes: {limits.notes if limits is not None else _no_limits(d)}\n" + (f"\n{tapered}" if tapered else ""))


def _no_limits(d: Derivation) -> str:
    return (f"No structure keeps the tip deflection of even a 1-wide void within the "
            f"{d.inputs.clearance_m * 1e3:g} mm clearance: there is no limits record (limits.json is not written).")


def summary(d: Derivation, limits: StructureLimits | None, calibration: dict, files: dict[str, str],
            rows: list[TableRow] | None = None, tapered: list[TaperRow] | None = None) -> dict:
    th = d.thresholds()
    out = {
        "thresholds": {k: th[k] for k in ("line", "two_line", "arch", "arch_levels")},
        "thresholds_per_structure": th["per_structure"],
        "robots_at_threshold": {c.structure.name: (c.robots[c.widths.index(c.threshold)] if c.threshold else None)
                                for c in d.curves},
        "thesis_thresholds": {k: v for k, v in thesis_limits().thresholds().items()},
        "max_span_widths": d.max_span if limits is None else limits.max_span_widths,
        "clearance_mm": round(d.inputs.clearance_m * 1e3, 6) if limits is None else limits.clearance_mm,
        "robot": d.inputs.robot.name,
        "levels": [{"name": s.name, "widths": [lo, hi]} for s, lo, hi in d.levels],
        "calibration": calibration,
        "files": files,
    }
    if tapered is not None:
        out["thesis_tapering_arches"] = {"verdict": tapered_verdict(tapered, d.inputs.clearance_m * 1e3),
                                         "rows": [asdict(r) for r in tapered]}
        why = tapered_not_applicable(d.inputs.connectors, d.inputs.robot.name)
        if why:
            out["thesis_tapering_arches"]["not_applicable"] = why
    if rows is not None:
        out["table"] = [{k: v for k, v in asdict(r).items()} for r in rows]
    return out


def piers_markdown(piers, why: str = "") -> str:
    """The section "Piers (multi-span)" of the table's Markdown from a
    :class:`structure_fem.analysis.piers.PierDerivation` (or why there is none)."""
    head = "## Piers (multi-span)\n\n"
    if piers is None:
        return "\n" + head + f"Pier rule {why}.\n"
    r = piers.rule
    rows = ["| robots in the pier | pier stiffness (N/m) | overhang beyond one pier | beyond a second pier | "
            "widest void, one pier | x the first span | tip at the overhang (mm) | tipping at it |",
            "|---|---|---|---|---|---|---|---|"]
    for c in piers.crossings:
        o = c.overhang
        tip = f"{c.one.tip_mm[o - 1]:.2f}" if o >= 1 else "-"
        tf = f"{c.one.tipping[o - 1]:.2f}" if o >= 1 else "-"
        v = r.max_void_for(c.robots)
        rows.append(f"| {c.robots} | {c.stiffness.n_per_m:.4g} | {o} | {c.overhang_two} | {v} | "
                    f"{v / r.first_span_widths:.3g} | {tip} | {tf} |")
    bad = [f"k={c.robots}: {st.what}" for c in piers.crossings for st in c.states_one + c.states_two
           if not st.passes]
    checked = sum(len(c.states_one) + len(c.states_two) for c in piers.crossings)
    return ("\n" + head
            + f"Structure `{r.structure}`, first span {r.first_span_widths} (its own threshold), pier "
            f"{r.pier_width_widths} robot wide. Counting rule beyond the last support: rows behind its far face >= "
            f"{r.ground_ratio:g} x rows beyond + {r.ground_margin}. {checked} states of the crossings checked at "
            f"these counts" + (f"; failing: {'; '.join(bad)}" if bad else ", all standing within the clearance")
            + f" (largest tip {r.max_deflection_mm:.2f} mm, smallest tipping factor {r.min_tipping_factor:.2f}).\n\n"
            + "\n".join(rows) + "\n\n" + f"Notes: {r.notes}\n")
