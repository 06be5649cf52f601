"""Validation of the 3D linear-elastic FE toolkit (structure_fem.couplings.fe_solid) against closed forms.

Measured on this machine (P2 tetrahedra, E = 2.2 GPa, nu = 0.35), signed error vs the closed form:

| problem | mesh | error |
|---|---|---|
| round pin d 5 x 50 mm, tip load, vs P L^3 / 3EI | h 2.5 mm, 16/circle, 26k dofs | +3.5 % |
| same pin, axial pull, vs P L / EA | same mesh | +1.6 % |
| clamped square plate 96 x 96 x 2.4 mm, uniform q | h 4.8 mm, 17k dofs | -1.6 % |
| same plate, P1 tetrahedra | same mesh | about -90 % (locks) |

Most of the pin's error is the polygonal section of a straight-sided tetrahedral mesh (16
sides: area -2.6 %, second moment about -5 %), not the elements.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

from structure_fem.couplings.fe_solid import (  # noqa: E402
    GmshSession,
    Load,
    cylinder_mesh,
    gmsh_tet_mesh,
    solve_linear_elastic,
    stiffness_matrix,
)

E, NU = 2.2e9, 0.35
L_MM, D_MM = 50.0, 5.0


@pytest.fixture(scope="module")
def pin_result():
    mesh = cylinder_mesh(L_MM, D_MM, 2.5, curvature_elements=16)
    L = L_MM * 1e-3

    def tip(x):
        return x[0] > L - 1e-9

    res = solve_linear_elastic(mesh, E, NU, lambda x: x[0] < 1e-9,
                               [Load(tip, (0.0, 0.0, -1.0)), Load(tip, (1.0, 0.0, 0.0))], order=2)
    return res, tip


def test_stiffness_matrix_equals_scikit_fem_form():
    from skfem import Basis, ElementTetP2, ElementVectorH1, asm
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    mesh = cylinder_mesh(10.0, 5.0, 2.0, curvature_elements=8)
    ref = asm(linear_elasticity(*lame_parameters(E, NU)), Basis(mesh, ElementVectorH1(ElementTetP2()), intorder=2))
    ours = stiffness_matrix(mesh, E, NU, order=2, chunk=300)
    assert abs(ours - ref).max() / abs(ref).max() < 1e-12


def test_pin_cantilever_tip_load(pin_result):
    """Round ABS pin (d 5 mm, L 50 mm, L/d 10: shear deflection ~0.5 %), clamped end face,
    1 N tip load as a uniform traction: mean tip deflection vs Euler-Bernoulli P L^3 / (3 E I)."""
    res, tip = pin_result
    inertia = math.pi * (D_MM * 1e-3) ** 4 / 64
    closed = (L_MM * 1e-3) ** 3 / (3 * E * inertia)
    w = -res.mean_displacement(tip, 0)[2]
    assert w == pytest.approx(closed, rel=0.05)


def test_pin_axial_bar(pin_result):
    """Same pin pulled along its axis: P L / (E A)."""
    res, tip = pin_result
    A = math.pi * (D_MM * 1e-3) ** 2 / 4
    u = res.mean_displacement(tip, 1)[0]
    assert u == pytest.approx(L_MM * 1e-3 / (E * A), rel=0.05)


def _plate(h_mm: float, order: int = 2, a_mm: float = 96.0, t_mm: float = 2.4) -> float:
    """Centre deflection / Timoshenko's closed form for a clamped square plate under uniform q."""
    with GmshSession("plate") as gmsh:
        gmsh.model.occ.addBox(-a_mm / 2, -a_mm / 2, 0, a_mm, a_mm, t_mm)
        gmsh.model.occ.synchronize()
        mesh = gmsh_tet_mesh(h_mm)
    a, t, q = a_mm * 1e-3, t_mm * 1e-3, 1000.0
    res = solve_linear_elastic(mesh, E, NU, lambda x: (np.abs(x[0]) > a / 2 - 1e-9) | (np.abs(x[1]) > a / 2 - 1e-9),
                               Load(lambda x: x[2] > t - 1e-9, (0.0, 0.0, -q * a * a)), order=order)
    D = E * t ** 3 / (12 * (1 - NU ** 2))
    return res.max_abs(2) / (0.00126 * q * a ** 4 / D)


def test_clamped_square_plate_uniform_pressure():
    """Clamped square plate a = 96 mm, t = 2.4 mm (the CuBot wall; a/t = 40, so shear deformation
    is small), uniform pressure q: w_max = 0.00126 q a^4 / D, D = E t^3 / 12 (1 - nu^2).
    Source: Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells (2nd ed., 1959), Art. 44
    (rectangular plates with built-in edges, uniform load), Table 35, b/a = 1.0: alpha = 0.00126."""
    assert _plate(4.8) == pytest.approx(1.0, rel=0.05)


def test_p1_locks_in_bending_so_p2_is_the_default():
    """Why P2: on the same plate mesh linear tetrahedra are far too stiff (shear locking)."""
    assert _plate(4.8, order=1) < 0.5


def test_mesh_refinement_changes_plate_stiffness_by_less_than_5_percent():
    coarse, fine = _plate(4.8), _plate(3.6)
    assert abs(coarse / fine - 1) < 0.05


def test_rejects_bad_inputs():
    from structure_fem.errors import InputError

    mesh = cylinder_mesh(10.0, 5.0, 3.0, curvature_elements=8)
    with pytest.raises(InputError):
        solve_linear_elastic(mesh, -1.0, NU, lambda x: x[0] < 1e-9, Load(lambda x: x[0] > 0.01 - 1e-9, (1, 0, 0)))
    with pytest.raises(InputError):
        solve_linear_elastic(mesh, E, NU, lambda x: x[0] < -1.0, Load(lambda x: x[0] > 0.01 - 1e-9, (1, 0, 0)))
