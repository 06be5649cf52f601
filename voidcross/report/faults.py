"""The report's "Robots that fail" section (issue 16): failure-rate curves and piers.

Runs with a fault spec (``faults_spec`` in their stored result) are kept out of the
fault-free sections (the thesis's tables) and summarised here, per preset and point
(swarm size, void width), one row per fault spec: crossing rate, robots failed (as a
fraction of the swarm), detection delays, robots delivered, robots in piers, robots lost.
The curve plots the crossing rate against the measured failed fraction, the fault-free
runs of the same point (if any) at 0.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np

from .data import Run
from .document import Figure, Note, Para, Section, Table


def faulted(r: Run) -> bool:
    return bool(r.extra.get("faults_spec"))


def split(runs: list[Run]) -> tuple[list[Run], list[Run]]:
    """(fault-free runs, runs with faults)."""
    return [r for r in runs if not faulted(r)], [r for r in runs if faulted(r)]


def _row(spec: str, runs: list[Run]) -> dict:
    n = len(runs)
    failed = np.array([r.extra.get("robots_failed", 0) / max(r.robots, 1) for r in runs], dtype=float)
    delays = [f["delay_s"] for r in runs for f in r.extra.get("faults", []) if f.get("delay_s") is not None]
    crossed = [r for r in runs if r.success]
    tt = [r.times.get("Tt") for r in crossed if r.times.get("Tt") is not None]
    return {"faults": spec or "none", "runs": n, "crossed": len(crossed), "rate": len(crossed) / n if n else 0.0,
            "failed_fraction": float(failed.mean()) if n else 0.0,
            "detected": sum(r.extra.get("robots_detected", 0) for r in runs),
            "failed": sum(r.extra.get("robots_failed", 0) for r in runs),
            "delay_mean_s": float(np.mean(delays)) if delays else None,
            "delay_max_s": float(np.max(delays)) if delays else None,
            "delivered_mean": float(np.mean([r.extra.get("robots_delivered", 0) for r in runs])) if n else 0.0,
            "in_piers_mean": float(np.mean([r.extra.get("robots_in_piers", 0) for r in runs])) if n else 0.0,
            "lost": sum(r.robots_lost for r in runs),
            "stranded": sum(1 for r in runs if r.extra.get("end_reason") == "stranded"),
            "Tt_mean_s": float(np.mean(tt)) if tt else None}


def _others(r: Run) -> str:
    """The run's overrides other than its faults (``void_depth_cm=0.0``), "" when none."""
    ov = {k: v for k, v in r.extra.get("_overrides", {}).items() if k != "faults"}
    return ", ".join(f"{k}={v}" for k, v in sorted(ov.items()))


def curves(clean: list[Run], faulty: list[Run]) -> dict:
    """{(preset, robots, void_width, other overrides): [row per fault spec, fault-free first]} for
    every point with fault runs."""
    groups: dict = defaultdict(lambda: defaultdict(list))
    for r in faulty:
        groups[(r.preset, r.robots, r.void_width, _others(r))][r.extra["faults_spec"]].append(r)
    for r in clean:
        key = (r.preset, r.robots, r.void_width, _others(r))
        if key in groups:
            groups[key][""].append(r)
    out = {}
    for key, by_spec in sorted(groups.items()):
        rows = [_row(s, rs) for s, rs in by_spec.items()]
        out[key] = sorted(rows, key=lambda d: (d["faults"] != "none", d["failed_fraction"], d["faults"]))
    return out


def _fmt(v, d=1) -> str:
    return "-" if v is None else f"{v:.{d}f}"


