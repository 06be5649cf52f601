"""FE stiffness of the CuBot's side rail and top twist key from the CAD's dimensions (issue 12, deliverable 1).

The companion of :mod:`structure_fem.couplings.connector_fe` (the front-rear coupling) for the CuBot's other
two couplings, built the same way: a geometry dataclass read from the parametric
:class:`cubot_cad.robots.cubot.CuBot`, gmsh OCC geometry, P2 tetrahedra solved by
:func:`structure_fem.couplings.fe_solid.solve_linear_elastic`, results with a ``provenance`` string, cached
by the sha256 of geometry + material + mesh (same cache directory, same packaged JSON).

**Side rail** (:class:`cubot_cad.couplings.connectors.RailSpec`, :class:`~cubot_cad.couplings.connectors.RailMale`,
:class:`~cubot_cad.couplings.connectors.RailFemale`). A representative slice of the engaged rail: each
half's cross-section (male: plate + dovetail tongue; female: plate with the groove) extruded
``slice_mm`` along the rail, its back face (on the robot's side wall) clamped: **the side walls
are rigid** in this slice (the walls come in below). The two rails' faces slide on each
other (docked gap 0). In the planar model's pitch direction the load is vertical (z): with the
play taken up the tongue bears on one slanted flank of the groove (the upper one when pushed up).
Each half is loaded on that flank alone by a uniform vertical traction (the tongue's flank on the
male, the groove's flank over the tongue's depth on the female: a bonded flank, no slip, no
wedging) and its compliance is the mean vertical displacement of the flank; the joint is the two
halves in series. Per metre of engagement: ``q = F / (u slice)``; the slice's ends are free (the
screws, IR holes and end lead-ins are left out: a slice between the screws).
:func:`structure_fem.couplings.connector_sources.rail_in_pitch` would give ``k_z = q l`` and
``k_pitch = q l^3 / 12`` over the overlap ``l`` (the rigid-wall bound; the play the CAD's clearance).

The model's values come from the **whole rails on their side walls**
(:func:`rail_wall_flexibility`, :func:`rail_wall_joint`; ``SideRailFE.wall``). The vertical load
goes from one robot's wall to the other's ``s = plate + female`` (10 mm) away, so the rail stack
turns both 2.4 mm walls out of their planes: a hand estimate of a wall strip (``k_t ~ D (4 / a +
4 / b)``, ``q_wall = 2 k_t / s^2`` ~ 1.4e7 N/m per m) is an order of magnitude softer than the
rail slice on rigid walls. So each half's whole 80 mm rail is meshed on its side-wall panel
(``wall_span_mm`` between the front and rear walls' mid-planes, from the floor's mid-plane to the
top), the wall clamped at the floor and at the front and rear walls (stiffer than the real corners,
which are 2.4 mm plates too: as :mod:`structure_fem.couplings.connector_fe`), its top edge free (the cover is
screwed to the corner bosses and only rests on the walls), the rail bonded to the wall (it is
screwed at +-28 mm: bonded is stiffer; assumption). Two staggered robots engage over
``overlap_mm`` (rail length less half a pitch: 30 mm): the male at its rail's front end, the female
at its rear end (the other stagger is the mirror image). That overlap's flank is split into
:data:`SHELL_SEGMENTS` patches (the rail is built in pieces cut there and fragmented with the
wall, so the mesh conforms to the patches), one vertical load case each: the flexibility matrix
``C`` per half, symmetric (Maxwell), the halves in series ``C = C_male + C_female``, ``K =
inv(C)``, ``k_z = 1^T K 1`` and ``k_pitch = a^T K a`` about the overlap's centre
(:func:`structure_fem.couplings.connector_sources.rail_in_pitch` uses these; the slice's ``q`` stays in the
record as the rigid-wall bound). For a uniform ``q`` the 8 patches give ``(1 - 1/64)`` of the
continuous ``q l^3 / 12``: 1.6 % low.

Measured (thesis CuBot, ABS 2.2 GPa, 30 mm overlap; 2-core shared machine, 2026-12):

| whole-wall model | h 4 mm | h 3 mm (default) | h 2.5 mm |
|---|---|---|---|
| k_z (N/m) | 1.806e6 | 1.782e6 | ~1.77e6 (4 patches: 1.772e6) |
| k_pitch (N m/rad) | 510 | 505 | (4 patches: 487, against 490 at h 3) |
| dofs (both halves) / cold s | 67k / 18 s | 115k / 35 s | 147k / 54 s |

Against the rail slice on rigid walls (``q l`` = 1.15e7 N/m, ``q l^3 / 12`` = 859 N m/rad over
30 mm) the walls make the joint 6.4x softer vertically and 1.7x in pitch (a differential load
along the rail is carried by the wall in its plane; the mean load turns it out of its plane).
A 3.4 mm wall: k_z x1.4, k_pitch x1.2 (h 4 mm; tests/structure_fem/test_coupling_fe_rail_key.py).

**Top twist key** (:class:`cubot_cad.couplings.twist.TwistKey`, :class:`~cubot_cad.couplings.connectors.TopTwistSpec`,
:class:`~cubot_cad.couplings.twist.TwistDriveSpec`; key frame, z up from the upper robot's underside). The
key's cross head (arms ``arm_width_mm`` x ``head_mm`` with the bottom chamfer, arm tips unchamfered),
the stem (the IR bore in) and the thrust disc, meshed as one solid; the shaft above the disc is
not meshed (the disc is held).

* horizontal (x): the lower robot's collar roof bears on the stem over the roof's thickness (the
  +x half of the stem's surface in the roof's band, uniform traction), the disc clamped (top face
  and rim: floor and ring rigid, as the hand formula's "shaft bearing rigid"); ``k_h = F / u_x``.
* vertical (pull-out, z): the head's arms are pulled up against the roof's underside where the
  roof is (outside its cross hole, turned ``twist_deg`` from the arms: locked), one load case per
  arm; the disc's underside clamped where it rests on the ring's lip (outside the lip's cross
  bore, also turned). ``C`` (4 x 4 at the arms' load patches), ``K = inv(C)``: vertical
  ``1^T K 1``, pitch ``a^T K a`` with ``a_i`` the arms' load centroids' x in the robot frame.
  The roof and the collar (the lower robot's cover) are not meshed (rigid; assumption).

Measured for the thesis CuBot (ABS, E = 2.2 GPa, nu 0.35 assumed, no knockdown; 2-core shared
machine, 2026-12; packaged in ``structure_fem/data/connector_fe.json``):

| quantity | FE (default mesh) | hand formula (record) |
|---|---|---|
| rail q, vertical per metre of engagement (N/m per m) | 3.82e8 (male 1.02e9, female 6.09e8) | 1.375e8 |
| rail k_z over the 30 mm staggered overlap, walls rigid, q l (N/m) | 1.15e7 | 4.13e6 |
| rail k_pitch over 30 mm, walls rigid, q l^3 / 12 (N m/rad) | 859 | 309 |
| **rail k_z, whole rails on their side walls (the model's)** (N/m) | **1.78e6** | |
| **rail k_pitch, whole rails on their side walls (the model's)** (N m/rad) | **505** | |
| key horizontal, roof on the stem (N/m) | 2.04e6 | 2.72e6 (stem cantilever, bending + shear) |
| key vertical, pull-out, four arms (N/m) | 5.29e5 | 4.75e5 (4 arms E w t^3 / 4 L^3) |
| key pitch about its axis (N m/rad) | 14.5 | 46.6 |

Mesh convergence. Rail (20 mm slice): h 2.0 / 1.5 / 1.2 / 1.0 mm give q 3.924 / 3.848 / 3.818 /
3.798e8 (18k / 42k / 68k / 110k dofs; default 1.2 mm, the next step changes it 0.5 %); a 10 mm slice
is 2 % softer (its free ends). Key: h 2.4 / 2.0 / 1.5 mm give horizontal 2.011 / 2.037 / 2.041e6,
vertical 5.351 / 5.334 / 5.291e5, pitch 14.48 / 14.54 / 14.46 (default 1.5 mm, 50k dofs). Cold time
(``python -m structure_fem.couplings.connector_sources``, the machine shared): rail ~70 s (33 s the slices,
~35 s the whole-wall model), key 66 s. The FE
strip (:func:`strip_cantilever_fe`, 20 x 3 x 2 mm, h 1 mm) is within 1 % of ``E w t^3 / 4 L^3``.

What the FE says about the hand formulas: the rail's "lip" is not a 2 mm thick cantilever 4 mm
long (the flank overhang as thickness, the groove depth as length) but the whole band of the
female beside the groove (about 6 mm thick) plus the tongue and the male's plate; widening the
overhang (a wider tongue tip) makes the FE rail *softer* (less material beside the groove), a
taller rail (thicker lips beside the groove) stiffer. The key's arms bear on the roof from the
cross hole's edge outwards (load centroid 11 mm from the axis, not the 14 mm tip), which stiffens
them, but the stem bends when the head tilts: the pitch stiffness is a third of the hand value.
"""

