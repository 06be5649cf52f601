"""FE stiffness of the OctBot's ring-and-capture coupling from the CAD's dimensions (issue 12, deliverable 1).

The companion of :mod:`structure_fem.couplings.connector_fe`, :mod:`structure_fem.couplings.rail_key_fe` and
:mod:`structure_fem.couplings.platform_bolt_fe` for the OctBot (:class:`cubot_cad.robots.octbot.OctBot`: robot A's
capturer housing with three fingers at 0/120/240 deg about the capture axis, held by the finger
retainer; robot B's ring, whose lip the fingers' hooks reach behind). Built the same way: a
geometry dataclass read from the parametric CAD (:class:`OctRingGeometry`), gmsh OCC geometry, P2
tetrahedra solved by :func:`structure_fem.couplings.fe_solid.solve_linear_elastic`, a result record with a
``provenance`` string, cached (and packaged) by the sha256 of geometry + material + mesh
(:func:`octbot_ring_fe`).

**The load path in pitch (frame in mm: A's housing frame, x from A's front face towards B, (y, z)
about the capture axis, z up).** When two docked OctBots sag, B turns about the bottom edge of its
ring's lip face, which bears on A's retainer plate (compression: a contact, taken as a rigid hinge,
as the hand formula :func:`cubot_cad.couplings.compliance.ring_capture` and the planar model do); above the
hinge the ring pulls away, its lip's inner face bears on the three hooks, each finger is pulled
along x, and its two shoulders bear on the retainer's back face beside the finger's slot. So:

* **Side A, fingers + retainer** (:func:`build_finger_side_mesh`). The three fingers as the CAD
  builds them (bar with its outer face rounded to the lip's bore less the clearance, hook with its
  lead-in chamfer, the shoulders on the tail; the cam peg is left out: it slides along x in the cam
  disc's slot and carries no axial load) and the retainer plate with its three slots. **The play is
  taken up**: the fingers sit ``clearance_mm`` further out than drawn, so their shoulders' front
  faces touch the retainer's back face and are **bonded** to it over the strips where they overlap
  it (a linear model: no separation, no slip). **The retainer is clamped where it rests on the
  housing's front face** (everywhere on its back face except over the fingers' chambers and the
  centre pocket, which open in that face): the housing is rigid and the two preloaded M2 screws keep
  the plate on it (assumption; the screw holes lie in the clamped area and are left out). The
  fingers' pegs, their slots in the retainer and the cam disc carry nothing in this load path
  (clearances all round) and are not meshed.
* **Side B, the ring** (:func:`build_ring_side_mesh`). The ring as the CAD builds it (mounting
  plate, tube, undercut, lip with its lead-in cone), **its plate's back face clamped**: robot B's
  2 mm rear wall is rigid (assumption; the two M3 screw holes are in the clamped face and left out).
  The rear wall is the next compliance in series (as the CuBot's walls are for its pins,
  :mod:`structure_fem.couplings.connector_fe`): not in this model.
* **The interface**: each hook's back face against the lip's inner face, over the overlap (the
  hook's outline beyond the lip's bore). One load case per finger on each side: a uniform traction
  of 1 N along x on that finger's patch (+x on the hook, -x on the lip), the generalised
  displacement the patch's mean ``u_x`` (work-conjugate with the uniform traction). The 3 x 3
  flexibilities ``C_A`` (fingers + retainer) and ``C_B`` (ring) add (the patches are the same points
  of the joint, in series): ``K = inv(C_A + C_B)``. Axial ``1^T K 1`` (the three fingers stretched
  alike), pitch ``a^T K a`` about the hinge with ``a_i`` the height of finger ``i``'s bearing patch
  centroid above the ring's bottom edge (the hand formula's arms are the bars' centre lines).
* **Shear is not modelled**: a vertical load goes from the lip's bore onto the top finger's bar
  radially, and from the finger through its peg into the cam disc's spiral slot and the worm (a
  self-locking drive with clearances), a path this model does not have. ``shear_stiffness_n_per_m``
  is NaN; the record has none either, so the planar model keeps taking the axial value along z.

Material: the record's (``cubot_cad.part.MATERIALS`` via :class:`~structure_fem.couplings.connector_fe.Material`,
Poisson 0.35 assumed), the same modulus for the fingers, the retainer and the ring.

**Play (kinematic, from the CAD).** Two clearances in series along x before the fingers carry
tension: the hook's back face is ``clearance_mm`` off the lip's inner face, and each finger floats
along x in its chamber, its shoulders ``clearance_mm`` short of the retainer's back face (its tail
``clearance_mm`` off the chamber's bottom: nothing holds it axially but the peg, which slides in
its slot). So one ``tension`` play (one-sided, along x) of the two in series, ``2 clearance_mm``;
the hand formula had the hook's only. (A record allows one play feature per axis and sense.) The pitch dead band is that play over the top
finger's arm (its bearing patch's height above the hinge).

Measured for the thesis OctBot (ABS, E = 2.2 GPa, nu 0.35 assumed; 2-core shared machine, 2026-12;
packaged in ``structure_fem/data/connector_fe.json``; more in ``docs/structure_fem.md``, "The
OctBot's ring"):

| quantity | FE (default mesh) | hand formula (record) |
|---|---|---|
| joint pitch about the ring's bottom edge (N m/rad) | 84.0 | 831 (three bars E A / L, sum k a^2) |
| joint axial (N/m) | 4.01e5 | 4.4e6 |
| one finger, both sides / fingers + retainer / ring (N/m) | 1.34e5 / 1.47e5 / 1.51e6 | 1.47e6 / - / rigid |
| arms above the hinge, top / lower fingers (mm) | 22.0 / 8.5 (bearing patches) | 19.3 / 9.85 (bar centres) |
| tension play (mm) / pitch dead band (mrad) | 0.4 / 18.2 | 0.2 / 10.4 |

The hooks bear 2.7 mm outside the bars' centre lines: the fingers bend under the pull, hence a
tenth of the axial-bar value. Mesh (fingers / lip / elsewhere, mm): 1.2 / 2 / 3, 0.8 / 1.2 / 3
(default, 92k dofs), 0.6 / 0.8 / 3 (189k dofs) give pitch 85.5 / 84.0 / 83.1 N m/rad, axial 4.09 /
4.01 / 3.97e5 N/m (the last step 1.0 %). Cold 20 s (mesh 1.4 s, fingers side 10.6 s, ring side
7.5 s); the finer mesh 74 s.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from structure_fem.couplings.connector_fe import FEResult, Material, _kilo
from structure_fem.couplings.fe_solid import GmshSession, Load, gmsh_tet_mesh, solve_linear_elastic
from structure_fem.couplings.rail_key_fe import _cached, _hash, _material
from structure_fem.errors import InputError

MODEL_VERSION = "octbot_ring_fe/2"
#: Default mesh: element size (mm) in the fingers, the hooks and the lip (a fifth of the 3 mm finger)
#: and elsewhere (retainer plate away from the slots, ring plate); P2 tetrahedra. Chosen by the mesh
#: convergence in docs/structure_fem.md.
FINGER_SIZE_MM = 0.8
RING_SIZE_MM = 1.2
SIZE_MM = 3.0
_TOL_MM = 1e-3


@dataclass(frozen=True)
class RingMesh:
    finger_size_mm: float = FINGER_SIZE_MM  # in and within a finger thickness of the fingers
    ring_size_mm: float = RING_SIZE_MM  # in the lip and the tube round it
    size_mm: float = SIZE_MM  # elsewhere
    order: int = 2
    curvature_elements: int = 24

    def check(self) -> None:
        for n in ("finger_size_mm", "ring_size_mm", "size_mm"):
            v = getattr(self, n)
            if not (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0):
                raise InputError(f"RingMesh.{n} must be > 0 mm, got {v!r}")
        if self.order not in (1, 2):
            raise InputError(f"RingMesh.order must be 1 or 2, got {self.order!r}")


@dataclass(frozen=True)
class OctRingGeometry:
    """Dimensions (mm) of two docked OctBots' ring coupling, read from the CAD. Frame: robot A's
    housing frame (x from A's front face towards B), (y, z) about the capture axis."""

    finger_angles_deg: tuple[float, ...]
    finger_mm: float  # the bar's width and thickness
    finger_radius_mm: float  # the bars' centres from the capture axis, spread (holding)
    bar_round_mm: float  # the bars' outer faces rounded to this radius (the lip's bore less the clearance)
    tail_x_mm: float
    shoulder_end_x_mm: float
    shoulder_mm: float  # the shoulders' width beyond the bar, each side
    tip_x_mm: float
    hook_mm: float  # the hook's length along x
    hook_top_mm: float  # the hook's reach from the capture axis
    hook_chamfer_mm: float
    retainer_x_mm: tuple[float, float]  # back face (the housing's front face) and front face
    retainer_yz_mm: tuple[float, float, float, float]  # y0, y1, z0, z1 about the capture axis
    retainer_slot_radii_mm: tuple[float, float]
    retainer_slot_half_mm: float
    chamber_radii_mm: tuple[float, float]
    chamber_half_width_mm: float
    pocket_half_mm: float
    lip_mm: float
    lip_radius_mm: float
    lip_chamfer_mm: float
    undercut_mm: float
    undercut_radius_mm: float
    outer_radius_mm: float
    plate_mm: float
    plate_half_mm: float
    plate_z_mm: tuple[float, float]  # about the capture axis
    docked_gap_mm: float  # B's rear face (the ring plate's back face) from A's front face
    clearance_mm: float
    centre_z_mm: float  # the capture axis above the robots' underside

    @classmethod
    def from_octbot(cls, robot=None) -> OctRingGeometry:
        """From a :class:`cubot_cad.robots.octbot.OctBot` (default: the thesis's); both robots alike."""
        from cubot_cad.robots.octbot import CapturerHousing, Finger, OctBot, OctRing

        r = robot if robot is not None else OctBot()
        s = r.ring_spec
        h = CapturerHousing(spec=s, length_mm=r.housing_mm)
        f = Finger(spec=s, housing_mm=r.housing_mm)
        zc = s.centre_z_mm
        y0, y1, z0, z1 = h.extent_mm
        pz0, pz1 = OctRing(spec=s).plate_z_mm
        return cls(finger_angles_deg=tuple(s.FINGER_ANGLES_DEG), finger_mm=s.finger_mm,
                   finger_radius_mm=s.finger_radius_mm, bar_round_mm=s.lip_radius_mm - s.clearance_mm,
                   tail_x_mm=f.tail_x_mm, shoulder_end_x_mm=f.shoulder_end_x_mm, shoulder_mm=s.shoulder_mm,
                   tip_x_mm=f.tip_x_mm, hook_mm=s.hook_mm, hook_top_mm=f.hook_top_mm,
                   hook_chamfer_mm=s.hook_chamfer_mm, retainer_x_mm=(h.front_mm, r.housing_mm),
                   retainer_yz_mm=(y0, y1, z0 - zc, z1 - zc), retainer_slot_radii_mm=s.retainer_slot_radii_mm,
                   retainer_slot_half_mm=s.finger_mm / 2 + s.clearance_mm,
                   chamber_radii_mm=h.chamber_radii_mm, chamber_half_width_mm=h.chamber_half_width_mm,
                   pocket_half_mm=h.CENTRE_POCKET_HALF_MM, lip_mm=s.lip_mm, lip_radius_mm=s.lip_radius_mm,
                   lip_chamfer_mm=s.lip_chamfer_mm, undercut_mm=s.undercut_mm,
                   undercut_radius_mm=s.undercut_radius_mm, outer_radius_mm=s.outer_radius_mm,
                   plate_mm=s.plate_mm, plate_half_mm=s.plate_half_mm, plate_z_mm=(pz0 - zc, pz1 - zc),
                   docked_gap_mm=r.docked_gap_mm, clearance_mm=s.clearance_mm, centre_z_mm=zc)

    # -- derived positions (mm) ----------------------------------------------------------------
    @property
    def lip_face_x_mm(self) -> float:
        """x of the lip's outer face (on the retainer's front face, docked)."""
        return self.retainer_x_mm[1]

    @property
    def lip_inner_x_mm(self) -> float:
        """x of the lip's inner face, where the hooks bear."""
        return self.lip_face_x_mm + self.lip_mm

    @property
    def hook_face_x_mm(self) -> float:
        """x of the hooks' bearing (back) faces in the model: the play taken up (fingers moved out
        by ``clearance_mm``, so the shoulders touch the retainer)."""
        return self.tip_x_mm - self.hook_mm + self.clearance_mm

    @property
    def hinge_z_mm(self) -> float:
        """The ring's bottom edge about the capture axis (the hinge)."""
        return -self.outer_radius_mm

    def check(self) -> None:
        for n in ("finger_mm", "finger_radius_mm", "bar_round_mm", "shoulder_mm", "hook_mm", "hook_top_mm",
                  "lip_mm", "lip_radius_mm", "undercut_mm", "undercut_radius_mm", "outer_radius_mm", "plate_mm",
                  "plate_half_mm", "docked_gap_mm", "clearance_mm", "pocket_half_mm", "chamber_half_width_mm",
                  "retainer_slot_half_mm"):
            v = getattr(self, n)
            if not (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0):
                raise InputError(f"OctRingGeometry.{n} must be > 0 mm, got {v!r}")
        if len(self.finger_angles_deg) < 2:
            raise InputError(f"OctRingGeometry.finger_angles_deg needs at least two fingers, got "
                             f"{self.finger_angles_deg!r}")
        xf, xr = self.retainer_x_mm
        if not self.tail_x_mm < self.shoulder_end_x_mm < xf < xr < self.lip_inner_x_mm < self.hook_face_x_mm:
            raise InputError("finger tail, shoulders, retainer, lip and hook are not in order along x")
        if not self.lip_radius_mm < self.hook_top_mm < self.undercut_radius_mm < self.outer_radius_mm:
            raise InputError("the hooks do not reach behind the lip inside the undercut")
        if not self.finger_radius_mm + self.finger_mm / 2 <= self.bar_round_mm + 1e-9 < self.lip_radius_mm:
            raise InputError("the finger bars do not pass the lip's bore")
        if not self.finger_mm / 2 < self.retainer_slot_half_mm < self.finger_mm / 2 + self.shoulder_mm:
            raise InputError("the retainer's slots must pass the finger bars but not their shoulders")
        if not self.lip_inner_x_mm + self.undercut_mm + self.plate_mm <= self.docked_gap_mm + 1e-9:
            raise InputError("the ring is longer than the docked gap")

    def play(self) -> list[dict]:
        """The coupling's kinematic play (``cubot_cad.properties.FeaturePlay`` fields, SI) from the CAD."""
        c = self.clearance_mm
        return [{"feature": "tension", "axis": "x", "sense": "tension", "play_m": 2 * c * 1e-3,
                 "cad_feature": (f"two {c:g} mm clearances in series: the hooks' back faces off the ring lip's "
                                 f"inner face, and the fingers' shoulders short of the retainer's back face (each "
                                 f"finger slides along x in its chamber)")}]

    def rotate(self, y: np.ndarray, z: np.ndarray, ang_deg: float) -> tuple[np.ndarray, np.ndarray]:
        """(lateral, radial) of points (y, z) in the frame of the finger at ``ang_deg`` (its radial
        direction (-sin, cos), turning about +x as the CAD does)."""
        a = math.radians(ang_deg)
        c, s = math.cos(a), math.sin(a)
        return c * y + s * z, -s * y + c * z


def input_hash(geom: OctRingGeometry, mat: Material, mesh: RingMesh) -> str:
    return _hash(MODEL_VERSION, geom, mat, mesh)


# --- geometry + mesh ----------------------------------------------------------------------

def _turn(occ, dimtags, ang_deg: float) -> None:
    if ang_deg:
        occ.rotate(dimtags, 0, 0, 0, 1, 0, 0, math.radians(ang_deg))


def _refine_near_fingers(geom: OctRingGeometry, mesh: RingMesh) -> None:
    """gmsh size fields: ``finger_size_mm`` within half a finger thickness of the fingers' surfaces
    (all of each finger, and the retainer's ledges the shoulders bear on), growing to ``size_mm`` a
    finger thickness further out."""
    import gmsh

    xf, xr = geom.retainer_x_mm
    vols = []
    for dim, tag in gmsh.model.getEntities(3):
        x0, _y0, _z0, x1, _y1, _z1 = gmsh.model.getBoundingBox(dim, tag)
        if x1 > xr + 0.1 or x0 < xf - 0.1:  # a finger's piece (the retainer lies within [xf, xr])
            vols.append((dim, tag))
    surfs = [t for _d, t in gmsh.model.getBoundary(vols, combined=False, oriented=False, recursive=False)]
    f = gmsh.model.mesh.field
    d = f.add("Distance")
    f.setNumbers(d, "SurfacesList", sorted(set(surfs)))
    f.setNumber(d, "Sampling", 20)
    t = f.add("Threshold")
    f.setNumber(t, "InField", d)
    f.setNumber(t, "SizeMin", mesh.finger_size_mm)
    f.setNumber(t, "SizeMax", mesh.size_mm)
    f.setNumber(t, "DistMin", geom.finger_mm / 2)
    f.setNumber(t, "DistMax", 1.5 * geom.finger_mm)
    f.setAsBackgroundMesh(t)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)


