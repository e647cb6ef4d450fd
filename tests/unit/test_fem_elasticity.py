"""Unit tests of alcontact.fem: Material, LinearElasticity, Factorization."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from _helpers import assert_rigid_modes_in_kernel
from alcontact.errors import InputError, MeshError
from alcontact.fem import Factorization, LinearElasticity, Material, meshes, nested_dissection

E, NU, S = 200.0, 0.3, 2.5  # modulus, Poisson ratio, applied tension


# ------------------------------------------------------------------ Material
@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(E=0.0, nu=0.3), "E=0.0"),
        (dict(E=-1.0, nu=0.3), "> 0"),
        (dict(E=float("inf"), nu=0.3), "finite"),
        (dict(E=1.0, nu=0.5), "-1 < nu < 0.5"),
        (dict(E=1.0, nu=-1.0), "nu=-1.0"),
        (dict(E=1.0, nu=float("nan")), "nu=nan"),
        (dict(E=1.0, nu=0.3, plane="axisymmetric"), "'strain', 'stress'"),
        (dict(E="steel", nu=0.3), "numbers"),
    ],
)
def test_material_validation(kwargs, match):
    with pytest.raises(InputError, match=match):
        Material(**kwargs)


def test_material_constants():
    m = Material(E=E, nu=NU)
    lam, mu = m.lame(3)
    assert lam == pytest.approx(E * NU / ((1 + NU) * (1 - 2 * NU)))
    assert mu == pytest.approx(E / (2 * (1 + NU)))
    assert m.lame(2) == m.lame(3)
    lam_s, mu_s = Material(E=E, nu=NU, plane="stress").lame(2)
    assert lam_s == pytest.approx(2 * lam * mu / (lam + 2 * mu))
    assert mu_s == pytest.approx(mu)
    assert Material(E=E, nu=NU, plane="stress").lame(3) == (lam, mu)  # plane ignored in 3D
    assert m.plane_strain_modulus == pytest.approx(E / (1 - NU**2))
    with pytest.raises(Exception):
        m.E = 3.0  # frozen


# ------------------------------------------------------------ helpers
def _graded_rectangle():
    return meshes.rectangle(0.0, 2.0, 0.0, 1.0, 4, 3,
                            refine=dict(center=(0.7, 1.0), h_min=0.1, width=0.2, depth=0.2, growth=1.5))


def _model(dim, order, plane="strain"):
    mesh = _graded_rectangle() if dim == 2 else meshes.box(0.0, 2.0, 0.0, 1.0, 0.0, 1.0, 3, 2, 2)
    return LinearElasticity(mesh, Material(E=E, nu=NU, plane=plane), order=order)


def _symmetry_supports(model):
    names = ["left", "bottom"] if model.dim == 2 else ["left", "front", "bottom"]
    return [model.dirichlet(n, components=[c]) for c, n in enumerate(names)]


def _exact_tension(model):
    """Linear displacement of uniaxial tension S in x with symmetry supports."""
    if model.dim == 3 or model.material.plane == "stress":
        exx, eyy = S / E, -NU * S / E
    else:
        exx, eyy = (1 - NU**2) * S / E, -NU * (1 + NU) * S / E
    return lambda x: np.array([exx * x[0]] + [eyy * x[i] for i in range(1, model.dim)])


CASES = [(2, 1, "strain"), (2, 1, "stress"), (2, 2, "strain"), (2, 2, "stress"), (3, 1, "strain"), (3, 2, "strain")]


# ------------------------------------------------------------ patch tests
@pytest.mark.parametrize("dim, order, plane", CASES)
def test_uniaxial_tension_patch(dim, order, plane):
    model = _model(dim, order, plane)
    traction = np.zeros(dim)
    traction[0] = S
    u = model.solve(model.traction_load("right", traction), dirichlet=_symmetry_supports(model))
    u_exact = model.interpolate(_exact_tension(model))
    assert np.max(np.abs(u - u_exact)) <= 1e-10 * np.max(np.abs(u_exact))
    # nodal stress equals the applied traction
    sig = model.stress(u)
    expected = np.zeros(sig.shape[1])
    expected[0] = S
    assert np.allclose(sig, expected, atol=1e-9 * S)
    vm = model.von_mises(u)
    if dim == 3 or plane == "stress":
        assert np.allclose(vm, S, rtol=1e-9)
    else:  # plane strain: szz = nu * S
        szz = model.stress(u, include_zz=True)[:, 3]
        assert np.allclose(szz, NU * S, rtol=1e-9)
        assert np.allclose(vm, S * np.sqrt(1 - NU + NU**2), rtol=1e-9)


@pytest.mark.parametrize("dim, order, plane", CASES)
def test_pressure_patch_and_resultants(dim, order, plane):
    """A pressure p on 'right' is a traction -p n = (-p, 0[, 0]): same as tension -p."""
    model = _model(dim, order, plane)
    f_p = model.pressure_load("right", -S)
    traction = np.zeros(dim)
    traction[0] = S
    assert np.allclose(f_p, model.traction_load("right", traction), atol=1e-12)
    _, dofs = model.all_node_dofs()
    # resultant of a pressure on the top = -p * area * e_top
    f_top = model.pressure_load("top", 3.0)
    area = 2.0
    resultant = f_top[dofs].sum(axis=0)
    expected = np.zeros(dim)
    expected[-1] = -3.0 * area
    assert np.allclose(resultant, expected)
    # body force resultant = f * volume
    f = np.arange(1.0, dim + 1.0)
    volume = 2.0
    assert np.allclose(model.body_load(f)[dofs].sum(axis=0), f * volume)
    # callable traction equals constant
    trac_fun = model.traction_load("top", lambda x: np.stack([np.ones_like(x[0])] + [np.zeros_like(x[0])] * (dim - 1)))
    trac_const = model.traction_load("top", np.eye(dim)[0])
    assert np.allclose(trac_fun, trac_const)


def _timoshenko(P=1.0, L=4.0, D=1.0, E_=1000.0, nu=0.25):
    """Exact plane-stress cantilever under an end shear load (Timoshenko & Goodier)."""
    I = D**3 / 12.0

    def u(x):
        X, Y = x[0], x[1]
        ux = -P * Y / (6 * E_ * I) * ((6 * L - 3 * X) * X + (2 + nu) * (Y**2 - D**2 / 4))
        uy = P / (6 * E_ * I) * (3 * nu * Y**2 * (L - X) + (4 + 5 * nu) * D**2 * X / 4 + (3 * L - X) * X**2)
        return np.array([ux, uy])

    def traction_right(x):  # sigma . (1, 0) at x = L: (sigma_xx = 0, tau_xy)
        Y = x[1]
        return np.stack([np.zeros_like(Y), P / (2 * I) * (D**2 / 4 - Y**2)])

    return u, traction_right


@pytest.mark.parametrize("order, n, tol", [(1, 8, 0.1), (2, 4, 2e-4), (2, 8, 2e-5)])
def test_cantilever_timoshenko(order, n, tol):
    L, D = 4.0, 1.0
    u_ex, trac = _timoshenko(L=L, D=D)
    model = LinearElasticity(meshes.rectangle(0.0, L, -D / 2, D / 2, 4 * n, n),
                             Material(E=1000.0, nu=0.25, plane="stress"), order=order)
    bc = model.dirichlet("left", value=u_ex)
    u = model.solve(model.traction_load("right", trac), dirichlet=[bc])
    ref = model.interpolate(u_ex)
    err = np.max(np.abs(u - ref)) / np.max(np.abs(ref))
    assert err < tol


def test_cantilever_p2_converges_at_third_order():
    L, D = 4.0, 1.0
    u_ex, trac = _timoshenko(L=L, D=D)
    errs = []
    for n in (2, 4, 8):
        model = LinearElasticity(meshes.rectangle(0.0, L, -D / 2, D / 2, 4 * n, n),
                                 Material(E=1000.0, nu=0.25, plane="stress"), order=2)
        u = model.solve(model.traction_load("right", trac), dirichlet=[model.dirichlet("left", value=u_ex)])
        ref = model.interpolate(u_ex)
        errs.append(np.max(np.abs(u - ref)))
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(rates > 2.5), rates


# ------------------------------------------------------------ DOFs, weights
@pytest.mark.parametrize("dim, order", [(2, 1), (2, 2), (3, 1), (3, 2)])
def test_node_dofs_and_weights(dim, order):
    if dim == 2:
        model = LinearElasticity(meshes.rectangle(0.0, 2.0, 0.0, 1.0, 4, 2), Material(E=E, nu=NU), order=order)
        n_top = 4 * order + 1
        measure = 2.0
    else:
        model = LinearElasticity(meshes.box(0.0, 2.0, 0.0, 1.0, 0.0, 1.0, 2, 2, 2), Material(E=E, nu=NU), order=order)
        n_top = (2 * order + 1) ** 2
        measure = 2.0
    pts, dofs = model.node_dofs("top")
    assert pts.shape == (n_top, dim) and dofs.shape == (n_top, dim)
    assert np.allclose(pts[:, -1], 1.0)
    assert len(np.unique(dofs)) == dofs.size
    # doflocs of the vector basis agree with the points, for every component
    for c in range(dim):
        assert np.allclose(model.basis.doflocs[:, dofs[:, c]].T, pts)
    if order == 2:  # midside locations are present
        vertices = model.mesh.p.T
        is_vertex = (np.linalg.norm(pts[:, None, :] - vertices[None], axis=2) < 1e-12).any(axis=1)
        assert (~is_vertex).sum() > 0
    w = model.boundary_weights("top")
    assert w.shape == (n_top,)
    assert w.sum() == pytest.approx(measure)
    assert np.all(w > 0)
    all_pts, all_dofs = model.all_node_dofs()
    assert all_dofs.size == model.ndofs and np.array_equal(np.sort(all_dofs.ravel()), np.arange(model.ndofs))


def test_weights_on_graded_mesh_sum_to_length():
    model = LinearElasticity(_graded_rectangle(), Material(E=E, nu=NU), order=2)
    assert model.boundary_weights("top").sum() == pytest.approx(2.0)
    assert model.boundary_weights("left").sum() == pytest.approx(1.0)


def test_weights_3d_p2_subtriangulation():
    model = LinearElasticity(meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 1, 1, 1), Material(E=E, nu=NU), order=2)
    pts, _ = model.node_dofs("top")
    w = model.boundary_weights("top")
    # two faces of area 1/2: corners on the diagonal get 2 * (1/2)/12, others 1/24; midpoints 1/8 or 2/8
    vertex = np.isin(np.round(pts[:, 0], 12), [0.0, 1.0]) & np.isin(np.round(pts[:, 1], 12), [0.0, 1.0])
    assert np.allclose(np.sort(w[vertex]), [1 / 24, 1 / 24, 1 / 12, 1 / 12])
    assert w.sum() == pytest.approx(1.0)


# ------------------------------------------------------------ errors
def test_unknown_boundary_name():
    model = _model(2, 1)
    with pytest.raises(MeshError, match=r"boundary 'nope' not found; known: bottom, left, right, top"):
        model.facets("nope")
    with pytest.raises(MeshError, match="nope"):
        model.dirichlet("nope")
    with pytest.raises(MeshError, match="nope"):
        model.traction_load("nope", [1.0, 0.0])


def test_bad_arguments():
    model = _model(2, 1)
    with pytest.raises(InputError, match="components"):
        model.dirichlet("left", components=[2])
    with pytest.raises(InputError, match="traction"):
        model.traction_load("top", [1.0, 2.0, 3.0])
    with pytest.raises(InputError, match="order"):
        LinearElasticity(model.mesh, model.material, order=3)
    with pytest.raises(MeshError, match="MeshLine"):
        LinearElasticity(meshes.interval(0, 1, 3), model.material)


def test_dirichlet_values():
    model = _model(2, 2)
    dofs, vals = model.dirichlet("top", components=[1], value=lambda x: np.array([x[0], 2 * x[0]]))
    pts, nd = model.node_dofs("top")
    assert np.array_equal(dofs, nd[:, 1])
    assert np.allclose(vals, 2 * pts[:, 0])
    dofs, vals = model.dirichlet("left", value=[1.0, -1.0])
    assert np.allclose(vals.reshape(-1, 2), [1.0, -1.0])


@pytest.mark.parametrize(
    "supports, match",
    [
        ([], "translation x.*translation y.*rotation about z"),
        ([("left", [0])], "translation y"),
        ([("bottom", [1])], "translation x"),
    ],
)
def test_singular_supports_are_reported(supports, match):
    model = _model(2, 1)
    bc = [model.dirichlet(n, components=c) for n, c in supports]
    with pytest.raises(InputError, match=match):
        model.solve(np.zeros(model.ndofs), dirichlet=bc)


def test_singular_3d_rotation_reported():
    model = _model(3, 1)
    # z fixed on the bottom and y on the front: the translation in x is free
    bc = [model.dirichlet("bottom", components=[2]), model.dirichlet("front", components=[1])]
    with pytest.raises(InputError, match="translation x"):
        model.factorize(np.concatenate([d for d, _ in bc]))


def test_generic_factorization_detects_singular_matrix():
    K = sp.diags([[-1.0] * 4, [1.0] + [2.0] * 3 + [1.0], [-1.0] * 4], [-1, 0, 1]).tocsr()  # Neumann Laplacian
    with pytest.raises(InputError, match="singular"):
        Factorization(K, [])
    fac = Factorization(K, [0])
    assert fac.free.size == 4


# ------------------------------------------------------------ factorization reuse
@pytest.mark.parametrize("dim", [2, 3])
def test_factorization_reuse_and_orderings(dim):
    model = _model(dim, 2)
    bc = _symmetry_supports(model)
    dofs = np.concatenate([d for d, _ in bc])
    f1 = model.traction_load("right", np.eye(dim)[0])
    f2 = model.pressure_load("top", 1.0)
    u_ref = model.solve(f1 + f2, dirichlet=bc)
    sols = []
    for backend, ordering in [("superlu", o) for o in ("auto", "nd", "MMD_AT_PLUS_A", "COLAMD")] + [
        ("cholmod", "auto"), ("auto", "auto")
    ]:
        fac = model.factorize(dofs, ordering=ordering, backend=backend)
        X = fac.solve(np.column_stack([fac.rhs(f1), fac.rhs(f2)]))
        assert X.shape == (fac.free.size, 2)
        u = fac.expand(X[:, 0] + X[:, 1])
        sols.append(u)
        assert np.allclose(u, u_ref, atol=1e-10 * np.abs(u_ref).max())
        # K_ff x = r in the original numbering
        r = fac.rhs(f1)
        assert np.allclose(fac.K_ff @ fac.solve(r), r)
    with pytest.raises(InputError, match="ordering"):
        model.factorize(dofs, ordering="metis")
    with pytest.raises(InputError, match="backend"):
        model.factorize(dofs, backend="pardiso")


def test_factorization_inhomogeneous_dirichlet():
    model = _model(2, 1)
    bc = [model.dirichlet("left", value=0.0), model.dirichlet("right", components=[0], value=0.01)]
    u = model.solve(np.zeros(model.ndofs), dirichlet=bc)
    _, dofs = model.node_dofs("right")
    assert np.allclose(u[dofs[:, 0]], 0.01)
    fac = model.factorize(np.concatenate([bc[0][0], bc[1][0]]))
    vals = np.zeros(fac.fixed.size)
    vals[np.isin(fac.fixed, bc[1][0])] = 0.01
    assert np.allclose(fac.solve_full(np.zeros(model.ndofs), vals), u)


def test_nested_dissection_is_a_permutation():
    model = _model(3, 1)
    pts, _ = model.all_node_dofs()
    perm = nested_dissection(pts, model.node_graph, leaf_size=4)
    assert np.array_equal(np.sort(perm), np.arange(pts.shape[0]))


def test_stiffness_symmetric_and_rigid_modes_in_kernel():
    for dim in (2, 3):
        model = _model(dim, 2)
        K = model.stiffness()
        assert abs(K - K.T).max() == 0.0
        assert_rigid_modes_in_kernel(model, K)