from __future__ import annotations

import hashlib
import json
import math
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from structure_fem.couplings.connector_fe import FEResult, Material, _kilo, default_cache_dir
from structure_fem.couplings.fe_solid import GmshSession, Load, gmsh_tet_mesh, solve_linear_elastic
from structure_fem.errors import InputError

RAIL_MODEL_VERSION = "side_rail_fe/3"
KEY_MODEL_VERSION = "top_twist_fe/1"
#: Default mesh sizes (mm): the rail's tongue and lips are 4 mm deep, the key's arms 3 mm thick.
RAIL_SIZE_MM = 1.2
KEY_SIZE_MM = 1.5
#: Length of the rail slice (mm).
RAIL_SLICE_MM = 20.0
#: Least mesh size (mm) of the whole-wall model (:func:`rail_wall_flexibility`): the 2.4 mm wall
#: panel, 95 x 70 mm, with the whole rail half on it.
SHELL_SIZE_MM = 3.0
#: Load patches the engaged overlap's flank is split into along the rail in the whole-wall model:
#: the joint's vertical and pitch stiffness come from their flexibility matrix (a uniform q gives
#: (1 - 1/n^2) of the continuous pitch stiffness: 1.6 % low at 8).
SHELL_SEGMENTS = 8
_TOL_MM = 1e-3


@dataclass(frozen=True)
class FEMesh:
    size_mm: float
    order: int = 2
    curvature_elements: int = 16


# --- side rail ------------------------------------------------------------------------------

