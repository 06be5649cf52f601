"""Connector compliance from the CAD dimensions by 3D finite elements (issue 12, deliverable 1).

The hand formulas in ``cubot_cad.couplings.compliance`` treat the CuBot front-rear coupling as pins
(``E A / L``) on rigid robots. The pin and latch blocks are, however, screwed to the robots'
2.4 mm front and rear walls, and those walls bend in series with the pins. This module builds
that load path from the parametric CuBot dimensions with gmsh's OCC kernel and solves it with
:func:`structure_fem.couplings.fe_solid.solve_linear_elastic`.

**Model of one robot's side of the coupling (robot frame, mm; x out of the front face).**

* Front wall panel: ``wall_mm`` thick (x in [-wall, 0]), spanning the body between the side
  walls' mid-planes in y and from the floor's mid-plane to the body's top edge in z; its three
  joined edges (both sides, floor) clamped, its top edge free (the cover only rests on it).
  Clamping the edges is stiffer than the real corner (the side walls are 2.4 mm plates too).
* Two pin blocks (the four plates a-d of the pin set, ``block_mm`` square, 12 mm deep) as one
  ABS solid bonded to the wall's inner face. In the real stack the plates are only screwed
  together and pressed onto the wall: one bonded solid is stiffer than the stack (assumption).
  Screw holes and IR windows are left out; the pin holes are in (pin + clearance).
* Three grooved pins per block, each a solid anchored at its head's front face in the block
  (bonded) and free in its clearance bores through the plates and the wall, out to the tip.

Load cases: one axial pull per pin on its groove's outer shoulder (where the latch blade
bears), giving the 6 x 6 flexibility matrix ``C_A`` at the load points and ``C_wb``, the same at the
pin roots (wall + block alone). The mating robot's side (latch block on its rear wall) is not
meshed: it is taken as the wall + block part of this side, ``C_B = C_wb`` (same wall, same
footprint, the blade bears about as deep in the latch stack as the pin heads in the pin stack;
assumption). The joint: ``K = inv(C_A + C_B)``.

* axial stiffness: all pins stretched equally, ``1^T K 1`` (joint), per block and per pin;
* rotational stiffness about the hinge the model uses (``cubot_cad.couplings.compliance.front_rear``: the
  underside edge of the touching faces for a zero docked gap, else the lowest pin row):
  the pins stretch by ``theta (z_i - hinge)``, ``k_rot = a^T K a``;
* shear stiffness after the play is taken up: a second mesh with the pins bonded in their
  wall holes and bores (clearance closed), a vertical load on every pin where the mating wall's
  hole bears on it (x in [0, wall]); one side, and the joint as two equal sides in series.

Results carry a ``provenance`` string and the sha256 of geometry + material + mesh settings, and
are cached as JSON by that hash (:func:`front_rear_fe`).

:func:`bare_wall_patch_stiffness` is the soft bracket: the wall alone with each block's footprint
as a uniform pressure patch (no bonded block stiffening the wall).

Measured for the thesis CuBot (ABS, E = 2.2 GPa, no knockdown; 2-core shared machine, 2026-12):

| quantity | bonded-block FE (h 4.8 mm, 114k dofs) | bare-wall bracket | hand formula today |
|---|---|---|---|
| joint rotational stiffness about the underside (N m/rad) | 1109 | ~174 (see below) | 6155 |
| joint axial stiffness (N/m) | 1.21e6 | ~1.9e5 | 6.66e6 |
| one pin alone, head to groove (N/m) | 1.50e6 | | 1.11e6 |
| wall (+ block) per block, one side (N/m) | 3.2e6 | 1.98e5 | (rigid) |
| joint shear after the play (N/m) | 7.8e6 | | (= axial) |

Bracket joint numbers: per block ``1 / (2 / k_wall + 1 / (3 k_pin))`` = 9.7e4 N/m, two blocks
1.9e5 N/m, and ``k_block * sum(z_block^2)`` = 174 N m/rad (blocks at 30 mm, their own tilt
stiffness ignored). Mesh convergence of the bonded model (rotational): h 10 / 6 / 4.8 mm give
1268 / 1135 / 1109 N m/rad (the last step changes it 2.3 %). Cold time 138-217 s depending on
the machine's load (mesh ~1 s, axial model 98-145 s, shear model 39-71 s; SuperLU's
factorisation is ~85 % of it); a cached call 1.4 ms.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from structure_fem.couplings.fe_solid import GmshSession, Load, gmsh_tet_mesh, solve_linear_elastic
from structure_fem.errors import InputError

#: Bump when the model (geometry build, loads, post-processing) changes: it is part of the hash.
MODEL_VERSION = "front_rear_fe/1"
#: Poisson's ratio of printed ABS/PLA (assumption; 0.35 is the usual datasheet value).
DEFAULT_POISSON = 0.35
#: Default mesh size (mm): two wall thicknesses, where P2 tetrahedra are within 2 % of
#: Timoshenko's clamped plate (tests/structure_fem/test_fe_solid.py).
DEFAULT_SIZE_MM = 4.8
#: Elements per full circle on the pins' curved edges.
DEFAULT_CURVATURE_ELEMENTS = 12
_TOL_MM = 1e-3


@dataclass(frozen=True)
class FrontRearGeometry:
    """Dimensions (mm) of one robot's side of a front-rear coupling, robot frame (x out of the face)."""

    wall_mm: float
    panel_y_mm: tuple[float, float]
    panel_z_mm: tuple[float, float]
    block_centres_mm: tuple[tuple[float, float], ...]  # (y, z) of each block's centre
    block_mm: float
    stack_mm: float  # depth of the plate stack behind the wall
    pin_offsets_mm: tuple[tuple[float, float], ...]  # (y, z) of each pin in a block
    pin_diameter_mm: float
    groove_diameter_mm: float
    clearance_mm: float
    head_end_x_mm: float  # front face of the pin head (negative: inside the robot)
    groove_x_mm: tuple[float, float]
    tip_x_mm: float
    hinge_z_mm: float

    @classmethod
    def from_cubot(cls, robot=None, gap_mm: float | None = None) -> FrontRearGeometry:
        """Read the dimensions of a :class:`cubot_cad.robots.cubot.CuBot` (default: the thesis's): its
        front wall between the side walls' mid-planes, from the floor's mid-plane to the top edge."""
        from cubot_cad.robots.cubot import CuBot

        r = robot if robot is not None else CuBot()
        w = r.wall_mm
        yc, wb = r.y_centre_mm, r.body_width_mm
        return cls._from_spec(r.fr_spec, w, (yc - wb / 2 + w / 2, yc + wb / 2 - w / 2),
                              (r.floor_mm / 2, r.body_height_mm),
                              tuple((yb, r.block_z_mm) for yb in r.block_ys_mm), gap_mm)

    @classmethod
    def from_cube_robot(cls, robot=None, gap_mm: float | None = None) -> FrontRearGeometry:
        """Read the dimensions of a :class:`cubot_cad.robots.cube_robot.CubeRobot` (default: the thesis's):
        the front wall of its connector cuboid (tier 2) between the side walls' mid-planes, from
        the cuboid floor's mid-plane to its top edge (the sensor cylinder rests on it: free, as
        the CuBot's cover), with the two pin blocks at ``+-block_offset_mm``."""
        from cubot_cad.robots.cube_robot import ConnectorCuboid, CubeRobot

        r = robot if robot is not None else CubeRobot()
        tier = next(pl.part for pl in r.build_placed() if isinstance(pl.part, ConnectorCuboid))
        S, w = tier.size_mm / 2, tier.wall_mm
        return cls._from_spec(r.fr_spec, w, (-S + w / 2, S - w / 2),
                              (tier.z0_mm + tier.floor_mm / 2, tier.z0_mm + tier.height_mm),
                              tuple((yb, r.block_z_mm) for yb in (-r.block_offset_mm, r.block_offset_mm)), gap_mm)

    @classmethod
    def of(cls, robot) -> FrontRearGeometry:
        """:meth:`from_cubot` or :meth:`from_cube_robot` by the CAD robot's kind."""
        from cubot_cad.robots.cube_robot import CubeRobot
        from cubot_cad.robots.cubot import CuBot

        if isinstance(robot, CuBot) or robot is None:
            return cls.from_cubot(robot)
        if isinstance(robot, CubeRobot):
            return cls.from_cube_robot(robot)
        raise InputError(f"no front-rear FE model of a {type(robot).__name__} (CuBot and Cube Robot only)")

    @classmethod
    def _from_spec(cls, fr, wall_mm: float, panel_y_mm, panel_z_mm, block_centres_mm,
                   gap_mm: float | None) -> FrontRearGeometry:
        """The pins, blocks and hinge of a :class:`cubot_cad.couplings.connectors.FrontRearSpec` on a wall panel.
        The hinge is :func:`cubot_cad.couplings.compliance.front_rear`'s: the underside (z = 0) when the docked
        faces touch, else the lowest pin row."""
        from cubot_cad.couplings import compliance as couplings

        gap = fr.design_gap_mm if gap_mm is None else gap_mm
        pins = [bz + z for _by, bz in block_centres_mm[:1] for _y, z in fr.pin_positions()]
        hinge = 0.0 if gap < couplings.CONTACT_GAP_MM else min(pins)
        x_back = fr.head_x_mm - fr.plate_mm
        g0 = fr.design_gap_mm + wall_mm + 2 * fr.plate_mm
        return cls(
            wall_mm=wall_mm,
            panel_y_mm=tuple(panel_y_mm),
            panel_z_mm=tuple(panel_z_mm),
            block_centres_mm=tuple(block_centres_mm),
            block_mm=fr.block_mm,
            stack_mm=-wall_mm - x_back,
            pin_offsets_mm=tuple(tuple(p) for p in fr.pin_positions()),
            pin_diameter_mm=fr.pin_diameter_mm,
            groove_diameter_mm=fr.groove_diameter_mm,
            clearance_mm=fr.clearance_mm,
            head_end_x_mm=fr.head_x_mm + fr.head_mm,
            groove_x_mm=(g0, g0 + fr.separation_mm),
            tip_x_mm=fr.protrusion_mm,
            hinge_z_mm=hinge,
        )

    def pin_axes_mm(self) -> list[tuple[float, float]]:
        """(y, z) of every pin axis, block by block."""
        return [(by + py, bz + pz) for by, bz in self.block_centres_mm for py, pz in self.pin_offsets_mm]

    def check(self) -> None:
        for n in ("wall_mm", "block_mm", "stack_mm", "pin_diameter_mm", "groove_diameter_mm"):
            v = getattr(self, n)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"FrontRearGeometry.{n} must be > 0 mm, got {v!r}")
        if not self.groove_diameter_mm < self.pin_diameter_mm:
            raise InputError("groove diameter must be smaller than the pin diameter")
        if not self.head_end_x_mm < -self.wall_mm < 0 < self.groove_x_mm[0] < self.groove_x_mm[1] < self.tip_x_mm:
            raise InputError("pin head, wall, groove and tip are not in order along x")


