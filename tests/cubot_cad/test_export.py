"""Exports: manifest contents, committed exports up to date, properties record, STEP round trip."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
COMMITTED = REPO / "exports"


def test_manifest_lists_every_printable_part_with_its_facts(export_dir, robots):
    m = json.loads((export_dir / "manifest.json").read_text())
    assert m["material"] == "ABS" and m["density_kg_m3"] == 1040.0 and m["clearance_mm"] == 0.2
    from cubot_cad.piers.deck import pier_parts

    expected = {(name, part.name): qty for name, r in robots.items() for part, qty in r.printable_parts()}
    expected.update({(name, part.name): qty for name, r in robots.items() for part, qty in pier_parts(r)})
    got = {(p["robot"], p["part"]): p["quantity"] for p in m["parts"]}
    assert got == expected
    for p in m["parts"]:
        f = export_dir / p["file"]
        data = f.read_bytes()
        (n,) = struct.unpack("<I", data[80:84])  # binary STL: 80-byte header, count, 50 bytes per facet
        assert len(data) == 84 + 50 * n and n > 0, p["file"]
        assert p["watertight"] and p["fits_bed"], p
        assert p["mass_g"] == pytest.approx(p["volume_mm3"] * 1.04e-3, abs=1e-4)
        assert p["mesh_volume_mm3"] == pytest.approx(p["volume_mm3"], rel=2e-3)
        assert p["bbox_mm"][2] == pytest.approx(0.0, abs=1e-6)  # lies on the bed
        assert p["description"]
    for name in robots:
        assert (export_dir / f"{name}.step").stat().st_size > 0
        rob = m["robots"][name]
        assert rob["total_mass_g"] > rob["printed_mass_g"] > 0
        assert rob["components"] and all(c["unit_mass_g"] > 0 for c in rob["components"])
    assert {d["pair"] for d in m["docked_pairs"]} >= {"cubot-front-rear", "octbot-ring", "cube-robot-front-rear"}


def test_committed_exports_match_a_fresh_export(export_dir):
    """The STLs users print without installing anything are what the code builds today."""
    fresh = json.loads((export_dir / "manifest.json").read_text())
    committed = json.loads((COMMITTED / "manifest.json").read_text())
    key = lambda p: (p["robot"], p["part"])  # noqa: E731
    f = {key(p): p for p in fresh["parts"]}
    c = {key(p): p for p in committed["parts"]}
    assert set(f) == set(c), "exports/ is stale: run `voidcross cad export --packaged-default`"
    for k, p in f.items():
        assert c[k]["volume_mm3"] == pytest.approx(p["volume_mm3"], rel=1e-3), k
        assert c[k]["quantity"] == p["quantity"], k
        assert (COMMITTED / c[k]["file"]).stat().st_size > 84, k


def test_robot_properties_record_comes_from_the_cad(export_dir):
    from cubot_cad.properties import RobotPropertiesFile, default_properties

    fresh = RobotPropertiesFile.load(export_dir / "robot_properties.json")
    assert fresh.names == ("cubot", "octbot", "cube-robot", "platform")
    cub = fresh.get("cubot")
    assert cub.wheel_exposed_height_m == pytest.approx(0.015, abs=1e-9)
    assert cub.connector("front_rear").gap_m == 0.0
    assert fresh.get("cube-robot").connector("front_rear").gap_m == pytest.approx(0.0017, abs=2e-5)
    assert fresh.get("octbot").connector("ring_capture").gap_m >= 0.04 - 2e-5
    assert "CAD export" in cub.source
    # The packaged default (cubot_cad/data/robot_properties.json) is still the hand estimate: switching it
    # to these CAD values needs structure_fem's packaged limits.json regenerated with it (see docs).
    assert default_properties().get("cubot").mass_kg > 0


def test_step_assembly_round_trips(export_dir, robots):
    import cadquery as cq

    r = robots["cubot"]
    shape = cq.importers.importStep(str(export_dir / "cubot.step")).val()
    solids = shape.Solids()
    expected = [p.shape for p in r.placed] + r.component_solids() + [h.shape for h in r.hardware()]
    assert len(solids) == len(expected)
    assert sum(s.Volume() for s in solids) == pytest.approx(sum(s.Volume() for s in expected), rel=1e-4)


def test_pla_and_3mf_for_one_robot(tmp_path):
    from cubot_cad.outputs.export import export_robots

    res = export_robots(["platform"], tmp_path, ("stl", "3mf"), "pla")
    (part,) = res.parts
    assert part.mass_g == pytest.approx(part.volume_mm3 * 1.24e-3, abs=1e-4)
    assert (tmp_path / "platform" / "test_platform.3mf").stat().st_size > 0
    assert not (tmp_path / "platform.step").exists()


def test_corrupt_manifest_is_an_input_error(tmp_path):
    from cubot_cad.errors import InputError
    from cubot_cad.manifest import load_manifest

    (tmp_path / "manifest.json").write_text("{not json")
    with pytest.raises(InputError, match="not valid JSON"):
        load_manifest(tmp_path)
    (tmp_path / "manifest.json").write_text('{"schema_version": 99}')
    with pytest.raises(InputError, match="manifest"):
        load_manifest(tmp_path)


def test_every_robot_has_a_bill_of_materials(export_dir, robots):
    import csv

    from cubot_cad.hardware.fasteners import THREADS

    m = json.loads((export_dir / "manifest.json").read_text())
    for name, r in robots.items():
        assert m["robots"][name]["bom"] == f"{name}/bom.csv"
        rows = list(csv.DictReader((export_dir / name / "bom.csv").open()))
        printed = {x["item"]: int(x["quantity"]) for x in rows if x["category"] == "printed"}
        assert printed == {p.name: q for p, q in r.printable_parts()}, name
        for x in rows:
            if x["category"] == "printed":
                assert (export_dir / x["file"]).exists() and float(x["unit_mass_g"]) > 0
        bought = {x["item"] for x in rows if x["category"] == "bought"}
        assert {c.key for c in r.components()} - {"fasteners"} <= bought, name
        fast = [x for x in rows if x["category"] == "fastener"]
        assert fast and all(x["size"].split()[0] in THREADS and int(x["quantity"]) > 0 for x in fast), name
    cub = {x["item"]: x for x in csv.DictReader((export_dir / "cubot" / "bom.csv").open())}
    assert int(cub["M3 insert"]["quantity"]) == 4 + 4  # the cover's and the side rails'
    assert int(cub["M3x20 ISO 10642"]["quantity"]) == 16
    assert int(cub["M3x12 ISO 10642"]["quantity"]) == 2 and int(cub["M3x8 ISO 10642"]["quantity"]) == 2  # rails
    assert int(cub["latch_shaft"]["quantity"]) == 2 and int(cub["wheel"]["quantity"]) == 2
    assert {"motor", "battery", "servo"} <= {w for x in cub.values() for w in ("motor", "battery", "servo")
                                              if w in x["item"]}


def test_the_manifest_records_each_parts_print_settings(export_dir):
    m = json.loads((export_dir / "manifest.json").read_text())
    ps = {p["part"]: p["print_settings"] for p in m["parts"]}
    needs = {k for k, v in ps.items() if v["supports"]}
    # (the Cube Robot's wheel block no longer: its wells go through the floor only, its bosses and ribs
    # hang on 45 deg undersides)
    assert needs == {"cross_key", "twist_key", "cover_cross_hole", "octbot_ring"}
    assert all(ps[k]["support_reason"] for k in needs)
    assert ps["pinset_e_grooved_pin"]["infill_percent"] == 100 and ps["cubot_body"]["infill_percent"] == 25
    assert all(v["layer_mm"] == 0.2 and v["nozzle_mm"] == 0.4 for v in ps.values())
