"""The one Newton driver of the contact algorithms and the hyperelastic body (:func:`alcontact.optim.newton`).

Small systems with known solutions: quadratic convergence on a smooth problem, each
failure status (line search, NaN, singular matrix, iteration limit, interrupt),
backtracking out of a domain error, and an outer loop that reads the status.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from alcontact.contact import ContactStatus, solve
from alcontact.contact.systems import DiscreteContact
from alcontact.optim import LineSearch, NewtonSettings, NewtonSystem, newton
from alcontact.problems.blocks import patch_block
from alcontact.status import Status

X_STAR = np.array([1.0, 2.0, -1.0])


class _Cubic(NewtonSystem):
    """``F(x) = x^3 + x - b`` componentwise, the gradient of ``Pi = sum(x^4/4 + x^2/2 - b x)``; root ``X_STAR``."""

    def __init__(self):
        self.b = X_STAR**3 + X_STAR
        self.solves = 0

    def evaluate(self, x):
        return x, x**3 + x - self.b, float(np.sum(x**4 / 4 + x**2 / 2 - self.b * x))

    def residual(self, state):
        return state[1]

    def merit(self, state):
        return state[2]

    def slope(self, x, state, dx):
        return float(state[1] @ dx)

    def measure(self, state):
        return float(np.max(np.abs(state[1])))

    def step(self, x, state, history):
        self.solves += 1
        return -state[1] / (3 * x**2 + 1)


def test_quadratic_convergence_on_a_smooth_problem():
    """Newton's theorem: with full steps ``|F_{k+1}| <= C |F_k|^2``, ``C = max|F''| / (2 min F'^2)``.

    Here ``F'' = 6x``, ``F' = 3x^2 + 1 >= 1`` and the iterates near the root stay below
    ``|x| = 2.1``, so ``C <= 6.3`` (asserted on every pair of full steps from a residual
    below 1e-2 to one above the round-off level 1e-13); the root is reached to 1e-14.
    """
    system = _Cubic()
    out = newton(system, np.zeros(3), tol=1e-14, maxiter=50)
    assert out.status == Status.CONVERGED and out.converged, out.message
    assert np.max(np.abs(out.x - X_STAR)) <= 1e-14
    assert out.iterations == system.solves == len(out.history) - 1
    pairs = [(a.residual, b.residual) for a, b in zip(out.history, out.history[1:])
             if a.step == 1.0 and a.residual <= 1e-2 and b.residual > 1e-13]
    assert len(pairs) >= 2, out.residuals
    assert all(r1 <= 6.3 * r0**2 for r0, r1 in pairs), pairs


def test_iteration_limit_is_maxiter():
    """One correction from ``x = 0`` cannot reach the root: status MAXITER, one iteration, residual > 0."""
    out = newton(_Cubic(), np.zeros(3), tol=1e-14, maxiter=1)
    assert out.status == Status.MAXITER and not out.converged
    assert out.iterations == 1 and out.residual > 0 and out.message


class _Ascent(_Cubic):
    """A broken step: the negative Newton direction, an ascent direction of the energy."""

    def step(self, x, state, history):
        return -super().step(x, state, history)


def test_line_search_failure_status():
    """An ascent direction raises the energy for every step length 2^-k and the full step raises |F|:
    LINE_SEARCH_FAILED after one correction, the iterate unchanged."""
    x0 = np.array([0.5, 1.0, 0.0])
    out = newton(_Ascent(), x0, tol=1e-12, maxiter=20, settings=NewtonSettings(LineSearch(halvings=10)))
    assert out.status == Status.LINE_SEARCH_FAILED and not out.converged
    assert out.iterations == 1
    np.testing.assert_array_equal(out.x, x0)


class _Floored(_Cubic):
    """The cubic with a residual floor: ``F`` is the cubic's plus a constant ``1e-10`` that no step removes,
    so every step length leaves ``|F|`` at or above its value at the root (a residual made of round-off)."""

    def evaluate(self, x):
        x_, F, pi = super().evaluate(x)
        return x_, F + 1e-10, pi

    def step(self, x, state, history):
        return np.zeros_like(x) + 1e-3  # a step that raises |F| wherever it starts near the root


@pytest.mark.parametrize("level, on, converged", [(1e-9, True, True), (1e-9, False, False), (1e-11, True, False)])
def test_failed_line_search_at_the_stall_level(level, on, converged):
    """``stall_on_failed_search``: a line search that fails at a residual below the stall level (here 1e-10
    against the level 1e-9) ends the iteration as converged, at the start already, the iterate unchanged;
    off, or with the residual above the level (1e-11), the failure is reported."""
    ls = LineSearch(halvings=4, merit=False, residual_decrease=True, full_step=False)
    settings = NewtonSettings(ls, stall=level, stall_on_failed_search=on)
    out = newton(_Floored(), X_STAR.copy(), tol=1e-14, maxiter=5, settings=settings)
    assert out.converged == converged, out.message
    assert out.status == (Status.CONVERGED if converged else Status.LINE_SEARCH_FAILED)
    np.testing.assert_array_equal(out.x, X_STAR)
    if converged:
        assert out.iterations == 0 and "round-off" in out.message


class _NaNAt(_Cubic):
    def evaluate(self, x):
        x_, F, pi = super().evaluate(x)
        return x_, np.where(x > 5.0, np.nan, F), pi


def test_nan_residual_is_nonfinite():
    """A NaN residual at the start: NONFINITE, no Newton step taken, residual NaN."""
    out = newton(_NaNAt(), np.array([6.0, 0.0, 0.0]), tol=1e-12, maxiter=20)
    assert out.status == Status.NONFINITE and out.iterations == 0 and np.isnan(out.residual)


class _Singular(_Cubic):
    def step(self, x, state, history):
        raise np.linalg.LinAlgError("singular")


def test_singular_matrix_is_newton_failed():
    out = newton(_Singular(), np.zeros(3), tol=1e-12, maxiter=20)
    assert out.status == Status.NEWTON_FAILED and out.iterations == 1


class _Outside(Exception):
    """Evaluation outside the domain (as an inverted element)."""


class _Exponential(NewtonSystem):
    """``F(x) = exp(x) - e`` (root 1) defined on ``x < 1.2`` only; no merit, residual backtracking."""

    domain_errors = (_Outside,)

    def __init__(self):
        self.outside = 0

    def evaluate(self, x):
        if np.any(x >= 1.2):
            self.outside += 1
            raise _Outside
        return np.exp(x) - np.e

    def residual(self, state):
        return state

    def measure(self, state):
        return float(np.max(np.abs(state))) / np.e

    def step(self, x, state, history):
        return -state / (state + np.e)


def test_domain_errors_make_the_line_search_backtrack():
    """From ``x = -2`` the Newton step ``e^3 - 1 ~ 19`` leaves the domain ``x < 1.2``: the line
    search halves it (domain errors counted) and Newton still reaches the root 1 to 1e-13."""
    system = _Exponential()
    settings = NewtonSettings(LineSearch(merit=False, residual_decrease=True, full_step=False))
    out = newton(system, np.array([-2.0]), tol=1e-14, maxiter=50, settings=settings)
    assert out.converged, out.message
    assert abs(out.x[0] - 1.0) <= 1e-13
    assert system.outside >= 4  # 19, 9.5, 4.7, 2.4 are outside
    assert out.history[0].step < 1.0


def test_domain_error_at_the_start_propagates():
    with pytest.raises(_Outside):
        newton(_Exponential(), np.array([2.0]), tol=1e-12, maxiter=5)


class _Interrupted(_Cubic):
    def interrupt(self, x, state, alpha):
        return "the active set changed"


def test_interrupt_stops_after_one_step():
    """A stop requested after the first accepted step: NEWTON_FAILED (not converged) after one correction."""
    out = newton(_Interrupted(), np.zeros(3), tol=1e-14, maxiter=50)
    assert out.status == Status.NEWTON_FAILED and out.iterations == 1 and np.isfinite(out.history[0].step)


def test_outer_loop_reads_the_inner_status_not_its_message(monkeypatch):
    """Algorithm 6.1 ends NONFINITE when the subproblem's status says so, whatever its message reads."""
    real = DiscreteContact.subproblem

    def nonfinite(self, *args, **kwargs):
        out = real(self, *args, **kwargs)
        return dataclasses.replace(out, status=Status.NONFINITE, message="words nobody compares")

    monkeypatch.setattr(DiscreteContact, "subproblem", nonfinite)
    res = solve(patch_block(2, 1, n=2), "simo-laursen").result
    assert res.status == ContactStatus.NONFINITE, res.message


