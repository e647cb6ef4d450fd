"""Regression (issue 23): the condensed Coulomb subproblem stopped at its round-off floor.

Cattaneo-Mindlin between two identical cylinders at 64 elements per a (113k DOFs): Algorithms 6.2 and 6.4
failed the second normal step at every cut-back, their Newton iterations stuck at a relative residual of
1.4e-11 against newton_tol = 1e-11 (the residual R - W t(y_f - A R) cancels terms of the size of eps_N |y_f|).
The subproblem's tolerance is now raised to the round-off bound of its residual, as on the AMG path; the run
converges (8 outer iterations, 333 / 351 Newton) and the stick zone is that of the reference solver (the same
stick/slip states: the same discrete solution).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.problems import two_body_friction as tbf


@pytest.mark.slow
@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p"])
def test_fine_two_body_mindlin_converges_at_the_roundoff_floor(algorithm):
    prob, hist = tbf.cattaneo_mindlin_cylinders(n_per_a=64)
    sol = solve(prob, algorithm, history=hist)
    assert sol.result.success, sol.result.message
    assert sol.record.cutbacks == 0
    ref = solve(prob, "ssn", history=hist)
    assert np.array_equal(sol.extra["state"], ref.extra["state"])
    assert np.max(np.abs(sol.u - ref.u)) <= 1e-6 * np.max(np.abs(ref.u))