def _refine_lip(geom: OctRingGeometry, mesh: RingMesh) -> None:
    """A gmsh Box size field: ``ring_size_mm`` in the lip and the tube round it, ``size_mm`` beyond."""
    import gmsh

    R = geom.outer_radius_mm
    x0 = geom.lip_face_x_mm
    f = gmsh.model.mesh.field
    b = f.add("Box")
    f.setNumber(b, "VIn", mesh.ring_size_mm)
    f.setNumber(b, "VOut", mesh.size_mm)
    for k, (lo, hi) in zip("XYZ", ((x0, geom.lip_inner_x_mm + geom.finger_mm), (-R, R), (-R, R)), strict=True):
        f.setNumber(b, f"{k}Min", lo)
        f.setNumber(b, f"{k}Max", hi)
    f.setNumber(b, "Thickness", geom.finger_mm)
    f.setAsBackgroundMesh(b)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)


def _finger(occ, geom: OctRingGeometry, ang_deg: float):
    """One finger (play taken up: ``clearance_mm`` further out along x than drawn), turned to ``ang_deg``."""
    d = geom.clearance_mm
    a, r, sh = geom.finger_mm / 2, geom.finger_radius_mm, geom.shoulder_mm
    x0, xs, xt = geom.tail_x_mm + d, geom.shoulder_end_x_mm + d, geom.tip_x_mm + d
    xh = geom.hook_face_x_mm
    zt, ch = geom.hook_top_mm, geom.hook_chamfer_mm

    def rounded(tag, xa, xb):
        cyl = occ.addCylinder(xa - 1.0, 0, 0, xb - xa + 2.0, 0, 0, geom.bar_round_mm)
        out, _ = occ.intersect([(3, tag)], [(3, cyl)])
        return out

    bar = rounded(occ.addBox(x0, -a, r - a, xt - x0, 2 * a, 2 * a), x0, xt)
    shoulder = rounded(occ.addBox(x0, -a - sh, r - a, xs - x0, 2 * (a + sh), 2 * a), x0, xs)
    hook = [(3, occ.addBox(xh, -a, r - a, xt - xh, 2 * a, zt - (r - a)))]
    body, _ = occ.fuse(bar, shoulder + hook)
    if ch > 0:  # the lead-in: the hook's leading outer edge chamfered 45 deg
        pts = [occ.addPoint(xt + 0.01, -a - 0.1, zt - ch - 0.01), occ.addPoint(xt + 0.01, -a - 0.1, zt + 0.01),
               occ.addPoint(xt - ch - 0.01, -a - 0.1, zt + 0.01)]
        lines = [occ.addLine(pts[i], pts[(i + 1) % 3]) for i in range(3)]
        tri = occ.addPlaneSurface([occ.addCurveLoop(lines)])
        wedge = [e for e in occ.extrude([(2, tri)], 0, 2 * a + 0.2, 0) if e[0] == 3]
        body, _ = occ.cut(body, wedge)
    # imprint the lip's bore (radius lip_radius) on the hook's back face: the bearing patch is beyond it
    ring = occ.addCylinder(xh, 0, 0, 0.5, 0, 0, zt + 1.0)
    core = occ.addCylinder(xh - 0.1, 0, 0, 0.7, 0, 0, geom.lip_radius_mm)
    shell, _ = occ.cut([(3, ring)], [(3, core)])
    piece, _ = occ.intersect(shell, occ.copy(body))
    body, _ = occ.fragment(body, piece)
    _turn(occ, body, ang_deg)
    return body


