"""A soak journal cut anywhere (the process killed mid-write, the disk full) resumes from its
last whole record or says which line is bad: never an internal failure (issue 41)."""

from __future__ import annotations

import json

import pytest

from swarm_sim.errors import InputError
from swarm_sim.experiments.soak import _read_journal, soak


@pytest.fixture(scope="module")
def journal(tmp_path_factory):
    j = tmp_path_factory.mktemp("soak") / "soak.jsonl"
    soak(2, seed=5, max_time_s=20.0, journal=j)
    data = j.read_bytes()
    return data, json.loads(data.split(b"\n")[0])


def _draws(lines: list[bytes]) -> int:
    return sum(1 for ln in lines if b'"i":' in ln)


def test_a_journal_cut_at_every_byte_resumes_from_its_last_whole_record(journal, tmp_path):
    data, header = journal
    for cut in range(1, len(data)):
        f = tmp_path / f"cut{cut}.jsonl"
        f.write_bytes(data[:cut])
        done, wall, _codes = _read_journal(f, header)
        *whole, tail = data[:cut].split(b"\n")  # whole lines, then what was cut
        # a cut just before a newline leaves a whole record: it counts (and gets its newline)
        expect = _draws(whole) + (1 if tail == data.split(b"\n")[len(whole)] and whole else 0) * _draws([tail])
        assert len(done) == expect, (cut, sorted(done))
        after = f.read_bytes()
        assert after == b"" or after.endswith(b"\n"), cut  # the next append starts its own line
        assert (data[:cut] + b"\n").startswith(after), cut  # nothing but the torn tail is removed
        assert wall >= 0.0


def test_a_cut_inside_a_utf8_character_is_a_torn_line(journal, tmp_path):
    data, header = journal
    f = tmp_path / "utf8.jsonl"
    f.write_bytes(data + '{"i": 1, "note": "é'.encode()[:-1])  # half of the two-byte é
    done, _w, _c = _read_journal(f, header)
    assert len(done) == 2 and f.read_bytes() == data


def test_a_bad_line_in_the_middle_is_one_error_naming_it(journal, tmp_path):
    data, header = journal
    lines = data.split(b"\n")
    f = tmp_path / "mid.jsonl"
    f.write_bytes(b"\n".join([lines[0], lines[1], b"{oops", *lines[2:]]))
    with pytest.raises(InputError, match="line 3 is not JSON"):
        _read_journal(f, header)
    f.write_bytes(b"\n".join([lines[0], b"[1, 2]", *lines[1:]]))
    with pytest.raises(InputError, match="line 2 is not JSON"):
        _read_journal(f, header)
    assert f.read_bytes() == b"\n".join([lines[0], b"[1, 2]", *lines[1:]])  # refused: never rewritten


def test_the_command_resumes_a_torn_journal(cli, journal, tmp_path):
    data, header = journal
    f = tmp_path / "cli.jsonl"
    res = cli("sim", "soak", "--runs", "1", "--seed", "5", "--journal", str(f))  # the presets' guards: it ends
    assert res.code == 0, res.err
    whole = f.read_bytes()
    f.write_bytes(whole[:-5])  # killed in the middle of the last record
    res = cli("sim", "soak", "--runs", "1", "--seed", "5", "--journal", str(f))
    assert res.code == 0, res.err
    assert f.read_bytes().endswith(b"\n")


def test_a_file_that_is_no_journal_is_refused_and_kept(journal, tmp_path):
    _data, header = journal
    f = tmp_path / "other.json"
    f.write_bytes(b'{"schema_version": 1, "robots": [tru')  # one torn line, but not this soak's header
    with pytest.raises(InputError, match="not a soak journal"):
        _read_journal(f, header)
    assert f.read_bytes() == b'{"schema_version": 1, "robots": [tru'  # never truncated
