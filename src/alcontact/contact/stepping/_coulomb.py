"""Load stepping of Coulomb friction: :func:`solve_friction` (small deformation) and
:func:`solve_finite_friction` (finite deformation), section 6.2.

Each load step runs one registered frictional algorithm (Algorithm 6.2, Algorithm 6.4 or the
Alart-Curnier reference, :mod:`alcontact.contact.algorithms._coulomb`) on the step's system:
the condensed one (:class:`~alcontact.contact.systems._condensed.FrictionalContact`, direct
solver), the full-space Krylov one (:class:`~alcontact.contact.systems._krylov.IterativeFrictionalContact`,
``linear_solver="amg"``) or the finite-deformation one
(:class:`~alcontact.contact.systems._full_space.FiniteFrictionContact`). A load step
(:class:`_StepPath`) adds candidates, checks a held body's equilibrium and is cut back when it
fails (:func:`~alcontact.contact.stepping._steps.step_through`); the accepted steps are
recorded (:mod:`alcontact.contact.solution._records`). The strategy of a small-deformation
solve is chosen by :func:`register_friction_strategy` (direct or Krylov), a problem with
``kinematics="finite"`` goes to :func:`solve_finite_friction`
(:func:`register_friction_kinematics`).
"""

from __future__ import annotations

import dataclasses
import logging
import time
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from ..._options import MAX_STEPS, VALUE_RANGE, is_integer, is_real, show
from ...errors import InputError, InvertedElementError
from ...linalg import select_solver
from .._verify import check_state, equilibrium_tolerance, reach, state_equilibrium, verified_status
from ..algorithms._coulomb import (_EQUILIBRIUM_TOL, FrictionOptions, _Ctx, _FiniteALCtx, _StepOut, _admissible,
                                   _step_ssn, friction_algorithms, state_reversals)
from ..algorithms._frictionless import check_solve_args, find_algorithm, options_with
from ..laws._coulomb import OPEN, SLIP, STICK
from ..kinematics._stacked_gap import pair_balance
from ..solution._sides import two_body_sides
from ..laws._stiffness import penalty_stiffness
from ..masters.obstacles import transport_tangent
from ..problem._loading import LoadHistory, problem_at
from ..solution._records import FiniteFrictionSolution, FiniteFrictionStep, FrictionSolution, FrictionStep
from ..solution._solution import ContactStatus
from ..systems._condensed import FrictionalContact
from ..systems._full_space import FiniteFrictionContact, contact_states, finite_solver
from ..systems._krylov import IterativeFrictionalContact, _FullCtx
from ._steps import Attempt, StepRecord, _StepData, _step_times, step_through


logger = logging.getLogger(__name__)


def _checked_steps(steps):
    """``steps`` of :func:`solve_friction`: a count in [1, MAX_STEPS] or increasing positive times."""
    if is_integer(steps):
        if not 1 <= steps <= MAX_STEPS:
            raise InputError(f"steps = {show(steps)}: out of range, must be in [1, {MAX_STEPS}] (or a sequence of "
                             "step times).")
        return int(steps)
    ok = isinstance(steps, (list, tuple, np.ndarray)) and 0 < len(steps) <= MAX_STEPS and all(
        is_real(t) and np.isfinite(t) and t > 0 for t in steps)
    if not ok or any(b <= a for a, b in zip(steps, steps[1:])):
        raise InputError(f"steps = {show(steps)}: expected a number of steps or positive, strictly increasing step "
                         "times, e.g. steps=[0.25, 0.5, 1.0].")
    return tuple(float(t) for t in steps)


def _resolve(algorithm: str, penalty: str | None):
    """Step function and penalty of the frictional ``algorithm`` (registry entry)."""
    entry = find_algorithm(algorithm, friction=True)
    return entry.run, entry.penalty_for(penalty)


# ---------------------------------------------------------------------------
# load stepping
# ---------------------------------------------------------------------------
@dataclass
class _State:
    """Converged state over all m contact-boundary points."""

    t: float
    u: np.ndarray
    y: np.ndarray  # (m, d) gap and u_T
    tN: np.ndarray  # (m,)
    tT: np.ndarray  # (m, d-1)
    R: np.ndarray  # (m, d)
    slip_total: np.ndarray  # (m, d)
    predictor: tuple | None = None  # (candidates, d lambda*/d y_free) of the last step, for the next start


def _on(mu, cand):
    """The Coulomb coefficient of the candidates ``cand``: ``mu`` itself when it is one number, else its entries
    (one per contact point: contact pairs with their own coefficient)."""
    return mu[cand] if np.ndim(mu) else mu


def _coefficients(problem, friction):
    """The Coulomb coefficient of a solve: one number when every contact point has the same, else one per point.

    ``friction`` (given) applies to every pair; otherwise each pair's own ``ContactPair.friction``
    applies to its stacked points (``problem.pair_of_points()``).

    Raises
    ------
    InputError
        A coefficient that is not a finite number >= 0.
    """
    pairs = getattr(problem, "pairs", ())
    given = [friction] if friction is not None else ([p.friction for p in pairs] or [problem.friction])
    for i, mu in enumerate(given):
        if not (is_real(mu) and 0 <= mu <= VALUE_RANGE[1]):  # comparisons, not isfinite: a huge int is no float
            where = "friction" if friction is not None or len(pairs) <= 1 else f"pairs[{i}].friction"
            raise InputError(f"{where} = {show(mu)}: the friction coefficient must be a finite number >= 0 (at most "
                             f"{VALUE_RANGE[1]:g}). Use 0 for frictionless contact.")
    values = [float(mu) for mu in given]
    if len(set(values)) == 1:
        return values[0]
    return np.asarray(values)[problem.pair_of_points()]


