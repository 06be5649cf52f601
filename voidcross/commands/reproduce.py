"""`voidcross reproduce`: every experiment of the thesis at its own run counts, resumable into
one SQLite file, then the report with ours beside the thesis's.

The experiments are data (:data:`EXPERIMENTS`): Ch. 4.7's four cases (A: N in {5, 7, 8, 10};
B: N in {3, 6, ..., 18}; C: N 3..18; D: N 3..18, 20, 25, 30, 40, 50; voids of 1..5 robot
widths; 5, 5, 30 and 30 runs per cell), Ch. 5.6's large void (70 robots, 6..10 widths,
10 runs) and Ch. 5.5.2's tapering arches beyond 10 widths (:data:`TAPERING`: the widest void
of each level, 11..30 widths, each with the swarm the counting rule needs there, one run per
width; minutes per run). ``--runs K`` shrinks every cell to K runs for a quick look. Each experiment is one
sweep in the database, so an interrupted reproduction resumes where it stopped.

Default limits: the thesis's (``--limits thesis``), since this reproduces its experiments;
``--limits derived`` runs the same grid under our mechanics.
"""

from __future__ import annotations

import argparse
import sys
import time

from swarm_sim.experiments.thesis_grid import (  # noqa: F401 (the grid and boundary have one home)
    EXPERIMENTS,
    TAPERING,
    observed_boundary,
    rule_swarm,
    thesis_boundary,
)

from ..output import MAX_RUNS, MAX_WORKERS, check_int, check_seed, emit, out_dir

EPILOG = """examples:
  voidcross reproduce --chapter 4 --runs 2 --out results/reproduce      a quick look (~470 runs)
  voidcross reproduce --chapter all --workers 2 --out results/reproduce the thesis's run counts (~5,850 runs)
  voidcross reproduce --chapter 4 --cases A,B --json
  voidcross reproduce --chapter 5 --cases taper-15,taper-30 the tapering arches, 11..30 widths (slow)
  voidcross reproduce --chapter 4 --limits derived --out results/reproduce-derived
Re-running the same command resumes: runs already stored are not repeated. The report
(OUT/report/index.html) has Tables 4.4-4.9 with ours beside the thesis's; --json prints,
per case, the observed crossing boundary against the thesis's (3w + 2 for A, 3w for B-D).
"""

def _selected(chapter: str, cases: str | None) -> list[tuple]:
    from swarm_sim.errors import InputError

    if chapter not in ("4", "5", "all"):
        raise InputError(f"--chapter {chapter!r}: one of 4, 5, all")
    exps = [e for e in EXPERIMENTS if chapter == "all" or str(e[0]) == chapter]
    if cases is not None:
        from voidcross.output import parse_choices

        want = set(parse_choices(cases, "--cases", sorted({e[1] for e in exps}), all_word=None))
        exps = [e for e in exps if e[1] in want]
    return exps


def run(args: argparse.Namespace) -> int:
    from swarm_sim.sweeps import SweepSpec, prepare_sweep

    from .sweep import execute_plan

    check_int(args.runs, "--runs", 1, MAX_RUNS, "runs per cell")
    check_int(args.workers, "--workers", 1, MAX_WORKERS, "worker processes")
    exps = _selected(args.chapter, args.cases)
    check_seed(args.seed, "--seed", max(args.runs or runs for *_, runs in exps))
    out_dir(args.out, "--out", create=False)  # checked, created only once every input is known good
    # the tapering rows: one sweep per width at the rule's swarm for these limits; a width no
    # structure of these limits can span (e.g. 20-30 widths with the derived record) is skipped
    # and said so, never run as a retreat nobody asked for
    from swarm_sim.errors import InputError

    expanded, skipped = [], []
    for ch, case, preset, robots, widths, runs in exps:
        if robots != "rule":
            expanded.append((ch, case, preset, robots, widths, runs))
            continue
        for w in widths:
            try:
                expanded.append((ch, case, preset, (rule_swarm(preset, w, args.limits),), (w,), runs))
            except InputError as e:
                skipped.append({"case": case, "void_width": w, "why": str(e)})
    if not expanded:
        raise InputError(f"--limits {args.limits}: no selected experiment can run with these limits "
                         f"({'; '.join(s['why'] for s in skipped)})")
    exps = expanded
    specs = [SweepSpec(preset, tuple(robots), tuple(widths), runs=args.runs or runs, limits=args.limits,
                       seed0=args.seed) for _, _, preset, robots, widths, runs in exps]
    from swarm_sim.sweeps.executors import resolve_run_fn
    from swarm_sim.sweeps.sweep import limits_digest, preflight

    if args.run_fn is None:  # the simulator's own checks of every point (limits, presets, sizes)
        for spec in specs:
            preflight(spec)
    else:
        resolve_run_fn(args.run_fn)
        limits_digest(args.limits)
    out = out_dir(args.out, "--out")
    db = out / "reproduce.sqlite"
    t0 = time.perf_counter()
    interrupted = False
    for (chapter, case, *_), spec in zip(exps, specs, strict=True):
        plan = prepare_sweep(spec, db, resume=True, run_fn=args.run_fn)
        s = execute_plan(plan, "local", args.workers, None,
                         desc=f"Ch. {chapter} case {case} ({plan.summary.already_stored} stored)")
        if s.interrupted:
            interrupted = True
            break
    wall = time.perf_counter() - t0
    cases = boundaries(db, exps, args.limits)
    report = None
    if not interrupted and not args.no_report:
        from ..report.build import build_report

        report = build_report(db, out / "report", limits=args.limits)
    payload = {"chapter": args.chapter, "limits": args.limits, "db": str(db), "wall_s": round(wall, 1),
               "interrupted": interrupted, "cases": cases, "skipped": skipped, "report": report}
    lines = [f"reproduce chapter {args.chapter} ({args.limits} limits) -> {db} in {wall:.0f} s"]
    for case, c in cases.items():
        parts = []
        for w, b in c["by_width"].items():
            th = f" (thesis {b['thesis']})" if b["thesis"] is not None else ""
            obs = b["observed"] if b["observed"] is not None else "none"
            parts.append(f"w={w}: {obs}{th}{'' if b['below_all_retreat'] or b['observed'] is None else ' *'}")
        lines.append(f"  case {case}: {c['runs']} runs; smallest swarm that always crossed: " + ", ".join(parts))
    for sk in skipped:
        lines.append(f"  skipped {sk['case']} at {sk['void_width']} widths: {sk['why']}")
    if report:
        lines.append(f"  report: {report['html']}")
    if interrupted:
        print("error: interrupted: the finished runs are stored; re-run the same command to resume",
              file=sys.stderr)
        emit(args, payload, "\n".join(lines))
        return 130
    emit(args, payload, "\n".join(lines))
    return 0


