"""`voidcross doctor` prints clean versions and lists the optional parquet writer."""

from __future__ import annotations

from voidcross.commands.doctor import CHECKS, clean_version


def test_versions_are_numbers_not_log_lines():
    prusa = "[2026-12-01 10:00:00.123] [info] loading 3.1 presets\nPrusaSlicer-2.5.0+UNKNOWN based on Slic3r"
    assert clean_version("prusa-slicer", prusa) == "2.5.0"
    assert clean_version("chromium", "Chromium 156.0.8078.114 built on Debian GNU/Linux 12") == "156.0.8078.114"
    assert clean_version("tool", "no number here") == "?"


def test_doctor_lists_pyarrow_for_parquet_export(cli):
    assert any(c[0] == "pyarrow" for c in CHECKS)
    res = cli("doctor", "--json")
    assert res.code in (0, 1)
    names = {c["name"]: c for c in res.json()["checks"]}
    assert "pyarrow" in names and names["prusa-slicer"]["version"] in (None, "?") or \
        names["prusa-slicer"]["version"][0].isdigit()
