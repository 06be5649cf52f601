"""Part classes: envelopes, analytic volumes, print orientation, parameter validation."""

from __future__ import annotations

import math

import pytest

from cubot_cad.errors import InputError


def test_cubot_printed_parts_stay_inside_the_thesis_envelope(robots):
    """100 x 100 x 85 mm; only what enters a docked neighbour (pins, dovetail tongue) leaves it,
    and nothing reaches below the wheels' contact plane."""
    r = robots["cubot"]
    for p in r.placed:
        x0, y0, z0, x1, y1, z1 = _bbox(p.shape)
        assert z1 <= 85.0 + 1e-6, p.part.name
        assert z0 >= -r.wheel_exposed_mm - 1e-6, p.part.name
        assert x0 >= -50 - 1e-6 and y0 >= -50 - 1e-6, p.part.name
        if p.role != "pin":
            assert x1 <= 50 + 1e-6, p.part.name
        if p.part.name != "rail_male_left":
            assert y1 <= 50 + 1e-6, p.part.name
    pins = [_bbox(p.shape)[3] for p in r.placed if p.role == "pin"]
    assert max(pins) == pytest.approx(50 + r.fr_spec.protrusion_mm, abs=1e-6)


def test_octbot_and_cube_robot_envelopes(robots):
    from cubot_cad.shapes import tight_bbox

    body = robots["octbot"].body
    x0, y0, z0, x1, y1, z1 = tight_bbox(body.solid)
    assert (x1 - x0, y1 - y0, z1 - z0) == pytest.approx((100.0, 100.0, 30.0), abs=1e-6)
    cube = robots["cube-robot"]
    bodies = [p for p in cube.placed if p.role == "body"]
    assert len(bodies) == 3  # wheel block, connector cuboid, sensor cylinder
    import cadquery as cq

    bb = tight_bbox(cq.Compound.makeCompound([p.shape for p in bodies]))
    assert bb[3] - bb[0] <= 120 + 1e-6 and bb[4] - bb[1] <= 120 + 1e-6 and bb[5] - bb[2] <= 120 + 1e-6


def _bbox(shape):
    from cubot_cad.shapes import tight_bbox

    return tight_bbox(shape)


@pytest.mark.parametrize("c", (0.1, 0.2, 0.5))
def test_grooved_pin_volume_is_the_analytic_sum_of_its_cylinders(c):
    from cubot_cad.couplings.connectors import FrontRearSpec, GroovedPin

    s = FrontRearSpec(clearance_mm=c)
    pin = GroovedPin(spec=s)
    x_head = -s.wall_mm - 2 * s.plate_mm - s.locking_plate_mm  # back face of the pin-locking plate
    g0, g1 = pin.groove_mm
    r, ch = s.pin_diameter_mm / 2, s.pin_chamfer_mm
    cone = math.pi * ch / 3 * (r * r + r * (r - ch) + (r - ch) ** 2)  # the 45 deg lead-in on the tip
    expected = math.pi * ((s.head_diameter_mm / 2) ** 2 * s.head_mm
                          + r ** 2 * (s.protrusion_mm - x_head - s.head_mm - (g1 - g0) - ch)
                          + (s.groove_diameter_mm / 2) ** 2 * (g1 - g0)) + cone
    # less the flat it prints lying on: a circular segment of each section below z = -(r - flat)
    from scipy.integrate import quad

    d = r - s.pin_flat_mm

    def seg(rr):
        return rr * rr * math.acos(d / rr) - d * math.sqrt(rr * rr - d * d) if rr > d else 0.0

    flat = (seg(s.head_diameter_mm / 2) * s.head_mm + seg(r) * (s.protrusion_mm - x_head - s.head_mm - (g1 - g0) - ch)
            + seg(s.groove_diameter_mm / 2) * (g1 - g0) + quad(lambda u: seg(r - u), 0.0, ch)[0])
    assert ch > 0 and s.pin_flat_mm > 0 and s.groove_diameter_mm / 2 < d  # the flat misses the groove
    assert pin.volume_mm3 == pytest.approx(expected - flat, rel=1e-6)


def test_platform_volume_is_plate_plus_tab_minus_recess_and_holes():
    from cubot_cad.robots.platform import PlatformPlate

    p = PlatformPlate()
    from cubot_cad.hardware.fasteners import clearance_hole_mm

    c, h = p.clearance_mm, p.thickness_mm / 2
    r = clearance_hole_mm("M3") / 2  # ISO 273 medium, from the fastener table
    plate = p.length_mm * p.width_mm * p.thickness_mm
    tab = p.tab_length_mm * p.tab_width_mm * h
    recess = (p.tab_length_mm + c) * (p.tab_width_mm + 2 * c) * (h + c)
    holes = math.pi * r * r * h + math.pi * r * r * (p.thickness_mm - h - c)
    assert p.volume_mm3 == pytest.approx(plate + tab - recess - holes, rel=1e-6)
    assert p.size_mm[:2] == pytest.approx((p.length_mm + p.tab_length_mm, p.width_mm))


