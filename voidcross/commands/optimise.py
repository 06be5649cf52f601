"""`voidcross optimise`: tune the bridge rules (the thesis's future work 3) with CMA-ES on the
compiled engine, every run stored in one SQLite file (resumable: re-run the same command), then
the best rules against the thesis's on held-out seeds and under faults and obstacles.

What is tuned, the objective and its penalties, the resume and the verdict are in
docs/optimise.md and :mod:`swarm_sim.optimise`.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from ..output import MAX_WORKERS, check_int, emit, out_dir, progress

DEFAULT_DB = "results/opt.sqlite"
EPILOG = f"""examples:
  voidcross optimise --cases a,b,c,d --trials 30 --db {DEFAULT_DB} --report
  voidcross optimise --cases d --trials 10 --params levy_mu,avoid_cm,stall_s --heldout-runs 0
  voidcross optimise --trials 60 --executor dask --address tcp://HOST:8786 --db {DEFAULT_DB}
Re-running the same command resumes the study (kill -9 loses only the runs in flight); more
--trials extend it. --report [DIR] writes DIR/index.html (default: beside the database).
"""


def _names(text: str, option: str) -> tuple[str, ...]:
    from swarm_sim.errors import InputError

    items = [s.strip() for s in (text or "").split(",")]
    if not any(items) or "" in items:
        raise InputError(f"{option} {text!r}: give a comma list of tunables (`voidcross sim params` lists them)")
    return tuple(items)


def _widths(text: str) -> tuple[int, ...]:
    from swarm_sim.errors import InputError

    try:
        ws = tuple(int(s) for s in text.split(","))
    except ValueError:
        raise InputError(f"--train-widths {text!r}: a comma list of void widths (robot widths), e.g. 2,4") from None
    if not ws or any(w < 1 for w in ws):
        raise InputError(f"--train-widths {text!r}: widths must be >= 1")
    return ws


def run(args: argparse.Namespace) -> int:
    from swarm_sim.optimise import SearchSpace, StudyConfig, compare, robustness, run_study
    from swarm_sim.sweeps.store import check_db
    from swarm_sim.tunables import BY_NAME

    check_int(args.workers, "--workers", 1, MAX_WORKERS, "worker processes")
    check_int(args.heldout_runs, "--heldout-runs", 0, 1000, "held-out runs per cell; 0: none")
    cfg = StudyConfig(cases=args.cases, space=SearchSpace(_names(args.params, "--params")), trials=args.trials,
                      train_seeds=args.train_seeds, train_widths=_widths(args.train_widths), limits=args.limits,
                      seed=args.seed, sigma0=args.sigma, population=args.population)
    cfg.cells()  # the limits and every cell checked before anything is written
    check_db(args.db)  # a corrupt or foreign file: one error line, the file untouched
    report_dir = None
    if args.report is not None:
        report_dir = Path(args.report or Path(args.db).with_suffix("").as_posix() + "-report")
        out_dir(report_dir, "--report", create=False)
    Path(args.db).parent.mkdir(parents=True, exist_ok=True)
    if args.engine is not None:
        import os

        from swarm_sim.runner import ENGINE_ENV, resolve_engine

        os.environ[ENGINE_ENV] = resolve_engine(args.engine)
    ex = {"executor": args.executor, "workers": args.workers, "address": args.address, "run_fn": args.run_fn}
    bar = (lambda it, desc, total: progress(it, desc=desc, total=total)) if not args.quiet else None
    t0 = time.perf_counter()

    def said(t, best):
        if not args.quiet and not args.json:
            print(f"trial {t.number:>3}: {t.score.value:8.1f} s (best {best:.1f} s)"
                  + ("  thesis's rules" if t.number == 0 else ""), file=sys.stderr, flush=True)

    study = run_study(cfg, args.db, progress=bar, on_trial=said, **ex)
    sd = study.to_dict()
    held = robust = None
    if args.heldout_runs:
        held = compare(study.best.params, cfg, args.db, runs=args.heldout_runs, progress=bar, **ex).to_dict()
        if not args.no_robustness:
            robust = robustness(study.best.params, cfg, args.db, runs=args.heldout_runs, progress=bar, **ex)
    report = None
    if report_dir is not None:
        from ..report.optimise import build

        report = build(sd, held, robust, out_dir(report_dir, "--report"), BY_NAME)
    wall = time.perf_counter() - t0
    payload = {"study": sd, "heldout": held, "robustness": robust, "report": report, "wall_s": round(wall, 1)}
    b = study.best
    lines = [f"optimise {sd['study_id']} -> {args.db}: {len(study.trials)} trials, {study.new_runs} new runs, "
             f"{wall:.0f} s",
             f"  thesis's rules: {study.baseline.score.value:.1f} s; best trial {b.number}: {b.score.value:.1f} s",
             "  best: " + (", ".join(f"{k}={v:g}" for k, v in b.params.items()) or "the thesis's rules")]
    if held:
        lines.append(f"  held-out ({held['runs_per_cell']} runs per cell, seeds from {held['seed0']}): pooled "
                     f"median Tt gain {held['pooled_gain_pct']:.1f} %, "
                     + ("accepted" if held["accepted"] else "REJECTED: " + "; ".join(held["reasons"])))
        for case in held["thesis"]:
            g = held["gain_pct"].get(case)
            lines.append(f"    case {case}: Tt median {held['thesis'][case]['Tt_median_s']:.1f} -> "
                         f"{held['tuned'][case]['Tt_median_s']:.1f} s"
                         + (f" ({g:+.1f} %)" if g is not None else ""))
    if report:
        lines.append(f"  report: {report['html']}")
    emit(args, payload, "\n".join(lines))
    return 0


def register(sub, common) -> None:
    from swarm_sim.optimise import DEFAULT_PARAMS

    p = sub.add_parser("optimise", parents=[common], formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog=EPILOG, help="tune the bridge rules with CMA-ES, then held-out and robustness checks",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", default="a,b,c,d", help="Chapter 4's cases to train and test on (default a,b,c,d)")
    p.add_argument("--params", default=",".join(DEFAULT_PARAMS),
                   help="tunables to tune, comma list (default: %(default)s; `voidcross sim params` lists them)")
    p.add_argument("--trials", type=int, default=30, help="trials (default 30; trial 0, the thesis's rules, extra)")
    p.add_argument("--train-seeds", dest="train_seeds", type=int, default=6,
                   help="runs per training cell, the same seeds for every trial (default 6: 3 overfit, "
                        "docs/optimise.md)")
    p.add_argument("--train-widths", dest="train_widths", default="2,4",
                   help="void widths of the training cells (default 2,4)")
    p.add_argument("--limits", default="thesis", help="thesis (default, the thesis's boundaries), derived or a path")
    p.add_argument("--seed", type=int, default=0, help="the optimiser's seed and first training seed (default 0)")
    p.add_argument("--sigma", type=float, default=0.25, help="CMA-ES's initial step in the unit cube (default 0.25)")
    p.add_argument("--population", type=int, default=None, help="CMA-ES population (default 4 + 3 ln dims)")
    p.add_argument("--db", default=DEFAULT_DB, help=f"results database (default {DEFAULT_DB}); re-run to resume")
    p.add_argument("--heldout-runs", dest="heldout_runs", type=int, default=10,
                   help="held-out runs per cell of Chapter 4's grid (default 10; 0: no held-out or robustness)")
    p.add_argument("--no-robustness", dest="no_robustness", action="store_true",
                   help="skip the faults and obstacles check")
    p.add_argument("--report", nargs="?", const="", default=None,
                   help="write the HTML report into this directory (default: beside --db)")
    p.add_argument("--executor", choices=("local", "dask", "serial"), default="local")
    p.add_argument("--address", help="Dask scheduler, e.g. tcp://HOST:8786 (default: a local cluster)")
    p.add_argument("--workers", type=int, help="worker processes (default: CPU count)")
    p.add_argument("--engine", default=None, help="compiled (default with numba) or reference")
    p.add_argument("--quiet", action="store_true", help="no progress bar or per-trial lines")
    p.add_argument("--run-fn", dest="run_fn", default=None,
                   help="advanced: run function 'module:function' (default: the simulator)")
    p.set_defaults(func=run)
