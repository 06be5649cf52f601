"""`voidcross cad props --scale-mass F`: a user's heavier (or lighter) robot as a consistent
record (issue 41): every field that changes with the mass changes with it, the source says so,
structure_fem reads it, and a hand edit that breaks the rule names the fields to change."""

from __future__ import annotations

import json

import pytest

from cubot_cad.properties import RobotPropertiesFile, default_properties, default_properties_path


def test_scaling_the_mass_scales_every_mass_field_together(cli, tmp_path):
    out = tmp_path / "heavy.json"
    res = cli("cad", "props", "--scale-mass", "1.5", "--out", str(out), "--json")
    assert res.code == 0, res.err
    base, heavy = default_properties(), RobotPropertiesFile.load(out)  # loading validates it
    assert heavy.names == base.names
    for a, b in zip(base.robots, heavy.robots, strict=True):
        assert b.mass_kg == pytest.approx(1.5 * a.mass_kg)
        assert b.inertia_kg_m2 == pytest.approx(tuple(1.5 * i for i in a.inertia_kg_m2))
        if a.solid_print_mass_kg is not None:
            assert b.solid_print_mass_kg == pytest.approx(1.5 * a.solid_print_mass_kg)
            assert "--scale-mass 1.5" in b.solid_print_mass_source
        assert b.com_m == a.com_m and b.connectors == a.connectors and "--scale-mass 1.5" in b.source
    payload = json.loads(res.out)
    assert payload["scale_mass"] == 1.5 and len(payload["robots"]) == len(base.robots)


def test_one_robot_only_and_the_others_untouched(cli, tmp_path):
    out = tmp_path / "light.json"
    assert cli("cad", "props", "--scale-mass", "0.5", "--robot", "cubot", "--out", str(out)).code == 0
    base, light = default_properties(), RobotPropertiesFile.load(out)
    assert light.get("cubot").mass_kg == pytest.approx(0.5 * base.get("cubot").mass_kg)
    assert light.get("octbot") == base.get("octbot")


def test_the_structure_model_reads_the_variant_and_bends_more(cli, tmp_path):
    out = tmp_path / "heavy.json"
    assert cli("cad", "props", "--scale-mass", "3", "--robot", "cubot", "--out", str(out)).code == 0
    from structure_fem.model.connectors import ConnectorSet
    from structure_fem.model.statics import Config, solve
    from structure_fem.model.structures import Structure

    tips = []
    for rec in (default_properties(), RobotPropertiesFile.load(out)):
        r = rec.get("cubot")
        tips.append(solve(Config(Structure("line"), 5, 2, 2), r, ConnectorSet.from_robot(r), True).tip_deflection_m)
    assert abs(tips[1]) > abs(tips[0])


@pytest.mark.parametrize("argv, names", [
    (("--scale-mass", "0"), "--scale-mass"),
    (("--scale-mass", "nan"), "--scale-mass"),
    (("--scale-mass", "1000"), "--scale-mass"),
    (("--scale-mass", "2", "--robot", "warp"), "warp"),
])
def test_bad_factors_and_names_are_one_error_line_and_nothing_written(cli, tmp_path, argv, names):
    out = tmp_path / "x.json"
    res = cli("cad", "props", *argv, "--out", str(out))
    assert res.code == 2 and res.err.count("\n") == 1 and names in res.err, res.err
    assert not out.exists()


def test_the_input_record_is_never_overwritten(cli, tmp_path):
    rec = tmp_path / "mine.json"
    rec.write_bytes(default_properties_path().read_bytes())
    before = rec.read_bytes()
    res = cli("cad", "props", "--scale-mass", "2", "--properties", str(rec), "--out", str(rec))
    assert res.code == 2 and "input record" in res.err
    assert rec.read_bytes() == before


def test_a_hand_edited_mass_names_the_fields_to_change_with_it(cli, tmp_path):
    d = json.loads(default_properties_path().read_text())
    d["robots"][0]["mass_kg"] *= 1.5  # the solid-print mass left behind
    f = tmp_path / "hand.json"
    f.write_text(json.dumps(d))
    res = cli("fem", "table", "--properties", str(f))
    assert res.code == 2 and res.err.count("\n") == 1
    for field in ("solid_print_mass_kg", "inertia_kg_m2", "cad props --scale-mass", "docs/records.md"):
        assert field in res.err, res.err
