"""Unit tests of alcontact.optim: methods, penalties, KKT measures, failure branches.

Reaches inside the package: one spy on ``optim._inner._sparse_direction`` to check the sparse path
ran (no result field records it).
"""

import dataclasses
import logging

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import BFGS, Bounds, LinearConstraint, NonlinearConstraint

from _helpers import sq, sq_grad, sq_hess
from alcontact import errors
from alcontact.optim import (ALResult, IterationRecord, Status, available_inner_solvers,
                             available_methods, available_strategies, minimize)

AL_PENALTIES = ["exp-met1", "exp-met2", "log-met1", "log-met2", "quad-met1", "quad-met2",
                "rockafellar"]


# x1 + x2 <= -1 -> solution (-1/2, -1/2), multiplier 1
HALFPLANE = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, -1.0,
                                jac=lambda x: np.array([[1.0, 1.0]]),
                                hess=lambda x, v: np.zeros((2, 2)))


def test_registries():
    assert available_methods() == ["al", "barrier", "exterior-penalty", "hestenes-powell"]
    assert {"fixed", "always", "infeasibility", "kkt"} <= set(available_strategies())
    assert "newton" in available_inner_solvers()


@pytest.mark.parametrize("penalty", AL_PENALTIES)
def test_al_each_penalty_inequality(penalty):
    res = minimize(sq, [1.0, 2.0], jac=sq_grad, hess=sq_hess, constraints=HALFPLANE,
                   penalty=penalty)
    assert res.status == Status.CONVERGED_KKT, res.message
    np.testing.assert_allclose(res.x, [-0.5, -0.5], atol=1e-7)
    assert res.multipliers_ineq[0] == pytest.approx(1.0, rel=1e-6)
    assert res.multipliers[0][0] == pytest.approx(1.0, rel=1e-6)
    assert res.feasibility <= 1e-8 and res.complementarity <= 1e-8
    assert res.stationarity <= 1e-8


@pytest.mark.parametrize("penalty", AL_PENALTIES)
def test_al_inactive_and_active_constraints(penalty):
    # min (x0-2)^2 + (x1-2)^2 + x2^2 s.t. x0 + x1 <= 1 (active), x0 - x1 + x2^2 <= 0.5
    # (inactive at the solution (0.5, 0.5, 0)); f* = 4.5, multipliers (3, 0)
    con = NonlinearConstraint(lambda x: np.array([x[0] + x[1], x[0] - x[1] + x[2] ** 2]),
                              -np.inf, [1.0, 0.5])
    f = lambda x: (x[0] - 2) ** 2 + (x[1] - 2) ** 2 + x[2] ** 2  # noqa: E731
    res = minimize(f, [0.0, 0.0, 0.0], jac=lambda x: 2 * (x - [2, 2, 0]),
                   hess=lambda x: 2 * np.eye(3), constraints=con, penalty=penalty)
    assert res.success, res.message
    np.testing.assert_allclose(res.x, [0.5, 0.5, 0.0], atol=1e-6)
    np.testing.assert_allclose(res.multipliers[0], [3.0, 0.0], atol=1e-6)


def test_hestenes_powell_equality():
    con = LinearConstraint([[1.0, 1.0]], 1.0, 1.0)
    res = minimize(sq, [3.0, -1.0], jac=sq_grad, hess=sq_hess, constraints=con,
                   method="hestenes-powell")
    assert res.success
    np.testing.assert_allclose(res.x, [0.5, 0.5], atol=1e-8)
    assert res.multipliers_eq[0] == pytest.approx(-1.0, rel=1e-6)
    assert res.multipliers_ineq.size == 0


def test_hestenes_powell_nonlinear_equality():
    # min x0 + x1 s.t. x0^2 + x1^2 = 2 -> (-1, -1), lambda = 1/2
    con = NonlinearConstraint(lambda x: x @ x, 2.0, 2.0, jac=lambda x: 2 * x[None, :],
                              hess=lambda x, v: 2 * v[0] * np.eye(2))
    res = minimize(lambda x: x[0] + x[1], [1.0, -0.5], jac=lambda x: np.ones(2),
                   hess=lambda x: np.zeros((2, 2)), constraints=con,
                   method="hestenes-powell")
    assert res.success, res.message
    np.testing.assert_allclose(res.x, [-1.0, -1.0], atol=1e-7)
    assert res.multipliers_eq[0] == pytest.approx(0.5, rel=1e-6)


