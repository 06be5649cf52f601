"""Small helpers shared by the sub-commands: JSON/human output, output dirs, progress bars."""

from __future__ import annotations

import json
import os
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


def out_dir(path: str | Path, what: str = "--out", create: bool = True) -> Path:
    """Create (if needed) and return an output directory; a path that cannot be one (a file, a
    path under a file, no permission) is an input error naming ``what`` and the path, raised
    before any work is done. ``create=False`` only checks (nothing is written)."""
    from cubot_cad.errors import InputError

    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputError(f"{what} {p}: is a file, not a directory")
    if not create:
        anc = p
        while not anc.exists() and anc != anc.parent:
            anc = anc.parent
        if not anc.is_dir():
            raise InputError(f"{what} {p}: {anc} is a file, not a directory")
        if not os.access(anc, os.W_OK | os.X_OK):
            raise InputError(f"{what} {p}: {anc} is not writable")
        return p
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{what} {p}: cannot create the directory ({exc.strerror or exc})") from None
    if not os.access(p, os.W_OK | os.X_OK):
        raise InputError(f"{what} {p}: the directory is not writable")
    return p


def out_file(path: str | Path, what: str) -> Path:
    """Check that an output file can be written (its directory is created); returns the path."""
    from cubot_cad.errors import InputError

    p = Path(path)
    if p.is_dir():
        raise InputError(f"{what} {p}: is a directory, not a file")
    out_dir(p.parent, what, create=False)
    return p


#: seconds between the plain progress lines written when stderr is not a terminal
PLAIN_EVERY_S = 30.0


def progress(iterable: Iterable, desc: str, total: int | None = None, disable: bool | None = None):
    """A tqdm progress bar on stderr; when stderr is not a terminal (a log file, CI), a plain
    line ``desc: i/total (elapsed, eta)`` every :data:`PLAIN_EVERY_S` seconds instead."""
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a core dependency
        return iterable
    if disable:
        return iterable
    if disable is None and not sys.stderr.isatty():
        return _plain(iterable, desc, total)
    return tqdm(iterable, desc=desc, total=total, file=sys.stderr, dynamic_ncols=True, leave=False)


def _plain(iterable: Iterable, desc: str, total: int | None):
    import time

    t0 = last = time.monotonic()
    i = 0
    for i, item in enumerate(iterable, 1):
        yield item
        now = time.monotonic()
        if now - last >= PLAIN_EVERY_S:
            last = now
            eta = f", ~{(now - t0) / i * (total - i):.0f} s left" if total else ""
            print(f"{desc}: {i}/{total if total else '?'} ({now - t0:.0f} s{eta})", file=sys.stderr, flush=True)
    if i and time.monotonic() - t0 >= PLAIN_EVERY_S:
        print(f"{desc}: {i}/{total if total else '?'} done ({time.monotonic() - t0:.0f} s)", file=sys.stderr,
              flush=True)


def parse_set(items: list[str] | None, option: str = "--set") -> dict:
    """``KEY=VALUE`` overrides, one parser for every command: VALUE is read as a TOML value
    (``800``, ``1.5``, ``true``, ``"text"``, ``[[30, 33, 5]]``), else as JSON, else kept as text."""
    import tomllib

    from cubot_cad.errors import InputError

    out: dict = {}
    for item in items or []:
        k, sep, v = item.partition("=")
        if not sep or not k.strip():
            raise InputError(f"{option} {item!r}: expected KEY=VALUE")
        v = v.strip()
        try:
            out[k.strip()] = tomllib.loads(f"v = {v}")["v"]
            continue
        except tomllib.TOMLDecodeError:
            pass
        try:
            out[k.strip()] = json.loads(v)
        except json.JSONDecodeError:
            out[k.strip()] = v
    return out


#: bounds "in user terms" shared by the commands (a typo like ``--runs 1000000000000`` is refused
#: at once, naming the limit, instead of queueing years of work or overflowing a seed)
MAX_RUNS = 1_000_000
MAX_WORKERS = 256
SEED_LIMIT = 2**63  # seeds are non-negative and < 2**63 (numpy's SeedSequence and SQLite's INTEGER)
MAX_SIM_TIME_S = 1_000_000.0  # simulated seconds of one run (the presets' guards are <= 50,000 s)
MAX_ROBOTS = 100_000


