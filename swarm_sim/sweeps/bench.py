"""Sweep throughput benchmark: runs per minute on 1 and 2 local workers and 2 Dask workers.

Each configuration gets a fresh executor and a temporary database; a warm-up
batch (one run per worker, other seeds) is run first so process start-up and
imports are not counted; then ``runs`` runs are timed end to end including
the SQLite writes. The Dask overhead per run is reported relative to the local
pool with the same number of workers, measured in the same invocation.
A second pass with the zero-work synthetic run function isolates the pure
per-run overhead of each executor (milliseconds per run).
"""

from __future__ import annotations

import tempfile
import time
from dataclasses import replace
from pathlib import Path

from .executors import DaskExecutor, LocalExecutor
from .sweep import DEFAULT_RUN_FN, SweepSpec, prepare_sweep

SYNTHETIC = "swarm_sim.sweeps.synthetic:synthetic_run"


def _timed(spec: SweepSpec, executor, run_fn, tmp: Path, tag: str) -> float:
    warm = replace(spec, runs=max(1, executor.workers), seed0=spec.seed0 + 10_000)
    plan = prepare_sweep(warm, tmp / f"{tag}-warm.sqlite", run_fn=run_fn)
    for _ in plan.execute(executor):
        pass
    plan.close()
    plan = prepare_sweep(spec, tmp / f"{tag}.sqlite", run_fn=run_fn)
    t0 = time.perf_counter()
    first_error = None
    n = 0
    for row in plan.execute(executor):
        n += 1
        if row["status"] == "error" and first_error is None:
            first_error = (row.get("error") or "").strip().splitlines()[-1:]
    wall = time.perf_counter() - t0
    errors = plan.summary.errors
    plan.close()
    if errors:
        raise RuntimeError(f"benchmark {tag}: {errors} of {n} runs raised, e.g. {first_error}")
    return wall


def bench(preset: str = "case-d", robots: int = 9, void_width: int = 3, runs: int = 8,
          limits: str = "derived", run_fn: str = DEFAULT_RUN_FN, max_time_s: float | None = None,
          overhead_runs: int = 200, dask: bool = True, repeat: int = 1, echo=lambda s: None) -> dict:
    """Configurations are interleaved ``repeat`` times (local-1, local-2, dask-2, local-1, ...) and
    each reports its best round (least disturbed by other load), as ``timeit`` does."""
    spec = SweepSpec(preset, (robots,), (void_width,), runs=runs, limits=limits, max_time_s=max_time_s)
    synth = SweepSpec(preset, (robots,), (void_width,), runs=overhead_runs, limits=limits)
    configs = [("local", 1), ("local", 2)] + ([("dask", 2)] if dask else [])
    out: dict = {"preset": preset, "robots": robots, "void_width": void_width, "runs": runs,
                 "limits": limits, "run_fn": run_fn, "repeat": repeat, "configs": {}}
    with tempfile.TemporaryDirectory(prefix="voidcross-bench-") as d:
        tmp = Path(d)
        for rep in range(repeat):
            for kind, workers in configs:
                tag = f"{kind}-{workers}"
                echo(f"bench: round {rep + 1}/{repeat} {tag} ...")
                ex = LocalExecutor(workers) if kind == "local" else DaskExecutor(workers=workers)
                t_start = time.perf_counter()
                with ex:
                    startup = time.perf_counter() - t_start
                    wall = _timed(spec, ex, run_fn, tmp, f"{tag}-{rep}")
                    synth_wall = _timed(synth, ex, SYNTHETIC, tmp, f"{tag}-{rep}-synthetic")
                echo(f"bench: {tag}: {60.0 * runs / wall:.1f} runs/min, "
                     f"{1000.0 * synth_wall / overhead_runs:.2f} ms overhead per run")
                prev = out["configs"].get(tag)
                rounds = (prev["rounds_wall_s"] if prev else []) + [wall]
                wall_best = min(rounds)
                synth_best = min(synth_wall, prev["overhead_ms_per_run"] * overhead_runs / 1000.0) if prev else synth_wall
                out["configs"][tag] = {
                    "executor": kind, "workers": workers, "wall_s": wall_best, "rounds_wall_s": rounds,
                    "runs_per_min": 60.0 * runs / wall_best, "wall_s_per_run": wall_best / runs,
                    "startup_s": startup, "overhead_ms_per_run": 1000.0 * synth_best / overhead_runs,
                }
    c = out["configs"]
    if "dask-2" in c:
        loc, dsk = c["local-2"]["wall_s_per_run"], c["dask-2"]["wall_s_per_run"]
        out["dask_overhead_vs_local_2"] = (dsk - loc) / loc
        out["dask_extra_ms_per_run_synthetic"] = (c["dask-2"]["overhead_ms_per_run"]
                                                  - c["local-2"]["overhead_ms_per_run"])
        # the robust figure on a shared machine: the executor's own extra cost per run (zero-work
        # runs) as a fraction of one real run on the local pool
        out["dask_extra_overhead_fraction"] = out["dask_extra_ms_per_run_synthetic"] / (1000.0 * loc)
    out["speedup_2_vs_1_local"] = c["local-1"]["wall_s"] / c["local-2"]["wall_s"]
    return out
