r"""Second-order forward differentiation of small local kernels (value, gradient, Hessian).

A :class:`Jet` holds, for ``P`` independent evaluations of one scalar quantity :math:`q`
depending on ``n`` local variables :math:`z`, the value :math:`q`, the gradient
:math:`\partial q/\partial z` and (optionally) the Hessian :math:`\partial^2 q/\partial z^2`.
Sums, products, quotients and square roots propagate them by the chain rule,

.. math::

    \nabla(ab) = a\nabla b + b\nabla a, \qquad
    \nabla^2(ab) = a\nabla^2 b + b\nabla^2 a + \nabla a\,\nabla b^T + \nabla b\,\nabla a^T, \\
    \nabla f(a) = f'(a)\nabla a, \qquad \nabla^2 f(a) = f'(a)\nabla^2 a + f''(a)\,\nabla a\,\nabla a^T,

so a kernel written once on jets gives its exact first and second derivatives (no finite
differences, no truncation). The mortar gap at the current configuration
(:mod:`alcontact.contact.kinematics._mortar_current`) uses it for the segment-to-segment
integrals of one slave and one master segment (12 local coordinates) and for the nodal gap
of the integrated quantities (7 local values), whose derivatives the chain rule then
assembles into the constraint rows and the curvature of the Newton matrix.
"""

from __future__ import annotations

import numpy as np


class Jet:
    """``P`` values of a scalar with gradients ``(P, n)`` and Hessians ``(P, n, n)`` (``None``: first order only).

    Examples
    --------
    >>> import numpy as np
    >>> x, y = Jet.variables(np.array([[3.0, 4.0]]), hessian=True)
    >>> r = (x * x + y * y).sqrt()
    >>> r.v, r.g.round(3).tolist(), r.h[0].round(3).tolist()
    (array([5.]), [[0.6, 0.8]], [[0.128, -0.096], [-0.096, 0.072]])
    """

    __slots__ = ("v", "g", "h")

    def __init__(self, v: np.ndarray, g: np.ndarray, h: np.ndarray | None):
        self.v, self.g, self.h = v, g, h

    @staticmethod
    def variables(values: np.ndarray, *, hessian: bool) -> list["Jet"]:
        """The ``n`` columns of ``values`` (``(P, n)``) as independent variables."""
        values = np.asarray(values, dtype=float)
        p, n = values.shape
        eye = np.eye(n)
        out = []
        for i in range(n):
            g = np.broadcast_to(eye[i], (p, n)).copy()
            out.append(Jet(values[:, i].copy(), g, np.zeros((p, n, n)) if hessian else None))
        return out

    @staticmethod
    def constant(value, like: "Jet") -> "Jet":
        """A quantity that does not depend on the variables (shapes of ``like``)."""
        v = np.broadcast_to(np.asarray(value, dtype=float), like.v.shape).copy()
        return Jet(v, np.zeros_like(like.g), None if like.h is None else np.zeros_like(like.h))

    # ------------------------------------------------------------------ arithmetic
    def _lift(self, other) -> "Jet":
        return other if isinstance(other, Jet) else Jet.constant(other, self)

    def __add__(self, other):
        if not isinstance(other, Jet):
            return Jet(self.v + other, self.g, self.h)
        h = None if self.h is None else self.h + other.h
        return Jet(self.v + other.v, self.g + other.g, h)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, -self.g, None if self.h is None else -self.h)

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        if not isinstance(other, Jet):
            c = np.asarray(other, dtype=float)
            return Jet(self.v * c, self.g * c[..., None], None if self.h is None else self.h * c[..., None, None])
        a, b = self, other
        g = a.g * b.v[:, None] + b.g * a.v[:, None]
        h = None
        if a.h is not None:
            outer = a.g[:, :, None] * b.g[:, None, :]
            h = a.h * b.v[:, None, None] + b.h * a.v[:, None, None] + outer + np.swapaxes(outer, 1, 2)
        return Jet(a.v * b.v, g, h)

    __rmul__ = __mul__

    def _apply(self, f, df, d2f) -> "Jet":
        """``f(self)`` from the values of ``f, f', f''`` at ``self.v``."""
        g = self.g * df[:, None]
        h = None
        if self.h is not None:
            h = self.h * df[:, None, None] + d2f[:, None, None] * (self.g[:, :, None] * self.g[:, None, :])
        return Jet(f, g, h)

    def reciprocal(self) -> "Jet":
        r""":math:`1/q`."""
        r = 1.0 / self.v
        return self._apply(r, -r * r, 2.0 * r * r * r)

    def __truediv__(self, other):
        if not isinstance(other, Jet):
            return self * (1.0 / np.asarray(other, dtype=float))
        return self * other.reciprocal()

    def __rtruediv__(self, other):
        return self.reciprocal() * other

    def sqrt(self) -> "Jet":
        r""":math:`\sqrt q` (``q > 0``)."""
        s = np.sqrt(self.v)
        return self._apply(s, 0.5 / s, -0.25 / (s * self.v))

    @staticmethod
    def where(mask: np.ndarray, a: "Jet", b: "Jet") -> "Jet":
        """``a`` where ``mask``, else ``b`` (a branch chosen by the values: its derivatives are the branch's)."""
        m = np.asarray(mask, dtype=bool)
        h = None if a.h is None else np.where(m[:, None, None], a.h, b.h)
        return Jet(np.where(m, a.v, b.v), np.where(m[:, None], a.g, b.g), h)
