"""Matplotlib figures of the report (Agg backend, PNG at 150 dpi, constrained layout, integer
ticks on counted axes). Each writes ``path`` and, beside it, ``path`` with ``.csv``: the numbers
the figure plots, for anyone who would rather re-plot than read pixels.

Times are simulated seconds; positions centimetres; robot ids as the simulator numbers them.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

from .data import Run, by_point, grid, metric_values, summary  # noqa: E402

DPI = 150
METRIC_NAMES = {
    "Tt": "total simulation time T_t", "Ts": "initial-zone exploration T_s",
    "Ta": "assembly and moving forward T_a", "Td": "retreat and disassembly T_d",
    "To": "target-zone exploration T_o", "Tb": "exploration after retreat T_b",
}


def _save(fig, path: Path) -> None:
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def _csv(path: Path, header: list[str], rows) -> None:
    """The plotted numbers beside the figure (``figure.png`` -> ``figure.csv``)."""
    import csv

    with open(Path(path).with_suffix(".csv"), "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for r in rows:
            w.writerow(["" if v is None or (isinstance(v, float) and np.isnan(v)) else
                        (round(v, 6) if isinstance(v, float) else v) for v in r])


def _subplots(*args, **kw):
    return plt.subplots(*args, layout="constrained", **kw)


def _integer(axis) -> None:
    axis.set_major_locator(MaxNLocator(integer=True))


def success_matrix(runs: list[Run], path: Path, preset: str, boundaries: dict[str, dict[int, int]]) -> None:
    """Fraction of runs that crossed, swarm size x void width, with the minimum swarm each
    set of limits requires drawn as a step line (``boundaries``: label -> {width: N_min})."""
    robots, widths = grid(runs)
    pts = by_point(runs)
    m = np.full((len(robots), len(widths)), np.nan)
    for i, n in enumerate(robots):
        for j, w in enumerate(widths):
            rs = pts.get((n, w))
            if rs:
                m[i, j] = np.mean([r.success for r in rs])
    fig, ax = _subplots(figsize=(3.2 + 1.0 * len(widths), 2.6 + 0.34 * len(robots)))
    im = ax.imshow(m, origin="lower", aspect="auto", cmap="RdYlGn", vmin=0, vmax=1)
    for i, n in enumerate(robots):
        for j, w in enumerate(widths):
            rs = pts.get((n, w))
            if rs:
                k = sum(r.success for r in rs)
                ax.text(j, i, f"{k}/{len(rs)}", ha="center", va="center", fontsize=8)
    styles = ["k-", "b--", "m:"]
    for (label, b), st in zip(boundaries.items(), styles, strict=False):
        xs, ys = [], []
        for j, w in enumerate(widths):
            if w in b:
                # first row whose swarm size reaches N_min, drawn at the cell's lower edge
                i = next((i for i, n in enumerate(robots) if n >= b[w]), len(robots))
                xs += [j - 0.5, j + 0.5]
                ys += [i - 0.5, i - 0.5]
        if xs:
            ax.plot(xs, ys, st, lw=2, label=f"N_min, {label} limits")
    ax.set_xticks(range(len(widths)), [str(w) for w in widths])
    ax.set_yticks(range(len(robots)), [str(n) for n in robots])
    ax.set_xlabel("void width (robot widths)")
    ax.set_ylabel("swarm size N")
    ax.set_title(f"{preset}: runs that crossed")
    fig.colorbar(im, ax=ax, fraction=0.05, label="fraction crossed")
    if ax.get_legend_handles_labels()[0]:
        fig.legend(loc="outside lower center", fontsize=8, ncol=2, frameon=False)  # never over a cell
    _csv(path, ["swarm_size", "void_width", "runs", "crossed"] + [f"n_min_{k}" for k in boundaries],
         [[n, w, len(pts.get((n, w), [])), sum(r.success for r in pts.get((n, w), []))]
          + [b.get(w) for b in boundaries.values()] for n in robots for w in widths])
    _save(fig, path)


def times_vs_size(runs: list[Run], metric: str, path: Path, preset: str, fig_ref: str) -> bool:
    """Mean and 25-75 % band of one time metric against swarm size, one panel per void width."""
    robots, widths = grid(runs)
    pts = by_point(runs)
    any_data = False
    fig, axes = _subplots(1, len(widths), figsize=(2.2 + 2.6 * len(widths), 3.0), squeeze=False,
                             sharey=True)
    rows = []
    for ax, w in zip(axes[0], widths, strict=True):
        xs, mean, lo, hi = [], [], [], []
        for n in robots:
            s = summary(metric_values(pts.get((n, w), []), metric))
            if s:
                xs.append(n)
                mean.append(s["mean"])
                lo.append(s["q25"])
                hi.append(s["q75"])
                rows.append([w, n, s["mean"], s["q25"], s["q75"]])
        _integer(ax.xaxis)
        if xs:
            any_data = True
            ax.fill_between(xs, lo, hi, alpha=0.3, label="25-75 %")
            ax.plot(xs, mean, "o-", ms=3, label="mean")
            ax.plot(xs, lo, "_", color="C0")
            ax.plot(xs, hi, "_", color="C0")
        ax.set_title(f"{w}-wide void", fontsize=9)
        ax.set_xlabel("swarm size N")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel(f"{metric} (s)")
    if axes[0][0].get_legend_handles_labels()[0]:
        axes[0][0].legend(fontsize=7)
    fig.suptitle(f"{preset}: {METRIC_NAMES[metric]} ({fig_ref})", fontsize=10)
    _csv(path, ["void_width", "swarm_size", f"{metric}_mean_s", f"{metric}_q25_s", f"{metric}_q75_s"], rows)
    _save(fig, path)
    return any_data


def id_frequency(runs: list[Run], attr: str, path: Path, preset: str, what: str) -> bool:
    """How often each robot id was the seed / found the target: swarm size x robot id per width."""
    robots, widths = grid(runs)
    pts = by_point(runs)
    max_id = max([getattr(r, attr) for r in runs if getattr(r, attr) is not None] + [max(robots) - 1, 0])
    fig, axes = _subplots(1, len(widths), figsize=(1.5 + 3.0 * len(widths), 1.6 + 0.25 * len(robots)),
                             squeeze=False)
    any_data = False
    im = None
    rows = []
    vmax = max([sum(1 for r in pts.get((n, w), []) if getattr(r, attr) is not None) for n in robots
                for w in widths] + [1])  # one colour scale for every panel
    for ax, w in zip(axes[0], widths, strict=True):
        m = np.full((len(robots), max_id + 1), np.nan)
        for i, n in enumerate(robots):
            rs = pts.get((n, w), [])
            if rs:
                m[i, :n] = 0
                for r in rs:
                    v = getattr(r, attr)
                    if v is not None:
                        m[i, v] += 1
                        any_data = True
        rows += [[w, n, k, int(m[i, k])] for i, n in enumerate(robots) for k in range(max_id + 1)
                 if not np.isnan(m[i, k]) and m[i, k] > 0]
        im = ax.imshow(m, origin="lower", aspect="auto", cmap="viridis", interpolation="nearest", vmin=0, vmax=vmax)
        _integer(ax.xaxis)
        ax.set_yticks(range(len(robots)), [str(n) for n in robots], fontsize=7)
        ax.set_xlabel("robot id")
        ax.set_title(f"{w}-wide void", fontsize=9)
    axes[0][0].set_ylabel("swarm size N")
    if im is not None:
        _integer(fig.colorbar(im, ax=axes[0].tolist(), fraction=0.03, label="runs").ax.yaxis)
    fig.suptitle(f"{preset}: {what}", fontsize=10)
    _csv(path, ["void_width", "swarm_size", "robot_id", "runs"], rows)
    _save(fig, path)
    return any_data


def seed_positions(runs: list[Run], path: Path, preset: str, fig_ref: str) -> bool:
    pts = [(r.seed_xy, r.void_width) for r in runs if r.seed_xy is not None]
    if not pts:
        return False
    fig, ax = _subplots(figsize=(6.5, 4))
    widths = sorted({w for _, w in pts})
    for k, w in enumerate(widths):
        xy = np.array([p for p, ww in pts if ww == w])
        ax.scatter(xy[:, 0], xy[:, 1], s=10, alpha=0.7, color=f"C{k}", label=f"{w}-wide void")
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")
    ax.set_title(f"{preset}: where the seed robot found the edge ({fig_ref})", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    _csv(path, ["void_width", "seed_x_cm", "seed_y_cm"], [[w, p[0], p[1]] for p, w in pts])
    _save(fig, path)
    return True


def large_void_ids(runs: list[Run], path: Path, preset: str) -> bool:
    """Fig. 5.9 equivalent: seed-id and target-finder-id counts over all runs."""
    seeds = [r.seed_robot for r in runs if r.seed_robot is not None]
    finders = [r.target_finder for r in runs if r.target_finder is not None]
    if not seeds and not finders:
        return False
    fig, axes = _subplots(2, 1, figsize=(8, 5), sharex=True)
    for ax, vals, what in ((axes[0], seeds, "(a) seed robot"), (axes[1], finders, "(b) target finder")):
        if vals:
            ids, counts = np.unique(vals, return_counts=True)
            ax.bar(ids, counts, width=0.8)
        ax.set_ylabel("runs")
        ax.set_title(what, fontsize=9)
    axes[1].set_xlabel("robot id")
    _integer(axes[1].xaxis)
    fig.suptitle(f"{preset}: which robots seed and find the target (cf. Fig. 5.9)", fontsize=10)
    rows = [[what, int(i), int(c)] for what, vals in (("seed", seeds), ("target_finder", finders)) if vals
            for i, c in zip(*np.unique(vals, return_counts=True), strict=True)]
    _csv(path, ["role", "robot_id", "runs"], rows)
    _save(fig, path)
    return True


def large_void_seed_edge(runs: list[Run], path: Path, preset: str) -> bool:
    """Fig. 5.10 equivalent: seed position along the void edge (y) per void width."""
    pts = [(r.void_width, r.seed_xy[1]) for r in runs if r.seed_xy is not None]
    if not pts:
        return False
    a = np.array(pts, dtype=float)
    fig, ax = _subplots(figsize=(6, 3.5))
    ax.scatter(a[:, 0], a[:, 1], s=14, alpha=0.7)
    ax.set_xlabel("void width (robot widths)")
    _integer(ax.xaxis)
    _csv(path, ["void_width", "seed_y_cm"], a.tolist())
    ax.set_ylabel("seed y along the edge (cm)")
    ax.set_title(f"{preset}: seed position at the void edge (cf. Fig. 5.10)", fontsize=10)
    ax.grid(alpha=0.3)
    _save(fig, path)
    return True


def large_void_times(runs: list[Run], metrics: list[tuple[str, str]], path: Path, title: str) -> bool:
    """Figs. 5.11-5.13 equivalents: box plots of times against void width (one panel per metric).

    ``metrics``: (label, key) where key is a time key or ``extra:<name>`` from the run's result."""
    widths = sorted({r.void_width for r in runs})
    fig, axes = _subplots(1, len(metrics), figsize=(1 + 3.6 * len(metrics), 3.2), squeeze=False)
    any_data = False
    rows = []
    for ax, (label, key) in zip(axes[0], metrics, strict=True):
        data = []
        for w in widths:
            rs = [r for r in runs if r.void_width == w]
            if key.startswith("extra:"):
                name = key.split(":", 1)[1]
                vals = [(r.extra.get("times") or {}).get(name, r.extra.get(name)) for r in rs]
                vals = np.array([v for v in vals if isinstance(v, (int, float))], dtype=float)
            else:
                vals = metric_values(rs, key)
            data.append(vals)
            rows += [[key.split(":")[-1], w, float(v)] for v in vals]
        if any(len(d) for d in data):
            any_data = True
            ax.boxplot([d if len(d) else [np.nan] for d in data], whis=(0, 100))
            ax.set_xticks(range(1, len(widths) + 1), [str(w) for w in widths])
            ax.plot(range(1, len(widths) + 1), [d.mean() if len(d) else np.nan for d in data], "r^",
                    ms=5, label="mean")
        else:
            ax.text(0.5, 0.5, "not recorded", ha="center", va="center", transform=ax.transAxes)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("void width (robot widths)")
        ax.set_ylabel("s")
        ax.grid(alpha=0.3)
    fig.suptitle(title, fontsize=10)
    _csv(path, ["metric", "void_width", "value_s"], rows)
    _save(fig, path)
    return any_data


