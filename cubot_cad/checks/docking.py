"""Docked pairs: put two robots together the way they couple and measure the result.

For each coupling one robot (B) approaches the other (A) along the coupling
direction with its connectors in the *open* state (latch blades open, cross
key aligned with the hole, OctBot fingers closed, no locking key). The docked
pose is the first contact, found by bisection on the intersection volume of
the two robots' meshes (manifold3d). The *docked gap* is then the distance
between the robots' faces in that pose: nothing is drawn in, it is whatever
the pin length, latch depth, ring and housing, or wheel height give.

Then the connectors are closed (blades turned, key turned and locked, fingers
opened) and the interference volume between every printed part of A and B is
measured (for the top-down pair with the twist drive's screws, nuts and horn as solids, for the
side rail with the rails' screws: :meth:`~cubot_cad.robots.base.Robot.hardware`). A pair is ``ok`` when that interference is <= 1 mm^3 and the measured
gap is the pair's designed gap (:func:`design_gap_mm`) within
:data:`GAP_TOLERANCE_MM`; :func:`require_docked` turns a failing pair into an
:class:`~cubot_cad.errors.InputError`, which stops an export before it writes.

How far off a robot may arrive and still be guided in by the lead-ins (the capture range) is
measured by :mod:`cubot_cad.checks.capture` on these docked pairs.

Couplings: ``cubot-front-rear``, ``cubot-side-rail`` (B slides in on A's left;
its lateral play is reported too), ``cubot-top-down`` (B stands on A's cover
on its wheels and casters, key through the collar), ``octbot-ring``,
``cube-robot-front-rear``, ``cube-robot-side`` (pins right into latches left),
``platform-bolt``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from cubot_cad.errors import InputError
from cubot_cad.part import DEFAULT_CLEARANCE_MM, check_clearance
from cubot_cad.shapes import loc_matrix

PAIRS = ("cubot-front-rear", "cubot-side-rail", "cubot-top-down", "octbot-ring",
         "cube-robot-front-rear", "cube-robot-side", "platform-bolt")
ROBOT_OF_PAIR = {p: ("cube-robot" if p.startswith("cube-robot") else p.split("-")[0]) for p in PAIRS}
KIND_OF_PAIR = {"cubot-front-rear": "front_rear", "cubot-side-rail": "side_rail", "cubot-top-down": "top_twist",
                "octbot-ring": "ring_capture", "cube-robot-front-rear": "front_rear", "cube-robot-side": None,
                "platform-bolt": "bolt"}
CONTACT_MM3 = 1e-3
INTERFERENCE_LIMIT_MM3 = 1.0
#: Gaps below this (mm) are contact: the bisection stops at 1e-4 mm, meshes are within 0.02 mm.
GAP_RESOLUTION_MM = 0.005
#: A measured docked gap may differ from the designed one by this much (mm): the meshes are
#: within 0.02 mm of the exact surfaces on each robot (STL tolerance), the bisection 1e-4 mm.
GAP_TOLERANCE_MM = 0.05


def to_manifold(shape, tolerance: float = 0.02):
    """OCC shape (mm) -> manifold3d.Manifold via tessellation."""
    import manifold3d as m3d

    from cubot_cad.mesh import mesh_of

    mesh = mesh_of(shape, tolerance, 0.1)
    return m3d.Manifold(m3d.Mesh(vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
                                 tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))


@lru_cache(maxsize=512)
def part_manifold(part):
    """Manifold of a part's solid in its mounting frame (tessellated once per distinct part)."""
    return to_manifold(part.solid)


def manifold_of(item):
    """A :class:`~cubot_cad.robots.base.Placed` (cached per part) or a plain OCC shape."""
    from cubot_cad.robots.base import Placed

    if isinstance(item, Placed):
        return part_manifold(item.part).transform(loc_matrix(item.loc))
    return to_manifold(item)


def shape_of(item):
    from cubot_cad.robots.base import Placed

    return item.shape if isinstance(item, Placed) else item


def union(manifolds):
    import manifold3d as m3d

    items = list(manifolds)
    return m3d.Manifold.batch_boolean(items, m3d.OpType.Add) if len(items) > 1 else items[0]


def intersection_volume(a, b) -> float:
    return max(0.0, float((a ^ b).volume()))  # manifold3d can return -0.0 / -1e-12 for no overlap


