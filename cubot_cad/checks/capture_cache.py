"""The capture ranges of ``voidcross cad dock`` kept by the geometry's hash, measured in parallel.

A capture range depends on nothing but the coupling's geometry (the two meshes at their docked
pose, the approach, pivot, axes and steps of :class:`~cubot_cad.checks.capture.CouplingGeometry`),
the ladders and the entry simulation's code. :func:`key_of` hashes all of that (the meshes as
``manifold3d`` returns them, the source of :mod:`cubot_cad.checks.capture`), so a second call on
the same CAD reads ``$XDG_CACHE_HOME/voidcross/capture/<key>.json`` (one file per coupling,
written atomically) in milliseconds, and any change of a dimension, a clearance, a ``--set`` or
the checker itself is a miss. Misses are measured in worker processes, one coupling each
(:func:`measure_all`): the meshes travel as arrays (a Manifold does not pickle) and every
measurement, in a worker or not, starts from those arrays, so the result does not depend on
where it ran.

The default robots' couplings at the default clearance (what ``cad dock`` measures on a fresh
clone) ship in ``cubot_cad/data/capture_ranges.json`` under the same keys, read after the user's
cache: a first ``cad dock`` is seconds, and a changed dimension, checker or manifold3d is still
a miss. ``python -m cubot_cad.checks.capture_cache`` regenerates it (a test says when it is stale).
"""

from __future__ import annotations

import hashlib
import json
import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict
from functools import lru_cache
from pathlib import Path

import numpy as np

from cubot_cad.atomic import write_bytes
from cubot_cad.checks import capture as C

#: Bumped when a cached entry's meaning changes without the checker's source changing.
CACHE_VERSION = 2
#: The packaged captures of the default robots (:func:`write_packaged`).
PACKAGED = Path(__file__).resolve().parents[1] / "data" / "capture_ranges.json"


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "voidcross" / "capture"


def _mesh(m) -> tuple[np.ndarray, np.ndarray]:
    mesh = m.to_mesh()
    # owned, writable copies: manifold3d >= 3.5 hands out read-only views of its mesh, and its
    # Mesh() refuses read-only arrays
    return np.array(mesh.vert_properties, dtype=np.float32, order="C"), \
        np.array(mesh.tri_verts, dtype=np.uint32, order="C")


def _manifold(arrays):
    import manifold3d as m3d

    v, t = arrays
    return m3d.Manifold(m3d.Mesh(vert_properties=v, tri_verts=t))


def portable(g: C.CouplingGeometry) -> dict:
    """``g`` as arrays and numbers (picklable, hashable)."""
    return {"fixed": _mesh(g.fixed), "moving": _mesh(g.moving), "approach": np.asarray(g.approach, float),
            "pivot": np.asarray(g.pivot, float), "axes": {k: np.asarray(v, float) for k, v in g.axes.items()},
            "start_mm": float(g.start_mm), "step_mm": float(g.step_mm)}


def rebuilt(p: dict) -> C.CouplingGeometry:
    return C.CouplingGeometry(_manifold(p["fixed"]), _manifold(p["moving"]), p["approach"], p["pivot"],
                              p["axes"], p["start_mm"], p["step_mm"])


def key_of(name: str, p: dict, full_ladder: bool) -> str:
    from importlib.metadata import version

    h = hashlib.sha256()
    # the booleans' library too: another manifold3d may cut the meshes differently
    h.update(f"{CACHE_VERSION}|{version('manifold3d')}|{name}|{full_ladder}|{p['start_mm']!r}|"
             f"{p['step_mm']!r}".encode())
    h.update(Path(C.__file__).read_bytes())
    for arr in (*p["fixed"], *p["moving"], p["approach"], p["pivot"]):
        h.update(arr.tobytes())
    for k in sorted(p["axes"]):
        h.update(k.encode())
        h.update(p["axes"][k].tobytes())
    return h.hexdigest()


def _to_json(cap: C.Capture) -> dict:
    return {"pair": cap.pair, "step_mm": cap.step_mm, "offset_mm": cap.offset_mm, "angle_deg": cap.angle_deg,
            "entries": [asdict(e) for e in cap.entries]}


def _from_json(d: dict) -> C.Capture:
    return C.Capture(d["pair"], d["step_mm"], dict(d["offset_mm"]), dict(d["angle_deg"]),
                     [C.Entry(**e) for e in d["entries"]])


