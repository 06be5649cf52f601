"""The objective of a study: the training cells, the penalties and a trial's score.

A trial runs every training cell (case, swarm size, void width) at every training seed with
the trial's tunables as overrides. Its value, in simulated seconds, is

    (sum of Tt over the runs that crossed as they should + the penalties) / runs that should cross

where a run *should cross* when its swarm is at least the structure's counting rule
(``min_robots_rule`` of the limits in use, e.g. the thesis's 3w, 3w + 2 for case A). So a rule
set that is faster where crossing is possible lowers the value, and one that gives up on a
crossing, times out, loses a robot or crosses with fewer robots than the rule (a bridge that would
not hold) pays for it (:class:`Penalties`). Retreats below the rule cost nothing but their
penalties: the thesis's rules retreat there too, and a retreat's time is not the goal.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass

from ..errors import InputError
from ..experiments.thesis_grid import CHAPTER4, rule_swarm

#: Params.max_time_s's default, the thesis's simulated-time budget of a run (s)
RUN_BUDGET_S = 1500.0


@dataclass(frozen=True)
class Penalties:
    """Seconds added to a trial's sum per offending run (per robot for ``lost_robot_s``).

    The defaults charge a failure the whole simulated-time budget of a run
    (:data:`RUN_BUDGET_S`, 1500 s: ten times a typical crossing) and twice that for what the
    brief forbids outright (a robot lost, a crossing the structure's rule says cannot hold)."""

    no_cross_s: float = RUN_BUDGET_S
    timeout_s: float = RUN_BUDGET_S
    lost_robot_s: float = 2 * RUN_BUDGET_S
    below_rule_s: float = 2 * RUN_BUDGET_S
    error_s: float = 2 * RUN_BUDGET_S

    def __post_init__(self):
        for k, v in asdict(self).items():
            if not (isinstance(v, (int, float)) and v >= 0):
                raise InputError(f"penalty {k}={v!r}: must be a number of seconds >= 0")


@dataclass(frozen=True)
class Cell:
    """One training or held-out cell: a case of Chapter 4 at one swarm size and void width."""

    case: str
    preset: str
    robots: int
    void_width: int


def parse_cases(cases) -> tuple[str, ...]:
    """``"a,b,c,d"`` / ``("A", "b")`` -> ``("A", "B", ...)``; anything else one error line."""
    items = [str(c).strip().upper() for c in (cases.split(",") if isinstance(cases, str) else cases)]
    if not items or "" in items:
        raise InputError(f"--cases {cases!r}: give a comma list of Chapter 4's cases ({', '.join(CHAPTER4)})")
    bad = [c for c in items if c not in CHAPTER4]
    if bad:
        raise InputError(f"--cases {cases!r}: {', '.join(map(repr, bad))} not one of {', '.join(CHAPTER4)} "
                         "(any case)")
    return tuple(dict.fromkeys(items))


def training_cells(cases, limits: str = "thesis", widths: tuple[int, ...] = (2, 4)) -> list[Cell]:
    """Per case and width, three swarm sizes of the thesis's grid around the counting rule of
    ``limits``: the largest below it (should retreat), the smallest at or above it (the hardest
    crossing) and the next above (a comfortable one). Widths the grid lacks are an error."""
    out = []
    for case in parse_cases(cases):
        preset, sizes, grid_w, _ = CHAPTER4[case]
        for w in widths:
            if w not in grid_w:
                raise InputError(f"--train-widths {w}: case {case}'s grid has widths {grid_w[0]}..{grid_w[-1]}")
            b = rule_swarm(preset, w, limits, robots=sizes[0])
            below = [n for n in sizes if n < b][-1:]
            above = [n for n in sizes if n >= b][:2]
            out += [Cell(case, preset, n, w) for n in (*below, *above)]
    return out


@dataclass(frozen=True)
class TrialScore:
    """A trial's value (s, lower is better) and what made it: runs, crossings, penalties."""

    value: float
    runs: int
    should_cross: int
    crossed: int
    mean_tt_s: float | None
    no_cross: int
    timeouts: int
    robots_lost: int
    below_rule: int
    errors: int

    def to_dict(self) -> dict:
        return asdict(self)


def score_runs(rows: list[dict], penalties: Penalties = Penalties()) -> TrialScore:
    """Score stored run rows (``ResultStore.iter_runs``' shape) by the module's formula."""
    if not rows:
        raise ValueError("no runs to score")
    total = 0.0
    tts = []
    n_should = crossed = no_cross = timeouts = lost = below = errors = 0
    for r in rows:
        if r["status"] != "ok":
            errors += 1
            n_should += 1
            total += penalties.error_s
            continue
        res = json.loads(r["result_json"])
        should = int(r["robots"]) >= int(res.get("min_robots_rule") or 0)
        success = bool(r["success"])
        n_should += should
        crossed += success
        if res.get("timed_out"):
            timeouts += 1
            total += penalties.timeout_s
        n_lost = int(r["robots_lost"] or 0)
        lost += n_lost
        total += n_lost * penalties.lost_robot_s
        if should and success:
            tt = float(r["t_t"])
            tts.append(tt)
            total += tt
        elif should:
            no_cross += 1
            total += penalties.no_cross_s
        elif success:
            below += 1
            total += penalties.below_rule_s
    return TrialScore(value=total / max(1, n_should), runs=len(rows), should_cross=n_should, crossed=crossed,
                      mean_tt_s=sum(tts) / len(tts) if tts else None, no_cross=no_cross, timeouts=timeouts,
                      robots_lost=lost, below_rule=below, errors=errors)
