r"""One globalized Newton method for every Newton solve of the package.

:func:`newton` solves a system :math:`F(x) = 0`; it serves the contact algorithms
(every inner solve of Algorithms 6.1-6.4, their full-space and finite-deformation
forms and the semi-smooth Newton references: :mod:`alcontact.contact`) and the
hyperelastic body's own load-stepped solves (:meth:`alcontact.fem.Hyperelastic.solve`).
It lives in :mod:`alcontact.optim` so that both :mod:`alcontact.fem` and
:mod:`alcontact.contact` use it with imports that run one way. A problem is a
:class:`NewtonSystem` that supplies what differs:

``evaluate(x)``
    The state at ``x`` (residual, energy, tractions ...); raises one of
    ``domain_errors`` where ``x`` lies outside the domain (an inverted element):
    the line search then halves the step.
``residual(state)``, ``measure(state)``
    :math:`F` and the relative residual tested against the tolerance.
``step(x, state, history)``
    The Newton correction: the caller's linear solve (dense, CG with a forcing
    term, :class:`~alcontact.linalg.SequenceSolver`, the unsymmetric friction
    Jacobian). :class:`numpy.linalg.LinAlgError` or ``ValueError`` mean a singular
    matrix.
``merit(state)``, ``slope(x, state, dx)``
    The merit function of the Armijo line search (the potential energy :math:`\Pi`
    where the problem has one, else e.g. :math:`\tfrac12|F|^2`) and its directional
    derivative along ``dx``.
``tolerance``, ``stall_level``, ``negligible``, ``interrupt``
    Hooks with neutral defaults: the round-off bound of the residual (raises the
    tolerance), the level below which a stalled residual counts as converged, a
    correction at round-off level, and a stop after an accepted step (the
    semi-smooth active-set switch).

The line search (:class:`LineSearch`) halves the step until a trial is accepted by
one of its tests: Armijo on the merit, :math:`|F_{try}| \le (1 - c\alpha)|F|`, a
decrease of the measured residual, or a step below ``accept_below``; when the merit
is flat to round-off, the full step is taken if it reduces :math:`\max|F|`.
Where :attr:`NewtonSettings.stall_on_failed_search` is set, a line search that fails at a
residual below the stall level (the round-off floor the system declares) ends the
iteration as converged, as the stall test does: no step lowers a residual made of round-off.

Every outcome carries a :class:`~alcontact.status.Status` (``CONVERGED``,
``MAXITER``, ``LINE_SEARCH_FAILED``, ``NONFINITE``, ``NEWTON_FAILED``) and a message
for people; callers test the status. The history records the relative residual of
every iterate and the step length taken from it (the quadratic-rate tests read it).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..status import Status

__all__ = ["LineSearch", "NewtonSettings", "NewtonSystem", "NewtonRecord", "NewtonResult", "newton",
           "inner_failure"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class LineSearch:
    """Backtracking of :func:`newton`: the tests that accept a trial step (any one suffices).

    Attributes
    ----------
    halvings : int
        Trials (step lengths 1, 1/2, 1/4, ...) before the line search gives up.
    armijo : float
        Sufficient-decrease constant :math:`c` of every test.
    merit : bool
        Armijo on the problem's merit:
        :math:`m(x + \\alpha d) \\le m(x) + c\\,\\alpha \\min(m'(x; d), 0) + 10^{-14}|m(x)|`
        (the last term admits round-off of the merit).
    residual_decrease : bool
        Accept :math:`\\|F(x + \\alpha d)\\|_2 \\le (1 - c\\alpha)\\|F(x)\\|_2` (near the solution
        the energy decrease drowns in its round-off; or no merit at all).
    residual_merit_slack : float
        With ``merit`` on, the residual test accepts a step only where the merit rose by at most this
        fraction of :math:`|m(x)|` (its round-off): two acceptance tests that each allow an increase
        of the other's measure let the iterates cycle (a penalty subproblem whose active set changes
        every iteration went 60 iterations without converging; finite-deformation ironing, issue 18).
        ``inf``: no limit.
    measure_decrease : bool
        Accept a relative residual (``measure``) below :math:`(1 - c\\alpha)` times the current one.
    accept_below : float
        Accept any trial inside the domain once :math:`\\alpha` is below this (0: never).
    full_step : bool
        When no trial is accepted (the merit is flat to round-off), take the full step if it
        reduces :math:`\\max|F|`.
    """

    halvings: int = 60
    armijo: float = 1e-4
    merit: bool = True
    residual_decrease: bool = False
    residual_merit_slack: float = np.inf
    measure_decrease: bool = False
    accept_below: float = 0.0
    full_step: bool = True


@dataclass(frozen=True)
class NewtonSettings:
    """Settings of :func:`newton` besides the tolerance and the iteration limit.

    Attributes
    ----------
    line_search : LineSearch
    stall : float
        A residual below this level (or the problem's :meth:`NewtonSystem.stall_level`) that
        dropped by less than half counts as converged: the round-off floor of the system
        (0 switches the test off).
    stall_from : int
        Measured iterates (the start included) before the stall test applies.
    negligible_tol : float
        A correction at round-off level (:meth:`NewtonSystem.negligible`) ends the iteration;
        converged when the residual is below ``negligible_tol`` times the tolerance.
    stall_on_failed_search : bool
        A failed line search at a residual below the stall level counts as converged (from any
        iterate, the start included): no trial step, the full one included, lowers a residual
        that is round-off. Off: the failure is reported (the caller cuts back).
    """

    line_search: LineSearch = LineSearch()
    stall: float = 1e-8
    stall_from: int = 2
    negligible_tol: float = np.inf
    stall_on_failed_search: bool = False


class NewtonSystem:
    """A system :math:`F(x) = 0` solved by :func:`newton` (module doc); override what differs.

    ``evaluate``, ``residual``, ``measure`` and ``step`` are required; the other methods
    have neutral defaults.
    """

    #: exceptions of :meth:`evaluate` meaning "outside the domain": the line search halves the step
    domain_errors: tuple[type[BaseException], ...] = ()

    def evaluate(self, x: np.ndarray) -> Any:
        """State at ``x`` (anything :meth:`residual` and :meth:`measure` read)."""
        raise TypeError(f"{type(self).__name__} must define evaluate(x)")

    def residual(self, state) -> np.ndarray:
        """The residual :math:`F` of ``state``."""
        raise TypeError(f"{type(self).__name__} must define residual(state)")

    def measure(self, state) -> float:
        """Relative residual of ``state``, compared with the tolerance."""
        raise TypeError(f"{type(self).__name__} must define measure(state)")

    def step(self, x: np.ndarray, state, history: list) -> np.ndarray:
        """Newton correction at ``x`` (``history``: the :class:`NewtonRecord` of every iterate so far)."""
        raise TypeError(f"{type(self).__name__} must define step(x, state, history)")

    def merit(self, state) -> float:
        """Merit of the Armijo test (``+inf`` outside a barrier's domain)."""
        return 0.5 * float(np.dot(self.residual(state), self.residual(state)))

    def merit_change(self, state, trial, merit: float, trial_merit: float) -> float:
        """:meth:`merit` at ``trial`` minus at ``state`` (default: the difference of the two values). A
        merit summed from large terms that cancel can give the change in a form that does not subtract
        them (the round-off of each value can exceed the change a Newton step brings)."""
        return trial_merit - merit

    def slope(self, x: np.ndarray, state, dx: np.ndarray) -> float:
        """Directional derivative of :meth:`merit` at ``x`` along ``dx`` (default: that of ``|F|^2/2``
        along a Newton direction)."""
        F = self.residual(state)
        return -float(F @ F)

    def inside(self, state) -> bool:
        """Whether the starting state lies in the domain (default: a finite merit)."""
        return bool(np.isfinite(self.merit(state)))

    def tolerance(self, state, tol: float) -> float:
        """Tolerance of this iterate: ``tol``, or the residual's round-off bound where that is larger."""
        return tol

    def stall_level(self, state, level: float) -> float:
        """Residual level below which a stall counts as converged (``level``: the settings' one)."""
        return level

    def negligible(self, x: np.ndarray, state, dx: np.ndarray) -> bool:
        """Whether the correction ``dx`` is at round-off level (the residual cannot drop further)."""
        return False

    def interrupt(self, x: np.ndarray, state, alpha: float) -> str | None:
        """After an accepted step: a reason to stop here (``NEWTON_FAILED``, not converged), or ``None``."""
        return None


@dataclass
class NewtonRecord:
    """One iterate of :func:`newton`: its relative residual and the step length taken from it.

    ``step`` is ``nan`` for the last iterate; ``full_step`` marks a full step taken because
    the merit was flat to round-off.
    """

    residual: float
    step: float = np.nan
    full_step: bool = False


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`newton`.

    Attributes
    ----------
    x : ndarray
        Last iterate.
    state
        The problem's state at ``x`` (:meth:`NewtonSystem.evaluate`).
    status : Status
        ``CONVERGED``; ``MAXITER``; ``LINE_SEARCH_FAILED``; ``NONFINITE`` (NaN/inf residual or
        merit at the start); ``NEWTON_FAILED`` (singular or non-finite Newton step, start outside
        the domain, stall above the tolerance, or stopped by :meth:`NewtonSystem.interrupt`).
    message : str
        For people; never compared by callers.
    iterations : int
        Newton corrections computed (linear solves).
    residual : float
        Relative residual of ``x``.
    history : tuple of NewtonRecord
    """

    x: np.ndarray
    state: Any
    status: Status
    message: str
    iterations: int
    residual: float
    history: tuple = ()

    @property
    def converged(self) -> bool:
        return self.status.success

    @property
    def residuals(self) -> list[float]:
        """Relative residual of every iterate."""
        return [rec.residual for rec in self.history]


def _norm(v) -> float:
    """Euclidean norm; a far-away trial may overflow to ``inf`` (then rejected)."""
    with np.errstate(over="ignore"):
        return float(np.linalg.norm(v))


def _finite(v) -> bool:
    return bool(np.all(np.isfinite(v)))


def newton(system: NewtonSystem, x0, *, tol: float, maxiter: int, settings: NewtonSettings = NewtonSettings(),
           log: list | None = None) -> NewtonResult:
    """Solve ``F(x) = 0`` by globalized Newton (module doc).

    Parameters
    ----------
    system : NewtonSystem
    x0 : ndarray
        Start; a domain error of :meth:`NewtonSystem.evaluate` there propagates to the caller.
    tol : float
        Relative residual (:meth:`NewtonSystem.measure`) of convergence.
    maxiter : int
        Newton corrections at most.
    settings : NewtonSettings
    log : list, optional
        The relative residual of every iterate is appended here as it is measured.

    Returns
    -------
    NewtonResult
    """
    ls = settings.line_search
    x = np.array(x0, dtype=float)
    state = system.evaluate(x)
    F = system.residual(state)
    history: list[NewtonRecord] = []

    def done(status, message, iterations, res):
        if not status.success:  # the callers decide (cut-back, fallback) and warn
            logger.debug("Newton stopped (%s) after %d iterations: %s", status.label, iterations, message)
        return NewtonResult(x, state, status, message, iterations, res, tuple(history))

    merit = system.merit(state) if ls.merit else 0.0
    if np.any(np.isnan(F)) or np.isnan(merit):
        return done(Status.NONFINITE, "the residual or merit is NaN at the start", 0, np.nan)
    if ls.merit and not system.inside(state):
        return done(Status.NEWTON_FAILED, "start outside the domain (e.g. of a barrier penalty)", 0, np.inf)
    if not _finite(F):
        return done(Status.NONFINITE, "non-finite residual at the start", 0, np.inf)
    prev = np.inf
    res = np.inf
    for it in range(maxiter + 1):  # it: corrections computed so far
        res = system.measure(state)
        history.append(NewtonRecord(res))
        if log is not None:
            log.append(res)
        if res <= system.tolerance(state, tol):
            return done(Status.CONVERGED, "converged", it, res)
        if it == maxiter:
            break
        if (len(history) >= settings.stall_from and res <= system.stall_level(state, settings.stall)
                and res > 0.5 * prev):
            return done(Status.CONVERGED, "converged (residual at round-off level)", it, res)
        prev = res
        try:
            dx = system.step(x, state, history)
        except (np.linalg.LinAlgError, ValueError):
            return done(Status.NEWTON_FAILED, "singular Newton matrix", it + 1, res)
        if not _finite(dx):
            return done(Status.NEWTON_FAILED, "non-finite Newton step", it + 1, res)
        if system.negligible(x, state, dx):
            if res <= settings.negligible_tol * tol:
                return done(Status.CONVERGED, "converged (step at round-off level)", it + 1, res)
            return done(Status.NEWTON_FAILED, f"step at round-off level with residual {res:.2e}", it + 1, res)
        trial, alpha, full, why = _line_search(system, ls, x, state, F, merit, res, dx)
        if trial is None:
            if settings.stall_on_failed_search and res <= system.stall_level(state, settings.stall):
                # no trial step decreases a residual already at the round-off level (the stall test's)
                return done(Status.CONVERGED, f"converged (residual at round-off level; {why})", it, res)
            return done(Status.LINE_SEARCH_FAILED, why, it + 1, res)
        history[-1].step = alpha
        history[-1].full_step = full
        logger.debug("Newton %d: residual %.2e, step %.3g", it + 1, res, alpha)
        x = x + alpha * dx
        state = trial
        F = system.residual(state)
        merit = system.merit(state) if ls.merit else 0.0
        stop = system.interrupt(x, state, alpha)
        if stop is not None:
            return done(Status.NEWTON_FAILED, stop, it + 1, system.measure(state))
    return done(Status.MAXITER, f"maximum Newton iterations ({maxiter}); relative residual {res:.2e}", maxiter, res)


def _line_search(system, ls: LineSearch, x, state, F, merit, res, dx):
    """``(trial state, step length, full step taken on a flat merit, "")``, or ``(None, 0, False, why not)``."""
    slope = min(system.slope(x, state, dx), 0.0) if ls.merit else 0.0
    nF = _norm(F) if ls.residual_decrease else 0.0
    alpha = 1.0
    for _ in range(ls.halvings):
        try:
            trial = system.evaluate(x + alpha * dx)
        except system.domain_errors:
            alpha *= 0.5
            continue
        if _accepts(system, ls, state, trial, alpha, res, merit, slope, nF):
            return trial, alpha, False, ""
        alpha *= 0.5
    why = f"line search failed (relative residual {res:.2e})"
    if not ls.full_step:
        return None, 0.0, False, why
    try:
        trial = system.evaluate(x + dx)
    except system.domain_errors:
        return None, 0.0, False, "line search failed (every trial step leaves the domain)"
    F_try = system.residual(trial)
    ok = _finite(F_try) and (not ls.merit or np.isfinite(system.merit(trial)))
    if ok and np.max(np.abs(F_try), initial=0.0) < np.max(np.abs(F), initial=0.0):
        return trial, 1.0, True, ""
    return None, 0.0, False, why


def _accepts(system, ls: LineSearch, state, trial, alpha, res, merit, slope, nF) -> bool:
    """Whether one test of :class:`LineSearch` accepts the trial state at step length ``alpha``."""
    if ls.measure_decrease and system.measure(trial) < (1 - ls.armijo * alpha) * res:
        return True
    if alpha < ls.accept_below:
        return True
    F_try = system.residual(trial)
    if not _finite(F_try):
        return False
    m_try = system.merit(trial) if ls.merit else 0.0
    if not np.isfinite(m_try):
        return False
    rise = system.merit_change(state, trial, merit, m_try) if ls.merit else 0.0
    if ls.merit and rise <= ls.armijo * alpha * slope + 1e-14 * abs(merit):
        return True
    if ls.merit and np.isfinite(ls.residual_merit_slack) and not rise <= ls.residual_merit_slack * abs(merit):
        return False
    return ls.residual_decrease and _norm(F_try) <= (1 - ls.armijo * alpha) * nF


def inner_failure(out: NewtonResult) -> Status:
    """Status of an outer loop whose inner Newton solve ``out`` failed.

    ``NONFINITE`` stays (a NaN/inf residual or merit); every other failure of the inner
    solve (line search, singular matrix, iteration limit) is ``NEWTON_FAILED``.
    """
    return Status.NONFINITE if out.status == Status.NONFINITE else Status.NEWTON_FAILED
