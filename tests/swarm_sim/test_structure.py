"""The stability rule is exact on the rigid line, and its inputs (the limits) move its result."""

from __future__ import annotations

from dataclasses import replace

import pytest

from swarm_sim.behaviour import rule as R
from swarm_sim.behaviour import structure as S
from swarm_sim.params import Params
from swarm_sim.state import Structure

THESIS = replace(Params(), ground_ratio=2.0, ground_margin=0, max_span_widths=5)


def counts(front_widths: float, n: int, w: int) -> R.Counts:
    return S.counts_at(front_widths * 10.0, n, 10.0, w * 10.0)


def test_counts_by_centre_of_mass():
    assert counts(0, 3, 1) == R.Counts(3, 0, 0)
    assert counts(1, 3, 1) == R.Counts(2, 1, 0)
    assert counts(2, 3, 1) == R.Counts(1, 1, 1)
    assert counts(3, 3, 1) == R.Counts(0, 1, 2)
    assert counts(3.4, 3, 2) == R.Counts(0, 2, 1)   # centres at 2.9, 1.9, 0.9 widths


def test_uniform_rows_are_counted_as_the_row_by_row_pass_counts_them_at_every_edge():
    """rule.counts finds the rows on each ground of a uniform structure by binary search; it
    must agree with the pass over every row (weights of 1), above all with a row centre right
    on an edge (within EPS either way) and for fronts before, over and past the void."""
    import random

    rnd = random.Random(5)
    for _ in range(20000):
        n = rnd.randint(0, 60)
        L = rnd.choice([1.0, 10.0, 7.3, 0.1 * rnd.randint(1, 200)])
        void = rnd.choice([L * rnd.randint(1, 30), rnd.uniform(0.5, 300.0)])
        k = rnd.randint(-5, n + 5)
        nudge = rnd.choice([0.0, R.EPS, -R.EPS, 1e-12, -1e-12, 2e-6])
        front = rnd.choice([(k + 0.5) * L + nudge, void + (k + 0.5) * L + nudge, rnd.uniform(-50.0, 400.0)])
        shell = rnd.choice([(0, 0, 0), (2, 1, 3)])
        fast, slow = R.counts(front, n, L, void, shell), R.counts(front, (1,) * n, L, void, shell)
        assert (fast.n_p, fast.n_g, fast.n_o, fast.span_rows) == (slow.n_p, slow.n_g, slow.n_o, slow.span_rows)


def test_a_move_is_checked_at_every_crossing_as_a_pass_over_every_row_would_find_them():
    """rule.move_stable looks only at the rows whose centre can cross an edge on the move; it
    must answer as the check at every row's crossing does (the rule's spec, written out here)."""
    import random

    def every_row(a, b, rows, L, void, ratio, margin, span):
        lo, hi = min(a, b), max(a, b)
        pts = [a, b]
        for k in range(rows):
            for edge in (0.0, void):
                f = edge + (k + 0.5) * L
                if lo - R.EPS <= f <= hi + R.EPS:
                    pts += [f - 10 * R.EPS, f + 10 * R.EPS]
        return all(R.stable(R.counts(f, (1,) * rows, L, void), ratio, margin, span)
                   for f in pts if lo - 20 * R.EPS <= f <= hi + 20 * R.EPS)

    rnd = random.Random(8)
    seen = set()
    for _ in range(5000):
        n, L = rnd.randint(1, 40), rnd.choice([1.0, 10.0, 7.3])
        void = L * rnd.randint(1, 12)
        a = rnd.choice([0.0, void]) + (rnd.randint(-2, n + 2) + 0.5) * L + rnd.choice([0.0, R.EPS, -R.EPS, 1e-12])
        b = a + rnd.choice([L, -L, rnd.uniform(-2 * L, 2 * L)])
        args = (n, L, void, rnd.choice([1.0, 2.0]), rnd.choice([0, 1]), rnd.randint(1, 12))
        want = every_row(a, b, *args)
        assert R.move_stable(a, b, *args) == want
        seen.add(want)
    assert seen == {True, False}


