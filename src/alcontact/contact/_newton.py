r"""One globalized Newton method for every contact algorithm.

Every inner solve of the contact algorithms is Newton's method on a system
:math:`F(x) = 0`: the condensed subproblem (S) of Algorithms 6.1 / 6.3
(:class:`CondensedSubproblem`), its full-space form with AMG-preconditioned CG
(:mod:`alcontact.contact._iterative`), the finite-deformation subproblem and its
active-set reference (:mod:`alcontact.contact._finite`), and the frictional
subproblems (6.2a) and Alart-Curnier systems (:mod:`alcontact.contact._friction`,
:mod:`alcontact.contact._finite_friction`). :func:`newton` is the one loop; a
problem is a :class:`NewtonSystem` that supplies what differs:

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

The systems and their settings:

==========================================  ===========================================================
system                                      line search / stall test
==========================================  ===========================================================
:class:`CondensedSubproblem` (direct path)  Armijo on :math:`\Pi`, full step on a flat merit; stall at
                                            ``max(1e-8, floor)``, ``floor`` the round-off of :math:`F`
``_iterative._FullSpaceSubproblem`` (AMG)   the same; tolerance raised to the round-off bound of
                                            :math:`R`; CG forcing tightened after a damped step
``_finite._Subproblem``                     Armijo on :math:`\Pi` (or :math:`|R|^2/2`) or a residual
                                            decrease; inverted elements halve; stall at
                                            ``max(1e-8, floor)``
``_finite._EqualityNewton`` (reference)     decrease of the relative residual, any step below
                                            :math:`2^{-20}`; stops when the active set changes
``_friction._CondensedSystem``              Armijo on the potential (radius :math:`\mu\lambda_N`) or a
                                            residual decrease (coupled radius, Alart-Curnier)
``_friction_iterative._FullSpaceFriction``  as ``_FullSpaceSubproblem`` (AMG); Armijo on the potential or
                                            a residual decrease (coupled radius, GMRES); stall 1e-8
``_finite_friction._FrictionSubproblem``    residual decrease, inverted elements halve; stall 1e-9
(and the Alart-Curnier reference)           (the reference: from the third iterate on)
==========================================  ===========================================================

Every outcome carries a :class:`~alcontact.status.Status` (``CONVERGED``,
``MAXITER``, ``LINE_SEARCH_FAILED``, ``NONFINITE``, ``NEWTON_FAILED``) and a message
for people; callers test the status. The history records the relative residual of
every iterate and the step length taken from it (the quadratic-rate tests read it).

For fixed multipliers :math:`\lambda` the subproblem (S) of Algorithms 6.1 / 6.3
on the condensed variables (:class:`CondensedSubproblem`) is the minimization of
the potential energy plus the penalty energy. On the manifold of equilibrium
states :math:`u = u_{free} - K^{-1}B^T r` it reads

.. math::

    \Pi(r) = \tfrac12 r^T S r + \sum_i w_i\, \psi_i(g_i), \qquad g = g_{free} - S r,

whose stationarity :math:`r = w \circ t_N(g)` is the equilibrium of the body with
the penalized contact traction. Newton's step solves
:math:`(I + W D S)\,\Delta r = -(r - w\circ t_N)` with :math:`D = \mathrm{diag}(dt_N/dg)`;
it is exactly the full-space Newton step, restricted to the contact points.
Globalized by backtracking (Armijo) on :math:`\Pi`, which is ``+inf`` outside the
domain of barrier-type penalties, so iterates stay inside it.
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as sla

from ..status import Status

__all__ = ["LineSearch", "NewtonSettings", "NewtonSystem", "NewtonRecord", "NewtonResult", "newton",
           "NewtonOutcome", "CondensedSubproblem", "newton_step", "solve_subproblem", "subproblem_outcome",
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
    """

    line_search: LineSearch = LineSearch()
    stall: float = 1e-8
    stall_from: int = 2
    negligible_tol: float = np.inf


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
        if _accepts(system, ls, trial, alpha, res, merit, slope, nF):
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


def _accepts(system, ls: LineSearch, trial, alpha, res, merit, slope, nF) -> bool:
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
    if ls.merit and m_try <= merit + ls.armijo * alpha * slope + 1e-14 * abs(merit):
        return True
    if ls.merit and np.isfinite(ls.residual_merit_slack) and not m_try <= merit + ls.residual_merit_slack * abs(merit):
        return False
    return ls.residual_decrease and _norm(F_try) <= (1 - ls.armijo * alpha) * nF


def inner_failure(out: NewtonResult) -> Status:
    """Status of an outer loop whose inner Newton solve ``out`` failed.

    ``NONFINITE`` stays (a NaN/inf residual or merit); every other failure of the inner
    solve (line search, singular matrix, iteration limit) is ``NEWTON_FAILED``.
    """
    return Status.NONFINITE if out.status == Status.NONFINITE else Status.NEWTON_FAILED


