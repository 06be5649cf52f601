"""Benchmarks (make bench; excluded from make test): goals 0.2 s per 15-robot line solve, 60 s per table."""

from __future__ import annotations

import pytest

pytest.importorskip("exudyn")

from structure_fem.model import Config  # noqa: E402
from structure_fem.model import solve_uncached as solve  # noqa: E402  (the solver, not the solve cache)
from structure_fem.runs import RunOptions, run_table  # noqa: E402
from structure_fem.structures import Structure  # noqa: E402
from structure_fem.study import StudyInputs  # noqa: E402


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
