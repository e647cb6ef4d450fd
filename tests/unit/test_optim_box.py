"""Variable bounds as an exact box of the AL subproblems (option ``bounds_as``).

- the projected Newton inner solver (``Newton.solve_box``) on bound-constrained QPs,
  dense and sparse: solution on a bound, sign-correct bound multipliers, every
  evaluated point inside the box;
- ``minimize(method="al")``: bound multipliers recovered from the gradient, x0 moved
  into the box, the Newton-KKT polish with active bounds, ``bounds_as="constraints"``
  still available and equivalent.

Reaches inside the package: unit tests of the inner solver classes ``optim._inner.Newton`` /
``TrustRegion`` (no public names; ``minimize`` is tested through its public name).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import Bounds, LinearConstraint, NonlinearConstraint

from alcontact.errors import InputError
from alcontact.optim import Status, minimize
from alcontact.optim._inner import Newton, TrustRegion


class BoxQP:
    """Subproblem ``0.5 x^T A x - b^T x`` on ``lower <= x <= upper``; records every x."""

    def __init__(self, A, b, lower, upper):
        self.A, self.b = A, np.asarray(b, float)
        self.lower, self.upper = np.asarray(lower, float), np.asarray(upper, float)
        self.unbounded_below = -1e20
        self.last_nonfinite = None
        self.seen = []

    def _see(self, x):
        self.seen.append(np.array(x, copy=True))

    def value(self, x):
        self._see(x)
        return float(0.5 * x @ (self.A @ x) - self.b @ x)

    def gradient(self, x):
        self._see(x)
        return np.asarray(self.A @ x).ravel() - self.b, 1.0

    def hessian(self, x):
        self._see(x)
        return self.A

    def max_step(self, x, d):
        return math.inf

    def inside(self):
        return all(np.all(x >= self.lower) and np.all(x <= self.upper) for x in self.seen)


def _check_box_kkt(sub, x, tol):
    """x in the box; gradient zero on free variables, sign-correct on active ones."""
    r = np.asarray(sub.A @ x).ravel() - sub.b
    assert np.all(x >= sub.lower) and np.all(x <= sub.upper)
    at_lo, at_up = x == sub.lower, x == sub.upper
    free = ~(at_lo | at_up)
    assert np.max(np.abs(r[free]), initial=0.0) <= tol
    assert np.all(r[at_lo & ~at_up] >= -tol)
    assert np.all(r[at_up & ~at_lo] <= tol)
    return r, at_lo, at_up


def test_box_qp_solution_on_a_bound():
    # min 0.5|x - c|^2 on [0, 1]^3, c = (2, -1, 0.5): x = (1, 0, 0.5), r = (-1, 1, 0)
    c = np.array([2.0, -1.0, 0.5])
    sub = BoxQP(np.eye(3), c, np.zeros(3), np.ones(3))
    res = Newton().solve(sub, np.array([0.3, 0.7, 0.9]), 1e-12, 50)
    assert res.status == "converged"
    np.testing.assert_array_equal(res.x, [1.0, 0.0, 0.5])  # bounds reached exactly
    r, at_lo, at_up = _check_box_kkt(sub, res.x, 1e-12)
    np.testing.assert_allclose(r, [-1.0, 1.0, 0.0], atol=1e-12)
    assert sub.inside()
    assert res.nit <= 3


def test_box_qp_coupled_dense_and_sparse_agree():
    # tridiagonal SPD A, b pushes some variables into each bound
    n = 60
    rng = np.random.default_rng(3)
    main = 2.5 + rng.random(n)
    A = sp.diags([-np.ones(n - 1), main, -np.ones(n - 1)], [-1, 0, 1], format="csr")
    b = 3.0 * np.sin(np.linspace(0, 6 * np.pi, n))
    lo, hi = np.full(n, -0.4), np.full(n, 0.6)
    x0 = np.zeros(n)
    sparse_sub = BoxQP(A, b, lo, hi)
    dense_sub = BoxQP(A.toarray(), b, lo, hi)
    rs = Newton().solve(sparse_sub, x0, 1e-12, 100)
    rd = Newton().solve(dense_sub, x0, 1e-12, 100)
    assert rs.status == rd.status == "converged"
    _, at_lo, at_up = _check_box_kkt(sparse_sub, rs.x, 1e-10)
    assert at_lo.sum() > 5 and at_up.sum() > 5 and (~(at_lo | at_up)).sum() > 5
    np.testing.assert_allclose(rs.x, rd.x, atol=1e-12)
    assert sparse_sub.inside() and dense_sub.inside()


def test_box_fixed_variable_and_trust_region_delegates():
    # lb == ub fixes a variable; the trust-region solver uses the projected Newton path
    c = np.array([2.0, 3.0])
    sub = BoxQP(np.array([[2.0, 0.5], [0.5, 1.0]]), c, [0.25, -5.0], [0.25, 5.0])
    res = TrustRegion().solve(sub, np.array([3.0, 0.0]), 1e-12, 50)  # x0 outside: clipped
    assert res.status == "converged"
    assert res.x[0] == 0.25
    assert res.x[1] == pytest.approx((3.0 - 0.5 * 0.25) / 1.0, rel=1e-12)
    assert sub.inside()


def test_box_escapes_a_saddle_on_a_bound():
    # min -x1^2 + x1 on [0, 2] (plus a convex x2): x1 = 0 has a positive gradient but
    # the lower value -2 lies at the other bound; the curvature step finds it
    A = np.diag([-2.0, 1.0])
    sub = BoxQP(A, np.array([-1.0, 0.0]), [0.0, -1.0], [2.0, 1.0])
    res = Newton().solve(sub, np.array([0.0, 0.5]), 1e-10, 50)
    assert res.status == "converged"
    np.testing.assert_allclose(res.x, [2.0, 0.0], atol=1e-12)
    assert sub.inside()


def test_minimize_bound_multipliers_from_the_gradient():
    c = np.array([2.0, -1.0, 0.5])
    res = minimize(lambda x: 0.5 * float((x - c) @ (x - c)), [0.5, 0.5, 0.5],
                   jac=lambda x: x - c, hess=lambda x: np.eye(3),
                   bounds=Bounds(0.0, 1.0))
    assert res.success and res.status == Status.CONVERGED_KKT, res.message
    np.testing.assert_array_equal(res.x, [1.0, 0.0, 0.5])
    # grad f + multipliers_bounds = 0: +1 at the upper bound, -1 at the lower one
    np.testing.assert_allclose(res.multipliers_bounds, [1.0, -1.0, 0.0], atol=1e-12)
    assert res.stationarity <= 1e-12 and res.complementarity == 0.0


def test_minimize_iterates_never_leave_the_box():
    # f = sum x^2.5 - c x is NaN for x < 0; x0 starts outside the box. Solution:
    # x1 at its upper bound 0.3, x2 at its lower bound 0, x0 = 0.6 from the constraint
    seen = []
    c = np.array([2.0, 3.0, -1.0])

    def f(x):
        seen.append(x.copy())
        return float(np.sum(x ** 2.5) - c @ x)

    def jac(x):
        seen.append(x.copy())
        return 2.5 * x ** 1.5 - c

    def hess(x):
        seen.append(x.copy())
        return np.diag(3.75 * x ** 0.5)

    con = NonlinearConstraint(lambda x: x[0] + 2 * x[1] + 3 * x[2], -np.inf, 1.2,
                              jac=lambda x: np.array([[1.0, 2.0, 3.0]]),
                              hess=lambda x, v: np.zeros((3, 3)))
    for penalty in ("exp-met1", "rockafellar", "log-met2", "quad-met2"):
        seen.clear()
        res = minimize(f, [-1.0, 0.2, 5.0], jac=jac, hess=hess, constraints=con,
                       bounds=Bounds([0.0, 0.0, 0.0], [np.inf, 0.3, np.inf]),
                       penalty=penalty)
        assert res.success, (penalty, res.message)
        assert "moved into the bounds" in res.message
        pts = np.array(seen)
        assert np.all(pts >= 0.0) and np.all(pts[:, 1] <= 0.3), penalty
        np.testing.assert_allclose(res.x, [0.6, 0.3, 0.0], atol=1e-9)
        mu = res.multipliers[0][0]
        assert mu == pytest.approx(2.0 - 2.5 * 0.6 ** 1.5, rel=1e-6)
        # grad f + mu grad c + multipliers_bounds = 0
        g = jac(res.x) + mu * np.array([1.0, 2.0, 3.0])
        np.testing.assert_allclose(res.multipliers_bounds, -g, atol=1e-7)
        assert res.multipliers_bounds[1] > 0 > res.multipliers_bounds[2]


def test_polish_keeps_active_bounds():
    # min (x0-2)^2 + (x1-2)^2 s.t. x0 + x1 <= 2.5, x1 <= 1 (bound): x = (1.5, 1),
    # mu = 1 for the constraint, 1 for the upper bound of x1
    f = lambda x: float((x[0] - 2) ** 2 + (x[1] - 2) ** 2)  # noqa: E731
    con = LinearConstraint([[1.0, 1.0]], -np.inf, 2.5)
    for penalty in ("exp-met1", "rockafellar", "quad-met2"):
        res = minimize(f, [0.0, 0.0], jac=lambda x: 2 * (x - 2), hess=lambda x: 2 * np.eye(2),
                       constraints=con, bounds=[(None, None), (-3.0, 1.0)], penalty=penalty)
        assert res.success, res.message
        np.testing.assert_allclose(res.x, [1.5, 1.0], atol=1e-9)
        assert res.x[1] <= 1.0
        assert res.multipliers[0][0] == pytest.approx(1.0, rel=1e-7)
        np.testing.assert_allclose(res.multipliers_bounds, [0.0, 1.0], atol=1e-7)


def test_bounds_as_constraints_gives_the_same_solution():
    f = lambda x: float((x[0] - 2) ** 2 + (x[1] - 2) ** 2)  # noqa: E731
    kw = dict(jac=lambda x: 2 * (x - 2), hess=lambda x: 2 * np.eye(2),
              constraints=LinearConstraint([[1.0, 1.0]], -np.inf, 2.5),
              bounds=[(None, None), (-3.0, 1.0)])
    box = minimize(f, [0.0, 0.0], **kw)
    rows = minimize(f, [0.0, 0.0], **kw, options={"bounds_as": "constraints"})
    assert box.success and rows.success
    np.testing.assert_allclose(box.x, rows.x, atol=1e-8)
    np.testing.assert_allclose(box.multipliers_bounds, rows.multipliers_bounds, atol=1e-6)


def test_x0_clipped_into_the_box_without_project_x0():
    res = minimize(lambda x: (x[0] - 1) ** 2, [3.0], bounds=[(-1.0, 0.0)],
                   options={"project_x0": False})
    assert res.success and "moved into the bounds" in res.message
    assert res.x[0] == 0.0
    assert res.multipliers_bounds[0] == pytest.approx(2.0, rel=1e-6)


def test_bounds_as_validated():
    with pytest.raises(InputError, match="bounds_as"):
        minimize(lambda x: x @ x, [1.0], bounds=[(0, 1)], options={"bounds_as": "penalty"})


def test_other_methods_keep_bounds_as_inequalities():
    # the exterior penalty approaches the bound from outside (bounds are penalised)
    res = minimize(lambda x: (x[0] - 2) ** 2, [0.5], jac=lambda x: 2 * (x - 2),
                   hess=lambda x: 2 * np.eye(1), bounds=[(0, 1)], method="exterior-penalty")
    assert res.x[0] > 1.0
    assert res.multipliers_bounds[0] == pytest.approx(2.0, rel=1e-3)
