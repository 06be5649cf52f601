"""Resumable Monte-Carlo sweeps of swarm_sim runs into SQLite, on local processes or Dask.

``ranges`` parses ``"3-18,20"``; ``store`` is the SQLite results database;
``executors`` runs keys on a process pool or a Dask cluster; ``sweep`` ties
them together (:func:`prepare_sweep`, :func:`run_sweep`); ``export`` writes
CSV/Parquet. Nothing here imports the simulator until a run executes.
May import every swarm_sim module (an experiments layer); nothing below it imports it.
"""

from .ranges import format_int_range, parse_int_range
from .store import SCHEMA_VERSION, ResultStore, check_db
from .sweep import SweepPlan, SweepSpec, SweepSummary, prepare_sweep, run_sweep

__all__ = ["SCHEMA_VERSION", "ResultStore", "SweepPlan", "SweepSpec", "SweepSummary", "check_db",
           "format_int_range", "parse_int_range", "prepare_sweep", "run_sweep"]
