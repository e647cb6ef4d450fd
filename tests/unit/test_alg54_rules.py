"""Algorithm 5.4's penalty update as printed and as corrected: registered rules, each checked by hand.

The dissertation prints ``eta <- alpha eta`` (``alpha > 1``); ``eta`` divides ``g`` in (5.28), so that
*weakens* the penalty; section 6.3.1 says the opposite (SEED_NOTES, "Inconsistency"). Both rules are
registered (``alg54-printed``: factor ``1/alpha``; ``alg54-corrected``: factor ``alpha``; the loop applies
``eta <- eta / factor``, contact ``eps_N <- factor * eps_N``). Hand-computed cases: with ``eta0 = 1`` and
``alpha = 2``, after ``k`` outer iterations ``eta = 2**k`` (printed) and ``2**-k`` (corrected); in contact,
``eps_N`` after ``k`` outer iterations is ``eps0 / 2**(k-1)`` or ``eps0 * 2**(k-1)`` (the last iteration stops
before its update).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import NonlinearConstraint

from alcontact.contact import solve
from alcontact.errors import InputError
from alcontact.optim import StrategyState, available_strategies, describe_strategies, make_strategy, minimize
from alcontact.problems.hertz import hertz_2d

STATE = StrategyState(k=3, feasibility=0.5, prev_feasibility=1.0, complementarity=0.0, prev_complementarity=0.0)


def test_both_rules_are_registered_with_a_description():
    assert {"alg54-printed", "alg54-corrected"} <= set(available_strategies())
    docs = describe_strategies()
    assert "as printed" in docs["alg54-printed"] and "corrected" in docs["alg54-corrected"]


@pytest.mark.parametrize("alpha", [2.0, 3.5])
def test_factor_by_hand(alpha):
    # the factor divides eta: printed eta <- alpha eta is factor 1/alpha; corrected eta <- eta/alpha is alpha
    assert make_strategy("alg54-printed", alpha=alpha)(STATE) == pytest.approx(1.0 / alpha, rel=0, abs=1e-15)
    assert make_strategy("alg54-corrected", alpha=alpha)(STATE) == alpha
    # every iteration, whatever the measures (the printed algorithm has no test)
    worse = StrategyState(k=1, feasibility=2.0, prev_feasibility=1.0, complementarity=1.0, prev_complementarity=0.0)
    assert make_strategy("alg54-corrected")(worse) == 2.0 and make_strategy("alg54-printed")(worse) == 0.5


@pytest.mark.parametrize("alpha", [1.0, 0.5, float("nan"), True, "2"])
def test_bad_alpha_names_the_rule_and_the_range(alpha):
    with pytest.raises(InputError, match=r"alg54-printed.*alpha.*> 1"):
        make_strategy("alg54-printed", alpha=alpha)


def test_contact_loop_factor_is_not_the_rule_alpha():
    # contact offers factor = its alpha (10); Algorithm 5.4's alpha is the rule's own (default 2)
    rule = make_strategy("alg54-corrected", {"tau": 0.5, "factor": 10.0, "feas_tol": 1e-8})
    assert rule(STATE) == 2.0


def _nlp(strategy):
    con = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, -1.0, jac=lambda x: np.array([[1.0, 1.0]]))
    return minimize(lambda x: x @ x, [1.0, 2.0], jac=lambda x: 2 * x, hess=lambda x: 2 * np.eye(2),
                    constraints=con, penalty="exp-met1",
                    options={"strategy": strategy, "eta0": 1.0, "maxiter": 4, "polish": False, "stall_iter": 50})


@pytest.mark.parametrize(("rule", "eta_k"), [("alg54-printed", lambda k: 2.0 ** k),
                                              ("alg54-corrected", lambda k: 2.0 ** -k)])
def test_minimize_eta_sequence_by_hand(rule, eta_k):
    res = _nlp(rule)
    # history record k holds eta used in outer iteration k: eta0 * 2**(+-(k-1))
    etas = [h.eta_min for h in res.history]
    assert len(etas) >= 3
    assert etas == pytest.approx([eta_k(k) for k in range(len(etas))], rel=1e-15)


@pytest.mark.parametrize(("rule", "growth"), [("alg54-printed", 0.5), ("alg54-corrected", 2.0)])
def test_contact_eps_sequence_by_hand(rule, growth):
    sol = solve(hertz_2d(n_per_a=2), "simo-laursen", None, {"strategy": rule, "penalty_scale": 1.0, "maxiter": 30})
    hist = sol.result.history
    eps0 = hist[0].eps_n
    assert [h.eps_n for h in hist] == pytest.approx([eps0 * growth ** i for i in range(len(hist))], rel=1e-14)
    assert len(hist) >= 3