@dataclass(frozen=True)
class MeshSettings:
    size_mm: float = DEFAULT_SIZE_MM
    order: int = 2
    curvature_elements: int = DEFAULT_CURVATURE_ELEMENTS


@dataclass(frozen=True)
class Material:
    name: str
    youngs_modulus_pa: float
    poisson: float = DEFAULT_POISSON
    #: Factor on the datasheet modulus for printed parts (1 = none applied).
    knockdown: float = 1.0
    source: str = "cubot_cad.part.MATERIALS (datasheet modulus); Poisson 0.35: assumption"

    @property
    def E_pa(self) -> float:
        return self.youngs_modulus_pa * self.knockdown

    @classmethod
    def from_cubot_cad(cls, name: str = "abs", knockdown: float = 1.0) -> Material:
        from cubot_cad.part import material

        m = material(name)
        if not (math.isfinite(knockdown) and 0 < knockdown <= 1):
            raise InputError(f"modulus knockdown must be in (0, 1], got {knockdown!r}")
        src = "cubot_cad.part.MATERIALS (datasheet modulus); Poisson 0.35: assumption"
        if knockdown != 1.0:
            src += f"; printed-part knockdown x{knockdown:g}: assumption"
        return cls(name.lower(), m["youngs_modulus_pa"], DEFAULT_POISSON, knockdown, src)


