r"""Load stepping of frictionless contact at finite deformation: :func:`solve_finite`.

The steps are walked by :func:`~alcontact.contact.stepping._steps.step_through` (cut-backs, statuses).

The loads of :func:`solve_finite` are applied over a pseudo-time :math:`t \in (0, 1]` in
steps :math:`t_1 < \dots < t_N`. At step time :math:`t`

- without a :class:`~alcontact.contact.LoadHistory`, every support value and load of
  the problem is scaled by :math:`t` (proportional loading);
- with one, the problem's own supports and loads are applied fully and each
  :class:`~alcontact.contact.LoadCase` is scaled by its amplitude :math:`a_k(t)`;
- the obstacle is translated by ``obstacle_path(t)`` (a vector; default no motion),
  a rigid motion along a prescribed path (:func:`~alcontact.contact.obstacles.translate`),
  or placed by it when it returns an :class:`~alcontact.contact.obstacles.RigidMotion`
  (rotation and translation, :func:`~alcontact.contact.obstacles.move`).

Each step starts from the last converged displacement (warm start) and runs one of
the frictionless algorithms of :mod:`alcontact.contact.algorithms._frictionless` on the
finite-deformation problem :class:`~alcontact.contact.systems._full_space.FiniteContact`. A step
whose solve fails (negative status, an inverted element) is cut back as above. Every
accepted step is recorded (:class:`FiniteStep`).
"""

from __future__ import annotations

import time
from typing import Any, Callable, Sequence

import numpy as np

from ..._options import is_integer, is_real
from ...errors import InputError, InvertedElementError
from .._verify import check_state, equilibrium_tolerance, reach, state_equilibrium, verified_status
from ..algorithms._frictionless import ContactOptions, _Run, find_algorithm, options_with
from ..problem._loading import LoadHistory
from ..solution._records import FiniteSolution, FiniteStep
from ..solution._solution import ContactResult, ContactSolution, ContactStatus
from ..systems._full_space import FiniteContact
from ._steps import Attempt, StepRecord, _StepData, _step_times, step_through


