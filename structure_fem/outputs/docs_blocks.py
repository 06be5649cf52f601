"""The numbers of ``docs/structure_fem.md``, generated from what the code computes.

``python -m structure_fem.outputs.docs_blocks docs/structure_fem.md`` rewrites every block between
``<!-- BEGIN generated NAME -->`` and ``<!-- END generated NAME -->`` (:data:`BLOCKS`):
the derived thresholds beside the thesis's (from the packaged ``limits.json``, itself checked
against a fresh derivation by the tests), the pier (multi-span) rule of that record, the CuBot
connector values of the packaged robot record, and the platform-bolt calibration family
(computed, ~1 s). ``--check`` reports a
stale file (exit 1); the tests run it, so the page cannot drift from the code.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

_BLOCK = re.compile(r"(<!-- BEGIN generated ([\w-]+) -->\n)(.*?)(<!-- END generated \2 -->)", re.S)


def _thresholds() -> str:
    from structure_fem.limits import load_limits, thesis_limits

    d, t = load_limits("derived"), thesis_limits()
    rows = ["| level | derived: void widths | derived: tip at widest (mm) | derived: tipping factor | "
            "derived: complete structure (robots) | thesis: void widths | thesis: robots at widest |",
            "|---|---|---|---|---|---|---|"]
    for k in range(max(len(d.levels), len(t.levels))):
        a = d.levels[k] if k < len(d.levels) else None
        b = t.levels[k] if k < len(t.levels) else None
        rows.append("| " + " | ".join([
            f"{a.name if a else '-'} / {b.name if b else '-'}",
            f"{a.min_span_widths}-{a.max_span_widths}" if a else "-",
            f"{a.max_deflection_mm:.2f}" if a and a.max_deflection_mm is not None else "-",
            f"{a.min_tipping_factor:.2f}" if a and a.min_tipping_factor is not None else "-",
            f"{a.min_robots[-1]}" if a else "-",
            f"{b.min_span_widths}-{b.max_span_widths}" if b else "-",
            f"{b.min_robots[-1]}" if b else "-"]) + " |")
    notes = getattr(d, "notes", "") or ""
    return (f"Derived for `{d.robot}` at {d.clearance_mm:g} mm clearance: thresholds {d.thresholds()}, widest "
            f"void {d.max_span_widths} widths; thesis: {t.thresholds()}, widest {t.max_span_widths}.\n\n"
            + "\n".join(rows) + "\n" + (f"\nThe record's notes: {notes}\n" if notes else ""))


def _connectors() -> str:
    from cubot_cad.properties import RobotPropertiesFile, default_properties_path
    from structure_fem.couplings.connector_sources import resolve

    rec = RobotPropertiesFile.load(default_properties_path())
    rows = ["| robot | coupling | rotational stiffness (N m/rad) | axial stiffness (N/m) | pitch play (mrad) | "
            "play per feature (mm) | values from |",
            "|---|---|---|---|---|---|---|"]
    prov = []
    for robot in rec.robots:
        used, _notes = resolve(robot)
        for c in used.connectors:
            play = ", ".join(f"{p.feature} {1e3 * p.play_m:.3g} ({p.axis}, {p.sense})" for p in c.play) or "-"
            orig = robot.connector(c.kind)
            was = ("" if c == orig else
                   f" (record: {orig.rotational_stiffness_nm_per_rad:.4g} / {orig.axial_stiffness_n_per_m:.3g})")
            rows.append(f"| {robot.name} | {c.kind} | {c.rotational_stiffness_nm_per_rad:.4g} | "
                        f"{c.axial_stiffness_n_per_m:.3g}{was} | {1000 * c.backlash_rad:.2f} | {play} | "
                        f"{c.provenance.split(':')[0]} |")
            prov.append(f"* `{robot.name}.{c.kind}`: {c.provenance}")
    src = {r.source for r in rec.robots}
    return ("From the packaged record `cubot_cad/data/robot_properties.json` (source: "
            + "; ".join(sorted(src)) + "), as the model uses it (`--connectors fe`, the default):\n\n"
            + "\n".join(rows) + "\n\nProvenance of each value:\n\n" + "\n".join(prov) + "\n")


def _calibration() -> str:
    from cubot_cad.properties import RobotPropertiesFile, default_properties_path
    from structure_fem.analysis.calibration import calibrate

    cal = calibrate(RobotPropertiesFile.load(default_properties_path()), None).to_dict()  # as `fem calibrate`
    out = []
    test = cal.get("platform_test", {})
    if test.get("available"):
        out += ["**The platform test, one set of inputs, nothing fitted** (flexible platforms with the CAD's plate, "
                "the bolt's FE joint; `fem calibrate` prints it first):", "",
                "| | 3 platforms | 4 platforms | 5 platforms |", "|---|---|---|---|",
                "| thesis Ch. 6.5.2 | " + " | ".join(f"{test['thesis'][n]}" + ("" if test["thesis"][n] == "slight" else " mm")
                                                   for n in ("3", "4", "5")) + " |"]
        out += [f"| model, `{r['reading']}` reading | " + " | ".join(f"{r['model_tips_mm'][n]:.3g} mm" for n in ("3", "4"))
                + f" | {r['model_tips_mm']['5']:.3g} mm ({r['model_faces_bearing_tip5_mm']:.3g} faces bearing) |"
                for r in test["readings"]]
        out += ["", test["statement"] + ".", ""]
    for r in cal["readings"]:
        su = r["set_up"]
        rows = [f"**Reading `{r['reading']}`**: {r['description']} ({su['platforms']} platforms, {su['held']} held, "
                f"{su['on_the_ground']} on the ground, {su['over']} over; supports {su['supports']}).", "",
                "| backlash (rad) | fitted stiffness (N m/rad) | tip 3 / 4 / 5 platforms (mm) |", "|---|---|---|"]
        rows += [f"| {f['backlash_rad']:.2g} | {f['stiffness_nm_per_rad']:.4g} | {f['tip3_mm']:.2f} / "
                 f"{f['tip4_mm']:.2f} / {f['tip5_mm']:.2f} |" for f in r["family"]]
        rows += ["", f"Chosen point b = {r['bolt_backlash_rad']:g} rad: k = {r['bolt_stiffness_nm_per_rad']:.4g} N m/rad "
                 f"({r['fitted_over_estimate']:.3g} x the platform record's estimate "
                 f"{cal['bolt_stiffness_estimate_nm_per_rad']:.4g} N m/rad); fed back into the model it gives "
                 f"{r['refit_tip5_mm']:.3f} mm for five platforms.", ""]
        out += rows
    return ("\n".join(out) + "\n"
            + f"The two readings' bolt stiffnesses differ by a factor {cal['readings_stiffness_ratio']:.3g}. "
            f"`--calibration-backlash` picks another point of both families; the `{cal['primary_reading']}` reading "
            "is the primary one (the top-level fields of `fem calibrate --json`, and the `--connectors calibrated` "
            "what-if).\n\n" + _fe_vs_fit(cal) + cal["robot_connectors"] + "\n")


def _fe_vs_fit(cal: dict) -> str:
    """The bolt's FE beside the fitted values (a table per reading) and the plain statement."""
    fe = cal.get("fe") or {}
    if not fe.get("available"):
        return cal.get("fe_statement", "") + "\n\n"
    rows = ["| reading | fitted to the thesis's 5 mm (N m/rad) | FE, whole pitch: faces free / lower edge bearing "
            "(N m/rad) | FE / fitted | FE is | five platforms with the FE (mm) |", "|---|---|---|---|---|---|"]
    rows += [f"| {r['reading']} | {r['fitted_nm_per_rad']:.4g} | {fe['pitch_stiffness_nm_per_rad']:.4g} / "
             f"{fe['contact_pitch_stiffness_nm_per_rad']:.4g} | {r['fe_over_fitted']:.3g} / "
             f"{r['fe_contact_over_fitted']:.3g} | {r['fe_is']} (x{r['factor']}) | {r['fe_tip5_mm']:.3g} / "
             f"{r['fe_contact_tip5_mm']:.3g} (measured {r['measured_tip5_mm']:g}) |" for r in fe["readings"]]
    return "\n".join(rows) + "\n\n" + cal["fe_statement"] + "\n\n"


