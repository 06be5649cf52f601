"""Tessellation of OCC shapes into trimesh meshes (millimetres), one home for the export's and
the checks' meshes."""

from __future__ import annotations

#: Tessellation of exported meshes (mm, rad).
STL_TOLERANCE_MM = 0.02


STL_ANGULAR_RAD = 0.15


def mesh_of(shape, tolerance: float = STL_TOLERANCE_MM, angular: float = STL_ANGULAR_RAD):
    """Tessellate an OCC shape into a trimesh.Trimesh (mm)."""
    import numpy as np
    import trimesh

    verts, tris = shape.tessellate(tolerance, angular)
    v = np.array([(p.x, p.y, p.z) for p in verts], dtype=float)
    f = np.array(tris, dtype=np.int64).reshape(-1, 3)
    mesh = trimesh.Trimesh(vertices=v, faces=f, process=True)
    mesh.merge_vertices()
    # OCC leaves zero-area slivers at sphere poles and seams: drop them
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.remove_unreferenced_vertices()
    return mesh
