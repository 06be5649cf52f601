"""The report's failure-rate curves (issue 16): runs with faults are summarised apart from the
fault-free tables, one row per fault spec, with the curve of crossing rate vs failed fraction."""

from __future__ import annotations

import csv

import pytest

from swarm_sim.sweeps import SweepSpec, run_sweep
from voidcross.report import build_report


@pytest.fixture(scope="module")
def fault_report(tmp_path_factory):
    d = tmp_path_factory.mktemp("faults")
    db = d / "f.sqlite"
    for faults in ("", "drive:200/h"):
        run_sweep(SweepSpec("case-d", (6,), (1,), runs=3, limits="derived", seed0=10,
                            overrides={"faults": faults} if faults else {}), db, executor="serial")
    return d, build_report(db, d / "report", watch=None)


def test_fault_runs_get_their_own_section_and_curve(fault_report):
    d, res = fault_report
    md = (d / "report" / "report.md").read_text()
    assert "Robots that fail" in md and "drive:200/h" in md
    curve = res["fault_curves"]["case-d N=6 w=1"]
    assert [row["faults"] for row in curve] == ["none", "drive:200/h"]
    none, hard = curve
    assert none["runs"] == hard["runs"] == 3 and none["failed_fraction"] == 0.0 and hard["failed_fraction"] > 0
    assert hard["lost"] == 0
    rows = list(csv.DictReader(open(d / "report" / "figures" / "faults_case-d.csv")))
    assert {r["faults"] for r in rows} == {"none", "drive:200/h"}
    assert (d / "report" / "figures" / "faults_case-d.png").stat().st_size > 1000


def test_fault_runs_stay_out_of_the_fault_free_tables(fault_report):
    d, res = fault_report
    assert res["runs"] == 6
    html = (d / "report" / "index.html").read_text()
    assert "6 completed runs (3 with faults)" in html