def solve_finite(problem, algorithm: str = "simo-laursen", penalty: str | None = None,
                 options: ContactOptions | None = None, *, steps: int | Sequence[float] = 10,
                 history: LoadHistory | None = None, obstacle_path: Callable[[float], Any] | None = None,
                 max_cutbacks: int = 6, on_step: Callable[[FiniteStep, np.ndarray, np.ndarray], None] | None = None,
                 **option_overrides) -> FiniteSolution:
    """Solve a frictionless contact problem at finite deformation in load steps.

    Parameters
    ----------
    problem : ContactProblem
        With a geometrically nonlinear body (``problem.kinematics`` is not consulted
        here, so a linear body can be run for comparisons).
    algorithm, penalty, options, **option_overrides
        As for :func:`alcontact.contact.solve`.
    steps : int or sequence of float
        Number of uniform steps on ``(0, 1]``, or the step times.
    history : LoadHistory, optional
        Amplitudes of extra supports and loads (module doc); its own step times are
        ignored in favour of ``steps``.
    obstacle_path : callable ``t -> (d,)`` or ``t -> RigidMotion``, optional
        Translation (or rigid placement) of the obstacle at pseudo-time ``t``.
    max_cutbacks : int
        Halvings of a step's increment allowed (at most ``2**max_cutbacks`` sub-steps per
        step); a failure at the smallest increment stops the run with a negative status.
    on_step : callable ``(step, u, pressure) -> None``, optional
        Called after every accepted step with its :class:`FiniteStep`, the full
        displacement and the contact pressure of every contact-boundary point
        (e.g. to write the deformed configuration of each step).

    Returns
    -------
    FiniteSolution
        A failed step is logged as a warning (what to try) and ends the run with its
        negative status; the steps reached so far are kept.
    """
    from ..systems._full_space import finite_solver
    from ..laws._stiffness import penalty_stiffness

    t_start = time.perf_counter()
    entry = find_algorithm(algorithm, kinematics="finite")
    run = entry.run
    pen_name = entry.penalty_for(penalty)
    opts = options_with(options, ContactOptions, option_overrides, "contact", entry)
    if not (is_integer(max_cutbacks) or (is_real(max_cutbacks) and float(max_cutbacks).is_integer())) \
            or not 0 <= max_cutbacks <= 60:
        raise InputError(f"max_cutbacks={max_cutbacks!r:.40} must be an integer in [0, 60]; use e.g. max_cutbacks=6.")
    if not (on_step is None or callable(on_step)):
        raise InputError(f"on_step = {on_step!r:.40}: expected None or a callable (step, u, pressure).")
    max_cutbacks = int(max_cutbacks)
    times = _step_times(steps)
    data = _StepData(problem, history, obstacle_path)
    dc = FiniteContact(problem, fixed=data.fixed, solver=finite_solver(opts.linear_solver, entry, problem.model),
                       predictor=opts.predictor, slide_start_reach=opts.slide_start_reach)
    eps0 = opts.eps_n if opts.eps_n is not None else penalty_stiffness(problem.model, dc.h, opts.penalty_scale)
    state = {"x": np.zeros(dc.free.size), "last": None}
    dc.configure(*data(0.0), state["x"])  # the undeformed state belongs to t = 0
    dc.accept(np.zeros(dc.points.shape[0]))
    records: list[FiniteStep] = []

    def attempt(t: float) -> Attempt:
        newton0, solves0 = dc.newton_iterations, dc.linear_solves
        out, u, exc = _attempt(dc, data, run, opts, eps0, pen_name, state["x"], t)
        counts = dict(newton=dc.newton_iterations - newton0, linear_solves=dc.linear_solves - solves0)
        if exc is not None:
            return Attempt(False, ContactStatus.NEWTON_FAILED, str(exc), **counts)
        if out.status > 0:  # a step is accepted only when its returned state passes every measure (cut back if not)
            check = _check(problem, dc, out, u, opts, fixed=data.fixed, load=data(t)[1])[0]
            if not check.ok:
                return Attempt(False, ContactStatus.NOT_VERIFIED, f"{algorithm} reported {out.message!r} but the "
                               f"state fails verification: {check.describe()}", outer=int(out.outer), **counts)
        return Attempt(out.status > 0, out.status, out.message, outer=int(out.outer), value=(out, u), **counts)

    def commit(t: float, att: Attempt, rec: StepRecord) -> FiniteStep:
        out, u = att.value
        state["x"] = out.r.copy()
        gap = dc.all_gaps(u).copy()
        force, pressure = _force(dc, out, u)
        dc.accept(pressure)  # the warm start of the next step: the law's tractions, as the algorithms left them
        force, pressure = _force(dc, out, u, balanced=True)
        step = FiniteStep(t, out.status, rec.newton_iterations, int(out.outer), rec.linear_solves, force,
                          rec.cutbacks, rec.seconds, out.message, u=u.copy(), pressure=pressure.copy(),
                          gap=gap, normal_force=float(np.sum(dc.weights * pressure)), requested=rec.requested,
                          normals=None if _own_forces(dc) is None else dc.normals.copy())
        records.append(step)
        state["last"] = (out, u, dc.cand.copy())
        return step

    hook = None if on_step is None else (lambda st: on_step(st, st.u.copy(), st.pressure.copy()))
    run_ = step_through(times, attempt, commit, max_cutbacks=max_cutbacks, on_step=hook,
                        what="finite-deformation contact",
                        advice="use more load steps, a smaller penalty_scale or algorithm='ssn'")
    status, message, last, x = run_.status, run_.message, state["last"], state["x"]
    if last is None:
        out, u = _Run(x, np.zeros(dc.cand.size), dc.gaps(x), status, message, 0, 0, eps0, np.inf, []), dc.expand(x)
    else:  # the last accepted state, with the candidates its multipliers belong to (a failed step changed them)
        out, u, dc.cand = last
    t_last = records[-1].t if (records and last is not None) else 0.0
    sol = _solution(problem, dc, out, u, algorithm, pen_name, opts, status, message, records, t_start,
                    fixed=data.fixed, load=data(t_last)[1])
    # the run's status is the verified one of its returned state
    return FiniteSolution(sol, tuple(records), sol.result.status, sol.result.message,
                          extra={"h": dc.h, "dofs": int(problem.model.ndofs), "residual_log": dc.residual_log})


