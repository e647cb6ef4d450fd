r"""The barrier anchor: Polyak's modified log barrier with fixed multipliers, the barrier parameter driven to zero.

Registered as ``log-barrier``: frictionless (small deformation on the direct and AMG paths, finite
deformation load-stepped on the direct path) and with Coulomb friction (:func:`step_barrier`, one load
step; small and finite deformation on the direct path). It is the interior-type method
*without multiplier updates* that the study compares the augmented Lagrangian methods with: the
same subproblem (S) and the same normal law as Algorithm 6.3 with ``log-met1``,

.. math::

    t_N(g) = p'(g/\eta, \mu) = \frac{\mu}{1 - g/\eta}, \qquad
    \psi(g) = -\eta\,\mu \ln(1 - g/\eta)

(MET 1 (5.23) with the generator (5.22): Polyak's modified barrier), but the multipliers
:math:`\mu` are those of the start and are never updated; instead the barrier parameter
:math:`\eta = \mu/\varepsilon_N` (the scale of :mod:`alcontact.contact.laws`, stiffness
:math:`\varepsilon_N` at zero gap) is driven to zero, :math:`\varepsilon_N \leftarrow \alpha\,\varepsilon_N`
after every subproblem (``alpha``, at most ``eps_max`` times the initial one): Algorithm 5.1's
:math:`\rho \to 0` with the modified barrier of section 5.3 in place of (5.2).

Why the modified barrier and not the classical :math:`-\rho\sum\ln(-g_i)` (5.2): the classical
barrier needs a strictly feasible start, :math:`g_i < 0` at every candidate point, and a contact
problem starts with its points *touching* (:math:`g = 0` where the body rests on the obstacle),
so it has none without moving the obstacle. The modified barrier's domain :math:`g < \eta`
contains every such start; with fixed multipliers it is a shifted log barrier (weight
:math:`\eta\mu`, shift :math:`\eta`) whose minimizers tend to the solution as :math:`\eta \to 0`
(Polyak, *Modified barrier functions*, Math. Programming 54, 1992). At a point in contact the gap
is :math:`g = \eta(1 - \mu/t_N)`, at an open one the traction is :math:`t_N \approx \mu\eta/|g|`:
penetration and complementarity fall like :math:`\eta`, first order, as for the pure penalty (6.10);
the multiplier update of Algorithm 6.3 is what removes that dependence.

The start is Algorithm 6.3's (``initial``: one pure-penalty solve, its pressures floored at
``multiplier_floor`` times the largest, or the uniform ``eps_n * h``). The stopping test is the
one the returned state is verified with (:mod:`alcontact.contact._verify`): penetration at most
``tol_penetration`` and complementarity at most ``tol_complementarity``, measured with the returned
tractions (the multiplier estimates :math:`p'(g/\eta, \mu)`); the estimate's change between
subproblems is recorded as the multiplier change of the history.

With Coulomb friction (:func:`step_barrier`) the normal part is the same barrier with fixed
multipliers, per load step; the tangential part is the return mapping (6.47)-(6.50) of Algorithms
6.2 / 6.4, unchanged, with the coupled disc radius :math:`\mu t_N(g)` (the normal multipliers
are not the tractions here, so the fixed radius :math:`\mu\lambda_N` of (6.2c) would be the wrong
bound) and its multiplier update (6.2c), :math:`\lambda_T \leftarrow t_T`. Why not a barrier on the
tangential part too: the Coulomb condition :math:`|t_T| \le \mu t_N` is a bound on the traction,
not a constraint on the displacement that an interior method could keep strictly satisfied; the
regularized tangential law *is* a penalty, and without its update a stick point slips by
:math:`|t_T - \lambda_T| / \varepsilon_T`, which no growth of :math:`\varepsilon_N` removes.
Every frictional method of the study shares this tangential part, so the comparison isolates the
normal treatment: held multipliers and :math:`\eta \to 0` against the multiplier updates.
:math:`\varepsilon_N` grows by ``alpha`` only after a subproblem whose penetration or complementarity
is still above its tolerance; the step stops when these hold and the tangential multiplier change
and the slip of the sticking points are below ``tol_multiplier`` and ``tol_slip`` (the stopping test
of Algorithm 6.2 without its normal multiplier change).
"""

from __future__ import annotations

import logging

import numpy as np

from ... import penalties as _pen
from ..laws._normal import eta_for_stiffness, make_law
from ..solution._solution import ContactIteration, ContactStatus
from ..systems._protocol import ContactSystem
from ._coulomb import _ALSystem, _first_subproblem, _StepOut
from ._coulomb import _measures as _friction_measures
from ._frictionless import (FRICTION_DEFAULTS, FRICTIONLESS_DEFAULTS, Algorithm, _al_start, _inside_domain, _measures,
                            _Run, _subproblem_failure, register)
from ._subproblem import inner_failure

logger = logging.getLogger(__name__)

__all__ = ["BARRIER_PENALTY", "run_barrier", "step_barrier"]

