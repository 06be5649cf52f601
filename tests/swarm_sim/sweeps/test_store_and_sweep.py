"""Sweeps store every run once, keyed by (preset, parameter hash, seed), and resume exactly."""

from __future__ import annotations

import hashlib
import os
import sqlite3

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from swarm_sim.errors import InputError
from swarm_sim.sweeps import (
    SCHEMA_VERSION,
    ResultStore,
    SweepSpec,
    check_db,
    prepare_sweep,
    run_sweep,
)
from swarm_sim.sweeps.executors import SerialExecutor

SYNTH = "swarm_sim.sweeps.synthetic:synthetic_run"


def fingerprint(path) -> tuple:
    """Bytes digest and mtime of a file: 'left untouched' means both unchanged."""
    st = os.stat(path)
    return hashlib.sha256(open(path, "rb").read()).hexdigest(), st.st_mtime_ns, st.st_size


def rows(db) -> list[tuple]:
    con = sqlite3.connect(db)
    try:
        return con.execute("SELECT preset, param_hash, seed, status, t_t FROM runs").fetchall()
    finally:
        con.close()


def spec(**kw):
    base = dict(preset="case-d", robots=(3, 5, 6), void_widths=(1, 2), runs=4, limits="thesis")
    base.update(kw)
    return SweepSpec(**base)


def run_serial(s, db, **kw):
    plan = prepare_sweep(s, db, run_fn=SYNTH, **kw)
    with SerialExecutor() as ex:
        out = list(plan.execute(ex))
    plan.close()
    return plan.summary, out


def test_sweep_stores_every_run_once_with_schema_version(tmp_path):
    db = tmp_path / "r.sqlite"
    summary, out = run_serial(spec(), db)
    assert summary.planned == 3 * 2 * 4 == summary.ok == len(rows(db))
    con = sqlite3.connect(db)
    assert con.execute("SELECT version FROM schema_version").fetchall() == [(SCHEMA_VERSION,)]
    assert con.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    keys = con.execute("SELECT preset, param_hash, seed FROM runs").fetchall()
    assert len(set(keys)) == len(keys)
    # seeds 0..3 per point; the synthetic rule N >= 3w crosses
    got = {(n, w): s for n, w, s in con.execute(
        "SELECT robots, void_width, SUM(success) FROM runs GROUP BY robots, void_width")}
    assert got == {(3, 1): 4, (5, 1): 4, (6, 1): 4, (3, 2): 0, (5, 2): 0, (6, 2): 4}
    assert check_db(db) == "ok"


def test_parameter_hash_moves_with_every_parameter():
    k = spec().keys("d1")[0]["param_hash"]
    assert spec(max_time_s=100.0).keys("d1")[0]["param_hash"] != k
    assert spec(overrides={"speed_cm_s": 10}).keys("d1")[0]["param_hash"] != k
    assert spec().keys("d2")[0]["param_hash"] != k  # limits content changed
    assert spec(runs=9).keys("d1")[0]["param_hash"] == k  # more seeds: same points
    assert spec(runs=9).sweep_id != spec().sweep_id


def test_same_sweep_without_resume_is_refused_and_db_untouched(tmp_path):
    db = tmp_path / "r.sqlite"
    run_serial(spec(), db)
    before = fingerprint(db)
    with pytest.raises(InputError, match="already holds this sweep .24/24.*--resume"):
        prepare_sweep(spec(), db, run_fn=SYNTH)
    assert fingerprint(db) == before


def test_interrupted_sweep_resumes_without_loss_or_duplicates(tmp_path):
    db = tmp_path / "r.sqlite"
    plan = prepare_sweep(spec(), db, run_fn=SYNTH)
    gen = plan.execute(SerialExecutor())
    for _ in range(7):
        next(gen)
    gen.close()  # the consumer stops mid-sweep
    plan.close()
    assert len(rows(db)) == 7
    summary, _ = run_serial(spec(), db, resume=True)
    assert summary.already_stored == 7 and summary.ran == 24 - 7 and summary.duplicates == 0
    r = rows(db)
    assert len(r) == 24 and len({x[:3] for x in r}) == 24


