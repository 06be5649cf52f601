"""Thresholds with an uncertainty band: what a population of printed robots spans (SI; issue 38.3).

The table's thresholds are for the robot as drawn. A print is not the drawing: its clearances
come out of the printer's dimensional accuracy, its modulus is below the moulded material's, the
couplings' FE idealises a printed part, and the robot weighs what the slicer and the parts list
only estimate. :data:`FACTORS` states one distribution per input (each with where it comes
from); :func:`band` draws a Latin hypercube over them (``scipy.stats.qmc``, seeded), re-derives
each structure's threshold per sample with the table's own search (:func:`structure_fem.analysis.study.min_rows`,
the same static solves, through the solve cache), and reports per structure the threshold that
5 %, 50 % and 95 % of the samples reach or exceed:

* ``p5``: the width **95 % of printed robots span** (the band's lower end; ``--pick p5``, the
  default with ``--band``),
* ``p50``: the median print, ``p95``: the best 5 %.

**Criterion.** Each sample's threshold is the widest void whose static tip at the longest
cantilever, plus the nominal robot's launch allowance at that width (the dynamic criterion's
overshoot, integrated once at the nominal inputs; a width beyond the ones integrated takes the
widest one's allowance), stays within the clearance, with the rows the sample needs to stand.
The launch allowance is not re-integrated per sample: it is a few percent of the tip and its
own scatter is second order (stated in every record).

**Cost.** A sample searches from the nominal threshold up or down (the tip grows with the
width), so a structure costs a few width evaluations per sample; the banded structures are the
line and the structures of the selection band (those the swarm uses), not every candidate.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace

import numpy as np

from structure_fem.analysis.study import Curve, Derivation, StudyInputs, min_rows
from structure_fem.errors import InputError, SolverFailure


@dataclass(frozen=True)
class Factor:
    """One uncertain input as a multiplier on the record's value: ``kind`` ``normal`` (mean,
    sd, truncated at ``low``), ``lognormal`` (median 1, ``sd`` of the log) or ``triangular``
    (``low``, ``mode``, ``high``)."""

    name: str
    kind: str
    mean: float = 1.0
    sd: float = 0.0
    low: float = 0.0
    mode: float = 1.0
    high: float = 1.0
    applies_to: str = ""
    source: str = ""

    def ppf(self, u: np.ndarray) -> np.ndarray:
        from scipy import stats

        u = np.clip(np.asarray(u, dtype=float), 1e-9, 1 - 1e-9)
        if self.kind == "normal":
            a = (self.low - self.mean) / self.sd
            return stats.truncnorm.ppf(u, a, np.inf, loc=self.mean, scale=self.sd)
        if self.kind == "lognormal":
            return np.exp(stats.norm.ppf(u) * self.sd)
        if self.kind == "triangular":
            c = (self.mode - self.low) / (self.high - self.low)
            return stats.triang.ppf(u, c, loc=self.low, scale=self.high - self.low)
        raise InputError(f"factor {self.name}: unknown distribution {self.kind!r}")

    def describe(self) -> str:
        if self.kind == "normal":
            d = f"normal x{self.mean:g} sd {self.sd:g} (>= {self.low:g})"
        elif self.kind == "lognormal":
            d = f"lognormal median x1, sd of ln {self.sd:g}"
        else:
            d = f"triangular x{self.low:g} / {self.mode:g} / {self.high:g}"
        return f"{self.name}: {d} on {self.applies_to} ({self.source})"


#: The band's inputs and their distributions (multipliers on the record's values).
FACTORS = (
    Factor("play", "normal", mean=1.0, sd=0.25, low=0.0,
           applies_to="every coupling's play (pitch dead band and per-feature translational play)",
           source="assumption: an FDM printer holds a dimension to about +-0.1 mm (2 sd) when calibrated (Prusa "
                  "MK3-class); per side that is +-0.05 mm on the CAD's 0.2 mm clearance, sd 25 % of the play"),
    Factor("stiffness", "lognormal", sd=0.2,
           applies_to="every coupling's stiffness beyond the modulus (the FE's idealisation: bonded interfaces, "
                      "solid walls where the print has perimeters and infill)",
           source="assumption: sd of ln 0.2 (a factor 1.5 at 2 sd) for an FE of a printed part against a test; "
                  "`fem calibrate --measured` replaces it with a measurement"),
    Factor("modulus", "triangular", low=0.65, mode=0.85, high=1.0,
           applies_to="the print's Young's modulus: every coupling's stiffness and the bodies' bending",
           source="assumption from the printed-ABS literature (Ahn et al. 2002, Rapid Prototyping J. 8(4): FDM "
                  "ABS at 65-72 % of moulded strength, the modulus knocked down alike by raster and layer "
                  "bonding); the record's E is the moulded value"),
    Factor("mass", "normal", mean=1.0, sd=0.03, low=0.5,
           applies_to="each robot's mass and inertia",
           source="assumption: the record's mass is the slicer's printed grams and the parts list; a built robot "
                  "(wires, glue, battery variant) within +-6 % (2 sd)"),
)

#: Latin-hypercube samples per band and the seed (a band is reproducible).
DEFAULT_SAMPLES = 20
DEFAULT_SEED = 38
#: The quantiles reported (percent): the threshold that (100 - q) % of the samples reach.
QUANTILES = (5, 50, 95)


def samples(n: int = DEFAULT_SAMPLES, seed: int = DEFAULT_SEED, factors=FACTORS) -> np.ndarray:
    """``(n, len(factors))`` multipliers: a Latin hypercube mapped through each factor's ppf."""
    from scipy.stats import qmc

    if isinstance(n, bool) or not isinstance(n, int) or n < 4:
        raise InputError(f"band samples must be an integer >= 4, got {n!r}")
    u = qmc.LatinHypercube(d=len(factors), seed=seed).random(n)
    return np.column_stack([f.ppf(u[:, k]) for k, f in enumerate(factors)])