def input_hash(geom: FrontRearGeometry, mat: Material, mesh: MeshSettings) -> str:
    """sha256 of everything that determines the result (geometry, material, mesh, model version)."""
    payload = {"model": MODEL_VERSION, "geometry": asdict(geom), "material": asdict(mat), "mesh": asdict(mesh)}
    return hashlib.sha256(json.dumps(payload, sort_keys=True, default=float).encode()).hexdigest()


# --- geometry + mesh ----------------------------------------------------------------------

def build_front_rear_mesh(geom: FrontRearGeometry, settings: MeshSettings = MeshSettings(),
                          play_closed: bool = False):
    """Mesh one side of the coupling (wall panel + blocks + pins) with gmsh OCC; metres out.
    ``play_closed``: pins bonded in their wall holes and bores (for shear after the play)."""
    geom.check()
    w = geom.wall_mm
    r = geom.pin_diameter_mm / 2
    rg = geom.groove_diameter_mm / 2
    rb = r if play_closed else r + geom.clearance_mm
    (y0, y1), (z0, z1) = geom.panel_y_mm, geom.panel_z_mm
    with GmshSession("front_rear") as gmsh:
        occ = gmsh.model.occ
        body = [(3, occ.addBox(-w, y0, z0, w, y1 - y0, z1 - z0))]
        h = geom.block_mm / 2
        for by, bz in geom.block_centres_mm:
            body.append((3, occ.addBox(-w - geom.stack_mm, by - h, bz - h, geom.stack_mm, 2 * h, 2 * h)))
        solid, _ = occ.fuse(body[:1], body[1:])
        x_root = geom.head_end_x_mm
        if not play_closed:
            cutters = [(3, occ.addCylinder(x_root, y, z, -x_root + 0.5, 0, 0, rb)) for y, z in geom.pin_axes_mm()]
            solid, _ = occ.cut(solid, cutters)
        g0, g1 = geom.groove_x_mm
        pins = []
        for y, z in geom.pin_axes_mm():
            pins.append((3, occ.addCylinder(x_root, y, z, g0 - x_root, 0, 0, r)))
            pins.append((3, occ.addCylinder(g0, y, z, g1 - g0, 0, 0, rg)))
            pins.append((3, occ.addCylinder(g1, y, z, geom.tip_x_mm - g1, 0, 0, r)))
        solid, _ = occ.fuse(solid, pins)
        occ.synchronize()
        return gmsh_tet_mesh(settings.size_mm, size_min_mm=0.5, curvature_elements=settings.curvature_elements)


