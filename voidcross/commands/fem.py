"""`voidcross fem`: structure_fem: deflection studies, derived thresholds, selection table.

Sub-commands: ``table`` (selection table, limits.json), ``study`` (plots,
sensitivity), ``calibrate`` (test-platform bolt fit), ``solve`` (one
configuration), ``piers`` (one configuration over piers of failed robots),
``bench`` (timings). exudyn is imported only when a sub-command runs.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from cubot_cad.errors import InputError
from voidcross.output import emit, out_dir, out_file, progress

EPILOG = """examples:
  voidcross fem table                          derived thresholds + table into results/fem
  voidcross fem table --json                   thresholds beside the thesis's 5/10/15/20/25/30
  voidcross fem table --band --json            with the uncertainty band (p5 / p50 / p95), the table at p5
  voidcross fem table --caster                 strict clearance: the casters' exposed height
  voidcross fem table --clearance-mm 10 --properties exports/robot_properties.json --out /tmp/fem
  voidcross fem study --out results/fem-study  deflection plots and sensitivity
  voidcross fem calibrate --json               fit the test-platform bolt to the thesis's 5 mm
  voidcross fem bench-example --out /tmp/m.json  the coupling bench test on the model (a SYNTHETIC --measured file)
  voidcross fem solve --structure line --rows 9 --over 4 --void 4
  voidcross fem solve --structure arch --lines 6 --layers 3 --taper-block-rows 5 --rows 30 --over 15 --void 15
                                               the thesis's tapering arch, core front at the far edge
  voidcross fem bench                          time the whole table and one 15-robot solve
  voidcross fem design --void-width 5 --structure line
                                               stiffness, play or mass that would make the line span 5
  voidcross fem connectors                     compute (and cache) the FE of the record's couplings
  voidcross fem table --piers none             the table without the pier (multi-span) rule
  voidcross fem piers --void-width 7 --piers 3 --pier-robots 2 --plot piers.png
                                               the line over a pier of 2 failed robots, front at the far edge
  voidcross fem piers --void-width 11 --piers 3,7 --pier-robots 4 --json
