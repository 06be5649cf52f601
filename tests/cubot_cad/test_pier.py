"""Piers of failed CuBots (issue 16): a column of k robots stacked with the top-down coupling,
with the printed deck on the top robot that the line rolls over.

The column is placed by the coupling's own docked offset, the deck by its own docking on the top
robot's collar; heights, contacts and checks are measured on the CAD (cubot_cad.piers.pier,
cubot_cad.piers.deck)."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest

from cubot_cad.checks.docking import GAP_TOLERANCE_MM, INTERFERENCE_LIMIT_MM3
from cubot_cad.errors import InputError
from cubot_cad.piers.deck import PierDeck
from cubot_cad.piers.pier import PIER_PAIR, PierColumn


@pytest.fixture(scope="module")
def cubot():
    from cubot_cad.robots.registry import make_robot

    return make_robot("cubot")


@pytest.fixture(scope="module")
def top_down():
    """The measured pair (docking's own cache: shared with the session's ``pairs``)."""
    from cubot_cad.checks.docking import dock

    return dock(PIER_PAIR)


@pytest.fixture(scope="module")
def column(cubot, top_down):
    """Three stacked CuBots: a bottom, a middle and a top robot (every connector state), the deck
    on the top one (the default)."""
    return PierColumn(cubot, 3, docked=top_down)


@pytest.fixture(scope="module")
def bare(cubot, top_down):
    """The same column without the deck: the line would roll on the top robot's cover."""
    return PierColumn(cubot, 3, docked=top_down, deck=False)


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
    from cubot_cad.robots.cubot import CuBot

    low = PierColumn(CuBot(height_mm=80.0), 2)  # docked here, on the new robot's own geometry
    assert low.cover_top_mm == pytest.approx(column.cover_top_mm - 5.0, abs=1e-6)
    assert low.stack_pitch_mm == pytest.approx(column.stack_pitch_mm - 5.0, abs=GAP_TOLERANCE_MM)
    assert low.standing_height_mm == pytest.approx(column.standing_height_mm - 5.0, abs=1e-6)
    assert low.measured_top_height_mm() == pytest.approx(column.top_height_mm(2) - 10.0, abs=2 * GAP_TOLERANCE_MM)
    assert low.pair.ok, low.pair.problems()


# --- checks ---------------------------------------------------------------------------------

def test_the_column_has_no_interference(column, cubot, top_down):
    it = column.interference
    assert [r["robots"] for r in it["pairs"]] == [[1, 2], [2, 3], [3, "deck"]]  # only neighbours come near
    assert it["ok"] and it["max_mm3"] <= INTERFERENCE_LIMIT_MM3
    # and the measurement sees a real overlap: stacked 1 mm too low, the wheels sink into the cover
    sunk = dataclasses.replace(top_down, offset_mm=(0.0, 0.0, top_down.offset_mm[2] - 1.0))
    bad = PierColumn(cubot, 2, docked=sunk, deck=False).interference
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


def test_without_the_deck_the_running_surface_is_blocked_by_the_collar(bare):
    """What the CAD says about a line robot rolling over the pier's bare top cover: its lowest part
    besides wheels and casters (the caster seats, 2.78 mm) is lower than the collar (8.7 mm),
    which lies in the track of its cross key and casters; each wheel runs over two cover screws'
    3 mm socket heads (wheels and cover screws are both centred on the body). The top cover is not a
    running surface as the robot is drawn."""
    rs = bare.running_surface
    assert not rs["ok"] and rs["wheels_on_surface"] and rs["surface"] == "top cover"
    assert bare.deck_height_mm is None and bare.running_surface_mm() == bare.top_height_mm()
    assert rs["ground_clearance_mm"] == pytest.approx(2.775, abs=0.01)
    assert rs["lowest_line_part"] == "caster_seat"
    collar = next(p for p in rs["protrusions"] if p["part"] == "cover_cross_hole")
    assert collar["height_mm"] == pytest.approx(8.705, abs=0.01) and collar["blocks"]
    assert {m["line_part"] for m in collar["meets"]} == {"twist_key", "caster_seat", "caster_ball"}
    heads = [p for p in rs["protrusions"] if p["role"] == "screw_head"]
    assert len(heads) == 4 and sum(p["blocks"] for p in heads) == 4  # under both wheels
    assert all(m["line_part"] == "wheel" for p in heads for m in p["meets"])
    assert set(rs["blocking"]) == {"cover_cross_hole"} | {p["part"] for p in heads if p["blocks"]}
    assert rs["clearance_margin_mm"] == pytest.approx(2.775 - 8.705, abs=0.02)  # negative: it does not pass


