"""`voidcross sweep`: the CLI over the sweep engine, killed and resumed for real."""

from __future__ import annotations

import csv
import hashlib
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

SYNTH = "swarm_sim.sweeps.synthetic:synthetic_run"


def fingerprint(path) -> tuple:
    """Bytes digest, mtime and size: 'left untouched' means all unchanged."""
    st = os.stat(path)
    return hashlib.sha256(Path(path).read_bytes()).hexdigest(), st.st_mtime_ns, st.st_size


def rows(db) -> list[tuple]:
    con = sqlite3.connect(db)
    try:
        return con.execute("SELECT preset, param_hash, seed, status, t_t FROM runs").fetchall()
    finally:
        con.close()


BASE = ["sweep", "--preset", "case-d", "--limits", "thesis", "--run-fn", SYNTH]


def _wait_rows(db: Path, n: int, proc: subprocess.Popen, timeout: float = 60.0) -> int:
    t0 = time.time()
    while time.time() - t0 < timeout:
        if proc.poll() is not None:
            raise AssertionError(f"sweep ended early: {proc.returncode} {proc.stderr.read()}")
        if db.exists():
            try:
                con = sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=5)
                k = con.execute("SELECT COUNT(*) FROM runs").fetchone()[0]
                con.close()
                if k >= n:
                    return k
            except sqlite3.Error:
                pass
        time.sleep(0.05)
    raise AssertionError(f"fewer than {n} rows after {timeout} s")


def _spawn(args: list[str]) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "voidcross.cli", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True,
                            cwd=Path(__file__).resolve().parents[2])


def _children(pid: int) -> list[int]:
    out = subprocess.run(["ps", "-o", "pid=", "--ppid", str(pid)], capture_output=True, text=True).stdout
    return [int(x) for x in out.split()]


def test_kill_9_then_resume_loses_nothing_and_duplicates_nothing(tmp_path):
    db = tmp_path / "k.sqlite"
    args = [*BASE, "--robots", "3-8", "--void-width", "1-2", "--runs", "6", "--workers", "2",
            "--set", "sleep_s=0.2", "--db", str(db)]
    planned = 6 * 2 * 6
    for kill_after in (5, 30):  # two kills at different moments
        proc = _spawn(args + (["--resume"] if kill_after == 30 else []))
        _wait_rows(db, kill_after, proc)
        workers = _children(proc.pid)
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        assert proc.returncode == -signal.SIGKILL
        for w in workers:  # the pool dies with its parent (PR_SET_PDEATHSIG); reap any straggler
            for _ in range(100):
                try:
                    os.kill(w, 0)
                except ProcessLookupError:
                    break
                time.sleep(0.05)
            else:
                os.kill(w, signal.SIGKILL)
                pytest.fail(f"worker {w} outlived the killed sweep")
        stored = rows(db)
        assert 0 < len(stored) < planned
        assert all(r[3] == "ok" and r[4] is not None for r in stored)  # whole rows only
    proc = _spawn(args + ["--resume"])
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err
    stored = rows(db)
    assert len(stored) == planned == len({r[:3] for r in stored})
    assert all(r[3] == "ok" and r[4] is not None for r in stored)
    con = sqlite3.connect(db)
    assert con.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
    con.close()