#: The penalty of the barrier anchor: Polyak's modified barrier, MET 1 (5.23) of the log generator (5.22).
BARRIER_PENALTY = "log-met1"


def run_barrier(dc: ContactSystem, opts, eps0, penalty_name=BARRIER_PENALTY) -> _Run:
    r"""Modified log barrier with fixed multipliers, :math:`\eta \to 0` (see the module doc).

    Parameters
    ----------
    dc : ContactSystem
        The contact model (its members only).
    opts : ContactOptions
        Reads ``alpha`` (growth of :math:`\varepsilon_N` per subproblem), ``eps_max``, ``maxiter``,
        ``tol_penetration``, ``tol_complementarity``, ``initial``, ``multiplier_floor``, ``newton_tol``,
        ``maxiter_newton``.
    eps0 : float
        Initial :math:`\varepsilon_N`: the barrier parameter is :math:`\eta = \mu/\varepsilon_N`.
    penalty_name : str
        The registered penalty (:data:`BARRIER_PENALTY`).

    Returns
    -------
    _Run
        ``CONVERGED`` when penetration and complementarity hold; ``PENALTY_LIMIT`` when
        :math:`\varepsilon_N` would pass ``eps_max`` times ``eps0`` first; ``MAXITER``; a failed subproblem's
        status otherwise.
    """
    pen = _pen.make(penalty_name)
    eps = eps0
    start = _al_start(dc, opts, eps, needs_positive=True)
    mu, r, newton, outer0, hist = start.lam, start.r, start.newton, start.outer0, start.history
    t_prev = np.maximum(mu, 0.0)
    out = None
    for k in range(1, opts.maxiter + 1):
        law = make_law(pen, eta_for_stiffness(pen, mu, eps))
        r = _inside_domain(dc, r, law.gap_bound(mu))  # a smaller eta shrinks the domain g < eta
        out = dc.subproblem(law, mu, r, tol=opts.newton_tol, maxiter=opts.maxiter_newton)
        newton += out.iterations
        failed = _subproblem_failure(out, mu, r, k, outer0 + k, newton, eps, hist, penalty_name)
        if failed is not None:
            return failed
        r = out.state
        pen_k, compl, dt = _measures(dc, out.t, out.g, t_prev)
        hist.append(ContactIteration(outer0 + k, pen_k, compl, dt, out.residual, out.iterations, eps,
                                     int(np.sum(out.g > -opts.tol_penetration * dc.h))))
        logger.info("barrier %d: eps_N %.3e, penetration %.2e h, complementarity %.2e, %d Newton",
                    outer0 + k, eps, pen_k, compl, out.iterations)
        if pen_k <= opts.tol_penetration and compl <= opts.tol_complementarity:
            return _Run(r, out.t, out.g, ContactStatus.CONVERGED, "converged", outer0 + k, newton, eps,
                        out.residual, hist)
        if eps * opts.alpha > opts.eps_max * eps0:
            return _Run(r, out.t, out.g, ContactStatus.PENALTY_LIMIT,
                        f"barrier: penetration {pen_k:.2e} h / complementarity {compl:.2e} still above the "
                        f"tolerances at the largest eps_N {eps:.3e} (eps_max = {opts.eps_max:g} times the initial); "
                        "raise eps_max, loosen the tolerances or use algorithm='family-p'",
                        outer0 + k, newton, eps, out.residual, hist)
        eps *= opts.alpha
        t_prev = out.t.copy()
    return _Run(out.state, out.t, out.g, ContactStatus.MAXITER,
                f"barrier: maximum iterations ({opts.maxiter}) reached; raise maxiter or alpha",
                outer0 + opts.maxiter, newton, eps, out.residual, hist)


