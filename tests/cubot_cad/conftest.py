"""Shared, session-scoped CAD builds: OCC is slow, so every robot, docked pair and
export is built once per test session and shared."""

from __future__ import annotations

import pytest

pytest.importorskip("cadquery")
pytest.importorskip("trimesh")
pytest.importorskip("manifold3d")


@pytest.fixture(scope="session")
def robots():
    from cubot_cad.robots.registry import ROBOT_NAMES, make_robot

    return {name: make_robot(name) for name in ROBOT_NAMES}


@pytest.fixture(scope="session")
def pairs():
    from cubot_cad.checks.docking import PAIRS, dock

    return {name: dock(name) for name in PAIRS}


@pytest.fixture(scope="session")
def export_dir(tmp_path_factory, pairs):
    """A fresh `cad export --robot all` (STL + STEP + GLB, the CLI's default formats) with the
    docked pairs checked and their measured gaps in the record, as the CLI does it."""
    from cubot_cad.outputs.export import DEFAULT_FORMATS, export_robots
    from cubot_cad.robots.registry import ROBOT_NAMES

    out = tmp_path_factory.mktemp("exports")
    export_robots(ROBOT_NAMES, out, DEFAULT_FORMATS, "abs", 0.2, pairs=list(pairs.values()))
    return out