def check_int(value: int | None, option: str, lo: int | None = None, hi: int | None = None,
              what: str = "") -> int | None:
    """``value`` must be an integer in ``lo..hi`` (None: no bound, and None passes); else an
    InputError naming the option, the value and the limit."""
    from cubot_cad.errors import InputError

    if value is None:
        return None
    what = f" ({what})" if what else ""
    if lo is not None and value < lo:
        raise InputError(f"{option} {value}: must be >= {lo}{what}")
    if hi is not None and value > hi:
        raise InputError(f"{option} {value}: must be <= {hi:,}{what}")
    return value


def check_seed(seed: int | None, option: str = "--seed", count: int = 1) -> int | None:
    """A first seed: >= 0 and, with ``count`` consecutive seeds, the last below 2**63."""
    from cubot_cad.errors import InputError

    if seed is None:
        return None
    if seed < 0:
        raise InputError(f"{option} {seed}: must be a non-negative integer")
    if seed + max(count, 1) - 1 >= SEED_LIMIT:
        more = f" (with {count:,} consecutive seeds, the last must be)" if count > 1 else ""
        raise InputError(f"{option} {seed}: must be < 2**63{more}")
    return seed


def check_float(value: float | None, option: str, lo: float | None = None, hi: float | None = None,
                lo_open: bool = True, what: str = "") -> float | None:
    """``value`` must be a finite number in (lo, hi] (``lo_open=False``: [lo, hi]); None passes."""
    import math

    from cubot_cad.errors import InputError

    if value is None:
        return None
    what = f" ({what})" if what else ""
    if not math.isfinite(value):
        raise InputError(f"{option} {value}: must be a finite number{what}")
    if lo is not None and (value <= lo if lo_open else value < lo):
        raise InputError(f"{option} {value:g}: must be {'>' if lo_open else '>='} {lo:g}{what}")
    if hi is not None and value > hi:
        raise InputError(f"{option} {value:g}: must be <= {hi:,g}{what}")
    return value


def refuse_empty_values(argv: list[str]) -> None:
    """Every option value and argument on the command line is non-blank: ``--stages ''``,
    ``--cases ' '``, ``--faults=`` are :class:`InputError` naming the option (an empty value is
    never a way to ask for the default: leave the option out). One rule for every command,
    checked before any command runs."""
    from cubot_cad.errors import InputError

    for i, tok in enumerate(argv):
        if tok.startswith("--") and "=" in tok:
            opt, _, val = tok.partition("=")
            if not val.strip():
                raise InputError(f"{opt} {val!r} is empty: give a value or leave {opt} out for its default")
        elif not tok.strip():
            prev = argv[i - 1] if i and argv[i - 1].startswith("-") else None
            what = prev or f"argument {i + 1}"
            raise InputError(f"{what} {tok!r} is empty: give a value or leave {prev or 'it'} out for its default")


def parse_choices(value: str, option: str, choices, all_word: str | None = "all") -> tuple[str, ...]:
    """A comma list of names from ``choices`` (``all_word`` alone: every choice), in the order
    given, duplicates dropped. Empty, blank, an empty item or an unknown name: one
    :class:`InputError` naming ``option`` and what it accepts."""
    from cubot_cad.errors import InputError

    choices = tuple(choices)
    accepted = ", ".join(choices) + (f" or {all_word}" if all_word else "")
    text = "" if value is None else str(value)
    items = [s.strip() for s in text.split(",")]
    if not text.strip() or not any(items):
        raise InputError(f"{option} {text!r} is empty: give a comma list of {accepted}")
    if "" in items:
        raise InputError(f"{option} {text!r}: an empty item (two commas or a trailing comma); "
                         f"give a comma list of {accepted}")
    if all_word and items == [all_word]:
        return choices
    bad = [s for s in items if s not in choices]
    if bad:
        raise InputError(f"{option} {text!r}: {', '.join(map(repr, bad))} not one of {accepted}")
    return tuple(dict.fromkeys(items))