@dataclass(frozen=True)
class SideRailGeometry:
    """Cross-section (mm, rail frame: y out of the robot's side face, z up, x along the rail) of one
    engaged side-rail pair, read from :class:`cubot_cad.couplings.connectors.RailSpec`."""

    height_mm: float
    plate_mm: float  # the male's plate
    tongue_mm: float
    tongue_root_mm: float
    tongue_tip_mm: float
    female_mm: float  # the female's thickness (plate + groove depth)
    groove_depth_mm: float
    groove_mouth_half_mm: float  # the groove's half-width at its mouth
    flank_slope: float
    rail_length_mm: float
    slice_mm: float = RAIL_SLICE_MM
    #: The robot's side wall the rail is screwed to (the whole-wall model):
    #: its thickness and its extent below (to the floor's mid-plane) and above (to the top) the rail's axis.
    wall_mm: float = 2.4
    wall_below_mm: float = 24.5
    wall_above_mm: float = 45.8
    #: The side wall's span along the rail between the front and rear walls' mid-planes (mm), and the
    #: length over which two staggered robots' rails engage (rail length less half a pitch; mm).
    wall_span_mm: float = 97.6
    overlap_mm: float = 30.0

    @classmethod
    def from_cubot(cls, robot=None, slice_mm: float = RAIL_SLICE_MM, overlap_mm: float | None = None) -> SideRailGeometry:
        """``overlap_mm``: the staggered rails' engagement (default: rail length less half the body
        length, i.e. a zero docked gap; the record's gap is passed by
        :func:`structure_fem.couplings.connector_sources.fe_side_rail_for`)."""
        from cubot_cad.robots.cubot import CuBot

        r = robot if robot is not None else CuBot()
        s = r.rail_spec
        return cls(height_mm=s.height_mm, plate_mm=s.plate_mm, tongue_mm=s.tongue_mm,
                   tongue_root_mm=s.tongue_root_mm, tongue_tip_mm=s.tongue_tip_mm, female_mm=s.female_mm,
                   groove_depth_mm=s.groove_depth_mm, groove_mouth_half_mm=s.groove_half_width_mm(0.0),
                   flank_slope=s.flank_slope, rail_length_mm=s.length_mm, slice_mm=slice_mm,
                   wall_mm=r.wall_mm, wall_below_mm=r.rail_z_mm - r.floor_mm / 2,
                   wall_above_mm=r.body_height_mm - r.rail_z_mm, wall_span_mm=r.length_mm - r.wall_mm,
                   overlap_mm=overlap_mm if overlap_mm is not None else s.length_mm - r.length_mm / 2)

    def check(self) -> None:
        for n in ("height_mm", "plate_mm", "tongue_mm", "tongue_root_mm", "tongue_tip_mm", "female_mm",
                  "groove_depth_mm", "groove_mouth_half_mm", "slice_mm", "rail_length_mm"):
            v = getattr(self, n)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"SideRailGeometry.{n} must be > 0 mm, got {v!r}")
        if not self.groove_depth_mm < self.female_mm:
            raise InputError("the rail's groove is deeper than the female half")
        if not self.groove_half_mm(self.groove_depth_mm) < self.height_mm / 2:
            raise InputError("the rail's groove is wider than the rail")
        if not self.rail_length_mm <= self.wall_span_mm:
            raise InputError(f"SideRailGeometry.rail_length_mm {self.rail_length_mm:g} is longer than the side wall "
                             f"({self.wall_span_mm:g} mm between the front and rear walls)")
        if not 0 < self.overlap_mm <= self.rail_length_mm:
            raise InputError(f"SideRailGeometry.overlap_mm {self.overlap_mm!r}: staggered rails must overlap, by at "
                             f"most the rail's {self.rail_length_mm:g} mm")

    def groove_half_mm(self, depth_mm: float) -> float:
        return self.groove_mouth_half_mm + depth_mm * self.flank_slope

    def male_section(self) -> list[tuple[float, float]]:
        p, T, h = self.plate_mm, self.tongue_mm, self.height_mm / 2
        a, b = self.tongue_root_mm / 2, self.tongue_tip_mm / 2
        return [(0, -h), (0, h), (p, h), (p, a), (p + T, b), (p + T, -b), (p, -a), (p, -h)]

    def female_section(self) -> list[tuple[float, float]]:
        t, d, T, h = self.female_mm, self.groove_depth_mm, self.tongue_mm, self.height_mm / 2
        w0, wT, wd = self.groove_half_mm(0), self.groove_half_mm(T), self.groove_half_mm(d)
        # an extra vertex on each flank where the tongue's tip reaches (the bearing flank ends there)
        return [(0, -h), (0, h), (t, h), (t, w0), (t - T, wT), (t - d, wd), (t - d, -wd), (t - T, -wT),
                (t, -w0), (t, -h)]


def _extruded_section(points_yz, length_mm: float, x0_mm: float = 0.0):
    """Add the (y, z) polygon at x = ``x0_mm`` extruded by ``length_mm`` along x to the open gmsh
    OCC model; returns the new volumes' dimtags."""
    import gmsh

    occ = gmsh.model.occ
    pts = [occ.addPoint(x0_mm, y, z) for y, z in points_yz]
    lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
    surf = occ.addPlaneSurface([occ.addCurveLoop(lines)])
    return [d for d in occ.extrude([(2, surf)], length_mm, 0, 0) if d[0] == 3]


def build_rail_half_mesh(geom: SideRailGeometry, half: str, mesh: FEMesh):
    """Mesh one half's slice (metres out)."""
    geom.check()
    sec = geom.male_section() if half == "male" else geom.female_section()
    with GmshSession(f"rail_{half}"):
        import gmsh

        _extruded_section(sec, geom.slice_mm)
        gmsh.model.occ.synchronize()
        return gmsh_tet_mesh(mesh.size_mm, size_min_mm=mesh.size_mm / 4, curvature_elements=0)


def _on_segment(p0, p1, span=(0.0, 1.0)):
    """Facet selector: midpoints on the (y, z) segment p0-p1 (mm; any x), within ``span`` of it."""
    (y0, z0), (y1, z1) = p0, p1
    d = np.array([y1 - y0, z1 - z0])
    ln = float(np.hypot(*d))
    t_ = d / ln
    n = np.array([-t_[1], t_[0]])
    tol = _TOL_MM

    def sel(x):
        y, z = x[1] * 1e3 - y0, x[2] * 1e3 - z0
        s = (y * t_[0] + z * t_[1]) / ln
        return (np.abs(y * n[0] + z * n[1]) < tol) & (s > span[0] - 1e-6) & (s < span[1] + 1e-6)
    return sel


def _back_face(x):
    return np.abs(x[1]) < _TOL_MM * 1e-3


