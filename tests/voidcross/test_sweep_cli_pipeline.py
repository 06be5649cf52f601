"""The sim and report pipeline stages, and one sweep through the real simulator."""

from __future__ import annotations

import json
import sqlite3

import pytest

from swarm_sim.sweeps import SweepSpec, prepare_sweep
from swarm_sim.sweeps.executors import SerialExecutor

SYNTH = "swarm_sim.sweeps.synthetic:synthetic_run"


def test_sim_then_report_stage_set_ctx_and_resume(tmp_path, monkeypatch):
    from voidcross.commands import report, sweep

    monkeypatch.setattr(sweep, "PIPELINE_RUN_FN", SYNTH)
    ctx: dict = {"limits": "thesis"}
    line = sweep.pipeline_stage(tmp_path / "sim", ctx)
    assert sweep.pipeline_points("thesis") == ((2, 1), (3, 1), (5, 2), (6, 2))  # 3w - 1 and 3w
    planned = 4 * sweep.PIPELINE_RUNS
    assert f"{planned}/{planned}" in line and ctx["db"].endswith(".sqlite")
    # the points straddle N = 3w - 1 / 3w: half cross
    con = sqlite3.connect(ctx["db"])
    assert con.execute("SELECT SUM(success), COUNT(*) FROM runs").fetchone() == (planned // 2, planned)
    con.close()
    # a second pipeline run resumes instead of refusing or duplicating
    assert f"{planned}/{planned}" in sweep.pipeline_stage(tmp_path / "sim", ctx)
    first_db = ctx["db"]
    # other limits (e.g. structure_fem re-derived them): a new database, not a refusal
    ctx2 = {"limits": "derived"}
    sweep.pipeline_stage(tmp_path / "sim", ctx2)
    assert ctx2["db"] != first_db
    line = report.pipeline_stage(tmp_path / "report", ctx)
    assert line == f"report at {ctx['report']}" and ctx["report"].endswith("index.html")


def test_report_stage_without_db_is_unavailable(tmp_path):
    from voidcross.commands import report
    from voidcross.pipeline import StageUnavailable

    with pytest.raises(StageUnavailable):
        report.pipeline_stage(tmp_path, {})


def test_real_simulator_through_the_sweep(tmp_path):
    try:
        import swarm_sim.runner  # noqa: F401
    except ImportError as exc:
        pytest.skip(f"swarm_sim.runner is not importable yet ({exc})")
    db = tmp_path / "real.sqlite"
    spec = SweepSpec("case-d", points=((3, 1),), runs=2, limits="thesis", max_time_s=20.0)
    plan = prepare_sweep(spec, db)  # the default run function: the simulator
    with SerialExecutor() as ex:
        rows = list(plan.execute(ex))
    plan.close()
    assert len(rows) == 2
    assert all(r["status"] == "ok" for r in rows), rows[0].get("error")
    for r in rows:
        res = json.loads(r["result_json"])
        assert res["robots"] == 3 and res["void_width"] == 1 and res["seed"] == r["seed"]
        assert res["robots_lost"] == 0 == r["robots_lost"]
        assert set(res["times"]) >= {"Ts", "Ta", "To", "Td", "Tb", "Tt"}
    # the same seed replays the same run
    from swarm_sim.runner import run_scenario

    again = run_scenario("case-d", 3, 1, rows[0]["seed"], limits="thesis", max_time_s=20.0).to_dict()
    assert again["times"] == json.loads(rows[0]["result_json"])["times"]


def test_pipeline_points_follow_the_limits(tmp_path):
    from dataclasses import replace

    from structure_fem.limits import thesis_limits
    from voidcross.commands import sweep

    lim = thesis_limits()
    line = replace(lim.levels[0], min_robots=(4, 7, 9, 12, 15))
    path = tmp_path / "limits.json"
    replace(lim, levels=(line, *lim.levels[1:])).save(path)
    assert sweep.pipeline_points(str(path)) == ((3, 1), (4, 1), (6, 2), (7, 2))


def test_the_thesis_stage_fills_every_thesis_table_of_the_demo_report(tmp_path, monkeypatch):
    """`make demo` runs Chapter 4 at one run per cell into the pipeline's database, so the report
    has ours beside the thesis's in all of Tables 4.4-4.9, not only case D's."""
    from voidcross.commands import report, reproduce, sweep

    monkeypatch.setattr(sweep, "PIPELINE_RUN_FN", SYNTH)
    monkeypatch.setattr(reproduce, "PIPELINE_RUN_FN", SYNTH)
    ctx: dict = {"limits": "thesis"}
    sweep.pipeline_stage(tmp_path / "sim", ctx)
    db = ctx["db"]
    line = reproduce.pipeline_stage(tmp_path / "thesis", ctx)
    assert ctx["db"] == db and "(A 20, B 30, C 80, D " in line and "(3 beyond the grid's largest swarm)" in line
    con = sqlite3.connect(db)
    n = dict(con.execute("SELECT preset, COUNT(*) FROM runs WHERE limits='thesis' GROUP BY preset").fetchall())
    assert n["case-a"] == 20 and n["case-b"] == 30 and n["case-c"] == 80 and n["case-d"] >= 105
    reproduce.pipeline_stage(tmp_path / "thesis", ctx)  # resumes: nothing runs twice
    assert con.execute("SELECT COUNT(*) FROM runs").fetchone()[0] == sum(n.values())
    con.close()
    report.pipeline_stage(tmp_path / "report", ctx)
    md = (tmp_path / "report" / "report.md").read_text()
    for t in ("4.4", "4.5", "4.6", "4.7", "4.8", "4.9"):
        assert f"thesis_table_{t.replace('.', '_')}_ratio.png" in md or t in ("4.5", "4.8"), t
    assert "no case-a runs" not in md and "no case-b runs" not in md