def test_more_seeds_reuse_stored_runs(tmp_path):
    db = tmp_path / "r.sqlite"
    run_serial(spec(), db)
    summary, _ = run_serial(spec(runs=6), db)  # a different sweep sharing 24 keys
    assert summary.already_stored == 24 and summary.ran == 12
    assert len(rows(db)) == 36


def test_run_that_raises_is_recorded_with_traceback_and_sweep_goes_on(tmp_path):
    db = tmp_path / "r.sqlite"
    s = spec(overrides={"raise_on_seed": 2})
    summary, _ = run_serial(s, db)
    assert summary.errors == 6 and summary.ok == 18
    with ResultStore.open_readonly(db) as st:
        errs = list(st.iter_runs("WHERE status='error'"))
    assert {e["seed"] for e in errs} == {2}
    assert all("Traceback" in e["error"] and "synthetic failure for seed 2" in e["error"] for e in errs)
    assert all(e["error_type"] == "builtins.RuntimeError" and e["t_t"] is None for e in errs)
    # resume keeps them (deterministic seeds would raise again) ...
    summary, _ = run_serial(s, db, resume=True)
    assert summary.ran == 0
    # ... unless asked to retry
    summary, _ = run_serial(s, db, resume=True, retry_errors=True)
    assert summary.ran == 6 and summary.errors == 6 and len(rows(db)) == 24


def test_bad_return_value_is_an_error_row(tmp_path):
    summary, out = run_serial(spec(runs=1, overrides={"return_bad": True}), tmp_path / "r.sqlite")
    assert summary.errors == 6 and "expected a dict" in out[0]["error"]


def test_changed_limits_are_refused_on_resume(tmp_path):
    db = tmp_path / "r.sqlite"
    plan = prepare_sweep(spec(), db, run_fn=SYNTH, digest="aaaa")
    plan.close()
    before = fingerprint(db)
    with pytest.raises(InputError, match="limits changed"):
        prepare_sweep(spec(), db, run_fn=SYNTH, resume=True, digest="bbbb")
    assert fingerprint(db) == before


def test_other_schema_version_and_foreign_and_corrupt_dbs(tmp_path):
    other = tmp_path / "other.sqlite"
    con = sqlite3.connect(other)
    con.execute("CREATE TABLE schema_version (version INTEGER)")
    con.execute("INSERT INTO schema_version VALUES (99)")
    con.commit()
    con.close()
    foreign = tmp_path / "foreign.sqlite"
    con = sqlite3.connect(foreign)
    con.execute("CREATE TABLE stuff (x)")
    con.commit()
    con.close()
    corrupt = tmp_path / "corrupt.sqlite"
    corrupt.write_bytes(b"SQLite format 3\x00" + b"\x07" * 4000)
    for path, pat in [(other, "schema version 99"), (foreign, "no schema_version"),
                      (corrupt, "not a readable")]:
        before = fingerprint(path)
        with pytest.raises(InputError, match=pat):
            prepare_sweep(spec(), path, run_fn=SYNTH)
        assert fingerprint(path) == before
        assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(path.name)) == [path.name]


def test_bad_spec_values():
    with pytest.raises(InputError, match="--runs 0"):
        spec(runs=0)
    with pytest.raises(InputError, match="no .robots, void width. point"):
        spec(robots=())
    with pytest.raises(InputError, match="--run-fn"):
        prepare_sweep(spec(), "/nonexistent/x.sqlite", run_fn="nosuch.module:fn")


def test_explicit_points(tmp_path):
    s = SweepSpec("case-d", points=((2, 1), (3, 1), (5, 2), (6, 2)), runs=2, limits="thesis")
    summary, _ = run_serial(s, tmp_path / "p.sqlite")
    assert summary.planned == 8 and summary.successes == 4