@dataclass
class DockedPair:
    """A measured docked pair. Lengths mm, volumes mm^3; ``shapes_*`` are OCC shapes in the A frame."""

    name: str
    robot: str
    kind: str | None
    direction: tuple[float, float, float]
    gap_mm: float
    interference_mm3: float
    open_interference_mm3: float
    play_mm: float | None = None
    offset_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    shapes_a: list = field(default_factory=list, repr=False)
    shapes_b: list = field(default_factory=list, repr=False)
    #: The gap the robot's geometry is designed to dock at (None: not known, not checked).
    design_gap_mm: float | None = None
    clearance_mm: float | None = None

    @property
    def interference_ok(self) -> bool:
        return self.interference_mm3 <= INTERFERENCE_LIMIT_MM3

    @property
    def gap_ok(self) -> bool:
        return self.design_gap_mm is None or abs(self.gap_mm - self.design_gap_mm) <= GAP_TOLERANCE_MM

    @property
    def ok(self) -> bool:
        return self.interference_ok and self.gap_ok

    def problems(self) -> list[str]:
        """What is wrong with the pair, one phrase each (empty when ``ok``)."""
        out = []
        if not self.gap_ok:
            out.append(f"gap {self.gap_mm:.2f} mm, designed {self.design_gap_mm:.2f} +- {GAP_TOLERANCE_MM:g} mm")
        if not self.interference_ok:
            out.append(f"interference {self.interference_mm3:.1f} mm^3 > {INTERFERENCE_LIMIT_MM3:g} mm^3")
        return out

    def summary(self) -> dict:
        d = {"pair": self.name, "robot": self.robot, "coupling": self.kind, "gap_mm": round(self.gap_mm, 3),
             "design_gap_mm": None if self.design_gap_mm is None else round(self.design_gap_mm, 3),
             "interference_mm3": round(self.interference_mm3, 4), "ok": self.ok,
             "offset_mm": [round(v, 3) for v in self.offset_mm]}
        if self.play_mm is not None:
            d["play_mm"] = round(self.play_mm, 3)
        return d

    def assembly(self):
        import cadquery as cq

        assy = cq.Assembly(name=self.name)
        for i, s in enumerate(self.shapes_a):
            assy.add(s, name=f"a_{i}", color=cq.Color(0.85, 0.85, 0.8))
        for i, s in enumerate(self.shapes_b):
            assy.add(s, name=f"b_{i}", color=cq.Color(0.55, 0.7, 0.9))
        return assy


def _contact_boundary(fixed, moving, direction, t_clear: float, t_hit: float, tol: float = 1e-4) -> float:
    """Bisect t between ``t_hit`` (intersecting) and ``t_clear`` (free) for ``moving`` translated by t*direction."""
    d = np.asarray(direction, dtype=float)

    def hits(t):
        return intersection_volume(fixed, moving.translate(tuple(d * t))) > CONTACT_MM3

    if hits(t_clear):
        raise RuntimeError(f"no free position at t = {t_clear} mm")
    if not hits(t_hit):
        return t_hit
    lo, hi = t_hit, t_clear
    while abs(hi - lo) > tol:
        mid = (lo + hi) / 2
        if hits(mid):
            lo = mid
        else:
            hi = mid
    return hi


def _bbox(m):
    b = m.bounding_box()
    return np.array(b[:3]), np.array(b[3:])


def _overlapping(ms, lo, hi, margin=0.5):
    """Indices of manifolds whose bbox overlaps the box [lo, hi] grown by ``margin``."""
    out = []
    for i, m in enumerate(ms):
        a, b = _bbox(m)
        if np.all(a <= hi + margin) and np.all(b >= lo - margin):
            out.append(i)
    return out


def _union_bbox(ms):
    boxes = [_bbox(m) for m in ms]
    return np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)


def _near_union(fixed_ms, moving_ms, shifts):
    """Unions of the parts of each side that can touch the other over the given shifts of ``moving``."""
    lo_a, hi_a = _union_bbox(fixed_ms)
    lo_b, hi_b = _union_bbox(moving_ms)
    sh = np.array(shifts, dtype=float)
    lo_b_all, hi_b_all = lo_b + sh.min(axis=0), hi_b + sh.max(axis=0)
    ia = _overlapping(fixed_ms, lo_b_all, hi_b_all)
    ib = _overlapping(moving_ms, lo_a - sh.max(axis=0), hi_a - sh.min(axis=0))
    if not ia or not ib:
        return None, None
    return union(fixed_ms[i] for i in ia), union(moving_ms[i] for i in ib)


