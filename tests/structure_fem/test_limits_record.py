"""StructureLimits (the fem -> sim record): thesis preset, round-trip, validation."""

from __future__ import annotations

import dataclasses
import json

import pytest

from structure_fem.errors import InputError
from structure_fem.limits import SCHEMA_VERSION, StructureLimits, load_limits, thesis_limits


def test_thesis_preset_reproduces_the_thesis_rules():
    lim = thesis_limits()
    assert lim.source == "thesis"
    assert lim.thresholds() == {"line": 5, "two_line": 10, "arch": 15, "arch_levels": [20, 25, 30]}
    assert [lim.min_robots(w) for w in range(1, 6)] == [3, 6, 9, 12, 15]  # N = 3 n_g
    assert lim.min_robots(8) == 48  # two lines: 2 x 3 n_g
    assert lim.min_robots(15) == (28 + 18 + 28) * 5  # 28a / 18a / 28a, a = 5 rows
    assert lim.level_for(12).layers == 3 and lim.level_for(27).layers == 4
    assert lim.level_for(3).ground_ratio == 2.0  # n_p = 2 n_g before landing


def test_round_trip(tmp_path):
    lim = thesis_limits()
    assert StructureLimits.load(lim.save(tmp_path / "limits.json")) == lim
    assert load_limits(tmp_path / "limits.json") == lim
    assert load_limits("thesis") == lim


def test_void_wider_than_widest_structure_is_input_error():
    with pytest.raises(InputError, match="void width 31 is wider than the widest structure"):
        thesis_limits().level_for(31)
    with pytest.raises(InputError, match="positive integer"):
        thesis_limits().level_for(0)


def test_levels_must_tile_widths_without_gaps():
    lim = thesis_limits()
    with pytest.raises(InputError, match="expected 6"):
        dataclasses.replace(lim, levels=(lim.levels[0], lim.levels[2]))


def test_arch_beyond_8_by_4_is_rejected():
    lvl = thesis_limits().levels[-1]
    with pytest.raises(InputError, match="layers=5"):
        dataclasses.replace(lvl, layers=5)
    with pytest.raises(InputError, match="lines=9"):
        dataclasses.replace(lvl, lines=9)


def test_other_schema_version_and_corrupt_files_are_rejected(tmp_path):
    data = thesis_limits().to_dict()
    data["schema_version"] = SCHEMA_VERSION + 1
    p = tmp_path / "limits.json"
    p.write_text(json.dumps(data))
    with pytest.raises(InputError, match="schema_version"):
        load_limits(p)
    p.write_text("not json")
    with pytest.raises(InputError, match="not valid JSON"):
        load_limits(p)


def test_unknown_limits_spec_names_it():
    with pytest.raises(InputError, match="--limits softest"):
        load_limits("softest")
