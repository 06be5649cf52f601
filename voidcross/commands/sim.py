"""`voidcross sim`: swarm_sim: run, soak and benchmark the swarm simulator.

Placeholder until issue #5 lands: the parser exists so the CLI contract
holds; running it says honestly that the stage is not built.
"""

from __future__ import annotations

import argparse
import sys

NOT_BUILT = "`voidcross sim` is not built yet (issue #5)"


def run(args: argparse.Namespace) -> int:
    print(f"error: {NOT_BUILT}", file=sys.stderr)
    return 1


def register(sub, common) -> None:
    p = sub.add_parser("sim", parents=[common], help="swarm_sim: run, soak and benchmark the swarm simulator (not built yet)")
    p.set_defaults(func=run)
