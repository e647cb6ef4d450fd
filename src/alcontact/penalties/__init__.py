r"""Penalty functions of chapter 5: generators θ, MET 1 / MET 2, classical penalties.

Every penalty is a small immutable object ``p`` with ``p.value(y, mu)``,
``p.derivative(y, mu)`` and ``p.second_derivative(y, mu)`` (derivatives in
``y``, vectorized with broadcasting), ``p.domain_upper(mu)`` (the bound ``b``
of the domain ``(-inf, b)``), the declared facts ``p.properties`` (subset of
``{"P1", ..., "P5"}`` of Definition 5.2), ``p.family_p`` and
``p.twice_differentiable``, plus ``p.name`` and a one-line ``p.doc``.
Outside the domain the evaluations return ``+inf`` without warnings.

The algorithms never test a penalty by name or class; they read its declared
facts through :func:`facts` (``equality_only``, ``usable_for_contact``,
``freezes_at_zero``, ``needs_multiplier_safeguard``, ``eta_min``, ``generator``,
with defaults for user penalties that declare none), and apply Matioli's
safeguard through :func:`safeguarded`, one implementation for contact and
optimization.

One augmented Lagrangian (5.28) covers all of them,

.. math::

    L(x, \mu, \eta) = f(x) + \eta \sum_i p(g_i(x)/\eta, \mu_i),
    \qquad \mu_i \leftarrow p'(g_i(x)/\eta, \mu_i),

with the conventions documented on each class (Rockafellar's ``eta_R`` is
``1/(2 eta)``, the exterior penalty's ``t`` is ``1/eta``, ...).

Examples
--------
>>> from alcontact import penalties
>>> p = penalties.make("log-met2")
>>> float(p.derivative(0.0, 2.0)), float(p.domain_upper(2.0)), p.family_p
(2.0, 0.5, True)
>>> float(p.value(1.0, 2.0))
inf
"""

from __future__ import annotations

from ._base import PROPERTY_LABELS, Penalty, PenaltyBase, minimizer_by_bisection
from ._facts import PenaltyFacts, facts
from ._safeguard import Safeguarded, safeguarded
from ._classical import ExteriorQuadratic, HestenesPowell, InverseBarrier, LogBarrier, Rockafellar
from ._met import Met1, Met2, generator_zero, properties_from_generator
from ._registry import (
    available,
    describe,
    make,
    register,
    register_theta,
    theta,
    thetas,
    unregister,
    unregister_theta,
)
from ._theta import GENERATOR_LABELS, Generator, Theta

__all__ = [
    "PROPERTY_LABELS",
    "GENERATOR_LABELS",
    "Penalty",
    "PenaltyBase",
    "Generator",
    "Theta",
    "Met1",
    "Met2",
    "Rockafellar",
    "HestenesPowell",
    "ExteriorQuadratic",
    "LogBarrier",
    "InverseBarrier",
    "properties_from_generator",
    "generator_zero",
    "minimizer_by_bisection",
    "PenaltyFacts",
    "facts",
    "Safeguarded",
    "safeguarded",
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
