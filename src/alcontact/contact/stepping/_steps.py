"""Load stepping: one driver, :func:`step_through`, for every stepped solve.

Every stepped solve (:func:`~alcontact.contact.solve_finite`, :func:`~alcontact.contact.solve_friction`,
:func:`~alcontact.contact.solve_finite_friction`) walks its step times with
:func:`step_through`: the solver gives an *attempt* callable (one try of the step to
``t`` from the last accepted state: predictor, candidate updates, the solve) and a
*commit* callable (accept the converged try, record the step). A failed try is cut
back: the increment is multiplied by ``factor`` (halved by default) and the failed
time is tried again once the smaller step is accepted; a failure at an increment of
``factor**max_cutbacks`` times the requested one ends the run with a negative
status, a logged warning and a message saying what to try. The accepted steps of all
three solves share one shape (:class:`StepRecords`, :class:`Frame`).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from ..._options import is_integer, is_real
from ...errors import InputError, InvertedElementError
from ...status import Status
from ..problem._loading import LoadHistory, component_fields


logger = logging.getLogger(__name__)


class _StepData:
    """Prescribed values, loads and obstacle of the problem at pseudo-time ``t``."""

    def __init__(self, problem, history: LoadHistory | None, obstacle_path):
        from ..._options import require
        from ..problem._problem import ContactProblem

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
        from ..masters.obstacles import RigidMotion, move, translate

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