def perturbed(inp: StudyInputs, row, factors=FACTORS) -> StudyInputs:
    """``inp`` with one sample's multipliers applied (:data:`FACTORS`' ``applies_to``)."""
    m = dict(zip((f.name for f in factors), (float(v) for v in row), strict=True))
    robot = inp.robot
    if m.get("mass", 1.0) != 1.0:
        robot = robot.with_mass_scaled(m["mass"])
    e = m.get("modulus", 1.0)
    if e != 1.0:
        robot = replace(robot, youngs_modulus_pa=robot.youngs_modulus_pa * e)
    conn = inp.connectors.scaled(m.get("stiffness", 1.0) * e, m.get("play", 1.0))
    return replace(inp, robot=robot, connectors=conn)


def _allowance(c: Curve, w: int) -> float:
    """The nominal launch allowance (mm) at width ``w`` (module docstring); 0 for a static table."""
    if not c.allowance_mm:
        return 0.0
    if w in c.allowance_mm:
        return c.allowance_mm[w]
    below = [k for k in c.allowance_mm if k <= w]
    return c.allowance_mm[max(below)] if below else c.allowance_mm[min(c.allowance_mm)]


def sample_threshold(c: Curve, inp: StudyInputs, start: int) -> int:
    """The widest void ``inp`` spans with structure ``c.structure`` (the table's tip criterion +
    the nominal allowance), searched from ``start`` (the tip grows with the width); a solve
    that does not converge counts as failing, as in the table."""
    clear = inp.clearance_m * 1e3

    def passes(w: int) -> bool:
        if w < 1:
            return True
        try:
            _rows, res = min_rows(c.structure, w, inp)
        except SolverFailure:
            return False
        return res.tip_deflection_mm + _allowance(c, w) <= clear

    w = max(1, min(start, inp.max_width))
    if passes(w):
        while w < inp.max_width and passes(w + 1):
            w += 1
        return w
    while w >= 1 and not passes(w):
        w -= 1
    return max(w, 0)


