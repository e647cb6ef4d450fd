"""Every frictionless algorithm converges on the factorization-free (AMG) path of a 3D P2 problem.

Reference: the direct path (one factorization, exact Newton on the condensed problem) on the
same mesh. Tolerances: the AMG path needs at most twice the direct path's outer iterations,
and its total contact force agrees with the direct one to a relative 1e-6 (the Newton
residuals of both paths are below 1e-8 of the contact forces).

Reaches inside the package: one unit check of the private stiff-point rule of
``contact.systems._krylov``.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.problems import hertz


#: (algorithm, penalty) of every frictionless algorithm and the family-P penalties of issue 11
VARIANTS = [
    ("penalty", None),
    ("simo-laursen", None),
    ("family-p", "exp-met1"),
    ("family-p", "log-met1"),
    ("family-p", "log-met2"),
    ("family-p", "quad-met2"),
    ("family-p", "rockafellar"),
    ("ssn", None),
]


@pytest.fixture(scope="module")
def sphere_p2():
    """Rigid sphere on a quarter block of P2 tetrahedra (about 9k DOFs, candidates on P2 faces)."""
    return hertz.hertz_3d(order=2, n_per_a=1, growth=1.6, size=6.0)


@pytest.mark.slow  # 16 solves of a 9k-DOF 3D problem
@pytest.mark.parametrize("algorithm,penalty", VARIANTS)
def test_amg_path_converges_like_direct(sphere_p2, algorithm, penalty):
    direct = solve(sphere_p2, algorithm, penalty, linear_solver="direct")
    amg = solve(sphere_p2, algorithm, penalty, linear_solver="amg")
    assert direct.result.success, direct.result.message
    assert amg.result.success, amg.result.message
    assert amg.result.outer_iterations <= 2 * direct.result.outer_iterations
    f_ref = float(np.max(np.abs(direct.total_contact_force)))
    df = float(np.max(np.abs(amg.total_contact_force - direct.total_contact_force))) / f_ref
    assert df < 1e-6
    assert amg.result.factorizations == 0 and amg.extra["cg_iterations"] > 0


def test_stiff_penalty_preconditioner_is_penalty_independent(sphere_p2):
    """CG iterations with the AMG preconditioner of ``J = K + eps B^T W B`` do not grow with ``eps``.

    Reference: the same CG solve (random right-hand side, relative residual 1e-8) at
    ``eps = E'/h``, where no spring dominates its node. Tolerance: at ``eps = 1e2, 1e4, 1e7
    E'/h`` (the default initial penalty, and up to the last level of the pure penalty: every
    candidate's spring is more than 10 times its node's normal stiffness, so the reflected
    hierarchy of ``linalg._amg.reflected_hierarchy`` is used) at most 1.5 times those iterations plus 5,
    and the residual reaches 1e-8. The Galerkin hierarchy of ``K`` alone needed 206 and 748
    against 30 iterations at ``1e5`` and ``1e7 E'/h`` on this mesh (pointwise Gauss-Seidel on
    the oblique stiff node blocks).
    """
    from alcontact.contact.systems import _krylov as it
    from alcontact.contact.laws import penalty_stiffness

    ic = it.IterativeContact(sphere_p2)
    Bc, w = ic.B[ic.cand], ic.weights[ic.cand]
    e_h = penalty_stiffness(sphere_p2.model, ic.h)
    rhs = np.random.default_rng(0).standard_normal(ic.K.shape[0])
    counts = {}
    for factor in (1.0, 1e2, 1e4, 1e7):
        k = w * e_h * factor
        stiff = it._stiff_points(ic.K, Bc, k)
        assert stiff.all() if factor > 1 else not stiff.any()
        delta = ic.contact_delta(Bc, k)
        J = ic.with_contact(delta)
        J0 = J.copy()  # the solve overwrites J by its reflection Q J Q
        x, counts[factor] = ic.precond.solve(J, rhs, rtol=1e-8, delta=delta, Bc=Bc, k=k)
        assert np.linalg.norm(J0 @ x - rhs) <= 1e-8 * np.linalg.norm(rhs) * (1 + 1e-6)
    for factor in (1e2, 1e4, 1e7):
        assert counts[factor] <= 1.5 * counts[1.0] + 5, counts
