"""`cad check`: is every exported STL printable?

Per STL: watertight and a valid volume (trimesh), manifold (manifold3d status
``NoError``), fits the bed (250 x 210 x 210 mm, as oriented), thinnest wall
>= 0.8 mm, and, when ``prusa-slicer`` is on PATH, a headless slice with the
part's print settings as ``manifest.json`` records them (:mod:`cubot_cad.checks.slicing`:
layer height, perimeters, infill, supports; the material's filament density),
which gives print time (s), filament (g) and the printed mass (g, supports and
skirt removed). :func:`slicing_totals` sums them per robot, beside the
solid-model mass.

Thin-wall probe: points are sampled uniformly over the surface; from each a
ray goes inward along the negative face normal and the first exit is found
(manifold3d ray casting). Where the exit face is roughly opposite (normals
more than 135 deg apart) the distance is a wall thickness; exits through an
adjacent face near a sharp convex edge are not walls and are ignored. The
thinnest wall is the minimum over the accepted samples.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from cubot_cad.checks.slicing import SliceResult, robot_totals, slice_stl, slicer_path  # noqa: F401  (re-exported)
from cubot_cad.errors import InputError
from cubot_cad.part import BED_MM, MIN_WALL_MM, PRINT_DEFAULTS, Part, material

WALL_SAMPLES = 3000
OPPOSITE_COS = -0.7071


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


@lru_cache(maxsize=8)
def _manifest_at(root: str, mtime_ns: int) -> dict | None:
    from cubot_cad.manifest import load_manifest

    try:
        return load_manifest(Path(root))
    except InputError:
        return None


def manifest_for(root: Path | None) -> dict | None:
    """The export's ``manifest.json`` under ``root`` (cached while the file is unchanged), or None."""
    if root is None or not (Path(root) / "manifest.json").is_file():
        return None
    return _manifest_at(str(Path(root).resolve()), (Path(root) / "manifest.json").stat().st_mtime_ns)


def recorded_settings(path: Path, root: Path | None) -> tuple[dict, float, str]:
    """(print settings, filament density g/cm^3, where they come from) for the STL ``path``: its
    ``manifest.json`` entry under ``root`` when there is one, else the shared defaults
    (:data:`~cubot_cad.part.PRINT_DEFAULTS`, 25 % infill, no supports) in ABS."""
    man = manifest_for(root)
    if man is not None:
        from cubot_cad.checks.slicing import density_g_cm3, part_entry

        entry = part_entry(man, Path(path).relative_to(root).as_posix())
        if entry is not None and entry.get("print_settings"):
            return dict(entry["print_settings"]), density_g_cm3(man), "manifest.json"
    return ({**PRINT_DEFAULTS, "infill_percent": Part.infill_percent, "supports": False},
            material("abs")["density_kg_m3"] / 1000.0, "defaults (no manifest entry)")


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
            settings, rho, source = recorded_settings(path, root)
            sl = {**slice_stl(path, settings, rho).summary(), "settings": settings, "settings_source": source}
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


def slicing_totals(results: list[PartCheck], root: Path | None) -> dict:
    """Per robot (from ``manifest.json`` under ``root``): print time (s), filament (g), printed mass (g)
    and the solid-model mass (g) over its per-robot parts times their quantities, from the checks'
    slices (:func:`cubot_cad.checks.slicing.robot_totals`); {} without a manifest or slices."""
    man = manifest_for(root)
    if man is None:
        return {}
    from cubot_cad.checks.slicing import part_entry

    rows = []
    for r in results:
        entry = part_entry(man, r.file)
        if entry is None or not r.slice or r.slice.get("skipped"):
            continue
        rows.append({"robot": entry["robot"], "quantity": entry["quantity"], "per": entry.get("per", "robot"),
                     "solid_mass_g": entry["mass_g"], "slice": r.slice})
    return robot_totals(rows)
