"""Cube Robot mechanisms checked in the CAD by moving their parts (OCC booleans, mm^3 and mm^2):

* the steered front wheels turn from -steer_deg to +steer_deg without touching the wheel block (or the
  stand-ins beside them) and stay inside the 120 mm cube (before: 37.8 mm^3 in the block at 30 deg,
  and outside the envelope);
* the three tiers bear on each other, locate (tabs in slots, a lip) and are screwed together through
  clearance holes into heat-set inserts in bosses (before: the sensor cylinder bore on 13.9 mm^2 of the
  cuboid, nothing located or fastened them)."""

from __future__ import annotations

import pytest

from cubot_cad.errors import InputError

#: The least contact area (mm^2) between two stacked tiers this spec asks for: a tier's walls carry the
#: one above on at least ~1 mm of wall all round (about 470 mm^2) and the corner bosses; 36x the 13.9
#: mm^2 the sensor cylinder had.
MIN_BEARING_MM2 = 500.0
#: Steering angles the motion tests visit, as fractions of the full lock.
STEPS = [k / 6 for k in range(-6, 7)]


def _vol(a, b) -> float:
    return a.intersect(b).Volume()


@pytest.fixture(scope="module")
def cube(robots):
    return robots["cube-robot"]


def _front_wheels(r, deg):
    """The front wheels' stand-ins (the component table's cylinders) turned ``deg`` about the vertical
    through each wheel's centre."""
    from cubot_cad.shapes import Z, rotated

    wheels = next(c for c in r.components() if c.key == "wheel")
    return [rotated(s, Z, deg, p) for s, p in zip(wheels.solids(), wheels.positions_mm, strict=True) if p[0] > 0]


# --- A1: the steered wheels clear the block at full lock, inside the envelope ---------------------------

def test_steered_wheels_turn_through_full_lock_clear_of_the_block_and_inside_the_cube(cube):
    from cubot_cad.checks.docking import intersection_volume, to_manifold
    from cubot_cad.robots.cube_robot import WHEEL_GAP_MM
    from cubot_cad.shapes import tight_bbox

    block = cube.wheel_block
    S, hi = cube.size_mm / 2, cube.size_mm / 2 - cube.wall_mm
    assert cube.steer_deg == 30.0
    # what else sits in the wheel block beside the steered wheels: the steering servo, the ground sensors
    near = [to_manifold(s) for c in cube.components() if c.key in ("steering_servo", "ground_sensor", "drive_motor")
            for s in c.solids()]
    assert len(near) == 6
    for f in STEPS:
        deg = f * cube.steer_deg
        for w in _front_wheels(cube, deg):
            assert _vol(block.solid, w) == pytest.approx(0.0, abs=1e-6), deg
            x0, y0, _z0, x1, y1, _z1 = tight_bbox(w)
            assert max(abs(x0), abs(x1), abs(y0), abs(y1)) <= hi - WHEEL_GAP_MM + 1e-6, deg  # inside the walls
            assert max(abs(x0), abs(x1), abs(y0), abs(y1)) < S, deg  # inside the 120 mm cube
            mw = to_manifold(w)
            assert all(intersection_volume(mw, m) < 1e-3 for m in near), deg
    # at full lock the wheels reach the gap to the walls (the track is as wide as the lock allows)
    y_reach = max(abs(tight_bbox(w)[k]) for w in _front_wheels(cube, cube.steer_deg) for k in (1, 4))
    assert y_reach == pytest.approx(hi - WHEEL_GAP_MM, abs=1e-3)


