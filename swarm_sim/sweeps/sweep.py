"""Monte-Carlo sweeps: a spec, its run keys, and a resumable execution into SQLite.

A run is identified by ``(preset, param_hash, seed)``; ``param_hash`` is a
digest of everything else that determines the run (swarm size, void width,
the limits and their content digest, ``max_time_s``, overrides). Run ``i``
of a point uses seed ``seed0 + i``, so any run can be replayed alone with
``voidcross sim run --seed``.

The sweep itself is recorded in the ``sweeps`` table under ``sweep_id`` (a
digest of the spec). Behaviour on an existing database:

* same sweep, no ``--resume``: refused (InputError naming how many runs are
  stored), so a typo cannot silently mix a second campaign into the file;
* same sweep, ``--resume``: runs only the missing keys (errored runs stay
  recorded; ``retry_errors=True`` re-runs them);
* a different sweep: added beside the others; keys it shares with runs
  already stored are not re-run nor duplicated;
* the limits changed content since the sweep started: refused.

The run function is injectable: ``run_fn(key: dict) -> dict`` with the
shape of ``swarm_sim.runner.RunResult.to_dict()``; the default calls the
simulator.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Iterator
from dataclasses import asdict, dataclass, field
from pathlib import Path

from ..errors import InputError
from .executors import RunFn, make_executor, resolve_run_fn
from .ranges import format_int_range
from .store import ResultStore, run_row

DEFAULT_RUN_FN = "swarm_sim.sweeps.sweep:simulate"


def _digest(obj) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True, separators=(",", ":")).encode()).hexdigest()[:16]


def limits_digest(limits: str) -> str:
    """Content digest of the limits a sweep uses (``derived``, ``thesis`` or a path)."""
    from structure_fem.limits import load_limits

    return _digest(load_limits(limits).to_dict())


def simulate(key: dict) -> dict:
    """The default run function: one simulator run (``swarm_sim.runner.run_scenario``)."""
    from swarm_sim.runner import run_scenario

    res = run_scenario(key["preset"], key["robots"], key["void_width"], key["seed"],
                       limits=key["limits"], max_time_s=key["params"].get("max_time_s"),
                       **key["params"].get("overrides", {}))
    return res.to_dict()


def preflight(spec: SweepSpec) -> None:
    """Validate every point with the simulator's own parameter checks before anything is written
    (unknown preset, a swarm that does not fit, a void wider than the arena ...: InputError)."""
    from swarm_sim.runner import resolve_params

    for n, w in spec.point_list():
        resolve_params(spec.preset, n, w, limits=spec.limits_label, max_time_s=spec.max_time_s,
                       **spec.overrides)


@dataclass(frozen=True)
class SweepSpec:
    """What to run: ``runs`` seeds for each (robots, void_width) point.

    Points are the product ``robots x void_widths`` unless ``points`` lists
    explicit ``(robots, void_width)`` pairs. ``max_time_s`` caps simulated
    time per run (None: the preset's own limit).
    """

    preset: str
    robots: tuple[int, ...] = ()
    void_widths: tuple[int, ...] = ()
    runs: int = 30
    limits: str = "derived"
    seed0: int = 0
    max_time_s: float | None = None
    overrides: dict = field(default_factory=dict)
    points: tuple[tuple[int, int], ...] | None = None

    def __post_init__(self):
        if not self.preset or not isinstance(self.preset, str):
            raise InputError(f"--preset {self.preset!r}: must be a preset name such as case-d")
        if not isinstance(self.runs, int) or self.runs < 1:
            raise InputError(f"--runs {self.runs!r}: must be an integer >= 1")
        if self.seed0 < 0:
            raise InputError(f"--seed {self.seed0}: must be >= 0")
        if self.max_time_s is not None and not self.max_time_s > 0:
            raise InputError(f"--max-time-s {self.max_time_s}: must be > 0")
        pts = self.point_list()
        if not pts:
            raise InputError("the sweep has no (robots, void width) point")
        for n, w in pts:
            if n < 1 or w < 1:
                raise InputError(f"point robots={n}, void_width={w}: both must be >= 1")

    def point_list(self) -> list[tuple[int, int]]:
        if self.points is not None:
            return sorted({(int(n), int(w)) for n, w in self.points})
        return [(n, w) for w in self.void_widths for n in self.robots]

    @property
    def limits_label(self) -> str:
        """``derived``/``thesis`` as given, a path made absolute (workers may run elsewhere)."""
        if self.limits in ("derived", "thesis"):
            return self.limits
        return str(Path(self.limits).resolve())

    def describe(self) -> dict:
        d = {"preset": self.preset, "runs": self.runs, "limits": self.limits_label, "seed0": self.seed0,
             "max_time_s": self.max_time_s, "overrides": dict(sorted(self.overrides.items()))}
        if self.points is not None:
            d["points"] = [list(p) for p in self.point_list()]
        else:
            d["robots"] = format_int_range(self.robots)
            d["void_widths"] = format_int_range(self.void_widths)
        return d

    @property
    def sweep_id(self) -> str:
        return _digest(self.describe())

    def keys(self, digest: str) -> list[dict]:
        """Every run key, points in order, seeds ``seed0 .. seed0 + runs - 1``."""
        out = []
        for n, w in self.point_list():
            params = {"robots": n, "void_width": w, "limits": self.limits_label, "limits_digest": digest,
                      "max_time_s": self.max_time_s, "overrides": dict(sorted(self.overrides.items()))}
            ph = _digest(params)
            for i in range(self.runs):
                out.append({"preset": self.preset, "param_hash": ph, "seed": self.seed0 + i, "robots": n,
                            "void_width": w, "limits": self.limits_label, "limits_digest": digest,
                            "params": params})
        return out


@dataclass
class SweepSummary:
    db: str
    sweep_id: str
    planned: int
    already_stored: int
    ran: int = 0
    ok: int = 0
    errors: int = 0
    successes: int = 0
    duplicates: int = 0
    interrupted: bool = False
    executor: str = ""
    workers: int = 0
    wall_s: float = 0.0

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class SweepPlan:
    """A validated sweep bound to an open store: ``todo`` are the keys still to run."""

    spec: SweepSpec
    store: ResultStore
    todo: list[dict]
    summary: SweepSummary
    run_fn: RunFn | str = DEFAULT_RUN_FN

    def execute(self, executor) -> Iterator[dict]:
        """Run ``todo`` on ``executor`` (entered), storing each run as it completes; yields rows."""
        self.summary.executor = executor.name
        self.summary.workers = getattr(executor, "workers", 0) or 0
        for key, outcome in executor.run(self.run_fn, self.todo):
            row = run_row(key, outcome)
            inserted = self.store.insert_run(row)
            self.summary.ran += 1
            if not inserted:
                self.summary.duplicates += 1
            elif row["status"] == "ok":
                self.summary.ok += 1
                self.summary.successes += int(bool(row["success"]))
            else:
                self.summary.errors += 1
            yield row

    def close(self) -> None:
        self.store.close()


def stored_count(db, preset: str, keys: list[dict]) -> int:
    """How many of ``keys`` a valid database already holds (read-only look)."""
    ro = ResultStore.open_readonly(db)
    try:
        have = set(ro.existing_keys(preset))
    finally:
        ro.close()
    return sum((k["preset"], k["param_hash"], k["seed"]) in have for k in keys)


def prepare_sweep(spec: SweepSpec, db: str | os.PathLike, resume: bool = False, retry_errors: bool = False,
                  run_fn: RunFn | str | None = None, digest: str | None = None) -> SweepPlan:
    """Validate everything, then open/create the database and list the runs still missing.

    Raises InputError (and leaves an existing file untouched) for a bad spec,
    limits, run function or database, or an existing sweep without ``resume``.
    """
    run_fn = run_fn or DEFAULT_RUN_FN
    if isinstance(run_fn, str):
        resolve_run_fn(run_fn)  # fail before touching the db
    if run_fn in (DEFAULT_RUN_FN, simulate):
        preflight(spec)
    digest = digest or limits_digest(spec.limits)
    keys = spec.keys(digest)
    from .store import check_db

    state = check_db(db)
    if state == "ok":  # decide with a read-only look before writing anything
        ro = ResultStore.open_readonly(db)
        try:
            existing = ro.get_sweep(spec.sweep_id)
        finally:
            ro.close()
        if existing is not None:
            if existing.limits_digest != digest:
                raise InputError(
                    f"--db {db}: sweep {spec.sweep_id} was started with limits {spec.limits_label} of digest "
                    f"{existing.limits_digest}; they now digest to {digest} (the limits changed: use a new --db)")
            if not resume:
                n = stored_count(db, spec.preset, keys)
                raise InputError(
                    f"--db {db} already holds this sweep ({n}/{len(keys)} runs stored): add --resume to "
                    "complete it, or choose another --db")
    store = ResultStore.open(db)
    have = store.existing_keys(spec.preset)
    if retry_errors:
        errs = [(k["preset"], k["param_hash"], k["seed"]) for k in keys
                if have.get((k["preset"], k["param_hash"], k["seed"])) == "error"]
        store.delete_errors(errs)
        for e in errs:
            have.pop(e, None)
    store.add_sweep(spec.sweep_id, spec.describe(), digest, len(keys))
    todo = [k for k in keys if (k["preset"], k["param_hash"], k["seed"]) not in have]
    summary = SweepSummary(db=str(db), sweep_id=spec.sweep_id, planned=len(keys),
                           already_stored=len(keys) - len(todo))
    return SweepPlan(spec, store, todo, summary, run_fn)


def dry_run(spec: SweepSpec, db: str | os.PathLike, run_fn: RunFn | str | None = None, workers: int = 1,
            calibrate: bool = True) -> dict:
    """What a sweep would do, writing nothing: runs planned, already stored in ``db``, to run, and a
    rough wall-time estimate from one timed run at the middle point (``calibrate``)."""
    import time

    run_fn = run_fn or DEFAULT_RUN_FN
    fn = resolve_run_fn(run_fn) if isinstance(run_fn, str) else run_fn
    if run_fn in (DEFAULT_RUN_FN, simulate):
        preflight(spec)
    digest = limits_digest(spec.limits)
    keys = spec.keys(digest)
    from .store import check_db

    stored = stored_count(db, spec.preset, keys) if check_db(db) == "ok" else 0
    out = {"planned": len(keys), "already_stored": stored, "to_run": len(keys) - stored, "points":
           len(spec.point_list()), "runs_per_point": spec.runs, "workers": workers, "calibration": None,
           "estimate_wall_s": None}
    if calibrate and out["to_run"]:
        key = keys[(len(keys) // spec.runs // 2) * spec.runs]
        t0 = time.perf_counter()
        fn(key)
        dt = time.perf_counter() - t0
        out["calibration"] = {"robots": key["robots"], "void_width": key["void_width"], "seed": key["seed"],
                              "wall_s": round(dt, 3)}
        out["estimate_wall_s"] = round(out["to_run"] * dt / max(1, workers), 1)
    return out


def run_sweep(spec: SweepSpec, db: str | os.PathLike, executor: str = "local", workers: int | None = None,
              address: str | None = None, resume: bool = False, run_fn: RunFn | str | None = None,
              retry_errors: bool = False) -> SweepSummary:
    """Library entry point without a progress bar: prepare, execute, return the summary."""
    import time

    plan = prepare_sweep(spec, db, resume=resume, retry_errors=retry_errors, run_fn=run_fn)
    t0 = time.perf_counter()
    try:
        if plan.todo:
            with make_executor(executor, workers=workers, address=address) as ex:
                for _ in plan.execute(ex):
                    pass
    finally:
        plan.summary.wall_s = time.perf_counter() - t0
        plan.close()
    return plan.summary
