"""StructureLimits (the fem -> sim record): thesis preset, round-trip, validation."""

from __future__ import annotations

import dataclasses
import json

import pytest

from structure_fem.errors import InputError
from structure_fem.limits import (
    SCHEMA_VERSION,
    THESIS_ROWS_PER_BLOCK,
    StructureLimits,
    load_limits,
    taper_half_level,
    tapered_arch_robots,
    thesis_limits,
)


def test_thesis_preset_reproduces_the_thesis_rules():
    lim = thesis_limits()
    assert lim.source == "thesis"
    assert lim.thresholds() == {"line": 5, "two_line": 10, "arch": 15, "arch_levels": [20, 25, 30]}
    assert [lim.min_robots(w) for w in range(1, 6)] == [3, 6, 9, 12, 15]  # N = 3 n_g
    assert lim.min_robots(8) == 48  # two lines: 2 x 3 n_g
    assert lim.min_robots(15) == (28 + 18 + 28) * 5  # 28a / 18a / 28a, a = 5 rows
    assert lim.level_for(12).layers == 3 and lim.level_for(27).layers == 4
    assert lim.level_for(3).ground_ratio == 2.0  # n_p = 2 n_g before landing
    assert lim.level_for(12).tapered and not lim.level_for(8).tapered
    assert (lim.level_for(12).ground_ratio, lim.level_for(12).ground_margin) == (1.0, 1)  # robots: ground > void


@pytest.mark.parametrize(("layers", "width", "a_units"), [
    (3, 15, (28, 18, 28)), (3, 20, (28, 20, 28)), (4, 25, (60, 54, 60)), (4, 30, (60, 56, 60))])
def test_tapering_arch_counts_are_the_thesis_ones(layers, width, a_units):
    """Ch. 5.5.2 (c)-(f): initial / over the void / target in units a = 5 robots."""
    c = tapered_arch_robots(layers, THESIS_ROWS_PER_BLOCK, width)
    assert (c["initial"], c["over"], c["target"]) == tuple(5 * a for a in a_units)
    assert thesis_limits().min_robots(width) == c["total"]


def test_tapering_arch_before_landing_and_its_section_profile():
    # Ch. 5.5.2 (c): before landing 28a on the initial ground, 12a over a 15-wide void
    before = tapered_arch_robots(3, 5, 15, far_foot=False)
    assert (before["initial"], before["over"], before["target"]) == (140, 60, 0)
    # half-levels along the rows: foot 1,2,3 to the near edge, 2 then core over the void, mirrored
    prof = [taper_half_level(3, 5, r, 15) for r in range(-15, 30, 5)]
    assert prof == [1, 2, 3, 2, 1, 2, 3, 2, 1]
    # the geometry follows its inputs: 2-row blocks shorten the feet
    assert tapered_arch_robots(3, 2, 15)["total"] < tapered_arch_robots(3, 5, 15)["total"]


def test_only_a_2k_by_k_arch_can_taper():
    lvl = thesis_limits().level_for(12)
    with pytest.raises(InputError, match="2k wide and k high"):
        dataclasses.replace(lvl, lines=8)
    with pytest.raises(InputError, match="only an arch can taper"):
        dataclasses.replace(thesis_limits().level_for(8), taper_block_rows=5)


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
