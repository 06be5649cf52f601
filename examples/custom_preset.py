"""A custom scenario: write a preset TOML, then simulate it at and below the rule's minimum swarm.

The preset is a smaller arena (300 x 200 cm) than the thesis's, with the target nearer; every
key not given keeps the simulator's default (swarm_sim/presets/case-d.toml lists them all).
The limits record says how many robots the 2-wide void needs; the run with that many crosses,
one fewer retreats with every robot safe.

    python examples/custom_preset.py [OUT_DIR] [--limits derived|thesis|PATH] [--seed 1]

OUT_DIR defaults to a new temporary directory; it receives small-arena.toml and runs.json.
A few seconds.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

from voidcross import api

PRESET = """\
# A small arena: case D (random starts) with a 2-wide void and the target 20 cm from the far wall.
[scenario]
case = "D"
start = "random"
robots = 7
void_width = 2             # robot widths

[arena]
width_cm = 300.0
height_cm = 200.0

[target]
x_cm = 280.0
y_cm = 100.0

[sim]
max_time_s = 5000.0        # a guard: these runs end well before it
"""


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", metavar="OUT_DIR", help="output directory (default: a new temporary directory)")
    ap.add_argument("--limits", default="derived", help="derived (default), thesis or a limits.json path")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="voidcross-preset-"))
    out.mkdir(parents=True, exist_ok=True)
    preset = out / "small-arena.toml"
    preset.write_text(PRESET)
    print(f"wrote {preset}")

    try:
        width = 2
        n_min = api.limits(args.limits).min_robots(width)
        results = []
        for n in (n_min, n_min - 1):
            res = api.simulate(preset, robots=n, void_width_robots=width, limits=args.limits, seed=args.seed)
            t = res.times
            print(f"{res.preset} N={n} (rule minimum {res.min_robots_rule}) void={width} widths seed={args.seed}: "
                  f"{res.end_reason}; delivered {res.robots_delivered}, lost {res.robots_lost}, "
                  f"Ta {t['Ta']} s, Tt {t['Tt']} s simulated ({res.wall_s:.1f} s wall)")
            results.append(res.to_dict())
    except api.InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    path = out / "runs.json"
    path.write_text(json.dumps(results, indent=2))
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
