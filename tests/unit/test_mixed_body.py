"""Unit tests of the mixed u-p hyperelastic body (:mod:`alcontact.fem.mixed`).

The consistent tangent is checked against central finite differences of the residual
(step 1e-6, relative tolerance 1e-7 of the largest entry: the truncation error is
O(h^2) ~ 1e-12 and round-off O(eps/h) ~ 1e-10), and the residual against finite
differences of the two-field functional, at random states with finite and infinite bulk
modulus and for two laws.
"""

from __future__ import annotations

import numpy as np
import pytest
import skfem

from alcontact.errors import InputError
from alcontact.fem import MooneyRivlin, meshes
from alcontact.fem.mixed import MixedHyperelastic


def _random_state(body, seed=0):
    rng = np.random.default_rng(seed)
    return np.concatenate([0.05 * rng.standard_normal(body.ndofs_u), 0.3 * rng.standard_normal(body.npressure)])


def _fd_columns(fun, x, h=1e-6):
    cols = []
    for j in range(x.size):
        e = np.zeros(x.size)
        e[j] = h
        cols.append((fun(x + e) - fun(x - e)) / (2 * h))
    return np.stack(cols, axis=-1)


@pytest.mark.parametrize("nu", [0.5, 0.4999, 0.45])
@pytest.mark.parametrize("model", ["neo-hookean", MooneyRivlin(c10=0.35, c01=0.15)])
def test_tangent_matches_finite_differences(nu, model):
    mesh = meshes.rectangle(0, 1, 0, 1, 2, 2)
    body = MixedHyperelastic(mesh, E=2.0 * (1 + nu), nu=nu, model=model)  # mu = 1 = 2 (c10 + c01)
    x = _random_state(body)
    K = body.tangent(x).toarray()
    Kfd = _fd_columns(body.internal_force, x)
    assert np.abs(K - Kfd).max() <= 1e-7 * np.abs(K).max()
    assert np.array_equal(K, K.T)
    # a saddle point: the tangent is indefinite (pressure block)
    eig = np.linalg.eigvalsh(K)
    assert eig.min() < 0 < eig.max()


def test_residual_is_gradient_of_functional():
    body = MixedHyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), E=3.0, nu=0.45)
    x = _random_state(body, 1)
    g = _fd_columns(lambda v: np.array([body.functional(v)]), x)[0]
    assert np.abs(g - body.internal_force(x)).max() <= 1e-7 * np.abs(g).max()


def test_tangent_3d_matches_finite_differences():
    mesh = skfem.MeshTet.init_tensor(np.linspace(0, 1, 2), np.linspace(0, 1, 2), np.linspace(0, 1, 2))
    body = MixedHyperelastic(mesh, E=3.0, nu=0.5)
    x = _random_state(body, 2)
    K = body.tangent(x).toarray()
    assert np.abs(K - _fd_columns(body.internal_force, x)).max() <= 1e-7 * np.abs(K).max()


def test_layout_and_split():
    body = MixedHyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), E=3.0, nu=0.5)
    assert (body.ndofs_u, body.npressure, body.ndofs) == (50, 9, 59)
    x = np.arange(body.ndofs, dtype=float)
    u, p = body.split(x)
    assert u.shape == (50,) and p.shape == (9,) and p[0] == 50.0
    assert body.pad(np.ones(50)).shape == (59,)
    assert np.isinf(body.kappa) and body.mu == pytest.approx(1.0)


@pytest.mark.parametrize("kwargs, words", [
    (dict(E=3.0, nu=0.6), ["nu", "0.5"]),
    (dict(E=-1.0, nu=0.5), ["E"]),
    (dict(E=3.0, nu=0.5, model="saint-venant-kirchhoff"), ["split", "displacement"]),
    (dict(E=3.0, nu=0.5, model=MooneyRivlin(c10=2.0)), ["shear modulus", "E ="]),
])
def test_bad_input_is_named(kwargs, words):
    with pytest.raises(InputError) as info:
        MixedHyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), **kwargs)
    for w in words:
        assert w in str(info.value)


@pytest.mark.parametrize("name", ["superlu", "mkl-pardiso"])
def test_named_indefinite_solver_runs(name):
    from alcontact.linalg import is_installed

    if not is_installed(name):
        pytest.skip(f"{name} not installed")
    body = MixedHyperelastic(meshes.rectangle(0, 1, 0, 1, 3, 3), E=3.0, nu=0.5, linear_solver=name)
    x = body.solve(body.traction_load("right", [0.2, 0.05]), [body.dirichlet("left")], steps=2)
    assert body.linear_solver_used == name
    assert body.linear_solves == sum(body.newton_iterations) > 0
    r = body.internal_force(x) - body.pad(body.traction_load("right", [0.2, 0.05]))
    free = np.setdiff1d(np.arange(body.ndofs), body.dirichlet("left")[0])
    assert np.linalg.norm(r[free]) <= 1e-9 * np.linalg.norm(body.traction_load("right", [0.2, 0.05]))


