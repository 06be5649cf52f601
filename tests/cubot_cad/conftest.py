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
def export_dir(cad_pipeline):
    """The session's `cad export --robot all` (STL + STEP + GLB, the CLI's default formats, docked
    pairs checked and their measured gaps in the record, every part sliced with its print
    settings): the cad pipeline stage's export, which is that command (read-only for the tests;
    the files reading it share one worker, ``tests/conftest.py`` GROUPS)."""
    return cad_pipeline[0]


@pytest.fixture(scope="session")
def unsliced_export(once):
    """An export made by :func:`~cubot_cad.outputs.export.export_robots` itself, not the CLI, and
    not sliced (STL only, the robots docked): for the tests about what that function writes and
    about slicing an export afterwards. Three robots: one with a pier (the CuBot), one without
    (the OctBot), the smallest (the platform)."""

    def build(out):
        from cubot_cad.checks.docking import PAIRS, ROBOT_OF_PAIR, dock
        from cubot_cad.outputs.export import export_robots

        robots = ("cubot", "octbot", "platform")
        export_robots(robots, out, ("stl",), "abs", 0.2,
                      pairs=[dock(name) for name in PAIRS if ROBOT_OF_PAIR[name] in robots])

    return once("unsliced_export", build)


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
