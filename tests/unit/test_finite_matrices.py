r"""Reuse in the finite-deformation Newton iterations: fixed matrix structures, kept states.

References: the Newton matrices built on the fixed structure of
:class:`~alcontact.contact.systems._layout.NewtonLayout` equal the sparse-algebra
construction :math:`K_{ff} + B^T \operatorname{diag}(wD) B + \sum_i w_i t_i H_i` (and the
saddle-point matrix of ``sp.bmat``) exactly (difference 0: the same products added in the
same order); a run analyses each matrix pattern once (PARDISO symbolic analyses counted by
the solver); a state evaluated twice costs one internal-force assembly, and the tangent of
an evaluated state reuses its deformation gradient (call counts).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from alcontact import penalties
from alcontact.contact import ContactProblem, Support, obstacles, solve_finite
from alcontact.contact.systems import FiniteContact
from alcontact.contact.laws import make_law
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic
from alcontact.linalg import PardisoSymmetricFactor, available_solvers
from alcontact.problems.half_cylinder import half_cylinder


def _contact(order=2):
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    body = Hyperelastic(mesh, Material(E=100.0, nu=0.3, plane="strain"), order=order)
    obstacle = obstacles.Circle(center=(0.5, 1.35), radius=0.4)  # curved: the H blocks count
    problem = ContactProblem(body, obstacle, "top", supports=(Support("bottom"),), kinematics="finite")
    dc = FiniteContact(problem)
    dc.cand = np.flatnonzero(dc.movable)
    x = 0.005 * np.random.default_rng(0).standard_normal(dc.free.size)
    return dc, x


def _sparse_free_tangent(dc, u):
    K = dc.body.tangent(u).tocsr()
    return K[dc.free][:, dc.free]


@pytest.mark.parametrize("order", [1, 2])
def test_newton_matrix_equals_sparse_construction(order):
    """J of subproblem (S) on the fixed structure equals the sparse-algebra J exactly (difference 0)."""
    dc, x = _contact(order)
    law = make_law(penalties.make("rockafellar"), np.full(dc.cand.size, 0.04))
    lam = np.full(dc.cand.size, 10.0)
    u = dc.expand(x)
    ev = dc.kinematics.evaluate(u, dc.cand, hessian=True)
    g, H = ev.g, ev.hessian
    t, D = law.traction(g, lam), law.stiffness(g, lam)
    assert np.all(t > 0) and np.any(H != 0)
    w = dc.weights[dc.cand]
    Bm = ev.gradient()  # the kinematics' constraint rows and curvature as sparse matrices
    ref = (_sparse_free_tangent(dc, u) + Bm.T @ sp.diags(w * D) @ Bm + ev.curvature(w * t)).tocsr()
    J = dc.jacobian(law, lam, x)
    assert dc._layout.built_here(J)  # the fixed structure, shared by every Newton matrix
    assert abs(J - ref).max() == 0.0
    # the free tangent alone, and with point blocks
    assert abs(dc._tangent_free(u) - _sparse_free_tangent(dc, u)).max() == 0.0
    blocks = (w * t)[:, None, None] * H
    assert abs(dc._tangent_blocks(u, dc.cand, blocks) - (_sparse_free_tangent(dc, u)
                                                         + dc._point_blocks(dc.cand, blocks))).max() == 0.0


def test_saddle_matrix_equals_block_construction():
    """The saddle-point matrix on the fixed structure equals sp.bmat of its blocks exactly (difference 0)."""
    dc, x = _contact()
    u = dc.expand(x)
    active = np.zeros(dc.cand.size, dtype=bool)
    active[::2] = True
    A = dc.cand[active]
    H = dc.kinematics.evaluate(u, A, hessian=True).hessian
    r = np.linspace(1.0, 2.0, A.size)
    Kt = dc._tangent_blocks(u, A, r[:, None, None] * H)
    S = dc._saddle_matrix(u, Kt, active)
    pts = dc._movable_pts
    on = np.zeros(pts.size, dtype=bool)
    on[dc._saddle_rows()] = active
    Bc = dc.kinematics.evaluate(u, pts).gradient(on)
    Dg = sp.diags((~on).astype(float))
    Kref = _sparse_free_tangent(dc, u) + dc._point_blocks(A, r[:, None, None] * H)
    ref = sp.bmat([[Kref, Bc.T], [Bc, Dg]], format="csr")
    assert S.shape == ref.shape and abs(S - ref).max() == 0.0
    # one structure for every active set
    S2 = dc._saddle_matrix(u, dc._tangent_blocks(u, A, 0.0 * H), ~active)
    assert S2.indptr is S.indptr and np.shares_memory(S2.indices, S.indices)


def test_state_evaluated_twice_costs_one_internal_force(monkeypatch):
    """_body_state of the same state twice: one internal-force assembly; the tangent there: no new F."""
    dc, x = _contact()
    body = dc.body
    calls = {"force": 0, "gradient": 0}
    force, gradient = body.internal_force, body._gradient

    def counted_force(u):
        calls["force"] += 1
        return force(u)

    def counted_gradient(*args):
        calls["gradient"] += 1
        return gradient(*args)

    monkeypatch.setattr(body, "internal_force", counted_force)
    monkeypatch.setattr(body, "_gradient", counted_gradient)
    u = dc.expand(x)
    r1, e1 = dc._body_state(u, True)
    r2, e2 = dc._body_state(u.copy(), True)
    assert calls["force"] == 1 and np.array_equal(r1, r2) and e1 == e2
    dc._tangent_free(u)
    assert calls["gradient"] == 1  # force, energy and tangent of one state share F
    dc._body_state(u + 1e-3, False)
    assert calls["force"] == 2 and calls["gradient"] == 2


def test_subproblem_full_steps_evaluate_once_per_iteration(monkeypatch):
    """A subproblem whose line search takes full steps assembles f_int once per Newton iteration (plus the
    start), and a second subproblem from the returned state none at its start."""
    dc, x = _contact()
    law = make_law(penalties.make("rockafellar"), np.full(dc.cand.size, 0.04))
    lam = np.full(dc.cand.size, 1.0)
    calls = {"force": 0}
    force = dc.body.internal_force

    def counted(u):
        calls["force"] += 1
        return force(u)

    monkeypatch.setattr(dc.body, "internal_force", counted)
    out = dc.subproblem(law, lam, np.zeros(dc.free.size), tol=1e-10, maxiter=30)
    assert out.converged and out.iterations >= 2
    assert len(dc.residual_log[-1]) == out.iterations + 1
    assert calls["force"] == out.iterations + 1  # every step here is a full step (one trial each)
    calls["force"] = 0
    out2 = dc.subproblem(law, lam, out.state, tol=1e-10, maxiter=30)
    assert out2.converged and out2.iterations == 0 and calls["force"] == 0


@pytest.mark.skipif("mkl-pardiso" not in available_solvers(), reason="needs MKL PARDISO (pypardiso)")
@pytest.mark.parametrize("algorithm, patterns", [("ssn", 2), ("simo-laursen", 1)])
def test_one_symbolic_analysis_per_pattern_over_a_run(algorithm, patterns):
    """A 4-step run analyses once per pattern: the tangent (predictor and subproblems (S)) and, for the
    reference, the saddle-point matrix; every other factorization reuses the analysis."""
    problem = half_cylinder(4, order=2)
    fs = solve_finite(problem, algorithm, None, steps=4)
    assert fs.status.success
    extra = fs.solution.extra
    assert extra["analyses"] == patterns
    assert extra["newton_total"] > 4 * patterns


def test_pardiso_refactorize_by_gather_equals_triangle_extraction():
    """Refactorizing a canonical CSR matrix of the analysed pattern by the gather solves like a new factor."""
    if "mkl-pardiso" not in available_solvers():
        pytest.skip("needs MKL PARDISO (pypardiso)")
    rng = np.random.default_rng(3)
    A = sp.random(40, 40, density=0.1, random_state=4)
    A = (A + A.T + 10 * sp.identity(40)).tocsr()
    A.sort_indices()
    f = PardisoSymmetricFactor(A)
    s = rng.uniform(0.5, 1.5, 40)
    rows = np.repeat(np.arange(40), np.diff(A.indptr))
    B = sp.csr_matrix((A.data * s[rows] * s[A.indices], A.indices.copy(), A.indptr.copy()), shape=A.shape)
    assert f._gathered(B) is not None
    b = rng.standard_normal(40)
    x = f.refactorize(B).solve(b)
    assert np.linalg.norm(B @ x - b) <= 1e-12 * np.linalg.norm(b)