@lru_cache(maxsize=1)
def _packaged() -> dict:
    """The packaged file's ``{key: capture}``, read once per process (:func:`write_packaged` clears it)."""
    try:
        return json.loads(PACKAGED.read_text())["captures"]
    except (OSError, ValueError, KeyError, TypeError):
        return {}  # none shipped (or unreadable): everything is measured


def lookup(key: str) -> C.Capture | None:
    """The user cache's entry, else the packaged one, else None (measure it)."""
    f = cache_dir() / f"{key}.json"
    try:
        return _from_json(json.loads(f.read_text()))
    except (OSError, ValueError, KeyError, TypeError):
        pass  # absent or unreadable (a torn write is impossible: atomic)
    d = _packaged().get(key)
    try:
        return None if d is None else _from_json(d)
    except (ValueError, KeyError, TypeError):
        return None


def store(key: str, cap: C.Capture) -> None:
    try:
        d = cache_dir()
        d.mkdir(parents=True, exist_ok=True)
        write_bytes(d / f"{key}.json", json.dumps(_to_json(cap), sort_keys=True).encode())
    except OSError:
        pass  # a read-only cache costs time, not results


def _job(name: str, p: dict, full_ladder: bool) -> C.Capture:
    return C.measure_geometry(name, rebuilt(p), full_ladder)


def measure_all(jobs: list[tuple], workers: int | None = None, full_ladder: bool = True,
                progress=lambda it, total: it) -> dict[str, C.Capture | None]:
    """Capture of every ``(robot, pair name, docked pair)`` in ``jobs``: cached ones read, the
    others measured in ``workers`` processes (default: one per coupling, at most the CPUs) and
    stored. ``{pair name: Capture or None}`` (None: the platform's hand-bolted joint)."""
    out: dict = {}
    todo = []
    for r, name, pair in jobs:
        g = C.geometry(r, name, pair)
        if g is None:
            out[name] = None
            continue
        p = portable(g)
        key = key_of(name, p, full_ladder)
        hit = lookup(key)
        if hit is not None:
            out[name] = hit
        else:
            todo.append((name, p, key))
    n = len(todo)
    workers = min(n, os.cpu_count() or 1) if workers is None else max(1, min(workers, n))
    if n and workers > 1:
        import multiprocessing as mp

        with ProcessPoolExecutor(workers, mp_context=mp.get_context("spawn")) as pool:
            futs = [pool.submit(_job, name, p, full_ladder) for name, p, _ in todo]
            for (name, _p, key), fut in progress(list(zip(todo, futs, strict=True)), n):
                out[name] = fut.result()
                store(key, out[name])
    else:
        for name, p, key in progress(todo, n):
            out[name] = _job(name, p, full_ladder)
            store(key, out[name])
    return {name: out[name] for _r, name, _p in jobs}


def default_jobs() -> list[tuple]:
    """``(robot, pair name, docked pair)`` of every default coupling at the default clearance."""
    from cubot_cad.checks.docking import PAIRS, ROBOT_OF_PAIR, dock
    from cubot_cad.robots.registry import make_robot

    robots: dict = {}
    jobs = []
    for name in PAIRS:
        r = ROBOT_OF_PAIR[name]
        robots.setdefault(r, make_robot(r))
        jobs.append((robots[r], name, dock(name)))
    return jobs


def packaged_keys(jobs: list[tuple] | None = None) -> dict[str, str]:
    """``{pair name: key}`` the packaged file must hold (full ladder, as ``cad dock``)."""
    out = {}
    for r, name, pair in default_jobs() if jobs is None else jobs:
        g = C.geometry(r, name, pair)
        if g is not None:
            out[name] = key_of(name, portable(g), True)
    return out


def write_packaged(workers: int | None = None) -> Path:
    """Measure (or read from the user cache) every default coupling's full capture ladder and
    write :data:`PACKAGED` atomically."""
    jobs = default_jobs()
    caps = measure_all(jobs, workers=workers, full_ladder=True)
    keys = packaged_keys(jobs)
    record = {"schema_version": 1,
              "note": "capture ranges of the default robots' couplings at the default clearance (cad dock's "
                      "full ladder), keyed by cubot_cad.checks.capture_cache.key_of: regenerate with "
                      "`python -m cubot_cad.checks.capture_cache`",
              "captures": {keys[n]: _to_json(c) for n, c in sorted(caps.items()) if c is not None}}
    write_bytes(PACKAGED, (json.dumps(record, indent=1, sort_keys=True) + "\n").encode())
    _packaged.cache_clear()
    return PACKAGED


if __name__ == "__main__":  # pragma: no cover
    print(write_packaged())
