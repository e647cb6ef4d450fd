"""Shared machinery: the penalty protocol, property labels and domain masking."""

from __future__ import annotations

import abc
import math
from collections.abc import Callable
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "PROPERTY_LABELS",
    "Penalty",
    "PenaltyBase",
]

#: Labels of the properties of Definition 5.2 (family P).
PROPERTY_LABELS: tuple[str, ...] = ("P1", "P2", "P3", "P4", "P5")


@runtime_checkable
class Penalty(Protocol):
    """What every penalty ``p(y, mu)`` provides (Definition 5.2 and (5.28)).

    Derivatives are taken in ``y``.  All three evaluations broadcast ``y`` and
    ``mu`` and return floats; outside the domain (``y >= domain_upper(mu)``)
    they return ``+inf`` without warnings.
    """

    name: str
    doc: str
    family_p: bool
    properties: frozenset[str]

    def value(self, y: ArrayLike, mu: ArrayLike) -> Any: ...

    def derivative(self, y: ArrayLike, mu: ArrayLike) -> Any: ...

    def second_derivative(self, y: ArrayLike, mu: ArrayLike) -> Any: ...

    def domain_upper(self, mu: ArrayLike) -> Any: ...


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
