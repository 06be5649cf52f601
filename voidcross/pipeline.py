"""The end-to-end pipeline: CAD export -> structure table -> simulations -> report.

Each stage is provided by its command module as
``pipeline_stage(out: Path, ctx: dict) -> str``: it writes under ``out``,
reads what earlier stages put in ``ctx`` (``robot_properties``, ``limits``,
``db`` paths) and adds its own outputs, and returns a one-line summary. A
stage whose package is not built yet, or whose optional dependency is
missing, reports that in one honest line and the others still run on the
packaged defaults.
"""

from __future__ import annotations

import importlib
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

STAGES = (
    ("cad", "CAD export and mass properties", "voidcross.commands.cad"),
    ("fem", "structure study and selection table", "voidcross.commands.fem"),
    ("sim", "swarm simulations (small sweep)", "voidcross.commands.sweep"),
    ("thesis", "the thesis's Chapter 4 experiments (1 run per cell)", "voidcross.commands.reproduce"),
    ("report", "report", "voidcross.commands.report"),
)


class StageUnavailable(Exception):
    """Raised by a stage that cannot run here (missing optional dependency); message says why."""


@dataclass
class StageResult:
    name: str
    status: str  # "ok" | "skipped" | "failed"
    summary: str
    seconds: float


def run_pipeline(out: Path, debug: bool = False, echo=print, only: tuple[str, ...] | None = None) -> list[StageResult]:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    ctx: dict = {"out": out}
    results: list[StageResult] = []
    stages = [s for s in STAGES if only is None or s[0] in only]
    for i, (name, title, module_name) in enumerate(stages, 1):
        prefix = f"[{i}/{len(stages)}] {title}"
        t0 = time.perf_counter()
        module = importlib.import_module(module_name)
        stage = getattr(module, "pipeline_stage", None)
        if stage is None:
            res = StageResult(name, "skipped", getattr(module, "NOT_BUILT", "not built yet"), 0.0)
        else:
            try:
                summary = stage(out / name, ctx)
                res = StageResult(name, "ok", summary, time.perf_counter() - t0)
            except StageUnavailable as exc:
                res = StageResult(name, "skipped", str(exc), time.perf_counter() - t0)
            except Exception as exc:
                if debug:
                    traceback.print_exc()
                res = StageResult(name, "failed", f"{type(exc).__name__}: {exc}", time.perf_counter() - t0)
        echo(f"{prefix}: {res.status} ({res.seconds:.1f} s) - {res.summary}")
        results.append(res)
    return results
