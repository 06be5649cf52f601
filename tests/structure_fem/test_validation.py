"""The model against closed forms: continuum beam (Eq. 7.1), rigid-link chain, symmetry, linearity."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("exudyn")

from structure_fem.model.beams import cantilever_tip, eq71_line_tip, eq71_tip  # noqa: E402
from structure_fem.model.connectors import ConnectorSet  # noqa: E402
from structure_fem.model.hinge import FACE_CONTACT_FACTOR  # noqa: E402
from structure_fem.model.statics import Config, SolverOptions, solve  # noqa: E402
from structure_fem.model.structures import GRAVITY, Structure  # noqa: E402


def test_continuum_cantilever_matches_w_L4_over_8EI():
    """ANCF cable cantilever of a solid ABS section 100 x 85 mm, 1 m long, under its own weight."""
    L, b, h, rho, E = 1.0, 0.1, 0.085, 1040.0, 2.2e9
    A, i_area = b * h, b * h ** 3 / 12
    expected = (A * rho * GRAVITY) * L ** 4 / (8 * E * i_area)
    assert eq71_tip(L, b, h, rho, E) == pytest.approx(expected, rel=1e-12)
    got = cantilever_tip(L, A * rho, E * i_area, E * A, elements=8)
    assert got == pytest.approx(expected, rel=0.02)


def test_eq71_says_a_solid_line_of_cubes_barely_bends(cubot):
    """Thesis 7.1.3: the continuum estimate of a 10-wide single line is far below the wheel clearance."""
    assert eq71_line_tip(cubot, 10) < 0.2 * cubot.wheel_exposed_height_m


CHAIN_K = 2.0e4  # N m/rad: stiff enough that n = 15 stays in the small-angle range (tip ~1 % of length)
CHAIN_KAX = 1.0e8  # N/m: stiff pins (their shear slip is in the closed form)


@pytest.mark.parametrize("hinge", ["lumped", "emergent"])
@pytest.mark.parametrize("supports", ["corners", "contacts"])
@pytest.mark.parametrize("n", range(1, 16))
def test_rigid_link_chain_matches_closed_form(n, supports, hinge, make_robot):
    """n rigid links (length a, mass m) cantilevered from a clamped root, a rotational spring k at
    each of the n joints (the root joint included), pins of axial/shear stiffness k_ax.

    Derivation (small angles): number the joints from the tip, joint i at distance i a from the
    tip. The links outboard of joint i have their centres at (l - 1/2) a, l = 1..i, so the
    moment there is M_i = m g a sum_{l=1}^{i} (l - 1/2) = m g a i^2 / 2 and the joint turns by
    theta_i = M_i / k. That rotation lowers the tip by theta_i * i a, so

        delta_rot = sum_i m g a^2 i^3 / (2 k) = m g a^2 / (2 k) * (n (n + 1) / 2)^2.

    Each pin also slides by its shear V_i / k_ax = m g i / k_ax:
    delta_pin = m g n (n + 1) / (2 k_ax).

    The clamp is the root row (x in [-a, 0]) held by springs k_c at its support points x_j: its
    bottom corners (-a, 0) for a robot without ground contacts, its wheel and caster contacts
    (-a/2 + c_j, c_j = -38, 0, +38 mm) for one standing on them. It carries the chain's shear
    V = n m g and moment M = m g a n^2 / 2 (nose down) at x = 0 and its own weight at -a/2. With
    the root's downward motion u + phi x at x, the reactions k_c (u + phi x_j) balance

        k_c (J u + phi S1) = V + m g,    k_c (u S1 + phi S2) = M - m g a / 2

    (J supports, S1 = sum x_j, S2 = sum x_j^2; moments about x = 0), and the root lowers the
    tip (x = n a) by delta_clamp = u + phi n a. (For the corners: F_front = V + m g / 2 + M / a,
    F_rear = m g / 2 - M / a, delta_clamp = [F_front + n (F_front - F_rear)] / k_c.)

    With the emergent hinge (:mod:`structure_fem.model.hinge`) the spring k is the tension row (of
    k_ax at lever a_e = sqrt(k / k_ax) above the bottom edge) and the bottom face contact
    (``FACE_CONTACT_FACTOR`` k_ax) in series: a moment M pulls the row by M / a_e and presses the
    contact as much, so theta = M / k (1 + 1 / FACE_CONTACT_FACTOR). Without play its one-sided
    springs are smoothed over the stretch one body's weight makes (``hinge.ZERO_PLAY_SCALE``), so
    a row bears about 5 % of that weight late: 1.2 % of the tip at n = 1, less as the moments
    grow. Hence 1.5 % there against 1 % for the lumped model's plain rotational springs.
    """
    contacts = None if supports == "corners" else ((-0.038, "caster"), (0.0, "wheel"), (0.038, "caster"))
    robot = make_robot(k=CHAIN_K, k_ax=CHAIN_KAX, contacts=contacts)
    a, m = robot.length_m, robot.mass_kg
    cfg = Config(Structure("line"), rows=n + 1, rows_over=n, void_widths=n, clamped=True)
    conn = replace(ConnectorSet.from_robot(robot), hinge=hinge)
    res = solve(cfg, robot, conn, options=SolverOptions(contact_n_per_m=1e9))
    kc = 1e9
    k_joint = CHAIN_K / (1 + 1 / FACE_CONTACT_FACTOR) if hinge == "emergent" else CHAIN_K
    s = n * (n + 1) / 2
    mg = m * GRAVITY
    xs = [-a, 0.0] if contacts is None else [-a / 2 + c for c, _ in contacts]
    root = [sp.point_m[0] for sp in res.layout.supports if sp.body == res.layout.rear_body]
    assert sorted(root) == pytest.approx(sorted(xs), abs=1e-12)  # the supports are where the closed form has them
    big_j, s1, s2 = len(xs), sum(xs), sum(x * x for x in xs)
    v, mom = n * mg, mg * a * n * n / 2
    det = big_j * s2 - s1 * s1
    u = ((v + mg) * s2 - s1 * (mom - mg * a / 2)) / (kc * det)
    phi = (big_j * (mom - mg * a / 2) - s1 * (v + mg)) / (kc * det)
    expected = (mg * a ** 2 / (2 * k_joint) * s ** 2 + mg * n * (n + 1) / (2 * CHAIN_KAX) + u + phi * n * a)
    if contacts is None:  # the general form reduces to the corner one
        f_front = n * mg + mg / 2 + mg * n * n / 2
        f_rear = mg / 2 - mg * n * n / 2
        assert u + phi * n * a == pytest.approx((f_front + n * (f_front - f_rear)) / kc, rel=1e-9)
    tol = 0.015 if hinge == "emergent" else 0.01
    # (emergent: the rows' 1e-8 m smoothing floor over their 14 mm lever turns a joint by 7e-7 rad,
    # 0.07 um at the tip of one link: 8 % of n = 1's 0.8 um, nothing from n = 2)
    assert res.tip_deflection_m == pytest.approx(expected, rel=tol, abs=1e-7 if hinge == "emergent" else 0.0)
    # The joint rotations follow M_i / k too (joint list runs front to rear: i = 1..n from the tip).
    rot = -res.joint_rotation_rad[:n]
    # (emergent: the lightly loaded tip joint's row stretches 1e-7 m, ten of its 1e-8 m smoothing)
    assert rot == pytest.approx([m * GRAVITY * a * i * i / 2 / k_joint for i in range(1, n + 1)], rel=tol,
                                abs=1e-6 if hinge == "emergent" else 0.0)


def _clamp_closed_form(xs, n, a, mg, kc):
    """Tip drop (m) from the clamp's springs alone at support points ``xs`` (see above)."""
    big_j, s1, s2 = len(xs), sum(xs), sum(x * x for x in xs)
    v, mom = n * mg, mg * a * n * n / 2
    det = big_j * s2 - s1 * s1
    u = ((v + mg) * s2 - s1 * (mom - mg * a / 2)) / (kc * det)
    phi = (big_j * (mom - mg * a / 2) - s1 * (v + mg)) / (kc * det)
    return u + phi * n * a


