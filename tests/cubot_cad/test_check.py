"""`cad check`: watertight, manifold, bed, thinnest wall (a probe that can fail), slicing."""

from __future__ import annotations

import pytest

from cubot_cad.checks.check import check_file, fits_bed, slicer_path, thinnest_wall_mm


def _box_stl(path, outer, wall=None):
    import cadquery as cq

    from cubot_cad.mesh import mesh_of

    w = cq.Workplane().box(*outer)
    if wall is not None:
        w = w.faces(">Z").shell(-wall)
    path.write_bytes(mesh_of(w.val()).export(file_type="stl"))
    return path


@pytest.mark.parametrize("robot, part", [("cubot", "cubot_body"), ("cubot", "latchset_d_triangular_blade"),
                                         ("cubot", "rail_female_right"), ("octbot", "octbot_ring"),
                                         ("cube-robot", "cube_connector_cuboid")])
def test_shipped_parts_pass(export_dir, robot, part):
    c = check_file(export_dir / robot / f"{part}.stl", export_dir, do_slice=False)
    assert c.watertight and c.manifold and c.fits_bed
    assert c.thinnest_wall_mm >= 0.8 and c.ok


def test_wall_probe_measures_walls(tmp_path):
    thin = check_file(_box_stl(tmp_path / "thin.stl", (40, 30, 20), wall=0.5), do_slice=False)
    assert thin.thinnest_wall_mm == pytest.approx(0.5, abs=0.02)
    assert not thin.wall_ok and not thin.ok
    ok = check_file(_box_stl(tmp_path / "ok.stl", (40, 30, 20), wall=1.6), do_slice=False)
    assert ok.thinnest_wall_mm == pytest.approx(1.6, abs=0.02) and ok.ok


def test_open_mesh_and_oversize_fail(tmp_path):
    import trimesh

    mesh = trimesh.load(_box_stl(tmp_path / "b.stl", (20, 20, 20)))
    mesh.update_faces(list(range(1, len(mesh.faces))))
    mesh.export(tmp_path / "open.stl")
    c = check_file(tmp_path / "open.stl", do_slice=False)
    assert not c.watertight and not c.ok
    big = check_file(_box_stl(tmp_path / "big.stl", (300, 20, 20)), do_slice=False)
    assert not big.fits_bed and not big.ok
    assert fits_bed((200, 240, 100)) and not fits_bed((100, 100, 220))


def test_thinnest_wall_of_a_solid_block():
    import trimesh

    assert thinnest_wall_mm(trimesh.creation.box((10, 20, 30))) == pytest.approx(10.0, abs=0.01)


def test_parts_slice_with_prusa_slicer(export_dir, require_tool):
    """`cad check` slices each part with the settings its manifest entry records (the locking key:
    25 % infill, no supports; the grooved pin: 100 %), and the totals add quantities up."""
    import json

    from cubot_cad.checks.check import slicing_totals

    require_tool(slicer_path(), "prusa-slicer")
    man = json.loads((export_dir / "manifest.json").read_text())
    rec = {p["file"]: p for p in man["parts"]}
    files = ["cubot/locking_key.stl", "cubot/pinset_e_grooved_pin.stl"]
    checks = [check_file(export_dir / f, export_dir, do_slice=True, samples=300) for f in files]
    for f, c in zip(files, checks, strict=True):
        s, want = c.slice, rec[f]["print_settings"]
        assert s["ok"], s["detail"]
        assert s["settings_source"] == "manifest.json" and s["settings"] == want
        assert f"{want['infill_percent']:g}%" in s["args"]
        assert ("--support-material" in s["args"]) is bool(want["supports"])
        assert s["print_time"] and s["print_time_s"] > 0 and 0 < s["printed_mass_g"] <= s["filament_g"]
    tot = slicing_totals(checks, export_dir)["cubot"]
    pin_q = rec[files[1]]["quantity"]
    assert tot["parts"] == 1 + pin_q and tot["complete"] and tot["solid_over_printed_pct"] is not None
    assert tot["filament_g"] == pytest.approx(checks[0].slice["filament_g"] + pin_q * checks[1].slice["filament_g"])
