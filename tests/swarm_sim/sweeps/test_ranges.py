"""Range lists for --robots / --void-width: the thesis's sweep spelled as text."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from swarm_sim.errors import InputError
from swarm_sim.sweeps.ranges import format_int_range, parse_int_range


def test_thesis_case_d_sizes():
    assert parse_int_range("3-18,20,25,30,40,50") == (*range(3, 19), 20, 25, 30, 40, 50)


def test_single_values_duplicates_and_spaces():
    assert parse_int_range(" 5 , 3-4,4,5 ") == (3, 4, 5)


@pytest.mark.parametrize("text, fragment", [
    ("", "empty"), ("   ", "empty"), ("5-3", "reversed"), ("x", "'x'"), ("3,,4", "bad item"),
    ("3-", "bad item"), ("-3", "bad item"), ("0-2", "minimum"), ("1.5", "bad item"),
])
def test_bad_ranges_name_the_value(text, fragment):
    with pytest.raises(InputError) as exc:
        parse_int_range(text, "--robots")
    assert "--robots" in str(exc.value) and fragment in str(exc.value)


@given(st.sets(st.integers(1, 200), min_size=1, max_size=40))
def test_format_parse_roundtrip(values):
    assert parse_int_range(format_int_range(values)) == tuple(sorted(values))
