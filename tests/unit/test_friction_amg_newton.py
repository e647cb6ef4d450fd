"""The friction AMG path on the one Newton driver (issues 9/10): outcomes are statuses.

Each subproblem of Algorithms 6.2 / 6.4 on the AMG path is a
:class:`~alcontact.contact.algorithms._subproblem.NewtonSystem` (``_FullSpaceFriction``) solved by
:func:`~alcontact.contact.algorithms._subproblem.newton`; a failed subproblem reaches the solution as a
negative status (``NEWTON_FAILED``, or ``NONFINITE`` for a NaN residual) with a logged
warning, as on the direct path. Reference for the converged case: the relative residual
tolerance ``max(newton_tol, 1e-11)`` of the module doc.

Reaches inside the package: unit test of the AMG friction Newton (``contact.systems._krylov``),
reached directly to feed it failing subproblems.
"""

from __future__ import annotations

import logging

import numpy as np

from alcontact import penalties
from alcontact.contact import ContactStatus, solve_friction
from alcontact.contact.systems import IterativeFrictionalContact
from alcontact.contact.systems._krylov import _FullCtx, friction_newton
from alcontact.contact.laws import make_law
from alcontact.optim import NewtonResult
from alcontact.contact.algorithms import ContactOptions
from alcontact.problems import friction as fp
from alcontact.status import Status


def _subproblem(x_shift=0.0):
    """The first subproblem (zero multipliers, Macaulay law) of the pressed 2D block on the AMG path."""
    prob, hist = fp.block_on_plane(dim=2, n=4)
    fc = IterativeFrictionalContact(prob, hist)
    t = float(hist.times[0])
    cand = fc.cand
    c, d = cand.size, fc.dim
    opts = ContactOptions()
    eps_n = 1e3 * prob.model.material.E / fc.h
    ctx = _FullCtx(fc, fc.rows(cand), fc.y_fix(t)[cand], fc.load(t), fc.weights[cand], np.zeros(c),
                   np.zeros((c, d - 1)), np.zeros((c, d - 1)), fc.u_free(t)[fc.free], fc.u_free(t)[fc.free], eps_n,
                   eps_n, 0.3, opts, fc.tfree[cand])
    law = make_law(penalties.make("rockafellar"), np.full(c, 1.0 / eps_n))
    return ctx, law


def test_subproblem_converges_on_the_driver():
    """From the contact-free solution: CONVERGED, relative residual <= 1e-11 (the tolerance floor of
    the AMG path), the history of the driver recorded, ``state.aux = (y, t, Dy, state)``."""
    ctx, law = _subproblem()
    out = friction_newton(ctx, law, ctx.lamN, ctx.lamT, ctx.x0, tol=1e-12, maxiter=60)
    assert isinstance(out, NewtonResult)
    assert out.status == Status.CONVERGED and out.converged, out.message
    assert out.residual <= 1e-11 and out.iterations >= 1 and len(out.history) == out.iterations + 1
    y, t, Dy, st = out.state.aux
    assert y.shape == t.shape == (ctx.c, ctx.d) and Dy.shape == (ctx.c, ctx.d, ctx.d) and st.shape == (ctx.c,)
    assert np.max(t[:, 0]) > 0  # the block is pressed on the plane


def test_subproblem_failures_are_statuses():
    """A NaN start is NONFINITE; no correction allowed (``maxiter=0``) above the tolerance is MAXITER."""
    ctx, law = _subproblem()
    x0 = ctx.x0.copy()
    x0[0] = np.nan
    out = friction_newton(ctx, law, ctx.lamN, ctx.lamT, x0, tol=1e-12, maxiter=60)
    assert out.status == Status.NONFINITE and not out.converged
    out = friction_newton(ctx, law, ctx.lamN, ctx.lamT, ctx.x0, tol=1e-12, maxiter=0)
    assert out.status == Status.MAXITER and out.iterations == 0 and out.residual > 1e-11


def test_failed_subproblem_reaches_the_solution_as_a_status(caplog):
    """Subproblems stopped after one correction at a 1e-300 tolerance on the AMG path: the solution's
    status is NEWTON_FAILED (negative) with a logged warning naming it, as on the direct path."""
    prob, hist = fp.block_on_plane(dim=2, n=4)
    with caplog.at_level(logging.WARNING, logger="alcontact"):
        sol = solve_friction(prob, hist, linear_solver="amg", maxiter_newton=1, newton_tol=1e-300, max_cutbacks=1)
    assert sol.extra["linear_solver"] == "amg"
    status = ContactStatus.NEWTON_FAILED
    assert sol.status == status and sol.status < 0, (sol.status, sol.message)
    assert any(r.levelno == logging.WARNING and status.label in r.getMessage() for r in caplog.records)
