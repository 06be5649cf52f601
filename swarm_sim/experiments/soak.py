"""Soak testing: many randomised whole runs, every invariant checked every step.

``soak(runs, seed)`` draws, per run, a preset (every shipped one), a set of limits (both the
derived and the thesis's), a swarm size around the rule's minimum, a void width, an arena
(small heights and a void near the left wall put walls near the edge), obstacles (the
preset's, none, or a random few) and a structure (line / auto / switch), then runs the draw
**to its end** (crossed or retreated) with the invariants of :mod:`swarm_sim.invariants`
checked after every step. It counts separately: runs that hit the time-limit guard
(``timeouts``: a bug), invariant violations, robots lost, runs that raised (a bug: valid
input never crashes) and draws rejected as invalid input before running. Every finding
carries its draw, so it can be replayed with ``voidcross sim run``.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from swarm_sim.errors import InputError
from swarm_sim.params import preset_names
from swarm_sim.runner import resolve_params, simulate

CASES = ("case-a", "case-b", "case-c", "case-d")
LIMITS = ("derived", "thesis")
#: share of draws from the large-void presets (their runs are long: a big target side to search)
LARGE_SHARE = 0.03


def _obstacles(rng: np.random.Generator, arena_w: float, arena_h: float, x0: float, x1: float,
               target: tuple[float, float], L: float) -> list:
    """A few small obstacles on either ground, away from the void, the walls and the target."""
    out = []
    for _ in range(int(rng.integers(1, 6))):
        r = float(rng.uniform(3.0, 6.0))
        for _try in range(20):
            x, y = float(rng.uniform(0, arena_w)), float(rng.uniform(0, arena_h))
            if (x + r + L < x0 or x - r - L > x1) and L + r < y < arena_h - L - r and \
                    r + L < x < arena_w - L - r and (x - target[0]) ** 2 + (y - target[1]) ** 2 > (3 * L + r) ** 2:
                out.append([x, y, r])
                break
    return out


def random_faults(rng: np.random.Generator, robots: int) -> str:
    """A random fault spec (issue 16): rates of 1..3 modes (0.5..40 per robot per hour) and,
    every other time, one to three robots failing at a random time in the first 300 s."""
    from swarm_sim.faults import MODES

    parts = [f"{m}:{float(rng.uniform(0.5, 40.0)):.3f}/h"
             for m in rng.choice(list(MODES), size=int(rng.integers(1, 4)), replace=False)]
    if rng.random() < 0.5:
        for r in rng.choice(robots, size=min(robots, int(rng.integers(1, 4))), replace=False):
            parts.append(f"{int(r)}@{float(rng.uniform(0, 300)):.2f}:{rng.choice(list(MODES))}")
    return ",".join(parts)


def draw(rng: np.random.Generator, limits: tuple = LIMITS, faults: bool = False) -> dict:
    """One random scenario (the keyword arguments of :func:`swarm_sim.runner.resolve_params`
    plus ``seed``); ``limits`` the sets to draw from. ``faults``: the pier preset is drawn too
    (one draw in ten) and half the draws get :func:`random_faults` (extra draws from ``rng``
    only then: a fault-free soak draws what it always drew)."""
    if faults:
        if rng.random() < 0.1:
            w = int(rng.integers(4, 9))
            return {"preset": "pier", "robots": int(rng.integers(8, 30)), "void_width": w,
                    "seed": int(rng.integers(0, 2**31 - 1)), "limits": str(rng.choice(list(limits)))}
        d = draw(rng, limits)
        if rng.random() < 0.5:
            d["faults"] = random_faults(rng, d["robots"])
        return d
    large = [n for n in preset_names() if n.startswith("large-void")]
    lim = str(rng.choice(list(limits)))
    if large and rng.random() < LARGE_SHARE:
        preset = str(rng.choice(large))
        w = int(rng.integers(1, 5))
        robots = int(rng.integers(max(1, 3 * w - 2), 3 * w + 13))
        return {"preset": preset, "robots": robots, "void_width": w, "seed": int(rng.integers(0, 2**31 - 1)),
                "limits": lim, "structure": "switch"}
    preset = str(rng.choice(CASES))
    w = int(rng.integers(1, 6))
    L = 12.0
    arena_w = float(rng.integers(250 if preset == "case-a" else 400, 501 if preset == "case-a" else 801))
    arena_h = float(rng.integers(100, 401))
    margin = 2 if preset == "case-a" else 0
    robots = int(rng.integers(1, 3 * w + margin + 5))
    d = {"preset": preset, "robots": robots, "void_width": w, "seed": int(rng.integers(0, 2**31 - 1)),
         "limits": lim, "arena_w_cm": arena_w, "arena_h_cm": arena_h, "target_x_cm": arena_w - 25.0,
         "target_y_cm": float(rng.uniform(0.2, 0.8)) * arena_h,
         "structure": str(rng.choice(["line", "auto", "switch"]))}
    x0 = 0.5 * (arena_w - w * L)
    if rng.random() < 0.25:  # the void near the left wall: walls close to the edge and the dock
        x0 = float(rng.uniform(3 * L, 6 * L))
        d["void_left_x_cm"] = x0
    kind = rng.random()
    if kind < 0.35:
        d["obstacles"] = []
    elif kind < 0.7:
        d["obstacles"] = _obstacles(rng, arena_w, arena_h, x0, x0 + w * L, (d["target_x_cm"], d["target_y_cm"]), L)
    else:  # the preset's own obstacles where they still fit this arena and void
        d["obstacles"] = None
    return d


def _one(d: dict, max_time_s: float | None, engine: str | None = None) -> dict:
    """Run one draw to its end; the findings as a small dict (runs in a worker process)."""
    kw = {k: v for k, v in d.items() if k not in ("preset", "robots", "void_width", "seed", "limits")}
    if kw.get("obstacles") is None:
        kw.pop("obstacles", None)
    try:
        p = resolve_params(d["preset"], d["robots"], d["void_width"], d["limits"], max_time_s, **kw)
    except InputError as exc:
        return {"status": "invalid", "why": str(exc)}
    try:
        _, res = simulate(p, d["seed"], check=True, engine=engine)
    except InputError as exc:  # e.g. the fixed start grid does not fit: refused, not run
        return {"status": "invalid", "why": str(exc)}
    except Exception as exc:  # noqa: BLE001 - a crash on valid input is a finding, not a stop
        return {"status": "error", "error": f"{type(exc).__name__}: {exc}"}
    return {"status": "ok", "end_reason": res.end_reason, "timed_out": res.timed_out, "lost": res.robots_lost,
            "violations": list(res.violations[:3]), "t_s": res.times.get("Tt"), "steps": res.steps,
            "hand_overs": res.hand_overs, "failed": len({f["robot"] for f in res.faults}),
            "in_piers": res.robots_in_piers}


def _star(a):
    i, d, max_time_s, engine = a
    return i, _one(d, max_time_s, engine)


def soak(runs: int, seed: int = 0, max_time_s: float | None = None, limits: str | tuple = LIMITS,
         workers: int = 1, progress=lambda it, total: it, journal: str | Path | None = None,
         engine: str | None = None, faults: bool = False) -> dict:
    """``runs`` random whole runs (module docstring); ``faults``: with robots that fail
    (:func:`draw`). ``limits``: ``"derived"``, ``"thesis"``,
    a path, or a tuple of them to draw from (default both); ``max_time_s``: override the
    presets' time-limit guard (None: keep it); ``workers``: processes. ``journal``: a JSON-lines
    file every finished draw is appended to; run again with the same file (and the same
    runs, seed, limits and guard) to resume: the draws it holds are tallied, not re-run, and
    ``wall_s_total`` adds the wall time of every session. ``engine``: ``compiled`` | ``reference``
    (:func:`swarm_sim.runner.simulate`; the invariants are checked after every step with both)."""
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise InputError(f"--runs must be a positive integer, got {runs!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise InputError(f"--seed must be a non-negative integer, got {seed!r}")
    if max_time_s is not None and not (max_time_s > 0 and max_time_s < float("inf")):
        raise InputError(f"--max-time must be a positive number of seconds, got {max_time_s}")
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(f"--workers must be a positive integer, got {workers!r}")
    from swarm_sim.runner import resolve_engine

    engine = resolve_engine(engine)
    lims = (limits,) if isinstance(limits, str) else tuple(limits)
    from structure_fem.limits import load_limits

    for name in lims:  # bad explicit limits are an input error, not "0 violations"
        load_limits(name)
    rng = np.random.default_rng(seed)
    draws = [draw(rng, lims, faults) for _ in range(runs)]
    t0 = time.perf_counter()
    report: dict = {"runs": runs, "seed": seed, "limits": list(lims), "max_time_s": max_time_s,
                    "whole_runs": True, "timeouts": 0, "n_violations": 0, "robots_lost": 0, "errors": 0,
                    "skipped_invalid": 0, "hand_overs": 0, "end_reasons": {}, "by_preset": {},
                    "violations": [], "timeout_draws": [], "error_draws": [], "simulated_s": 0.0}
    header = {"soak": 1, "runs": runs, "seed": seed, "limits": list(lims), "max_time_s": max_time_s}
    if faults:
        header["faults"] = True
    done, earlier_wall, codes = _read_journal(Path(journal), header) if journal is not None else ({}, 0.0, [])
    outs = dict(done)
    todo = [i for i in range(runs) if i not in done]
    args = [(i, draws[i], max_time_s, engine) for i in todo]
    fh = None
    if journal is not None:
        try:
            fh = open(journal, "a", encoding="utf-8")  # append only: what is written stays written
        except OSError as exc:
            raise InputError(f"--journal {journal}: cannot append ({exc.strerror})") from None
        if not done and Path(journal).stat().st_size == 0:
            _append(fh, header)
        _append(fh, {"session": time.time(), "resumed": len(done), "code": code_version()})
    if workers == 1 or len(todo) <= 1:
        results: Iterable = map(_star, args)
        pool = None
    else:
        import multiprocessing as mp

        pool = mp.get_context("spawn").Pool(workers)
        results = pool.imap_unordered(_star, args, chunksize=2)
    try:
        for i, out in progress(results, len(todo)):
            outs[i] = out
            if fh is not None:
                _append(fh, {"i": i, "out": out, "wall_s": round(time.perf_counter() - t0, 2)})
    finally:
        if pool is not None:
            pool.terminate()
        if fh is not None:
            fh.close()
    report["wall_s"] = round(time.perf_counter() - t0, 2)
    report["wall_s_total"] = round(earlier_wall + report["wall_s"], 2)
    report["resumed_runs"] = len(done)
    # a resumed soak may span code changes: say which code ran its draws (one figure, one code)
    report["code_versions"] = sorted(set(codes) | {code_version()})
    for i in sorted(outs):  # in draw order, whatever order the workers finished in
        _tally(report, draws[i], outs[i])
    report["simulated_s"] = round(report["simulated_s"], 2)
    return report


def _append(fh, rec: dict) -> None:
    fh.write(json.dumps(rec, sort_keys=True) + "\n")
    fh.flush()


def _header_bytes(header: dict) -> bytes:
    """The journal's first line as _append writes it (without its newline)."""
    return json.dumps(header, sort_keys=True).encode("utf-8")


