"""Piers of failed CuBots (issue 16): a column of k robots stacked with the top-down coupling.

The column is placed by the coupling's own docked offset; its heights, its contacts and its
checks are measured on the CAD (cubot_cad.pier)."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest

from cubot_cad.docking import GAP_TOLERANCE_MM, INTERFERENCE_LIMIT_MM3
from cubot_cad.errors import InputError
from cubot_cad.pier import PIER_PAIR, PierColumn


@pytest.fixture(scope="module")
def cubot():
    from cubot_cad.export import make_robot

    return make_robot("cubot")


@pytest.fixture(scope="module")
def top_down():
    """The measured pair (docking's own cache: shared with the session's ``pairs``)."""
    from cubot_cad.docking import dock

    return dock(PIER_PAIR)


@pytest.fixture(scope="module")
def column(cubot, top_down):
    """Three stacked CuBots: a bottom, a middle and a top robot (every connector state)."""
    return PierColumn(cubot, 3, docked=top_down)


# --- heights ----------------------------------------------------------------------------------

def test_pitch_is_the_top_down_couplings_docked_offset(column, top_down, cubot):
    off = top_down.offset_mm
    assert column.stack_pitch_mm == off[2]
    for i, o in enumerate(column.offsets_mm):  # robot i at i x the coupling's offset, straight up
        assert o == pytest.approx(tuple(i * v for v in off), abs=1e-12)
    assert off[0] == pytest.approx(0.0, abs=1e-9) and off[1] == pytest.approx(0.0, abs=1e-9)
    # the docked offset is cover top (74.8 mm) + the upper robot standing on its 15 mm of wheel
    assert column.cover_top_mm == pytest.approx(cubot.body_height_mm + cubot.top_spec.cover_mm, abs=1e-6)
    assert column.stack_pitch_mm == pytest.approx(74.8 + 15.0, abs=GAP_TOLERANCE_MM)


def test_standing_height_is_floor_to_cover_on_the_cads_exposed_heights(column, cubot):
    assert column.floor_depths_mm["wheels"] == pytest.approx(cubot.wheel_exposed_mm)
    assert column.floor_depths_mm["casters"] == pytest.approx(15.0, abs=1e-6)  # seat -12.2 mm, ball 2.78 mm below
    assert column.level_mm == pytest.approx(0.0, abs=1e-6)  # stands level on wheels and casters
    assert column.standing_height_mm == pytest.approx(15.0 + 74.8, abs=1e-6)
    # standing on the floor and standing on a cover are the same stance: height == pitch
    assert column.standing_height_mm == pytest.approx(column.stack_pitch_mm, abs=GAP_TOLERANCE_MM)


@pytest.mark.parametrize("k", [1, 2])
def test_k_plus_one_robots_is_exactly_one_pitch_taller(cubot, top_down, k):
    lo, hi = PierColumn(cubot, k, docked=top_down), PierColumn(cubot, k + 1, docked=top_down)
    # measured on the placed top covers, not by the formula
    assert hi.measured_top_height_mm() - lo.measured_top_height_mm() == pytest.approx(hi.stack_pitch_mm, abs=1e-6)
    assert lo.measured_top_height_mm() == pytest.approx(lo.top_height_mm(), abs=1e-6)
    assert hi.top_height_mm() == pytest.approx(lo.standing_height_mm + k * lo.stack_pitch_mm, abs=1e-9)
    assert PierColumn(cubot, 1, docked=top_down).top_height_mm() == lo.standing_height_mm


def test_the_height_moves_with_the_robots_body_height(column):
    """A CuBot 5 mm lower (height_mm 80) docks 5 mm lower: pitch, standing and pier heights follow."""
    from cubot_cad.cubot import CuBot

    low = PierColumn(CuBot(height_mm=80.0), 2)  # docked here, on the new robot's own geometry
    assert low.cover_top_mm == pytest.approx(column.cover_top_mm - 5.0, abs=1e-6)
    assert low.stack_pitch_mm == pytest.approx(column.stack_pitch_mm - 5.0, abs=GAP_TOLERANCE_MM)
    assert low.standing_height_mm == pytest.approx(column.standing_height_mm - 5.0, abs=1e-6)
    assert low.measured_top_height_mm() == pytest.approx(column.top_height_mm(2) - 10.0, abs=2 * GAP_TOLERANCE_MM)
    assert low.pair.ok, low.pair.problems()


# --- checks ---------------------------------------------------------------------------------

def test_the_column_has_no_interference(column, cubot, top_down):
    it = column.interference
    assert [r["robots"] for r in it["pairs"]] == [[1, 2], [2, 3]]  # only neighbours come near
    assert it["ok"] and it["max_mm3"] <= INTERFERENCE_LIMIT_MM3
    # and the measurement sees a real overlap: stacked 1 mm too low, the wheels sink into the cover
    sunk = dataclasses.replace(top_down, offset_mm=(0.0, 0.0, top_down.offset_mm[2] - 1.0))
    bad = PierColumn(cubot, 2, docked=sunk).interference
    assert not bad["ok"] and bad["max_mm3"] > 10 * INTERFERENCE_LIMIT_MM3


def test_every_interface_docks_and_its_key_engages(column):
    dk = column.docking
    assert dk["pair_ok"] and dk["ok"]
    assert [r["interface"] for r in dk["interfaces"]] == [[1, 2], [2, 3]]
    for r in dk["interfaces"]:
        assert r["turned_key_lifted_into_roof_mm3"] > 10  # the turned key is held by the collar roof
        assert r["aligned_key_lifted_into_roof_mm3"] <= 1.0  # aligned, it comes out (as it went in)
        assert r["aligned_key_into_locking_key_mm3"] > 10  # the locking key stops it turning back
    assert dk["pull_out_play_mm"] == pytest.approx(0.2)  # = the clearance under the roof


def test_the_running_surface_is_blocked_by_the_collar(column):
    """What the CAD says about a line robot rolling over the pier's top cover: its lowest part
    besides wheels and casters (the caster seats, 2.78 mm) is lower than the collar (8.7 mm),
    which lies in the track of its cross key and casters; the right wheel runs over two cover
    screws' 3 mm socket heads. The top cover is not a running surface as the robot is drawn."""
    rs = column.running_surface
    assert not rs["ok"] and rs["wheels_on_cover"]
    assert rs["ground_clearance_mm"] == pytest.approx(2.775, abs=0.01)
    assert rs["lowest_line_part"] == "caster_seat"
    collar = next(p for p in rs["protrusions"] if p["part"] == "cover_cross_hole")
    assert collar["height_mm"] == pytest.approx(8.705, abs=0.01) and collar["blocks"]
    assert {m["line_part"] for m in collar["meets"]} == {"cross_key", "caster_seat", "caster_ball"}
    heads = [p for p in rs["protrusions"] if p["role"] == "screw_head"]
    assert len(heads) == 4 and sum(p["blocks"] for p in heads) == 2  # under the right wheel only
    assert all(m["line_part"] == "wheel" for p in heads for m in p["meets"])
    assert set(rs["blocking"]) == {"cover_cross_hole"} | {p["part"] for p in heads if p["blocks"]}


