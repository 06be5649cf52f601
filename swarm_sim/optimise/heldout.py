"""Held-out evaluation and robustness: the tuned rules against the thesis's rules on the same new
seeds, on Chapter 4's whole grid (the training cells included, so the crossing boundary is read
at every width; the "unseen cells" figures leave the training cells out).

A tuned rule set is *accepted* only when, on every case and width, its observed crossing
boundary (the smallest swarm of the grid that crossed in every run, every smaller one retreating
in every run) is the counting rule's, as the thesis's rules' is, and it loses no robot. A faster
rule set that crosses with a swarm the structure cannot hold, or gives up where it should cross,
is rejected whatever its time.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field

import numpy as np

from ..experiments.thesis_grid import CHAPTER4, observed_boundary, rule_swarm
from ..sweeps import SweepSpec
from ..sweeps.executors import make_executor
from ..sweeps.sweep import DEFAULT_RUN_FN, limits_digest
from .runs import Progress, ensure_runs, stored_rows
from .study import HELDOUT_OFFSET, StudyConfig

#: the robustness scenarios: overrides added to both rule sets. ``faults``: the failure rate of
#: the thesis's future work (a drive failure rate per robot-hour); ``obstacles``: Algorithm 3's
#: five obstacles (case B's preset) placed in every case's arena that has none
FAULTS = "drive:1.7/h"
BOOTSTRAP = 2000


def _median(xs) -> float | None:
    return float(np.median(xs)) if len(xs) else None


def _mean(xs) -> float | None:
    return float(np.mean(xs)) if len(xs) else None


def summarise(rows: list[dict], limits: str, preset: str, unseen: set[tuple[int, int]] | None = None) -> dict:
    """One case's runs: crossings, losses, times (simulated s) and the boundary per width."""
    ok = [r for r in rows if r["status"] == "ok"]
    crossed = [r for r in ok if r["success"]]
    tt = [float(r["t_t"]) for r in crossed]
    cells: dict = {}
    for r in ok:
        cells.setdefault((int(r["robots"]), int(r["void_width"])), []).append(bool(r["success"]))
    widths = sorted({w for _, w in cells})
    bounds = {}
    for w in widths:
        b = observed_boundary({k: v for k, v in cells.items() if k[1] == w}, w)
        sizes = sorted(n for n, ww in cells if ww == w)
        rule = rule_swarm(preset, w, limits, robots=sizes[0])
        # a rule above the grid's largest swarm (case A: N <= 10, 3w + 2 = 11 at 3 widths): no
        # swarm of the grid should cross, so none crossing is the boundary held
        b["expected"] = rule if rule <= sizes[-1] else None
        b["rule"] = rule
        b["ok"] = (b["observed"] == b["expected"]
                   and (b["below_all_retreat"] or b["expected"] is None and not any(any(v) for k, v in cells.items()
                                                                                   if k[1] == w)))
        bounds[str(w)] = b
    timeouts = sum(bool(json.loads(r["result_json"]).get("timed_out")) for r in ok)
    out = {"runs": len(rows), "errors": len(rows) - len(ok), "crossed": len(crossed),
           "lost": sum(int(r["robots_lost"] or 0) for r in ok), "timeouts": timeouts,
           "Tt_median_s": _median(tt), "Tt_mean_s": _mean(tt),
           "Ta_mean_s": _mean([float(r["t_a"]) for r in crossed if r["t_a"] is not None]),
           "Td_mean_s": _mean([float(r["t_d"]) for r in ok if not r["success"] and r["t_d"] is not None]),
           "boundary": bounds, "Tt": tt}
    if unseen is not None:
        out["Tt_unseen_median_s"] = _median([float(r["t_t"]) for r in crossed
                                             if (int(r["robots"]), int(r["void_width"])) in unseen])
    return out


def _ratio_ci(a: list[float], b: list[float], seed: int = 0) -> list[float] | None:
    """95 % bootstrap interval of median(a) / median(b) (resampling runs, a fixed seed)."""
    if not a or not b:
        return None
    rng = np.random.default_rng(seed)
    a, b = np.asarray(a), np.asarray(b)
    ia = rng.integers(0, len(a), (BOOTSTRAP, len(a)))
    ib = rng.integers(0, len(b), (BOOTSTRAP, len(b)))
    r = np.median(a[ia], axis=1) / np.median(b[ib], axis=1)
    return [float(np.percentile(r, 2.5)), float(np.percentile(r, 97.5))]


@dataclass
class Comparison:
    """Tuned against the thesis's rules: per case summaries, the gain and the verdict."""

    tuned_params: dict
    runs_per_cell: int
    seed0: int
    tuned: dict
    thesis: dict
    gain_pct: dict = field(default_factory=dict)
    ratio_ci95: dict = field(default_factory=dict)
    pooled_gain_pct: float | None = None
    accepted: bool = False
    reasons: list = field(default_factory=list)
    new_runs: int = 0

    def to_dict(self) -> dict:
        d = asdict(self)
        for side in ("tuned", "thesis"):
            for c in d[side].values():
                c.pop("Tt", None)
        return d


def _grid_specs(cfg: StudyConfig, overrides: dict, runs: int, extra: dict | None = None,
                cases=None) -> list[SweepSpec]:
    ov = {**overrides, **(extra or {})}
    return [SweepSpec(CHAPTER4[c][0], tuple(CHAPTER4[c][1]), tuple(CHAPTER4[c][2]), runs=runs, limits=cfg.limits,
                      seed0=cfg.seed + HELDOUT_OFFSET, overrides=ov) for c in (cases or cfg.cases)]


