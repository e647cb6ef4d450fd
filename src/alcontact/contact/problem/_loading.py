r"""Load histories for incremental (quasi-static) frictional contact.

Coulomb friction is path dependent, so the loads are applied in steps over a
pseudo-time :math:`t \in [0, 1]` (section 6.2, the time-discrete scheme
(6.45)-(6.50)). A :class:`LoadHistory` scales extra supports and loads by
amplitude functions :math:`a_k(t)`; the supports and loads stored in the
:class:`~alcontact.contact.ContactProblem` itself are applied fully at every
step. Because the body is linear elastic, the contact-free displacement at time
``t`` is the superposition

.. math::

    u_{free}(t) = u_0 + \sum_k a_k(t)\, u_k ,

with one linear solve per component (the stiffness is factorized once: the set
of prescribed DOFs is the same at every step, only the values change).

Examples
--------
>>> from alcontact.contact import Support
>>> from alcontact.contact.problem._loading import LoadCase, LoadHistory, Ramp
>>> press = LoadCase(Support("top", value=(0.0, -1e-3)), Ramp((0.0, 0.5, 1.0), (0.0, 1.0, 1.0)))
>>> shear = LoadCase(Support("top", components=(0,), value=1e-3), Ramp((0.5, 1.0), (0.0, 1.0)),
...                  tangential=True)
>>> hist = LoadHistory((press, shear), times=LoadHistory.uniform(8))
>>> hist.times[:3]
(0.125, 0.25, 0.375)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from ..._options import MAX_STEPS, is_integer, is_real, show
from ...errors import InputError
from ._problem import BodyForce, Pressure, Support, Traction


def _finite_number(x) -> bool:
    try:
        return math.isfinite(x)
    except OverflowError:
        return False


@dataclass(frozen=True)
class Ramp:
    """Piecewise-linear amplitude through the knots ``(times[k], values[k])``.

    Defined only on ``[times[0], times[-1]]`` -- except that it is constant
    ``values[0]`` before the first knot when ``hold_before`` (default) and
    constant ``values[-1]`` after the last one when ``hold_after`` (default
    False: evaluating past the last knot is an error, so a history that stops
    too early is caught).
    """

    times: tuple[float, ...]
    values: tuple[float, ...]
    hold_before: bool = True
    hold_after: bool = False

    def __post_init__(self) -> None:
        try:
            t = np.asarray(self.times, dtype=float)
            v = np.asarray(self.values, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"Ramp knots must be lists of numbers; got times={show(self.times)}, "
                             f"values={show(self.values)}.") from None
        if t.ndim != 1 or t.size < 1 or t.shape != v.shape:
            raise InputError(f"Ramp needs equally long, non-empty knot lists; got times={self.times!r}, "
                             f"values={self.values!r}.")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise InputError(f"Ramp knots must be finite; got times={self.times!r}, values={self.values!r}.")
        if np.any(np.diff(t) <= 0):
            raise InputError(f"Ramp times must increase strictly; got {self.times!r}.")
        object.__setattr__(self, "times", tuple(float(x) for x in t))
        object.__setattr__(self, "values", tuple(float(x) for x in v))

    def __call__(self, t: float) -> float:
        t0, t1 = self.times[0], self.times[-1]
        eps = 1e-12 * max(1.0, abs(t1))
        if t < t0 - eps and not self.hold_before:
            raise InputError(f"load amplitude not defined at t={t:g} (knots start at {t0:g}).")
        if t > t1 + eps and not self.hold_after:
            raise InputError(f"load amplitude not defined at t={t:g} (knots end at {t1:g}); add a knot or use "
                             "hold_after=True.")
        return float(np.interp(t, self.times, self.values))


@dataclass(frozen=True)
class LoadCase:
    """One support or load scaled by an amplitude :math:`a(t)`.

    Parameters
    ----------
    item : Support, Traction, Pressure or BodyForce
        The component at amplitude 1 (a Support's value is multiplied by ``a(t)``).
    amplitude : Ramp or callable ``t -> float``
        Must be finite at every step time (else :class:`~alcontact.errors.InputError`).
    tangential : bool
        Declares a tangential (shearing) action. It may only be non-zero at steps
        that start with some point in contact; applying it earlier is an
        :class:`~alcontact.errors.InputError` (apply the normal load first).
    name : str
        Label used in messages.
    """

    item: Any
    amplitude: Ramp | Callable[[float], float]
    tangential: bool = False
    name: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.item, (Support, Traction, Pressure, BodyForce)):
            raise InputError(f"LoadCase item must be a Support, Traction, Pressure or BodyForce; got {self.item!r}.")
        if not callable(self.amplitude):
            raise InputError(f"LoadCase amplitude must be a Ramp or a callable t -> float; got {self.amplitude!r}.")

    @property
    def label(self) -> str:
        if self.name:
            return self.name
        it = self.item
        return f"{type(it).__name__}({getattr(it, 'boundary', 'body')})"

    def value(self, t: float) -> float:
        """Amplitude at ``t`` (clear error when undefined or not finite)."""
        try:
            a = float(self.amplitude(float(t)))
        except InputError as exc:
            raise InputError(f"load history: {self.label}: {exc}") from exc
        except Exception as exc:  # user callables may fail in any way
            raise InputError(f"load history: amplitude of {self.label} failed at t={t:g}: {exc!r}") from exc
        if not np.isfinite(a):
            raise InputError(f"load history: amplitude of {self.label} is not finite at t={t:g} (got {a!r}); "
                             "define it at every load step.")
        return a


@dataclass(frozen=True)
class LoadHistory:
    """Scaled supports and loads plus the pseudo-times of the load steps.

    Parameters
    ----------
    cases : sequence of LoadCase
    times : sequence of float
        Step times :math:`0 < t_1 < \\dots < t_N` (the state at :math:`t_0 = 0`
        is the contact-free solution at ``t = 0``).
    friction : Ramp or callable, optional
        Factor :math:`f(t) \\ge 0` of the friction coefficient,
        :math:`\\mu(t) = f(t)\\,\\mu` (default 1). E.g. a frictionless approach
        followed by frictional shearing, the Cattaneo-Mindlin hypothesis.
    """

    cases: tuple[LoadCase, ...]
    times: tuple[float, ...]
    friction: Any = None

    def __post_init__(self) -> None:
        if isinstance(self.cases, LoadCase):
            raise InputError("LoadHistory cases = LoadCase(...): expected a list; wrap the single case in a list, "
                             "e.g. LoadHistory([case], times).")
        if isinstance(self.cases, (str, bytes, dict, np.ndarray)) or not np.iterable(self.cases):
            raise InputError(f"LoadHistory cases = {show(self.cases)}: expected a list of LoadCase objects.")
        cases = tuple(self.cases)
        for c in cases:
            if not isinstance(c, LoadCase):
                raise InputError(f"LoadHistory cases must be LoadCase objects; got {c!r}.")
        object.__setattr__(self, "cases", cases)
        object.__setattr__(self, "times", self.check_times(self.times))
        if self.friction is not None and not callable(self.friction):
            raise InputError(f"LoadHistory friction must be a Ramp or a callable t -> factor; got {self.friction!r}.")
        for k, t in enumerate(self.times):  # defined at every step
            for c in cases:
                try:
                    c.value(t)
                except InputError as exc:
                    raise InputError(f"load history not defined at step {k + 1} (t={t:g}): {exc}") from exc
            self.friction_factor(t)

    def friction_factor(self, t: float) -> float:
        """Factor of the friction coefficient at ``t`` (1 without a friction amplitude)."""
        if self.friction is None:
            return 1.0
        try:
            f = float(self.friction(float(t)))
        except InputError as exc:
            raise InputError(f"load history: friction factor: {exc}") from exc
        if not np.isfinite(f) or f < 0:
            raise InputError(f"load history: friction factor at t={t:g} must be finite and >= 0; got {f!r}.")
        return f

    @staticmethod
    def check_times(times: Sequence[float]) -> tuple[float, ...]:
        """Step times as a tuple of floats; :class:`InputError` unless finite, positive, increasing, at most
        :data:`~alcontact._options.MAX_STEPS` of them."""
        try:
            n = len(times)
        except TypeError:
            raise InputError(f"load step times = {show(times)}: expected a sequence of numbers, e.g. "
                             "times=(0.5, 1.0), or LoadHistory.uniform(n).") from None
        if n > MAX_STEPS:
            raise InputError(f"load step times: {n:,} steps, more than {MAX_STEPS:,} (each step is a full solve); "
                             "use fewer steps.")
        try:
            t = np.asarray(tuple(times), dtype=float).ravel()
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"load step times = {show(times)}: expected numbers, e.g. times=(0.5, 1.0).") from None
        if t.size == 0:
            raise InputError("a load history needs at least one step time.")
        if not np.all(np.isfinite(t)) or t[0] <= 0 or np.any(np.diff(t) <= 0):
            raise InputError(f"load step times must be finite, positive and strictly increasing; got {tuple(times)!r}.")
        return tuple(float(x) for x in t)

    @staticmethod
    def uniform(n: int, t_end: float = 1.0) -> tuple[float, ...]:
        """``n`` equal steps on ``(0, t_end]``, ``1 <= n <=`` :data:`~alcontact._options.MAX_STEPS`.

        Raises
        ------
        InputError
            ``n`` is not an integer in range, or ``t_end`` is not a finite positive number.
        """
        if not is_integer(n) or not 1 <= n <= MAX_STEPS:
            raise InputError(f"number of load steps n = {show(n)}: expected an integer in [1, {MAX_STEPS}] (each "
                             "step is a full solve); pass fewer steps, or explicit step times.")
        if not (is_real(t_end) and math.isfinite(t_end) and t_end > 0):
            raise InputError(f"t_end = {show(t_end)}: expected a finite number > 0 (the last pseudo-time), e.g. "
                             "t_end=1.0.")
        return tuple(float(x) for x in np.linspace(0.0, float(t_end), int(n) + 1)[1:])

    def with_times(self, times: Sequence[float] | int) -> "LoadHistory":
        """The same cases on other step times (an int: that many uniform steps)."""
        if isinstance(times, (int, np.integer)) or type(times).__name__ == "bool_":
            times = self.uniform(times, self.times[-1])
        return LoadHistory(self.cases, tuple(times), self.friction)

    def amplitudes(self, t: float) -> np.ndarray:
        return np.array([c.value(t) for c in self.cases])


def component_fields(problem, history: LoadHistory):
    """Fixed DOFs and, per component (base first, then each case), values and loads.

    Returns
    -------
    fixed : ndarray of int
        Union of the prescribed DOFs of the problem and of the history.
    parts : list of (fixed_values, load) pairs
        ``parts[0]`` is the problem's own data (amplitude 1), ``parts[k+1]`` the
        case ``k`` at amplitude 1. A DOF prescribed twice takes the last
        prescription (problem supports first, then the cases in order).
    """
    model = problem.model
    entries = []  # (dofs, vals, owner)
    if model.axis_dofs.size:  # u_r = 0 on the axis of a body of revolution (fem._geometry)
        entries.append((model.axis_dofs, np.zeros(model.axis_dofs.size), 0))
    for s in problem.supports:
        d, v = model.dirichlet(s.boundary, None if s.components is None else list(s.components), s.value)
        entries.append((d, v, 0))
    for k, c in enumerate(history.cases):
        if isinstance(c.item, Support):
            s = c.item
            d, v = model.dirichlet(s.boundary, None if s.components is None else list(s.components), s.value)
            entries.append((d, v, k + 1))
    ncomp = len(history.cases) + 1
    if entries:
        dofs = np.concatenate([e[0] for e in entries])
        vals = np.concatenate([e[1] for e in entries])
        owner = np.concatenate([np.full(e[0].size, e[2]) for e in entries])
        fixed, idx = np.unique(dofs[::-1], return_index=True)
        vals, owner = vals[::-1][idx], owner[::-1][idx]
    else:
        fixed, vals, owner = np.empty(0, np.int64), np.empty(0), np.empty(0, np.int64)
    parts = []
    base_load = problem.load_vector()
    for k in range(ncomp):
        fv = np.where(owner == k, vals, 0.0)
        if k == 0:
            load = base_load
        else:
            item = history.cases[k - 1].item
            load = np.zeros(model.ndofs)
            if isinstance(item, Traction):
                load = model.traction_load(item.boundary, item.vector)
            elif isinstance(item, Pressure):
                load = model.pressure_load(item.boundary, item.value)
            elif isinstance(item, BodyForce):
                load = model.body_load(item.vector)
        parts.append((fv, load))
    return fixed, parts


def _scaled_support(s: Support, a: float) -> Support:
    v = s.value
    if callable(v):
        return Support(s.boundary, s.components, (lambda x, _v=v, _a=a: _a * np.asarray(_v(x), dtype=float)))
    return Support(s.boundary, s.components, (a * np.asarray(v, dtype=float)).tolist()
                   if np.ndim(v) else a * float(v))


def _scaled_load(ld, a: float):
    if isinstance(ld, Pressure):
        return Pressure(ld.boundary, a * ld.value)
    vec = ld.vector
    if callable(vec):
        scaled = lambda x, _v=vec, _a=a: _a * np.asarray(_v(x), dtype=float)  # noqa: E731
    else:
        scaled = tuple(a * float(c) for c in vec)
    return type(ld)(ld.boundary, scaled) if isinstance(ld, Traction) else BodyForce(scaled)


def problem_at(problem, history: LoadHistory, t: float):
    """The (frictionless-solvable) problem with every case frozen at amplitude ``a(t)``.

    Used to compare a frictional run with the frictionless solution of its
    final loads (equal for :math:`\\mu = 0`).
    """
    import dataclasses

    from ._problem import ContactProblem

    if not isinstance(problem, ContactProblem):
        raise InputError(f"problem_at: problem = {show(problem)}: expected a ContactProblem.")
    if not isinstance(history, LoadHistory):
        raise InputError(f"problem_at: history = {show(history)}: expected a LoadHistory.")
    if not (is_real(t) and _finite_number(t)):
        raise InputError(f"problem_at: t = {show(t)}: expected a finite number (a time of the history).")
    supports = list(problem.supports)
    loads = list(problem.loads)
    for c in history.cases:
        a = c.value(t)
        if isinstance(c.item, Support):
            supports.append(_scaled_support(c.item, a))
        else:
            loads.append(_scaled_load(c.item, a))
    return dataclasses.replace(problem, supports=tuple(supports), loads=tuple(loads))