"""


def _add_inputs(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("inputs")
    g.add_argument("--properties", metavar="JSON", default=None,
                   help="robot_properties.json (default: the packaged one, or the cad stage's)")
    g.add_argument("--robot", default="cubot", help="robot model in the properties file (default cubot)")
    g.add_argument("--clearance-mm", type=float, default=None, metavar="MM",
                   help="climb clearance (default: the robot's exposed main-wheel height, thesis 15 mm)")
    g.add_argument("--caster", action="store_true",
                   help="strict alternative: clearance = exposed caster height (thesis 3.3 mm)")
    g.add_argument("--connectors", choices=("fe", "properties", "calibrated"), default="fe",
                   help="connector stiffness: FE where a result applies to the record's geometry, else the "
                        "record (default fe); the record's hand formulas only (properties); or those scaled by "
                        "the platform calibration (calibrated). Play always comes from the CAD's clearances")
    g.add_argument("--measured", metavar="JSON", default=None,
                   help="measured couplings ({\"front_rear\": {\"rotational_stiffness_nm_per_rad\": ..}}): "
                        "replace those connectors' stiffness (provenance measured: FILE)")
    g.add_argument("--stiffness-scale", type=float, default=1.0, help="multiply every coupling stiffness")
    g.add_argument("--backlash-scale", type=float, default=1.0, help="multiply every coupling backlash")
    g.add_argument("--mass-scale", type=float, default=1.0, help="multiply the robot's mass and inertia")
    g.add_argument("--tipping", type=float, default=1.0, metavar="F",
                   help="required tipping safety factor (> F at the longest cantilever; default 1)")
    bodies = g.add_mutually_exclusive_group()
    bodies.add_argument("--rigid", dest="flexible", action="store_false",
                        help="rigid robot bodies (only the couplings bend); default: flexible bodies")
    bodies.add_argument("--flexible", dest="flexible", action="store_true", default=True,
                        help="the default: each robot bends with its printed shell's section from the CAD "
                             "(E of the material, I of body_second_moment_m4)")
    crit = g.add_mutually_exclusive_group()
    crit.add_argument("--dynamic", dest="dynamic", action="store_true", default=True,
                      help="the default: threshold = static tip + launch-transient overshoot (a row leaving the "
                           "ledge, a recruit docking) <= clearance; exudyn time integration at the threshold, "
                           "cached by input hash (cold: 1-120 s per structure; the packaged record's are shipped)")
    crit.add_argument("--static", dest="dynamic", action="store_false",
                      help="threshold = static tip <= clearance (no launch transients)")
    g.add_argument("--hinge", choices=("lumped", "emergent"), default="emergent",
                   help="couplings whose faces touch (the CuBot's front-rear, every layer's twist-lock): "
                        "tension rows with their play + compression-only face contacts, sliding side rails: "
                        "the hinge emerges (emergent, the default and the packaged record's); or one point "
                        "spring + a pitch dead band of tension play / highest pin, side rails tie along x (lumped)")
    g.add_argument("--damping-ratio", type=float, default=0.02, metavar="Z",
                   help="first-mode damping ratio of the launch transients (default 0.02, an assumption: "
                        "printed ABS/PLA 0.5-2.5 %% plus joint friction)")
    g.add_argument("--max-width", type=int, default=30, metavar="W",
                   help="widest void studied, robot widths (default 30)")
    g.add_argument("--calibration-backlash", type=float, default=None, metavar="RAD",
                   help="backlash of the platform bolt for the calibration fit (default 0: stiffness only)")


#: user-term bounds of the study's scale options (checked before any solve)
SCALE_BOUNDS = {"--stiffness-scale": (0.0, 1e3, True), "--backlash-scale": (0.0, 100.0, False),
                "--mass-scale": (0.0, 100.0, True), "--tipping": (0.0, 100.0, True)}
MAX_CLEARANCE_MM = 100.0  # more than a robot's height (CuBot 85 mm): not a climb the model describes


def _opts(args):
    from structure_fem.outputs.runs import RunOptions
    from voidcross.output import check_float

    for opt, (lo, hi, lo_open) in SCALE_BOUNDS.items():
        check_float(getattr(args, opt[2:].replace("-", "_")), opt, lo, hi, lo_open=lo_open)
    check_float(args.clearance_mm, "--clearance-mm", 0.0, MAX_CLEARANCE_MM,
                what="a climb clearance above the robots' height is outside the model")
    if getattr(args, "damping_ratio", None) is not None:
        check_float(args.damping_ratio, "--damping-ratio", 0.0, 0.99, lo_open=False,
                    what="a damping ratio of 1 or more is no longer an oscillation")

    return RunOptions(properties=args.properties, robot=args.robot, clearance_mm=args.clearance_mm,
                      caster=args.caster, connectors=args.connectors, stiffness_scale=args.stiffness_scale,
                      backlash_scale=args.backlash_scale, mass_scale=args.mass_scale, required_tipping=args.tipping,
                      flexible=args.flexible, calibration_backlash=args.calibration_backlash,
                      max_width=args.max_width, measured=args.measured,
                      piers=getattr(args, "piers_rule", "auto"), dynamic=getattr(args, "dynamic", True),
                      damping_ratio=getattr(args, "damping_ratio", 0.02),
                      sensitivity_dynamic=getattr(args, "sensitivity_dynamic", False),
                      hinge=getattr(args, "hinge", "emergent"),
                      band_samples=getattr(args, "band_samples", 0) or 0, pick=getattr(args, "pick", "p5"),
                      ranges=getattr(args, "ranges", True))


def _bar(iterable, desc, total):
    return progress(iterable, desc, total)


def _warn(res: dict) -> None:
    """One ``warning: ...`` line on stderr per solve that did not converge (``res["warnings"]``)."""
    for line in res.get("warnings", ()):
        print(line, file=sys.stderr)


def run_table(args) -> int:
    from structure_fem.outputs.runs import run_table as _run

    out = out_dir(args.out, "--out", create=False)  # checked before the 30 s of solving
    if args.docs:
        out_dir(args.docs, "--docs", create=False)
    res = _run(out, _opts(args), docs_dir=args.docs, progress=_bar)
    th, tt = res["thresholds"], res["thesis_thresholds"]
    human = (f"derived thresholds (robot widths, clearance {res['clearance_mm']:g} mm): line {th['line']}, "
             f"two_line {th['two_line']}, arch {th['arch']}, arch levels {th['arch_levels']}; "
             f"widest void {res['max_span_widths']}\n"
             f"thesis thresholds: line {tt['line']}, two_line {tt['two_line']}, arch {tt['arch']}, "
             f"arch levels {tt['arch_levels']}\n"
             f"calibrated platform bolt: {res['calibration']['bolt_stiffness_nm_per_rad']:.4g} N m/rad at "
             f"{res['calibration']['bolt_backlash_rad']:g} rad backlash ("
             + ", ".join(f"{r['reading']} reading {r['bolt_stiffness_nm_per_rad']:.4g}"
                         for r in res["calibration"].get("readings", ()))
             + "); not used for the CuBot's connectors (they come from FE / the record, "
             "`fem calibrate` says which)\n"
             + _band_line(res.get("band"))
             + _tapered_line(res.get("thesis_tapering_arches"))
             + _piers_line(res.get("piers"))
             + _margins_lines(res.get("structures", []))
             + "\n".join(f"  {k}: {v}" for k, v in res["files"].items()))
    if not args.full_json:
        res.pop("table", None)
    _warn(res)
    emit(args, res, human)
    return 0


def _band_line(band: dict | None) -> str:
    if not band:
        return ""
    return (f"uncertainty band ({len(band['samples'])} samples; thresholds above at {band['pick']}): "
            + ", ".join(f"{s} {v['p5']} / {v['p50']} / {v['p95']} (nominal {v['nominal']})"
                        for s, v in band["per_structure"].items()) + " (p5 / p50 / p95)\n")


def _margins_lines(structures: list[dict]) -> str:
    """One line per structure: threshold, margin, what sets it, range over plausible inputs."""
    out = []
    for r in structures:
        if not r.get("threshold"):
            out.append(f"  {r['structure']}: crosses no void")
            continue
        rg = r.get("range")
        rng = "" if rg is None else f", range {rg['min']}-{rg['max']} over print clearance and modulus"
        share = f" ({100 * r['set_by_share']:.0f} %)" if "set_by_share" in r else ""
        setby = f", set by {r['set_by']}{share}" if "set_by" in r else ""
        flag = " MARGINAL" if r.get("marginal") else ""
        flag += ", at --max-width: a lower bound" if r.get("capped_by_max_width") else ""
        out.append(f"  {r['structure']}: {r['threshold']} (margin {r['margin_mm']:.2f} mm{flag}{setby}{rng})")
    return ("thresholds, margins and what sets them:\n" + "\n".join(out) + "\n") if out else ""


def _piers_line(p: dict | None) -> str:
    """One line: the pier (multi-span) rule, or why there is none."""
    if not p:
        return ""
    r = p.get("rule")
    if r is None:
        return f"pier rule: {p.get('why', 'not derived')}\n"
    ratio = max(r["max_void_widths"]) / r["first_span_widths"]
    return (f"pier rule ({r['structure']}, first span {r['first_span_widths']}): overhang beyond one pier of "
            f"1..{len(r['overhang_widths'])} robots {r['overhang_widths']}, beyond a second "
            f"{r['overhang_widths_two_piers']}; widest void with one pier {r['max_void_widths']} "
            f"(x{ratio:.3g}); rows behind the last support >= {r['ground_ratio']:g} x rows beyond + "
            f"{r['ground_margin']}\n")


def _tapered_line(t: dict | None) -> str:
    """One line: do the thesis's tapering arches hold under our mechanics?"""
    if not t:
        return ""
    if t.get("not_applicable"):
        return f"thesis tapering arches: not evaluated ({t['not_applicable']})\n"
    v, rows = t["verdict"], t["rows"]
    tips = [r["tip_mm"] for r in rows if r["tip_mm"] is not None]
    bridged = [r["bridged_max_mm"] for r in rows if r["bridged_max_mm"] is not None]
    span = f"tip {min(tips):.1f}..{max(tips):.1f} mm at g = w" if tips else "no standing cantilever"
    return (f"thesis tapering arches under our mechanics: hold at {len(v['widths_passing'])} of "
            f"{v['widths_evaluated']} band widths ({span}, clearance {v['clearance_mm']:g} mm; bridged at most "
            f"{max(bridged, default=float('nan')):.1f} mm)\n")