# ---------------------------------------------------------------------- subproblem (S) of the outer loops
@dataclass(frozen=True)
class NewtonOutcome:
    """Outcome of one subproblem (S) for the outer loops of :mod:`alcontact.contact._algorithms`.

    ``state`` is the iterate of the outer loops: the contact forces ``r`` of the
    condensed path, the free displacement ``x`` of the AMG and finite-deformation paths;
    ``g`` and ``t`` the gaps and normal tractions of the candidates there.
    """

    state: np.ndarray
    g: np.ndarray
    t: np.ndarray
    iterations: int
    status: Status
    residual: float
    message: str

    @property
    def converged(self) -> bool:
        return self.status.success


def subproblem_outcome(out: NewtonResult, g, t) -> NewtonOutcome:
    """The :class:`NewtonOutcome` of a :func:`newton` result with the gaps ``g`` and tractions ``t`` of its state."""
    return NewtonOutcome(out.x, g, t, out.iterations, out.status, out.residual, out.message)


class CondensedSubproblem(NewtonSystem):
    r"""Subproblem (S) on the condensed contact forces ``r`` (module doc): :math:`F = r - w\circ t_N(g)`.

    State: ``(r, g, t, F, Pi)``. Relative residual :math:`\max|F|` over the largest contact
    force (of the start, or the current iterate where larger).

    A residual that stalls (drops by less than half) counts as converged below the
    round-off floor of that residual (:meth:`roundoff_floor`, the stall level of
    :func:`newton` where it exceeds the fixed 1e-8 of :class:`NewtonSettings`): at a large
    penalty stiffness the gaps :math:`g = g^{free} - S r` lose digits to cancellation and
    :math:`F` carries their error times :math:`w D`, so no Newton step can bring it lower.
    The pure penalty stalled at 1.4e-8 to 2.0e-8 relative on the 2D Hertz model at 983,616
    DOFs (847 candidates, :math:`\varepsilon_N = 1.1\cdot 10^{13}`) and failed after 60
    Newton steps with the fixed level alone. The tolerance itself is not raised: a
    residual still decreasing, or an iteration limit reached, keeps its status.
    """

    #: safety factor of :meth:`roundoff_floor`: the stalled residuals measured on 2D Hertz
    #: models (30, 111 and 847 candidates) lie at 0.05-0.1 times ``sqrt(m) u`` times the bound
    FLOOR_FACTOR = 1.0

    def __init__(self, dc, law, lam):
        self.S = dc.S
        self.w = dc.weights[dc.cand]
        self.gfree = dc.g_free[dc.cand]
        self.law, self.lam = law, lam
        self.scale = None
        self.fscale = 1e-300
        self._Sabs = None  # |S|, built the first time the round-off floor may matter
        self._Smax = float(max(np.max(self.S, initial=0.0), -np.min(self.S, initial=0.0)))  # max|S|, no copy

    def evaluate(self, r):
        g = self.gfree - self.S @ r
        t = self.law.traction(g, self.lam)
        pi = 0.5 * r @ (self.S @ r) + float(np.sum(self.w * self.law.energy(g, self.lam)))
        return r, g, t, r - self.w * t, pi

    def residual(self, state):
        return state[3]

    def merit(self, state):
        return state[4]

    def measure(self, state):
        r, _, t, F, _ = state
        if self.scale is None:
            self.scale = max(float(np.max(np.abs(self.w * t), initial=0.0)),
                             float(np.max(np.abs(r), initial=0.0)))
        self.fscale = max(self.scale, float(np.max(np.abs(r), initial=0.0)), 1e-300)
        return float(np.max(np.abs(F), initial=0.0)) / self.fscale

    def step(self, r, state, history):
        with warnings.catch_warnings():  # ill-conditioning shows in the residual test, not as a warning
            warnings.simplefilter("ignore", sla.LinAlgWarning)
            return newton_step(self.S, self.w * self.law.stiffness(state[1], self.lam), state[3])

    def slope(self, r, state, dr):
        return float((self.S @ state[3]) @ dr)  # grad Pi = S F

    def negligible(self, r, state, dr):
        return float(np.max(np.abs(dr), initial=0.0)) <= 1e-13 * self.fscale

    def stall_level(self, state, level):
        return max(level, self.roundoff_floor(state, level))

    def roundoff_floor(self, state, tol: float = 0.0) -> float:
        r"""Round-off floor of the relative residual :meth:`measure` at ``state``.

        In floating point (unit round-off :math:`u`) the gaps carry the error
        :math:`|\delta g_i| \lesssim u\,(|g^{free}_i| + (|S|\,|r|)_i)` (the rounding of
        :math:`S r`, whose terms cancel against :math:`g^{free}` where the body is in
        contact), the traction :math:`t_N(g)` passes it on times :math:`D_i = dt_N/dg`
        and adds :math:`u|t_i|`, and the difference :math:`r - w\circ t` adds
        :math:`u|r_i|`. To first order

        .. math::

            |\delta F_i| \lesssim u\,\bigl(|r_i| + w_i|t_i|
                + w_i D_i\,(|g^{free}_i| + (|S|\,|r|)_i)\bigr),

        and the residual an exact Newton step :math:`(I + W D S)\Delta r = -F`
        leaves is this evaluation error of the next iterate. The rounding errors of the
        :math:`m` products of :math:`(S r)_i` add up like a random walk, so the floor is
        :attr:`FLOOR_FACTOR` times :math:`\sqrt{m}` times the maximum of the bound over the
        force scale of :meth:`measure` (:math:`m` the candidates).
        It grows with :math:`\max(w D)\,\max|S|`, the conditioning of the Newton
        matrix: about :math:`u` at the default penalty, 1e-8 and more for the pure penalty
        at :math:`\varepsilon_N h / E'` of 1e5 and beyond. A residual far above it is
        not round-off and still fails.

        A non-finite bound (a barrier's infinite stiffness) gives 0: no round-off is claimed.
        ``tol``: where the cheap bound with :math:`\max|S|\sum|r|` in place of :math:`|S||r|`
        already stays below it, that bound is returned (no :math:`|S|` is built).
        """
        r, g, t, _, _ = state
        if r.size == 0:
            return 0.0
        unit = self.FLOOR_FACTOR * np.sqrt(r.size) * np.finfo(float).eps
        wd = self.w * np.abs(self.law.stiffness(g, self.lam))
        base = np.abs(r) + self.w * np.abs(t)
        fscale = max(self.fscale, 1e-300)
        cheap = unit * float(np.max(
            base + wd * (np.abs(self.gfree) + self._Smax * float(np.sum(np.abs(r)))))) / fscale
        if not np.isfinite(cheap):  # an infinite stiffness (barrier at its pole): no floor is claimed
            return 0.0
        if cheap <= tol:
            return cheap
        if self._Sabs is None:
            self._Sabs = np.abs(self.S)
        bound = base + wd * (np.abs(self.gfree) + self._Sabs @ np.abs(r))
        return unit * float(np.max(bound)) / fscale