def _bearing_flank(geom: SideRailGeometry, half: str):
    """(facet selector, load sign) of the flank a half bears on when the lines are pushed apart
    vertically: the tongue's lower flank (pushed down) on the male, the groove's flank over the
    tongue's depth on the female (pushed up)."""
    if half == "male":
        p, T = geom.plate_mm, geom.tongue_mm
        return _on_segment((p, geom.tongue_root_mm / 2), (p + T, geom.tongue_tip_mm / 2)), -1.0
    t, T = geom.female_mm, geom.tongue_mm
    return _on_segment((t, geom.groove_half_mm(0)), (t - T, geom.groove_half_mm(T))), 1.0


def rail_half_compliance(geom: SideRailGeometry, half: str, mat: Material, mesh: FEMesh) -> dict:
    """One half of the rail slice, back face clamped, a vertical force on its bearing flank: the
    flank's mean vertical displacement per newton (m/N) and solve facts."""
    t0 = time.perf_counter()
    m = build_rail_half_mesh(geom, half, mesh)
    t_mesh = time.perf_counter() - t0
    flank, f = _bearing_flank(geom, half)
    res = solve_linear_elastic(m, mat.E_pa, mat.poisson, _back_face, [Load(flank, (0.0, 0.0, f))], order=mesh.order)
    u = res.mean_displacement(flank, 0)[2] / f
    if not u > 0:
        raise InputError(f"rail {half}: the flank moved against its load ({u:g} m/N)")
    return {"compliance_m_per_n": float(u), "n_dofs": res.n_dofs, "n_elements": res.n_elements,
            "seconds": {"mesh": round(t_mesh, 3), "solve": round(res.seconds, 3),
                        "total": round(time.perf_counter() - t0, 3)}}


def build_rail_wall_mesh(geom: SideRailGeometry, half: str, mesh: FEMesh, cuts_mm=()):
    """Mesh one half's whole rail on its robot's side-wall panel (metres out): the rail over its
    length centred on x = 0, joined to the wall (``wall_mm`` thick behind the rail's back face,
    ``wall_span_mm`` along x between the front and rear walls' mid-planes, from the floor's mid-plane
    to the body's top). The rail is built in pieces split at ``cuts_mm`` (x, mm) and fragmented with
    the wall, so the mesh is conforming and no facet straddles a cut (the load patches' ends)."""
    geom.check()
    sec = geom.male_section() if half == "male" else geom.female_section()
    L = geom.rail_length_mm
    xs = sorted({-L / 2, L / 2, *(c for c in cuts_mm if -L / 2 + _TOL_MM < c < L / 2 - _TOL_MM)})
    with GmshSession(f"rail_wall_{half}"):
        import gmsh

        occ = gmsh.model.occ
        pieces = [d for a, b in zip(xs[:-1], xs[1:], strict=True) for d in _extruded_section(sec, b - a, a)]
        xa = geom.wall_span_mm / 2
        w = occ.addBox(-xa, -geom.wall_mm, -geom.wall_below_mm, 2 * xa, geom.wall_mm,
                       geom.wall_below_mm + geom.wall_above_mm)
        occ.fragment(pieces, [(3, w)])
        occ.synchronize()
        return gmsh_tet_mesh(mesh.size_mm, size_min_mm=mesh.size_mm / 4, curvature_elements=0)


def _panel_edges(geom: SideRailGeometry):
    """The side wall's joined edges: the floor (its mid-plane) and the front and rear walls (their
    mid-planes), clamped; the top edge is free (the cover is screwed to the corner bosses and only
    rests on the walls' top edges)."""
    t = _TOL_MM * 1e-3
    lo, xa = -geom.wall_below_mm * 1e-3, geom.wall_span_mm / 2 * 1e-3

    def sel(x):
        return (x[1] < 0) & ((np.abs(x[2] - lo) < t) | (np.abs(np.abs(x[0]) - xa) < t))
    return sel


def _in_x(select, x0_mm: float, x1_mm: float):
    """``select`` restricted to facets whose midpoints have x in [x0, x1) (mm)."""
    def sel(x):
        return select(x) & (x[0] >= x0_mm * 1e-3) & (x[0] < x1_mm * 1e-3)
    return sel


def overlap_levers_m(geom: SideRailGeometry, segments: int = SHELL_SEGMENTS) -> np.ndarray:
    """The load patches' centres along the engaged overlap, from its centre (m)."""
    return geom.overlap_mm * 1e-3 * ((np.arange(segments) + 0.5) / segments - 0.5)


def rail_wall_flexibility(geom: SideRailGeometry, half: str, mat: Material, mesh: FEMesh,
                          segments: int = SHELL_SEGMENTS) -> dict:
    """One half's rail on its whole side wall (:func:`build_rail_wall_mesh`, :func:`_panel_edges`
    clamped), loaded vertically on its bearing flank over the staggered overlap only: the male at its
    rail's front end, the female at its rear end (the partner half a pitch ahead; the other stagger is
    the mirror image). The overlap is split into ``segments`` patches along the rail, one load case
    each: the flexibility matrix ``C[i, j]`` (m/N), the mean vertical displacement of patch i per
    newton on patch j, symmetrised (Maxwell: equal up to the discretisation), and solve facts."""
    if not (isinstance(segments, int) and segments >= 2):
        raise InputError(f"segments must be an integer >= 2 (a pitch needs two patches), got {segments!r}")
    t0 = time.perf_counter()
    L, lo = geom.rail_length_mm, geom.overlap_mm
    x0 = L / 2 - lo if half == "male" else -L / 2
    cuts = [x0 + lo * j / segments for j in range(segments + 1)]
    m = build_rail_wall_mesh(geom, half, mesh, cuts)
    t_mesh = time.perf_counter() - t0
    flank, f = _bearing_flank(geom, half)
    cuts[-1] += _TOL_MM  # the overlap's last patch includes the rail's end face's edge
    patches = [_in_x(flank, cuts[j], cuts[j + 1]) for j in range(segments)]
    res = solve_linear_elastic(m, mat.E_pa, mat.poisson, _panel_edges(geom),
                               [Load(p_, (0.0, 0.0, f)) for p_ in patches], order=mesh.order)
    C = np.array([[res.mean_displacement(patches[i], j)[2] / f for j in range(segments)] for i in range(segments)])
    asym = float(np.max(np.abs(C - C.T)) / np.max(np.abs(C)))
    C = 0.5 * (C + C.T)
    if not (np.all(np.diag(C) > 0) and np.all(np.linalg.eigvalsh(C) > 0)):
        raise InputError(f"rail {half} on its wall: the flexibility matrix is not positive definite ({C.tolist()})")
    return {"C_m_per_n": C.tolist(), "asymmetry": asym, "n_dofs": res.n_dofs, "n_elements": res.n_elements,
            "seconds": {"mesh": round(t_mesh, 3), "solve": round(res.seconds, 3),
                        "total": round(time.perf_counter() - t0, 3)}}