def step_barrier(ctx: _ALSystem, penalty_name: str = BARRIER_PENALTY) -> _StepOut:
    r"""One load step of the frictional barrier anchor (module doc): held normal multipliers, :math:`\eta \to 0`.

    Parameters
    ----------
    ctx : _ALSystem
        The step's system (the condensed forces of the direct path, or the free displacements of a
        finite-deformation step), driven through its members only, as by Algorithms 6.2 / 6.4.
    penalty_name : str
        The registered penalty (:data:`BARRIER_PENALTY`).

    Returns
    -------
    _StepOut
        Converged when penetration, complementarity, the tangential multiplier change and the slip
        of the sticking points hold; ``PENALTY_LIMIT`` when :math:`\varepsilon_N` would pass
        ``eps_max`` times the step's initial one first; ``MAXITER``; a failed subproblem's status.

    Notes
    -----
    The start is Algorithm 6.4's predictor: one Simo-Laursen subproblem (coupled radius) at the
    step's multipliers; its normal tractions, floored at ``multiplier_floor`` times the largest, are
    the multipliers held for the step (its tangential ones too on a system whose predictor is a full
    outer iteration, ``ctx.full_predictor``, which then counts as one). The barrier scale is that of
    Algorithm 6.4, :math:`\eta = p''(0, \max(\mu, \texttt{eta\_floor}\,p_{ref}))/\varepsilon_N`.
    """
    opts = ctx.opts
    pen = _pen.make(penalty_name)
    lamN, lamT = ctx.lamN.copy(), ctx.lamT.copy()
    z = ctx.start
    eps0 = eps = ctx.eps_n
    macaulay = make_law(_pen.make("rockafellar"), np.full(ctx.c, 1.0 / eps0))
    out, _ = _first_subproblem(ctx, macaulay, lamN, lamT, z, True)
    newton = out.iterations
    outer0 = 1 if ctx.full_predictor else 0
    if out.converged:
        z = ctx.iterate(out)
        lamN = out.state.aux[1][:, 0].copy()
        if ctx.full_predictor:
            lamT = out.state.aux[1][:, 1:].copy()
    pref = max(float(np.max(lamN, initial=0.0)), eps0 * ctx.fc.h * 1e-6)
    mu = np.maximum(lamN, opts.multiplier_floor * pref)  # held for the whole step
    lam_eta = np.maximum(mu, opts.eta_floor * pref)
    t = np.zeros((ctx.c, ctx.d))
    for k in range(1, opts.maxiter + 1):
        law = make_law(pen, eta_for_stiffness(pen, lam_eta, eps))
        z = ctx.inside_domain(law, mu, z)  # a smaller eta shrinks the domain g < eta
        out = ctx.subproblem(law, mu, lamT, z, coupled=True)
        newton += out.iterations
        if not out.converged:
            t = out.state.aux[1] if out.state is not None else np.zeros((ctx.c, ctx.d))
            return _StepOut(False, f"barrier: Newton failed in outer iteration {k}: {out.message}", ctx.forces(z, t),
                            t, k + outer0, newton, inner_failure(out), z=z, last_state=out.state)
        z = ctx.iterate(out)
        y, t, _, st = out.state.aux
        if not np.all(np.isfinite(t)):
            return _StepOut(False, f"barrier: non-finite tractions in outer iteration {k}", ctx.forces(z, t), t,
                            k + outer0, newton, ContactStatus.NONFINITE, z=z, last_state=out.state)
        # the normal multipliers are held: the change measured is the tangential one only
        pen_k, compl, dlam, stick_slip = _friction_measures(ctx, t, y, st, t[:, 0], lamT)
        logger.debug("friction barrier outer %d: eps_N %.3e pen=%.2e compl=%.2e dlam_T=%.2e stick-slip=%.2e "
                     "newton=%d", k + outer0, eps, pen_k, compl, dlam, stick_slip, out.iterations)
        normal_ok = pen_k <= opts.tol_penetration and compl <= opts.tol_complementarity
        if normal_ok and dlam <= opts.tol_multiplier and stick_slip <= opts.tol_slip:
            return _StepOut(True, "converged", ctx.forces(z, t), t, k + outer0, newton, z=z, last_state=out.state)
        if not normal_ok:
            if eps * opts.alpha > opts.eps_max * eps0:
                return _StepOut(False, f"barrier: penetration {pen_k:.2e} h / complementarity {compl:.2e} still "
                                       f"above the tolerances at the largest eps_N {eps:.3e} (eps_max = "
                                       f"{opts.eps_max:g} times the initial); raise eps_max or use "
                                       "algorithm='family-p'", ctx.forces(z, t), t, k + outer0, newton,
                                ContactStatus.PENALTY_LIMIT, z=z, last_state=out.state)
            eps *= opts.alpha
        lamT = t[:, 1:].copy()  # (6.2c): the return mapping's traction (coupled radius)
    return _StepOut(False, f"barrier: maximum outer iterations ({opts.maxiter}) reached", ctx.forces(z, t), t,
                    opts.maxiter + outer0, newton, ContactStatus.MAXITER, z=z, last_state=out.state)


_DOC = ("barrier anchor: Polyak's modified log barrier (log-met1) with fixed multipliers, eta -> 0 "
        "(Algorithm 5.1 with section 5.3's barrier), no multiplier update")
_FRICTION_DOC = ("barrier anchor with Coulomb friction: the modified log barrier with fixed normal multipliers, "
                 "eta -> 0, per load step; tangential part of Algorithm 6.2 (return mapping, coupled radius)")
# small deformation: condensed (direct) and AMG paths; finite deformation: the load-stepped engine, direct only
# (the paths it was checked on: tests/verification/test_log_barrier.py)
for _kin, _paths in (("small", ("direct", "amg")), ("finite", ("direct",))):
    register(Algorithm("log-barrier", run_barrier, _DOC, friction=False, kinematics=_kin, linear_solvers=_paths,
                       penalty=BARRIER_PENALTY, defaults=FRICTIONLESS_DEFAULTS))
    # with friction: the direct paths only (the AMG step's subproblem has no coupled radius;
    # tests/verification/test_friction_log_barrier.py)
    register(Algorithm("log-barrier", step_barrier, _FRICTION_DOC, friction=True, kinematics=_kin,
                       linear_solvers=("direct",), penalty=BARRIER_PENALTY, defaults=FRICTION_DEFAULTS))
del _kin, _paths
