"""Unit tests of alcontact.fem.Hyperelastic and the hyperelastic law registry.

Stress, tangent, internal force and tangent stiffness are checked against
central finite differences (step h, relative error below a bound that the
O(h^2) truncation and the round-off of the chosen h comfortably meet).

Reaches inside the package: ``fem._hyper_materials`` (the law registry's table and its ``det``) to
generate one check per registered law, and the private sparsity-pattern builders of
``fem.hyperelastic`` to compare them.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import sympy

from alcontact.errors import (
    ConvergenceError,
    InputError,
    InvertedElementError,
    NonFiniteError,
    UnknownNameError,
)
from alcontact.fem import (
    Body,
    Hyperelastic,
    HyperelasticLaw,
    LinearElasticity,
    Material,
    SymbolicMaterial,
    available_materials,
    example_material_parameters,
    make_material,
    meshes,
    register_material,
)
from alcontact.fem._hyper_materials import _REGISTRY, det
from alcontact.fem.hyperelastic import _pattern_generic, _pattern_interleaved

LAM, MU = 1.7, 0.9
LAWS = available_materials()


def _law(name):
    """The registered law built with its documented example parameters (initial shear modulus MU = 0.9)."""
    return make_material(name, **example_material_parameters(name))


def _material(name, nu=0.3):
    """Material(E, nu) consistent with law ``name``: E = 10, or 2 mu0 (1 + nu) when its parameters fix mu0."""
    mu0 = _law(name).fixed_moduli()[0]
    return Material(E=10.0 if mu0 is None else 2.0 * mu0 * (1.0 + nu), nu=nu)


def _random_F(rng, n, d):
    """Random deformation gradients with det F > 0 (well away from inversion)."""
    F = np.eye(d) + 0.3 * rng.standard_normal((n, d, d))
    flip = det(F) < 0.2
    F[flip] = np.eye(d) + 0.1 * rng.standard_normal((int(flip.sum()), d, d))
    assert np.all(det(F) > 0.05)
    return F


def _neo_hookean_W(F, lam, mu):
    J = F.det()
    return mu / 2 * ((F.T * F).trace() - 3) - mu * sympy.log(J) + lam / 2 * sympy.log(J) ** 2


def _svk_W(F, lam, mu):
    E = (F.T * F - sympy.eye(3)) / 2
    return mu * (E.T * E).trace() + lam / 2 * E.trace() ** 2


SYMBOLIC = {"neo-hookean": _neo_hookean_W, "saint-venant-kirchhoff": _svk_W}
#: shared so that each derivation is compiled once per test session
SYMBOLIC_LAWS = {name: SymbolicMaterial(W, name=f"sym-{name}") for name, W in SYMBOLIC.items()}


# ----------------------------------------------------------------- registry
def test_registry_lists_and_builds_the_builtin_laws():
    assert set(LAWS) >= {"neo-hookean", "saint-venant-kirchhoff", "mooney-rivlin", "yeoh", "ogden", "gent",
                         "arruda-boyce"}
    for name in LAWS:
        law = _law(name)
        assert isinstance(law, HyperelasticLaw) and law.name == name


def test_unknown_law_name_lists_the_known_ones():
    with pytest.raises(UnknownNameError, match="neo-hookean") as info:
        make_material("neo-hooke")
    assert "Did you mean 'neo-hookean'" in str(info.value)
    with pytest.raises(UnknownNameError):
        Hyperelastic(meshes.rectangle(0, 1, 0, 1, 1, 1), Material(1.0, 0.3), model="mooney")


def test_register_user_law_by_energy():
    law = SymbolicMaterial(lambda F, lam, mu: lam / 2 * (F.det() - 1) ** 2 + mu / 2 * ((F.T * F).trace() - 3),
                           name="test-user-law")
    register_material("test-user-law", law)
    try:
        assert "test-user-law" in available_materials()
        with pytest.raises(InputError, match="already registered"):
            register_material("test-user-law", law)
        body = Hyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(1.0, 0.3), model="test-user-law")
        assert body.law is law
        u = body.interpolate(lambda x: np.stack([0.1 * x[0], -0.05 * x[1]]))
        h, v = 1e-6, np.random.default_rng(3).standard_normal(body.ndofs)
        fd = (body.energy(u + h * v) - body.energy(u - h * v)) / (2 * h)
        assert fd == pytest.approx(body.internal_force(u) @ v, rel=1e-7)
    finally:
        _REGISTRY.pop("test-user-law")
    with pytest.raises(InputError, match="HyperelasticLaw"):
        register_material("x", 3.0)
    register_material("test-bad-factory", lambda: 3.0)
    try:
        with pytest.raises(InputError, match="returned 3.0, not a HyperelasticLaw"):
            make_material("test-bad-factory")
    finally:
        _REGISTRY.pop("test-bad-factory")


def test_symbolic_law_rejects_bad_energy():
    with pytest.raises(InputError, match="W must be a callable"):
        SymbolicMaterial(3.0)
    bad = SymbolicMaterial(lambda F, lam, mu: F.inverse_nonexistent(), name="bad")
    with pytest.raises(InputError, match="'bad'.*SymPy operations"):
        bad.energy(np.eye(3)[None], LAM, MU)
    stray = SymbolicMaterial(lambda F, lam, mu: sympy.Symbol("k") * F.det(), name="stray")
    with pytest.raises(InputError, match="expression of F, lam and mu"):
        stray.stress(np.eye(2)[None], LAM, MU)


# ------------------------------------------------------- pointwise law checks
@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("name", LAWS)
def test_stress_is_derivative_of_energy(name, d):
    """P = dW/dF by central differences at random F with J > 0 (rel. error < 1e-7)."""
    law, rng, h = _law(name), np.random.default_rng(0), 1e-6
    F = _random_F(rng, 20, d)
    P = law.stress(F, LAM, MU)
    fd = np.empty_like(P)
    for i in range(d):
        for j in range(d):
            dF = np.zeros((d, d))
            dF[i, j] = h
            fd[:, i, j] = (law.energy(F + dF, LAM, MU) - law.energy(F - dF, LAM, MU)) / (2 * h)
    assert np.max(np.abs(fd - P)) <= 1e-7 * np.max(np.abs(P))


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("name", LAWS)
def test_tangent_is_derivative_of_stress(name, d):
    """A = dP/dF by central differences at random F with J > 0 (rel. error < 1e-7); major symmetry."""
    law, rng, h = _law(name), np.random.default_rng(1), 1e-6
    F = _random_F(rng, 20, d)
    A = law.tangent(F, LAM, MU)
    for k in range(d):
        for m in range(d):
            dF = np.zeros((d, d))
            dF[k, m] = h
            fd = (law.stress(F + dF, LAM, MU) - law.stress(F - dF, LAM, MU)) / (2 * h)
            assert np.max(np.abs(fd - A[:, :, :, k, m])) <= 1e-7 * np.max(np.abs(A))
    np.testing.assert_allclose(A, A.transpose(0, 3, 4, 1, 2), rtol=0, atol=1e-13 * np.abs(A).max())


def _random_rotations(rng, n, d):
    Q, R = np.linalg.qr(rng.standard_normal((n, d, d)))
    Q = Q * np.sign(np.diagonal(R, axis1=1, axis2=2))[:, None, :]
    Q[np.linalg.det(Q) < 0, :, 0] *= -1.0
    return Q


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("name", LAWS)
def test_objectivity_and_isotropy(name, d):
    """W(QF) = W(F) = W(FQ), P(QF) = Q P(F), A(QF) = Q A(F) Q for random rotations Q (rel. 1e-12)."""
    law, rng = _law(name), np.random.default_rng(7)
    F, Q = _random_F(rng, 20, d), _random_rotations(rng, 20, d)
    W = law.energy(F, LAM, MU)
    np.testing.assert_allclose(law.energy(Q @ F, LAM, MU), W, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(law.energy(F @ Q, LAM, MU), W, rtol=1e-12, atol=1e-13)
    P = law.stress(F, LAM, MU)
    np.testing.assert_allclose(law.stress(Q @ F, LAM, MU), Q @ P, rtol=1e-12, atol=1e-12 * np.abs(P).max())
    A = law.tangent(F, LAM, MU)
    QAQ = np.einsum("nia,naJbL,nkb->niJkL", Q, A, Q)
    np.testing.assert_allclose(law.tangent(Q @ F, LAM, MU), QAQ, rtol=1e-12, atol=1e-12 * np.abs(A).max())


@pytest.mark.parametrize("name", LAWS)
def test_small_strain_limit_is_linear_elasticity(name):
    """At F = I: W = 0, P = 0 and A = lam d_iJ d_kL + mu (d_ik d_JL + d_iL d_Jk) (the example laws have
    initial shear modulus MU). Absolute tolerance 1e-14 (moduli of order 1): the isochoric split evaluates
    P(I) as a sum of O(mu) terms that cancel, leaving a few ulps."""
    law, I = _law(name), np.eye(3)
    assert law.energy(I[None], LAM, MU)[0] == pytest.approx(0.0, abs=1e-14)
    np.testing.assert_allclose(law.stress(I[None], LAM, MU)[0], 0.0, atol=1e-14)
    C = (LAM * np.einsum("ij,kl->ijkl", I, I)
         + MU * (np.einsum("ik,jl->ijkl", I, I) + np.einsum("il,jk->ijkl", I, I)))
    np.testing.assert_allclose(law.tangent(I[None], LAM, MU)[0], C, atol=1e-14)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("name", sorted(SYMBOLIC))
def test_closed_forms_match_symbolic_derivation(name, d):
    """The hand-written laws agree with SymPy's derivatives of the same W to 1e-12."""
    law, sym = _law(name), SYMBOLIC_LAWS[name]
    F = _random_F(np.random.default_rng(2), 30, d)
    for what in ("energy", "stress", "tangent"):
        a, b = getattr(law, what)(F, LAM, MU), getattr(sym, what)(F, LAM, MU)
        assert a.shape == b.shape
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())
    if d == 2:
        np.testing.assert_allclose(law.stress_zz(F, LAM, MU), sym.stress_zz(F, LAM, MU), rtol=1e-12, atol=1e-13)


