"""`voidcross sweep`: resumable Monte-Carlo sweeps into SQLite, on local processes or Dask.

Every run is stored in its own transaction as soon as it completes, keyed by
(preset, parameter hash, seed): kill the sweep at any moment and re-run the
same command with ``--resume`` to complete it. See docs/experiments.md.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import BrokenExecutor
from pathlib import Path

from ..output import (
    MAX_ROBOTS,
    MAX_RUNS,
    MAX_SIM_TIME_S,
    MAX_WORKERS,
    check_float,
    check_int,
    check_seed,
    emit,
    out_file,
    parse_set,
    progress,
)

#: runs handed to a worker per task (the executors' own bound)
MAX_BATCH = 10_000
#: sweep bench: timed runs per configuration and interleaved rounds
MAX_BENCH_RUNS = 10_000
MAX_BENCH_REPEAT = 100

EPILOG = """examples:
  voidcross sweep --preset case-d --robots 3-18,20,25,30,40,50 --void-width 1-5 --runs 30 \\
                  --db results/case-d.sqlite
  voidcross sweep ... --db results/case-d.sqlite --resume        complete an interrupted sweep
  voidcross sweep ... --dry-run                                  how many runs, roughly how long
  voidcross sweep ... --limits thesis                            the thesis's 5/10/15 limits
  voidcross sweep ... --executor dask --address tcp://10.0.0.5:8786
  voidcross sweep export --db results/case-d.sqlite --to runs.csv
  voidcross sweep status --db results/case-d.sqlite
  voidcross sweep bench --runs 8 --json

