"""How `make test` spreads the suite over its workers (issue 40): a file's tests stay on one
worker (``--dist loadgroup``, the group set per file by tests/conftest.py) so its module fixtures
are built once, except the files listed in ``conftest.SPREAD``."""

from __future__ import annotations

import pytest


def test_under_make_test_a_file_is_one_group(request):
    """The group is read into the node id (``...@tests/test_suite_layout.py``). It was not for a
    while: the conftest set the groups after xdist had read them, and pytest 9 dropped the node id
    attribute xdist 3.8 writes (hence ``pytest<9`` in pyproject.toml), so every module fixture
    was built once per worker."""
    if not request.config.getvalue("loadgroup"):
        pytest.skip("only under make test's --dist loadgroup")
    assert request.node.nodeid.endswith("@tests/test_suite_layout.py"), request.node.nodeid


def test_spread_files_have_no_group(request):
    from tests.conftest import SPREAD

    assert "tests/structure_fem/test_never_crash.py" in SPREAD
    marks = [m.args for m in request.node.iter_markers("xdist_group")]
    assert marks == [("tests/test_suite_layout.py",)]
