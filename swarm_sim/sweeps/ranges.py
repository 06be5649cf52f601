"""Parse integer range lists such as ``"3-18,20,25,30"`` (swarm sizes, void widths).

Each comma-separated item is a single integer ``N`` or an inclusive range
``LO-HI`` with ``LO <= HI``. The result is sorted and de-duplicated. An empty
string, an empty item, a reversed range (``"5-3"``), a non-integer or a value
below ``minimum`` raises :class:`swarm_sim.errors.InputError` naming the bad
value and the option it came from.
"""

from __future__ import annotations

import re

from ..errors import InputError

_ITEM = re.compile(r"^\s*(\d+)\s*(?:-\s*(\d+)\s*)?$")
#: Refuse absurd ranges early (a typo like "3-180000" would queue millions of runs).
MAX_VALUES = 10_000


def parse_int_range(text: str, option: str = "range", minimum: int = 1) -> tuple[int, ...]:
    """``"3-5,8"`` -> ``(3, 4, 5, 8)``; raises InputError on empty, reversed or bad items."""
    if text is None or not str(text).strip():
        raise InputError(f"{option} {text!r}: empty range (expected e.g. '3-18,20,25')")
    values: set[int] = set()
    for item in str(text).split(","):
        m = _ITEM.match(item)
        if not m:
            raise InputError(f"{option} {text!r}: bad item {item.strip()!r} "
                             "(expected an integer N or a range LO-HI, e.g. '3-18,20')")
        lo = int(m.group(1))
        hi = int(m.group(2)) if m.group(2) is not None else lo
        if hi < lo:
            raise InputError(f"{option} {text!r}: range {item.strip()!r} is reversed ({lo} > {hi})")
        if lo < minimum:
            raise InputError(f"{option} {text!r}: value {lo} is below the minimum {minimum}")
        if hi - lo + 1 + len(values) > MAX_VALUES:
            raise InputError(f"{option} {text!r}: more than {MAX_VALUES} values")
        values.update(range(lo, hi + 1))
    return tuple(sorted(values))


def format_int_range(values) -> str:
    """Inverse of :func:`parse_int_range`: ``(3, 4, 5, 8)`` -> ``"3-5,8"``."""
    vals = sorted(set(int(v) for v in values))
    parts: list[str] = []
    i = 0
    while i < len(vals):
        j = i
        while j + 1 < len(vals) and vals[j + 1] == vals[j] + 1:
            j += 1
        parts.append(str(vals[i]) if i == j else f"{vals[i]}-{vals[j]}")
        i = j + 1
    return ",".join(parts)
