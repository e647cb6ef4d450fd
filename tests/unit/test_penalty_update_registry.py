"""One registry of penalty-parameter update rules serves ``optim.minimize`` and the contact algorithms.

A rule registered with :func:`alcontact.optim.register_strategy` becomes a valid ``strategy``
of both; these tests check that the configured rule is the one that ran (a counting rule is
called, with the loop's measures and the parameters the loop offers) and that its factor
took effect.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import NonlinearConstraint

from _helpers import sq, sq_grad, sq_hess
from alcontact.contact import ContactOptions, solve
from alcontact.errors import InputError, UnknownNameError
from alcontact.optim import (StrategyState, available_strategies, make_strategy, minimize, register_strategy,
                             unregister_strategy)
from alcontact.problems.blocks import patch_block

HALFPLANE = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, -1.0, jac=lambda x: np.array([[1.0, 1.0]]),
                                hess=lambda x, v: np.zeros((2, 2)))


class _Counting:
    """Records every call; returns ``factor`` at the outer iterations in ``at`` (1 elsewhere)."""

    name = "counting"
    made: list = []

    def __init__(self, factor: float = 1.0, at: tuple = (), tau=None, feas_tol=None):
        self.factor, self.at, self.tau, self.feas_tol = factor, tuple(at), tau, feas_tol
        self.calls: list[StrategyState] = []
        _Counting.made.append(self)

    def __call__(self, s: StrategyState) -> float:
        self.calls.append(s)
        return self.factor if s.k in self.at else 1.0


@pytest.fixture
def counting():
    _Counting.made = []
    register_strategy("counting", _Counting, doc="test rule that records its calls",
                      loop_parameters=("tau", "factor", "feas_tol"))
    yield _Counting
    unregister_strategy("counting")


def test_registered_rule_is_listed_and_unregistered(counting):
    assert "counting" in available_strategies()
    assert ContactOptions(strategy="counting").strategy == "counting"
    unregister_strategy("counting")
    assert "counting" not in available_strategies()
    with pytest.raises(InputError, match="counting"):
        ContactOptions(strategy="counting")
    register_strategy("counting", _Counting, doc="again", loop_parameters=("tau", "factor", "feas_tol"))


def test_register_refuses_duplicates_and_unknown_names_list_the_rules():
    with pytest.raises(InputError, match="already registered"):
        register_strategy("fixed", _Counting, doc="clash")
    with pytest.raises(UnknownNameError, match="infeasibility"):
        make_strategy("infeasibilty")


def test_offered_loop_parameters_reach_only_the_rules_that_take_them():
    offered = {"tau": 0.5, "factor": 3.0, "feas_tol": 1e-3}
    rule = make_strategy("infeasibility", offered)
    assert (rule.tau, rule.factor, rule.feas_tol) == (0.5, 3.0, 1e-3)
    per = make_strategy("per-constraint", offered)
    assert (per.tau, per.factor, per.feas_tol) == (0.5, 3.0, 0.0)  # a relative test: no absolute tolerance
    assert make_strategy("always", offered).factor == 3.0
    assert make_strategy("infeasibility", offered, tau=0.1).tau == 0.1  # the user's value wins


def test_optim_runs_the_configured_rule(counting):
    res = minimize(sq, [1.0, 2.0], jac=sq_grad, hess=sq_hess, constraints=HALFPLANE, penalty="exp-met1",
                   options={"strategy": "counting", "feas_tol": 1e-7})
    assert res.success, res.message
    assert res.strategy == "counting"
    (rule,) = counting.made
    assert rule.feas_tol == 1e-7  # optim offers its feasibility tolerance
    assert len(rule.calls) >= 1
    assert [s.k for s in rule.calls] == list(range(1, len(rule.calls) + 1))
    np.testing.assert_allclose(res.x, [-0.5, -0.5], atol=1e-7)


def test_contact_runs_the_configured_rule(counting):
    problem = patch_block(2, 1, n=2)
    base = solve(problem, "simo-laursen", penalty_scale=1.0, tau=0.3, alpha=7.0, strategy="fixed")
    assert base.result.success and base.result.outer_iterations >= 3
    assert counting.made == []
    sol = solve(problem, "simo-laursen", penalty_scale=1.0, tau=0.3, alpha=7.0, strategy="counting")
    (rule,) = counting.made
    # contact offers tau, alpha as the factor and tol_penetration as the feasibility tolerance
    assert (rule.tau, rule.factor, rule.feas_tol) == (0.3, 7.0, 1e-8)
    hist = sol.result.history
    # called after every outer iteration but the converged last one, with that iteration's penetration
    assert [s.k for s in rule.calls] == [h.k for h in hist[:-1]]
    assert [s.feasibility for s in rule.calls] == [h.penetration for h in hist[:-1]]
    assert [s.complementarity for s in rule.calls] == [h.complementarity for h in hist[:-1]]
    assert rule.calls[0].prev_feasibility == np.inf
    assert [s.prev_feasibility for s in rule.calls[1:]] == [h.penetration for h in hist[:-2]]
    # a factor of 1 keeps the stiffness: the same run as "fixed"
    assert sol.result.outer_iterations == base.result.outer_iterations
    np.testing.assert_array_equal(sol.u, base.u)


def test_contact_rule_factor_multiplies_the_stiffness():
    """A rule tightening once, at outer iteration 2, multiplies eps_N by its factor from iteration 3 on."""

    class _Once:
        name = "once"

        def __init__(self, factor):
            self.factor = factor

        def __call__(self, s):
            return self.factor if s.k == 2 else 1.0

    register_strategy("once", _Once, doc="tighten once", loop_parameters=("factor",))
    try:
        sol = solve(patch_block(2, 1, n=2), "simo-laursen", penalty_scale=1.0, strategy="once", alpha=5.0)
    finally:
        unregister_strategy("once")
    eps = [h.eps_n for h in sol.result.history]
    assert len(eps) >= 3, eps
    assert eps[1] == eps[0] and eps[2] == pytest.approx(5.0 * eps[0], rel=1e-15)
    assert sol.result.success
