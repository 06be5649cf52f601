"""Runs from a results database, grouped and summarised for the report (times in simulated s)."""

from __future__ import annotations

import json
from collections import defaultdict
from dataclasses import dataclass, field

import numpy as np

from swarm_sim.sweeps.store import TIME_COLUMNS, ResultStore

TIME_KEYS = tuple(TIME_COLUMNS)


@dataclass
class Run:
    preset: str
    robots: int
    void_width: int
    seed: int
    limits: str
    success: bool
    retreated: bool
    robots_lost: int
    times: dict
    seed_robot: int | None
    seed_xy: tuple[float, float] | None
    target_finder: int | None
    timed_out: bool
    extra: dict = field(default_factory=dict)


@dataclass
class RunSet:
    db: str
    runs: list[Run]
    errors: list[dict]
    sweeps: list[dict]

    def presets(self) -> list[str]:
        return sorted({r.preset for r in self.runs} | {e["preset"] for e in self.errors})

    def of(self, preset: str) -> list[Run]:
        return [r for r in self.runs if r.preset == preset]


def load_runs(db) -> RunSet:
    with ResultStore.open_readonly(db) as store:
        rows = list(store.iter_runs())
        sweeps = [{"sweep_id": s.sweep_id, "created_utc": s.created_utc, "spec": s.spec,
                   "runs_planned": s.runs_planned} for s in store.sweeps()]
    runs, errors = [], []
    for r in rows:
        if r["status"] != "ok":
            errors.append(r)
            continue
        extra = json.loads(r["result_json"]) if r["result_json"] else {}
        try:  # the run's parameter overrides (the report tells apart runs that differ only in them)
            extra["_overrides"] = json.loads(r["params_json"]).get("overrides", {}) if r["params_json"] else {}
        except (ValueError, AttributeError):
            extra["_overrides"] = {}
        runs.append(Run(
            preset=r["preset"], robots=r["robots"], void_width=r["void_width"], seed=r["seed"],
            limits=r["limits_source"] or r["limits"], success=bool(r["success"]),
            retreated=bool(r["retreated"]), robots_lost=int(r["robots_lost"] or 0),
            times={k: r[c] for k, c in TIME_COLUMNS.items()}, seed_robot=r["seed_robot"],
            seed_xy=(r["seed_x_cm"], r["seed_y_cm"]) if r["seed_x_cm"] is not None else None,
            target_finder=r["target_finder"], timed_out=bool(extra.get("timed_out", False)), extra=extra))
    return RunSet(str(db), runs, errors, sweeps)


def grid(runs: list[Run]) -> tuple[list[int], list[int]]:
    """Sorted swarm sizes and void widths present."""
    return sorted({r.robots for r in runs}), sorted({r.void_width for r in runs})


def by_point(runs: list[Run]) -> dict[tuple[int, int], list[Run]]:
    out: dict = defaultdict(list)
    for r in runs:
        out[(r.robots, r.void_width)].append(r)
    return dict(out)


def metric_values(runs: list[Run], metric: str) -> np.ndarray:
    """Values of one time metric over the runs it applies to.

    ``Td``/``Tb`` only for runs that retreated (the thesis's "when the structure
    fails"), ``To`` only for runs that crossed; null times (timed out) are left out.
    """
    sel = runs
    if metric in ("Td", "Tb"):
        sel = [r for r in runs if r.retreated]
    elif metric == "To":
        sel = [r for r in runs if r.success]
    vals = [r.times.get(metric) for r in sel]
    return np.array([v for v in vals if v is not None], dtype=float)


def summary(values: np.ndarray) -> dict | None:
    if values.size == 0:
        return None
    q25, q50, q75 = np.percentile(values, [25, 50, 75])
    return {"n": int(values.size), "mean": float(values.mean()), "q25": float(q25), "median": float(q50),
            "q75": float(q75)}
