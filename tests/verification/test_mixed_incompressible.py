"""Verification of the mixed u-p (Taylor-Hood P2/P1) hyperelastic body.

1. Homogeneous plane-strain compression of a neo-Hookean block between frictionless rigid
   planes (rollers on "bottom" and "top", symmetry roller on "left", "right" traction free),
   top displacement ``(lambda - 1) H``. The exact solution is ``F = diag(a, lambda, 1)``:

   * incompressible (``nu = 0.5``): ``a = 1/lambda``, pressure (Lagrange multiplier, the
     hydrostatic Cauchy stress) from ``P_xx = 0``: ``p = mu (I1/3 - lambda^-2)`` with
     ``I1 = lambda^-2 + lambda^2 + 1``, nominal stress ``P_yy = mu (lambda - lambda^-3)``, force
     on the top ``P_yy W`` per unit thickness;
   * compressible (``nu = 0.45``, ``p = kappa (J - 1)``): ``a`` is the root of
     ``P_xx = mu J^(-2/3) (a - I1/(3a)) + p J / a = 0`` (brentq to 1e-15), ``J = a lambda``.

   Linear displacements and a constant pressure lie in P2/P1: the discrete solution is
   exact, asserted to 1e-10 relative (deformation gradient, pressure, reaction force).

2. Locking: Cook's membrane (trapezoid (0,0), (48,44), (48,60), (0,44); "left" clamped;
   uniform vertical shear traction 6.25 on the right edge, total 100; E = 250, nu = 0.4999,
   plane strain), linear elastic regime: the system is the mixed body's tangent at the
   reference state, which is the linear elastic Taylor-Hood system. Reference tip
   displacement ``u_y(48, 60) = 7.771``: there is no closed form; this value is bracketed by
   two independent discretizations, the P2-P0 element of ``LinearElasticity`` (converging
   from above: 7.7863, 7.7788, 7.7750 at n = 32, 64, 128, Richardson extrapolation at rate 1:
   7.7713) and the mixed element (from below: 7.7348, 7.7540 at n = 32, 64, extrapolated
   7.770). (The often-quoted 23.96 is the compressible plane-stress Cook membrane, E = 1,
   nu = 1/3, F = 1: a different problem.) The tests assert: the mixed tip displacement
   increases monotonically with refinement, its successive differences shrink, it is within
   1% of the reference at n = 32 and bracketed with P2-P0; the pure-displacement P1 body on
   the same meshes stays below 35% of the reference (locked).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from scipy.optimize import brentq

from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.fem.mixed import MixedHyperelastic

MU = 1.0
W_BLOCK, H_BLOCK = 2.0, 1.0


def _compress(nu, lam, steps=2):
    E = 2.0 * MU * (1.0 + nu)
    body = MixedHyperelastic(meshes.rectangle(0, W_BLOCK, 0, H_BLOCK, 4, 3), E=E, nu=nu)
    top = body.dirichlet("top", [1], (lam - 1.0) * H_BLOCK)
    x = body.solve(np.zeros(body.ndofs_u), [body.dirichlet("left", [0]), body.dirichlet("bottom", [1]), top],
                   steps=steps)
    reaction = float(body.internal_force(x)[top[0]].sum())
    return body, x, reaction


@pytest.mark.parametrize("lam", [0.7, 0.5, 1.3])
def test_incompressible_block_compression_exact(lam):
    body, x, reaction = _compress(0.5, lam, steps=3)
    F = body.deformation_gradient(x)
    _, p = body.split(x)
    I1 = lam**-2 + lam**2 + 1.0
    p_exact = MU * (I1 / 3.0 - lam**-2)
    force_exact = MU * (lam - lam**-3) * W_BLOCK
    assert np.abs(F[..., 0, 0] - 1.0 / lam).max() <= 1e-10 / lam
    assert np.abs(F[..., 1, 1] - lam).max() <= 1e-10 * lam
    assert np.abs(F[..., 0, 1]).max() <= 1e-10 and np.abs(F[..., 1, 0]).max() <= 1e-10
    assert np.abs(np.linalg.det(F) - 1.0).max() <= 1e-10
    assert np.abs(p - p_exact).max() <= 1e-10 * abs(p_exact)
    assert abs(reaction - force_exact) <= 1e-10 * abs(force_exact)
    assert max(body.newton_iterations) <= 6  # quadratic convergence from the consistent tangent
    # nodal Cauchy stress (L2 projection of an exact constant field): sigma_xx = 0 (free sides),
    # sigma_yy = P_yy lambda / J = mu (lambda^2 - lambda^-2), sigma_xy = 0, sigma_zz = mu (1 - I1/3) + p
    s = body.stress(x, include_zz=True)
    scale = MU * max(lam**2, lam**-2)
    assert np.abs(s[:, 0]).max() <= 1e-9 * scale
    assert np.abs(s[:, 1] - MU * (lam**2 - lam**-2)).max() <= 1e-9 * scale
    assert np.abs(s[:, 2]).max() <= 1e-9 * scale
    assert np.abs(s[:, 3] - (MU * (1.0 - I1 / 3.0) + p_exact)).max() <= 1e-9 * scale


def test_compressible_block_compression_exact():
    nu, lam = 0.45, 0.7
    kappa = 2.0 * MU * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))

    def pxx(a):
        J = a * lam
        I1 = a * a + lam * lam + 1.0
        return MU * J ** (-2.0 / 3.0) * (a - I1 / (3.0 * a)) + kappa * (J - 1.0) * J / a

    a = brentq(pxx, 0.5, 3.0, xtol=1e-15, rtol=1e-15)
    J = a * lam
    I1 = a * a + lam * lam + 1.0
    pyy = MU * J ** (-2.0 / 3.0) * (lam - I1 / (3.0 * lam)) + kappa * (J - 1.0) * J / lam
    body, x, reaction = _compress(nu, lam)
    F = body.deformation_gradient(x)
    _, p = body.split(x)
    assert np.abs(F[..., 0, 0] - a).max() <= 1e-10 * a
    assert np.abs(F[..., 1, 1] - lam).max() <= 1e-10
    assert np.abs(p - kappa * (J - 1.0)).max() <= 1e-10 * abs(kappa * (J - 1.0))
    assert abs(reaction - pyy * W_BLOCK) <= 1e-10 * abs(pyy * W_BLOCK)


# ------------------------------------------------------------------------ Cook's membrane
COOK_REFERENCE = 7.771  # see the module doc: bracketed by P2-P0 (above) and the mixed element (below)
COOK_E, COOK_NU, COOK_TRACTION = 250.0, 0.4999, 6.25


def _cook_mesh(n):
    m = meshes.rectangle(0, 1, 0, 1, n, n)
    xi, eta = m.p
    return dataclasses.replace(m, doflocs=np.stack([48.0 * xi, 44.0 * xi + eta * (44.0 - 28.0 * xi)]))


def _tip(body, x):
    pts, dofs = body.node_dofs("right")
    i = int(np.argmin(np.hypot(pts[:, 0] - 48.0, pts[:, 1] - 60.0)))
    assert np.hypot(pts[i, 0] - 48.0, pts[i, 1] - 60.0) < 1e-9
    return float(x[dofs[i, 1]])


def _cook_mixed(n):
    body = MixedHyperelastic(_cook_mesh(n), E=COOK_E, nu=COOK_NU)
    f = body.pad(body.traction_load("right", [0.0, COOK_TRACTION]))
    fixed = body.dirichlet("left")[0]
    free = np.setdiff1d(np.arange(body.ndofs), fixed)
    K = body.tangent(np.zeros(body.ndofs)).tocsc()  # linearization at the reference state
    x = np.zeros(body.ndofs)
    x[free] = spla.spsolve(K[free][:, free], f[free])
    return _tip(body, x)


def _cook_displacement(n, order, volumetric="full"):
    body = LinearElasticity(_cook_mesh(n), Material(COOK_E, COOK_NU), order=order, volumetric=volumetric)
    u = body.solve(body.traction_load("right", [0.0, COOK_TRACTION]), [body.dirichlet("left")])
    return _tip(body, u)


def test_cook_membrane_mixed_converges_where_p1_locks():
    ns = (8, 16, 32)
    mixed = [_cook_mixed(n) for n in ns]
    p1 = [_cook_displacement(n, 1) for n in ns]
    diffs = np.diff(mixed)
    assert np.all(diffs > 0) and diffs[1] < 0.6 * diffs[0]  # monotone, converging
    assert abs(mixed[-1] - COOK_REFERENCE) <= 0.01 * COOK_REFERENCE
    upper = _cook_displacement(32, 2, "p0")
    assert mixed[-1] < COOK_REFERENCE < upper and upper - mixed[-1] <= 0.01 * COOK_REFERENCE
    assert max(p1) < 0.35 * COOK_REFERENCE  # locked: about a quarter of the answer


def test_cook_membrane_small_load_matches_linear():
    """The nonlinear solve at a small load (1e-3 of the above) reproduces the linearized answer."""
    body = MixedHyperelastic(_cook_mesh(8), E=COOK_E, nu=COOK_NU)
    s = 1e-3
    x = body.solve(body.traction_load("right", [0.0, s * COOK_TRACTION]), [body.dirichlet("left")])
    assert abs(_tip(body, x) / s - _cook_mixed(8)) <= 2e-3 * _cook_mixed(8)
    assert body.newton_iterations[0] <= 4
