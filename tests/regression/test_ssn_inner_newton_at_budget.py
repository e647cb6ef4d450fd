"""Issue 18, case 1: ``run_ssn`` accepted load steps whose inner Newton had stopped at its budget.

Finite-deformation ironing with the semi-smooth Newton reference: the active-set step
(``FiniteContact.solve_active``) stopped at its 50-iteration budget with a relative residual
up to 6e-2, and ``run_ssn`` took the state because the active set "settled". An inner Newton
that stops at its budget must be a failure (``NEWTON_FAILED``: the load step is cut back),
never a state the outer loop keeps.
"""

from __future__ import annotations

import numpy as np

from alcontact.contact import ContactProblem, ContactStatus, Ramp, Support, obstacles, solve_finite
from alcontact.contact.systems import FiniteContact
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic


def _ironing(steps=6):
    mesh = meshes.rectangle(0.0, 4.0, 0.0, 1.0, 16, 4)
    body = Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain"))
    problem = ContactProblem(body, obstacles.Circle(center=(1.0, 1.5), radius=0.5), "top",
                             supports=(Support("bottom"),), kinematics="finite")
    press = Ramp((0.0, 0.25), (0.0, -0.1), hold_after=True)
    slide = Ramp((0.25, 1.0), (0.0, 1.0))
    return problem, dict(steps=steps, obstacle_path=lambda t: np.array([slide(t), press(t)]))


def test_active_set_newton_out_of_budget_fails_the_step(monkeypatch):
    """Two Newton iterations per active-set solve cannot converge a step: every attempt fails, no step is
    accepted, and the run ends NEWTON_FAILED naming the residual the inner Newton stopped at."""
    seen = []
    orig = FiniteContact.solve_active

    def short_budget(self, active, lam, x, c, *, tol=1e-12, maxiter=50):
        out = orig(self, active, lam, x, c, tol=tol, maxiter=2)
        seen.append(self.active_converged)
        return out

    monkeypatch.setattr(FiniteContact, "solve_active", short_budget)
    problem, kw = _ironing()
    fs = solve_finite(problem, "ssn", max_cutbacks=2, **kw)
    assert seen and not any(seen)  # the budget really was too short every time (the option took effect)
    assert fs.status == ContactStatus.NEWTON_FAILED and not fs.success
    assert len(fs.steps) == 0
    assert "stopped at relative residual" in fs.message


def test_converged_ssn_steps_are_in_equilibrium():
    """With its normal budget every accepted step's inner Newton converged, and the returned state balances to
    newton_tol (1e-12) with the nonvanishing scale of the equilibrium measure."""
    problem, kw = _ironing()
    fs = solve_finite(problem, "ssn", **kw)
    assert fs.success, fs.message
    eq = fs.solution.equilibrium(problem)  # no load history: the problem's loads are the final step's
    assert eq.free_residual <= 1e-12, eq.free_residual
    assert all(s.status == ContactStatus.CONVERGED for s in fs.steps)


def test_run_ssn_refuses_an_unconverged_active_set_solve():
    """The acceptance logic alone: a model whose active-set solve reports it did not converge gets NEWTON_FAILED
    at once, even though its active set repeats and the gaps look closed."""
    from alcontact.contact.algorithms import ContactOptions, run_ssn
    from alcontact.contact.kinematics import ContactPoints

    class Model(ContactPoints):  # the declared "not available" members of every model (contact.systems)
        h = 1.0
        cand = np.arange(3)
        active_residual = 6e-2

        def start(self):
            return np.zeros(3)

        def gaps(self, x):
            return np.zeros(3)

        def solve_active(self, active, lam, x, c):
            self.active_converged = False  # stopped at its budget
            return x, np.ones(3), np.zeros(3)

    out = run_ssn(Model(), ContactOptions(newton_tol=1e-12), 1.0)
    assert out.status == ContactStatus.NEWTON_FAILED
    assert "6.00e-02" in out.message and out.outer == 1


def test_amg_active_set_solve_out_of_budget_fails(monkeypatch):
    """The factorization-free path (small deformation): an inner Uzawa iteration stopped at its budget (one
    update) is a failure of run_ssn too; with its budget (60) the same solve converges."""
    from alcontact.contact import solve
    from alcontact.contact.systems import _krylov as _iterative
    from alcontact.problems import hertz

    problem = hertz.hertz_2d(0, n_per_a=4)
    assert solve(problem, "ssn", linear_solver="amg").status == ContactStatus.CONVERGED
    monkeypatch.setattr(_iterative, "_UZAWA_MAXITER", 1)
    sol = solve(problem, "ssn", linear_solver="amg")
    assert sol.status == ContactStatus.NEWTON_FAILED
    assert "stopped at relative residual" in sol.result.message
