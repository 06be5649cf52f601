"""A Python API for notebooks and scripts: the CLI's computations as functions.

Every function here wraps the package function the matching `voidcross` command calls,
so a notebook gets the same numbers as the command line:

| function | what it returns | the command that computes the same |
|---|---|---|
| :func:`simulate` | one run, a ``swarm_sim.runner.RunResult`` | ``voidcross sim run`` |
| :func:`trajectory` | per-step poses and modes of one run, a ``pandas.DataFrame`` | ``voidcross sim run --snapshots`` (its frames) |
| :func:`sweep` | one row per run of a Monte-Carlo sweep, a ``pandas.DataFrame`` | ``voidcross sweep`` + ``sweep export`` |
| :func:`fem_table` | the structure-selection table, a list of records | ``voidcross fem table --json --full-json`` |
| :func:`deflection_curves` | tip deflection per structure and void width, a list of records | ``voidcross fem study`` (``deflection_vs_width.csv``) |
| :func:`limits` | the limits record, a ``structure_fem.limits.StructureLimits`` | ``--limits derived / thesis / PATH`` |

Units are in the names, as everywhere in voidcross: centimetres (``_cm``), seconds of
simulated time (``_s``; ``wall_s`` is real time), radians (``_rad``), millimetres
(``_mm``), and void widths in robot widths (``_robots``/``_widths``).

Bad input raises the packages' :class:`InputError` (a subclass of
:class:`voidcross.api.InputError`, which is ``cubot_cad.errors.InputError``) with a message
naming the bad value, the same message the CLI prints as ``error: ...``. The DataFrame
functions need pandas (the ``api`` extra, part of ``all``): without it they raise
:class:`ModuleNotFoundError` saying so.

Nothing heavy is imported until a function is called (the simulator, exudyn, pandas).

Example:
    >>> from voidcross import api
    >>> res = api.simulate("case-d", robots=3, void_width_robots=1, limits="thesis", seed=1)
    >>> res.success, res.end_reason, res.times["Tt"]          # Tt in simulated seconds
    (True, 'crossed', 112.63)
"""

from __future__ import annotations

import json
import math
import os
import tempfile
import warnings
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cubot_cad.errors import InputError

if TYPE_CHECKING:  # pragma: no cover - for the annotations and the API reference only
    from structure_fem.limits import StructureLimits
    from swarm_sim.runner import RunResult

    try:
        import pandas
    except ImportError:  # optional: the DataFrame functions say so when called
        pass

__all__ = ["InputError", "deflection_curves", "fem_table", "limits", "simulate", "sweep", "trajectory"]

#: Executors :func:`sweep` accepts: ``serial`` (this process), ``local`` (a process pool), ``dask``.
EXECUTORS = ("serial", "local", "dask")

#: Sweep DataFrame columns, in order (units in the names; see :func:`sweep`).
SWEEP_COLUMNS = (
    "preset", "robots", "void_width_robots", "seed", "limits", "limits_source", "status", "success",
    "retreated", "timed_out", "end_reason", "robots_lost", "robots_delivered", "robots_on_initial_side",
    "min_robots_rule", "record_min_robots", "Ts_s", "Ta_s", "To_s", "Td_s", "Tb_s", "Tt_s", "assembly_s",
    "disassembly_s", "levels_used", "seed_robot", "seed_x_cm", "seed_y_cm", "target_finder", "steps",
    "hand_overs", "wall_s", "error_type",
)

#: Trajectory DataFrame columns, in order (see :func:`trajectory`).
TRAJECTORY_COLUMNS = ("t_s", "robot", "x_cm", "y_cm", "heading_rad", "mode")


# --------------------------------------------------------------------------- helpers

def _pandas(what: str):
    """Import pandas for ``what``, or say clearly that it is missing (it is optional)."""
    try:
        import pandas
    except ImportError:
        raise ModuleNotFoundError(
            f"voidcross.api.{what}() returns a pandas.DataFrame, and pandas is not installed "
            "(pip install 'voidcross[api]')", name="pandas") from None
    return pandas


def _limits_arg(limits: str | os.PathLike) -> str:
    """``derived`` / ``thesis`` / a path, as the string the packages take."""
    from swarm_sim.errors import InputError

    if isinstance(limits, (str, os.PathLike)) and str(limits):
        return os.fspath(limits)
    raise InputError(f"limits {limits!r}: must be 'derived', 'thesis' or a path to a limits.json file")


