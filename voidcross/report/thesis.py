"""The thesis's own Tables 4.4-4.9 and its words on the figures the report redraws.

Tables: each CSV file in ``thesis_data/`` names its table in its first comment
line and holds the printed grid: one row per void width (``void_cm``,
``void_width`` in robot widths), one column per swarm size, seconds; an empty
cell is the thesis's '-'.

Figures: ``thesis_data/figures.toml`` holds, per thesis figure the report has an
equivalent of, its caption and what the thesis's text says it shows, both quoted
verbatim after :func:`normalise_text` (see :func:`thesis_figures`).
"""

from __future__ import annotations

import csv
import re
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

#: (file, table number, preset, metric)
THESIS_TABLES = (
    ("table_4_4_case_a_mean_Ta.csv", "4.4", "case-a", "Ta"),
    ("table_4_5_case_a_mean_Td.csv", "4.5", "case-a", "Td"),
    ("table_4_6_case_a_mean_Tt.csv", "4.6", "case-a", "Tt"),
    ("table_4_7_case_b_mean_Ta.csv", "4.7", "case-b", "Ta"),
    ("table_4_8_case_b_mean_Td.csv", "4.8", "case-b", "Td"),
    ("table_4_9_case_b_mean_Tt.csv", "4.9", "case-b", "Tt"),
)


@dataclass(frozen=True)
class ThesisTable:
    number: str
    preset: str
    metric: str
    title: str
    robots: tuple[int, ...]
    #: {(robots, void_width): seconds or None}
    values: dict
    void_cm: dict
    path: Path

    def widths(self) -> list[int]:
        return sorted({w for _, w in self.values})


def data_dir() -> Path:
    return Path(str(resources.files("voidcross.report") / "thesis_data"))


def load_table(fname: str, number: str, preset: str, metric: str) -> ThesisTable:
    path = data_dir() / fname
    lines = path.read_text().splitlines()
    comments = [ln[1:].strip() for ln in lines if ln.startswith("#")]
    title = comments[0] if comments else fname
    body = [ln for ln in lines if ln.strip() and not ln.startswith("#")]
    reader = csv.reader(body)
    header = next(reader)
    robots = tuple(int(c) for c in header[2:])
    values, void_cm = {}, {}
    for row in reader:
        w = int(row[1])
        void_cm[w] = int(row[0])
        for n, cell in zip(robots, row[2:], strict=True):
            values[(n, w)] = float(cell) if cell.strip() else None
    return ThesisTable(number, preset, metric, title, robots, values, void_cm, path)


def thesis_tables() -> list[ThesisTable]:
    return [load_table(*t) for t in THESIS_TABLES]


# ------------------------------------------------------------------ figures
FIGURES_FILE = "figures.toml"
_LINE_BREAK_HYPHEN = re.compile(r"([A-Za-z])-[ \t]*\n\s*([a-z])")


def normalise_text(text: str) -> str:
    """The thesis text as the quotes in ``figures.toml`` are written: a hyphen at a line end
    followed (after any blank lines) by a lowercase letter is line-break hyphenation and is
    joined ("posi-\\ntions" -> "positions"), then every run of whitespace is one space.

    A genuine hyphen that falls at a line end ("x-\\ncoordinates") is joined too, so no quote
    spans one."""
    return " ".join(_LINE_BREAK_HYPHEN.sub(r"\1\2", text).split())


@dataclass(frozen=True)
class ThesisFigure:
    #: "4.39"
    number: str
    #: the thesis's caption, verbatim (normalised), without its "Figure 4.39: " label
    caption: str
    #: one to three contiguous sentences of the thesis's text on what the figure shows, verbatim
    finding: str
    #: 1-based line of the thesis text where the caption starts
    line: int
    #: 1-based line of the thesis text where the finding starts
    finding_line: int


_FIGURE_KEYS = {"figure", "caption", "finding", "line", "finding_line"}


def thesis_figures() -> dict[str, ThesisFigure]:
    """{"4.39": ThesisFigure, ...} from ``thesis_data/figures.toml``, in the file's order.

    A malformed entry (a key missing or unknown, a figure listed twice) raises ValueError."""
    path = data_dir() / FIGURES_FILE
    with open(path, "rb") as fh:
        entries = tomllib.load(fh).get("figure", [])
    out: dict[str, ThesisFigure] = {}
    for k, e in enumerate(entries):
        if set(e) != _FIGURE_KEYS:
            raise ValueError(f"{path.name}: entry {k + 1} ({e.get('figure', '?')}) has keys {sorted(e)}, "
                             f"expected {sorted(_FIGURE_KEYS)}")
        number = str(e["figure"])
        if number in out:
            raise ValueError(f"{path.name}: Fig. {number} is listed twice")
        out[number] = ThesisFigure(number, e["caption"], e["finding"], int(e["line"]), int(e["finding_line"]))
    return out
