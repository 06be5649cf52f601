"""Provenance of every connector input (issue 12): FE by default where it applies, the record's
hand formula elsewhere (saying why), a user's measurement; cached by the geometry + material hash."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from cubot_cad.properties import default_properties
from structure_fem.couplings import connector_sources as cs
from structure_fem.errors import InputError
from structure_fem.limits import load_limits
from structure_fem.outputs.runs import RunOptions, make_inputs


@pytest.fixture(scope="module")
def packaged_fe():
    key = cs.fe_key(default_properties().get("cubot"))[2]
    (d,) = [e for e in cs.packaged_fe() if e["kind"] == "front_rear" and e["input_hash"] == key]
    return d


def test_the_fe_result_is_what_the_model_uses_by_default(packaged_fe):
    inp, info = make_inputs(RunOptions())
    fr = inp.connectors.front_rear
    assert fr.provenance.startswith("fe: ")
    assert packaged_fe["input_hash"][:16] in fr.provenance and "h=4.8 mm" in fr.provenance
    assert fr.rotational_nm_per_rad == pytest.approx(packaged_fe["rotational_stiffness_nm_per_rad"], rel=1e-12)
    assert fr.axial_n_per_m == pytest.approx(packaged_fe["axial_stiffness_n_per_m"], rel=1e-12)
    assert fr.k_z == pytest.approx(packaged_fe["shear_stiffness_n_per_m"], rel=1e-12)
    # the play stays the CAD's: the FE is of the play-free, bonded load path
    rec = default_properties().get("cubot").connector("front_rear")
    assert fr.play_x == (0.0, rec.play_of("tension").play_m)
    assert fr.backlash_rad == rec.backlash_rad
    assert info["connector_sources"]["front_rear"].startswith("fe")
    assert info["robot_connectors"]["front_rear"]["provenance"] == fr.provenance


def test_the_record_mode_keeps_the_hand_formula():
    inp, _ = make_inputs(RunOptions(connectors="properties"))
    assert inp.connectors.front_rear.provenance.startswith("hand formula: ")
    assert inp.connectors.front_rear.rotational_nm_per_rad == pytest.approx(
        default_properties().get("cubot").connector("front_rear").rotational_stiffness_nm_per_rad)


def test_an_edited_record_gets_no_fe_and_says_why():
    rec = default_properties().get("cubot")
    fr = rec.connector("front_rear")
    edited = rec.with_connector(replace(fr, axial_stiffness_n_per_m=2 * fr.axial_stiffness_n_per_m))
    robot, notes = cs.resolve(edited)
    assert robot.connector("front_rear").provenance.startswith("hand formula")
    assert "not the parametric CuBot" in notes["front_rear"]
    other = default_properties().get("octbot")
    _, notes = cs.resolve(other)
    assert notes["ring_capture"].startswith("fe (result found in the")  # its ring: octbot_ring_fe
    assert "no FE model of this robot" in cs.fe_key(other)[1]  # no front-rear coupling to model


def test_the_fe_is_looked_up_by_its_geometry_and_material_hash(tmp_path, packaged_fe):
    """A cache entry under the record's key is used (and its key is in the provenance); an entry
    under another key is not."""
    rec = default_properties().get("cubot")
    _what, _why, key = cs.fe_key(rec)
    assert key == packaged_fe["input_hash"]
    entry = dict(packaged_fe, rotational_stiffness_nm_per_rad=1234.5)
    (tmp_path / f"{key}.json").write_text(json.dumps(entry))
    fe, where = cs.fe_front_rear_for(rec, cache_dir=tmp_path)
    assert fe.rotational_stiffness_nm_per_rad == 1234.5 and where == "user cache"
    (tmp_path / f"{key}.json").unlink()
    (tmp_path / ("0" * 64 + ".json")).write_text(json.dumps(entry))
    fe, where = cs.fe_front_rear_for(rec, cache_dir=tmp_path)
    assert fe.rotational_stiffness_nm_per_rad == packaged_fe["rotational_stiffness_nm_per_rad"]
    assert where.startswith("packaged")
    # another print clearance is another geometry: another key
    from cubot_cad.robots.cubot import CuBot

    loose = replace(rec, connectors=tuple(CuBot(clearance_mm=0.3).connector_properties(
        rec.youngs_modulus_pa, {c.kind: c.gap_m * 1e3 for c in rec.connectors})))
    assert cs.fe_key(loose)[2] not in (None, key)


def test_a_measured_coupling_replaces_the_stiffness_with_its_file_as_provenance(tmp_path):
    p = tmp_path / "bench.json"
    p.write_text(json.dumps({"front_rear": {"rotational_stiffness_nm_per_rad": 800.0, "note": "3 samples"}}))
    inp, info = make_inputs(RunOptions(measured=str(p)))
    fr = inp.connectors.front_rear
    assert fr.rotational_nm_per_rad == 800.0
    assert fr.provenance == f"measured: {p}; 3 samples"
    assert info["connector_sources"]["front_rear"].startswith("measured")
    for bad, match in (({"front_rear": {"rotational_stiffness_nm_per_rad": -1}}, "must be a number > 0"),
                       ({"glue": {"axial_stiffness_n_per_m": 1.0}}, "glue"),
                       ({"front_rear": {"stiffness": 1.0}}, "unknown field")):
        p.write_text(json.dumps(bad))
        with pytest.raises(InputError, match=match):
            make_inputs(RunOptions(measured=str(p)))


def test_the_packaged_limits_list_every_input_with_its_provenance():
    lim = load_limits("derived")
    prov = lim.input_provenance
    # every CuBot coupling's stiffness comes from the packaged 3D FE (front-rear, rail, key)
    for kind in ("front_rear", "side_rail", "top_twist"):
        assert prov[kind].startswith("fe: "), prov[kind][:80]
    for kind in ("front_rear", "side_rail", "top_twist"):
        assert prov[f"{kind}_play"].startswith("CAD clearances")
        for q in ("nm_per_rad", "axial_n_per_m", "shear_n_per_m", "backlash_rad", "play_x_opening_m",
                  "play_z_opening_m"):
            assert f"{kind}_{q}" in lim.inputs
    # the wedge latch takes up the tension play; the pins keep their vertical slip (2 clearances)
    fr = default_properties().get("cubot").connector("front_rear")
    assert lim.inputs["front_rear_play_x_opening_m"] == pytest.approx(fr.play_of("tension").play_m, abs=1e-12) == 0
    assert lim.inputs["front_rear_play_z_opening_m"] == pytest.approx(4e-4, rel=1e-9)


def test_a_missing_or_bad_measurement_file_is_one_error_line_exit_2(cli, tmp_path):
    res = cli("fem", "table", "--measured", str(tmp_path / "nope.json"), "--out", str(tmp_path / "o"))
    assert res.code == 2 and len(res.error_lines) == 1 and "nope.json" in res.error_lines[0]
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"front_rear": {"axial_stiffness_n_per_m": 0}}))
    res = cli("fem", "table", "--measured", str(bad), "--out", str(tmp_path / "o"))
    assert res.code == 2 and len(res.error_lines) == 1 and "axial_stiffness_n_per_m" in res.error_lines[0]
    assert not (tmp_path / "o").exists()


def test_measured_moment_rotation_points_give_stiffness_and_play(tmp_path):
    """A bench reading of the coupling (item 7): rotation = play + M / k fitted to the points."""
    k, b = 900.0, 4e-3
    pts = [[m, b + m / k] for m in (0.5, 1.0, 2.0, 3.0)]
    p = tmp_path / "mr.json"
    p.write_text(json.dumps({"front_rear": {"moment_rotation": pts}}))
    assert cs.fit_moment_rotation(pts, "x") == pytest.approx((k, b, 4))
    inp, _ = make_inputs(RunOptions(measured=str(p)))
    fr = inp.connectors.front_rear
    assert fr.rotational_nm_per_rad == pytest.approx(k) and fr.backlash_rad == pytest.approx(b)
    assert fr.provenance.startswith(f"measured: {p}; fit of 4 moment-rotation points")
    for bad, match in (([[1.0, 0.01]], "at least two"), ([[1.0, 0.01], [1.0, 0.02]], "all equal"),
                       ([[1.0, 0.02], [2.0, 0.01]], "does not grow"), ([[1.0, -0.01], [2.0, 0.01]], "rotation_rad > 0")):
        with pytest.raises(InputError, match=match):
            cs.fit_moment_rotation(bad, "x")


def test_calibrate_reports_a_measured_coupling(cli, tmp_path):
    p = tmp_path / "mr.json"
    p.write_text(json.dumps({"front_rear": {"moment_rotation": [[0.5, 0.0045], [1.0, 0.0051], [2.0, 0.0062]]}}))
    res = cli("fem", "calibrate", "--measured", str(p), "--json")
    assert res.code == 0, res.err
    m = res.json()["measured"]["front_rear"]
    assert m["provenance"].startswith(f"measured: {p}") and m["backlash_rad"] == pytest.approx(3.95e-3, rel=0.01)


def test_the_cube_robot_front_rear_comes_from_its_packaged_fe():
    """The packaged Cube Robot record's front-rear coupling is recognised as the parametric Cube
    Robot's (hand formula reproduced at its clearance and modulus) and takes the packaged FE of
    its geometry, with the CAD's play; an edited one keeps its hand formula and says why."""
    rec = default_properties().get("cube-robot")
    _what, why, key = cs.fe_key(rec)
    assert why == "" and key != cs.fe_key(default_properties().get("cubot"))[2]
    (entry,) = [e for e in cs.packaged_fe() if e["input_hash"] == key]
    robot, notes = cs.resolve(rec)
    fr = robot.connector("front_rear")
    assert notes["front_rear"].startswith("fe (result found in the")  # the package (or a cache copy)
    assert fr.provenance.startswith("fe: ") and key[:16] in fr.provenance
    assert fr.rotational_stiffness_nm_per_rad == entry["rotational_stiffness_nm_per_rad"]
    assert fr.play == rec.connector("front_rear").play and fr.gap_m == rec.connector("front_rear").gap_m
    assert entry["hinge_z_m"] == pytest.approx(0.0515)
    edited = rec.with_connector(replace(rec.connector("front_rear"), backlash_rad=0.05))
    robot, notes = cs.resolve(edited)
    assert robot.connector("front_rear").provenance.startswith("hand formula")
    assert "not the parametric CubeRobot" in notes["front_rear"]


