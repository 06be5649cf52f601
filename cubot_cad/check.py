"""`cad check`: is every exported STL printable?

Per STL: watertight and a valid volume (trimesh), manifold (manifold3d status
``NoError``), fits the bed (250 x 210 x 210 mm, as oriented), thinnest wall
>= 0.8 mm, and, when ``prusa-slicer`` is on PATH, a headless slice that
records print time and filament.

Thin-wall probe: points are sampled uniformly over the surface; from each a
ray goes inward along the negative face normal and the first exit is found
(manifold3d ray casting). Where the exit face is roughly opposite (normals
more than 135 deg apart) the distance is a wall thickness; exits through an
adjacent face near a sharp convex edge are not walls and are ignored. The
thinnest wall is the minimum over the accepted samples.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from .errors import InputError
from .part import BED_MM, MIN_WALL_MM

WALL_SAMPLES = 3000
OPPOSITE_COS = -0.7071


@dataclass
class SliceResult:
    ok: bool
    print_time: str | None = None
    filament_g: float | None = None
    detail: str = ""


@dataclass
class PartCheck:
    file: str
    watertight: bool
    manifold: bool
    fits_bed: bool
    size_mm: list[float]
    thinnest_wall_mm: float | None
    wall_ok: bool
    volume_mm3: float
    slice: dict | None = None

    @property
    def ok(self) -> bool:
        return self.watertight and self.manifold and self.fits_bed and self.wall_ok and \
            (self.slice is None or self.slice.get("ok", True) or self.slice.get("skipped", False))


def _manifold(mesh):
    import manifold3d as m3d

    return m3d.Manifold(m3d.Mesh(vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
                                 tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))


def thinnest_wall_mm(mesh, samples: int = WALL_SAMPLES, seed: int = 0) -> float | None:
    """Minimum wall thickness (mm) by inward ray casting; None if no wall was found."""
    import trimesh

    man = _manifold(mesh)
    pts, fi = trimesh.sample.sample_surface(mesh, samples, seed=seed)
    normals = mesh.face_normals[fi]
    span = float(np.linalg.norm(mesh.extents)) + 1.0
    best = None
    for p, n in zip(pts, normals, strict=True):
        o = p - n * 1e-3
        for hit in man.ray_cast(tuple(map(float, o)), tuple(map(float, o - n * span))):
            hn = np.asarray(hit.normal, dtype=float)
            if np.linalg.norm(hn) == 0:
                continue
            if np.dot(hn / np.linalg.norm(hn), n) < OPPOSITE_COS:
                d = float(np.linalg.norm(np.asarray(hit.position, dtype=float) - o)) + 1e-3
                if best is None or d < best:
                    best = d
            break  # only the first exit matters
    return best


def fits_bed(size_mm) -> bool:
    x, y, z = size_mm
    bx, by, bz = BED_MM
    return z <= bz and ((x <= bx and y <= by) or (y <= bx and x <= by))


def slicer_path() -> str | None:
    return shutil.which("prusa-slicer") or shutil.which("prusa-slicer-console")


def slice_stl(path: Path, density_g_cm3: float = 1.04, timeout_s: float = 300) -> SliceResult:
    """Slice with prusa-slicer (headless) and read print time and filament from the G-code header."""
    exe = slicer_path()
    if exe is None:
        return SliceResult(False, detail="prusa-slicer not on PATH")
    with tempfile.TemporaryDirectory() as td:
        gcode = Path(td) / "out.gcode"
        cmd = [exe, "--export-gcode", str(path), "--output", str(gcode), "--filament-density", str(density_g_cm3)]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            return SliceResult(False, detail=f"prusa-slicer timed out after {timeout_s:g} s")
        if proc.returncode != 0 or not gcode.exists():
            return SliceResult(False, detail=(proc.stderr or proc.stdout).strip().splitlines()[-1:] and
                               (proc.stderr or proc.stdout).strip().splitlines()[-1] or f"exit {proc.returncode}")
        text = gcode.read_text(errors="replace")
    t = re.search(r";\s*estimated printing time \(normal mode\)\s*=\s*(.+)", text)
    g = re.search(r";\s*total filament used \[g\]\s*=\s*([0-9.]+)", text) or \
        re.search(r";\s*filament used \[g\]\s*=\s*([0-9.]+)", text)
    return SliceResult(True, t.group(1).strip() if t else None, float(g.group(1)) if g else None, "sliced")


def check_file(path: Path, root: Path | None = None, do_slice: bool = True, samples: int = WALL_SAMPLES) -> PartCheck:
    import trimesh

    try:
        mesh = trimesh.load(path, force="mesh")
    except Exception as exc:  # corrupt file
        raise InputError(f"{path} is not a readable STL ({type(exc).__name__})") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise InputError(f"{path} holds no triangles")
    size = [float(v) for v in mesh.extents]
    watertight = bool(mesh.is_watertight and mesh.is_volume)
    try:
        import manifold3d as m3d

        manifold = _manifold(mesh).status() == m3d.Error.NoError
    except Exception:
        manifold = False
    wall = thinnest_wall_mm(mesh, samples) if watertight else None
    sl = None
    if do_slice:
        if slicer_path() is None:
            sl = {"skipped": True, "ok": None, "detail": "prusa-slicer not on PATH (apt install prusa-slicer)"}
        else:
            sl = asdict(slice_stl(path))
    rel = str(path.relative_to(root)) if root else str(path)
    return PartCheck(rel, watertight, manifold, fits_bed(size), [round(s, 3) for s in size],
                     None if wall is None else round(wall, 3), wall is not None and wall >= MIN_WALL_MM - 1e-6,
                     round(float(mesh.volume), 3), sl)


def stl_files(directory: str | os.PathLike) -> list[Path]:
    d = Path(directory)
    if not d.exists():
        raise InputError(f"directory not found: {d}")
    if not d.is_dir():
        raise InputError(f"not a directory: {d}")
    files = sorted(d.rglob("*.stl"))
    if not files:
        raise InputError(f"no .stl files under {d} (run `voidcross cad export --out {d}` first)")
    return files
