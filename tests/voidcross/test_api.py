"""voidcross.api: the Python API for notebooks and scripts, read as its spec.

Small swarms, 1-wide voids and capped simulated time keep every test to a few seconds. The
DataFrame functions need pandas, which is optional: their tests skip without it, and one test
checks the error a user without pandas gets.
"""

from __future__ import annotations

import inspect
import math
import sys

import pytest

from swarm_sim.errors import InputError as SimInputError
from voidcross import api

THESIS_W = 1  # a 1-wide void: the thesis's minimum swarm is 3 robots


# --------------------------------------------------------------------------- simulate

def test_a_swarm_at_the_thesis_minimum_crosses_and_one_fewer_retreats():
    n_min = api.limits("thesis").min_robots(THESIS_W)
    assert n_min == 3 * THESIS_W  # the thesis's rule: N = 3 w
    at = api.simulate("case-d", robots=n_min, void_width_robots=THESIS_W, limits="thesis", seed=1)
    assert at.success and at.end_reason == "crossed"
    assert at.robots_lost == 0 and at.robots_delivered == n_min
    below = api.simulate("case-d", robots=n_min - 1, void_width_robots=THESIS_W, limits="thesis", seed=1)
    assert below.retreated and below.end_reason == "retreated-no-robots"
    assert below.robots_lost == 0 and below.robots_on_initial_side == n_min - 1
    assert below.times["Tt"] > 0  # simulated seconds


def test_same_arguments_same_run_and_the_result_record_is_the_cli_record():
    a = api.simulate(robots=2, void_width_robots=1, limits="thesis", seed=3)
    b = api.simulate(robots=2, void_width_robots=1, limits="thesis", seed=3)
    da, db = a.to_dict(), b.to_dict()
    da.pop("wall_s"), db.pop("wall_s")
    assert da == db
    assert {"success", "retreated", "timed_out", "end_reason", "times", "robots_lost"} <= set(da)


def test_overrides_take_unit_named_preset_parameters():
    res = api.simulate("case-d", robots=3, void_width_robots=1, seed=0, max_time_s=2.0, arena_w_cm=400.0,
                       target_x_cm=380.0)
    assert res.timed_out and res.times["Tt"] is None  # capped at 2 simulated seconds
    assert res.steps == 200  # dt_s = 0.01


def test_robots_and_void_width_none_take_the_presets_own(tmp_path):
    toml = tmp_path / "tiny.toml"
    toml.write_text('[scenario]\nrobots = 2\nvoid_width = 1\n\n[sim]\nmax_time_s = 1.0\n')
    res = api.simulate(toml, robots=None, void_width_robots=None)
    assert (res.preset, res.robots, res.void_width, res.timed_out) == ("tiny", 2, 1, True)


@pytest.mark.parametrize("kwargs, named", [
    ({"robots": 0}, "robots must be a positive integer, got 0"),
    ({"robots": 2.5}, "robots must be an integer, got 2.5"),
    ({"void_width_robots": 0}, "void_width must be a positive integer"),
    ({"void_width_robots": 60}, "void_width 60"),
    ({"preset": "case-z"}, "unknown preset 'case-z'"),
    ({"arena_width": 800.0}, "unknown parameter 'arena_width'"),
    ({"arena_w_cm": "wide"}, "arena_w_cm must be float, got 'wide'"),
    ({"limits": "nonsense"}, "nonsense"),
    ({"seed": -1}, "seed must be a non-negative integer, got -1"),
])
def test_bad_input_raises_input_error_naming_the_value(kwargs, named):
    with pytest.raises(SimInputError) as exc:
        api.simulate(**{"robots": 3, "void_width_robots": 1, **kwargs})
    assert named in str(exc.value)
    assert isinstance(exc.value, api.InputError)  # one base class to catch for every package


# --------------------------------------------------------------------------- trajectory

def test_trajectory_samples_every_period_and_the_end_of_a_capped_run():
    pytest.importorskip("pandas")
    df = api.trajectory("case-d", robots=3, void_width_robots=1, seed=1, every_s=0.5, max_time_s=5.0)
    assert list(df.columns) == ["t_s", "robot", "x_cm", "y_cm", "heading_rad", "mode"]
    # 0, 0.5, .., 5.0 s: floor(5 / 0.5) + 1 = 11 samples, one row per robot each
    assert sorted(df["t_s"].unique()) == pytest.approx([0.5 * i for i in range(11)])
    assert len(df) == 11 * 3
    assert df.groupby("t_s")["robot"].apply(lambda ids: sorted(ids) == [0, 1, 2]).all()
    assert df["x_cm"].between(0, 500).all() and df["y_cm"].between(0, 300).all()
    assert set(df["mode"]) <= {"EXPLORE", "SEED", "RECRUIT", "MEMBER", "TARGET", "RETREAT", "STOPPED"}
    assert df.attrs["run"]["timed_out"] and df.attrs["every_s"] == 0.5


