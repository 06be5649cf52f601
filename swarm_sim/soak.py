"""Soak testing: many randomised short runs, every invariant checked every step.

``soak(runs, seed)`` draws case (preset), swarm size, void width, arena size and
seed per run, simulates ``max_time_s`` of it with the invariants of
:mod:`swarm_sim.invariants` checked after every step, and reports every violation
(and every robot lost) with the draw that produced it, so it can be replayed with
``voidcross sim run``.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from .errors import InputError
from .runner import resolve_params, simulate

PRESETS = ("case-a", "case-b", "case-c", "case-d")


def draw(rng: np.random.Generator) -> dict:
    """One random scenario: preset, robots, void width, arena size, seed and structure
    (``auto`` builds the limits' level for the void; ``switch`` widens it during the build)."""
    preset = str(rng.choice(PRESETS))
    w = int(rng.integers(1, 6))
    big = preset != "case-a"
    arena_w = float(rng.integers(400 if big else 250, 801 if big else 501))
    arena_h = float(rng.integers(150, 401))
    robots = int(rng.integers(1, 3 * w + 4))
    return {"preset": preset, "robots": robots, "void_width": w, "seed": int(rng.integers(0, 2**31 - 1)),
            "arena_w_cm": arena_w, "arena_h_cm": arena_h, "target_x_cm": arena_w - 25.0,
            "target_y_cm": arena_h / 2, "structure": str(rng.choice(["line", "auto", "switch"]))}


def soak(runs: int, seed: int = 0, max_time_s: float = 60.0, limits: str = "thesis",
         progress=lambda it, total: it) -> dict:
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise InputError(f"--runs must be a positive integer, got {runs!r}")
    if not (max_time_s > 0):
        raise InputError(f"--max-time must be > 0 s, got {max_time_s}")
    rng = np.random.default_rng(seed)
    report: dict = {"runs": runs, "seed": seed, "max_time_s": max_time_s, "limits": limits,
                    "violations": [], "robots_lost": 0, "skipped_invalid": 0, "outcomes": {}}
    todo: Iterable = progress(range(runs), runs)
    for _ in todo:
        d = draw(rng)
        kw = {k: v for k, v in d.items() if k not in ("preset", "robots", "void_width", "seed")}
        try:
            p = resolve_params(d["preset"], d["robots"], d["void_width"], limits, max_time_s, **kw)
            _, res = simulate(p, d["seed"], check=True)
        except InputError:
            report["skipped_invalid"] += 1  # e.g. the swarm does not fit: rejected before running
            continue
        outcome = "success" if res.success else "retreated" if res.retreated else "running_at_cap"
        report["outcomes"][outcome] = report["outcomes"].get(outcome, 0) + 1
        report["robots_lost"] += res.robots_lost
        for v in res.violations:
            report["violations"].append({**d, "violation": v})
    report["n_violations"] = len(report["violations"])
    return report
