"""`voidcross fem ...`: outputs, --json shape, bad input (one line, exit 2), properties drive the table."""

from __future__ import annotations

import csv
import json

import pytest

pytest.importorskip("exudyn")

from dataclasses import replace  # noqa: E402

from cubot_cad.properties import RobotPropertiesFile, default_properties  # noqa: E402
from structure_fem.limits import StructureLimits  # noqa: E402


def _props_file(path, robot):
    others = tuple(r for r in default_properties().robots if r.name != "cubot")
    RobotPropertiesFile((replace(robot, name="cubot"),) + others).save(path)
    return path


@pytest.fixture(scope="module")
def test_properties(tmp_path_factory, make_robot):
    """A properties file whose CuBot has test-chosen, soft couplings (fast, small thresholds)."""
    return _props_file(tmp_path_factory.mktemp("props") / "robot_properties.json",
                       make_robot(k=200.0, backlash=0.002))


@pytest.fixture(scope="module")
def modified_properties(tmp_path_factory, make_robot):
    """The same CuBot 30 % heavier with 20 % softer couplings."""
    return _props_file(tmp_path_factory.mktemp("props2") / "robot_properties.json",
                       make_robot(mass=0.39, k=160.0, backlash=0.002))


def test_table_json_outputs_and_properties_change_the_table(cli, tmp_path, test_properties, modified_properties,
                                                            monkeypatch):
    import structure_fem.outputs.runs as runs

    with monkeypatch.context() as m:  # the base table is compared by its thresholds and records only
        m.setattr(runs, "tapered_arches", lambda d, thesis=None, progress=None: [])
        base = cli("fem", "table", "--static", "--out", str(tmp_path / "base"), "--properties", str(test_properties),
                   "--json", "--max-width", "8", "--no-ranges")
    assert base.code == 0, base.err
    res = cli("fem", "table", "--static", "--out", str(tmp_path), "--properties", str(modified_properties), "--json",
              "--docs", str(tmp_path / "docs"), "--max-width", "8")
    assert res.code == 0, res.err
    out = res.json()
    assert set(out["thresholds"]) >= {"line", "two_line", "arch", "arch_levels"}
    assert out["thesis_thresholds"] == {"line": 5, "two_line": 10, "arch": 15, "arch_levels": [20, 25, 30]}
    assert out["clearance_mm"] == pytest.approx(15.0)  # the test robot's exposed wheel height
    assert out["calibration"]["bolt_stiffness_nm_per_rad"] > 0
    assert "thresholds_with_calibrated_connectors" in out["calibration"]["calibrated_alternative"]
    # issue 12: per structure the threshold, its margin, what sets it, the bodies and the range
    by = {r["structure"]: r for r in out["structures"]}
    assert set(by) == set(out["thresholds_per_structure"])
    for name, r in by.items():
        assert r["threshold"] == out["thresholds_per_structure"][name] and r["bodies"] == "flexible"
        if r["threshold"]:
            assert r["margin_mm"] >= 0 and r["set_by"] in ("play", "elastic", "bodies", "support (tipping about the edge)")
    assert by["line"]["range"]["min"] <= by["line"]["threshold"] <= by["line"]["range"]["max"]
    assert "## Thresholds, margins and what sets them" in (tmp_path / "selection_table.md").read_text()
    # the test robot is not the parametric CuBot: its hand-formula values are used, and it says why
    assert out["calibration"]["connector_sources"]["front_rear"].startswith("record (hand formula)")
    for name in ("selection_table.md", "selection_table.csv", "limits.json", "deflection_vs_width.png",
                 "side_view.png"):
        assert (tmp_path / name).stat().st_size > 0
    assert (tmp_path / "docs" / "structure_fem_table.md").exists()
    lim = StructureLimits.load(tmp_path / "limits.json")
    assert lim.source == "derived" and lim.max_span_widths == out["max_span_widths"]
    base_lim = StructureLimits.load(tmp_path / "base" / "limits.json")
    assert lim != base_lim  # different robot record -> different table
    assert (tmp_path / "selection_table.md").read_text() != (tmp_path / "base" / "selection_table.md").read_text()
    rows = list(csv.DictReader((tmp_path / "selection_table.csv").open()))
    assert [int(r["width"]) for r in rows] == list(range(1, 9))
    assert all("nan" not in json.dumps(r).lower() for r in rows)
    md = (tmp_path / "selection_table.md").read_text()
    assert "| line |" in md and "thesis" in md
    # Heavier, softer robots never cross wider.
    for kind in ("line", "two_line", "arch"):
        assert out["thresholds"][kind] <= base.json()["thresholds"][kind]
    assert out["body_bending"] if "body_bending" in out else out["calibration"]["body_bending"]
    # The thesis's tapering arches under the same mechanics: every band width, both truths side by side.
    taper = out["thesis_tapering_arches"]
    assert [r["width"] for r in taper["rows"]] == list(range(11, 31))
    assert taper["verdict"]["widths_evaluated"] == 20
    assert "## The thesis's tapering arches under our mechanics" in md and "**Verdict:" in md
    assert (tmp_path / "thesis_tapering_arches.png").stat().st_size > 0
    trows = list(csv.DictReader((tmp_path / "thesis_tapering_arches.csv").open()))
    assert [int(r["width"]) for r in trows] == list(range(11, 31))
    assert [r["passes"] == "True" for r in trows] == [r["passes"] for r in taper["rows"]]
    docs_md = (tmp_path / "docs" / "structure_fem_table.md").read_text()
    assert "(img/thesis_tapering_arches.png)" in docs_md
    assert (tmp_path / "docs" / "img" / "thesis_tapering_arches.png").stat().st_size > 0