def compare(tuned: dict, cfg: StudyConfig, db, runs: int = 10, executor: str = "local", workers: int | None = None,
            address: str | None = None, run_fn=None, progress: Progress | None = None) -> Comparison:
    """Run (or read) the held-out grid for ``tuned`` and for the thesis's rules; compare."""
    run_fn = run_fn or DEFAULT_RUN_FN
    digest = limits_digest(cfg.limits)
    train = {(c.case, c.robots, c.void_width) for c in cfg.cells()}
    specs_t, specs_b = _grid_specs(cfg, tuned, runs), _grid_specs(cfg, {}, runs)
    with make_executor(executor, workers=workers, address=address) as ex:
        new = ensure_runs(specs_b + specs_t, db, ex, run_fn, digest, progress,
                          f"held-out: {runs} runs per cell, thesis's and tuned rules")
    rows_b, rows_t = stored_rows(specs_b, db, digest), stored_rows(specs_t, db, digest)
    cmp = Comparison(tuned, runs, cfg.seed + HELDOUT_OFFSET, {}, {}, new_runs=new)
    all_t, all_b = [], []
    for case, rb, rt in zip(cfg.cases, rows_b, rows_t, strict=True):
        preset, sizes, widths, _ = CHAPTER4[case]
        unseen = {(n, w) for n in sizes for w in widths if (case, n, w) not in train}
        cmp.thesis[case] = summarise(rb, cfg.limits, preset, unseen)
        cmp.tuned[case] = summarise(rt, cfg.limits, preset, unseen)
        a, b = cmp.tuned[case]["Tt"], cmp.thesis[case]["Tt"]
        all_t += a
        all_b += b
        if a and b:
            cmp.gain_pct[case] = 100.0 * (1.0 - np.median(a) / np.median(b))
            cmp.ratio_ci95[case] = _ratio_ci(a, b)
        for w, bt in cmp.tuned[case]["boundary"].items():
            bb = cmp.thesis[case]["boundary"][w]
            if not bt["ok"] and (bb["ok"] or bt["observed"] != bb["observed"]):
                cmp.reasons.append(f"case {case} at {w} widths: the boundary is {bt['observed']} "
                                   f"(rule {bt['rule']}, thesis's rules {bb['observed']})"
                                   + ("" if bt["below_all_retreat"] else ", a smaller swarm crossed"))
        if cmp.tuned[case]["lost"]:
            cmp.reasons.append(f"case {case}: {cmp.tuned[case]['lost']} robots lost")
    if all_t and all_b:
        cmp.pooled_gain_pct = 100.0 * (1.0 - np.median(all_t) / np.median(all_b))
        cmp.ratio_ci95["pooled"] = _ratio_ci(all_t, all_b)
    cmp.accepted = not cmp.reasons
    return cmp


def obstacles_of(preset: str = "case-b") -> list[list[float]]:
    """Algorithm 3's obstacles as the thesis placed them (case B's preset), ``[[x, y, r] cm]``."""
    from ..runner import resolve_params

    return [list(o) for o in resolve_params(preset, 9, 3).obstacles]


def robustness(tuned: dict, cfg: StudyConfig, db, runs: int = 10, executor: str = "local",
               workers: int | None = None, address: str | None = None, run_fn=None,
               progress: Progress | None = None, faults: str = FAULTS) -> dict:
    """Both rule sets on the training cells' crossing swarms (held-out seeds) under faults, and
    with obstacles in the cases that have none; per scenario and case: crossing rate of the
    runs that should cross, median Tt, robots lost."""
    run_fn = run_fn or DEFAULT_RUN_FN
    digest = limits_digest(cfg.limits)
    no_obstacles = [c for c in cfg.cases if not obstacles_in(CHAPTER4[c][0])]
    scenarios = {f"faults {faults}": ({"faults": faults}, list(cfg.cases)),
                 "obstacles (Algorithm 3's five)": ({"obstacles": obstacles_of()}, no_obstacles)}
    cells = cfg.cells()
    out: dict = {}
    new = 0
    with make_executor(executor, workers=workers, address=address) as ex:
        for name, (extra, cases) in scenarios.items():
            if not cases:
                continue
            rows_by = {}
            for side, ov in (("thesis", {}), ("tuned", tuned)):
                specs = []
                for case in cases:
                    pts = tuple((c.robots, c.void_width) for c in cells if c.case == case
                                and c.robots >= rule_swarm(c.preset, c.void_width, cfg.limits, robots=c.robots))
                    specs.append(SweepSpec(CHAPTER4[case][0], points=pts, runs=runs, limits=cfg.limits,
                                           seed0=cfg.seed + HELDOUT_OFFSET, overrides={**ov, **extra}))
                new += ensure_runs(specs, db, ex, run_fn, digest, progress, f"robustness: {name}, {side} rules")
                rows_by[side] = dict(zip(cases, stored_rows(specs, db, digest), strict=True))
            out[name] = {side: {case: _robust_row(rows) for case, rows in by.items()} for side, by in rows_by.items()}
    out["new_runs"] = new
    return out


def obstacles_in(preset: str) -> bool:
    from ..runner import resolve_params

    return bool(resolve_params(preset, 9, 1).obstacles)


def _robust_row(rows: list[dict]) -> dict:
    ok = [r for r in rows if r["status"] == "ok"]
    crossed = [r for r in ok if r["success"]]
    return {"runs": len(rows), "errors": len(rows) - len(ok), "crossed": len(crossed),
            "rate": len(crossed) / len(rows) if rows else 0.0,
            "Tt_median_s": _median([float(r["t_t"]) for r in crossed]),
            "lost": sum(int(r["robots_lost"] or 0) for r in ok)}
