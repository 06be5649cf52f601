"""SQLite results store for Monte-Carlo sweeps (standard library ``sqlite3``, WAL).

One row per run, keyed by ``(preset, param_hash, seed)``; every run is
inserted in its own transaction the moment it completes, so a sweep killed
at any instant (Ctrl-C, ``kill -9``, power loss with ``synchronous=FULL``)
leaves only whole rows behind and ``--resume`` finds exactly what is missing.

Opening an existing file first validates it read-only (``mode=ro``): a
corrupt file, a database of another application or another schema version
raises :class:`swarm_sim.errors.InputError` and the file is not written to.

Times are simulated seconds; positions centimetres.
"""

from __future__ import annotations

import json
import os
import socket
import sqlite3
import time
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError

SCHEMA_VERSION = 1
TIME_KEYS = ("Ts", "Ta", "To", "Td", "Tb", "Tt")
#: Column name in the ``runs`` table for each time key (``TO`` is an SQL keyword).
TIME_COLUMNS = {k: "t_" + k[1].lower() for k in TIME_KEYS}

_SCHEMA = f"""
CREATE TABLE schema_version (version INTEGER NOT NULL);
CREATE TABLE sweeps (
    sweep_id      TEXT PRIMARY KEY,
    created_utc   TEXT NOT NULL,
    spec_json     TEXT NOT NULL,
    limits_digest TEXT NOT NULL,
    runs_planned  INTEGER NOT NULL
);
CREATE TABLE runs (
    preset        TEXT NOT NULL,
    param_hash    TEXT NOT NULL,
    seed          INTEGER NOT NULL,
    robots        INTEGER NOT NULL,
    void_width    INTEGER NOT NULL,
    limits        TEXT NOT NULL,
    limits_digest TEXT NOT NULL,
    params_json   TEXT NOT NULL,
    status        TEXT NOT NULL CHECK (status IN ('ok', 'error')),
    success       INTEGER,
    retreated     INTEGER,
    robots_lost   INTEGER,
    {", ".join(f"{c} REAL" for c in TIME_COLUMNS.values())},
    seed_robot    INTEGER,
    seed_x_cm     REAL,
    seed_y_cm     REAL,
    target_finder INTEGER,
    limits_source TEXT,
    result_json   TEXT,
    error_type    TEXT,
    error         TEXT,
    wall_s        REAL,
    worker        TEXT,
    finished_utc  TEXT NOT NULL,
    PRIMARY KEY (preset, param_hash, seed)
);
CREATE INDEX runs_point ON runs (preset, robots, void_width);
"""

RUN_COLUMNS = (
    "preset", "param_hash", "seed", "robots", "void_width", "limits", "limits_digest", "params_json",
    "status", "success", "retreated", "robots_lost", *TIME_COLUMNS.values(), "seed_robot",
    "seed_x_cm", "seed_y_cm", "target_finder", "limits_source", "result_json", "error_type", "error",
    "wall_s", "worker", "finished_utc",
)


def utc_now() -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())


def worker_id() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


def _fmt_err(path: Path, exc: BaseException) -> str:
    return f"--db {path}: not a readable voidcross results database ({exc})"


def check_db(path: str | os.PathLike) -> str:
    """Validate ``path`` read-only without writing to it.

    Returns ``"missing"`` (no file), ``"empty"`` (a file SQLite sees as an
    empty database) or ``"ok"`` (our schema, our version); raises InputError
    for anything else.
    """
    p = Path(path)
    if not p.exists():
        return "missing"
    if p.is_dir():
        raise InputError(f"--db {p}: is a directory, expected a database file")
    if p.stat().st_size == 0:
        return "empty"
    try:
        con = sqlite3.connect(f"{p.resolve().as_uri()}?mode=ro", uri=True, timeout=30)
    except sqlite3.Error as exc:
        raise InputError(_fmt_err(p, exc)) from None
    try:
        names = {r[0] for r in con.execute("SELECT name FROM sqlite_master WHERE type='table'")}
        if not names:
            return "empty"
        if "schema_version" not in names:
            raise InputError(f"--db {p}: not a voidcross results database (no schema_version table; "
                             f"tables: {', '.join(sorted(names))})")
        rows = con.execute("SELECT version FROM schema_version").fetchall()
        if len(rows) != 1:
            raise InputError(f"--db {p}: schema_version table holds {len(rows)} rows, expected 1")
        version = rows[0][0]
        if version != SCHEMA_VERSION:
            raise InputError(f"--db {p}: results schema version {version!r}, this voidcross reads "
                             f"version {SCHEMA_VERSION} (use a new --db, or the voidcross that wrote it)")
        missing = {"sweeps", "runs"} - names
        if missing:
            raise InputError(f"--db {p}: schema version {version} but tables {sorted(missing)} are missing")
        cols = {r[1] for r in con.execute("PRAGMA table_info(runs)")}
        if not set(RUN_COLUMNS) <= cols:
            raise InputError(f"--db {p}: runs table lacks columns {sorted(set(RUN_COLUMNS) - cols)}")
        ok = con.execute("PRAGMA quick_check").fetchone()[0]
        if ok != "ok":
            raise InputError(f"--db {p}: database is damaged (quick_check: {ok})")
        return "ok"
    except sqlite3.Error as exc:
        raise InputError(_fmt_err(p, exc)) from None
    finally:
        con.close()


