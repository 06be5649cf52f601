"""The print clearance: one advertised range (0.1-0.5 mm per side), and every value in it
builds, docks and exports every robot; values outside it are refused naming the value."""

from __future__ import annotations

import math

import pytest

from cubot_cad.checks.docking import GAP_TOLERANCE_MM, INTERFERENCE_LIMIT_MM3, PAIRS
from cubot_cad.errors import InputError
from cubot_cad.part import (
    LENGTH_TOL_MM,
    MAX_CLEARANCE_MM,
    MIN_CLEARANCE_MM,
    MIN_WALL_MM,
    check_clearance,
)
from cubot_cad.robots.registry import ROBOT_NAMES

ENDS = (MIN_CLEARANCE_MM, MAX_CLEARANCE_MM)
#: Every 0.01 mm of the range. 0.4 is the value a float comparison used to refuse
#: (3 - 1.8 - 0.4 = 0.7999999999999998 < 0.8) for CuBot and the Cube Robot.
GRID = tuple(round(MIN_CLEARANCE_MM + 0.01 * i, 2)
             for i in range(round((MAX_CLEARANCE_MM - MIN_CLEARANCE_MM) / 0.01) + 1))


def test_the_range_is_the_fdm_one_and_the_cli_advertises_it(cli):
    assert (MIN_CLEARANCE_MM, MAX_CLEARANCE_MM) == (0.1, 0.5)
    assert 0.2 in GRID and 0.4 in GRID and GRID[0] == MIN_CLEARANCE_MM and GRID[-1] == MAX_CLEARANCE_MM
    for sub in ("export", "dock", "render"):
        res = cli("cad", sub, "--help")
        assert res.code == 0
        assert "0.1-0.5 mm" in " ".join(res.out.split()), sub


@pytest.mark.parametrize("value", [MIN_CLEARANCE_MM, 0.3, 0.4, MAX_CLEARANCE_MM,
                                   0.1 + 0.2 - 0.2, 0.7 - 0.2])  # last two: not exactly 0.1 / 0.5 in binary
def test_values_in_the_range_are_accepted(value):
    assert check_clearance(value) == pytest.approx(value)


@pytest.mark.parametrize("value", [0.0, 0.05, MIN_CLEARANCE_MM - 10 * LENGTH_TOL_MM,
                                   MAX_CLEARANCE_MM + 10 * LENGTH_TOL_MM, 0.51, 1.0, -0.2])
def test_values_outside_the_range_are_refused_naming_the_value(value):
    with pytest.raises(InputError) as exc:
        check_clearance(value, "--clearance-mm")
    msg = str(exc.value)
    assert msg.startswith(f"--clearance-mm {value:g} mm") and "0.1-0.5 mm" in msg and "\n" not in msg


@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_every_robot_accepts_every_clearance_of_the_range(name):
    """Every dimension check passes at every 0.01 mm of the range (no float trap, no fixed
    dimension that the clearance outgrows)."""
    from cubot_cad.robots.registry import _make_robot

    for c in GRID:
        _make_robot.__wrapped__(name, c)  # uncached: a fresh validation at every value


@pytest.mark.parametrize("c", (MIN_CLEARANCE_MM, 0.4, MAX_CLEARANCE_MM))
def test_every_part_of_every_robot_builds_at_the_ends_of_the_range_and_at_0_4(c):
    from cubot_cad.robots.registry import make_robot

    for name in ROBOT_NAMES:
        for part, _ in make_robot(name, c).printable_parts():
            assert part.volume_mm3 > 0, (name, part.name)  # one solid (Part.solid raises otherwise)


@pytest.mark.parametrize("c", (MIN_CLEARANCE_MM, 0.4, MAX_CLEARANCE_MM))
def test_pin_head_shoulder_and_locking_wall_keep_their_size_as_the_clearance_grows(c):
    """What failed at 0.4 (and would at 0.45): the head (a fixed 7.5 mm) overlapping its hole
    (pin + 2c) and the pin-locking plate (a fixed 3 mm) in front of its counterbore (head + c).
    Measured on the solids: the head overlaps the hole by the same 1.05 mm shoulder and the
    plate keeps a 1 mm wall in front of the counterbore at every clearance; the head has
    exactly the clearance as axial play."""
    from cubot_cad.couplings.connectors import (
        FrontRearSpec,
        GroovedPin,
        PinIrPlate,
        PinLockingPlate,
    )
    from cubot_cad.shapes import location, tight_bbox

    s = FrontRearSpec(clearance_mm=c)
    y, z = s.pin_positions()[0]
    pin = GroovedPin(spec=s).solid
    head_r = (tight_bbox(pin)[4] - tight_bbox(pin)[1]) / 2
    hole_r = max(e.radius() for e in PinIrPlate(spec=s).solid.Edges()
                 if e.geomType() == "CIRCLE" and abs(e.Center().y - y) < 1e-6 and abs(e.Center().z - z) < 1e-6)
    assert hole_r == pytest.approx(s.pin_diameter_mm / 2 + c, abs=1e-6)
    assert head_r - hole_r == pytest.approx(1.05, abs=1e-6) and head_r - hole_r >= MIN_WALL_MM
    plate = PinLockingPlate(spec=s).solid
    x_front = tight_bbox(plate)[3]
    floor_x = [e.Center().x for e in plate.Edges()
               if e.geomType() == "CIRCLE" and abs(e.radius() - (head_r + c)) < 1e-6 and e.Center().x > tight_bbox(plate)[0] + 0.05]
    assert floor_x, "no counterbore floor found"
    assert x_front - max(floor_x) == pytest.approx(1.0, abs=1e-6)
    placed = pin.moved(location((0, y, z)))
    assert plate.distance(placed) == pytest.approx(c, abs=1e-6)  # head free by c, no contact
    assert plate.intersect(placed).Volume() == pytest.approx(0.0, abs=1e-9)


