"""Capture range of each coupling: how far off its docked pose a robot may start and still be
guided in by the lead-ins (measured on the meshes, mm and degrees).

The criterion (what "captured" means here)
------------------------------------------
Robot B starts *misaligned* from its docked pose against robot A by one of:

* an offset of ``m`` mm along one of the coupling's two transverse axes (for the front-rear
  and side couplings: lateral = horizontal, vertical = z; for the top-down coupling: x and y),
* a turn of ``m`` degrees about one of those two axes through B's *entry point* (the centre
  of B's coupling face, the key tip, the rail's leading end, the finger tips' base),

with its connectors open, far enough back along the docking axis that nothing touches
(``start_mm``, further in 1 mm steps if the turn makes it touch there). It is then driven along the docking axis toward the docked pose in steps of
:data:`STEP_MM` (:data:`RAIL_STEP_MM` along the rail). Across the axis B is compliant, as a docking robot on its wheels is: at each
step it keeps its misalignment if that pose is collision-free (intersection of the two meshes
<= :data:`~cubot_cad.checks.docking.CONTACT_MM3`), and otherwise gives way to the largest fraction
``s`` (at most the fraction it had) of its starting misalignment at which it is collision-free
(bisection, 2^-8 of the misalignment).

A step is *guided* when giving way moved the contact point (the centre of the overlap A/B
before giving way) by at most ``STEP_MM / FRICTION`` (:data:`FRICTION` = 0.5, ABS or PLA on
itself): a contact face whose normal makes an angle beta with the docking axis turns an
advance of dt into a sideways slide of dt / tan(beta), and B only slides along it when
tan(beta) > friction. A lead-in (a 45 deg chamfer or cone: 1 x dt) passes; a face across the
axis (the flat around a hole without a lead-in: the whole offset at once) does not, whatever
the step. The entry is *captured* when every step down to the docked pose is guided (except within
:data:`SEAT_MM` of it: there B meets the faces or pin tips that stop it at its docked gap, and squares
up on them).

The capture range of a direction is the largest misalignment of the ladder
(:data:`OFFSET_LADDER_MM`, :data:`ANGLE_LADDER_DEG`) that is captured with every rung from the
required one up to it captured too (below the required rung: the largest captured one); a coupling's capture is the smallest over its four offset and
four angle directions. Required (issue 15): >= :data:`REQUIRED_OFFSET_MM` and >=
:data:`REQUIRED_ANGLE_DEG`.

Only the coupling's own parts are checked (front-rear: the two robots' bodies and connector
stacks within a slab around the interface; rail: the rails; top-down: the cover and the cross
key; ring: the ring, housing and fingers): the wheels landing or a robot's own drive are not
lead-ins. The platform's bolted lap joint is assembled by hand, not docked, and has no
capture range (``None``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

#: Axial step of the driven entry (mm); the rail, 80 mm long with 1.5-2.5 mm lead-ins, takes RAIL_STEP_MM.
STEP_MM = 0.2
RAIL_STEP_MM = 0.5
#: Friction coefficient of printed ABS/PLA sliding on itself (dry, typical 0.3-0.5; the upper end).
FRICTION = 0.5
#: A step is guided when the contact point gives way by at most this times the step.
MAX_GIVE_PER_STEP = 1.0 / FRICTION
BISECTIONS = 8
#: A new contact is judged on the first ONSET_MM of advance past its onset (mm): a face across the
#: axis needs its whole give there, a lead-in only ONSET_MM (so without lead-ins the measured capture
#: is at most the clearance + 2 x ONSET_MM).
ONSET_MM = 0.05
#: The last SEAT_MM before the docked pose is the seat: the faces or pin tips that stop B there (the
#: docked gap) square it up on whatever misalignment is left (a turn of at most a few tenths of a
#: degree by then); contacts there are not judged as lead-ins.
SEAT_MM = 0.1
#: Tessellation of the capture meshes (mm, rad): coarser than the export's, fine against the lead-ins.
CAPTURE_TOLERANCE_MM = 0.03
CAPTURE_ANGULAR_RAD = 0.3
REQUIRED_OFFSET_MM = 1.0
REQUIRED_ANGLE_DEG = 3.0
OFFSET_LADDER_MM = (0.5, 1.0, 1.5, 2.0)
ANGLE_LADDER_DEG = (1.5, 3.0, 4.5, 6.0)
#: Margin (mm) of the slab the front-rear parts are clipped to, beyond the entry travel.
SLAB_MARGIN_MM = 6.0


@dataclass
class Entry:
    """One driven entry: misalignment, whether it was captured, and why not."""

    direction: str
    magnitude: float
    captured: bool
    residual_fraction: float
    worst_give_per_step: float
    reason: str = ""


@dataclass
class CouplingGeometry:
    """What the entry simulation needs, in robot A's frame with B at its docked pose."""

    fixed: object  # manifold3d.Manifold
    moving: object
    approach: np.ndarray  # unit vector B moves along while docking
    pivot: np.ndarray  # B's entry point (docked pose)
    axes: dict  # name -> unit transverse vector
    start_mm: float
    step_mm: float = 0.2