def _check_tangential_start(fc, prev, t: float, tangential: list, opts) -> None:
    """An :class:`InputError` when a tangential load case acts at ``t`` while no point of the step's start
    state ``prev`` is in contact (the tangential problem would have no support)."""
    if tangential and not np.any(_closed(fc, prev.tN, prev.y[:, 0], opts)):
        active = [c.label for c in tangential if c.value(t) != 0.0]
        if active:
            raise InputError(
                f"tangential load {', '.join(active)} is applied at t={t:g} but no point is in contact at "
                f"the start of that step (t={prev.t:g}); apply the normal load first (start the tangential "
                "amplitude at 0 until contact exists).")


def _closed(fc, tN, g, opts):
    return (tN > 0) & (g >= -max(1e-6, 10 * opts.tol_penetration) * fc.h)


class _StepPath(ABC):
    """How a solution path sets up one load step; the step itself (:meth:`advance`) is shared.

    A path gives the system of a step (:meth:`context`, an :class:`_ALSystem` for the AL
    algorithms), the step without candidates (:meth:`without_candidates`) and the
    displacement of a solved step (:meth:`displacement`); :meth:`advance` adds the
    candidates that penetrate, assembles the state over all points and accepts a step of a
    body held by the obstacle only in equilibrium.
    """

    @abstractmethod
    def context(self, fc, prev: _State, t: float, last: _StepOut | None, step_fn, eps_n, eps_t, mu, opts):
        """The step's system on the candidates ``fc.cand`` and the Newton iterations spent to set it up.

        ``last`` is the previous attempt of the same step (before candidates were added), or ``None``.
        """

    @abstractmethod
    def without_candidates(self, fc, t: float) -> tuple[_StepOut, np.ndarray]:
        """The step without contact candidates and its displacement."""

    @abstractmethod
    def displacement(self, fc, t: float, out: _StepOut) -> np.ndarray:
        """The displacement of the solved step ``out``."""

    def advance(self, fc, prev: _State, t: float, step_fn, pen_name, eps_n, eps_t, mu, opts):
        """Solve one step from ``prev`` to time ``t`` (adding candidates that penetrate).

        Returns ``(result, out, outer, newton)`` with ``result = (u, y_all, tN, tT, R, predictor)``
        over all points (``None`` when the step failed; ``out`` says why).
        """
        outer = newton = 0
        last = None
        for _attempt in range(8):
            cand = fc.cand
            d = fc.dim
            if cand.size == 0:
                out, u = self.without_candidates(fc, t)
            else:
                ctx, pre = self.context(fc, prev, t, last, step_fn, eps_n, eps_t, mu, opts)
                newton += pre
                out = step_fn(ctx, pen_name)
                outer += out.outer
                newton += out.newton
                if not out.ok:
                    return None, out, outer, newton
                u = self.displacement(fc, t, out)
            y_all = fc.all_local(u)
            outside = np.ones(fc.points.shape[0], bool)
            outside[cand] = False
            add = fc.add(np.flatnonzero(outside & (y_all[:, 0] > opts.tol_penetration * fc.h)))
            if add.size:
                logger.info("t=%g: adding %d contact candidates that penetrate", t, add.size)
                last = out
                continue
            m = fc.points.shape[0]
            tN = np.zeros(m)
            tT = np.zeros((m, d - 1))
            R = np.zeros((m, d))
            tN[cand], tT[cand], R[cand] = out.t[:, 0], out.t[:, 1:], out.R
            if fc.spring is not None:  # held by the obstacle: accept only a step in equilibrium
                R_phys = np.zeros((m, d))
                R_phys[cand] = fc.weights[cand, None] * out.t
                defect = fc.equilibrium_defect(t, u, R_phys)
                if not defect <= _EQUILIBRIUM_TOL:
                    return None, _StepOut(False, f"no equilibrium found (relative residual {defect:.2e}): the "
                                                 "obstacle and friction do not hold the body there", prev.R, prev.R,
                                          outer, newton, ContactStatus.NEWTON_FAILED), outer, newton
            pred = (cand.copy(), out.predictor) if out.predictor is not None else None
            return (u, y_all, tN, tT, R, pred), out, outer, newton
        return None, _StepOut(False, "candidate set did not settle", prev.R, prev.R, 0, 0, ContactStatus.MAXITER), \
            outer, newton