def test_stability_margin_is_com_to_edge_less_lean_times_height(column):
    poly = column.support_polygon_mm  # wheel treads (0, +-31..39) and the casters (+-38, 0)
    assert sorted(poly) == sorted([(-38.0, 0.0), (0.0, -39.0), (38.0, 0.0), (0.0, 39.0)])
    st0, st5 = column.stability(0.0), column.stability(5.0)
    assert st0["margin_mm"] == st0["com_to_edge_mm"] > 20
    h = column.com_height_mm
    assert h == pytest.approx(15.0 + column.robot.mass_properties().com_m[2] * 1000 + column.stack_pitch_mm, abs=1e-6)
    assert st5["margin_mm"] == pytest.approx(st0["com_to_edge_mm"] - h * math.tan(math.radians(5)), abs=2e-3)
    assert math.tan(math.radians(st5["tipping_deg"])) == pytest.approx(st0["com_to_edge_mm"] / h, rel=1e-4)
    assert st5["ok"] and not column.stability(st5["tipping_deg"] + 0.1)["ok"]
    with pytest.raises(InputError, match="lean_deg 60"):
        column.stability(60)


def test_mass_and_com_are_k_robots(column):
    one = column.robot.mass_properties()
    assert column.mass_kg == pytest.approx(3 * one.mass_kg)
    assert column.com_mm[2] == pytest.approx(one.com_m[2] * 1000 + column.stack_pitch_mm)