@dataclass
class Capture:
    pair: str
    step_mm: float = STEP_MM
    offset_mm: dict[str, float] = field(default_factory=dict)
    angle_deg: dict[str, float] = field(default_factory=dict)
    entries: list[Entry] = field(default_factory=list, repr=False)

    @property
    def min_offset_mm(self) -> float:
        return min(self.offset_mm.values())

    @property
    def min_angle_deg(self) -> float:
        return min(self.angle_deg.values())

    @property
    def ok(self) -> bool:
        return self.min_offset_mm >= REQUIRED_OFFSET_MM - 1e-9 and self.min_angle_deg >= REQUIRED_ANGLE_DEG - 1e-9

    def summary(self) -> dict:
        return {"offset_mm": self.offset_mm, "angle_deg": self.angle_deg,
                "min_offset_mm": self.min_offset_mm, "min_angle_deg": self.min_angle_deg,
                "required_offset_mm": REQUIRED_OFFSET_MM, "required_angle_deg": REQUIRED_ANGLE_DEG,
                "ok": self.ok, "step_mm": self.step_mm, "onset_mm": ONSET_MM, "friction": FRICTION,
                "ladder_mm": list(OFFSET_LADDER_MM), "ladder_deg": list(ANGLE_LADDER_DEG)}


# --- poses ---------------------------------------------------------------------------------

def _rotation(axis, deg: float) -> np.ndarray:
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    th = math.radians(deg)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K


def pose(g: CouplingGeometry, t_mm: float, kind: str, vec, magnitude: float, s: float) -> np.ndarray:
    """4x4 transform of B (from its docked pose, A frame): backed off ``t_mm`` along the approach,
    misaligned by the fraction ``s`` of ``magnitude`` (mm offset along ``vec`` or deg about ``vec``)."""
    M = np.eye(4)
    if kind == "offset":
        M[:3, 3] = s * magnitude * np.asarray(vec, dtype=float)
    else:
        R = _rotation(vec, s * magnitude)
        M[:3, :3] = R
        M[:3, 3] = g.pivot - R @ g.pivot
    M[:3, 3] -= g.approach * t_mm
    return M


def _apply(M, m):
    return m.transform(M[:3, :4])


def _overlap(g: CouplingGeometry, M):
    from cubot_cad.checks.docking import intersection_volume

    return intersection_volume(g.fixed, _apply(M, g.moving))


def entry(g: CouplingGeometry, kind: str, name: str, magnitude: float) -> Entry:
    """Drive B in from ``start_mm`` misaligned by ``magnitude`` (see the module docstring)."""
    from cubot_cad.checks.docking import CONTACT_MM3

    vec = g.axes[name]
    t, s, worst = g.start_mm, 1.0, 0.0
    label = f"{'' if kind == 'offset' else 'rot '}{name}"

    def free(tt, ss):
        return _overlap(g, pose(g, tt, kind, vec, magnitude, ss)) <= CONTACT_MM3

    def give_way(tn, ss, dt):
        """(new fraction, contact point moved / dt, contact point) for the step to ``tn``."""
        M_before = pose(g, tn, kind, vec, magnitude, ss)
        b = (g.fixed ^ _apply(M_before, g.moving)).bounding_box()
        contact = (np.array(b[:3]) + np.array(b[3:])) / 2
        lo, hi = 0.0, ss
        for _ in range(BISECTIONS):
            mid = (lo + hi) / 2
            if free(tn, mid):
                lo = mid
            else:
                hi = mid
        moved = pose(g, tn, kind, vec, magnitude, lo) @ np.linalg.inv(M_before) @ np.append(contact, 1.0)
        return lo, float(np.linalg.norm(moved[:3] - contact)) / dt, contact

    def steep(tn, ratio, contact):
        return Entry(label, magnitude, False, s, max(worst, ratio),
                     f"steep contact {tn:.2f} mm from docked: gave way {ratio:.2f} x the advance "
                     f"(> {MAX_GIVE_PER_STEP:g}) at {np.round(contact, 2).tolist()}")

    for _ in range(20):  # a turned robot reaches further forward: start it further back, 1 mm at a time
        if free(t, s):
            break
        t += 1.0
    else:
        return Entry(label, magnitude, False, s, 0.0, f"touches even {t:g} mm back")
    sliding = False
    while t > 1e-9:
        dt = min(g.step_mm, t)
        tn = max(t - dt, 0.0)
        if free(tn, s):
            t, sliding = tn, False
            continue
        if not free(tn, 0.0):
            return Entry(label, magnitude, False, s, worst, f"blocked even when aligned, {tn:.2f} mm from docked")
        if not sliding:
            # a new contact: find where it starts and look at the first ONSET_MM past it, so that a
            # face across the axis cannot hide in a long step (it needs the whole give at once)
            lo, hi = tn, t
            for _ in range(BISECTIONS):
                mid = (lo + hi) / 2
                if free(mid, s):
                    hi = mid
                else:
                    lo = mid
            t_on = max(hi - ONSET_MM, 0.0)
            if t_on >= SEAT_MM - 1e-9 and not free(t_on, s):
                _, ratio, contact = give_way(t_on, s, ONSET_MM)
                worst = max(worst, ratio)
                if ratio > MAX_GIVE_PER_STEP:
                    return steep(t_on, ratio, contact)
        s_new, ratio, contact = give_way(tn, s, dt)
        if tn < SEAT_MM - 1e-9:  # the stops that define the docked pose: B squares up on them
            s, t, sliding = s_new, tn, True
            continue
        worst = max(worst, ratio)
        if ratio > MAX_GIVE_PER_STEP:
            return steep(tn, ratio, contact)
        s, t, sliding = s_new, tn, True
    return Entry(label, magnitude, True, s, worst)


