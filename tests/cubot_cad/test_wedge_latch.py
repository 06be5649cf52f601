"""The wedge latch (issue 38, deliverable 1): a front-rear coupling without free play by design."""

from __future__ import annotations

import math

import pytest

from cubot_cad.couplings.connectors import FrontRearSpec
from cubot_cad.couplings.preload import FRICTION_RANGE, WedgeLatch
from cubot_cad.errors import InputError


def _spec(**kw) -> FrontRearSpec:
    return FrontRearSpec(wedge=WedgeLatch(**kw))


def test_the_default_cubot_couples_through_the_wedge_with_no_tension_play_and_a_servo_preload():
    from cubot_cad.hardware.servos import servo
    from cubot_cad.robots.cubot import CuBot

    r = CuBot()
    assert r.front_rear_coupling == "wedge" and r.fr_spec.wedge is not None
    fr = r.connector_properties(2.2e9)[0]
    assert fr.play_of("tension").play_m == 0.0
    assert fr.backlash_rad == 0.0
    assert fr.play_of("vertical_slip").play_m == pytest.approx(2 * r.clearance_mm * 1e-3)  # not counted away
    torque = servo(r.latch_spec.servo).stall_torque_nm
    per_pin = r.fr_spec.wedge.preload_per_pin_n(r.fr_spec, torque)
    assert fr.preload_n == pytest.approx(per_pin * len(r.pin_heights_mm()))
    assert 5.0 < fr.preload_n < 200.0
    assert "SG90" in fr.preload_source and "friction" in fr.preload_source


def test_the_clearance_latch_stays_a_selectable_variant_with_its_two_clearances_of_play():
    from cubot_cad.robots.cubot import CuBot

    r = CuBot(front_rear_coupling="clearance")
    fr = r.connector_properties(2.2e9)[0]
    assert fr.play_of("tension").play_m == pytest.approx(2 * r.clearance_mm * 1e-3)
    assert fr.preload_n == 0.0 and fr.backlash_rad > 0
    with pytest.raises(InputError, match="front_rear_coupling 'bolted'"):
        CuBot(front_rear_coupling="bolted")


def test_the_preload_follows_the_servo_torque_and_falls_with_friction():
    s = _spec()
    w = s.wedge
    assert w.preload_per_pin_n(s, 0.2) == pytest.approx(2 * w.preload_per_pin_n(s, 0.1))
    lo, hi = FRICTION_RANGE
    assert w.preload_per_pin_n(s, 0.18, lo) > w.preload_per_pin_n(s, 0.18, hi) > 0


def test_what_the_wedge_cannot_take_up_is_left_as_play():
    s = _spec()
    w = s.wedge
    reach = w.take_up_mm(s)
    assert reach == pytest.approx(s.clearance_mm + w.take_up_margin_mm)
    assert w.residual_play_mm(s, s.clearance_mm) == 0.0
    assert w.residual_play_mm(s, reach + 0.07) == pytest.approx(0.07)  # a loose print keeps the excess
    tight = _spec(take_up_margin_mm=0.0)
    assert tight.wedge.residual_play_mm(tight, tight.clearance_mm, stretch_mm=0.01) == pytest.approx(0.01)


def test_a_wedge_that_would_not_lock_or_not_fit_is_refused_naming_the_dimension():
    with pytest.raises(InputError, match="does not lock at friction"):
        FrontRearSpec(blade_turn_deg=6.0, wedge=WedgeLatch())
    with pytest.raises(InputError, match="cone_deg"):
        FrontRearSpec(wedge=WedgeLatch(cone_deg=60.0, take_up_margin_mm=0.6))
    with pytest.raises(InputError, match="cone_deg 70"):
        WedgeLatch(cone_deg=70.0)


