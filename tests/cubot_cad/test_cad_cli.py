"""`voidcross cad ...`: exit codes, one-line errors, JSON outputs, the pipeline stage."""

from __future__ import annotations

import math

import pytest


@pytest.mark.parametrize("argv, word", [
    (("cad", "export", "--clearance-mm", "-1"), "clearance"),
    (("cad", "export", "--clearance-mm", "nan"), "clearance"),
    (("cad", "export", "--robot", "hexbot"), "hexbot"),
    (("cad", "export", "--format", "obj"), "obj"),
    (("cad", "export", "--material", "wood"), "wood"),
    (("cad", "dock", "--pair", "cubot-sideways"), "cubot-sideways"),
    (("cad", "check", "/nonexistent/dir"), "/nonexistent/dir"),
    (("cad", "render", "--robot", "hexbot"), "hexbot"),
])
def test_bad_input_gives_one_error_line_and_exit_2(cli, tmp_path, argv, word):
    res = cli(*argv, "--out", str(tmp_path)) if argv[1] in ("export", "render") else cli(*argv)
    assert res.code == 2, res.err
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error:")
    assert word in res.error_lines[0]
    assert not any(tmp_path.iterdir())  # nothing written on bad input


def test_check_rejects_empty_and_corrupt_inputs(cli, tmp_path):
    res = cli("cad", "check", str(tmp_path))
    assert res.code == 2 and "no .stl" in res.err
    (tmp_path / "broken.stl").write_bytes(b"\x00" * 10)
    res = cli("cad", "check", str(tmp_path), "--no-slice")
    assert res.code == 2 and len(res.error_lines) == 1


def test_export_and_check_one_robot(cli, tmp_path, pairs):
    res = cli("cad", "export", "--robot", "platform", "--out", str(tmp_path), "--json")
    assert res.code == 0, res.err
    out = res.json()
    assert out["parts"] == 1 and out["all_watertight"]
    assert out["docked_pairs"][0]["pair"] == "platform-bolt"
    assert (tmp_path / "platform" / "test_platform.stl").exists() and (tmp_path / "platform.step").exists()
    res = cli("cad", "check", str(tmp_path), "--no-slice", "--json")
    assert res.code == 0, res.err
    chk = res.json()
    assert chk["files"] == 1 and chk["failed"] == 0 and chk["parts"][0]["thinnest_wall_mm"] >= 0.8


def test_dock_reports_every_pair(cli, pairs):
    res = cli("cad", "dock", "--json", "--no-capture")  # capture: test_capture.py
    assert res.code == 0, res.err
    rows = {r["pair"]: r for r in res.json()["pairs"]}
    assert rows["cube-robot-front-rear"]["gap_mm"] == pytest.approx(1.7, abs=0.02)
    assert all(r["ok"] for r in rows.values())


def test_pipeline_stage_sets_the_context(cad_pipeline):
    """The cad stage (run once per session by the ``cad_pipeline`` fixture: test_slicing reads
    its sliced manifest too)."""
    from cubot_cad.properties import RobotPropertiesFile

    cad, ctx, line = cad_pipeline
    assert "\n" not in line and "CuBot" in line
    assert RobotPropertiesFile.load(ctx["robot_properties"]).get("cubot").mass_kg > 0.2
    assert ctx["cad_dir"] == str(cad)
    assert (cad / "manifest.json").exists()
    # what `make demo`'s report picks up from the cad dir: renders (PNG) and 3D models (GLB)
    pngs = {p.name for p in cad.rglob("*.png")}
    assert {"cubot.png", "bridge-cubot-line.png"} <= pngs
    glbs = {p.name for p in cad.rglob("*.glb")}
    assert glbs == {"cubot.glb", "octbot.glb", "cube-robot.glb", "platform.glb", "bridge-cubot-line.glb"}
    for p in cad.rglob("*"):
        if p.suffix in (".png", ".glb"):
            assert p.read_bytes()[:4] == (b"\x89PNG" if p.suffix == ".png" else b"glTF"), p
    assert "GLB" in line and "renders" in line
    # sliced as the packaged record is: `make demo`'s structure study derives for the packaged CuBot
    # (the README's thresholds) and finds its packaged launch transients
    from cubot_cad.checks.slicing import slicer_path
    from cubot_cad.jsonrecord import to_jsonable
    from cubot_cad.properties import default_properties

    assert slicer_path() is not None, "make's clients target installs prusa-slicer"
    assert "sliced masses" in line
    got = RobotPropertiesFile.load(ctx["robot_properties"]).get("cubot")
    # the same record; floats to 1e-12: the CAD kernel's mass properties differ in their last bit
    # from run to run (seen: inertia 4.551733319049401e-4 against ...4007e-4)
    _assert_same_record(to_jsonable(got), to_jsonable(default_properties().get("cubot")))
    assert f"CuBot record {1e3 * got.mass_kg:.1f} g" in line  # the mass the structure study uses


def _assert_same_record(a, b, path="record"):
    if isinstance(a, float) or isinstance(b, float):
        assert isinstance(a, (int, float)) and isinstance(b, (int, float)), (path, a, b)
        assert math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-18), (path, a, b)
    elif isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), (path, a, b)
        for k in a:
            _assert_same_record(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, (list, tuple)):
        assert isinstance(b, (list, tuple)) and len(a) == len(b), (path, a, b)
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _assert_same_record(x, y, f"{path}[{i}]")
    else:
        assert a == b, (path, a, b)


# --- the clearance range on the command line -------------------------------------------------