def test_plate_volume_tracks_its_holes_and_clearance():
    from cubot_cad.couplings.connectors import FrontRearSpec, LatchFrontPlate

    def vol(c):
        s = FrontRearSpec(clearance_mm=c)
        r = s.pin_diameter_mm / 2 + c
        expected = s.plate_mm * (s.block_mm ** 2 - 3 * math.pi * r * r - 4 * math.pi * (3.4 / 2) ** 2)  # M3, ISO 273
        return LatchFrontPlate(spec=s).volume_mm3, expected

    for c in (0.1, 0.2, 0.3):
        got, expected = vol(c)
        assert got == pytest.approx(expected, rel=1e-6)
    assert vol(0.3)[0] < vol(0.1)[0]  # a looser fit removes material


def test_every_printable_part_lies_flat_on_the_bed(robots):
    """Printed orientation: z >= 0 and a planar face of real area on z = 0."""
    for r in robots.values():
        for part, _ in r.printable_parts():
            s = part.printable
            bb = _bbox(s)
            assert bb[2] == pytest.approx(0.0, abs=1e-6), part.name
            bottom = sum(f.Area() for f in s.Faces()
                         if f.geomType() == "PLANE" and abs(_bbox(f)[2]) < 1e-6 and abs(_bbox(f)[5]) < 1e-6)
            assert bottom >= 0.05 * (bb[3] - bb[0]) * (bb[4] - bb[1]) or bottom > 20.0, part.name


@pytest.mark.parametrize("factory, name", [
    (lambda: __import__("cubot_cad.robots.cubot", fromlist=["x"]).CuBot(length_mm=120), "length_mm"),
    (lambda: __import__("cubot_cad.robots.cubot", fromlist=["x"]).CuBot(wall_mm=0.6), "wall_mm"),
    (lambda: __import__("cubot_cad.robots.cubot", fromlist=["x"]).CuBot(clearance_mm=-0.1), "clearance_mm"),
    (lambda: __import__("cubot_cad.robots.cubot", fromlist=["x"]).CuBot(block_y_mm=35), "block_y_mm"),
    (lambda: __import__("cubot_cad.robots.cubot", fromlist=["x"]).CuBot(wheel_base_mm=90), "wheel_base_mm"),
    (lambda: __import__("cubot_cad.robots.cubot", fromlist=["x"]).CuBot(caster_ball_mm=30), "30 mm ball"),
    (lambda: __import__("cubot_cad.couplings.connectors", fromlist=["x"]).FrontRearSpec(groove_diameter_mm=5.0),
     "groove_diameter_mm"),
    (lambda: __import__("cubot_cad.couplings.connectors", fromlist=["x"]).FrontRearSpec(blade_radius_mm=14.0),
     "blade_radius_mm"),
    (lambda: __import__("cubot_cad.couplings.connectors", fromlist=["x"]).FrontRearSpec(head_shoulder_mm=0.5),
     "head_shoulder_mm"),
    (lambda: __import__("cubot_cad.couplings.connectors", fromlist=["x"]).FrontRearSpec(head_wall_mm=0.6),
     "head_wall_mm"),
    (lambda: __import__("cubot_cad.couplings.connectors", fromlist=["x"]).FrontRearSpec(pin_diameter_mm=4.2,
                                                                             clearance_mm=0.3),
     "would not hold the pin"),
    (lambda: __import__("cubot_cad.couplings.connectors", fromlist=["x"]).FrontRearSpec(pin_protrusion_mm=5.0),
     "pin_protrusion_mm"),
    (lambda: __import__("cubot_cad.couplings.connectors", fromlist=["x"]).TopTwistSpec(key_protrusion_mm=14.5),
     "key_protrusion_mm"),
    (lambda: __import__("cubot_cad.couplings.connectors", fromlist=["x"]).RailSpec(tongue_tip_mm=7.0), "tongue_tip_mm"),
    (lambda: __import__("cubot_cad.robots.octbot", fromlist=["x"]).OctBot(docked_gap_mm=30), "docked_gap_mm"),
    (lambda: __import__("cubot_cad.robots.octbot", fromlist=["x"]).OctBot(height_mm=40), "height_mm"),
    (lambda: __import__("cubot_cad.robots.cube_robot", fromlist=["x"]).CubeRobot(sensor_mm=60), "sensor_mm"),
    (lambda: __import__("cubot_cad.robots.cube_robot", fromlist=["x"]).CubeRobot(block_offset_mm=30), "block_offset_mm"),
    (lambda: __import__("cubot_cad.robots.platform", fromlist=["x"]).TestPlatform(thickness_mm=1.5), "thickness_mm"),
    (lambda: __import__("cubot_cad.robots.platform", fromlist=["x"]).TestPlatform(tab_length_mm=-3), "tab_length_mm"),
])
def test_impossible_parameters_raise_input_error_naming_the_parameter(factory, name):
    with pytest.raises(InputError) as exc:
        factory()
    assert name in str(exc.value)
    assert "\n" not in str(exc.value)


