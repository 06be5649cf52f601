"""The thesis's crossing boundaries at scale (issue 13; ``make boundary``, also in ``make bench``):
for each of cases A-D, 50 seeds spread over several void widths, the thesis's minimum swarm
(3w + 2 for case A, 3w for B-D) crosses and one robot fewer retreats, every time, with 0 lost
and 0 runs reaching the time-limit guard."""

from __future__ import annotations

import multiprocessing as mp
import os

import pytest

from swarm_sim.runner import resolve_params, run_scenario

SEEDS = int(os.environ.get("VOIDCROSS_BOUNDARY_SEEDS", "50"))
WIDTHS = {"case-a": (1, 2, 3, 4, 5), "case-b": (1, 2, 3, 4, 5), "case-c": (1, 2, 3, 4, 5), "case-d": (1, 2, 3, 4, 5)}


def arena(preset: str, w: int) -> dict:
    """Case A's 250 cm arena holds the line's 2w + 2 ground rows only up to w = 2 (beyond, the
    rear dock point falls off the arena and the swarm retreats, ``retreated-blocked``): wider
    voids get an arena long enough for them, (5w + 12) robot lengths (the thesis ran w = 5 in 700 cm)."""
    if preset != "case-a" or w <= 2:
        return {}
    a = (5 * w + 12) * 12.0
    return {"arena_w_cm": a, "target_x_cm": a - 12.5}


def _pair(args):
    preset, w, seed = args
    kw = arena(preset, w)
    n = resolve_params(preset, 9, w, "thesis", **kw).min_robots_rule
    ok = run_scenario(preset, n, w, seed, limits="thesis", **kw)
    below = run_scenario(preset, n - 1, w, seed, limits="thesis", **kw)
    return (preset, w, seed, n, ok.success, ok.timed_out, ok.robots_lost, below.retreated, below.timed_out,
            below.robots_lost, ok.end_reason, below.end_reason)


@pytest.mark.bench
@pytest.mark.parametrize("preset", sorted(WIDTHS))
def test_boundary_holds_on_every_seed(preset):
    widths = WIDTHS[preset]
    jobs = [(preset, widths[i % len(widths)], 20_000 + i) for i in range(SEEDS)]
    with mp.get_context("spawn").Pool(min(2, os.cpu_count() or 1)) as pool:
        rows = pool.map(_pair, jobs, chunksize=2)
    bad = [r for r in rows if not (r[4] and not r[5] and r[6] == 0 and r[7] and not r[8] and r[9] == 0)]
    crossed = sum(r[4] for r in rows)
    retreated = sum(r[7] for r in rows)
    print(f"{preset}: {len(rows)} seeds over widths {widths}: minimum crossed {crossed}, one fewer retreated "
          f"{retreated}, timeouts {sum(r[5] + r[8] for r in rows)}, lost {sum(r[6] + r[9] for r in rows)}")
    assert not bad, bad[:5]
