"""`voidcross report`: the thesis's tables and figures regenerated from a sweep database,
beside the thesis's own values, as one static HTML page plus Markdown."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..output import MAX_ROBOTS, SEED_LIMIT, emit, out_dir

EPILOG = """examples:
  voidcross report --db results/case-d.sqlite
  voidcross report --db results/case-d.sqlite --out report/ --fem-dir exports/fem --cad-dir exports/cad
  voidcross report --db results/all.sqlite --limits results/pipeline/fem/limits.json --json
  voidcross report --db results/case-d.sqlite --watch case-d,9,3,1,thesis

Sections: structure limits (derived and thesis), a run played back interactively, per case the success matrix, mean T_a/T_d/T_t
tables, times vs swarm size (mean, 25/75 %), seed-id / target-finder-id frequencies and seed
positions; Tables 4.4-4.9 (ours / thesis); large voids (Fig. 5.9-5.13); structure_fem and CAD
outputs when their directories are given. A section without data says so.
"""


def run(args: argparse.Namespace) -> int:
    from swarm_sim.errors import InputError

    from ..report import build_report

    out_dir(args.out, "--out", create=False)  # before reading anything
    watch = parse_watch(args.watch)
    for opt, d in (("--fem-dir", args.fem_dir), ("--cad-dir", args.cad_dir)):
        if d is not None and not Path(d).is_dir():
            raise InputError(f"{opt} {d}: " + ("is a file, not a directory" if Path(d).exists()
                                               else "no such directory"))
    if args.limits is not None:  # an explicit --limits that cannot be read is bad input, not a note
        from structure_fem.limits import load_limits

        load_limits(args.limits)
    if isinstance(watch, dict):  # the simulator's own checks of the run to play back (preset, limits, sizes)
        from swarm_sim.runner import resolve_params

        try:
            resolve_params(watch["preset"], watch["robots"], watch["void_width"], watch["limits"])
        except InputError as exc:
            raise InputError(f"--watch {args.watch!r}: {exc}") from None
    res = build_report(args.db, args.out, fem_dir=args.fem_dir, cad_dir=args.cad_dir, limits=args.limits,
                       watch=watch)
    emit(args, res, f"report at {res['html']} (Markdown: {res['markdown']}; {res['figures']} figures, "
                    f"{res['runs']} runs, {res['no_data_notes']} sections without data)")
    return 0


def parse_watch(text: str | None):
    """``--watch``: ``auto`` (a crossing from the database), ``none``, or PRESET,ROBOTS,WIDTH,SEED[,LIMITS]."""
    from swarm_sim.errors import InputError

    if text is None or text == "auto":
        return "auto"
    if text == "none":
        return None
    parts = text.split(",")
    if len(parts) not in (4, 5):
        raise InputError(f"--watch {text!r}: expected auto, none or PRESET,ROBOTS,WIDTH,SEED[,LIMITS]")
    try:
        robots, width, seed = (int(v) for v in parts[1:4])
    except ValueError:
        raise InputError(f"--watch {text!r}: ROBOTS, WIDTH and SEED must be integers") from None
    if robots < 1 or width < 1 or seed < 0:
        raise InputError(f"--watch {text!r}: ROBOTS and WIDTH must be >= 1 and SEED >= 0")
    if robots > MAX_ROBOTS or seed >= SEED_LIMIT:
        raise InputError(f"--watch {text!r}: ROBOTS must be <= {MAX_ROBOTS:,} and SEED < 2**63")
    return {"preset": parts[0], "robots": robots, "void_width": width, "seed": seed,
            "limits": parts[4] if len(parts) == 5 else "derived"}


def register(sub, common) -> None:
    p = sub.add_parser("report", parents=[common], formatter_class=argparse.RawDescriptionHelpFormatter,
                       help="the thesis's tables and figures regenerated, one HTML/Markdown report",
                       description="Build report/index.html and report/report.md (figures in report/figures/) "
                                   "from a sweep database.", epilog=EPILOG)
    p.add_argument("--db", required=True, help="results database written by `voidcross sweep`")
    p.add_argument("--out", default="report", help="output directory (default: report/)")
    p.add_argument("--fem-dir", dest="fem_dir", help="structure_fem output directory (.md tables, .png plots)")
    p.add_argument("--cad-dir", dest="cad_dir", help="cubot_cad output directory (.png renders)")
    p.add_argument("--limits", default=None,
                   help="limits.json to show as the derived limits (default: the packaged derived limits)")
    p.add_argument("--watch", default="auto", metavar="RUN",
                   help="the run played back in the page: auto (a crossing from the database, the default), "
                        "none, or PRESET,ROBOTS,WIDTH,SEED[,LIMITS]")
    p.set_defaults(func=run)


def pipeline_stage(out: Path, ctx: dict) -> str:
    from ..report import build_report

    db = ctx.get("db")
    if not db:
        from ..pipeline import StageUnavailable

        raise StageUnavailable("no results database from the sim stage (ctx['db'] is unset)")
    res = build_report(db, out, fem_dir=ctx.get("fem_dir"), cad_dir=ctx.get("cad_dir"),
                       limits=ctx.get("limits"))
    ctx["report"] = res["html"]
    return f"report at {res['html']}"