@dataclass(frozen=True)
class SweepRecord:
    sweep_id: str
    created_utc: str
    spec: dict
    limits_digest: str
    runs_planned: int


class ResultStore:
    """The results database. Use :meth:`open` (validates first) or :meth:`open_readonly`."""

    def __init__(self, path: Path, con: sqlite3.Connection, readonly: bool):
        self.path, self.con, self.readonly = path, con, readonly

    # ------------------------------------------------------------------ opening
    @classmethod
    def open(cls, path: str | os.PathLike, create: bool = True) -> ResultStore:
        p = Path(path)
        state = check_db(p)
        if state == "missing" and not create:
            raise InputError(f"--db {p}: no such results database")
        if state == "missing":
            p.parent.mkdir(parents=True, exist_ok=True)
        try:
            con = sqlite3.connect(p, timeout=60, isolation_level=None)
            con.execute("PRAGMA busy_timeout = 60000")
            con.execute("PRAGMA journal_mode = WAL")
            con.execute("PRAGMA synchronous = FULL")
            if state in ("missing", "empty"):
                con.execute("BEGIN IMMEDIATE")
                # a concurrent creator may have won the race
                if not con.execute("SELECT 1 FROM sqlite_master WHERE name='schema_version'").fetchone():
                    for stmt in _SCHEMA.split(";"):
                        if stmt.strip():
                            con.execute(stmt)
                    con.execute("INSERT INTO schema_version (version) VALUES (?)", (SCHEMA_VERSION,))
                con.execute("COMMIT")
        except sqlite3.Error as exc:
            raise InputError(_fmt_err(p, exc)) from None
        return cls(p, con, readonly=False)

    @classmethod
    def open_readonly(cls, path: str | os.PathLike) -> ResultStore:
        p = Path(path)
        state = check_db(p)
        if state == "missing":
            raise InputError(f"--db {p}: no such results database")
        if state == "empty":
            raise InputError(f"--db {p}: empty database (no sweep has written to it)")
        con = sqlite3.connect(f"{p.resolve().as_uri()}?mode=ro", uri=True, timeout=60)
        return cls(p, con, readonly=True)

    def close(self) -> None:
        self.con.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ------------------------------------------------------------------ sweeps
    def get_sweep(self, sweep_id: str) -> SweepRecord | None:
        row = self.con.execute(
            "SELECT sweep_id, created_utc, spec_json, limits_digest, runs_planned FROM sweeps WHERE sweep_id=?",
            (sweep_id,)).fetchone()
        if row is None:
            return None
        return SweepRecord(row[0], row[1], json.loads(row[2]), row[3], row[4])

    def sweeps(self) -> list[SweepRecord]:
        rows = self.con.execute(
            "SELECT sweep_id, created_utc, spec_json, limits_digest, runs_planned FROM sweeps ORDER BY created_utc")
        return [SweepRecord(r[0], r[1], json.loads(r[2]), r[3], r[4]) for r in rows]

    @contextmanager
    def _immediate(self):
        """One write transaction (``BEGIN IMMEDIATE`` ... ``COMMIT``), rolled back on any exception
        while it is open. An interrupt (Ctrl-C) that lands just after the COMMIT leaves nothing to
        roll back: the interrupt itself propagates, never a "no transaction is active" error in
        its place (the row is stored, and the sweep reports the interruption)."""
        self.con.execute("BEGIN IMMEDIATE")
        try:
            yield
            self.con.execute("COMMIT")
        except BaseException:
            if self.con.in_transaction:
                self.con.execute("ROLLBACK")
            raise

    def add_sweep(self, sweep_id: str, spec: dict, limits_digest: str, runs_planned: int) -> None:
        with self._immediate():
            self.con.execute(
                "INSERT OR IGNORE INTO sweeps (sweep_id, created_utc, spec_json, limits_digest, runs_planned) "
                "VALUES (?, ?, ?, ?, ?)",
                (sweep_id, utc_now(), json.dumps(spec, sort_keys=True), limits_digest, runs_planned))

    # ------------------------------------------------------------------ runs
    def existing_keys(self, preset: str | None = None) -> dict[tuple[str, str, int], str]:
        """``{(preset, param_hash, seed): status}`` of every stored run."""
        q = "SELECT preset, param_hash, seed, status FROM runs"
        rows = self.con.execute(q + (" WHERE preset=?" if preset else ""), (preset,) if preset else ())
        return {(r[0], r[1], r[2]): r[3] for r in rows}

    def delete_errors(self, keys: Iterable[tuple[str, str, int]]) -> int:
        keys = list(keys)
        n = 0
        with self._immediate():
            for k in keys:
                n += self.con.execute(
                    "DELETE FROM runs WHERE preset=? AND param_hash=? AND seed=? AND status='error'", k).rowcount
        return n

    def insert_run(self, row: dict) -> bool:
        """Insert one run in its own transaction; False if that key was already stored."""
        values = [row.get(c) for c in RUN_COLUMNS]
        sql = (f"INSERT INTO runs ({', '.join(RUN_COLUMNS)}) VALUES ({', '.join('?' * len(RUN_COLUMNS))}) "
               "ON CONFLICT (preset, param_hash, seed) DO NOTHING")
        with self._immediate():
            cur = self.con.execute(sql, values)
        return cur.rowcount == 1

    def iter_runs(self, where: str = "", params: tuple = ()) -> Iterator[dict]:
        cur = self.con.execute(f"SELECT {', '.join(RUN_COLUMNS)} FROM runs {where} "
                               "ORDER BY preset, robots, void_width, seed, param_hash", params)
        for r in cur:
            yield dict(zip(RUN_COLUMNS, r, strict=True))

    def count(self) -> dict[str, int]:
        rows = self.con.execute("SELECT status, COUNT(*) FROM runs GROUP BY status").fetchall()
        out = {"ok": 0, "error": 0}
        out.update({r[0]: r[1] for r in rows})
        return out


