"""The optimiser's search space and objective read like the issue: tunables of the behaviour
only, the thesis's values as the start, penalties for what a rule set must never do."""

from __future__ import annotations

import json

import numpy as np
import pytest

from swarm_sim.errors import InputError
from swarm_sim.optimise import DEFAULT_PARAMS, Penalties, SearchSpace, score_runs, training_cells
from swarm_sim.params import Params
from swarm_sim.tunables import KINDS, TUNABLES


def test_every_tunable_has_a_kind_and_the_default_subset_tunes_at_least_six_rules():
    assert {t.kind for t in TUNABLES} <= set(KINDS)
    assert len(DEFAULT_PARAMS) >= 6
    assert all(t.kind != "robot" for t in SearchSpace().tunables)


def test_the_start_point_is_the_thesis_values_and_maps_back_to_them():
    space = SearchSpace()
    x0 = space.start()
    assert np.all((x0 >= 0) & (x0 <= 1))
    back = space.values(x0)
    for name, v in back.items():
        assert v == pytest.approx(getattr(Params(), name), rel=1e-5)


def test_wide_ranges_are_searched_on_a_log_scale_and_whole_numbers_stay_whole():
    space = SearchSpace(("recruit_stall_s", "levy_mu", "heartbeat_misses"))
    mid = space.values(np.full(3, 0.5))
    assert mid["recruit_stall_s"] == pytest.approx((0.1 * 200.0) ** 0.5, rel=1e-5)  # geometric middle
    assert mid["levy_mu"] == pytest.approx((1.1 + 3.0) / 2)
    assert isinstance(mid["heartbeat_misses"], int)
    assert space.values(np.array([2.0, -1.0, 0.0])) == {"recruit_stall_s": 200.0, "levy_mu": 1.1,
                                                         "heartbeat_misses": 1}  # clipped to the ranges


@pytest.mark.parametrize("names, says", [
    (("speed_cm_s",), "robot's body"), (("levy_mu", "nope"), "not a tunable"), ((), "empty"),
    (("levy_mu", "levy_mu"), "twice")])
def test_a_bad_search_space_is_one_error_naming_it(names, says):
    with pytest.raises(InputError, match=says):
        SearchSpace(names)


def test_training_cells_straddle_the_counting_rule_of_the_limits():
    cells = training_cells("a,d", "thesis", (2,))
    d = [c.robots for c in cells if c.case == "D"]
    a = [c.robots for c in cells if c.case == "A"]
    assert d == [5, 6, 7]  # 3w = 6: one below, the boundary, one above
    assert a == [7, 8, 10]  # 3w + 2 = 8 in the grid 5, 7, 8, 10
    with pytest.raises(InputError, match="--cases"):
        training_cells("e", "thesis")


def _row(robots=9, rule=9, success=True, tt=100.0, lost=0, timed_out=False, status="ok"):
    return {"status": status, "robots": robots, "success": int(success), "t_t": tt, "robots_lost": lost,
            "result_json": json.dumps({"min_robots_rule": rule, "timed_out": timed_out})}


def test_the_value_is_the_mean_crossing_time_when_every_run_does_what_it_should():
    s = score_runs([_row(tt=100.0), _row(tt=200.0), _row(robots=6, success=False)])
    assert s.value == pytest.approx(150.0) and s.should_cross == 2 and s.mean_tt_s == pytest.approx(150.0)


@pytest.mark.parametrize("bad, field, charge", [
    (_row(success=False), "no_cross", Penalties().no_cross_s),
    (_row(robots=6, success=True), "below_rule", Penalties().below_rule_s),
    (_row(robots=6, success=False, lost=2), "robots_lost", 2 * Penalties().lost_robot_s),
    (_row(robots=6, success=False, timed_out=True), "timeouts", Penalties().timeout_s),
    (_row(status="error"), "errors", Penalties().error_s),
])
def test_each_penalty_is_charged_for_what_a_rule_set_must_not_do(bad, field, charge):
    good = [_row(tt=100.0), _row(tt=100.0)]
    base = score_runs(good)
    s = score_runs([*good, bad])
    assert getattr(s, field) >= 1
    should = base.should_cross + (bad["robots"] >= 9 or bad["status"] != "ok")
    assert s.value == pytest.approx((200.0 + charge) / should)
    assert s.value > base.value
    # and the penalty is an input: halving it moves the value
    half = Penalties(**{k: v / 2 for k, v in Penalties().__dict__.items()})
    assert score_runs([*good, bad], half).value < s.value


def test_penalties_are_seconds_at_or_above_zero():
    with pytest.raises(InputError, match="no_cross_s"):
        Penalties(no_cross_s=-1)
