"""Name registries for penalties and generators."""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..errors import InputError, UnknownNameError
from ._base import Penalty
from ._classical import ExteriorQuadratic, HestenesPowell, InverseBarrier, LogBarrier, Rockafellar
from ._met import Met1, Met2
from ._theta import EXP, LOG, QUAD, GENERATOR_LABELS, Generator

__all__ = [
    "available",
    "describe",
    "make",
    "register",
    "unregister",
    "theta",
    "thetas",
    "register_theta",
    "unregister_theta",
]


@dataclass(frozen=True)
class _Entry:
    factory: Callable[..., Penalty]
    doc: str


_PENALTIES: dict[str, _Entry] = {}
_THETAS: dict[str, Generator] = {}


def available() -> list[str]:
    """Sorted names of the registered penalties.

    Examples
    --------
    >>> "exp-met1" in available()
    True
    """
    return sorted(_PENALTIES)


def describe() -> dict[str, str]:
    """Map each registered penalty name to its one-line description."""
    return {name: _PENALTIES[name].doc for name in available()}


def make(name: str, **params: Any) -> Penalty:
    """Build the penalty registered as ``name``.

    Parameters
    ----------
    name : str
        A name from :func:`available`.
    **params
        Keyword arguments for the factory (the built-in ones take none).

    Raises
    ------
    UnknownNameError
        ``name`` is not registered; the message lists the known names.
    InputError
        ``params`` do not fit the factory's signature.

    Examples
    --------
    >>> p = make("log-met2")
    >>> float(p.value(0.0, 3.0)), p.family_p
    (0.0, True)
    """
    try:
        entry = _PENALTIES[name]
    except (KeyError, TypeError):
        raise UnknownNameError("penalty", name, available()) from None
    try:
        inspect.signature(entry.factory).bind(**params)
    except TypeError as exc:
        raise InputError(
            f"penalty {name!r} does not accept parameters {sorted(params)}: {exc}; "
            f"its factory signature is {inspect.signature(entry.factory)}"
        ) from None
    return entry.factory(**params)


def register(name: str, factory: Callable[..., Penalty], *, doc: str, overwrite: bool = False) -> None:
    """Register a penalty factory under ``name``.

    Parameters
    ----------
    name : str
        Registry name (e.g. ``"my-penalty"``).
    factory : callable
        Returns an object following :class:`Penalty`; keyword arguments of
        :func:`make` are forwarded to it.  The object may declare the facts read by
        :func:`alcontact.penalties.facts` (e.g. ``freezes_at_zero``); the others get
        their defaults.
    doc : str
        One-line description, shown by :func:`describe`.
    overwrite : bool
        Replace an existing registration instead of raising.

    Raises
    ------
    InputError
        ``name`` is already registered (and ``overwrite`` is false), or
        ``factory`` is not callable.
    """
    if not isinstance(name, str) or not name:
        raise InputError(f"penalty name must be a non-empty string, got {name!r}")
    if not callable(factory):
        raise InputError(f"factory for penalty {name!r} must be callable, got {factory!r}")
    if name in _PENALTIES and not overwrite:
        raise InputError(f"penalty {name!r} is already registered; pass overwrite=True to replace it")
    _PENALTIES[name] = _Entry(factory, str(doc))


def unregister(name: str) -> None:
    """Remove a registered penalty (raises :class:`UnknownNameError` if absent)."""
    if name not in _PENALTIES:
        raise UnknownNameError("penalty", name, available())
    del _PENALTIES[name]


def thetas() -> list[str]:
    """Sorted names of the registered generators θ (Definition 5.3)."""
    return sorted(_THETAS)


def theta(name: str) -> Generator:
    """The generator registered as ``name`` (``"exp"``, ``"log"``, ``"quad"``, ...).

    Examples
    --------
    >>> float(theta("log").derivative(0.0))
    1.0
    """
    try:
        return _THETAS[name]
    except (KeyError, TypeError):
        raise UnknownNameError("generator", name, thetas()) from None