def _piers() -> str:
    from structure_fem.limits import load_limits

    d = load_limits("derived")
    r = d.piers
    if r is None:
        return "The packaged `limits.json` has no pier rule (`voidcross fem table --piers none`).\n"
    rows = ["| robots in the pier (k) | pier stiffness (N/m) | overhang beyond one pier | beyond a second pier | "
            "widest void, one pier | x the line's threshold |", "|---|---|---|---|---|---|"]
    for k in range(1, r.max_pier_robots + 1):
        v = r.max_void_for(k)
        rows.append(f"| {k} | {r.pier_stiffness_n_per_m[k - 1]:.4g} | {r.overhang_for(k)} | "
                    f"{r.overhang_for(k, second=True)} | {v} | {v / r.first_span_widths:.3g} |")
    two = [r.first_span_widths + r.pier_width_widths + r.overhang_for(k) + r.pier_width_widths
           + r.overhang_for(k, second=True) for k in range(1, r.max_pier_robots + 1)]
    return (f"From the packaged `limits.json` (`{d.robot}`, {d.clearance_mm:g} mm clearance): structure "
            f"`{r.structure}`, first span {r.first_span_widths} (its own threshold), pier {r.pier_width_widths} "
            f"robot wide; beyond the last support rows behind its far face >= {r.ground_ratio:g} x rows beyond + "
            f"{r.ground_margin}; largest tip over the checked states {r.max_deflection_mm:.2f} mm, smallest tipping "
            f"factor {r.min_tipping_factor:.2f}. With two piers the widest void is {two} robot widths.\n\n"
            + "\n".join(rows) + f"\n\nThe rule's notes: {r.notes}\n")