def test_local_process_pool(tmp_path):
    summary = run_sweep(spec(runs=3), tmp_path / "l.sqlite", workers=2, run_fn=SYNTH)
    assert summary.ok == 18 and summary.executor == "local" and summary.workers == 2
    with ResultStore.open_readonly(tmp_path / "l.sqlite") as st:
        workers = {r["worker"] for r in st.iter_runs()}
    assert len(workers) >= 1 and all(":" in w for w in workers)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(cuts=st.lists(st.integers(0, 24), min_size=1, max_size=3))
def test_any_sequence_of_interruptions_gives_the_uninterrupted_result(tmp_path_factory, cuts):
    d = tmp_path_factory.mktemp("cuts")
    ref, _ = run_serial(spec(), d / "ref.sqlite")
    db = d / "cut.sqlite"
    for k in cuts:
        plan = prepare_sweep(spec(), db, run_fn=SYNTH, resume=True)
        gen = plan.execute(SerialExecutor())
        for _ in zip(range(k), gen, strict=False):
            pass
        gen.close()
        plan.close()
    run_serial(spec(), db, resume=True)
    cols = "preset, param_hash, seed, status, success, t_s, t_a, t_o, t_d, t_b, t_t, seed_robot, target_finder"

    def table(p):
        con = sqlite3.connect(p)
        try:
            return sorted(con.execute(f"SELECT {cols} FROM runs").fetchall())
        finally:
            con.close()

    assert table(db) == table(d / "ref.sqlite")


def test_workers_get_runs_in_batches_and_every_run_comes_back_once(tmp_path, monkeypatch):
    """One task per batch of runs (one round trip, one pickled run function), never per run;
    a short last batch; every key's outcome paired with its key."""
    from swarm_sim.sweeps import executors as E

    keys = [{"preset": "case-d", "robots": 3, "void_width": 1, "seed": s, "limits": "thesis"} for s in range(10)]
    ex = E.LocalExecutor(workers=2, batch=3)
    with ex:
        sizes = []
        real = ex._pool.submit

        def counting(fn, run_fn, batch):
            sizes.append(len(batch))
            return real(fn, run_fn, batch)

        monkeypatch.setattr(ex._pool, "submit", counting)
        out = list(ex.run(SYNTH, keys))
    assert sorted(sizes) == [1, 3, 3, 3]
    assert sorted(k["seed"] for k, _ in out) == list(range(10))
    assert all(o["status"] == "ok" and o["result"]["seed"] == k["seed"] for k, o in out)
    with pytest.raises(InputError, match="--batch 0"):
        E.LocalExecutor(workers=1, batch=0)


def test_ctrl_c_just_after_a_commit_is_the_interrupt_not_a_rollback_error(tmp_path):
    """A Ctrl-C that lands between COMMIT and the end of the write used to try a ROLLBACK with no
    transaction open, and the sweep ended with "internal failure: cannot rollback" (exit 1)
    instead of "interrupted" (130). The run written is kept."""
    run_sweep(SweepSpec("case-d", (3,), (1,), runs=1, limits="thesis"), tmp_path / "k.sqlite", run_fn=SYNTH)
    st = ResultStore.open(tmp_path / "k.sqlite")
    real = st.con

    class InterruptAfterCommit:
        in_transaction = property(lambda self: real.in_transaction)

        def execute(self, sql, *a):
            cur = real.execute(sql, *a)
            if sql == "COMMIT":
                raise KeyboardInterrupt
            return cur

    st.con = InterruptAfterCommit()
    row = {**next(iter(st.iter_runs())), "seed": 999}
    with pytest.raises(KeyboardInterrupt):
        st.insert_run(row)
    st.con = real
    assert any(r["seed"] == 999 for r in st.iter_runs())
    st.close()
