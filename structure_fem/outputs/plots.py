"""Figures: deflection vs void width, side view of a deflected structure, sensitivity.

matplotlib with the Agg backend; every function writes one PNG and returns its path.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from structure_fem.analysis.study import Derivation, TaperRow
from structure_fem.limits import thesis_limits
from structure_fem.model.statics import StaticResult


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def deflection_plot(d: Derivation, path: str | Path) -> Path:
    """Tip deflection at the longest cantilever vs void width, per structure, with the clearance."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 5))
    clear = d.inputs.clearance_m * 1e3
    for c in d.curves:
        (ln,) = ax.plot(c.widths, c.tip_mm, marker="o", ms=3, label=f"{c.structure.name} (threshold {c.threshold})")
        if c.threshold:
            i = c.widths.index(c.threshold)
            ax.plot([c.threshold], [c.tip_mm[i]], marker="*", ms=12, color=ln.get_color())
    ax.axhline(clear, color="k", ls="--", lw=1, label=f"clearance {clear:g} mm")
    for t in sorted({lvl.max_span_widths for lvl in thesis_limits().levels}):
        if t <= max((w for c in d.curves for w in c.widths), default=0):
            ax.axvline(t, color="grey", ls=":", lw=0.8)
    ax.set_yscale("log")
    ax.set_xlabel("void width (robot widths)")
    ax.set_ylabel("tip deflection at the longest cantilever (mm)")
    ax.set_title(f"{d.inputs.robot.name}: deflection vs void width (dotted: thesis switch points)")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def band_plot(band: dict, path: str | Path, title: str = "") -> Path:
    """The uncertainty band per structure (:mod:`structure_fem.analysis.band`): every sample's
    threshold (dots), p5-p95 (bar), p50 (tick), the nominal (as drawn, star) and the pick."""
    plt = _plt()
    per = band["per_structure"]
    names = list(per)
    fig, ax = plt.subplots(figsize=(9, 1.6 + 0.8 * len(names)))
    rng = np.random.default_rng(0)  # jitter only, so equal thresholds do not hide each other
    for i, s in enumerate(names):
        v = per[s]
        ax.plot([v["p5"], v["p95"]], [i, i], color="C0", lw=6, alpha=0.35, solid_capstyle="butt",
                label="p5 - p95" if i == 0 else None)
        xs = np.asarray(v["samples"], dtype=float)
        ax.scatter(xs, i + rng.uniform(-0.18, 0.18, len(xs)), s=10, color="C0", alpha=0.6,
                   label="samples" if i == 0 else None)
        ax.plot([v["p50"]], [i], marker="|", ms=18, mew=2, color="C0", label="p50" if i == 0 else None)
        ax.plot([v["nominal"]], [i], marker="*", ms=14, color="C3", label="nominal (as drawn)" if i == 0 else None)
        ax.plot([min(v[band["pick"]], v["nominal"]) if band["pick"] != "nominal" else v["nominal"]], [i - 0.32],
                marker="^", ms=8, color="k", label=f"picked ({band['pick']})" if i == 0 else None)
    from matplotlib.ticker import MaxNLocator

    ax.set_yticks(range(len(names)), names)
    ax.set_ylim(-0.7, len(names) - 0.3)
    every = [x for v in per.values() for x in (*v["samples"], v["nominal"])]
    ax.set_xlim(min(every) - 0.6, max(every) + 0.6)
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("threshold (robot widths): the widest void a print of the robot spans")
    ax.set_title(title or f"uncertainty band of the thresholds ({len(band['samples'])} samples)")
    ax.grid(True, axis="x", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def tapered_plot(d: Derivation, rows: list[TaperRow], path: str | Path) -> Path:
    """Tip deflection vs void width: the thesis's tapering arches (core front at the far edge, near
    foot only; bridged dashed) beside the derived uniform 2k x k arches, with the clearance."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 5))
    clear = d.inputs.clearance_m * 1e3
    for level in dict.fromkeys(r.level for r in rows):
        sub = [r for r in rows if r.level == level]
        xs = [r.width for r in sub if r.tip_mm is not None]
        (ln,) = ax.plot(xs, [r.tip_mm for r in sub if r.tip_mm is not None], marker="s", ms=4,
                        label=f"thesis {level}: {sub[0].structure} before landing")
        xb = [r.width for r in sub if r.bridged_max_mm is not None]
        ax.plot(xb, [r.bridged_max_mm for r in sub if r.bridged_max_mm is not None], ls="--", lw=1,
                color=ln.get_color(), label=f"thesis {level}: bridged (both feet)")
    arches = [c for c in d.curves if c.structure.kind == "arch" and c.structure.lines >= 2 * c.structure.layers]
    for c, (grey, mk) in zip(arches, (("0.6", "o"), ("0.4", "^"), ("0.15", "v"), ("0.3", "d")), strict=False):
        ax.plot(c.widths, c.tip_mm, marker=mk, ms=4, color=grey, lw=1,
                label=f"derived uniform {c.structure.name} (threshold {c.threshold})")
    ax.axhline(clear, color="k", ls=":", lw=1.2, label=f"clearance {clear:g} mm")
    ax.set_yscale("log")
    ax.set_xlabel("void width (robot widths)")
    ax.set_ylabel("tip deflection, core front at the far edge (mm)")
    ax.set_title(f"{d.inputs.robot.name}: the thesis's tapering arches under our mechanics", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def side_view(res: StaticResult, path: str | Path, height_m: float, exaggerate: float | None = None) -> Path:
    """The deflected structure from the side (deflections scaled by ``exaggerate``), ledges shaded."""
    plt = _plt()
    lay = res.layout
    tip = max(res.tip_deflection_m, 1e-9)
    if exaggerate is None:
        exaggerate = max(1.0, min(20.0, 0.05 * lay.void_m / tip)) if tip < 0.05 * lay.void_m else 1.0
    fig, ax = plt.subplots(figsize=(10, 3.5))
    for i, b in enumerate(lay.bodies):
        rear, front = res.underside_m[i]
        ref_r = np.array([b.x_m - lay.length_m / 2, b.z_m])
        ref_f = np.array([b.x_m + lay.length_m / 2, b.z_m])
        r = ref_r + exaggerate * (rear - ref_r)
        f = ref_f + exaggerate * (front - ref_f)
        t = f - r
        nrm = np.array([-t[1], t[0]]) / max(np.linalg.norm(t), 1e-12) * height_m
        poly = np.array([r, f, f + nrm, r + nrm])
        ax.fill(poly[:, 0], poly[:, 1], alpha=0.35 if b.parity else 0.6,
                color="tab:orange" if b.parity else "tab:blue", ec="k", lw=0.5)
    xmin = min(b.x_m for b in lay.bodies) - lay.length_m
    xmax = max(lay.void_m, max(b.x_m for b in lay.bodies)) + lay.length_m
    depth = 0.05
    for k, pier in enumerate(lay.piers):  # columns of stacked robots (their top drawn where it went down)
        x0, x1 = lay.pier_range_m(k)
        h = pier.robots * height_m if pier.robots else depth
        depth = max(depth, h)
        top = -exaggerate * (res.pier_compression_m[k] if k < len(res.pier_compression_m) else 0.0)
        for j in range(max(pier.robots, 1)):
            z1 = top - j * (h / max(pier.robots, 1))
            z0 = z1 - h / max(pier.robots, 1)
            ax.fill([x0, x1, x1, x0], [z0, z0, z1, z1], color="tab:red", alpha=0.45, ec="k", lw=0.5)
        ax.text(0.5 * (x0 + x1), top - 0.5 * h, f"pier {k + 1}\n{pier.robots} robots" if pier.robots
                else f"pier {k + 1}", ha="center", va="center", fontsize=7)
    ax.fill_between([xmin, 0], -depth, 0, color="0.6")
    ax.fill_between([lay.void_m, xmax], -depth, 0, color="0.6")
    ax.set_aspect("equal")
    cfg = res.config
    piers = f", piers at {', '.join(f'{q.at_widths:g}' for q in lay.piers)}" if lay.piers else ""
    ax.set_title(f"{cfg.structure.name}, {cfg.rows} rows, {cfg.rows_over:g} over a {cfg.void_widths:g}-wide void"
                 f"{piers}: tip {res.tip_deflection_mm:.1f} mm (drawn x{exaggerate:.3g}), tipping "
                 f"{res.tipping_factor:.2f}", fontsize=9)
    ax.set_xlabel("x (m), near edge at 0")
    ax.set_ylabel("z (m)")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def sensitivity_plot(rows: list[dict], path: str | Path) -> Path:
    """Threshold per structure kind vs each input's factor (one panel per input)."""
    plt = _plt()
    params = list(dict.fromkeys(r["parameter"] for r in rows))
    fig, axes = plt.subplots(1, len(params), figsize=(4 * len(params), 3.6), squeeze=False)
    for ax, p in zip(axes[0], params, strict=True):
        sub = [r for r in rows if r["parameter"] == p]
        xs = [r["value"] for r in sub]
        for key in ("line", "two_line", "arch", "max_span"):
            ax.plot(xs, [r[key] for r in sub], marker="o", label=key)
        ax.set_title(p, fontsize=9)
        ax.set_xlabel(sub[0]["unit"])
        ax.set_ylabel("threshold (robot widths)")
        ax.grid(True, alpha=0.3)
        if any(x > 0 for x in xs) and max(xs) / max(min(x for x in xs if x > 0), 1e-12) > 3 and min(xs) > 0:
            ax.set_xscale("log")
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def finite_or_none(x: float) -> float | None:
    return x if math.isfinite(x) else None