def rail_wall_joint(geom: SideRailGeometry, male: dict, female: dict, segments: int = SHELL_SEGMENTS) -> dict:
    """The joint of the two halves on their walls: at each patch the halves are in series (the
    relative vertical displacement is the sum), ``C = C_male + C_female``, ``K = inv(C)``; vertical
    ``k_z = 1^T K 1``, pitch about the overlap's centre ``k_pitch = a^T K a`` (``a``: the patches'
    levers, :func:`overlap_levers_m`)."""
    C = np.asarray(male["C_m_per_n"]) + np.asarray(female["C_m_per_n"])
    K = np.linalg.inv(C)
    a = overlap_levers_m(geom, segments)
    one = np.ones(segments)
    return {"k_z_n_per_m": float(one @ K @ one), "k_pitch_nm_per_rad": float(a @ K @ a),
            "levers_m": a.tolist(), "overlap_mm": geom.overlap_mm, "segments": segments}


@dataclass
class SideRailFE(FEResult):
    """FE stiffness of the side rail per metre of engagement (SI) and where it comes from."""

    kind: str
    q_n_per_m_per_m: float  # the joint (male + female in series)
    male_q_n_per_m_per_m: float
    female_q_n_per_m_per_m: float
    rail_stiffness_n_per_m: float  # q times the whole rail length (for comparison with the record)
    #: The model's values: both halves' whole rails on their side walls, engaged over the staggered
    #: overlap (:func:`rail_wall_flexibility`, :func:`rail_wall_joint`): ``k_z_n_per_m``,
    #: ``k_pitch_nm_per_rad``, the overlap and patches, per half the flexibility matrix, dofs, seconds.
    wall: dict
    provenance: str
    input_hash: str
    inputs: dict
    timings_s: dict = field(default_factory=dict)
    cache_hit: bool = False


def _hash(model: str, geom, mat: Material, mesh: FEMesh) -> str:
    payload = {"model": model, "geometry": asdict(geom), "material": asdict(mat), "mesh": asdict(mesh)}
    return hashlib.sha256(json.dumps(payload, sort_keys=True, default=float).encode()).hexdigest()


def rail_input_hash(geom: SideRailGeometry, mat: Material, mesh: FEMesh) -> str:
    return _hash(RAIL_MODEL_VERSION, geom, mat, mesh)


def compute_side_rail(geom: SideRailGeometry, mat: Material, mesh: FEMesh = FEMesh(RAIL_SIZE_MM),
                      wall: bool = True, wall_mesh: FEMesh | None = None) -> SideRailFE:
    """Cold FE of the side rail (no cache): the rail slice's vertical stiffness per length (walls
    rigid) and, with ``wall``, the model's values, the whole rails on their side walls
    (:attr:`SideRailFE.wall`; ``wall_mesh`` default: :data:`SHELL_SIZE_MM` or the rail's mesh if
    coarser). See the module docstring."""
    t0 = time.perf_counter()
    male = rail_half_compliance(geom, "male", mat, mesh)
    female = rail_half_compliance(geom, "female", mat, mesh)
    ls = geom.slice_mm * 1e-3
    walls: dict = {}
    if wall:
        wmesh = wall_mesh or FEMesh(max(mesh.size_mm, SHELL_SIZE_MM), mesh.order, mesh.curvature_elements)
        wm = rail_wall_flexibility(geom, "male", mat, wmesh)
        wf = rail_wall_flexibility(geom, "female", mat, wmesh)
        walls = rail_wall_joint(geom, wm, wf) | {
            "male": wm, "female": wf, "mesh_size_mm": wmesh.size_mm, "n_dofs": wm["n_dofs"] + wf["n_dofs"],
            "seconds": round(wm["seconds"]["total"] + wf["seconds"]["total"], 3)}
    qm = 1.0 / (male["compliance_m_per_n"] * ls)
    qf = 1.0 / (female["compliance_m_per_n"] * ls)
    q = 1.0 / (1.0 / qm + 1.0 / qf)
    dofs = male["n_dofs"] + female["n_dofs"]
    prov = (f"fe: scikit-fem P{mesh.order} tetra, gmsh h={mesh.size_mm:g} mm, {_kilo(dofs)} dofs (male "
            f"{_kilo(male['n_dofs'])} + female {_kilo(female['n_dofs'])}), E={mat.E_pa:.3g} Pa, nu={mat.poisson:g}; "
            f"{geom.slice_mm:g} mm slice of each rail half, back face clamped (side walls rigid: assumption), "
            f"vertical load on the bearing flank (bonded), halves in series: q = {q:.4g} N/m per m")
    if walls:
        prov += (f"; the model's values: each half's whole {geom.rail_length_mm:g} mm rail bonded to its "
                 f"{geom.wall_mm:g} mm side wall ({geom.wall_span_mm:g} x {geom.wall_below_mm + geom.wall_above_mm:g} mm, "
                 f"clamped at the floor and the front and rear walls, top free; gmsh h={walls['mesh_size_mm']:g} mm, "
                 f"{_kilo(walls['n_dofs'])} dofs), loaded over the {geom.overlap_mm:g} mm staggered overlap in "
                 f"{walls['segments']} patches, halves in series: k_z = {walls['k_z_n_per_m']:.4g} N/m, "
                 f"k_pitch = {walls['k_pitch_nm_per_rad']:.4g} N m/rad")
    return SideRailFE(
        kind="side_rail", q_n_per_m_per_m=q, male_q_n_per_m_per_m=qm, female_q_n_per_m_per_m=qf,
        rail_stiffness_n_per_m=q * geom.rail_length_mm * 1e-3, wall=walls, provenance=prov,
        input_hash=rail_input_hash(geom, mat, mesh),
        inputs={"geometry": asdict(geom), "material": asdict(mat), "mesh": asdict(mesh), "model": RAIL_MODEL_VERSION,
                "n_dofs": dofs, "n_elements": male["n_elements"] + female["n_elements"]},
        timings_s={"male": male["seconds"], "female": female["seconds"],
                   "total": round(time.perf_counter() - t0, 3)})