def _read_journal(path: Path, header: dict) -> tuple[dict[int, dict], float, list[str]]:
    """The finished draws of an earlier session (index -> outcome) and its wall time; an
    absent or empty file is a fresh start. A journal of another soak is refused. A torn last
    line (the process was killed mid-write, even inside a UTF-8 character) is cut, so the
    soak resumes from the last whole record; a whole last line without its newline gets one; a
    torn header alone (a prefix of this soak's header) is a fresh start. Any other bad line is one error naming its number."""
    if path.is_dir():
        raise InputError(f"--journal {path} is a directory")
    if not path.exists() or path.stat().st_size == 0:
        return {}, 0.0, []
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"--journal {path}: cannot read ({exc.strerror})") from None
    ends_whole = data.endswith(b"\n")
    lines = data.split(b"\n")
    if ends_whole:
        lines.pop()
    recs: list = []
    keep = len(data)  # bytes of the file that hold whole records
    for n, raw in enumerate(lines, 1):
        last_torn = n == len(lines) and not ends_whole
        try:
            rec = json.loads(raw.decode("utf-8"))
            if not isinstance(rec, dict):
                raise ValueError("not a record")
        except (UnicodeDecodeError, ValueError):
            # a torn header must be the start of the header this soak writes, a torn record the
            # start of one ({"); anything else is not ours to cut (a user's file is never truncated)
            ours = (_header_bytes(header).startswith(raw) if n == 1 else raw[:2] == b'{"'[:len(raw)])
            if last_torn and ours:
                keep = len(data) - len(raw)
                break
            if n == 1:
                raise InputError(f"--journal {path} is not a soak journal (its first line is not JSON)") from None
            raise InputError(f"--journal {path}: line {n} is not JSON (corrupt journal; "
                             f"lines 1-{n - 1} are whole)") from None
        recs.append(rec)
    if not recs:  # only a torn header: nothing was run
        os.truncate(path, 0)
        return {}, 0.0, []
    if recs[0].get("soak") != 1:
        raise InputError(f"--journal {path} is not a soak journal (no header line)")
    if recs[0] != header:
        diff = {k: recs[0].get(k) for k in header if recs[0].get(k) != header[k]}
        raise InputError(f"--journal {path} is another soak's ({diff}); use a new file or the same options")
    if keep < len(data):  # a journal of this soak: cut the torn record so the next append starts its own line
        os.truncate(path, keep)
    elif not ends_whole:  # the last record is whole but its newline was not written
        with open(path, "ab") as fh:
            fh.write(b"\n")
    done: dict[int, dict] = {}
    wall, session_wall = 0.0, 0.0
    codes: list[str] = []
    for r in recs[1:]:
        if "session" in r:
            wall, session_wall = wall + session_wall, 0.0
            codes.append(str(r.get("code", "unknown")))
        elif isinstance(r.get("i"), int) and 0 <= r["i"] < header["runs"] and isinstance(r.get("out"), dict):
            w = r.get("wall_s", 0.0)
            if isinstance(w, bool) or not isinstance(w, (int, float)):
                raise InputError(f"--journal {path}: draw {r['i']} has no wall time (wall_s {w!r})")
            done[r["i"]] = r["out"]
            session_wall = max(session_wall, float(w))
        else:
            raise InputError(f"--journal {path}: a record is not a finished draw: {str(r)[:80]}")
    return done, wall + session_wall, codes


