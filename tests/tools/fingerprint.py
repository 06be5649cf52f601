"""Fingerprint a pipeline output folder, so a refactor can be proven to change no output.

    python tests/tools/fingerprint.py OUT > fp.json           # before and after the change
    python tests/tools/fingerprint.py --compare before.json after.json

Two things differ between any two runs of the same code, and are compared for what they mean:
PrusaSlicer's estimates are not deterministic (three slices of one STL gave 98.34, 98.34 and
98.35 g, print times a few seconds apart), so the numbers derived from a slice (print times,
filament and printed masses, and the robot record's masses and inertia made from them) are kept
as values and compared to 0.1 %; and OCC writes a STEP file's colour styles in no fixed order, so
a STEP file is fingerprinted as the multiset of its entities with the references renumbered out.

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


#: Records holding numbers derived from a PrusaSlicer run (module docstring).
SLICED = ("manifest.json", "robot_properties.json")
SLICER_KEYS = re.compile(r"(print_time|filament_g|printed_mass_g|waste_fraction|solid_over_printed_pct|mass_kg|"
                         r"mass_g|inertia_kg_m2|com_m|solid_print_mass_kg)")
REL_TOL = 1e-3


def _step(path: Path) -> str:
    from collections import Counter

    body = path.read_bytes().decode("latin-1").split("DATA;", 1)[-1]
    ents = Counter(re.sub(r"#\d+", "#", " ".join(f"{k}({v}".split()))
                   for k, v in re.findall(r"#\d+\s*=\s*([A-Z_0-9]+)\((.*?)\);", body, flags=re.S))
    return _sha(repr(sorted(ents.items())).encode())


def _leaves(obj, path: str = "") -> dict:
    """``{json path: value}`` of every leaf; values whose path names a slicer-derived quantity
    stay numbers (compared with a tolerance), the others are kept as they are (compared exactly)."""
    if isinstance(obj, dict):
        return {k: v for key, val in obj.items() for k, v in _leaves(val, f"{path}/{key}").items()}
    if isinstance(obj, list):
        return {k: v for i, val in enumerate(obj) for k, v in _leaves(val, f"{path}[{i}]").items()}
    if SLICER_KEYS.search(path) and isinstance(obj, str) and "print_time" in path:
        return {}  # the "10h 17m 16s" text of print_time_s
    return {path: obj}


def compare(a: dict, b: dict) -> list[str]:
    """What differs between two fingerprints (slicer-derived numbers within REL_TOL are equal)."""
    out = []
    for key in sorted(set(a) | set(b)):
        x, y = a.get(key), b.get(key)
        if isinstance(x, dict) and isinstance(y, dict) and key.endswith(SLICED):
            for leaf in sorted(set(x) | set(y)):
                u, v = x.get(leaf), y.get(leaf)
                if u == v:
                    continue
                num = all(isinstance(t, (int, float)) and not isinstance(t, bool) for t in (u, v))
                # a percentage printed to 0.1 may round either way: one step of its rounding
                tol = 0.1 + 1e-9 if leaf.endswith("_pct") else REL_TOL * max(abs(u), abs(v)) if num else 0
                if num and SLICER_KEYS.search(leaf) and abs(u - v) <= tol:
                    continue
                out.append(f"{key}{leaf}: {u!r} != {v!r}")
        elif x != y:
            out.append(f"{key}: {x!r} != {y!r}")
    return out


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
            out[rel] = _step(f)
        elif suffix == ".json" and f.name in SLICED:
            out[rel] = _leaves(json.loads(f.read_text()))
        elif suffix == ".json":
            out[rel] = _sha(VOLATILE_JSON.sub("", f.read_text()).encode())
        elif suffix in (".sqlite", ".db"):
            out[rel] = _db(f)
        else:
            out[rel] = "present"
    return out


if __name__ == "__main__":
    if sys.argv[1:2] == ["--compare"]:
        diffs = compare(*(json.loads(Path(p).read_text()) for p in sys.argv[2:4]))
        print("\n".join(diffs) if diffs else "identical (slicer-derived numbers within 0.1 %)")
        sys.exit(1 if diffs else 0)
    json.dump(fingerprint(Path(sys.argv[1])), sys.stdout, indent=1, sort_keys=True)
    print()
