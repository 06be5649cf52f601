"""FE stiffness of the test platform's bolted lap joint from the CAD's dimensions (issue 12, deliverable 1).

The companion of :mod:`structure_fem.couplings.connector_fe` and :mod:`structure_fem.couplings.rail_key_fe` for the
thesis's test platform (:class:`cubot_cad.robots.platform.TestPlatform`: 100 x 100 x 5 mm ABS plates, the
front tab of one (lower half of the plate, ``tab_length_mm`` x ``tab_width_mm``) under the rear
recess of the next, one M3 bolt with a nut through both on the centre line). Built the same way:
a geometry dataclass read from the parametric CAD, gmsh OCC geometry, P2 tetrahedra solved by
:func:`structure_fem.couplings.fe_solid.solve_linear_elastic`, a result record with a ``provenance`` string,
cached (and packaged) by the sha256 of geometry + material + mesh (:func:`platform_bolt_fe`).

**Model (frame in mm: x along the line from platform A's centre, z up from the plates' undersides,
y across; the joint's abutting faces at x = L/2, platform B's centre at x = L).**

* Two plates as the CAD builds them: A from its centre (x = 0) to its front face with the tab
  (half the plate thick) beyond it; B from its rear face to its centre (x = L) with the rear
  recess the tab slides into (the CAD's ``clearance_mm`` over the tab, at its end and at its
  sides: the tab and the recess do not touch). Full width (100 mm): the plates are the beam.
* **Clamped / loaded far from the joint**: A's centre section (x = 0) clamped, the loads on B's
  centre section (x = L), 50 mm (ten plate thicknesses) from the joint on each side, so the
  joint's local stress field has decayed (Saint-Venant) and each plate half is a beam.
* **The bolt** (steel, :data:`BOLT_E_PA`): shank of the bolt's nominal diameter from the nut's
  underside to the head's top, socket head ISO 4762 (``dk`` x ``k``) on B's top face, hex nut
  ISO 4032 on the tab's underside as a cylinder of the width across flats (a little less bearing
  area than the hexagon). **The shank is tied (bonded) to both hole walls** as if the hole
  clearance were taken up all round, and **the head's and the nut's bearing rings are tied** to
  the plates' faces (a tightened bolt; its preload and the friction it makes are not modelled:
  linear elasticity, no contact). The clearance is not lost: it is the joint's **kinematic play**
  (below), taken from the CAD's ISO 273 hole, not a hand number.
* **Faces that only touch are left free**: the abutting end faces (zero gap in the CAD; the model
  moves B's by :data:`FACE_GAP_MM` so the mesher does not join them) and the tab against the
  recess (the CAD's clearance). In the thesis's bench test (tip down, hogging) the upper parts of
  the abutting faces open and their lower parts bear: a compression-only contact this linear
  model does not have, so **the FE joint is a lower bound** on the hogging stiffness (the whole
  moment goes through the tab, the bolt and the roof over the recess). The **contact-closed
  variant** (``contact_*`` fields) bonds the abutting faces over a strip :data:`CONTACT_STRIP_MM`
  deep at the underside (outside the tab's recess), free above: B then turns about that edge and
  the tab must carry the bolt's vertical push 6 mm from it. The strip's depth is an assumption
  (0.5 / 1.25 / 2.5 mm give whole-pitch 12.3 / 16.8 / 21.0 N m/rad on a coarse mesh: the deeper
  strips would also carry tension) and the bonded strip has no slip (infinite friction), so this
  variant is an estimate, not a bound: the pair brackets the hogging joint, and
  :func:`structure_fem.couplings.connector_sources.resolve` uses the faces-free values (the multibody model
  has its own face contact at the joint; the other FE records are of the bonded load path too).
* Material: the plates' ABS from ``cubot_cad.part.MATERIALS`` (:class:`~structure_fem.couplings.connector_fe.Material`,
  Poisson 0.35 assumed), no printed-part knockdown unless the material says so.

**Post-processing.** Three load cases on B's centre section: +x on its upper half, +x on its
lower half (their difference is a couple, their sum an axial pull) and a vertical force. The
generalised displacements there are the mean ``u_x`` and ``u_z`` and the section's rotation
(upper minus lower mean ``u_x`` over the halves' centroid distance, work-conjugate with the
couple), giving the flexibility ``C`` (vertical force, moment) of the whole pitch. The same cases
on a **continuous plate** of the same length, width and thickness (same mesh settings) give
``C_ref``; the joint is the difference ``dC = C - C_ref`` (what the joint adds to plates the
multibody model already has), read as a rotational spring ``k_r`` and a vertical (shear) spring
``k_s`` at one point ``x_j`` (a rigid lever ``a = L - x_j`` to the load):
``k_r = 1 / dC_MM``, ``a = -dC_VM / dC_MM``, ``1 / k_s = dC_VV - dC_VM^2 / dC_MM``; axial
``1 / k_ax = dC_ax``. ``pitch_stiffness_nm_per_rad = 1 / C_MM`` is the whole pitch (joint + the
two half plates, centre to centre): the spring a chain of *rigid* platforms needs, the number to
hold against :mod:`structure_fem.analysis.calibration`'s fit (its platforms are rigid bodies).

**Play (kinematic, from the CAD).** Each plate's hole is the ISO 273 medium clearance hole
(``cubot_cad.hardware.fasteners.clearance_hole_mm``: 3.4 mm for M3) on the bolt's nominal diameter: each
plate slides ``(hole - bolt) / 2`` either way on the bolt, the two in series ``hole - bolt``
(0.4 mm) either way along the line (``bolt_slip``, x, both). The tightened head and nut hold the
plates to the bolt vertically and against turning, so no rotational dead band (``backlash_rad``
0) and no vertical slip (the record's hand estimate had ``clearance / tab length``).

Measured for the thesis platform (ABS, E = 2.2 GPa, nu 0.35 assumed; 2-core shared machine, 2026-12;
packaged in ``structure_fem/data/connector_fe.json``):

| quantity | FE (default mesh) | hand formula (record) |
|---|---|---|
| joint pitch stiffness (N m/rad) | 5.40 | 4.77 (tab E I / L) |
| whole pitch, centre to centre: joint + two half plates (N m/rad) | 4.41 | |
| continuous plate over the same 100 mm (N m/rad) | 24.1 (beam E I / L 22.9) | |
| joint axial (N/m) | 1.41e6 | 1.65e4 (hole bearing E d t) |
| joint vertical shear (N/m) | 5.8e4 | (= axial) |
| rotation acts at (from A's centre) | 54.0 mm (faces 50, bolt 56) | |
| contact-closed variant: joint / whole pitch (N m/rad) | 21.8 / 11.45 | |
| play | bolt_slip 0.4 mm along x, 0 rad | 0.2 / 12 = 16.7 mrad |

Mesh refinement (joint / plate size, mm): 2.5 / 6, 1.5 / 5 (default, 87k dofs), 1.25 / 5 (124k
dofs) give joint pitch 5.589 / 5.404 / 5.344 N m/rad, whole pitch 4.537 / 4.413 / 4.373, axial
1.434 / 1.414 / 1.404e6, shear 5.89 / 5.81 / 5.80e4: the last step changes each by 1.1 % or less.
The reference plate at h 6 / 5 / 4 mm: 24.09 / 24.08 / 24.06 N m/rad. The contact-closed variant
(the bonded strip's edge is a stress singularity) is meshed at :data:`CONTACT_JOINT_SIZE_MM`: whole
pitch 12.34 at h 3 / 10 mm, 11.45 at 2.5 / 5 (used), 11.25 at 1.5 / 5 (1.8 % from the one used; it
cost 70 s more). Cold time 26 s for the faces-free model alone (lap solve 23 s, mesh 1 s,
reference plate 2 s), 48 s with the contact variant on the shared machine at a load average of
4.8 (lap 32 s, variant 12 s); h 1.25 mm took 180 s for the faces-free solve alone, so the default
stays at 1.5 mm.
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

MODEL_VERSION = "platform_bolt_fe/3"
#: Steel bolt and nut: E = 210 000 N/mm^2 and nu = 0.3, EN 1993-1-1:2005 section 3.2.6 (structural
#: steel; a class 8.8 bolt's modulus is the same).
BOLT_E_PA = 210e9
BOLT_POISSON = 0.3
#: The abutting end faces (zero gap in the CAD) are moved apart by this much (mm) so the mesher keeps
#: them free (they carry no tension; see the module docstring).
FACE_GAP_MM = 0.01
#: Depth (mm) of the strip at the bottom of the abutting faces bonded in the contact-closed variant
#: (the lower edge bearing in hogging; a tenth of the plate: assumption, see the module docstring).
CONTACT_STRIP_MM = 0.5
#: Least joint element size (mm) of the contact-closed variant: an estimate (its strip's edge is
#: singular), kept cheap so the packaged cold FE stays under its time goal (module docstring).
CONTACT_JOINT_SIZE_MM = 2.5
#: Default mesh: element size (mm) in the joint region (tab, recess, bolt) and in the plates
#: (P2 tetrahedra; one plate thickness, where P2 is within 2 % of a clamped plate, test_fe_solid).
JOINT_SIZE_MM = 1.5
PLATE_SIZE_MM = 5.0
_TOL_MM = 1e-3


@dataclass(frozen=True)
class PlatformMesh:
    joint_size_mm: float = JOINT_SIZE_MM
    plate_size_mm: float = PLATE_SIZE_MM
    order: int = 2
    curvature_elements: int = 12


@dataclass(frozen=True)
class PlatformBoltGeometry:
    """Dimensions (mm) of two lapped test platforms and their bolt, read from the CAD."""

    length_mm: float
    width_mm: float
    thickness_mm: float
    tab_length_mm: float
    tab_width_mm: float
    tab_mm: float  # the tab's thickness (half the plate)
    clearance_mm: float  # the recess's clearance around the tab
    bolt_mm: float
    hole_mm: float  # ISO 273 medium clearance hole
    head_diameter_mm: float
    head_height_mm: float
    nut_flats_mm: float
    nut_height_mm: float

    @classmethod
    def from_platform(cls, platform=None) -> PlatformBoltGeometry:
        """From a :class:`cubot_cad.robots.platform.TestPlatform` (default: the thesis's)."""
        from cubot_cad.hardware.fasteners import thread
        from cubot_cad.robots.platform import TestPlatform

        p = (platform if platform is not None else TestPlatform()).plate
        t = thread(p.bolt_size)
        return cls(length_mm=p.length_mm, width_mm=p.width_mm, thickness_mm=p.thickness_mm,
                   tab_length_mm=p.tab_length_mm, tab_width_mm=p.tab_width_mm, tab_mm=p.half_mm,
                   clearance_mm=p.clearance_mm, bolt_mm=p.bolt_mm, hole_mm=p.bolt_hole_mm,
                   head_diameter_mm=t.shcs_head_diameter_mm, head_height_mm=t.shcs_head_height_mm,
                   nut_flats_mm=t.nut_flats_mm, nut_height_mm=t.nut_height_mm)

    @property
    def bolt_x_mm(self) -> float:
        return self.length_mm / 2 + self.tab_length_mm / 2

    def check(self) -> None:
        for n in ("length_mm", "width_mm", "thickness_mm", "tab_length_mm", "tab_width_mm", "tab_mm", "bolt_mm",
                  "hole_mm", "head_diameter_mm", "head_height_mm", "nut_flats_mm", "nut_height_mm"):
            v = getattr(self, n)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"PlatformBoltGeometry.{n} must be > 0 mm, got {v!r}")
        if not (0 <= self.clearance_mm and self.tab_mm + self.clearance_mm < self.thickness_mm):
            raise InputError("the platform's recess (tab + clearance) is as thick as the plate")
        if not self.bolt_mm <= self.hole_mm < min(self.tab_length_mm, self.tab_width_mm):
            raise InputError("the bolt hole must take the bolt and fit in the tab")
        if not self.tab_width_mm + 2 * self.clearance_mm < self.width_mm:
            raise InputError("the tab is wider than the plate")

    def play(self) -> list[dict]:
        """The joint's kinematic play (``cubot_cad.properties.FeaturePlay`` fields, SI) from the CAD's hole."""
        return [{"feature": "bolt_slip", "axis": "x", "sense": "both",
                 "play_m": (self.hole_mm - self.bolt_mm) * 1e-3,
                 "cad_feature": (f"two ISO 273 medium {self.hole_mm:g} mm clearance holes on the M{self.bolt_mm:g} "
                                 f"bolt, in series: (hole - bolt) / 2 per plate either way")}]


