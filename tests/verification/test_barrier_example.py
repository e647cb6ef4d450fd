"""Barrier example (5.4) of section 5.1.1 with Algorithm 5.1.

min (x1 + 1)^2 + (x2 - 1)^2  s.t.  -x1 <= 0, solution (0, 1). The barrier
subproblem B(x, rho) = f - rho ln(x1) has the minimiser
x1 = (-1 + sqrt(1 + 2 rho)) / 2 (corrected sign, SEED_NOTES) and the Hessian
diag(2 + rho / x1^2, 2), whose condition number grows like 2 / rho.
"""

import logging

import numpy as np
import pytest
from scipy.optimize import LinearConstraint

from alcontact.optim import Status, minimize


def f(x):
    return (x[0] + 1.0) ** 2 + (x[1] - 1.0) ** 2


def grad(x):
    return np.array([2.0 * (x[0] + 1.0), 2.0 * (x[1] - 1.0)])


def hess(x):
    return 2.0 * np.eye(2)


CON = LinearConstraint([[-1.0, 0.0]], -np.inf, 0.0)  # -x1 <= 0


# the inverse barrier's complementarity mu*g = rho/|g| ~ sqrt(2 rho) only reaches 1e-8
# at rho ~ 1e-16, below the default floor of eta: minimize lowers the floor to 1e-24 for it
@pytest.mark.parametrize("penalty, ctol", [("log-barrier", 1e-8), ("inverse-barrier", 1e-5),
                                           ("inverse-barrier", 1e-8)])
def test_algorithm_5_1_reaches_solution(penalty, ctol):
    res = minimize(f, [1.0, 0.5], jac=grad, hess=hess, constraints=CON,
                   method="barrier", penalty=penalty, options={"ctol": ctol})
    assert res.status == Status.CONVERGED_KKT
    np.testing.assert_allclose(res.x, [0.0, 1.0], atol=ctol)
    assert res.fun == pytest.approx(1.0, abs=3 * ctol)
    # multiplier of -x1 <= 0 at the solution: grad f + mu * (-1, 0) = 0 -> mu = 2
    assert res.multipliers_ineq[0] == pytest.approx(2.0, rel=10 * ctol)
    # rho halves every outer iteration (Algorithm 5.1)
    etas = [r.eta_max for r in res.history]
    np.testing.assert_allclose(np.array(etas[1:]) / np.array(etas[:-1]), 0.5)
    assert all(r.f >= 1.0 - 1e-12 for r in res.history)  # interior: f > f*


def _barrier_subproblem_solution(rho):
    """x solving min B(x, rho) exactly: one outer iteration with a fixed rho."""
    logging.getLogger("alcontact.optim").disabled = True
    try:
        res = minimize(f, [1.0, 0.5], jac=grad, hess=hess, constraints=CON,
                       method="barrier", options={"eta0": rho, "strategy": "fixed",
                                                  "maxiter": 1, "gtol": 1e-13,
                                                  "inner_tol0": 1e-13})
    finally:
        logging.getLogger("alcontact.optim").disabled = False
    assert res.history[0].inner_status == "converged"
    return res.x


def test_subproblem_minimiser_matches_corrected_formula():
    for rho in [1.0, 1e-2, 1e-4]:
        x = _barrier_subproblem_solution(rho)
        x1 = (-1.0 + np.sqrt(1.0 + 2.0 * rho)) / 2.0
        assert x[0] == pytest.approx(x1, rel=1e-8)
        assert x[1] == pytest.approx(1.0, abs=1e-10)


def test_hessian_condition_grows_like_one_over_rho():
    rhos = np.array([1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6])
    products = []
    for rho in rhos:
        x = _barrier_subproblem_solution(rho)
        # Hessian of B measured by central differences of grad B at the engine's x
        def grad_b(z, rho=rho):
            return grad(z) + np.array([-rho / z[0], 0.0])
        h = 1e-4 * x[0]
        H = np.column_stack([(grad_b(x + h * e) - grad_b(x - h * e)) / (2 * h)
                             for e in np.eye(2)])
        products.append(np.linalg.cond(H) * rho)
    products = np.array(products)
    # cond * rho -> 2 (cond ~ (2 + 4/rho) / 2); the limit is approached monotonically
    assert products[-1] == pytest.approx(2.0, rel=1e-2)
    assert np.all(np.diff(np.abs(products - 2.0)) < 0)
    # and the condition number itself blows up (the chapter's point)
    assert products[-1] / rhos[-1] > 1e6
