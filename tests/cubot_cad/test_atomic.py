"""One way to write an output file in every package: complete or not at all, world-readable."""

from __future__ import annotations

import stat

import pytest

from cubot_cad.atomic import OUTPUT_MODE, atomic_path, write_json, write_text, write_via


def test_a_written_file_is_complete_and_world_readable(tmp_path):
    p = write_text(tmp_path / "sub" / "a.md", "line\r\nnext\n")
    assert p.read_bytes() == b"line\r\nnext\n"              # no newline translation
    assert stat.S_IMODE(p.stat().st_mode) == OUTPUT_MODE == 0o644
    assert write_json(tmp_path / "b.json", {"x": 1}).read_text() == '{\n  "x": 1\n}\n'
    assert list(tmp_path.glob(".*")) == [] and list((tmp_path / "sub").glob(".*")) == []


def test_a_failed_or_interrupted_write_leaves_the_old_file_and_no_debris(tmp_path):
    p = tmp_path / "keep.csv"
    p.write_text("old\n")
    for exc in (OSError("disk full"), KeyboardInterrupt()):
        with pytest.raises(type(exc)), atomic_path(p) as tmp:
            tmp.write_text("half")
            raise exc
        assert p.read_text() == "old\n"
        assert [f.name for f in tmp_path.iterdir()] == ["keep.csv"]


def test_the_temporary_name_keeps_the_suffix_for_writers_that_read_it(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1])
    seen = []
    write_via(tmp_path / "f.png", lambda t: (seen.append(t), fig.savefig(t)))
    plt.close(fig)
    assert seen[0].endswith(".png") and (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"