def _yz_quad(occ, x: float, pts_yz) -> tuple[int, int]:
    """A plane quadrilateral at x with corners (y, z): to imprint outlines on a face."""
    p = [occ.addPoint(x, y, z) for y, z in pts_yz]
    lines = [occ.addLine(p[i], p[(i + 1) % len(p)]) for i in range(len(p))]
    return (2, occ.addPlaneSurface([occ.addCurveLoop(lines)]))


def _turned_rect(geom: OctRingGeometry, half: float, r0: float, r1: float, ang_deg: float):
    """Corners (y, z) of the rectangle |lateral| <= half, radial in [r0, r1] of the finger at ``ang_deg``."""
    a = math.radians(ang_deg)
    c, s = math.cos(a), math.sin(a)
    return [(c * u - s * v, s * u + c * v) for u, v in ((-half, r0), (half, r0), (half, r1), (-half, r1))]


def build_finger_side_mesh(geom: OctRingGeometry, mesh: RingMesh = RingMesh()):
    """Mesh robot A's side: the three fingers bonded at their shoulders to the retainer plate (metres out)."""
    geom.check()
    mesh.check()
    xf, xr = geom.retainer_x_mm
    y0, y1, z0, z1 = geom.retainer_yz_mm
    s0, s1 = geom.retainer_slot_radii_mm
    with GmshSession("octbot_fingers") as gmsh:
        occ = gmsh.model.occ
        plate = [(3, occ.addBox(xf, y0, z0, xr - xf, y1 - y0, z1 - z0))]
        slots = []
        for ang in geom.finger_angles_deg:
            b = [(3, occ.addBox(xf - 0.1, -geom.retainer_slot_half_mm, s0, xr - xf + 0.2,
                                2 * geom.retainer_slot_half_mm, s1 - s0))]
            _turn(occ, b, ang)
            slots += b
        plate, _ = occ.cut(plate, slots)
        fingers = []
        for ang in geom.finger_angles_deg:
            fingers += _finger(occ, geom, ang)
        # the housing's openings behind the retainer (finger chambers, centre pocket) imprinted on its back face
        r0, r1 = geom.chamber_radii_mm
        p = geom.pocket_half_mm
        marks = [_yz_quad(occ, xf, _turned_rect(geom, geom.chamber_half_width_mm, r0, r1, ang))
                 for ang in geom.finger_angles_deg]
        marks.append(_yz_quad(occ, xf, [(-p, -p), (p, -p), (p, p), (-p, p)]))
        occ.fragment(plate + fingers, marks)
        occ.synchronize()
        _refine_near_fingers(geom, mesh)
        return gmsh_tet_mesh(mesh.size_mm, size_min_mm=mesh.finger_size_mm / 2,
                             curvature_elements=mesh.curvature_elements)