# --- the couplings -------------------------------------------------------------------------

def _box(lo, hi):
    import manifold3d as m3d

    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return m3d.Manifold.cube(tuple(hi - lo)).translate(tuple(lo))


@lru_cache(maxsize=512)
def _part_manifold(part):
    import manifold3d as m3d

    from cubot_cad.mesh import mesh_of

    mesh = mesh_of(part.solid.copy(False), CAPTURE_TOLERANCE_MM, CAPTURE_ANGULAR_RAD)  # own triangulation
    return m3d.Manifold(m3d.Mesh(vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
                                 tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))


def _union_of(items, shift=(0.0, 0.0, 0.0)):
    from cubot_cad.checks.docking import union
    from cubot_cad.shapes import loc_matrix

    return union(_part_manifold(p.part).transform(loc_matrix(p.loc)) for p in items).translate(
        tuple(float(v) for v in shift))


def _slab(m, axis: int, lo: float, hi: float):
    big = 1e4
    a, b = [-big] * 3, [big] * 3
    a[axis], b[axis] = lo, hi
    return m ^ _box(a, b)


def geometry(r, name: str, pair) -> CouplingGeometry | None:
    """The coupling geometry of docked pair ``pair`` (a :class:`~cubot_cad.checks.docking.DockedPair`
    of robot ``r``); None for the platform's hand-bolted joint."""
    off = np.asarray(pair.offset_mm, dtype=float)
    X, Y, Z = np.eye(3)
    if name in ("cubot-front-rear", "cube-robot-front-rear", "cube-robot-side"):
        fr = r.fr_spec
        items = list(r.placed)
        if name == "cube-robot-side":
            approach, axis, lat = Y, 1, {"x": X, "z": Z}
            face_b = np.array([0.0, r.size_mm / 2, r.block_z_mm])  # B's left (latch) face
        else:
            approach, axis, lat = X, 0, ({"y": Y, "z": Z})
            yc = getattr(r, "y_centre_mm", 0.0)
            face_b = np.array([r.envelope_mm[0] / 2, yc, r.block_z_mm])  # B's front (pin) face
        start = fr.protrusion_mm - pair.gap_mm + 1.0
        plane = float((face_b + off) @ approach)  # B's coupling face; A lies beyond it (+approach)
        # the pins reach protrusion - gap into the latch side; the pin side is reached only at its face
        # (B only backs off); the margin covers what the largest turn moves along the axis
        reach = fr.protrusion_mm + SLAB_MARGIN_MM
        conn = _union_of([p for p in items if p.role.removesuffix("_side") in ("pin", "pinset", "latchset", "blade")])
        lo, hi = (np.array(v) for v in (conn.bounding_box()[:3], conn.bounding_box()[3:]))
        lo, hi = lo - SLAB_MARGIN_MM, hi + SLAB_MARGIN_MM  # across the axis: the connector blocks' region
        if name == "cube-robot-side":  # A's pins enter B's latches: B's side is the deep one
            lo[axis], hi[axis] = plane - reach, plane + SLAB_MARGIN_MM
        else:  # B's pins enter A's latches
            lo[axis], hi[axis] = plane - SLAB_MARGIN_MM, plane + reach
        region = _box(lo, hi)
        fixed = _union_of(items) ^ region
        moving = _union_of(items, off) ^ region
        return CouplingGeometry(fixed, moving, approach, face_b + off, lat, start)
    if name == "cubot-top-down":
        ts = r.top_spec
        fixed = _union_of([p for p in r.build_placed(with_locking_key=False) if p.role == "cover"])
        moving = _union_of([p for p in r.placed if p.role == "cross_key"], off)
        pivot = np.array([0.0, r.y_centre_mm, -ts.key_protrusion_mm]) + off
        start = ts.collar_mm - ts.head_z0_mm + 1.0
        return CouplingGeometry(fixed, moving, -Z, pivot, {"x": X, "y": Y}, start)
    if name == "cubot-side-rail":
        rs = r.rail_spec
        rails = [p for p in r.placed if p.role == "rail"]
        # B slides in from behind along +x (the dovetail cannot be entered sideways)
        fixed = _union_of(rails)
        moving = _union_of(rails, off)
        pivot = np.array([rs.length_mm / 2, r.y_centre_mm - r.body_width_mm / 2 - rs.female_mm, r.rail_z_mm]) + off
        # 0.5 mm steps along the 80 mm rail: the lead-ins are 1.5-2.5 mm long, and a new contact is
        # always judged on its first ONSET_MM
        return CouplingGeometry(fixed, moving, X, pivot, {"y": Y, "z": Z}, rs.length_mm + 1.0, RAIL_STEP_MM)
    if name == "octbot-ring":
        rs = r.ring_spec
        fixed = _union_of([p for p in r.placed if p.role == "ring"])
        moving = _union_of([p for p in r.placed if p.role in ("housing", "finger")], off)
        h = r.across_flats_mm / 2
        from cubot_cad.robots.octbot import Finger

        protrude = Finger(spec=rs, housing_mm=r.housing_mm).tip_x_mm - r.housing_mm
        pivot = np.array([h + r.housing_mm, 0.0, rs.centre_z_mm]) + off
        return CouplingGeometry(fixed, moving, X, pivot, {"y": Y, "z": Z}, protrude + 1.0)
    if name == "platform-bolt":
        return None
    raise AssertionError(name)