On an existing --db the same sweep (same preset, ranges, runs, seeds, limits) is
refused unless --resume is given; a different sweep is added beside it, and runs
already stored under the same (preset, parameter hash, seed) are never repeated.
A run that raises is stored with its traceback (status 'error'); --retry-errors
re-runs those on --resume.
"""

DEFAULT_DB = "results/sweep.sqlite"


def build_spec(args):
    from swarm_sim.errors import InputError
    from swarm_sim.sweeps import SweepSpec, parse_int_range

    for opt in ("preset", "robots", "void_width"):
        if getattr(args, opt) is None:
            raise InputError(f"--{opt.replace('_', '-')} is required to run a sweep (see voidcross sweep --help)")
    check_run_options(args)
    robots = parse_int_range(args.robots, "--robots")
    widths = parse_int_range(args.void_width, "--void-width")
    if robots[-1] > MAX_ROBOTS:
        raise InputError(f"--robots {args.robots}: {robots[-1]} must be <= {MAX_ROBOTS:,} (robots in the swarm)")
    if args.db is not None:  # a database path that cannot be a file is refused before any run
        out_file(args.db, "--db")
    overrides = parse_set(args.set)
    faults = fault_specs(getattr(args, "faults", None))
    if faults is None:
        return SweepSpec(args.preset, robots, widths, runs=args.runs, limits=args.limits, seed0=args.seed,
                         max_time_s=args.max_time_s, overrides=overrides)
    if "faults" in overrides:
        raise InputError("give the faults either with --faults or with --set faults=..., not both")
    return [SweepSpec(args.preset, robots, widths, runs=args.runs, limits=args.limits, seed0=args.seed,
                      max_time_s=args.max_time_s, overrides={**overrides, **({"faults": f} if f else {})})
            for f in faults]


def fault_specs(text: str | None) -> list[str] | None:
    """``--faults "none;drive:0.5/h;drive:1/h"`` -> one canonical spec per sweep (a failure-rate
    curve: the same seeds at each rate); None without ``--faults``."""
    if text is None:
        return None
    from swarm_sim.errors import InputError
    from swarm_sim.faults import parse_faults

    out = []
    for item in text.split(";"):
        spec = parse_faults(item.strip())
        canon = "" if spec.empty else spec.describe()
        if canon in out:
            raise InputError(f"--faults {text!r}: {item.strip() or 'none'!r} is given twice")
        out.append(canon)
    return out


def check_run_options(args) -> None:
    """Bounds, in user terms, of the options every sweep-running command shares (before any work)."""
    check_int(args.runs, "--runs", 1, MAX_RUNS, "seeded runs per point")
    check_seed(args.seed, "--seed", args.runs or 1)
    check_int(args.workers, "--workers", 1, MAX_WORKERS, "worker processes")
    check_int(getattr(args, "batch", None), "--batch", 1, MAX_BATCH, "runs per worker task")
    check_float(getattr(args, "max_time_s", None), "--max-time-s", 0.0, MAX_SIM_TIME_S, what="simulated seconds")


def execute_plan(plan, executor, workers, address, desc: str, batch: int | None = None):
    """Run a prepared plan with a progress bar; returns the summary (interrupted=True on Ctrl-C).
    ``batch``: runs per worker task (default :data:`swarm_sim.sweeps.executors.DEFAULT_BATCH`)."""
    from swarm_sim.sweeps.executors import DEFAULT_BATCH, make_executor

    t0 = time.perf_counter()
    try:
        if plan.todo:
            with make_executor(executor, workers=workers, address=address, batch=batch or DEFAULT_BATCH) as ex:
                for _ in progress(plan.execute(ex), desc=desc, total=len(plan.todo)):
                    pass
    except KeyboardInterrupt:
        plan.summary.interrupted = True
    except BrokenExecutor as exc:  # a worker process died (killed, out of memory): not the run's fault
        s = plan.summary
        raise RuntimeError(f"a worker process died ({exc}); {s.already_stored + s.ok + s.errors}/{s.planned} "
                           "runs are safely stored: re-run the same command with --resume") from None
    finally:
        plan.summary.wall_s = time.perf_counter() - t0
        plan.close()
    return plan.summary


def run(args: argparse.Namespace) -> int:
    from swarm_sim.sweeps import prepare_sweep

    if getattr(args, "engine", None) is not None:
        import os

        from swarm_sim.runner import ENGINE_ENV, resolve_engine

        # the workers (local processes, a local Dask cluster) inherit it; same results either way
        os.environ[ENGINE_ENV] = resolve_engine(args.engine)
    spec = build_spec(args)
    if isinstance(spec, list):  # --faults A;B;...: one sweep per fault spec, run one after another
        return _run_fault_curve(args, spec)
    if args.dry_run:
        import os

        from swarm_sim.sweeps.sweep import dry_run

        workers = args.workers or os.cpu_count() or 1
        d = dry_run(spec, args.db, run_fn=args.run_fn, workers=workers)
        est = d["estimate_wall_s"]
        cal = d["calibration"]
        human = (f"dry run (nothing written): {d['planned']} runs planned ({d['points']} points x "
                 f"{d['runs_per_point']} runs), {d['already_stored']} already in {args.db}, {d['to_run']} to run")
        if cal:
            human += (f"\none run at robots={cal['robots']}, void width {cal['void_width']} took {cal['wall_s']:.2f} s: "
                      f"roughly {est / 60:.1f} min on {workers} worker(s) (runs of larger swarms take longer)")
        emit(args, d, human)
        return 0
    plan = prepare_sweep(spec, args.db, resume=args.resume, retry_errors=args.retry_errors,
                         run_fn=args.run_fn)
    s = execute_plan(plan, args.executor, args.workers, args.address, batch=args.batch,
                     desc=f"sweep {spec.preset} ({plan.summary.already_stored} stored)")
    stored = s.already_stored + s.ok + s.errors
    human = (f"sweep {s.sweep_id} -> {s.db}: {stored}/{s.planned} runs stored "
             f"(this time {s.ran} in {s.wall_s:.1f} s on {s.executor or 'nothing'}"
             f"{f' x{s.workers}' if s.workers else ''}: {s.ok} ok, {s.successes} crossed, {s.errors} raised)")
    if s.errors:
        human += "; runs that raised keep their traceback (voidcross sweep status --db ...)"
    if s.interrupted:
        print(f"error: interrupted: {stored}/{s.planned} runs are safely stored; re-run the same command "
              "with --resume to complete the sweep", file=sys.stderr)
        emit(args, s.to_dict(), human)
        return 130
    emit(args, s.to_dict(), human)
    return 0


def _run_fault_curve(args: argparse.Namespace, specs: list) -> int:
    from swarm_sim.sweeps import prepare_sweep

    if args.dry_run:
        planned = sum(s.runs * len(s.point_list()) for s in specs)
        emit(args, {"sweeps": len(specs), "planned": planned},
             f"dry run (nothing written): {len(specs)} sweeps (one per fault spec) x "
             f"{specs[0].runs * len(specs[0].point_list())} runs = {planned} runs planned")
        return 0
    done, lines = [], []
    for spec in specs:
        label = spec.overrides.get("faults") or "none"
        plan = prepare_sweep(spec, args.db, resume=True, retry_errors=args.retry_errors, run_fn=args.run_fn)
        s = execute_plan(plan, args.executor, args.workers, args.address, batch=args.batch,
                         desc=f"sweep {spec.preset} faults {label}")
        done.append({"faults": label, **s.to_dict()})
        lines.append(f"faults {label}: {s.already_stored + s.ok + s.errors}/{s.planned} runs stored, {s.successes} "
                     f"crossed this time, {s.errors} raised ({s.wall_s:.1f} s)")
        if s.interrupted:
            print("error: interrupted: the runs that finished are stored; re-run the same command to complete",
                  file=sys.stderr)
            emit(args, {"sweeps": done}, "\n".join(lines))
            return 130
    lines.append(f"-> {args.db}; voidcross report --db {args.db} draws the failure-rate curves")
    emit(args, {"sweeps": done}, "\n".join(lines))
    return 0


def run_export(args: argparse.Namespace) -> int:
    from swarm_sim.sweeps.export import export_db

    out_file(args.to, "--to")
    res = export_db(args.db, args.to)
    emit(args, res, f"exported {res['rows']} runs from {args.db} to {res['path']}")
    return 0


def run_status(args: argparse.Namespace) -> int:
    from swarm_sim.sweeps import ResultStore

    with ResultStore.open_readonly(args.db) as store:
        counts = store.count()
        sweeps = [s.__dict__ for s in store.sweeps()]
        errors = [
            {k: r[k] for k in ("preset", "robots", "void_width", "seed", "error_type", "error")}
            for r in store.iter_runs("WHERE status='error'")
        ]
        presets = store.con.execute(
            "SELECT preset, COUNT(*), SUM(success), SUM(robots_lost) FROM runs WHERE status='ok' "
            "GROUP BY preset").fetchall()
    lines = [f"{args.db}: {counts['ok']} runs ok, {counts['error']} raised"]
    for p, n, succ, lost in presets:
        lines.append(f"  {p}: {n} runs, {succ or 0} crossed, robots lost {lost or 0}")
    for s in sweeps:
        lines.append(f"  sweep {s['sweep_id']} ({s['created_utc']}): {s['runs_planned']} planned, "
                     f"{json.dumps(s['spec'], sort_keys=True)}")
    for e in errors[:5]:
        last = (e["error"] or "").strip().splitlines()[-1:] or [""]
        lines.append(f"  raised: {e['preset']} N={e['robots']} w={e['void_width']} seed={e['seed']}: {last[0]}")
    if len(errors) > 5:
        lines.append(f"  ... and {len(errors) - 5} more (--json lists all)")
    emit(args, {"db": args.db, "counts": counts, "sweeps": sweeps, "errors": errors}, "\n".join(lines))
    return 0


def run_bench(args: argparse.Namespace) -> int:
    from swarm_sim.sweeps.bench import bench

    check_int(args.robots, "--robots", 1, MAX_ROBOTS, "robots in the swarm")
    check_int(args.void_width, "--void-width", 1, None, "robot widths")
    check_int(args.runs, "--runs", 1, MAX_BENCH_RUNS, "timed runs per configuration")
    check_int(args.repeat, "--repeat", 1, MAX_BENCH_REPEAT, "interleaved rounds")
    check_float(args.max_time_s, "--max-time-s", 0.0, MAX_SIM_TIME_S, what="simulated seconds")
    if args.run_fn == "swarm_sim.sweeps.sweep:simulate":  # the simulator's own checks, before any timing
        from swarm_sim.runner import resolve_params

        resolve_params(args.preset, args.robots, args.void_width, args.limits, args.max_time_s)
    echo = (lambda s: None) if args.json else (lambda s: print(s, file=sys.stderr))
    res = bench(args.preset, args.robots, args.void_width, runs=args.runs, limits=args.limits,
                run_fn=args.run_fn, max_time_s=args.max_time_s, dask=not args.no_dask, repeat=args.repeat,
                echo=echo)
    lines = [f"sweep throughput, {res['preset']}, {res['robots']} robots, {res['void_width']}-wide void, "
             f"{res['runs']} runs per configuration, best of {res['repeat']} interleaved round(s):"]
    for tag, c in res["configs"].items():
        lines.append(f"  {tag:8s} {c['runs_per_min']:8.1f} runs/min  ({c['wall_s_per_run']:.3f} s/run, "
                     f"executor overhead {c['overhead_ms_per_run']:.2f} ms/run, start-up {c['startup_s']:.1f} s)")
    if "dask_overhead_vs_local_2" in res:
        lines.append(f"  Dask overhead per run vs local (2 workers): {100 * res['dask_overhead_vs_local_2']:+.1f} % "
                     "of wall time per run (noisy on a shared machine)")
        lines.append(f"  Dask extra executor cost: {res['dask_extra_ms_per_run_synthetic']:+.2f} ms per run = "
                     f"{100 * res['dask_extra_overhead_fraction']:+.2f} % of a local run")
    lines.append(f"  local speed-up 2 vs 1 workers: {res['speedup_2_vs_1_local']:.2f}x")
    emit(args, res, "\n".join(lines))
    return 0


def register(sub, common) -> None:
    fmt = argparse.RawDescriptionHelpFormatter
    p = sub.add_parser("sweep", parents=[common], formatter_class=fmt, epilog=EPILOG,
                       help="resumable Monte-Carlo sweeps into SQLite (local processes or Dask)",
                       description="Run RUNS seeded simulations for every swarm size x void width, storing "
                                   "each as it completes. Actions: (none) run a sweep; export; status; bench.")
    p.add_argument("--preset", help="scenario preset, e.g. case-c, case-d, large-void")
    p.add_argument("--robots", help="swarm sizes, e.g. 3-18,20,25,30,40,50")
    p.add_argument("--void-width", dest="void_width", help="void widths in robot widths, e.g. 1-5")
    p.add_argument("--runs", type=int, default=30, help="seeded runs per point (default 30)")
    p.add_argument("--seed", type=int, default=0, help="first seed; run i uses seed+i (default 0)")
    p.add_argument("--db", default=DEFAULT_DB, help=f"results database (default {DEFAULT_DB})")
    p.add_argument("--limits", default="derived", help="derived (default), thesis, or a limits.json path")
    p.add_argument("--executor", choices=("local", "dask"), default="local")
    p.add_argument("--address", help="Dask scheduler, e.g. tcp://HOST:8786 (default: a local cluster)")
    p.add_argument("--workers", type=int, help="worker processes (default: CPU count)")
    p.add_argument("--batch", type=int, default=None,
                   help="runs handed to a worker per task (default 4: one round trip per batch; Ctrl-C "
                        "loses at most the unfinished batches)")
    p.add_argument("--engine", default=None,
                   help="compiled | reference (default: compiled when numba is installed; the same results)")
    p.add_argument("--resume", action="store_true", help="complete the sweep already in --db")
    p.add_argument("--retry-errors", action="store_true", help="with --resume: re-run runs that raised")
    p.add_argument("--dry-run", action="store_true",
                   help="print the run count and a rough wall-time estimate (one timed run); write nothing")
    p.add_argument("--max-time-s", "--max-time", dest="max_time_s", type=float,
                   help="cap on simulated seconds per run (default: the preset's guard)")
    p.add_argument("--faults", default=None, metavar="SPEC[;SPEC...]",
                   help="robots that fail (as in sim run --faults); several specs separated by ';' run one "
                        "sweep each with the same seeds, a failure-rate curve (e.g. 'none;drive:0.5/h;drive:1/h')")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="scenario override passed to the simulator (repeatable; VALUE parsed as JSON)")
    p.add_argument("--run-fn", dest="run_fn", default=None,
                   help="advanced: run function 'module:function' (default: the simulator)")
    p.set_defaults(func=run)
    actions = p.add_subparsers(dest="sweep_action", metavar="ACTION", parser_class=type(p))

    e = actions.add_parser("export", parents=[common], formatter_class=fmt,
                           help="write one row per run to CSV or Parquet",
                           epilog="examples:\n  voidcross sweep export --db results/case-d.sqlite --to runs.csv\n"
                                  "  voidcross sweep export --db results/case-d.sqlite --to runs.parquet")
    e.add_argument("--db", dest="db", required=True, help="results database")
    e.add_argument("--to", required=True, help="output file: .csv or .parquet (needs pyarrow)")
    e.set_defaults(func=run_export)

    s = actions.add_parser("status", parents=[common], formatter_class=fmt,
                           help="what a results database holds (sweeps, counts, runs that raised)",
                           epilog="examples:\n  voidcross sweep status --db results/case-d.sqlite --json")
    s.add_argument("--db", dest="db", required=True, help="results database")
    s.set_defaults(func=run_status)

    b = actions.add_parser("bench", parents=[common], formatter_class=fmt,
                           help="throughput: runs/min on 1 and 2 local workers and 2 Dask workers",
                           epilog="examples:\n  voidcross sweep bench\n  voidcross sweep bench --runs 16 --json")
    b.add_argument("--preset", dest="preset", default="case-d")
    b.add_argument("--robots", dest="robots", type=int, default=9)
    b.add_argument("--void-width", dest="void_width", type=int, default=3)
    b.add_argument("--runs", dest="runs", type=int, default=8, help="timed runs per configuration (default 8)")
    b.add_argument("--limits", dest="limits", default="derived")
    b.add_argument("--max-time-s", dest="max_time_s", type=float, default=None)
    b.add_argument("--run-fn", dest="run_fn", default="swarm_sim.sweeps.sweep:simulate")
    b.add_argument("--repeat", dest="repeat", type=int, default=1,
                   help="interleaved rounds; each configuration reports its best (default 1)")
    b.add_argument("--no-dask", dest="no_dask", action="store_true", help="skip the Dask configuration")
    b.set_defaults(func=run_bench)


# --------------------------------------------------------------------------- pipeline

#: The pipeline's small default sweep: case D on both sides of the crossing boundary the limits
#: in use predict (N_min - 1 retreats, N_min crosses; thesis: 3w - 1 and 3w) for these void widths.
PIPELINE_WIDTHS = (1, 2)
PIPELINE_RUNS = 3
#: Cap on simulated seconds per pipeline run, so `make demo` stays bounded (timed-out runs are
#: recorded as such and shown by the report).
PIPELINE_MAX_TIME_S = 400.0
PIPELINE_RUN_FN = None  # None: the simulator (tests substitute the synthetic run function)


def pipeline_stage(out: Path, ctx: dict) -> str:
    from swarm_sim.sweeps import SweepSpec, prepare_sweep

    if PIPELINE_RUN_FN is None:
        try:
            import swarm_sim.runner  # noqa: F401
        except ImportError as exc:
            from ..pipeline import StageUnavailable

            raise StageUnavailable(f"swarm_sim.runner is not available ({exc})") from None
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    limits = str(ctx.get("limits") or "derived")
    points = pipeline_points(limits)
    spec = SweepSpec("case-d", points=points, runs=PIPELINE_RUNS, limits=limits,
                     max_time_s=PIPELINE_MAX_TIME_S)
    from swarm_sim.sweeps.sweep import limits_digest

    # one database per limits content: a re-run resumes, changed limits start a new file
    # instead of being refused (results under two different limits never mix)
    digest = limits_digest(limits)
    db = out / f"case-d-{digest[:8]}.sqlite"
    plan = prepare_sweep(spec, db, resume=True, run_fn=PIPELINE_RUN_FN, digest=digest)
    s = execute_plan(plan, "local", None, None, desc="pipeline sweep")
    if s.interrupted:
        raise KeyboardInterrupt
    ctx["db"] = str(db)
    stored = s.already_stored + s.ok + s.errors
    pts = ", ".join(f"N={n} w={w}" for n, w in points)
    return (f"{stored}/{s.planned} case-d runs ({pts}; N_min-1 and N_min of limits {limits}) in {db}: "
            f"{s.ok} new ok, {s.errors} raised")


def pipeline_points(limits: str) -> tuple[tuple[int, int], ...]:
    """(N_min - 1, w) and (N_min, w) for each pipeline width, N_min from ``limits``."""
    from structure_fem.limits import load_limits

    lim = load_limits(limits)
    pts = []
    for w in PIPELINE_WIDTHS:
        if w <= lim.max_span_widths:
            n = lim.min_robots(w)
            pts += [(n - 1, w)] if n - 1 >= 2 else []
            pts.append((n, w))
    return tuple(pts)
