"""Declared facts of a penalty, read in one place with defaults for user penalties.

The algorithms never test a penalty by name or class: they read these facts.
Penalties derived from :class:`~alcontact.penalties.PenaltyBase` declare them as
class attributes / properties; any other object following the
:class:`~alcontact.penalties.Penalty` protocol gets the defaults documented on
:class:`PenaltyFacts` (and may declare any of the attributes itself).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ._base import PROPERTY_LABELS

__all__ = ["PenaltyFacts", "facts"]


@dataclass(frozen=True)
class PenaltyFacts:
    """What the algorithms need to know about a penalty ``p(y, mu)``.

    Attributes
    ----------
    properties : frozenset of str
        Declared properties among (P1)-(P5) of Definition 5.2.
    family_p : bool
        All of (P1)-(P5).
    equality_only : bool
        A penalty of equality constraints (Hestenes-Powell (5.13)); default ``False``.
    usable_for_contact : bool
        (P1), (P3), (P4) and not equality-only: accepted by Algorithms 6.3 / 6.4.
    freezes_at_zero : bool
        ``p'(y, 0) = 0`` for all ``y`` (MET 1 (5.23) / MET 2 (5.25)): a zero multiplier
        never revives, so the outer loops keep multipliers above a floor.  Default:
        probed on a grid of ``y``.
    needs_multiplier_safeguard : bool
        ``p'`` is negative somewhere, so ``mu <- p'(g/eta, mu)`` can turn negative
        (Matioli's quadratic (5.27)); the algorithms then use
        :func:`alcontact.penalties.safeguarded`.  Default: no (P5) and not equality-only.
    twice_differentiable : bool
        ``p(., mu)`` is C^2 (no kinks, see ``p.kinks(mu)``); default ``True``.
    uses_multiplier : bool
        ``p`` depends on ``mu`` (an augmented Lagrangian penalty); ``False`` for the
        barriers (5.2), (5.3) and the exterior penalty (5.9).  Default: probed.
    bounded_domain : bool
        ``domain_upper(1)`` is finite (barrier type: iterates must stay inside).
    eta_min : float or None
        Smallest ``eta`` the optimization outer loop must be allowed to reach
        (``None``: the method's default).
    generator : object or None
        The generator θ of MET 1 / MET 2 penalties.
    eta0_factor : float
        Multiplier of the automatic initial ``eta`` of :func:`alcontact.optim.minimize`
        (default 1).
    """

    properties: frozenset[str]
    family_p: bool
    equality_only: bool
    usable_for_contact: bool
    freezes_at_zero: bool
    needs_multiplier_safeguard: bool
    twice_differentiable: bool
    uses_multiplier: bool
    bounded_domain: bool
    eta_min: float | None
    generator: Any
    eta0_factor: float


_PROBE = np.array([-5.0, -1.0, -0.1, 0.0, 0.1, 0.5])


def _probe_freezes(pen: Any) -> bool:
    with np.errstate(all="ignore"):
        d = np.asarray(pen.derivative(_PROBE, np.zeros_like(_PROBE)), dtype=float)
    return bool(np.all(d == 0.0))


def _probe_uses_multiplier(pen: Any) -> bool:
    y = _PROBE - 10.0  # inside the domain of any barrier with b >= 0
    with np.errstate(all="ignore"):
        a = np.asarray(pen.value(y, np.full_like(y, 0.5)), dtype=float)
        b = np.asarray(pen.value(y, np.full_like(y, 2.0)), dtype=float)
    return not bool(np.array_equal(a, b))


def facts(pen: Any) -> PenaltyFacts:
    """The declared facts of ``pen``, with defaults for attributes it does not declare.

    Parameters
    ----------
    pen : Penalty
        A penalty from :func:`alcontact.penalties.make` or any object following
        the :class:`~alcontact.penalties.Penalty` protocol.

    Examples
    --------
    >>> from alcontact.penalties import facts, make
    >>> f = facts(make("quad-met2"))
    >>> f.freezes_at_zero, f.needs_multiplier_safeguard, f.usable_for_contact
    (True, True, True)
    >>> facts(make("hestenes-powell")).equality_only
    True
    """
    if not (callable(getattr(pen, "domain_upper", None)) and callable(getattr(pen, "value", None))):
        from ..errors import InputError

        raise InputError(f"facts: pen = {pen!r:.60}: expected a penalty, e.g. alcontact.penalties.make('exp-met1').")
    props = frozenset(getattr(pen, "properties", frozenset()))
    equality_only = bool(getattr(pen, "equality_only", False))
    freezes = getattr(pen, "freezes_at_zero", None)
    safeguard = getattr(pen, "needs_multiplier_safeguard", None)
    usable = getattr(pen, "usable_for_contact", None)
    eta_min = getattr(pen, "eta_min", None)
    uses = getattr(pen, "uses_multiplier", None)
    with np.errstate(all="ignore"):
        upper = float(np.asarray(pen.domain_upper(1.0), dtype=float))
    return PenaltyFacts(
        properties=props,
        family_p=bool(getattr(pen, "family_p", set(PROPERTY_LABELS) <= props)),
        equality_only=equality_only,
        usable_for_contact=bool({"P1", "P3", "P4"} <= props and not equality_only if usable is None else usable),
        freezes_at_zero=_probe_freezes(pen) if freezes is None else bool(freezes),
        needs_multiplier_safeguard=bool(
            ("P5" not in props and not equality_only) if safeguard is None else safeguard
        ),
        twice_differentiable=bool(getattr(pen, "twice_differentiable", True)),
        uses_multiplier=_probe_uses_multiplier(pen) if uses is None else bool(uses),
        bounded_domain=bool(np.isfinite(upper)),
        eta_min=None if eta_min is None else float(eta_min),
        generator=getattr(pen, "generator", None),
        eta0_factor=float(getattr(pen, "eta0_factor", 1.0)),
    )