def limits_plot(limits: dict, path: Path, max_width: int = 30, rule: dict | None = None) -> None:
    """Minimum swarm size per void width for each set of limits (log scale): the launch rule's
    N_min (``rule``: label -> {width: N}) solid, the record's complete-structure count dotted;
    structure switches as vertical lines."""
    fig, ax = _subplots(figsize=(7.5, 4))
    rows = []
    for k, (label, lim) in enumerate(limits.items()):
        ws = list(range(1, min(max_width, lim.max_span_widths) + 1))
        rec = [lim.min_robots(w) for w in ws]
        if rule and label in rule:
            ax.step(ws, [rule[label][w] for w in ws], where="mid", color=f"C{k}", label=f"{label}: N_min (launch rule)")
        ax.step(ws, rec, where="mid", color=f"C{k}", ls=":", label=f"{label}: complete structure (record)")
        rows += [[label, w, (rule or {}).get(label, {}).get(w), r] for w, r in zip(ws, rec, strict=True)]
        for lvl in lim.levels:
            ax.axvline(lvl.max_span_widths + 0.5, color=f"C{k}", ls="--", lw=0.6, alpha=0.6)
    ax.set_yscale("log")
    ax.set_xlabel("void width (robot widths)")
    _integer(ax.xaxis)
    _csv(path, ["limits", "void_width", "n_min_launch_rule", "complete_structure_record"], rows)
    ax.set_ylabel("swarm size")
    ax.set_title("Minimum swarm per void width (dashed: structure switches)", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    _save(fig, path)


def thesis_ratio(cells, path: Path, title: str) -> bool:
    """Ours / thesis per cell of one thesis table (``cells``: :class:`compare.CellComparison`):
    colour on a log scale from x0.5 (blue, ours faster) to x2 (red, ours slower), each cell
    annotated with its ratio and ``*`` where the thesis's mean is outside our spread."""
    robots = sorted({c.robots for c in cells})
    widths = sorted({c.void_width for c in cells})
    m = np.full((len(widths), len(robots)), np.nan)
    for c in cells:
        if c.ratio is not None and c.ratio > 0:
            m[widths.index(c.void_width), robots.index(c.robots)] = math.log2(c.ratio)
    fig, ax = _subplots(figsize=(2.8 + 0.75 * len(robots), 1.9 + 0.42 * len(widths)))
    im = ax.imshow(m, origin="lower", aspect="auto", cmap="RdBu_r", vmin=-1, vmax=1)
    for c in cells:
        j, i = robots.index(c.robots), widths.index(c.void_width)
        if c.ratio is not None:
            ax.text(j, i, f"{c.ratio:.2f}{'*' if c.inside is False else ''}", ha="center", va="center", fontsize=8)
        elif c.thesis_s is None and c.ours_mean_s is not None:
            ax.text(j, i, "thesis –", ha="center", va="center", fontsize=6, color="0.4")
    ax.set_xticks(range(len(robots)), [str(n) for n in robots])
    ax.set_yticks(range(len(widths)), [str(w) for w in widths])
    ax.set_xlabel("swarm size N")
    ax.set_ylabel("void width (robot widths)")
    ax.set_title(title, fontsize=9)
    cb = fig.colorbar(im, ax=ax, fraction=0.05, ticks=[-1, 0, 1])
    cb.ax.set_yticklabels(["×0.5", "×1", "×2"])
    cb.set_label("ours / thesis")
    _csv(path, ["table", "metric", "swarm_size", "void_width", "runs", "ours_mean_s", "ours_sd_s", "thesis_s",
                "ratio", "inside_spread"],
         [[c.table, c.metric, c.robots, c.void_width, c.n, c.ours_mean_s, c.ours_sd_s, c.thesis_s, c.ratio,
           "" if c.inside is None else int(c.inside)] for c in cells])
    _save(fig, path)
    return bool(np.isfinite(m).any())