#: rows whose coupling ``wd_i * max|S|`` is below this are decoupled (``dr_i = -F_i``): far below round-off
_DECOUPLED = 1e-200


def newton_step(S, wd, F) -> np.ndarray:
    r"""Newton correction: solve :math:`(I + \mathrm{diag}(wd)\,S)\,\Delta r = -F`.

    With :math:`wd \ge 0` (every law of family P and the Macaulay law) the system is
    solved in its symmetric form. Rows with :math:`wd_i = 0` (points off contact under a
    Macaulay law, or whose coupling is below round-off) give :math:`\Delta r_i = -F_i`;
    on the others, ``P``,

    .. math::

        (\mathrm{diag}(1/wd_P) + S_{PP})\,\Delta r_P = -F_P / wd_P - S_{PZ}\,\Delta r_Z,

    a symmetric positive definite system (``S`` is) solved by Cholesky on the ``|P|``
    rows only: a third of the LU of the whole matrix when every row is coupled, less when
    part of the candidates is off contact. A negative ``wd_i`` (contact springs of a body
    held only by the obstacle) or a Cholesky that fails falls back to the LU of the whole
    matrix.
    """
    n = F.size
    smax = float(np.max(np.abs(np.diagonal(S)), initial=0.0))
    if n and np.all(wd >= 0):
        P = wd * smax > _DECOUPLED
        dr = -np.asarray(F, dtype=float).copy()
        if not np.any(P):
            return dr
        Z = ~P
        A = S[np.ix_(P, P)]
        A[np.diag_indices_from(A)] += 1.0 / wd[P]
        rhs = dr[P] / wd[P]
        if np.any(Z):
            rhs -= S[np.ix_(P, Z)] @ dr[Z]
        try:
            c = sla.cho_factor(A, lower=True, check_finite=True)
        except np.linalg.LinAlgError:
            pass  # not positive definite to round-off: the LU below
        else:
            dr[P] = sla.cho_solve(c, rhs, check_finite=False)
            return dr
    J = S * wd[:, None]
    J[np.diag_indices_from(J)] += 1.0
    return sla.solve(J, -F, check_finite=True)


def solve_subproblem(dc, law, lam, r0, *, tol=1e-12, maxiter=60) -> NewtonOutcome:
    """Solve ``r = w t_N(g_free - S r; lam)`` by :func:`newton` (:class:`CondensedSubproblem`)."""
    out = newton(CondensedSubproblem(dc, law, lam), r0, tol=tol, maxiter=maxiter)
    return subproblem_outcome(out, out.state[1], out.state[2])
