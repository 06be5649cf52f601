"""Optimised bridge rules (the thesis's future work 3): CMA-ES over the behaviour's tunables, the
objective a sweep over training cells, every run stored in the sweep SQLite store, then held-out
and robustness checks against the thesis's rules on the same seeds.
May import every swarm_sim module (the top layer beside ``sweeps`` and ``experiments``); nothing
in swarm_sim imports it.
"""

from .heldout import Comparison, compare, robustness
from .objective import Penalties, TrialScore, score_runs, training_cells
from .space import DEFAULT_PARAMS, SearchSpace
from .study import StudyConfig, StudyResult, Trial, run_study

__all__ = ["DEFAULT_PARAMS", "Comparison", "Penalties", "SearchSpace", "StudyConfig", "StudyResult", "Trial",
           "TrialScore", "compare", "robustness", "run_study", "score_runs", "training_cells"]