def test_mass_properties_add_printed_parts_and_the_component_table(robots):
    r = robots["cubot"]
    mp = r.mass_properties("abs")
    comps = sum(c.unit_mass_g * c.count for c in r.components()) / 1000
    printed = sum(p.part.volume_mm3 for p in r.placed) * 1e-9 * 1040
    assert mp.printed_mass_kg == pytest.approx(printed, rel=1e-9)
    assert mp.mass_kg == pytest.approx(printed + comps, rel=1e-9)
    L, W, H = r.envelope_mm
    assert abs(mp.com_m[0]) < L / 2000 and abs(mp.com_m[1]) < W / 2000 and 0 < mp.com_m[2] < H / 1000
    ixx, iyy, izz = mp.inertia_kg_m2[:3]
    assert min(ixx, iyy, izz) > 0 and ixx + iyy >= izz and iyy + izz >= ixx
    pla = r.mass_properties("pla")
    assert pla.printed_mass_kg / mp.printed_mass_kg == pytest.approx(1240 / 1040, rel=1e-9)
    with pytest.raises(InputError, match="wood"):
        r.mass_properties("wood")


def test_exposed_heights_are_measured_on_the_wheel_and_caster_solids(robots):
    cub = robots["cubot"]
    assert cub.wheel_exposed_mm == pytest.approx(15.0, abs=1e-6)  # thesis: 15 mm
    # 10 mm caster retained by a 0.3 mm undercut (mouth 0.3 mm narrower than the ball each side)
    expected = 5.0 - math.sqrt((5.0 + 0.2) ** 2 - (5.0 - 0.3) ** 2)
    assert cub.caster_exposed_mm == pytest.approx(expected, abs=1e-6) and expected == pytest.approx(2.775, abs=1e-3)
    from cubot_cad.robots.cubot import CuBot

    other = CuBot(wheel_exposed_mm=14.5)
    assert other.wheel_exposed_mm == pytest.approx(14.5, abs=1e-6)
    assert other.top_spec.collar_mm < cub.top_spec.collar_mm  # the collar follows the wheel height


def test_coupling_backlash_and_stiffness_follow_the_geometry(robots):
    from cubot_cad.robots.cubot import CuBot

    E = 2.2e9
    wedge = {c.kind: c for c in robots["cubot"].connector_properties(E)}
    # the backlash of the clearance latch follows the clearance and the lever arm; the wedge latch has none
    base = {c.kind: c for c in CuBot(front_rear_coupling="clearance").connector_properties(E)}
    loose = {c.kind: c for c in CuBot(clearance_mm=0.3, front_rear_coupling="clearance").connector_properties(E)}
    for kind in ("front_rear", "side_rail", "top_twist"):
        assert loose[kind].backlash_rad == pytest.approx(1.5 * base[kind].backlash_rad, rel=1e-9)
    assert wedge["front_rear"].backlash_rad == 0
    assert {c.kind: c for c in CuBot(clearance_mm=0.3).connector_properties(E)}["front_rear"].backlash_rad == 0
    high = {c.kind: c for c in CuBot(block_z_mm=38, front_rear_coupling="clearance").connector_properties(E)}
    assert high["front_rear"].backlash_rad < base["front_rear"].backlash_rad  # longer lever arm
    assert high["front_rear"].rotational_stiffness_nm_per_rad > base["front_rear"].rotational_stiffness_nm_per_rad
    cube = robots["cube-robot"].connector_properties(E)[0]
    # The Cube Robot's 1.7 mm gap: no face contact, the joint hinges on its pins -> softer, looser.
    assert cube.gap_m == pytest.approx(0.0017, abs=1e-6)
    assert cube.rotational_stiffness_nm_per_rad < 0.1 * base["front_rear"].rotational_stiffness_nm_per_rad
    assert cube.backlash_rad > 2 * base["front_rear"].backlash_rad
