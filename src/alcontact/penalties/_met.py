"""Penalties of family P built from a generator θ: MET 1 (5.23) and MET 2 (5.25)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import DomainError, InputError
from ._base import PenaltyBase
from ._theta import Generator

__all__ = ["Met1", "Met2", "properties_from_generator", "generator_zero"]


def _check_generator(theta: Any, where: str) -> None:
    """:class:`InputError` unless ``theta`` is a generator (``name``, ``satisfies``, value and derivatives)."""
    ok = all(hasattr(theta, a) for a in ("name", "satisfies")) and all(
        callable(getattr(theta, a, None)) for a in ("value", "derivative", "second_derivative"))
    if not ok:
        raise InputError(f"{where}: theta = {theta!r:.60}: expected a generator θ, e.g. "
                         "alcontact.penalties.theta('exp') (see alcontact.penalties.thetas()).")


def properties_from_generator(theta: Generator) -> frozenset[str]:
    """Properties (P1)-(P5) that MET 1 / MET 2 inherit from θ's (a)-(e).

    (e) gives (P1) and (P3); (b) gives (P2); (a) and (c) give (P4); (d) gives (P5).
    """
    _check_generator(theta, "properties_from_generator")
    s = set(theta.satisfies)
    props = set()
    if "e" in s:
        props |= {"P1", "P3"}
    if "b" in s:
        props.add("P2")
    if {"a", "c"} <= s:
        props.add("P4")
    if "d" in s:
        props.add("P5")
    return frozenset(props)


def generator_zero(theta: Generator) -> float | None:
    """Point ``y0 < 0`` with ``θ'(y0) = 0``, or ``None`` if ``θ' > 0`` on ``(-1e8, 0]``.

    Exists only for generators without (d) whose derivative changes sign, e.g.
    Matioli's quadratic (5.27) with ``y0 = -1``.  Bisection to relative precision
    ``1e-15``.
    """
    _check_generator(theta, "generator_zero")
    lo, hi = -1.0, 0.0
    with np.errstate(all="ignore"):
        while float(theta.derivative(lo)) > 0:
            lo *= 2.0
            if lo < -1e8:
                return None
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if float(theta.derivative(mid)) > 0:
                hi = mid
            else:
                lo = mid
            if hi - lo <= 1e-15 * max(1.0, abs(lo)):
                break
    return hi


@dataclass(frozen=True)
class _Met(PenaltyBase):
    """Fields shared by MET 1 and MET 2: the generator, a name and doc derived from it.

    Declared facts: ``freezes_at_zero`` (``p'(y, 0) = 0``), ``generator`` (θ), and
    ``needs_multiplier_safeguard`` when θ lacks (d) and ``θ'`` has a zero ``y0``
    (then ``p'`` is negative left of :meth:`minimizer`).
    """

    theta: Generator
    name: str = ""
    doc: str = ""
    properties: frozenset[str] = field(init=False)
    eta0_factor: float = 1.0  # type: ignore[misc]
    suffix: ClassVar[str] = ""
    formula: ClassVar[str] = ""
    freezes_at_zero: ClassVar[bool] = True

    @property
    def generator(self) -> Generator:  # type: ignore[override]
        """The generator θ this penalty is built from."""
        return self.theta

    @cached_property
    def _y0(self) -> float | None:
        if "d" in set(self.theta.satisfies):
            return None
        return generator_zero(self.theta)

    @property
    def needs_multiplier_safeguard(self) -> bool:
        """Whether θ lacks (d) and ``θ'`` changes sign (multipliers can turn negative)."""
        return self._y0 is not None

    def with_generator(self, theta: Any, doc: str = "") -> "_Met":
        """The same MET penalty (same name) on the generator ``theta``."""
        return dataclasses.replace(self, theta=theta, name=self.name, doc=doc or self.doc)

    def __post_init__(self) -> None:
        _check_generator(self.theta, type(self).__name__)
        if not self.name:
            object.__setattr__(self, "name", f"{self.theta.name}-{self.suffix}")
        if not self.doc:
            object.__setattr__(self, "doc", f"{self.formula} with theta = {self.theta.name}")
        object.__setattr__(self, "properties", properties_from_generator(self.theta))


@dataclass(frozen=True)
class Met1(_Met):
    r"""MET 1: scale a generator by the multiplier (5.23).

    .. math:: p(y, \mu) = \mu\,\theta(y), \qquad y < b, \quad \mu > 0.

    With θ = exp - 1 (5.21) this is the exponential multiplier method (5.24)
    (Tseng & Bertsekas 1993); with θ = -log(1 - y) (5.22) it is Polyak's
    modified barrier.  ``p' = μ θ'``, ``p'' = μ θ''``; the domain bound is θ's.

    Parameters
    ----------
    theta : Generator
        The generator θ (Definition 5.3).
    name, doc : str, optional
        Registry name and one-line description (derived from θ when empty).
    eta0_factor : float, optional
        Declared multiplier of the automatic initial ``eta`` of
        :func:`alcontact.optim.minimize` (default 1).

    Examples
    --------
    >>> from alcontact.penalties import make
    >>> p = make("exp-met1")
    >>> float(p.value(0.0, 2.0)), float(p.derivative(0.0, 2.0))
    (0.0, 2.0)
    """

    suffix: ClassVar[str] = "met1"
    formula: ClassVar[str] = "MET 1 (5.23) p(y, mu) = mu*theta(y)"

    def _scaled(self, mu: NDArray[np.float64], t: NDArray[np.float64]) -> NDArray[np.float64]:
        # mu = 0 times an overflowed θ (inf) must give 0, not NaN.
        return np.where(mu == 0.0, 0.0, mu * t)

    def _p(self, y, mu):
        return self._scaled(mu, np.asarray(self.theta.value(y), dtype=float))

    def _dp(self, y, mu):
        return self._scaled(mu, np.asarray(self.theta.derivative(y), dtype=float))

    def _d2p(self, y, mu):
        return self._scaled(mu, np.asarray(self.theta.second_derivative(y), dtype=float))

    def _upper(self, mu):
        return np.full(np.shape(mu), float(self.theta.upper))

    def minimizer(self, mu: ArrayLike) -> Any:
        """``y* = y0``, the zero of θ' (``-inf`` if θ' > 0): independent of ``mu > 0``."""
        y0 = -math.inf if self._y0 is None else self._y0
        return np.full(np.shape(mu), y0)[()]


@dataclass(frozen=True)
class Met2(_Met):
    r"""MET 2: scale the argument of a generator by the multiplier (5.25).

    .. math:: p(y, \mu) = \theta(\mu y), \qquad \mu y < b, \quad \mu > 0.

    With θ = -log(1 - y) (5.22) this is Matioli & Gonzaga's penalty (5.26),
    ``p = -log(1 - μ y)`` with domain bound ``1/μ``.  ``p' = μ θ'(μ y)``,
    ``p'' = μ² θ''(μ y)``.

    A finite bound ``b`` of θ gives ``domain_upper(mu) = b / mu``
    (``inf`` for ``mu = 0``); negative ``mu`` then has no upper bound and
    raises :class:`~alcontact.errors.DomainError`.

    Examples
    --------
    >>> from alcontact.penalties import make
    >>> p = make("log-met2")
    >>> float(p.domain_upper(4.0)), float(p.derivative(0.0, 4.0))
    (0.25, 4.0)
    """

    suffix: ClassVar[str] = "met2"
    formula: ClassVar[str] = "MET 2 (5.25) p(y, mu) = theta(mu*y)"

    def _p(self, y, mu):
        return np.asarray(self.theta.value(mu * y), dtype=float)

    def _dp(self, y, mu):
        return mu * np.asarray(self.theta.derivative(mu * y), dtype=float)

    def _d2p(self, y, mu):
        return mu * mu * np.asarray(self.theta.second_derivative(mu * y), dtype=float)

    def _upper(self, mu):
        b = float(self.theta.upper)
        if math.isinf(b):
            return np.full(np.shape(mu), math.inf)
        if np.any(mu < 0):
            raise DomainError(
                f"penalty {self.name!r}: multiplier mu must be >= 0 (got min {float(np.min(mu))!r}); "
                "a negative mu leaves theta(mu*y) without an upper domain bound -- "
                "safeguard the update, e.g. mu = max(mu, 0)"
            )
        with np.errstate(divide="ignore"):
            return np.where(mu > 0, b / np.where(mu > 0, mu, 1.0), math.inf)

    def minimizer(self, mu: ArrayLike) -> Any:
        """``y* = y0 / mu`` with the zero ``y0`` of θ' (``-inf`` for ``mu <= 0`` or θ' > 0)."""
        mu_arr = np.asarray(mu, dtype=float)
        if self._y0 is None:
            return np.full(mu_arr.shape, -math.inf)[()]
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(mu_arr > 0, self._y0 / mu_arr, -math.inf)[()]
