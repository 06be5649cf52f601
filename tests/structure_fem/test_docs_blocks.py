"""docs/structure_fem.md's numbers are generated from the code (issues 12 and 17)."""

from __future__ import annotations

from pathlib import Path

import pytest

from structure_fem.outputs import docs_blocks as B

DOCS = Path(__file__).resolve().parents[2] / "docs" / "structure_fem.md"
README = Path(__file__).resolve().parents[2] / "README.md"


def test_the_page_shows_what_the_code_computes():
    text = DOCS.read_text()
    assert B.render(text) == text, "run: python -m structure_fem.outputs.docs_blocks docs/structure_fem.md"
    for name in B.BLOCKS:
        assert f"<!-- BEGIN generated {name} -->" in text


def test_a_block_moves_when_its_input_moves(monkeypatch, tmp_path):
    f = tmp_path / "p.md"
    f.write_text("<!-- BEGIN generated calibration -->\n<!-- END generated calibration -->\n")
    assert B.main([str(f)]) == 0 and B.main(["--check", str(f)]) == 0
    monkeypatch.setitem(B.BLOCKS, "calibration", lambda: "other numbers\n")
    assert B.main(["--check", str(f)]) == 1
    f.write_text("<!-- BEGIN generated nope -->\n<!-- END generated nope -->\n")
    with pytest.raises(KeyError, match="nope"):
        B.main(["--check", str(f)])


def test_the_readme_shows_the_derived_thresholds_beside_the_thesis():
    text = README.read_text()
    assert "<!-- BEGIN generated thresholds -->" in text
    assert B.render(text) == text, "run: make docs (python -m structure_fem.outputs.docs_blocks ... README.md)"
