"""Printable exports: one binary STL (and optionally 3MF) per distinct printable
part laid flat, one STEP assembly per robot, ``manifest.json`` and
``robot_properties.json`` (SI record for `structure_fem`).

Layout under the output directory::

    manifest.json                 per part: robot, file, quantity, volume, bbox, mass, watertight
    robot_properties.json         RobotPropertiesFile of the exported robots
    <robot>/<part>.stl            binary STL, mm, oriented flat (z >= 0)
    <robot>/<part>.3mf            with --format 3mf
    <robot>/pier_deck.stl         (CuBot) the deck a pier's top robot wears, one per pier (cubot_cad.piers.deck)
    <robot>/bom.csv               bill of materials: printed parts, bought parts, ISO fasteners, pier parts
    <robot>.step                  STEP assembly (printed parts + stand-ins for bought parts)
    <robot>.glb                   GLB (binary glTF 2.0, metres, +Y up) of the assembled robot
    bridge-cubot-line.glb         GLB of five docked CuBots spanning a void (with cubot and glb)

Nothing is written unless everything is: every input (robots, formats, material,
clearance, and the docked pairs when given: interference and designed gap) is
checked first, then the whole export is written into a hidden staging directory
(``.<out>.partial-*`` in the nearest existing parent of a new ``--out``, or
``.export.partial-*`` inside an existing one) and only then moved into place: a
new ``--out`` appears complete with one rename; into an existing one the files
are renamed one by one, manifest and properties last. A failure on the way
removes the staging directory: no empty or partial ``--out`` is left and an
existing ``robot_properties.json`` is kept.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path

from cubot_cad.atomic import write_bytes, write_via
from cubot_cad.errors import InputError
from cubot_cad.jsonrecord import write_json_atomic
from cubot_cad.manifest import MANIFEST_SCHEMA, load_manifest  # noqa: F401  (the manifest's home)
from cubot_cad.mesh import STL_ANGULAR_RAD, STL_TOLERANCE_MM, mesh_of  # noqa: F401  (the mesh's home)
from cubot_cad.part import BED_MM, DEFAULT_CLEARANCE_MM, check_clearance, material
from cubot_cad.robots.registry import ROBOT_NAMES, make_robot, parse_robots  # noqa: F401  (the registry's home)

FORMATS = ("stl", "step", "3mf", "glb")
DEFAULT_FORMATS = ("stl", "step", "glb")


def parse_formats(value: str) -> tuple[str, ...]:
    items = [v.strip().lower() for v in str(value).split(",") if v.strip()]
    if not items:
        raise InputError("--format is empty")
    for v in items:
        if v not in FORMATS:
            raise InputError(f"--format {v!r} is not one of {', '.join(FORMATS)}")
    return tuple(dict.fromkeys(items))


def _atomic_bytes(path: Path, data: bytes) -> None:
    write_bytes(path, data)


def _atomic_via(path: Path, writer: Callable[[str], None]) -> None:
    """Let ``writer`` write a temporary file next to ``path``, then rename it into place."""
    write_via(path, writer)


def _nearest_existing(p: Path) -> Path:
    p = p.absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


@contextlib.contextmanager
def staged_output(out: Path):
    """Yield a hidden, empty staging directory for everything that goes to ``out``; on success
    move it into place (see the module docstring), on any failure remove it."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: is a file, not a directory")
    tag = f"{os.getpid()}-{secrets.token_hex(4)}"
    if out.is_dir():
        stage = out / f".export.partial-{tag}"
    else:
        anchor = _nearest_existing(out.parent)
        if not anchor.is_dir():
            raise InputError(f"--out {out}: {anchor} is a file, not a directory")
        stage = anchor / f".{out.name or 'export'}.partial-{tag}"
    stage.mkdir()
    try:
        yield stage
        _commit(stage, out)
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise


#: Moved into an existing output directory last, so a reader never sees a new manifest or
#: properties record next to old parts.
_LAST = ("robot_properties.json", "manifest.json")


def _commit(stage: Path, out: Path) -> None:
    if not out.exists():
        out.parent.mkdir(parents=True, exist_ok=True)
        os.rename(stage, out)
        return
    def order(f: Path):
        rel = f.relative_to(stage).as_posix()
        return (1 + _LAST.index(rel) if rel in _LAST else 0, rel)

    files = sorted((f for f in stage.rglob("*") if f.is_file()), key=order)
    for src in files:
        dst = out / src.relative_to(stage)
        dst.parent.mkdir(parents=True, exist_ok=True)
        os.replace(src, dst)
    shutil.rmtree(stage)