def _pair(name, robot_name, fixed_open, moving_open, fixed_closed, moving_closed, direction, nominal,
          t_clear, t_hit, misalign=(0.0, 0.0, 0.0)) -> DockedPair:
    """Approach with the open sets, then measure the closed sets at the docked pose."""
    d = np.asarray(direction, dtype=float)
    nominal = np.asarray(nominal, dtype=float)
    fo = [manifold_of(x) for x in fixed_open]
    mo = [manifold_of(x).translate(tuple(nominal)) for x in moving_open]
    fa, mb = _near_union(fo, mo, [d * t_clear, d * t_hit])
    if fa is None:
        raise RuntimeError(f"{name}: the robots never come near each other")
    t = _contact_boundary(fa, mb, d, t_clear, t_hit)
    open_int = intersection_volume(fa, mb.translate(tuple(d * t)))
    offset = nominal + d * t + np.asarray(misalign, dtype=float)
    fc = [manifold_of(x) for x in fixed_closed]
    mc = [manifold_of(x).translate(tuple(offset)) for x in moving_closed]
    ma, mbc = _near_union(fc, mc, [np.zeros(3)])
    inter = 0.0 if ma is None else intersection_volume(ma, mbc)
    a_shapes = [shape_of(x) for x in fixed_closed]
    b_shapes = [shape_of(x).translate(tuple(float(v) for v in offset)) for x in moving_closed]
    gap = 0.0 if abs(t) < GAP_RESOLUTION_MM else round(float(t), 3)
    return DockedPair(name, robot_name, KIND_OF_PAIR[name], tuple(d), gap, inter, open_int, None,
                      tuple(float(v) for v in offset), a_shapes, b_shapes)


def dock(name: str, clearance_mm: float = DEFAULT_CLEARANCE_MM,
         misalign_mm: tuple[float, float, float] = (0.0, 0.0, 0.0), settings: tuple = ()) -> DockedPair:
    """Build and measure the docked pair ``name`` (one of :data:`PAIRS`) of the default robots, or of
    robots built with ``settings`` (``--set`` (name, value) pairs, :func:`~cubot_cad.outputs.export.make_robot`).

    ``misalign_mm`` shifts B after docking before the closed-state interference
    is measured (a check that the measurement sees real overlaps).

    Measured once per process for each robot (the registry's shared instance) and misalignment,
    however the arguments are spelled: ``dock(n)``, ``dock(n, 0.2)`` and ``dock(n, 0.2,
    settings=())`` are one pair (the cache was keyed by the spelling, so the cad stage, `cad dock`
    and the pier docked the same pairs up to three times in one process).
    """
    check_clearance(clearance_mm, "--clearance-mm")
    if name not in PAIRS:
        raise InputError(f"docked pair {name!r} is not one of {', '.join(PAIRS)}")
    from cubot_cad.robots.registry import make_robot

    return dock_of(make_robot(ROBOT_OF_PAIR[name], clearance_mm, tuple(settings)), name, misalign_mm)