def input_hash(geom: PlatformBoltGeometry, mat: Material, mesh: PlatformMesh) -> str:
    return _hash(MODEL_VERSION, geom, mat, mesh)


# --- geometry + mesh ----------------------------------------------------------------------

def _refine_near_joint(geom: PlatformBoltGeometry, mesh: PlatformMesh) -> None:
    """A gmsh Box size field: ``joint_size_mm`` around the tab, recess and bolt, ``plate_size_mm`` beyond."""
    import gmsh

    L, T = geom.length_mm, geom.thickness_mm
    f = gmsh.model.mesh.field
    b = f.add("Box")
    f.setNumber(b, "VIn", mesh.joint_size_mm)
    f.setNumber(b, "VOut", mesh.plate_size_mm)
    f.setNumber(b, "XMin", L / 2 - 2 * T)
    f.setNumber(b, "XMax", L / 2 + geom.tab_length_mm + 2 * T)
    f.setNumber(b, "YMin", -geom.tab_width_mm / 2 - 2 * T)
    f.setNumber(b, "YMax", geom.tab_width_mm / 2 + 2 * T)
    f.setNumber(b, "ZMin", -geom.nut_height_mm - 1)
    f.setNumber(b, "ZMax", T + geom.head_height_mm + 1)
    f.setNumber(b, "Thickness", 2 * T)
    f.setAsBackgroundMesh(b)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)