@dataclass
class PartRecord:
    robot: str
    part: str
    description: str
    file: str
    quantity: int
    volume_mm3: float
    mesh_volume_mm3: float
    bbox_mm: list[float]
    size_mm: list[float]
    mass_g: float
    watertight: bool
    fits_bed: bool
    extra_files: list[str] = field(default_factory=list)
    print_settings: dict = field(default_factory=dict)
    #: What ``quantity`` counts: per ``robot``, or per ``pier`` (the pier deck).
    per: str = "robot"


@dataclass
class ExportResult:
    out: Path
    material: str
    clearance_mm: float
    parts: list[PartRecord]
    robots: dict
    step_files: list[str]
    seconds: float
    manifest: Path
    properties: Path
    glb_files: list[str] = field(default_factory=list)


def export_robots(robots: Iterable[str], out: str | os.PathLike, formats: Iterable[str] = ("stl", "step"),
                  material_name: str = "abs", clearance_mm: float = DEFAULT_CLEARANCE_MM,
                  progress: Callable | None = None, gaps: dict[str, dict[str, float]] | None = None,
                  pairs: list | None = None, settings: tuple = (), slice_parts: bool = False) -> ExportResult:
    """Export the named robots' printable parts, assemblies, manifest and properties under ``out``.

    ``pairs`` (:class:`~cubot_cad.checks.docking.DockedPair` measured at this clearance) are checked
    first: if any interferes or misses its designed gap, :class:`InputError` and nothing is
    written; otherwise their gaps go into the connector records and their summaries into the
    manifest. ``gaps`` (robot -> coupling kind -> mm) passes measured gaps directly; with
    neither, the geometric design gap of each connector is used. ``slice_parts``: slice every STL
    with its recorded print settings when prusa-slicer is on PATH (:mod:`cubot_cad.checks.slicing`; minutes)
    and record the numbers in the manifest. ``settings``: the ``--set``
    dimensions (:mod:`cubot_cad.settings`), each robot built with those it has and recorded in the
    manifest. All or nothing: see :func:`staged_output`.
    """
    t0 = time.perf_counter()
    robots = tuple(robots)
    formats = tuple(formats)
    mat = material(material_name)
    check_clearance(clearance_mm, "--clearance-mm")
    out = Path(out)
    from cubot_cad.settings import check_applicable, parse_settings

    settings = tuple((k, v) for k, v in parse_settings(settings) if k != "clearance_mm")
    check_applicable(settings, robots)
    models = {name: make_robot(name, clearance_mm, settings) for name in robots}
    if pairs is not None:
        from cubot_cad.checks.docking import measured_gaps, require_docked

        require_docked(pairs, "--clearance-mm", "nothing written")
        gaps = {**(gaps or {}), **measured_gaps(pairs)}
    with staged_output(out) as stage:
        res = _write_export(stage, models, formats, material_name, mat, clearance_mm, progress, gaps, pairs,
                            settings, slice_parts)
    return ExportResult(out, material_name, clearance_mm, res["parts"], res["robots"], res["step_files"],
                        time.perf_counter() - t0, out / "manifest.json", out / "robot_properties.json",
                        res["glb_files"])