class _CondensedPath(_StepPath):
    """The direct path: steps on the condensed forces of :class:`FrictionalContact` (:class:`_Ctx`).

    A body held by the obstacle starts each step sticking (:meth:`FrictionalContact.frozen_start`),
    at first contact from the semi-smooth Newton solution; the multipliers start from the tangent
    predictor of the last step where it has the same candidates.
    """

    def context(self, fc, prev, t, last, step_fn, eps_n, eps_t, mu, opts):
        cand = fc.cand
        c, d = cand.size, fc.dim
        newton = 0
        ctx = _Ctx(fc, fc.y_free(t)[cand], fc.weights[cand], fc.A.reshape(c, d, c, d), prev.tN[cand].copy(),
                   prev.tT[cand].copy(), prev.y[cand, 1:].copy(), prev.R[cand].copy(), eps_n, eps_t, _on(mu, cand),
                   opts, fc.tfree[cand])
        if fc.spring is not None:  # held by the obstacle only
            closed = prev.tN[cand] > 0
            if np.any(closed):  # start sticking (FrictionalContact.frozen_start)
                R0 = fc.frozen_start(prev.t, t, ctx.R0, closed)
                ctx.R0 = ctx.R0 if R0 is None else R0
            elif step_fn is not _step_ssn:
                # first contact: with zero multipliers the Coulomb discs of the AL subproblem have radius 0
                # and nothing holds the tangential rigid motion; start from the semi-smooth Newton solution
                # of the same discrete problem (a predictor: the AL stopping test decides)
                pre = _step_ssn(ctx)
                newton += pre.newton
                if pre.ok:
                    ctx.R0, ctx.lamN, ctx.lamT = pre.R, pre.t[:, 0].copy(), pre.t[:, 1:].copy()
        if prev.predictor is not None and np.array_equal(prev.predictor[0], cand):
            # tangent predictor: lambda_n + (d lambda*/d y_free) (y_free(t) - y_free(t_n))
            dyf = (ctx.yf - fc.y_free(prev.t)[cand]).ravel()
            lam0 = np.concatenate([ctx.lamN[:, None], ctx.lamT], axis=1) + (prev.predictor[1] @ dyf).reshape(c, d)
            if np.all(np.isfinite(lam0)):
                ctx.lamN, ctx.lamT = _admissible(ctx, lam0)
        return ctx, newton

    def without_candidates(self, fc, t):
        d = fc.dim
        return _StepOut(True, "no candidate points", np.zeros((0, d)), np.zeros((0, d)), 0, 0), fc.u_free(t)

    def displacement(self, fc, t, out):
        return fc.displacement(t, out.R)


#: The direct path's step (:meth:`_StepPath.advance` of :class:`_CondensedPath`).
_advance = _CondensedPath().advance


