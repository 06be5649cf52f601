"""Bill of materials per robot: ``<robot>/bom.csv``, written by ``cad export``.

Three kinds of rows (``category``):

* ``printed``: every distinct printed part with its quantity, its size as printed (mm, the
  exported STL's bounding box), its mass at the export's material (solid, as the manifest) and
  its file;
* ``bought``: the robot's non-printed components (motors, wheels, caster balls, battery,
  boards, servos, sensors) with the size of their stand-in in the CAD and their assumed mass
  (:meth:`~cubot_cad.robots.base.Robot.components`); the component table's lump ``fasteners`` (a mass
  estimate) is replaced by the next kind; drive parts outside the mass table (the latch blades'
  D-shafts, :meth:`~cubot_cad.robots.base.Robot.drive_parts`) are listed too;
* ``fastener``: screws, nuts and heat-set inserts from :meth:`~cubot_cad.robots.base.Robot.fasteners`,
  sized from the ISO table (:mod:`cubot_cad.hardware.fasteners`), one row per kind, size and length,
  with where they go;
* ``pier``: what a pier of these robots needs once, not per robot (the CuBot: the printed
  :class:`~cubot_cad.piers.deck.PierDeck` the top robot wears, its flanged ``cross_key`` and the key
  flange's screws), quantities per pier.
"""

from __future__ import annotations

import csv
import io
from collections import OrderedDict

COLUMNS = ("robot", "category", "item", "description", "size", "quantity", "unit_mass_g", "file", "where")


def _size_text(c) -> str:
    if c.kind == "box" and getattr(c, "servo_model", None):
        from cubot_cad.hardware.servos import servo

        sv = servo(c.servo_model)
        return (f"case {' x '.join(f'{v:g}' for v in c.size_mm)} mm, tabs {sv.tab_length_mm:g} mm "
                f"(holes {sv.hole_spacing_mm:g} mm apart), {sv.horn.spline} spline")
    if c.kind == "box":
        return " x ".join(f"{v:g}" for v in c.size_mm) + " mm"
    if c.kind in ("cyl_y", "cyl_z"):
        return f"diameter {c.size_mm[0]:g} x {c.size_mm[1]:g} mm"
    return f"diameter {c.size_mm[0]:g} mm"


def _printed_row(robot, part, qty, density_kg_m3, printed_sizes_mm, category="printed", where="",
                 description=None) -> dict:
    size = (printed_sizes_mm or {}).get(part.name)
    if size is None:
        from cubot_cad.shapes import tight_bbox

        b = tight_bbox(part.printable)
        size = [b[3] - b[0], b[4] - b[1], b[5] - b[2]]
    return {"robot": robot.name, "category": category, "item": part.name,
            "description": part.description if description is None else description,
            "size": " x ".join(f"{v:.1f}" for v in size) + " mm (as printed)", "quantity": qty,
            "unit_mass_g": round(part.volume_mm3 * 1e-9 * density_kg_m3 * 1e3, 2),
            "file": f"{robot.name}/{part.name}.stl", "where": where}


def _fastener_item(kind: str, size: str, length: float) -> str:
    return f"{size} {kind}" if kind in ("insert", "ISO 4032") else f"{size}x{length:g} {kind}"


def _fastener_size(kind: str, size: str, length: float) -> str:
    return f"{size}" + ("" if kind in ("insert", "ISO 4032") else f" x {length:g} mm")


def bom_rows(robot, density_kg_m3: float, printed_sizes_mm: dict | None = None) -> list[dict]:
    """The BOM rows of ``robot`` (printed parts at ``density_kg_m3``; ``printed_sizes_mm``: part name ->
    as-printed size, else the part's own bounding box)."""
    rows = [_printed_row(robot, part, qty, density_kg_m3, printed_sizes_mm) for part, qty in robot.printable_parts()]
    for c in robot.components():
        if c.key == "fasteners":
            continue  # a mass lump in the component table; the fastener rows below list the real ones
        rows.append({"robot": robot.name, "category": "bought", "item": c.key, "description": c.description,
                     "size": _size_text(c), "quantity": c.count, "unit_mass_g": c.unit_mass_g, "file": "",
                     "where": ""})
    for item, desc, size, count in robot.drive_parts():
        rows.append({"robot": robot.name, "category": "bought", "item": item, "description": desc, "size": size,
                     "quantity": count, "unit_mass_g": "", "file": "", "where": ""})
    agg: OrderedDict = OrderedDict()
    for u in robot.fasteners():
        key = (u.kind, u.size, u.length_mm)
        if key not in agg:
            agg[key] = {"use": u, "count": 0, "where": []}
        agg[key]["count"] += u.count
        agg[key]["where"].append(f"{u.count} {u.where}")
    for (kind, size, length), a in agg.items():
        u = a["use"]
        rows.append({"robot": robot.name, "category": "fastener", "item": _fastener_item(kind, size, length),
                     "description": u.description, "size": _fastener_size(kind, size, length),
                     "quantity": a["count"], "unit_mass_g": "", "file": "", "where": "; ".join(a["where"])})
    return rows + pier_rows(robot, density_kg_m3, printed_sizes_mm)


def pier_rows(robot, density_kg_m3: float, printed_sizes_mm: dict | None = None) -> list[dict]:
    """The ``pier`` rows: per pier of ``robot``, the deck, its cross key and the key's screws (none for
    a robot that does not stack)."""
    from cubot_cad.piers.deck import default_deck

    rows = []
    deck = default_deck(robot)
    for qty in ([] if deck is None else [1]):
        rows.append(_printed_row(robot, deck, qty, density_kg_m3, printed_sizes_mm, "pier",
                                 "one per pier: docked on the top robot's cover (the line rolls over it)"))
        rows.append(_printed_row(robot, deck.key_part, qty, density_kg_m3, printed_sizes_mm, "pier",
                                 f"under the {deck.name}, turned {deck.spec.twist_deg:g} deg clockwise"))
        for u in deck.screws():
            rows.append({"robot": robot.name, "category": "pier", "item": _fastener_item(u.kind, u.size, u.length_mm),
                         "description": u.description, "size": _fastener_size(u.kind, u.size, u.length_mm),
                         "quantity": u.count * qty, "unit_mass_g": "", "file": "", "where": u.where})
    return rows


def bom_csv(rows: list[dict]) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=COLUMNS, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow(r)
    return buf.getvalue()