# --- top twist key --------------------------------------------------------------------------

@dataclass(frozen=True)
class TwistKeyGeometry:
    """Dimensions (mm, key frame: z up from the upper robot's underside) of the twist key and the
    lower robot's collar roof it bears on, docked and locked."""

    arm_width_mm: float
    arm_length_mm: float
    head_mm: float
    chamfer_mm: float
    head_bottom_z_mm: float  # -key_protrusion
    disc_z_mm: tuple[float, float]
    disc_diameter_mm: float
    bore_mm: float
    roof_z_mm: tuple[float, float]  # the collar roof's underside and top, key frame
    hole_half_width_mm: float  # half-width of the roof's cross hole's arms (and of the ring lip's bore)
    twist_deg: float

    @classmethod
    def from_cubot(cls, robot=None) -> TwistKeyGeometry:
        from cubot_cad.robots.cubot import CuBot

        r = robot if robot is not None else CuBot()
        s, d = r.top_spec, r.drive_spec
        under = s.roof_under_mm - s.stand_mm
        return cls(arm_width_mm=s.arm_width_mm, arm_length_mm=s.arm_length_mm, head_mm=s.head_mm,
                   chamfer_mm=s.key_chamfer_mm, head_bottom_z_mm=-s.key_protrusion_mm,
                   disc_z_mm=tuple(d.disc_z_mm), disc_diameter_mm=d.disc_diameter_mm, bore_mm=s.ir_bore_mm,
                   roof_z_mm=(under, under + s.roof_mm), hole_half_width_mm=s.arm_width_mm / 2 + s.clearance_mm,
                   twist_deg=s.twist_deg)

    @property
    def head_top_z_mm(self) -> float:
        return self.head_bottom_z_mm + self.head_mm

    def check(self) -> None:
        for n in ("arm_width_mm", "arm_length_mm", "head_mm", "disc_diameter_mm", "bore_mm"):
            v = getattr(self, n)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"TwistKeyGeometry.{n} must be > 0 mm, got {v!r}")
        if not self.bore_mm < self.arm_width_mm:
            raise InputError("the key's IR bore is wider than its stem")
        r0, r1 = self.roof_z_mm
        if not self.head_top_z_mm < r0 < r1 < self.disc_z_mm[0] < self.disc_z_mm[1] <= 0:
            raise InputError("key head, collar roof and thrust disc are not in order along z")


def build_key_mesh(geom: TwistKeyGeometry, mesh: FEMesh):
    geom.check()
    w, L, ch = geom.arm_width_mm, geom.arm_length_mm, geom.chamfer_mm
    zb, zt = geom.head_bottom_z_mm, geom.head_top_z_mm
    z0, z1 = geom.disc_z_mm
    r0, r1 = geom.roof_z_mm
    with GmshSession("twist_key") as gmsh:
        occ = gmsh.model.occ
        # each arm: its chamfered cross-section extruded along its length
        sec = [(-w / 2, zb + ch), (-w / 2 + ch, zb), (w / 2 - ch, zb), (w / 2, zb + ch), (w / 2, zt), (-w / 2, zt)]
        vols = []
        for along_x in (True, False):
            if along_x:
                pts = [occ.addPoint(-L / 2, a, b) for a, b in sec]
                vec = (L, 0, 0)
            else:
                pts = [occ.addPoint(a, -L / 2, b) for a, b in sec]
                vec = (0, L, 0)
            lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
            s = occ.addPlaneSurface([occ.addCurveLoop(lines)])
            out = occ.extrude([(2, s)], *vec)
            vols += [e for e in out if e[0] == 3]
        # the stem in three pieces (the roof's band imprinted on it), the disc
        for za, zc in ((zt, r0), (r1, z0)):
            vols.append((3, occ.addCylinder(0, 0, za, 0, 0, zc - za, w / 2)))
        for turn in (-math.pi / 2, math.pi / 2):  # the band in two halves: the +x one is loaded
            half = occ.addCylinder(0, 0, r0, 0, 0, r1 - r0, w / 2, angle=math.pi)
            occ.rotate([(3, half)], 0, 0, 0, 0, 0, 1, turn)
            vols.append((3, half))
        vols.append((3, occ.addCylinder(0, 0, z0, 0, 0, z1 - z0, geom.disc_diameter_mm / 2)))
        bore = (3, occ.addCylinder(0, 0, zb - 1, 0, 0, z1 - zb + 2, geom.bore_mm / 2))
        key, _ = occ.fragment(vols[:1], vols[1:])
        key, _ = occ.cut(key, [bore])
        # imprint the roof's cross hole (on the head's top) and the ring lip's cross bore (on the disc's
        # underside), both turned twist_deg from the arms, so the load and support patches follow them
        hw, big = geom.hole_half_width_mm, L
        cutters = []
        for za, zc in ((zb - 0.5, zt + 0.5), (z0 - 0.5, z1 + 0.5)):
            for bx, by in ((big, hw), (hw, big)):
                b = occ.addBox(-bx, -by, za, 2 * bx, 2 * by, zc - za)
                occ.rotate([(3, b)], 0, 0, 0, 0, 0, 1, math.radians(geom.twist_deg))
                cutters.append((3, b))
        inside, _ = occ.intersect(cutters, occ.copy(key))
        key, _ = occ.fragment(key, inside)
        occ.synchronize()
        return gmsh_tet_mesh(mesh.size_mm, size_min_mm=mesh.size_mm / 4, curvature_elements=mesh.curvature_elements)


