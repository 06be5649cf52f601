"""Sweep throughput benchmark (make bench): case D, 9 robots, 3-wide void; 1 and 2 local workers and
2 Dask workers, and the Dask overhead per run relative to the local pool, measured in one run.
Numbers go to the benchmark's extra_info; nothing here asserts a time."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.bench


def test_sweep_throughput_local_and_dask(benchmark):
    pytest.importorskip("swarm_sim.runner")
    pytest.importorskip("distributed")
    from swarm_sim.sweeps.bench import bench

    res = benchmark.pedantic(bench, kwargs={"runs": 6}, rounds=1, iterations=1)
    benchmark.extra_info.update({
        **{f"{tag}_runs_per_min": c["runs_per_min"] for tag, c in res["configs"].items()},
        **{f"{tag}_overhead_ms_per_run": c["overhead_ms_per_run"] for tag, c in res["configs"].items()},
        "dask_overhead_vs_local_2": res["dask_overhead_vs_local_2"],
        "speedup_2_vs_1_local": res["speedup_2_vs_1_local"],
    })
    print(res)
    assert set(res["configs"]) == {"local-1", "local-2", "dask-2"}
    assert all(c["runs_per_min"] > 0 for c in res["configs"].values())
