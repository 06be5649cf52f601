"""Writing an output file so that nobody ever sees it half-written: the one home of that rule
for every package (``cubot_cad`` is where the dependencies start; this module imports neither
cadquery nor anything else heavy, so ``structure_fem``, ``swarm_sim`` and ``voidcross`` use it).

The data goes to a hidden temporary file beside the target (same directory, so the final
``os.replace`` is an atomic rename on every POSIX file system), which is made world-readable
(``0644``: outputs are for others to read; ``mkstemp`` creates ``0600``) and renamed over the
target only when the writer finished. On any exception, Ctrl-C included, the temporary file
is removed and an existing target is left exactly as it was.

The temporary name keeps the target's suffix, so writers that pick a format from the file
name (matplotlib's ``savefig``, imageio, pyarrow) write the right one.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

#: permissions of every output file
OUTPUT_MODE = 0o644


@contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """``with atomic_path(p) as tmp: write(tmp)``: ``p`` appears, complete, when the block ends."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.stem}.", suffix=p.suffix or ".tmp", dir=p.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, OUTPUT_MODE)
        os.replace(tmp, p)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_via(path: str | os.PathLike, writer: Callable[[str], Any]) -> Path:
    """Let ``writer(tmp_path)`` write the file, then move it into place."""
    with atomic_path(path) as tmp:
        writer(str(tmp))
    return Path(path)


def write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def write_text(path: str | os.PathLike, text: str) -> Path:
    """UTF-8, newlines as given (no translation)."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
        fh.write(text)
    return Path(path)


def write_json(path: str | os.PathLike, data: Any, **dump_kw) -> Path:
    """Indented JSON and a final newline (``dump_kw`` go to :func:`json.dump`)."""
    dump_kw.setdefault("indent", 2)
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(data, fh, **dump_kw)
        fh.write("\n")
    return Path(path)


__all__ = ["OUTPUT_MODE", "atomic_path", "write_bytes", "write_json", "write_text", "write_via"]