def test_the_packaged_fe_set_is_gathered_in_the_finders_order_from_one_or_two_processes(tmp_path):
    """``compute_packaged_fe`` returns one result per (record, coupling) of PACKAGED_FINDERS, in that
    order, each the packaged one when nothing is missing, whether it runs in one process or two
    (spawned workers, longest first)."""
    keys = [e["input_hash"] for e in cs.packaged_fe()]
    for workers in (1, 2):
        done: list = []
        results, wall, per_task = cs.compute_packaged_fe(tmp_path, workers=workers,
                                                         progress=lambda d, n, label, done=done: done.append((d, n, label)))
        assert [fe.input_hash for fe in results] == keys
        assert [d for d, _n, _l in done] == [1, 2, 3, 4, 5, 6] and {n for _d, n, _l in done} == {6}
        assert set(per_task) == {"cubot:front_rear", "cubot:side_rail", "cubot:top_twist", "cube-robot:front_rear",
                                 "platform:platform_bolt", "octbot:octbot_ring"}
        assert wall >= 0 and not any(tmp_path.iterdir())  # nothing computed, nothing cached


def test_without_the_packaged_file_a_missing_result_is_not_invented(tmp_path):
    """``packaged=False`` (the cold measurement) does not read the packaged results: a lookup
    that may not compute finds nothing and says how to compute it."""
    rec = default_properties().get("cubot")
    fe, why = cs.fe_front_rear_for(rec, cache_dir=tmp_path, packaged=False)
    assert fe is None and "computes it" in why
    fe, why = cs.fe_side_rail_for(rec, cache_dir=tmp_path, packaged=False)
    assert fe is None and "computes it" in why
    assert cs.fe_front_rear_for(rec, cache_dir=tmp_path)[0] is not None  # the package has it


