"""Docked pairs: interference <= 1 mm^3 at the default clearance, and gaps that come out of the geometry."""

from __future__ import annotations

import pytest

from cubot_cad.docking import INTERFERENCE_LIMIT_MM3, PAIRS


@pytest.mark.parametrize("name", PAIRS)
def test_docked_pair_interference_is_at_most_one_cubic_mm(pairs, name):
    p = pairs[name]
    assert p.interference_mm3 <= INTERFERENCE_LIMIT_MM3, p.summary()
    assert p.open_interference_mm3 <= INTERFERENCE_LIMIT_MM3


def test_docked_gaps_match_the_thesis(pairs):
    assert pairs["cubot-front-rear"].gap_mm == pytest.approx(0.0, abs=0.01)  # CuBot: zero gap
    assert pairs["cubot-side-rail"].gap_mm == pytest.approx(0.0, abs=0.01)
    assert pairs["platform-bolt"].gap_mm == pytest.approx(0.0, abs=0.01)
    assert pairs["cube-robot-front-rear"].gap_mm == pytest.approx(1.7, abs=0.02)  # thesis: 1.7 mm
    assert pairs["cube-robot-side"].gap_mm == pytest.approx(1.7, abs=0.02)
    assert pairs["octbot-ring"].gap_mm >= 40.0 - 0.02  # thesis: >= 40 mm
    # top-down: the upper robot stands on its wheels (15 mm exposed) on the lower's cover
    assert pairs["cubot-top-down"].gap_mm == pytest.approx(15.0, abs=0.02)
    # the dovetail lets the pair be pulled apart only by about its flank clearance
    assert 0.2 <= pairs["cubot-side-rail"].play_mm <= 1.0


def test_a_misaligned_pair_shows_interference(pairs):
    """The measurement sees real overlaps: shifting the docked rear CuBot 0.6 mm (three clearances)
    drives its pins into the hole walls."""
    from cubot_cad.docking import dock

    bad = dock("cubot-front-rear", 0.2, (0.0, 0.0, 0.6))
    assert bad.interference_mm3 > INTERFERENCE_LIMIT_MM3
    assert bad.gap_mm == pytest.approx(pairs["cubot-front-rear"].gap_mm, abs=0.01)


def test_cube_robot_gap_is_pin_length_minus_latch_depth():
    """Not drawn in: lengthen the pins and the measured gap grows by the same amount."""
    from cubot_cad.cube_robot import CubeRobot
    from cubot_cad.docking import dock_robot

    r = CubeRobot(pin_overrun_mm=3.0)
    assert r.fr_spec.protrusion_mm - r.fr_spec.latch_depth_mm == pytest.approx(3.0)
    p = dock_robot(r, "cube-robot-front-rear")
    assert p.gap_mm == pytest.approx(3.0, abs=0.02)
    assert p.interference_mm3 <= INTERFERENCE_LIMIT_MM3


def test_octbot_gap_follows_its_parameter():
    from cubot_cad.docking import dock_robot
    from cubot_cad.octbot import OctBot

    p = dock_robot(OctBot(docked_gap_mm=55.0), "octbot-ring")
    assert p.gap_mm == pytest.approx(55.0, abs=0.05)
    assert p.interference_mm3 <= INTERFERENCE_LIMIT_MM3


def test_manifold_interference_agrees_with_occ(pairs, robots):
    """Cross-check one overlap with OCC booleans: a pin pushed 0.5 mm into its plate."""
    from cubot_cad.connectors import FrontRearSpec, GroovedPin, LatchFrontPlate
    from cubot_cad.docking import intersection_volume, to_manifold

    s = FrontRearSpec()
    plate = LatchFrontPlate(spec=s).solid
    y, z = s.pin_positions()[0]
    pin = GroovedPin(spec=s).solid.translate((-10.0, y + 0.5 + s.clearance_mm, z))
    occ = plate.intersect(pin).Volume()
    man = intersection_volume(to_manifold(plate, 0.005), to_manifold(pin, 0.005))
    assert occ > 1.0
    assert man == pytest.approx(occ, rel=0.02)


def test_unknown_pair_is_an_input_error():
    from cubot_cad.docking import dock
    from cubot_cad.errors import InputError

    with pytest.raises(InputError, match="no-such-pair"):
        dock("no-such-pair")