def test_trajectory_of_a_run_that_ends_between_samples_keeps_its_last_state():
    pytest.importorskip("pandas")
    df = api.trajectory("case-d", robots=2, void_width_robots=1, limits="thesis", seed=0, every_s=10.0)
    run = df.attrs["run"]
    assert run["end_reason"] == "retreated-no-robots"
    t_end = run["times"]["Tt"]
    n = math.floor(t_end / 10.0) + 1 + (t_end % 10.0 > 1e-9)
    assert df["t_s"].nunique() == n and len(df) == 2 * n
    assert df["t_s"].max() == pytest.approx(t_end)
    last = df[df["t_s"] == df["t_s"].max()]
    assert (last["mode"] == "STOPPED").all()  # every robot safe and stopped on the initial side


@pytest.mark.parametrize("every_s, named", [(0, "every_s 0"), (-1.0, "every_s -1"), ("1", "every_s '1'"),
                                            (0.001, "shorter than one step")])
def test_trajectory_bad_period_raises_input_error(every_s, named):
    with pytest.raises(SimInputError, match="every_s") as exc:
        api.trajectory(robots=2, void_width_robots=1, every_s=every_s, max_time_s=1.0)
    assert named in str(exc.value)


# --------------------------------------------------------------------------- sweep

def test_sweep_dataframe_has_one_row_per_run_and_unit_named_columns(tmp_path):
    pytest.importorskip("pandas")
    db = tmp_path / "d.sqlite"
    df = api.sweep("case-d", robots=[2, 3], void_width_robots=THESIS_W, runs=2, limits="thesis", db=db)
    assert len(df) == 2 * 1 * 2  # robots x void widths x seeds
    assert sorted(zip(df["robots"], df["seed"], strict=True)) == [(2, 0), (2, 1), (3, 0), (3, 1)]
    assert list(df.columns) == list(api.SWEEP_COLUMNS)
    for t in ("Ts", "Ta", "To", "Td", "Tb", "Tt"):
        assert f"{t}_s" in df.columns and t not in df.columns  # times carry their unit
    assert {"void_width_robots", "seed_x_cm", "seed_y_cm", "wall_s", "assembly_s"} <= set(df.columns)
    assert (df["status"] == "ok").all() and (df["robots_lost"] == 0).all()
    # the thesis's boundary: 3 robots cross a 1-wide void, 2 retreat
    assert df.groupby("robots")["success"].mean().to_dict() == {2: 0.0, 3: 1.0}
    assert set(df.loc[df["robots"] == 2, "end_reason"]) == {"retreated-no-robots"}
    assert df.attrs["db"] == str(db) and db.exists()

    again = api.sweep("case-d", robots=[2, 3], void_width_robots=THESIS_W, runs=2, limits="thesis", db=db)
    assert again.attrs["summary"]["ran"] == 0 and again.attrs["summary"]["already_stored"] == 4
    assert again["Tt_s"].tolist() == df["Tt_s"].tolist()  # resumed from the database, nothing re-run
    with pytest.raises(SimInputError, match="already holds this sweep"):
        api.sweep("case-d", robots=[2, 3], void_width_robots=THESIS_W, runs=2, limits="thesis", db=db,
                  resume=False)


def test_sweep_without_a_database_uses_a_temporary_one():
    pytest.importorskip("pandas")
    df = api.sweep("case-d", robots="2", void_width_robots="1", runs=1, limits="thesis", seed=5)
    assert len(df) == 1 and df.attrs["db"] is None
    assert df.loc[0, "seed"] == 5 and df.loc[0, "end_reason"] == "retreated-no-robots"


@pytest.mark.parametrize("kwargs, named", [
    ({"robots": "5-3"}, "range '5-3' is reversed"),
    ({"robots": [0, 3]}, "0 must be >= 1"),
    ({"void_width_robots": "one"}, "bad item 'one'"),
    ({"runs": 0}, "--runs 0"),
    ({"executor": "gpu"}, "executor 'gpu'"),
    ({"preset": "case-z"}, "unknown preset 'case-z'"),
    ({"arena_width": 800.0}, "unknown parameter 'arena_width'"),
])
def test_sweep_bad_input_raises_before_anything_is_written(tmp_path, kwargs, named):
    db = tmp_path / "never.sqlite"
    with pytest.raises(SimInputError) as exc:
        api.sweep(**{"robots": [2], "void_width_robots": 1, "runs": 1, "db": db, **kwargs})
    assert named in str(exc.value)
    assert not db.exists()


