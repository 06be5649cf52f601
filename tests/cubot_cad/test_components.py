"""Component stand-ins (motors, wheels, battery, boards, servos, casters, sensors) have room: none
overlaps another or a printed part or the drive hardware (manifold3d intersection < 1e-3 mm^3);
the mass lumps (screws, wires spread through the robot) have no stand-in."""

from __future__ import annotations

import itertools

import pytest

LIMIT_MM3 = 1e-3


def _solids(robot):
    from cubot_cad.checks.docking import to_manifold

    return [(f"{c.key}[{i}]", to_manifold(s)) for c in robot.components() for i, s in enumerate(c.solids())]


@pytest.mark.parametrize("name", ["cubot", "octbot", "cube-robot", "platform"])
def test_stand_ins_overlap_nothing(robots, name):
    from cubot_cad.checks.docking import intersection_volume, manifold_of, to_manifold

    r = robots[name]
    comps = _solids(r)
    assert comps, name
    hits = [(a, b, v) for (a, ma), (b, mb) in itertools.combinations(comps, 2)
            if (v := intersection_volume(ma, mb)) > LIMIT_MM3]
    others = [(p.part.name, manifold_of(p)) for p in r.placed] + \
             [(h.label, to_manifold(h.shape)) for h in r.hardware(r.placed)]
    hits += [(a, b, v) for a, ma in comps for b, mb in others if (v := intersection_volume(ma, mb)) > LIMIT_MM3]
    assert not hits, hits


def test_the_check_sees_an_overlap(robots):
    """The same measurement on the old CuBot placement (26 mm motors 13 mm in from the wheels) finds the
    motors in the wheels."""
    from dataclasses import replace

    from cubot_cad.checks.docking import intersection_volume, to_manifold

    r = robots["cubot"]
    comps = {c.key: c for c in r.components()}
    wb, yc = r.wheel_base_mm / 2, r.y_centre_mm
    old = replace(comps["drive_motor"], size_mm=(12.0, 26.0, 10.0),
                  positions_mm=tuple((x, yc + s * (wb - 13), z) for (x, _, z), s in
                                     zip(comps["drive_motor"].positions_mm, (-1, 1), strict=True)))
    wheel = to_manifold(comps["wheel"].solids()[1])
    assert intersection_volume(to_manifold(old.solids()[1]), wheel) > 100.0


def test_mass_lumps_have_mass_but_no_stand_in(robots):
    for r in robots.values():
        for c in r.components():
            if c.lump:
                assert c.solids() == [] and c.mass_items(), c.key
    cub = {c.key: c for c in robots["cubot"].components()}
    assert cub["fasteners"].lump and cub["wiring"].lump and not cub["battery"].lump


def test_drive_motors_sit_between_the_key_shaft_and_their_wheels(robots):
    """The CuBot's N20 motors (24 mm) fit between the twist key's turning shaft and the wheels' inner faces."""
    from cubot_cad.shapes import tight_bbox

    r = robots["cubot"]
    comps = {c.key: c for c in r.components()}
    yc = r.y_centre_mm
    shaft_r = r.drive_spec.shaft_diameter_mm / 2
    wheel_in = r.wheel_base_mm / 2 - r.wheel_width_mm / 2
    for s in comps["drive_motor"].solids():
        b = tight_bbox(s)
        near, far = sorted((abs(b[1] - yc), abs(b[4] - yc)))
        assert near > shaft_r and far < wheel_in
        assert far - near == pytest.approx(24.0)