def test_the_sweep_sees_a_well_too_small_for_the_lock(cube):
    """The same sweep against a block whose wells are cut for unsteered wheels finds the turned wheels
    in its floor: the test measures what it claims."""
    from dataclasses import replace

    straight = replace(cube.wheel_block, steer_deg=0.0)
    assert sum(_vol(straight.solid, w) for w in _front_wheels(cube, cube.steer_deg)) > 1.0
    assert sum(_vol(straight.solid, w) for w in _front_wheels(cube, 0.0)) == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize("kw, name", [
    ({"wheel_y_mm": 48.0}, "wheel_y_mm 48"),  # the old track: past the walls at 30 deg
    ({"wheel_x_mm": 38.0}, "wheel_x_mm 38"),
    ({"steer_deg": 95.0}, "steer_deg"),
])
def test_a_layout_the_turned_wheels_cannot_fit_is_refused_naming_the_value(kw, name):
    from cubot_cad.robots.cube_robot import CubeRobot

    with pytest.raises(InputError) as exc:
        CubeRobot(**kw)
    assert name in str(exc.value) and "\n" not in str(exc.value)


def test_the_track_follows_the_lock():
    from cubot_cad.robots.cube_robot import CubeRobot

    assert CubeRobot().track_half_mm == pytest.approx(42.270, abs=1e-3)
    assert CubeRobot(steer_deg=20.0).track_half_mm > CubeRobot().track_half_mm
    assert CubeRobot(wheel_y_mm=40.0).track_half_mm == 40.0


# --- A2: the tiers bear, locate and fasten ----------------------------------------------------------------

def _bearing_mm2(lower, upper, z) -> float:
    """Contact area (mm^2) of ``lower``'s faces at height ``z`` with ``upper``'s: both cut 0.01 mm either
    side of the plane, the lower slice lifted onto the upper one, their overlap divided by 0.01 mm."""
    from cubot_cad.shapes import box

    e = 0.01
    a = lower.intersect(box(-100, 100, -100, 100, z - e, z)).translate((0, 0, e))
    b = upper.intersect(box(-100, 100, -100, 100, z, z + e))
    return a.intersect(b).Volume() / e


def _joints(cube):
    """(lower tier, upper tier, joint, interface height, upper tier's floor thickness) per interface."""
    return [(cube.wheel_block, cube.cuboid, cube.joint, cube.wheel_block_mm, cube.cuboid.floor_mm),
            (cube.cuboid, cube.sensor_tier, cube.top_joint, cube.cuboid.top_mm, cube.sensor_tier.floor_mm)]


def test_each_tier_bears_on_the_one_below_over_a_real_area(cube):
    for lower, upper, _j, z, _f in _joints(cube):
        area = _bearing_mm2(lower.solid, upper.solid, z)
        assert area >= MIN_BEARING_MM2, (lower.name, upper.name, area)


def test_tier_screws_go_through_the_upper_tier_into_inserts_in_bosses(cube):
    """Under each clearance hole of the upper tier the lower one has an open insert hole with a full ring
    of material round it; the screw (from the BOM) reaches into the insert and not past it, and its head
    sits free on the upper floor."""
    from cubot_cad.hardware.fasteners import clearance_hole_mm, thread
    from cubot_cad.shapes import Z, cyl

    others = [p.shape for p in cube.placed]
    screws = {u.where.split(":")[0]: u for u in cube.fasteners() if u.kind == "ISO 4762" and "latch" not in u.where}
    assert set(screws) == {"connector cuboid", "sensor tier"} and all(u.count == 4 for u in screws.values())
    for (lower, upper, j, z, f), who in zip(_joints(cube), ("connector cuboid", "sensor tier"), strict=True):
        ins = thread(j.screw_size)
        pts = j.screw_points(cube.size_mm / 2)
        assert len(pts) == 4
        screw = screws[who]
        assert screw.size == j.screw_size
        engaged = screw.length_mm - f
        assert ins.insert_length_mm / 2 <= engaged <= ins.insert_hole_depth_mm, (who, engaged)
        for x, y in pts:
            through = cyl(clearance_hole_mm(j.screw_size) / 2 - 0.05, f, (x, y, z), Z)
            assert _vol(upper.solid, through) == pytest.approx(0.0, abs=1e-6), (who, x, y)
            hole = cyl(ins.insert_hole_mm / 2 - 0.05, ins.insert_hole_depth_mm - 0.1,
                       (x, y, z - ins.insert_hole_depth_mm + 0.05), Z)
            assert _vol(lower.solid, hole) == pytest.approx(0.0, abs=1e-6), (who, x, y)
            d = ins.insert_hole_depth_mm
            ring = cyl(ins.insert_hole_mm / 2 + 1.5, d, (x, y, z - d), Z).cut(
                cyl(ins.insert_hole_mm / 2 + 0.05, d, (x, y, z - d), Z))
            assert _vol(lower.solid, ring) == pytest.approx(ring.Volume(), rel=1e-3), (who, x, y)
            # and under the insert, material: the boss continues below the hole
            below = cyl(ins.insert_hole_mm / 2, 0.5, (x, y, z - d - 0.6), Z)
            assert _vol(lower.solid, below) == pytest.approx(below.Volume(), rel=1e-3), (who, x, y)
            cap = cyl(ins.shcs_head_diameter_mm / 2, ins.shcs_head_height_mm, (x, y, z + f + 0.01), Z)
            hit = [v for s in others if (v := _vol(s, cap)) > 1e-6]
            assert not hit, (who, x, y, hit)