def run_study(args) -> int:
    from structure_fem.outputs.runs import run_study as _run

    res = _run(out_dir(args.out, "--out", create=False), _opts(args), progress=_bar)
    th = res["thresholds"]
    human = (f"thresholds: line {th['line']}, two_line {th['two_line']}, arch {th['arch']}, "
             f"arch levels {th['arch_levels']} (clearance {res['clearance_mm']:g} mm)\n"
             + "\n".join(f"  {k}: {v}" for k, v in res["files"].items()))
    _warn(res)
    emit(args, res, human)
    return 0


def _readings_text(cal: dict) -> str:
    """Both readings of the platform measurement: fitted bolt, predicted tips, family."""
    out = [cal["platform_test"]["statement"]] if cal.get("platform_test", {}).get("available") else []
    out += [f"platform bolt fitted to {cal['measurement']}; record's estimate "
           f"{cal['bolt_stiffness_estimate_nm_per_rad']:.4g} N m/rad"]
    for r in cal["readings"]:
        primary = " (primary: --connectors calibrated uses it)" if r["reading"] == cal["primary_reading"] else ""
        out.append(f"reading {r['reading']}{primary}: {r['description']}\n"
                   f"  bolt {r['bolt_stiffness_nm_per_rad']:.4g} N m/rad at {r['bolt_backlash_rad']:g} rad backlash "
                   f"(x{r['fitted_over_estimate']:.3g} the estimate); fed back: 5 platforms {r['refit_tip5_mm']:.3f} mm; "
                   f"predicted tips mm {r['predicted_tip_mm']}\n"
                   "  family (backlash rad -> stiffness, tips 3/4/5 mm):\n"
                   + "\n".join(f"    {f['backlash_rad']:.4g} -> {f['stiffness_nm_per_rad']:.4g}: "
                               f"{f['tip3_mm']:.2f} / {f['tip4_mm']:.2f} / {f['tip5_mm']:.2f}" for f in r["family"]))
    out.append(f"the two readings' stiffnesses differ x{cal['readings_stiffness_ratio']:.3g}")
    if cal.get("fe_statement"):
        out.append(cal["fe_statement"])
    return "\n".join(out)


def _masses(text: str | None) -> tuple[float, ...] | None:
    if text is None:
        return None
    items = [t.strip() for t in str(text).split(",")]
    if not any(items) or "" in items:
        raise InputError(f"--masses-kg {text!r}: give a comma list of masses in kg, e.g. 0,0.5,1,2")
    try:
        return tuple(float(t) for t in items)
    except ValueError:
        raise InputError(f"--masses-kg {text!r}: not a comma list of numbers (kg)") from None