@pytest.mark.parametrize("penalty", ["exp-met1", "log-met1", "rockafellar", "quad-met2"])
def test_al_mixed_equality_inequality_bounds(penalty):
    # min (x0-1)^2 + (x1-2)^2 + (x2-3)^2 s.t. x0 + x1 + x2 = 3, x2 <= 1.5, x >= 0
    # solution: x2 = 1.5 (active), x0 + x1 = 1.5 with x1 - x0 = 1 -> (0.25, 1.25, 1.5)
    f = lambda x: float(np.sum((x - [1, 2, 3]) ** 2))  # noqa: E731
    cons = [LinearConstraint([[1, 1, 1]], 3, 3), LinearConstraint([[0, 0, 1]], -np.inf, 1.5)]
    res = minimize(f, [1.0, 1.0, 1.0], jac=lambda x: 2 * (x - [1, 2, 3]),
                   hess=lambda x: 2 * np.eye(3), constraints=cons,
                   bounds=Bounds(0, np.inf), penalty=penalty)
    assert res.success, res.message
    np.testing.assert_allclose(res.x, [0.25, 1.25, 1.5], atol=1e-7)
    assert res.fun == pytest.approx(0.75 ** 2 + 0.75 ** 2 + 1.5 ** 2, rel=1e-8)
    lam = res.multipliers[0][0]
    assert lam == pytest.approx(1.5, rel=1e-6)  # 2(x0 - 1) + lam = 0
    assert res.multipliers[1][0] == pytest.approx(1.5, rel=1e-6)
    np.testing.assert_allclose(res.multipliers_bounds, 0.0, atol=1e-7)


def test_bounds_active_lower_and_upper():
    # min (x0+1)^2 + (x1-3)^2 on [0, 2]^2 -> (0, 2), bound multipliers (-2 at lb, +2 at ub)
    f = lambda x: (x[0] + 1) ** 2 + (x[1] - 3) ** 2  # noqa: E731
    res = minimize(f, [1.0, 1.0], jac=lambda x: np.array([2 * (x[0] + 1), 2 * (x[1] - 3)]),
                   hess=lambda x: 2 * np.eye(2), bounds=[(0, 2), (0, 2)])
    assert res.success
    np.testing.assert_allclose(res.x, [0.0, 2.0], atol=1e-7)
    np.testing.assert_allclose(res.multipliers_bounds, [-2.0, 2.0], rtol=1e-6)
    assert res.multipliers == ()


def test_sparse_jacobian_and_hessian_stay_sparse(monkeypatch):
    n = 30
    target = np.linspace(-1, 2, n)
    seen = []
    f = lambda x: float(np.sum((x - target) ** 2))  # noqa: E731

    def hess(x):
        return sp.identity(n, format="csr") * 2.0

    # chain constraints x_{i+1} - x_i <= 0.05 (sparse Jacobian), and sum x^2 <= 20
    D = sp.diags([-np.ones(n - 1), np.ones(n - 1)], [0, 1], shape=(n - 1, n), format="csr")
    cons = [LinearConstraint(D, -np.inf, 0.05),
            NonlinearConstraint(lambda x: np.array([x @ x]), -np.inf, 20.0,
                                jac=lambda x: sp.csr_matrix(2 * x[None, :]),
                                hess=lambda x, v: sp.identity(n, format="csr") * 2 * v[0])]
    from alcontact.optim import _inner
    orig = _inner._sparse_direction

    def spy(H, g, beta):
        seen.append(sp.issparse(H))
        return orig(H, g, beta)

    monkeypatch.setattr(_inner, "_sparse_direction", spy)
    res = minimize(f, np.zeros(n), jac=lambda x: 2 * (x - target), hess=hess,
                   constraints=cons, penalty="rockafellar")
    assert res.success, res.message
    assert seen and all(seen)
    assert np.all(np.diff(res.x) <= 0.05 + 1e-8)
    # the same problem with dense data gives the same answer
    cons_dense = [LinearConstraint(D.toarray(), -np.inf, 0.05),
                  NonlinearConstraint(lambda x: np.array([x @ x]), -np.inf, 20.0,
                                      jac=lambda x: 2 * x[None, :],
                                      hess=lambda x, v: 2 * v[0] * np.eye(n))]
    res_d = minimize(f, np.zeros(n), jac=lambda x: 2 * (x - target),
                     hess=lambda x: 2 * np.eye(n), constraints=cons_dense,
                     penalty="rockafellar")
    np.testing.assert_allclose(res.x, res_d.x, atol=1e-7)


def test_finite_differences_and_jac_true_and_strings():
    # no jac / hess at all; constraint jac '2-point', hess BFGS -> finite differences
    con = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, -1.0, jac="2-point", hess=BFGS())
    res = minimize(sq, [1.0, 2.0], constraints=con)
    assert res.success and "finite differences" in res.message
    np.testing.assert_allclose(res.x, [-0.5, -0.5], atol=1e-6)
    res2 = minimize(lambda x: (sq(x), sq_grad(x)), [1.0, 2.0], jac=True, constraints=HALFPLANE)
    assert res2.success and res2.njev == res2.nfev
    np.testing.assert_allclose(res2.x, [-0.5, -0.5], atol=1e-7)


