"""Runs a study needs, as sweeps in the one SQLite store: what is stored is read, what is
missing is run (on one executor shared by the whole study) and stored run by run, so a study
killed at any instant (``kill -9``) loses at most the runs in flight and resumes by replay."""

from __future__ import annotations

from collections.abc import Callable, Iterable

from ..sweeps import ResultStore, SweepSpec, prepare_sweep
from ..sweeps.store import run_row

#: ``progress(iterable, desc, total) -> iterable`` (the CLI passes its progress bar)
Progress = Callable[[Iterable, str, int], Iterable]


def ensure_runs(specs: list[SweepSpec], db, executor, run_fn, digest: str, progress: Progress | None = None,
                desc: str = "") -> int:
    """Run every key of ``specs`` not yet stored in ``db`` on the entered ``executor``; returns
    how many ran. Each spec is recorded as a sweep (``voidcross sweep status`` lists them)."""
    todo = []
    for spec in specs:
        plan = prepare_sweep(spec, db, resume=True, run_fn=run_fn, digest=digest)
        todo += plan.todo
        plan.close()
    if not todo:
        return 0
    store = ResultStore.open(db)
    try:
        it = executor.run(run_fn, todo)
        if progress is not None:
            it = progress(it, desc, len(todo))
        for key, outcome in it:
            store.insert_run(run_row(key, outcome))
    finally:
        store.close()
    return len(todo)


def stored_rows(specs: list[SweepSpec], db, digest: str) -> list[list[dict]]:
    """Per spec, its stored rows (one per key, in key order; a key never run is an error)."""
    out = []
    with ResultStore.open_readonly(db) as store:
        for spec in specs:
            keys = spec.keys(digest)
            want = {(k["param_hash"], k["seed"]) for k in keys}
            got = {}
            for ph in {k["param_hash"] for k in keys}:
                for r in store.iter_runs("WHERE preset=? AND param_hash=?", (spec.preset, ph)):
                    if (r["param_hash"], r["seed"]) in want:
                        got[(r["param_hash"], r["seed"])] = r
            missing = want - set(got)
            if missing:
                raise RuntimeError(f"{len(missing)} runs of {spec.preset} missing from {db} after running them")
            out.append([got[(k["param_hash"], k["seed"])] for k in keys])
    return out