def _preset_arg(preset: str | os.PathLike) -> str:
    return os.fspath(preset) if isinstance(preset, os.PathLike) else preset


def _ints(value: int | str | Iterable[int], name: str) -> tuple[int, ...]:
    """An int, a range text (``"3-5,8"``) or an iterable of ints -> sorted unique tuple."""
    import numbers

    from swarm_sim.errors import InputError
    from swarm_sim.sweeps import parse_int_range

    if isinstance(value, str):
        return parse_int_range(value, name)
    items = [value] if isinstance(value, numbers.Integral) else value
    try:
        items = list(items)
    except TypeError:
        raise InputError(f"{name} {value!r}: expected an integer, a range such as '3-5,8' or a list of "
                         "integers") from None
    out = set()
    for v in items:
        if isinstance(v, bool) or not isinstance(v, numbers.Integral):
            raise InputError(f"{name} {value!r}: {v!r} is not an integer")
        if v < 1:
            raise InputError(f"{name} {value!r}: {v} must be >= 1")
        out.add(int(v))
    if not out:
        raise InputError(f"{name} {value!r}: empty (expected at least one value)")
    return tuple(sorted(out))


# --------------------------------------------------------------------------- swarm_sim

def simulate(preset: str | os.PathLike = "case-d", robots: int | None = 9, void_width_robots: int | None = 3,
             limits: str | os.PathLike = "derived", seed: int = 0, **overrides: Any) -> RunResult:
    """One simulated crossing attempt, as ``voidcross sim run`` computes it.

    Calls :func:`swarm_sim.runner.run_scenario`: the preset, its overrides and the limits are
    resolved and validated, then the swarm runs until it crossed and found the target, retreated
    with every robot safe, or reached ``max_time_s``.

    Args:
        preset: a shipped preset (``case-a`` .. ``case-d``, ``large-void``, ``large-void-8``,
            ``-15``, ``-30``, ``pier``) or the path of a TOML file in the same format
            (``swarm_sim/presets/case-d.toml`` shows every key).
        robots: swarm size (robots); ``None``: the preset's.
        void_width_robots: void width in robot widths (the void is ``void_width_robots x
            robot_length_cm`` wide); ``None``: the preset's.
        limits: ``"derived"`` (structure_fem's packaged limits.json, the default), ``"thesis"``
            (the thesis's 5/10/15.. thresholds and counting rules) or a limits.json path.
        seed: random seed (>= 0); same arguments, same run.
        **overrides: any preset parameter by its flat, unit-carrying name, e.g.
            ``arena_w_cm=800.0``, ``arena_h_cm=200.0``, ``speed_cm_s=10.0``, ``max_time_s=600.0``
            (simulated-time cap), ``obstacles=[(200.0, 100.0, 15.0)]`` (x_cm, y_cm, r_cm),
            ``structure="switch"``, ``faults="drive:1.7/h,3@120:total"`` (robots that fail:
            docs/faults.md), ``void_depth_cm=20.0`` (a floor piers can stand on); plus
            ``check_invariants=True`` (raise
            ``swarm_sim.errors.InvariantViolation`` on the first broken invariant).

    Returns:
        ``swarm_sim.runner.RunResult``: ``success`` / ``retreated`` / ``timed_out``,
        ``end_reason`` (``crossed``, ``retreated-no-robots``, ``retreated-span``, ...), ``times``
        (``Ts``, ``Ta``, ``To``, ``Td``, ``Tb``, ``Tt``: simulated seconds; ``None`` for a phase a
        timed-out run never reached), ``robots_lost``, ``robots_delivered``, ``min_robots_rule``,
        ``seed_robot``, ``seed_position`` (cm), ``levels_used``, ``switches``, ``wall_s`` (real
        seconds), ``faults`` (per failure: when, how and when it was detected), ``robots_in_piers``;
        ``to_dict()`` is the ``sim run --json`` record.

    Raises:
        InputError: (``swarm_sim.errors.InputError``) an unknown preset or parameter, a bad swarm
            size, void width, seed or limits, a void wider than the arena: the message names the
            value.

    Example:
        >>> from voidcross import api
        >>> api.limits("thesis").min_robots(1)          # the thesis: N = 3 w
        3
        >>> api.simulate(robots=3, void_width_robots=1, limits="thesis", seed=1).end_reason
        'crossed'
        >>> api.simulate(robots=2, void_width_robots=1, limits="thesis", seed=1).end_reason
        'retreated-no-robots'
        >>> api.simulate("case-d", 9, 3, arena_w_cm=600.0, target_x_cm=575.0).success
        True
    """
    from swarm_sim.params import load_preset
    from swarm_sim.runner import run_scenario

    preset = _preset_arg(preset)
    if robots is None or void_width_robots is None:
        base = load_preset(preset)
        robots = base.robots if robots is None else robots
        void_width_robots = base.void_width if void_width_robots is None else void_width_robots
    return run_scenario(preset, robots, void_width_robots, seed, limits=_limits_arg(limits), **overrides)


