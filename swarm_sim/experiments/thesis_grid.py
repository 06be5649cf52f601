"""The thesis's experiments as data, and its crossing boundary: one home for both, read by
``voidcross reproduce`` (the runs) and by :mod:`swarm_sim.optimise` (training and held-out cells).

Ch. 4.7's four cases (A: N in {5, 7, 8, 10}; B: N in {3, 6, ..., 18}; C: N 3..18; D: N 3..18,
20, 25, 30, 40, 50; voids of 1..5 robot widths; 5, 5, 30 and 30 runs per cell), Ch. 5.6's large
void (70 robots, 6..10 widths, 10 runs) and Ch. 5.5.2's tapering arches beyond 10 widths (each
width with the swarm the counting rule needs there, one run per width).
"""

from __future__ import annotations

#: (chapter, case, preset, swarm sizes, void widths, runs per cell): Ch. 4.7 and Ch. 5.6
EXPERIMENTS = (
    (4, "A", "case-a", (5, 7, 8, 10), (1, 2, 3, 4, 5), 5),
    (4, "B", "case-b", (3, 6, 9, 12, 15, 18), (1, 2, 3, 4, 5), 5),
    (4, "C", "case-c", tuple(range(3, 19)), (1, 2, 3, 4, 5), 30),
    (4, "D", "case-d", (*range(3, 19), 20, 25, 30, 40, 50), (1, 2, 3, 4, 5), 30),
    (5, "large", "large-void", (70,), (6, 7, 8, 9, 10), 10),
    (5, "taper-15", "large-void-15", "rule", (11, 15), 1),
    (5, "taper-30", "large-void-30", "rule", (20, 25, 30), 1),
)
#: the tapering rows (swarm size ``"rule"``: per width, the smallest swarm the counting rule
#: of the chosen limits admits, ``resolve_params(...).min_robots_rule``, computed, not listed)
TAPERING = tuple(e[1] for e in EXPERIMENTS if e[3] == "rule")
#: Chapter 4's cases by letter: (preset, swarm sizes, void widths, runs per cell)
CHAPTER4 = {case: (preset, robots, widths, runs) for ch, case, preset, robots, widths, runs in EXPERIMENTS
            if ch == 4}


def rule_swarm(preset: str, width: int, limits: str, robots: int = 100) -> int:
    """The swarm the counting rule needs to cross ``width`` with ``preset`` under ``limits``
    (``robots``: a swarm that fits the preset's arena; the rule does not depend on it)."""
    from swarm_sim.runner import resolve_params

    return int(resolve_params(preset, robots, width, limits=limits).min_robots_rule)


def thesis_boundary(case: str, w: int, preset: str | None = None) -> int | None:
    """The thesis's smallest crossing swarm: 3w + 2 for case A, 3w for B-D (Ch. 4.6.3); for the
    tapering rows the thesis's counting rule (Ch. 5.5.2) at that width (``preset`` needed)."""
    if case in TAPERING and preset is not None:
        return rule_swarm(preset, w, "thesis")
    return {"A": 3 * w + 2, "B": 3 * w, "C": 3 * w, "D": 3 * w}.get(case)


def observed_boundary(cells: dict[tuple[int, int], list[bool]], w: int) -> dict:
    """From {(robots, width): [crossed?]}: the smallest swarm of the grid at which every run
    crossed, and whether every run of every smaller swarm retreated."""
    sizes = sorted(n for n, ww in cells if ww == w)
    all_cross = [n for n in sizes if cells[(n, w)] and all(cells[(n, w)])]
    n_obs = all_cross[0] if all_cross else None
    below_ok = n_obs is not None and all(not any(cells[(n, w)]) for n in sizes if n < n_obs)
    return {"observed": n_obs, "below_all_retreat": below_ok,
            "runs": sum(len(cells[(n, w)]) for n in sizes)}