@pytest.mark.parametrize("c,ok", [
    (R.Counts(2, 1, 0), True), (R.Counts(1, 1, 0), False),        # n_p = 2 n_g to hold the cantilever
    (R.Counts(6, 3, 0), True), (R.Counts(5, 3, 0), False),
    (R.Counts(3, 3, 3), True), (R.Counts(2, 3, 3), False),        # bridged: n_p = n_g = n_o
    (R.Counts(0, 2, 4), True), (R.Counts(0, 2, 3), False),        # cantilever from the target side
    (R.Counts(0, 1, 0), False), (R.Counts(4, 0, 0), True),
])
def test_thesis_rule(c, ok):
    assert R.stable(c, *THESIS.rule) is ok


def test_rule_moves_with_the_limits():
    assert not R.stable(R.Counts(3, 2, 0), *THESIS.rule)
    assert R.stable(R.Counts(3, 2, 0), *replace(THESIS, ground_ratio=1.0, ground_margin=1).rule)
    assert not R.stable(R.Counts(4, 1, 0), *replace(THESIS, ground_margin=3).rule)
    assert not R.stable(R.Counts(20, 6, 0), *THESIS.rule)                      # wider than the line may span


def line(n: int, front_widths: float, landed=False, retreating=False) -> Structure:
    return Structure(members=tuple(range(n)), origin_x_cm=235.0, origin_y_cm=150.0, dir_x=1.0, dir_y=0.0,
                     front_s_cm=front_widths * 10.0, action="idle", landed=landed, retreating=retreating)


def params(w: int, **kw) -> Params:
    return replace(THESIS, void_width=w, **kw)


def test_decision_table_launch_recruit_advance_retreat():
    p = params(3)
    assert S.decide(line(1, 0), p, True, True)[0] == "recruit"          # fewer than 3: recruit
    assert S.decide(line(3, 0), p, True, True)[0] == "advance"          # 3 robots: launch
    assert S.decide(line(3, 1), p, True, True)[0] == "recruit"          # (2,1,0): n_p = 2 n_g, recruit
    assert S.decide(line(6, 2), p, False, True)[0] == "retreat"         # no free robot, no far ledge
    assert S.decide(line(6, 2), p, True, True)[0] == "recruit"
    assert S.decide(line(6, 2), p, True, False)[0] == "retreat"         # dock point off the arena


def test_decision_table_bridged_and_delivery():
    p = params(1)
    assert S.decide(line(3, 1, landed=True), p, False, True)[0] == "advance"       # (2,1,0) -> (1,1,1)
    assert S.decide(line(3, 2, landed=True), p, True, True)[0] == "recruit"        # (1,1,1): keep n_p
    assert S.decide(line(4, 2, landed=True), p, True, True)[0] == "release_front"  # (2,1,1) -> (2,1,0)
    assert S.decide(line(3, 3, landed=True), p, False, True)[0] == "advance"       # (0,1,2) can't release
    assert S.decide(line(3, 4, landed=True), p, False, True)[0] == "release_front"


def test_retreat_table_releases_rear_only_when_stable():
    p = params(2)
    assert S.decide(line(5, 1, retreating=True), p, False, True)[0] == "release_rear"  # (4,1,0) -> (3,1,0)
    assert S.decide(line(3, 1, retreating=True), p, False, True)[0] == "back"          # (2,1,0) needs all
    assert S.decide(line(1, 0, retreating=True), p, False, True)[0] == "release_rear"


def test_span_limit_forces_retreat():
    p = params(3, max_span_widths=2)
    assert S.decide(line(9, 2), p, True, True)[0] == "retreat"


def test_moves_checked_through_every_intermediate_configuration():
    p = params(1)
    assert R.move_stable(0.0, 10.0, 3, 10.0, p.void_width_cm, *p.rule)
    assert not R.move_stable(0.0, 10.0, 2, 10.0, p.void_width_cm, *p.rule)
    assert R.move_stable(10.0, 20.0, 3, 10.0, p.void_width_cm, *p.rule)          # (2,1,0) -> (1,1,1)