class _Sampler:
    """``on_step`` collector: the poses and modes at t = 0, every_s, 2 every_s, ... and the last state.

    The sample clock is ``step * dt_s`` (no drift from summing ``dt_s``)."""

    def __init__(self, every_s: float, dt_s: float):
        self.every_s, self.dt_s = every_s, dt_s
        self.next_i = 0
        self.last_step = -1
        self.t, self.x, self.y, self.h, self.mode = [], [], [], [], []

    def take(self, s) -> None:
        self.t.append(float(s.t_s))
        self.x.append(s.x_cm.copy())
        self.y.append(s.y_cm.copy())
        self.h.append(s.heading_rad.copy())
        self.mode.append(s.mode.copy())
        self.last_step = s.step

    def __call__(self, s) -> None:
        clock = s.step * self.dt_s
        if clock + 1e-9 * max(1.0, self.every_s) >= self.next_i * self.every_s:
            self.take(s)
            self.next_i = math.floor(clock / self.every_s + 1e-9) + 1

    def finish(self, s) -> None:
        if s.step != self.last_step:
            self.take(s)


def trajectory(preset: str | os.PathLike = "case-d", robots: int | None = 9, void_width_robots: int | None = 3,
               seed: int = 0, every_s: float = 1.0, limits: str | os.PathLike = "derived",
               **overrides: Any) -> pandas.DataFrame:
    """Per-step data of one run: every robot's pose and mode every ``every_s`` simulated seconds.

    Runs :func:`swarm_sim.runner.simulate` on the parameters :func:`simulate` would use, with an
    ``on_step`` collector (the hook ``voidcross sim run --video/--snapshots`` records its frames
    with). Samples are taken at simulated times ``0, every_s, 2 every_s, ...`` (the first step at
    or after each; the clock is ``step x dt_s``) and at the run's last step, so a run that ends at
    ``T`` s has ``floor(T / every_s) + 1`` samples, one more when ``T`` is not a multiple of
    ``every_s``. Cap long runs with ``max_time_s=...``.

    Args:
        preset, robots, void_width_robots, seed, limits, **overrides: as :func:`simulate`
            (``check_invariants`` is not taken here).
        every_s: simulated seconds between samples; at least one step (``dt_s``, 0.01 s in the
            shipped presets).

    Returns:
        ``pandas.DataFrame``, one row per (sample, robot), columns ``t_s`` (simulated s),
        ``robot`` (id 0..N-1), ``x_cm``, ``y_cm`` (arena frame: the void is a vertical band, the
        robots start on its left), ``heading_rad`` (0 = +x, towards the target side), ``mode``
        (``EXPLORE``, ``SEED``, ``RECRUIT``, ``MEMBER``, ``TARGET``, ``RETREAT``, ``STOPPED``;
        ``swarm_sim.state.Mode`` names). ``df.attrs["run"]`` holds the run's result record
        (``RunResult.to_dict()``) and ``df.attrs["every_s"]`` the sample period.

    Raises:
        InputError: as :func:`simulate`, and ``every_s`` not a positive number of at least one step.
        ModuleNotFoundError: pandas is not installed.

    Example:
        >>> from voidcross import api
        >>> df = api.trajectory("case-d", robots=3, void_width_robots=1, seed=1, every_s=0.5,
        ...                     max_time_s=5.0)
        >>> len(df), df["t_s"].nunique()                 # 11 samples (0, 0.5, .. 5 s) x 3 robots
        (33, 11)
        >>> list(df.columns)
        ['t_s', 'robot', 'x_cm', 'y_cm', 'heading_rad', 'mode']
    """
    import numpy as np

    from swarm_sim.errors import InputError as SimInputError
    from swarm_sim.params import load_preset
    from swarm_sim.runner import resolve_params
    from swarm_sim.runner import simulate as run_sim
    from swarm_sim.state import Mode

    if isinstance(every_s, bool) or not isinstance(every_s, (int, float)) or not (
            math.isfinite(every_s) and every_s > 0):
        raise SimInputError(f"every_s {every_s!r}: must be a positive number of simulated seconds")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise SimInputError(f"seed must be a non-negative integer, got {seed!r}")
    if "check_invariants" in overrides or "until" in overrides:
        raise SimInputError("trajectory() takes preset parameters only (not check_invariants / until)")
    preset = _preset_arg(preset)
    if robots is None or void_width_robots is None:
        base = load_preset(preset)
        robots = base.robots if robots is None else robots
        void_width_robots = base.void_width if void_width_robots is None else void_width_robots
    max_time_s = overrides.pop("max_time_s", None)
    p = resolve_params(preset, robots, void_width_robots, _limits_arg(limits), max_time_s, **overrides)
    if every_s < p.dt_s - 1e-12:
        raise SimInputError(f"every_s {every_s:g}: shorter than one step ({p.dt_s:g} s)")
    pd = _pandas("trajectory")  # after the input checks, before the run
    sampler = _Sampler(float(every_s), p.dt_s)
    state, res = run_sim(p, int(seed), on_step=sampler)
    sampler.finish(state)
    k, n = len(sampler.t), p.robots
    names = np.array([m.name for m in sorted(Mode, key=int)], dtype=object)
    df = pd.DataFrame({
        "t_s": np.repeat(np.round(np.array(sampler.t), 6), n),
        "robot": np.tile(np.arange(n), k),
        "x_cm": np.concatenate(sampler.x),
        "y_cm": np.concatenate(sampler.y),
        "heading_rad": np.concatenate(sampler.h),
        "mode": names[np.concatenate(sampler.mode).astype(int)],
    }, columns=list(TRAJECTORY_COLUMNS))
    df.attrs["run"] = res.to_dict()
    df.attrs["every_s"] = float(every_s)
    return df