def _outside_turned_cross(xm, ym, half: float, twist_deg: float):
    """Mask: (x, y) (mm) outside both arms of a cross of half-width ``half`` turned ``twist_deg``."""
    c, s = math.cos(math.radians(twist_deg)), math.sin(math.radians(twist_deg))
    u, v = c * xm + s * ym, -s * xm + c * ym
    return (np.abs(u) > half) & (np.abs(v) > half)


def _arm_patch(geom: TwistKeyGeometry, arm: int):
    """Selector of arm ``arm``'s (0 +x, 1 +y, 2 -x, 3 -y) top face under the roof."""
    zt = geom.head_top_z_mm * 1e-3
    t = _TOL_MM * 1e-3

    def sel(x):
        xm, ym = x[0] * 1e3, x[1] * 1e3
        ang = np.mod(np.round(np.arctan2(ym, xm) / (np.pi / 2)), 4)
        return ((np.abs(x[2] - zt) < t) & (np.hypot(xm, ym) > geom.arm_width_mm / 2 + 1e-3) & (ang == arm)
                & _outside_turned_cross(xm, ym, geom.hole_half_width_mm, geom.twist_deg))
    return sel


def _disc_land(geom: TwistKeyGeometry):
    z0 = geom.disc_z_mm[0] * 1e-3
    t = _TOL_MM * 1e-3

    def sel(x):
        xm, ym = x[0] * 1e3, x[1] * 1e3
        return (np.abs(x[2] - z0) < t) & _outside_turned_cross(xm, ym, geom.hole_half_width_mm, geom.twist_deg)
    return sel


def _disc_held(geom: TwistKeyGeometry):
    z0, z1 = geom.disc_z_mm[0] * 1e-3, geom.disc_z_mm[1] * 1e-3
    rd = geom.disc_diameter_mm / 2 * 1e-3
    t = _TOL_MM * 1e-3

    def sel(x):
        rim = (np.abs(np.hypot(x[0], x[1]) - rd) < 0.05 * rd) & (x[2] > z0 - t) & (x[2] < z1 + t)
        return (np.abs(x[2] - z1) < t) | rim
    return sel


def _stem_band(geom: TwistKeyGeometry):
    r0, r1 = geom.roof_z_mm[0] * 1e-3, geom.roof_z_mm[1] * 1e-3
    rs = geom.arm_width_mm / 2 * 1e-3

    def sel(x):
        return ((x[2] > r0) & (x[2] < r1) & (np.abs(np.hypot(x[0], x[1]) - rs) < 0.05 * rs) & (x[0] > 0))
    return sel


@dataclass
class TwistKeyFE(FEResult):
    """FE stiffness of the top twist key (SI) and where it comes from."""

    kind: str
    horizontal_stiffness_n_per_m: float  # x, the roof bearing on the stem
    vertical_stiffness_n_per_m: float  # z, pull-out: the four arms under the roof together
    rotational_stiffness_nm_per_rad: float  # pitch about the key axis (y), the arms' vertical springs
    per_arm_vertical_n_per_m: float
    lever_arms_m: list[float]
    provenance: str
    input_hash: str
    inputs: dict
    timings_s: dict = field(default_factory=dict)
    cache_hit: bool = False


def key_input_hash(geom: TwistKeyGeometry, mat: Material, mesh: FEMesh) -> str:
    return _hash(KEY_MODEL_VERSION, geom, mat, mesh)