def curve_figure(cv: dict, path: Path, preset: str) -> bool:
    from .figures import _csv, _save, _subplots

    keys = [k for k in cv if k[0] == preset]
    if not keys:
        return False
    fig, ax = _subplots(figsize=(6.4, 4.0))
    rows = []
    for k in keys:
        pts = cv[k]
        x = [100 * d["failed_fraction"] for d in pts]
        y = [100 * d["rate"] for d in pts]
        order = np.argsort(x)
        ax.plot(np.array(x)[order], np.array(y)[order], marker="o",
                label=f"N={k[1]}, w={k[2]}" + (f" ({k[3]})" if k[3] else ""))
        rows += [[k[1], k[2], d["faults"], d["runs"], 100 * d["failed_fraction"], 100 * d["rate"], d["lost"]]
                 for d in pts]
    ax.set_xlabel("robots failed during the run (% of the swarm, mean)")
    ax.set_ylabel("runs that crossed (%)")
    ax.set_ylim(-3, 103)
    ax.set_title(f"{preset}: crossing rate vs failures")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    _save(fig, path)
    _csv(path, ["robots", "void_width", "faults", "runs", "failed_pct", "crossed_pct", "robots_lost"], rows)
    return True


def section(clean: list[Run], faulty: list[Run], fig_dir: Path, rel: str) -> tuple[Section, dict]:
    sec = Section("Robots that fail (faults and piers)")
    if not faulty:
        sec.add(Note("no runs with faults in this database (voidcross sweep ... --faults 'none;drive:0.5/h;...')."))
        return sec, {}
    cv = curves(clean, faulty)
    sec.add(Para("Runs with robots failing mid-task (`--faults`, swarm_sim.faults; detection and handling: "
                 "swarm_sim.behaviour.detection; piers: swarm_sim.behaviour.piers). The fault-free runs of the same point are the "
                 "`none` row. Delays: from a robot's first fault until the swarm detected it."))
    for preset in sorted({k[0] for k in cv}):
        name = f"faults_{preset}.png"
        if curve_figure(cv, fig_dir / name, preset):
            sec.add(Figure(f"{rel}/{name}", f"{preset}: crossing rate against the fraction of the swarm that failed",
                           f"{rel}/{Path(name).with_suffix('.csv').name}"))
    for (preset, n, w, other), pts in cv.items():
        sec.add(Table(["faults", "runs", "crossed", "failed (% swarm)", "detected/failed", "delay mean / max (s)",
                       "delivered (mean)", "in piers (mean)", "stranded", "lost", "Tt crossed (s)"],
                      [[d["faults"], str(d["runs"]), f"{d['crossed']} ({100 * d['rate']:.0f} %)",
                        f"{100 * d['failed_fraction']:.1f}", f"{d['detected']}/{d['failed']}",
                        f"{_fmt(d['delay_mean_s'])} / {_fmt(d['delay_max_s'])}", _fmt(d["delivered_mean"]),
                        _fmt(d["in_piers_mean"]), str(d["stranded"]), str(d["lost"]), _fmt(d["Tt_mean_s"], 0)]
                       for d in pts], f"{preset}, {n} robots, {w}-wide void" + (f", {other}" if other else "")))
    piers = [r for r in faulty if r.extra.get("robots_in_piers")]
    if piers:
        by = defaultdict(list)
        for r in faulty:
            by[r.preset].append(r)
        rows = []
        for preset, rs in sorted(by.items()):
            crossed_p = [r.void_width for r in rs if r.success and r.extra.get("robots_in_piers")]
            crossed_0 = [r.void_width for r in clean + rs if r.preset == preset and r.success
                         and not r.extra.get("robots_in_piers")]
            rows.append([preset, str(max(crossed_0)) if crossed_0 else "-", str(max(crossed_p)) if crossed_p else "-"])
        sec.add(Table(["preset", "widest void crossed without a pier", "widest with piers"], rows,
                      "piers of failed robots (robot widths)"))
    return sec, {f"{k[0]} N={k[1]} w={k[2]}" + (f" {k[3]}" if k[3] else ""): v for k, v in cv.items()}


__all__ = ["curve_figure", "curves", "faulted", "section", "split"]
