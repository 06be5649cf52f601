"""Slicing the exported parts with PrusaSlicer, each with the print settings ``manifest.json`` records
for it, and reading print time, filament and printed mass from the G-code.

Units: lengths mm, masses g, times s, densities g/cm^3 (the slicer's) or kg/m^3 (the manifest's).

* :func:`slicer_args` turns a part's recorded ``print_settings`` (``cubot_cad.part.Part.print_settings``:
  layer height, nozzle, perimeters, top/bottom layers, infill, supports) into PrusaSlicer's CLI
  options. Every recorded setting maps to an option or is a note (``*_reason``, ``notes``, the
  orientation the STL already has: :data:`NOTE_KEYS`); one
  that does neither is an :class:`~cubot_cad.errors.InputError`, so no setting is silently dropped.
  A recorded 100 % infill with no pattern is sliced rectilinear (PrusaSlicer refuses its default
  sparse pattern at 100 %; rectilinear is what it uses for solid layers).
* :func:`slice_stl` runs ``prusa-slicer --export-gcode`` headless with those options and
  ``--filament-density`` from the material, then checks the settings block PrusaSlicer writes at
  the end of the G-code: a recorded setting the slicer did not take is an error, not a number.
* :func:`parse_gcode` reads ``; estimated printing time (normal mode)`` and ``; total filament
  used [g]`` from the G-code and splits the extrusion by feature (``;TYPE:`` comments): the
  printed mass is the filament less what goes to support, skirt/brim and wipe tower (removed
  after printing), in proportion to the extruded length.
* :func:`slice_manifest` slices every part of a ``manifest.json`` and totals per robot (parts
  times their quantity), beside the solid-model mass the manifest records (``mass_g``: the OCC
  volume at the material's density, as if printed solid).
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import asdict, dataclass, field
from pathlib import Path

from cubot_cad.errors import InputError

#: Filament diameter assumed when the settings record none (mm; the common 1.75 mm filament).
FILAMENT_DIAMETER_MM = 1.75
#: Features whose extrusion is removed from the part after printing.
WASTE_FEATURES = ("Support material", "Support material interface", "Skirt/Brim", "Skirt", "Brim", "Wipe tower")
#: Recorded settings that are not slicer options: notes for the maker, and the orientation (and the
#: rotations giving it) that the exported STL already has on the bed.
NOTE_KEYS = ("support_reason", "notes", "orientation", "print_orientation", "print_rotation")
SLICE_TIMEOUT_S = 600.0


def slicer_path() -> str | None:
    """The PrusaSlicer executable on PATH (``prusa-slicer`` or ``prusa-slicer-console``), or None."""
    return shutil.which("prusa-slicer") or shutil.which("prusa-slicer-console")


def _num(v, key: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
        raise InputError(f"print setting {key} = {v!r} is not a length/count >= 0")
    return float(v)


def _fmt(v: float) -> str:
    return f"{v:g}"


def slicer_args(settings: dict, density_g_cm3: float) -> tuple[list[str], dict[str, str]]:
    """PrusaSlicer options for a part's recorded ``settings`` and the filament density (g/cm^3).

    Returns (CLI options, expected values of PrusaSlicer's config keys, as the G-code's settings
    block prints them), the second for :func:`check_applied`. Raises InputError for a setting that
    maps to no option."""
    if not (isinstance(density_g_cm3, (int, float)) and math.isfinite(density_g_cm3) and density_g_cm3 > 0):
        raise InputError(f"filament density {density_g_cm3!r} g/cm^3 must be > 0")
    args: list[str] = []
    want: dict[str, str] = {}

    def opt(flag: str, key: str, value: str) -> None:
        args.extend([flag, value])
        want[key] = value

    unknown = []
    s = dict(settings)
    layer = None
    for key, v in s.items():
        if key in NOTE_KEYS or key.endswith("_reason"):
            continue
        if key == "nozzle_mm":
            opt("--nozzle-diameter", "nozzle_diameter", _fmt(_num(v, key)))
        elif key == "layer_mm":
            layer = _num(v, key)
            opt("--layer-height", "layer_height", _fmt(layer))
        elif key == "first_layer_mm":
            opt("--first-layer-height", "first_layer_height", _fmt(_num(v, key)))
        elif key == "perimeters":
            opt("--perimeters", "perimeters", str(int(_num(v, key))))
        elif key == "top_bottom_layers":
            n = str(int(_num(v, key)))
            opt("--top-solid-layers", "top_solid_layers", n)
            opt("--bottom-solid-layers", "bottom_solid_layers", n)
        elif key == "top_layers":
            opt("--top-solid-layers", "top_solid_layers", str(int(_num(v, key))))
        elif key == "bottom_layers":
            opt("--bottom-solid-layers", "bottom_solid_layers", str(int(_num(v, key))))
        elif key == "infill_percent":
            p = _num(v, key)
            if p > 100:
                raise InputError(f"print setting infill_percent = {v!r} is above 100")
            opt("--fill-density", "fill_density", f"{p:g}%")
        elif key in ("infill_pattern", "fill_pattern"):
            opt("--fill-pattern", "fill_pattern", str(v))
        elif key == "supports":
            if not isinstance(v, bool):
                raise InputError(f"print setting supports = {v!r} is not true/false")
            if v:
                args.append("--support-material")
            want["support_material"] = "1" if v else "0"
        elif key == "supports_buildplate_only":
            if v:
                args.append("--support-material-buildplate-only")
            want["support_material_buildplate_only"] = "1" if v else "0"
        elif key == "brim_mm":
            opt("--brim-width", "brim_width", _fmt(_num(v, key)))
        elif key == "filament_diameter_mm":
            opt("--filament-diameter", "filament_diameter", _fmt(_num(v, key)))
        else:
            unknown.append(key)
    if unknown:
        raise InputError(f"print settings {', '.join(sorted(unknown))} map to no PrusaSlicer option "
                         "(cubot_cad.checks.slicing.slicer_args)")
    if "fill_density" in want and float(want["fill_density"].rstrip("%")) >= 100 and "fill_pattern" not in want:
        # solid: PrusaSlicer refuses its default sparse pattern at 100 % ("not supposed to work at 100%
        # density") and fills solid layers rectilinear itself, so a recorded 100 % means that
        opt("--fill-pattern", "fill_pattern", "rectilinear")
    if layer is not None and "first_layer_height" not in want:  # the first layer as recorded, not the 0.35 default
        opt("--first-layer-height", "first_layer_height", _fmt(layer))
    if "filament_diameter" not in want:
        opt("--filament-diameter", "filament_diameter", _fmt(FILAMENT_DIAMETER_MM))
    opt("--filament-density", "filament_density", _fmt(float(density_g_cm3)))
    return args, want


_TIME = re.compile(r"(?:(\d+)d\s*)?(?:(\d+)h\s*)?(?:(\d+)m\s*)?(?:(\d+)s)?")


def parse_duration_s(text: str) -> float:
    """``"1d 2h 3m 4s"`` / ``"28m 2s"`` / ``"45s"`` (PrusaSlicer's estimate) -> seconds."""
    t = text.strip()
    m = _TIME.fullmatch(t)
    if not t or m is None or not any(m.groups()):
        raise ValueError(f"not a PrusaSlicer duration: {text!r}")
    d, h, mi, s = (int(g) if g else 0 for g in m.groups())
    return float(((d * 24 + h) * 60 + mi) * 60 + s)


@dataclass
class GcodeStats:
    """What the G-code says: estimated print time (s, normal mode), filament used (g, mm), the
    share of the extruded length per feature, and the printed mass (g) without the waste features."""

    print_time_s: float
    print_time: str
    filament_g: float
    filament_mm: float | None
    extruded_by_feature_mm: dict[str, float]
    waste_fraction: float
    printed_mass_g: float
    config: dict[str, str] = field(default_factory=dict)


_CFG = re.compile(r"^;\s*([a-z0-9_]+)\s*=\s*(.*)$")


def read_config(text: str) -> dict[str, str]:
    """The ``; key = value`` settings block PrusaSlicer appends to the G-code (lower-case keys)."""
    cfg = {}
    for line in text.splitlines()[-2000:]:
        m = _CFG.match(line.strip())
        if m:
            cfg[m.group(1)] = m.group(2).strip()
    return cfg


def parse_gcode(text: str) -> GcodeStats:
    """Print time, filament and printed mass from PrusaSlicer G-code (see the module docstring).
    ValueError when the header lines are missing (no estimate: not PrusaSlicer's G-code)."""
    t = re.search(r"^;\s*estimated printing time \(normal mode\)\s*=\s*(.+)$", text, re.M)
    g = re.search(r"^;\s*total filament used \[g\]\s*=\s*([0-9.]+)", text, re.M) or \
        re.search(r"^;\s*filament used \[g\]\s*=\s*([0-9.]+)", text, re.M)
    mm = re.search(r"^;\s*filament used \[mm\]\s*=\s*([0-9.]+)", text, re.M)
    if t is None or g is None:
        raise ValueError("no '; estimated printing time (normal mode)' / '; total filament used [g]' line: "
                         "not PrusaSlicer G-code")
    relative = False
    e_prev = 0.0
    feature = "unknown"
    by: dict[str, float] = {}
    for line in text.splitlines():
        if line.startswith(";TYPE:"):
            feature = line[6:].strip()
            continue
        if not line or line[0] == ";":
            continue
        code = line.split(";", 1)[0].split()
        if not code:
            continue
        c = code[0]
        if c == "M83":
            relative = True
        elif c == "M82":
            relative = False
        elif c == "G92":
            for w in code[1:]:
                if w[0] == "E":
                    e_prev = float(w[1:])
        elif c in ("G1", "G0", "G2", "G3"):
            e = None
            xy = False
            for w in code[1:]:
                if w[0] == "E":
                    e = float(w[1:])
                elif w[0] in "XYIJ":
                    xy = True
            if e is None:
                continue
            d = e if relative else e - e_prev
            if not relative:
                e_prev = e
            if xy and d > 0:  # deposits; E-only moves are retracts/unretracts, negative XY ones wipes
                by[feature] = by.get(feature, 0.0) + d
    total = sum(by.values())
    waste = sum(v for k, v in by.items() if k in WASTE_FEATURES)
    frac = waste / total if total > 0 else 0.0
    fil_g = float(g.group(1))
    return GcodeStats(print_time_s=parse_duration_s(t.group(1)), print_time=t.group(1).strip(), filament_g=fil_g,
                      filament_mm=float(mm.group(1)) if mm else None,
                      extruded_by_feature_mm={k: round(v, 3) for k, v in sorted(by.items())},
                      waste_fraction=frac, printed_mass_g=fil_g * (1.0 - frac), config=read_config(text))


def _same(a: str, b: str) -> bool:
    try:
        return math.isclose(float(a.rstrip("%")), float(b.rstrip("%")), rel_tol=1e-6, abs_tol=1e-9) and \
            a.endswith("%") == b.endswith("%")
    except ValueError:
        return a == b


def check_applied(want: dict[str, str], config: dict[str, str]) -> list[str]:
    """The recorded settings the slicer did not apply: ``"key: wanted X, G-code says Y"``."""
    bad = []
    for k, v in want.items():
        got = config.get(k)
        if got is None or not _same(v, got.split(",")[0].strip()):
            bad.append(f"{k}: wanted {v}, G-code says {got}")
    return bad


@dataclass
class SliceResult:
    """One slice: ``ok``, the G-code numbers (time s, filament g, printed mass g), the options used."""

    ok: bool
    print_time: str | None = None
    print_time_s: float | None = None
    filament_g: float | None = None
    printed_mass_g: float | None = None
    waste_fraction: float | None = None
    args: list[str] = field(default_factory=list)
    detail: str = ""

    def summary(self) -> dict:
        return asdict(self)


def _cache_key(path: Path, args: list[str], exe: str) -> str:
    import hashlib

    h = hashlib.sha256()
    h.update(Path(path).read_bytes())
    h.update("\0".join([*args, os.path.realpath(exe), str(os.path.getmtime(exe))]).encode())
    return h.hexdigest()


def slice_stl(path: str | os.PathLike, settings: dict, density_g_cm3: float,
              timeout_s: float = SLICE_TIMEOUT_S, exe: str | None = None,
              cache_dir: str | os.PathLike | None = None) -> SliceResult:
    """Slice ``path`` with ``settings`` (a manifest part's ``print_settings``) and the filament
    density (g/cm^3); check that the G-code carries the settings; return its numbers.

    ``cache_dir``: keep each successful result there under the hash of the STL's bytes, the options
    and the slicer binary, and return it instead of slicing again (a whole export takes minutes)."""
    exe = exe or slicer_path()
    if exe is None:
        return SliceResult(False, detail="prusa-slicer not on PATH (Debian: apt-get install prusa-slicer)")
    try:
        args, want = slicer_args(settings, density_g_cm3)
    except InputError as exc:
        return SliceResult(False, detail=str(exc))
    if cache_dir is not None:
        import json

        from cubot_cad.atomic import write_json

        entry = Path(cache_dir) / f"{_cache_key(Path(path), args, exe)}.json"
        if entry.is_file():
            try:
                return SliceResult(**json.loads(entry.read_text(encoding="utf-8")))
            except (ValueError, TypeError):
                pass  # a bad entry is sliced again and overwritten
        res = slice_stl(path, settings, density_g_cm3, timeout_s, exe)
        if res.ok:
            write_json(entry, res.summary())
        return res
    with tempfile.TemporaryDirectory(prefix="slice-") as td:
        gcode = Path(td) / "out.gcode"
        cmd = [exe, "--export-gcode", str(path), "--output", str(gcode), *args]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            return SliceResult(False, args=args, detail=f"prusa-slicer timed out after {timeout_s:g} s")
        if proc.returncode != 0 or not gcode.exists():
            lines = (proc.stderr or proc.stdout or "").strip().splitlines()
            return SliceResult(False, args=args, detail=lines[-1] if lines else f"exit {proc.returncode}")
        text = gcode.read_text(errors="replace")
    try:
        st = parse_gcode(text)
    except ValueError as exc:
        return SliceResult(False, args=args, detail=str(exc))
    bad = check_applied(want, st.config)
    if bad:
        return SliceResult(False, args=args, detail="settings not applied by the slicer: " + "; ".join(bad))
    return SliceResult(True, st.print_time, st.print_time_s, round(st.filament_g, 3), round(st.printed_mass_g, 3),
                       round(st.waste_fraction, 4), args, "sliced with the recorded settings")


def density_g_cm3(manifest: dict) -> float:
    """The manifest's material density in g/cm^3 (it records kg/m^3)."""
    rho = manifest.get("density_kg_m3")
    if not isinstance(rho, (int, float)) or rho <= 0:
        raise InputError("manifest has no density_kg_m3 > 0")
    return float(rho) / 1000.0


def part_entry(manifest: dict, rel_file: str) -> dict | None:
    """The manifest entry whose ``file`` is ``rel_file`` (posix path relative to the export), or None."""
    rel = Path(rel_file).as_posix()
    return next((p for p in manifest.get("parts", []) if p.get("file") == rel), None)


def slice_manifest(export_dir: str | os.PathLike, robots: tuple[str, ...] | None = None,
                   progress=None, cache_dir: str | os.PathLike | None = None) -> dict:
    """Slice every part of the export at ``export_dir`` with its recorded settings.

    Returns ``{"parts": [...], "robots": {...}}``: per part its file, quantity, ``per`` (robot or
    pier), the slice (print_time_s, filament_g, printed_mass_g) and ``solid_mass_g`` (the manifest's
    solid-model mass); per robot the totals over its per-robot parts times their quantities
    (``print_time_s``, ``filament_g``, ``printed_mass_g``, ``solid_mass_g``, and
    ``solid_over_printed_pct``: how much heavier the solid model is than the print), and
    ``complete``: every part sliced."""
    from cubot_cad.manifest import load_manifest

    root = Path(export_dir)
    man = load_manifest(root)
    rho = density_g_cm3(man)
    parts = [p for p in man["parts"] if p.get("file") and (robots is None or p["robot"] in robots)]
    it = progress(parts, "slice", len(parts)) if progress else parts
    rows = []
    for p in it:
        res = slice_stl(root / p["file"], p.get("print_settings", {}), rho, cache_dir=cache_dir)
        rows.append({"robot": p["robot"], "part": p["part"], "file": p["file"], "quantity": p["quantity"],
                     "per": p.get("per", "robot"), "solid_mass_g": p["mass_g"],
                     "print_settings": p.get("print_settings", {}), "slice": res.summary()})
    return {"material": man.get("material"), "density_g_cm3": rho, "parts": rows, "robots": robot_totals(rows)}


def slice_into_manifest(manifest: dict, root: str | os.PathLike, progress=None,
                        cache_dir: str | os.PathLike | None = None) -> dict:
    """Add the slicer's numbers to a manifest being written (the export's hook): per part
    ``slice`` (print_time_s, filament_g, printed_mass_g, ok, the options used), per robot
    ``slicing`` (:func:`robot_totals`), and ``slicer`` (which binary). The STLs are read from
    ``root`` (the staging directory the manifest goes into). Returns ``manifest``."""
    exe = slicer_path()
    rho = density_g_cm3(manifest)
    parts = [p for p in manifest["parts"] if p.get("file")]
    it = progress(parts, "slice", len(parts)) if progress else parts
    rows = []
    for p in it:
        res = slice_stl(Path(root) / p["file"], p.get("print_settings", {}), rho, exe=exe, cache_dir=cache_dir)
        p["slice"] = res.summary()
        rows.append({"robot": p["robot"], "quantity": p["quantity"], "per": p.get("per", "robot"),
                     "solid_mass_g": p["mass_g"], "slice": p["slice"]})
    for name, t in robot_totals(rows).items():
        manifest.setdefault("robots", {}).setdefault(name, {})["slicing"] = t
    manifest["slicer"] = exe
    manifest["slicer_version"] = slicer_version(exe)
    return manifest


def slicer_version(exe: str | None = None) -> str | None:
    """The slicer's version line (``PrusaSlicer-2.5.0+...``) from ``--help``, or None."""
    exe = exe or slicer_path()
    if exe is None:
        return None
    try:
        proc = subprocess.run([exe, "--help"], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return None
    for line in (proc.stdout or "").splitlines():
        if line.startswith("PrusaSlicer"):
            return line.split(" based on")[0].strip()
    return None


def printed_fractions(manifest: dict) -> dict[str, dict[str, float]]:
    """Per robot whose every per-robot part sliced: part name -> the slicer's printed mass over the
    solid model's (what :meth:`cubot_cad.robots.base.Robot.mass_properties` scales each part by). A
    robot with any part unsliced is left out (its record keeps the solid model, and says so)."""
    out: dict[str, dict[str, float]] = {}
    bad: set[str] = set()
    for p in manifest.get("parts", []):
        if p.get("per", "robot") != "robot":
            continue
        s = p.get("slice") or {}
        solid = float(p.get("mass_g") or 0.0)
        if not s.get("ok") or not s.get("printed_mass_g") or solid <= 0:
            bad.add(p["robot"])
            continue
        out.setdefault(p["robot"], {})[p["part"]] = float(s["printed_mass_g"]) / solid
    return {r: f for r, f in out.items() if r not in bad}


def robot_totals(rows: list[dict]) -> dict:
    """Per robot: totals over its per-robot parts (quantities counted), see :func:`slice_manifest`."""
    out: dict[str, dict] = {}
    for r in rows:
        if r.get("per", "robot") != "robot":
            continue
        t = out.setdefault(r["robot"], {"print_time_s": 0.0, "filament_g": 0.0, "printed_mass_g": 0.0,
                                        "solid_mass_g": 0.0, "parts": 0, "sliced": 0})
        q = int(r["quantity"])
        t["parts"] += q
        t["solid_mass_g"] += q * float(r["solid_mass_g"])
        s = r["slice"]
        if s.get("ok"):
            t["sliced"] += q
            t["print_time_s"] += q * s["print_time_s"]
            t["filament_g"] += q * s["filament_g"]
            t["printed_mass_g"] += q * s["printed_mass_g"]
    for t in out.values():
        t["complete"] = t["sliced"] == t["parts"]
        for k in ("print_time_s", "filament_g", "printed_mass_g", "solid_mass_g"):
            t[k] = round(t[k], 3)
        t["solid_over_printed_pct"] = (round(100.0 * (t["solid_mass_g"] / t["printed_mass_g"] - 1.0), 1)
                                       if t["complete"] and t["printed_mass_g"] > 0 else None)
    return out


def duration_text(seconds: float) -> str:
    """Seconds as ``"5h 12m"`` (or ``"12m 5s"`` under an hour)."""
    s = int(round(seconds))
    h, m = divmod(s // 60, 60)
    return f"{h}h {m:02d}m" if h else f"{m}m {s % 60:02d}s"


__all__ = ["FILAMENT_DIAMETER_MM", "GcodeStats", "SliceResult", "WASTE_FEATURES", "check_applied", "density_g_cm3",
           "duration_text", "parse_duration_s", "parse_gcode", "part_entry", "printed_fractions", "read_config",
           "robot_totals", "slicer_version",
           "slice_into_manifest", "slice_manifest", "slice_stl", "slicer_args", "slicer_path"]
