"""Docked pairs: interference <= 1 mm^3 at the default clearance, and gaps that come out of the
geometry and match what the robots are designed for."""

from __future__ import annotations

import dataclasses

import pytest

from cubot_cad.checks.docking import GAP_TOLERANCE_MM, INTERFERENCE_LIMIT_MM3, PAIRS


@pytest.mark.parametrize("name", PAIRS)
def test_docked_pair_interference_is_at_most_one_cubic_mm(pairs, name):
    p = pairs[name]
    assert p.interference_mm3 <= INTERFERENCE_LIMIT_MM3, p.summary()
    assert p.open_interference_mm3 <= INTERFERENCE_LIMIT_MM3
    assert abs(p.gap_mm - p.design_gap_mm) <= GAP_TOLERANCE_MM, p.summary()
    assert p.ok and p.problems() == []


def test_a_pair_that_interferes_or_misses_its_designed_gap_fails_naming_it(pairs):
    """What `--clearance-mm 0` produced (CuBot front-rear 5.06 mm apart, 12.1 mm^3 of overlap) is
    not ok, and require_docked (which guards the export) says so in one line."""
    from cubot_cad.checks.docking import require_docked
    from cubot_cad.errors import InputError

    good = pairs["cubot-front-rear"]
    far = dataclasses.replace(good, gap_mm=5.06)
    assert far.interference_ok and not far.gap_ok and not far.ok
    both = dataclasses.replace(good, gap_mm=5.06, interference_mm3=12.1)
    assert not both.ok and len(both.problems()) == 2
    require_docked([good, pairs["cube-robot-front-rear"]])  # ok: no error
    with pytest.raises(InputError) as exc:
        require_docked([good, both], then="nothing written")
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("--clearance-mm 0.2: ")
    assert "cubot-front-rear" in msg and "gap 5.06 mm, designed 0.00" in msg and "12.1 mm^3" in msg
    assert msg.endswith("nothing written")


def test_designed_gaps_are_the_robots_own():
    from cubot_cad.checks.docking import design_gap_mm
    from cubot_cad.robots.cube_robot import CubeRobot
    from cubot_cad.robots.cubot import CuBot
    from cubot_cad.robots.octbot import OctBot

    assert design_gap_mm(CuBot(), "cubot-front-rear") == 0.0
    assert design_gap_mm(CuBot(), "cubot-top-down") == 15.0  # stands on its wheels
    assert design_gap_mm(CuBot(wheel_exposed_mm=14.5), "cubot-top-down") == 14.5
    assert design_gap_mm(CubeRobot(), "cube-robot-side") == pytest.approx(1.7)
    assert design_gap_mm(CubeRobot(pin_overrun_mm=3.0), "cube-robot-front-rear") == pytest.approx(3.0)
    assert design_gap_mm(OctBot(docked_gap_mm=55.0), "octbot-ring") == 55.0


def test_docked_gaps_match_the_thesis(pairs):
    assert pairs["cubot-front-rear"].gap_mm == pytest.approx(0.0, abs=0.01)  # CuBot: zero gap
    assert pairs["cubot-side-rail"].gap_mm == pytest.approx(0.0, abs=0.01)
    assert pairs["platform-bolt"].gap_mm == pytest.approx(0.0, abs=0.01)
    assert pairs["cube-robot-front-rear"].gap_mm == pytest.approx(1.7, abs=0.02)  # thesis: 1.7 mm
    assert pairs["cube-robot-side"].gap_mm == pytest.approx(1.7, abs=0.02)
    assert pairs["octbot-ring"].gap_mm >= 40.0 - 0.02  # thesis: >= 40 mm
    # top-down: the upper robot stands on its wheels (15 mm exposed) on the lower's cover
    assert pairs["cubot-top-down"].gap_mm == pytest.approx(15.0, abs=0.02)
    # the dovetail lets the pair be pulled apart only by about its flank clearance (see test_rail)
    assert 0.2 <= pairs["cubot-side-rail"].play_mm <= 1.0


def test_a_misaligned_pair_shows_interference(pairs):
    """The measurement sees real overlaps: shifting the docked rear CuBot 0.6 mm (three clearances)
    drives its pins into the hole walls."""
    from cubot_cad.checks.docking import dock

    bad = dock("cubot-front-rear", 0.2, (0.0, 0.0, 0.6))
    assert bad.interference_mm3 > INTERFERENCE_LIMIT_MM3 and not bad.ok
    assert bad.gap_mm == pytest.approx(pairs["cubot-front-rear"].gap_mm, abs=0.01)


def test_cube_robot_gap_is_pin_length_minus_latch_depth():
    """Not drawn in: lengthen the pins and the measured gap grows by the same amount."""
    from cubot_cad.checks.docking import dock_robot
    from cubot_cad.robots.cube_robot import CubeRobot

    r = CubeRobot(pin_overrun_mm=3.0)
    assert r.fr_spec.protrusion_mm - r.fr_spec.latch_depth_mm == pytest.approx(3.0)
    p = dock_robot(r, "cube-robot-front-rear")
    assert p.gap_mm == pytest.approx(3.0, abs=0.02)
    assert p.interference_mm3 <= INTERFERENCE_LIMIT_MM3 and p.design_gap_mm == pytest.approx(3.0) and p.ok


def test_octbot_gap_follows_its_parameter():
    from cubot_cad.checks.docking import dock_robot
    from cubot_cad.robots.octbot import OctBot

    p = dock_robot(OctBot(docked_gap_mm=55.0), "octbot-ring")
    assert p.gap_mm == pytest.approx(55.0, abs=0.05)
    assert p.interference_mm3 <= INTERFERENCE_LIMIT_MM3 and p.ok


def test_manifold_interference_agrees_with_occ(pairs, robots):
    """Cross-check one overlap with OCC booleans: a pin pushed 0.5 mm into its plate."""
    from cubot_cad.checks.docking import intersection_volume, to_manifold
    from cubot_cad.couplings.connectors import FrontRearSpec, GroovedPin, LatchFrontPlate

    s = FrontRearSpec()
    plate = LatchFrontPlate(spec=s).solid
    y, z = s.pin_positions()[0]
    pin = GroovedPin(spec=s).solid.translate((-10.0, y + 0.5 + s.clearance_mm, z))
    occ = plate.intersect(pin).Volume()
    man = intersection_volume(to_manifold(plate, 0.005), to_manifold(pin, 0.005))
    assert occ > 1.0
    assert man == pytest.approx(occ, rel=0.02)


def test_unknown_pair_is_an_input_error():
    from cubot_cad.checks.docking import dock
    from cubot_cad.errors import InputError

    with pytest.raises(InputError, match="no-such-pair"):
        dock("no-such-pair")


def test_a_pair_is_measured_once_however_its_arguments_are_spelled(pairs):
    """`dock` is keyed by the robot and the misalignment, not by how a caller spells the defaults:
    the cad stage (``dock(n, 0.2)``), `cad dock` (``settings=()``) and the session's pairs
    (``dock(n)``) share one measurement; another clearance or a misalignment is another pair."""
    from cubot_cad.checks.docking import dock

    p = pairs["platform-bolt"]
    assert dock("platform-bolt", 0.2) is p
    assert dock("platform-bolt", 0.2, settings=()) is p
    assert dock("platform-bolt", 0.2, (0, 0, 0)) is p
    assert dock("platform-bolt", 0.2, (0.0, 0.0, 0.5)) is not p
    assert dock("platform-bolt", 0.3) is not p