def build_lap_mesh(geom: PlatformBoltGeometry, mesh: PlatformMesh = PlatformMesh(), contact_mm: float = 0.0):
    """Mesh the two lapped half platforms and the bolt (metres out) and say which tetrahedra are
    the bolt's: ``(MeshTet, is_bolt mask)``. The holes are at the bolt's diameter (play taken up).
    ``contact_mm`` > 0: the abutting end faces bonded from the underside up to that height (outside
    the tab's recess), free above it; 0: free everywhere."""
    geom.check()
    L, W, T, c = geom.length_mm, geom.width_mm, geom.thickness_mm, geom.clearance_mm
    tl, tw, h = geom.tab_length_mm, geom.tab_width_mm, geom.tab_mm
    xb, rb = geom.bolt_x_mm, geom.bolt_mm / 2
    zlo, zhi = -geom.nut_height_mm, T + geom.head_height_mm
    with GmshSession("platform_bolt") as gmsh:
        occ = gmsh.model.occ
        a, _ = occ.fuse([(3, occ.addBox(0, -W / 2, 0, L / 2, W, T))],
                        [(3, occ.addBox(L / 2 - 0.01, -tw / 2, 0, tl + 0.01, tw, h))])
        x0 = L / 2
        cut = [(3, occ.addBox(x0 - 1, -tw / 2 - c, -1, tl + c + 1, tw + 2 * c, h + c + 1)),
               (3, occ.addBox(x0 - 1, -W / 2 - 1, contact_mm, 1 + FACE_GAP_MM, W + 2, T + 1))]  # free above
        b, _ = occ.cut([(3, occ.addBox(x0, -W / 2, 0, L - x0, W, T))], cut)
        shank = (3, occ.addCylinder(xb, 0, zlo, 0, 0, zhi - zlo, rb))
        a, _ = occ.cut(a, [(3, occ.addCylinder(xb, 0, -1, 0, 0, T + 2, rb))])
        b, _ = occ.cut(b, [(3, occ.addCylinder(xb, 0, -1, 0, 0, T + 2, rb))])
        head = (3, occ.addCylinder(xb, 0, T, 0, 0, geom.head_height_mm, geom.head_diameter_mm / 2))
        nut = (3, occ.addCylinder(xb, 0, zlo, 0, 0, geom.nut_height_mm, geom.nut_flats_mm / 2))
        bolt, _ = occ.fuse([shank], [head, nut])
        occ.fragment(a + b, bolt)
        occ.synchronize()
        _refine_near_joint(geom, mesh)
        m = gmsh_tet_mesh(mesh.plate_size_mm, size_min_mm=mesh.joint_size_mm / 2,
                          curvature_elements=mesh.curvature_elements)
    return m, _bolt_elements(m, geom)