def _ladder_capture(g, kind, axis_name, sign, ladder, required, entries, full_ladder) -> float:
    """Largest rung of ``ladder`` captured with every smaller rung captured: from the required rung up
    (only that rung unless ``full_ladder``), or down from it when it fails."""
    def run(m):
        e = entry(g, kind, axis_name, sign * m)
        e.direction = f"{'+' if sign > 0 else '-'}{e.direction}"
        e.magnitude = m
        entries.append(e)
        return e.captured

    i0 = ladder.index(required)
    if run(required):
        got = required
        for m in (ladder[i0 + 1:] if full_ladder else ()):
            if not run(m):
                break
            got = m
        return got
    for m in reversed(ladder[:i0]):
        if run(m):
            return m
    return 0.0


def measure(r, name: str, pair, full_ladder: bool = True) -> Capture | None:
    """Capture range of coupling ``name`` (see the module docstring); None for the platform.

    ``full_ladder`` False checks the required rung only (and the smaller ones when it fails)."""
    g = geometry(r, name, pair)
    return None if g is None else measure_geometry(name, g, full_ladder)


def measure_geometry(name: str, g: CouplingGeometry, full_ladder: bool = True) -> Capture:
    """Capture range of coupling ``name`` from its geometry alone (:func:`measure`)."""
    cap = Capture(name, step_mm=g.step_mm)
    for ax in g.axes:
        for sign in (1, -1):
            cap.offset_mm[f"{'+' if sign > 0 else '-'}{ax}"] = _ladder_capture(
                g, "offset", ax, sign, OFFSET_LADDER_MM, REQUIRED_OFFSET_MM, cap.entries, full_ladder)
    for ax in g.axes:
        for sign in (1, -1):
            cap.angle_deg[f"{'+' if sign > 0 else '-'}rot_{ax}"] = _ladder_capture(
                g, "angle", ax, sign, ANGLE_LADDER_DEG, REQUIRED_ANGLE_DEG, cap.entries, full_ladder)
    return cap


def capture_of(pair_name: str, clearance_mm: float, full_ladder: bool = True) -> Capture | None:
    """Capture of one of :data:`~cubot_cad.checks.docking.PAIRS` for the default robot at ``clearance_mm``."""
    from cubot_cad.checks.docking import ROBOT_OF_PAIR, dock
    from cubot_cad.robots.registry import make_robot

    return measure(make_robot(ROBOT_OF_PAIR[pair_name], clearance_mm), pair_name, dock(pair_name, clearance_mm),
                   full_ladder)