def test_ctrl_c_stops_cleanly_and_says_how_to_resume(tmp_path):
    db = tmp_path / "c.sqlite"
    args = [*BASE, "--robots", "3-8", "--void-width", "1-2", "--runs", "5", "--workers", "2",
            "--set", "sleep_s=0.2", "--db", str(db)]
    proc = _spawn(args)
    _wait_rows(db, 4, proc)
    os.killpg(proc.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the whole process group
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert "--resume" in err and "error: interrupted" in err
    n = len(rows(db))
    assert 0 < n < 60
    proc = _spawn(args + ["--resume"])
    proc.communicate(timeout=120)
    assert proc.returncode == 0 and len(rows(db)) == 60


def test_sweep_then_export_csv(cli, tmp_path):
    db, out = tmp_path / "e.sqlite", tmp_path / "runs.csv"
    res = cli(*BASE, "--robots", "2-3", "--void-width", "1", "--runs", "3", "--workers", "1",
              "--db", str(db), "--json")
    assert res.code == 0, res.err
    assert res.json()["ok"] == 6
    res = cli("sweep", "export", "--db", str(db), "--to", str(out))
    assert res.code == 0, res.err
    with open(out) as fh:
        table = list(csv.DictReader(fh))
    assert len(table) == 6
    need = {"preset", "robots", "void_width", "seed", "success", "retreated", "robots_lost", "Ts", "Ta",
            "To", "Td", "Tb", "Tt", "seed_robot", "target_finder"}
    assert need <= set(table[0])
    assert {(r["robots"], r["success"]) for r in table} == {("2", "False"), ("3", "True")}
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []
    res = cli("sweep", "status", "--db", str(db), "--json")
    assert res.code == 0 and res.json()["counts"] == {"ok": 6, "error": 0}


def test_parquet_export_needs_pyarrow(cli, tmp_path):
    db = tmp_path / "e.sqlite"
    assert cli(*BASE, "--robots", "3", "--void-width", "1", "--runs", "2", "--workers", "1",
               "--db", str(db)).code == 0
    res = cli("sweep", "export", "--db", str(db), "--to", str(tmp_path / "r.parquet"))
    try:
        import pyarrow.parquet as pq
    except ImportError:
        assert res.code == 2 and len(res.error_lines) == 1 and "pyarrow" in res.error_lines[0]
        assert not (tmp_path / "r.parquet").exists()
    else:
        assert res.code == 0 and pq.read_table(tmp_path / "r.parquet").num_rows == 2


@pytest.fixture
def existing_db(cli, tmp_path):
    db = tmp_path / "x.sqlite"
    assert cli(*BASE, "--robots", "3", "--void-width", "1", "--runs", "2", "--workers", "1",
               "--db", str(db)).code == 0
    return db


@pytest.mark.parametrize("robots, widths, fragment", [
    ("5-3", "1", "reversed"), ("", "1", "empty"), ("x", "1", "'x'"), ("3", "", "empty"),
    ("3", "2-1", "reversed"),
])
def test_bad_ranges_exit_2_and_leave_the_db_untouched(cli, existing_db, robots, widths, fragment):
    before = fingerprint(existing_db)
    res = cli(*BASE, "--robots", robots, "--void-width", widths, "--db", str(existing_db), "--resume")
    assert res.code == 2 and len(res.error_lines) == 1 and fragment in res.error_lines[0]
    assert fingerprint(existing_db) == before


def test_same_sweep_again_without_resume_is_refused(cli, existing_db):
    before = fingerprint(existing_db)
    res = cli(*BASE, "--robots", "3", "--void-width", "1", "--runs", "2", "--db", str(existing_db))
    assert res.code == 2 and len(res.error_lines) == 1 and "--resume" in res.error_lines[0]
    assert fingerprint(existing_db) == before


def test_other_schema_version_and_corrupt_db_exit_2_untouched(cli, tmp_path):
    other = tmp_path / "v2.sqlite"
    con = sqlite3.connect(other)
    con.execute("CREATE TABLE schema_version (version INTEGER)")
    con.execute("INSERT INTO schema_version VALUES (2)")
    con.commit()
    con.close()
    corrupt = tmp_path / "bad.sqlite"
    corrupt.write_bytes(os.urandom(8192))
    for db in (other, corrupt):
        before = fingerprint(db)
        for argv in ([*BASE, "--robots", "3", "--void-width", "1", "--db", str(db)],
                     ["sweep", "export", "--db", str(db), "--to", str(tmp_path / "o.csv")],
                     ["report", "--db", str(db), "--out", str(tmp_path / "rep")]):
            res = cli(*argv)
            assert res.code == 2 and len(res.error_lines) == 1 and str(db) in res.error_lines[0], res.err
            assert fingerprint(db) == before
    assert not (tmp_path / "o.csv").exists()


def test_dask_executor_against_a_scheduler_address(cli, tmp_path):
    distributed = pytest.importorskip("distributed")
    db = tmp_path / "d.sqlite"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  protocol="tcp://", host="127.0.0.1", dashboard_address=None) as cluster:
        res = cli(*BASE, "--robots", "3-6", "--void-width", "1-2", "--runs", "3", "--executor", "dask",
                  "--address", cluster.scheduler_address, "--db", str(db), "--json")
    assert res.code == 0, res.err
    s = res.json()
    assert s["executor"] == "dask" and s["ok"] == 24 and len(rows(db)) == 24


def test_address_without_dask_is_bad_input(cli, tmp_path):
    res = cli(*BASE, "--robots", "3", "--void-width", "1", "--address", "tcp://127.0.0.1:1",
              "--db", str(tmp_path / "a.sqlite"))
    assert res.code == 2 and "--address" in res.error_lines[0]


def test_dead_worker_is_an_internal_failure_that_keeps_stored_runs(cli, tmp_path):
    db = tmp_path / "w.sqlite"
    # one run per task: the runs before the one that kills its worker are stored (with batches,
    # a dead worker takes its unfinished batch with it; --resume re-runs them)
    res = cli(*BASE, "--robots", "3-6", "--void-width", "1", "--runs", "4", "--workers", "1", "--batch", "1",
              "--set", "exit_on_seed=3", "--db", str(db))
    assert res.code == 1 and "worker process died" in res.err and "--resume" in res.err
    stored = rows(db)
    assert stored and all(r[3] == "ok" and r[2] != 3 for r in stored)


def test_dry_run_counts_and_estimates_without_writing(cli, tmp_path):
    db = tmp_path / "dry.sqlite"
    res = cli(*BASE, "--robots", "3-5", "--void-width", "1-2", "--runs", "4", "--db", str(db), "--dry-run",
              "--workers", "2", "--json")
    assert res.code == 0, res.err
    d = res.json()
    assert (d["planned"], d["already_stored"], d["to_run"], d["points"]) == (24, 0, 24, 6)
    assert d["calibration"]["wall_s"] >= 0 and d["estimate_wall_s"] is not None
    assert not db.exists()
    assert cli(*BASE, "--robots", "3-5", "--void-width", "1-2", "--runs", "4", "--db", str(db)).code == 0
    again = cli(*BASE, "--robots", "3-5", "--void-width", "1-2", "--runs", "4", "--db", str(db), "--dry-run",
                "--json").json()
    assert again["already_stored"] == 24 and again["to_run"] == 0 and again["estimate_wall_s"] is None