def build_ring_side_mesh(geom: OctRingGeometry, mesh: RingMesh = RingMesh()):
    """Mesh robot B's ring (plate, tube, undercut, lip) with the hooks' footprints imprinted on the
    lip's inner face (metres out)."""
    geom.check()
    mesh.check()
    x0, xl = geom.lip_face_x_mm, geom.lip_inner_x_mm
    xp, xb = xl + geom.undercut_mm, geom.docked_gap_mm
    ph, (pz0, pz1) = geom.plate_half_mm, geom.plate_z_mm
    a, zt = geom.finger_mm / 2, geom.hook_top_mm
    with GmshSession("octbot_ring") as gmsh:
        occ = gmsh.model.occ
        tube = [(3, occ.addCylinder(x0, 0, 0, xp - x0 + 0.01, 0, 0, geom.outer_radius_mm))]
        plate = [(3, occ.addBox(xp, -ph, pz0, xb - xp, 2 * ph, pz1 - pz0))]
        body, _ = occ.fuse(tube, plate)
        cut = [(3, occ.addCylinder(xl, 0, 0, geom.undercut_mm, 0, 0, geom.undercut_radius_mm)),
               (3, occ.addCylinder(x0 - 0.1, 0, 0, geom.lip_mm + 0.2, 0, 0, geom.lip_radius_mm))]
        ch = geom.lip_chamfer_mm
        if ch > 0:  # the lead-in: a 45 deg cone on the lip's mouth
            cut.append((3, occ.addCone(x0 - 0.1, 0, 0, ch + 0.1, 0, 0, geom.lip_radius_mm + ch + 0.1,
                                       geom.lip_radius_mm)))
        body, _ = occ.cut(body, cut)
        prisms = []
        for ang in geom.finger_angles_deg:
            b = [(3, occ.addBox(xl - 0.5, -a, geom.finger_radius_mm - a, 0.5, 2 * a, zt - geom.finger_radius_mm + a))]
            _turn(occ, b, ang)
            prisms += b
        pieces, _ = occ.intersect(prisms, occ.copy(body))
        occ.fragment(body, pieces)
        occ.synchronize()
        _refine_lip(geom, mesh)
        return gmsh_tet_mesh(mesh.size_mm, size_min_mm=mesh.ring_size_mm / 2,
                             curvature_elements=mesh.curvature_elements)