def sweep(preset: str | os.PathLike = "case-d", robots: int | str | Iterable[int] = "3-4",
          void_width_robots: int | str | Iterable[int] = 1, runs: int = 2, limits: str | os.PathLike = "derived",
          seed: int = 0, db: str | os.PathLike | None = None, executor: str = "serial", workers: int | None = None,
          resume: bool = True, max_time_s: float | None = None, **overrides: Any) -> pandas.DataFrame:
    """A small Monte-Carlo sweep over swarm sizes x void widths x seeds, one DataFrame row per run.

    Uses the sweep machinery of ``voidcross sweep`` (``swarm_sim.sweeps``: ``SweepSpec``,
    ``run_sweep``, the SQLite ``ResultStore``): every point is validated before anything runs,
    each run is stored as it completes, and run ``i`` of a point uses seed ``seed + i`` (replay
    one with ``simulate(..., seed=...)``).

    Args:
        preset: as :func:`simulate`.
        robots: swarm sizes: an int, a list of ints or a range text ``"3-18,20"``.
        void_width_robots: void widths in robot widths, same forms.
        runs: seeded runs per (robots, void width) point.
        limits: as :func:`simulate`.
        seed: first seed.
        db: results database (SQLite) to store the runs in and resume from, e.g.
            ``results/d.sqlite`` (``voidcross sweep status/export --db`` and ``voidcross report
            --db`` read it); ``None``: a temporary database, deleted afterwards.
        executor: ``"serial"`` (this process: no start-up cost, best for small sweeps),
            ``"local"`` (a pool of ``workers`` processes) or ``"dask"`` (a local Dask cluster).
        workers: processes for ``local``/``dask`` (default: the CPU count).
        resume: on a ``db`` that already holds this sweep, run only the missing runs (``False``:
            refuse, as ``voidcross sweep`` without ``--resume`` does).
        max_time_s: simulated-time cap per run (default: the preset's guard).
        **overrides: preset parameters by their flat names, as :func:`simulate`.

    Returns:
        ``pandas.DataFrame``, one row per run of this sweep (other sweeps in ``db`` are left out),
        ordered by robots, void width, seed; columns (:data:`SWEEP_COLUMNS`): ``preset``,
        ``robots``, ``void_width_robots``, ``seed``, ``limits``, ``limits_source``, ``status``
        (``ok`` / ``error``: a run that raised is stored with its ``error_type``), ``success``,
        ``retreated``, ``timed_out``, ``end_reason``, ``robots_lost``, ``robots_delivered``,
        ``robots_on_initial_side``, ``min_robots_rule``, ``record_min_robots``, ``Ts_s`` ..
        ``Tt_s`` (the thesis's phase times, simulated s), ``assembly_s``, ``disassembly_s``,
        ``levels_used`` (``"line -> arch-4x2-staggered"``), ``seed_robot``, ``seed_x_cm``,
        ``seed_y_cm``, ``target_finder``, ``steps``, ``hand_overs``, ``wall_s`` (real s per run),
        ``error_type``. ``df.attrs["summary"]`` is the sweep summary (``SweepSummary.to_dict()``)
        and ``df.attrs["db"]`` the database path (``None`` when temporary).

    Raises:
        InputError: a bad preset, range, run count, limits, executor or database, a point that
            does not validate, or (``resume=False``) a database already holding this sweep.
        ModuleNotFoundError: pandas is not installed (checked before anything runs).

    Example:
        >>> from voidcross import api
        >>> df = api.sweep("case-d", robots=[2, 3], void_width_robots=1, runs=2, limits="thesis")
        >>> df[["robots", "seed", "success", "end_reason", "Tt_s"]].shape
        (4, 5)
        >>> df.groupby("robots")["success"].mean().to_dict()     # the thesis: N = 3 w crosses
        {2: 0.0, 3: 1.0}
    """
    from swarm_sim.errors import InputError as SimInputError
    from swarm_sim.sweeps import ResultStore, SweepSpec, run_sweep
    from swarm_sim.sweeps.store import TIME_COLUMNS
    from swarm_sim.sweeps.sweep import limits_digest, preflight

    if executor not in EXECUTORS:
        raise SimInputError(f"executor {executor!r}: choose one of {', '.join(EXECUTORS)}")
    if isinstance(runs, bool) or not isinstance(runs, int):
        raise SimInputError(f"runs {runs!r}: must be an integer >= 1")
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise SimInputError(f"seed {seed!r}: must be an integer >= 0")
    spec = SweepSpec(_preset_arg(preset), _ints(robots, "robots"), _ints(void_width_robots, "void_width_robots"),
                     runs=runs, limits=_limits_arg(limits), seed0=seed,
                     max_time_s=None if max_time_s is None else float(max_time_s), overrides=dict(overrides))
    preflight(spec)  # every point validated by the simulator's own checks, before anything is written
    keys = {(k["preset"], k["param_hash"], k["seed"]) for k in spec.keys(limits_digest(spec.limits))}
    pd = _pandas("sweep")  # after the input checks, before any run or file

    def collect(path) -> pandas.DataFrame:
        summary = run_sweep(spec, path, executor=executor, workers=workers, resume=resume)
        rows = []
        with ResultStore.open_readonly(path) as store:
            for r in store.iter_runs("WHERE preset=?", (spec.preset,)):
                if (r["preset"], r["param_hash"], r["seed"]) not in keys:
                    continue
                res = json.loads(r["result_json"]) if r["result_json"] else {}
                row = {"preset": r["preset"], "robots": r["robots"], "void_width_robots": r["void_width"],
                       "seed": r["seed"], "limits": r["limits"], "limits_source": r["limits_source"],
                       "status": r["status"],
                       "success": None if r["success"] is None else bool(r["success"]),
                       "retreated": None if r["retreated"] is None else bool(r["retreated"]),
                       "timed_out": res.get("timed_out"), "end_reason": res.get("end_reason"),
                       "robots_lost": r["robots_lost"], "assembly_s": res.get("assembly"),
                       "disassembly_s": res.get("disassembly"),
                       "levels_used": " -> ".join(res.get("levels_used") or []) if res else None,
                       "seed_robot": r["seed_robot"], "seed_x_cm": r["seed_x_cm"], "seed_y_cm": r["seed_y_cm"],
                       "target_finder": r["target_finder"], "wall_s": r["wall_s"], "error_type": r["error_type"]}
                for k in ("robots_delivered", "robots_on_initial_side", "min_robots_rule", "record_min_robots",
                          "steps", "hand_overs"):
                    row[k] = res.get(k)
                for k, col in TIME_COLUMNS.items():
                    row[f"{k}_s"] = r[col]
                rows.append(row)
        df = pd.DataFrame(rows, columns=list(SWEEP_COLUMNS))
        df.attrs["summary"] = summary.to_dict()
        return df

    if db is not None:
        df = collect(Path(db))
        df.attrs["db"] = str(db)
        return df
    with tempfile.TemporaryDirectory(prefix="voidcross-sweep-") as tmp:
        df = collect(Path(tmp) / "sweep.sqlite")
    df.attrs["summary"]["db"] = None
    df.attrs["db"] = None
    return df


