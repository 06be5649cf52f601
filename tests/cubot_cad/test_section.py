"""The body's bending section cut from the CAD (cubot_cad.checks.section): closed forms, refinement,
and the section moving with the wall the CAD is built with."""

from dataclasses import dataclass
from types import SimpleNamespace

import pytest

cq = pytest.importorskip("cadquery")

from cubot_cad.checks.section import body_section  # noqa: E402
from cubot_cad.errors import InputError  # noqa: E402
from cubot_cad.robots.registry import make_robot  # noqa: E402


@dataclass(frozen=True)
class _Part:
    name: str


def _fake_robot(*shapes, role="body"):
    """An object with what body_section reads: ``name`` and ``placed`` (role, part.name, shape)."""
    placed = [SimpleNamespace(role=role, part=_Part(f"p{k}"), shape=s) for k, s in enumerate(shapes)]
    return SimpleNamespace(name="fake", placed=placed)


def test_a_solid_bar_is_b_h_cubed_over_12():
    b, h = 30.0, 12.0
    bar = cq.Workplane().box(100, b, h).val()
    s = body_section(_fake_robot(bar), stations=8)
    assert s.effective_second_moment_mm4 == pytest.approx(b * h ** 3 / 12, rel=1e-6)
    assert s.length_mm == pytest.approx(100)


def test_a_tube_is_the_difference_of_two_rectangles_about_its_own_centroid():
    B, H, t = 40.0, 30.0, 2.0
    tube = cq.Workplane().box(80, B, H).cut(cq.Workplane().box(80, B - 2 * t, H - 2 * t)).translate((0, 0, 55)).val()
    s = body_section(_fake_robot(tube), stations=8)
    expect = (B * H ** 3 - (B - 2 * t) * (H - 2 * t) ** 3) / 12
    assert s.effective_second_moment_mm4 == pytest.approx(expect, rel=1e-6)  # about its centroid, not z = 0


def test_a_narrow_neck_sets_the_compliance_harmonically():
    """Half the length at I1 and half at I2: L / integral dx / I = 2 / (1/I1 + 1/I2)."""
    a = cq.Workplane().box(50, 20, 20).translate((-25, 0, 0)).val()
    b = cq.Workplane().box(50, 20, 10).translate((25, 0, 0)).val()
    s = body_section(_fake_robot(a.fuse(b)), stations=10)
    i1, i2 = 20 * 20 ** 3 / 12, 20 * 10 ** 3 / 12
    assert s.effective_second_moment_mm4 == pytest.approx(2 / (1 / i1 + 1 / i2), rel=1e-6)
    assert s.min_second_moment_mm4 == pytest.approx(i2, rel=1e-6)
    assert s.min_at_x_mm > 0


def test_stacked_parts_add_without_composite_action():
    lower = cq.Workplane().box(60, 20, 10).translate((0, 0, 5)).val()
    upper = cq.Workplane().box(60, 20, 10).translate((0, 0, 15)).val()
    s = body_section(_fake_robot(lower, upper), stations=6)
    assert s.effective_second_moment_mm4 == pytest.approx(2 * 20 * 10 ** 3 / 12, rel=1e-6)  # not 20 * 20^3 / 12


@pytest.fixture(scope="module")
def cubot_sections():
    r = make_robot("cubot")
    return body_section(r), body_section(r, stations=80)


def test_cubot_body_is_a_thin_walled_shell_and_converges_in_stations(cubot_sections):
    s40, s80 = cubot_sections
    assert s80.effective_second_moment_mm4 == pytest.approx(s40.effective_second_moment_mm4, rel=0.02)
    # far below the envelope box (100 x 85 mm solid: 5.1e6 mm^4): a 2.4 mm shell, open at the top
    assert 1e5 < s40.effective_second_moment_mm4 < 1e6
    assert s40.parts == ("cubot_body",)
    assert "stations" in s40.source and "mm^4" in s40.source


def test_a_thicker_wall_in_the_cad_gives_a_stiffer_body(cubot_sections):
    thick = body_section(make_robot("cubot", settings=(("wall_mm", 2.5),)))
    assert thick.effective_second_moment_mm4 > 1.02 * cubot_sections[0].effective_second_moment_mm4


def test_bad_inputs_are_refused_with_the_value():
    bar = cq.Workplane().box(10, 10, 10).val()
    with pytest.raises(InputError, match="stations"):
        body_section(_fake_robot(bar), stations=2)
    with pytest.raises(InputError, match="role"):
        body_section(_fake_robot(bar, role="cover"))
    gap = cq.Workplane().box(10, 10, 10).translate((-20, 0, 0)).val().fuse(
        cq.Workplane().box(10, 10, 10).translate((20, 0, 0)).val())
    with pytest.raises(InputError, match="no material"):
        body_section(_fake_robot(gap), stations=10)


def test_coupling_zones_are_left_to_the_coupling_and_the_platform_is_its_5_mm_plate():
    """The platform's lap joint (tab, recess) is its coupling's FE's; the body is the plate the FE's
    reference is: b t^3 / 12 of the CAD's plate, and it moves with the plate's thickness."""
    bar = cq.Workplane().box(100, 20, 10).val().fuse(cq.Workplane().box(20, 20, 4).translate((55, 0, -3)).val())
    robot = _fake_robot(bar)
    whole = body_section(robot, stations=12)
    robot.coupling_zones_mm = ((50.0, 70.0),)
    kept = body_section(robot, stations=12)
    assert kept.effective_second_moment_mm4 == pytest.approx(20 * 10 ** 3 / 12, rel=1e-6)
    assert whole.effective_second_moment_mm4 < 0.5 * kept.effective_second_moment_mm4
    assert kept.kept_stations < 12 and "left to its model" in kept.source
    plat = body_section(make_robot("platform"))
    assert plat.effective_second_moment_mm4 == pytest.approx(100 * 5 ** 3 / 12, rel=1e-6)
    from cubot_cad.robots.platform import TestPlatform

    thin = body_section(TestPlatform(thickness_mm=4.0))
    assert thin.effective_second_moment_mm4 == pytest.approx(100 * 4 ** 3 / 12, rel=1e-6)
    robot.coupling_zones_mm = ((-60.0, 60.0),)
    with pytest.raises(InputError, match="coupling zones leave"):
        body_section(robot, stations=12)