# --- selectors ----------------------------------------------------------------------------

def _on_x(x_mm: float):
    t = _TOL_MM * 1e-3
    return lambda x: np.abs(x[0] - x_mm * 1e-3) < t


def _retainer_held(geom: OctRingGeometry):
    """The retainer's back face where the housing's front face is (outside the chambers and the pocket)."""
    on = _on_x(geom.retainer_x_mm[0])
    r0, r1 = geom.chamber_radii_mm
    hw, p = geom.chamber_half_width_mm, geom.pocket_half_mm
    e = _TOL_MM

    def sel(x):
        y, z = x[1] * 1e3, x[2] * 1e3
        opening = (np.abs(y) < p - e) & (np.abs(z) < p - e)
        for ang in geom.finger_angles_deg:
            lat, rad = geom.rotate(y, z, ang)
            opening |= (np.abs(lat) < hw - e) & (rad > r0 + e) & (rad < r1 - e)
        return on(x) & ~opening
    return sel


def _hook_patch(geom: OctRingGeometry, ang_deg: float):
    """Finger ``ang_deg``'s hook back face beyond the lip's bore (where the lip bears on it)."""
    on = _on_x(geom.hook_face_x_mm)
    a = geom.finger_mm / 2

    def sel(x):
        y, z = x[1] * 1e3, x[2] * 1e3
        lat, rad = geom.rotate(y, z, ang_deg)
        return on(x) & (np.abs(lat) < a) & (rad > 0) & (np.hypot(y, z) > geom.lip_radius_mm)
    return sel


