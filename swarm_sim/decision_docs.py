"""The decision tables of the docs, generated from the code's tables (one home per rule).

``python -m swarm_sim.decision_docs docs/swarm_sim.md`` rewrites every block between
``<!-- BEGIN decision-table NAME -->`` and ``<!-- END decision-table NAME -->`` with the
rows of the table ``NAME`` (:data:`TABLES`); ``--check`` only reports whether the file is up
to date (exit 1 if not). The tests run the check, so a table changed in the code without its
docs fails.
"""

from __future__ import annotations

import re
import sys

from swarm_sim.behaviour import structure as S
from swarm_sim.behaviour import taper as T

TABLES = {
    "BUILD_TABLE": S.BUILD_TABLE, "RETREAT_TABLE": S.RETREAT_TABLE,
    "TAPER_TABLE": T.TAPER_TABLE, "TAPER_RETREAT_TABLE": T.TAPER_RETREAT_TABLE,
}
_BLOCK = re.compile(r"(<!-- BEGIN decision-table (\w+) -->\n)(.*?)(<!-- END decision-table \2 -->)", re.S)


def markdown(name: str) -> str:
    """The table ``name`` as a Markdown table: row number, action, guard in words."""
    rows = ["| # | action | when (first match wins) |", "|---|---|---|"]
    rows += [f"| {k} | `{action}` | {words} |" for k, (action, _, words) in enumerate(TABLES[name], 1)]
    return "\n".join(rows) + "\n"


def render(text: str) -> str:
    """``text`` with every decision-table block regenerated."""
    def sub(m):
        if m.group(2) not in TABLES:
            raise KeyError(f"unknown decision table {m.group(2)!r} in the docs (known: {', '.join(TABLES)})")
        return m.group(1) + markdown(m.group(2)) + m.group(4)

    return _BLOCK.sub(sub, text)


def main(argv: list[str] | None = None) -> int:
    from structure_fem.outputs.docs_blocks import rewrite

    return rewrite(argv, render, "docs/swarm_sim.md", "python -m swarm_sim.decision_docs")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
