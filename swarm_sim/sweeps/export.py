"""Export a results database to CSV or Parquet, one row per run (times in simulated seconds).

Files are written atomically (temporary file in the same directory, then
``os.replace``): an interrupted export never leaves a truncated file.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

from cubot_cad.atomic import atomic_path

from ..errors import InputError
from .store import TIME_COLUMNS, ResultStore

EXPORT_COLUMNS = (
    "preset", "robots", "void_width", "seed", "status", "success", "retreated", "robots_lost",
    *TIME_COLUMNS.keys(), "seed_robot", "seed_x_cm", "seed_y_cm", "target_finder",
    "limits", "limits_source", "param_hash", "wall_s", "worker", "error_type",
)


def export_rows(store: ResultStore) -> list[dict]:
    out = []
    for r in store.iter_runs():
        row = {c: r.get(c) for c in EXPORT_COLUMNS if c in r}
        for k, col in TIME_COLUMNS.items():
            row[k] = r[col]
        for b in ("success", "retreated"):
            row[b] = None if r[b] is None else bool(r[b])
        out.append({c: row.get(c) for c in EXPORT_COLUMNS})
    return out


def export_db(db: str | os.PathLike, to: str | os.PathLike) -> dict:
    """Write ``to`` (``.csv`` or ``.parquet``); returns ``{"path", "rows", "format"}``."""
    to = Path(to)
    fmt = to.suffix.lower().lstrip(".")
    if fmt not in ("csv", "parquet"):
        raise InputError(f"--to {to}: unknown format {to.suffix!r} (use .csv or .parquet)")
    if fmt == "parquet":
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:
            raise InputError(f"--to {to}: Parquet export needs pyarrow, which is not installed "
                             "(pip install pyarrow, or export to .csv)") from None
    with ResultStore.open_readonly(db) as store:
        rows = export_rows(store)
    with atomic_path(to) as tmp:
        if fmt == "csv":
            with open(tmp, "w", newline="") as fh:
                w = csv.DictWriter(fh, fieldnames=list(EXPORT_COLUMNS))
                w.writeheader()
                for r in rows:
                    w.writerow({k: ("" if v is None else v) for k, v in r.items()})
        else:
            table = pa.Table.from_pylist(rows) if rows else pa.table({c: [] for c in EXPORT_COLUMNS})
            pq.write_table(table, tmp)
    return {"path": str(to), "rows": len(rows), "format": fmt}
