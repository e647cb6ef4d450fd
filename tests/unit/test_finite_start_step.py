"""Load-step starts of the pure penalty and Algorithm 6.3 at finite deformation, on stand-in models."""

from __future__ import annotations

from types import SimpleNamespace

from alcontact.contact.systems import _full_space as _finite
from alcontact.contact.kinematics import ContactPoints
from alcontact.contact.systems import FiniteContact


class _Model(SimpleNamespace):
    start_multiplier_step = FiniteContact.start_multiplier_step


class _StandIn(ContactPoints):
    """A stand-in model: the declared "not available" members of every model, the rest given."""

    def __init__(self, **members):
        self.__dict__.update(members)


def _model(solver):
    seen = []

    def multiplier_step(law, lam, out):
        seen.append(getattr(solver, "resolve_rtol", None))
        return ("lam", "x")

    return _Model(solver=solver, multiplier_step=multiplier_step), seen


def test_iterative_products_are_tightened_then_restored():
    """An AMG-type solver (``resolve_rtol`` 1e-2) solves the start's dual step to _START_RESOLVE_RTOL (1e-8)
    and gets its own tolerance back; the dual step's result is returned."""
    solver = SimpleNamespace(resolve_rtol=1e-2)
    model, seen = _model(solver)
    assert model.start_multiplier_step(None, None, None) == ("lam", "x")
    assert seen == [_finite._START_RESOLVE_RTOL] and _finite._START_RESOLVE_RTOL == 1e-8
    assert solver.resolve_rtol == 1e-2


def test_direct_solver():
    """A direct solver (no ``resolve_rtol``) is used as it is."""
    model, seen = _model(SimpleNamespace())
    assert model.start_multiplier_step(None, None, None) == ("lam", "x") and seen == [None]


def test_penalty_start_zeroes_floor_pressures_before_the_entry_rule():
    """_penalty_start: predicted pressures at or below multiplier_floor x the largest (the positive floor of MET
    multipliers: a barrier penalty's tiny traction at open points) reach the entry rule as zero, the others
    unchanged; without a dual step the start's tractions are the initial multipliers."""
    import numpy as np

    from alcontact.contact.algorithms import ContactOptions
    from alcontact.contact.algorithms._frictionless import _penalty_start
    from alcontact.contact.algorithms._subproblem import NewtonOutcome
    from alcontact.status import Status

    seen = {}
    x0 = np.zeros(2)

    def entry_multipliers(lam, law, **options):
        seen["entry"] = np.array(lam)
        seen["options"] = options
        return lam

    def subproblem(law, lam, r0, *, tol, maxiter):
        seen["sub"] = np.array(lam)
        return NewtonOutcome(r0 + 1.0, np.zeros(3), np.array([3.0, 2.0, 1.0]), 2, Status.CONVERGED, 0.0, "ok")

    dc = _StandIn(cand=np.arange(3), h=1.0, warm_penalty_start=True, start=lambda: x0,
                  initial_multipliers=lambda: np.array([1.0, 1e-12, 0.5]),
                  entry_multipliers=entry_multipliers, subproblem=subproblem)
    opts = ContactOptions(newton_tol=1e-12, maxiter_newton=60)
    out, lam, r = _penalty_start(dc, opts, 10.0)
    assert np.array_equal(seen["entry"], [1.0, 0.0, 0.5]) and np.array_equal(seen["sub"], [1.0, 0.0, 0.5])
    assert seen["options"] == {"penalty_start": True}  # the model knows it is Algorithm 6.3's penalty start
    assert np.array_equal(lam, [3.0, 2.0, 1.0]) and np.array_equal(r, x0 + 1.0) and out.iterations == 2


def test_penalty_continuation_restarts_from_eps0_after_a_failed_first_solve():
    """run_penalty: a step starts at the carried stiffness / alpha; when that first solve fails, the step's
    sequence restarts from eps0 (and from the step's start) instead of failing, and the stiffness it
    converges with is carried on."""
    import numpy as np

    from alcontact.contact.algorithms import ContactOptions, run_penalty
    from alcontact.contact.algorithms._subproblem import NewtonOutcome
    from alcontact.status import Status

    eps_seen = []

    def subproblem(law, lam, r0, *, tol, maxiter):
        eps = 1.0 / float(law.eta[0])
        eps_seen.append(eps)
        if len(eps_seen) == 1:
            return NewtonOutcome(r0, np.full(2, 1.0), np.zeros(2), 5, Status.NEWTON_FAILED, 1.0, "line search")
        g = np.full(2, 5e-5 / eps)  # penetration falls with the stiffness: <= 1e-8 from eps = 1e4 on
        return NewtonOutcome(r0, g, eps * g, 2, Status.CONVERGED, 0.0, "ok")

    dc = _StandIn(cand=np.arange(2), h=1.0, start=lambda: np.zeros(2), subproblem=subproblem,
                  penalty_continuation=True, carried_stiffness=1e4)
    opts = ContactOptions(newton_tol=1e-12, maxiter_newton=60, tol_penetration=1e-8)
    run = run_penalty(dc, opts, 10.0)
    assert run.status > 0, run.message
    assert np.allclose(eps_seen, [1e3, 10.0, 1e2, 1e3, 1e4])
    assert dc.carried_stiffness == run.eps and np.isclose(run.eps, 1e4)