def _radial(x, y_mm, z_mm):
    return np.hypot(x[1] - y_mm * 1e-3, x[2] - z_mm * 1e-3)


def _clamp_selector(geom: FrontRearGeometry):
    (y0, y1), (z0, _z1) = geom.panel_y_mm, geom.panel_z_mm
    t = _TOL_MM * 1e-3

    def sel(x):
        return (np.abs(x[1] - y0 * 1e-3) < t) | (np.abs(x[1] - y1 * 1e-3) < t) | (np.abs(x[2] - z0 * 1e-3) < t)
    return sel


def _shoulder_selector(geom: FrontRearGeometry, y, z, x_mm, r_in_mm, r_out_mm):
    t = _TOL_MM * 1e-3

    def sel(x):
        rho = _radial(x, y, z)
        return (np.abs(x[0] - x_mm * 1e-3) < t) & (rho > r_in_mm * 1e-3) & (rho < r_out_mm * 1e-3)
    return sel


def _bearing_selector(geom: FrontRearGeometry, y, z):
    """The pin's surface where the mating robot's wall hole bears on it: x in (0, wall)."""
    r = geom.pin_diameter_mm / 2

    def sel(x):
        rho = _radial(x, y, z)
        return (x[0] > 0) & (x[0] < geom.wall_mm * 1e-3) & (rho < (r + 0.3) * 1e-3)
    return sel


