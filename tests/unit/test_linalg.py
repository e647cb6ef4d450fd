"""The linear-solver layer (alcontact.linalg): registry, default rule, solvers, factorization reuse."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp

from alcontact import linalg
from alcontact.contact import ContactOptions, LoadCase, LoadHistory, Pressure, Support, problem_at, solve
from alcontact.errors import InputError, UnknownNameError
from alcontact.fem import Factorization, LinearElasticity, Material, meshes
from alcontact.problems import blocks


def _system(dim: int, order: int = 2):
    """Condensed stiffness of a clamped block and its hints (SPD, a few thousand DOFs)."""
    mesh = meshes.rectangle(0, 2, 0, 1, 8, 4) if dim == 2 else meshes.box(0, 1, 0, 1, 0, 1, 3, 3, 3)
    model = LinearElasticity(mesh, Material(E=100.0, nu=0.3), order=order)
    dofs, _ = model.dirichlet("left")
    mask = np.ones(model.ndofs, dtype=bool)
    mask[dofs] = False
    free = np.flatnonzero(mask)
    K = model.stiffness()[free][:, free].tocsr()
    hints = linalg.MatrixHints(dim=dim, ordering=lambda: model.ordering(free),
                               near_null=lambda: model._free_rigid_modes(free))
    return model, K, hints


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("name", linalg.available_solvers())
def test_every_installed_solver_solves_one_and_many_rhs(name, dim):
    """K x = b for one and three right-hand sides; reference: the residual.

    Direct solvers: relative residual <= 1e-10. ``amg`` runs CG to rtol 1e-10 per column,
    so its relative residual is <= 1e-10 as well (checked per column).
    """
    _, K, hints = _system(dim)
    rng = np.random.default_rng(3)
    B = rng.standard_normal((K.shape[0], 3))
    solver = linalg.make_solver(name)
    assert isinstance(solver, linalg.LinearSolver) and solver.name == name
    fac = solver.factorize(K, hints)
    assert isinstance(fac, linalg.Factor) and fac.name == name and fac.n == K.shape[0]
    assert fac.exact == (solver.kind == "direct")
    x = fac.solve(B[:, 0])
    assert x.shape == (K.shape[0],)
    assert np.linalg.norm(K @ x - B[:, 0]) <= 1e-10 * np.linalg.norm(B[:, 0])
    X = fac.solve(B)
    assert X.shape == B.shape
    for j in range(3):
        assert np.linalg.norm(K @ X[:, j] - B[:, j]) <= 1e-10 * np.linalg.norm(B[:, j])
    with pytest.raises(InputError, match="rhs"):
        fac.solve(np.ones(K.shape[0] + 1))
    assert fac.factor_seconds >= 0
    if name in ("superlu", "mkl-pardiso"):  # these report their factor
        assert fac.nnz >= sp.triu(K).nnz and fac.memory_bytes > 0


@pytest.mark.parametrize("name", [n for n in linalg.available_solvers() if linalg.solver_kind(n) == "direct"])
def test_direct_solvers_reject_singular_matrix(name):
    """The condensed Neumann matrix (no supports) is singular: InputError, not garbage."""
    model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 3, 3), Material(E=1.0, nu=0.3), order=1)
    with pytest.raises(InputError, match="singular|positive definite"):
        Factorization(model.stiffness(), [], backend=name)


def test_superlu_uses_the_ordering_hint():
    """SuperLU factorizes in the hinted order (here: reversed), else with its own ordering."""
    _, K, _ = _system(3, order=1)
    calls = []

    def reverse():
        calls.append(1)
        return np.arange(K.shape[0])[::-1]

    hinted = linalg.make_solver("superlu").factorize(K, linalg.MatrixHints(ordering=reverse))
    own = linalg.make_solver("superlu").factorize(K)
    assert calls == [1] and hinted.ordering == "given" and own.ordering == "MMD_AT_PLUS_A"
    b = np.arange(K.shape[0], dtype=float)
    assert np.allclose(hinted.solve(b), own.solve(b), rtol=1e-10, atol=0)
    plain = linalg.SuperLUSolver(use_ordering=False).factorize(K, linalg.MatrixHints(ordering=reverse))
    assert plain.ordering == "MMD_AT_PLUS_A" and calls == [1]


def test_unknown_and_missing_solvers_say_what_to_do():
    with pytest.raises(UnknownNameError, match="superlu"):
        linalg.make_solver("lu")
    linalg.register_solver("needs-missing", linalg.SuperLUSolver, requires="alcontact_no_such_module",
                           install="pip install alcontact-no-such-module")
    try:
        assert "needs-missing" in linalg.registered_solvers()
        assert "needs-missing" not in linalg.available_solvers()
        assert not linalg.describe_solvers()["needs-missing"]["installed"]
        with pytest.raises(InputError, match="not installed: pip install alcontact-no-such-module"):
            linalg.make_solver("needs-missing")
        with pytest.raises(InputError, match="already registered"):
            linalg.register_solver("needs-missing", linalg.SuperLUSolver)
    finally:
        linalg.unregister_solver("needs-missing")
    assert "needs-missing" not in linalg.registered_solvers()
    with pytest.raises(InputError, match="reserved"):
        linalg.register_solver("auto", linalg.SuperLUSolver)
    with pytest.raises(InputError, match="options"):
        linalg.make_solver("superlu", no_such_option=1)


def test_registered_solver_is_accepted_by_factorize_and_the_contact_option():
    """A user-registered solver is usable everywhere a solver name is (same solution as SuperLU)."""

    class Counting(linalg.SuperLUSolver):
        calls = 0

        def factorize(self, matrix, hints=None, **kw):
            Counting.calls += 1
            return super().factorize(matrix, hints, **kw)

    linalg.register_solver("counting-superlu", Counting)
    try:
        assert ContactOptions(linear_solver="counting-superlu").validate().linear_solver == "counting-superlu"
        prob = blocks.signorini_block(n=4)
        ref = solve(prob, "simo-laursen", linear_solver="superlu")
        sol = solve(prob, "simo-laursen", linear_solver="counting-superlu")
        assert Counting.calls == 1 and sol.extra["linear_solver"] == "counting-superlu"
        assert np.allclose(sol.u, ref.u, rtol=0, atol=1e-10 * np.abs(ref.u).max())
    finally:
        linalg.unregister_solver("counting-superlu")
    with pytest.raises(InputError, match="linear_solver"):
        ContactOptions(linear_solver="counting-superlu").validate()


def test_choose_solver_is_the_one_rule():
    n = linalg.AUTO_AMG_DOFS
    everything = ["amg", "cholmod", "mkl-pardiso", "superlu"]
    assert linalg.choose_solver(3, n + 1, installed=everything) == "amg"
    assert linalg.choose_solver(3, n + 1, installed=everything, allow_iterative=False) == "mkl-pardiso"
    assert linalg.choose_solver(3, n, installed=everything) == "mkl-pardiso"
    assert linalg.choose_solver(2, 100 * n, installed=everything) == "mkl-pardiso"
    assert linalg.choose_solver(2, 1000, installed=["amg", "cholmod", "superlu"]) == "cholmod"
    assert linalg.choose_solver(3, 1000, installed=["superlu"]) == "superlu"
    assert linalg.choose_solver(2, 1000) in linalg.available_solvers()
    assert linalg.DIRECT_PREFERENCE[-1] == "superlu"  # always installed: the fallback


# ------------------------------------------------------------------ factorization reuse
def test_factorize_reuses_the_factor_of_the_same_matrix_and_supports():
    model = LinearElasticity(meshes.rectangle(0, 2, 0, 1, 6, 3), Material(E=100.0, nu=0.3), order=1)
    left, _ = model.dirichlet("left")
    bottom, _ = model.dirichlet("bottom", components=[1])
    n0 = model.factorization_count
    f1 = model.factorize(left)
    f2 = model.factorize(left[::-1])  # same set, other order: reused
    assert f2 is f1 and model.factorization_count == n0 + 1
    f3 = model.factorize(np.concatenate([left, bottom]))  # changed supports: new factor
    assert f3 is not f1 and model.factorization_count == n0 + 2
    f4 = model.factorize(np.concatenate([left, bottom]), backend="superlu")  # other solver: new factor
    assert f4.backend == "superlu" and model.factorization_count == n0 + 3
    K2 = model.stiffness() * 2.0  # another matrix object: new factor
    f5 = model.factorize(np.concatenate([left, bottom]), matrix=K2, backend="superlu")
    assert f5 is not f4 and model.factorization_count == n0 + 4
    assert model.factorize(left, reuse=False) is not f1 and model.factorization_count == n0 + 5
    model.clear_factorization()
    model.factorize(left)
    assert model.factorization_count == n0 + 6


def test_stepped_frictionless_run_factorizes_once():
    """Load steps of a frictionless run share one factorization; a changed support set does not.

    Reference for the solutions: each step solved on a fresh model (same mesh), displacements
    equal to 1e-10 of their maximum.
    """
    base = blocks.signorini_block(n=4)
    unloaded = dataclasses.replace(base, loads=())
    hist = LoadHistory(cases=(LoadCase(Pressure("top", 2.0), lambda t: t),), times=(0.5, 1.0))
    model = base.model
    n0 = model.factorization_count
    sols = [solve(problem_at(unloaded, hist, t), "simo-laursen") for t in hist.times]
    assert model.factorization_count == n0 + 1
    assert [s.result.factorizations for s in sols] == [1, 0]
    assert all(s.result.success for s in sols)
    fresh = blocks.signorini_block(n=4, pressure=1.0)
    ref = solve(fresh, "simo-laursen")
    assert np.allclose(sols[0].u, ref.u, rtol=0, atol=1e-10 * np.abs(ref.u).max())
    # one more support (bottom right corner rollers): the fixed set changes, so it refactorizes
    more = dataclasses.replace(problem_at(unloaded, hist, 1.0),
                               supports=base.supports + (Support("right", components=(0,)),))
    solve(more, "simo-laursen")
    assert model.factorization_count == n0 + 2


@pytest.mark.parametrize("name", linalg.available_solvers())
def test_model_factorize_with_every_solver_gives_the_same_displacement(name):
    """Reference: SuperLU on the same condensed system; direct solvers agree to 1e-10 of max|u|,
    ``amg`` (CG to a relative residual of 1e-10, condition number ~1e4 here) to 1e-6."""
    model = LinearElasticity(meshes.rectangle(0, 2, 0, 1, 8, 4), Material(E=100.0, nu=0.3), order=2)
    left, _ = model.dirichlet("left")
    f = model.traction_load("right", [0.0, -1.0])
    ref = model.factorize(left, backend="superlu", reuse=False).solve_full(f)
    fac = model.factorize(left, backend=name, reuse=False)
    assert fac.backend == name
    tol = 1e-10 if linalg.solver_kind(name) == "direct" else 1e-6
    assert np.max(np.abs(fac.solve_full(f) - ref)) <= tol * np.max(np.abs(ref))


# ---------------------------------------------------------------------- symmetric indefinite sequences
def _saddle(n: int = 200, m: int = 10, seed: int = 4) -> sp.csr_matrix:
    """Symmetric indefinite saddle-point matrix [[A, B^T], [B, 0]] with A SPD and B of full rank."""
    A = sp.random(n, n, 0.03, random_state=seed)
    A = A + A.T + 8.0 * sp.eye(n)
    B = sp.random(m, n, 0.05, random_state=seed + 1) + sp.eye(m, n)
    return sp.bmat([[A, B.T], [B, None]], format="csr")


def test_choose_solver_respects_the_matrix_type():
    """Indefinite matrices go to solvers registered for them: never CHOLMOD or AMG."""
    assert linalg.choose_solver(3, 10**6, installed=["amg", "cholmod", "superlu"],
                                matrix_type="symmetric-indefinite") == "superlu"
    assert linalg.choose_solver(2, 10, installed=["cholmod", "mkl-pardiso"],
                                matrix_type="symmetric-indefinite") == "mkl-pardiso"
    assert linalg.choose_solver(2, 10, installed=["cholmod", "superlu"]) == "cholmod"
    assert "symmetric-indefinite" not in linalg.solver_matrix_types("cholmod")
    with pytest.raises(InputError, match="matrix_types"):
        linalg.register_solver("bad-type", linalg.SuperLUSolver, matrix_types=("hermitian",))


@pytest.mark.parametrize("name", [n for n in linalg.available_solvers()
                                  if "symmetric-indefinite" in linalg.solver_matrix_types(n)])
def test_indefinite_hint_solves_a_saddle_point_matrix(name):
    """Reference: the residual; relative residual <= 1e-10 for the saddle-point matrix.

    With the hint both pivot (PARDISO's SPD factor refuses this matrix: its zero block
    leaves empty rows in the upper triangle).
    """
    M = _saddle()
    b = np.random.default_rng(1).standard_normal(M.shape[0])
    f = linalg.make_solver(name).factorize(M, linalg.MatrixHints(matrix_type="symmetric-indefinite"))
    x = f.solve(b)
    assert np.max(np.abs(M @ x - b)) <= 1e-10 * np.max(np.abs(b))


@pytest.mark.skipif(not linalg.is_installed("mkl-pardiso"), reason="needs pypardiso")
def test_pardiso_symmetric_factor_refactorizes_on_its_analysis():
    """refactorize of a same-pattern matrix: residual <= 1e-10 relative, one analysis, two factorizations;
    another pattern is refused with an InputError."""
    M = _saddle()
    f = linalg.PardisoSymmetricFactor(M)
    b = np.ones(M.shape[0])
    assert f.refactorize(3.0 * M) is f
    x = f.solve(b)
    assert np.max(np.abs(3.0 * M @ x - b)) <= 1e-10
    assert (f.analyses, f.factorizations) == (1, 2)
    with pytest.raises(InputError, match="pattern"):
        f.refactorize(_saddle(seed=9))
    f.release()
    assert not f.alive


@pytest.mark.parametrize("name", [None, "superlu"])
def test_sequence_solver_keeps_analyses_by_pattern_and_falls_back(name):
    """Three patterns in turn, twice: residual <= 1e-10 relative each time; with PARDISO three
    analyses and six factorizations (keep=3), SuperLU keeps nothing; resolve reuses the last
    factor; a zero matrix raises numpy.linalg.LinAlgError."""
    s = linalg.SequenceSolver(name, keep=3)
    mats = [_saddle(seed=k) for k in (4, 6, 8)]
    rng = np.random.default_rng(2)
    for _ in range(2):
        for M in mats:
            b = rng.standard_normal(M.shape[0])
            x = s.solve(M, b)
            assert np.max(np.abs(M @ x - b)) <= 1e-10 * np.max(np.abs(b))
    b2 = rng.standard_normal(mats[-1].shape[0])
    assert np.max(np.abs(mats[-1] @ s.resolve(b2) - b2)) <= 1e-10 * np.max(np.abs(b2))
    if s.backend == "mkl-pardiso":
        assert (s.analyses, s.factorizations) == (3, 6)
    else:
        assert (s.analyses, s.factorizations) == (0, 0)
    with pytest.raises(np.linalg.LinAlgError):
        s.solve(sp.csr_matrix((5, 5)), np.ones(5))
    with pytest.raises(InputError, match="matrix_type"):
        linalg.SequenceSolver(name, matrix_type="hermitian")


@pytest.mark.parametrize("name", [None, "superlu"])
def test_sequence_solver_solves_unsymmetric_matrices(name):
    """Non-symmetric Newton matrices (friction): relative residual <= 1e-10 with the whole matrix
    factorized (a symmetric factor of the upper triangle would miss it by O(1)); the second matrix of
    the same pattern reuses the analysis with PARDISO."""
    M = _saddle().tolil()
    M[0, 1] += 3.0  # break the symmetry, same pattern
    M = M.tocsr()
    assert abs(M - M.T).max() > 1.0
    s = linalg.SequenceSolver(name, matrix_type="unsymmetric")
    b = np.random.default_rng(5).standard_normal(M.shape[0])
    for scale in (1.0, 2.0):
        x = s.solve(scale * M, b)
        assert np.max(np.abs(scale * M @ x - b)) <= 1e-10 * np.max(np.abs(b))
    if s.backend == "mkl-pardiso":
        assert (s.analyses, s.factorizations) == (1, 2)
