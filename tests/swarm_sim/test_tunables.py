"""The behaviour's tunables (issue 39, deliverable 1): one table, the defaults the runs use, and
a value outside its range refused as one error line before any run."""

from __future__ import annotations

from dataclasses import fields

import pytest

from swarm_sim.errors import InputError
from swarm_sim.params import Params, load_preset, with_overrides
from swarm_sim.tunables import TUNABLES, table


def test_every_tunable_is_a_parameter_of_the_run_with_its_default_inside_its_range():
    names = {f.name for f in fields(Params)}
    for t in TUNABLES:
        assert t.name in names, t.name
        assert t.lo <= getattr(Params(), t.name) <= t.hi, t.name
        assert t.unit and t.changes and t.source, t.name
    assert len({t.name for t in TUNABLES}) == len(TUNABLES)


def test_every_preset_keeps_its_tunables_in_range():
    from swarm_sim.params import preset_names

    for name in preset_names():
        p = load_preset(name)
        for t in TUNABLES:
            assert t.lo <= getattr(p, t.name) <= t.hi, (name, t.name)


@pytest.mark.parametrize("name, bad", [("stall_s", 1.0), ("levy_mu", 5.0), ("heartbeat_misses", 0),
                                       ("speed_cm_s", float("nan")), ("random_turn_prob", 1.5)])
def test_a_value_outside_its_range_is_one_error_naming_it_and_the_range(name, bad):
    t = next(t for t in TUNABLES if t.name == name)
    with pytest.raises(InputError, match=rf"{name}=.* outside its range {t.lo:g}\.\.{t.hi:g}"):
        with_overrides(Params(), {name: bad}, "--set")


def test_a_value_inside_its_range_is_the_run_s_value():
    assert with_overrides(Params(), {"recruit_stall_s": 10.0}).recruit_stall_s == 10.0


def test_the_command_lists_the_table(cli):
    res = cli("sim", "params", "--json")
    assert res.code == 0
    assert res.json()["tunables"] == table(Params())
    res = cli("sim", "run", "--preset", "case-d", "--robots", "9", "--void-width", "2", "--set", "stall_s=5")
    assert res.code == 2 and "stall_s" in res.err and "10..1000" in res.err
