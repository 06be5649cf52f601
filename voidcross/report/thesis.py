"""The thesis's own Tables 4.4-4.9, read from the CSV files that transcribe them.

Each file in ``thesis_data/`` names its table in its first comment line and
holds the printed grid: one row per void width (``void_cm``, ``void_width``
in robot widths), one column per swarm size, seconds; an empty cell is the
thesis's '-'.
"""

from __future__ import annotations

import csv
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