def _bolt_elements(m, geom: PlatformBoltGeometry) -> np.ndarray:
    """Tetrahedra inside the bolt (shank, head, nut), by their centroids (the mesh is conformal to them)."""
    cen = m.p[:, m.t].mean(axis=1) * 1e3
    rho = np.hypot(cen[0] - geom.bolt_x_mm, cen[1])
    z, T = cen[2], geom.thickness_mm
    shank = rho < geom.bolt_mm / 2
    head = (z > T) & (rho < geom.head_diameter_mm / 2)
    nut = (z < 0) & (rho < geom.nut_flats_mm / 2)
    return shank | head | nut


def build_plate_mesh(geom: PlatformBoltGeometry, mesh: PlatformMesh = PlatformMesh()):
    """The continuous reference plate (x in [0, L], full width and thickness) at the plates' mesh
    size (no joint to refine for: P2 at one plate thickness is within 1 % of a finer plate here)."""
    geom.check()
    with GmshSession("platform_plate") as gmsh:
        gmsh.model.occ.addBox(0, -geom.width_mm / 2, 0, geom.length_mm, geom.width_mm, geom.thickness_mm)
        gmsh.model.occ.synchronize()
        return gmsh_tet_mesh(mesh.plate_size_mm, size_min_mm=mesh.plate_size_mm / 4, curvature_elements=0)


