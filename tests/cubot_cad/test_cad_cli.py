"""`voidcross cad ...`: exit codes, one-line errors, JSON outputs, the pipeline stage."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize("argv, word", [
    (("cad", "export", "--clearance-mm", "-1"), "clearance"),
    (("cad", "export", "--clearance-mm", "nan"), "clearance"),
    (("cad", "export", "--robot", "hexbot"), "hexbot"),
    (("cad", "export", "--format", "obj"), "obj"),
    (("cad", "export", "--material", "wood"), "wood"),
    (("cad", "dock", "--pair", "cubot-sideways"), "cubot-sideways"),
    (("cad", "check", "/nonexistent/dir"), "/nonexistent/dir"),
    (("cad", "render", "--robot", "hexbot"), "hexbot"),
])
def test_bad_input_gives_one_error_line_and_exit_2(cli, tmp_path, argv, word):
    res = cli(*argv, "--out", str(tmp_path)) if argv[1] in ("export", "render") else cli(*argv)
    assert res.code == 2, res.err
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:")
    assert word in res.error_lines[0]
    assert not any(tmp_path.iterdir())  # nothing written on bad input


def test_check_rejects_empty_and_corrupt_inputs(cli, tmp_path):
    res = cli("cad", "check", str(tmp_path))
    assert res.code == 2 and "no .stl" in res.err
    (tmp_path / "broken.stl").write_bytes(b"\x00" * 10)
    res = cli("cad", "check", str(tmp_path), "--no-slice")
    assert res.code == 2 and len(res.error_lines) == 1


def test_export_and_check_one_robot(cli, tmp_path, pairs):
    res = cli("cad", "export", "--robot", "platform", "--out", str(tmp_path), "--json")
    assert res.code == 0, res.err
    out = res.json()
    assert out["parts"] == 1 and out["all_watertight"]
    assert out["docked_pairs"][0]["pair"] == "platform-bolt"
    assert (tmp_path / "platform" / "test_platform.stl").exists() and (tmp_path / "platform.step").exists()
    res = cli("cad", "check", str(tmp_path), "--no-slice", "--json")
    assert res.code == 0, res.err
    chk = res.json()
    assert chk["files"] == 1 and chk["failed"] == 0 and chk["parts"][0]["thinnest_wall_mm"] >= 0.8


def test_dock_reports_every_pair(cli, pairs):
    res = cli("cad", "dock", "--json")
    assert res.code == 0, res.err
    rows = {r["pair"]: r for r in res.json()["pairs"]}
    assert rows["cube-robot-front-rear"]["gap_mm"] == pytest.approx(1.7, abs=0.02)
    assert all(r["ok"] for r in rows.values())


def test_pipeline_stage_sets_the_context(tmp_path, pairs):
    from cubot_cad.properties import RobotPropertiesFile
    from voidcross.commands.cad import pipeline_stage

    ctx: dict = {}
    line = pipeline_stage(tmp_path / "cad", ctx)
    assert "\n" not in line and "CuBot" in line
    assert RobotPropertiesFile.load(ctx["robot_properties"]).get("cubot").mass_kg > 0.2
    assert ctx["cad_dir"] == str(tmp_path / "cad")
    assert (tmp_path / "cad" / "manifest.json").exists()
