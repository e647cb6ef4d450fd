"""The pure penalty at a huge stiffness: the condensed Newton stops at its round-off floor (issue 11).

The 2D Hertz benchmark at 983,616 DOFs (847 candidates) ended the pure penalty with
``newton-failed`` in its 4th penalty iteration (eps_N = 1.1e13, eps_N h / E' = 1e5): the
relative residual of the condensed subproblem stalled at 1.4e-8 to 2.0e-8, above the fixed
round-off level 1e-8 of ``NewtonSettings.stall``, for 60 Newton steps. The gaps
``g_free - S r`` lose digits to cancellation and the residual carries their error times
``w eps_N``. :meth:`CondensedSubproblem.roundoff_floor` computes that floor.

The small model here (2D Hertz, 16 elements per ``a``, 30 candidates) reaches the same
residual level at eps_N h / E' = 1e8. At 847 candidates the Newton corrections at the
stall are 1.2e-13 to 1.9e-13 of the force scale (round-off amplified by the condition of
``S``, which grows with the candidates), above the 1e-13 at which a correction counts as
negligible; at 30 candidates they are about 1e-15 and that guard alone ends the solve. The
tests that reproduce the benchmark's failure switch that guard off (``_no_negligible_guard``),
which is what the 847-candidate model does by itself.

Reaches inside the package: the rule under test is ``CondensedSubproblem``'s round-off floor
(``contact.algorithms._subproblem``); the test swaps in the former rule to show the failure it
fixed.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact import penalties as _pen
from alcontact.contact import ContactStatus, solve
from alcontact.contact.systems import DiscreteContact
from alcontact.contact.laws import make_law
from alcontact.contact.algorithms._subproblem import CondensedSubproblem
from alcontact.optim import NewtonSystem, newton
from alcontact.problems import hertz
from alcontact.status import Status


def _model():
    return hertz.hertz_2d(n_per_a=16, growth=1.4)


@pytest.fixture
def _no_negligible_guard(monkeypatch):
    """Corrections never count as negligible: the behaviour of the 847-candidate model (module doc)."""
    monkeypatch.setattr(CondensedSubproblem, "negligible", lambda self, r, state, dr: False)


def _penalty_law(dc, ratio):
    """Rockafellar's law with lambda = 0 (the pure penalty) at ``eps_N = ratio * E' / h``."""
    eps = ratio * _model().reference.e_star / dc.h
    law = make_law(_pen.make("rockafellar"), np.full(dc.cand.size, 1.0 / eps))
    return law, np.zeros(dc.cand.size)


def _solve_at(dc, ratio, r0=None, maxiter=60, system=CondensedSubproblem):
    law, lam = _penalty_law(dc, ratio)
    sub = system(dc, law, lam)
    r0 = dc.start() if r0 is None else r0
    return sub, newton(sub, r0, tol=1e-12, maxiter=maxiter)


class _FixedLevel(CondensedSubproblem):
    """The former rule: no computed floor, only the fixed stall level 1e-8 of the settings."""

    stall_level = NewtonSystem.stall_level


def test_pure_penalty_converges_where_the_fixed_round_off_level_failed(monkeypatch, _no_negligible_guard):
    """Regression of the 984k failure on a 30-candidate model; the force agrees with SSN.

    penalty_scale = 1e5 and tol_penetration = 1e-9: four penalty iterations, the last at
    eps_N h / E' = 1e8, where the subproblem residual stalls at about 1.3e-7 (> 1e-8).
    With the former fixed level the run ends ``newton-failed`` after 60 Newton steps in
    penalty iteration 4, as the benchmark did; with the computed floor it converges.

    Reference: the SSN solution of the same model (exact contact constraints). Tolerance on
    the total contact force, relative: the penalty's own error E' / (eps_N h) plus the round-off
    of the returned tractions, 10 times the final relative residual (the residual is measured
    against a force scale alpha = 10 times the contact forces of the start).
    """
    prob = _model()
    ref = solve(prob, "ssn")
    assert ref.status == ContactStatus.CONVERGED
    sol = solve(prob, "penalty", penalty_scale=1e5, tol_penetration=1e-9)
    assert sol.status == ContactStatus.CONVERGED, sol.result.message
    last = sol.result.history[-1]
    ratio = last.eps_n * prob.meta["h"] / prob.reference.e_star
    assert ratio >= 1e8
    assert last.residual > 1e-8  # the stall sits above the fixed level: the floor decided
    assert last.penetration <= 1e-9
    tol = 1.0 / ratio + 10.0 * last.residual
    assert abs(sol.normal_force - ref.normal_force) <= tol * ref.normal_force

    monkeypatch.setattr(CondensedSubproblem, "stall_level", NewtonSystem.stall_level)  # the former rule
    old = solve(prob, "penalty", penalty_scale=1e5, tol_penetration=1e-9)
    assert old.status == ContactStatus.NEWTON_FAILED
    assert old.result.history[-1].newton_iterations == 60


def test_stalled_residuals_lie_below_the_floor_and_the_floor_is_not_loose(_no_negligible_guard):
    """The residuals of a stalled condensed Newton lie below the computed floor, and within 100x of it.

    Model of the first test at eps_N h / E' = 1e8, started from the solution at 1e7 (as in
    the penalty loop). With the former fixed level Newton runs its 60 steps (``MAXITER``),
    the residual wandering at its round-off level; every iterate after the second is compared
    with :meth:`CondensedSubproblem.roundoff_floor` of that iterate: at most the floor (it
    is an upper bound), at least 1/100 of it (the floor is not a blanket acceptance; measured:
    1/20 to 1/10).
    """
    dc = DiscreteContact(_model())
    _, start = _solve_at(dc, 1e7)
    assert start.status.success
    sub, out = _solve_at(dc, 1e8, r0=start.x, system=_FixedLevel)
    assert out.status == Status.MAXITER
    stalled = [rec.residual for rec in out.history[2:]]
    assert min(stalled) > 1e-8
    floor = sub.roundoff_floor(out.state)
    assert max(stalled) <= floor
    assert np.median(stalled) >= floor / 100.0

    sub_new, out_new = _solve_at(dc, 1e8, r0=start.x)
    assert out_new.status == Status.CONVERGED
    assert out_new.residual <= sub_new.roundoff_floor(out_new.state)
    assert out_new.iterations <= 3


def test_floor_is_at_round_off_for_the_default_penalty():
    """At the default stiffness (penalty_scale 100) the floor is far below the Newton tolerance 1e-12.

    The floor must not loosen ordinary solves: bound 1e-13 (it is about sqrt(m) u = 1.2e-15
    times the force ratios there).
    """
    dc = DiscreteContact(_model())
    sub, out = _solve_at(dc, 100.0)
    assert out.status == Status.CONVERGED
    assert out.residual <= 1e-12
    assert sub.roundoff_floor(out.state) <= 1e-13


def test_a_subproblem_far_from_its_solution_still_fails(_no_negligible_guard):
    """A genuinely unconverged subproblem keeps its failure status: the floor is no blanket pass.

    eps_N h / E' = 1e8 from the contact-free start: two Newton steps leave a relative residual
    far above the floor (asserted, by more than 1e3); ``newton`` returns ``MAXITER``, and the
    pure penalty with ``maxiter_newton = 2`` ends ``newton-failed`` with a negative status.
    """
    dc = DiscreteContact(_model())
    sub, out = _solve_at(dc, 1e8, maxiter=2)
    assert out.status == Status.MAXITER
    assert out.residual > 1e3 * sub.roundoff_floor(out.state)

    sol = solve(_model(), "penalty", penalty_scale=1e8, maxiter_newton=2)
    assert sol.status == ContactStatus.NEWTON_FAILED
    assert sol.status < 0
    assert not sol.result.success