# --- the deck -------------------------------------------------------------------------------------

def test_the_deck_docks_on_the_collar(column, cubot):
    """Lowered open (turned 45 deg: its key aligned with the cross hole) it stands on its ring with
    the key-mount face at the coupling's stance, turns square touching nothing (the cover screws'
    heads included), does not interfere with the locking key in, and its key engages: held by the
    roof when lifted square, free when lifted open, stopped by the locking key turning back."""
    from cubot_cad.checks.docking import _near_union, intersection_volume, manifold_of
    from cubot_cad.piers.deck import TWIST_STEPS, _deck_manifolds

    dd = column.deck_dock
    assert dd.ok, dd.problems()
    assert dd.stand_mm == pytest.approx(cubot.top_spec.stand_mm, abs=GAP_TOLERANCE_MM)
    assert dd.offset_mm == pytest.approx((0.0, cubot.y_centre_mm, column.cover_top_mm), abs=GAP_TOLERANCE_MM)
    assert [r["turn_deg"] for r in dd.twist] == pytest.approx([45.0 * (1 - i / TWIST_STEPS)
                                                               for i in range(TWIST_STEPS + 1)])
    assert all(r["interference_mm3"] <= INTERFERENCE_LIMIT_MM3 for r in dd.twist)
    assert dd.interference_mm3 <= INTERFERENCE_LIMIT_MM3
    k = dd.keys
    assert k["turned_key_lifted_into_roof_mm3"] > 10 and k["aligned_key_lifted_into_roof_mm3"] <= 1.0
    assert k["aligned_key_into_locking_key_mm3"] > 10 and k["pull_out_play_mm"] == pytest.approx(0.2)
    # the key is the robots' cross head (same spec as the robot's twist key), on a flange, mounted turned
    robot_key = next(p.part for p in cubot.placed if p.role == "cross_key")
    assert column.deck_part.key.spec is robot_key.spec is cubot.top_spec
    # and the measurement sees real overlaps: 1 mm low the ring sinks into the cover; a ring of
    # radius 58 (past the check_fits guard) would sweep through the cover screws' heads turning on
    robot = [manifold_of(p) for p in cubot.build_placed()]
    low = tuple(v - (0, 0, 1.0)[i] for i, v in enumerate(dd.offset_mm))
    a, b = _near_union(robot, _deck_manifolds(dd.deck, 0.0, low), [(0.0, 0.0, 0.0)])
    assert intersection_volume(a, b) > 10 * INTERFERENCE_LIMIT_MM3
    from cubot_cad.checks.docking import to_manifold
    from cubot_cad.piers.deck import screw_head_solids

    wide = dataclasses.replace(dd.deck, ring_radius_mm=62.0, ring_wall_mm=6.0, length_mm=130.0, width_mm=130.0)
    heads = [to_manifold(h) for h in screw_head_solids(cubot)]
    hits = []
    for turn in (45.0, 22.5, 0.0):
        a, b = _near_union(heads, _deck_manifolds(wide, turn, dd.offset_mm), [(0.0, 0.0, 0.0)])
        hits.append(0.0 if a is None else intersection_volume(a, b))
    assert max(hits) > 10 * INTERFERENCE_LIMIT_MM3


def test_the_running_surface_passes_with_the_deck(column, bare):
    """A line robot rolls over the deck on its wheels: nothing of the pier reaches above the deck's
    top, so it keeps its whole ground clearance (2.78 mm, the caster seats) as the margin; the deck
    stands 9.8 mm over the highest thing it covers (the locking key's lip, 10.2 mm above the cover)
    and its 45 deg, 2 mm chamfers are within what the robot climbs and clears."""
    rs = column.running_surface
    assert rs["ok"], rs["blocking"]
    assert rs["surface"] == "pier_deck" and rs["wheels_on_surface"]
    assert rs["protrusions"] == [] and rs["blocking"] == []
    assert rs["ground_clearance_mm"] == pytest.approx(2.775, abs=0.01) and rs["lowest_line_part"] == "caster_seat"
    assert rs["clearance_margin_mm"] == rs["ground_clearance_mm"]
    u = rs["under_deck"]
    assert u["highest_part"] == "locking_key" and u["above_cover_mm"] == pytest.approx(10.2, abs=0.01)
    assert u["below_running_surface_mm"] == pytest.approx(column.deck_height_mm - 10.2, abs=0.01)
    e = rs["ends"]
    assert e["ok"] and len(e["chamfers"]) == 2
    assert e["slope_deg"] == pytest.approx(45.0, abs=1e-3) and e["slope_deg"] <= e["climb_limit_deg"]
    assert e["climb_limit_deg"] == pytest.approx(math.degrees(math.acos((21.0 - 15.0) / 21.0)), abs=1e-3)
    assert e["drop_mm"] == pytest.approx(2.0, abs=1e-3)
    assert e["arrival_margin_mm"] == pytest.approx(rs["ground_clearance_mm"] - 2.0, abs=1e-3)
    assert e["flat_length_mm"] == pytest.approx(100.0) == e["robot_length_mm"]
    # the same column without the deck fails (above), the pier's other checks pass with it
    assert not bare.running_surface["ok"]
    assert column.summary()["ok"]