def run_bench_example(args) -> int:
    """`fem bench-example`: the bench test of docs/measure-coupling.md on the model, written as a
    ``--measured`` file labelled SYNTHETIC (the protocol's worked example, never a measurement)."""
    from cubot_cad.jsonrecord import write_json_atomic
    from structure_fem.analysis.bench_test import (
        DEFAULT_MASSES_KG,
        bench_test,
        synthetic_measurement,
    )
    from structure_fem.outputs.runs import make_inputs

    masses = _masses(args.masses_kg) or DEFAULT_MASSES_KG
    path = out_file(args.out, "--out")
    inp, _ = make_inputs(_opts(args))
    test = bench_test(inp.robot, inp.connectors, masses, flexible=inp.flexible)
    data = synthetic_measurement(test)
    k, play, n = test.fit()
    write_json_atomic(path, data)
    payload = {"file": str(path), "robot": test.robot, "coupling": test.coupling, "synthetic": True,
               "lever_mm": round(test.lever_m * 1e3, 3), "gauge_span_mm": round(test.span_m * 1e3, 3),
               "readings": [{"mass_kg": r.mass_kg, "moment_nm": round(r.moment_nm, 5),
                             "drop_near_mm": round(r.drop_near_m * 1e3, 4), "drop_far_mm": round(r.drop_far_m * 1e3, 4),
                             "rotation_mrad": round(r.rotation_rad * 1e3, 4)} for r in test.readings],
               "fit": {"rotational_stiffness_nm_per_rad": round(k, 3), "play_rad": play, "points": n},
               "model_coupling": {"rotational_stiffness_nm_per_rad": round(inp.connectors.front_rear.rotational_nm_per_rad, 3),
                                  "backlash_rad": inp.connectors.front_rear.backlash_rad}}
    human = (f"wrote {path}: SYNTHETIC bench test of {test.robot}'s front_rear coupling (the model, not a measurement)\n"
             + "\n".join(f"  {r['mass_kg']:g} kg: moment {r['moment_nm']:.4g} N m, gauges {r['drop_near_mm']:.3f} / "
                         f"{r['drop_far_mm']:.3f} mm, rotation {r['rotation_mrad']:.3g} mrad" for r in payload["readings"])
             + f"\n  fit: k = {k:.4g} N m/rad, play {play * 1e3:.3g} mrad over {n} points (the model's coupling: "
               f"{payload['model_coupling']['rotational_stiffness_nm_per_rad']:.4g} N m/rad without the bodies' bending)"
             + f"\n  use it: voidcross fem calibrate --measured {path}; voidcross fem table --measured {path}")
    emit(args, payload, human)
    return 0


def run_calibrate(args) -> int:
    from structure_fem.analysis.calibration import calibrate
    from structure_fem.outputs.runs import load_file

    props = load_file(_opts(args))
    if props is not None:
        props.get(args.robot)  # an unknown --robot is an input error here too (InputError naming it)
    cal = calibrate(props, args.calibration_backlash).to_dict()
    measured = ""
    if args.measured:
        from structure_fem.couplings.connector_sources import load_measured

        robot = (props.get(args.robot) if props is not None else None)
        got = load_measured(args.measured, robot) if robot is not None else []
        cal["measured"] = {c.kind: {"rotational_stiffness_nm_per_rad": c.rotational_stiffness_nm_per_rad,
                                    "axial_stiffness_n_per_m": c.axial_stiffness_n_per_m,
                                    "backlash_rad": c.backlash_rad, "provenance": c.provenance} for c in got}
        measured = "".join(f"\nmeasured {args.robot} {k}: {v['rotational_stiffness_nm_per_rad']:.4g} N m/rad, "
                           f"play {v['backlash_rad'] * 1e3:.3g} mrad ({v['provenance']}); `fem table --measured "
                           f"{args.measured}` uses it" for k, v in cal["measured"].items())
    human = (_readings_text(cal) + measured + "\n" + cal["robot_connectors"])
    emit(args, cal, human)
    return 0


def _structure(args):
    from structure_fem.model.structures import Structure

    kind = args.structure
    if args.taper_block_rows is not None:  # the thesis's tapering arch (lines aligned); bad kinds fail in Structure
        lines, layers = (1, 1) if kind == "line" else (2, 1) if kind == "two_line" else (args.lines, args.layers)
        return Structure(kind, lines, layers, "aligned", args.taper_block_rows)
    if kind == "line":
        return Structure("line")
    if kind == "two_line":
        return Structure("two_line", 2, 1, args.arrangement)
    return Structure("arch", args.lines, args.layers, args.arrangement)


MAX_SOLVE_ROWS = 1000  # a structure of more rows is far past the widest void (30 widths)


def run_solve(args) -> int:
    from structure_fem.errors import SolverFailure
    from structure_fem.model.statics import Config, solve
    from structure_fem.outputs.runs import make_inputs

    if args.plot:
        if Path(args.plot).suffix.lower() not in (".png", ".svg", ".pdf"):
            raise InputError(f"--plot {args.plot}: use a .png, .svg or .pdf file name")
        out_file(args.plot, "--plot")
    from voidcross.output import check_float, check_int

    check_int(args.rows, "--rows", 1, MAX_SOLVE_ROWS)
    check_float(args.void, "--void", 0.0, float(args.max_width), lo_open=False,
                what="void width in robot widths, at most --max-width")
    check_float(args.over, "--over", 0.0, float(args.rows), lo_open=False, what="rows past the near edge")
    inp, _ = make_inputs(_opts(args))
    s = _structure(args)
    cfg = Config(s, args.rows, args.over, args.void, args.phase)
    try:
        res = solve(cfg, inp.robot, inp.connectors, inp.flexible)
    except SolverFailure as exc:  # valid input without a converged solution: say so, no traceback
        print(f"warning: {s.name} at void width {args.void:g}: the static solve did not converge: {exc}",
              file=sys.stderr)
        emit(args, {"structure": s.name, "converged": False, "reason": str(exc)},
             f"{cfg.describe(inp.robot.name)}: the static solve did not converge (no result)")
        return 0
    payload = {"structure": s.name, "converged": True, "robots": res.robots,
               "tip_deflection_mm": res.tip_deflection_mm,
               "max_deflection_mm": res.max_deflection_m * 1e3,
               "tipping_factor": res.tipping_factor if res.tipping_factor != float("inf") else None,
               "joint_rotations_rad": res.joint_rotation_rad.tolist(),
               "support_reactions_n": res.reactions_n.tolist(), "weight_n": res.total_weight_n}
    if args.plot:
        from structure_fem.outputs.plots import side_view

        payload["plot"] = str(side_view(res, Path(args.plot), inp.robot.height_m))
    tf = payload["tipping_factor"]
    human = (f"{res.config.describe(inp.robot.name)}: {res.robots} robots, tip {res.tip_deflection_mm:.3f} mm, "
             f"tipping factor {'-' if tf is None else f'{tf:.3f}'}, reactions {res.reactions_n.sum():.3f} N "
             f"of {res.total_weight_n:.3f} N weight")
    emit(args, payload, human)
    return 0


