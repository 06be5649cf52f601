"""Translational play per feature in the multibody model (issue 12): tension-only gaps,
compression contact, vertical slip; the CAD's clearance moves the thresholds the right way."""

from __future__ import annotations

from dataclasses import replace

import pytest

pytest.importorskip("exudyn")

from cubot_cad.properties import FeaturePlay, default_properties  # noqa: E402
from structure_fem.analysis.study import StudyInputs, structure_curve  # noqa: E402
from structure_fem.model.connectors import ConnectorSet, band_force, joint_play  # noqa: E402
from structure_fem.model.statics import Config, SolverOptions, solve  # noqa: E402
from structure_fem.model.structures import Structure  # noqa: E402


def test_band_force_is_free_inside_the_play_and_a_spring_outside():
    k, g, e = 1e6, 2e-4, 1e-7
    assert band_force(0.0, k, 0.0, g, e) == 0.0
    assert abs(band_force(0.5 * g, k, 0.0, g, e)) < 1e-3 * k * g  # inside the tension gap: free
    assert band_force(3 * g, k, 0.0, g, e) == pytest.approx(k * 2 * g, rel=1e-3)  # bears after the gap
    assert band_force(-g, k, 0.0, g, e) == pytest.approx(-k * g, rel=1e-3)  # compression: contact at once
    assert band_force(-3 * g, k, g, g, e) == pytest.approx(-k * 2 * g, rel=1e-3)  # both ways: symmetric
    assert band_force(1e-3, k, 0.0, 0.0, e) == k * 1e-3  # no play: the plain spring


def test_feature_play_maps_to_closing_and_opening_travel():
    play = (FeaturePlay("tension", "x", "tension", 4e-4, "head + blade"),
            FeaturePlay("vertical_slip", "z", "both", 3e-4, "bores"))
    assert joint_play(play) == {"play_x": (0.0, 4e-4), "play_z": (3e-4, 3e-4)}


@pytest.mark.parametrize("n", [1, 3, 6])
def test_vertical_slip_adds_one_slip_per_joint_to_the_tip(n, make_robot):
    """Clamped chain with stiff joints: the shear pushes every front body down through its pins'
    vertical slip s before they bear, so the tip drops n s more (first order)."""
    robot = make_robot(k=2e4, k_ax=1e8)
    conn = ConnectorSet.from_robot(robot)
    s = 3e-4
    slip = replace(conn, front_rear=replace(conn.front_rear, play_z=(s, s)))
    cfg = Config(Structure("line"), rows=n + 1, rows_over=n, void_widths=n, clamped=True)
    opts = SolverOptions(contact_n_per_m=1e9)
    base = solve(cfg, robot, conn, options=opts).tip_deflection_m
    got = solve(cfg, robot, slip, options=opts).tip_deflection_m
    assert got - base == pytest.approx(n * s, rel=0.02)


def test_a_tension_gap_lets_an_arch_sag_by_about_the_gap_over_its_height(make_robot):
    """A 2-layer arch bends by opening its upper front-rear couplings (tension) against its lower
    ones (compression, faces touching): a tension-only gap g turns every joint by about g / H
    more, which lowers the tip by about (g / H) times the sum of the joints' distances to it.
    (Aligned lines and soft pitch springs, so that only the couple between the layers carries the
    bending; staggered lines bridge each joint through the rails, which hides part of the gap.)"""
    robot = make_robot(k=20.0, k_ax=2e6)
    conn = ConnectorSet.from_robot(robot)
    g, w = 3e-4, 4
    cfg = Config(Structure("arch", 2, 2, "aligned"), 9, w, w)
    base = solve(cfg, robot, conn).tip_deflection_m
    tension = solve(cfg, robot, replace(conn, front_rear=replace(conn.front_rear, play_x=(0.0, g)))).tip_deflection_m
    a, H = robot.length_m, robot.height_m
    expected = g / H * a * sum(range(1, w + 1))  # joints over the void only: a lower bound
    assert tension - base > 0.8 * expected


def _cubot_at(clearance_mm, coupling="clearance"):
    """The packaged CuBot with the couplings a print at ``clearance_mm`` gives (``coupling``: the
    front-rear latch, the thesis's clearance latch by default: its play follows the clearance)."""
    from cubot_cad.robots.cubot import CuBot

    rec = default_properties().get("cubot")
    gaps = {c.kind: c.gap_m * 1e3 for c in rec.connectors}
    return replace(rec, connectors=tuple(CuBot(clearance_mm=clearance_mm, front_rear_coupling=coupling)
                                         .connector_properties(rec.youngs_modulus_pa, gaps)))


def test_the_wedge_latch_has_no_tension_play_at_either_clearance_and_keeps_the_slip():
    for c in (0.2, 0.4):
        fr = _cubot_at(c, "wedge").connector("front_rear")
        assert fr.play_of("tension").play_m == 0 and fr.preload_n > 0
        assert fr.play_of("vertical_slip").play_m == pytest.approx(2 * c * 1e-3)


def test_doubling_the_cad_clearance_does_not_raise_the_line_threshold():
    """More print clearance -> more play per feature -> the line droops more: its threshold
    can only fall (the thresholds are what the CAD gives, never tuned back)."""
    base, loose = _cubot_at(0.2), _cubot_at(0.4)
    t = {}
    for name, r in (("base", base), ("loose", loose)):
        fr = r.connector("front_rear")
        assert fr.play_of("tension").play_m > 0
        t[name] = structure_curve(Structure("line"), StudyInputs.for_robot(r), extra=0)
    assert loose.connector("front_rear").play_of("tension").play_m > base.connector("front_rear").play_of(
        "tension").play_m
    assert t["loose"].threshold <= t["base"].threshold
    w = t["base"].threshold
    assert t["loose"].tip_mm[t["loose"].index(w, StudyInputs.for_robot(loose))] > t["base"].tip_mm[
        t["base"].index(w)]
