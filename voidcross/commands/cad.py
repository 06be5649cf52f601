"""`voidcross cad`: cubot_cad: parametric robots, printable exports, mass properties.

Placeholder until issue #3 lands: the parser exists so the CLI contract
holds; running it says honestly that the stage is not built.
"""

from __future__ import annotations

import argparse
import sys

NOT_BUILT = "`voidcross cad` is not built yet (issue #3)"


def run(args: argparse.Namespace) -> int:
    print(f"error: {NOT_BUILT}", file=sys.stderr)
    return 1


def register(sub, common) -> None:
    p = sub.add_parser("cad", parents=[common], help="cubot_cad: parametric robots, printable exports, mass properties (not built yet)")
    p.set_defaults(func=run)
