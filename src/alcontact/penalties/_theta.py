"""Generators θ of Definition 5.3 and the built-in ones (5.21), (5.22), (5.27)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["GENERATOR_LABELS", "Generator", "Theta", "EXP", "LOG", "QUAD"]

#: Labels of the properties (a)-(e) of Definition 5.3.
GENERATOR_LABELS: tuple[str, ...] = ("a", "b", "c", "d", "e")

_Fn = Callable[[NDArray[np.float64]], NDArray[np.float64]]


@runtime_checkable
class Generator(Protocol):
    """A generator θ of Definition 5.3, used by MET 1 (5.23) and MET 2 (5.25).

    ``upper`` is the bound ``b`` of ``int dom θ = (-inf, b)``; ``satisfies`` is
    the set of labels among ``"a"``-``"e"`` the generator claims.
    """

    name: str
    upper: float
    satisfies: frozenset[str]

    def value(self, y: ArrayLike) -> Any: ...

    def derivative(self, y: ArrayLike) -> Any: ...

    def second_derivative(self, y: ArrayLike) -> Any: ...


@dataclass(frozen=True)
class Theta:
    r"""A generator θ built from three vectorized callables.

    Parameters
    ----------
    name : str
        Short name (``"exp"``, ``"log"``, ...).
    f, df, d2f : callable
        θ, θ' and θ'' on float arrays.  They are only trusted inside
        ``(-inf, upper)``; outside it the public methods return ``+inf``.
    upper : float
        The bound ``b > 0`` of the domain, ``math.inf`` when unbounded.
    satisfies : frozenset of str
        The properties among (a)-(e) of Definition 5.3 that θ has.
    doc : str
        One-line description.

    Examples
    --------
    >>> import numpy as np
    >>> th = Theta("frac", lambda y: y / (1 - y), lambda y: 1 / (1 - y) ** 2,
    ...            lambda y: 2 / (1 - y) ** 3, upper=1.0)
    >>> float(th.derivative(0.0)), float(th.value(2.0))
    (1.0, inf)
    """

    name: str
    f: _Fn = field(repr=False)
    df: _Fn = field(repr=False)
    d2f: _Fn = field(repr=False)
    upper: float = math.inf
    satisfies: frozenset[str] = frozenset(GENERATOR_LABELS)
    doc: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "satisfies", frozenset(self.satisfies))
        object.__setattr__(self, "upper", float(self.upper))

    @property
    def satisfies_d(self) -> bool:
        """Whether θ' -> 0 as y -> -inf (property (d)); without it multipliers can turn negative."""
        return "d" in self.satisfies

    @property
    def is_generator(self) -> bool:
        """Whether θ claims all of (a)-(e) of Definition 5.3."""
        return set(GENERATOR_LABELS) <= self.satisfies

    def value(self, y: ArrayLike) -> Any:
        """θ(y); ``+inf`` for ``y >= upper``."""
        return self._masked(self.f, y)

    def derivative(self, y: ArrayLike) -> Any:
        """θ'(y); ``+inf`` for ``y >= upper``."""
        return self._masked(self.df, y)

    def second_derivative(self, y: ArrayLike) -> Any:
        """θ''(y); ``+inf`` for ``y >= upper``."""
        return self._masked(self.d2f, y)

    def _masked(self, fn: _Fn, y: ArrayLike) -> Any:
        y_arr = np.asarray(y, dtype=float)
        with np.errstate(all="ignore"):
            out = np.asarray(fn(y_arr), dtype=float)
            out = np.where(y_arr >= self.upper, np.inf, out)
        return out[()]


def _exp(y: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.expm1(y)


def _log(y: NDArray[np.float64]) -> NDArray[np.float64]:
    return -np.log1p(-y)


def _log_d1(y: NDArray[np.float64]) -> NDArray[np.float64]:
    return 1.0 / (1.0 - y)


def _log_d2(y: NDArray[np.float64]) -> NDArray[np.float64]:
    return 1.0 / (1.0 - y) ** 2


EXP = Theta(
    "exp",
    _exp,
    np.exp,
    np.exp,
    upper=math.inf,
    doc="exponential θ(y) = exp(y) - 1, b = inf (5.21)",
)
LOG = Theta(
    "log",
    _log,
    _log_d1,
    _log_d2,
    upper=1.0,
    doc="modified log barrier θ(y) = -log(1 - y), b = 1 (5.22)",
)
QUAD = Theta(
    "quad",
    lambda y: y * (0.5 * y + 1.0),
    lambda y: y + 1.0,
    lambda y: np.ones_like(y),
    upper=math.inf,
    satisfies=frozenset({"a", "b", "c", "e"}),
    doc="Matioli's quadratic θ(y) = y²/2 + y (5.27); violates (d): θ' -> -inf",
)