def test_legacy_dict_constraint():
    # SciPy dict convention: 'ineq' means fun(x) >= 0
    res = minimize(sq, [1.0, 2.0], jac=sq_grad, hess=sq_hess,
                   constraints={"type": "ineq", "fun": lambda x: -1.0 - x[0] - x[1]})
    assert res.success
    np.testing.assert_allclose(res.x, [-0.5, -0.5], atol=1e-7)


def test_exterior_penalty_method():
    res = minimize(sq, [1.0, 2.0], jac=sq_grad, hess=sq_hess, constraints=HALFPLANE,
                   method="exterior-penalty")
    assert res.success
    np.testing.assert_allclose(res.x, [-0.5, -0.5], atol=1e-7)
    # t = 1/eta doubles every iteration (Algorithm 5.2); iterates are infeasible
    etas = [r.eta_max for r in res.history]
    np.testing.assert_allclose(np.array(etas[1:]) / np.array(etas[:-1]), 0.5)
    assert all(r.feasibility > 0 for r in res.history)


def test_unconstrained():
    res = minimize(lambda x: (x[0] - 3) ** 4 + (x[1] + 1) ** 2, [0.0, 0.0])
    assert res.status == Status.UNCONSTRAINED_CONVERGED
    np.testing.assert_allclose(res.x, [3.0, -1.0], atol=1e-2)


def test_kkt_measures_match_definitions():
    res = minimize(sq, [1.0, 2.0], jac=sq_grad, hess=sq_hess, constraints=HALFPLANE)
    x, mu = res.x, res.multipliers_ineq
    g = x[0] + x[1] + 1.0
    assert res.constr_ineq[0] == pytest.approx(g)
    assert res.feasibility == pytest.approx(max(g, 0.0))
    assert res.complementarity == pytest.approx(abs(mu[0] * g))
    r = 2 * x + mu[0] * np.ones(2)
    assert res.stationarity == pytest.approx(np.max(np.abs(r)) / max(1, np.max(np.abs(2 * x))))
    h = res.history[-1]
    assert isinstance(h, IterationRecord)
    assert h.feasibility == res.feasibility and h.stationarity == res.stationarity
    assert res.nit == len(res.history) and res.nit_inner == sum(
        r.inner_iterations for r in res.history)


def test_result_is_frozen():
    res = minimize(sq, [1.0, 2.0], jac=sq_grad, hess=sq_hess, constraints=HALFPLANE)
    assert isinstance(res, ALResult)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.x = np.zeros(2)
    with pytest.raises(ValueError):
        res.x[0] = 1.0
    assert res.raise_for_status() is res


# ----------------------------------------------------------------- failures
def test_maxiter_gives_negative_status_warning_and_raise(caplog):
    with caplog.at_level(logging.WARNING, logger="alcontact.optim"):
        res = minimize(sq, [1.0, 2.0], jac=sq_grad, hess=sq_hess, constraints=HALFPLANE,
                       options={"maxiter": 1})
    assert res.status == Status.MAXITER and res.status < 0 and not res.success
    assert "maxiter" in res.message
    assert any("failed" in r.message and "try" in r.message for r in caplog.records)
    with pytest.raises(errors.ConvergenceError, match="MAXITER"):
        res.raise_for_status()


def test_nan_mid_run_gives_nonfinite_status(caplog):
    calls = {"n": 0}

    def jac(x):
        calls["n"] += 1
        return np.full(2, np.nan) if calls["n"] > 3 else 2 * x

    with caplog.at_level(logging.WARNING, logger="alcontact.optim"):
        res = minimize(sq, [1.0, 2.0], jac=jac, hess=sq_hess, constraints=HALFPLANE)
    assert res.status == Status.NONFINITE
    assert "non-finite value from jac" in res.message
    assert caplog.records


def test_nan_hessian_mid_run():
    calls = {"n": 0}

    def hess(x):
        calls["n"] += 1
        return np.full((2, 2), np.nan) if calls["n"] > 1 else 2 * np.eye(2)

    res = minimize(sq, [1.0, 2.0], jac=sq_grad, hess=hess, constraints=HALFPLANE)
    assert res.status == Status.NONFINITE and "hess" in res.message


def test_nan_at_x0_raises():
    with pytest.raises(errors.NonFiniteError, match="fun"):
        minimize(lambda x: np.nan, [1.0, 2.0], jac=sq_grad)
    bad = NonlinearConstraint(lambda x: np.array([np.nan]), -np.inf, 0.0)
    with pytest.raises(errors.NonFiniteError, match="constraints"):
        minimize(sq, [1.0, 2.0], jac=sq_grad, constraints=bad)


