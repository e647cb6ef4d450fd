"""Verification: the mixed u-p body on curved second-order meshes and on bodies of revolution.

1. Curved (isoparametric) P2 geometry (and, in 3D, a curved MeshTet2 cube): homogeneous compression of an incompressible
   neo-Hookean block (the problem of ``test_mixed_incompressible.py``) on a ``MeshTri2`` whose interior
   edge nodes are moved off the midpoints by a smooth bump (curved elements, straight boundary).
   Linear displacements lie in the isoparametric P2 space and the constant pressure in P1, so the
   discrete solution is the exact one: ``F = diag(1/lambda, lambda)``, ``p = mu (I1/3 - lambda^-2)``,
   top force ``mu (lambda - lambda^-3) W``; asserted to 1e-10 relative.
2. Axisymmetric, exact: a solid incompressible neo-Hookean cylinder (radius R, height H, rollers on
   both ends) compressed axially by the stretch ``lambda``. Exact: ``F = diag(a, lambda, a)`` in
   ``(r, z, theta)`` with ``a = lambda^(-1/2)``, ``P_rr = mu (a - I1/(3a)) + p/a = 0`` gives
   ``p = mu (I1/3 - a^2)``, ``I1 = 2 a^2 + lambda^2``, and the total end force (2 pi integrated)
   ``mu (lambda - lambda^-2) pi R^2``. ``u_r = (a - 1) r`` is linear, the hoop stretch ``1 + u_r/r``
   is exactly ``a``: the discrete solution is exact, asserted to 1e-10.
3. Axisymmetric, nearly incompressible against a closed form: Lame's thick cylinder (inner radius a = 1,
   outer b = 2, plane strain through ``u_z = 0`` on both ends, inner pressure ``p_i = 1e-5 E``: the
   linear range) at ``nu = 0.4999`` and ``nu = 0.5``: ``u_r(a) = (1 + nu) p_i a^2 / (E (b^2 - a^2))
   ((1 - 2 nu) a + b^2 / a)`` (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., section 28, with the
   plane-strain constants). Measured relative errors of the mean inner ``u_r``: 4.4e-4, 9.8e-5, 2.6e-5
   at n = 2, 4, 8 radial elements (rate 2; the last includes the 1e-5 of geometric nonlinearity);
   asserted below 5e-4, 1.5e-4, 5e-5 and decreasing at a rate above 1.5.
4. Axisymmetric, against the axisymmetric displacement body at ``nu = 0.45`` (where both work): the
   same thick cylinder at finite deformation (``p_i = 0.1 E``, the split law ``c10 (I1b - 3) + K/2
   (J - 1)^2``): the inner ``u_r`` agree up to the discretization error, measured 1.4e-4, 3.4e-5,
   8.2e-6 at n = 4, 8, 16; asserted below 3e-4, 6e-5, 1.5e-5.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import skfem

from alcontact.fem import Hyperelastic, Material, MooneyRivlin, meshes
from alcontact.fem.mixed import MixedHyperelastic

MU = 1.0


def _curved_rectangle(w, h, nx, ny, amplitude):
    m2 = skfem.MeshTri2.from_mesh(meshes.rectangle(0, w, 0, h, nx, ny))
    p = m2.doflocs.copy()
    nv = int(m2.t.max()) + 1
    bump = amplitude * np.sin(np.pi * p[0, nv:] / w) * np.sin(np.pi * p[1, nv:] / h)
    p[:, nv:] += bump * np.array([[1.0], [0.6]])
    tol = 1e-9 * max(w, h)
    return dataclasses.replace(m2, doflocs=p, _boundaries=None).with_boundaries({
        "left": lambda x: x[0] < tol, "right": lambda x: x[0] > w - tol,
        "bottom": lambda x: x[1] < tol, "top": lambda x: x[1] > h - tol})


@pytest.mark.parametrize("lam", [0.7, 1.3])
def test_incompressible_block_on_curved_mesh_exact(lam):
    W, H = 2.0, 1.0
    mesh = _curved_rectangle(W, H, 4, 3, 0.08)
    body = MixedHyperelastic(mesh, E=3.0 * MU, nu=0.5)
    assert type(body.mesh) is skfem.MeshTri2
    # the elements are curved: some interior edge node is off its edge midpoint by a visible amount
    nv = int(mesh.t.max()) + 1
    mid = 0.5 * (mesh.doflocs[:, mesh.facets[0]] + mesh.doflocs[:, mesh.facets[1]])
    assert np.abs(mesh.doflocs[:, nv:] - mid).max() > 0.05
    top = body.dirichlet("top", [1], (lam - 1.0) * H)
    x = body.solve(np.zeros(body.ndofs_u), [body.dirichlet("left", [0]), body.dirichlet("bottom", [1]), top],
                   steps=3)
    F = body.deformation_gradient(x)
    _, p = body.split(x)
    I1 = lam**-2 + lam**2 + 1.0
    p_exact = MU * (I1 / 3.0 - lam**-2)
    force = float(body.internal_force(x)[top[0]].sum())
    assert np.abs(F[..., 0, 0] - 1.0 / lam).max() <= 1e-10 / lam
    assert np.abs(F[..., 1, 1] - lam).max() <= 1e-10 * lam
    assert np.abs(F[..., 0, 1]).max() <= 1e-10 and np.abs(F[..., 1, 0]).max() <= 1e-10
    assert np.abs(p - p_exact).max() <= 1e-10 * abs(p_exact)
    assert abs(force - MU * (lam - lam**-3) * W) <= 1e-10 * abs(MU * (lam - lam**-3) * W)


def test_incompressible_block_on_curved_tetra10_mesh_exact():
    """3D: a unit cube of ``MeshTet2`` with its interior edge nodes moved (curved tetrahedra), rollers on
    x = 0, y = 0, z = 0, the top y = 1 moved by ``lambda - 1``: ``F = diag(a, lambda, a)``,
    ``a = lambda^(-1/2)``, ``p = mu (I1/3 - a^2)``, top force ``mu (lambda - lambda^-2)``; to 1e-10."""
    lam = 0.8
    m2 = skfem.MeshTet2.from_mesh(skfem.MeshTet.init_tensor(*(np.linspace(0.0, 1.0, 3),) * 3))
    p = m2.doflocs.copy()
    nv = int(m2.t.max()) + 1
    x = p[:, nv:]
    p[:, nv:] += 0.04 * np.prod(np.sin(np.pi * x), axis=0) * np.array([[1.0], [0.6], [-0.8]])
    tol = 1e-9
    mesh = dataclasses.replace(m2, doflocs=p, _boundaries=None).with_boundaries({
        "x0": lambda X: X[0] < tol, "y0": lambda X: X[1] < tol, "z0": lambda X: X[2] < tol,
        "top": lambda X: X[1] > 1 - tol})
    body = MixedHyperelastic(mesh, E=3.0 * MU, nu=0.5)
    assert type(body.mesh) is skfem.MeshTet2 and body.npressure == 27
    top = body.dirichlet("top", [1], lam - 1.0)
    x = body.solve(np.zeros(body.ndofs_u), [body.dirichlet("x0", [0]), body.dirichlet("y0", [1]),
                                            body.dirichlet("z0", [2]), top], steps=2)
    F = body.deformation_gradient(x)
    _, pr = body.split(x)
    a = lam**-0.5
    p_exact = MU * ((2.0 * a * a + lam * lam) / 3.0 - a * a)
    assert np.abs(F - np.diag([a, lam, a])).max() <= 1e-10
    assert np.abs(pr - p_exact).max() <= 1e-10 * abs(p_exact)
    force = MU * (lam - lam**-2)
    assert abs(float(body.internal_force(x)[top[0]].sum()) - force) <= 1e-10 * abs(force)


@pytest.mark.parametrize("lam", [0.7, 1.2])
def test_incompressible_cylinder_axisymmetric_exact(lam):
    R, H = 1.0, 2.0
    body = MixedHyperelastic(meshes.rectangle(0, R, 0, H, 3, 4), E=3.0 * MU, nu=0.5, geometry="axisymmetric")
    top = body.dirichlet("top", [1], (lam - 1.0) * H)
    x = body.solve(np.zeros(body.ndofs_u), [body.dirichlet("bottom", [1]), top], steps=3)
    F = body.deformation_gradient(x)
    _, p = body.split(x)
    a = lam**-0.5
    I1 = 2.0 * a * a + lam * lam
    p_exact = MU * (I1 / 3.0 - a * a)
    force_exact = MU * (lam - lam**-2) * np.pi * R * R  # total over the revolution
    assert F.shape[-2:] == (3, 3)
    assert np.abs(F[..., 0, 0] - a).max() <= 1e-10 * a and np.abs(F[..., 2, 2] - a).max() <= 1e-10 * a
    assert np.abs(F[..., 1, 1] - lam).max() <= 1e-10 * lam
    assert np.abs(F[..., 0, 1]).max() <= 1e-10 and np.abs(F[..., 1, 0]).max() <= 1e-10
    assert np.abs(p - p_exact).max() <= 1e-10 * abs(p_exact)
    assert abs(float(body.internal_force(x)[top[0]].sum()) - force_exact) <= 1e-10 * abs(force_exact)
    assert max(body.newton_iterations) <= 6
    # nodal Cauchy stress: sigma_rr = sigma_hoop = 0 (free mantle), sigma_zz = mu (lambda^2 - a^2)
    s = body.stress(x, include_zz=True)
    scale = MU * max(lam**2, a**2)
    assert np.abs(s[:, 0]).max() <= 1e-9 * scale and np.abs(s[:, 3]).max() <= 1e-9 * scale
    assert np.abs(s[:, 1] - MU * (lam**2 - a * a)).max() <= 1e-9 * scale


A_IN, B_OUT, HEIGHT, E_LAME = 1.0, 2.0, 0.25, 3.0


def _inner_ur(body, x):
    _, dofs = body.node_dofs("left")
    return float(x[dofs[:, 0]].mean())


@pytest.mark.parametrize("nu", [0.4999, 0.5])
def test_lame_cylinder_axisymmetric_nearly_incompressible(nu):
    p_in = 1e-5 * E_LAME
    exact = (1 + nu) * p_in * A_IN**2 / (E_LAME * (B_OUT**2 - A_IN**2)) * ((1 - 2 * nu) * A_IN + B_OUT**2 / A_IN)
    errors = []
    for n in (2, 4, 8):
        body = MixedHyperelastic(meshes.rectangle(A_IN, B_OUT, 0, HEIGHT, n, 1), E=E_LAME, nu=nu,
                                 geometry="axisymmetric")
        x = body.solve(body.pressure_load("left", p_in), [body.dirichlet("bottom", [1]), body.dirichlet("top", [1])])
        errors.append(abs(_inner_ur(body, x) / exact - 1.0))
    assert errors[0] < 5e-4 and errors[1] < 1.5e-4 and errors[2] < 5e-5, errors
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(rates > 1.5), rates


def test_axisymmetric_mixed_matches_displacement_at_moderate_nu():
    nu = 0.45
    law = MooneyRivlin(c10=E_LAME / (4.0 * (1.0 + nu)))  # mu / 2: the split law of both bodies
    diffs = []
    for n in (4, 8, 16):
        mesh = meshes.rectangle(A_IN, B_OUT, 0, HEIGHT, n, 1)
        fixed = [("bottom", [1]), ("top", [1])]
        ur = []
        for body in (MixedHyperelastic(mesh, E=E_LAME, nu=nu, model=law, geometry="axisymmetric"),
                     Hyperelastic(mesh, Material(E_LAME, nu), order=2, model=law, geometry="axisymmetric")):
            x = body.solve(body.pressure_load("left", 0.1 * E_LAME), [body.dirichlet(*f) for f in fixed], steps=2)
            ur.append(_inner_ur(body, x))
        assert ur[1] > 0.2 * A_IN  # finite deformation: a 21 % radial displacement of the bore
        diffs.append(abs(ur[0] / ur[1] - 1.0))
    assert diffs[0] < 3e-4 and diffs[1] < 6e-5 and diffs[2] < 1.5e-5, diffs
