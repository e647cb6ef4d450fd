r"""Load stepping for finite-deformation contact (:func:`solve_finite`).

The loads are applied over a pseudo-time :math:`t \in (0, 1]` in steps
:math:`t_1 < \dots < t_N`. At step time :math:`t`

- without a :class:`~alcontact.contact.LoadHistory`, every support value and load of
  the problem is scaled by :math:`t` (proportional loading);
- with one, the problem's own supports and loads are applied fully and each
  :class:`~alcontact.contact.LoadCase` is scaled by its amplitude :math:`a_k(t)`;
- the obstacle is translated by ``obstacle_path(t)`` (a vector; default no motion),
  a rigid motion along a prescribed path (:func:`~alcontact.contact.obstacles.translate`).

Each step starts from the last converged displacement (warm start) and runs one of
the frictionless algorithms of :mod:`alcontact.contact._algorithms` on the
finite-deformation problem :class:`~alcontact.contact._finite.FiniteContact`. A step
whose solve fails (negative status, an inverted element) is cut back: the increment
is halved, up to ``max_cutbacks`` times in a row, and the remaining interval is then
walked with the smaller increments. Every accepted step is recorded
(:class:`FiniteStep`).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import InputError, InvertedElementError
from ._algorithms import ContactOptions, _Run, get_algorithm, options_with, resolve_penalty
from ._finite import FiniteContact
from ._loading import LoadHistory, component_fields
from ._solution import ContactResult, ContactSolution, ContactStatus
from ._verify import check_state, verified_status

__all__ = ["FiniteStep", "FiniteSolution", "solve_finite"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class FiniteStep:
    """One accepted load step.

    Attributes
    ----------
    t : float
        Pseudo-time of the step.
    status : ContactStatus
    newton_iterations : int
        Newton iterations of this step (all subproblems and active-set steps, the
        failed attempts of cut-backs included).
    outer_iterations : int
        Outer (multiplier / active-set) iterations of the accepted attempt.
    linear_solves : int
        Newton systems solved in this step.
    force : ndarray (d,)
        Resultant contact force on the body :math:`\\sum_i w_i t_{N,i}\\,\\nu_i`.
    cutbacks : int
        Halvings of the increment needed before this step was accepted.
    seconds : float
        Wall time of the step (failed attempts included).
    message : str
    """

    t: float
    status: ContactStatus
    newton_iterations: int
    outer_iterations: int
    linear_solves: int
    force: np.ndarray
    cutbacks: int
    seconds: float
    message: str


class StepRecords:
    """Views on the per-step records ``steps`` (each with ``t`` and ``force``) and ``status``
    of a load-stepped solution (frictionless and frictional finite deformation)."""

    @property
    def success(self) -> bool:
        return self.status > 0

    @property
    def times(self) -> np.ndarray:
        return np.array([s.t for s in self.steps])

    @property
    def forces(self) -> np.ndarray:
        """Resultant contact force on the body per step, shape ``(steps, d)``."""
        return np.array([s.force for s in self.steps])


@dataclass(frozen=True)
class FiniteSolution(StepRecords):
    """Outcome of a load-stepped finite-deformation contact solve.

    Attributes
    ----------
    solution : ContactSolution
        State of the last accepted step (displacement, pressures, gaps at the
        current configuration, normals at the current projections).
    steps : tuple of FiniteStep
    status : ContactStatus
        ``CONVERGED`` when every step was reached, else the status of the failed step.
    message : str
    extra : dict
        ``h``, ``dofs`` and ``residual_log`` (relative residuals of every Newton solve,
        :attr:`FiniteContact.residual_log <alcontact.contact._finite.FiniteContact>`).
    """

    solution: ContactSolution
    steps: tuple[FiniteStep, ...]
    status: ContactStatus
    message: str
    extra: dict = field(default_factory=dict)

    @property
    def u(self) -> np.ndarray:
        return self.solution.u

    def raise_for_status(self) -> None:
        self.solution.result.raise_for_status()


class _StepData:
    """Prescribed values, loads and obstacle of the problem at pseudo-time ``t``."""

    def __init__(self, problem, history: LoadHistory | None, obstacle_path):
        self.problem = problem
        self.history = history
        self.path = obstacle_path
        if history is not None:
            self.fixed, self.parts = component_fields(problem, history)
        else:
            self.fixed, vals = problem.dirichlet()
            self.parts = [(vals, problem.load_vector())]

    def __call__(self, t: float):
        from .obstacles import translate

        if self.history is None:
            amps = np.array([t])
        else:
            amps = np.concatenate([[1.0], self.history.amplitudes(t)])
        fv = sum(a * p[0] for a, p in zip(amps, self.parts))
        load = sum(a * p[1] for a, p in zip(amps, self.parts))
        ob = self.problem.obstacle
        if self.path is not None:
            try:
                off = np.asarray(self.path(float(t)), dtype=float)
            except Exception as exc:  # user callables may fail in any way
                raise InputError(f"obstacle_path failed at t={t:g}: {exc!r}; it must map t to a "
                                 "translation vector") from exc
            if off.shape != (self.problem.model.dim,) or not np.all(np.isfinite(off)):
                raise InputError(f"obstacle_path({t:g}) must be a finite vector of length "
                                 f"{self.problem.model.dim}; got {off!r}")
            ob = translate(ob, off)
        return np.asarray(fv, dtype=float), np.asarray(load, dtype=float), ob


def _step_times(steps) -> tuple[float, ...]:
    if isinstance(steps, (int, np.integer)):
        return LoadHistory.uniform(int(steps))
    return LoadHistory.check_times(steps)


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
    obstacle_path : callable ``t -> (d,)``, optional
        Translation of the obstacle at pseudo-time ``t``.
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
    from ._solve import DEFAULT_PENALTY, penalty_stiffness

    t_start = time.perf_counter()
    run = get_algorithm(algorithm)
    pen_name = resolve_penalty(algorithm, penalty, DEFAULT_PENALTY)
    opts = options_with(options, ContactOptions, option_overrides, "contact")
    if int(max_cutbacks) < 0:
        raise InputError(f"max_cutbacks={max_cutbacks!r} must be >= 0.")
    times = _step_times(steps)
    data = _StepData(problem, history, obstacle_path)
    dc = FiniteContact(problem, fixed=data.fixed)
    eps0 = opts.eps_n if opts.eps_n is not None else penalty_stiffness(problem.model, dc.h, opts.penalty_scale)
    x = np.zeros(dc.free.size)
    dc.configure(*data(0.0), x)  # the undeformed state belongs to t = 0
    dc.accept(np.zeros(dc.points.shape[0]))
    t_prev = 0.0
    records: list[FiniteStep] = []
    status, message = ContactStatus.CONVERGED, "all load steps converged"
    last = None
    queue = list(times)
    level = 0  # halvings of the nominal increment of the current step interval
    nominal = None
    while queue:
        t_target = queue[0]
        if nominal is None:
            nominal = t_target - t_prev
        cut = 0
        dt = min(t_target - t_prev, nominal * 0.5**level)
        newton0, solves0 = dc.newton_iterations, dc.linear_solves
        t0 = time.perf_counter()
        while True:
            t = t_prev + dt if t_prev + dt < t_target - 1e-14 * max(1.0, t_target) else t_target
            out, u, exc = _attempt(dc, data, run, opts, eps0, pen_name, x, t)
            if exc is None and out.status > 0:
                break
            reason = str(exc) if exc is not None else f"{out.status.label}: {out.message}"
            if level >= max_cutbacks:
                status = out.status if (exc is None and out.status < 0) else ContactStatus.NEWTON_FAILED
                message = (f"load step to t={t:.6g} failed at the smallest increment {dt:.3g} ({max_cutbacks} "
                           f"halvings; {reason}); use more load "
                           "steps, a smaller penalty_scale or algorithm='ssn'")
                logger.warning("finite-deformation contact: %s", message)
                break
            cut += 1
            level += 1
            dt = min(t_target - t_prev, nominal * 0.5**level)
            logger.info("load step to t=%.6g failed (%s); cutting back to dt=%.3g", t, reason, dt)
        if status < 0:
            break
        x = out.r.copy()
        force, pressure = _force(dc, out, u)
        dc.accept(pressure)
        records.append(FiniteStep(t, out.status, dc.newton_iterations - newton0, int(out.outer),
                                  dc.linear_solves - solves0, force, cut, time.perf_counter() - t0, out.message))
        logger.info("load step t=%.6g: %d Newton, %d outer, force %s", t, records[-1].newton_iterations,
                    out.outer, np.array2string(force, precision=6))
        if on_step is not None:
            on_step(records[-1], u.copy(), pressure.copy())
        last = (out, u)
        t_prev = t
        if t >= t_target - 1e-14 * max(1.0, t_target):
            queue.pop(0)
            level, nominal = 0, None  # the next step interval starts at its full increment
    if last is None:
        out, u = _Run(x, np.zeros(dc.cand.size), dc.gaps(x), status, message, 0, 0, eps0, np.inf, []), dc.expand(x)
    else:
        out, u = last
    sol = _solution(problem, dc, out, u, algorithm, pen_name, opts, status, message, records, t_start)
    return FiniteSolution(sol, tuple(records), status, message,
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
    from .. import penalties as _pen
    from ._laws import make_law

    law = make_law(_pen.make("rockafellar"), np.ones(0))
    out = dc.subproblem(law, np.zeros(0), dc.start(), tol=opts.newton_tol, maxiter=opts.maxiter_newton)
    st = ContactStatus.CONVERGED if out.converged else ContactStatus.NEWTON_FAILED
    return _Run(out.state, np.zeros(0), out.g, st, "no contact in this step" if out.converged else out.message,
                0, out.iterations, 0.0, out.residual, [])


def _force(dc, out, u) -> tuple[np.ndarray, np.ndarray]:
    """Resultant contact force and pressures (all points) of a converged step."""
    dc.all_gaps(u)  # the normals at the current configuration
    p = np.zeros(dc.points.shape[0])
    if out.lam.size:
        p[dc.cand] = np.maximum(out.lam, 0.0)
    return np.sum((dc.weights * p)[:, None] * dc.normals, axis=0), p


def _solution(problem, dc, out, u, algorithm, pen_name, opts, status, message, records, t_start):
    g_all = dc.all_gaps(u)
    m = dc.points.shape[0]
    pressure = np.zeros(m)
    if out.lam.size:
        pressure[dc.cand] = out.lam
    # the one place a finite-deformation result is built: a "converged" state must pass the tolerances
    check = check_state(g_all, pressure, dc.h, tol_penetration=opts.tol_penetration,
                        tol_complementarity=opts.tol_complementarity)
    status, message = verified_status(status if status < 0 else out.status, message, check,
                                      what=f"finite-deformation contact solve {algorithm}")
    pressure = np.maximum(pressure, 0.0)
    nodal = dc.weights * pressure
    force = np.sum(nodal[:, None] * dc.normals, axis=0)
    closed = g_all > -max(1e-6, 10 * opts.tol_penetration) * dc.h
    active = closed & (pressure > 1e-12 * max(float(pressure.max(initial=0.0)), 1e-300))
    pen_final = float(np.max(g_all, initial=0.0)) / dc.h
    pref = max(float(pressure.max(initial=0.0)), 1e-300)
    compl = float(np.max(np.abs(pressure * g_all), initial=0.0)) / (pref * dc.h)
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
               "steps": len(records), **dc.extra()},
    )
