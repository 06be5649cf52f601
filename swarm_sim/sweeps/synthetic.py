"""A deterministic stand-in run function with the shape of ``RunResult.to_dict()``.

Used by the sweep tests (no simulator needed, runs in microseconds) and by
``voidcross sweep bench`` to measure pure executor overhead. It is never the
default: a sweep uses it only when asked (``--run-fn
swarm_sim.sweeps.synthetic:synthetic_run``). It follows the thesis's
cases C/D rule (a swarm of ``N >= 3 w`` crosses a ``w``-wide void, fewer
retreat) with times drawn from a generator seeded by (robots, width, seed).

Overrides it understands (``--set KEY=VALUE``): ``sleep_s`` (wall seconds
to sleep), ``spin_s`` (wall seconds of busy CPU work), ``raise_on_seed``
(raise RuntimeError for that seed), ``exit_on_seed`` (the worker
process exits abruptly), ``return_bad`` (return a non-dict).
"""

from __future__ import annotations

import os
import time

import numpy as np


def synthetic_run(key: dict) -> dict:
    ov = key.get("params", {}).get("overrides", {})
    n, w, seed = int(key["robots"]), int(key["void_width"]), int(key["seed"])
    if "raise_on_seed" in ov and int(ov["raise_on_seed"]) == seed:
        raise RuntimeError(f"synthetic failure for seed {seed}")
    if "exit_on_seed" in ov and int(ov["exit_on_seed"]) == seed:
        os._exit(17)  # a worker that dies outright (as if killed or out of memory)
    if ov.get("return_bad"):
        return "not a dict"  # type: ignore[return-value]
    if ov.get("sleep_s"):
        time.sleep(float(ov["sleep_s"]))
    if ov.get("spin_s"):
        end = time.perf_counter() + float(ov["spin_s"])
        x = 0
        while time.perf_counter() < end:
            x += 1
    rng = np.random.default_rng([n, w, seed])
    success = n >= 3 * w
    ts = float(rng.gamma(4.0, 10.0))
    ta = float(8.0 * n + rng.normal(0, 3))
    times = {"Ts": ts, "Ta": ta, "To": None, "Td": None, "Tb": None, "Tt": None}
    if success:
        times["To"] = float(rng.gamma(3.0, 20.0))
        times["Tt"] = ts + ta + times["To"]
    else:
        times["Td"] = float(4.0 * n + rng.normal(0, 1))
        times["Tb"] = 5.01
        times["Tt"] = ts + ta + times["Td"] + times["Tb"]
    edge_x = 250.0 - 5.0 * w
    return {
        "success": success, "retreated": not success, "robots_lost": 0, "times": times,
        "seed_robot": int(rng.integers(0, n)),
        "seed_position": [edge_x - 5.0, float(rng.uniform(10, 290))],
        "target_finder": int(rng.integers(0, n)) if success else None,
        "preset": key["preset"], "robots": n, "void_width": w, "seed": seed,
        "limits_source": key.get("limits", "thesis"),
    }
