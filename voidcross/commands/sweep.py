"""`voidcross sweep`: Monte-Carlo sweeps into SQLite (local or Dask).

Placeholder until issue #7 lands: the parser exists so the CLI contract
holds; running it says honestly that the stage is not built.
"""

from __future__ import annotations

import argparse
import sys

NOT_BUILT = "`voidcross sweep` is not built yet (issue #7)"


def run(args: argparse.Namespace) -> int:
    print(f"error: {NOT_BUILT}", file=sys.stderr)
    return 1


def register(sub, common) -> None:
    p = sub.add_parser("sweep", parents=[common], help="Monte-Carlo sweeps into SQLite (local or Dask) (not built yet)")
    p.set_defaults(func=run)
