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
def export_dir(once):
    """A fresh `cad export --robot all` (STL + STEP + GLB, the CLI's default formats) with the
    docked pairs checked and their measured gaps in the record, as the CLI does it. Built once
    per session for all xdist workers (read-only for the tests)."""

    def build(out):
        from cubot_cad.checks.docking import PAIRS, dock
        from cubot_cad.outputs.export import DEFAULT_FORMATS, export_robots
        from cubot_cad.robots.registry import ROBOT_NAMES

        export_robots(ROBOT_NAMES, out, DEFAULT_FORMATS, "abs", 0.2, pairs=[dock(name) for name in PAIRS])

    return once("export_dir", build)


@pytest.fixture(scope="session")
def cad_pipeline(once):
    """The pipeline's cad stage (export of every robot sliced with its print settings, renders,
    GLB models) run once per session for all xdist workers: ``(dir, ctx, summary line)``."""
    import json

    def build(root):
        from voidcross.commands.cad import pipeline_stage

        ctx: dict = {}
        line = pipeline_stage(root / "cad", ctx)
        (root / "stage.json").write_text(json.dumps({"ctx": ctx, "line": line}))

    root = once("cad_pipeline", build)
    stage = json.loads((root / "stage.json").read_text())
    return root / "cad", stage["ctx"], stage["line"]