def test_the_running_surface_is_the_top_cover_plus_the_deck_height(column, cubot, top_down):
    assert column.deck_height_mm == pytest.approx(cubot.top_spec.stand_mm + 5.0, abs=GAP_TOLERANCE_MM)
    for k in (1, 2, 3):
        assert column.running_surface_mm(k) == pytest.approx(column.top_height_mm(k) + column.deck_height_mm, abs=1e-9)
    # measured on the placed deck, not by the formula
    assert column.measured_running_surface_mm() == pytest.approx(column.running_surface_mm(), abs=1e-6)
    assert column.running_surface["running_surface_mm"] == pytest.approx(column.running_surface_mm(), abs=1e-3)


def test_the_deck_height_moves_with_its_plate(cubot, top_down, column):
    """A 1 mm thicker plate docks 1 mm higher: deck height and running surface follow (measured)."""
    thick = PierColumn(cubot, 1, docked=top_down, deck=PierDeck.for_robot(cubot, plate_mm=6.0))
    assert thick.deck_height_mm == pytest.approx(column.deck_height_mm + 1.0, abs=1e-6)
    assert thick.measured_running_surface_mm() == pytest.approx(column.running_surface_mm(1) + 1.0, abs=1e-6)
    assert thick.deck_dock.ok and thick.running_surface["ok"]


@pytest.mark.parametrize("dims, word", [
    ({"plate_mm": 0.0}, "PierDeck.plate_mm"),
    ({"plate_mm": -5.0}, "PierDeck.plate_mm"),
    ({"plate_mm": float("nan")}, "PierDeck.plate_mm"),
    ({"plate_mm": 3.5}, "PierDeck.plate_mm 3.5"),  # the tap holes (3.5 mm) need a 0.8 mm skin over them
    ({"ramp_deg": 30.0}, "PierDeck.ramp_deg 30"),  # would overhang the bed printed top down
    ({"ramp_deg": 80.0}, "PierDeck.ramp_deg 80"),  # steeper than the robot climbs (73.4 deg)
    ({"ramp_deg": "45"}, "PierDeck.ramp_deg '45'"),
    ({"ramp_drop_mm": 4.5}, "PierDeck.ramp_drop_mm 4.5"),
    ({"ring_radius_mm": 20.0}, "PierDeck.ring_radius_mm 20"),  # inside the key flange
    ({"ring_radius_mm": 46.0}, "PierDeck.ring_radius_mm 46"),  # beyond the 90 mm wide cover
    ({"ring_wall_mm": 0.5}, "PierDeck.ring_wall_mm"),
    # short of the wheel track (+-39 mm about the body's centre; a ring that fits the narrower plate)
    ({"width_mm": 76.0, "ring_radius_mm": 36.0}, "PierDeck.width_mm 76"),
    ({"length_mm": 90.0}, "PierDeck.length_mm 90"),  # shorter than the robot
])
def test_bad_deck_dimensions_are_one_line_input_errors(cubot, dims, word):
    with pytest.raises(InputError) as exc:
        PierDeck.for_robot(cubot, **dims)
    assert "\n" not in str(exc.value) and word in str(exc.value), str(exc.value)


def test_a_deck_that_does_not_fit_the_column_is_refused(cubot, top_down):
    from cubot_cad.robots.cubot import CuBot

    with pytest.raises(InputError, match="PierColumn.deck must be"):
        PierColumn(cubot, 2, docked=top_down, deck="yes")
    other = PierDeck.for_robot(CuBot(clearance_mm=0.3))  # another robot's coupling spec
    with pytest.raises(InputError, match="PierDeck.spec is not the cubot's") as exc:
        PierColumn(cubot, 2, docked=top_down, deck=other)
    assert "\n" not in str(exc.value)


