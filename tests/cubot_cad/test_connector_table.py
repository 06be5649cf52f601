"""The connector family as data: the block plates are one class (:class:`BlockPlate`) with the variants
in a table (:data:`PLATES`); the refactor kept every exported part's geometry: each volume (the OCC
solid and the STL mesh as exported) equals the one recorded by running the code before the change
(``data/volumes_before_connector_refactor.json``), to 1e-6 relative."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

RECORD = json.loads((Path(__file__).parent / "data" / "volumes_before_connector_refactor.json").read_text())


def _parts(clearance):
    from cubot_cad.piers.deck import pier_parts
    from cubot_cad.robots.registry import ROBOT_NAMES, make_robot

    out = {}
    for name in ROBOT_NAMES:
        # the record predates the wedge latch (issue 38): the CuBot it guards is the clearance latch
        settings = (("front_rear_coupling", "clearance"),) if name == "cubot" else ()
        r = make_robot(name, clearance, settings)
        for part, _ in list(r.printable_parts()) + list(pier_parts(r)):
            out[f"{name}/{part.name}"] = part
    return out


@pytest.mark.parametrize("c", sorted(RECORD["clearances"]))
def test_every_exported_part_keeps_its_volume(c):
    from cubot_cad.mesh import mesh_of

    before = RECORD["clearances"][c]
    now = _parts(float(c))
    assert set(now) == set(before)
    for key, rec in before.items():
        part = now[key]
        assert part.volume_mm3 == pytest.approx(rec["volume_mm3"], rel=1e-6), key
        if "mesh_volume_mm3" in rec:
            assert float(mesh_of(part.printable).volume) == pytest.approx(rec["mesh_volume_mm3"], rel=1e-6), key


def test_the_plates_are_one_class_with_a_table_of_variants(robots):
    from cubot_cad.couplings.connectors import (
        LATCH_SET_PLATES,
        PIN_SET_PLATES,
        PLATES,
        BlockPlate,
        LatchRearPlate,
    )

    plates = [p for r in robots.values() for p, _ in r.printable_parts() if isinstance(p, BlockPlate)]
    assert {p.name for p in plates} == set(PLATES) == set(PIN_SET_PLATES) | set(LATCH_SET_PLATES)
    assert all(type(p) is BlockPlate for p in plates)
    p = LatchRearPlate()
    assert p == BlockPlate(kind="latchset_e_rear_locking_plate") and p.mates["pocket_bottom"].point[0] < 0
    # the two pairs that share their geometry are still two printed parts each
    a, b = BlockPlate(kind="pinset_d_front_locking_plate"), BlockPlate(kind="latchset_a_front_locking_plate")
    assert a != b and a.volume_mm3 == pytest.approx(b.volume_mm3, rel=1e-12)


def test_a_plate_kind_not_in_the_table_is_refused():
    from cubot_cad.couplings.connectors import BlockPlate
    from cubot_cad.errors import InputError

    with pytest.raises(InputError, match="BlockPlate.kind 'pinset_z'"):
        BlockPlate(kind="pinset_z")


def test_the_screw_holes_come_from_the_fastener_table(monkeypatch):
    import dataclasses

    from cubot_cad.couplings.connectors import PLATES, BlockPlate, FrontRearSpec
    from cubot_cad.hardware import fasteners

    def radii(kind):
        return sorted({round(e.radius(), 4) for e in BlockPlate(kind=kind, spec=FrontRearSpec()).solid.Edges()
                       if e.geomType() == "CIRCLE"})

    before = {k: radii(k) for k in PLATES}
    monkeypatch.setitem(fasteners.THREADS, "M3", dataclasses.replace(fasteners.THREADS["M3"], clearance_medium_mm=3.8))
    for k in PLATES:
        after = radii(k)
        assert 1.9 in after and 1.7 not in after and 1.7 in before[k], k
