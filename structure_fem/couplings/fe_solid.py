"""Small 3D linear-elastic finite-element toolkit (SI units): gmsh meshes, scikit-fem solves.

Used by :mod:`structure_fem.couplings.connector_fe` to compute connector compliance from the CAD
dimensions. Everything here is plain linear elasticity, small strain, isotropic material.

* :func:`gmsh_tet_mesh` meshes the OCC model currently open in gmsh (lengths in mm, the CAD's
  unit) and returns a :class:`skfem.MeshTet` in metres.
* :func:`solve_linear_elastic` assembles ``linear_elasticity`` on tetrahedral P1 or P2 vector
  elements, clamps the ``fixed`` facets, applies each load as a uniform traction of a given
  total force over its facets, factorises once and solves every load case.
* :class:`ElasticResult` holds the displacement of every load case, and the mean displacement
  over any facet set (the "load point" displacement used for stiffnesses).

P2 is the default: on the validation problems (tests/structure_fem/test_fe_solid.py) P1 tetrahedra
lock in bending (a pin cantilever at 4-5 elements per diameter is 20-40 % too stiff), while P2
is within 1-3 % on coarse meshes at a fraction of P1's dof count for the same accuracy.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from structure_fem.errors import InputError

#: Facet selector: a callable of facet-midpoint coordinates (3 x n array, metres) returning a mask,
#: or an explicit array of facet indices.
FacetSelector = Callable[[np.ndarray], np.ndarray] | np.ndarray


def _require_fe():
    try:
        import skfem  # noqa: F401
    except ImportError as e:  # pragma: no cover - exercised only without the extra
        raise InputError("connector FE needs scikit-fem and gmsh: pip install 'voidcross[fem]'") from e


def facets(mesh, select: FacetSelector, boundary_only: bool = True) -> np.ndarray:
    """Facet indices of ``mesh`` chosen by ``select`` (see :data:`FacetSelector`)."""
    if callable(select):
        cand = mesh.boundary_facets() if boundary_only else np.arange(mesh.facets.shape[1])
        mid = mesh.p[:, mesh.facets[:, cand]].mean(axis=1)
        out = cand[np.asarray(select(mid), dtype=bool)]
    else:
        out = np.asarray(select, dtype=np.int64)
    if out.size == 0:
        raise InputError("a facet selection matched no boundary facet of the mesh")
    return out


@dataclass(frozen=True)
class Load:
    """A uniform traction over ``select`` facets whose resultant is ``force_n`` (3-vector, N)."""

    select: FacetSelector
    force_n: tuple[float, float, float]


@dataclass
class ElasticResult:
    """Displacements (one column per load case) on a P1/P2 vector basis, plus solve facts."""

    basis: object
    u: np.ndarray  # (ndofs, nloads)
    order: int
    n_dofs: int
    n_elements: int
    seconds: float
    load_facets: list[np.ndarray] = field(default_factory=list)

    @property
    def mesh(self):
        return self.basis.mesh

    def mean_displacement(self, select: FacetSelector, case: int = 0) -> np.ndarray:
        """Area-weighted mean displacement vector (m) over the facets ``select`` in load ``case``."""
        from skfem import FacetBasis, Functional

        fb = FacetBasis(self.mesh, self.basis.elem, facets=facets(self.mesh, select), intorder=2 * self.order)
        area = Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(fb)
        uf = fb.interpolate(self.u[:, case])
        comps = []
        for i in range(3):
            comps.append(Functional(lambda w, i=i: w["u"][i]).assemble(fb, u=uf) / area)
        return np.array(comps)

    def max_abs(self, component: int, case: int = 0) -> float:
        """Largest |u_component| over the nodes (m)."""
        return float(np.max(np.abs(self.u[self.basis.nodal_dofs[component], case])))


def solve_linear_elastic(mesh, E_pa, nu, fixed: FacetSelector,
                         load: Load | Sequence[Load], order: int = 2) -> ElasticResult:
    """Linear elasticity on a tetrahedral mesh (metres, Pa, N): clamp ``fixed`` facets
    (all three displacement components zero), apply each :class:`Load` (one load case each;
    pass a sequence for several cases, solved with one factorisation). ``order`` 1 or 2.
    ``E_pa`` and ``nu``: one value, or one per element (several materials, e.g. a steel bolt in
    printed plates; see :func:`stiffness_matrix`)."""
    _require_fe()
    from scipy.sparse.linalg import splu
    from skfem import (
        Basis,
        ElementTetP1,
        ElementTetP2,
        ElementVectorH1,
        FacetBasis,
        Functional,
        LinearForm,
        asm,
    )

    E_arr, nu_arr = np.atleast_1d(np.asarray(E_pa, dtype=float)), np.atleast_1d(np.asarray(nu, dtype=float))
    if not (np.all(np.isfinite(E_arr)) and np.all(E_arr > 0)):
        raise InputError(f"Young's modulus must be > 0 Pa, got {E_pa!r}")
    if not (np.all(nu_arr > -1.0) and np.all(nu_arr < 0.5)):
        raise InputError(f"Poisson's ratio must be in (-1, 0.5), got {nu!r}")
    for name, arr in (("Young's modulus", E_arr), ("Poisson's ratio", nu_arr)):
        if arr.size not in (1, mesh.t.shape[1]):
            raise InputError(f"{name}: give one value or one per element ({mesh.t.shape[1]}), got {arr.size}")
    if order not in (1, 2):
        raise InputError(f"element order must be 1 or 2, got {order!r}")
    loads = [load] if isinstance(load, Load) else list(load)
    t0 = time.perf_counter()
    e = ElementVectorH1(ElementTetP2() if order == 2 else ElementTetP1())
    ib = Basis(mesh, e, intorder=max(2 * (order - 1), 1))
    K = stiffness_matrix(mesh, E_pa, nu, order)
    fixed_dofs = ib.get_dofs(facets(mesh, fixed)).all()
    rhs = np.zeros((ib.N, len(loads)))
    load_facets = []
    for j, ld in enumerate(loads):
        fsel = facets(mesh, ld.select)
        load_facets.append(fsel)
        fb = FacetBasis(mesh, e, facets=fsel, intorder=2 * order)
        area = Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(fb)
        t = np.asarray(ld.force_n, dtype=float) / area

        @LinearForm
        def traction(v, w, t=t):
            return t[0] * v[0] + t[1] * v[1] + t[2] * v[2]

        rhs[:, j] = asm(traction, fb)
    free = np.setdiff1d(np.arange(ib.N), fixed_dofs)
    A = K[free][:, free].tocsc()
    lu = splu(A, permc_spec="COLAMD")
    u = np.zeros_like(rhs)
    u[free] = lu.solve(rhs[free])
    return ElasticResult(ib, u, order, int(free.size), int(mesh.t.shape[1]), time.perf_counter() - t0, load_facets)


def stiffness_matrix(mesh, E_pa, nu, order: int = 2, chunk: int = 20000):
    """Global stiffness matrix of isotropic linear elasticity on P1/P2 tetrahedra (CSR).

    Same matrix as ``asm(linear_elasticity(*lame_parameters(E, nu)), Basis(mesh,
    ElementVectorH1(ElementTetP2())))`` (global dof ``3 s + i`` for scalar dof ``s``, component
    ``i``; a test checks equality), but vectorised over elements with numpy: scikit-fem's generic
    form loop spends ~3 s per 5k P2 tetrahedra, this ~0.3 s. Exact quadrature on straight tets
    (degree 2(order-1)). ``E_pa`` / ``nu``: scalars, or arrays of one value per element.
    """
    from scipy.sparse import coo_matrix
    from skfem import Basis, ElementTetP1, ElementTetP2

    nel = mesh.t.shape[1]
    E_e = np.broadcast_to(np.asarray(E_pa, dtype=float), (nel,))
    nu_e = np.broadcast_to(np.asarray(nu, dtype=float), (nel,))
    lam_all = E_e * nu_e / ((1 + nu_e) * (1 - 2 * nu_e))
    mu_all = E_e / (2 * (1 + nu_e))
    el = ElementTetP2() if order == 2 else ElementTetP1()
    nloc = 10 if order == 2 else 4
    rows, cols, vals = [], [], []
    eye = np.eye(3)
    ndof = None
    for s0 in range(0, nel, chunk):
        sel = np.arange(s0, min(nel, s0 + chunk))
        sb = Basis(mesh, el, intorder=max(2 * (order - 1), 1), elements=sel)
        ndof = sb.N
        G = np.stack([sb.basis[a][0].grad for a in range(nloc)])  # (a, k, e, q)
        ne, nq = G.shape[2], G.shape[3]
        Gt = G.transpose(2, 0, 1, 3).reshape(ne, 3 * nloc, nq)  # (e, a k, q)
        S = np.matmul(Gt * sb.dx[:, None, :], Gt.transpose(0, 2, 1)).reshape(ne, nloc, 3, nloc, 3)
        # S[e, a, k, b, l] = int dphi_a/dx_k dphi_b/dx_l; K[(a,i),(b,j)] =
        # lam S[a,i,b,j] + mu (delta_ij sum_k S[a,k,b,k] + S[a,j,b,i])
        trace = np.einsum("eakbk->eab", S)
        lam = lam_all[sel][:, None, None, None, None]
        mu = mu_all[sel][:, None, None, None, None]
        Ke = lam * S + mu * (trace[:, :, None, :, None] * eye[None, None, :, None, :]
                             + S.transpose(0, 1, 4, 3, 2))
        Ke = Ke.reshape(ne, 3 * nloc, 3 * nloc)  # (e, a i, b j)
        sd = sb.element_dofs  # (a, e) scalar dofs of the selected elements
        vd = (3 * sd[:, None, :] + np.arange(3)[None, :, None]).reshape(3 * nloc, -1).T  # (e, a i)
        rows.append(np.broadcast_to(vd[:, :, None], Ke.shape).ravel())
        cols.append(np.broadcast_to(vd[:, None, :], Ke.shape).ravel())
        vals.append(Ke.ravel())
    n = 3 * ndof
    K = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))
    return K.tocsr()


# --- gmsh -------------------------------------------------------------------------------

def gmsh_tet_mesh(size_mm: float, size_min_mm: float | None = None, optimize: bool = True,
                  curvature_elements: int = 16):
    """Mesh the gmsh OCC model that is open (geometry in mm) with linear tetrahedra and return
    a :class:`skfem.MeshTet` in metres. gmsh must be initialised; the caller finalises it.
    ``curvature_elements``: elements per full circle on curved edges (so a round pin's
    polygonal section is within ~2.5 % of its area at 16), 0 to switch that off."""
    import gmsh
    from skfem import MeshTet

    gmsh.option.setNumber("Mesh.MeshSizeMax", size_mm)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size_min_mm if size_min_mm is not None else size_mm / 4)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", curvature_elements)
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    gmsh.option.setNumber("Mesh.Optimize", 1 if optimize else 0)
    gmsh.model.mesh.generate(3)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    types, _, conn = gmsh.model.mesh.getElements(3)
    tets = [c for ty, c in zip(types, conn, strict=True) if ty == 4]
    if not tets:
        raise InputError("gmsh produced no tetrahedra")
    idx = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    idx[tags.astype(np.int64)] = np.arange(tags.size)
    t = idx[np.concatenate(tets).astype(np.int64)].reshape(-1, 4).T
    used = np.unique(t)
    remap = np.full(tags.size, -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    p = coords.reshape(-1, 3).T[:, used] * 1e-3
    return MeshTet(np.ascontiguousarray(p), np.ascontiguousarray(remap[t]))


class GmshSession:
    """``with GmshSession("name"): ...`` initialises a silent gmsh model and always finalises it."""

    def __init__(self, name: str = "fe", threads: int = 1):
        self.name = name
        self.threads = threads

    def __enter__(self):
        import gmsh

        if gmsh.isInitialized():
            gmsh.finalize()
        gmsh.initialize(interruptible=False)
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", self.threads)
        gmsh.model.add(self.name)
        return gmsh

    def __exit__(self, *exc):
        import gmsh

        gmsh.finalize()
        return False


def box_mesh(lx_mm: float, ly_mm: float, lz_mm: float, size_mm: float):
    """A box [0, lx] x [-ly/2, ly/2] x [-lz/2, lz/2] (mm) meshed by gmsh, in metres."""
    with GmshSession("box") as gmsh:
        gmsh.model.occ.addBox(0, -ly_mm / 2, -lz_mm / 2, lx_mm, ly_mm, lz_mm)
        gmsh.model.occ.synchronize()
        return gmsh_tet_mesh(size_mm)


def cylinder_mesh(length_mm: float, diameter_mm: float, size_mm: float, curvature_elements: int = 16):
    """A round bar along +x from x = 0 to ``length_mm`` (mm) meshed by gmsh, in metres."""
    with GmshSession("cyl") as gmsh:
        gmsh.model.occ.addCylinder(0, 0, 0, length_mm, 0, 0, diameter_mm / 2)
        gmsh.model.occ.synchronize()
        return gmsh_tet_mesh(size_mm, curvature_elements=curvature_elements)