def solve_friction(problem, history: LoadHistory | None, algorithm: str = "simo-laursen", penalty: str | None = None,
                   options: FrictionOptions | None = None, *, steps=None, friction: float | None = None,
                   on_step=None, obstacle_path=None, **option_overrides) -> FrictionSolution:
    r"""Quasi-static frictional contact over a load history.

    Parameters
    ----------
    problem : ContactProblem
        Bodies and contact pairs; its own supports and loads act at full value at
        every step; each pair's ``friction`` is its Coulomb coefficient :math:`\mu` (of
        the pair's stacked points, :meth:`ContactProblem.point_friction`).
    history : LoadHistory
        Scaled supports/loads and the step times.
    algorithm : {"simo-laursen", "family-p", "ssn"}
        Algorithm 6.2, Algorithm 6.4, or the semi-smooth Newton reference.
    penalty : str, optional
        Family-P penalty of ``"family-p"`` (default ``"exp-met1"``).
    options : FrictionOptions or dict, optional
        Options; a dict holds :class:`FrictionOptions` fields.
    steps : int or sequence of float, optional
        Overrides ``history.times`` (an int: that many equal steps).
    friction : float, optional
        Overrides the coefficient of every pair.
    on_step : callable, optional
        ``on_step(k, t, n)`` is called before requested step ``k`` (0-based) of ``n``,
        at pseudo-time ``t`` (for progress bars).
    obstacle_path : callable ``t -> (d,)``, optional
        Finite kinematics only: translation of the obstacle at pseudo-time ``t``.
    **option_overrides
        Fields of :class:`FrictionOptions`.

    Returns
    -------
    FrictionSolution or FiniteFrictionSolution
        A problem with ``kinematics="finite"`` is solved by
        :func:`~alcontact.contact.solve_finite_friction` (Algorithms 6.2 / 6.4 in the
        current configuration) over ``steps`` (default: the history's times, or 10
        uniform steps without a history, every support and load then scaled by the
        pseudo-time); both solutions share the per-step views
        (:class:`~alcontact.contact.solution._records.StepRecords`: ``times``, ``forces``,
        ``frames``, ...).

        Small kinematics: per-step states; ``status`` negative (and a logged warning) when a step
        failed after ``max_cutbacks`` cut-backs, or ``NOT_VERIFIED`` when a recorded
        step fails the penetration, complementarity or Coulomb check of
        :mod:`alcontact.contact._verify`. ``UNBOUNDED`` when a body held only by
        the obstacle has no static equilibrium at a step (the free tangential load
        exceeds :math:`\mu N`, or the loads pull it off a flat obstacle,
        :meth:`FrictionalContact.slides_away`); the steps before it are kept.

    Raises
    ------
    InputError
        Bad options, a negative friction coefficient, a load history not
        defined at some step, or a tangential load case that is non-zero at a
        step that starts without contact.

    Notes
    -----
    Supports may leave rigid motions free when the obstacle holds the body:
    springs on all components of the touching points make the stiffness regular
    and the frictional law is shifted by the same springs, an exact rewriting
    (:meth:`FrictionalContact._stabilize`). Each step of such a body starts from
    sticking (:meth:`FrictionalContact.frozen_start`; at first contact the AL
    algorithms start from the semi-smooth Newton solution, since zero
    multipliers give Coulomb discs of radius 0) and is accepted only in global
    equilibrium (relative residual ``1e-7``).

    Examples
    --------
    >>> from alcontact.problems import friction as fp
    >>> prob, hist = fp.block_on_plane(dim=2, n=4)
    >>> sol = solve_friction(prob, hist)  # doctest: +SKIP
    """
    t_start = time.perf_counter()
    check_solve_args(problem, algorithm, penalty, friction_algorithms(), "friction ")
    step_fn, pen_name = _resolve(algorithm, penalty)
    if getattr(problem, "kinematics", "small") == "finite":
        return _solve_finite(problem, history, algorithm, penalty, options, steps=steps, friction=friction,
                             on_step=on_step, obstacle_path=obstacle_path, **option_overrides)
    opts = options_with(options, FrictionOptions, option_overrides, "friction",
                        find_algorithm(algorithm, friction=True))
    if not isinstance(history, LoadHistory):
        raise InputError(f"history must be a LoadHistory; got {type(history).__name__}.")
    if obstacle_path is not None:
        raise InputError("obstacle_path: a moving obstacle needs kinematics='finite' (ContactProblem(..., "
                         "kinematics='finite') with a hyperelastic body); at small kinematics move the body with "
                         "a ramped support instead.")
    if steps is not None:
        history = history.with_times(_checked_steps(steps))
    mu = _coefficients(problem, friction)  # one number, or one per contact point (pairs with their own)

    solver = select_solver(opts.linear_solver, dim=problem.model.dim, ndofs=problem.model.ndofs)
    fc, advance = _FRICTION_PATHS[solver.exact](problem, history, opts, solver)
    # between two bodies the two surface layers in series (a master E x 1e6 gets the rigid obstacle's penalty)
    pairs = problem.pairs if fc.mortar is not None else None
    eps_n = opts.eps_n if opts.eps_n is not None else penalty_stiffness(problem.model, fc.h, opts.penalty_scale,
                                                                        pairs=pairs)
    eps_t = opts.eps_t if opts.eps_t is not None else opts.tangential_scale * eps_n
    m, d = fc.points.shape
    u0 = fc.u_free(0.0)
    y0 = fc.all_local(u0)
    state = _State(0.0, u0, y0, np.zeros(m), np.zeros((m, d - 1)), np.zeros((m, d)), np.zeros((m, d)))
    tangential = [c for c in history.cases if c.tangential]
    records: list[FrictionStep] = []
    cur = {"state": state}
    t_solve = time.perf_counter()

    def attempt(t: float) -> Attempt:
        prev = cur["state"]
        _check_tangential_start(fc, prev, t, tangential, opts)
        away = fc.slides_away(t, float(np.max(mu)) * history.friction_factor(t))  # body held by the obstacle only
        if away is not None:
            return Attempt(False, ContactStatus.UNBOUNDED, away, final=True)
        solves0 = fc.linear_solves
        res, out, o, nw = advance(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu * history.friction_factor(t),
                                   opts)
        counts = dict(newton=nw, outer=o, linear_solves=fc.linear_solves - solves0)
        if res is not None:  # a step is accepted only when its returned state passes every measure (cut back if not)
            check = verify(t, prev, res)
            if not check.ok:
                return Attempt(False, ContactStatus.NOT_VERIFIED, f"{algorithm} reported {out.message!r} but the "
                               f"state fails verification: {check.describe()}", **counts)
        return Attempt(res is not None, out.status, out.message, value=(res, out), **counts)

    def verify(t: float, prev: _State, res):
        """Every measure of the step's returned state (:mod:`alcontact.contact._verify`)."""
        u, y_all, tN, tT = res[:4]
        closed = _closed(fc, tN, y_all[:, 0], opts)
        duT = y_all[:, 1:] - prev.y[:, 1:]
        w = fc.weights
        # equilibrium of the step's displacement with the forces it reports (loads and supports at t; on both
        # bodies of a two-body pair)
        p_t = problem_at(problem, history, t)
        eq = state_equilibrium(problem.model, u, p_t.dirichlet()[0], p_t.load_vector(),
                               *fc.contact_force_points(tN, tT), fc.h, pressure=tN, weights=w)
        return check_state(y_all[:, 0], tN, fc.h, tol_penetration=opts.tol_penetration,
                           tol_complementarity=opts.tol_complementarity, traction_t=tT,
                           slip=np.where(closed[:, None] & fc.tfree, duT, 0.0), mu=mu * history.friction_factor(t),
                           tol_friction=max(opts.tol_multiplier, opts.tol_slip), equilibrium=eq.largest,
                           tol_equilibrium=equilibrium_tolerance(opts, multipliers=True), reach=reach(fc.points, u))

    def commit(t: float, att: Attempt, rec: StepRecord) -> FrictionStep:
        prev = cur["state"]
        (u, y_all, tN, tT, R, pred), out = att.value
        closed = _closed(fc, tN, y_all[:, 0], opts)
        duT = y_all[:, 1:] - prev.y[:, 1:]
        slip = np.where(closed[:, None], np.einsum("ijk,ik->ij", fc.tangents, duT), 0.0)
        nT = np.linalg.norm(tT, axis=1)
        pref = max(float(np.max(tN, initial=0.0)), 1e-300)
        mu_t = mu * history.friction_factor(t)
        saturated = nT >= mu_t * tN - 1e-6 * np.maximum(mu_t, 1e-300) * pref
        st = np.where(~closed, OPEN, np.where(saturated, SLIP, STICK))
        shear = -np.einsum("ijk,ik->ij", fc.tangents, tT)
        w = fc.weights
        tang_force = np.sum(w[:, None] * shear, axis=0)
        normal_force = float(np.sum(w * tN))
        slip_total = prev.slip_total + slip
        step = FrictionStep(
            t=float(t), requested=rec.requested, u=u, pressure=tN, traction_t=tT, shear=shear, slip=slip,
            slip_total=slip_total, gap=y_all[:, 0], state=st, normal_force=normal_force,
            tangential_force=tang_force, contact_force=tang_force + np.sum((w * tN)[:, None] * fc.normals, axis=0),
            outer_iterations=int(out.outer), newton_iterations=int(out.newton), cutbacks=rec.step_cutbacks,
            penetration=float(np.max(y_all[:, 0], initial=0.0)) / fc.h,
            coulomb=float(np.max(np.maximum(nT - mu_t * tN, 0.0), initial=0.0)) / pref, seconds=rec.seconds,
            linear_solves=int(rec.linear_solves), two_body=_two_body_forces(fc, tN, tT, y_all[:, 0]),
        )
        records.append(step)
        cur["state"] = _State(float(t), u, y_all, tN, tT, R, slip_total, pred)
        return step

    def advice() -> str:
        tip = "use more load steps, a smaller penalty_scale or algorithm='ssn'"
        if fc.spring is not None:
            tip += ("; the body is held by the obstacle only: if contact and friction cannot balance the loads it "
                    "slides or turns away (no static equilibrium), so prescribe that motion as a displacement or "
                    "add a support")
        return tip

    run = step_through(history.times, attempt, commit, max_cutbacks=opts.max_cutbacks, factor=opts.cutback_factor,
                       before_step=on_step, recoverable=(), what=f"frictional contact {algorithm}", advice=advice,
                       done_message="converged")
    status, message = run.status, run.message
    n_outer, n_newton, n_cut = run.outer_iterations, run.newton_iterations, run.cutbacks
    if fc.ncand == 0 and status > 0:
        i = int(np.argmax(np.where(fc.movable, fc.gmax_t, -np.inf)))
        status = ContactStatus.NO_CONTACT
        message = (f"the body never reaches the obstacle: smallest clearance {-fc.gmax_t[i]:.4g} at point "
                   f"{np.round(fc.points[i], 6).tolist()}; check the loads, the obstacle or the contact boundary")
    if status < 0 and status != run.status:  # a step failure was logged by step_through
        logger.warning("frictional contact %s failed (%s): %s", algorithm, status.label, message)
    t_end = time.perf_counter()
    return FrictionSolution(
        problem=problem, history=history, algorithm=algorithm, penalty=pen_name, friction=float(np.max(mu)),
        points=fc.points,
        normals=fc.normals, tangents=fc.tangents, weights=fc.weights, steps=tuple(records), status=status,
        message=message, outer_iterations=n_outer, newton_iterations=n_newton, cutbacks=n_cut,
        linear_solves=fc.linear_solves, eps_n=float(eps_n), eps_t=float(eps_t), h=fc.h,
        # the direct path's factorizations (two when the Schur block was chosen again); none on the AMG path
        factorizations=int(fc.factorizations),
        timings={"setup_s": fc.setup_seconds, "factor_s": fc.factor_seconds, "solve_s": t_end - t_solve,
                 "total_s": t_end - t_start},
        extra={"candidates": fc.ncand, "dofs": int(problem.model.ndofs), "linear_solver": solver.name,
               "strategy": fc.strategy, **fc.stats(),
               **({"point_friction": mu} if np.ndim(mu) else {})},
    )