def _lip_patch(geom: OctRingGeometry, ang_deg: float):
    """The lip's inner face under finger ``ang_deg``'s hook."""
    on = _on_x(geom.lip_inner_x_mm)
    a = geom.finger_mm / 2

    def sel(x):
        y, z = x[1] * 1e3, x[2] * 1e3
        lat, rad = geom.rotate(y, z, ang_deg)
        return on(x) & (np.abs(lat) < a) & (rad > 0) & (rad < geom.hook_top_mm)
    return sel


def _patch_centroid_radius_m(res, sel_facets, ang_deg: float, geom: OctRingGeometry) -> float:
    """Area-weighted mean radial coordinate (m) of a patch, in its finger's frame."""
    from skfem import FacetBasis, Functional

    a = math.radians(ang_deg)
    fb = FacetBasis(res.mesh, res.basis.elem, facets=sel_facets, intorder=2)
    area = Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(fb)
    return float(Functional(lambda w: -math.sin(a) * w.x[1] + math.cos(a) * w.x[2]).assemble(fb) / area)


def side_flexibility(m, geom: OctRingGeometry, mat: Material, side: str, order: int = 2) -> dict:
    """``C`` (3 x 3, m/N) of one side at the fingers' bearing patches, the patches' radial centroids
    and solve facts. ``side``: ``"fingers"`` (A: +x on the hooks, retainer held) or ``"ring"`` (B:
    -x on the lip, its plate's back face held)."""
    angs = geom.finger_angles_deg
    if side == "fingers":
        patches, held, sign = [_hook_patch(geom, a) for a in angs], _retainer_held(geom), 1.0
    elif side == "ring":
        patches, held, sign = [_lip_patch(geom, a) for a in angs], _on_x(geom.docked_gap_mm), -1.0
    else:
        raise InputError(f"side must be 'fingers' or 'ring', got {side!r}")
    res = solve_linear_elastic(m, mat.E_pa, mat.poisson, held, [Load(p, (sign, 0.0, 0.0)) for p in patches],
                               order=order)
    n = len(angs)
    C = np.array([[sign * res.mean_displacement(patches[i], j)[0] for j in range(n)] for i in range(n)])
    asym = float(np.max(np.abs(C - C.T)) / np.max(np.abs(C)))
    radii = [_patch_centroid_radius_m(res, res.load_facets[i], angs[i], geom) for i in range(n)]
    return {"C": 0.5 * (C + C.T), "asymmetry": asym, "patch_radius_m": radii,
            "patch_facets": [int(f.size) for f in res.load_facets], "n_dofs": res.n_dofs,
            "n_elements": res.n_elements, "seconds": round(res.seconds, 3)}


