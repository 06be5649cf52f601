"""`voidcross reproduce`: the thesis's experiments as data, resumable into one database, with the
observed crossing boundary beside the thesis's."""

from __future__ import annotations

import sqlite3

from voidcross.commands.reproduce import EXPERIMENTS, observed_boundary, thesis_boundary

SYNTH = "swarm_sim.sweeps.synthetic:synthetic_run"  # follows the 3w rule of cases B-D


def test_the_experiments_are_the_thesis_run_counts():
    counts = {case: len(n) * len(w) * runs for _ch, case, _p, n, w, runs in EXPERIMENTS}
    assert counts == {"A": 100, "B": 150, "C": 2400, "D": 3150, "large": 50}   # Ch. 4.7: 5,800 runs; Ch. 5.6: 50
    assert [thesis_boundary(c, 2) for c in "ABCD"] == [8, 6, 6, 6]


def test_observed_boundary_is_the_smallest_swarm_that_always_crossed():
    cells = {(5, 2): [False, False], (6, 2): [True, False], (7, 2): [True, True], (8, 2): [True, True]}
    assert observed_boundary(cells, 2) == {"observed": 7, "below_all_retreat": False, "runs": 8}
    cells[(6, 2)] = [False, False]
    assert observed_boundary(cells, 2)["below_all_retreat"]
    assert observed_boundary({(3, 1): [False]}, 1)["observed"] is None


def test_reproduce_runs_resumes_and_reports_the_boundary(cli, tmp_path):
    out = tmp_path / "rep"
    argv = ("reproduce", "--chapter", "4", "--cases", "A,B", "--runs", "2", "--run-fn", SYNTH, "--out", str(out),
            "--json")
    res = cli(*argv)
    assert res.code == 0, res.err
    d = res.json()
    assert d["cases"]["B"]["by_width"]["3"] == {"observed": 9, "below_all_retreat": True, "runs": 12,
                                                "thesis": 9, "matches": True}
    # the stand-in crosses at 3w, case A's thesis boundary is 3w + 2: the mismatch is reported
    assert d["cases"]["A"]["by_width"]["1"]["observed"] == 5 and d["cases"]["A"]["by_width"]["1"]["matches"]
    assert d["cases"]["A"]["by_width"]["2"]["observed"] == 7 and not d["cases"]["A"]["by_width"]["2"]["matches"]
    assert (out / "report" / "index.html").is_file()
    n = sqlite3.connect(out / "reproduce.sqlite").execute("SELECT COUNT(*) FROM runs").fetchone()[0]
    assert n == (4 + 6) * 5 * 2
    again = cli(*argv)                      # resumes: nothing is run twice
    assert again.code == 0
    assert sqlite3.connect(out / "reproduce.sqlite").execute("SELECT COUNT(*) FROM runs").fetchone()[0] == n


def test_reproduce_refuses_bad_selections_with_one_line(cli, tmp_path):
    for argv in (("--chapter", "6"), ("--cases", "Z"), ("--runs", "0"), ("--chapter", "5", "--cases", "A")):
        res = cli("reproduce", *argv, "--out", str(tmp_path / "x"))
        assert res.code == 2 and len(res.error_lines) == 1, argv
    f = tmp_path / "file"
    f.write_text("")
    assert cli("reproduce", "--cases", "A", "--out", str(f)).code == 2


def test_reproduce_case_a_with_the_simulator(cli, tmp_path):
    res = cli("reproduce", "--chapter", "4", "--cases", "A", "--runs", "1", "--out", str(tmp_path / "a"),
              "--no-report", "--json")
    assert res.code == 0, res.err
    a = res.json()["cases"]["A"]["by_width"]
    assert (a["1"]["observed"], a["2"]["observed"]) == (5, 8) and a["1"]["matches"] and a["2"]["matches"]
    assert a["3"]["observed"] is None    # 11 robots needed; the thesis's grid stops at 10