# --- solve + post-processing --------------------------------------------------------------

def _section(geom: PlatformBoltGeometry, x_mm: float, part: str):
    t = _TOL_MM * 1e-3
    zm = geom.thickness_mm / 2 * 1e-3

    def sel(x):
        on = np.abs(x[0] - x_mm * 1e-3) < t
        if part == "upper":
            return on & (x[2] > zm)
        if part == "lower":
            return on & (x[2] < zm)
        return on
    return sel


def _mean_z(res, select) -> float:
    """Area-weighted mean height (m) of the facets ``select`` (the load's centroid)."""
    from skfem import FacetBasis, Functional

    from structure_fem.couplings.fe_solid import facets

    fb = FacetBasis(res.mesh, res.basis.elem, facets=facets(res.mesh, select), intorder=2)
    area = Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(fb)
    return float(Functional(lambda w: w.x[2]).assemble(fb) / area)


def pitch_flexibility(m, geom: PlatformBoltGeometry, E, nu, order: int = 2) -> dict:
    """Clamp x = 0, load x = L (see the module docstring): the flexibility of the far section
    (vertical force V, couple M about y, axial pull) and solve facts."""
    L = geom.length_mm
    up, lo, whole = (_section(geom, L, p) for p in ("upper", "lower", "whole"))
    clamp = _section(geom, 0.0, "whole")
    res = solve_linear_elastic(m, E, nu, clamp, [Load(up, (1.0, 0.0, 0.0)), Load(lo, (1.0, 0.0, 0.0)),
                                                 Load(whole, (0.0, 0.0, 1.0))], order=order)
    zu, zl = _mean_z(res, up), _mean_z(res, lo)
    d = zu - zl

    def gen(case):  # (mean u_x upper, mean u_x lower, mean u_z whole)
        return (res.mean_displacement(up, case)[0], res.mean_displacement(lo, case)[0],
                res.mean_displacement(whole, case)[2])

    g0, g1, g2 = gen(0), gen(1), gen(2)
    # couple: +1 N upper, -1 N lower: M = d (N m), rotation about y = (u_up - u_lo) / d
    m_mom = d
    th_m = ((g0[0] - g1[0]) - (g0[1] - g1[1])) / d
    w_m = g0[2] - g1[2]
    th_v = (g2[0] - g2[1]) / d
    ax = 0.5 * (0.5 * (g0[0] + g1[0]) + 0.5 * (g0[1] + g1[1]))  # 2 N axial: mean u_x per N
    return {"C_MM": th_m / m_mom, "C_VM": w_m / m_mom, "C_MV": th_v, "C_VV": g2[2], "C_ax": ax,
            "lever_m": d, "n_dofs": res.n_dofs, "n_elements": res.n_elements, "seconds": round(res.seconds, 3)}