def _two_body_forces(fc, tN, tT, gaps) -> dict:
    r"""Contact forces on the slave and master sides of a two-body pair and their balance (``{}`` against a rigid
    master): the keys of the frictionless solve (:func:`alcontact.contact._solve._force_balance`), here with the
    tangential forces :math:`-L^T R` too (:mod:`alcontact.contact.kinematics._mortar_tangent`)."""
    if fc.mortar is None:
        return {}
    points = fc.contact_force_points(tN, tT)
    if len(fc.problem.pairs) > 1:  # a two-body pair beside other pairs: each pair's sides (kinematics._stacked_gap)
        R = fc.weights[:, None] * np.concatenate([tN[:, None], tT], axis=1)
        balance = pair_balance(fc.problem, fc._mortar_rows(), R, fc.dofs)
        return {**balance, "contact_force_points": points,
                **two_body_sides(fc.problem, fc.mortar, fc.weights * tN, gaps, points=points, balance=balance)}
    nodes, forces = points
    slave_rows = np.isin(nodes[:, 0], fc.dofs[:, 0])
    master_rows = np.isin(nodes[:, 0], fc.mortar.master_dofs[:, 0])
    slave = forces[slave_rows].sum(axis=0)
    master = forces[master_rows & ~slave_rows].sum(axis=0)
    norm = float(np.linalg.norm(slave))
    balance = float(np.linalg.norm(slave + master)) / norm if norm > 0 else 0.0
    return {"slave_contact_force": slave.tolist(), "master_contact_force": master.tolist(),
            "contact_force_balance": balance, "contact_force_points": (nodes, forces),
            **two_body_sides(fc.problem, fc.mortar, fc.weights * tN, gaps, points=points)}


def finite_friction_steps(history, steps):
    """The load steps of a finite-deformation Coulomb solve: ``steps``, else the history's times, else 10.

    Raises
    ------
    InputError
        ``history`` not a :class:`LoadHistory`, or one with a friction amplitude (the coefficient is
        constant at finite kinematics).
    """
    if history is not None and not isinstance(history, LoadHistory):
        raise InputError(f"history must be a LoadHistory or None; got {type(history).__name__}.")
    if history is not None and history.friction is not None:
        raise InputError("history: a friction amplitude (friction_ramp) is not available at finite kinematics; "
                         "remove it (the coefficient is constant) or use kinematics='small'.")
    if steps is None:
        steps = history.times if history is not None else 10
    return steps


