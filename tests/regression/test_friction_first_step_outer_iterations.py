"""Issue 9: Cattaneo-Mindlin with friction active from the first step, outer iterations of Algorithms 6.2 / 6.4.

With friction in the normal phase, points that enter contact start with
:math:`\\lambda_N = 0`. With the fixed Coulomb radius :math:`\\mu\\lambda_N`
((6.2c)) in every subproblem they slip freely in the first subproblem of the
step, the second-order multiplier update cannot foresee that they stick, and a
normal step needs 3 (6.2) or 4 (6.4) outer iterations: 2.5x and 3x the
semi-smooth Newton reference over the 8 steps. With the coupled radius
:math:`\\mu t_N(g)` (``radius="traction"``) they stick from the first subproblem
and every step needs 2 (the subproblem from the warm start and the one that
confirms the fixed point): 2x, with the same solution. The default
(``radius="multiplier"``) takes the coupled radius in the first subproblem of a
step only (the hybrid radius of ``_friction._coupled_start``), the fixed one
afterwards: 2x as well, with the same solution.

Reaches inside the package: the rule under test (``_coupled_start`` of
``contact.algorithms._coulomb``) is switched off to show the cost it saves.
"""

import numpy as np
import pytest

from _helpers import assert_same_friction_steps
from alcontact.contact import solve_friction
from alcontact.contact.algorithms import _coulomb as _friction
from alcontact.problems import friction as fp

#: as in tests/regression/test_friction_outer_iterations.py: tractions of two solvers of the
#: same discrete problem agree to this fraction of the largest pressure (10x tol_multiplier)
TRACTION_TOL = 1e-7


@pytest.fixture(scope="module")
def mindlin():
    prob, hist = fp.cattaneo_mindlin_2d(n_per_a=6, order=2, volumetric="p0", nu=0.4999, size=320.0, growth=1.5,
                                        frictionless_approach=False)
    assert hist.friction_factor(hist.times[0]) == 1.0
    return prob, hist, solve_friction(prob, hist, "ssn")


def _same_solution(sol, ref):
    """Same steps, tractions within TRACTION_TOL of the largest pressure, same open / stick / slip zones."""
    assert_same_friction_steps(sol, ref, TRACTION_TOL)


@pytest.mark.parametrize("alg,pen", [("simo-laursen", None), ("family-p", "exp-met1"), ("family-p", "log-met1")])
def test_coupled_radius_outer_iterations_within_twice_reference(mindlin, alg, pen):
    """radius="traction": outer(AL) <= 2 outer(SSN) = 16 over 4 normal + 4 tangential steps (measured 16).

    Reference: the SSN solution of the same discrete problem; tractions agree to
    TRACTION_TOL = 1e-7 of the largest pressure and the open/stick/slip zones are identical.
    """
    prob, hist, ref = mindlin
    assert ref.status > 0 and ref.outer_iterations == len(hist.times)
    sol = solve_friction(prob, hist, alg, pen, radius="traction")
    assert sol.status > 0, sol.message
    assert sol.outer_iterations <= 2 * ref.outer_iterations
    _same_solution(sol, ref)
    assert np.any(sol.steps[0].shear != 0.0)  # friction acts in the normal phase


@pytest.mark.parametrize("alg,pen", [("simo-laursen", None), ("family-p", "exp-met1"), ("family-p", "exp-met2"),
                                     ("family-p", "log-met1"), ("family-p", "log-met2"),
                                     ("family-p", "quad-met2")])
def test_default_outer_iterations_within_twice_reference(mindlin, alg, pen):
    """Default options (hybrid radius): outer(AL) <= 2 outer(SSN) = 16 over 4 + 4 steps (measured 16 for all).

    Reference: the SSN solution of the same discrete problem; tractions agree to
    TRACTION_TOL = 1e-7 of the largest pressure and the open/stick/slip zones are identical;
    every step needs at most 2 outer iterations (measured [2] * 8).
    """
    prob, hist, ref = mindlin
    sol = solve_friction(prob, hist, alg, pen)
    assert sol.status > 0, sol.message
    _same_solution(sol, ref)
    assert sol.outer_iterations <= 2 * ref.outer_iterations
    assert max(s.outer_iterations for s in sol.steps) <= 2, [s.outer_iterations for s in sol.steps]
    assert np.any(sol.steps[0].shear != 0.0)  # friction acts in the normal phase


def test_fixed_radius_needs_more_outer_iterations_in_the_normal_phase(mindlin, monkeypatch):
    """Fixed radius in every subproblem (the hybrid switched off): same solution, 3 outer per normal step.

    Measured 20 = [3, 3, 3, 3, 2, 2, 2, 2]; asserted: at most 3 per normal step and 2 per
    tangential step, and more than 2x the reference (the gap the hybrid radius closes).
    """
    monkeypatch.setattr(_friction, "_coupled_start", lambda ctx: False)
    prob, hist, ref = mindlin
    sol = solve_friction(prob, hist, "simo-laursen")
    assert sol.status > 0, sol.message
    _same_solution(sol, ref)
    per_step = [s.outer_iterations for s in sol.steps]
    assert max(per_step[:4]) <= 3 and max(per_step[4:]) <= 2, per_step
    assert sol.outer_iterations > 2 * ref.outer_iterations
