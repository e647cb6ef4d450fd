"""Safeguarded forms of the penalties used inside the AL subproblems.

Two standard modifications, applied by :func:`safeguard_penalty` according to the
penalty's declared facts (:func:`alcontact.penalties.facts`; the registry objects
themselves are not changed):

- **Quadratic extrapolation** of the generator θ (Definition 5.3) of a MET 1 / MET 2
  penalty (fact ``generator``) beyond a point :math:`t_0` (Ben-Tal & Zibulevsky,
  "Penalty/barrier multiplier methods for convex programming problems", SIAM J.
  Optim. 7, 1997; the same device caps the exponential of Tseng & Bertsekas'
  exponential multiplier method):

  .. math::

      \\hat\\theta(y) = \\theta(t_0) + \\theta'(t_0)(y - t_0)
                       + \\tfrac12 \\theta''(t_0)(y - t_0)^2, \\qquad y > t_0,

  which is C^2, convex, and defined on the whole line. For the modified log
  barrier :math:`t_0 = b/2 = 1/2` (the subproblem is then defined everywhere, no
  fraction-to-boundary step is needed); for the exponential :math:`t_0` is a cap
  (default 20) that avoids overflow of :math:`e^{g/\\eta}`. Near a solution
  ``g/eta`` is small, so the multiplier update and the limit are unchanged.

- **Matioli's safeguard** for penalties declaring ``needs_multiplier_safeguard``
  (θ' becomes negative, e.g. the quadratic (5.27)): :func:`alcontact.penalties.safeguarded`,
  the implementation the contact laws use too; ``p`` is extended by its minimum
  left of the point where ``p' = 0``, so the updated multipliers stay non-negative
  (and inactive constraints get exactly zero multipliers).
"""

from __future__ import annotations

import math

import numpy as np

from ..penalties import Theta, facts, safeguarded

__all__ = ["safeguard_penalty", "extrapolated"]


def extrapolated(theta, t0: float) -> Theta:
    """θ continued by its second-order Taylor polynomial at ``t0`` for ``y > t0``."""
    t0 = float(t0)
    v0 = float(theta.value(t0))
    d0 = float(theta.derivative(t0))
    s0 = float(theta.second_derivative(t0))

    def f(y):
        z = np.minimum(y, t0)
        e = np.maximum(y - t0, 0.0)
        return np.where(y > t0, v0 + d0 * e + 0.5 * s0 * e * e, theta.value(z))

    def df(y):
        z = np.minimum(y, t0)
        e = np.maximum(y - t0, 0.0)
        return np.where(y > t0, d0 + s0 * e, theta.derivative(z))

    def d2f(y):
        z = np.minimum(y, t0)
        return np.where(y > t0, s0, theta.second_derivative(z))

    return Theta(f"{theta.name}~q({t0:g})", f, df, d2f, upper=math.inf,
                 satisfies=frozenset(theta.satisfies),
                 doc=f"{getattr(theta, 'doc', theta.name)}, quadratic extrapolation for "
                     f"y > {t0:g}")


def safeguard_penalty(pen, *, extrapolate: bool, cap: float):
    """The penalty used in the subproblems: ``pen`` with the safeguards above.

    Parameters
    ----------
    pen : penalty
        A penalty from :func:`alcontact.penalties.make`.  Its generator (MET 1 /
        MET 2) is extrapolated, and Matioli's safeguard is applied when it declares
        ``needs_multiplier_safeguard``; other penalties are returned unchanged.
    extrapolate : bool
        Quadratic extrapolation beyond half the domain bound (bounded θ) or beyond
        ``cap`` (unbounded, fast-growing θ such as the exponential).
    cap : float
        Extrapolation point for unbounded generators.
    """
    theta = facts(pen).generator
    if extrapolate and theta is not None:
        b = float(theta.upper)
        new = None
        if math.isfinite(b):
            new = extrapolated(theta, 0.5 * b)
        else:
            with np.errstate(all="ignore"):
                fast = float(theta.value(50.0)) > 1e15
            if fast:
                new = extrapolated(theta, cap)
        if new is not None:
            pen = pen.with_generator(new, doc=f"{pen.doc} [safeguarded: {new.doc}]")
    return safeguarded(pen)