def dock_of(robot, name: str, misalign_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> DockedPair:
    """:func:`dock_robot`, measured once per process for each (equal) robot, pair and misalignment."""
    return _dock_cached(robot, name, tuple(float(v) for v in misalign_mm))


@lru_cache(maxsize=64)
def _dock_cached(robot, name: str, misalign_mm: tuple[float, float, float]) -> DockedPair:
    return dock_robot(robot, name, misalign_mm)


def design_gap_mm(r, name: str) -> float:
    """The face gap (mm) robot ``r``'s geometry is designed to dock at through coupling ``name``."""
    if name in ("cubot-front-rear", "cube-robot-front-rear", "cube-robot-side"):
        return r.fr_spec.design_gap_mm  # 0 (CuBot), the pins' overrun (Cube Robot, 1.7 mm)
    if name == "cubot-top-down":
        return r.top_spec.stand_mm  # the upper robot stands on its wheels; the key is made for it
    if name == "octbot-ring":
        return r.docked_gap_mm
    return 0.0  # side rail, platform bolt: faces touch


def require_docked(pairs, what: str = "--clearance-mm", then: str = "") -> None:
    """Raise :class:`InputError` (one line) naming every pair that interferes or misses its
    designed gap and the clearance (``what``) it was built with; ``then`` is appended
    (e.g. ``"nothing written"``)."""
    bad = [p for p in pairs if not p.ok]
    if not bad:
        return
    cs = sorted({p.clearance_mm for p in bad if p.clearance_mm is not None})
    at = f"{what} {', '.join(f'{c:g}' for c in cs)}: " if cs else ""
    rows = "; ".join(f"{p.name}: {', '.join(p.problems())}" for p in bad)
    raise InputError(f"{at}docked pair{'s' if len(bad) > 1 else ''} fail{'' if len(bad) > 1 else 's'} "
                     f"({rows})" + (f"; {then}" if then else ""))


def dock_robot(r, name: str, misalign_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> DockedPair:
    """Dock two copies of robot ``r`` (any parameters) through coupling ``name``."""
    if name not in PAIRS:
        raise InputError(f"docked pair {name!r} is not one of {', '.join(PAIRS)}")
    if ROBOT_OF_PAIR[name] != r.name:
        raise InputError(f"docked pair {name!r} needs a {ROBOT_OF_PAIR[name]}, got {r.name}")
    pair = _dock_robot(r, name, misalign_mm)
    pair.design_gap_mm = float(design_gap_mm(r, name))
    pair.clearance_mm = float(r.clearance_mm)
    return pair


def _dock_robot(r, name: str, misalign_mm: tuple[float, float, float]) -> DockedPair:
    if name in ("cubot-front-rear", "cube-robot-front-rear", "platform-bolt"):
        L = r.envelope_mm[0]
        open_ = list(r.placed)
        closed = open_ if name == "platform-bolt" else r.build_placed(blades_locked=True)
        # B is the rear robot: its front (pins / tab) enters A's rear (latches / recess); t = face gap
        return _pair(name, r.name, open_, open_, closed, closed, (-1, 0, 0), (-L, 0, 0), 10.0, -3.0, misalign_mm)
    if name == "cube-robot-side":
        W = r.envelope_mm[1]
        open_ = list(r.placed)
        closed = r.build_placed(blades_locked=True)
        # B on A's right (-y): A's right pins enter B's left latches
        return _pair(name, r.name, open_, open_, closed, closed, (0, -1, 0), (0, -W, 0), 10.0, -3.0, misalign_mm)
    if name == "cubot-side-rail":
        W = r.width_mm
        items = list(r.placed)
        # the rails' screws count too (heads sunk below the faces the other half slides on)
        closed = items + [h.shape for h in r.hardware(items)]
        pair = _pair(name, r.name, items, items, closed, closed, (0, 1, 0), (0, W, 0), 0.0, -2.0, misalign_mm)
        # lateral play: how far B can be pulled away before the dovetail flanks catch
        fa = union(manifold_of(p) for p in r.placed if p.role == "rail")
        fb = union(manifold_of(p) for p in r.placed if p.role == "rail").translate((0, W, 0))
        pair.play_mm = _contact_boundary(fa, fb, (0, -1, 0), 0.0, -2.0)
        pair.play_mm = -pair.play_mm
        return pair
    if name == "cubot-top-down":
        H = r.body_height_mm + r.top_spec.cover_mm
        a_open = r.build_placed(with_locking_key=False)
        b_open = list(r.placed) + r.component_solids(ground_only=True)
        a_closed = list(r.placed)
        b_closed = r.build_placed(key_turned=True)
        # the bought drive parts that are not printed (the twist-lock's screws, nuts and horn) count too
        a_closed += [h.shape for h in r.hardware(a_closed)]
        b_closed += [h.shape for h in r.hardware(b_closed)]
        return _pair(name, r.name, a_open, b_open, a_closed, b_closed, (0, 0, 1), (0, 0, H), 40.0, 0.0, misalign_mm)
    if name == "octbot-ring":
        L = r.envelope_mm[0]
        open_ = list(r.placed)  # fingers closed
        closed = r.build_placed(fingers_open=True)
        return _pair(name, r.name, open_, open_, closed, closed, (-1, 0, 0), (-L, 0, 0),
                     r.docked_gap_mm + 30.0, 0.0, misalign_mm)
    raise AssertionError(name)


def measured_gaps(pairs: list[DockedPair]) -> dict[str, dict[str, float]]:
    """robot -> coupling kind -> measured gap (mm), for the properties record."""
    out: dict[str, dict[str, float]] = {}
    for p in pairs:
        if p.kind:
            out.setdefault(p.robot, {})[p.kind] = p.gap_mm
    return out


def pairs_for(robots) -> list[str]:
    return [p for p in PAIRS if ROBOT_OF_PAIR[p] in robots]