# --------------------------------------------------------------------------- structure_fem

def limits(name: str | os.PathLike = "derived") -> StructureLimits:
    """The structure-limits record the simulator reads: which structure spans which void.

    Calls :func:`structure_fem.limits.load_limits` (what ``--limits`` of ``sim run`` and
    ``sweep`` resolves). Importing it needs neither exudyn nor cadquery.

    Args:
        name: ``"derived"`` (the packaged ``structure_fem/data/limits.json``, derived from the
            robots' mechanics), ``"thesis"`` (the thesis's own thresholds and counting rules), or
            the path of a limits.json (``voidcross fem table`` writes one).

    Returns:
        ``structure_fem.limits.StructureLimits``: ``source``, ``robot``, ``clearance_mm``,
        ``levels`` (each a ``StructureLevel``: ``name``, ``kind``, ``lines``, ``layers``,
        ``min_span_widths`` .. ``max_span_widths`` in robot widths, ``ground_ratio``,
        ``ground_margin``, ``min_robots`` per width); ``max_span_widths``, ``thresholds()``,
        ``level_for(w)``, ``min_robots(w)``; ``to_dict()`` is the JSON record.

    Raises:
        InputError: (``structure_fem.errors.InputError``) not ``derived``, ``thesis`` or an
            existing, valid limits.json.

    Example:
        >>> from voidcross import api
        >>> api.limits("thesis").thresholds()
        {'line': 5, 'two_line': 10, 'arch': 15, 'arch_levels': [20, 25, 30]}
        >>> api.limits().min_robots(3)                  # derived: N = 2 w + 1
        7
        >>> api.limits().level_for(8).name
        'arch-4x2-staggered'
    """
    from structure_fem.errors import InputError as FemInputError
    from structure_fem.limits import load_limits

    if not isinstance(name, (str, os.PathLike)) or not str(name):
        raise FemInputError(f"limits {name!r}: must be 'derived', 'thesis' or a path to a limits.json file")
    return load_limits(os.fspath(name))