def _attempt(dc, data, run, opts, eps0, pen_name, x, t):
    """One try of the step to ``t`` from ``x``: ``(run, u, exception or None)``."""
    try:
        fv, load, ob = data(t)
        dc.configure(fv, load, ob, x, predictor_stiffness=eps0)
        if dc.cand.size == 0:
            # no point near the obstacle: the step is a contact-free Newton solve
            out = _free_solve(dc, opts)
            return out, dc.expand(out.r), None
        for _attempt_no in range(8):
            out = run(dc, opts, eps0, pen_name)
            u = dc.final_displacement(out.r)
            added = dc.extend(dc.all_gaps(u), opts.tol_penetration * dc.h)
            if added.size == 0 or out.status < 0:
                break
        return out, u, None
    except InvertedElementError as exc:
        return None, None, exc


def _free_solve(dc, opts) -> _Run:
    """Contact-free equilibrium of a step (no candidate): Newton with a zero-force law."""
    from ... import penalties as _pen
    from ..laws._normal import make_law

    law = make_law(_pen.make("rockafellar"), np.ones(0))
    out = dc.subproblem(law, np.zeros(0), dc.start(), tol=opts.newton_tol, maxiter=opts.maxiter_newton)
    st = ContactStatus.CONVERGED if out.converged else ContactStatus.NEWTON_FAILED
    return _Run(out.state, np.zeros(0), out.g, st, "no contact in this step" if out.converged else out.message,
                0, out.iterations, 0.0, out.residual, [])


def _own_forces(dc):
    """The kinematics of ``dc`` when it gives the contact forces itself (a two-body pair: they act on the slave
    and master nodes, :meth:`~alcontact.contact.kinematics.CurrentMortarGap.force_points`), else ``None``
    (a rigid master: the force on point ``i`` is :math:`w_i t_{N,i} \nu_i`)."""
    kin = dc.kinematics
    return kin if hasattr(kin, "force_points") else None


def _contact_points(dc, u, nodal):
    """``(dofs, forces)`` of the contact forces on the bodies for the nodal normal forces ``nodal``."""
    own = _own_forces(dc)
    if own is None:
        return dc.dofs, nodal[:, None] * dc.normals
    return own.force_points(u, nodal)


