"""The docs' decision tables are generated from the code's tables (issue 17 house-keeping)."""

from __future__ import annotations

from pathlib import Path

import pytest

from swarm_sim import decision_docs as D

DOCS = Path(__file__).resolve().parents[2] / "docs" / "swarm_sim.md"


def test_the_docs_tables_are_the_codes_tables():
    text = DOCS.read_text()
    assert D.render(text) == text, "run: python -m swarm_sim.decision_docs docs/swarm_sim.md"
    for name, table in D.TABLES.items():
        assert f"<!-- BEGIN decision-table {name} -->" in text
        for k, (action, _, words) in enumerate(table, 1):
            assert f"| {k} | `{action}` | {words} |" in text


def test_every_row_says_in_words_when_it_applies():
    for table in D.TABLES.values():
        assert all(len(row) == 3 and isinstance(row[2], str) and len(row[2]) > 8 for row in table)


def test_a_changed_table_makes_the_docs_stale(monkeypatch, tmp_path):
    f = tmp_path / "d.md"
    f.write_text("x\n<!-- BEGIN decision-table RETREAT_TABLE -->\nold\n<!-- END decision-table RETREAT_TABLE -->\n")
    assert D.main(["--check", str(f)]) == 1
    assert D.main([str(f)]) == 0 and D.main(["--check", str(f)]) == 0
    monkeypatch.setitem(D.TABLES, "RETREAT_TABLE", D.TABLES["RETREAT_TABLE"][:1])
    assert D.main(["--check", str(f)]) == 1
    f.write_text("<!-- BEGIN decision-table NOPE -->\n<!-- END decision-table NOPE -->\n")
    with pytest.raises(KeyError, match="NOPE"):
        D.main(["--check", str(f)])
