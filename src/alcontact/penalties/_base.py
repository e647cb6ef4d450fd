"""Shared machinery: the penalty protocol, property labels and domain masking."""

from __future__ import annotations

import abc
import math
from collections.abc import Callable
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError

__all__ = [
    "PROPERTY_LABELS",
    "Penalty",
    "PenaltyBase",
    "minimizer_by_bisection",
]

#: Labels of the properties of Definition 5.2 (family P).
PROPERTY_LABELS: tuple[str, ...] = ("P1", "P2", "P3", "P4", "P5")


@runtime_checkable
class Penalty(Protocol):
    """What every penalty ``p(y, mu)`` provides (Definition 5.2 and (5.28)).

    Derivatives are taken in ``y``.  All three evaluations broadcast ``y`` and
    ``mu`` and return floats; outside the domain (``y >= domain_upper(mu)``)
    they return ``+inf`` without warnings.

    A penalty may also declare the facts the algorithms read through
    :func:`alcontact.penalties.facts` (``equality_only``, ``freezes_at_zero``,
    ``needs_multiplier_safeguard``, ``usable_for_contact``, ``uses_multiplier``,
    ``eta_min``, ``eta0_factor``, ``generator``, ``minimizer(mu)``, ``kinks(mu)``,
    ``twice_differentiable``); undeclared ones get documented defaults.
    """

    name: str
    doc: str
    family_p: bool
    properties: frozenset[str]

    def value(self, y: ArrayLike, mu: ArrayLike) -> Any: ...

    def derivative(self, y: ArrayLike, mu: ArrayLike) -> Any: ...

    def second_derivative(self, y: ArrayLike, mu: ArrayLike) -> Any: ...

    def domain_upper(self, mu: ArrayLike) -> Any: ...


def minimizer_by_bisection(penalty: Any, mu: ArrayLike) -> Any:
    """Zero ``y*`` of the increasing ``p'(., mu)`` per entry of ``mu``; ``-inf`` if none.

    Doubles a left end from ``-1`` until ``p' <= 0`` (``-inf`` when ``p' > 0`` down to
    ``-2**30``), then bisects the bracket to relative precision ``1e-15``.
    """
    if not callable(getattr(penalty, "derivative", None)):
        raise InputError(f"minimizer_by_bisection: penalty = {penalty!r:.60}: expected a penalty, e.g. "
                         "alcontact.penalties.make('exp-met1').")
    try:
        mu_arr = np.atleast_1d(np.asarray(mu, dtype=float))
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"minimizer_by_bisection: mu = {mu!r:.40}: expected a number or an array of numbers."
                         ) from None
    lo = -np.ones_like(mu_arr)
    with np.errstate(all="ignore"):
        for _ in range(30):
            pos = np.asarray(penalty.derivative(lo, mu_arr), dtype=float) > 0
            if not np.any(pos):
                break
            lo = np.where(pos, 2.0 * lo, lo)
        none = np.asarray(penalty.derivative(lo, mu_arr), dtype=float) > 0
        hi = np.zeros_like(mu_arr)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            pos = np.asarray(penalty.derivative(mid, mu_arr), dtype=float) > 0
            hi = np.where(pos, mid, hi)
            lo = np.where(pos, lo, mid)
            if np.all(hi - lo <= 1e-15 * np.maximum(1.0, np.abs(lo))):
                break
    out = np.where(none, -math.inf, hi)
    return out.reshape(np.shape(mu))[()]


_Kernel = Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]]


