"""Negative curvature in the inner solvers, automatic scaling, the pushed start.

- a saddle where the gradient vanishes by symmetry is left along the eigenvector of
  the negative eigenvalue (Newton's second-order test and the trust-region solver);
- the exact trust-region step solves its subproblem, hard case included;
- with ``scale=True`` (ALGENCAN's scaling) every reported quantity is in the user's
  units and agrees with the unscaled run;
- ``x0`` outside the bounds is pushed inside by IPOPT's margin.

Reaches inside the package: unit tests of the inner solvers and the trust-region step
(``optim._inner``, ``optim._problem.NLP``), which have no public names.
"""

import logging

import numpy as np
import pytest
from scipy.optimize import Bounds, NonlinearConstraint

from alcontact.errors import InputError
from alcontact.optim import available_inner_solvers, minimize
from alcontact.optim._inner import Newton, TrustRegion, _tr_step


# f = x1^2 - x2^2 + x2^4: saddle at x2 = 0 (grad_x2 = 0 there for every x1),
# minima at x2 = +-1/sqrt(2) with f = -1/4
def saddle_f(x):
    return x[0] ** 2 - x[1] ** 2 + x[1] ** 4


def saddle_g(x):
    return np.array([2 * x[0], -2 * x[1] + 4 * x[1] ** 3])


def saddle_h(x):
    return np.diag([2.0, -2.0 + 12 * x[1] ** 2])


class _Unconstrained:
    """Minimal subproblem object for the inner solvers (see ``_inner`` docs)."""

    unbounded_below = -1e20
    last_nonfinite = None

    def value(self, x):
        return float(saddle_f(x))

    def gradient(self, x):
        return saddle_g(x), 1.0

    def hessian(self, x):
        return saddle_h(x)

    def max_step(self, x, d):
        return np.inf


@pytest.mark.parametrize("solver", [Newton(), TrustRegion()])
def test_inner_solver_leaves_symmetric_saddle(solver):
    res = solver.solve(_Unconstrained(), np.array([1.0, 0.0]), 1e-10, 100)
    assert res.status == "converged"
    np.testing.assert_allclose(abs(res.x[1]), 1 / np.sqrt(2), rtol=1e-8)
    assert res.value == pytest.approx(-0.25, abs=1e-12)


def test_newton_without_second_order_test_stops_at_saddle():
    # the pre-existing behaviour: a positive definite modification never moves x2
    res = Newton(max_dense=0).solve(_Unconstrained(), np.array([1.0, 0.0]), 1e-10, 100)
    assert res.status == "converged" and res.x[1] == 0.0


def test_minimize_escapes_saddle_with_constraint():
    # the constraint x1 >= 0.5 is active; x2 = 0 is a KKT point but not a minimum
    con = NonlinearConstraint(lambda x: x[0], 0.5, np.inf,
                              jac=lambda x: np.array([[1.0, 0.0]]))
    for inner in ("newton", "trust-region"):
        res = minimize(saddle_f, [2.0, 0.0], jac=saddle_g, hess=saddle_h,
                       constraints=con, options={"inner": inner})
        assert res.success, res.message
        np.testing.assert_allclose(res.x, [0.5, res.x[1]], atol=1e-8)
        assert abs(res.x[1]) == pytest.approx(1 / np.sqrt(2), rel=1e-7)


def test_tr_step_interior_boundary_and_hard_case():
    rng = np.random.default_rng(0)
    A = rng.standard_normal((4, 4))
    H = A @ A.T + 4 * np.eye(4)
    g = rng.standard_normal(4)
    lam, Q = np.linalg.eigh(H)
    newton = -np.linalg.solve(H, g)
    # interior: the Newton step
    np.testing.assert_allclose(_tr_step(lam, Q, g, 2 * np.linalg.norm(newton)), newton)
    # boundary: |p| = radius and p = -(H + sigma I)^{-1} g with sigma >= 0
    r = 0.3 * np.linalg.norm(newton)
    p = _tr_step(lam, Q, g, r)
    assert np.linalg.norm(p) == pytest.approx(r, rel=1e-5)
    sigma = -np.mean((H @ p + g) / p)
    assert sigma > 0
    np.testing.assert_allclose(H @ p + sigma * p, -g, atol=1e-6 * np.linalg.norm(g))
    # indefinite, g orthogonal to the negative eigenvector: hard case, step reaches
    # the boundary with a component along that eigenvector
    Hi = np.diag([-1.0, 2.0, 3.0])
    gi = np.array([0.0, 1.0, 1.0])
    lam, Q = np.linalg.eigh(Hi)
    p = _tr_step(lam, Q, gi, 2.0)
    assert np.linalg.norm(p) == pytest.approx(2.0)
    assert abs(p[0]) > 1.0
    model = gi @ p + 0.5 * p @ Hi @ p
    assert model < gi @ (-gi / 3) + 0.5 * (gi / 3) @ Hi @ (gi / 3)


def test_trust_region_is_registered_and_validated():
    assert "trust-region" in available_inner_solvers()
    with pytest.raises(InputError, match="eta1"):
        minimize(saddle_f, [1.0, 0.5], options={"inner": "trust-region",
                                                "inner_options": {"eta1": 0.5}})