@pytest.mark.parametrize("name", LAWS)
def test_plane_strain_is_the_in_plane_block_of_3d(name):
    """2D laws equal the 3D law at F = diag(F2, 1): W, P_ab, A_abcd and P33 = stress_zz."""
    law = _law(name)
    F2 = _random_F(np.random.default_rng(4), 10, 2)
    F3 = np.zeros((10, 3, 3))
    F3[:, :2, :2], F3[:, 2, 2] = F2, 1.0
    np.testing.assert_allclose(law.energy(F2, LAM, MU), law.energy(F3, LAM, MU), rtol=1e-13, atol=1e-14)
    P3 = law.stress(F3, LAM, MU)
    np.testing.assert_allclose(law.stress(F2, LAM, MU), P3[:, :2, :2], rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(law.stress_zz(F2, LAM, MU), P3[:, 2, 2], rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(law.tangent(F2, LAM, MU), law.tangent(F3, LAM, MU)[:, :2, :2, :2, :2],
                               rtol=1e-13, atol=1e-14)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("name", LAWS)
def test_fast_element_tangent_matches_generic_contraction(name, d):
    law, rng = _law(name), np.random.default_rng(5)
    for nqp, nloc in [(1, d + 1), (3, 3 * d)]:  # P1 (one point) and a P2-sized local basis
        F = _random_F(rng, 4 * nqp, d).reshape(4, nqp, d, d)
        G = rng.standard_normal((4, nqp, nloc, d))
        dx = rng.uniform(0.1, 1.0, (4, nqp))
        fast = law.element_tangent(F, G, dx, LAM, MU)
        # reference: the definition K_aibk = sum_q dx G_aJ A_iJkL G_bL, term by term
        ref = np.einsum("eq,eqaJ,eqiJkL,eqbL->eaibk", dx, G, law.tangent(F, LAM, MU), G)
        generic = HyperelasticLaw.element_tangent(law, F, G, dx, LAM, MU)
        assert fast.shape == ref.shape == (4, nloc, d, nloc, d)
        np.testing.assert_allclose(fast, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
        np.testing.assert_allclose(generic, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())


# ------------------------------------------------------------ assembled body
def _mesh(dim):
    if dim == 2:
        return meshes.rectangle(0.0, 2.0, 0.0, 1.0, 3, 2)
    return meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 2, 1, 1)


BODIES = [(dim, order, name) for dim in (2, 3) for order in (1, 2) for name in LAWS]


@pytest.mark.parametrize("dim, order, name", BODIES)
def test_assembled_force_and_tangent_against_finite_differences(dim, order, name):
    """f_int = dPi/du and K_T = df_int/du by central differences along random directions (rel. 1e-6)."""
    body = Hyperelastic(_mesh(dim), _material(name), order=order, model=_law(name))
    rng, h = np.random.default_rng(6), 1e-6
    u = 0.01 * rng.standard_normal(body.ndofs) + body.interpolate(lambda x: 0.2 * x[::-1] * np.array(
        [1.0, -0.5, 0.3][:dim])[:, None])
    f, K = body.internal_force(u), body.tangent(u)
    assert isinstance(K, sp.csr_matrix) and K.shape == (body.ndofs, body.ndofs)
    assert abs(K - K.T).max() == 0.0  # exactly symmetric
    K0 = body.tangent(np.zeros(body.ndofs))
    K0.eliminate_zeros()  # in-place structure change of one tangent leaves the next intact
    assert (body.tangent(u) != K).nnz == 0
    for _ in range(3):
        v = rng.standard_normal(body.ndofs)
        dE = (body.energy(u + h * v) - body.energy(u - h * v)) / (2 * h)
        assert dE == pytest.approx(f @ v, rel=1e-6)
        df = (body.internal_force(u + h * v) - body.internal_force(u - h * v)) / (2 * h)
        assert np.linalg.norm(df - K @ v) <= 1e-6 * np.linalg.norm(df)


@pytest.mark.parametrize("dim, order, name", BODIES)
def test_stiffness_is_the_linear_elastic_stiffness(dim, order, name):
    """tangent(0) equals LinearElasticity.stiffness() to round-off."""
    mat = _material(name)
    body = Hyperelastic(_mesh(dim), mat, order=order, model=_law(name))
    K0, K = body.stiffness(), LinearElasticity(_mesh(dim), mat, order=order).stiffness()
    assert abs(K0 - K).max() <= 1e-13 * abs(K).max()
    assert body.linear is False and body.energy(np.zeros(body.ndofs)) == 0.0
    assert isinstance(body, Body)
    np.testing.assert_allclose(body.internal_force(np.zeros(body.ndofs)), 0.0, atol=1e-14)


def test_rigid_rotation_is_stress_free():
    """A finite rigid rotation stores no energy and has zero internal force (objectivity)."""
    body = Hyperelastic(_mesh(3), Material(E=10.0, nu=0.3), order=2)
    c, s = np.cos(1.0), np.sin(1.0)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    u = body.interpolate(lambda x: R @ x - x)
    assert abs(body.energy(u)) < 1e-13
    assert np.abs(body.internal_force(u)).max() < 1e-12


@pytest.mark.parametrize("dim, order", [(2, 1), (2, 2), (3, 1), (3, 2)])
def test_interleaved_pattern_matches_generic(dim, order):
    body = Hyperelastic(_mesh(dim), Material(E=10.0, nu=0.3), order=order)
    a = _pattern_generic(body._vdofs, body.ndofs)
    b = _pattern_interleaved(body._sdofs, body.scalar_basis.N, dim)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)
    # the pattern is the element graph with dense dim x dim blocks, and holds every entry of K
    ind, idx, _, tperm = a
    rows = np.repeat(np.arange(body.ndofs), np.diff(ind))
    np.testing.assert_array_equal(rows[tperm], idx)  # tperm points at the transposed entry
    np.testing.assert_array_equal(idx[tperm], rows)
    S0 = sp.csr_matrix((np.ones(idx.size), idx, ind), shape=(body.ndofs, body.ndofs))
    expect = sp.kron(body.node_graph, np.ones((dim, dim)), format="csr")
    assert S0.nnz == expect.nnz and abs(S0 - (expect != 0)).max() == 0
    K = LinearElasticity(_mesh(dim), Material(E=10.0, nu=0.3), order=order).stiffness()
    S = (K != 0).astype(float)
    assert S.multiply(S0).nnz == S.nnz


def test_inverted_element_raises_with_element_list():
    body = Hyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=10.0, nu=0.3))
    u = body.interpolate(lambda x: np.stack([-2.0 * x[0], 0.0 * x[1]]))  # x -> -x: every element flips
    for call in (body.internal_force, body.tangent, body.energy, body.stress, body.first_piola):
        with pytest.raises(InvertedElementError, match="8 of 8 elements inverted") as info:
            call(u)
        np.testing.assert_array_equal(info.value.elements, np.arange(8))
    v = np.zeros(body.ndofs)
    _, dofs = body.all_node_dofs()
    v[dofs[4, 0]] = 5.0  # drag the centre node across: only its neighbours invert
    with pytest.raises(InvertedElementError) as info:
        body.internal_force(v)
    assert 0 < info.value.elements.size < 8
    with pytest.raises(NonFiniteError, match="NaN"):
        body.internal_force(np.full(body.ndofs, np.nan))
    with pytest.raises(InputError, match="shape"):
        body.tangent(np.zeros(3))