@dataclass
class Band:
    """Per structure the sampled thresholds and their quantiles; the factors and the method."""

    structures: list[str]
    nominal: dict[str, int]
    thresholds: dict[str, list[int]]
    multipliers: np.ndarray
    seed: int
    factors: tuple[Factor, ...] = FACTORS
    quantiles: dict[str, dict[int, int]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for s, ts in self.thresholds.items():
            self.quantiles[s] = {q: quantile_reached(ts, q) for q in QUANTILES}

    def pick(self, q: int) -> dict[str, int]:
        return {s: v[q] for s, v in self.quantiles.items()}

    def to_dict(self) -> dict:
        return {"method": (f"Latin hypercube of {len(self.multipliers)} samples (seed {self.seed}) over "
                           f"{', '.join(f.name for f in self.factors)}; per sample each structure's threshold by the "
                           "table's static tip at the longest cantilever + the nominal launch allowance; p<q>: the "
                           "threshold that (100 - q) % of the samples reach or exceed (p5: what 95 % of prints span)"),
                "factors": [{"name": f.name, "distribution": f.kind, "mean": f.mean, "sd": f.sd, "low": f.low,
                             "mode": f.mode, "high": f.high, "applies_to": f.applies_to, "source": f.source}
                            for f in self.factors],
                "per_structure": {s: {"nominal": self.nominal[s], **{f"p{q}": v for q, v in self.quantiles[s].items()},
                                      "samples": self.thresholds[s]} for s in self.structures},
                "samples": [[round(float(v), 4) for v in row] for row in self.multipliers]}


def quantile_reached(values: Iterable[int], q: float) -> int:
    """The largest ``t`` that at least ``100 - q`` % of ``values`` reach or exceed (``q = 5``: 95 %
    of them are ``>= t``): sorted ascending, the one at index ``n - ceil(n (100 - q) / 100)``."""
    v = sorted(int(x) for x in values)
    if not v:
        raise InputError("no samples to take a quantile of")
    need = max(1, math.ceil(len(v) * (100.0 - q) / 100.0 - 1e-9))
    return v[len(v) - need]


def banded_structures(d: Derivation) -> list[str]:
    """The line and every structure of the selection band (what the swarm builds)."""
    names = ["line"] + [s.name for s, _a, _b in d.levels]
    return [n for n in dict.fromkeys(names) if any(c.structure.name == n for c in d.curves)]


def _sample_thresholds(curves: list[Curve], inp: StudyInputs) -> list[int]:
    """One sample's threshold for each curve's structure (a worker's job: picklable in and out)."""
    return [sample_threshold(c, inp, c.threshold) for c in curves]


def band(d: Derivation, n: int = DEFAULT_SAMPLES, seed: int = DEFAULT_SEED,
         progress: Callable[[Iterable, str, int], Iterable] | None = None,
         structures: list[str] | None = None, workers: int | None = None) -> Band:
    """The band of ``d``'s thresholds over :data:`FACTORS` (module docstring).

    The samples are independent: they run ``workers`` at a time in separate processes (default:
    the launch transients' worker count, :func:`structure_fem.model.dynamics_cache.workers_default`,
    i.e. the CPU count), sharing the solve cache; the band is the same whatever the count
    (each sample's thresholds land in its own slot)."""
    import concurrent.futures as cf
    import multiprocessing as mp

    from structure_fem.model.dynamics_cache import process_context, workers_default

    names = banded_structures(d) if structures is None else list(structures)
    rows = samples(n, seed)
    curves = [d.curve(s) for s in names]
    inputs = [perturbed(d.inputs, r) for r in rows]
    workers = workers_default() if workers is None else workers
    if mp.current_process().daemon:  # a pool's worker may not start processes of its own
        workers = 1
    wrap = progress or (lambda it, _label, _total: it)
    per_sample: list[list[int] | None] = [None] * len(rows)
    if workers <= 1:
        for i in wrap(range(len(rows)), "fem band samples", len(rows)):
            per_sample[i] = _sample_thresholds(curves, inputs[i])
    else:
        with cf.ProcessPoolExecutor(max_workers=min(workers, len(rows)), mp_context=process_context()) as ex:
            futs = {ex.submit(_sample_thresholds, curves, inp_i): i for i, inp_i in enumerate(inputs)}
            for f in wrap(cf.as_completed(futs), "fem band samples", len(futs)):
                per_sample[futs[f]] = f.result()
    out = {s: [ts[k] for ts in per_sample] for k, s in enumerate(names)}
    return Band(names, {s: d.curve(s).threshold for s in names}, out, rows, seed)


#: What ``--pick`` accepts: a quantile of the band or the nominal (as drawn) thresholds.
PICKS = ("p5", "p50", "nominal")


def apply_pick(d: Derivation, b: Band, pick: str = "p5") -> dict[str, int]:
    """Set the banded structures' thresholds in ``d`` to the band's ``pick`` and re-tile the
    selection band (:func:`structure_fem.analysis.study.levels_of`); returns the nominal
    thresholds it replaced. A pick is never wider than the nominal threshold (the robot as drawn,
    whose tips the record's deflections are): ``p95`` is reported, not picked. A structure outside the band added nothing at the nominal inputs; it
    is capped at the picked threshold of the best banded structure that matched it there, so
    it cannot add a band at the pick it did not add as drawn."""
    from structure_fem.analysis.study import levels_of

    if pick not in PICKS:
        raise InputError(f"--pick {pick!r} is not one of {', '.join(PICKS)}")
    nominal = {c.structure.name: c.threshold for c in d.curves}
    if pick == "nominal":
        return nominal
    q = int(pick[1:])
    picked = b.pick(q)
    for c in d.curves:
        name = c.structure.name
        if name in picked:
            c.threshold = min(picked[name], c.threshold)  # never wider than the drawn robot's own
        else:
            peers = [picked[n] for n in picked if nominal[n] >= nominal[name]]
            c.threshold = min(c.threshold, max(peers) if peers else max(picked.values(), default=0))
    d.levels = levels_of(d.curves)
    return nominal


__all__ = ["DEFAULT_SAMPLES", "DEFAULT_SEED", "FACTORS", "PICKS", "QUANTILES", "Band", "Factor", "apply_pick", "band",
           "banded_structures", "perturbed", "quantile_reached", "sample_threshold", "samples"]