# a badly scaled problem: f ~ 1e4, constraint gradient ~ 1e3
def big_f(x):
    return 1e4 * ((x[0] - 2.0) ** 2 + (x[1] - 1.0) ** 2)


def big_g(x):
    return 2e4 * np.array([x[0] - 2.0, x[1] - 1.0])


def big_h(x):
    return 2e4 * np.eye(2)


BIG_CON = NonlinearConstraint(lambda x: 1e3 * (x[0] + x[1]), -np.inf, 1e3,
                              jac=lambda x: np.array([[1e3, 1e3]]),
                              hess=lambda x, v: np.zeros((2, 2)))


@pytest.mark.parametrize("penalty", ["rockafellar", "exp-met1", "log-met1"])
def test_scaling_reports_user_units(penalty):
    kw = dict(jac=big_g, hess=big_h, constraints=BIG_CON, penalty=penalty)
    scaled = minimize(big_f, [0.0, 0.0], **kw)
    plain = minimize(big_f, [0.0, 0.0], **kw, options={"scale": False})
    assert scaled.success and plain.success
    # solution (1, 0): f = 1e4 * (1 + 1) = 2e4; multiplier of c = 1e3 (x1 + x2) <= 1e3
    # from grad f + mu * 1e3 (1, 1) = 0: mu = 20
    np.testing.assert_allclose(scaled.x, [1.0, 0.0], atol=1e-8)
    assert scaled.fun == pytest.approx(2e4, rel=1e-10)
    assert scaled.fun == pytest.approx(plain.fun, rel=1e-10)
    assert scaled.multipliers_ineq[0] == pytest.approx(20.0, rel=1e-6)
    assert scaled.multipliers[0][0] == pytest.approx(20.0, rel=1e-6)
    np.testing.assert_allclose(scaled.multipliers_ineq, plain.multipliers_ineq, rtol=1e-6)
    # the constraint value is the user's c - ub, and the measures use user units
    x, mu = scaled.x, scaled.multipliers_ineq[0]
    assert scaled.constr_ineq[0] == pytest.approx(1e3 * (x[0] + x[1]) - 1e3, abs=1e-9)
    r = big_g(x) + mu * np.array([1e3, 1e3])
    assert scaled.stationarity == pytest.approx(
        np.max(np.abs(r)) / max(1.0, np.max(np.abs(big_g(x)))), abs=1e-12)
    assert scaled.complementarity == pytest.approx(abs(mu * scaled.constr_ineq[0]),
                                                   abs=1e-12)
    assert scaled.history[-1].f == pytest.approx(scaled.fun)


def test_scaling_factors_of_the_nlp():
    from alcontact.optim._problem import NLP

    nlp = NLP(big_f, [0.0, 0.0], jac=big_g, hess=big_h, constraints=BIG_CON,
              bounds=Bounds([-5, -5], [5, 5]))
    sf, sg, sh = nlp.set_scaling()
    assert sf == pytest.approx(1 / 4e4)
    # the constraint row has gradient 1e3; the four bound rows keep scale 1
    np.testing.assert_allclose(sg, [1e-3, 1, 1, 1, 1])
    assert sh.size == 0 and nlp.scaled
    x = np.array([0.3, -0.2])
    assert nlp.f(x) == pytest.approx(sf * big_f(x))
    g, _ = nlp.constraints(x)
    assert g[0] == pytest.approx(1e-3 * (1e3 * (x[0] + x[1]) - 1e3))
    gu, _, mu, _ = nlp.unscale(g, np.zeros(0), np.full(5, 2.0), np.zeros(0))
    assert gu[0] == pytest.approx(1e3 * (x[0] + x[1]) - 1e3)
    assert mu[0] == pytest.approx(2.0 * 1e-3 / sf)


def test_x0_outside_bounds_is_pushed_inside():
    from alcontact.optim._problem import NLP

    nlp = NLP(lambda x: x @ x, [-2.0, 1.0, 7.0, 0.0], bounds=Bounds(
        [-0.5, -np.inf, 0.0, 0.0], [0.5, 1.0, 100.0, 0.0]))
    assert nlp.project_into_bounds(1e-2)
    # lb + min(0.01 max(1, 0.5), 0.01 * 1); ub - 0.01; inside: unchanged; fixed: kept
    np.testing.assert_allclose(nlp.x0, [-0.49, 0.99, 7.0, 0.0])
    logging.getLogger("alcontact.optim").disabled = True
    try:
        res = minimize(lambda x: (x[0] - 1) ** 2, [3.0], bounds=[(-1.0, 0.0)])
    finally:
        logging.getLogger("alcontact.optim").disabled = False
    assert res.success and "moved into the bounds" in res.message
    assert res.x[0] == pytest.approx(0.0, abs=1e-8)


@pytest.mark.parametrize("bad", [{"bound_push": -0.1}, {"bound_push": 0.7},
                                 {"eta0_factor": 0.0}, {"eta0_factor": np.inf}])
def test_new_options_validated(bad):
    with pytest.raises(InputError):
        minimize(lambda x: x @ x, [1.0], options=bad)