def code_version() -> str:
    """The git commit of the simulator's source tree (``+dirty`` with local changes), else
    the package version: what a soak journal records per session."""
    import subprocess

    root = Path(__file__).resolve().parents[2]
    try:
        rev = subprocess.run(["git", "-C", str(root), "rev-parse", "--short=12", "HEAD"], capture_output=True,
                             text=True, timeout=5)
        if rev.returncode == 0:
            dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--", "swarm_sim"],
                                   capture_output=True, text=True, timeout=5).stdout.strip()
            return rev.stdout.strip() + ("+dirty" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        pass
    from importlib.metadata import PackageNotFoundError, version

    try:
        return "voidcross " + version("voidcross")
    except PackageNotFoundError:
        return "unknown"


def _tally(report: dict, d: dict, out: dict) -> None:
    if out["status"] == "invalid":
        report["skipped_invalid"] += 1
        return
    bp = report["by_preset"].setdefault(d["preset"], {"runs": 0, "crossed": 0, "retreated": 0, "timeouts": 0})
    bp["runs"] += 1
    if out["status"] == "error":
        report["errors"] += 1
        report["error_draws"].append({**d, "error": out["error"]})
        return
    reason = out["end_reason"] or "running"
    report["end_reasons"][reason] = report["end_reasons"].get(reason, 0) + 1
    if reason == "crossed":
        bp["crossed"] += 1
    elif reason.startswith("retreated"):
        bp["retreated"] += 1
    if out["timed_out"]:
        report["timeouts"] += 1
        bp["timeouts"] += 1
        report["timeout_draws"].append(d)
    report["robots_lost"] += out["lost"]
    report["hand_overs"] += out["hand_overs"]
    report["robots_failed"] = report.get("robots_failed", 0) + out.get("failed", 0)
    report["robots_in_piers"] = report.get("robots_in_piers", 0) + out.get("in_piers", 0)
    report["simulated_s"] += out["t_s"] or 0.0
    for v in out["violations"]:
        report["n_violations"] += 1
        report["violations"].append({**d, "violation": v})