def compute_twist_key(geom: TwistKeyGeometry, mat: Material, mesh: FEMesh = FEMesh(KEY_SIZE_MM)) -> TwistKeyFE:
    """Cold FE of the twist key (no cache): see the module docstring."""
    t0 = time.perf_counter()
    m = build_key_mesh(geom, mesh)
    t_mesh = time.perf_counter() - t0
    band = _stem_band(geom)
    res_h = solve_linear_elastic(m, mat.E_pa, mat.poisson, _disc_held(geom), [Load(band, (1.0, 0.0, 0.0))],
                                 order=mesh.order)
    k_h = 1.0 / res_h.mean_displacement(band, 0)[0]
    patches = [_arm_patch(geom, i) for i in range(4)]
    res_v = solve_linear_elastic(m, mat.E_pa, mat.poisson, _disc_land(geom),
                                 [Load(p, (0.0, 0.0, -1.0)) for p in patches], order=mesh.order)
    C = np.array([[-res_v.mean_displacement(patches[i], j)[2] for j in range(4)] for i in range(4)])
    C = 0.5 * (C + C.T)
    K = np.linalg.inv(C)
    # load centroids of the arms' patches, robot frame x (the key turned twist_deg from its open position)
    from skfem import FacetBasis, Functional

    arms = []
    for i, fs in enumerate(res_v.load_facets):
        fb = FacetBasis(m, res_v.basis.elem, facets=fs, intorder=2)
        area = Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(fb)
        rc = Functional(lambda w: np.hypot(w.x[0], w.x[1])).assemble(fb) / area
        arms.append(float(rc * math.cos(math.radians(90.0 * i + geom.twist_deg))))
    a = np.array(arms)
    ones = np.ones(4)
    k_v, k_rot = float(ones @ K @ ones), float(a @ K @ a)
    if not (k_h > 0 and k_v > 0 and k_rot > 0):
        raise InputError("twist key FE: a stiffness came out <= 0 (selection or mesh problem)")
    prov = (f"fe: scikit-fem P{mesh.order} tetra, gmsh h={mesh.size_mm:g} mm ({mesh.curvature_elements}/circle), "
            f"{_kilo(res_h.n_dofs)} dofs, E={mat.E_pa:.3g} Pa, nu={mat.poisson:g}; key head + stem + thrust disc "
            f"(disc held; collar roof rigid: assumption): horizontal = roof on the stem over its "
            f"{geom.roof_z_mm[1] - geom.roof_z_mm[0]:g} mm, vertical/pitch = arms under the roof outside its cross "
            f"hole (locked {geom.twist_deg:g} deg), disc on the ring's lip")
    return TwistKeyFE(
        kind="top_twist", horizontal_stiffness_n_per_m=float(k_h), vertical_stiffness_n_per_m=k_v,
        rotational_stiffness_nm_per_rad=k_rot, per_arm_vertical_n_per_m=float(1.0 / C[0, 0]), lever_arms_m=arms,
        provenance=prov, input_hash=key_input_hash(geom, mat, mesh),
        inputs={"geometry": asdict(geom), "material": asdict(mat), "mesh": asdict(mesh), "model": KEY_MODEL_VERSION,
                "n_dofs": res_h.n_dofs, "n_elements": res_h.n_elements},
        timings_s={"mesh": round(t_mesh, 3), "horizontal": round(res_h.seconds, 3), "vertical": round(res_v.seconds, 3),
                   "total": round(time.perf_counter() - t0, 3)})


# --- cache ----------------------------------------------------------------------------------

def _cached(key: str, cls, compute, cache_dir, use_cache: bool):
    t0 = time.perf_counter()
    path = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    file = path / f"{key}.json"
    if use_cache and file.is_file():
        try:
            d = json.loads(file.read_text())
            if d.get("input_hash") == key:
                out = cls.from_dict(d, cache_hit=True)
                out.timings_s = dict(out.timings_s, cached_call=round(time.perf_counter() - t0, 4))
                return out
        except (OSError, ValueError, KeyError, TypeError):
            pass  # unreadable or stale: recompute and overwrite
    out = compute()
    if use_cache:
        path.mkdir(parents=True, exist_ok=True)
        tmp = file.with_suffix(".tmp")
        tmp.write_text(json.dumps(out.to_dict(), indent=1, sort_keys=True))
        tmp.replace(file)
    return out


def _material(material) -> Material:
    return material if isinstance(material, Material) else Material.from_cubot_cad(material)


def side_rail_fe(robot=None, material: str | Material = "abs", mesh: FEMesh = FEMesh(RAIL_SIZE_MM),
                 cache_dir=None, use_cache: bool = True, slice_mm: float = RAIL_SLICE_MM,
                 overlap_mm: float | None = None) -> SideRailFE:
    """FE of a CuBot's side rail (default: the thesis's), cached as ``<cache_dir>/<hash>.json``;
    ``overlap_mm``: the staggered engagement (:meth:`SideRailGeometry.from_cubot`)."""
    geom = SideRailGeometry.from_cubot(robot, slice_mm, overlap_mm)
    mat = _material(material)
    return _cached(rail_input_hash(geom, mat, mesh), SideRailFE, lambda: compute_side_rail(geom, mat, mesh),
                   cache_dir, use_cache)


def twist_key_fe(robot=None, material: str | Material = "abs", mesh: FEMesh = FEMesh(KEY_SIZE_MM),
                 cache_dir=None, use_cache: bool = True) -> TwistKeyFE:
    """FE of a CuBot's top twist key (default: the thesis's), cached as ``<cache_dir>/<hash>.json``."""
    geom = TwistKeyGeometry.from_cubot(robot)
    mat = _material(material)
    return _cached(key_input_hash(geom, mat, mesh), TwistKeyFE, lambda: compute_twist_key(geom, mat, mesh),
                   cache_dir, use_cache)


# --- validation helper ---------------------------------------------------------------------

def strip_cantilever_fe(length_mm: float, thickness_mm: float, width_mm: float, E_pa: float, nu: float,
                        mesh: FEMesh) -> float:
    """Tip stiffness (N/m) of a rectangular strip clamped at its root (x = 0), a uniform line load
    across its tip face (the groove lip of the hand formula), by the same FE as the couplings:
    compare with ``E w t^3 / (4 L^3)``."""
    with GmshSession("strip"):
        import gmsh

        gmsh.model.occ.addBox(0, -width_mm / 2, 0, length_mm, width_mm, thickness_mm)
        gmsh.model.occ.synchronize()
        m = gmsh_tet_mesh(mesh.size_mm, size_min_mm=mesh.size_mm / 4, curvature_elements=0)
    t = _TOL_MM * 1e-3
    L = length_mm * 1e-3

    def tip(x):
        return np.abs(x[0] - L) < t

    def root(x):
        return np.abs(x[0]) < t

    res = solve_linear_elastic(m, E_pa, nu, root, [Load(tip, (0.0, 0.0, -1.0))], order=mesh.order)
    return float(1.0 / -res.mean_displacement(tip, 0)[2])
