"""`voidcross doctor`: what is installed and usable, and what is missing without it."""

from __future__ import annotations

import argparse
import importlib
import importlib.metadata as md
import platform
import shutil
import subprocess
import time

from ..output import emit

#: (name, import or command, distribution, feature it enables)
CHECKS = (
    ("numpy", "numpy", "numpy", "everything (core)"),
    ("scipy", "scipy", "scipy", "neighbour queries, fitting (core)"),
    ("matplotlib", "matplotlib", "matplotlib", "plots, snapshots, report figures (core)"),
    ("cadquery/OCP", "cadquery", "cadquery", "`voidcross cad`: parametric robots, STL/STEP/3MF export"),
    ("trimesh", "trimesh", "trimesh", "`voidcross cad check`: watertight checks, thin-wall probe"),
    ("manifold3d", "manifold3d", "manifold3d", "`voidcross cad check`: manifold status, interference"),
    ("exudyn", "exudyn", "exudyn", "`voidcross fem`: multibody deflection, derived thresholds"),
    ("dask.distributed", "distributed", "distributed", "`voidcross sweep --executor dask`: sweeps beyond one machine"),
    ("numba", "numba", "numba", "faster swarm_sim kernels (numpy fallback otherwise)"),
    ("imageio-ffmpeg", "imageio_ffmpeg", "imageio-ffmpeg", "`voidcross sim run --video x.mp4` (GIF works without)"),
    ("hypothesis", "hypothesis", "hypothesis", "property-based tests (dev)"),
    ("pytest-benchmark", "pytest_benchmark", "pytest-benchmark", "`make bench` (dev)"),
    ("pyarrow", "pyarrow", "pyarrow", "`voidcross sweep export --to runs.parquet` (in [api] and [all]; CSV works without)"),
)
TOOLS = (
    ("prusa-slicer", "prusa-slicer", "`voidcross cad check`: slicing, print time and filament (apt install prusa-slicer)"),
    ("chromium", "chromium", "report page test in a headless browser (apt install chromium)"),
)


def _check_module(name: str, module: str, dist: str, feature: str) -> dict:
    t0 = time.perf_counter()
    try:
        mod = importlib.import_module(module)
    except Exception as exc:  # ImportError or a broken binary
        return {"name": name, "ok": False, "version": None, "feature": feature,
                "detail": f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"}
    try:
        version = md.version(dist)
    except md.PackageNotFoundError:
        version = getattr(mod, "__version__", "?")
    detail = f"import {time.perf_counter() - t0:.2f} s"
    if module == "imageio_ffmpeg":
        try:
            detail = f"ffmpeg at {mod.get_ffmpeg_exe()}"
        except Exception as exc:  # binary missing on this platform
            return {"name": name, "ok": False, "version": version, "feature": feature, "detail": str(exc)}
    if module == "cadquery":
        try:
            detail += f", OCP {md.version('cadquery-ocp')}"
        except md.PackageNotFoundError:
            pass
    return {"name": name, "ok": True, "version": version, "feature": feature, "detail": detail}


def _check_tool(name: str, command: str, feature: str) -> dict:
    path = shutil.which(command)
    if not path:
        return {"name": name, "ok": False, "version": None, "feature": feature, "detail": "not on PATH"}
    version = "?"
    try:
        res = subprocess.run([path, "--version"], capture_output=True, text=True, timeout=30)
        version = clean_version(name, (res.stdout or "") + "\n" + (res.stderr or ""))
    except (OSError, subprocess.TimeoutExpired):
        pass
    return {"name": name, "ok": True, "version": version, "feature": feature, "detail": path}


def clean_version(name: str, text: str) -> str:
    """The version number in a tool's ``--version`` output (skipping log lines such as
    PrusaSlicer's ``[info]`` ones): from the line naming the tool, else the first number seen."""
    import re

    num = re.compile(r"\b(\d+\.\d+(?:\.\d+)*)")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("[")]
    key = name.split("-")[0].lower()
    for ln in lines:
        if key in ln.lower() and num.search(ln):
            return num.search(ln).group(1)
    for ln in lines:
        if num.search(ln):
            return num.search(ln).group(1)
    return "?"


def diagnose() -> dict:
    checks = [_check_module(*c) for c in CHECKS] + [_check_tool(*t) for t in TOOLS]
    return {"python": platform.python_version(), "platform": platform.platform(), "checks": checks}


def run(args: argparse.Namespace) -> int:
    report = diagnose()
    lines = [f"voidcross doctor (Python {report['python']}, {report['platform']})"]
    for c in report["checks"]:
        mark = "ok  " if c["ok"] else "MISS"
        ver = c["version"] or "-"
        lines.append(f"  [{mark}] {c['name']:<17} {ver:<22} {c['detail']}")
        if not c["ok"]:
            lines.append(f"         missing: {c['feature']}")
    emit(args, report, "\n".join(lines))
    return 0


def register(sub, common) -> None:
    p = sub.add_parser("doctor", parents=[common], help="what is installed and usable",
                       description="List the optional libraries and tools voidcross uses, their versions, "
                                   "and what is missing without each.",
                       epilog="examples:\n  voidcross doctor\n  voidcross doctor --json",
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.set_defaults(func=run)
