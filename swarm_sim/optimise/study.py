"""A study: CMA-ES (the ``cmaes`` package) over a :class:`~swarm_sim.optimise.space.SearchSpace`,
each trial the training sweep of :mod:`swarm_sim.optimise.objective`.

Every trial uses the same training seeds (common random numbers: two rule sets are compared on
the same draws, so the optimiser sees the rules' difference, not the seeds'). The optimiser is
seeded, so its sequence of trials is a function of the configuration and the values it was told;
the values are functions of the stored runs. A resumed study therefore replays: it asks the same
points, finds their runs in the store (nothing re-run), tells the same values and carries on
where the runs stop. That is the whole resume mechanism, and why ``kill -9`` loses nothing but
the runs in flight. Trial 0 is the thesis's rules (no override), run first as the reference.
"""

from __future__ import annotations

import hashlib
import json
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import InputError
from ..sweeps import SweepSpec
from ..sweeps.executors import make_executor
from ..sweeps.sweep import DEFAULT_RUN_FN, limits_digest
from .objective import Cell, Penalties, TrialScore, parse_cases, score_runs, training_cells
from .runs import Progress, ensure_runs, stored_rows
from .space import SearchSpace

#: held-out seeds start this far above the study's seed: never a training seed
HELDOUT_OFFSET = 1_000_000


def _digest(obj) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True).encode()).hexdigest()[:12]


@dataclass(frozen=True)
class StudyConfig:
    """What a study tunes and on what. ``seed``: the optimiser's seed and the first training
    seed (training runs use ``seed .. seed + train_seeds - 1``, held-out ones start at
    ``seed + HELDOUT_OFFSET``). ``sigma0``: CMA-ES's initial step in the unit cube."""

    cases: tuple[str, ...] = ("A", "B", "C", "D")
    space: SearchSpace = field(default_factory=SearchSpace)
    trials: int = 30
    train_seeds: int = 6
    train_widths: tuple[int, ...] = (2, 4)
    limits: str = "thesis"
    seed: int = 0
    sigma0: float = 0.25
    population: int | None = None
    penalties: Penalties = field(default_factory=Penalties)

    def __post_init__(self):
        object.__setattr__(self, "cases", parse_cases(self.cases))

        def whole(v, name, lo, hi):
            if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
                raise InputError(f"{name} {v!r}: must be an integer in {lo}..{hi}")

        whole(self.trials, "--trials", 1, 100_000)
        whole(self.train_seeds, "--train-seeds", 1, 1000)
        whole(self.seed, "--seed", 0, HELDOUT_OFFSET - 1001)
        if self.population is not None:
            whole(self.population, "--population", 2, 1000)
        if not (isinstance(self.sigma0, (int, float)) and 0 < self.sigma0 <= 1):
            raise InputError(f"--sigma {self.sigma0!r}: must be in (0, 1] (a step in the unit cube)")
        if not self.train_widths:
            raise InputError("--train-widths is empty")

    def cells(self) -> list[Cell]:
        """The training cells (computed once: every trial's sweep asks for them)."""
        got = self.__dict__.get("_cells")
        if got is None:
            got = training_cells(self.cases, self.limits, self.train_widths)
            object.__setattr__(self, "_cells", got)
        return list(got)

    def describe(self) -> dict:
        d = asdict(self)
        d["space"] = list(self.space.names)
        d.pop("trials")  # more trials extend the same study
        return d

    @property
    def study_id(self) -> str:
        return _digest(self.describe())

    def specs(self, overrides: dict) -> list[SweepSpec]:
        """The training sweep of one trial: one spec per case (its cells as points)."""
        by_preset: dict[str, list[tuple[int, int]]] = {}
        for c in self.cells():
            by_preset.setdefault(c.preset, []).append((c.robots, c.void_width))
        return [SweepSpec(preset, points=tuple(pts), runs=self.train_seeds, limits=self.limits, seed0=self.seed,
                          overrides=dict(overrides)) for preset, pts in by_preset.items()]


@dataclass
class Trial:
    number: int  # 0: the thesis's rules
    generation: int  # -1 for trial 0
    params: dict
    score: TrialScore

    def to_dict(self) -> dict:
        return {"number": self.number, "generation": self.generation, "params": self.params,
                "value": self.score.value, "score": self.score.to_dict()}