def test_the_deck_prints_flat_without_support(column, tmp_path):
    """The repository's printability check (watertight, manifold, on the bed, walls >= 0.8 mm) passes
    on the deck's STL as exported; printed top down, the running deck lies on the bed and no face
    looks down more steeply than 45 deg off the bed (the chamfers are exactly 45)."""
    import numpy as np
    import trimesh

    from cubot_cad.checks.check import check_file
    from cubot_cad.mesh import mesh_of

    deck = column.deck_part
    stl = tmp_path / "pier_deck.stl"
    stl.write_bytes(mesh_of(deck.printable).export(file_type="stl"))
    c = check_file(stl, do_slice=False)
    assert c.ok and c.watertight and c.manifold and c.fits_bed and c.thinnest_wall_mm >= 0.8
    assert c.size_mm == pytest.approx([104.0, 100.0, 20.0], abs=0.01)
    m = trimesh.load(stl)
    on_bed = m.area_faces[(m.face_normals[:, 2] < -1 + 1e-6) & (m.triangles[:, :, 2].max(axis=1) < 1e-6)].sum()
    assert on_bed == pytest.approx(100.0 * 100.0, rel=1e-3)  # the running deck is the bed face
    off_bed = m.triangles[:, :, 2].max(axis=1) > 1e-3
    down = m.face_normals[:, 2] < -math.cos(math.radians(45.0)) - 1e-4
    assert not np.any(off_bed & down)
    assert deck.print_settings()["supports"] is False


def test_the_deck_is_exported_and_listed_once_per_pier(export_dir, cubot):
    """`cad export`: exports/cubot/pier_deck.stl, a manifest record counted per pier, the BOM's
    pier rows (the deck, its flanged cross key, the key's four button-head screws)."""
    import csv

    m = json.loads((export_dir / "manifest.json").read_text())
    rec = next(p for p in m["parts"] if p["part"] == "pier_deck")
    assert rec["robot"] == "cubot" and rec["file"] == "cubot/pier_deck.stl" and rec["per"] == "pier"
    assert rec["quantity"] == 1 and rec["watertight"] and rec["fits_bed"] and rec["bbox_mm"][2] == pytest.approx(0.0)
    assert not rec["print_settings"]["supports"]
    assert {p["per"] for p in m["parts"] if p["part"] not in ("pier_deck", "cross_key")} == {"robot"}
    assert next(p for p in m["parts"] if p["part"] == "cross_key")["per"] == "pier"
    rows = [r for r in csv.DictReader((export_dir / "cubot" / "bom.csv").open()) if r["category"] == "pier"]
    assert [(r["item"], int(r["quantity"])) for r in rows] == [("pier_deck", 1), ("cross_key", 1),
                                                               ("M3x5 ISO 7380", 4)]
    assert rows[0]["file"] == "cubot/pier_deck.stl" and rows[1]["file"] == "cubot/cross_key.stl"
    assert all((export_dir / r["file"]).exists() for r in rows if r["file"])
    for other in ("octbot", "cube-robot", "platform"):
        assert not [r for r in csv.DictReader((export_dir / other / "bom.csv").open()) if r["category"] == "pier"]


def test_stability_margin_is_com_to_edge_less_lean_times_height(column):
    poly = column.support_polygon_mm  # wheel treads (0, 2 +- 31..39: centred on the body) and the casters (+-38, 0)
    assert sorted(poly) == sorted([(-38.0, 0.0), (0.0, -37.0), (38.0, 0.0), (0.0, 41.0)])
    st0, st5 = column.stability(0.0), column.stability(5.0)
    assert st0["margin_mm"] == st0["com_to_edge_mm"] > 20
    h = column.com_height_mm
    assert h == pytest.approx(column.com_mm[2] + 15.0, abs=1e-9)
    assert st5["margin_mm"] == pytest.approx(st0["com_to_edge_mm"] - h * math.tan(math.radians(5)), abs=2e-3)
    assert math.tan(math.radians(st5["tipping_deg"])) == pytest.approx(st0["com_to_edge_mm"] / h, rel=1e-4)
    assert st5["ok"] and not column.stability(st5["tipping_deg"] + 0.1)["ok"]
    with pytest.raises(InputError, match="lean_deg 60"):
        column.stability(60)


