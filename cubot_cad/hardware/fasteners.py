"""Fasteners as data: ISO metric screws, nuts and heat-set inserts, with the holes printed for them (mm).

Every part that takes a screw asks this table for its hole (``clearance_hole_mm``,
``tap_hole_mm``, ``insert_hole_mm``) instead of repeating a literal, and the bill of
materials (:mod:`cubot_cad.outputs.bom`) lists the screws and inserts the robots use from the
same table (:data:`USES`).

Sources of the numbers (per row below):

* clearance holes: ISO 273:1979 *Fasteners - Clearance holes for bolts and screws*, the
  "medium" series (M2 2.4, M2.5 2.9, M3 3.4 mm); "fine" and "coarse" are listed too;
* tap-drill holes (for a screw cut straight into the print): ISO 2306:1972 *Drills for use
  prior to tapping*, 6H class (M2 1.6, M2.5 2.05, M3 2.5 mm);
* socket head cap screws ISO 4762: head diameter dk max and head height k max
  (M2 3.8 / 2.0, M2.5 4.5 / 2.5, M3 5.5 / 3.0 mm); button head ISO 7380-1 (M3 only, the
  standard starts at M3: dk 5.7, k 1.65 mm); countersunk ISO 10642 (M3 only, the standard
  starts at M3: dk 6.72 theoretical, k 1.86 mm, 90 deg); below M3 the countersunk screw is
  the cross-recessed ISO 7046-1 (= DIN 965), M2: dk actual max 3.8, k max 1.2 mm, 90 deg
  (:data:`CROSS_COUNTERSUNK_MM`);
* hex nuts ISO 4032: width across flats s and height m max (M2 4.0 / 1.6, M2.5 5.0 / 2.0,
  M3 5.5 / 2.4 mm);
* heat-set inserts (brass, knurled, for thermoplastics): ruthex RX-M2x3, RX-M2.5x4,
  RX-M3x5.7 (the CNC Kitchen sizes are the same): the printed hole is the insert's nominal
  outside diameter (M2 3.2, M2.5 3.6, M3 4.0 mm) and the hole is the insert length plus
  0.5 mm deep (room for the displaced plastic); as tabulated in the heat-set insert hole
  chart at https://tools.creative3dp.com/blog/heat-set-insert-hole-size-chart (ruthex / CNC
  Kitchen datasheet values; a printer that prints holes undersize adds its own compensation).
"""

from __future__ import annotations

from dataclasses import dataclass

from cubot_cad.errors import InputError


@dataclass(frozen=True)
class Thread:
    """One metric coarse thread size and the holes and parts made for it (mm)."""

    size: str
    nominal_mm: float
    pitch_mm: float
    clearance_fine_mm: float
    clearance_medium_mm: float
    clearance_coarse_mm: float
    tap_drill_mm: float
    shcs_head_diameter_mm: float
    shcs_head_height_mm: float
    nut_flats_mm: float
    nut_height_mm: float
    insert_hole_mm: float
    insert_length_mm: float
    button_head_diameter_mm: float | None = None
    button_head_height_mm: float | None = None
    countersunk_head_diameter_mm: float | None = None
    countersunk_head_height_mm: float | None = None

    @property
    def insert_hole_depth_mm(self) -> float:
        """Blind hole depth for the insert: its length plus 0.5 mm for the displaced plastic."""
        return self.insert_length_mm + 0.5


#: ISO metric coarse threads used by the robots (sources: module docstring).
THREADS: dict[str, Thread] = {
    "M2": Thread("M2", 2.0, 0.40, 2.2, 2.4, 2.6, 1.6, 3.8, 2.0, 4.0, 1.6, 3.2, 3.0),
    "M2.5": Thread("M2.5", 2.5, 0.45, 2.7, 2.9, 3.1, 2.05, 4.5, 2.5, 5.0, 2.0, 3.6, 4.0),
    "M3": Thread("M3", 3.0, 0.50, 3.2, 3.4, 3.6, 2.5, 5.5, 3.0, 5.5, 2.4, 4.0, 5.7,
                 button_head_diameter_mm=5.7, button_head_height_mm=1.65,
                 countersunk_head_diameter_mm=6.72, countersunk_head_height_mm=1.86),
}

#: Cross-recessed countersunk screws ISO 7046-1 (the countersunk head below M3, where ISO 10642 has
#: none): size -> (head diameter dk actual max, head height k max), mm (source: module docstring).
CROSS_COUNTERSUNK_MM: dict[str, tuple[float, float]] = {"M2": (3.8, 1.2)}

#: Screw standards the table covers and what each head is called in the BOM.
STANDARDS = {"ISO 4762": "socket head cap screw", "ISO 7380": "button head screw",
             "ISO 10642": "countersunk screw", "ISO 7046-1": "countersunk screw (cross recess)",
             "ISO 4032": "hex nut", "insert": "heat-set insert"}

#: The screw kinds :func:`bolted` takes.
SCREW_KINDS = ("ISO 4762", "ISO 7380", "ISO 10642", "ISO 7046-1")


