"""Penalty-parameter strategies (a registry).

Every method keeps one parameter vector ``eta`` whose limit ``eta -> 0`` is the
constrained problem: the AL parameter of (5.28) (a smaller ``eta`` is a stronger
penalty, because it divides ``g``), the barrier weight ``rho`` of (5.1), and
``1/t`` for the exterior penalty (5.10). A strategy returns a factor
``alpha``; the outer loop applies ``eta <- eta / alpha`` ("tighten" when
``alpha > 1``, keep when ``alpha == 1``; ``alpha < 1`` weakens, which is how the
printed Algorithm 5.4, ``eta <- 2 eta``, is reproduced).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, UnknownNameError

__all__ = ["make_strategy", "available_strategies", "StrategyState"]


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
        if not factor > 0 or factor == 1:
            raise InputError(f"strategy 'always': factor = {factor!r} must be > 0 and != 1 "
                             "(> 1 tightens, < 1 weakens)")
        self.factor = float(factor)

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
        if not 0 < tau < 1:
            raise InputError(f"strategy 'infeasibility': tau = {tau!r} must lie in (0, 1)")
        if not factor > 1:
            raise InputError(f"strategy 'infeasibility': factor = {factor!r} must be > 1")
        self.tau, self.factor, self.feas_tol = float(tau), float(factor), float(feas_tol)

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
        if not 0 < tau < 1:
            raise InputError(f"strategy 'per-constraint': tau = {tau!r} must lie in (0, 1)")
        if not factor > 1:
            raise InputError(f"strategy 'per-constraint': factor = {factor!r} must be > 1")
        self.tau, self.factor, self.feas_tol = float(tau), float(factor), float(feas_tol)

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


_REGISTRY = {c.name: c for c in (_Fixed, _Always, _Infeasibility, _KKT, _PerConstraint)}


def available_strategies() -> list[str]:
    """Names of the registered penalty-parameter strategies."""
    return sorted(_REGISTRY)


def make_strategy(name: str, **params):
    """Build a strategy by registry name (``"fixed"``, ``"always"``, ``"infeasibility"``,
    ``"kkt"``, ``"per-constraint"``).

    Raises
    ------
    UnknownNameError
        For an unknown name.
    InputError
        For an unknown or out-of-range parameter.
    """
    try:
        cls = _REGISTRY[name]
    except (KeyError, TypeError):
        raise UnknownNameError("strategy", name, list(_REGISTRY)) from None
    try:
        return cls(**params)
    except TypeError as exc:
        raise InputError(f"strategy {name!r}: bad parameters {sorted(params)}: {exc}") from None
