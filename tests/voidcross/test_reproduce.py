"""`voidcross reproduce`: the thesis's experiments as data, resumable into one database, with the
observed crossing boundary beside the thesis's."""

from __future__ import annotations

import sqlite3

from voidcross.commands.reproduce import EXPERIMENTS, observed_boundary, thesis_boundary

SYNTH = "swarm_sim.sweeps.synthetic:synthetic_run"  # follows the 3w rule of cases B-D


def test_the_experiments_are_the_thesis_run_counts():
    counts = {case: len(n) * len(w) * runs for _ch, case, _p, n, w, runs in EXPERIMENTS if n != "rule"}
    assert counts == {"A": 100, "B": 150, "C": 2400, "D": 3150, "large": 50}   # Ch. 4.7: 5,800 runs; Ch. 5.6: 50
    taper = {case: w for _ch, case, _p, n, w, _r in EXPERIMENTS if n == "rule"}
    assert taper == {"taper-15": (11, 15), "taper-30": (20, 25, 30)}          # each tapering level's widest void
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


def test_the_tapering_rows_run_at_the_swarm_the_rule_needs_for_the_chosen_limits(cli, tmp_path):
    from swarm_sim.runner import resolve_params

    out = tmp_path / "t"
    res = cli("reproduce", "--chapter", "5", "--cases", "taper-15,taper-30", "--run-fn", SYNTH, "--out", str(out),
              "--no-report", "--json")
    assert res.code == 0, res.err
    d = res.json()
    rows = sqlite3.connect(out / "reproduce.sqlite").execute(
        "SELECT preset, void_width, robots FROM runs ORDER BY void_width").fetchall()
    want = [(p, w, resolve_params(p, 100, w, limits="thesis").min_robots_rule)
            for p, w in (("large-void-15", 11), ("large-void-15", 15), ("large-void-30", 20),
                         ("large-void-30", 25), ("large-void-30", 30))]
    assert rows == want                        # computed from the rule, e.g. 200 at 15 widths, 470 at 30
    assert d["cases"]["taper-30"]["by_width"]["30"]["thesis"] == want[-1][2]
    assert d["skipped"] == []
    # a width no structure of the derived record spans (it reaches 17 widths today) is skipped and said so
    from swarm_sim.errors import InputError

    def spans(p, w):
        try:
            resolve_params(p, 100, w, limits="derived")
            return True
        except InputError:
            return False

    rows_all = [("taper-15", "large-void-15", 11), ("taper-15", "large-void-15", 15), ("taper-30", "large-void-30", 20),
                ("taper-30", "large-void-30", 25), ("taper-30", "large-void-30", 30)]
    assert not spans("large-void-30", 30)      # so the skip is exercised whatever the record derives
    der = cli("reproduce", "--chapter", "5", "--cases", "taper-15,taper-30", "--limits", "derived", "--run-fn", SYNTH,
              "--out", str(tmp_path / "d"), "--no-report", "--json")
    skipped = [(c, w) for c, p, w in rows_all if not spans(p, w)]
    if len(skipped) < len(rows_all):
        assert der.code == 0, der.err
        assert [(s["case"], s["void_width"]) for s in der.json()["skipped"]] == skipped
    else:  # the derived record spans none of them (8 widths today): nothing to run is one error line, exit 2
        assert der.code == 2 and len(der.error_lines) == 1 and "--limits derived" in der.error_lines[0]
        assert not (tmp_path / "d").exists()
