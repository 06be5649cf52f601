"""Fasteners as data: the ISO table, and every screw hole of every part taken from it (a table
change moves every hole; a hole left as a literal would stay where it was)."""

from __future__ import annotations

import dataclasses
from collections import Counter

import pytest

from cubot_cad.hardware import fasteners


def test_the_table_is_consistent_with_its_standards():
    for size, t in fasteners.THREADS.items():
        assert size == f"M{t.nominal_mm:g}"
        # ISO 2306 tap drill < nominal < ISO 273 fine < medium < coarse < heat-set insert hole
        assert t.tap_drill_mm < t.nominal_mm < t.clearance_fine_mm < t.clearance_medium_mm < t.clearance_coarse_mm
        assert t.clearance_coarse_mm < t.insert_hole_mm
        assert t.shcs_head_diameter_mm > t.clearance_coarse_mm and t.nut_flats_mm > t.insert_hole_mm - 0.5
        assert t.insert_hole_depth_mm == pytest.approx(t.insert_length_mm + 0.5)
    m3 = fasteners.thread("M3")
    assert (m3.clearance_medium_mm, m3.tap_drill_mm, m3.insert_hole_mm) == (3.4, 2.5, 4.0)
    assert fasteners.clearance_hole_mm("M2.5", "fine") == 2.7
    with pytest.raises(fasteners.InputError, match="M4"):
        fasteners.thread("M4")
    with pytest.raises(fasteners.InputError, match="snug"):
        fasteners.clearance_hole_mm("M3", "snug")


def test_screw_lengths_come_from_the_preferred_series():
    assert fasteners.screw_length_mm(17.8) == 20.0 and fasteners.screw_length_mm(8.0) == 8.0
    (screw, insert) = fasteners.bolted("x", "M3", 3.0, 4, "cover", insert=True)
    assert screw.length_mm == 8.0 and insert.kind == "insert"  # 3 mm cover + 5 mm into the 5.7 mm insert
    screw, nut = fasteners.bolted("x", "M3", 14.4, 8, "block", nut=True, kind="ISO 10642")
    assert screw.length_mm == 20.0 and nut.kind == "ISO 4032" and "countersunk" in screw.description


def _circles(robot) -> dict[str, Counter]:
    out = {}
    for part, _ in robot.printable_parts():
        out[f"{robot.name}/{part.name}"] = Counter(round(e.radius(), 4) for e in part.solid.Edges() if e.geomType() == "CIRCLE")
    return out


def _fresh_robots():
    from cubot_cad.robots.cube_robot import CubeRobot
    from cubot_cad.robots.cubot import CuBot
    from cubot_cad.robots.octbot import OctBot
    from cubot_cad.robots.platform import TestPlatform

    return [CuBot(), OctBot(), CubeRobot(), TestPlatform()]


def test_every_screw_hole_follows_the_table(monkeypatch):
    """Move the M3 clearance (3.4 -> 3.8), tap (2.5 -> 2.3) and insert (4.0 -> 4.4) holes in the table and
    rebuild every robot: every part that had such holes has them at the new size, and none is left at
    the old one (the grooved pin's 3.4 mm groove is the only other 1.7 mm radius)."""
    before = {}
    for r in _fresh_robots():
        before.update(_circles(r))
    m3 = fasteners.THREADS["M3"]
    monkeypatch.setitem(fasteners.THREADS, "M3", dataclasses.replace(
        m3, clearance_medium_mm=3.8, tap_drill_mm=2.3, insert_hole_mm=4.4))
    after = {}
    for r in _fresh_robots():
        after.update(_circles(r))
    assert set(before) == set(after)
    moved = Counter()
    for name in before:
        for old, new, what in ((1.7, 1.9, "clearance"), (1.25, 1.15, "tap"), (2.0, 2.2, "insert")):
            gone = before[name][old] - after[name][old]
            came = after[name][new] - before[name][new]
            assert gone == came, (name, what, gone, came)
            moved[what] += came
            if what == "clearance" and not name.endswith("/pinset_e_grooved_pin"):
                assert after[name][old] == 0, (name, "a clearance hole that is not from the table")
        assert after["cubot/pinset_e_grooved_pin"] == before["cubot/pinset_e_grooved_pin"]
    # the screw holes that exist: block stacks, cover, key bearing, floor, ring, platform; caster tap holes;
    # the cover bosses' inserts
    assert moved["clearance"] >= 40 and moved["tap"] >= 2 and moved["insert"] >= 8, moved
    for name in ("cubot/cubot_body", "cubot/cover_cross_hole", "cubot/key_bearing", "cubot/latchset_a_front_locking_plate",
                 "octbot/octbot_ring", "octbot/octbot_body", "cube-robot/cube_connector_cuboid",
                 "platform/test_platform", "cubot/caster_seat"):
        assert sum(after[name][v] - before[name][v] for v in (1.9, 1.15, 2.2)) > 0, name


def test_every_robot_lists_its_fasteners_from_the_table(robots):
    for name, r in robots.items():
        uses = r.fasteners()
        assert uses, name
        for u in uses:
            assert u.size in fasteners.THREADS and u.count > 0
            assert u.kind in fasteners.STANDARDS
    cub = {(u.kind, u.where): u for u in robots["cubot"].fasteners()}
    assert cub[("insert", "cover into the body's corner bosses")].count == 4
