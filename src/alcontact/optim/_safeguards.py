"""Safeguarded forms of the MET 1 / MET 2 penalties used inside the AL subproblems.

Two standard modifications of a generator θ (Definition 5.3), applied by
:func:`safeguard_penalty` to the ``Met1``/``Met2`` penalties of
:mod:`alcontact.penalties` (the registry objects themselves are not changed):

- **Quadratic extrapolation** beyond a point :math:`t_0` (Ben-Tal & Zibulevsky,
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

- **Matioli's safeguard** for generators without property (d) (θ' becomes
  negative, e.g. the quadratic (5.27)): θ is extended by its minimum left of the
  point :math:`y_0` where :math:`\\theta'(y_0) = 0`; for (5.27)
  :math:`\\theta'(y) = \\max(0, y + 1)`, so the updated multipliers stay
  non-negative (and inactive constraints get exactly zero multipliers).
"""

from __future__ import annotations

import math

import numpy as np

from ..penalties import Met1, Met2, Theta

__all__ = ["safeguard_penalty", "extrapolated", "matioli_safeguard"]


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


def _zero_of_derivative(theta) -> float | None:
    """Point ``y0 < 0`` with ``θ'(y0) = 0`` (None if θ' > 0 on (-1e8, 0])."""
    lo, hi = -1.0, 0.0
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


def matioli_safeguard(theta) -> Theta:
    """θ extended by its minimum left of the zero of θ' (θ' -> max(0, θ'))."""
    y0 = _zero_of_derivative(theta)
    if y0 is None:
        return theta
    v0 = float(theta.value(y0))

    def f(y):
        return np.where(y < y0, v0, theta.value(np.maximum(y, y0)))

    def df(y):
        return np.where(y < y0, 0.0, np.maximum(theta.derivative(np.maximum(y, y0)), 0.0))

    def d2f(y):
        return np.where(y < y0, 0.0, theta.second_derivative(np.maximum(y, y0)))

    sat = (set(theta.satisfies) - {"b"}) | {"d"}  # theta' -> 0, but no longer strictly convex
    return Theta(f"{theta.name}+", f, df, d2f, upper=float(theta.upper),
                 satisfies=frozenset(sat),
                 doc=f"{getattr(theta, 'doc', theta.name)}, Matioli's safeguard: constant "
                     f"minimum for y < {y0:g}")


def safeguard_penalty(pen, *, extrapolate: bool, cap: float):
    """The penalty used in the subproblems: MET penalties with the safeguards above.

    Parameters
    ----------
    pen : penalty
        A penalty from :func:`alcontact.penalties.make`; only ``Met1``/``Met2`` are
        modified, others are returned unchanged.
    extrapolate : bool
        Quadratic extrapolation beyond half the domain bound (bounded θ) or beyond
        ``cap`` (unbounded, fast-growing θ such as the exponential).
    cap : float
        Extrapolation point for unbounded generators.
    """
    if not isinstance(pen, (Met1, Met2)):
        return pen
    theta = pen.theta
    changed = False
    if "d" not in theta.satisfies:
        theta = matioli_safeguard(theta)
        changed = theta is not pen.theta
    if extrapolate:
        b = float(theta.upper)
        if math.isfinite(b):
            theta, changed = extrapolated(theta, 0.5 * b), True
        else:
            with np.errstate(all="ignore"):
                fast = float(theta.value(50.0)) > 1e15
            if fast:
                theta, changed = extrapolated(theta, cap), True
    if not changed:
        return pen
    return type(pen)(theta, name=pen.name, doc=f"{pen.doc} [safeguarded: {theta.doc}]")