def run_row(key: dict, outcome: dict) -> dict:
    """Flatten a run key and its outcome (from :func:`swarm_sim.sweeps.executors.execute_run`) into a row."""
    row = {
        "preset": key["preset"], "param_hash": key["param_hash"], "seed": int(key["seed"]),
        "robots": int(key["robots"]), "void_width": int(key["void_width"]), "limits": key["limits"],
        "limits_digest": key["limits_digest"], "params_json": json.dumps(key["params"], sort_keys=True),
        "wall_s": outcome.get("wall_s"), "worker": outcome.get("worker"), "finished_utc": utc_now(),
    }
    if outcome["status"] != "ok":
        row.update(status="error", error_type=outcome.get("error_type"), error=outcome.get("error"))
        return row
    res = outcome["result"]
    times = res.get("times") or {}
    pos = res.get("seed_position")
    row.update(
        status="ok", success=_b(res.get("success")), retreated=_b(res.get("retreated")),
        robots_lost=res.get("robots_lost"), seed_robot=res.get("seed_robot"),
        seed_x_cm=pos[0] if pos else None, seed_y_cm=pos[1] if pos else None,
        target_finder=res.get("target_finder"), limits_source=res.get("limits_source"),
        result_json=json.dumps(res, sort_keys=True, default=_json_default),
    )
    for k, col in TIME_COLUMNS.items():
        v = times.get(k)
        row[col] = None if v is None else float(v)
    return row


def _b(v) -> int | None:
    return None if v is None else int(bool(v))


def _json_default(o):
    try:
        import numpy as np

        if isinstance(o, np.generic):
            return o.item()
        if isinstance(o, np.ndarray):
            return o.tolist()
    except ImportError:  # pragma: no cover
        pass
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")