def parse_pier_positions(raw: str, void_width: float, width: float = 1.0) -> tuple[float, ...]:
    """``--piers 3[,7]``: the piers' near faces in robot widths from the near edge, each ``width``
    robot lengths wide, inside the void, in order and not overlapping; else an InputError naming
    the value."""
    import math

    items = [x.strip() for x in str(raw).split(",")]
    if not items or any(x == "" for x in items):
        raise InputError(f"--piers {raw!r}: give pier positions as a comma list of numbers (robot widths from "
                         "the near edge), e.g. 3 or 3,7")
    out: list[float] = []
    for x in items:
        try:
            v = float(x)
        except ValueError:
            raise InputError(f"--piers {raw!r}: {x!r} is not a number (pier positions in robot widths from "
                             "the near edge)") from None
        if not math.isfinite(v):
            raise InputError(f"--piers {raw!r}: {x!r} is not a finite number")
        if v <= 0:
            raise InputError(f"--piers {raw!r}: pier at {v:g} is not inside the void (positions are > 0 robot "
                             "widths from the near edge)")
        if v + width >= void_width:
            raise InputError(f"--piers {raw!r}: pier at {v:g} ({width:g} robot wide) reaches beyond the "
                             f"{void_width:g}-wide void (--void-width)")
        if out and v < out[-1] + width:
            raise InputError(f"--piers {raw!r}: pier at {v:g} overlaps the pier at {out[-1]:g} (each is {width:g} "
                             "robot wide; give them in order from the near edge)")
        out.append(v)
    return tuple(out)


def run_piers(args) -> int:
    from structure_fem.analysis.piers import MAX_PIER_ROBOTS, PIER_WIDTH_WIDTHS, solve_piers
    from structure_fem.errors import SolverFailure
    from structure_fem.outputs.runs import make_inputs
    from voidcross.output import check_float, check_int

    if args.plot:
        if Path(args.plot).suffix.lower() not in (".png", ".svg", ".pdf"):
            raise InputError(f"--plot {args.plot}: use a .png, .svg or .pdf file name")
        out_file(args.plot, "--plot")
    check_float(args.void_width, "--void-width", 0.0, float(args.max_width),
                what="void width in robot widths, at most --max-width")
    check_int(args.pier_robots, "--pier-robots", 1, MAX_PIER_ROBOTS,
              what=f"robots stacked in a pier; the thesis stacks at most {MAX_PIER_ROBOTS} high")
    at = parse_pier_positions(args.pier_positions, args.void_width, PIER_WIDTH_WIDTHS)
    check_int(args.rows, "--rows", 1, MAX_SOLVE_ROWS)
    check_float(args.over, "--over", 0.0, args.void_width, lo_open=False,
                what="rows past the near edge, at most the void width (the front before the far ledge)")
    if args.rows is not None and args.over is not None:
        check_float(args.over, "--over", 0.0, float(args.rows), lo_open=False, what="rows past the near edge")
    inp, _ = make_inputs(_opts(args))
    s = _structure(args)
    try:
        sol = solve_piers(inp, args.void_width, at, args.pier_robots, s, args.rows, args.over)
    except SolverFailure as exc:
        print(f"warning: {s.name} at void width {args.void_width:g} over piers at {list(at)}: the static solve "
              f"did not converge: {exc}", file=sys.stderr)
        emit(args, {"structure": s.name, "converged": False, "reason": str(exc)},
             f"{s.name} over piers at {list(at)}: the static solve did not converge (no result)")
        return 0
    payload = {"converged": True, **sol.to_dict()}
    if args.plot:
        from structure_fem.outputs.plots import side_view

        payload["plot"] = str(side_view(sol.result, Path(args.plot), inp.robot.height_m))
    res = sol.result
    tf = payload["tipping_factor"]
    by: dict[str, list[float]] = {}
    for r in payload["support_reactions"]:
        by.setdefault(r["support"], []).append(r["reaction_n"])
    piers = "\n".join(f"  pier {i + 1} at {p['at_widths']:g}: {p['robots']} robots, K = {p['stiffness_n_per_m']:.4g} "
                      f"N/m ({p['stiffness_formula']}), load {p['load_n']:.3f} N, compression "
                      f"{p['compression_mm']:.4f} mm" for i, p in enumerate(payload["piers"]))
    human = (f"{res.config.describe(inp.robot.name)}: {res.robots} robots, tip {res.tip_deflection_mm:.3f} mm "
             f"(clearance {payload['clearance_mm']:g} mm), tipping factor "
             f"{'-' if tf is None else f'{tf:.3f}'} about x = {payload['tipping_edge_m']:.3f} m: "
             f"{'passes' if payload['passes'] else 'FAILS'}\n{piers}\n"
             "  reactions: " + ", ".join(f"{k} {sum(v):.3f} N ({len(v)} contacts)" for k, v in by.items())
             + f"; sum {payload['support_reactions_sum_n']:.3f} N of {payload['weight_n']:.3f} N weight"
             + (f"\n  plot: {payload['plot']}" if args.plot else ""))
    emit(args, payload, human)
    return 0