@dataclass
class PlatformBoltFE(FEResult):
    """FE stiffness of the test platform's bolted lap joint (SI) and where it comes from."""

    kind: str
    rotational_stiffness_nm_per_rad: float  # the joint alone, pitch (what it adds to continuous plates)
    axial_stiffness_n_per_m: float  # the joint alone, along the line
    shear_stiffness_n_per_m: float  # the joint alone, vertical (after the play)
    pitch_stiffness_nm_per_rad: float  # the whole pitch, centre to centre: joint + the two half plates
    #: The same with the abutting faces' lower edge bearing (bonded strip, CONTACT_STRIP_MM): hogging bracket
    contact_rotational_stiffness_nm_per_rad: float
    contact_pitch_stiffness_nm_per_rad: float
    plate_pitch_stiffness_nm_per_rad: float  # the continuous plate over the same pitch
    hinge_x_m: float  # where the joint's rotation acts, from platform A's centre
    backlash_rad: float
    play: list
    provenance: str
    input_hash: str
    inputs: dict
    timings_s: dict = field(default_factory=dict)
    cache_hit: bool = False


def compute_platform_bolt(geom: PlatformBoltGeometry, mat: Material, mesh: PlatformMesh = PlatformMesh(),
                          with_contact: bool = True) -> PlatformBoltFE:
    """Cold FE of the platform's bolted lap joint (no cache): see the module docstring.
    ``with_contact``: also the contact-closed variant (else its fields are NaN)."""
    t0 = time.perf_counter()
    lap, is_bolt = build_lap_mesh(geom, mesh)
    E = np.where(is_bolt, BOLT_E_PA, mat.E_pa)
    nu = np.where(is_bolt, BOLT_POISSON, mat.poisson)
    t_mesh = time.perf_counter() - t0
    c = pitch_flexibility(lap, geom, E, nu, mesh.order)
    tc = time.perf_counter()
    cc = {k: math.nan for k in ("C_MM", "C_VM", "C_MV", "C_VV", "C_ax", "n_dofs")}
    if with_contact:
        cmesh = PlatformMesh(max(mesh.joint_size_mm, CONTACT_JOINT_SIZE_MM), mesh.plate_size_mm, mesh.order,
                             mesh.curvature_elements)
        lap_c, bolt_c = build_lap_mesh(geom, cmesh, CONTACT_STRIP_MM)
        cc = pitch_flexibility(lap_c, geom, np.where(bolt_c, BOLT_E_PA, mat.E_pa),
                               np.where(bolt_c, BOLT_POISSON, mat.poisson), mesh.order)
    t_contact = time.perf_counter() - tc
    t1 = time.perf_counter()
    ref = pitch_flexibility(build_plate_mesh(geom, mesh), geom, mat.E_pa, mat.poisson, mesh.order)
    t_ref = time.perf_counter() - t1
    d_mm = c["C_MM"] - ref["C_MM"]
    d_vm = 0.5 * (c["C_VM"] + c["C_MV"] - ref["C_VM"] - ref["C_MV"])
    d_vv = c["C_VV"] - ref["C_VV"]
    d_ax = c["C_ax"] - ref["C_ax"]
    d_mm_c = cc["C_MM"] - ref["C_MM"]
    if not (d_mm > 0 and d_ax > 0 and (d_mm_c > 0 or not with_contact)):
        raise InputError(f"platform bolt FE: the joint came out stiffer than the continuous plate "
                         f"(dC_MM {d_mm:.3g}, dC_ax {d_ax:.3g}): a mesh or selection problem")
    k_r = 1.0 / d_mm
    a = -d_vm / d_mm  # the joint's lever to the load (m)
    s = d_vv - d_vm ** 2 / d_mm
    k_s = 1.0 / s if s > 0 else math.inf
    L = geom.length_mm * 1e-3
    prov = (f"fe: scikit-fem P{mesh.order} tetra, gmsh h={mesh.joint_size_mm:g} mm at the joint / "
            f"{mesh.plate_size_mm:g} mm in the plates, {_kilo(c['n_dofs'])} dofs, E={mat.E_pa:.3g} Pa, "
            f"nu={mat.poisson:g}, steel bolt E={BOLT_E_PA:.3g} Pa; two lapped half platforms (A's centre clamped, "
            f"B's centre loaded) + M{geom.bolt_mm:g} bolt tied in both holes and under its head and nut (play "
            f"taken up), touching faces free (lower bound in hogging), less a continuous plate")
    return PlatformBoltFE(
        kind="bolt", rotational_stiffness_nm_per_rad=k_r, axial_stiffness_n_per_m=1.0 / d_ax,
        shear_stiffness_n_per_m=k_s, pitch_stiffness_nm_per_rad=1.0 / c["C_MM"],
        contact_rotational_stiffness_nm_per_rad=1.0 / d_mm_c, contact_pitch_stiffness_nm_per_rad=1.0 / cc["C_MM"],
        plate_pitch_stiffness_nm_per_rad=1.0 / ref["C_MM"], hinge_x_m=L - a, backlash_rad=0.0,
        play=geom.play(), provenance=prov, input_hash=input_hash(geom, mat, mesh),
        inputs={"geometry": asdict(geom), "material": asdict(mat), "mesh": asdict(mesh), "model": MODEL_VERSION,
                "bolt_material": {"youngs_modulus_pa": BOLT_E_PA, "poisson": BOLT_POISSON,
                                  "source": "EN 1993-1-1:2005 3.2.6"},
                "n_dofs": c["n_dofs"], "n_elements": c["n_elements"], "n_dofs_reference": ref["n_dofs"],
                "contact_strip_mm": CONTACT_STRIP_MM, "n_dofs_contact": cc["n_dofs"],
                "flexibility_contact": {k: cc[k] for k in ("C_MM", "C_VM", "C_MV", "C_VV", "C_ax")},
                "flexibility_lap": {k: c[k] for k in ("C_MM", "C_VM", "C_MV", "C_VV", "C_ax")},
                "flexibility_plate": {k: ref[k] for k in ("C_MM", "C_VM", "C_MV", "C_VV", "C_ax")}},
        timings_s={"mesh": round(t_mesh, 3), "lap_solve": c["seconds"], "contact_variant": round(t_contact, 3),
                   "reference": round(t_ref, 3),
                   "total": round(time.perf_counter() - t0, 3)})


def platform_bolt_fe(platform=None, material: str | Material = "abs", mesh: PlatformMesh = PlatformMesh(),
                     cache_dir=None, use_cache: bool = True) -> PlatformBoltFE:
    """FE of a test platform's bolt joint (default: the thesis's), cached as ``<cache_dir>/<hash>.json``."""
    geom = PlatformBoltGeometry.from_platform(platform)
    mat = _material(material)
    return _cached(input_hash(geom, mat, mesh), PlatformBoltFE, lambda: compute_platform_bolt(geom, mat, mesh),
                   cache_dir, use_cache)