def register_theta(name: str, generator: Generator, *, doc: str | None = None, overwrite: bool = False) -> None:
    """Register a generator θ and the penalties ``"<name>-met1"``, ``"<name>-met2"``.

    Parameters
    ----------
    name : str
        Generator name; the penalties are named after it.
    generator : Generator
        Object with ``value``, ``derivative``, ``second_derivative``,
        ``upper`` and ``satisfies`` (see :class:`Theta`).  ``family_p`` of the
        derived penalties is true only if it claims all of (a)-(e).
    doc : str, optional
        One-line description (defaults to the generator's ``doc``).
    overwrite : bool
        Replace existing registrations instead of raising.

    Examples
    --------
    >>> from alcontact.penalties import Theta
    >>> th = Theta("frac", lambda y: y / (1 - y), lambda y: (1 - y) ** -2.0,
    ...            lambda y: 2 * (1 - y) ** -3.0, upper=1.0)
    >>> register_theta("frac", th)
    >>> make("frac-met2").family_p
    True
    >>> unregister_theta("frac")
    """
    missing = [a for a in ("value", "derivative", "second_derivative", "upper", "satisfies") if not hasattr(generator, a)]
    if missing:
        raise InputError(f"generator {name!r} lacks {missing}; build it with alcontact.penalties.Theta")
    unknown = set(generator.satisfies) - set(GENERATOR_LABELS)
    if unknown:
        raise InputError(f"generator {name!r} claims unknown properties {sorted(unknown)}; use labels {GENERATOR_LABELS}")
    if not float(generator.upper) > 0:
        raise InputError(f"generator {name!r}: domain bound upper must be > 0 (Definition 5.3 (a)), got {generator.upper!r}")
    text = doc or getattr(generator, "doc", "") or name
    _register_generator(
        name,
        generator,
        f"MET 1 (5.23) p = mu*theta(y), theta: {text}",
        f"MET 2 (5.25) p = theta(mu*y), theta: {text}",
        overwrite=overwrite,
    )


def _register_generator(
    name: str, generator: Generator, doc1: str, doc2: str, *, overwrite: bool, eta0_factor1: float = 1.0
) -> None:
    n1, n2 = f"{name}-met1", f"{name}-met2"
    if not overwrite:
        taken = [n for n in (n1, n2) if n in _PENALTIES] + ([name] if name in _THETAS else [])
        if taken:
            raise InputError(f"{taken} already registered; pass overwrite=True to replace")
    _THETAS[name] = generator
    register(n1, lambda: Met1(generator, name=n1, doc=doc1, eta0_factor=eta0_factor1), doc=doc1, overwrite=True)
    register(n2, lambda: Met2(generator, name=n2, doc=doc2), doc=doc2, overwrite=True)


def unregister_theta(name: str) -> None:
    """Remove a generator and its ``-met1`` / ``-met2`` penalties."""
    if name not in _THETAS:
        raise UnknownNameError("generator", name, thetas())
    del _THETAS[name]
    for suffix in ("-met1", "-met2"):
        _PENALTIES.pop(name + suffix, None)


# -- built-ins -------------------------------------------------------------
# Descriptions name the methods of the literature.
_register_generator(
    "exp",
    EXP,
    "exponential multiplier method (5.24), Tseng-Bertsekas: p = mu*(exp(y) - 1)",
    "MET 2 exponential (5.21)+(5.25): p = exp(mu*y) - 1",
    overwrite=False,
)
_register_generator(
    "log",
    LOG,
    "Polyak's modified barrier (5.22)+(5.23): p = -mu*log(1 - y), y < 1",
    "Matioli-Gonzaga (5.26): p = -log(1 - mu*y), y < 1/mu",
    overwrite=False,
    # measured on the Hock-Schittkowski set (benchmarks/nlp_hs.py): a 10x stronger start
    # (eta0_factor 0.1) lifts log-met1 from 46 to 48 of 53 problems; for the other
    # penalties factors 0.1 and 10 were no better than 1
    eta0_factor1=0.1,
)
_register_generator(
    "quad",
    QUAD,
    "MET 1 quadratic (5.27)+(5.23): p = mu*(y^2/2 + y); not family P (no (P5))",
    "Matioli's quadratic (5.27)+(5.25): p = (mu*y)^2/2 + mu*y; not family P, multipliers can turn negative",
    overwrite=False,
)
for _cls in (Rockafellar, HestenesPowell, ExteriorQuadratic, LogBarrier, InverseBarrier):
    register(_cls.name, _cls, doc=_cls.doc)  # type: ignore[attr-defined]
del _cls