def _solve_finite(problem, history, algorithm, penalty, options, *, steps, friction, on_step, obstacle_path,
                  **option_overrides):
    """:func:`solve_friction` of a ``kinematics="finite"`` problem: :func:`solve_finite_friction`
    (registered by :mod:`._finite_friction`, :func:`register_friction_kinematics`)."""
    solve_finite_friction = _KINEMATICS_SOLVERS["finite"]
    steps = finite_friction_steps(history, steps)
    mu = problem.friction if friction is None else friction
    return solve_finite_friction(problem, mu, algorithm, penalty, options, steps=steps, history=history,
                                 obstacle_path=obstacle_path, progress=on_step, **option_overrides)


def _direct_path(problem, history, opts, solver):
    """The condensed problem (:class:`FrictionalContact`) on the exact factorization of ``solver``, and its step."""
    return FrictionalContact(problem, history, margin=opts.margin, linear_solver=solver.name), _advance


#: :attr:`SolverChoice.exact <alcontact.linalg.SolverChoice>` -> ``(problem, history, opts, solver) ->
#: (contact problem, step)``: the condensed problem needs an exact factorization; the full-space problem whose
#: Krylov solves an approximate solver preconditions is registered by :mod:`._friction_iterative`
_FRICTION_PATHS = {True: _direct_path}
#: :func:`solve_friction` of the kinematics other than ``"small"``, registered by their modules
_KINEMATICS_SOLVERS: dict = {}


def register_friction_strategy(exact: bool, make) -> None:
    """Register how :func:`solve_friction` builds its problem for solvers that factorize exactly (``exact``) or not.

    The modules that build on this one (:mod:`._friction_iterative`) register themselves, so that the
    imports run one way (the package imports them).
    """
    _FRICTION_PATHS[bool(exact)] = make


def register_friction_kinematics(kinematics: str, solver) -> None:
    """Register the frictional solver of ``kinematics`` (``"finite"``: :mod:`._finite_friction`)."""
    _KINEMATICS_SOLVERS[kinematics] = solver


class _FullSpacePath(_StepPath):
    """The AMG path's AL step: the loop of :func:`~alcontact.contact.algorithms._coulomb._step_al` on :class:`_FullCtx`.

    Every step starts from the previous converged displacement (all closed points
    sticking, as :meth:`FrictionalContact.frozen_start` on the direct path), or from the
    last attempt's when candidates were added.
    """

    def context(self, fc: IterativeFrictionalContact, prev, t, last, step_fn, eps_n, eps_t, mu, opts):
        cand = fc.cand
        x0 = prev.u[fc.free] if last is None else last.z
        return _FullCtx(fc, fc.rows(cand), fc.y_fix(t)[cand], fc.load(t), fc.weights[cand], prev.tN[cand].copy(),
                        prev.tT[cand].copy(), prev.y[cand, 1:].copy(), x0, fc.u_free(t)[fc.free], eps_n, eps_t,
                        _on(mu, cand), opts, fc.tfree[cand], load_scale=fc.load_scale(t)), 0

    def without_candidates(self, fc, t):
        d = fc.dim
        x = fc.u_free(t)[fc.free]
        return _StepOut(True, "no candidate points", np.zeros((0, d)), np.zeros((0, d)), 0, 0, z=x), \
            fc.expand_at(t, x)

    def displacement(self, fc, t, out):
        return fc.expand_at(t, out.z)


class _CondensedOnAMG(_CondensedPath):
    """The semi-smooth Newton reference: the direct path's step on the compliance built by AMG-CG solves."""

    def advance(self, fc: IterativeFrictionalContact, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts):
        fc.condense()
        return super().advance(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts)


#: Path of each frictional step function on the AMG path (default: the full-space AL step).
_STEP_PATHS = {_step_ssn: _CondensedOnAMG()}
_FULL_SPACE = _FullSpacePath()


def advance(fc: IterativeFrictionalContact, prev, t: float, step_fn, pen_name, eps_n, eps_t, mu, opts):
    """One load step on the AMG path (the contract of :meth:`alcontact.contact.stepping._coulomb._StepPath.advance`)."""
    return _STEP_PATHS.get(step_fn, _FULL_SPACE).advance(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts)


def _krylov_path(problem, history, opts, solver):
    """The full-space problem solved by Krylov methods preconditioned by the approximate ``solver``, and its step."""
    return IterativeFrictionalContact(problem, history, margin=opts.margin, solver=solver), advance


register_friction_strategy(False, _krylov_path)