def test_bad_dimensions():
    with pytest.raises(errors.InputError, match="3.*2|2.*3"):
        minimize(sq, [1.0, 2.0], jac=lambda x: np.zeros(3))
    with pytest.raises(errors.InputError, match="3 columns|columns"):
        minimize(sq, [1.0, 2.0], constraints=LinearConstraint(np.ones((1, 3)), 0, 1))
    with pytest.raises(errors.InputError, match="2 entries.*3 components|3 components"):
        minimize(sq, [1.0, 2.0, 3.0],
                 constraints=NonlinearConstraint(lambda x: x, [0, 0], [1, 1]))
    with pytest.raises(errors.InputError, match="Hessian"):
        minimize(sq, [1.0, 2.0], jac=sq_grad, hess=lambda x: np.eye(3))
    with pytest.raises(errors.InputError, match="lb"):
        minimize(sq, [1.0, 2.0], bounds=Bounds([1, 1], [0, 2]))


def test_unknown_names():
    with pytest.raises(errors.UnknownNameError, match="Did you mean 'barrier'"):
        minimize(sq, [1.0], method="barier")
    with pytest.raises(errors.UnknownNameError, match="penalty"):
        minimize(sq, [1.0], penalty="exp-met3")
    with pytest.raises(errors.UnknownNameError, match="strategy"):
        minimize(sq, [1.0], options={"strategy": "doubling"})
    with pytest.raises(errors.UnknownNameError, match="option"):
        minimize(sq, [1.0], options={"maxiters": 3})
    with pytest.raises(errors.UnknownNameError, match="inner solver"):
        minimize(sq, [1.0], options={"inner": "bfgs"})


def test_method_penalty_mismatch():
    with pytest.raises(errors.InputError, match="does not take"):
        minimize(sq, [1.0, 2.0], constraints=HALFPLANE, method="barrier", penalty="exp-met1")
    with pytest.raises(errors.InputError, match="equality constraints only"):
        minimize(sq, [1.0, 2.0], constraints=HALFPLANE, method="hestenes-powell")
    with pytest.raises(errors.InputError, match="inequality constraints only"):
        minimize(sq, [-1.0, -2.0], constraints=LinearConstraint([[1, 1]], 1, 1),
                 method="barrier")


def test_barrier_start_outside_domain():
    with pytest.raises(errors.DomainError, match=r"inequality 0 .*constraints\[0\]"):
        minimize(sq, [1.0, 2.0], constraints=HALFPLANE, method="barrier")


def test_modified_barrier_user_eta0_outside_domain():
    # g(x0) = 4; the pure log-met1 needs g/eta < 1
    with pytest.raises(errors.DomainError, match="eta0 > 4"):
        minimize(sq, [1.0, 2.0], constraints=HALFPLANE, penalty="log-met1",
                 options={"eta0": 1.0, "extrapolate": False})
    # automatic eta0 puts x0 inside the domain
    res = minimize(sq, [1.0, 2.0], constraints=HALFPLANE, penalty="log-met1",
                   options={"extrapolate": False})
    assert res.success
    # with the quadratic extrapolation (default) the subproblem is defined everywhere
    res = minimize(sq, [1.0, 2.0], constraints=HALFPLANE, penalty="log-met1",
                   options={"eta0": 1.0})
    assert res.success


def test_bad_options():
    with pytest.raises(errors.InputError, match="maxiter"):
        minimize(sq, [1.0], options={"maxiter": 0})
    with pytest.raises(errors.InputError, match="gtol"):
        minimize(sq, [1.0], options={"tol": -1.0})
    with pytest.raises(errors.InputError, match="tau"):
        minimize(sq, [1.0], constraints=HALFPLANE if False else (),
                 options={"strategy": "infeasibility", "strategy_options": {"tau": 2}})


def test_infeasible_problem_stops():
    cons = [LinearConstraint([[1.0, 0.0]], -np.inf, -1.0), LinearConstraint([[1.0, 0.0]], 1.0,
                                                                            np.inf)]
    logging.getLogger("alcontact.optim").disabled = True
    try:
        res = minimize(sq, [0.0, 0.0], jac=sq_grad, hess=sq_hess, constraints=cons,
                       penalty="rockafellar", options={"maxiter": 60})
    finally:
        logging.getLogger("alcontact.optim").disabled = False
    assert res.status < 0
    assert res.feasibility >= 0.99


def test_inner_line_search_failure_status():
    # a gradient inconsistent with fun: Newton directions are not descent directions
    logging.getLogger("alcontact.optim").disabled = True
    try:
        res = minimize(sq, [1.0, 2.0], jac=lambda x: -2 * x, hess=lambda x: -2 * np.eye(2),
                       constraints=HALFPLANE, penalty="rockafellar")
    finally:
        logging.getLogger("alcontact.optim").disabled = False
    assert res.status == Status.INNER_FAILED