def test_stacked_tiers_do_not_interfere(cube):
    import itertools

    tiers = [cube.wheel_block.solid, cube.cuboid.solid, cube.sensor_tier.solid]
    for a, b in itertools.combinations(tiers, 2):
        assert _vol(a, b) == pytest.approx(0.0, abs=1e-6)
    # nor with the connector blocks screwed into the cuboid
    blocks = [p.shape for p in cube.placed if p.role != "body"]
    for t in tiers:
        for s in blocks:
            assert _vol(t, s) == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize("which", [0, 1])
def test_a_located_tier_slides_no_further_than_the_clearance(cube, which):
    """Pushed sideways within the print clearance the upper tier moves freely; pushed 0.1 mm further it
    bears on the tabs (cuboid) or the lip (sensor tier), in x and in y, either way."""
    lower, upper, j, _z, _f = _joints(cube)[which]
    c = j.clearance_mm
    for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        free = upper.solid.translate(((c - 0.02) * dx, (c - 0.02) * dy, 0))
        assert _vol(lower.solid, free) == pytest.approx(0.0, abs=1e-6), (upper.name, dx, dy)
        held = upper.solid.translate(((c + 0.1) * dx, (c + 0.1) * dy, 0))
        assert _vol(lower.solid, held) > 0.5, (upper.name, dx, dy)


def test_the_wheel_block_and_the_cuboids_bosses_print_without_support(cube):
    """Every face of the wheel block that looks straight down lies on the bed (the wells go through the
    floor; bosses and ribs hang from the walls on 45 deg undersides), and so do the cuboid's new bosses."""
    block = cube.wheel_block
    down = [fc for fc in block.solid.Faces() if fc.geomType() == "PLANE" and fc.normalAt().z < -0.99
            and fc.Center().z > 1e-6 and fc.Area() > 0.05]
    assert down == [], [fc.Center() for fc in down]
    assert block.support == ""
    cub = cube.cuboid
    hi, z1 = cube.size_mm / 2 - cube.wall_mm, cub.top_mm
    corner = [fc for fc in cub.solid.Faces() if min(abs(fc.Center().x), abs(fc.Center().y)) > hi - cub.above.boss_mm - 0.5
              and fc.Center().z > z1 - cub.above.boss_depth_mm - cub.above.boss_mm - 1]
    assert sum(1 for fc in corner if -0.75 < fc.normalAt().z < -0.65) >= 8  # the 45 deg undersides
    assert [fc for fc in corner if fc.geomType() == "PLANE" and fc.normalAt().z < -0.99 and fc.Area() > 0.05] == []


def test_the_bom_lists_the_tier_screws_and_inserts(cube):
    from cubot_cad.outputs.bom import bom_rows

    rows = {x["item"]: x for x in bom_rows(cube, 1040.0) if x["category"] == "fastener"}
    assert int(rows["M3 insert"]["quantity"]) == 8
    assert int(rows["M3x8 ISO 4762"]["quantity"]) == 8
