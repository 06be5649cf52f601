"""`voidcross sim run | soak | bench`: JSON contract, files only under --out, exit 2 on bad input."""

from __future__ import annotations

import pytest


def test_run_json_contract(cli):
    res = cli("sim", "run", "--preset", "case-c", "--robots", "3", "--void-width", "1", "--seed", "2",
              "--limits", "thesis", "--json")
    assert res.code == 0, res.err
    d = res.json()
    assert d["success"] is True and d["retreated"] is False and d["robots_lost"] == 0
    assert set(d["times"]) >= {"Ts", "Ta", "To", "Td", "Tb", "Tt"}
    assert isinstance(d["seed_robot"], int) and len(d["seed_position"]) == 2
    assert isinstance(d["target_finder"], int) and d["limits_source"] == "thesis"
    assert d["files"] == []


def test_run_human_text_and_debug_checks(cli):
    res = cli("sim", "run", "--preset", "case-d", "--robots", "2", "--void-width", "1", "--seed", "1",
              "--limits", "thesis", "--debug")
    assert res.code == 0, res.err
    assert "RETREATED" in res.out and "robots lost 0" in res.out


@pytest.mark.parametrize("argv,needle", [
    (["--robots", "0"], "--robots 0"),
    (["--robots", "-3"], "--robots -3"),
    (["--void-width", "70"], "void_width 70"),
    (["--preset", "case-q"], "case-q"),
    (["--set", "target_x_cm=250.0"], "target x=250"),
    (["--video", "run.avi"], "run.avi"),
    (["--limits", "nowhere.json"], "nowhere.json"),
])
def test_run_bad_input_is_one_line_exit_2(cli, tmp_path, argv, needle):
    res = cli("sim", "run", "--limits", "thesis", *argv, "--out", str(tmp_path / "o"))
    assert res.code == 2
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:") and needle in res.error_lines[0]
    assert not (tmp_path / "o").exists()


def test_malformed_toml_preset_is_exit_2(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[robot\nlength_cm = ")
    res = cli("sim", "run", "--preset", str(bad))
    assert res.code == 2 and "malformed TOML" in res.error_lines[0]


def test_run_writes_gif_snapshots_and_json_under_out(cli, tmp_path):
    res = cli("sim", "run", "--preset", "case-c", "--robots", "3", "--void-width", "1", "--seed", "2",
              "--limits", "thesis", "--max-time", "20", "--frame-every", "5", "--video", "run.gif",
              "--snapshots", "snaps", "--out", str(tmp_path), "--json")
    assert res.code == 0, res.err
    files = res.json()["files"]
    assert (tmp_path / "run.gif").stat().st_size > 10_000
    pngs = sorted((tmp_path / "snaps").glob("*.png"))
    assert len(pngs) >= 2 and all(f.stat().st_size > 5_000 for f in pngs)
    assert any(f.endswith(".json") for f in files)
    assert not list(tmp_path.glob(".*"))  # no temporary files left behind


def test_soak_runs_whole_runs_and_reports_zero_timeouts_violations_and_losses(cli):
    res = cli("sim", "soak", "--runs", "3", "--json")
    assert res.code == 0, res.err + res.out
    d = res.json()
    assert d["runs"] == 3 and d["whole_runs"] and d["limits"] == ["derived", "thesis"]
    assert d["timeouts"] == 0 and d["n_violations"] == 0 and d["robots_lost"] == 0 and d["errors"] == 0
    assert cli("sim", "soak", "--runs", "0").code == 2
    bad = cli("sim", "soak", "--runs", "2", "--limits", "nosuch")
    assert bad.code == 2 and "nosuch" in bad.err


def test_soak_counts_a_run_cut_by_the_guard_as_a_timeout_and_fails(cli):
    res = cli("sim", "soak", "--runs", "2", "--max-time", "3", "--json")
    assert res.code == 1
    assert res.json()["timeouts"] >= 1


def test_bench_json_fields(cli):
    res = cli("sim", "bench", "--robots", "500", "--steps", "5", "--no-scaling", "--json")
    assert res.code == 0, res.err
    d = res.json()
    assert d["robots"] == 500 and d["steps"] == 5 and d["robot_steps_per_s"] > 0
    assert "scaling_exponent" in d and "state_bytes_100k" in d
    assert cli("sim", "bench", "--robots", "0").code == 2


@pytest.mark.parametrize("argv,names", [
    (("--seed", "-1"), "--seed -1"), (("--frame-every", "0"), "--frame-every 0"),
    (("--frame-every", "-1"), "--frame-every -1"), (("--frame-every", "nan"), "--frame-every nan"),
    (("--frame-every", "0.001"), "shorter than one step"),
])
def test_sim_run_refuses_bad_seeds_and_frame_intervals_with_one_line(cli, argv, names):
    res = cli("sim", "run", "--preset", "case-d", *argv)
    assert res.code == 2 and len(res.error_lines) == 1 and names in res.err