def test_input_errors():
    mesh = meshes.rectangle(0, 1, 0, 1, 1, 1)
    with pytest.raises(InputError, match="plane strain only"):
        Hyperelastic(mesh, Material(E=1.0, nu=0.3, plane="stress"))
    with pytest.raises(InputError, match=r"nu=0.5\b.*use nu <= 0.49"):
        Hyperelastic(mesh, Material(E=1.0, nu=0.5))
    for bad in (0, 1.5, "two"):
        with pytest.raises(InputError, match="intorder"):
            Hyperelastic(mesh, Material(E=1.0, nu=0.3), intorder=bad)
    assert Hyperelastic(mesh, Material(E=1.0, nu=0.3), order=2, intorder=4).intorder == 4


def test_cauchy_and_piola_output_of_a_homogeneous_stretch():
    """Nodal P and sigma = P F^T / J of u = (F - I) X equal the law's values at F (to 1e-10)."""
    body = Hyperelastic(meshes.rectangle(0, 1, 0, 1, 3, 3), Material(E=10.0, nu=0.3), order=2)
    F = np.array([[1.2, 0.1], [0.05, 0.9]])
    u = body.interpolate(lambda x: (F - np.eye(2)) @ x)
    P = body.law.stress(F[None], body.lam, body.mu)[0]
    P33 = body.law.stress_zz(F[None], body.lam, body.mu)[0]
    J = np.linalg.det(F)
    sig = P @ F.T / J
    nodal_P = body.first_piola(u, include_zz=True)
    np.testing.assert_allclose(nodal_P, np.tile([*P.ravel(), P33], (nodal_P.shape[0], 1)), atol=1e-10)
    nodal_s = body.stress(u, include_zz=True)
    expect = [sig[0, 0], sig[1, 1], sig[0, 1], P33 / J]
    np.testing.assert_allclose(nodal_s, np.tile(expect, (nodal_s.shape[0], 1)), atol=1e-10)
    assert body.von_mises(u).shape == (body.scalar_basis.N,)