def test_mass_and_com_are_k_robots_and_the_deck(column, bare):
    one = column.robot.mass_properties()
    assert bare.mass_kg == pytest.approx(3 * one.mass_kg)
    assert bare.com_mm[2] == pytest.approx(one.com_m[2] * 1000 + bare.stack_pitch_mm)
    assert bare.com_height_mm == pytest.approx(15.0 + one.com_m[2] * 1000 + bare.stack_pitch_mm, abs=1e-6)
    deck = column.deck_part
    md = (deck.volume_mm3 + deck.key.volume_mm3) * 1.04e-6  # ABS, solid (kg)
    assert column.deck_mass_kg == pytest.approx(md, rel=1e-9) and 0.05 < md < 0.1
    assert column.mass_kg == pytest.approx(3 * one.mass_kg + md)
    zd = deck.assembly_com_mm()[2] + column.deck_offset_mm[2]
    assert column.com_mm[2] == pytest.approx((3 * one.mass_kg * bare.com_mm[2] + md * zd) / column.mass_kg, abs=1e-6)
    assert column.stability()["margin_mm"] < bare.stability()["margin_mm"]  # the deck's weight sits high


# --- validation and CLI -----------------------------------------------------------------------

@pytest.mark.parametrize("k", [0, 9, -1, 2.5, True, "3"])
def test_a_bad_robot_count_is_one_line_naming_it(cubot, k):
    with pytest.raises(InputError) as exc:
        PierColumn(cubot, k)
    assert "\n" not in str(exc.value) and f"robots {k!r}" in str(exc.value)


def test_only_a_robot_with_the_top_down_coupling_stacks():
    from cubot_cad.robots.registry import make_robot

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
    assert res.code == 0 and out["ok"], res.err  # with the deck every check passes
    assert out["robots"] == 2 and out["stack_pitch_mm"] == pytest.approx(top_down.offset_mm[2], abs=1e-4)
    assert out["heights_mm"]["2"] == pytest.approx(out["standing_height_mm"] + out["stack_pitch_mm"], abs=1e-3)
    assert out["deck"] == "pier_deck" and out["deck_height_mm"] == pytest.approx(20.0, abs=GAP_TOLERANCE_MM)
    assert out["running_surface_mm"] == pytest.approx(out["top_height_mm"] + out["deck_height_mm"], abs=1e-3)
    assert out["checks"]["running_surface"]["ok"] and out["checks"]["docking"]["deck"]["ok"]
    for f in ("pier-cubot-2.step", "pier-cubot-2.glb", "pier-cubot-2.json"):
        assert (tmp_path / f).stat().st_size > 0
    assert json.loads((tmp_path / "pier-cubot-2.json").read_text())["checks"]["docking"]["ok"]
    import trimesh

    from cubot_cad.outputs.gltf import cad_bounds_mm

    b = cad_bounds_mm(trimesh.load(tmp_path / "pier-cubot-2.glb").bounds)
    assert b[1][2] == pytest.approx(out["running_surface_mm"] - 15.0, abs=0.3)  # the deck is the top
    assert out["footprint"]["plan_mm"][0] == pytest.approx(-52.0, abs=1e-3)  # its chamfers: 2 mm past the rear
    res = cli("cad", "pier", "--robots", "2", "--no-deck", "--out", str(tmp_path / "bare"))
    assert res.code == 1 and "FAIL running surface (top cover)" in res.out, res.out


# --- the properties record --------------------------------------------------------------------

def test_record_fields_are_the_columns_numbers(column, cubot, top_down):
    from cubot_cad.piers.pier import record_fields

    f = record_fields(cubot, top_down)
    assert f["standing_height_m"] == pytest.approx(column.standing_height_mm / 1000, abs=1e-12)
    assert f["stack_pitch_m"] == pytest.approx(column.stack_pitch_mm / 1000, abs=1e-12)
    assert "docked offset" in f["stack_pitch_source"] and "wheel" in f["standing_height_source"]
    assert f["deck_height_m"] == pytest.approx(column.deck_height_mm / 1000, abs=1e-12)
    assert "docked" in f["deck_height_source"]
    design = record_fields(cubot, None)  # an export without docking: the designed pitch and deck
    assert design["stack_pitch_m"] == pytest.approx(0.0898, abs=1e-9) and "design" in design["stack_pitch_source"]
    assert design["deck_height_m"] == pytest.approx(0.020, abs=1e-12) and "design" in design["deck_height_source"]