def test_no_ranges_leaves_out_only_the_ranges(cli, tmp_path, test_properties, monkeypatch):
    """`fem table --no-ranges` (issue 40: the ranges are about half of a cold table's solves): the
    same thresholds, margins and limits.json byte for byte, the structures without their range."""
    import structure_fem.outputs.runs as runs

    monkeypatch.setattr(runs, "tapered_arches", lambda d, thesis=None, progress=None: [])

    def run(name, *extra):
        res = cli("fem", "table", "--static", "--properties", str(test_properties), "--max-width", "4", "--json",
                  "--out", str(tmp_path / name), *extra)
        assert res.code == 0, res.err
        return res.json()

    full, quick = run("full"), run("quick", "--no-ranges")
    assert quick["thresholds"] == full["thresholds"] and quick["structures"]
    assert (tmp_path / "quick" / "limits.json").read_bytes() == (tmp_path / "full" / "limits.json").read_bytes()
    for a, b in zip(full["structures"], quick["structures"], strict=True):
        assert "range" not in b and {k: v for k, v in a.items() if k != "range"} == b
    assert any("range" in a for a in full["structures"])


def test_caster_clearance_is_the_strict_alternative(cli, tmp_path):
    res = cli("fem", "solve", "--rows", "5", "--over", "2", "--void", "2", "--json", "--caster")
    assert res.code == 0, res.err
    assert res.json()["tip_deflection_mm"] > 0


@pytest.mark.parametrize("argv,word", [
    (("fem", "table", "--stiffness-scale", "0"), "--stiffness-scale 0"),
    (("fem", "table", "--mass-scale", "-1"), "--mass-scale -1"),
    (("fem", "table", "--clearance-mm", "-3"), "clearance"),
    (("fem", "solve", "--rows", "5", "--over", "2", "--void", "-2"), "void width"),
    (("fem", "solve", "--rows", "0", "--over", "0", "--void", "2"), "rows"),
    (("fem", "solve", "--structure", "arch", "--lines", "9", "--rows", "5", "--over", "2", "--void", "2"), "8 wide"),
    (("fem", "solve", "--structure", "arch", "--layers", "5", "--rows", "5", "--over", "2", "--void", "2"), "4 high"),
    (("fem", "table", "--robot", "nosuchbot"), "nosuchbot"),
    (("fem", "solve", "--structure", "line", "--taper-block-rows", "5", "--rows", "30", "--over", "15",
      "--void", "15"), "only an arch can taper"),
    (("fem", "solve", "--structure", "arch", "--lines", "6", "--layers", "3", "--taper-block-rows", "0",
      "--rows", "30", "--over", "15", "--void", "15"), "taper_block_rows=0"),
    (("fem", "table", "--properties", "/nonexistent/robot_properties.json"), "not found"),
    (("fem", "table", "--hinge", "bogus"), "bogus"),
])
def test_bad_input_is_one_line_exit_2(cli, tmp_path, argv, word):
    out = tmp_path / "out"
    res = cli(*argv, "--out", str(out)) if argv[1] == "table" else cli(*argv)
    assert res.code == 2, res.err
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:")
    assert word in res.error_lines[0]
    assert not out.exists()  # nothing created on bad input