# --- the result -----------------------------------------------------------------------------

class FEResult:
    """What every FE result record shares (dataclasses with a ``cache_hit`` field): JSON without
    ``cache_hit``, and back (``cache_hit`` says whether it came from a cache or the package)."""

    def to_dict(self) -> dict:
        d = asdict(self)
        d.pop("cache_hit")
        return d

    @classmethod
    def from_dict(cls, d: dict, cache_hit: bool = False):
        return cls(**d, cache_hit=cache_hit)


@dataclass
class ConnectorFE(FEResult):
    """FE stiffnesses of one coupling (SI) and where they come from."""

    kind: str
    axial_stiffness_n_per_m: float  # the whole joint (both blocks, both robots' sides)
    rotational_stiffness_nm_per_rad: float  # about hinge_z_m, both sides
    shear_stiffness_n_per_m: float  # the whole joint after the play, both sides
    per_block_axial_n_per_m: float  # one block's pins + wall, both sides
    per_pin_axial_n_per_m: float  # one pin + its share of the wall, both sides
    one_side: dict  # the same for the pin side alone (the meshed robot)
    hinge_z_m: float
    lever_arms_m: list[float]
    provenance: str
    input_hash: str
    inputs: dict
    timings_s: dict = field(default_factory=dict)
    cache_hit: bool = False


def _kilo(n: int) -> str:
    return f"{n / 1000:.0f}k" if n >= 1000 else str(n)