@pytest.mark.parametrize("n", [1, 3, 5, 8])
def test_soft_clamp_tip_follows_its_support_points(n, make_robot):
    """The same chain on soft clamp springs (1e6 N/m per support), where the root's motion is a
    large part of the tip: the solved tip matches the closed form at the actual support points,
    and the contacts (38 mm either side of the centre) give a different tip from the corners
    (100 mm apart): the test would see supports in the wrong place."""
    kc = 1e6
    tips = {}
    for supports in ("corners", "contacts"):
        contacts = None if supports == "corners" else ((-0.038, "caster"), (0.0, "wheel"), (0.038, "caster"))
        robot = make_robot(k=CHAIN_K, k_ax=CHAIN_KAX, contacts=contacts)
        a, mg = robot.length_m, robot.mass_kg * GRAVITY
        lumped = replace(ConnectorSet.from_robot(robot), hinge="lumped")  # the closed form's joints
        res = solve(Config(Structure("line"), rows=n + 1, rows_over=n, void_widths=n, clamped=True), robot,
                    lumped, options=SolverOptions(contact_n_per_m=kc))
        xs = [-a, 0.0] if contacts is None else [-a / 2 + c for c, _ in contacts]
        s = n * (n + 1) / 2
        expected = (mg * a ** 2 / (2 * CHAIN_K) * s ** 2 + mg * n * (n + 1) / (2 * CHAIN_KAX)
                    + _clamp_closed_form(xs, n, a, mg, kc))
        assert res.tip_deflection_m == pytest.approx(expected, rel=0.01)
        tips[supports] = res.tip_deflection_m
    assert tips["contacts"] > 1.05 * tips["corners"]