# ---------------------------------------------------------------------------
# load stepping
# ---------------------------------------------------------------------------
def solve_finite_friction(problem, mu: float, algorithm: str = "simo-laursen", penalty: str | None = None,
                          options: FrictionOptions | dict | None = None, *, steps: int | Sequence[float] = 10,
                          history: LoadHistory | None = None,
                          obstacle_path: Callable[[float], Any] | None = None,
                          on_step: Callable[[FiniteFrictionStep], None] | None = None,
                          progress: Callable[[int, float, int], None] | None = None,
                          **option_overrides) -> FiniteFrictionSolution:
    """Coulomb friction at finite deformation, in load steps (module doc).

    Parameters
    ----------
    problem : ContactProblem
        Body (e.g. :class:`~alcontact.fem.hyperelastic.Hyperelastic`), supports, loads,
        obstacle and contact boundary.
    mu : float
        Coulomb coefficient (>= 0).
    algorithm : {"simo-laursen", "family-p"}
        Algorithm 6.2 (Macaulay normal law) or 6.4 (family-P normal law ``penalty``).
    penalty : str, optional
        Family-P penalty of Algorithm 6.4 (default ``exp-met1``).
    options : FrictionOptions or dict, optional
        Tolerances and penalties (``eps_n``, ``eps_t``, ``penalty_scale``, ``tangential_scale``,
        ``tol_*``, ``maxiter``, ``newton_tol``, ``max_cutbacks``, ``cutback_factor``, ``radius``).
    steps : int or sequence of float
        Number of uniform load steps or the increasing step times in (0, 1].
    history : LoadHistory, optional
        Amplitudes of the load cases (as :func:`~alcontact.contact.solve_finite`); without it
        every support value and load is scaled by the pseudo-time.
    obstacle_path : callable ``t -> (d,)`` or ``t -> RigidMotion``, optional
        Translation of the obstacle at pseudo-time ``t`` (default none), or its rigid
        placement (rotation and translation, :class:`~alcontact.contact.obstacles.RigidMotion`);
        the slip is measured on the moving obstacle's surface in its own frame.
    on_step : callable ``step -> None``, optional
        Called with every accepted :class:`FiniteFrictionStep` (it carries the step's
        displacement, pressures, gaps, tangential tractions, slip and stick/slip states).
    progress : callable ``(k, t, n) -> None``, optional
        Called before requested step ``k`` (0-based) of ``n`` at pseudo-time ``t``
        (the ``on_step`` of :func:`~alcontact.contact.solve_friction`).

    Returns
    -------
    FiniteFrictionSolution
        A negative status (with a logged warning) when a step fails at the smallest increment
        (``max_cutbacks`` reductions by ``cutback_factor``, :func:`~alcontact.contact.stepping._steps.step_through`)
        or its state fails the verification.
    """
    t_start = time.perf_counter()
    if not (is_real(mu) and 0 <= mu <= 1e100):  # comparisons, not isfinite: a huge int is no float
        raise InputError(f"mu = {show(mu)}: the Coulomb coefficient must be a finite number >= 0 (at most 1e100).")
    entry = find_algorithm(algorithm, friction=True, kinematics="finite")
    pen_name = entry.penalty_for(penalty)
    opts = options_with(options, FrictionOptions, option_overrides, "friction options", entry)
    times = _step_times(steps)
    step_fn = entry.run
    data = _StepData(problem, history, obstacle_path)
    dc = FiniteFrictionContact(problem, fixed=data.fixed, predictor=opts.predictor,
                               slide_start_reach=opts.slide_start_reach,
                               solver=finite_solver(opts.linear_solver, entry, problem.model))
    d = dc.dim
    m = dc.points.shape[0]
    eps_n = opts.eps_n if opts.eps_n is not None else penalty_stiffness(problem.model, dc.h, opts.penalty_scale)
    eps_t = opts.eps_t if opts.eps_t is not None else opts.tangential_scale * eps_n

    x0 = np.zeros(dc.free.size)
    dc.configure(*data(0.0), x0)
    dc.accept(np.zeros(m))
    dc.place()
    # the committed state every try starts from
    u0 = dc.expand(x0)
    state = {"x": x0, "y_prev": dc.surface_points(u0), "nu_prev": dc.obstacle.normal(dc.points + u0[dc.dofs]),
             "lamN": np.zeros(m), "lamT": np.zeros((m, d)), "last": None}
    records: list[FiniteFrictionStep] = []

    def attempt(t: float) -> Attempt:
        newton0, solves0 = dc.newton_iterations, dc.linear_solves
        res, exc = _attempt(dc, data, step_fn, state["x"], t, state["y_prev"], state["nu_prev"],
                            state["lamN"], state["lamT"], mu, eps_n, eps_t, pen_name, opts)
        counts = dict(newton=dc.newton_iterations - newton0, linear_solves=dc.linear_solves - solves0)
        if exc is not None:
            return Attempt(False, ContactStatus.NEWTON_FAILED, str(exc), **counts)
        return Attempt(bool(res.ok), res.status, res.message, outer=int(res.outer), value=res, **counts)

    def commit(t: float, att: Attempt, rec: StepRecord) -> FiniteFrictionStep:
        res = att.value
        step, full = _record(dc, res, t, mu, opts, rec.cutbacks, rec.newton_iterations, rec.seconds,
                             rec.linear_solves, fixed=data.fixed, load=data(t)[1])
        step = dataclasses.replace(step, requested=rec.requested)  # False: a sub-step of a cut-back
        records.append(step)
        state["last"] = full
        if step.status > 0:
            state["x"] = res.z
            state["y_prev"] = dc.surface_points(dc.expand(res.z))
            state["nu_prev"] = full["normals"].copy()
            state["lamN"], state["lamT"] = full["pressure"].copy(), full["traction_t"].copy()
            dc.accept(state["lamN"])
        return step

    run = step_through(times, attempt, commit, max_cutbacks=opts.max_cutbacks, factor=opts.cutback_factor,
                       on_step=on_step, before_step=progress, what="finite-deformation friction",
                       advice="use more load steps, a smaller penalty_scale or a smaller tangential_scale",
                       done_message="all load steps converged and verified")
    status, message, last, x = run.status, run.message, state["last"], state["x"]
    if last is None:
        u = dc.expand(x)
        g_all = dc.all_gaps(u)
        last = {"u": u, "pressure": np.zeros(m), "gap": g_all, "traction_t": np.zeros((m, d)),
                "normals": dc.normals.copy()}
    return FiniteFrictionSolution(
        u=last["u"], steps=tuple(records), status=status, message=message, pressure=last["pressure"],
        gap=last["gap"], traction_t=last["traction_t"], normals=last["normals"],
        extra={"h": dc.h, "weights": dc.weights.copy(), "points": dc.points.copy(), "eps_n": float(eps_n),
               # the automatic penalty's multiplier that ran (the algorithm's default or the user's; None: eps_n given)
               "penalty_scale": None if opts.eps_n is not None else float(opts.penalty_scale),
               "eps_t": float(eps_t), "mu": float(mu), "algorithm": algorithm, "penalty": pen_name,
               "dofs": int(problem.model.ndofs), "residual_log": dc.residual_log,
               "newton_total": int(dc.newton_iterations), "linear_solves": int(dc.linear_solves),
               "cutbacks": int(run.cutbacks), "total_s": time.perf_counter() - t_start,
               "linear_solver": dc.friction_solver.backend, "strategy": dc.strategy,
               "fallback_solves": int(dc.friction_solver.fallback_solves + dc.solver.fallback_solves),
               "krylov_iterations": int(dc.friction_solver.krylov_iterations + dc.solver.krylov_iterations),
               "linear_solve_s": float(dc.solve_seconds)})  # all Newton linear solves together