# --- validation and CLI -----------------------------------------------------------------------

@pytest.mark.parametrize("k", [0, 9, -1, 2.5, True, "3"])
def test_a_bad_robot_count_is_one_line_naming_it(cubot, k):
    with pytest.raises(InputError) as exc:
        PierColumn(cubot, k)
    assert "\n" not in str(exc.value) and f"robots {k!r}" in str(exc.value)


def test_only_a_robot_with_the_top_down_coupling_stacks():
    from cubot_cad.export import make_robot

    with pytest.raises(InputError, match="octbot has none"):
        PierColumn(make_robot("octbot"), 2)


@pytest.mark.parametrize("value", ["9", "0", "-2", "x", "2.5"])
def test_cli_bad_k_exits_2_with_one_error_line(cli, tmp_path, value):
    out = tmp_path / "pier"
    res = cli("cad", "pier", "--robots", value, "--out", str(out))
    assert res.code == 2, res.err
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:")
    assert f"--robots {value}" in res.error_lines[0] or f"--robots '{value}'" in res.error_lines[0]
    assert not out.exists()


def test_cli_writes_numbers_step_and_glb(cli, tmp_path, top_down):
    res = cli("cad", "pier", "--robots", "2", "--out", str(tmp_path), "--json")
    out = res.json()
    assert res.code == (0 if out["ok"] else 1), res.err  # 1: the running surface check fails (above)
    assert out["robots"] == 2 and out["stack_pitch_mm"] == pytest.approx(top_down.offset_mm[2], abs=1e-4)
    assert out["heights_mm"]["2"] == pytest.approx(out["standing_height_mm"] + out["stack_pitch_mm"], abs=1e-3)
    for f in ("pier-cubot-2.step", "pier-cubot-2.glb", "pier-cubot-2.json"):
        assert (tmp_path / f).stat().st_size > 0
    assert json.loads((tmp_path / "pier-cubot-2.json").read_text())["checks"]["docking"]["ok"]
    import trimesh

    from cubot_cad.gltf import cad_bounds_mm

    b = cad_bounds_mm(trimesh.load(tmp_path / "pier-cubot-2.glb").bounds)
    assert b[1][2] == pytest.approx(out["top_height_mm"] - 15.0 + 8.705, abs=0.3)  # top robot's collar


# --- the properties record --------------------------------------------------------------------

def test_record_fields_are_the_columns_numbers(column, cubot, top_down):
    from cubot_cad.pier import record_fields

    f = record_fields(cubot, top_down)
    assert f["standing_height_m"] == pytest.approx(column.standing_height_mm / 1000, abs=1e-12)
    assert f["stack_pitch_m"] == pytest.approx(column.stack_pitch_mm / 1000, abs=1e-12)
    assert "docked offset" in f["stack_pitch_source"] and "wheel" in f["standing_height_source"]
    design = record_fields(cubot, None)  # an export without docking: the designed pitch
    assert design["stack_pitch_m"] == pytest.approx(0.0898, abs=1e-9) and "design" in design["stack_pitch_source"]


