"""Static solves cached by a hash of their inputs and of the model's code.

A ``fem table`` is a few thousand static solves (thresholds, launch steps, tapering arches,
ranges, the calibrated alternative; 0.05-2 s each). Every one is a pure function of the
configuration, the robot record, the connector set, the bodies and the solver options, and of
the code that builds and solves the model. :func:`cached_solve` keys each solve by the sha256
of the ``repr`` of those inputs (dataclasses: every field, floats exactly) and of the source of
every ``structure_fem`` module and ``cubot_cad/properties.py`` (:func:`code_hash`: any edit to
the model invalidates every entry), and keeps the result, or the solver's failure message, in
one SQLite file, ``$XDG_CACHE_HOME/voidcross/solves.sqlite`` (zlib-compressed pickles,
~17 kB for the 8 x 4 arch). A repeated table with the same inputs then costs what reading them
costs (`voidcross fem bench` reports the table both ways).

``VOIDCROSS_SOLVE_CACHE=0`` turns it off (benchmarks of the solver itself; the cold figure).
The cache is the user's own (pickles are only read from there); an unreadable or corrupt file
is ignored (solved again, never trusted), and a read-only location just means no caching. The
file is pruned to its newest :data:`MAX_ENTRIES` entries. Processes sharing the file claim a key
while they solve it (:func:`_claim`): a second process asking for the same configuration waits
and reads the first one's result instead of solving it again.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import pickle
import sqlite3
import time
import zlib
from pathlib import Path

#: Entries kept (oldest pruned beyond it): ~17 kB each at most, about 1 GB for the largest arches.
MAX_ENTRIES = 50_000

_CODE_HASH: str | None = None
_CONN: sqlite3.Connection | None = None
_CONN_PATH: Path | None = None
_CONN_PID: int | None = None
_FAILED = object()
_PUTS = 0
_LOCK_FD: int | None = None
_LOCK_PATH: Path | None = None


def enabled() -> bool:
    return os.environ.get("VOIDCROSS_SOLVE_CACHE", "1") not in ("0", "false", "no", "off")


def writable() -> bool:
    """Whether this process can keep solves in the cache (on, and its file opens)."""
    return enabled() and _db() is not None


def cache_path() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "voidcross" / "solves.sqlite"


def code_hash() -> str:
    """sha256 of the source of every structure_fem module (sub-packages too) and of cubot_cad/properties.py."""
    global _CODE_HASH
    if _CODE_HASH is None:
        here = Path(__file__).parent
        files = sorted(here.rglob("*.py")) + [here.parent / "cubot_cad" / "properties.py"]
        h = hashlib.sha256()
        for f in files:
            h.update(f.relative_to(here.parent).as_posix().encode())
            h.update(f.read_bytes())
        _CODE_HASH = h.hexdigest()
    return _CODE_HASH


def key_of(*inputs) -> str:
    return hashlib.sha256((code_hash() + repr(inputs)).encode()).hexdigest()


def _db() -> sqlite3.Connection | None:
    """This process's connection (a forked worker opens its own: SQLite connections must not
    cross a fork)."""
    global _CONN, _CONN_PATH, _CONN_PID
    p = cache_path()
    if _CONN is not None and _CONN_PATH == p and _CONN_PID == os.getpid():
        return _CONN
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        c = sqlite3.connect(p, timeout=10)
        c.execute("PRAGMA journal_mode=WAL")
        c.execute("PRAGMA synchronous=OFF")  # a cache: a lost write is a solve again
        c.execute("CREATE TABLE IF NOT EXISTS solves (key TEXT PRIMARY KEY, ok INTEGER, value BLOB, t REAL)")
    except (OSError, sqlite3.Error):
        return None
    _CONN, _CONN_PATH, _CONN_PID = c, p, os.getpid()
    return c


def _get(key: str):
    c = _db()
    if c is None:
        return None
    try:
        row = c.execute("SELECT ok, value FROM solves WHERE key = ?", (key,)).fetchone()
        if row is None:
            return None
        ok, blob = row
        if not ok:
            return (_FAILED, blob.decode())
        return (True, pickle.loads(zlib.decompress(blob)))
    except Exception:  # noqa: BLE001 - corrupt entry or file: solve again
        return None


def _put(key: str, ok: bool, value) -> None:
    global _PUTS
    c = _db()
    if c is None:
        return
    try:
        blob = zlib.compress(pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL)) if ok else value.encode()
        c.execute("INSERT OR REPLACE INTO solves VALUES (?, ?, ?, ?)", (key, int(ok), blob, time.time()))
        c.commit()
        _PUTS += 1
        if _PUTS % 500 == 1:  # prune now and then, not on every write
            n = c.execute("SELECT COUNT(*) FROM solves").fetchone()[0]
            if n > MAX_ENTRIES:
                c.execute("DELETE FROM solves WHERE key IN (SELECT key FROM solves ORDER BY t LIMIT ?)",
                          (n - MAX_ENTRIES,))
                c.commit()
    except Exception:  # noqa: BLE001 - read-only or corrupt: no caching
        pass


def cached_solve(solver, failure_type, config, robot, conn, flexible, options):
    """``solver(config, robot, conn, flexible, options)`` through the cache (module docstring);
    a cached failure is raised again as ``failure_type(message)``."""
    if not enabled():
        return solver(config, robot, conn, flexible, options)
    key = key_of(config, robot, conn, bool(flexible), options)
    hit = _get(key)
    if hit is not None:
        ok, v = hit
        if ok is _FAILED:
            raise failure_type(v)
        return v
    with _claim(key):  # another process solving the same key: wait for it, then read its result
        hit = _get(key)
        if hit is not None:
            ok, v = hit
            if ok is _FAILED:
                raise failure_type(v)
            return v
        try:
            res = solver(config, robot, conn, flexible, options)
        except failure_type as exc:
            _put(key, False, str(exc))
            raise
        _put(key, True, res)
    return res


#: Lock slots in ``solves.lock`` (one byte each; two keys on one slot only wait for each other).
LOCK_SLOTS = 4093


@contextlib.contextmanager
def _claim(key: str):
    """Hold the key's byte of ``solves.lock`` (a POSIX record lock, released if the process dies)
    while it is solved, so processes sharing the cache (``fem table`` twice, xdist workers) solve
    a configuration once between them. No lock file (read-only location): no waiting."""
    try:
        import fcntl

        if _LOCK_FD is None or _LOCK_PATH != cache_path():
            _open_lock()
        slot = int(key[:12], 16) % LOCK_SLOTS
        fcntl.lockf(_LOCK_FD, fcntl.LOCK_EX, 1, slot)
    except (OSError, ImportError, TypeError):
        yield
        return
    try:
        yield
    finally:
        try:
            fcntl.lockf(_LOCK_FD, fcntl.LOCK_UN, 1, slot)
        except OSError:
            pass


def _open_lock() -> None:
    global _LOCK_FD, _LOCK_PATH
    p = cache_path()
    p.parent.mkdir(parents=True, exist_ok=True)
    _LOCK_FD = os.open(p.with_suffix(".lock"), os.O_RDWR | os.O_CREAT, 0o644)
    _LOCK_PATH = p
