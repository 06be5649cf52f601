"""GLB models (binary glTF 2.0) of the robots and of a CuBot bridge, for the report's 3D viewer.

Written by OCC's own glTF writer (``RWGltf_CafWriter``, through cadquery's ``toCAF``) from the
robot's :meth:`~cubot_cad.robots.base.Robot.assembly`: one mesh per solid (faces merged), one material
per colour (printed parts by role, bought parts in their stand-in colours), repeated parts as
instances of one mesh.

Units and axes are glTF's: **metres, +Y up**. The CAD's robot frame (mm; x forward, y left,
z up) maps to glTF as (x, y, z) mm -> (x, z, -y) / 1000 m; :func:`cad_bounds_mm` undoes it.

``bridge-cubot-line.glb``: :data:`BRIDGE_ROBOTS` CuBots docked front to rear (latches locked),
robot *i* placed at *i* times the docked offset measured by :mod:`cubot_cad.checks.docking` (B behind
A), standing on their wheels across a void between two ground slabs: the front and the rear
robot each stand on one slab, the middle ones span the void.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Tessellation of the GLB meshes (mm, rad): coarser than the STLs, a viewer needs no more.
GLB_TOLERANCE_MM = 0.2
GLB_ANGULAR_RAD = 0.3
BRIDGE_NAME = "bridge-cubot-line"
BRIDGE_ROBOTS = 5
SLAB_THICKNESS_MM = 10.0
#: Slab width across the line, as a multiple of the robot width.
SLAB_WIDTH_FACTOR = 1.6
SLAB_COLOUR = (0.42, 0.36, 0.28)


def write_glb(assy, path: str | os.PathLike, tolerance: float = GLB_TOLERANCE_MM,
              angular: float = GLB_ANGULAR_RAD) -> Path:
    """Write ``assy`` (a cq.Assembly in mm, z up) as a GLB in metres, +Y up."""
    from cadquery.occ_impl.assembly import toCAF
    from OCP.Message import Message_ProgressRange
    from OCP.RWGltf import RWGltf_CafWriter
    from OCP.RWMesh import RWMesh_CoordinateSystem_Zup
    from OCP.TCollection import TCollection_AsciiString
    from OCP.TColStd import TColStd_IndexedDataMapOfStringString

    _, doc = toCAF(assy, True, True, tolerance, angular)
    writer = RWGltf_CafWriter(TCollection_AsciiString(str(path)), True)
    conv = writer.ChangeCoordinateSystemConverter()
    conv.SetInputLengthUnit(0.001)  # the CAD is in mm; the writer's output unit is the metre
    conv.SetInputCoordinateSystem(RWMesh_CoordinateSystem_Zup)  # output: glTF's +Y up
    writer.SetMergeFaces(True)
    if not writer.Perform(doc, TColStd_IndexedDataMapOfStringString(), Message_ProgressRange()):
        raise RuntimeError(f"the glTF writer failed on {path}")
    return Path(path)


def cad_bounds_mm(gltf_bounds) -> np.ndarray:
    """glTF bounds [[x0, y0, z0], [x1, y1, z1]] (m, +Y up) -> CAD bounds (mm, z up), same layout."""
    b = np.asarray(gltf_bounds, dtype=float) * 1000.0
    lo, hi = b
    return np.array([[lo[0], -hi[2], lo[1]], [hi[0], -lo[2], hi[1]]])


@dataclass(frozen=True)
class BridgeLayout:
    """Where the bridge's robots and slabs go (mm, the front robot's frame)."""

    offsets_mm: tuple[tuple[float, float, float], ...]
    pitch_mm: float
    slabs_mm: tuple[tuple[float, float, float, float, float, float], ...]  # x0, x1, y0, y1, z0, z1
    void_mm: float
    span_mm: float

    def summary(self) -> dict:
        return {"robots": len(self.offsets_mm), "pitch_mm": round(self.pitch_mm, 3),
                "void_mm": round(self.void_mm, 3), "span_mm": round(self.span_mm, 3),
                "offsets_mm": [[round(v, 3) for v in o] for o in self.offsets_mm],
                "slabs_mm": [[round(v, 3) for v in s] for s in self.slabs_mm]}


def bridge_layout(robot, pair, n: int = BRIDGE_ROBOTS) -> BridgeLayout:
    """Robot *i* at *i* x the docked offset of ``pair`` (the measured ``cubot-front-rear`` pair);
    slabs under the first and the last robot's footprint, top on the wheels' contact plane."""
    off = np.asarray(pair.offset_mm, dtype=float)
    offsets = [tuple(float(v) for v in off * i) for i in range(n)]
    L = float(robot.length_mm)
    x0, y0, _, x1, y1, _ = robot.bbox_mm(include_components=True)
    xs = [o[0] for o in offsets]
    ground = -float(robot.wheel_exposed_mm)
    yc = (y0 + y1) / 2
    half_w = SLAB_WIDTH_FACTOR * (y1 - y0) / 2
    z = (ground - SLAB_THICKNESS_MM, ground)
    front = (max(xs) - L / 2, max(xs) + L / 2)
    rear = (min(xs) - L / 2, min(xs) + L / 2)
    slabs = tuple((a, b, yc - half_w, yc + half_w, *z) for a, b in (rear, front))
    return BridgeLayout(tuple(offsets), float(np.linalg.norm(off)), slabs, front[0] - rear[1],
                        (max(xs) + x1) - (min(xs) + x0))


def bridge_assembly(robot, pair, n: int = BRIDGE_ROBOTS):
    """cq.Assembly of the bridge (see :func:`bridge_layout`), latches locked as docked."""
    import cadquery as cq

    from cubot_cad.shapes import box

    lay = bridge_layout(robot, pair, n)
    unit = robot.assembly(placed=robot.build_placed(blades_locked=True), fresh=True, name=robot.name)
    assy = cq.Assembly(name=BRIDGE_NAME)
    for i, o in enumerate(lay.offsets_mm):
        assy.add(unit, name=f"{robot.name}_{i + 1}", loc=cq.Location(cq.Vector(*o)))
    for k, s in enumerate(lay.slabs_mm):
        assy.add(box(*s), name=f"ground_slab_{k + 1}", color=cq.Color(*SLAB_COLOUR))
    return assy, lay


def robot_glb_assembly(robot):
    """The robot as :meth:`~cubot_cad.robots.base.Robot.assembly` builds it (components included),
    on fresh copies of its solids (the GLB's tessellation does not depend on earlier meshing)."""
    return robot.assembly(fresh=True)