def _fem_options(properties, robot, clearance_mm, caster, connectors, max_width_robots, stiffness_scale,
                 backlash_scale, mass_scale, tipping, flexible, dynamic=True):
    from structure_fem.outputs.runs import RunOptions

    try:
        import exudyn  # noqa: F401
    except ImportError:
        raise ModuleNotFoundError("structure_fem's multibody model needs exudyn, which is not installed: "
                                  "pip install 'voidcross[fem]'", name="exudyn") from None
    return RunOptions(properties=None if properties is None else os.fspath(properties), robot=robot,
                      clearance_mm=clearance_mm, caster=caster, connectors=connectors,
                      stiffness_scale=stiffness_scale, backlash_scale=backlash_scale, mass_scale=mass_scale,
                      required_tipping=tipping, flexible=flexible, max_width=max_width_robots, dynamic=dynamic)


def fem_table(properties: str | os.PathLike | None = None, robot: str = "cubot", clearance_mm: float | None = None,
              caster: bool = False, connectors: str = "fe", max_width_robots: int = 30,
              stiffness_scale: float = 1.0, backlash_scale: float = 1.0, mass_scale: float = 1.0,
              tipping: float = 1.0, flexible: bool = True, dynamic: bool = True,
              out: str | os.PathLike | None = None) -> list[dict]:
    """The structure-selection table, one record per void width, as ``voidcross fem table`` derives it.

    Calls :func:`structure_fem.outputs.runs.run_table` (the function behind ``voidcross fem table``; its
    ``--json --full-json`` output holds these rows under ``table``): the multibody model solves
    every candidate structure, finds each one's threshold, and the table gives, for each void
    width, the structure used and its launch and bridged states. Each record also carries its
    structure's derived threshold (``threshold_widths``, from the same run's
    ``thresholds_per_structure``) and the robots it needs there. Takes ~10 s for
    ``max_width_robots=6`` and ~2 min for 30 on a busy 2-core machine (margins and ranges included). Needs exudyn.

    Args:
        properties: a ``robot_properties.json`` (``voidcross cad export`` writes one); ``None``:
            the packaged ``cubot_cad/data/robot_properties.json``.
        robot: robot model in the properties file (``cubot``, ``octbot``, ``cube-robot``).
        clearance_mm: climb clearance in mm (default: the robot's exposed main-wheel height,
            15 mm for the CuBot).
        caster: strict alternative: clearance = the exposed caster height (from the record: 2.78 mm for the CuBot since the caster socket holds its ball with a 0.3 mm undercut).
        connectors: ``"fe"`` (default, as the CLI: the CuBot front-rear coupling's stiffness from
            the cached 3D finite-element solve, the rest from the record, each with its
            provenance), ``"properties"`` (the robot's own coupling record, hand formulas) or
            ``"calibrated"`` (the record scaled by the test-platform calibration).
        max_width_robots: widest void studied, in robot widths (1..100).
        stiffness_scale, backlash_scale, mass_scale: multiply every coupling stiffness, every
            backlash, the robot's mass and inertia (sensitivity studies).
        tipping: required tipping safety factor at the longest cantilever (>= 1).
        flexible: the robots bend with their printed shell's section from the CAD (default);
            False: rigid bodies.
        dynamic: threshold criterion static tip + launch-transient allowance <= clearance
            (default; cached by input hash); False: static tip <= clearance.
        out: also keep the files ``fem table`` writes (``selection_table.md/.csv``,
            ``limits.json``, ``thesis_tapering_arches.csv``) in this directory; ``None``: a
            temporary directory, deleted.

    Returns:
        list of dicts, one per void width 1..``max_width_robots``: ``width`` (robot widths),
        ``band`` (``"lo-hi"``: the widths this structure is used for, or ``"beyond"``),
        ``structure`` (``line``, ``arch-4x2-staggered`` .., ``none`` beyond the widest),
        ``lines``, ``layers``, ``min_robots``, ``thesis_robots``, ``launch_initial`` /
        ``launch_over`` / ``launch_target`` and ``bridged_initial`` / ``bridged_over`` /
        ``bridged_target`` (robots on each ground and over the void), ``max_deflection_mm``,
        ``bridged_deflection_mm``, ``margin_mm`` (clearance minus tip), ``min_tipping_factor``,
        ``thesis_count_tipping``, ``case_a_count_tipping``, ``converged``, ``note``,
        ``threshold_widths`` and ``robots_at_threshold`` (of the row's structure; ``None``
        beyond). Missing values are ``None``, never NaN. A static solve that did not converge
        is reported as a ``RuntimeWarning`` (the CLI's ``warning: ...`` line), never silently.

    Raises:
        InputError: (``structure_fem.errors.InputError`` / ``cubot_cad.errors.InputError``) a
            missing or invalid properties file, an unknown robot, conflicting ``clearance_mm``
            and ``caster``, a bad scale or width: the message names the value.
        ModuleNotFoundError: exudyn is not installed.

    Example:
        >>> from voidcross import api
        >>> rows = api.fem_table(max_width_robots=6)
        >>> [(r["width"], r["structure"], r["threshold_widths"]) for r in rows][4:6]
        [(5, 'line', 5), (6, 'arch-4x2-staggered', 6)]
        >>> rows[2]["max_deflection_mm"], rows[2]["min_robots"]      # 3-wide void: the line
        (4.97, 7)
    """
    from structure_fem.outputs.runs import run_table

    opts = _fem_options(properties, robot, clearance_mm, caster, connectors, max_width_robots, stiffness_scale,
                        backlash_scale, mass_scale, tipping, flexible, dynamic)

    def records(res: dict) -> list[dict]:
        for line in res.get("warnings", ()):  # solves that did not converge, as the CLI's stderr lines
            warnings.warn(line.removeprefix("warning: "), RuntimeWarning, stacklevel=3)
        th, n_at = res["thresholds_per_structure"], res["robots_at_threshold"]
        return [{**row, "threshold_widths": th.get(row["structure"]), "robots_at_threshold":
                 n_at.get(row["structure"])} for row in res["table"]]

    if out is not None:
        from voidcross.output import out_dir

        return records(run_table(out_dir(out, "out", create=False), opts, alternative=False, plots=False,
                                 ranges=False))
    with tempfile.TemporaryDirectory(prefix="voidcross-fem-") as tmp:  # the records carry no range: not solved
        return records(run_table(Path(tmp), opts, alternative=False, plots=False, ranges=False))


