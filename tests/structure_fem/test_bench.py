"""Benchmarks (make bench; excluded from make test): goals 0.2 s per 15-robot line solve, 60 s per table."""

from __future__ import annotations

import pytest

pytest.importorskip("exudyn")

from structure_fem.analysis.study import StudyInputs  # noqa: E402
from structure_fem.model.statics import Config  # noqa: E402
from structure_fem.model.statics import solve_uncached as solve  # noqa: E402  (the solver, not the solve cache)
from structure_fem.model.structures import Structure  # noqa: E402
from structure_fem.outputs.runs import RunOptions, run_table  # noqa: E402


@pytest.mark.bench
def test_bench_one_15_robot_line_solve(benchmark, cubot):
    inp = StudyInputs.for_robot(cubot)
    cfg = Config(Structure("line"), 15, 5, 5)
    res = benchmark(solve, cfg, cubot, inp.connectors)
    assert res.robots == 15
    if benchmark.stats:
        benchmark.extra_info["ratio_to_goal_0.2s"] = benchmark.stats.stats.mean / 0.2


@pytest.mark.bench
def test_bench_whole_table(benchmark, tmp_path):
    out = benchmark.pedantic(run_table, args=(tmp_path, RunOptions()), kwargs={"alternative": False, "plots": False},
                             rounds=1, iterations=1)
    assert len(out["table"]) == 30
    if benchmark.stats:
        benchmark.extra_info["ratio_to_goal_60s"] = benchmark.stats.stats.mean / 60.0


@pytest.mark.bench
def test_bench_all_packaged_connector_fe_cold(benchmark, tmp_path):
    """Issue 12's goal: every packaged connector FE from nothing <= 5 min (2 processes)."""
    from structure_fem.couplings.connector_sources import PACKAGED_FINDERS, compute_packaged_fe

    results, _wall, _per = benchmark.pedantic(compute_packaged_fe, args=(tmp_path,),
                                              kwargs={"workers": 2, "packaged": False}, rounds=1, iterations=1)
    assert len(results) == sum(len(f) for f in PACKAGED_FINDERS.values())
    if benchmark.stats:
        benchmark.extra_info["ratio_to_goal_300s"] = benchmark.stats.stats.mean / 300.0
