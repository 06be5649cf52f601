"""Deflection study: tip deflection of every candidate structure over void widths.

For each structure the swarm can build (single line, two lines, 4x2 / 6x3 / 8x4 arches) the
multibody model (structure_fem, exudyn) solves the longest cantilever of the launch, front at
the far edge, for void widths 1..MAX robot widths; the structure may span a void while its tip
stays within the climb clearance (15 mm for the CuBot). Prints the table and saves a plot.

    python examples/deflection_study.py [OUT_DIR] [--max-width 8] [--static]

OUT_DIR defaults to a new temporary directory; the plot is OUT_DIR/deflection_vs_width.png.
The threshold column is the table's criterion: static tip + launch-transient allowance within the
clearance. The transients the packaged table uses are shipped; others (e.g. at a --max-width
below a structure's threshold) are integrated, about 15 s on 2 cores the first time, then cached.
``--static`` judges by the tip alone (no transients: a few seconds). Needs exudyn
(pip install 'voidcross[fem]').
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
    ap.add_argument("--max-width", type=int, default=8, help="widest void, robot widths (default 8)")
    ap.add_argument("--static", action="store_true",
                    help="threshold by the static tip alone, without the launch transients (faster)")
    args = ap.parse_args(argv)
    try:
        curves = api.deflection_curves(max_width_robots=args.max_width, dynamic=not args.static)
    except (api.InputError, ModuleNotFoundError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2

    structures = list(dict.fromkeys(c["structure"] for c in curves))
    widths = sorted({c["void_width_robots"] for c in curves})
    tip = {(c["structure"], c["void_width_robots"]): c["tip_deflection_mm"] for c in curves}
    clearance = curves[0]["clearance_mm"]
    criterion = "static tip" if args.static else "static tip + launch allowance"
    print(f"tip deflection (mm) at the longest cantilever; clearance {clearance:g} mm; threshold: {criterion}")
    print(f"{'structure':22s}" + "".join(f"{f'w={w}':>8s}" for w in widths) + "  threshold (widths)")
    for s in structures:
        cells = "".join(f"{tip[(s, w)]:8.2f}" if (s, w) in tip else f"{'-':>8s}" for w in widths)
        th = next(c["threshold_widths"] for c in curves if c["structure"] == s)
        print(f"{s:22s}{cells}  {th}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="voidcross-deflection-"))
    out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for s in structures:
        pts = [(c["void_width_robots"], c["tip_deflection_mm"]) for c in curves if c["structure"] == s]
        # the aligned two lines bend exactly as one line: dashed, so the line stays visible under it
        ax.plot(*zip(*pts, strict=True), marker="o", linestyle="--" if "aligned" in s else "-", label=s)
    ax.axhline(clearance, color="k", linestyle="--", linewidth=1, label=f"clearance {clearance:g} mm")
    ax.set_xlabel("void width (robot widths)")
    ax.set_ylabel("tip deflection at the longest cantilever (mm)")
    ax.set_title("structure_fem: tip deflection per structure")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = out / "deflection_vs_width.png"
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