def _stiffnesses(C: np.ndarray, arms: np.ndarray) -> dict:
    K = np.linalg.inv(C)
    ones = np.ones(len(arms))
    return {"axial_n_per_m": float(ones @ K @ ones), "rotational_nm_per_rad": float(arms @ K @ arms),
            "per_finger_axial_n_per_m": float(1.0 / C[0, 0])}


@dataclass
class OctRingFE(FEResult):
    """FE stiffness of the OctBot's ring-and-capture coupling (SI) and where it comes from."""

    kind: str
    axial_stiffness_n_per_m: float  # the three fingers stretched alike, both sides
    rotational_stiffness_nm_per_rad: float  # pitch about the ring's bottom edge (hinge_z_m)
    shear_stiffness_n_per_m: float  # NaN: not modelled (module docstring)
    per_finger_axial_n_per_m: float  # the top finger alone (the others unloaded), both sides
    finger_side: dict  # the same for side A (fingers + retainer) alone
    ring_side: dict  # and for side B (the ring) alone
    hinge_z_m: float  # the hinge above the robots' underside
    lever_arms_m: list[float]  # the bearing patches' heights above the hinge
    backlash_rad: float  # the tension play over the top finger's arm
    play: list
    provenance: str
    input_hash: str
    inputs: dict
    timings_s: dict = field(default_factory=dict)
    cache_hit: bool = False


def compute_octbot_ring(geom: OctRingGeometry, mat: Material, mesh: RingMesh = RingMesh()) -> OctRingFE:
    """Cold FE of the OctBot's ring coupling (no cache): see the module docstring."""
    t0 = time.perf_counter()
    ma = build_finger_side_mesh(geom, mesh)
    mb = build_ring_side_mesh(geom, mesh)
    t_mesh = time.perf_counter() - t0
    fa = side_flexibility(ma, geom, mat, "fingers", mesh.order)
    fb = side_flexibility(mb, geom, mat, "ring", mesh.order)
    for name, f in (("fingers", fa), ("ring", fb)):
        if not (np.all(np.linalg.eigvalsh(f["C"]) > 0) and f["asymmetry"] < 0.05):
            raise InputError(f"octbot ring FE: the {name} side's flexibility is not symmetric positive "
                             f"(asymmetry {f['asymmetry']:.3g}): a mesh or selection problem")
    # the bearing patches' heights above the hinge (ring side: B turns; the hook side's for the record)
    arms = np.array([rad * math.cos(math.radians(ang)) - geom.hinge_z_mm * 1e-3
                     for rad, ang in zip(fb["patch_radius_m"], geom.finger_angles_deg, strict=True)])
    joint = _stiffnesses(fa["C"] + fb["C"], arms)
    side_a, side_b = _stiffnesses(fa["C"], arms), _stiffnesses(fb["C"], arms)
    for d, f in ((side_a, fa), (side_b, fb)):
        d.update(flexibility_m_per_n=f["C"].tolist(), patch_radius_m=f["patch_radius_m"], n_dofs=f["n_dofs"],
                 n_elements=f["n_elements"], asymmetry=f["asymmetry"])
    play = geom.play()
    backlash = sum(p["play_m"] for p in play) / float(np.max(arms))
    dofs = fa["n_dofs"] + fb["n_dofs"]
    prov = (f"fe: scikit-fem P{mesh.order} tetra, gmsh h={mesh.finger_size_mm:g} mm in the fingers / "
            f"{mesh.ring_size_mm:g} mm in the lip / {mesh.size_mm:g} mm elsewhere, {_kilo(dofs)} dofs (fingers + retainer {_kilo(fa['n_dofs'])}, ring "
            f"{_kilo(fb['n_dofs'])}), E={mat.E_pa:.3g} Pa, nu={mat.poisson:g}; three fingers bonded at their "
            f"shoulders to the retainer (play taken up), retainer held where the housing backs it (housing rigid), "
            f"ring held at its plate's back face (rear wall rigid), per-finger hook-on-lip patches in series, "
            f"pitch about the ring's bottom edge")
    return OctRingFE(
        kind="ring_capture", axial_stiffness_n_per_m=joint["axial_n_per_m"],
        rotational_stiffness_nm_per_rad=joint["rotational_nm_per_rad"], shear_stiffness_n_per_m=math.nan,
        per_finger_axial_n_per_m=joint["per_finger_axial_n_per_m"], finger_side=side_a, ring_side=side_b,
        hinge_z_m=(geom.centre_z_mm + geom.hinge_z_mm) * 1e-3, lever_arms_m=[float(v) for v in arms],
        backlash_rad=backlash, play=play, provenance=prov, input_hash=input_hash(geom, mat, mesh),
        inputs={"geometry": asdict(geom), "material": asdict(mat), "mesh": asdict(mesh), "model": MODEL_VERSION,
                "n_dofs": dofs, "n_elements": fa["n_elements"] + fb["n_elements"],
                "hook_patch_radius_m": fa["patch_radius_m"]},
        timings_s={"mesh": round(t_mesh, 3), "fingers_solve": fa["seconds"], "ring_solve": fb["seconds"],
                   "total": round(time.perf_counter() - t0, 3)})


