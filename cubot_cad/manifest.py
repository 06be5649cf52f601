"""The export manifest (manifest.json): its schema version and its reader."""

from __future__ import annotations

import os
from pathlib import Path

from .errors import InputError
from .jsonrecord import read_json

MANIFEST_SCHEMA = 1


def load_manifest(path: str | os.PathLike) -> dict:
    """Read a manifest (file or directory holding ``manifest.json``)."""
    p = Path(path)
    if p.is_dir():
        p = p / "manifest.json"
    data = read_json(p)
    if not isinstance(data, dict) or data.get("schema_version") != MANIFEST_SCHEMA or "parts" not in data:
        raise InputError(f"{p} is not a cubot_cad manifest (schema_version {MANIFEST_SCHEMA})")
    return data