def _force(dc, out, u, *, balanced: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Resultant contact force (on the slave body) and pressures (all points) of a converged step
    (``balanced``: the pressures of :func:`_applied_pressure`, else the algorithm's tractions)."""
    dc.all_gaps(u)  # the normals at the current configuration
    p = np.zeros(dc.points.shape[0])
    if out.lam.size:
        p[dc.cand] = np.maximum(_applied_pressure(dc, out.lam, u) if balanced else out.lam, 0.0)
    own = _own_forces(dc)
    if own is not None:
        return own.side_forces(u, dc.weights * p)[0], p
    return np.sum((dc.weights * p)[:, None] * dc.normals, axis=0), p


def _applied_pressure(dc, lam, u) -> np.ndarray:
    r"""Pressures on the candidates that the state ``u`` carries: the forces in equilibrium with it.

    At a candidate :math:`i` with :math:`\lambda_i > 0` the residual of (S) on its free DOFs is
    :math:`(f_{int} - f_{ext})_i - \nu_i w_i t_i`, so the normal force that balances the body
    there is :math:`w_i p_i = \nu_i \cdot (f_{int} - f_{ext})_i` (free components only). It
    equals the law's traction :math:`t_i = p'(g_i/\eta_i, \lambda_i)` up to the Newton residual,
    except where the law's round-off dominates: the pure penalty at :math:`\varepsilon_N \sim
    10^6 \varepsilon_0` (penetration below ``tol_penetration`` ``h``) evaluates
    :math:`\varepsilon_N g(x)` with gaps from absolute coordinates, a force noise of
    :math:`\varepsilon_N \epsilon_{mach} |x|` (4.5e-8 relative on ``examples/finite_ironing.toml``),
    at which its Newton iteration stalls; the balanced forces are in equilibrium with the
    returned displacement to 6e-16 there (law forces: 2.3e-8). The same choice as the
    small-deformation direct path (:meth:`DiscreteContact.applied_pressure
    <alcontact.contact.systems._condensed.DiscreteContact.applied_pressure>`). The residual left on
    the other free DOFs (tangential components at the contact points, the interior) is what
    the ``equilibrium`` measure of :mod:`alcontact.contact._verify` checks. Points with
    :math:`\lambda_i \le 0`, or without a free DOF, keep :math:`\lambda_i`.
    """
    lam = np.asarray(lam, dtype=float)
    cand = dc.cand
    if lam.size != cand.size or not np.any(lam > 0):
        return lam
    if _own_forces(dc) is not None:
        return _applied_mortar_pressure(dc, lam, u)
    rb, _ = dc._body_state(u, False)
    rb_free = rb[dc.free]
    pos = dc.pos[cand]
    free = pos >= 0
    nu = np.where(free, dc.normals[cand], 0.0)
    f = np.where(free, rb_free[np.maximum(pos, 0)], 0.0)
    nn = np.einsum("ij,ij->i", nu, nu)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.einsum("ij,ij->i", nu, f) / (nn * dc.weights[cand])
    keep = (lam > 0) & (nn > 0.5) & np.isfinite(p)
    return np.where(keep, p, lam)


def _applied_mortar_pressure(dc, lam, u) -> np.ndarray:
    r""":func:`_applied_pressure` of a two-body pair: the pressures of the pressed candidates whose forces
    :math:`-G_A^T (w_A p_A)` balance the body residual best, :math:`\min_p |f_{int} - f_{ext} + G_A^T (w_A p_A)|`
    on the free DOFs (normal equations :math:`G_A G_A^T y = -G_A (f_{int} - f_{ext})`, :math:`y = w_A p_A`): a
    mortar row couples a slave node with its neighbours and the master nodes, so the force of one point is
    not read off its own DOFs. ``lam`` where that system is singular."""
    import scipy.sparse.linalg as spla

    act = np.flatnonzero(lam > 0)
    rb, _ = dc._body_state(u, False)
    Ga = dc.kinematics.evaluate(u, dc.cand[act]).gradient()
    A = (Ga @ Ga.T).tocsc()
    try:
        with np.errstate(all="raise"):
            y = spla.spsolve(A, -(Ga @ rb[dc.free]))
    except (RuntimeError, FloatingPointError, ValueError):
        return lam
    y = np.atleast_1d(np.asarray(y, dtype=float))
    if not np.all(np.isfinite(y)):
        return lam
    p = lam.copy()
    p[act] = y / dc.weights[dc.cand[act]]
    return p


def _check(problem, dc, out, u, opts, *, fixed, load):
    """``(check, pressures, gaps)`` of a returned state (all contact points): every measure of
    :mod:`alcontact.contact._verify`, equilibrium of ``u`` with the reported forces (loads ``load``) included."""
    g_all = dc.all_gaps(u)
    pressure = np.zeros(dc.points.shape[0])
    try:
        if out.lam.size:
            pressure[dc.cand] = _applied_pressure(dc, out.lam, u)
        nodal = dc.weights * np.maximum(pressure, 0.0)
        residual = state_equilibrium(problem.model, u, fixed, load, *_contact_points(dc, u, nodal),
                                     dc.h, pressure=pressure, weights=dc.weights).largest
    except InvertedElementError:  # the state of a failed run (its status already says so): no equilibrium
        if out.lam.size:
            pressure[dc.cand] = out.lam
        residual = np.inf
    check = check_state(g_all, pressure, dc.h, tol_penetration=opts.tol_penetration,
                        tol_complementarity=opts.tol_complementarity, equilibrium=residual,
                        tol_equilibrium=equilibrium_tolerance(opts, floor=_tol_floor(dc)), reach=reach(dc.points, u))
    return check, pressure, g_all


def _tol_floor(dc) -> float:
    """Lowest Newton tolerance of the model's Newton solver (its declared ``tol_floor``: 0 for exact solves,
    the AMG + CG floor ``_NEWTON_TOL_FLOOR`` for inexact ones)."""
    return float(getattr(getattr(dc, "solver", None), "tol_floor", 0.0))


def _solution(problem, dc, out, u, algorithm, pen_name, opts, status, message, records, t_start, *, fixed, load):
    # the one place a finite-deformation result is built: a "converged" state must pass the tolerances,
    # equilibrium of the returned displacement with the returned forces (loads of the last step) included
    check, pressure, g_all = _check(problem, dc, out, u, opts, fixed=fixed, load=load)
    nodal = dc.weights * np.maximum(pressure, 0.0)
    status, message = verified_status(status if status < 0 else out.status, message, check,
                                      what=f"finite-deformation contact solve {algorithm}")
    pressure = np.maximum(pressure, 0.0)
    force = np.sum(nodal[:, None] * dc.normals, axis=0)
    two_body = {}
    own = _own_forces(dc)
    if own is not None:  # the forces on both bodies (action = reaction), as at small deformation
        force, master = own.side_forces(u, nodal)
        norm = float(np.linalg.norm(force))
        two_body = {"slave_contact_force": force.tolist(), "master_contact_force": master.tolist(),
                    "contact_force_balance": float(np.linalg.norm(force + master)) / norm if norm > 0 else 0.0,
                    "contact_force_points": own.force_points(u, nodal)}
        if hasattr(own, "pair_forces"):  # several two-body pairs: each pair's slave force, the worst pair's balance
            per = own.pair_forces(u, nodal)
            two_body["pair_slave_contact_forces"] = per[:, 0].tolist()
            norms = np.linalg.norm(per[:, 0], axis=1)
            two_body["contact_force_balance"] = float(np.max(np.where(
                norms > 0, np.linalg.norm(per[:, 0] + per[:, 1], axis=1) / np.where(norms > 0, norms, 1.0), 0.0)))
    closed = g_all > -max(1e-6, 10 * opts.tol_penetration) * dc.h
    active = closed & (pressure > 1e-12 * max(float(pressure.max(initial=0.0)), 1e-300))
    pen_final = check.value("penetration")
    compl = check.value("complementarity")
    result = ContactResult(
        status=status,
        message=message,
        algorithm=algorithm,
        penalty=pen_name,
        outer_iterations=int(sum(s.outer_iterations for s in records)),
        newton_iterations=int(dc.newton_iterations),
        linear_solves=int(dc.linear_solves),
        factorizations=int(dc.linear_solves),
        penetration=pen_final,
        complementarity=compl,
        residual=float(out.residual),
        eps_n=float(out.eps),
        history=tuple(out.history),
    )
    t_end = time.perf_counter()
    return ContactSolution(
        problem=problem, u=u, points=dc.points, pressure=pressure, gap=g_all, weights=dc.weights,
        active=active, normals=dc.normals.copy(), total_contact_force=force, result=result, nodal_forces=nodal,
        timings=dict(dc.timings(), total_s=t_end - t_start),
        extra={"h": dc.h, "candidates": int(dc.cand.size), "dofs": int(problem.model.ndofs),
               "steps": len(records), **dc.extra(), **two_body},
    )
