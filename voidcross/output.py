"""Small helpers shared by the sub-commands: JSON/human output, output dirs, progress bars."""

from __future__ import annotations

import json
import sys
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from cubot_cad.jsonrecord import to_jsonable


def emit(args, payload: Any, human: str) -> None:
    """Print ``payload`` as JSON when ``--json`` was given, else ``human``."""
    if getattr(args, "json", False):
        json.dump(to_jsonable(payload), sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
    else:
        print(human)


def out_dir(path: str | Path) -> Path:
    """Create (if needed) and return an output directory."""
    p = Path(path)
    p.mkdir(parents=True, exist_ok=True)
    return p


def progress(iterable: Iterable, desc: str, total: int | None = None, disable: bool | None = None):
    """A tqdm progress bar on stderr (plain iteration when tqdm is missing or output is not a TTY)."""
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a core dependency
        return iterable
    if disable is None:
        disable = not sys.stderr.isatty()
    return tqdm(iterable, desc=desc, total=total, file=sys.stderr, disable=disable,
                dynamic_ncols=True, leave=False)
