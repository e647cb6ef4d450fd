r"""Penalty-parameter update rules (one registry for :mod:`alcontact.optim` and :mod:`alcontact.contact`).

Every method keeps one parameter vector ``eta`` whose limit ``eta -> 0`` is the
constrained problem: the AL parameter of (5.28) (a smaller ``eta`` is a stronger
penalty, because it divides ``g``), the barrier weight ``rho`` of (5.1), and
``1/t`` for the exterior penalty (5.10). A rule (a *strategy*, :class:`PenaltyUpdate`)
returns a factor ``alpha``; the outer loop applies ``eta <- eta / alpha`` ("tighten" when
``alpha > 1``, keep when ``alpha == 1``; ``alpha < 1`` weakens, which is how the
printed Algorithm 5.4, ``eta <- 2 eta``, is reproduced).

The contact algorithms (:func:`alcontact.contact.solve`, option ``strategy``) read the
same factor as the growth of the penalty stiffness between outer iterations,
:math:`\varepsilon_N \leftarrow \alpha\,\varepsilon_N` (Algorithms 6.1 / 6.3), with the
penetration over ``h`` as the feasibility measure.

Rules are registered by name (:func:`register_strategy`), built by :func:`make_strategy`,
listed by :func:`available_strategies`; the name is looked up here and nowhere else.

Examples
--------
>>> rule = make_strategy("infeasibility", tau=0.5, factor=10.0)
>>> rule(StrategyState(k=2, feasibility=0.9, prev_feasibility=1.0,
...                    complementarity=0.0, prev_complementarity=0.0))
10.0
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from .._options import is_real, show
from ..errors import InputError, UnknownNameError

__all__ = ["make_strategy", "available_strategies", "describe_strategies", "register_strategy",
           "unregister_strategy", "StrategyState", "PenaltyUpdate"]


@runtime_checkable
class PenaltyUpdate(Protocol):
    r"""What a penalty-parameter update rule provides.

    ``rule(state)`` returns the factor ``alpha`` (a float, or one per constraint) by which
    the penalty is tightened after an outer iteration: ``eta <- eta / alpha`` in
    :mod:`alcontact.optim`, :math:`\varepsilon_N \leftarrow \alpha\varepsilon_N` in contact
    (which has one stiffness and takes the largest factor of a vector).
    """

    name: str

    def __call__(self, state: "StrategyState") -> Any: ...


@dataclass(frozen=True)
class StrategyState:
    """What a strategy sees after outer iteration ``k``.

    Attributes
    ----------
    k : int
        Outer iteration (1-based).
    feasibility, prev_feasibility : float
        (C4) measure now and after the previous iteration (``inf`` at k = 1,
        the value at ``x0`` is used instead when available).
    complementarity, prev_complementarity : float
        (C2) measure now and before.
    violation, prev_violation : ndarray or None
        Per-constraint complementarity-feasibility measure (m inequalities, then p
        equalities) now and before: :math:`V_i = |\\max(g_i, -\\eta_i \\bar\\mu_i)|`
        for inequalities (Birgin & Martinez's measure, in the units of ``g``),
        :math:`|h_j|` for equalities; None when the method has none.
    """

    k: int
    feasibility: float
    prev_feasibility: float
    complementarity: float
    prev_complementarity: float
    violation: np.ndarray | None = None
    prev_violation: np.ndarray | None = None


def _real(rule: str, name: str, value, ok, what: str) -> float:
    """``value`` as a float if it is a finite real number (not a bool) with ``ok(value)``; else InputError."""
    try:
        good = is_real(value) and math.isfinite(value) and bool(ok(float(value)))
    except OverflowError:  # an integer no float holds
        good = False
    if not good:
        raise InputError(f"strategy {rule!r}: {name} = {show(value)} must be {what}")
    return float(value)


def _tau_factor_tol(rule: str, tau, factor, feas_tol) -> tuple[float, float, float]:
    """The checked ``(tau, factor, feas_tol)`` of the rules that compare with a required drop."""
    return (_real(rule, "tau", tau, lambda v: 0 < v < 1, "a number in (0, 1)"),
            _real(rule, "factor", factor, lambda v: v > 1, "a number > 1"),
            _real(rule, "feas_tol", feas_tol, lambda v: v >= 0, "a number >= 0"))


class _Fixed:
    """Keep ``eta`` (the convergence theory of Algorithm 5.4 allows a constant ``eta``)."""

    name = "fixed"

    def __init__(self):
        pass

    def __call__(self, s: StrategyState) -> float:
        return 1.0


class _Always:
    """``eta <- eta / factor`` every iteration (Algorithms 5.1/5.2: halve ``rho``, double ``t``)."""

    name = "always"

    def __init__(self, factor: float = 2.0):
        self.factor = _real("always", "factor", factor, lambda v: v > 0 and v != 1,
                            "> 0 and != 1 (> 1 tightens, < 1 weakens)")

    def __call__(self, s: StrategyState) -> float:
        return self.factor


class _Infeasibility:
    """Tighten when infeasibility did not drop by the factor ``tau`` (Algorithm 5.3).

    ``eta <- eta / factor`` when ``feas_k > tau * feas_{k-1}``; the dissertation
    prints ``tau = 0.1`` and says "at least 10 % improvement"; both readings are
    available through ``tau``. Already-feasible iterates (``feas <= feas_tol``)
    never tighten.
    """

    name = "infeasibility"

    def __init__(self, tau: float = 0.25, factor: float = 10.0, feas_tol: float = 0.0):
        self.tau, self.factor, self.feas_tol = _tau_factor_tol(self.name, tau, factor, feas_tol)

    def _measure(self, s):
        return s.feasibility, s.prev_feasibility

    def __call__(self, s: StrategyState) -> float:
        now, before = self._measure(s)
        if now <= self.feas_tol or now <= self.tau * before:
            return 1.0
        return self.factor


class _KKT(_Infeasibility):
    """Like ``infeasibility`` but on ``max(feasibility, complementarity)``.

    Family-P multiplier updates shrink the multipliers of inactive constraints
    by a factor that improves as ``eta`` decreases (e.g. ``exp(g/eta)`` for
    exp-met1), so stalled complementarity also triggers a tightening.
    """

    name = "kkt"

    def _measure(self, s):
        return (max(s.feasibility, s.complementarity),
                max(s.prev_feasibility, s.prev_complementarity))


class _PerConstraint:
    """Per-constraint tightening on the complementarity-feasibility measure ``V``.

    ALGENCAN / LANCELOT-style (Birgin & Martinez, *Practical augmented Lagrangian
    methods*, SIAM 2014, Alg. 4.1, with one parameter per constraint as in
    Conn, Gould & Toint): nothing changes when ``max V`` dropped by the factor
    ``tau``; otherwise the constraints whose ``V_i`` did not drop by ``tau`` and are
    not negligible (``V_i > tau max V`` and ``V_i > feas_tol``) get
    ``eta_i <- eta_i / factor``. Returns a vector of factors.
    """

    name = "per-constraint"

    def __init__(self, tau: float = 0.5, factor: float = 10.0, feas_tol: float = 0.0):
        self.tau, self.factor, self.feas_tol = _tau_factor_tol(self.name, tau, factor, feas_tol)

    def __call__(self, s: StrategyState):
        v, vp = s.violation, s.prev_violation
        if v is None or vp is None or v.size == 0:
            now = max(s.feasibility, s.complementarity)
            before = max(s.prev_feasibility, s.prev_complementarity)
            return 1.0 if now <= self.feas_tol or now <= self.tau * before else self.factor
        vmax = float(np.max(v))
        if vmax <= self.feas_tol or vmax <= self.tau * float(np.max(vp)):
            return np.ones(v.size)
        bad = (v > self.tau * vp) & (v >= self.tau * vmax) & (v > self.feas_tol)
        return np.where(bad, self.factor, 1.0)


class _Alg54Printed:
    """Algorithm 5.4 as printed: ``eta <- alpha * eta`` (``alpha > 1``) after every outer iteration.

    ``eta`` divides ``g`` in (5.28), so this *weakens* the penalty every iteration (in contact:
    :math:`\\varepsilon_N \\leftarrow \\varepsilon_N / \\alpha`), the opposite of section 6.3.1
    (see SEED_NOTES, "Inconsistency" of Algorithm 5.4). Returns the factor ``1 / alpha``.
    Kept so that the printed rule can be measured against its correction.
    """

    name = "alg54-printed"

    def __init__(self, alpha: float = 2.0):
        self.alpha = _real(self.name, "alpha", alpha, lambda v: v > 1, "a number > 1")

    def __call__(self, s: StrategyState) -> float:
        return 1.0 / self.alpha


class _Alg54Corrected(_Alg54Printed):
    """Algorithm 5.4 corrected: ``eta <- eta / alpha`` (``alpha > 1``) after every outer iteration.

    The direction of section 6.3.1: a stronger penalty each iteration (in contact
    :math:`\\varepsilon_N \\leftarrow \\alpha\\,\\varepsilon_N`). Returns the factor ``alpha``; the
    same ``alpha`` as :class:`_Alg54Printed`, so the two differ only in the direction.
    """

    name = "alg54-corrected"

    def __call__(self, s: StrategyState) -> float:
        return self.alpha


@dataclass(frozen=True)
class _Entry:
    factory: Callable[..., PenaltyUpdate]
    doc: str
    loop_parameters: tuple[str, ...]


_REGISTRY: dict[str, _Entry] = {}


def available_strategies() -> list[str]:
    """Sorted names of the registered penalty-parameter update rules."""
    return sorted(_REGISTRY)


def describe_strategies() -> dict[str, str]:
    """Map each registered rule name to its one-line description."""
    return {name: _REGISTRY[name].doc for name in available_strategies()}


def register_strategy(name: str, factory: Callable[..., PenaltyUpdate], *, doc: str,
                      loop_parameters: tuple[str, ...] = (), overwrite: bool = False) -> None:
    """Register a penalty-parameter update rule under ``name``.

    Parameters
    ----------
    name : str
        Registry name; it becomes a valid ``strategy`` of :func:`alcontact.optim.minimize`
        and of the contact options.
    factory : callable
        Returns a :class:`PenaltyUpdate`; the keyword arguments of :func:`make_strategy` are
        forwarded to it.
    doc : str
        One-line description (:func:`describe_strategies`).
    loop_parameters : tuple of str
        Factory parameters taken from the outer loop that runs the rule when it offers them
        (``offered`` of :func:`make_strategy`: ``tau``, ``factor``, ``feas_tol``).
    overwrite : bool
        Replace an existing registration instead of raising.

    Raises
    ------
    InputError
        ``name`` is empty or already registered (and ``overwrite`` is false), or ``factory``
        is not callable.
    """
    if not isinstance(name, str) or not name:
        raise InputError(f"strategy name must be a non-empty string, got {name!r}")
    if not callable(factory):
        raise InputError(f"factory for strategy {name!r} must be callable, got {factory!r}")
    if name in _REGISTRY and not overwrite:
        raise InputError(f"strategy {name!r} is already registered; pass overwrite=True to replace it")
    _REGISTRY[name] = _Entry(factory, str(doc), tuple(loop_parameters))


def unregister_strategy(name: str) -> None:
    """Remove a registered rule (raises :class:`UnknownNameError` if absent)."""
    if name not in _REGISTRY:
        raise UnknownNameError("strategy", name, available_strategies())
    del _REGISTRY[name]


def _entry(name: str) -> _Entry:
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise UnknownNameError("strategy", name, available_strategies()) from None


def make_strategy(name: str, offered: Mapping[str, Any] | None = None, **params) -> PenaltyUpdate:
    """Build a rule by registry name (``"fixed"``, ``"always"``, ``"infeasibility"``,
    ``"kkt"``, ``"per-constraint"``, ``"alg54-printed"``, ``"alg54-corrected"``, or a registered one).

    Parameters
    ----------
    name : str
    offered : mapping, optional
        Values of the outer loop that runs the rule (:mod:`alcontact.optim` offers
        ``feas_tol``; contact offers ``tau``, ``factor`` = ``alpha`` and ``feas_tol`` =
        ``tol_penetration``); the rule gets those of its registered ``loop_parameters``.
        ``params`` override them.
    **params
        Parameters given by the user: every one must be accepted by the factory.

    Raises
    ------
    UnknownNameError
        For an unknown name.
    InputError
        For an unknown or out-of-range parameter.
    """
    entry = _entry(name)
    if offered is not None and not isinstance(offered, Mapping):
        raise InputError(f"strategy {name!r}: offered = {show(offered)} must be a mapping of loop parameters "
                         "(or None)")
    kwargs = {k: v for k, v in (offered or {}).items() if k in entry.loop_parameters}
    kwargs.update(params)
    try:
        return entry.factory(**kwargs)
    except TypeError as exc:
        raise InputError(f"strategy {name!r}: bad parameters {sorted(params)}: {exc}") from None


# the loop parameters: (C4)-type rules stop at the caller's feasibility tolerance; the
# per-constraint test is relative (ALGENCAN) and keeps feas_tol = 0 unless it is given
for _cls, _loop in ((_Fixed, ()), (_Always, ("factor",)), (_Infeasibility, ("tau", "factor", "feas_tol")),
                    (_KKT, ("tau", "factor", "feas_tol")), (_PerConstraint, ("tau", "factor")),
                    # Algorithm 5.4's own alpha (default 2), not the loop's factor: one meaning in optim and contact
                    (_Alg54Printed, ()), (_Alg54Corrected, ())):
    register_strategy(_cls.name, _cls, doc=(_cls.__doc__ or "").strip().splitlines()[0], loop_parameters=_loop)
del _cls, _loop