class PenaltyBase(abc.ABC):
    """Mixin giving the public, domain-safe evaluations.

    Subclasses (frozen dataclasses) implement the kernels ``_p``, ``_dp``,
    ``_d2p`` (called on broadcast float arrays, possibly outside the domain
    -- the result there is discarded) and ``_upper(mu)``.
    """

    name: str
    doc: str
    properties: frozenset[str]
    #: ``True`` when ``p(., mu)`` is C^2 on its whole domain (no kinks).
    twice_differentiable: ClassVar[bool] = True
    #: ``True`` for penalties of equality constraints only (Hestenes-Powell (5.13)):
    #: their multipliers have any sign, so they are no inequality / contact penalty.
    equality_only: ClassVar[bool] = False
    #: ``True`` when ``p'(y, 0) = 0`` for every ``y`` (MET 1 (5.23), MET 2 (5.25)): a
    #: zero multiplier never revives, so the outer loops keep multipliers above a floor.
    freezes_at_zero: ClassVar[bool] = False
    #: Smallest penalty parameter ``eta`` the outer loop of :func:`alcontact.optim.minimize`
    #: must be allowed to reach (its option ``eta_min``), or ``None`` for the method's
    #: default.  The inverse barrier (5.3) declares ``1e-24``.
    eta_min: ClassVar[float | None] = None
    #: Multiplier of the automatic initial ``eta`` of :func:`alcontact.optim.minimize`
    #: (its option ``eta0_factor``); < 1 is a stronger start.
    eta0_factor: ClassVar[float] = 1.0
    #: ``False`` when ``p`` ignores ``mu`` (barriers (5.2), (5.3), exterior penalty (5.9)):
    #: a pure penalty method, no multiplier update.
    uses_multiplier: ClassVar[bool] = True
    #: The generator θ of MET 1 / MET 2 penalties (``None`` for the others).
    generator: ClassVar[Any] = None

    # -- kernels ---------------------------------------------------------
    @abc.abstractmethod
    def _p(self, y: NDArray[np.float64], mu: NDArray[np.float64]) -> NDArray[np.float64]:
        """Kernel on arrays inside the domain (subclasses implement it)."""

    @abc.abstractmethod
    def _dp(self, y: NDArray[np.float64], mu: NDArray[np.float64]) -> NDArray[np.float64]:
        """Kernel on arrays inside the domain (subclasses implement it)."""

    @abc.abstractmethod
    def _d2p(self, y: NDArray[np.float64], mu: NDArray[np.float64]) -> NDArray[np.float64]:
        """Kernel on arrays inside the domain (subclasses implement it)."""

    def _upper(self, mu: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.full(np.shape(mu), math.inf)

    # -- public API ------------------------------------------------------
    @property
    def family_p(self) -> bool:
        """Whether the penalty claims all of (P1)-(P5) (Definition 5.2)."""
        return set(PROPERTY_LABELS) <= set(self.properties)

    @property
    def needs_multiplier_safeguard(self) -> bool:
        """Whether ``p'(y, mu) < 0`` somewhere, so updated multipliers can turn negative.

        Default: the penalty lacks (P5) and is no equality penalty (Matioli's quadratic
        (5.27) is the built-in case).  Such a penalty is used through
        :func:`alcontact.penalties.safeguarded` (``p'`` replaced by ``max(0, p')``).
        """
        return "P5" not in self.properties and not self.equality_only

    @property
    def usable_for_contact(self) -> bool:
        """Whether Algorithms 6.3 / 6.4 accept it: (P1), (P3), (P4) and not equality-only."""
        return {"P1", "P3", "P4"} <= set(self.properties) and not self.equality_only

    def minimizer(self, mu: ArrayLike) -> Any:
        """Point ``y*`` with ``p'(y*, mu) = 0`` (``-inf`` where ``p' > 0`` down to ``-2**30``).

        The left end of the safeguarded penalty (:func:`alcontact.penalties.safeguarded`).
        The default bisects ``p'`` (increasing in ``y``); MET penalties use θ's zero.
        """
        return minimizer_by_bisection(self, mu)

    def with_generator(self, theta: Any, doc: str = "") -> "PenaltyBase":
        """The same kind of penalty built on another generator θ (MET 1 / MET 2 only)."""
        raise InputError(
            f"penalty {self.name!r} is not built from a generator theta; "
            "only MET 1 / MET 2 penalties (generator is not None) can be rebuilt with one"
        )

    def domain_upper(self, mu: ArrayLike) -> Any:
        """Bound ``b`` of the domain ``(-inf, b)`` in ``y`` (``inf`` if unbounded)."""
        with np.errstate(all="ignore"):
            return np.asarray(self._upper(np.asarray(mu, dtype=float)), dtype=float)[()]

    def kinks(self, mu: ArrayLike) -> tuple[Any, ...]:
        """Points ``y`` where ``p''(., mu)`` jumps (empty for C^2 penalties)."""
        return ()

    def value(self, y: ArrayLike, mu: ArrayLike) -> Any:
        """Penalty value ``p(y, mu)``; ``+inf`` outside the domain."""
        return self._masked(self._p, y, mu)

    def derivative(self, y: ArrayLike, mu: ArrayLike) -> Any:
        """First derivative ``p'(y, mu)`` in ``y``; ``+inf`` outside the domain."""
        return self._masked(self._dp, y, mu)

    def second_derivative(self, y: ArrayLike, mu: ArrayLike) -> Any:
        """Second derivative ``p''(y, mu)`` in ``y``; ``+inf`` outside the domain."""
        return self._masked(self._d2p, y, mu)

    def _masked(self, kernel: _Kernel, y: ArrayLike, mu: ArrayLike) -> Any:
        y_arr, mu_arr = np.broadcast_arrays(np.asarray(y, dtype=float), np.asarray(mu, dtype=float))
        upper = np.asarray(self.domain_upper(mu_arr), dtype=float)
        # Outside the domain the kernels may overflow or produce NaN; that part
        # of the result is replaced by +inf, so floating-point warnings are noise.
        with np.errstate(all="ignore"):
            out = np.asarray(kernel(y_arr, mu_arr), dtype=float)
            out = np.where(y_arr >= upper, np.inf, out)
        return out[()]
