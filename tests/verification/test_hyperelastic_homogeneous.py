"""Verification: homogeneous finite deformation of hyperelastic blocks.

A block ``[0, L] x [0, H] (x [0, B])`` is stretched by the prescribed stretch
``lambda_1`` in x (``u_x = 0`` on "left", ``u_x = (lambda_1 - 1) L`` on "right",
symmetry planes "bottom" (and "front" in 3D) fixed normally, the other faces
traction free). The exact solution is homogeneous, ``F = diag(lambda_1,
lambda_2[, lambda_2])`` in 3D and ``F = diag(lambda_1, lambda_2, 1)`` in plane
strain, with the lateral stretch ``lambda_2`` from ``P_22 = 0``:

* neo-Hookean: ``mu (lambda_2^2 - 1) + lam ln J = 0`` (``J = lambda_1 lambda_2`` in plane
  strain, ``lambda_1 lambda_2^2`` in 3D; one scalar root, brentq to 1e-15), and the
  nominal stress ``P_11 = mu lambda_1 + (lam ln J - mu) / lambda_1``;
* St Venant-Kirchhoff: ``E_22 = -lam E_11 / (lam + 2 mu)`` (plane strain) or
  ``-lam E_11 / (2 lam + 2 mu)`` (3D), ``E_11 = (lambda_1^2 - 1) / 2``, and
  ``P_11 = lambda_1 (lam tr E + 2 mu E_11)``.

Linear displacements are in every P1/P2 space, so the discrete solution is
exact: the tests assert displacement, nodal first Piola-Kirchhoff stress and
reaction force ``P_11 * H (* B)`` to a relative 1e-9, and that a plain Newton
loop on the body's internal force and tangent converges quadratically.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from alcontact.fem import Hyperelastic, Material, meshes

E, NU = 100.0, 0.3
L, H, B = 2.0, 1.0, 1.0
STRETCH = 1.4


def _exact(name, lam, mu, dim, l1):
    """Lateral stretch and nominal stress P_11 of the homogeneous uniaxial state."""
    if name == "neo-hookean":
        nlat = 1 if dim == 2 else 2

        def p22(l2):
            return mu * (l2**2 - 1) + lam * np.log(l1 * l2**nlat)

        l2 = brentq(p22, 0.2, 1.0, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        lnJ = np.log(l1 * l2**nlat)
        return l2, mu * l1 + (lam * lnJ - mu) / l1
    E11 = 0.5 * (l1**2 - 1)
    E22 = -lam * E11 / (lam + 2 * mu) if dim == 2 else -lam * E11 / (2 * lam + 2 * mu)
    trE = E11 + (1 if dim == 2 else 2) * E22
    return np.sqrt(1 + 2 * E22), l1 * (lam * trE + 2 * mu * E11)


def _block(dim, order, name):
    if dim == 2:
        mesh = meshes.rectangle(0.0, L, 0.0, H, 4, 3)
        sym = [("bottom", 1)]
    else:
        mesh = meshes.box(0.0, L, 0.0, H, 0.0, B, 2, 2, 2)
        sym = [("front", 1), ("bottom", 2)]
    body = Hyperelastic(mesh, Material(E=E, nu=NU), order=order, model=name)
    bc = [body.dirichlet("left", components=[0]),
          body.dirichlet("right", components=[0], value=(STRETCH - 1.0) * L)]
    bc += [body.dirichlet(n, components=[c]) for n, c in sym]
    return body, bc


def _newton(body, bc, u0, tol=1e-12, max_iter=20):
    """Plain Newton on f_int(u) = 0 with the Dirichlet DOFs held at their values."""
    dofs, vals = body._collect(bc)
    free = np.ones(body.ndofs, dtype=bool)
    free[dofs] = False
    u = u0.copy()
    u[dofs] = vals
    norms = []
    for _ in range(max_iter):
        r = body.internal_force(u)
        norms.append(np.linalg.norm(r[free]))
        if norms[-1] <= tol * norms[0]:
            break
        fac = body.factorize(dofs, matrix=body.tangent(u), check=False)
        u[free] -= fac.solve(r[free])
    return u, np.array(norms)


CASES = [(dim, order, name) for dim in (2, 3) for order in (1, 2)
         for name in ("neo-hookean", "saint-venant-kirchhoff")]


@pytest.mark.parametrize("dim, order, name", CASES)
def test_uniaxial_stretch_matches_homogeneous_solution(dim, order, name):
    """Displacement, nodal P and the reaction equal the analytical state (rel. 1e-9); Newton is quadratic."""
    body, bc = _block(dim, order, name)
    l2, P11 = _exact(name, body.lam, body.mu, dim, STRETCH)
    # start from the stretch alone (lateral stretch 1): far from the solution for a 40 % stretch
    u0 = body.interpolate(lambda x: np.vstack([(STRETCH - 1.0) * x[0], 0.0 * x[1:]]))
    u, norms = _newton(body, bc, u0)

    assert norms[-1] <= 1e-12 * norms[0], norms
    assert len(norms) <= 8, norms
    # quadratic convergence: once in the asymptotic range, r_{k+1} / r_k^2 stays bounded
    # (the normalized contraction e_{k+1} <= C e_k^2 with C = 10) and the last step
    # before the tolerance gains at least as many digits as the one before it
    e = norms / norms[0]
    asym = [k for k in range(1, len(e) - 1) if e[k] < 1e-2]
    assert asym, e
    for k in asym:
        assert e[k + 1] <= 10.0 * e[k] ** 2 or e[k + 1] <= 1e-13, e

    exact_u = body.interpolate(lambda x: np.vstack([(STRETCH - 1.0) * x[0], (l2 - 1.0) * x[1:]]))
    assert np.max(np.abs(u - exact_u)) <= 1e-9 * np.max(np.abs(exact_u))

    Pn = body.first_piola(u)
    d = dim
    expect = np.zeros((d, d))
    expect[0, 0] = P11
    np.testing.assert_allclose(Pn, np.tile(expect.ravel(), (Pn.shape[0], 1)), rtol=0, atol=1e-9 * P11)

    # reaction on "right" = P_11 times the reference face area
    _, rdofs = body.node_dofs("right")
    reaction = body.internal_force(u)[rdofs[:, 0]].sum()
    area = H if dim == 2 else H * B
    assert reaction == pytest.approx(P11 * area, rel=1e-9)


def test_body_solve_reaches_the_same_state_by_load_steps():
    """Hyperelastic.solve (Newton with load steps) gives the analytical neo-Hookean state (rel. 1e-9)."""
    body, bc = _block(2, 2, "neo-hookean")
    l2, _ = _exact("neo-hookean", body.lam, body.mu, 2, STRETCH)
    u = body.solve(np.zeros(body.ndofs), dirichlet=bc, steps=2)
    exact_u = body.interpolate(lambda x: np.vstack([(STRETCH - 1.0) * x[0], (l2 - 1.0) * x[1:]]))
    assert np.max(np.abs(u - exact_u)) <= 1e-9 * np.max(np.abs(exact_u))


def test_traction_controlled_stretch_matches_the_nominal_stress():
    """A dead traction t = P_11 on "right" (reference area) gives stretch lambda_1 (rel. 1e-9)."""
    body = Hyperelastic(meshes.rectangle(0.0, L, 0.0, H, 3, 2), Material(E=E, nu=NU), order=2)
    bc = [body.dirichlet("left", components=[0]), body.dirichlet("bottom", components=[1])]
    l2, P11 = _exact("neo-hookean", body.lam, body.mu, 2, STRETCH)
    u = body.solve(body.traction_load("right", [P11, 0.0]), dirichlet=bc, steps=3)
    exact_u = body.interpolate(lambda x: np.vstack([(STRETCH - 1.0) * x[0], (l2 - 1.0) * x[1:]]))
    assert np.max(np.abs(u - exact_u)) <= 1e-9 * np.max(np.abs(exact_u))
