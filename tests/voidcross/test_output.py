"""Progress on long work: a bar on a terminal, periodic plain lines in a log or CI."""

from __future__ import annotations

from voidcross import output


def test_progress_writes_plain_lines_when_stderr_is_not_a_terminal(monkeypatch, capsys):
    monkeypatch.setattr(output, "PLAIN_EVERY_S", 0.0)
    assert list(output.progress(range(4), "soak", 4)) == [0, 1, 2, 3]
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("soak: 1/4 (") and "left" in err[0]
    assert err[-1].startswith("soak: 4/4 done")


def test_progress_is_silent_for_short_work_and_when_disabled(capsys):
    assert list(output.progress(range(3), "quick", 3)) == [0, 1, 2]
    assert list(output.progress(range(3), "off", 3, disable=True)) == [0, 1, 2]
    assert capsys.readouterr().err == ""


def test_one_set_parser_for_every_command():
    from voidcross.output import parse_set

    got = parse_set(["arena_w_cm=800", "finish_delivery=true", 'walk="random"', "obstacles=[[30, 33, 5]]",
                     "sleep_s=0.03", "shape=octagon", 'note={"a": 1}'])
    assert got == {"arena_w_cm": 800, "finish_delivery": True, "walk": "random", "obstacles": [[30, 33, 5]],
                   "sleep_s": 0.03, "shape": "octagon", "note": {"a": 1}}


def test_a_set_without_a_key_is_an_input_error():
    import pytest

    from cubot_cad.errors import InputError
    from voidcross.output import parse_set

    for bad in ("novalue", "=3"):
        with pytest.raises(InputError, match="KEY=VALUE"):
            parse_set([bad])
