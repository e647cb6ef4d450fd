"""Decisions of the AMG path for large problems, checked on a small one (thresholds lowered).

Reaches inside the package: the size above which the AMG path solves inexactly
(``contact.systems._krylov.INEXACT_DOFS``) is an internal rule, no option; the test sets it to 0 to
reach the inexact path on a small model.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.contact.systems import _krylov as _iterative
from alcontact.problems import hertz



@pytest.fixture(scope="module")
def prob():
    return hertz.hertz_3d(n_per_a=2, growth=1.3)


@pytest.mark.parametrize("algorithm,penalty", [("simo-laursen", None), ("family-p", "exp-met1")])
def test_inexact_subproblems_agree_with_direct_and_save_cg(prob, monkeypatch, algorithm, penalty):
    """Inexact subproblems (above INEXACT_DOFS, here forced): contact force within 1e-6 of the direct
    path (the tolerance of test_contact_iterative), at most 2x its outer iterations, and no more CG
    iterations than the exact subproblems of the same path."""
    direct = solve(prob, algorithm, penalty, linear_solver="direct")
    exact = solve(prob, algorithm, penalty, linear_solver="amg")
    monkeypatch.setattr(_iterative, "INEXACT_DOFS", 0)
    inexact = solve(prob, algorithm, penalty, linear_solver="amg")
    assert direct.result.success and exact.result.success and inexact.result.success, inexact.result.message
    f_ref = np.max(np.abs(direct.total_contact_force))
    assert np.max(np.abs(inexact.total_contact_force - direct.total_contact_force)) / f_ref <= 1e-6
    assert inexact.result.outer_iterations <= 2 * direct.result.outer_iterations
    assert inexact.extra["cg_iterations"] <= exact.extra["cg_iterations"]
    assert exact.extra["amg_setups"] == inexact.extra["amg_setups"] == 1  # only the hierarchy of K is built


def test_small_problems_solve_subproblems_exactly(prob):
    """Below INEXACT_DOFS the subproblems are exact (the direct path's outer iterations, pinned elsewhere)."""
    ic = _iterative.IterativeContact(prob)
    assert ic.K.shape[0] <= _iterative.INEXACT_DOFS and not ic.inexact_subproblems
