"""Classical penalties of sections 5.1-5.1.3, written in the form ``p(y, mu)``.

Conventions are chosen so that the single augmented Lagrangian (5.28),
``L = f + sum_i eta * p(g_i / eta, mu_i)`` with update ``mu <- p'(g / eta, mu)``,
reproduces each classical method.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ._base import PenaltyBase

__all__ = ["Rockafellar", "HestenesPowell", "ExteriorQuadratic", "LogBarrier", "InverseBarrier"]


@dataclass(frozen=True)
class Rockafellar(PenaltyBase):
    r"""Rockafellar's augmented Lagrangian penalty for inequalities (5.18).

    .. math::

        p(y, \mu) = \tfrac12\left(\max(0, \mu + y)^2 - \mu^2\right)
        = \begin{cases} y^2/2 + \mu y & y \ge -\mu \\ -\mu^2/2 & y < -\mu \end{cases}

    ``p' = max(0, mu + y)``; ``p'' = 1`` for ``y > -mu``, else 0.  Then
    ``eta p(g/eta, mu) = g^2/(2 eta) + mu g`` is (5.18) with Rockafellar's
    ``eta_R = 1/(2 eta)``, and ``mu <- p'(g/eta, mu) = max(0, mu + g/eta)``.
    Only C^1 (kink of ``p''`` at ``y = -mu``) and not strictly convex, so not in
    family P, but (P1), (P3), (P4), (P5) hold.

    Examples
    --------
    >>> p = Rockafellar()
    >>> float(p.value(-3.0, 1.0)), float(p.derivative(0.5, 1.0))
    (-0.5, 1.5)
    """

    name: str = "rockafellar"
    doc: str = "Rockafellar (5.18): p = (max(0, mu + y)^2 - mu^2)/2, update mu <- max(0, mu + g/eta)"
    properties: ClassVar[frozenset[str]] = frozenset({"P1", "P3", "P4", "P5"})
    twice_differentiable: ClassVar[bool] = False

    def _p(self, y, mu):
        return np.where(y >= -mu, y * (mu + 0.5 * y), -0.5 * mu * mu)

    def _dp(self, y, mu):
        return np.maximum(0.0, mu + y)

    def _d2p(self, y, mu):
        return np.where(y > -mu, 1.0, 0.0)

    def kinks(self, mu: ArrayLike) -> tuple[Any, ...]:
        return (-np.asarray(mu, dtype=float)[()],)


@dataclass(frozen=True)
class HestenesPowell(PenaltyBase):
    r"""Hestenes-Powell penalty for equality constraints (5.13), (5.15).

    .. math:: p(y, \lambda) = \lambda y + y^2/2

    so ``eta p(h/eta, lam) = lam h + h^2/(2 eta)`` is (5.13) with ``rho = 1/eta``
    and ``lam <- p'(h/eta, lam) = lam + h/eta`` is (5.15).  ``lam`` may have any
    sign.  Strictly convex (P2) but ``p' -> -inf`` as ``y -> -inf`` (no P5).
    Declares ``equality_only``: no inequality or contact method takes it.

    Examples
    --------
    >>> p = HestenesPowell()
    >>> float(p.derivative(2.0, -1.0))
    1.0
    """

    name: str = "hestenes-powell"
    doc: str = "Hestenes-Powell (5.13): p = lam*y + y^2/2 for equalities, update lam <- lam + h/eta (5.15)"
    properties: ClassVar[frozenset[str]] = frozenset({"P1", "P2", "P3", "P4"})
    equality_only: ClassVar[bool] = True

    def _p(self, y, mu):
        return y * (mu + 0.5 * y)

    def _dp(self, y, mu):
        return mu + y

    def _d2p(self, y, mu):
        return np.ones_like(y)


@dataclass(frozen=True)
class ExteriorQuadratic(PenaltyBase):
    r"""Exterior quadratic penalty for inequalities (5.9); ``mu`` is ignored.

    .. math:: p(y, \mu) = \max(0, y)^2

    so ``eta p(g/eta, .) = max(0, g)^2 / eta``: Algorithm 5.2 with ``t = 1/eta``.

    Examples
    --------
    >>> p = ExteriorQuadratic()
    >>> float(p.value(-1.0, 1.0)), float(p.value(3.0, 1.0))
    (0.0, 9.0)
    """

    name: str = "exterior-quadratic"
    doc: str = "exterior quadratic penalty (5.9): p = max(0, y)^2, mu ignored (t = 1/eta)"
    properties: ClassVar[frozenset[str]] = frozenset({"P1", "P4", "P5"})
    uses_multiplier: ClassVar[bool] = False
    twice_differentiable: ClassVar[bool] = False

    def _p(self, y, mu):
        return np.maximum(0.0, y) ** 2

    def _dp(self, y, mu):
        return 2.0 * np.maximum(0.0, y)

    def _d2p(self, y, mu):
        return np.where(y > 0.0, 2.0, 0.0)

    def kinks(self, mu: ArrayLike) -> tuple[Any, ...]:
        return (np.zeros(np.shape(mu))[()],)


@dataclass(frozen=True)
class LogBarrier(PenaltyBase):
    r"""Logarithmic barrier (5.2); ``mu`` is ignored, domain ``y < 0``.

    .. math:: p(y, \mu) = -\log(-y)

    so ``eta p(g/eta, .) = -eta log(-g) + eta log(eta)``: Algorithm 5.1 with
    ``rho = eta`` (up to a constant).

    Examples
    --------
    >>> p = LogBarrier()
    >>> float(p.derivative(-0.5, 1.0)), float(p.value(0.0, 1.0))
    (2.0, inf)
    """

    name: str = "log-barrier"
    doc: str = "logarithmic barrier (5.2): p = -log(-y) for y < 0, mu ignored"
    properties: ClassVar[frozenset[str]] = frozenset({"P2", "P4", "P5"})
    uses_multiplier: ClassVar[bool] = False

    def _p(self, y, mu):
        return -np.log(-y)

    def _dp(self, y, mu):
        return -1.0 / y

    def _d2p(self, y, mu):
        return 1.0 / (y * y)

    def _upper(self, mu):
        return np.zeros(np.shape(mu))


@dataclass(frozen=True)
class InverseBarrier(PenaltyBase):
    r"""Inverse barrier (5.3); ``mu`` is ignored, domain ``y < 0``.

    .. math:: p(y, \mu) = -1/y

    so ``eta p(g/eta, .) = -eta^2 / g``: Algorithm 5.1 with ``rho = eta^2``.
    Declares ``eta_min = 1e-24``: its complementarity ``mu g`` behaves like
    ``sqrt(rho)``, so reaching ``ctol`` needs ``eta`` far below the default floor
    ``1e-12`` of :func:`alcontact.optim.minimize`.

    Examples
    --------
    >>> p = InverseBarrier()
    >>> float(p.value(-0.5, 1.0)), float(p.derivative(-0.5, 1.0))
    (2.0, 4.0)
    """

    name: str = "inverse-barrier"
    doc: str = "inverse barrier (5.3): p = -1/y for y < 0, mu ignored"
    properties: ClassVar[frozenset[str]] = frozenset({"P2", "P4", "P5"})
    uses_multiplier: ClassVar[bool] = False
    eta_min: ClassVar[float | None] = 1e-24

    def _p(self, y, mu):
        return -1.0 / y

    def _dp(self, y, mu):
        return 1.0 / (y * y)

    def _d2p(self, y, mu):
        return -2.0 / (y * y * y)

    def _upper(self, mu):
        return np.zeros(np.shape(mu))