def deflection_curves(properties: str | os.PathLike | None = None, robot: str = "cubot",
                      clearance_mm: float | None = None, caster: bool = False, connectors: str = "fe",
                      max_width_robots: int = 8, stiffness_scale: float = 1.0, backlash_scale: float = 1.0,
                      mass_scale: float = 1.0, tipping: float = 1.0, flexible: bool = True,
                      dynamic: bool = True) -> list[dict]:
    """Tip deflection at the longest cantilever for each candidate structure and void width.

    What ``voidcross fem study`` writes to ``deflection_vs_width.csv`` and plots in
    ``deflection_vs_width.png``: :func:`structure_fem.analysis.study.derive` on the inputs
    ``structure_fem.outputs.runs.make_inputs`` builds, one record per solved (structure, width). Each
    structure is solved at its minimal row count (the fewest rows that stand) with its front
    at the far edge, the worst moment of the launch; widths are those the threshold search
    solved (1..8 one by one, then doubling and bisection, 2 past the threshold), up to
    ``max_width_robots``. Tens of seconds cold on 2 cores (the arches' solves, and with ``dynamic``
    the launch transients at each threshold), then served by the solve cache. Needs exudyn.

    Args:
        properties, robot, clearance_mm, caster, connectors, stiffness_scale, backlash_scale,
            mass_scale, tipping, flexible, dynamic: as :func:`fem_table` (``dynamic`` sets only
            ``threshold_widths``: static tip + launch allowance <= clearance, or the tip alone).
        max_width_robots: widest void studied, in robot widths.

    Returns:
        list of dicts: ``structure`` (``line``, ``two_line-aligned``, ``two_line-staggered``,
        ``arch-4x2-staggered``, ``arch-6x3-staggered``, ``arch-8x4-staggered``),
        ``void_width_robots``, ``tip_deflection_mm``, ``tipping_factor`` (``None`` when it
        cannot tip), ``rows``, ``robots``, ``clearance_mm``, ``within_clearance`` (tip <=
        clearance) and ``threshold_widths`` (the structure's widest void within the clearance).
        A width whose solve did not converge is left out (it counts as failing) and reported as a
        ``RuntimeWarning``.

    Raises:
        InputError: as :func:`fem_table`.
        ModuleNotFoundError: exudyn is not installed.

    Example:
        >>> from voidcross import api
        >>> curves = api.deflection_curves(max_width_robots=4)
        >>> [round(c["tip_deflection_mm"], 2) for c in curves if c["structure"] == "line"]
        [0.54, 2.18, 4.97, 9.22]
    """
    from structure_fem.analysis.study import derive
    from structure_fem.outputs.runs import make_inputs

    opts = _fem_options(properties, robot, clearance_mm, caster, connectors, max_width_robots, stiffness_scale,
                        backlash_scale, mass_scale, tipping, flexible, dynamic)
    inp, _ = make_inputs(opts)
    d = derive(inp, extra=2)
    for f in d.failures:  # never silent: a width whose solve did not converge counts as failing
        warnings.warn(f"{f.structure} at void width {f.width}: {f.what} did not converge ({f.counted_as})",
                      RuntimeWarning, stacklevel=2)
    clear = inp.clearance_m * 1e3
    out = []
    for c in d.curves:
        for i, w in enumerate(c.widths):
            tf = c.tipping[i]
            out.append({"structure": c.structure.name, "void_width_robots": w, "tip_deflection_mm": c.tip_mm[i],
                        "tipping_factor": tf if math.isfinite(tf) else None, "rows": c.rows[i],
                        "robots": c.robots[i], "clearance_mm": clear, "within_clearance": c.tip_mm[i] <= clear,
                        "threshold_widths": c.threshold})
    return out
