"""PNG renders of robots and docked pairs (matplotlib, tessellated meshes, mm)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .atomic import write_via

PRINTED = (0.86, 0.86, 0.80)
SECOND = (0.55, 0.70, 0.90)


def _tris(shape, tol: float = 0.3, angular: float = 0.5):
    if isinstance(shape, np.ndarray):  # already triangles (n, 3, 3)
        return shape
    verts, tris = shape.tessellate(tol, angular)
    if not tris:
        return np.zeros((0, 3, 3))
    v = np.array([(p.x, p.y, p.z) for p in verts])
    return v[np.array(tris)]


def render_shapes(groups, path: str | os.PathLike, title: str, elev: float = 22, azim: float = -58,
                  size_in: float = 6.0) -> Path:
    """``groups``: list of (shapes, rgb); a shape may also be an (n, 3, 3) array of triangles.
    Writes a PNG atomically and returns its path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig = plt.figure(figsize=(size_in, size_in * 0.8), dpi=110)
    ax = fig.add_subplot(projection="3d")
    light = np.array([0.4, -0.5, 0.8])
    light /= np.linalg.norm(light)
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for shapes, rgb in groups:
        for s in shapes:
            t = _tris(s)
            if len(t) == 0:
                continue
            n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
            ln = np.linalg.norm(n, axis=1, keepdims=True)
            n = n / np.where(ln == 0, 1, ln)
            shade = 0.45 + 0.55 * np.clip(np.abs(n @ light), 0, 1)
            cols = np.clip(np.outer(shade, rgb), 0, 1)
            ax.add_collection3d(Poly3DCollection(t, facecolors=cols, edgecolors="none", linewidths=0))
            lo = np.minimum(lo, t.reshape(-1, 3).min(axis=0))
            hi = np.maximum(hi, t.reshape(-1, 3).max(axis=0))
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=elev, azim=azim)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    p = Path(path)
    try:
        write_via(p, lambda tmp: fig.savefig(tmp, format="png"))
    finally:
        plt.close(fig)
    return p


def render_robot(robot, path) -> Path:
    comps = []
    for comp in robot.components():
        if comp.role in ("wheel", "caster", "motor", "power"):
            comps.append((comp.solids(), tuple(comp.colour)))
    mp = robot.mass_properties()
    title = f"{robot.title}: {mp.printed_mass_kg * 1e3:.0f} g printed, {mp.mass_kg * 1e3:.0f} g total"
    return render_shapes([(robot.shapes(), PRINTED)] + comps, path, title)


def render_pair(pair, path) -> Path:
    title = f"{pair.name}: gap {pair.gap_mm:.2f} mm, interference {pair.interference_mm3:.3f} mm^3"
    return render_shapes([(pair.shapes_a, PRINTED), (pair.shapes_b, SECOND)], path, title)


#: Printed parts shown in the bridge render (the others are inside the bodies).
BRIDGE_RENDER_ROLES = ("body", "cover", "rail", "pin", "blade", "cross_key")


def render_bridge(robot, pair, path) -> Path:
    """The bridge of :mod:`cubot_cad.gltf` (five docked CuBots across a void between two slabs).
    One robot is tessellated once (coarse: a 1 rad angular step) and its triangles translated."""
    from .gltf import SLAB_COLOUR, bridge_layout
    from .shapes import box

    lay = bridge_layout(robot, pair)
    printed = [_tris(p.shape.copy(False), 0.5, 1.0) for p in robot.build_placed(blades_locked=True)
               if p.role in BRIDGE_RENDER_ROLES]
    comps = [_tris(s, 0.5, 1.0) for c in robot.components() if c.role in ("wheel", "caster") for s in c.solids()]
    printed, comps = np.concatenate(printed), np.concatenate(comps)
    groups = []
    for i, o in enumerate(lay.offsets_mm):
        groups.append(([printed + np.asarray(o)], PRINTED if i % 2 == 0 else SECOND))
        groups.append(([comps + np.asarray(o)], (0.25, 0.25, 0.25)))
    groups.append(([box(*s) for s in lay.slabs_mm], SLAB_COLOUR))
    title = (f"bridge: {len(lay.offsets_mm)} CuBots docked front to rear (pitch {lay.pitch_mm:.1f} mm) "
             f"across a {lay.void_mm:.0f} mm void")
    return render_shapes(groups, path, title, elev=18, azim=-70, size_in=8.0)