def test_without_pandas_the_dataframe_functions_say_so(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas -> ImportError
    db = tmp_path / "d.sqlite"
    with pytest.raises(ModuleNotFoundError, match=r"pip install .voidcross\[api\]."):
        api.sweep(robots=[2], void_width_robots=1, runs=1, db=db)
    assert not db.exists()  # checked before any run
    with pytest.raises(ModuleNotFoundError, match=r"trajectory\(\) returns a pandas.DataFrame"):
        api.trajectory(robots=2, void_width_robots=1, max_time_s=1.0)


# --------------------------------------------------------------------------- limits

def test_limits_records_derived_thesis_and_a_file(tmp_path):
    thesis = api.limits("thesis")
    assert thesis.thresholds() == {"line": 5, "two_line": 10, "arch": 15, "arch_levels": [20, 25, 30]}
    derived = api.limits()
    assert derived.source == "derived" and derived.levels[0].kind == "line"
    path = derived.save(tmp_path / "limits.json")
    assert api.limits(path) == derived and api.limits(str(path)) == derived


@pytest.mark.parametrize("name", ["nonsense", "/no/such/limits.json", 5])
def test_limits_bad_name_raises_input_error_naming_it(name):
    from structure_fem.errors import InputError as FemInputError

    with pytest.raises(FemInputError, match=str(name)):
        api.limits(name)


# --------------------------------------------------------------------------- structure_fem

@pytest.fixture(scope="module")
def table(tmp_path_factory):
    """The table for voids 1..6 wide from the packaged robot_properties.json, without the thesis's
    tapering arches (up to 470-robot models, minutes of solves since the wedge latch; they are
    tested in tests/structure_fem/test_tapered_arch.py, not what the API's records are about)."""
    pytest.importorskip("exudyn")
    import structure_fem.outputs.runs as runs

    out = tmp_path_factory.mktemp("fem")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(runs, "tapered_arches", lambda d, thesis=None, progress=None: [])
        return out, api.fem_table(max_width_robots=6, dynamic=False, out=out)


def test_fem_table_records_carry_thresholds_for_each_structure(table):
    out, rows = table
    assert [r["width"] for r in rows] == list(range(1, 7))
    structures = {r["structure"] for r in rows}
    assert "line" in structures  # (the structures used up to 6 widths move with the coupling: issue 38)
    for s in structures:
        mine = [r for r in rows if r["structure"] == s]
        th = {r["threshold_widths"] for r in mine}
        assert len(th) == 1 and th.pop() == max(r["width"] for r in mine)  # widest void it is used for
        assert all(r["band"].endswith(f"-{r['threshold_widths']}") for r in mine)
        assert all(r["robots_at_threshold"] >= r["min_robots"] for r in mine)
    line = [r for r in rows if r["structure"] == "line"]
    written = api.limits(out / "limits.json")  # this (static) table's record, not the packaged dynamic one
    assert line[-1]["threshold_widths"] == written.levels[0].max_span_widths
    assert [r["min_robots"] for r in line] == [written.min_robots(r["width"]) for r in line]
    for r in rows:  # every number within the clearance, no NaN
        assert r["converged"] and 0 < r["max_deflection_mm"] <= 15.0
        assert all(not (isinstance(v, float) and math.isnan(v)) for v in r.values())
    assert (out / "selection_table.csv").stat().st_size > 0 and (out / "limits.json").exists()


def test_deflection_curves_grow_with_the_void_width():
    pytest.importorskip("exudyn")
    from cubot_cad.properties import default_properties_path

    curves = api.deflection_curves(max_width_robots=3, dynamic=False)  # the tips: no launch transients
    line = [c for c in curves if c["structure"] == "line"]
    assert [c["void_width_robots"] for c in line] == [1, 2, 3]
    tips = [c["tip_deflection_mm"] for c in line]
    assert tips == sorted(tips) and tips[0] > 0
    assert {c["structure"] for c in curves} >= {"line", "two_line-staggered", "arch-4x2-staggered"}
    # properties=None is the packaged robot_properties.json
    assert api.deflection_curves(properties=default_properties_path(), max_width_robots=3, dynamic=False) == curves
    assert all(c["threshold_widths"] == max(x["void_width_robots"] for x in curves if x["structure"] == c["structure"]
                                            and x["within_clearance"]) for c in curves if c["within_clearance"])


@pytest.mark.parametrize("kwargs, named", [
    ({"properties": "/no/such/robot_properties.json"}, "/no/such/robot_properties.json"),
    ({"robot": "nobot"}, "nobot"),
    ({"clearance_mm": 10.0, "caster": True}, "not both"),
    ({"max_width_robots": 0}, "got 0"),
    ({"connectors": "guessed"}, "'guessed'"),
])
def test_fem_bad_input_raises_input_error_naming_the_value(kwargs, named):
    pytest.importorskip("exudyn")
    with pytest.raises(api.InputError) as exc:
        api.fem_table(**kwargs)
    assert named in str(exc.value)


# --------------------------------------------------------------------------- the docstrings

@pytest.mark.parametrize("name", ["simulate", "trajectory", "sweep", "limits", "fem_table", "deflection_curves"])
def test_every_function_documents_units_and_an_example(name):
    doc = inspect.getdoc(getattr(api, name))
    assert "Example:" in doc and ">>> " in doc
    assert "Args:" in doc and "Returns:" in doc and "Raises:" in doc
    assert any(u in doc for u in ("_cm", "_s", "_mm", "robot widths"))