class _Inconsistent(NewtonSystem):
    """One unknown; the merit rises along the step while the residual norm halves (a residual that is
    not the merit's gradient, as where a penalty's active set changes between the two)."""

    def evaluate(self, x):
        return x, np.array([1.0 - 0.5 * x[0]]), float(x[0])  # merit rises with x, |F| falls

    def residual(self, state):
        return state[1]

    def merit(self, state):
        return state[2]

    def slope(self, x, state, dx):
        return -1.0  # claims descent

    def measure(self, state):
        return float(abs(state[1][0]))

    def step(self, x, state, history):
        return np.array([1.0])


@pytest.mark.parametrize("slack,accepted", [(np.inf, True), (1e-10, False)])
def test_residual_test_respects_merit_slack(slack, accepted):
    """Issue 18: the residual-decrease test accepted steps that raised the energy, and the two tests
    took turns (the iterates cycled). With ``residual_merit_slack`` the merit may rise by at most that
    fraction of itself; here it rises by 100 %: the step is refused (the line search fails)."""
    ls = LineSearch(halvings=3, residual_decrease=True, residual_merit_slack=slack, full_step=False)
    out = newton(_Inconsistent(), np.array([1.0]), tol=1e-12, maxiter=1, settings=NewtonSettings(ls))
    assert (out.status != Status.LINE_SEARCH_FAILED) == accepted
    if accepted:
        assert out.history[0].step == 1.0 and out.x[0] == 2.0
    else:
        assert out.x[0] == 1.0


class _CancellingMerit(_Inconsistent):
    """The merit of :class:`_Inconsistent` as its values read, but the system knows the exact change: a
    decrease (as a potential summed from large cancelling terms whose values carry more round-off than
    the change a Newton step brings: 2D P1 Hertz at 984k DOFs, log-met1 on the AMG path)."""

    def merit_change(self, state, trial, merit, trial_merit):
        return -(trial[0][0] - state[0][0])


def test_the_line_search_reads_the_merit_change_the_system_gives():
    """``NewtonSystem.merit_change`` takes effect: the values say the merit rose by 100 % (refused at a
    slack of 1e-10, the test above); the system's own change says it fell, and the full step is taken."""
    ls = LineSearch(halvings=3, residual_decrease=True, residual_merit_slack=1e-10, full_step=False)
    out = newton(_CancellingMerit(), np.array([1.0]), tol=1e-12, maxiter=1, settings=NewtonSettings(ls))
    assert out.status != Status.LINE_SEARCH_FAILED
    assert out.history[0].step == 1.0 and out.x[0] == 2.0