def compute_front_rear(geom: FrontRearGeometry, mat: Material, settings: MeshSettings = MeshSettings(),
                       with_shear: bool = True) -> ConnectorFE:
    """Cold FE of the front-rear coupling (no cache): see the module docstring for the model."""
    t0 = time.perf_counter()
    mesh = build_front_rear_mesh(geom, settings)
    t_mesh = time.perf_counter() - t0
    axes = geom.pin_axes_mm()
    r, rg, c = geom.pin_diameter_mm / 2, geom.groove_diameter_mm / 2, geom.clearance_mm
    g1 = geom.groove_x_mm[1]
    unit = 1.0  # N per load case; linear, so stiffnesses do not depend on it
    loads = [Load(_shoulder_selector(geom, y, z, g1, rg + 0.01, r + 0.05), (unit, 0.0, 0.0)) for y, z in axes]
    res = solve_linear_elastic(mesh, mat.E_pa, mat.poisson, _clamp_selector(geom), loads, order=settings.order)
    n = len(axes)
    C_a = np.zeros((n, n))
    C_wb = np.zeros((n, n))
    for i, (y, z) in enumerate(axes):
        tip = _shoulder_selector(geom, y, z, g1, rg + 0.01, r + 0.05)
        root = _shoulder_selector(geom, y, z, geom.head_end_x_mm, r - 0.05, r + c + 0.05)
        for j in range(n):
            C_a[i, j] = res.mean_displacement(tip, j)[0] / unit
            C_wb[i, j] = res.mean_displacement(root, j)[0] / unit
    C_a = 0.5 * (C_a + C_a.T)
    C_wb = 0.5 * (C_wb + C_wb.T)
    t_axial = time.perf_counter() - t0 - t_mesh

    arms = np.array([(z - geom.hinge_z_mm) * 1e-3 for _y, z in axes])
    ones = np.ones(n)
    per_block = len(geom.pin_offsets_mm)

    def stiffnesses(C):
        K = np.linalg.inv(C)
        blk = np.ones(per_block)
        return {"axial_n_per_m": float(ones @ K @ ones),
                "rotational_nm_per_rad": float(arms @ K @ arms),
                "per_block_axial_n_per_m": float(blk @ np.linalg.inv(C[:per_block, :per_block]) @ blk),
                "per_pin_axial_n_per_m": float(1.0 / C[0, 0])}

    side = stiffnesses(C_a)
    side["wall_and_block_only"] = stiffnesses(C_wb)
    side["pin_only_axial_n_per_m"] = float(1.0 / (C_a[0, 0] - C_wb[0, 0]))
    joint = stiffnesses(C_a + C_wb)

    shear_side = float("nan")
    n_dofs_shear = 0
    t_shear = 0.0
    if with_shear:
        ts = time.perf_counter()
        mesh_s = build_front_rear_mesh(geom, settings, play_closed=True)
        sel = [_bearing_selector(geom, y, z) for y, z in axes]
        f = 1.0 / n
        res_s = solve_linear_elastic(mesh_s, mat.E_pa, mat.poisson, _clamp_selector(geom),
                                     [Load(s, (0.0, 0.0, -f)) for s in sel], order=settings.order)
        # one load case per pin: superpose for all pins loaded together
        u_mean = np.mean([sum(res_s.mean_displacement(s, j)[2] for j in range(n)) for s in sel])
        shear_side = float(1.0 / -u_mean)
        n_dofs_shear = res_s.n_dofs
        t_shear = time.perf_counter() - ts
    side["shear_n_per_m"] = shear_side

    prov = (f"fe: scikit-fem P{settings.order} tetra, gmsh h={settings.size_mm:g} mm "
            f"({settings.curvature_elements}/circle on pins), {_kilo(res.n_dofs)} dofs, E={mat.E_pa:.3g} Pa, "
            f"nu={mat.poisson:g}; wall panel + bonded block + pins, mating side = wall + block (assumption)")
    return ConnectorFE(
        kind="front_rear",
        axial_stiffness_n_per_m=joint["axial_n_per_m"],
        rotational_stiffness_nm_per_rad=joint["rotational_nm_per_rad"],
        shear_stiffness_n_per_m=shear_side / 2,
        per_block_axial_n_per_m=joint["per_block_axial_n_per_m"],
        per_pin_axial_n_per_m=joint["per_pin_axial_n_per_m"],
        one_side=side,
        hinge_z_m=geom.hinge_z_mm * 1e-3,
        lever_arms_m=[float(a) for a in arms],
        provenance=prov,
        input_hash=input_hash(geom, mat, settings),
        inputs={"geometry": asdict(geom), "material": asdict(mat), "mesh": asdict(settings),
                "model": MODEL_VERSION, "n_dofs": res.n_dofs, "n_elements": res.n_elements,
                "n_dofs_shear": n_dofs_shear},
        timings_s={"mesh": round(t_mesh, 3), "axial_solve": round(t_axial, 3), "shear": round(t_shear, 3),
                   "total": round(time.perf_counter() - t0, 3)},
    )


# --- cache --------------------------------------------------------------------------------

def default_cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "voidcross" / "connector_fe"