@pytest.fixture(scope="module")
def range_pairs():
    from cubot_cad.checks.docking import dock

    return {c: {name: dock(name, c) for name in PAIRS} for c in ENDS}


@pytest.mark.parametrize("c", ENDS)
@pytest.mark.parametrize("name", PAIRS)
def test_docked_pairs_keep_their_designed_gap_without_interference_across_the_range(range_pairs, pairs, c, name):
    p = range_pairs[c][name]
    assert p.interference_mm3 <= INTERFERENCE_LIMIT_MM3, p.summary()
    assert abs(p.gap_mm - p.design_gap_mm) <= GAP_TOLERANCE_MM, p.summary()
    assert p.ok
    # the designed gap does not depend on the clearance: the same as at the default 0.2 mm
    assert p.design_gap_mm == pytest.approx(pairs[name].design_gap_mm, abs=1e-9)


@pytest.mark.parametrize("c", ENDS)
def test_every_robot_exports_at_the_ends_of_the_range(range_pairs, tmp_path, c):
    from cubot_cad.outputs.export import export_robots
    from cubot_cad.properties import RobotPropertiesFile

    res = export_robots(ROBOT_NAMES, tmp_path / "out", ("stl",), "abs", c, pairs=list(range_pairs[c].values()))
    assert {p.robot for p in res.parts} == set(ROBOT_NAMES)
    assert all(p.watertight and p.fits_bed for p in res.parts), [p.part for p in res.parts if not p.watertight]
    props = RobotPropertiesFile.load(res.properties)
    assert props.get("cubot").connector("front_rear").gap_m == 0.0
    assert props.get("cube-robot").connector("front_rear").gap_m == pytest.approx(0.0017, abs=2e-5)
    # the rail's backlash is the clearance over the half-width of the tongue's tip (6 mm)
    assert props.get("cubot").connector("side_rail").backlash_rad == pytest.approx(c / 6.0, rel=1e-9)
    assert all(math.isfinite(r.mass_kg) and r.mass_kg > 0 for r in props.robots)


def test_the_cli_exports_cubot_and_cube_robot_at_0_4(cli, tmp_path):
    """The reported failure: `--clearance-mm 0.4` refused for CuBot and Cube Robot, naming head_mm."""
    res = cli("cad", "export", "--robot", "cubot,cube-robot", "--clearance-mm", "0.4", "--format", "stl",
              "--out", str(tmp_path / "out"), "--json")
    assert res.code == 0, res.err
    out = res.json()
    assert out["all_watertight"] and out["clearance_mm"] == 0.4
    rows = {r["pair"]: r for r in out["docked_pairs"]}
    assert set(rows) == {"cubot-front-rear", "cubot-side-rail", "cubot-top-down", "cube-robot-front-rear",
                         "cube-robot-side"}
    for r in rows.values():
        assert r["ok"] and abs(r["gap_mm"] - r["design_gap_mm"]) <= GAP_TOLERANCE_MM, r


def test_a_robot_that_cannot_take_a_clearance_names_the_clearance(monkeypatch):
    """Should a robot ever not build at an accepted clearance, the error names the value the user
    set (--clearance-mm), not a connector dimension the command line cannot reach (head_mm)."""
    import cubot_cad.couplings.connectors as connectors
    from cubot_cad.robots.registry import make_robot

    monkeypatch.setattr(connectors, "MIN_LATCH_OVERLAP_MM", 0.5)  # a stricter latch: fails above 0.3 mm
    with pytest.raises(InputError) as exc:
        make_robot("cube-robot", 0.43)
    msg = str(exc.value)
    assert msg.startswith("--clearance-mm 0.43: the cube-robot cannot be built with it (") and "\n" not in msg
