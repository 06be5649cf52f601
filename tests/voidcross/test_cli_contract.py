"""The CLI contract every sub-command keeps (issue 2): help with examples, exit codes, --json."""

from __future__ import annotations

import subprocess
import sys

import pytest

from voidcross.cli import COMMANDS


def test_top_level_help_lists_every_command_with_examples(cli):
    res = cli("--help")
    assert res.code == 0
    for name in COMMANDS:
        assert name in res.out
    assert "examples:" in res.out


@pytest.mark.parametrize("name", COMMANDS)
def test_every_command_has_help(cli, name):
    res = cli(name, "--help")
    assert res.code == 0, res.err
    assert name in res.out


def test_unknown_command_is_one_error_line_exit_2(cli):
    res = cli("fly")
    assert res.code == 2
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:")
    assert "fly" in res.error_lines[0]


def test_unknown_option_is_one_error_line_exit_2(cli):
    res = cli("doctor", "--frobnicate")
    assert res.code == 2
    assert len(res.error_lines) == 1 and "--frobnicate" in res.error_lines[0]


def test_doctor_json_parses_and_names_versions(cli):
    res = cli("doctor", "--json")
    assert res.code == 0
    report = res.json()
    names = {c["name"] for c in report["checks"]}
    assert {"numpy", "cadquery/OCP", "exudyn", "manifold3d", "dask.distributed",
            "imageio-ffmpeg", "prusa-slicer"} <= names
    for c in report["checks"]:
        assert c["ok"] is (c["version"] is not None) or c["name"] in ("prusa-slicer", "chromium")
        assert c["feature"]


def test_doctor_human_marks_missing_features(cli, monkeypatch):
    from voidcross.commands import doctor

    monkeypatch.setattr(doctor, "CHECKS", doctor.CHECKS + (("nosuchlib", "nosuchlib_xyz", "nosuchlib", "the moon"),))
    res = cli("doctor")
    assert res.code == 0
    assert "MISS" in res.out and "missing: the moon" in res.out


def test_pipeline_rejects_unknown_stage_with_exit_2(cli, tmp_path):
    res = cli("pipeline", "--out", str(tmp_path), "--stages", "cad,warp")
    assert res.code == 2
    assert len(res.error_lines) == 1 and "warp" in res.error_lines[0]
    assert list(tmp_path.iterdir()) == []


def test_internal_failure_is_exit_1_traceback_only_with_debug(cli, monkeypatch):
    from voidcross.commands import doctor

    def boom():
        raise RuntimeError("kaput")

    monkeypatch.setattr(doctor, "diagnose", boom)
    res = cli("doctor")
    assert res.code == 1 and "kaput" in res.err and "Traceback" not in res.err
    res = cli("doctor", "--debug")
    assert res.code == 1 and "Traceback" in res.err


def test_input_error_maps_to_exit_2(cli, monkeypatch):
    from cubot_cad.errors import InputError
    from voidcross.commands import doctor

    def bad():
        raise InputError("--robots -3: must be >= 1")

    monkeypatch.setattr(doctor, "diagnose", bad)
    res = cli("doctor")
    assert res.code == 2 and res.error_lines == ["error: --robots -3: must be >= 1"]


def test_console_script_is_installed():
    res = subprocess.run([sys.executable, "-m", "voidcross.cli", "--version"], capture_output=True, text=True)
    assert res.returncode == 0 and "voidcross" in res.stdout