def test_symmetric_bridge_deflects_symmetrically(make_robot):
    robot = make_robot(backlash=0.002)
    w, side = 5, 3
    rows = w + 2 * side
    res = solve(Config(Structure("line"), rows, w + side, w, "bridged"), robot)
    drop = -res.underside_m[:, :, 1]  # (rows, [rear, front]) front row first
    mirrored = drop[::-1, ::-1]
    assert np.max(np.abs(drop - mirrored)) < 1e-6 * max(np.max(np.abs(drop)), 1e-9) + 1e-10
    mid = drop[side + w // 2]
    assert mid.max() > 0  # it sags
    r = res.reactions_n
    assert r.sum() == pytest.approx(res.total_weight_n, rel=1e-6)
    near = sum(f for f, s in zip(r, res.layout.supports, strict=True) if s.ledge == "near")
    assert near == pytest.approx(res.total_weight_n / 2, rel=1e-6)


@pytest.mark.parametrize("phase,over", [("cantilever", 4), ("bridged", 6)])
def test_doubling_every_stiffness_halves_small_deflection(phase, over, make_robot):
    robot = make_robot(k=2000.0)
    cfg = Config(Structure("two_line", 2, 1, "staggered"), 10, over, 4, phase)
    # linear joints (the emergent hinge's smoothing has a fixed 1e-8 m floor, not scaled with k)
    conn = replace(ConnectorSet.from_robot(robot), hinge="lumped")
    base = solve(cfg, robot, conn, options=SolverOptions(contact_n_per_m=1e6))
    stiff = solve(cfg, robot, conn.scaled(2.0), options=SolverOptions(contact_n_per_m=2e6))
    assert base.max_deflection_m > 0 and math.isfinite(base.max_deflection_m)
    assert stiff.max_deflection_m == pytest.approx(base.max_deflection_m / 2, rel=2e-3)
    assert stiff.joint_rotation_rad == pytest.approx(base.joint_rotation_rad / 2, rel=2e-3, abs=1e-9)


def test_aligned_side_by_side_lines_deflect_exactly_like_one_line(robot):
    """Same load per coupling: two aligned lines add no bending stiffness (why the thesis's two-line
    step buys nothing in this model)."""
    one = solve(Config(Structure("line"), 9, 4, 4), robot)
    two = solve(Config(Structure("two_line", 2, 1, "aligned"), 9, 4, 4), robot)
    assert two.tip_deflection_m == pytest.approx(one.tip_deflection_m, rel=1e-6)
    assert two.robots == 2 * one.robots


@pytest.mark.parametrize("k", [200.0, 2.0e4])
def test_beam_element_robots_vs_rigid_and_lumped_flexible(make_robot, k):
    """Robots as ANCF beams (E of ABS, hollow section) joined by short compliant elements,
    against the rigid-body model and its lumped-flexible option (clamped, no backlash, 5 robots).

    With couplings as soft as the CuBot's (k ~ 200 N m/rad) the robots' own bending is lost in
    the joints (Eq. 7.1's point): the beam model is within 2 % of the rigid one. With joints 100x
    stiffer the bodies' bending shows, and the lumped option stays on the safe side of the beam
    model (it puts the bodies' compliance at the joints' larger moment) within 15 %."""
    from structure_fem.model.beams import flexible_line_tip

    robot = make_robot(k=k, k_ax=1e9)
    conn = replace(ConnectorSet.from_robot(robot), hinge="lumped")  # the beam model's rotational joints
    n = 5
    cfg = Config(Structure("line"), n + 1, n, n, clamped=True)
    opts = SolverOptions(contact_n_per_m=1e9)
    beam = flexible_line_tip(robot, k, n)
    rigid = solve(cfg, robot, conn, options=opts).tip_deflection_m
    lumped = solve(cfg, replace(robot), conn, flexible=True, options=opts).tip_deflection_m
    if k < 1e3:
        assert beam == pytest.approx(rigid, rel=0.02)
    else:
        assert beam > 1.2 * rigid
    assert beam <= lumped <= 1.15 * beam
