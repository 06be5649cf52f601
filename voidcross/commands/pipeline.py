"""`voidcross pipeline`: every stage in order on the embedded defaults (what `make demo` runs)."""

from __future__ import annotations

import argparse

from ..output import emit, out_dir
from ..pipeline import STAGES, run_pipeline


def run(args: argparse.Namespace) -> int:

    from voidcross.output import parse_choices

    only = None
    if args.stages is not None:
        only = parse_choices(args.stages, "--stages", [s[0] for s in STAGES], all_word=None)
    out = out_dir(args.out, "--out", create=False)
    echo = (lambda s: None) if args.json else print
    results = run_pipeline(out, debug=args.debug, echo=echo, only=only)
    payload = {"out": str(out), "stages": [r.__dict__ for r in results]}
    failed = [r for r in results if r.status == "failed"]
    report = next((r for r in results if r.name == "report" and r.status == "ok"), None)
    human = f"pipeline finished: outputs under {out}/" + (f"; report: {report.summary}" if report else "")
    emit(args, payload, human)
    return 1 if failed else 0


def register(sub, common) -> None:
    p = sub.add_parser(
        "pipeline", parents=[common], help="run CAD -> FEM -> simulations -> report end to end",
        description="Run every stage in order on the embedded defaults, one progress line per stage. "
                    "A stage whose package or optional dependency is missing says so and the others "
                    "run on packaged defaults.",
        epilog="examples:\n  voidcross pipeline\n  voidcross pipeline --out /tmp/vc --stages fem,sim\n"
               "  voidcross pipeline --json",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="results/pipeline", help="output directory (default: results/pipeline)")
    p.add_argument("--stages", default=None, help="comma-separated subset of: cad,fem,sim,thesis,report")
    p.set_defaults(func=run)
