"""Ours beside the thesis's, cell by cell: Tables 4.4-4.9 with the deviation.

For every cell of a thesis table (a swarm size N and a void width, a mean time in
simulated seconds) this module takes our runs of the same preset, size and width and
reports our mean, our run-to-run spread (the sample standard deviation, ``n >= 2``),
the thesis's mean, the ratio ours / thesis and whether the difference is *inside our
spread*: ``|ours - thesis| <= sd``, i.e. the thesis's mean lies within one standard
deviation of ours. With one run the spread is unknown (``inside`` is None), and a cell
the thesis leaves empty ('-') or we have no value for is not compared.

The thesis ran its tables with its own limits, so the comparison takes our runs with the
``thesis`` limits when the database has any for the preset, else whatever limits it has
(and says so): never a blend of both.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from .data import Run, by_point, metric_values
from .thesis import ThesisTable


@dataclass(frozen=True)
class CellComparison:
    table: str          # thesis table number, e.g. "4.6"
    preset: str
    metric: str         # Ta, Td, Tt (simulated seconds)
    robots: int
    void_width: int     # robot widths
    n: int              # our runs with a value
    ours_mean_s: float | None
    ours_sd_s: float | None
    thesis_s: float | None
    ratio: float | None  # ours / thesis
    inside: bool | None  # |ours - thesis| <= ours_sd_s (None: fewer than 2 runs or nothing to compare)

    def as_dict(self) -> dict:
        d = asdict(self)
        for k in ("ours_mean_s", "ours_sd_s", "ratio"):
            if d[k] is not None:
                d[k] = round(d[k], 4)
        return d


def runs_for(table: ThesisTable, runs: list[Run]) -> tuple[list[Run], str]:
    """The runs a table is compared with, and the limits they used (see the module doc)."""
    own = [r for r in runs if r.preset == table.preset]
    thesis = [r for r in own if r.limits == "thesis"]
    if thesis:
        return thesis, "thesis"
    used = sorted({r.limits for r in own})
    return own, ", ".join(used) if used else "none"


def compare_table(table: ThesisTable, runs: list[Run]) -> list[CellComparison]:
    """One :class:`CellComparison` per cell of ``table`` (row-major: widths, then sizes)."""
    pts = by_point(runs)
    cells = []
    for w in table.widths():
        for n in table.robots:
            v = metric_values(pts.get((n, w), []), table.metric)
            th = table.values[(n, w)]
            mean = float(v.mean()) if v.size else None
            sd = float(v.std(ddof=1)) if v.size >= 2 else None
            ratio = mean / th if (mean is not None and th) else None
            inside = (abs(mean - th) <= sd) if (sd is not None and th is not None) else None
            cells.append(CellComparison(table.number, table.preset, table.metric, n, w, int(v.size), mean, sd,
                                        th, ratio, inside))
    return cells


def table_summary(cells: list[CellComparison]) -> dict:
    """How ours compares over a table: cells compared, the median and the range of the ratio,
    how many cells are inside our spread, and how many are faster or slower outside it."""
    both = [c for c in cells if c.ratio is not None]
    judged = [c for c in both if c.inside is not None]
    ratios = np.array([c.ratio for c in both]) if both else np.array([])
    return {
        "cells": len(cells),
        "compared": len(both),
        "median_ratio": round(float(np.median(ratios)), 4) if both else None,
        "min_ratio": round(float(ratios.min()), 4) if both else None,
        "max_ratio": round(float(ratios.max()), 4) if both else None,
        "judged": len(judged),
        "inside_spread": sum(bool(c.inside) for c in judged),
        "faster_outside": sum(1 for c in judged if not c.inside and c.ratio < 1),
        "slower_outside": sum(1 for c in judged if not c.inside and c.ratio > 1),
    }


def cell_text(c: CellComparison) -> str:
    """``ours ±sd / thesis (x ratio)``, a trailing ``*`` when the thesis is outside our spread."""
    ours = "–" if c.ours_mean_s is None else f"{c.ours_mean_s:.0f}"
    if c.ours_sd_s is not None:
        ours += f" ±{c.ours_sd_s:.0f}"
    th = "–" if c.thesis_s is None else f"{c.thesis_s:.0f}"
    txt = f"{ours} / {th}"
    if c.ratio is not None and math.isfinite(c.ratio):
        txt += f" (×{c.ratio:.2f}){'*' if c.inside is False else ''}"
    return txt


__all__ = ["CellComparison", "cell_text", "compare_table", "runs_for", "table_summary"]