@dataclass
class StudyResult:
    config: StudyConfig
    db: str
    baseline: Trial
    trials: list[Trial]
    #: runs this call ran (0 when every trial was found in the store: a finished study replayed)
    new_runs: int = 0
    wall_s: float = 0.0

    @property
    def best(self) -> Trial:
        """The lowest value, ties to the earliest trial; the thesis's rules when nothing beat them."""
        return min([self.baseline, *self.trials], key=lambda t: (t.score.value, t.number))

    def convergence(self) -> list[float]:
        """Best value so far after each trial (trial 0 included)."""
        out, best = [], self.baseline.score.value
        out.append(best)
        for t in self.trials:
            best = min(best, t.score.value)
            out.append(best)
        return out

    def defaults(self) -> dict:
        """``{tunable: {case: the thesis's value in that case's preset}}``."""
        from ..experiments.thesis_grid import CHAPTER4
        from ..runner import resolve_params

        out: dict = {n: {} for n in self.config.space.names}
        for case in self.config.cases:
            preset, sizes, widths, _ = CHAPTER4[case]
            p = resolve_params(preset, sizes[0], widths[0], limits=self.config.limits)
            for n in out:
                out[n][case] = getattr(p, n)
        return out

    def to_dict(self) -> dict:
        return {"study_id": self.config.study_id, "defaults": self.defaults(), "db": self.db, "config": self.config.describe(),
                "trials_asked": self.config.trials, "cells": [asdict(c) for c in self.config.cells()],
                "baseline": self.baseline.to_dict(), "best": self.best.to_dict(),
                "trials": [t.to_dict() for t in self.trials], "convergence": self.convergence(),
                "new_runs": self.new_runs, "wall_s": round(self.wall_s, 1)}


def run_study(cfg: StudyConfig, db, executor: str = "local", workers: int | None = None,
              address: str | None = None, run_fn=None, progress: Progress | None = None,
              on_trial=None) -> StudyResult:
    """Run (or resume) ``cfg`` into ``db``; ``on_trial(trial, best_so_far)`` after each trial."""
    try:
        from cmaes import CMA
    except ImportError:
        raise InputError("voidcross optimise needs the cmaes package: pip install 'voidcross[opt]'") from None

    run_fn = run_fn or DEFAULT_RUN_FN
    digest = limits_digest(cfg.limits)
    cfg.cells()  # every cell valid before anything runs
    t0 = time.perf_counter()
    with make_executor(executor, workers=workers, address=address) as ex:
        def evaluate(overrides: list[dict], desc: str) -> tuple[list[TrialScore], int]:
            specs = [cfg.specs(o) for o in overrides]
            flat = [s for ss in specs for s in ss]
            new = ensure_runs(flat, db, ex, run_fn, digest, progress, desc)
            rows = stored_rows(flat, db, digest)
            scores, i = [], 0
            for ss in specs:
                scores.append(score_runs([r for rr in rows[i:i + len(ss)] for r in rr], cfg.penalties))
                i += len(ss)
            return scores, new

        (s0,), new0 = evaluate([{}], "trial 0: the thesis's rules")
        baseline = Trial(0, -1, {}, s0)
        ran = new0
        best = s0.value
        if on_trial:
            on_trial(baseline, best)
        opt = CMA(mean=cfg.space.start(), sigma=cfg.sigma0, bounds=np.tile([0.0, 1.0], (cfg.space.dim, 1)),
                  seed=cfg.seed, population_size=cfg.population)
        trials: list[Trial] = []
        gen = 0
        while len(trials) < cfg.trials:
            xs = [opt.ask() for _ in range(opt.population_size)]
            n = min(len(xs), cfg.trials - len(trials))
            vals = [cfg.space.values(x) for x in xs[:n]]
            first = len(trials) + 1
            scores, new = evaluate(vals, f"trials {first}-{first + n - 1}/{cfg.trials} (best {best:.1f} s)")
            ran += new
            for j, (v, s) in enumerate(zip(vals, scores, strict=True)):
                t = Trial(first + j, gen, v, s)
                trials.append(t)
                best = min(best, s.value)
                if on_trial:
                    on_trial(t, best)
            if n == len(xs):
                opt.tell([(x, s.value) for x, s in zip(xs, scores, strict=True)])
            gen += 1
    return StudyResult(cfg, str(db), baseline, trials, ran, time.perf_counter() - t0)