@pytest.mark.parametrize("sub", ["export", "dock", "render"])
@pytest.mark.parametrize("value", ["0", "0.05", "0.09", "0.51", "1"])
def test_a_clearance_outside_the_range_is_refused_before_any_work(cli, tmp_path, sub, value):
    """`--clearance-mm 0` used to exit 0 and write a record with a 5.06 mm front-rear gap and
    12.1 mm^3 of interference; now: exit 2, one line naming the value, nothing created."""
    out = tmp_path / "new"
    res = cli("cad", sub, "--clearance-mm", value, "--out", str(out))
    assert res.code == 2, res.err
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith(f"error: --clearance-mm {value} mm ")
    assert "0.1-0.5 mm" in res.error_lines[0]
    assert not out.exists()


# --- an export is all or nothing ---------------------------------------------------------------

def _tree(d):
    return sorted(str(p.relative_to(d)) for p in d.rglob("*"))


@pytest.fixture
def good_export(cli, tmp_path):
    """A finished `cad export --robot platform` in tmp/good: its files and record bytes."""
    out = tmp_path / "good"
    res = cli("cad", "export", "--robot", "platform", "--out", str(out))
    assert res.code == 0, res.err
    return out, _tree(out), (out / "robot_properties.json").read_bytes()


@pytest.mark.parametrize("failure", ["interference", "gap"])
def test_an_export_whose_docked_pair_fails_exits_2_and_writes_nothing(cli, tmp_path, monkeypatch, good_export,
                                                                      failure):
    import dataclasses

    import cubot_cad.checks.docking as docking
    from cubot_cad.robots.registry import make_robot

    real = docking.dock("platform-bolt", 0.2)
    if failure == "interference":  # a real overlap: the rear plate's recess shifted 1 mm onto the tab
        bad = docking.dock_robot(make_robot("platform", 0.2), "platform-bolt", (0.0, 1.0, 0.0))
        assert bad.interference_mm3 > docking.INTERFERENCE_LIMIT_MM3
    else:  # docked 5.06 mm short of its designed (touching) gap
        bad = dataclasses.replace(real, gap_mm=5.06)
    monkeypatch.setattr(docking, "dock", lambda name, clearance_mm=0.2, misalign_mm=(0, 0, 0): bad)
    out, tree, record = good_export
    for target in (out, tmp_path / "fresh" / "sub"):
        res = cli("cad", "export", "--robot", "platform", "--out", str(target))
        assert res.code == 2, res.err
        assert len(res.error_lines) == 1, res.err
        line = res.error_lines[0]
        assert line.startswith("error: --clearance-mm 0.2: docked pair fails (platform-bolt: ")
        assert ("interference" in line) if failure == "interference" else ("gap 5.06 mm, designed 0.00" in line)
        assert line.endswith("nothing written")
    assert _tree(out) == tree and (out / "robot_properties.json").read_bytes() == record
    assert not (tmp_path / "fresh").exists()


def test_a_failed_export_leaves_no_trace(cli, tmp_path, monkeypatch, good_export):
    """An internal failure half-way (the third part's mesh) removes everything it wrote: no new
    empty or partial --out, nothing added to or replaced in an existing one."""
    import cubot_cad.outputs.export as export

    real, calls = export.mesh_of, []

    def failing(*a, **k):
        calls.append(1)
        if len(calls) == 3:
            raise RuntimeError("disk on fire")
        return real(*a, **k)

    monkeypatch.setattr(export, "mesh_of", failing)
    out, tree, record = good_export
    for target in (tmp_path / "fresh" / "sub", out):
        calls.clear()
        res = cli("cad", "export", "--robot", "cubot", "--no-dock", "--format", "stl", "--out", str(target))
        assert res.code == 1 and "disk on fire" in res.err, res.err
    assert not (tmp_path / "fresh").exists()
    assert _tree(out) == tree and (out / "robot_properties.json").read_bytes() == record


def test_an_export_into_an_existing_directory_replaces_its_files(cli, good_export):
    out, tree, _ = good_export
    before = (out / "manifest.json").stat().st_mtime_ns
    res = cli("cad", "export", "--robot", "platform", "--format", "stl", "--out", str(out))
    assert res.code == 0, res.err
    assert _tree(out) == tree  # same files (the old STEP kept), no staging directory left behind
    assert (out / "manifest.json").stat().st_mtime_ns > before


# --- cad check reports every unreadable STL ---------------------------------------------------

def test_check_reports_every_unreadable_stl_and_then_exits_2(cli, tmp_path):
    import trimesh

    trimesh.creation.box((20, 20, 10)).export(tmp_path / "good.stl")
    (tmp_path / "a_zeros.stl").write_bytes(b"\x00" * 10)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b_empty.stl").write_text("solid nothing\nendsolid nothing\n")
    res = cli("cad", "check", str(tmp_path), "--no-slice")
    assert res.code == 2, res.err
    assert len(res.error_lines) == 2 and all(ln.startswith("error: ") for ln in res.error_lines)
    assert "a_zeros.stl" in res.error_lines[0] and "b_empty.stl" in res.error_lines[1]
    assert "ok   good.stl" in res.out and "1/1 parts printable, 2 unreadable" in res.out
    res = cli("cad", "check", str(tmp_path), "--no-slice", "--json")
    assert res.code == 2
    out = res.json()
    assert out["files"] == 3 and [p["file"] for p in out["parts"]] == ["good.stl"]
    assert [u["file"] for u in out["unreadable"]] == ["a_zeros.stl", "sub/b_empty.stl"]