def _dynamics() -> str:
    from structure_fem.limits import load_limits
    from structure_fem.model.dynamics_cache import PACKAGED, packaged

    def mm(v) -> str:
        return "-" if v is None else f"{v:.2f}"

    d = load_limits("derived")
    rows = ["| level | threshold (widths) | static tip at it (mm) | launch allowance (mm) | tip + allowance (mm) | "
            "clearance (mm) |", "|---|---|---|---|---|---|"]
    for lv in d.levels:
        tip, a = lv.max_deflection_mm, lv.dynamic_allowance_mm
        total = None if tip is None or a is None else tip + a
        rows.append(f"| {lv.name} | {lv.max_span_widths} | {mm(tip)} | {mm(a)} | {mm(total)} | {d.clearance_mm:g} |")
    entries = packaged()
    record = _record_keys(entries)
    by: dict[str, list] = {}
    for e in entries:
        by.setdefault(e.get("structure", "?"), []).append(e)
    tr = ["| structure | bodies | the record's inputs: width (robot widths): allowance (mm) | the range's input "
          "variants: width: allowance (mm) |", "|---|---|---|---|"]
    for name in sorted(by):
        es = sorted(by[name], key=lambda e: (e["width"], e["allowance_m"]))
        bodies = ", ".join(sorted({"flexible" if e.get("flexible") else "rigid" for e in es}))
        own = ", ".join(f"{e['width']:g}: {1e3 * e['allowance_m']:.2f}" for e in es if e["key"] in record) or "-"
        var = ", ".join(f"{e['width']:g}: {1e3 * e['allowance_m']:.2f}" for e in es if e["key"] not in record) or "-"
        tr.append(f"| {name} | {bodies} | {own} | {var} |")
    return (f"From the packaged `limits.json` (`{d.robot}`, {d.clearance_mm:g} mm clearance) and the "
            f"packaged transients (`structure_fem/data/{PACKAGED.name}`, {len(entries)} integrations, "
            f"{sum(e['key'] in record for e in entries)} of them with the record's own inputs):\n\n"
            + "\n".join(rows) + "\n\nThe transients integrated (the larger overshoot of the support loss and the "
            "docking push, per width; the variants are the margins table's range: print clearance, printed "
            "modulus, solid parts):\n\n" + "\n".join(tr) + "\n")


def _record_keys(entries: list[dict]) -> set[str]:
    """The keys among ``entries`` whose inputs are the packaged record's own (not a range variant's):
    the key recomputed from the default table's inputs for the entry's structure, width and rows."""
    from structure_fem.analysis.study import candidate_structures
    from structure_fem.model.dynamics_cache import inputs_of, key_of
    from structure_fem.outputs.runs import RunOptions, make_inputs

    inp, _ = make_inputs(RunOptions())
    structs = {s.name: s for s in candidate_structures(inp.connectors, narrow=True)}
    out = set()
    for e in entries:
        s = structs.get(e.get("structure"))
        if s is not None and key_of(inputs_of(s, e["width"], e["rows"], inp.robot, inp.connectors, e["flexible"],
                                              e["damping_ratio"], ("support_loss", "docking"))) == e["key"]:
            out.add(e["key"])
    return out


BLOCKS = {"thresholds": _thresholds, "dynamics": _dynamics, "connectors": _connectors, "calibration": _calibration,
          "piers": _piers}


def render(text: str) -> str:
    cache: dict = {}

    def sub(m):
        name = m.group(2)
        if name not in BLOCKS:
            raise KeyError(f"unknown generated block {name!r} (known: {', '.join(BLOCKS)})")
        if name not in cache:
            cache[name] = BLOCKS[name]()
        return m.group(1) + cache[name] + m.group(4)

    return _BLOCK.sub(sub, text)


def rewrite(argv: list[str] | None, render_fn, default: str, hint: str) -> int:
    """The command line of a docs generator: rewrite each path's generated blocks with
    ``render_fn``; ``--check`` only reports stale files (exit 1). Shared by
    :mod:`swarm_sim.decision_docs`."""
    args = list(sys.argv[1:] if argv is None else argv)
    check = "--check" in args
    paths = [a for a in args if a != "--check"] or [default]
    stale = []
    for p in map(Path, paths):
        old = p.read_text()
        new = render_fn(old)
        if new != old:
            stale.append(str(p))
            if not check:
                p.write_text(new)
    if check and stale:
        print(f"out of date (run {hint}): " + ", ".join(stale))
        return 1
    return 0


def main(argv: list[str] | None = None) -> int:
    return rewrite(argv, render, "docs/structure_fem.md", "python -m structure_fem.outputs.docs_blocks")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
