"""The launch transients' allowance, cached by a hash of everything it depends on (SI units).

A launch transient (:func:`structure_fem.model.dynamics.dynamic_allowance_m`) is an exudyn time
integration: 1-120 s per structure and width. The threshold criterion of the table is static
tip + that allowance <= clearance (issue 12, deliverable 4), so without a cache every
``fem table`` would integrate the transients again. The allowance is a pure function of

* the structure (kind, lines, layers, arrangement, taper) and the width and rows solved,
* the robot record (every field: mass, inertia, section, contacts, connectors as recorded),
* the connector set the model uses (after the FE, measured or calibrated sources and scales),
* the bodies (flexible or rigid), the damping ratio, the events and the integration settings,
* the code (:data:`MODEL_VERSION`: bump it when ``dynamics.py`` or the static model changes
  what a transient gives; ``tests/structure_fem/test_dynamics_cache.py`` holds a cached value
  to a fresh integration, so a stale version shows),

so its sha256 over a canonical JSON of those inputs is the key: every float to
:data:`KEY_DIGITS` significant digits (:func:`canonical`). The CAD's mass properties differ in
their last bits between builds (measured: the CuBot's inertia, 1.2e-16 relative, between the
packaged record and a fresh ``make demo``'s CAD stage), and a key over exact floats then missed
every packaged transient: the demo integrated all 58 cold (~20 min). Twelve digits are far
finer than any input is known (a mass to 0.1 g is four digits) and far coarser than such
noise (and a magnitude below :data:`KEY_ZERO` counts as zero). Entries live in the user cache
(``$XDG_CACHE_HOME/voidcross/dynamics/<key>.json``, one file each, written atomically) and in
the packaged results (``structure_fem/data/dynamic_allowance.json``, written with the packaged
limits by :func:`write_packaged` from the keys the regeneration used), so the shipped table's
transients are never integrated on a fresh clone. A corrupt cache file is ignored (recomputed
and rewritten), never trusted.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from dataclasses import asdict, dataclass
from pathlib import Path

from cubot_cad.jsonrecord import to_jsonable

#: Bump when the transient model (dynamics.py, the static solve it starts from) changes its result.
MODEL_VERSION = "launch_transient/3"  # 2, 3: the emergent hinge (structure_fem.model.hinge), its smoothing floor
#: The packaged allowances (a list of entries ``{"key", "allowance_m", "inputs"}``).
PACKAGED = Path(__file__).parents[1] / "data" / "dynamic_allowance.json"

#: Keys looked up or computed in this process (what :func:`write_packaged` ships).
_USED: dict[str, dict] = {}
#: Entries computed by :func:`prefill`'s worker processes (found here when the user cache could
#: not be written: a read-only home).
_PREFILLED: dict[str, dict] = {}
#: Keys whose transient did not converge in a :func:`prefill` worker, with why.
_FAILED: dict[str, str] = {}
#: Environment variable: worker processes :func:`prefill` may start (default: the CPU count).
WORKERS_ENV = "VOIDCROSS_TRANSIENT_WORKERS"
_PACKAGED: dict[str, dict] | None = None


def default_cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "voidcross" / "dynamics"


def inputs_of(structure, width, rows: int, robot, connectors, flexible: bool, damping_ratio: float,
              events: tuple[str, ...]) -> dict:
    """The canonical inputs of one allowance (what the key hashes)."""
    from structure_fem.model.dynamics import (
        DEFAULT_PERIODS,
        DEFAULT_STEPS_PER_PERIOD,
        LOW_DAMPING_STEPS_PER_PERIOD,
    )
    from structure_fem.model.statics import SolverOptions

    return {"model": MODEL_VERSION, "structure": asdict(structure), "width": float(width), "rows": int(rows),
            "robot": to_jsonable(robot), "connectors": connectors.to_dict(), "flexible": bool(flexible),
            "damping_ratio": float(damping_ratio), "events": list(events),
            "integration": {"steps_per_period": DEFAULT_STEPS_PER_PERIOD,
                            "low_damping_steps_per_period": LOW_DAMPING_STEPS_PER_PERIOD,
                            "periods": DEFAULT_PERIODS},
            "solver": asdict(SolverOptions())}


#: Significant digits of every float in a key (module docstring).
KEY_DIGITS = 12


#: Floats smaller than this in magnitude count as zero in a key (SI: a product of inertia of a
#: symmetric body is 0 or rounding noise of ~1e-22 kg m^2; no input is meaningful this small).
KEY_ZERO = 1e-18


def canonical(obj):
    """``obj`` (JSON-like) with every number a float rounded to :data:`KEY_DIGITS` significant
    digits (and below :data:`KEY_ZERO` in magnitude to 0.0: a record's ``0`` and a build's
    ``1e-22`` or ``0.0`` are the same input); booleans and strings as they are."""
    if isinstance(obj, int) and not isinstance(obj, bool):
        obj = float(obj)
    if isinstance(obj, float):
        if not math.isfinite(obj):
            return obj
        return 0.0 if abs(obj) < KEY_ZERO else float(f"{obj:.{KEY_DIGITS}g}")
    if isinstance(obj, dict):
        return {k: canonical(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [canonical(v) for v in obj]
    return obj


def key_of(inputs: dict) -> str:
    """sha256 of the canonical JSON of :func:`inputs_of`'s inputs (floats: :func:`canonical`)."""
    return hashlib.sha256(json.dumps(canonical(inputs), sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def _packaged() -> dict[str, dict]:
    global _PACKAGED
    if _PACKAGED is None:
        _PACKAGED = {}
        try:
            rows = json.loads(PACKAGED.read_text())
            for e in rows if isinstance(rows, list) else []:
                if isinstance(e, dict) and isinstance(e.get("key"), str) and _valid(e.get("allowance_m")):
                    _PACKAGED[e["key"]] = e
        except (OSError, ValueError):
            _PACKAGED = {}
    return _PACKAGED


def packaged() -> list[dict]:
    """The packaged entries (valid ones only), by key."""
    table = _packaged()
    return [table[k] for k in sorted(table)]


def _valid(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v >= 0


def lookup(key: str, cache_dir: Path | None = None) -> dict | None:
    """The cached entry of ``key`` (user cache, then packaged), or None."""
    p = (cache_dir or default_cache_dir()) / f"{key}.json"
    try:
        e = json.loads(p.read_text())
        if isinstance(e, dict) and e.get("key") == key and _valid(e.get("allowance_m")):
            return e
    except (OSError, ValueError):
        pass
    return _packaged().get(key)


def store(entry: dict, cache_dir: Path | None = None) -> None:
    """Write ``entry`` to the user cache (atomically; a read-only cache is skipped, not an error)."""
    d = cache_dir or default_cache_dir()
    try:
        d.mkdir(parents=True, exist_ok=True)
        tmp = d / f".{entry['key']}.{os.getpid()}.tmp"
        tmp.write_text(json.dumps(entry, sort_keys=True))
        os.replace(tmp, d / f"{entry['key']}.json")
    except OSError:
        pass


def allowance_m(structure, width, robot, damping_ratio: float, *, rows: int, connectors, flexible: bool,
                static=None, events: tuple[str, ...] | None = None, cache_dir: Path | None = None,
                compute=None) -> float:
    """:func:`structure_fem.model.dynamics.dynamic_allowance_m` through the cache (module docstring);
    ``compute`` replaces the integration (tests)."""
    from structure_fem.model.dynamics import EVENTS, dynamic_allowance_m

    events = EVENTS if events is None else tuple(events)
    inputs = inputs_of(structure, width, rows, robot, connectors, flexible, damping_ratio, events)
    key = key_of(inputs)
    hit = lookup(key, cache_dir) or _PREFILLED.get(key)
    if hit is not None:
        _USED[key] = hit
        return float(hit["allowance_m"])
    if key in _FAILED and compute is None:  # a prefill worker met this failure already
        from structure_fem.errors import SolverFailure

        raise SolverFailure(_FAILED[key])
    fn = compute or dynamic_allowance_m
    a = float(fn(structure, width, robot, damping_ratio, events=events, rows=rows, connectors=connectors,
                 flexible=flexible, static=static))
    entry = {"key": key, "allowance_m": a, "structure": structure.name, "width": float(width), "rows": int(rows),
             "robot": robot.name, "flexible": bool(flexible), "damping_ratio": float(damping_ratio),
             "model": MODEL_VERSION}
    store(entry, cache_dir)
    _USED[key] = entry
    return a


@dataclass(frozen=True)
class Job:
    """One launch transient :func:`prefill` may compute (the arguments of :func:`allowance_m`)."""

    structure: object
    width: int
    rows: int
    robot: object
    connectors: object
    flexible: bool
    damping_ratio: float

    def key(self) -> str:
        from structure_fem.model.dynamics import EVENTS

        return key_of(inputs_of(self.structure, self.width, self.rows, self.robot, self.connectors, self.flexible,
                                self.damping_ratio, EVENTS))


def _run_job(job: Job, cache_dir) -> tuple[str, dict | None, str]:
    """Worker: (key, entry, "") or (key, None, why) when the transient does not converge (the
    caller's own :func:`allowance_m` call meets the failure again and counts it as failing)."""
    from structure_fem.errors import SolverFailure

    try:
        allowance_m(job.structure, job.width, job.robot, job.damping_ratio, rows=job.rows,
                    connectors=job.connectors, flexible=job.flexible, cache_dir=cache_dir)
    except SolverFailure as exc:
        return job.key(), None, str(exc)
    key = job.key()
    return key, _USED[key], ""


def workers_default() -> int:
    """:data:`WORKERS_ENV` when set (an integer >= 1), else the machine's CPU count."""
    v = os.environ.get(WORKERS_ENV, "").strip()
    if v:
        if not v.isdigit() or int(v) < 1:
            from structure_fem.errors import InputError

            raise InputError(f"{WORKERS_ENV} must be an integer >= 1, got {v!r}")
        return int(v)
    return os.cpu_count() or 1


def process_context():
    """Fork where there is fork: the workers start at once with everything imported, and a
    caller's script needs no ``if __name__ == "__main__"`` guard (spawn re-imports it). The
    static model and the transients are single-threaded (exudyn's solvers run here without
    its task manager; ``tests/structure_fem/test_dynamics_cache.py`` integrates in forked
    workers and compares with this process)."""
    import multiprocessing as mp

    return mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")


def prefill(jobs, workers: int | None = None, cache_dir: Path | None = None, progress=None,
            label: str = "launch transients") -> int:
    """Compute the transients of ``jobs`` that no cache holds yet, ``workers`` at a time in
    separate processes (each integration is single-threaded; default :func:`workers_default`),
    so the callers' own :func:`allowance_m` calls afterwards are cache hits. Returns how many
    were integrated. One missing job, or ``workers == 1``, runs here. ``progress(iterable, label,
    total)`` wraps the completions (a progress bar). What a worker computed is written to the
    user cache by the worker and kept in this process too (for :func:`write_packaged`, and when
    the cache is read-only); a transient that does not converge is remembered, so the caller's
    own call fails at once (and counts it as failing) instead of integrating it again."""
    import concurrent.futures as cf
    import multiprocessing as mp

    workers = workers_default() if workers is None else workers
    if mp.current_process().daemon:  # a pool's worker may not start processes of its own: run here
        workers = 1
    todo: dict[str, Job] = {}
    for j in jobs:
        k = j.key()
        if k not in todo and lookup(k, cache_dir) is None and k not in _PREFILLED and k not in _FAILED:
            todo[k] = j
    if not todo:
        return 0
    # the longest first (the cost grows with the robots in the structure), so the workers end together
    order = sorted(todo.values(), key=lambda j: -j.rows * getattr(j.structure, "lines", 1)
                   * getattr(j.structure, "layers", 1))

    def keep(res: tuple[str, dict | None, str]) -> None:
        key, entry, why = res
        if entry is None:
            _FAILED[key] = why
        else:
            _PREFILLED[key] = _USED[key] = entry

    wrap = progress or (lambda it, _label, _total: it)
    if workers <= 1 or len(order) == 1:
        for j in wrap(order, label, len(order)):
            keep(_run_job(j, cache_dir))
        return len(order)
    with cf.ProcessPoolExecutor(max_workers=min(workers, len(order)), mp_context=process_context()) as ex:
        futs = [ex.submit(_run_job, j, cache_dir) for j in order]
        for f in wrap(cf.as_completed(futs), label, len(futs)):
            keep(f.result())
    return len(order)


def used() -> list[dict]:
    """The entries looked up or computed in this process, by key."""
    return [_USED[k] for k in sorted(_USED)]


def write_packaged(path: Path = PACKAGED) -> Path:
    """Ship this process's entries (the regeneration's) as the packaged allowances."""
    from cubot_cad.jsonrecord import write_json_atomic

    global _PACKAGED
    write_json_atomic(path, used())
    _PACKAGED = None
    return path
