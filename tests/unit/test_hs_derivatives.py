"""Hock-Schittkowski problems: exact derivatives against finite differences, and the
reported solutions against the reported optimal values.

Generated from the registry, so a newly added problem is covered automatically.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import NonlinearConstraint

from alcontact.errors import UnknownNameError
from alcontact.problems import hock_schittkowski as hs

NUMBERS = hs.numbers()


def _points(p: hs.HSProblem) -> list[np.ndarray]:
    """x0, x* and a reproducible perturbation of x*, all pulled inside the bounds."""
    rng = np.random.default_rng(p.number)
    pts = [p.x0.copy(), p.x_star.copy()]
    pts.append(p.x_star + 0.02 * (1.0 + np.abs(p.x_star)) * rng.standard_normal(p.n))
    if p.bounds is not None:
        lb, ub = np.asarray(p.bounds.lb, float), np.asarray(p.bounds.ub, float)
        pts = [np.clip(x, lb, ub) for x in pts]
    return pts


def _fd(fun, x, h_rel=1e-6):
    """Central differences of a scalar or vector function, one column per variable."""
    cols = []
    for i in range(x.size):
        h = h_rel * (1.0 + abs(x[i]))
        e = np.zeros_like(x)
        e[i] = h
        cols.append((np.asarray(fun(x + e), float) - np.asarray(fun(x - e), float)) / (2 * h))
    return np.stack(cols, axis=-1)


def _assert_close(exact, approx, what, rtol=2e-5):
    exact, approx = np.asarray(exact, float), np.asarray(approx, float)
    scale = max(1.0, float(np.max(np.abs(exact), initial=0.0)))
    err = float(np.max(np.abs(exact - approx), initial=0.0))
    assert err <= rtol * scale, f"{what}: max error {err:.3e} vs scale {scale:.3e}"


def _nonlinear(p):
    return [c for c in p.constraints if isinstance(c, NonlinearConstraint)]


def test_selection_size_and_inequalities():
    assert len(NUMBERS) >= 45
    for p in hs.problems():
        assert p.n_ineq >= 1, f"{p.name} has no inequality constraint"
        assert p.x0.shape == (p.n,) and p.x_star.shape == (p.n,)


def test_unknown_number_lists_known_ones():
    with pytest.raises(UnknownNameError, match="Known"):
        hs.get(1)


@pytest.mark.parametrize("number", NUMBERS)
def test_reported_solution_is_feasible_and_optimal(number):
    p = hs.get(number)
    assert p.max_violation(p.x_star) <= 1e-6
    assert abs(p.fun(p.x_star) - p.f_star) <= 1e-6 * max(1.0, abs(p.f_star))
    assert p.is_solved(p.fun(p.x_star), p.x_star)


@pytest.mark.parametrize("number", NUMBERS)
def test_objective_gradient_and_hessian(number):
    p = hs.get(number)
    for x in _points(p):
        _assert_close(p.jac(x), _fd(p.fun, x), f"{p.name} gradient at {x}")
        H = p.hess(x)
        assert np.allclose(H, H.T)
        _assert_close(H, _fd(p.jac, x), f"{p.name} Hessian at {x}")


@pytest.mark.parametrize("number", NUMBERS)
def test_constraint_jacobian_and_hessian(number):
    p = hs.get(number)
    rng = np.random.default_rng(1000 + number)
    for con in _nonlinear(p):
        for x in _points(p):
            J = np.atleast_2d(con.jac(x))
            _assert_close(J, np.atleast_2d(_fd(con.fun, x)), f"{p.name} constraint Jacobian at {x}")
            v = rng.standard_normal(J.shape[0])
            Hv = con.hess(x, v)
            assert np.allclose(Hv, Hv.T)
            _assert_close(Hv, _fd(lambda y: v @ np.atleast_2d(con.jac(y)), x), f"{p.name} constraint Hessian")


@pytest.mark.parametrize("number", NUMBERS)
def test_minimize_kwargs_are_scipy_ready(number):
    p = hs.get(number)
    kw = p.minimize_kwargs()
    assert set(kw) == {"fun", "x0", "jac", "hess", "constraints", "bounds"}
    kw["x0"][0] += 1.0  # a copy: the problem's start point must not change
    assert kw["x0"][0] != p.x0[0]
    assert "hess" not in p.minimize_kwargs(with_hess=False)
