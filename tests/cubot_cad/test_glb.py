"""GLB models for the report's 3D viewer: valid glTF 2.0 binaries that load back, robots at
their true size (metres, +Y up), coloured parts, and the docked CuBot bridge."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
COMMITTED = REPO / "exports"
ROBOTS = ("cubot", "octbot", "cube-robot", "platform")
MAX_BYTES = 10 * 2**20


def _load(path: Path):
    import trimesh

    data = path.read_bytes()
    magic, version, length = struct.unpack("<4sII", data[:12])
    assert magic == b"glTF" and version == 2 and length == len(data), path
    assert len(data) < MAX_BYTES, (path, len(data))
    scene = trimesh.load(path)
    assert isinstance(scene, trimesh.Scene)
    return scene


def _colours(scene) -> np.ndarray:
    """Distinct material colours, back in the sRGB the CAD gave them (glTF stores linear rgb;
    trimesh reads it as 0-255)."""
    lin = np.unique(np.array([np.asarray(g.visual.material.baseColorFactor, dtype=float)[:3] / 255.0
                              for g in scene.geometry.values()]), axis=0)
    return np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * lin ** (1 / 2.4) - 0.055)


def _has(cols: np.ndarray, rgb) -> bool:
    return bool(np.any(np.all(np.abs(cols - np.asarray(rgb)) < 0.02, axis=1)))


@pytest.mark.parametrize("name", ROBOTS)
def test_robot_glb_loads_back_at_the_robot_size(export_dir, robots, name):
    from cubot_cad.outputs.gltf import cad_bounds_mm

    scene = _load(export_dir / f"{name}.glb")
    r = robots[name]
    assert len(scene.geometry) > 1
    b = cad_bounds_mm(scene.bounds)  # m, +Y up -> mm, z up
    x0, y0, z0, x1, y1, z1 = r.bbox_mm(include_components=True)
    assert b == pytest.approx(np.array([[x0, y0, z0], [x1, y1, z1]]), abs=0.5)
    # the envelope (what the thesis quotes) fits inside; only what enters a neighbour (pins, tongue,
    # OctBot's capturer housing: 46 mm) and the wheels below stick out of it
    L, W, H = r.envelope_mm
    size = b[1] - b[0]
    assert np.all(size >= np.array([L, W, H]) - 0.5) and np.all(size <= np.array([L, W, H]) + 50.0)


def test_connectors_have_their_own_colours(export_dir):
    from cubot_cad.robots.base import ROLE_COLOURS

    cols = _colours(_load(export_dir / "cubot.glb"))
    for role in ("body", "pin", "blade", "rail", "cross_key"):
        assert _has(cols, ROLE_COLOURS[role]), role
    assert len(cols) >= 8


def test_bridge_is_five_docked_cubots_over_a_void(export_dir, robots, pairs):
    from cubot_cad.outputs.gltf import (
        BRIDGE_ROBOTS,
        SLAB_COLOUR,
        SLAB_THICKNESS_MM,
        bridge_layout,
        cad_bounds_mm,
    )

    r = robots["cubot"]
    scene = _load(export_dir / "bridge-cubot-line.glb")
    lay = bridge_layout(r, pairs["cubot-front-rear"])
    assert BRIDGE_ROBOTS == 5 and len(lay.offsets_mm) == 5
    # the pitch is the docked pair's measured offset: body length + the 0 mm docked gap
    assert lay.pitch_mm == pytest.approx(r.length_mm + pairs["cubot-front-rear"].gap_mm, abs=0.01)
    one = len(_load(export_dir / "cubot.glb").geometry)
    assert len(scene.geometry) >= 5 * one + 2
    b = cad_bounds_mm(scene.bounds)
    x0, y0, z0, x1, y1, z1 = r.bbox_mm(include_components=True)
    assert b[1][0] - b[0][0] == pytest.approx(4 * lay.pitch_mm + (x1 - x0), abs=0.5)
    assert (b[1][0] - b[0][0]) / r.length_mm == pytest.approx(5.0, abs=0.3)  # about 5 robot lengths
    assert b[0][2] == pytest.approx(-r.wheel_exposed_mm - SLAB_THICKNESS_MM, abs=0.5)  # slabs under the wheels
    assert lay.void_mm == pytest.approx(3 * lay.pitch_mm, abs=0.5)
    assert _has(_colours(scene), SLAB_COLOUR)


def test_manifest_lists_the_glbs(export_dir):
    m = json.loads((export_dir / "manifest.json").read_text())
    files = m["glb"]["files"]
    assert files == [f"{n}.glb" for n in ROBOTS] + ["bridge-cubot-line.glb"]
    assert m["glb"]["units"].startswith("m, +Y up")
    assert all(m["robots"][n]["glb"] == f"{n}.glb" for n in ROBOTS)
    bridge = m["glb"]["models"][-1]
    assert bridge["robots"] == 5 and bridge["pitch_mm"] == pytest.approx(100.0, abs=0.05)


def test_committed_glbs_are_there_and_load(export_dir):
    fresh = json.loads((export_dir / "manifest.json").read_text())
    committed = json.loads((COMMITTED / "manifest.json").read_text())
    assert committed.get("glb", {}).get("files") == fresh["glb"]["files"], \
        "exports/ is stale: run `voidcross cad export`"
    for f in committed["glb"]["files"]:
        assert len(_load(COMMITTED / f).geometry) > 1, f
