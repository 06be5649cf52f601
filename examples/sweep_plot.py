"""A small Monte-Carlo sweep into a pandas DataFrame, and the crossing rate plotted against swarm size.

Case D with the thesis's limits: a void w robot widths wide needs N = 3 w robots, so the
crossing rate should jump from 0 to 1 between 3 w - 1 and 3 w robots. The runs go to a SQLite
database in OUT_DIR (resumable: run the script again and nothing is re-run), the DataFrame to
sweep.csv, the plot to crossing_rate.png.

    python examples/sweep_plot.py [OUT_DIR] [--robots 2-6] [--void-widths 1-2] [--runs 1] [--limits thesis]

OUT_DIR defaults to a new temporary directory. About 15 s with the defaults (needs pandas).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from voidcross import api


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", metavar="OUT_DIR", help="output directory (default: a new temporary directory)")
    ap.add_argument("--robots", default="2-6", help="swarm sizes (default 2-6)")
    ap.add_argument("--void-widths", default="1-2", help="void widths, robot widths (default 1-2)")
    ap.add_argument("--runs", type=int, default=1, help="seeds per point (default 1)")
    ap.add_argument("--limits", default="thesis", help="thesis (default), derived or a limits.json path")
    args = ap.parse_args(argv)
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="voidcross-sweep-"))
    out.mkdir(parents=True, exist_ok=True)
    try:
        df = api.sweep("case-d", robots=args.robots, void_width_robots=args.void_widths, runs=args.runs,
                       limits=args.limits, db=out / "sweep.sqlite")
    except (api.InputError, ModuleNotFoundError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    s = df.attrs["summary"]
    print(f"{len(df)} runs in {df.attrs['db']} ({s['ran']} run now, {s['already_stored']} already stored)")
    rate = df.groupby(["void_width_robots", "robots"])["success"].mean().unstack(0)
    print("crossing rate (rows: robots, columns: void width in robot widths)")
    print(rate.to_string())
    print("mean simulated time to cross or retreat, Tt_s:")
    print(df.groupby(["void_width_robots", "robots"])["Tt_s"].mean().round(1).unstack(0).to_string())
    df.to_csv(out / "sweep.csv", index=False)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    lim = api.limits(args.limits)
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for w in rate.columns:
        line, = ax.plot(rate.index, rate[w], marker="o", label=f"void {w} widths")
        if w <= lim.max_span_widths:
            ax.axvline(lim.min_robots(int(w)), color=line.get_color(), linestyle=":", linewidth=1)
    ax.set_xlabel("swarm size (robots)")
    ax.set_ylabel("crossing rate")
    ax.set_ylim(-0.05, 1.05)
    ax.set_title(f"case D, {args.limits} limits (dotted: the rule's minimum swarm)")
    ax.legend()
    fig.tight_layout()
    path = out / "crossing_rate.png"
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print(f"wrote {out / 'sweep.csv'}, {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