def test_the_slot_tapers_from_its_open_end_to_its_locking_end_and_the_locked_turn_stops_on_the_cone():
    s = _spec()
    w = s.wedge
    h0, h1 = s.slot_half_width_mm(0.0), s.slot_half_width_mm(1.0)
    assert h0 > h1 > s.groove_diameter_mm / 2
    assert math.tan(math.radians(w.cone_deg)) > 0
    assert 0 < s.locked_turn_deg < s.blade_turn_deg  # reach kept for a looser print
    assert w.tan_taper(s) < w.friction_min  # self-locking


def test_turning_the_wedge_blade_draws_the_pins_in_and_bears_on_their_cones():
    """Moved, not assumed: with the pins as drawn (head at the back of its counterbore) the open blade
    passes them; turned to its locked angle it meets them (the cone), while pins drawn in by the head's
    clearance fit it exactly; turned on to the end of its turn it would cut into those (the preload)."""
    import cadquery as cq

    from cubot_cad.couplings.connectors import GroovedPin, TriangularBlade

    s = _spec()
    pin = GroovedPin(spec=s).solid.rotate(cq.Vector(0, 0, 0), cq.Vector(0, 0, 1), 180)

    def pins(draw):
        return [pin.translate((-draw, -y, z)) for y, z in s.pin_positions()]

    def overlap(blade, ps):
        return sum(blade.intersect(p).Volume() for p in ps)

    X, o = cq.Vector(1, 0, 0), cq.Vector(0, 0, 0)
    open_blade = TriangularBlade(spec=s).solid
    assert overlap(open_blade, pins(0.0)) == pytest.approx(0.0, abs=1e-6)
    at_lock = open_blade.rotate(o, X, s.locked_turn_deg)
    assert overlap(at_lock, pins(0.0)) > 1e-4  # loose pins: the edges are on the cones before the lock
    assert overlap(at_lock, pins(s.pin_draw_mm)) == pytest.approx(0.0, abs=1e-5)
    at_end = open_blade.rotate(o, X, s.blade_turn_deg)
    assert overlap(at_end, pins(s.pin_draw_mm)) > 1e-4


@pytest.mark.parametrize("c", [0.1, 0.2, 0.3, 0.4, 0.5])
def test_every_print_clearance_of_the_range_builds_a_self_locking_wedge(c):
    """The locking taper stays below the lowest friction at every clearance; a print looser than
    lock_below_mm past the head clearance gets an unloaded lead-in for the extra draw, none otherwise;
    the profile is continuous (the lead-in ends where the locking taper starts) and the locked turn is
    where the slot meets pins drawn in by the head clearance."""
    s = FrontRearSpec(clearance_mm=c, wedge=WedgeLatch())
    w = s.wedge
    assert w.tan_taper(s) < FRICTION_RANGE[0]
    assert (w.lead_fraction(s) > 0) == (c > w.lock_below_mm)
    f = w.lead_fraction(s)
    assert w.half_width_mm(s, f) == pytest.approx(w.lock_start_half_width_mm(s))
    assert w.half_width_mm(s, 0.0) == pytest.approx(w.entry_half_width_mm(s))
    assert w.half_width_mm(s, 1.0) == pytest.approx(w.lock_half_width_mm(s))
    hs = [w.half_width_mm(s, k / 50) for k in range(51)]
    assert all(a >= b for a, b in zip(hs, hs[1:], strict=False))  # it only ever closes
    h_c = w.lock_half_width_mm(s) + w.take_up_margin_mm * w.tan_cone
    assert w.half_width_mm(s, s.locked_turn_deg / s.blade_turn_deg) == pytest.approx(h_c)


def test_without_the_lead_in_a_loose_print_would_not_lock():
    """The lead-in is what makes 0.5 mm lock: with the locking taper starting at the open end
    (lock_below_mm covering the whole clearance) the one taper is above the friction angle."""
    with pytest.raises(InputError, match="does not lock at friction"):
        FrontRearSpec(clearance_mm=0.5, wedge=WedgeLatch(lock_below_mm=0.5))
    assert FrontRearSpec(clearance_mm=0.5, wedge=WedgeLatch()).wedge.lead_fraction(
        FrontRearSpec(clearance_mm=0.5, wedge=WedgeLatch())) > 0