def test_energy_is_no_merit():
    """A saddle-point functional is no line-search merit: ``energy`` is nan (Body protocol), ``functional`` finite."""
    body = MixedHyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), E=3.0, nu=0.5)
    x = _random_state(body, 0)
    assert np.isnan(body.energy(x)) and np.isfinite(body.functional(x))


def test_failures_are_named():
    from alcontact.errors import ConvergenceError, NonFiniteError

    body = MixedHyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), E=3.0, nu=0.5)
    with pytest.raises(NonFiniteError):
        body.internal_force(np.full(body.ndofs, np.nan))
    with pytest.raises(InputError, match="shape"):
        body.tangent(np.zeros(3))
    with pytest.raises(ConvergenceError, match="load steps"):  # one Newton iteration cannot reach 1e-10
        body.solve(body.traction_load("right", [0.5, 0.2]), [body.dirichlet("left")], max_iter=1)


def _curved_square(n=2, amplitude=0.06):
    """A second-order mesh of the unit square whose interior edge nodes are moved off the edge
    midpoints (curved elements, straight boundary), with the rectangle's boundary names."""
    import dataclasses

    m2 = skfem.MeshTri2.from_mesh(meshes.rectangle(0, 1, 0, 1, n, n))
    p = m2.doflocs.copy()
    nv = int(m2.t.max()) + 1
    bump = amplitude * np.sin(np.pi * p[0, nv:]) * np.sin(np.pi * p[1, nv:])
    p[:, nv:] += bump * np.array([[1.0], [0.6]])
    tol = 1e-9
    return dataclasses.replace(m2, doflocs=p, _boundaries=None).with_boundaries({
        "left": lambda x: x[0] < tol, "right": lambda x: x[0] > 1 - tol,
        "bottom": lambda x: x[1] < tol, "top": lambda x: x[1] > 1 - tol})


@pytest.mark.parametrize("nu", [0.5, 0.45])
@pytest.mark.parametrize("model", ["neo-hookean", MooneyRivlin(c10=0.35, c01=0.15)])
def test_axisymmetric_tangent_matches_finite_differences(nu, model):
    """Body of revolution: the hoop terms of the residual and tangent (3x3 F, 2 pi r weights)."""
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2)  # touches the axis r = 0
    body = MixedHyperelastic(mesh, E=2.0 * (1 + nu), nu=nu, model=model, geometry="axisymmetric")
    assert body.axisymmetric and body.intorder == 4 and body.axis_dofs.size == 5
    x = _random_state(body, 3)
    # a smooth nonlinear displacement with u_r = 0 on the axis (the hoop stretch 1 + u_r / r stays positive)
    x[: body.ndofs_u] = body.interpolate(lambda X: np.stack([X[0] * (0.1 * np.sin(2 * X[1]) - 0.05 * X[0]),
                                                             0.08 * X[0] ** 2 - 0.1 * X[1] * X[0]]))
    assert body.deformation_gradient(x).shape[-2:] == (3, 3)
    K = body.tangent(x).toarray()
    assert np.abs(K - _fd_columns(body.internal_force, x)).max() <= 1e-7 * np.abs(K).max()
    assert np.array_equal(K, K.T)
    g = _fd_columns(lambda v: np.array([body.functional(v)]), x)[0]
    assert np.abs(g - body.internal_force(x)).max() <= 1e-7 * np.abs(g).max()


def test_axisymmetric_weights_are_the_revolved_volume():
    """The pressure rows at x = 0 are -(1/kappa) int p q dV = 0 and at p = 0 give int (J - 1) q 2 pi r dr dz:
    with a uniform radial stretch u_r = e r (J = (1 + e)^2), their sum is ((1 + e)^2 - 1) pi R^2 H."""
    R, H, e = 2.0, 0.5, 0.01
    body = MixedHyperelastic(meshes.rectangle(0.0, R, 0.0, H, 3, 2), E=3.0, nu=0.5, geometry="axisymmetric")
    x = np.zeros(body.ndofs)
    x[: body.ndofs_u] = body.interpolate(lambda X: np.stack([e * X[0], 0.0 * X[1]]))
    rp = body.internal_force(x)[body.ndofs_u:]
    assert rp.sum() == pytest.approx(((1 + e) ** 2 - 1) * np.pi * R**2 * H, rel=1e-12)


def test_curved_mesh_keeps_its_map():
    mesh = _curved_square()
    body = MixedHyperelastic(mesh, E=3.0, nu=0.5)
    assert type(body.mesh) is skfem.MeshTri2 and body.intorder == 4
    assert body.npressure == 9 and body.ndofs_u == 50  # pressure on the vertices only
    x = _random_state(body, 4)
    x[: body.ndofs_u] *= 0.3  # the curved elements' gradients are larger: keep J > 0
    K = body.tangent(x).toarray()
    assert np.abs(K - _fd_columns(body.internal_force, x)).max() <= 1e-7 * np.abs(K).max()
    # the measure is the curved map's: the area is still 1 (interior nodes moved, boundary straight)
    assert float(body.pressure_basis.dx.sum()) == pytest.approx(1.0, rel=1e-12)
