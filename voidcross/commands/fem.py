"""`voidcross fem`: structure_fem: deflection studies, derived thresholds, selection table.

Placeholder until issue #4 lands: the parser exists so the CLI contract
holds; running it says honestly that the stage is not built.
"""

from __future__ import annotations

import argparse
import sys

NOT_BUILT = "`voidcross fem` is not built yet (issue #4)"


def run(args: argparse.Namespace) -> int:
    print(f"error: {NOT_BUILT}", file=sys.stderr)
    return 1


def register(sub, common) -> None:
    p = sub.add_parser("fem", parents=[common], help="structure_fem: deflection studies, derived thresholds, selection table (not built yet)")
    p.set_defaults(func=run)