def _attempt(dc, data, step_fn, x, t, y_prev, nu_prev, lamN_all, lamT_all, mu, eps_n, eps_t, pen_name,
             opts):
    """One try of the step to ``t`` from ``x``: ``(step result, exception or None)``.

    The last tangential tractions (tangent to the obstacle at the normals ``nu_prev``) are
    transported into the tangent planes at the step's predictor
    (:func:`~alcontact.contact.obstacles.transport_tangent`) and start the step's multipliers.
    """
    try:
        fv, load, ob = data(t)
        dc.configure(fv, load, ob, x, predictor_stiffness=eps_n)
        dc.set_history(y_prev, mu, eps_t, opts.radius)
        nu_start = dc.obstacle.normal(dc.points + dc.expand(dc.x0)[dc.dofs])
        lamT_all = transport_tangent(lamT_all, nu_prev, nu_start)
        res = None
        for _ in range(8):
            cand = dc.cand
            dc.state_trace = []
            res = step_fn(_FiniteALCtx(dc, lamN_all[cand].copy(), lamT_all[cand].copy(), dc.x0, eps_n, opts),
                          pen_name)
            trace, dc.state_trace = dc.state_trace, None
            if not res.ok:
                break
            if res.last_state is not None and res.last_state.reversals is None:
                # the AL algorithms: reversals over the Newton iterates of all the step's subproblems, and the result
                trace.append(contact_states(res.last_state))
                res.last_state = dataclasses.replace(res.last_state, reversals=state_reversals(trace),
                                                     stick_slip_reversals=state_reversals(trace, among=(STICK, SLIP)))
            added = dc.extend(dc.all_gaps(dc.expand(res.z)), opts.tol_penetration * dc.h)
            if added.size == 0:
                break
            dc.x0 = res.z
        return res, None
    except InvertedElementError as exc:
        return None, exc


def _record(dc, res, t, mu, opts, cut, newton, seconds, solves=0, *, fixed, load):
    """Verified step record and the full-size fields of an accepted step."""
    m, d = dc.points.shape
    cand = dc.cand
    loc = res.last_state
    u = dc.expand(res.z)
    g_all = dc.all_gaps(u)
    pressure = np.zeros(m)
    traction_t = np.zeros((m, d))
    slip = np.zeros((m, d))
    states = np.full(m, OPEN)
    pressure[cand] = loc.tN
    traction_t[cand] = loc.tT
    slip[cand] = loc.slip
    states[cand] = loc.state
    w = dc.weights
    closed = pressure > 0
    # equilibrium of the step's displacement with the forces it reports (normal and tangential)
    problem = dc.problem
    forces = (w * pressure)[:, None] * dc.normals - w[:, None] * traction_t
    eq = state_equilibrium(problem.model, u, fixed, load, problem.slave_nodes()[1],
                           forces, dc.h, pressure=pressure, weights=w)
    check = check_state(g_all, pressure, dc.h, tol_penetration=opts.tol_penetration,
                        tol_complementarity=opts.tol_complementarity, traction_t=traction_t,
                        slip=np.where(closed[:, None], slip, 0.0), mu=mu,
                        tol_friction=max(opts.tol_multiplier, opts.tol_slip), equilibrium=eq.largest,
                        tol_equilibrium=equilibrium_tolerance(opts, multipliers=True), reach=reach(dc.points, u))
    status, message = verified_status(res.status, res.message, check,
                                      what=f"finite-deformation friction step to t={t:.6g}")
    tang = -np.sum(w[:, None] * traction_t, axis=0)
    force = np.sum((w * pressure)[:, None] * dc.normals, axis=0) + tang
    dissipation = float(np.sum(w * np.einsum("ij,ij->i", traction_t, slip)))
    rec = FiniteFrictionStep(
        t=float(t), status=status, newton_iterations=int(newton), outer_iterations=int(res.outer), cutbacks=cut,
        force=force, normal_force=float(np.sum(w * pressure)), tangential_force=tang, states=states,
        dissipation=dissipation, stored_energy=float(dc.body.energy(u)), offset=dc.offset.copy(), seconds=seconds,
        message=message, u=u, pressure=pressure, gap=g_all, traction_t=traction_t,
        slip=np.where(closed[:, None], slip, 0.0), normals=dc.normals.copy(), linear_solves=int(solves),
        state_reversals=loc.reversals, stick_slip_reversals=loc.stick_slip_reversals)
    full = {"u": u, "pressure": pressure, "gap": g_all, "traction_t": traction_t, "normals": dc.normals.copy()}
    return rec, full


register_friction_kinematics("finite", solve_finite_friction)