def _write_export(out: Path, models: dict, formats: tuple, material_name: str, mat: dict, clearance_mm: float,
                  progress, gaps, pairs, settings: tuple = (), slice_parts: bool = False) -> dict:
    from cubot_cad.piers.deck import pier_parts

    jobs = [(name, part, qty, "robot") for name, r in models.items() for part, qty in r.printable_parts()]
    jobs += [(name, part, qty, "pier") for name, r in models.items() for part, qty in pier_parts(r)]
    it = progress(jobs, "cad export", len(jobs)) if progress else jobs
    records: list[PartRecord] = []
    rho = mat["density_kg_m3"]
    for name, part, qty, per in it:
        shape = part.printable
        mesh = mesh_of(shape)
        rel = f"{name}/{part.name}.stl"
        extra = []
        if "stl" in formats:
            _atomic_bytes(out / rel, mesh.export(file_type="stl"))
        if "3mf" in formats:
            import cadquery as cq

            rel3 = f"{name}/{part.name}.3mf"
            _atomic_via(out / rel3, lambda p, s=shape: cq.exporters.export(s, p, tolerance=STL_TOLERANCE_MM,
                                                                           angularTolerance=STL_ANGULAR_RAD))
            extra.append(rel3)
        from cubot_cad.shapes import tight_bbox

        b = tight_bbox(shape)
        dims = [b[3] - b[0], b[4] - b[1], b[5] - b[2]]
        size = sorted(dims)
        bed = sorted(BED_MM)
        records.append(PartRecord(
            robot=name, part=part.name, description=part.description,
            file=rel if "stl" in formats else "", quantity=qty,
            volume_mm3=round(part.volume_mm3, 4), mesh_volume_mm3=round(float(mesh.volume), 4),
            bbox_mm=[round(v, 4) for v in b],
            size_mm=[round(v, 4) for v in dims],
            mass_g=round(part.volume_mm3 * 1e-9 * rho * 1e3, 4),
            watertight=bool(mesh.is_watertight and mesh.is_volume),
            fits_bed=all(s <= b for s, b in zip(size, bed, strict=True)), extra_files=extra,
            print_settings=part.print_settings(), per=per))
    step_files = []
    if "step" in formats:
        for name, r in models.items():
            rel = f"{name}.step"
            assy = r.assembly()
            _atomic_via(out / rel, lambda p, a=assy: a.export(p, exportType="STEP"))
            step_files.append(rel)
    glb_files, models_summary = [], []
    if "glb" in formats:  # after the STLs: the GLB meshes are made on copies, at their own tolerance
        glb_files, models_summary = _write_glbs(out, models, clearance_mm, pairs, settings)
    from cubot_cad.hardware.components import component_table
    from cubot_cad.outputs.bom import bom_csv, bom_rows
    from cubot_cad.properties import RobotPropertiesFile, ground_contact_fields
    from cubot_cad.settings import settings_text

    robots_summary = {}
    for name, r in models.items():
        mp = r.mass_properties(material_name)
        robots_summary[name] = {
            "title": r.title, "envelope_mm": list(r.envelope_mm), "printed_mass_g": round(mp.printed_mass_kg * 1e3, 3),
            "total_mass_g": round(mp.mass_kg * 1e3, 3), "com_mm": [round(c * 1e3, 3) for c in mp.com_m],
            "step": f"{name}.step" if "step" in formats else None,
            "glb": f"{name}.glb" if "glb" in formats else None,
            "printable_parts": sum(q for _, q in r.printable_parts()),
            "components": component_table(r.components()),
            "bom": f"{name}/bom.csv",
        }
        sizes = {rec.part: rec.size_mm for rec in records if rec.robot == name}
        _atomic_bytes(out / name / "bom.csv", bom_csv(bom_rows(r, rho, sizes)).encode())
    manifest = {
        "schema_version": MANIFEST_SCHEMA, "units": "mm, g", "material": material_name.upper(),
        "density_kg_m3": rho, "clearance_mm": clearance_mm, "settings": dict(settings), "bed_mm": list(BED_MM),
        "stl_tolerance_mm": STL_TOLERANCE_MM, "robots": robots_summary,
        "parts": [vars(p) for p in records],
    }
    if "glb" in formats:
        from cubot_cad.outputs.gltf import GLB_ANGULAR_RAD, GLB_TOLERANCE_MM

        manifest["glb"] = {"units": "m, +Y up (glTF): CAD (x, y, z) mm -> (x, z, -y) / 1000",
                           "tolerance_mm": GLB_TOLERANCE_MM, "angular_rad": GLB_ANGULAR_RAD,
                           "files": glb_files, "models": models_summary}
    if pairs is not None:
        manifest["docked_pairs"] = [p.summary() for p in pairs]
    fractions: dict = {}
    if slice_parts and "stl" in formats:  # slicer's print time, filament and printed mass per part and robot
        from cubot_cad.checks.slicing import printed_fractions, slice_into_manifest, slicer_path

        if slicer_path() is not None:
            slice_into_manifest(manifest, out, progress=progress)
            fractions = printed_fractions(manifest)
    tuned = f", --set {settings_text(settings)}" if settings else ""
    props = {}
    for name, r in models.items():
        frac = fractions.get(name)
        mass = ("mass/COM/inertia = printed parts (OCC solids, each part's density scaled to the slicer's printed "
                f"grams at its recorded print settings: {manifest.get('slicer_version') or manifest.get('slicer')}; "
                "mass distributed as the solid's: assumption) + non-printed component table" if frac else
                "mass/COM/inertia = printed parts as solid (OCC; not sliced: the print at its infill is lighter) "
                "+ non-printed component table")
        source = (f"cubot_cad CAD export (material {material_name.upper()}, clearance {clearance_mm:g} mm{tuned}): "
                  f"{mass}; exposed heights measured on the wheel/caster solids; connector stiffness = documented "
                  "estimate (structure_fem calibrates)")
        props[name] = r.robot_properties(material_name, source=source, printed_fraction=frac) \
            if not gaps or name not in gaps else _with_gaps(r, material_name, source, gaps[name], frac)
        if frac:  # the heavy end of the infill range: the same robot with its printed parts solid
            solid = r.mass_properties(material_name).mass_kg
            props[name] = replace(props[name], solid_print_mass_kg=solid, solid_print_mass_source=(
                f"cubot_cad: the same robot with its printed parts as OCC solids (100 % infill) at "
                f"{material_name.upper()}'s density, {1e3 * solid:.1f} g against {1e3 * props[name].mass_kg:.1f} g as "
                "sliced"))
    from cubot_cad.piers.pier import stack_fields

    # standing height, stack pitch and deck height of the robots that stack (measured when docked)
    props = {n: replace(p, **stack_fields(models[n], pairs)) for n, p in props.items()}
    # where each robot touches the ground (wheel and caster contacts: structure_fem's ledge supports)
    props = {n: replace(p, **ground_contact_fields(models[n])) for n, p in props.items()}
    # the printed body's bending section (structure_fem's flexible bodies)
    from cubot_cad.checks.section import body_section_fields

    props = {n: replace(p, **body_section_fields(models[n])) for n, p in props.items()}
    pfile = RobotPropertiesFile(robots=tuple(props.values()))
    pfile.save(out / "robot_properties.json")
    write_json_atomic(out / "manifest.json", manifest)
    return {"parts": records, "robots": robots_summary, "step_files": step_files, "glb_files": glb_files}