def test_corrupt_properties_file_is_exit_2_and_keeps_old_outputs(cli, tmp_path):
    bad = tmp_path / "robot_properties.json"
    bad.write_text('{"schema_version": 1, "robots": [{"name": "cubot"')
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "limits.json").write_text("old")
    res = cli("fem", "table", "--properties", str(bad), "--out", str(tmp_path / "out"))
    assert res.code == 2 and len(res.error_lines) == 1 and "robot_properties.json" in res.error_lines[0]
    assert (tmp_path / "out" / "limits.json").read_text() == "old"


def test_non_positive_stiffness_in_properties_is_exit_2(cli, tmp_path):
    d = default_properties().to_dict()
    d["robots"][0]["connectors"][0]["rotational_stiffness_nm_per_rad"] = -1.0
    p = tmp_path / "p.json"
    p.write_text(json.dumps(d))
    res = cli("fem", "table", "--properties", str(p), "--out", str(tmp_path))
    assert res.code == 2 and "rotational_stiffness_nm_per_rad" in res.error_lines[0]


def test_pipeline_stage_sets_limits_and_fem_dir(tmp_path, test_properties, monkeypatch):
    """The stage's glue: it derives from the cad stage's record and hands limits.json and its
    folder on. Without the thesis's tapering arches (20 solves that retry for minutes on the
    soft test robot; test_never_crash runs them on the real path) and on voids 1..6 by the static
    tip (the default dynamic table to 30 widths cost 255 s here; test_never_crash integrates the
    dynamic path): this test is about the hand-over."""
    import structure_fem.outputs.runs as runs
    from voidcross.commands.fem import pipeline_stage

    monkeypatch.setattr(runs, "tapered_arches", lambda d, thesis=None, progress=None: [])
    real = runs.run_table
    seen: list = []

    def small(out, opts, **kw):  # the stage's own options, narrowed to voids 1..6 and the static tip
        seen.append(opts)
        return real(out, replace(opts, max_width=6, dynamic=False), **kw)

    monkeypatch.setattr(runs, "run_table", small)
    ctx: dict = {"robot_properties": str(test_properties)}
    line = pipeline_stage(tmp_path / "fem", ctx)
    assert "derived thresholds" in line and "thesis tapering arches hold at" in line
    assert StructureLimits.load(ctx["limits"]).source == "derived"
    assert (tmp_path / "fem" / "selection_table.md").exists() and ctx["fem_dir"] == str(tmp_path / "fem")
    # the stage asked for the default table (the launch transients on) from the cad stage's record
    assert seen[0].dynamic is True and seen[0].properties == str(test_properties)


def test_study_writes_plots_and_a_sensitivity_that_moves_the_right_way(tmp_path, test_properties):
    from structure_fem.outputs.runs import RunOptions, run_study

    grid = (("connector stiffness", "x record", (0.5, 2.0)), ("clearance", "mm", (5.0, 20.0)))
    res = run_study(tmp_path, RunOptions(properties=str(test_properties), max_width=8, dynamic=False), grid=grid)
    for key in ("deflection_plot", "side_view", "curves_csv", "sensitivity_csv", "sensitivity_plot"):
        assert (tmp_path / res["files"][key].split("/")[-1]).stat().st_size > 0
    rows = {(r["parameter"], r["value"]): r for r in res["sensitivity"]}
    for kind in ("line", "arch", "max_span"):
        assert rows[("connector stiffness", 0.5)][kind] <= rows[("connector stiffness", 2.0)][kind]
        assert rows[("clearance", 5.0)][kind] <= rows[("clearance", 20.0)][kind]
    assert rows[("clearance", 5.0)]["max_span"] < rows[("clearance", 20.0)]["max_span"]


