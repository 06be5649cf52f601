"""A study runs as sweeps in the SQLite store, resumes by replay after kill -9, extends with more
trials, and the held-out check rejects a rule set that breaks the crossing boundary."""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time

import pytest

from swarm_sim.optimise import SearchSpace, StudyConfig, compare, run_study

TINY = dict(cases=("D",), train_seeds=1, train_widths=(2,), space=SearchSpace(("levy_mu", "avoid_cm", "stall_s")))


def _cli(*args, **kw):
    return subprocess.run([sys.executable, "-m", "voidcross.cli", *args], capture_output=True, text=True, **kw)


def _runs(db) -> int:
    try:
        con = sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=5)
        try:
            return con.execute("SELECT COUNT(*) FROM runs").fetchone()[0]
        finally:
            con.close()
    except sqlite3.Error:
        return 0


def test_more_trials_extend_the_same_study_and_a_replay_runs_nothing(tmp_path):
    db = tmp_path / "opt.sqlite"
    short = run_study(StudyConfig(trials=3, **TINY), db, executor="serial")
    assert short.new_runs == 4 * 3  # trial 0 (the thesis's rules) + 3 trials, 3 cells x 1 seed
    longer = run_study(StudyConfig(trials=5, **TINY), db, executor="serial")
    assert [t.params for t in longer.trials[:3]] == [t.params for t in short.trials]
    assert longer.convergence()[:4] == short.convergence()
    assert longer.new_runs == 2 * 3  # only trials 4 and 5 ran
    again = run_study(StudyConfig(trials=5, **TINY), db, executor="serial")
    assert again.new_runs == 0 and again.convergence() == longer.convergence()
    assert again.best.score.value <= again.baseline.score.value


def test_kill_9_mid_study_loses_nothing_and_the_resumed_study_is_the_uninterrupted_one(tmp_path):
    args = ["optimise", "--cases", "d", "--trials", "8", "--train-seeds", "2", "--train-widths", "2",
            "--params", "levy_mu,avoid_cm,stall_s", "--heldout-runs", "0", "--executor", "serial", "--quiet",
            "--json"]
    whole = _cli(*args, "--db", str(tmp_path / "whole.sqlite"), timeout=600)
    assert whole.returncode == 0, whole.stderr
    ref = json.loads(whole.stdout)["study"]
    db = tmp_path / "killed.sqlite"
    proc = subprocess.Popen([sys.executable, "-m", "voidcross.cli", *args, "--db", str(db)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    t0 = time.monotonic()
    while _runs(db) < 20 and proc.poll() is None and time.monotonic() - t0 < 300:
        time.sleep(0.05)
    assert proc.poll() is None, "the study ended before it could be killed: make it longer"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    stored = _runs(db)
    assert 20 <= stored < ref["new_runs"]
    resumed = _cli(*args, "--db", str(db), timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    got = json.loads(resumed.stdout)["study"]
    assert got["new_runs"] == ref["new_runs"] - stored  # nothing stored was run again
    assert got["convergence"] == ref["convergence"]
    assert [t["params"] for t in got["trials"]] == [t["params"] for t in ref["trials"]]
    assert got["best"] == ref["best"]


def _fake_run(key: dict) -> dict:
    """Crosses at 3w like the thesis's rules; with any override it crosses at 3w - 2 (a bridge the
    rule says cannot hold) and 20 % faster: the held-out check must reject it anyway."""
    n, w, seed = int(key["robots"]), int(key["void_width"]), int(key["seed"])
    tuned = bool(key["params"]["overrides"])
    ok = n >= 3 * w - (2 if tuned else 0)
    tt = (100.0 + 10 * w + seed % 7) * (0.8 if tuned else 1.0)
    return {"success": ok, "retreated": not ok, "robots_lost": 0, "timed_out": False, "min_robots_rule": 3 * w,
            "times": {"Ts": 1.0, "Ta": 50.0, "To": 1.0, "Td": None if ok else 5.0, "Tb": None, "Tt": tt},
            "seed_position": None, "preset": key["preset"], "robots": n, "void_width": w, "seed": seed}


def test_the_held_out_check_rejects_a_faster_rule_set_that_crosses_below_the_boundary(tmp_path):
    cfg = StudyConfig(trials=1, **TINY)
    cmp = compare({"levy_mu": 2.5}, cfg, tmp_path / "h.sqlite", runs=2, executor="serial", run_fn=_fake_run)
    assert cmp.gain_pct["D"] > 10  # faster on the held-out seeds ...
    assert not cmp.accepted  # ... and rejected: at 2 widths it crosses with 4 robots, the rule is 6
    assert any(r.startswith("case D at 2 widths: the boundary is 4 (rule 6") for r in cmp.reasons), cmp.reasons
    assert cmp.tuned["D"]["boundary"]["2"]["observed"] == 4 and cmp.thesis["D"]["boundary"]["2"]["ok"]
    same = compare({}, cfg, tmp_path / "h.sqlite", runs=2, executor="serial", run_fn=_fake_run)
    assert same.accepted and same.gain_pct["D"] == pytest.approx(0.0) and same.new_runs == 0