def boundaries(db, exps, limits: str) -> dict:
    """Per case and width, from the database (this and earlier invocations): the smallest swarm
    of the grid that crossed in every run, against the thesis's (:func:`thesis_boundary`)."""
    from swarm_sim.sweeps import ResultStore

    cases: dict = {}
    with ResultStore.open_readonly(db) as store:
        for chapter, case, preset, robots, widths, _runs in exps:
            cells: dict = {}
            for r in store.iter_runs("WHERE status='ok' AND preset=?", (preset,)):
                if r["limits"] != limits:
                    continue
                cells.setdefault((int(r["robots"]), int(r["void_width"])), []).append(bool(r["success"]))
            c = cases.setdefault(case, {"preset": preset, "chapter": chapter, "cells": 0, "runs": 0, "by_width": {}})
            c["cells"] += len(robots) * len(widths)
            c["runs"] += sum(len(v) for k, v in cells.items() if k[0] in robots and k[1] in widths)
            for w in widths:
                b = observed_boundary({k: v for k, v in cells.items() if k[0] in robots and k[1] == w}, w)
                b["thesis"] = thesis_boundary(case, w, preset)
                b["matches"] = b["thesis"] is not None and b["observed"] == b["thesis"] and b["below_all_retreat"]
                c["by_width"][str(w)] = b
    return cases


#: ``make demo``'s reproduction (the pipeline's ``thesis`` stage): Chapter 4 at this many runs
#: per cell with the thesis's limits, so the demo report fills Tables 4.4-4.9
PIPELINE_RUNS = 1
PIPELINE_RUN_FN = None  # None: the simulator (tests substitute the synthetic run function)


def pipeline_stage(out, ctx: dict) -> str:
    """Chapter 4's four cases, :data:`PIPELINE_RUNS` run(s) per cell, thesis limits, into the
    pipeline's database (``ctx["db"]``, else ``out/reproduce.sqlite``); resumes like the command."""
    from pathlib import Path

    from swarm_sim.sweeps import SweepSpec, prepare_sweep

    from .sweep import execute_plan

    exps = _selected("4", None)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    db = Path(ctx.get("db") or out / "reproduce.sqlite")
    t0 = time.perf_counter()
    for chapter, case, preset, robots, widths, _runs in exps:
        spec = SweepSpec(preset, tuple(robots), tuple(widths), runs=PIPELINE_RUNS, limits="thesis")
        plan = prepare_sweep(spec, db, resume=True, run_fn=PIPELINE_RUN_FN)
        s = execute_plan(plan, "local", None, None, desc=f"Ch. {chapter} case {case}")
        if s.interrupted:
            raise KeyboardInterrupt
    ctx["db"] = str(db)
    cases = boundaries(db, exps, "thesis")
    largest = {case: max(robots) for _ch, case, _p, robots, _w, _r in exps}
    widths = [(case, b) for case, c in cases.items() for b in c["by_width"].values() if b["thesis"] is not None]
    beyond = sum(1 for case, b in widths if b["thesis"] > largest[case])
    runs = ", ".join(f"{k} {c['runs']}" for k, c in cases.items())
    return (f"the thesis's Chapter 4 grid, {PIPELINE_RUNS} run(s) per cell, thesis limits ({runs} runs) in "
            f"{time.perf_counter() - t0:.0f} s: crossing boundary as the thesis's at "
            f"{sum(b['matches'] for _c, b in widths)}/{len(widths)} widths ({beyond} beyond the grid's largest swarm)")


def register(sub, common) -> None:
    fmt = argparse.RawDescriptionHelpFormatter
    p = sub.add_parser("reproduce", parents=[common], formatter_class=fmt, epilog=EPILOG,
                       help="every thesis experiment at its own run counts, then the report",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("--chapter", default="all", help="4 (cases A-D), 5 (large void) or all (default)")
    p.add_argument("--cases", default=None,
                   help="only these cases, e.g. A,B or large,taper-15,taper-30 (default: all of the chapter)")
    p.add_argument("--runs", type=int, default=None, help="runs per cell (default: the thesis's own counts)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: CPU count)")
    p.add_argument("--limits", default="thesis", help="thesis (default: reproduce the thesis), derived, or a path")
    p.add_argument("--seed", type=int, default=0, help="first seed; run i of a cell uses seed + i (default 0)")
    p.add_argument("--out", default="results/reproduce", help="output directory (default results/reproduce)")
    p.add_argument("--no-report", action="store_true", help="only run (and resume) the sweeps")
    p.add_argument("--run-fn", dest="run_fn", default=None,
                   help="advanced: run function 'module:function' (default: the simulator)")
    p.set_defaults(func=run)