def countersunk_head_mm(size: str) -> tuple[float, float, str]:
    """(head diameter, head height, standard) of the countersunk screw of ``size``: ISO 10642 where the
    table has it (M3), else ISO 7046-1; :class:`InputError` for a size neither covers."""
    t = thread(size)
    if t.countersunk_head_diameter_mm is not None:
        return t.countersunk_head_diameter_mm, t.countersunk_head_height_mm, "ISO 10642"
    if size in CROSS_COUNTERSUNK_MM:
        return (*CROSS_COUNTERSUNK_MM[size], "ISO 7046-1")
    raise InputError(f"fastener size {size!r} has no countersunk screw in the table "
                     f"(ISO 10642: M3; ISO 7046-1: {', '.join(CROSS_COUNTERSUNK_MM)})")


def thread(size: str) -> Thread:
    """The table row for ``size`` (``"M2"``, ``"M2.5"``, ``"M3"``); :class:`InputError` otherwise."""
    if size not in THREADS:
        raise InputError(f"fastener size {size!r} is not one of {', '.join(THREADS)}")
    return THREADS[size]


def clearance_hole_mm(size: str, fit: str = "medium") -> float:
    """ISO 273 clearance hole diameter for a screw of ``size`` (fit ``fine``, ``medium``, ``coarse``)."""
    t = thread(size)
    if fit not in ("fine", "medium", "coarse"):
        raise InputError(f"clearance fit {fit!r} is not one of fine, medium, coarse")
    return getattr(t, f"clearance_{fit}_mm")


def tap_hole_mm(size: str) -> float:
    """ISO 2306 tap-drill diameter for ``size``."""
    return thread(size).tap_drill_mm


def insert_hole_mm(size: str) -> float:
    """Printed hole diameter for the heat-set insert of ``size`` (the insert's nominal outside diameter)."""
    return thread(size).insert_hole_mm


def all_hole_diameters_mm() -> set[float]:
    """Every hole diameter the table defines (clearance, tap, insert), for checks of the exports."""
    out: set[float] = set()
    for t in THREADS.values():
        out |= {t.clearance_fine_mm, t.clearance_medium_mm, t.clearance_coarse_mm, t.tap_drill_mm, t.insert_hole_mm}
    return out


@dataclass(frozen=True)
class FastenerUse:
    """A bought fastener a robot needs: ``count`` of ``kind`` (ISO standard or ``insert``) ``size`` x ``length_mm``."""

    robot: str
    kind: str
    size: str
    length_mm: float
    count: int
    where: str

    @property
    def description(self) -> str:
        if self.kind == "insert":
            return f"{self.size} x {thread(self.size).insert_length_mm:g} heat-set insert (brass)"
        if self.kind == "ISO 4032":
            return f"{self.size} hex nut ISO 4032"
        return f"{self.size} x {self.length_mm:g} {STANDARDS[self.kind]} {self.kind}"


#: Preferred lengths of ISO 4762 socket head cap screws M2-M3 (ISO 4762 table of lengths, mm).
ISO_4762_LENGTHS_MM = (3, 4, 5, 6, 8, 10, 12, 16, 20, 25, 30, 35, 40)


def screw_length_mm(grip_mm: float) -> float:
    """The shortest preferred ISO 4762 length that is at least ``grip_mm`` long."""
    for length in ISO_4762_LENGTHS_MM:
        if length >= grip_mm - 1e-9:
            return float(length)
    raise InputError(f"no ISO 4762 screw of {grip_mm:g} mm or longer in the table (up to {ISO_4762_LENGTHS_MM[-1]} mm)")


def bolted(robot: str, size: str, clamp_mm: float, count: int, where: str, nut: bool = False,
           insert: bool = False, thread_mm: float = 0.0, kind: str = "ISO 4762") -> list[FastenerUse]:
    """The screws (and nuts or inserts) for ``count`` joints clamping ``clamp_mm`` of plastic.

    With a nut the screw is the clamp + the nut's height + 1 mm (the shortest preferred length at
    least that long); into an insert, the longest preferred length that stays inside the insert
    (clamp + insert length) and still engages half of it; into a tap hole, the clamp + ``thread_mm``.
    ``kind`` ISO 10642 or, below M3, ISO 7046-1 (countersunk: its length includes the head) for screws
    flush with a docking face."""
    t = thread(size)
    if kind not in SCREW_KINDS:
        raise InputError(f"screw kind {kind!r} is not one of {', '.join(SCREW_KINDS)}")
    if insert:
        top = clamp_mm + t.insert_length_mm
        fits = [v for v in ISO_4762_LENGTHS_MM if clamp_mm + t.insert_length_mm / 2 <= v <= top + 1e-9]
        if not fits:
            raise InputError(f"no preferred {size} length between {clamp_mm + t.insert_length_mm / 2:g} and {top:g} mm")
        length = float(max(fits))
    else:
        length = screw_length_mm(clamp_mm + (t.nut_height_mm + 1.0 if nut else 0.0) + thread_mm)
    out = [FastenerUse(robot, kind, size, length, count, where)]
    if nut:
        out.append(FastenerUse(robot, "ISO 4032", size, t.nut_height_mm, count, where))
    if insert:
        out.append(FastenerUse(robot, "insert", size, t.insert_length_mm, count, where))
    return out
