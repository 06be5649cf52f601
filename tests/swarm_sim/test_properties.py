"""Property-based: any case, swarm size, void width, arena size and seed keeps the invariants."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from structure_fem.limits import packaged_limits_path
from swarm_sim.errors import InputError
from swarm_sim.runner import resolve_params, simulate

LIMITS = ["thesis", "derived"] if packaged_limits_path().exists() else ["thesis"]


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=st.sampled_from(["case-a", "case-b", "case-c", "case-d"]),
       robots=st.integers(1, 24), width=st.integers(1, 5),
       arena_w=st.integers(250, 700), arena_h=st.integers(120, 400),
       seed=st.integers(0, 2**31 - 1), limits=st.sampled_from(LIMITS), structure=st.sampled_from(["line", "auto"]))
def test_invariants_hold_on_short_runs(case, robots, width, arena_w, arena_h, seed, limits, structure):
    try:
        p = resolve_params(case, robots, width, limits, 25.0, arena_w_cm=float(arena_w),
                           arena_h_cm=float(arena_h), target_x_cm=arena_w - 20.0, target_y_cm=arena_h / 2,
                           structure=structure)
        state, res = simulate(p, seed, check=True)
    except InputError as exc:  # a draw that is not a valid scenario must be rejected clearly
        assert str(exc)
        return
    assert res.violations == []
    assert res.robots_lost == 0
    assert state.n == robots