def run_design(args) -> int:
    from structure_fem.analysis.design import PARAMETERS, describe, design
    from structure_fem.outputs.runs import make_inputs
    from voidcross.output import check_int

    check_int(args.void_width, "--void-width", 1, args.max_width)
    from voidcross.output import parse_choices

    params = parse_choices(args.vary, "--vary", PARAMETERS, all_word=None)
    inp, _ = make_inputs(_opts(args))
    res = design(inp, args.structure, args.void_width, params)
    emit(args, res, describe(res))
    return 0


def run_connectors(args) -> int:
    from structure_fem.couplings.connector_sources import (
        fe_front_rear_for,
        fe_octbot_ring_for,
        fe_platform_bolt_for,
    )
    from structure_fem.outputs.runs import load_file

    props = load_file(_opts(args))
    robot = props.get(args.robot)
    kinds = {c.kind for c in robot.connectors}
    # the test platform's lap joint, the OctBot's ring, else the front-rear coupling
    finder = (fe_platform_bolt_for if "bolt" in kinds else fe_octbot_ring_for if "ring_capture" in kinds
              else fe_front_rear_for)
    fe, where = finder(robot, compute=True)
    if fe is None:
        raise InputError(f"no FE model applies to robot {robot.name!r}: {where}")
    import math

    shear = fe.shear_stiffness_n_per_m if math.isfinite(fe.shear_stiffness_n_per_m) else None  # the ring: not modelled
    payload = {"robot": robot.name, "kind": fe.kind, "rotational_stiffness_nm_per_rad": fe.rotational_stiffness_nm_per_rad,
               "axial_stiffness_n_per_m": fe.axial_stiffness_n_per_m, "shear_stiffness_n_per_m": shear,
               "provenance": fe.provenance, "input_hash": fe.input_hash, "from": where, "timings_s": fe.timings_s}
    emit(args, payload, f"{robot.name} {fe.kind}: {fe.rotational_stiffness_nm_per_rad:.4g} N m/rad, "
                        f"{fe.axial_stiffness_n_per_m:.3g} N/m axial, "
                        + (f"{shear:.3g} N/m shear" if shear is not None else "shear not modelled")
                        + f" ({where}; key {fe.input_hash[:16]})\n  {fe.provenance}")
    return 0


def run_bench(args) -> int:
    from cubot_cad.properties import default_properties
    from structure_fem.analysis.study import StudyInputs
    from structure_fem.model.statics import Config
    from structure_fem.model.statics import solve_uncached as solve
    from structure_fem.model.structures import Structure
    from structure_fem.outputs.runs import RunOptions, run_table

    out_dir(args.out, "--out", create=False)  # before a minute of solving
    if args.cold_fe and args.fe_workers < 1:
        raise InputError(f"--fe-workers must be >= 1, got {args.fe_workers}")
    robot = default_properties().get("cubot")
    inp = StudyInputs.for_robot(robot)
    cfg = Config(Structure("line"), 15, 5, 5)
    solve(cfg, robot, inp.connectors)  # warm-up (exudyn import)
    n = 20
    t0 = time.perf_counter()
    for _ in range(n):
        solve(cfg, robot, inp.connectors)
    one = (time.perf_counter() - t0) / n
    # the whole default table twice in a fresh private cache: cold (every static solve) and warm
    # (the solve cache filled by the first; the launch allowances are the packaged ones both times)
    import os
    import tempfile

    from structure_fem import solve_cache

    saved = os.environ.get("XDG_CACHE_HOME")
    times = []
    with tempfile.TemporaryDirectory() as cache:
        os.environ["XDG_CACHE_HOME"] = cache
        try:
            for _ in range(2):
                t0 = time.perf_counter()
                run_table(Path(args.out), RunOptions(), alternative=False, plots=False)
                times.append(time.perf_counter() - t0)
        finally:
            solve_cache._CONN = None
            if saved is None:
                os.environ.pop("XDG_CACHE_HOME", None)
            else:
                os.environ["XDG_CACHE_HOME"] = saved
    cold_table, whole = times
    from structure_fem.couplings.connector_sources import fe_front_rear_for

    t0 = time.perf_counter()
    fe, where = fe_front_rear_for(robot)
    fe_s = time.perf_counter() - t0
    cold = None if fe is None else fe.timings_s.get("total")
    # every packaged FE result's cold time as recorded when it was computed (issue 12's goal: all <= 5 min)
    from structure_fem.couplings.connector_sources import packaged_fe

    per_fe = {f"{d.get('kind')}:{str(d.get('input_hash'))[:12]}": (d.get("timings_s") or {}).get("total")
              for d in packaged_fe()}
    all_cold = sum(v for v in per_fe.values() if isinstance(v, (int, float)))
    payload = {"line_15_robots_solve_s": one, "line_15_goal_s": 0.2, "table_s": whole, "table_goal_s": 60.0,
               "table_cold_s": cold_table, "table_warm_is": "second run, solve cache filled by the first",
               "line_15_ratio_to_goal": one / 0.2, "table_ratio_to_goal": whole / 60.0,
               "connector_fe_lookup_s": fe_s, "connector_fe_from": where, "connector_fe_cold_s_when_computed": cold,
               "connector_fe_all_cold_s_recorded": round(all_cold, 3), "connector_fe_all_goal_s": 300.0,
               "connector_fe_all_ratio_to_goal": round(all_cold / 300.0, 3), "connector_fe_cold_s_per_result": per_fe,
               "connector_fe_all_is": "sum of the packaged results' recorded cold times (each measured when it was "
                                      "computed, not in this run)"}
    cold_fe_text = ""
    if args.cold_fe:
        # every packaged result computed again from nothing, in a private cache, 2 processes
        from structure_fem.couplings.connector_sources import compute_packaged_fe

        with tempfile.TemporaryDirectory() as tmp:
            def tick(done, total, label):
                print(f"  cold connector FE {done}/{total}: {label} done", file=sys.stderr, flush=True)

            _res, wall, per_task = compute_packaged_fe(tmp, workers=args.fe_workers, packaged=False, progress=tick)
        payload.update({"connector_fe_all_cold_wall_s": round(wall, 3), "connector_fe_all_cold_workers": args.fe_workers,
                        "connector_fe_all_cold_ratio_to_goal": round(wall / 300.0, 3),
                        "connector_fe_cold_s_per_task": per_task})
        cold_fe_text = (f"\nconnector FE, all {len(per_task)} computed now from nothing on {args.fe_workers} "
                        f"process(es): {wall:.0f} s wall (goal 300 s, ratio {wall / 300:.2f})")
    emit(args, payload, f"one 15-robot line solve: {one * 1e3:.1f} ms (goal 200 ms, ratio {one / 0.2:.3f})\n"
                        f"whole table w=1..30 (flexible bodies, launch allowance): warm {whole:.1f} s (goal 60 s, "
                        f"ratio {whole / 60:.3f}), cold {cold_table:.1f} s (every static solve)\n"
                        f"connector FE (CuBot front-rear): {fe_s * 1e3:.1f} ms from the {where} "
                        f"(cold solve when it was computed: {cold} s)\n"
                        f"connector FE, all {len(per_fe)} packaged results: {all_cold:.0f} s cold as recorded (goal "
                        f"300 s, ratio {all_cold / 300:.2f})" + cold_fe_text)
    return 0


