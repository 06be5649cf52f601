"""Benchmarks (``make bench``; excluded from ``make test``): exploration step throughput."""

from __future__ import annotations

import pytest

from swarm_sim.bench import _setup
from swarm_sim.step import step


@pytest.mark.bench
@pytest.mark.parametrize("robots", [1_000, 10_000])
def test_exploration_step(benchmark, robots):
    p, world, rng, s = _setup(robots, 0, 0.05)
    s = step(s, p, world, rng)  # compile / warm up
    state = {"s": s}

    def one():
        state["s"] = step(state["s"], p, world, rng)

    benchmark(one)
    benchmark.extra_info["robot_steps_per_s"] = robots / benchmark.stats.stats.mean