def test_packaged_record_carries_standing_height_and_pitch():
    from cubot_cad.properties import default_properties

    props = default_properties()
    cub = props.get("cubot")
    assert cub.standing_height_m == pytest.approx(0.0898, abs=1e-6)
    assert cub.stack_pitch_m == pytest.approx(0.0898, abs=GAP_TOLERANCE_MM / 1000)
    assert cub.standing_height_source and cub.stack_pitch_source
    assert cub.pier_height_m(4) == pytest.approx(cub.standing_height_m + 3 * cub.stack_pitch_m)
    for name in ("octbot", "cube-robot", "platform"):  # no top-down coupling: they do not stack
        r = props.get(name)
        assert r.standing_height_m is None and r.stack_pitch_m is None and r.stack_pitch_source is None
        with pytest.raises(InputError, match="no standing height"):
            r.pier_height_m(2)


def test_record_round_trips_with_and_without_the_new_fields(tmp_path):
    from cubot_cad.pier import add_record_fields
    from cubot_cad.properties import RobotPropertiesFile, default_properties

    props = default_properties()
    path = props.save(tmp_path / "with.json")
    assert RobotPropertiesFile.load(path) == props
    data = props.to_dict()
    for r in data["robots"]:
        for k in ("standing_height_m", "standing_height_source", "stack_pitch_m", "stack_pitch_source"):
            r.pop(k)
    old = tmp_path / "old.json"
    old.write_text(json.dumps(data))
    legacy = RobotPropertiesFile.load(old)  # a record from before the fields loads, without them
    assert legacy.get("cubot").standing_height_m is None and legacy.get("cubot").stack_pitch_source is None
    assert RobotPropertiesFile.load(legacy.save(tmp_path / "again.json")) == legacy
    cub = props.get("cubot")
    fields = {k: getattr(cub, k) for k in ("standing_height_m", "standing_height_source", "stack_pitch_m",
                                          "stack_pitch_source")}
    assert add_record_fields(old, {"cubot": fields}) == props  # what `cad export` adds back
    assert RobotPropertiesFile.load(old) == props


@pytest.mark.parametrize("change, match", [
    ({"stack_pitch_source": None}, "needs a stack_pitch_source"),
    ({"standing_height_m": None}, "standing_height_source is given without"),
    ({"stack_pitch_m": -0.09}, "stack_pitch_m must be in"),
    ({"standing_height_m": float("nan")}, "standing_height_m must be in"),
])
def test_bad_stacking_fields_are_named(change, match):
    from cubot_cad.properties import default_properties

    with pytest.raises(InputError, match=match):
        dataclasses.replace(default_properties().get("cubot"), **change)


@pytest.mark.parametrize("argv, word", [
    (("--robots", "2", "--clearance-mm", "0.05"), "--clearance-mm 0.05"),
    (("--robots", "2", "--lean-deg", "50"), "--lean-deg 50"),
])
def test_cli_other_bad_values_exit_2_before_any_work(cli, tmp_path, argv, word):
    out = tmp_path / "pier"
    res = cli("cad", "pier", *argv, "--out", str(out))
    assert res.code == 2 and len(res.error_lines) == 1 and word in res.error_lines[0], res.err
    assert not out.exists()


def test_cad_export_adds_the_fields_for_the_robots_that_stack(top_down):
    """`cad export` (do_export) computes them before writing: measured pitch with docking,
    designed pitch without; the robots without a top-down coupling get none."""
    from voidcross.commands.cad import _stack_fields

    got = _stack_fields(("cubot", "octbot", "platform"), 0.2, [top_down])
    assert set(got) == {"cubot"}
    assert got["cubot"]["stack_pitch_m"] == top_down.offset_mm[2] / 1000
    assert "design" in _stack_fields(("cubot",), 0.2, None)["cubot"]["stack_pitch_source"]
