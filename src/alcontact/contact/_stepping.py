r"""Load stepping: one driver (:func:`step_through`) and the finite-deformation solve :func:`solve_finite`.

Every stepped solve (:func:`solve_finite`, :func:`~alcontact.contact.solve_friction`,
:func:`~alcontact.contact.solve_finite_friction`) walks its step times with
:func:`step_through`: the solver gives an *attempt* callable (one try of the step to
``t`` from the last accepted state: predictor, candidate updates, the solve) and a
*commit* callable (accept the converged try, record the step). A failed try is cut
back: the increment is multiplied by ``factor`` (halved by default) and the failed
time is tried again once the smaller step is accepted; a failure at an increment of
``factor**max_cutbacks`` times the requested one ends the run with a negative
status, a logged warning and a message saying what to try. The accepted steps of all
three solves share one shape (:class:`StepRecords`, :class:`Frame`).

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
the frictionless algorithms of :mod:`alcontact.contact._algorithms` on the
finite-deformation problem :class:`~alcontact.contact._finite.FiniteContact`. A step
whose solve fails (negative status, an inverted element) is cut back as above. Every
accepted step is recorded (:class:`FiniteStep`).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from .._options import is_integer, is_real
from ..errors import ConvergenceError, InputError, InvertedElementError
from ..status import Status
from ._algorithms import ContactOptions, _Run, find_algorithm, options_with
from ._finite import FiniteContact
from ._loading import LoadHistory, component_fields
from ._solution import ContactResult, ContactSolution, ContactStatus
from ._verify import check_state, equilibrium_tolerance, reach, state_equilibrium, verified_status

__all__ = ["FiniteStep", "FiniteSolution", "solve_finite", "Frame", "StepRecords", "Attempt", "StepRecord",
           "SteppingResult", "step_through"]

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
    u : ndarray (ndofs,)
        Displacement at the end of the step.
    pressure, gap : ndarray (m,)
        Contact pressure and gap (current configuration) of every contact-boundary point.
    normal_force : float
        :math:`\\sum_i w_i t_{N,i}`.
    requested : bool
        ``t`` is a requested step time; ``False`` for a sub-step a cut-back inserted
        (the increment halved after a failed try).
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
    u: np.ndarray | None = None
    pressure: np.ndarray | None = None
    gap: np.ndarray | None = None
    normal_force: float = float("nan")
    requested: bool = True


@dataclass(frozen=True)
class Frame:
    r"""State of one accepted load step, the same shape for every stepped solve.

    Attributes
    ----------
    t : float
        Pseudo-time.
    u : ndarray (ndofs,)
        Displacement.
    pressure, gap : ndarray (m,)
        Normal traction :math:`t_N \ge 0` and gap (:math:`g \le 0`: no penetration) of every
        contact-boundary point.
    force : ndarray (d,)
        Resultant contact force on the body (normal and tangential parts).
    normal_force : float
        :math:`\sum_i w_i t_{N,i}`.
    tangential_force : ndarray (d,)
        Resultant friction force on the body (zeros without friction).
    newton_iterations, outer_iterations, cutbacks : int
        Counters of the step as its solver records them.
    seconds : float
        Wall time of the step (NaN where the solver does not time steps).
    slip : ndarray (m, d) or None
        Slip increment of the step (frictional solves).
    state : ndarray of int (m,) or None
        ``OPEN`` / ``STICK`` / ``SLIP`` (frictional solves, :mod:`alcontact.contact._friction_laws`).
    """

    t: float
    u: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    force: np.ndarray
    normal_force: float
    tangential_force: np.ndarray
    newton_iterations: int
    outer_iterations: int
    cutbacks: int
    seconds: float
    slip: np.ndarray | None = None
    state: np.ndarray | None = None


def frame_of(step) -> Frame:
    """The :class:`Frame` of a step record (:class:`FiniteStep`, ``FrictionStep``, ``FiniteFrictionStep``)."""
    force = np.asarray(step.force, dtype=float)
    tang = getattr(step, "tangential_force", None)
    return Frame(t=float(step.t), u=step.u, pressure=step.pressure, gap=step.gap, force=force,
                 normal_force=float(step.normal_force),
                 tangential_force=np.zeros_like(force) if tang is None else np.asarray(tang, dtype=float),
                 newton_iterations=int(step.newton_iterations), outer_iterations=int(step.outer_iterations),
                 cutbacks=int(step.cutbacks), seconds=float(getattr(step, "seconds", float("nan"))),
                 slip=getattr(step, "slip", None), state=getattr(step, "state", None))


class StepRecords:
    """Views on the per-step records ``steps`` and ``status`` of a load-stepped solution.

    Shared by :class:`FiniteSolution`, ``FiniteFrictionSolution`` and ``FrictionSolution``:
    every step record has ``t``, ``u``, ``pressure``, ``gap``, ``force``, ``normal_force``
    and the counters, so :attr:`frames` gives one :class:`Frame` per accepted step.
    """

    @property
    def success(self) -> bool:
        return self.status > 0

    def raise_for_status(self) -> None:
        """Raise :class:`~alcontact.errors.ConvergenceError` unless every step converged."""
        if not self.success:
            raise ConvergenceError(f"load-stepped contact solve failed ({self.status.label}): {self.message}")

    @property
    def times(self) -> np.ndarray:
        """Pseudo-time of every accepted step, in order: the requested step times *and* the sub-steps
        that cut-backs inserted (a failed step's increment halved, ``max_cutbacks`` times at most).

        :attr:`requested` marks which is which; :attr:`requested_times` keeps the requested ones.
        """
        return np.array([s.t for s in self.steps])

    @property
    def requested(self) -> np.ndarray:
        """Per accepted step: ``True`` at a requested step time, ``False`` at a cut-back sub-step."""
        return np.array([bool(getattr(s, "requested", True)) for s in self.steps], dtype=bool)

    @property
    def requested_times(self) -> np.ndarray:
        """The requested step times that were reached (:attr:`times` without the cut-back sub-steps)."""
        return self.times[self.requested] if self.steps else np.array([])

    @property
    def forces(self) -> np.ndarray:
        """Resultant contact force on the body per step, shape ``(steps, d)``."""
        return np.array([s.force for s in self.steps])

    @property
    def normal_forces(self) -> np.ndarray:
        """:math:`\\sum_i w_i t_{N,i}` per step."""
        return np.array([s.normal_force for s in self.steps])

    @property
    def tangential_forces(self) -> np.ndarray:
        """``(steps, d)`` resultants of the friction forces on the body (zeros without friction)."""
        out = [getattr(s, "tangential_force", None) for s in self.steps]
        out = [np.zeros_like(np.asarray(s.force, dtype=float)) if f is None else f for s, f in zip(self.steps, out)]
        return np.array(out, dtype=float).reshape(len(self.steps), -1)

    @property
    def step_newton_iterations(self) -> list[int]:
        """Newton iterations of every accepted step."""
        return [int(s.newton_iterations) for s in self.steps]

    @property
    def frames(self) -> tuple[Frame, ...]:
        """One :class:`Frame` per accepted step."""
        return tuple(frame_of(s) for s in self.steps)


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
        from .._options import require
        from ._problem import ContactProblem

        require("finite-deformation solve", "problem", problem, isinstance(problem, ContactProblem),
                "a ContactProblem (kinematics='finite')")
        require("finite-deformation solve", "history", history, history is None or isinstance(history, LoadHistory),
                "None or a LoadHistory")
        require("finite-deformation solve", "obstacle_path", obstacle_path, obstacle_path is None
                or callable(obstacle_path), "None or a callable t -> offset (or RigidMotion)")
        self.problem = problem
        self.history = history
        self.path = obstacle_path
        if history is not None:
            self.fixed, self.parts = component_fields(problem, history)
        else:
            self.fixed, vals = problem.dirichlet()
            self.parts = [(vals, problem.load_vector())]

    def __call__(self, t: float):
        from .obstacles import RigidMotion, move, translate

        if self.history is None:
            amps = np.array([t])
        else:
            amps = np.concatenate([[1.0], self.history.amplitudes(t)])
        fv = sum(a * p[0] for a, p in zip(amps, self.parts))
        load = sum(a * p[1] for a, p in zip(amps, self.parts))
        ob = self.problem.obstacle
        if self.path is not None:
            try:
                off = self.path(float(t))
                if isinstance(off, RigidMotion):  # rotation and translation
                    return np.asarray(fv, dtype=float), np.asarray(load, dtype=float), move(ob, off)
                off = np.asarray(off, dtype=float)
            except InputError:
                raise
            except Exception as exc:  # user callables may fail in any way
                raise InputError(f"obstacle_path failed at t={t:g}: {exc!r}; it must map t to a "
                                 "translation vector or an obstacles.RigidMotion") from exc
            if off.shape != (self.problem.model.dim,) or not np.all(np.isfinite(off)):
                raise InputError(f"obstacle_path({t:g}) must be a finite vector of length "
                                 f"{self.problem.model.dim}; got {off!r}")
            ob = translate(ob, off)
        return np.asarray(fv, dtype=float), np.asarray(load, dtype=float), ob


def _step_times(steps) -> tuple[float, ...]:
    if isinstance(steps, (int, np.integer)):
        return LoadHistory.uniform(int(steps))
    return LoadHistory.check_times(steps)


# ---------------------------------------------------------------------------
# the load-stepping driver (every stepped solve: solve_finite, solve_friction, solve_finite_friction)
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class Attempt:
    """Outcome of one try of a load step (what the ``attempt`` callable of :func:`step_through` returns).

    Attributes
    ----------
    ok : bool
        The step converged; :func:`step_through` then commits it.
    status : Status
        Negative when the try failed.
    message : str
        Why it failed (or the solver's message).
    newton, outer, linear_solves : int
        Counters of this try.
    value : object
        Whatever the ``commit`` callable needs (the solver's own state).
    final : bool
        A failure no smaller increment can cure (e.g. no static equilibrium): the run
        stops at once with ``status`` and ``message``, without cut-backs.
    """

    ok: bool
    status: Status = Status.CONVERGED
    message: str = ""
    newton: int = 0
    outer: int = 0
    linear_solves: int = 0
    value: Any = None
    final: bool = False


@dataclass(frozen=True)
class StepRecord:
    """What :func:`step_through` records of one accepted step.

    Attributes
    ----------
    t : float
        Pseudo-time reached.
    index : int
        0-based index of the requested step this step belongs to.
    requested : bool
        ``t`` is a requested step time (False for a sub-step inserted by a cut-back).
    newton_iterations, linear_solves : int
        Of every try since the last accepted step (failed tries included).
    outer_iterations : int
        Of the accepted try.
    cutbacks : int
        Failed tries since the last accepted step.
    step_cutbacks : int
        Failed tries of the requested step so far.
    seconds : float
        Wall time of the tries since the last accepted step.
    """

    t: float
    index: int
    requested: bool
    newton_iterations: int
    outer_iterations: int
    linear_solves: int
    cutbacks: int
    step_cutbacks: int
    seconds: float


@dataclass(frozen=True)
class SteppingResult:
    """Outcome of :func:`step_through`.

    Attributes
    ----------
    records : tuple of StepRecord
        Every accepted step, in order.
    status : Status
        ``CONVERGED`` when every requested step was reached, else the failure's (negative) status.
    message : str
        On failure: which step failed, why, and what to try.
    cutbacks : int
        Failed tries over the run (the one that ended it included).
    newton_iterations, outer_iterations, linear_solves : int
        Totals over every try.
    """

    records: tuple[StepRecord, ...]
    status: Status
    message: str
    cutbacks: int
    newton_iterations: int
    outer_iterations: int
    linear_solves: int

    @property
    def success(self) -> bool:
        return self.status > 0


def step_through(times: Sequence[float], attempt: Callable[[float], Attempt],
                 commit: Callable[[float, Attempt, StepRecord], Any], *, t0: float = 0.0, max_cutbacks: int = 6,
                 factor: float = 0.5, on_step: Callable[[Any], None] | None = None,
                 before_step: Callable[[int, float, int], None] | None = None,
                 recoverable: tuple[type[BaseException], ...] = (InvertedElementError,),
                 what: str = "load stepping", advice: str | Callable[[], str] = "use more load steps",
                 done_message: str = "all load steps converged") -> SteppingResult:
    r"""Walk the pseudo-times ``times`` from ``t0``, cutting failed steps back.

    Each step tries ``attempt(t)`` from the last committed state. A converged try is
    passed to ``commit(t, attempt, record)`` (which stores the state the next try
    starts from) and its return value to ``on_step``. A failed try is cut back: the
    increment from the last accepted time :math:`s` is reduced, :math:`t \leftarrow s +
    \text{factor}\,(t - s)`, and the failed time is tried again once the smaller step
    is accepted (a stack of targets). A failure at an increment of at most
    :math:`\text{factor}^{\text{max\_cutbacks}}` times the requested one ends the run
    with the try's negative status, a logged warning and a message naming the step,
    the reason and ``advice``.

    Parameters
    ----------
    times : sequence of float
        Increasing requested step times, all above ``t0``.
    attempt : callable ``t -> Attempt``
        One try of the step to ``t`` (predictors, candidate updates and the solve live here).
        Exceptions of the ``recoverable`` types count as a failed try (``NEWTON_FAILED``).
    commit : callable ``(t, attempt, record) -> step``
        Accepts the converged try. A returned object with a negative ``status`` (e.g. a
        step that fails its verification) ends the run with that status and its ``message``.
    t0 : float
        Pseudo-time of the starting state.
    max_cutbacks : int
        Reductions of a requested increment allowed (at most ``factor**-max_cutbacks``
        sub-steps per requested step).
    factor : float
        Fraction of the failed increment tried next (0.5: halving).
    on_step : callable ``step -> None``, optional
        Called with ``commit``'s return value after every accepted step.
    before_step : callable ``(k, t, n) -> None``, optional
        Called before requested step ``k`` (0-based) of ``n`` at time ``t`` (progress).
    what : str
        Name of the solve in the logged messages.
    advice : str or callable ``() -> str``
        What to try when a step fails at the smallest increment.
    done_message : str
        Message of a run whose every step converged.

    Returns
    -------
    SteppingResult
    """
    if not (is_integer(max_cutbacks) or (is_real(max_cutbacks) and float(max_cutbacks).is_integer())) \
            or not 0 <= max_cutbacks <= 60:
        raise InputError(f"max_cutbacks={max_cutbacks!r:.40} must be an integer in [0, 60] (halvings of a failed "
                         "step's increment); use e.g. max_cutbacks=6.")
    if not (on_step is None or callable(on_step)) or not (before_step is None or callable(before_step)):
        raise InputError(f"on_step = {(on_step if not callable(on_step) else before_step)!r:.40}: expected None or "
                         "a callable (called after each step).")
    if not (is_real(factor) and 0.0 < factor < 1.0):
        raise InputError(f"cutback_factor={factor!r} must be in (0, 1); use 0.5 (halving).")
    records: list[StepRecord] = []
    status, message = Status.CONVERGED, done_message
    n_cut = n_newton = n_outer = n_solves = 0
    t_prev = float(t0)
    times = [float(t) for t in times]
    for k, t_req in enumerate(times):
        if before_step is not None:
            before_step(k, t_req, len(times))
        smallest = (t_req - t_prev) * float(factor) ** int(max_cutbacks) * (1.0 + 1e-9)
        queue = [t_req]
        step_cuts = cuts = newton = solves = 0
        t_start = time.perf_counter()
        while queue:
            t = queue[-1]
            try:
                att = attempt(t)
            except recoverable as exc:
                att = Attempt(False, Status.NEWTON_FAILED, str(exc))
            newton += att.newton
            solves += att.linear_solves
            n_newton += att.newton
            n_outer += att.outer
            n_solves += att.linear_solves
            if att.ok:
                rec = StepRecord(float(t), k, len(queue) == 1, newton, int(att.outer), solves, cuts, step_cuts,
                                 time.perf_counter() - t_start)
                records.append(rec)
                step = commit(t, att, rec)
                logger.info("%s: step t=%.6g accepted (%d Newton, %d outer, %d cut-backs)", what, t, newton,
                            att.outer, cuts)
                if on_step is not None:
                    on_step(step)
                st = getattr(step, "status", None)
                if st is not None and st < 0:
                    status, message = st, step.message
                    break
                queue.pop()
                t_prev = float(t)
                cuts = newton = solves = 0
                t_start = time.perf_counter()
                continue
            st = att.status if att.status < 0 else Status.NEWTON_FAILED
            if att.final:
                status, message = st, att.message
                break
            n_cut += 1
            cuts += 1
            step_cuts += 1
            dt = t - t_prev
            reason = f"{st.label}: {att.message}" if att.message else st.label
            if dt <= smallest:
                tip = advice() if callable(advice) else advice
                status = st
                message = (f"load step to t={t:.6g} failed at the smallest increment {dt:.3g} ({int(max_cutbacks)} "
                           f"cut-backs allowed; {reason}); {tip}")
                break
            queue.append(t_prev + float(factor) * dt)
            logger.info("%s: step to t=%.6g failed (%s); cutting back to t=%.6g", what, t, reason, queue[-1])
        if status < 0:
            logger.warning("%s failed (%s): %s", what, status.label, message)
            break
    return SteppingResult(tuple(records), status, message, n_cut, n_newton, n_outer, n_solves)


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
    from ._finite_iterative import finite_solver
    from ._stiffness import penalty_stiffness

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
                          gap=gap, normal_force=float(np.sum(dc.weights * pressure)), requested=rec.requested)
        records.append(step)
        state["last"] = (out, u)
        return step

    hook = None if on_step is None else (lambda st: on_step(st, st.u.copy(), st.pressure.copy()))
    run_ = step_through(times, attempt, commit, max_cutbacks=max_cutbacks, on_step=hook,
                        what="finite-deformation contact",
                        advice="use more load steps, a smaller penalty_scale or algorithm='ssn'")
    status, message, last, x = run_.status, run_.message, state["last"], state["x"]
    if last is None:
        out, u = _Run(x, np.zeros(dc.cand.size), dc.gaps(x), status, message, 0, 0, eps0, np.inf, []), dc.expand(x)
    else:
        out, u = last
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
    from .. import penalties as _pen
    from ._laws import make_law

    law = make_law(_pen.make("rockafellar"), np.ones(0))
    out = dc.subproblem(law, np.zeros(0), dc.start(), tol=opts.newton_tol, maxiter=opts.maxiter_newton)
    st = ContactStatus.CONVERGED if out.converged else ContactStatus.NEWTON_FAILED
    return _Run(out.state, np.zeros(0), out.g, st, "no contact in this step" if out.converged else out.message,
                0, out.iterations, 0.0, out.residual, [])


def _force(dc, out, u, *, balanced: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Resultant contact force and pressures (all points) of a converged step (``balanced``: the
    pressures of :func:`_applied_pressure`, else the algorithm's tractions)."""
    dc.all_gaps(u)  # the normals at the current configuration
    p = np.zeros(dc.points.shape[0])
    if out.lam.size:
        p[dc.cand] = np.maximum(_applied_pressure(dc, out.lam, u) if balanced else out.lam, 0.0)
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
    <alcontact.contact._discrete.DiscreteContact.applied_pressure>`). The residual left on
    the other free DOFs (tangential components at the contact points, the interior) is what
    the ``equilibrium`` measure of :mod:`alcontact.contact._verify` checks. Points with
    :math:`\lambda_i \le 0`, or without a free DOF, keep :math:`\lambda_i`.
    """
    lam = np.asarray(lam, dtype=float)
    cand = dc.cand
    if lam.size != cand.size or not np.any(lam > 0):
        return lam
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


def _check(problem, dc, out, u, opts, *, fixed, load):
    """``(check, pressures, gaps)`` of a returned state (all contact points): every measure of
    :mod:`alcontact.contact._verify`, equilibrium of ``u`` with the reported forces (loads ``load``) included."""
    g_all = dc.all_gaps(u)
    pressure = np.zeros(dc.points.shape[0])
    try:
        if out.lam.size:
            pressure[dc.cand] = _applied_pressure(dc, out.lam, u)
        nodal = dc.weights * np.maximum(pressure, 0.0)
        residual = state_equilibrium(problem.model, u, fixed, load, dc.dofs, nodal[:, None] * dc.normals,
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
    """Lowest Newton tolerance of the model's linear-solver path (AMG + CG: ``_NEWTON_TOL_FLOOR``)."""
    from ._finite_iterative import AMGNewtonSolver
    from ._iterative import _NEWTON_TOL_FLOOR

    return _NEWTON_TOL_FLOOR if isinstance(getattr(dc, "solver", None), AMGNewtonSolver) else 0.0


def _solution(problem, dc, out, u, algorithm, pen_name, opts, status, message, records, t_start, *, fixed, load):
    # the one place a finite-deformation result is built: a "converged" state must pass the tolerances,
    # equilibrium of the returned displacement with the returned forces (loads of the last step) included
    check, pressure, g_all = _check(problem, dc, out, u, opts, fixed=fixed, load=load)
    nodal = dc.weights * np.maximum(pressure, 0.0)
    status, message = verified_status(status if status < 0 else out.status, message, check,
                                      what=f"finite-deformation contact solve {algorithm}")
    pressure = np.maximum(pressure, 0.0)
    force = np.sum(nodal[:, None] * dc.normals, axis=0)
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
               "steps": len(records), **dc.extra()},
    )
