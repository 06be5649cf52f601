"""Fingerprint a pipeline output folder, so a refactor can be proven to change no output.

    python tests/tools/fingerprint.py OUT > fp.json      # before and after, then diff

Hashes every robot_properties.json, limits.json, STL and 3MF file and every JSON record under
OUT, and the rows of every SQLite results database with the columns that record the clock
(wall times, timestamps, host names) left out: those differ between any two runs. STEP files
are hashed without their FILE_NAME header line, which carries the time of writing; GLB files
and HTML reports are listed but not hashed (they embed the time and the run's folder).
"""
from __future__ import annotations

import hashlib
import json
import re
import sqlite3
import sys
from pathlib import Path

CLOCK = re.compile(r"(wall|time_s$|_at$|stamp|host|elapsed|started|finished|created|duration|pid|cpu)", re.I)
VOLATILE_JSON = re.compile(r'"(wall_s|elapsed_s|created|started|finished|written_at|host|duration_s|seconds|cpu_s|path|out|dir)": [^,}\n]*')


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()[:16]


def _db(path: Path) -> dict:
    con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    out = {}
    for (table,) in con.execute("select name from sqlite_master where type='table' order by name"):
        cols = [r[1] for r in con.execute(f"pragma table_info('{table}')")]
        keep = [c for c in cols if not CLOCK.search(c)]
        if not keep:
            continue
        rows = con.execute(f"select {', '.join(map(repr, keep))} from '{table}' order by 1, 2" if len(keep) > 1
                           else f"select {keep[0]!r} from '{table}' order by 1").fetchall()
        out[table] = {"columns": keep, "rows": len(rows), "sha": _sha(repr(rows).encode())}
    con.close()
    return out


def fingerprint(root: Path) -> dict:
    out: dict = {}
    for f in sorted(p for p in root.rglob("*") if p.is_file()):
        rel = str(f.relative_to(root))
        suffix = f.suffix.lower()
        if ".partial" in rel:
            continue
        if suffix in (".stl", ".3mf", ".csv"):
            out[rel] = _sha(f.read_bytes())
        elif suffix in (".step", ".stp"):
            text = f.read_bytes().decode("latin-1")
            out[rel] = _sha(re.sub(r"FILE_NAME\([^;]*;", "", text).encode("latin-1"))
        elif suffix == ".json":
            out[rel] = _sha(VOLATILE_JSON.sub("", f.read_text()).encode())
        elif suffix in (".sqlite", ".db"):
            out[rel] = _db(f)
        else:
            out[rel] = "present"
    return out


if __name__ == "__main__":
    json.dump(fingerprint(Path(sys.argv[1])), sys.stdout, indent=1, sort_keys=True)
    print()
