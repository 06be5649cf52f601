"""Connectors, structure descriptions, layouts and the solver's typed result and failures."""

from __future__ import annotations

import math

import pytest

pytest.importorskip("exudyn")

from structure_fem.errors import InputError, SolverFailure  # noqa: E402
from structure_fem.model.connectors import ConnectorSet, Joint, dead_band_moment  # noqa: E402
from structure_fem.model.statics import Config, SolverOptions, solve  # noqa: E402
from structure_fem.model.structures import Structure, layout  # noqa: E402


def test_dead_band_is_free_inside_and_linear_outside():
    k, h = 100.0, 0.01
    assert dead_band_moment(0.0, k, h) == 0.0
    assert abs(dead_band_moment(0.5 * h, k, h)) < 0.02 * k * h  # (almost) free inside the band
    assert dead_band_moment(0.1, k, h) == pytest.approx(k * (0.1 - h), rel=1e-3)
    assert dead_band_moment(-0.1, k, h) == pytest.approx(-dead_band_moment(0.1, k, h))
    assert dead_band_moment(0.3, k, 0.0) == k * 0.3


@pytest.mark.parametrize("kw", [dict(rotational_nm_per_rad=0.0), dict(rotational_nm_per_rad=-5.0),
                                dict(axial_n_per_m=0.0), dict(backlash_rad=-0.1), dict(backlash_rad=0.6)])
def test_joint_rejects_bad_values(kw):
    base = dict(kind="front_rear", rotational_nm_per_rad=10.0, axial_n_per_m=1e5)
    with pytest.raises(InputError):
        Joint(**{**base, **kw})


@pytest.mark.parametrize("args,word", [(("arch", 9, 2), "8 wide"), (("arch", 8, 5), "4 high"),
                                       (("line", 2, 1), "1 x 1"), (("arch", 4, 1), "2 layers"),
                                       (("tower", 1, 1), "tower")])
def test_structure_beyond_limits_is_input_error(args, word):
    with pytest.raises(InputError, match=word):
        Structure(*args)


def test_robot_counts_follow_the_cross_section():
    assert Structure("line").robots(9) == 9
    assert Structure("two_line", 2, 1, "aligned").robots(9) == 18
    assert Structure("two_line", 2, 1, "staggered").robots(9) == 9 + 8  # offset line is one shorter
    assert Structure("arch", 8, 4, "staggered").robots(5) == 4 * (5 * 4 + 4 * 4)


def test_layout_rests_rows_on_the_right_ledge(robot):
    conn = ConnectorSet.from_robot(robot)
    lay = layout(Structure("line"), robot, conn, 7, 3, 3)
    assert {s.ledge for s in lay.supports} == {"near"}
    assert len(lay.supports) == 2 * 4  # four rows behind the edge, two corners each
    bridged = layout(Structure("line"), robot, conn, 7, 5, 3, "bridged")
    assert sum(s.ledge == "far" for s in bridged.supports) == 2 * 2
    with pytest.raises(InputError, match="past the far ledge"):
        layout(Structure("line"), robot, conn, 7, 4, 3)
    with pytest.raises(InputError, match="void width"):
        layout(Structure("line"), robot, conn, 7, 0, -1)


def test_layers_need_a_top_connector(make_robot):
    from dataclasses import replace

    robot = make_robot()
    bare = replace(robot, connectors=robot.connectors[:1])
    with pytest.raises(InputError, match="top_twist"):
        solve(Config(Structure("arch", 1, 2, "aligned"), 5, 2, 2), bare)
    with pytest.raises(InputError, match="side_rail"):
        solve(Config(Structure("two_line", 2, 1), 5, 2, 2), bare)


def test_result_is_typed_and_balanced(robot):
    res = solve(Config(Structure("line"), 9, 4, 4), robot)
    assert res.robots == 9
    assert res.tip_deflection_m > 0 and res.tip_deflection_m == pytest.approx(res.max_deflection_m)
    assert res.reactions_n.sum() == pytest.approx(res.total_weight_n, rel=1e-6)
    assert len(res.joint_rotation_rad) == 8
    assert all(r <= 1e-9 for r in res.joint_rotation_rad[:4])  # hogging: every overhang joint turns nose-down
    # Rigid tipping about the edge of a uniform line: (n_p / n_g)^2 = (5/4)^2; deflection moves it a hair.
    assert res.tipping_factor == pytest.approx((5 / 4) ** 2, rel=0.01)


@pytest.mark.parametrize("k", [2e3, 1e5])
def test_backlash_adds_a_rigid_droop(make_robot, k):
    """A dead band b lets each of the w overhang joints (at distances a..w a from the tip) turn
    freely by b: b a w (w + 1) / 2. The row resting at the edge also pivots about the edge
    corner by b (its rear lifts until the joint behind it takes up its own play), adding
    b w a: in all b a w (w + 3) / 2, independent of the spring stiffness."""
    from dataclasses import replace

    from structure_fem.model.connectors import ConnectorSet

    def lumped(r):  # the record's pitch dead band is the lumped hinge's (the emergent one has none)
        return replace(ConnectorSet.from_robot(r), hinge="lumped")

    w, b = 3, 0.002
    r0, r1 = make_robot(k=k), make_robot(k=k, backlash=b)
    d0 = solve(Config(Structure("line"), 7, w, w), r0, lumped(r0)).tip_deflection_m
    d1 = solve(Config(Structure("line"), 7, w, w), r1, lumped(r1)).tip_deflection_m
    # 2 %: the weak spring that fixes unloaded joints inside their play takes <= 1 % of m g L.
    assert d1 - d0 == pytest.approx(b * 0.1 * w * (w + 3) / 2, rel=0.02)


def test_solver_failure_names_the_configuration(robot):
    with pytest.raises(SolverFailure, match=r"testbot line 9 rows, 4 over a 4-wide void"):
        solve(Config(Structure("line"), 9, 4, 4), robot, options=SolverOptions(max_iterations=1, load_steps=1))


def test_flexible_bodies_matter_only_when_joints_are_stiff(make_robot):
    """Body compliance L/(E I) in series with the joint: negligible next to a 200 N m/rad coupling
    (Eq. 7.1's point), tens of percent next to a 10000 N m/rad one."""
    cfg = Config(Structure("line"), 9, 4, 4)
    for k, lo, hi in ((200.0, 1.0, 1.05), (1e4, 1.1, 2.0)):
        robot = make_robot(k=k)
        rigid = solve(cfg, robot)
        flex = solve(cfg, robot, flexible=True)
        assert lo * rigid.tip_deflection_m <= flex.tip_deflection_m < hi * rigid.tip_deflection_m
        assert math.isfinite(flex.tipping_factor)
    assert math.isfinite(flex.tipping_factor)


def test_dead_band_is_odd_and_monotone_for_any_play():
    from hypothesis import given, settings
    from hypothesis import strategies as st

    @settings(max_examples=200, deadline=None)
    @given(st.floats(1.0, 1e5), st.floats(0.0, 0.1), st.floats(-0.3, 0.3), st.floats(1e-6, 0.05))
    def check(k, h, t, dt):
        m0, m1 = dead_band_moment(t, k, h), dead_band_moment(t + dt, k, h)
        assert m1 >= m0 - 1e-12 * k
        assert dead_band_moment(-t, k, h) == pytest.approx(-m0, abs=1e-9 * k)
        assert abs(m0) <= k * abs(t) + 1e-12 * k  # never stiffer than the spring without play

    check()
