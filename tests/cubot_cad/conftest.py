"""Shared, session-scoped CAD builds: OCC is slow, so every robot, docked pair and
export is built once per test session and shared."""

from __future__ import annotations

import pytest

pytest.importorskip("cadquery")
pytest.importorskip("trimesh")
pytest.importorskip("manifold3d")


@pytest.fixture(scope="session")
def robots():
    from cubot_cad.export import ROBOT_NAMES, make_robot

    return {name: make_robot(name) for name in ROBOT_NAMES}


@pytest.fixture(scope="session")
def pairs():
    from cubot_cad.docking import PAIRS, dock

    return {name: dock(name) for name in PAIRS}


@pytest.fixture(scope="session")
def export_dir(tmp_path_factory, pairs):
    """A fresh `cad export --robot all` (STL + STEP) with measured gaps, as the CLI does it."""
    from cubot_cad.docking import measured_gaps
    from cubot_cad.export import ROBOT_NAMES, export_robots
    from cubot_cad.jsonrecord import read_json, write_json_atomic

    out = tmp_path_factory.mktemp("exports")
    res = export_robots(ROBOT_NAMES, out, ("stl", "step"), "abs", 0.2, gaps=measured_gaps(list(pairs.values())))
    manifest = read_json(res.manifest)
    manifest["docked_pairs"] = [p.summary() for p in pairs.values()]
    write_json_atomic(res.manifest, manifest)
    return out