def test_the_sensitivity_grid_by_the_tables_criterion_on_request(tmp_path, test_properties, monkeypatch):
    """`fem study --sensitivity-dynamic`: each grid point's thresholds by static tip + its own launch
    allowance (never wider than by the static tip alone, and narrower somewhere: the allowance is
    real), the JSON says which criterion; the default grid stays static and says so."""
    import structure_fem.analysis.study as study
    from structure_fem.outputs.runs import RunOptions, sensitivity

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    every = study.candidate_structures  # the line, both two lines and the 4 x 2 arch: each kind once
    monkeypatch.setattr(study, "candidate_structures", lambda conn, narrow=False: [
        s for s in every(conn, narrow) if s.name in ("line", "two_line-aligned", "two_line-staggered",
                                                     "arch-4x2-staggered")])
    # at 10 mm the test robot's two lines span 4 by the static tip, 3 with their launch allowance
    # (measured 2026-12-04, emergent hinge; 7.5 and 15 mm give the same thresholds both ways)
    grid = (("clearance", "mm", (10.0,)), ("robot mass", "x record", (2.0,)))
    opts = RunOptions(properties=str(test_properties), max_width=6)
    static = sensitivity(opts, grid=grid)
    dyn = sensitivity(replace(opts, sensitivity_dynamic=True), grid=grid)
    assert [(r["parameter"], r["value"]) for r in dyn] == [(r["parameter"], r["value"]) for r in static]
    for a, b in zip(dyn, static, strict=True):
        for kind in ("line", "two_line", "arch", "max_span"):
            assert a[kind] <= b[kind], (a, b)
    assert any(a[k] < b[k] for a, b in zip(dyn, static, strict=True) for k in ("line", "two_line", "arch"))
    assert list((tmp_path / "cache" / "voidcross" / "dynamics").glob("*.json"))  # cached for the next study
    from voidcross.cli import build_parser
    from voidcross.commands.fem import _opts

    assert _opts(build_parser().parse_args(["fem", "study", "--sensitivity-dynamic"])).sensitivity_dynamic is True
    assert _opts(build_parser().parse_args(["fem", "study"])).sensitivity_dynamic is False


def test_bodies_are_flexible_by_default_and_rigid_on_request():
    """`fem table|study|solve` bend the robots with the CAD's section unless told `--rigid`."""
    from voidcross.cli import build_parser
    from voidcross.commands.fem import _opts

    p = build_parser()
    assert _opts(p.parse_args(["fem", "table"])).flexible is True
    assert _opts(p.parse_args(["fem", "table", "--flexible"])).flexible is True
    assert _opts(p.parse_args(["fem", "study", "--rigid"])).flexible is False
    with pytest.raises(SystemExit):
        p.parse_args(["fem", "table", "--rigid", "--flexible"])


def test_the_hinge_model_is_a_choice_and_the_lumped_one_is_the_earlier_model(cli, tmp_path, monkeypatch):
    """The default emergent hinge against ``--hinge lumped`` (one point spring + a dead band, side
    rails as ties: the default until 2026-12-04) on the packaged CuBot, static criterion: the
    staggered arches lose the rails' tie, and the record says which model it derived with. Without the thesis's tapering arches
    (their widest widths do not converge under the emergent hinge and cost minutes of retries;
    they are not what this test is about)."""
    import structure_fem.outputs.runs as runs

    monkeypatch.setattr(runs, "tapered_arches", lambda d, thesis=None, progress=None: [])

    def run(name, *extra):
        res = cli("fem", "table", "--static", "--json", "--max-width", "6", "--no-ranges", "--out", str(tmp_path / name),
                  *extra)
        assert res.code == 0, res.err
        return res.json()

    em, lu = run("em"), run("lu", "--hinge", "lumped")
    te, tl = em["thresholds_per_structure"], lu["thresholds_per_structure"]
    # the lumped model keeps the rails' tie: never less (with the wedge latch both may reach the cap)
    assert tl["arch-4x2-staggered"] >= te["arch-4x2-staggered"]
    curves = [(tmp_path / n / "selection_table.csv").read_text() for n in ("em", "lu")]
    assert curves[0] != curves[1]  # and the two models give different deflections
    assert em["calibration"]["robot_connectors"]["hinge"] == "emergent"
    assert lu["calibration"]["robot_connectors"]["hinge"] == "lumped"
    notes = json.loads((tmp_path / "em" / "limits.json").read_text())["notes"]
    assert "emergent hinges" in notes