def register(sub, common) -> None:
    p = sub.add_parser("fem", parents=[common], help="structure_fem: deflection studies, derived thresholds, selection table",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    fs = p.add_subparsers(dest="fem_command", metavar="SUBCOMMAND", parser_class=type(p))
    p.set_defaults(func=lambda a: (p.print_help(), 0)[1])

    t = fs.add_parser("table", parents=[common], help="structure-selection table w=1..30, limits.json",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    t.add_argument("--out", default="results/fem", help="output directory (default results/fem)")
    t.add_argument("--docs", default=None, metavar="DIR", help="also write DIR/structure_fem_table.md")
    t.add_argument("--full-json", action="store_true", help="include the table rows in --json output")
    t.add_argument("--piers", dest="piers_rule", choices=("auto", "none"), default="auto",
                   help="derive the pier (multi-span) rule into limits.json (auto, the default) or not (none)")
    t.add_argument("--band", dest="band_samples", type=int, nargs="?", const=20, default=0, metavar="N",
                   help="thresholds with an uncertainty band: N Latin-hypercube samples (default 20) over the "
                        "print's play, coupling stiffness, modulus and the robot's mass; per structure p5 / p50 / "
                        "p95 (minutes: a few solves per structure and sample, cached)")
    t.add_argument("--pick", choices=("p5", "p50", "nominal"), default="p5",
                   help="with --band: the thresholds the table and limits.json use (default p5: the width 95 %% "
                        "of printed robots span; nominal: the robot as drawn)")
    t.add_argument("--no-ranges", dest="ranges", action="store_false", default=True,
                   help="leave out each structure's range over print clearance, modulus and infill (about half "
                        "of a cold table's solves; the thresholds, margins and limits.json are the same)")
    _add_inputs(t)
    t.set_defaults(func=run_table)

    s = fs.add_parser("study", parents=[common], help="deflection vs width plots, side view, sensitivity",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    s.add_argument("--out", default="results/fem-study", help="output directory (default results/fem-study)")
    s.add_argument("--band", dest="band_samples", type=int, nargs="?", const=20, default=0, metavar="N",
                   help="also the thresholds' uncertainty band (N Latin-hypercube samples, default 20) and its plot "
                        "threshold_band.png")
    s.add_argument("--sensitivity-dynamic", action="store_true",
                   help="the sensitivity grid by the table's criterion too (static tip + each grid point's own "
                        "launch allowance; its transients run side by side, cached: tens of minutes cold); "
                        "default: the grid by the static tip, labelled so in the JSON")
    _add_inputs(s)
    s.set_defaults(func=run_study)

    c = fs.add_parser("calibrate", parents=[common], help="fit the test-platform bolt to the thesis's measurement",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _add_inputs(c)
    c.set_defaults(func=run_calibrate)

    e = fs.add_parser("bench-example", parents=[common],
                      help="the coupling bench test (docs/measure-coupling.md) run on the model: a SYNTHETIC "
                           "--measured file",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    e.add_argument("--out", required=True, metavar="JSON",
                   help="the --measured file to write (labelled synthetic in its note)")
    e.add_argument("--masses-kg", default=None, metavar="M1,M2,...",
                   help="hung masses of the loading sequence (default 0,0.5,1,1.5,2,3)")
    _add_inputs(e)
    e.set_defaults(func=run_bench_example)

    o = fs.add_parser("solve", parents=[common], help="solve one configuration",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    o.add_argument("--structure", choices=("line", "two_line", "arch"), default="line")
    o.add_argument("--arrangement", choices=("aligned", "staggered"), default="staggered")
    o.add_argument("--lines", type=int, default=4, help="arch lines side by side (<= 8)")
    o.add_argument("--layers", type=int, default=2, help="arch layers (<= 4)")
    o.add_argument("--rows", type=int, required=True, help="rows in the structure")
    o.add_argument("--over", type=float, required=True, help="rows past the near edge")
    o.add_argument("--void", type=float, required=True, help="void width (robot widths)")
    o.add_argument("--phase", choices=("cantilever", "bridged"), default="cantilever")
    o.add_argument("--taper-block-rows", type=int, default=None, metavar="B",
                   help="the thesis's tapering arch (lines = 2 x layers, aligned), feet in blocks of B rows: "
                        "--rows counts the core from its rear to its front, >= layers x B on the initial ground")
    o.add_argument("--plot", default=None, metavar="PNG", help="write a side view")
    _add_inputs(o)
    o.set_defaults(func=run_solve)

    q = fs.add_parser("piers", parents=[common], help="solve one configuration over piers of failed robots",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    q.add_argument("--void-width", type=float, required=True, metavar="W", help="void width (robot widths)")
    q.add_argument("--piers", dest="pier_positions", required=True, metavar="X[,X2]",
                   help="near face of each pier, robot widths from the near edge (each pier 1 robot wide)")
    q.add_argument("--pier-robots", type=int, default=1, metavar="K",
                   help="robots stacked in each pier with the top-down coupling (default 1)")
    q.add_argument("--rows", type=int, default=None,
                   help="rows in the structure (default: the fewest that stand, at least one on the near ledge)")
    q.add_argument("--over", type=float, default=None,
                   help="rows past the near edge (default: the void width, the front at the far edge)")
    q.add_argument("--structure", choices=("line", "two_line", "arch"), default="line")
    q.add_argument("--arrangement", choices=("aligned", "staggered"), default="staggered")
    q.add_argument("--lines", type=int, default=4, help="arch lines side by side (<= 8)")
    q.add_argument("--layers", type=int, default=2, help="arch layers (<= 4)")
    q.add_argument("--plot", default=None, metavar="PNG", help="write a side view with the piers")
    q.set_defaults(taper_block_rows=None)
    _add_inputs(q)
    q.set_defaults(func=run_piers)

    d = fs.add_parser("design", parents=[common], help="connector stiffness, play or mass that makes a structure span W",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    d.add_argument("--void-width", type=int, required=True, metavar="W", help="void width in robot widths")
    d.add_argument("--structure", required=True,
                   help="structure name as in the table: line, two_line-staggered, arch-4x2-staggered, ...")
    d.add_argument("--vary", default="stiffness,play,mass", help="comma list of stiffness, play, mass (default all)")
    _add_inputs(d)
    d.set_defaults(func=run_design)

    k = fs.add_parser("connectors", parents=[common], help="FE of the record's along-the-line coupling (cached)",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _add_inputs(k)
    k.set_defaults(func=run_connectors)

    b = fs.add_parser("bench", parents=[common], help="time one 15-robot solve and the whole table",
                      epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    b.add_argument("--out", default="results/fem-bench", help="scratch output directory")
    b.add_argument("--cold-fe", action="store_true",
                   help="also compute every packaged connector FE from nothing (private cache, about 3 min "
                        "on 2 cores) and report its wall time against the 5 min goal")
    b.add_argument("--fe-workers", type=int, default=2, help="processes for --cold-fe (default 2)")
    b.set_defaults(func=run_bench)


def pipeline_stage(out: Path, ctx: dict) -> str:
    """Derived table + plots from the cad stage's robot_properties.json (or the packaged one)."""
    try:
        import exudyn  # noqa: F401
    except ImportError as exc:
        from voidcross.pipeline import StageUnavailable

        raise StageUnavailable(f"exudyn is not installed ({exc}); swarm_sim uses the packaged derived limits") from exc
    from structure_fem.outputs.runs import RunOptions
    from structure_fem.outputs.runs import run_table as _run

    props = ctx.get("robot_properties")
    res = _run(out_dir(out), RunOptions(properties=str(props) if props else None), alternative=False)
    _warn(res)
    if "limits" in res["files"]:
        ctx["limits"] = res["files"]["limits"]
    ctx["fem_dir"] = str(out)
    th = res["thresholds"]
    v = res["thesis_tapering_arches"]["verdict"]
    return (f"derived thresholds line {th['line']}, two_line {th['two_line']}, arch {th['arch']} "
            f"{th['arch_levels']} (thesis 5/10/15 [20, 25, 30]); widest void {res['max_span_widths']}; "
            f"thesis tapering arches hold at {len(v['widths_passing'])} of {v['widths_evaluated']} band widths"
            + ("" if "limits" in res["files"] else "; no structure crosses a 1-wide void: no limits.json")
            + (f"; {len(res['not_converged'])} solves did not converge (see warnings)"
               if res.get("not_converged") else ""))