def front_rear_fe(robot=None, material: str | Material = "abs", settings: MeshSettings = MeshSettings(),
                  cache_dir: str | os.PathLike | None = None, use_cache: bool = True,
                  with_shear: bool = True) -> ConnectorFE:
    """FE stiffness of a CuBot's or Cube Robot's front-rear coupling, cached as ``<cache_dir>/<hash>.json``.

    ``robot``: a :class:`cubot_cad.robots.cubot.CuBot` or :class:`cubot_cad.robots.cube_robot.CubeRobot`
    (default: the thesis's CuBot). ``material``:
    a :data:`cubot_cad.part.MATERIALS` name or a :class:`Material`. A repeat call with the same
    geometry, material and mesh settings reads the cache (``cache_hit`` is True)."""
    t0 = time.perf_counter()
    geom = FrontRearGeometry.of(robot)
    mat = material if isinstance(material, Material) else Material.from_cubot_cad(material)
    key = input_hash(geom, mat, settings)
    path = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    file = path / f"{key}.json"
    if use_cache and file.is_file():
        try:
            d = json.loads(file.read_text())
            shear = d["one_side"].get("shear_n_per_m")
            has_shear = isinstance(shear, float) and math.isfinite(shear)
            if d.get("input_hash") == key and (has_shear or not with_shear):
                out = ConnectorFE.from_dict(d, cache_hit=True)
                out.timings_s = dict(out.timings_s, cached_call=round(time.perf_counter() - t0, 4))
                return out
        except (OSError, ValueError, KeyError, TypeError):
            pass  # unreadable or stale entry: recompute and overwrite
    out = compute_front_rear(geom, mat, settings, with_shear=with_shear)
    if use_cache:
        path.mkdir(parents=True, exist_ok=True)
        tmp = file.with_suffix(".tmp")
        tmp.write_text(json.dumps(out.to_dict(), indent=1, sort_keys=True))
        tmp.replace(file)
    return out


def bare_wall_patch_stiffness(geom: FrontRearGeometry, mat: Material,
                              settings: MeshSettings = MeshSettings()) -> dict:
    """Lower-bound companion of :func:`compute_front_rear`: the wall panel alone (pin holes in, no
    block), each block's footprint on its inner face loaded by a uniform outward pressure (the
    block as a soft patch instead of a bonded solid; the FE counterpart of the plate estimate
    in the toolchain notes). Both blocks loaded together by F each: F / mean outward displacement
    of a footprint (N/m, per block, one robot's wall)."""
    geom.check()
    w = geom.wall_mm
    rb = geom.pin_diameter_mm / 2 + geom.clearance_mm
    (y0, y1), (z0, z1) = geom.panel_y_mm, geom.panel_z_mm
    h = geom.block_mm / 2
    t0 = time.perf_counter()
    with GmshSession("bare_wall") as gmsh:
        occ = gmsh.model.occ
        wall = [(3, occ.addBox(-w, y0, z0, w, y1 - y0, z1 - z0))]
        holes = [(3, occ.addCylinder(-w - 0.5, y, z, w + 1.0, 0, 0, rb)) for y, z in geom.pin_axes_mm()]
        occ.cut(wall, holes)
        # imprint the footprints on the inner face so the load facets follow their edges
        pads = [(2, occ.addRectangle(-w, by - h, bz - h, 2 * h, 2 * h)) for by, bz in geom.block_centres_mm]
        for _dim, tag in pads:
            occ.rotate([(2, tag)], -w, 0, 0, 0, 1, 0, -math.pi / 2)
        occ.fragment(occ.getEntities(3), pads)
        occ.synchronize()
        mesh = gmsh_tet_mesh(settings.size_mm, size_min_mm=0.5, curvature_elements=settings.curvature_elements)
    t = _TOL_MM * 1e-3

    def footprint(by, bz):
        return lambda x: ((np.abs(x[0] + w * 1e-3) < t) & (np.abs(x[1] - by * 1e-3) < h * 1e-3)
                          & (np.abs(x[2] - bz * 1e-3) < h * 1e-3))

    sels = [footprint(by, bz) for by, bz in geom.block_centres_mm]
    res = solve_linear_elastic(mesh, mat.E_pa, mat.poisson, _clamp_selector(geom),
                               [Load(s, (1.0, 0.0, 0.0)) for s in sels], order=settings.order)
    k = [1.0 / sum(res.mean_displacement(s, j)[0] for j in range(len(sels))) for s in sels]
    return {"per_block_axial_n_per_m": float(np.mean(k)), "n_dofs": res.n_dofs,
            "seconds": round(time.perf_counter() - t0, 3)}