def octbot_ring_fe(robot=None, material: str | Material = "abs", mesh: RingMesh = RingMesh(),
                   cache_dir=None, use_cache: bool = True) -> OctRingFE:
    """FE of an OctBot's ring coupling (default: the thesis's), cached as ``<cache_dir>/<hash>.json``."""
    geom = OctRingGeometry.from_octbot(robot)
    mat = _material(material)
    return _cached(input_hash(geom, mat, mesh), OctRingFE, lambda: compute_octbot_ring(geom, mat, mesh),
                   cache_dir, use_cache)


# --- validation helper ---------------------------------------------------------------------

def finger_bar_fe(geom: OctRingGeometry, length_mm: float, E_pa: float, nu: float, mesh: RingMesh,
                  load: str = "axial") -> tuple[float, float, float]:
    """One finger's bar (its CAD section: ``finger_mm`` square, outer face rounded to ``bar_round_mm``)
    ``length_mm`` long, clamped at x = 0, a uniform traction of 1 N over its end face, along x
    (``load="axial"``) or radially (``"bending"``, towards the capture axis). Returns ``(stiffness N/m
    from the end face's mean displacement, section area m^2, second moment about the lateral axis
    m^4)``, the section properties by the same mesh's end face (to compare with ``E A / L`` and
    Timoshenko's cantilever)."""
    from skfem import FacetBasis, Functional

    if load not in ("axial", "bending"):
        raise InputError(f"load must be 'axial' or 'bending', got {load!r}")
    if not (math.isfinite(length_mm) and length_mm > 0):
        raise InputError(f"finger bar length must be > 0 mm, got {length_mm!r}")
    a, r = geom.finger_mm / 2, geom.finger_radius_mm
    with GmshSession("finger_bar") as gmsh:
        occ = gmsh.model.occ
        box = occ.addBox(0, -a, r - a, length_mm, 2 * a, 2 * a)
        cyl = occ.addCylinder(-1, 0, 0, length_mm + 2, 0, 0, geom.bar_round_mm)
        occ.intersect([(3, box)], [(3, cyl)])
        occ.synchronize()
        m = gmsh_tet_mesh(mesh.finger_size_mm, size_min_mm=mesh.finger_size_mm / 2,
                          curvature_elements=mesh.curvature_elements)
    end, root = _on_x(length_mm), _on_x(0.0)
    f = (1.0, 0.0, 0.0) if load == "axial" else (0.0, 0.0, -1.0)
    res = solve_linear_elastic(m, E_pa, nu, root, [Load(end, f)], order=mesh.order)
    u = res.mean_displacement(end, 0)
    k = 1.0 / (u[0] if load == "axial" else -u[2])
    fb = FacetBasis(m, res.basis.elem, facets=res.load_facets[0], intorder=4)
    area = float(Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(fb))
    zc = float(Functional(lambda w: w.x[2]).assemble(fb)) / area
    inertia = float(Functional(lambda w: (w.x[2] - zc) ** 2).assemble(fb))
    return float(k), area, inertia
