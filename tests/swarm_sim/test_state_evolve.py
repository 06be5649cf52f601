"""state.evolve is dataclasses.replace for the per-step records, only cheaper."""

from dataclasses import replace

import numpy as np
import pytest

from swarm_sim.params import Params
from swarm_sim.state import Structure, evolve, new_state


def _records():
    s = new_state(np.arange(4.0), np.ones(4), np.zeros(4))
    st = Structure((2, 0, -1), 10.0, 20.0, 1.0, 0.0, 3.5, recruits=(1,), recruit_best_cm=(4.0,))
    return s, st


@pytest.mark.parametrize("changes", [{"front_s_cm": 7.25}, {"members": (1, 2), "action": "wait", "landed": True}, {}])
def test_a_structure_evolved_equals_the_one_replace_builds(changes):
    _, st = _records()
    new = evolve(st, **changes)
    assert new == replace(st, **changes) and type(new) is Structure
    assert new is not st and st.front_s_cm == 3.5 and st.action == "align"  # the old record is untouched
    assert hash(new) == hash(replace(st, **changes))


def test_a_state_evolved_shares_the_arrays_it_does_not_change_as_replace_does():
    s, st = _records()
    x = np.full(4, 9.0)
    new = evolve(s, x_cm=x, t_s=1.5, structure=st)
    ref = replace(s, x_cm=x, t_s=1.5, structure=st)
    for name in ("x_cm", "y_cm", "heading_rad", "mode", "struct_index"):
        assert getattr(new, name) is getattr(ref, name)
    assert (new.t_s, new.structure, new.step, new.events) == (ref.t_s, ref.structure, ref.step, ref.events)
    with pytest.raises(AttributeError):  # still frozen
        new.t_s = 2.0


def test_an_unknown_field_is_refused_as_replace_refuses_it():
    s, st = _records()
    with pytest.raises(TypeError, match="front_cm"):
        evolve(st, front_cm=1.0)
    with pytest.raises(TypeError, match="speed"):
        evolve(s, speed=1.0)


def test_another_record_goes_through_replace_and_its_checks():
    p = Params()
    assert evolve(p, robots=12) == replace(p, robots=12)