@pytest.mark.parametrize("workers", [0, -1, 1.5, "2"])
def test_the_worker_count_is_validated(tmp_path, workers):
    with pytest.raises(InputError, match="workers"):
        cs.compute_packaged_fe(tmp_path, workers=workers)


def test_a_record_without_its_fe_result_is_a_warning_line_and_marked_in_the_json(tmp_path):
    """Issue 38 item 2: a record whose geometry has no FE result (another print clearance, an edit)
    used to run on the hand formula silently; now the table says so, once per coupling."""
    from cubot_cad.properties import RobotPropertiesFile
    from structure_fem.outputs.runs import hand_formula_warnings

    props = default_properties()
    rec = props.get("cubot")
    fr = rec.connector("front_rear")
    edited = rec.with_connector(replace(fr, axial_stiffness_n_per_m=2 * fr.axial_stiffness_n_per_m))
    path = tmp_path / "robot_properties.json"
    RobotPropertiesFile(robots=tuple(edited if r.name == "cubot" else r for r in props.robots)).save(path)
    _, info = make_inputs(RunOptions(properties=str(path)))
    lines = hand_formula_warnings(info, "cubot")
    assert len(lines) == 1 and lines[0].startswith("warning: cubot front_rear: no FE result applies")
    assert "not the parametric CuBot" in lines[0]
    _, info = make_inputs(RunOptions())
    assert hand_formula_warnings(info, "cubot") == []  # the packaged record has its FE
    _, info = make_inputs(RunOptions(properties=str(path), connectors="properties"))
    assert hand_formula_warnings(info, "cubot") == []  # asked for the hand formula: no warning