def test_packaged_record_carries_standing_height_and_pitch():
    from cubot_cad.properties import default_properties

    props = default_properties()
    cub = props.get("cubot")
    assert cub.standing_height_m == pytest.approx(0.0898, abs=1e-6)
    assert cub.stack_pitch_m == pytest.approx(0.0898, abs=GAP_TOLERANCE_MM / 1000)
    assert cub.standing_height_source and cub.stack_pitch_source
    assert cub.pier_height_m(4) == pytest.approx(cub.standing_height_m + 3 * cub.stack_pitch_m)
    assert cub.deck_height_m == pytest.approx(0.020, abs=GAP_TOLERANCE_MM / 1000) and cub.deck_height_source
    assert cub.running_surface_height_m(4) == pytest.approx(cub.pier_height_m(4) + cub.deck_height_m)
    for name in ("octbot", "cube-robot", "platform"):  # no top-down coupling: they do not stack
        r = props.get(name)
        assert r.standing_height_m is None and r.stack_pitch_m is None and r.stack_pitch_source is None
        assert r.deck_height_m is None and r.deck_height_source is None
        with pytest.raises(InputError, match="no standing height"):
            r.pier_height_m(2)


NEW_FIELDS = ("standing_height_m", "standing_height_source", "stack_pitch_m", "stack_pitch_source",
              "deck_height_m", "deck_height_source")


def test_record_round_trips_with_and_without_the_new_fields(tmp_path):
    from cubot_cad.piers.pier import add_record_fields
    from cubot_cad.properties import RobotPropertiesFile, default_properties

    props = default_properties()
    path = props.save(tmp_path / "with.json")
    assert RobotPropertiesFile.load(path) == props
    data = props.to_dict()
    for r in data["robots"]:
        for k in NEW_FIELDS:
            r.pop(k)
    old = tmp_path / "old.json"
    old.write_text(json.dumps(data))
    legacy = RobotPropertiesFile.load(old)  # a record from before the fields loads, without them
    assert legacy.get("cubot").standing_height_m is None and legacy.get("cubot").stack_pitch_source is None
    assert RobotPropertiesFile.load(legacy.save(tmp_path / "again.json")) == legacy
    cub = props.get("cubot")
    fields = {k: getattr(cub, k) for k in NEW_FIELDS}
    assert add_record_fields(old, {"cubot": fields}) == props  # what `cad export` adds back
    assert RobotPropertiesFile.load(old) == props


@pytest.mark.parametrize("change, match", [
    ({"stack_pitch_source": None}, "needs a stack_pitch_source"),
    ({"standing_height_m": None}, "standing_height_source is given without"),
    ({"stack_pitch_m": -0.09}, "stack_pitch_m must be in"),
    ({"standing_height_m": float("nan")}, "standing_height_m must be in"),
    ({"deck_height_source": None}, "needs a deck_height_source"),
    ({"deck_height_m": 0.0}, "deck_height_m must be in"),
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
    from cubot_cad.piers.deck import dock_deck
    from voidcross.commands.cad import _stack_fields

    got = _stack_fields(("cubot", "octbot", "platform"), 0.2, [top_down])
    assert set(got) == {"cubot"}
    assert got["cubot"]["stack_pitch_m"] == top_down.offset_mm[2] / 1000
    assert got["cubot"]["deck_height_m"] == dock_deck(top_down_robot()).deck_height_mm / 1000
    design = _stack_fields(("cubot",), 0.2, None)["cubot"]
    assert "design" in design["stack_pitch_source"] and "design" in design["deck_height_source"]


def top_down_robot():
    from cubot_cad.robots.registry import make_robot

    return make_robot("cubot")


def test_export_robots_writes_the_fields_itself(unsliced_export, top_down):
    """export_robots() (not only `cad export`) writes them: an export of that function, docked."""
    from cubot_cad.properties import RobotPropertiesFile

    props = RobotPropertiesFile.load(unsliced_export / "robot_properties.json")
    cub = props.get("cubot")
    assert cub.stack_pitch_m == top_down.offset_mm[2] / 1000 and "docked offset" in cub.stack_pitch_source
    assert cub.deck_height_m == pytest.approx(0.020, abs=GAP_TOLERANCE_MM / 1000) and "docked" in cub.deck_height_source
    assert props.get("octbot").deck_height_m is None and props.get("octbot").standing_height_m is None