@pytest.mark.parametrize("dim", [2, 3])
def test_symbolic_law_body_matches_builtin_body(dim):
    """A body on SymPy-derived neo-Hookean (generic tangent contraction) equals the built-in one to 1e-11."""
    mat = Material(E=10.0, nu=0.3)
    fast = Hyperelastic(_mesh(dim), mat, order=2)
    sym = Hyperelastic(_mesh(dim), mat, order=2, model=SYMBOLIC_LAWS["neo-hookean"])
    u = fast.interpolate(lambda x: 0.2 * x[::-1] * np.array([1.0, -0.5, 0.3][:dim])[:, None])
    assert sym.energy(u) == pytest.approx(fast.energy(u), rel=1e-12)
    np.testing.assert_allclose(sym.internal_force(u), fast.internal_force(u), rtol=0, atol=1e-12)
    Ks, Kf = sym.tangent(u), fast.tangent(u)
    assert abs(Ks - Kf).max() <= 1e-11 * abs(Kf).max() and abs(Ks - Ks.T).max() == 0.0


def test_solve_failures_raise_convergence_error_with_advice(caplog):
    body = Hyperelastic(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=10.0, nu=0.3))
    left = body.dirichlet("left")
    pull = [left, body.dirichlet("right", components=[0], value=0.5)]
    with caplog.at_level("WARNING", logger="alcontact.fem.hyperelastic"):
        with pytest.raises(ConvergenceError, match=r"did not converge in load step 1/1.*steps=2"):
            body.solve(np.zeros(body.ndofs), dirichlet=pull, max_iter=1)
    assert any("did not converge" in r.message for r in caplog.records)
    crush = [left, body.dirichlet("right", components=[0], value=-1.5)]  # x = 1 -> x = -0.5: inverted
    with pytest.raises(ConvergenceError, match="invert elements"):
        body.solve(np.zeros(body.ndofs), dirichlet=crush)
    with pytest.raises(InputError, match="steps"):
        body.solve(np.zeros(body.ndofs), dirichlet=pull, steps=0)
    with pytest.raises(InputError, match="rigid-body"):
        body.solve(np.zeros(body.ndofs), dirichlet=[body.dirichlet("left", components=[0])])


def test_singular_tangent_inside_a_load_step_is_a_convergence_error():
    """A restrained Saint Venant-Kirchhoff strip bent by a dead load loses the definiteness of its tangent in step 2.

    The supports are fine (checked before the first step): the failure is the Newton
    solve's, reported as a ConvergenceError naming the singular matrix and the way out,
    not as an input error about rigid-body motions.
    """
    body = Hyperelastic(meshes.rectangle(0, 2.0, 0, 1.0, 6, 3), Material(E=100.0, nu=0.3), order=1,
                        model="saint-venant-kirchhoff")
    with pytest.raises(ConvergenceError, match=r"load step 2/4 \(singular Newton matrix.*steps=8"):
        body.solve(body.traction_load("right", [0.0, -12.0]), dirichlet=[body.dirichlet("left")], steps=4)
