r"""Matioli's multiplier safeguard: the one implementation used by contact and optim.

A penalty whose derivative turns negative (no (P5), e.g. Matioli's quadratic
(5.27) with θ' = y + 1) would give negative multipliers ``mu <- p'(g/eta, mu)``
(tension in contact).  The safeguard extends ``p(., mu)`` by its minimum left of
the minimizer :math:`y^*(\mu)` (``p.minimizer(mu)``, where ``p'(y^*, mu) = 0``):

.. math::

    \hat p(y, \mu) = p(\max(y, y^*(\mu)), \mu), \qquad
    \hat p'(y, \mu) = \max(0, p'(y, \mu)), \qquad
    \hat p''(y, \mu) = \begin{cases} p''(y, \mu) & y > y^* \\ 0 & y < y^* \end{cases}

which is convex and C^1 with a kink of ``p''`` at :math:`y^*`; the updated
multipliers stay non-negative and inactive constraints (contact points out of
contact) get exactly zero multipliers.  For MET 1 :math:`y^* = y_0`, for MET 2
:math:`y^* = y_0/\mu`, with :math:`\theta'(y_0) = 0` (:math:`y_0 = -1` for (5.27)).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ._base import PenaltyBase, minimizer_by_bisection
from ._facts import facts

__all__ = ["Safeguarded", "safeguarded"]


@dataclass(frozen=True)
class Safeguarded(PenaltyBase):
    """``base`` extended by its minimum left of ``base.minimizer(mu)`` (see module doc).

    Facts: (P2) is dropped (constant left of ``y*``), (P5) is gained, no further
    safeguard is needed, ``freezes_at_zero``, ``generator`` and ``eta_min`` are the base's.

    Examples
    --------
    >>> from alcontact.penalties import make, safeguarded
    >>> p = safeguarded(make("quad-met2"))
    >>> float(p.derivative(-3.0, 1.0)), float(p.derivative(1.0, 1.0))
    (0.0, 2.0)
    """

    base: Any
    name: str = ""
    doc: str = ""
    properties: frozenset[str] = field(init=False)
    twice_differentiable = False

    def __post_init__(self) -> None:
        if not (hasattr(self.base, "name") and callable(getattr(self.base, "derivative", None))):
            from ..errors import InputError

            raise InputError(f"Safeguarded: base = {self.base!r:.60}: expected a penalty, e.g. "
                             "alcontact.penalties.make('quad-met2').")
        if not self.name:
            object.__setattr__(self, "name", self.base.name)
        if not self.doc:
            object.__setattr__(self, "doc", f"{self.base.doc} [Matioli's safeguard: p' -> max(0, p')]")
        props = (set(getattr(self.base, "properties", ())) - {"P2"}) | {"P5"}
        object.__setattr__(self, "properties", frozenset(props))

    @property
    def freezes_at_zero(self) -> bool:  # type: ignore[override]
        """The base penalty's fact."""
        return facts(self.base).freezes_at_zero

    @property
    def needs_multiplier_safeguard(self) -> bool:
        """``False``: ``p' >= 0`` everywhere."""
        return False

    @property
    def equality_only(self) -> bool:  # type: ignore[override]
        return bool(getattr(self.base, "equality_only", False))

    @property
    def uses_multiplier(self) -> bool:  # type: ignore[override]
        return facts(self.base).uses_multiplier

    @property
    def eta0_factor(self) -> float:  # type: ignore[override]
        return facts(self.base).eta0_factor

    @property
    def eta_min(self) -> float | None:  # type: ignore[override]
        return getattr(self.base, "eta_min", None)

    @property
    def generator(self) -> Any:  # type: ignore[override]
        return getattr(self.base, "generator", None)

    def minimizer(self, mu: ArrayLike) -> Any:
        """The base penalty's minimizer ``y*(mu)`` (bisection if it declares none)."""
        fn = getattr(self.base, "minimizer", None)
        return fn(mu) if fn is not None else minimizer_by_bisection(self.base, mu)

    def kinks(self, mu: ArrayLike) -> tuple[Any, ...]:
        return (self.minimizer(mu),)

    def _upper(self, mu):
        return np.asarray(self.base.domain_upper(mu), dtype=float)

    def domain_upper(self, mu: ArrayLike) -> Any:
        """The base penalty's domain bound ``b(mu)`` (the safeguard changes only ``y < y*``)."""
        return self.base.domain_upper(mu)

    def _kernels(self):
        # the base's raw kernels when it is a PenaltyBase (this wrapper masks the domain
        # itself), else its public evaluations
        base = self.base
        if all(hasattr(base, k) for k in ("_p", "_dp", "_d2p")):
            return base._p, base._dp, base._d2p
        return base.value, base.derivative, base.second_derivative

    def _ys(self, y, mu):
        ys = np.asarray(self.minimizer(mu), dtype=float)
        return ys, np.maximum(y, ys)

    def _p(self, y, mu):
        _, z = self._ys(y, mu)
        return np.asarray(self._kernels()[0](z, mu), dtype=float)

    def _dp(self, y, mu):
        ys, z = self._ys(y, mu)
        return np.where(y < ys, 0.0, np.maximum(np.asarray(self._kernels()[1](z, mu), dtype=float), 0.0))

    def _d2p(self, y, mu):
        ys, z = self._ys(y, mu)
        return np.where(y < ys, 0.0, np.asarray(self._kernels()[2](z, mu), dtype=float))


def safeguarded(pen: Any) -> Any:
    """``pen`` with Matioli's safeguard if its facts say it needs one, else ``pen`` itself.

    Examples
    --------
    >>> from alcontact.penalties import make, safeguarded
    >>> safeguarded(make("exp-met1")).name, type(safeguarded(make("quad-met1"))).__name__
    ('exp-met1', 'Safeguarded')
    """
    return Safeguarded(pen) if facts(pen).needs_multiplier_safeguard else pen