def _write_glbs(out: Path, models: dict, clearance_mm: float, pairs, settings: tuple = ()) -> tuple[list[str], list[dict]]:
    """``<robot>.glb`` per robot and, with the CuBot, ``bridge-cubot-line.glb`` placed by the
    measured ``cubot-front-rear`` pair (docked now if the export was given no pairs)."""
    from cubot_cad.outputs.gltf import BRIDGE_NAME, bridge_assembly, robot_glb_assembly, write_glb

    files, summary = [], []
    for name, r in models.items():
        rel = f"{name}.glb"
        assy = robot_glb_assembly(r)
        _atomic_via(out / rel, lambda p, a=assy: write_glb(a, p))
        files.append(rel)
        summary.append({"file": rel, "robot": name, "what": f"{r.title} assembled, bought parts as stand-ins"})
    if "cubot" in models:
        from cubot_cad.checks.docking import dock

        pair = next((p for p in pairs or [] if p.name == "cubot-front-rear"), None) or \
            (dock("cubot-front-rear", clearance_mm, settings=settings) if settings else
             dock("cubot-front-rear", clearance_mm))
        assy, lay = bridge_assembly(models["cubot"], pair)
        rel = f"{BRIDGE_NAME}.glb"
        _atomic_via(out / rel, lambda p, a=assy: write_glb(a, p))
        files.append(rel)
        summary.append({"file": rel, "robot": "cubot", "what": f"{len(lay.offsets_mm)} CuBots docked front to "
                        "rear across a void between two ground slabs", **lay.summary()})
    return files, summary


def _with_gaps(robot, material_name: str, source: str, gaps: dict[str, float], printed_fraction: dict | None = None):
    from dataclasses import replace

    rp = robot.robot_properties(material_name, source=source, printed_fraction=printed_fraction)
    conns = robot.connector_properties(rp.youngs_modulus_pa, gaps)
    return replace(rp, connectors=tuple(conns))


