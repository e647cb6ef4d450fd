"""Axisymmetric hyperelastic bodies (finite deformation) against closed forms and the 3D model.

- Consistency: the axisymmetric neo-Hookean tangent at u = 0 is the axisymmetric linear stiffness (to
  round-off); internal force and tangent against central finite differences of the energy and the force
  (relative 1e-6).
- Homogeneous deformation of a solid cylinder, u_r = (l_r - 1) r, u_z = (l_z - 1) z: linear in the
  coordinates, so exact for P1; the 3x3 F = diag(l_r, l_z, l_r) (hoop stretch 1 + u_r/r = l_r). The
  internal force vanishes at interior nodes and the axial force on the top face is the closed form
  P_zz(F) * pi R^2 (total over the revolution), P the neo-Hookean first Piola-Kirchhoff stress
  mu (F - F^-T) + lam ln J F^-T; tolerance 1e-10 relative.
- Neo-Hookean hemisphere on a plane at delta/R = 0.25 (P2, curved): the axisymmetric force against the 3D
  quarter model of the same ball (times 4). Measured (docs/benchmarks/axisym.md): axisymmetric n = 16
  257.604, n = 64 257.575; 3D quarter n = 6 257.877, n = 8 257.487. Here the 3D n = 6 mesh (the
  finer one costs 15 s) within 2e-3 of the axisymmetric n = 32, and the axisymmetric mesh converged
  (n = 16 against n = 32 within 2e-4).
"""

import numpy as np
import pytest

from alcontact.contact import solve_finite
from alcontact.fem import Hyperelastic, LinearElasticity, Material, meshes
from alcontact.problems.hemisphere import hemisphere, hemisphere_axisym

MAT = Material(E=10.0, nu=0.3)


@pytest.mark.parametrize("order", [1, 2])
def test_tangent_at_rest_is_the_linear_stiffness_and_derivatives_are_consistent(order):
    mesh = meshes.rectangle(0, 1, 0, 1, 3, 3)
    body = Hyperelastic(mesh, MAT, order=order, geometry="axisymmetric")
    lin = LinearElasticity(mesh, MAT, order=order, geometry="axisymmetric")
    K0, KL = body.stiffness(), lin.stiffness()
    assert abs(K0 - KL).max() <= 1e-13 * abs(KL).max()
    rng = np.random.default_rng(0)
    u = 0.01 * rng.standard_normal(body.ndofs)
    u[body.axis_dofs] = 0.0
    du = rng.standard_normal(body.ndofs)
    eps = 1e-6
    fd_force = (body.internal_force(u + eps * du) - body.internal_force(u - eps * du)) / (2 * eps)
    assert np.abs(body.tangent(u) @ du - fd_force).max() <= 1e-6 * np.abs(fd_force).max()
    fd_energy = (body.energy(u + eps * du) - body.energy(u - eps * du)) / (2 * eps)
    assert abs(body.internal_force(u) @ du - fd_energy) <= 1e-6 * abs(fd_energy)


def test_homogeneous_stretch_of_a_cylinder_matches_the_closed_form():
    lr, lz, R, H = 0.9, 1.2, 1.0, 2.0
    body = Hyperelastic(meshes.rectangle(0, R, 0, H, 4, 6), MAT, geometry="axisymmetric")
    u = body.interpolate(lambda x: np.stack([(lr - 1) * x[0], (lz - 1) * x[1]]))
    F = body.deformation_gradient(u)
    np.testing.assert_allclose(F[..., 2, 2], lr, rtol=1e-12)
    lam, mu = MAT.lame(3)
    J = lr * lr * lz
    Pzz = mu * (lz - 1 / lz) + lam * np.log(J) / lz
    f = body.internal_force(u)
    pts, dofs = body.all_node_dofs()
    interior = (pts[:, 0] > 1e-12) & (pts[:, 0] < R - 1e-12) & (pts[:, 1] > 1e-12) & (pts[:, 1] < H - 1e-12)
    assert np.abs(f[dofs[interior]]).max() <= 1e-10 * abs(Pzz)
    _, top = body.node_dofs("top")
    assert f[top[:, 1]].sum() == pytest.approx(Pzz * np.pi * R * R, rel=1e-10)
    # stress output: sigma_zz = P_zz F_zz / J and the hoop sigma_tt = sigma_rr
    s = body.stress(u, include_zz=True)
    np.testing.assert_allclose(s[:, 1], Pzz * lz / J, rtol=1e-8)
    np.testing.assert_allclose(s[:, 3], s[:, 0], rtol=1e-8)


@pytest.mark.slow
def test_hemisphere_axisymmetric_matches_the_3d_quarter_model():
    ax16 = solve_finite(hemisphere_axisym(16, order=2, delta=0.25), steps=10)
    ax32 = solve_finite(hemisphere_axisym(32, order=2, delta=0.25), steps=10)
    q = solve_finite(hemisphere(6, order=2, delta=0.25), steps=10)
    assert ax16.success and ax32.success and q.success
    f16, f32, f3d = ax16.forces[-1, 1], ax32.forces[-1, 1], 4.0 * q.forces[-1, 1]
    assert abs(f16 / f32 - 1) <= 2e-4, (f16, f32)
    assert abs(f3d / f32 - 1) <= 2e-3, (f3d, f32)
