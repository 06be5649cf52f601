"""The fault model (issue 16): named modes, rates or a schedule, seeded, on its own stream."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarm_sim.errors import InputError
from swarm_sim.faults import (
    DRIVE,
    SENSOR,
    TOTAL,
    Fault,
    FaultSpec,
    draw_schedule,
    expected_failed_fraction,
    from_table,
    parse_faults,
    rate_for_fraction,
)


def test_the_command_line_form_gives_rates_per_hour_and_scheduled_faults():
    spec = parse_faults("drive:0.5/h,sensor:1/min,3@120:drive,7@300.5:total")
    assert spec.rates_per_h == {"drive": 0.5, "sensor": 60.0}
    assert spec.schedule == (Fault(3, 120.0, "drive"), Fault(7, 300.5, "total"))
    assert parse_faults("total:0.001/s").rates_per_h == {"total": 3.6}
    assert parse_faults("none").empty and parse_faults("").empty and parse_faults("drive:0/h").empty
    assert spec.describe() == "drive:0.5/h,sensor:60/h,3@120:drive,7@300.5:total"


@pytest.mark.parametrize("text, needle", [
    ("wheels:0.5/h", "'wheels'"), ("drive:-1/h", "-1"), ("drive:x/h", "'x'"), ("drive:0.5", "drive:0.5"),
    ("drive:nan/h", "nan"), ("3@-1:drive", "-1"), ("3.5@10:drive", "'3.5'"), ("3@10:wheels", "'wheels'"),
    ("drive:1/h,,sensor:1/h", "empty item"), ("drive:1/h,drive:2/h", "twice"), ("drive:1e9/h", "per hour"),
])
def test_a_bad_fault_item_is_one_error_naming_it(text, needle):
    with pytest.raises(InputError) as e:
        parse_faults(text)
    assert needle in str(e.value) and "\n" not in str(e.value)


def test_a_preset_table_gives_the_same_spec():
    t = from_table({"drive_per_h": 0.5, "schedule": [[3, 120, "drive"]]})
    assert t == parse_faults("drive:0.5/h,3@120:drive")
    for bad in ({"wheels_per_h": 1}, {"drive_per_h": "fast"}, {"schedule": [[3, "later", "drive"]]}, {"speed": 1}):
        with pytest.raises(InputError):
            from_table(bad)


def test_a_scheduled_robot_must_exist():
    with pytest.raises(InputError, match="no robot 9 in a swarm of 9"):
        draw_schedule(parse_faults("9@10:drive"), 9, 1000.0, 0)


def test_the_draw_is_seeded_sorted_and_on_its_own_stream():
    spec = parse_faults("drive:2/h,total:1/h,5@10:sensor")
    a, b = draw_schedule(spec, 200, 3600.0, 7), draw_schedule(spec, 200, 3600.0, 7)
    assert np.array_equal(a.robot, b.robot) and np.array_equal(a.t_s, b.t_s) and np.array_equal(a.bits, b.bits)
    c = draw_schedule(spec, 200, 3600.0, 8)
    assert not np.array_equal(a.t_s, c.t_s)
    assert np.all(np.diff(a.t_s) >= 0) and np.all(a.t_s <= 3600.0)
    assert (5, 10.0, SENSOR) in zip(a.robot.tolist(), a.t_s.tolist(), a.bits.tolist(), strict=True)
    # the run's own generator is never touched: a fault draw between two uses changes nothing
    rng = np.random.default_rng(7)
    first = rng.random(3)
    draw_schedule(spec, 200, 3600.0, 7)
    rest = rng.random(3)
    ref = np.random.default_rng(7).random(6)
    assert np.array_equal(np.r_[first, rest], ref)


def test_rates_give_the_poisson_fraction_of_failed_robots():
    """A rate lambda per robot per hour fails 1 - exp(-lambda t) of the swarm by time t."""
    spec = parse_faults("drive:0.5/h")
    t = 1800.0
    want = expected_failed_fraction(spec, t)
    assert want == pytest.approx(1 - math.exp(-0.25))
    got = np.mean([len(draw_schedule(spec, 1000, t, s)) / 1000 for s in range(20)])
    assert got == pytest.approx(want, abs=0.01)  # 20,000 robots: sd of the mean ~0.003
    assert rate_for_fraction(0.10, 1000.0) == pytest.approx(-math.log(0.9) * 3.6)
    assert expected_failed_fraction(parse_faults(f"drive:{rate_for_fraction(0.1, 1000.0)}/h"), 1000.0) \
        == pytest.approx(0.10)


def test_faults_accumulate_and_total_disables_everything():
    s = draw_schedule(parse_faults("1@10:drive,1@20:sensor,2@5:total"), 3, 100.0, 0)
    assert s.state_at(4.9, 3).tolist() == [0, 0, 0]
    assert s.state_at(10.0, 3).tolist() == [0, DRIVE, DRIVE | SENSOR | TOTAL]
    assert s.state_at(20.0, 3)[1] == DRIVE | SENSOR
    assert [e[1:3] for e in s.events()] == [("fault", 2), ("fault", 1), ("fault", 1)]
    assert s.events()[0][3] == {"mode": "total"} and TOTAL == 4


def test_no_rate_and_no_schedule_draws_nothing():
    assert len(draw_schedule(FaultSpec(), 50, 1e4, 1)) == 0
    assert len(draw_schedule(parse_faults("drive:0/h"), 50, 1e4, 1)) == 0
