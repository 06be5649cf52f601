"""Output paths meet the error contract before any work: a file where a directory must go, a
path under a file, a directory where a file must go: exit 2, one ``error:`` line naming the
option, nothing written."""

from __future__ import annotations

import pytest


@pytest.fixture
def afile(tmp_path):
    f = tmp_path / "a_file"
    f.write_text("keep me")
    return f


CASES = [
    ("sim", "run", "--out", "{f}"),
    ("sim", "run", "--video", "{f}/sub/run.mp4"),
    ("sim", "run", "--snapshots", "{f}"),
    ("fem", "table", "--out", "{f}"),
    ("fem", "table", "--out", "{f}/sub"),
    ("fem", "study", "--out", "{f}"),
    ("fem", "solve", "--rows", "5", "--over", "2", "--void", "2", "--plot", "{f}/side.png"),
    ("fem", "solve", "--rows", "5", "--over", "2", "--void", "2", "--plot", "{d}/side.txt"),
    ("pipeline", "--out", "{f}"),
    ("reproduce", "--out", "{f}"),
    ("report", "--db", "{d}/none.sqlite", "--out", "{f}"),
    ("sweep", "export", "--db", "{d}/none.sqlite", "--to", "{d}"),
    ("cad", "export", "--robot", "cubot", "--out", "{f}"),
    ("cad", "render", "--out", "{f}/x"),
]


@pytest.mark.parametrize("argv", CASES, ids=[" ".join(c[:2]) + " " + c[-2] for c in CASES])
def test_a_bad_output_path_is_one_error_line_and_exit_2(cli, tmp_path, afile, argv):
    args = [a.format(f=afile, d=tmp_path) for a in argv]
    res = cli(*args)
    assert res.code == 2, (args, res.err)
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:"), res.err
    opt = argv[-2]
    assert opt in res.err or "--db" in res.err, res.err
    assert afile.read_text() == "keep me"


def test_an_absolute_video_path_creates_nothing_under_results(cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    res = cli("sim", "run", "--preset", "case-d", "--robots", "3", "--void-width", "1", "--max-time", "3",
              "--video", str(tmp_path / "v" / "run.gif"))
    assert res.code == 0, res.err
    assert (tmp_path / "v" / "run.gif").is_file() and not (tmp_path / "results").exists()
