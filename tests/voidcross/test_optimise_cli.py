"""`voidcross optimise` from the command line: bad input is one error line and exit 2 with
nothing written; a study with held-out seeds writes the report with its table and plot."""

from __future__ import annotations

import json

import pytest

from voidcross.cli import main

SMALL = ["optimise", "--cases", "d", "--trials", "2", "--train-seeds", "1", "--train-widths", "2",
         "--params", "levy_mu,avoid_cm,stall_s", "--executor", "serial", "--quiet"]


@pytest.mark.parametrize("extra, says", [
    (["--params", "speed_cm_s"], "speed_cm_s"), (["--params", ""], "--params"), (["--cases", "e"], "--cases"),
    (["--cases", "d,,a"], "--cases"), (["--trials", "0"], "--trials"), (["--train-seeds", "-1"], "--train-seeds"),
    (["--train-widths", "9"], "--train-widths"), (["--sigma", "0"], "--sigma"), (["--heldout-runs", "-2"],
                                                                               "--heldout-runs"),
    (["--limits", "nowhere.json"], "nowhere.json")])
def test_bad_input_is_one_error_line_and_exit_2_with_nothing_written(tmp_path, capsys, extra, says):
    db = tmp_path / "opt.sqlite"
    assert main([*SMALL, "--db", str(db), *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and says in err[0], err
    assert not db.exists()


def test_a_corrupt_database_is_refused_and_left_as_it_was(tmp_path, capsys):
    db = tmp_path / "opt.sqlite"
    db.write_bytes(b"not a database at all" * 50)
    before = db.read_bytes()
    assert main([*SMALL, "--db", str(db)]) == 2
    assert "error:" in capsys.readouterr().err
    assert db.read_bytes() == before


def test_the_report_shows_tuned_against_the_thesis_rules_on_held_out_seeds(tmp_path, capsys):
    db = tmp_path / "opt.sqlite"
    rc = main([*SMALL, "--db", str(db), "--heldout-runs", "1", "--report", str(tmp_path / "rep"), "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    held = out["heldout"]
    assert held["seed0"] >= 1_000_000 and set(held["thesis"]) == {"D"}
    assert held["thesis"]["D"]["runs"] == 21 * 5  # Chapter 4's case D grid, one run per cell
    assert {"faults drive:1.7/h", "obstacles (Algorithm 3's five)"} <= set(out["robustness"])
    html = (tmp_path / "rep" / "index.html").read_text()
    for text in ("Held-out seeds", "Tt median thesis", "Robustness", "convergence.png", "levy_mu"):
        assert text in html
    assert (tmp_path / "rep" / "figures" / "convergence.png").stat().st_size > 1000
    rows = (tmp_path / "rep" / "figures" / "convergence.csv").read_text().splitlines()
    assert len(rows) == 1 + 1 + 2  # header, trial 0, two trials
