r"""Hock-Schittkowski test problems with inequality constraints.

Transcribed from

    W. Hock and K. Schittkowski, *Test Examples for Nonlinear Programming Codes*,
    Lecture Notes in Economics and Mathematical Systems 187, Springer, 1981,

and K. Schittkowski, *An updated set of 306 test problems for nonlinear programming
with validated optimal solutions - user's guide*, Report, University of Bayreuth, 2009
(same numbering). Every problem below has at least one general inequality constraint
(some also have equalities and bounds). The collection writes

.. math::

    \min_x f(x) \quad\text{s.t.}\quad g_j(x) \ge 0,\; h_k(x) = 0,\; l \le x \le u,

and the problems keep that form: each :class:`HSProblem` carries SciPy constraint
objects (:class:`~scipy.optimize.NonlinearConstraint` with exact ``jac`` and
``hess(x, v)``, :class:`~scipy.optimize.LinearConstraint`, :class:`~scipy.optimize.Bounds`)
so that ``scipy.optimize.minimize(**p.minimize_kwargs())`` and
``alcontact.optim.minimize(**p.minimize_kwargs(), method="al")`` run unchanged. The
engine, not the problem, converts to the ``g(x) <= 0`` convention of the dissertation.

Derivatives are exact. Polynomial (and posynomial, real exponents) parts are written
the way the book prints them, with :class:`_Poly` variables; their gradients and
Hessians are the exact derivatives of the monomials, evaluated in one vectorized pass.
The few non-polynomial pieces (``exp``, ``sin``, ``sqrt``, quotients) go through the
chain, product and quotient rules in :class:`_Smooth` nodes.

Example
-------
>>> from scipy.optimize import minimize
>>> from alcontact.problems.hock_schittkowski import get
>>> p = get(43)
>>> res = minimize(**p.minimize_kwargs(), method="trust-constr")
>>> bool(abs(res.fun - p.f_star) < 1e-6 * max(1.0, abs(p.f_star)))
True
"""

from __future__ import annotations

import abc
import functools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import Bounds, LinearConstraint, NonlinearConstraint

from alcontact.errors import UnknownNameError

__all__ = ["HSProblem", "problems", "get", "numbers", "max_violation", "SOURCE"]

SOURCE = (
    "W. Hock and K. Schittkowski, Test Examples for Nonlinear Programming Codes, "
    "Lecture Notes in Economics and Mathematical Systems 187, Springer, 1981"
)


# --------------------------------------------------------------------------------------
# Exact derivatives: polynomials with real exponents, and a few smooth compositions
# --------------------------------------------------------------------------------------


class _Smooth(abc.ABC):
    """A twice differentiable scalar function of x with value, gradient and Hessian."""

    n: int

    @abc.abstractmethod
    def vgh(self, x: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """Value, gradient and Hessian at ``x``."""

    # arithmetic builds expression nodes; polynomials stay polynomials (see _Poly)
    def __add__(self, other):
        return _Sum(self, _as_smooth(other, self.n))

    __radd__ = __add__

    def __sub__(self, other):
        return _Sum(self, -1.0 * _as_smooth(other, self.n))

    def __rsub__(self, other):
        return _Sum(_as_smooth(other, self.n), -1.0 * self)

    def __neg__(self):
        return -1.0 * self

    def __mul__(self, other):
        if isinstance(other, (int, float)):
            return _Scaled(float(other), self)
        return _Product(self, _as_smooth(other, self.n))

    __rmul__ = __mul__

    def __truediv__(self, other):
        if isinstance(other, (int, float)):
            return _Scaled(1.0 / other, self)
        return _Product(self, _Compose(_RECIPROCAL, _as_smooth(other, self.n)))

    def __rtruediv__(self, other):
        return _Product(_as_smooth(other, self.n), _Compose(_RECIPROCAL, self))

    def __pow__(self, k):
        k = float(k)
        return _Compose((lambda v: v**k, lambda v: k * v ** (k - 1), lambda v: k * (k - 1) * v ** (k - 2)), self)


def _as_smooth(obj, n: int) -> _Smooth:
    if isinstance(obj, _Smooth):
        return obj
    return _Poly.constant(n, float(obj))


class _Sum(_Smooth):
    def __init__(self, a: _Smooth, b: _Smooth):
        self.n, self.a, self.b = a.n, a, b

    def vgh(self, x):
        va, ga, ha = self.a.vgh(x)
        vb, gb, hb = self.b.vgh(x)
        return va + vb, ga + gb, ha + hb


class _Scaled(_Smooth):
    def __init__(self, c: float, a: _Smooth):
        self.n, self.c, self.a = a.n, c, a

    def vgh(self, x):
        v, g, h = self.a.vgh(x)
        return self.c * v, self.c * g, self.c * h


class _Product(_Smooth):
    def __init__(self, a: _Smooth, b: _Smooth):
        self.n, self.a, self.b = a.n, a, b

    def vgh(self, x):
        va, ga, ha = self.a.vgh(x)
        vb, gb, hb = self.b.vgh(x)
        outer = np.outer(ga, gb)
        return va * vb, va * gb + vb * ga, va * hb + vb * ha + outer + outer.T


class _Compose(_Smooth):
    """phi(inner(x)) with phi given as (phi, phi', phi'')."""

    def __init__(self, phi, inner: _Smooth):
        self.n, self.phi, self.inner = inner.n, phi, inner

    def vgh(self, x):
        v, g, h = self.inner.vgh(x)
        p0, p1, p2 = (float(fn(v)) for fn in self.phi)
        return p0, p1 * g, p1 * h + p2 * np.outer(g, g)


_RECIPROCAL = (lambda v: 1.0 / v, lambda v: -1.0 / v**2, lambda v: 2.0 / v**3)
_EXP = (math.exp, math.exp, math.exp)
_SIN = (math.sin, math.cos, lambda v: -math.sin(v))
_SQRT = (math.sqrt, lambda v: 0.5 / math.sqrt(v), lambda v: -0.25 / v**1.5)


def _exp(a: _Smooth) -> _Smooth:
    return _Compose(_EXP, a)


def _sin(a: _Smooth) -> _Smooth:
    return _Compose(_SIN, a)


def _sqrt(a: _Smooth) -> _Smooth:
    return _Compose(_SQRT, a)


class _Poly(_Smooth):
    r"""Sum of monomials :math:`c \prod_i x_i^{p_i}` with real exponents :math:`p_i`.

    Closed under ``+``, ``-``, ``*``, non-negative integer powers and, for a single
    monomial, real powers and division. Anything else falls back to :class:`_Smooth`.
    """

    def __init__(self, n: int, terms: dict[tuple[float, ...], float]):
        self.n = n
        self.terms = {e: c for e, c in terms.items() if c != 0.0}

    @classmethod
    def constant(cls, n: int, c: float) -> _Poly:
        return cls(n, {(0.0,) * n: float(c)})

    @classmethod
    def variable(cls, n: int, i: int) -> _Poly:
        e = [0.0] * n
        e[i] = 1.0
        return cls(n, {tuple(e): 1.0})

    def _coerce(self, other):
        if isinstance(other, _Poly):
            return other
        if isinstance(other, (int, float)):
            return _Poly.constant(self.n, other)
        return None

    def __add__(self, other):
        o = self._coerce(other)
        if o is None:
            return _Smooth.__add__(self, other)
        terms = dict(self.terms)
        for e, c in o.terms.items():
            terms[e] = terms.get(e, 0.0) + c
        return _Poly(self.n, terms)

    __radd__ = __add__

    def __neg__(self):
        return _Poly(self.n, {e: -c for e, c in self.terms.items()})

    def __sub__(self, other):
        o = self._coerce(other)
        return self + (-o) if o is not None else _Smooth.__sub__(self, other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        o = self._coerce(other)
        if o is None:
            return _Smooth.__mul__(self, other)
        terms: dict[tuple[float, ...], float] = {}
        for e1, c1 in self.terms.items():
            for e2, c2 in o.terms.items():
                e = tuple(a + b for a, b in zip(e1, e2))
                terms[e] = terms.get(e, 0.0) + c1 * c2
        return _Poly(self.n, terms)

    __rmul__ = __mul__

    def __pow__(self, k):
        if isinstance(k, int) and k >= 0:
            out = _Poly.constant(self.n, 1.0)
            for _ in range(k):
                out = out * self
            return out
        if len(self.terms) == 1:
            ((e, c),) = self.terms.items()
            return _Poly(self.n, {tuple(a * k for a in e): c**k})
        return _Smooth.__pow__(self, k)

    def __truediv__(self, other):
        if isinstance(other, (int, float)):
            return self * (1.0 / other)
        if isinstance(other, _Poly) and len(other.terms) == 1:
            return self * other**-1.0
        return _Smooth.__truediv__(self, other)

    def __rtruediv__(self, other):
        if len(self.terms) == 1:
            return other * self**-1.0
        return _Smooth.__rtruediv__(self, other)

    def is_linear(self) -> bool:
        return all(sum(e) <= 1.0 and all(a in (0.0, 1.0) for a in e) for e in self.terms)

    def linear_part(self) -> tuple[np.ndarray, float]:
        """(a, c) with p(x) = a.x + c; only for linear polynomials."""
        a, c = np.zeros(self.n), 0.0
        for e, coef in self.terms.items():
            if sum(e) == 0.0:
                c += coef
            else:
                a[e.index(1.0)] += coef
        return a, c

    @functools.cached_property
    def _block(self) -> _PolyBlock:
        return _PolyBlock([self], self.n)

    def vgh(self, x):
        b = self._block
        return float(b.value(x)[0]), b.jac(x)[0], b.hess(x, np.ones(1))


class _PolyBlock:
    """Vectorized value, Jacobian and weighted Hessian of m polynomials."""

    def __init__(self, polys: Sequence[_Poly], n: int):
        self.m, self.n = len(polys), n
        val, grad, hess = [], [], []
        for k, p in enumerate(polys):
            for e, c in p.terms.items():
                val.append((k, c, e))
                for i in range(n):
                    if e[i] == 0.0:
                        continue
                    ci, ei = c * e[i], list(e)
                    ei[i] -= 1.0
                    grad.append((k, i, ci, tuple(ei)))
                    for j in range(i, n):
                        if ei[j] == 0.0:
                            continue
                        eij = list(ei)
                        eij[j] -= 1.0
                        hess.append((k, i, j, ci * ei[j], tuple(eij)))
        self._val = self._pack(val, 1)
        self._grad = self._pack(grad, 2)
        self._hess = self._pack(hess, 3)

    def _pack(self, rows, nidx):
        if not rows:
            return [np.zeros(0, int)] * nidx + [np.zeros(0), np.zeros((0, self.n))]
        cols = list(zip(*rows))
        idx = [np.asarray(c, dtype=int) for c in cols[:nidx]]
        return idx + [np.asarray(cols[nidx], dtype=float), np.asarray(cols[nidx + 1], dtype=float)]

    @staticmethod
    def _monomials(x, coef, expo):
        return coef * np.prod(np.power(x[None, :], expo), axis=1)

    def value(self, x):
        k, c, e = self._val
        return np.bincount(k, weights=self._monomials(x, c, e), minlength=self.m).astype(float)

    def jac(self, x):
        k, i, c, e = self._grad
        out = np.zeros((self.m, self.n))
        np.add.at(out, (k, i), self._monomials(x, c, e))
        return out

    def hess(self, x, v):
        k, i, j, c, e = self._hess
        upper = np.zeros((self.n, self.n))
        np.add.at(upper, (i, j), np.asarray(v, dtype=float)[k] * self._monomials(x, c, e))
        return upper + np.triu(upper, 1).T


class _ConstraintBlock:
    """Stacked nonlinear constraints: polynomials vectorized, other rows one by one."""

    def __init__(self, exprs: Sequence[_Smooth], n: int):
        self.n, self.m = n, len(exprs)
        self.poly_rows = [r for r, e in enumerate(exprs) if isinstance(e, _Poly)]
        self.other_rows = [r for r, e in enumerate(exprs) if not isinstance(e, _Poly)]
        self.block = _PolyBlock([exprs[r] for r in self.poly_rows], n)
        self.others = [exprs[r] for r in self.other_rows]

    def fun(self, x):
        x = np.asarray(x, dtype=float)
        out = np.empty(self.m)
        out[self.poly_rows] = self.block.value(x)
        for r, e in zip(self.other_rows, self.others):
            out[r] = e.vgh(x)[0]
        return out

    def jac(self, x):
        x = np.asarray(x, dtype=float)
        out = np.empty((self.m, self.n))
        out[self.poly_rows] = self.block.jac(x)
        for r, e in zip(self.other_rows, self.others):
            out[r] = e.vgh(x)[1]
        return out

    def hess(self, x, v):
        x, v = np.asarray(x, dtype=float), np.asarray(v, dtype=float)
        out = self.block.hess(x, v[self.poly_rows])
        for r, e in zip(self.other_rows, self.others):
            if v[r] != 0.0:
                out = out + v[r] * e.vgh(x)[2]
        return out


class _Objective:
    """fun/jac/hess callables in SciPy's signature around one expression."""

    def __init__(self, expr: _Smooth):
        self.expr = expr
        self.block = expr._block if isinstance(expr, _Poly) else None

    def fun(self, x):
        x = np.asarray(x, dtype=float)
        if self.block is not None:
            return float(self.block.value(x)[0])
        return float(self.expr.vgh(x)[0])

    def jac(self, x):
        x = np.asarray(x, dtype=float)
        if self.block is not None:
            return self.block.jac(x)[0]
        return self.expr.vgh(x)[1]

    def hess(self, x):
        x = np.asarray(x, dtype=float)
        if self.block is not None:
            return self.block.hess(x, np.ones(1))
        return self.expr.vgh(x)[2]


# --------------------------------------------------------------------------------------
# The problem object
# --------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class HSProblem:
    """One Hock-Schittkowski problem: data plus callables, in SciPy's conventions.

    Attributes
    ----------
    number : int
        Problem number in the collection (``get(number)`` returns it).
    x0 : ndarray, shape (n,)
        The collection's starting point (not necessarily feasible).
    fun, jac, hess : callable
        Objective ``f(x) -> float``, gradient ``(n,)`` and Hessian ``(n, n)``.
    constraints : tuple
        SciPy constraint objects, ``lb <= c(x) <= ub`` (the book's ``g(x) >= 0`` is
        ``lb = 0, ub = inf``; equalities have ``lb == ub``).
    bounds : scipy.optimize.Bounds or None
        Simple bounds ``l <= x <= u``.
    f_star : float
        Optimal value reported in the collection.
    x_star : ndarray or None
        A minimizer (the reported one, polished to full precision).
    doc : str
        Formulation and source.
    """

    number: int
    x0: np.ndarray
    fun: Callable[[np.ndarray], float]
    jac: Callable[[np.ndarray], np.ndarray]
    hess: Callable[[np.ndarray], np.ndarray]
    constraints: tuple
    bounds: Bounds | None
    f_star: float
    x_star: np.ndarray | None = None
    doc: str = field(default="", repr=False)
    n_eq: int = 0
    n_ineq: int = 0

    @property
    def n(self) -> int:
        return int(self.x0.size)

    @property
    def name(self) -> str:
        return f"hs{self.number:03d}"

    def minimize_kwargs(self, *, with_hess: bool = True) -> dict:
        """Keyword arguments for a SciPy-style ``minimize`` (a fresh copy of ``x0``)."""
        kw = dict(
            fun=self.fun,
            x0=self.x0.copy(),
            jac=self.jac,
            constraints=list(self.constraints),
            bounds=self.bounds,
        )
        if with_hess:
            kw["hess"] = self.hess
        return kw

    def max_violation(self, x) -> float:
        """Largest violation of any constraint or bound at ``x`` (0 when feasible)."""
        return max_violation(x, self.constraints, self.bounds)

    def is_solved(self, fun: float, x, *, rtol: float = 1e-6, feas_tol: float = 1e-6) -> bool:
        """``|f - f*| <= rtol * max(1, |f*|)`` and ``max_violation(x) <= feas_tol``."""
        ok_f = abs(float(fun) - self.f_star) <= rtol * max(1.0, abs(self.f_star))
        return bool(ok_f and self.max_violation(x) <= feas_tol)


def max_violation(x, constraints: Iterable = (), bounds: Bounds | None = None) -> float:
    """Largest violation of SciPy-style constraints and bounds at ``x``."""
    x = np.asarray(x, dtype=float)
    worst = 0.0
    if bounds is not None:
        worst = max(worst, float(np.max(np.asarray(bounds.lb) - x, initial=0.0)))
        worst = max(worst, float(np.max(x - np.asarray(bounds.ub), initial=0.0)))
    for con in constraints:
        if isinstance(con, LinearConstraint):
            c = np.atleast_1d(np.asarray(con.A, dtype=float) @ x)
        else:
            c = np.atleast_1d(np.asarray(con.fun(x), dtype=float))
        lb = np.broadcast_to(np.asarray(con.lb, dtype=float), c.shape)
        ub = np.broadcast_to(np.asarray(con.ub, dtype=float), c.shape)
        worst = max(worst, float(np.max(lb - c, initial=0.0)), float(np.max(c - ub, initial=0.0)))
    return worst


# --------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------

_INF = math.inf
_BUILDERS: dict[int, Callable[[], HSProblem]] = {}


def _ge(g, lo: float = 0.0):
    """The collection's ``g(x) >= 0``."""
    return (g, lo, _INF)


def _eq(h):
    """The collection's ``h(x) = 0``."""
    return (h, 0.0, 0.0)


def _range(lo: float, g, hi: float):
    return (g, lo, hi)


def _assemble(number, doc, x0, f, cons, lb, ub, f_star, x_star) -> HSProblem:
    n = len(x0)
    lin_rows, nl_exprs, nl_lb, nl_ub = [], [], [], []
    n_eq = n_ineq = 0
    for expr, lo, hi in cons:
        expr = _as_smooth(expr, n)
        if lo == hi:
            n_eq += 1
        else:
            n_ineq += (lo > -_INF) + (hi < _INF)
        if isinstance(expr, _Poly) and expr.is_linear():
            a, c = expr.linear_part()
            lin_rows.append((a, lo - c, hi - c))
        else:
            nl_exprs.append(expr)
            nl_lb.append(lo)
            nl_ub.append(hi)
    constraints = []
    if lin_rows:
        A = np.array([r[0] for r in lin_rows])
        constraints.append(LinearConstraint(A, [r[1] for r in lin_rows], [r[2] for r in lin_rows]))
    if nl_exprs:
        blk = _ConstraintBlock(nl_exprs, n)
        constraints.append(NonlinearConstraint(blk.fun, nl_lb, nl_ub, jac=blk.jac, hess=blk.hess))
    bounds = None
    if lb is not None or ub is not None:
        lo = np.array([-_INF if v is None else v for v in (lb or [None] * n)], dtype=float)
        hi = np.array([_INF if v is None else v for v in (ub or [None] * n)], dtype=float)
        bounds = Bounds(lo, hi)
    obj = _Objective(_as_smooth(f, n))
    return HSProblem(
        number=number,
        x0=np.asarray(x0, dtype=float),
        fun=obj.fun,
        jac=obj.jac,
        hess=obj.hess,
        constraints=tuple(constraints),
        bounds=bounds,
        f_star=float(f_star),
        x_star=None if x_star is None else np.asarray(x_star, dtype=float),
        doc=" ".join((doc or "").split()),
        n_eq=n_eq,
        n_ineq=n_ineq,
    )


def _hs(number: int, *, x0, f_star, x_star=None, lb=None, ub=None):
    """Register a builder ``build(x1, ..., xn) -> (f, constraints)``."""

    def deco(build):
        def make() -> HSProblem:
            n = len(x0)
            xs = [_Poly.variable(n, i) for i in range(n)]
            f, cons = build(*xs)
            return _assemble(number, build.__doc__, x0, f, cons, lb, ub, f_star, x_star)

        _BUILDERS[number] = make
        return build

    return deco


def numbers() -> list[int]:
    """Numbers of the problems in this selection, ascending."""
    return sorted(_BUILDERS)


@functools.lru_cache(maxsize=None)
def get(number: int) -> HSProblem:
    """Problem ``number`` of the collection.

    Raises
    ------
    UnknownNameError
        If the number is not in this selection (the message lists the ones that are).
    """
    try:
        make = _BUILDERS[int(number)]
    except (KeyError, ValueError, TypeError):
        raise UnknownNameError("Hock-Schittkowski problem", str(number), [str(k) for k in numbers()]) from None
    return make()


def problems() -> tuple[HSProblem, ...]:
    """All problems of this selection, by ascending number."""
    return tuple(get(k) for k in numbers())


# --------------------------------------------------------------------------------------
# The problems. Docstrings: formulation as printed in the collection (g >= 0).
# --------------------------------------------------------------------------------------

_SQ3 = math.sqrt(3.0)


@_hs(10, x0=[-10, 10], f_star=-1.0, x_star=[0, 1])
def _hs10(x1, x2):
    """HS10 (Biggs): min x1 - x2 s.t. -3x1^2 + 2x1x2 - x2^2 + 1 >= 0."""
    return x1 - x2, [_ge(-3 * x1**2 + 2 * x1 * x2 - x2**2 + 1)]


@_hs(11, x0=[4.9, 0.1], f_star=-8.498464223, x_star=[1.23477282505, 1.52466392949])
def _hs11(x1, x2):
    """HS11 (Biggs): min (x1-5)^2 + x2^2 - 25 s.t. -x1^2 + x2 >= 0."""
    return (x1 - 5) ** 2 + x2**2 - 25, [_ge(-(x1**2) + x2)]


@_hs(12, x0=[0, 0], f_star=-30.0, x_star=[2, 3])
def _hs12(x1, x2):
    """HS12 (Mine et al.): min 0.5x1^2 + x2^2 - x1x2 - 7x1 - 7x2 s.t. 25 - 4x1^2 - x2^2 >= 0."""
    return 0.5 * x1**2 + x2**2 - x1 * x2 - 7 * x1 - 7 * x2, [_ge(25 - 4 * x1**2 - x2**2)]


@_hs(
    14,
    x0=[2, 2],
    f_star=9 - 2.875 * math.sqrt(7),
    x_star=[0.5 * (math.sqrt(7) - 1), 0.25 * (math.sqrt(7) + 1)],
)
def _hs14(x1, x2):
    """HS14 (Bracken-McCormick): min (x1-2)^2 + (x2-1)^2 s.t. -x1^2/4 - x2^2 + 1 >= 0,
    x1 - 2x2 + 1 = 0."""
    return (x1 - 2) ** 2 + (x2 - 1) ** 2, [_ge(-0.25 * x1**2 - x2**2 + 1), _eq(x1 - 2 * x2 + 1)]


def _rosenbrock(x1, x2):
    return 100 * (x2 - x1**2) ** 2 + (1 - x1) ** 2


@_hs(15, x0=[-2, 1], f_star=306.5, x_star=[0.5, 2], ub=[0.5, None])
def _hs15(x1, x2):
    """HS15 (Betts): min 100(x2-x1^2)^2 + (1-x1)^2 s.t. x1x2 - 1 >= 0, x1 + x2^2 >= 0,
    x1 <= 0.5."""
    return _rosenbrock(x1, x2), [_ge(x1 * x2 - 1), _ge(x1 + x2**2)]


@_hs(16, x0=[-2, 1], f_star=0.25, x_star=[0.5, 0.25], lb=[-0.5, None], ub=[0.5, 1])
def _hs16(x1, x2):
    """HS16 (Betts): min 100(x2-x1^2)^2 + (1-x1)^2 s.t. x1 + x2^2 >= 0, x1^2 + x2 >= 0,
    -0.5 <= x1 <= 0.5, x2 <= 1."""
    return _rosenbrock(x1, x2), [_ge(x1 + x2**2), _ge(x1**2 + x2)]


@_hs(17, x0=[-2, 1], f_star=1.0, x_star=[0, 0], lb=[-0.5, None], ub=[0.5, 1])
def _hs17(x1, x2):
    """HS17 (Betts): min 100(x2-x1^2)^2 + (1-x1)^2 s.t. x2^2 - x1 >= 0, x1^2 - x2 >= 0,
    -0.5 <= x1 <= 0.5, x2 <= 1."""
    return _rosenbrock(x1, x2), [_ge(x2**2 - x1), _ge(x1**2 - x2)]


@_hs(
    18,
    x0=[2, 2],
    f_star=5.0,
    x_star=[math.sqrt(250), math.sqrt(2.5)],
    lb=[2, 0],
    ub=[50, 50],
)
def _hs18(x1, x2):
    """HS18 (Betts): min 0.01x1^2 + x2^2 s.t. x1x2 - 25 >= 0, x1^2 + x2^2 - 25 >= 0,
    2 <= x1 <= 50, 0 <= x2 <= 50."""
    return 0.01 * x1**2 + x2**2, [_ge(x1 * x2 - 25), _ge(x1**2 + x2**2 - 25)]


@_hs(
    19,
    x0=[20.1, 5.84],
    f_star=-6961.81381,
    x_star=[14.095, 5 - math.sqrt(100 - 9.095**2)],
    lb=[13, 0],
    ub=[100, 100],
)
def _hs19(x1, x2):
    """HS19 (Betts, Gould): min (x1-10)^3 + (x2-20)^3 s.t. (x1-5)^2 + (x2-5)^2 - 100 >= 0,
    -(x2-5)^2 - (x1-6)^2 + 82.81 >= 0, 13 <= x1 <= 100, 0 <= x2 <= 100."""
    return (x1 - 10) ** 3 + (x2 - 20) ** 3, [
        _ge((x1 - 5) ** 2 + (x2 - 5) ** 2 - 100),
        _ge(-((x2 - 5) ** 2) - (x1 - 6) ** 2 + 82.81),
    ]


@_hs(20, x0=[-2, 1], f_star=81.5 - 25 * _SQ3, x_star=[0.5, _SQ3 / 2], lb=[-0.5, None], ub=[0.5, None])
def _hs20(x1, x2):
    """HS20 (Betts): min 100(x2-x1^2)^2 + (1-x1)^2 s.t. x1 + x2^2 >= 0, x1^2 + x2 >= 0,
    x1^2 + x2^2 - 1 >= 0, -0.5 <= x1 <= 0.5."""
    return _rosenbrock(x1, x2), [_ge(x1 + x2**2), _ge(x1**2 + x2), _ge(x1**2 + x2**2 - 1)]


@_hs(21, x0=[-1, -1], f_star=-99.96, x_star=[2, 0], lb=[2, -50], ub=[50, 50])
def _hs21(x1, x2):
    """HS21 (Betts): min 0.01x1^2 + x2^2 - 100 s.t. 10x1 - x2 - 10 >= 0, 2 <= x1 <= 50,
    -50 <= x2 <= 50."""
    return 0.01 * x1**2 + x2**2 - 100, [_ge(10 * x1 - x2 - 10)]


@_hs(22, x0=[2, 2], f_star=1.0, x_star=[1, 1])
def _hs22(x1, x2):
    """HS22 (Bracken-McCormick): min (x1-2)^2 + (x2-1)^2 s.t. -x1 - x2 + 2 >= 0,
    -x1^2 + x2 >= 0."""
    return (x1 - 2) ** 2 + (x2 - 1) ** 2, [_ge(-x1 - x2 + 2), _ge(-(x1**2) + x2)]


@_hs(23, x0=[3, 1], f_star=2.0, x_star=[1, 1], lb=[-50, -50], ub=[50, 50])
def _hs23(x1, x2):
    """HS23 (Betts): min x1^2 + x2^2 s.t. x1 + x2 - 1 >= 0, x1^2 + x2^2 - 1 >= 0,
    9x1^2 + x2^2 - 9 >= 0, x1^2 - x2 >= 0, x2^2 - x1 >= 0, -50 <= x <= 50."""
    return x1**2 + x2**2, [
        _ge(x1 + x2 - 1),
        _ge(x1**2 + x2**2 - 1),
        _ge(9 * x1**2 + x2**2 - 9),
        _ge(x1**2 - x2),
        _ge(x2**2 - x1),
    ]


@_hs(24, x0=[1, 0.5], f_star=-1.0, x_star=[3, _SQ3], lb=[0, 0])
def _hs24(x1, x2):
    """HS24 (Betts, Box): min ((x1-3)^2 - 9) x2^3 / (27 sqrt 3) s.t. x1/sqrt3 - x2 >= 0,
    x1 + sqrt3 x2 >= 0, -x1 - sqrt3 x2 + 6 >= 0, x >= 0."""
    return ((x1 - 3) ** 2 - 9) * x2**3 / (27 * _SQ3), [
        _ge(x1 / _SQ3 - x2),
        _ge(x1 + _SQ3 * x2),
        _ge(-x1 - _SQ3 * x2 + 6),
    ]


@_hs(29, x0=[1, 1, 1], f_star=-16 * math.sqrt(2), x_star=[4, 2 * math.sqrt(2), 2])
def _hs29(x1, x2, x3):
    """HS29 (Biggs): min -x1x2x3 s.t. -x1^2 - 2x2^2 - 4x3^2 + 48 >= 0 (four symmetric
    minimizers)."""
    return -x1 * x2 * x3, [_ge(-(x1**2) - 2 * x2**2 - 4 * x3**2 + 48)]


@_hs(30, x0=[1, 1, 1], f_star=1.0, x_star=[1, 0, 0], lb=[1, -10, -10], ub=[10, 10, 10])
def _hs30(x1, x2, x3):
    """HS30 (Betts): min x1^2 + x2^2 + x3^2 s.t. x1^2 + x2^2 - 1 >= 0, 1 <= x1 <= 10,
    -10 <= x2, x3 <= 10."""
    return x1**2 + x2**2 + x3**2, [_ge(x1**2 + x2**2 - 1)]


@_hs(
    31,
    x0=[1, 1, 1],
    f_star=6.0,
    x_star=[1 / _SQ3, _SQ3, 0],
    lb=[-10, 1, -10],
    ub=[10, 10, 1],
)
def _hs31(x1, x2, x3):
    """HS31 (Betts): min 9x1^2 + x2^2 + 9x3^2 s.t. x1x2 - 1 >= 0, -10 <= x1 <= 10,
    1 <= x2 <= 10, -10 <= x3 <= 1."""
    return 9 * x1**2 + x2**2 + 9 * x3**2, [_ge(x1 * x2 - 1)]


@_hs(32, x0=[0.1, 0.7, 0.2], f_star=1.0, x_star=[0, 0, 1], lb=[0, 0, 0])
def _hs32(x1, x2, x3):
    """HS32 (Evtushenko): min (x1 + 3x2 + x3)^2 + 4(x1-x2)^2 s.t. 6x2 + 4x3 - x1^3 - 3 >= 0,
    1 - x1 - x2 - x3 = 0, x >= 0."""
    return (x1 + 3 * x2 + x3) ** 2 + 4 * (x1 - x2) ** 2, [
        _ge(6 * x2 + 4 * x3 - x1**3 - 3),
        _eq(1 - x1 - x2 - x3),
    ]


@_hs(
    33,
    x0=[0, 0, 3],
    f_star=math.sqrt(2) - 6,
    x_star=[0, math.sqrt(2), math.sqrt(2)],
    lb=[0, 0, 0],
    ub=[None, None, 5],
)
def _hs33(x1, x2, x3):
    """HS33 (Beltrami): min (x1-1)(x1-2)(x1-3) + x3 s.t. x3^2 - x2^2 - x1^2 >= 0,
    x1^2 + x2^2 + x3^2 - 4 >= 0, x >= 0, x3 <= 5."""
    return (x1 - 1) * (x1 - 2) * (x1 - 3) + x3, [
        _ge(x3**2 - x2**2 - x1**2),
        _ge(x1**2 + x2**2 + x3**2 - 4),
    ]


_LN10 = math.log(10.0)


@_hs(
    34,
    x0=[0, 1.05, 2.9],
    f_star=-math.log(_LN10),
    x_star=[math.log(_LN10), _LN10, 10],
    lb=[0, 0, 0],
    ub=[100, 100, 10],
)
def _hs34(x1, x2, x3):
    """HS34 (Eckhardt): min -x1 s.t. x2 - exp(x1) >= 0, x3 - exp(x2) >= 0,
    0 <= x1 <= 100, 0 <= x2 <= 100, 0 <= x3 <= 10."""
    return -x1, [_ge(x2 - _exp(x1)), _ge(x3 - _exp(x2))]


@_hs(35, x0=[0.5, 0.5, 0.5], f_star=1 / 9, x_star=[4 / 3, 7 / 9, 4 / 9], lb=[0, 0, 0])
def _hs35(x1, x2, x3):
    """HS35 (Asaadi, Charalambous): min 9 - 8x1 - 6x2 - 4x3 + 2x1^2 + 2x2^2 + x3^2
    + 2x1x2 + 2x1x3 s.t. 3 - x1 - x2 - 2x3 >= 0, x >= 0."""
    f = 9 - 8 * x1 - 6 * x2 - 4 * x3 + 2 * x1**2 + 2 * x2**2 + x3**2 + 2 * x1 * x2 + 2 * x1 * x3
    return f, [_ge(3 - x1 - x2 - 2 * x3)]


@_hs(36, x0=[10, 10, 10], f_star=-3300.0, x_star=[20, 11, 15], lb=[0, 0, 0], ub=[20, 11, 42])
def _hs36(x1, x2, x3):
    """HS36 (Biggs): min -x1x2x3 s.t. 72 - x1 - 2x2 - 2x3 >= 0, 0 <= x <= (20, 11, 42)."""
    return -x1 * x2 * x3, [_ge(72 - x1 - 2 * x2 - 2 * x3)]


@_hs(37, x0=[10, 10, 10], f_star=-3456.0, x_star=[24, 12, 12], lb=[0, 0, 0], ub=[42, 42, 42])
def _hs37(x1, x2, x3):
    """HS37 (Box): min -x1x2x3 s.t. 72 - x1 - 2x2 - 2x3 >= 0, x1 + 2x2 + 2x3 >= 0,
    0 <= x <= 42."""
    return -x1 * x2 * x3, [_ge(72 - x1 - 2 * x2 - 2 * x3), _ge(x1 + 2 * x2 + 2 * x3)]


@_hs(43, x0=[0, 0, 0, 0], f_star=-44.0, x_star=[0, 1, 2, -1])
def _hs43(x1, x2, x3, x4):
    """HS43 (Rosen-Suzuki): min x1^2 + x2^2 + 2x3^2 + x4^2 - 5x1 - 5x2 - 21x3 + 7x4 s.t.
    8 - x1^2 - x2^2 - x3^2 - x4^2 - x1 + x2 - x3 + x4 >= 0,
    10 - x1^2 - 2x2^2 - x3^2 - 2x4^2 + x1 + x4 >= 0,
    5 - 2x1^2 - x2^2 - x3^2 - 2x1 + x2 + x4 >= 0."""
    f = x1**2 + x2**2 + 2 * x3**2 + x4**2 - 5 * x1 - 5 * x2 - 21 * x3 + 7 * x4
    return f, [
        _ge(8 - x1**2 - x2**2 - x3**2 - x4**2 - x1 + x2 - x3 + x4),
        _ge(10 - x1**2 - 2 * x2**2 - x3**2 - 2 * x4**2 + x1 + x4),
        _ge(5 - 2 * x1**2 - x2**2 - x3**2 - 2 * x1 + x2 + x4),
    ]


@_hs(44, x0=[0, 0, 0, 0], f_star=-15.0, x_star=[0, 3, 0, 4], lb=[0, 0, 0, 0])
def _hs44(x1, x2, x3, x4):
    """HS44 (Konno): min x1 - x2 - x3 - x1x3 + x1x4 + x2x3 - x2x4 s.t. 8 - x1 - 2x2 >= 0,
    12 - 4x1 - x2 >= 0, 12 - 3x1 - 4x2 >= 0, 8 - 2x3 - x4 >= 0, 8 - x3 - 2x4 >= 0,
    5 - x3 - x4 >= 0, x >= 0 (nonconvex, several local minima)."""
    f = x1 - x2 - x3 - x1 * x3 + x1 * x4 + x2 * x3 - x2 * x4
    return f, [
        _ge(8 - x1 - 2 * x2),
        _ge(12 - 4 * x1 - x2),
        _ge(12 - 3 * x1 - 4 * x2),
        _ge(8 - 2 * x3 - x4),
        _ge(8 - x3 - 2 * x4),
        _ge(5 - x3 - x4),
    ]


# Appendix data of HS57: a_i and b_i, i = 1..44.
_HS57_A = np.repeat(
    [8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30, 32, 34, 36, 38, 40, 42],
    [2, 4, 4, 3, 3, 2, 3, 3, 3, 3, 2, 3, 2, 1, 2, 2, 1, 1],
).astype(float)
_HS57_B = np.array(
    [0.49, 0.49, 0.48, 0.47, 0.48, 0.47, 0.46, 0.46, 0.45, 0.43, 0.45, 0.43, 0.43, 0.44, 0.43,
     0.43, 0.46, 0.45, 0.42, 0.42, 0.43, 0.41, 0.41, 0.40, 0.42, 0.40, 0.40, 0.41, 0.40, 0.41,
     0.41, 0.40, 0.40, 0.40, 0.38, 0.41, 0.40, 0.40, 0.41, 0.38, 0.40, 0.40, 0.39, 0.39]
)  # fmt: skip


class _HS57Objective(_Smooth):
    r"""Sum of squares :math:`\sum_i r_i^2`, :math:`r_i = b_i - x_1 - (0.49 - x_1) e^{-x_2 t_i}`,
    :math:`t_i = a_i - 8` (vectorized by hand: 44 residuals)."""

    n = 2

    def vgh(self, x):
        x1, x2 = float(x[0]), float(x[1])
        t = _HS57_A - 8.0
        e = np.exp(-x2 * t)
        r = _HS57_B - x1 - (0.49 - x1) * e
        dr = np.stack([-1.0 + e, (0.49 - x1) * t * e])  # (2, 44)
        d12 = -t * e
        d22 = -(0.49 - x1) * t**2 * e
        g = 2.0 * dr @ r
        H = 2.0 * dr @ dr.T
        H[0, 1] += 2.0 * r @ d12
        H[1, 0] += 2.0 * r @ d12
        H[1, 1] += 2.0 * r @ d22
        return float(r @ r), g, H


@_hs(57, x0=[0.42, 5], f_star=0.02845966972, x_star=[0.419952650766, 1.28484519377], lb=[0.4, -4])
def _hs57(x1, x2):
    """HS57 (Betts, Gould): min sum_{i=1}^{44} (b_i - x1 - (0.49 - x1) exp(-x2 (a_i - 8)))^2
    s.t. 0.49x2 - x1x2 - 0.09 >= 0, x1 >= 0.4, x2 >= -4 (a_i, b_i from the appendix)."""
    return _HS57Objective(), [_ge(0.49 * x2 - x1 * x2 - 0.09)]


@_hs(
    59,
    x0=[90, 10],
    f_star=-7.80278947,
    x_star=[13.5501423236, 51.65997399],
    lb=[0, 0],
    ub=[75, 65],
)
def _hs59(x1, x2):
    """HS59 (Barnes, Himmelblau): min -75.196 + 3.8112x1 + 0.0020567x1^3 - 1.0345e-5x1^4
    + 6.8306x2 - 0.030234x1x2 + 1.28134e-3x2x1^2 + 2.266e-7x1^4x2 - 0.25645x2^2
    + 0.0034604x2^3 - 1.3514e-5x2^4 + 28.106/(x2+1) + 5.2375e-6x1^2x2^2 + 6.3e-8x1^3x2^2
    - 7e-10x1^3x2^3 - 3.405e-4x1x2^2 + 1.6638e-6x1x2^3 + 2.8673exp(0.0005x1x2)
    - 3.5256e-5x1^3x2 - 0.12694x1^2 s.t. x1x2 - 700 >= 0, x2 - x1^2/125 >= 0,
    (x2-50)^2 - 5(x1-55) >= 0, 0 <= x1 <= 75, 0 <= x2 <= 65. The book prints
    f* = -7.802786 at x* = (13.55010424, 51.66018129); the polished minimizer of this
    formulation gives -7.80278947 (they agree to 5e-7 relative)."""
    p = (
        -75.196 + 3.8112 * x1 + 0.0020567 * x1**3 - 1.0345e-5 * x1**4 + 6.8306 * x2
        - 0.030234 * x1 * x2 + 1.28134e-3 * x2 * x1**2 + 2.266e-7 * x1**4 * x2
        - 0.25645 * x2**2 + 0.0034604 * x2**3 - 1.3514e-5 * x2**4
        + 5.2375e-6 * x1**2 * x2**2 + 6.3e-8 * x1**3 * x2**2 - 7e-10 * x1**3 * x2**3
        - 3.405e-4 * x1 * x2**2 + 1.6638e-6 * x1 * x2**3 - 3.5256e-5 * x1**3 * x2
        - 0.12694 * x1**2
    )  # fmt: skip
    f = p + 28.106 / (x2 + 1) + 2.8673 * _exp(0.0005 * x1 * x2)
    return f, [
        _ge(x1 * x2 - 700),
        _ge(x2 - x1**2 / 125),
        _ge((x2 - 50) ** 2 - 5 * (x1 - 55)),
    ]


@_hs(
    64,
    x0=[1, 1, 1],
    f_star=6299.842428,
    x_star=[108.734704988, 85.1262127905, 204.324596604],
    lb=[1e-5, 1e-5, 1e-5],
)
def _hs64(x1, x2, x3):
    """HS64 (Best): min 5x1 + 50000/x1 + 20x2 + 72000/x2 + 10x3 + 144000/x3 s.t.
    1 - 4/x1 - 32/x2 - 120/x3 >= 0, x >= 1e-5."""
    f = 5 * x1 + 50000 / x1 + 20 * x2 + 72000 / x2 + 10 * x3 + 144000 / x3
    return f, [_ge(1 - 4 / x1 - 32 / x2 - 120 / x3)]


@_hs(
    65,
    x0=[-5, 5, 0],
    f_star=0.9535288567,
    x_star=[3.65046172295, 3.65046172295, 4.62041755889],
    lb=[-4.5, -4.5, -5],
    ub=[4.5, 4.5, 5],
)
def _hs65(x1, x2, x3):
    """HS65 (Murtagh-Sargent): min (x1-x2)^2 + (x1+x2-10)^2/9 + (x3-5)^2 s.t.
    48 - x1^2 - x2^2 - x3^2 >= 0, -4.5 <= x1, x2 <= 4.5, -5 <= x3 <= 5."""
    f = (x1 - x2) ** 2 + (x1 + x2 - 10) ** 2 / 9 + (x3 - 5) ** 2
    return f, [_ge(48 - x1**2 - x2**2 - x3**2)]


@_hs(
    66,
    x0=[0, 1.05, 2.9],
    f_star=0.5181632741,
    x_star=[0.184126487788, 1.20216787304, 3.32732232206],
    lb=[0, 0, 0],
    ub=[100, 100, 10],
)
def _hs66(x1, x2, x3):
    """HS66 (Eckhardt): min 0.2x3 - 0.8x1 s.t. x2 - exp(x1) >= 0, x3 - exp(x2) >= 0,
    0 <= x1 <= 100, 0 <= x2 <= 100, 0 <= x3 <= 10."""
    return 0.2 * x3 - 0.8 * x1, [_ge(x2 - _exp(x1)), _ge(x3 - _exp(x2))]


@_hs(
    71,
    x0=[1, 5, 5, 1],
    f_star=17.0140173,
    x_star=[1, 4.74299963726, 3.82114998418, 1.37940829317],
    lb=[1, 1, 1, 1],
    ub=[5, 5, 5, 5],
)
def _hs71(x1, x2, x3, x4):
    """HS71 (Bartholomew-Biggs): min x1x4(x1 + x2 + x3) + x3 s.t. x1x2x3x4 - 25 >= 0,
    x1^2 + x2^2 + x3^2 + x4^2 - 40 = 0, 1 <= x <= 5."""
    f = x1 * x4 * (x1 + x2 + x3) + x3
    return f, [_ge(x1 * x2 * x3 * x4 - 25), _eq(x1**2 + x2**2 + x3**2 + x4**2 - 40)]


@_hs(
    72,
    x0=[1, 1, 1, 1],
    f_star=727.67937,
    x_star=[193.407427272, 179.547076032, 185.018063358, 168.706791127],
    lb=[0.001] * 4,
    ub=[4e5, 3e5, 2e5, 1e5],
)
def _hs72(x1, x2, x3, x4):
    """HS72 (Bracken-McCormick): min 1 + x1 + x2 + x3 + x4 s.t.
    0.0401 - 4/x1 - 2.25/x2 - 1/x3 - 0.25/x4 >= 0,
    0.010085 - 0.16/x1 - 0.36/x2 - 0.64/x3 - 0.64/x4 >= 0,
    0.001 <= x_i <= (5 - i) 1e5."""
    return 1 + x1 + x2 + x3 + x4, [
        _ge(0.0401 - 4 / x1 - 2.25 / x2 - 1 / x3 - 0.25 / x4),
        _ge(0.010085 - 0.16 / x1 - 0.36 / x2 - 0.64 / x3 - 0.64 / x4),
    ]


@_hs(
    73,
    x0=[1, 1, 1, 1],
    f_star=29.894378,
    x_star=[0.635521568636, 0, 0.312701880751, 0.0517765506129],
    lb=[0, 0, 0, 0],
)
def _hs73(x1, x2, x3, x4):
    """HS73 (Bracken-McCormick, cattle feed): min 24.55x1 + 26.75x2 + 39x3 + 40.5x4 s.t.
    2.3x1 + 5.6x2 + 11.1x3 + 1.3x4 - 5 >= 0,
    12x1 + 11.9x2 + 41.8x3 + 52.1x4 - 21
    - 1.645 sqrt(0.28x1^2 + 0.19x2^2 + 20.5x3^2 + 0.62x4^2) >= 0,
    x1 + x2 + x3 + x4 - 1 = 0, x >= 0."""
    q = 0.28 * x1**2 + 0.19 * x2**2 + 20.5 * x3**2 + 0.62 * x4**2
    return 24.55 * x1 + 26.75 * x2 + 39 * x3 + 40.5 * x4, [
        _ge(2.3 * x1 + 5.6 * x2 + 11.1 * x3 + 1.3 * x4 - 5),
        _ge(12 * x1 + 11.9 * x2 + 41.8 * x3 + 52.1 * x4 - 21 - 1.645 * _sqrt(q)),
        _eq(x1 + x2 + x3 + x4 - 1),
    ]


def _hs74_75(a, x1, x2, x3, x4):
    f = 3 * x1 + 1e-6 * x1**3 + 2 * x2 + (2e-6 / 3) * x2**3
    return f, [
        _ge(x4 - x3 + a),
        _ge(x3 - x4 + a),
        _eq(1000 * _sin(-x3 - 0.25) + 1000 * _sin(-x4 - 0.25) + 894.8 - x1),
        _eq(1000 * _sin(x3 - 0.25) + 1000 * _sin(x3 - x4 - 0.25) + 894.8 - x2),
        _eq(1000 * _sin(x4 - 0.25) + 1000 * _sin(x4 - x3 - 0.25) + 1294.8),
    ]


@_hs(
    74,
    x0=[0, 0, 0, 0],
    f_star=5126.4981,
    x_star=[679.945319851, 1026.06713261, 0.118876364493, -0.396233553203],
    lb=[0, 0, -0.55, -0.55],
    ub=[1200, 1200, 0.55, 0.55],
)
def _hs74(x1, x2, x3, x4):
    """HS74 (Beuneu): min 3x1 + 1e-6x1^3 + 2x2 + (2e-6/3)x2^3 s.t. x4 - x3 + a >= 0,
    x3 - x4 + a >= 0, 1000 sin(-x3-0.25) + 1000 sin(-x4-0.25) + 894.8 - x1 = 0,
    1000 sin(x3-0.25) + 1000 sin(x3-x4-0.25) + 894.8 - x2 = 0,
    1000 sin(x4-0.25) + 1000 sin(x4-x3-0.25) + 1294.8 = 0, 0 <= x1, x2 <= 1200,
    -a <= x3, x4 <= a, a = 0.55."""
    return _hs74_75(0.55, x1, x2, x3, x4)


@_hs(
    75,
    x0=[0, 0, 0, 0],
    f_star=5174.4129,
    x_star=[776.159026586, 925.195138469, 0.0511089285384, -0.428891071462],
    lb=[0, 0, -0.48, -0.48],
    ub=[1200, 1200, 0.48, 0.48],
)
def _hs75(x1, x2, x3, x4):
    """HS75 (Beuneu): HS74 with a = 0.48."""
    return _hs74_75(0.48, x1, x2, x3, x4)


@_hs(
    76,
    x0=[0.5, 0.5, 0.5, 0.5],
    f_star=-103 / 22,
    x_star=[3 / 11, 23 / 11, 0, 6 / 11],
    lb=[0, 0, 0, 0],
)
def _hs76(x1, x2, x3, x4):
    """HS76 (Murtagh-Sargent): min x1^2 + 0.5x2^2 + x3^2 + 0.5x4^2 - x1x3 + x3x4 - x1 - 3x2
    + x3 - x4 s.t. 5 - x1 - 2x2 - x3 - x4 >= 0, 4 - 3x1 - x2 - 2x3 + x4 >= 0,
    x2 + 4x3 - 1.5 >= 0, x >= 0."""
    f = x1**2 + 0.5 * x2**2 + x3**2 + 0.5 * x4**2 - x1 * x3 + x3 * x4 - x1 - 3 * x2 + x3 - x4
    return f, [
        _ge(5 - x1 - 2 * x2 - x3 - x4),
        _ge(4 - 3 * x1 - x2 - 2 * x3 + x4),
        _ge(x2 + 4 * x3 - 1.5),
    ]


@_hs(
    83,
    x0=[78, 33, 27, 27, 27],
    f_star=-30665.53867,
    x_star=[78, 33, 29.9952560256, 45, 36.7758129057],
    lb=[78, 33, 27, 27, 27],
    ub=[102, 45, 45, 45, 45],
)
def _hs83(x1, x2, x3, x4, x5):
    """HS83 (Colville No. 3, Himmelblau): min 5.3578547x3^2 + 0.8356891x1x5 + 37.293239x1
    - 40792.141 s.t. 0 <= 85.334407 + 0.0056858x2x5 + 0.0006262x1x4 - 0.0022053x3x5 <= 92,
    90 <= 80.51249 + 0.0071317x2x5 + 0.0029955x1x2 + 0.0021813x3^2 <= 110,
    20 <= 9.300961 + 0.0047026x3x5 + 0.0012547x1x3 + 0.0019085x3x4 <= 25,
    78 <= x1 <= 102, 33 <= x2 <= 45, 27 <= x3, x4, x5 <= 45."""
    f = 5.3578547 * x3**2 + 0.8356891 * x1 * x5 + 37.293239 * x1 - 40792.141
    return f, [
        _range(0, 85.334407 + 0.0056858 * x2 * x5 + 0.0006262 * x1 * x4 - 0.0022053 * x3 * x5, 92),
        _range(90, 80.51249 + 0.0071317 * x2 * x5 + 0.0029955 * x1 * x2 + 0.0021813 * x3**2, 110),
        _range(20, 9.300961 + 0.0047026 * x3 * x5 + 0.0012547 * x1 * x3 + 0.0019085 * x3 * x4, 25),
    ]


_HS84_A = (
    -24345.0, -8720288.849, 150512.5253, -156.6950325, 476470.3222, 729482.8271,
    -145421.402, 2931.1506, -40.427932, 5106.192, 15711.36,
    -155011.1084, 4360.53352, 12.9492344, 10236.884, 13176.786,
    -326669.5104, 7390.68412, -27.8986976, 16643.076, 30988.146,
)  # fmt: skip


@_hs(
    84,
    x0=[2.52, 2, 37.5, 9.25, 6.8],
    f_star=-5280335.133,
    x_star=[4.53743097, 2.4, 60, 9.3, 7],
    lb=[0, 1.2, 20, 9, 6.5],
    ub=[1000, 2.4, 60, 9.3, 7],
)
def _hs84(x1, x2, x3, x4, x5):
    """HS84 (Himmelblau): min -a1 - a2x1 - a3x1x2 - a4x1x3 - a5x1x4 - a6x1x5 s.t.
    0 <= a7x1 + a8x1x2 + a9x1x3 + a10x1x4 + a11x1x5 <= 294000,
    0 <= a12x1 + a13x1x2 + a14x1x3 + a15x1x4 + a16x1x5 <= 294000,
    0 <= a17x1 + a18x1x2 + a19x1x3 + a20x1x4 + a21x1x5 <= 277200,
    (0, 1.2, 20, 9, 6.5) <= x <= (1000, 2.4, 60, 9.3, 7); a_i in the collection."""
    a = (0.0,) + _HS84_A  # 1-based like the book
    f = -a[1] - a[2] * x1 - a[3] * x1 * x2 - a[4] * x1 * x3 - a[5] * x1 * x4 - a[6] * x1 * x5

    def g(k):
        return a[k] * x1 + a[k + 1] * x1 * x2 + a[k + 2] * x1 * x3 + a[k + 3] * x1 * x4 + a[k + 4] * x1 * x5

    return f, [_range(0, g(7), 294000), _range(0, g(12), 294000), _range(0, g(17), 277200)]


# Data shared by HS86 (primal) and HS117 (its dual): the collection's Colville No. 2.
_COLVILLE_A = np.array(
    [
        [-16, 2, 0, 1, 0],
        [0, -2, 0, 4, 2],
        [-3.5, 0, 2, 0, 0],
        [0, -2, 0, -4, -1],
        [0, -9, -2, 1, -2.8],
        [2, 0, -4, 0, 0],
        [-1, -1, -1, -1, -1],
        [-1, -2, -3, -2, -1],
        [1, 2, 3, 4, 5],
        [1, 1, 1, 1, 1],
    ]
)
_COLVILLE_B = np.array([-40, -2, -0.25, -4, -4, -1, -40, -60, 5, 1], dtype=float)
_COLVILLE_C = np.array(
    [
        [30, -20, -10, 32, -10],
        [-20, 39, -6, -31, 32],
        [-10, -6, 10, -6, -10],
        [32, -31, -6, 39, -20],
        [-10, 32, -10, -20, 30],
    ],
    dtype=float,
)
_COLVILLE_D = np.array([4, 8, 10, 6, 2], dtype=float)
_COLVILLE_E = np.array([-15, -27, -36, -18, -12], dtype=float)


@_hs(
    86,
    x0=[0, 0, 0, 0, 1],
    f_star=-32.34867897,
    x_star=[0.3, 0.33346761, 0.4, 0.42831010, 0.22396487],
    lb=[0] * 5,
)
def _hs86(*x):
    """HS86 (Colville No. 1): min sum_j e_j x_j + sum_ij c_ij x_i x_j + sum_j d_j x_j^3
    s.t. sum_j a_ij x_j - b_i >= 0 (i = 1..10), x >= 0; data a, b, c, d, e in the
    collection."""
    f = sum(_COLVILLE_E[j] * x[j] + _COLVILLE_D[j] * x[j] ** 3 for j in range(5))
    f = f + sum(_COLVILLE_C[i, j] * x[i] * x[j] for i in range(5) for j in range(5))
    cons = [_ge(sum(_COLVILLE_A[i, j] * x[j] for j in range(5)) - _COLVILLE_B[i]) for i in range(10)]
    return f, cons


@_hs(
    93,
    x0=[5.54, 4.4, 12.02, 11.82, 0.702, 0.852],
    f_star=135.075961,
    x_star=[
        5.33266584898, 4.65674530802, 10.4329926717, 12.0823036055, 0.752607532105,
        0.878650744611
    ],
    lb=[0] * 6,
)
def _hs93(x1, x2, x3, x4, x5, x6):
    """HS93 (Bartholomew-Biggs, transformer design): min 0.0204x1x4(x1+x2+x3)
    + 0.0187x2x3(x1+1.57x2+x4) + 0.0607x1x4x5^2(x1+x2+x3) + 0.0437x2x3x6^2(x1+1.57x2+x4)
    s.t. 0.001x1x2x3x4x5x6 - 2.07 >= 0,
    1 - 0.00062x1x4x5^2(x1+x2+x3) - 0.00058x2x3x6^2(x1+1.57x2+x4) >= 0, x >= 0."""
    s, t = x1 + x2 + x3, x1 + 1.57 * x2 + x4
    f = 0.0204 * x1 * x4 * s + 0.0187 * x2 * x3 * t + 0.0607 * x1 * x4 * x5**2 * s + 0.0437 * x2 * x3 * x6**2 * t
    return f, [
        _ge(0.001 * x1 * x2 * x3 * x4 * x5 * x6 - 2.07),
        _ge(1 - 0.00062 * x1 * x4 * x5**2 * s - 0.00058 * x2 * x3 * x6**2 * t),
    ]


def _hs95_98(b, x1, x2, x3, x4, x5, x6):
    f = 4.3 * x1 + 31.8 * x2 + 63.3 * x3 + 15.8 * x4 + 68.5 * x5 + 4.7 * x6
    return f, [
        _ge(
            17.1 * x1 + 38.2 * x2 + 204.2 * x3 + 212.3 * x4 + 623.4 * x5 + 1495.5 * x6
            - 169 * x1 * x3 - 3580 * x3 * x5 - 3810 * x4 * x5 - 18500 * x4 * x6
            - 24300 * x5 * x6 - b[0]
        ),
        _ge(
            17.9 * x1 + 36.8 * x2 + 113.9 * x3 + 169.7 * x4 + 337.8 * x5 + 1385.2 * x6
            - 139 * x1 * x3 - 2450 * x4 * x5 - 16600 * x4 * x6 - 17200 * x5 * x6 - b[1]
        ),
        _ge(-273 * x2 - 70 * x4 - 819 * x5 + 26000 * x4 * x5 - b[2]),
        _ge(159.9 * x1 - 311 * x2 + 587 * x4 + 391 * x5 + 2198 * x6 - 14000 * x1 * x6 - b[3]),
    ]  # fmt: skip


_HS95_UB = [0.31, 0.046, 0.068, 0.042, 0.028, 0.0134]
_HS95_DOC = """min 4.3x1 + 31.8x2 + 63.3x3 + 15.8x4 + 68.5x5 + 4.7x6 s.t.
    17.1x1 + 38.2x2 + 204.2x3 + 212.3x4 + 623.4x5 + 1495.5x6 - 169x1x3 - 3580x3x5
    - 3810x4x5 - 18500x4x6 - 24300x5x6 - b1 >= 0,
    17.9x1 + 36.8x2 + 113.9x3 + 169.7x4 + 337.8x5 + 1385.2x6 - 139x1x3 - 2450x4x5
    - 16600x4x6 - 17200x5x6 - b2 >= 0,
    -273x2 - 70x4 - 819x5 + 26000x4x5 - b3 >= 0,
    159.9x1 - 311x2 + 587x4 + 391x5 + 2198x6 - 14000x1x6 - b4 >= 0,
    0 <= x <= (0.31, 0.046, 0.068, 0.042, 0.028, 0.0134)"""


@_hs(
    95,
    x0=[0] * 6,
    f_star=0.015619514,
    x_star=[0, 0, 0, 0, 0, 0.00332330324063],
    lb=[0] * 6,
    ub=_HS95_UB,
)
def _hs95(*x):
    return _hs95_98((4.97, -1.88, -29.08, -78.02), *x)


@_hs(
    96,
    x0=[0] * 6,
    f_star=0.015619514,
    x_star=[0, 0, 0, 0, 0, 0.00332330324633],
    lb=[0] * 6,
    ub=_HS95_UB,
)
def _hs96(*x):
    return _hs95_98((4.97, -1.88, -69.08, -118.02), *x)


@_hs(
    97,
    x0=[0] * 6,
    f_star=3.1358091,
    x_star=[0.26856491228, 0, 0, 0, 0.028, 0.0134],
    lb=[0] * 6,
    ub=_HS95_UB,
)
def _hs97(*x):
    return _hs95_98((32.97, 25.12, -29.08, -78.02), *x)


@_hs(
    98,
    x0=[0] * 6,
    f_star=3.1358091,
    x_star=[0.268564912281, 0, 0, 0, 0.028, 0.0134],
    lb=[0] * 6,
    ub=_HS95_UB,
)
def _hs98(*x):
    return _hs95_98((32.97, 25.12, -124.08, -173.02), *x)


_hs95.__doc__ = "HS95 (Holzman): " + _HS95_DOC + ", b = (4.97, -1.88, -29.08, -78.02)."
_hs96.__doc__ = "HS96 (Holzman): " + _HS95_DOC + ", b = (4.97, -1.88, -69.08, -118.02)."
_hs97.__doc__ = "HS97 (Holzman): " + _HS95_DOC + ", b = (32.97, 25.12, -29.08, -78.02)."
_hs98.__doc__ = "HS98 (Holzman): " + _HS95_DOC + ", b = (32.97, 25.12, -124.08, -173.02)."


@_hs(
    100,
    x0=[1, 2, 0, 4, 0, 1, 1],
    f_star=680.6300573,
    x_star=[
        2.33049921908, 1.95137274917, -0.477541431875, 4.36572518211, -0.624486040677,
        1.03813103181, 1.59422643994
    ],
)
def _hs100(x1, x2, x3, x4, x5, x6, x7):
    """HS100 (Asaadi, Charalambous): min (x1-10)^2 + 5(x2-12)^2 + x3^4 + 3(x4-11)^2
    + 10x5^6 + 7x6^2 + x7^4 - 4x6x7 - 10x6 - 8x7 s.t.
    127 - 2x1^2 - 3x2^4 - x3 - 4x4^2 - 5x5 >= 0, 282 - 7x1 - 3x2 - 10x3^2 - x4 + x5 >= 0,
    196 - 23x1 - x2^2 - 6x6^2 + 8x7 >= 0, -4x1^2 - x2^2 + 3x1x2 - 2x3^2 - 5x6 + 11x7 >= 0."""
    f = (
        (x1 - 10) ** 2 + 5 * (x2 - 12) ** 2 + x3**4 + 3 * (x4 - 11) ** 2 + 10 * x5**6
        + 7 * x6**2 + x7**4 - 4 * x6 * x7 - 10 * x6 - 8 * x7
    )  # fmt: skip
    return f, [
        _ge(127 - 2 * x1**2 - 3 * x2**4 - x3 - 4 * x4**2 - 5 * x5),
        _ge(282 - 7 * x1 - 3 * x2 - 10 * x3**2 - x4 + x5),
        _ge(196 - 23 * x1 - x2**2 - 6 * x6**2 + 8 * x7),
        _ge(-4 * x1**2 - x2**2 + 3 * x1 * x2 - 2 * x3**2 - 5 * x6 + 11 * x7),
    ]


@_hs(
    104,
    x0=[6, 3, 0.4, 0.2, 6, 6, 1, 0.5],
    f_star=3.9511634396,
    x_star=[
        6.46511381385, 2.23270883729, 0.667397492922, 0.59575644275, 5.9326757142,
        5.52723456992, 1.0133220642, 0.400668236526
    ],
    lb=[0.1] * 8,
    ub=[10] * 8,
)
def _hs104(x1, x2, x3, x4, x5, x6, x7, x8):
    """HS104 (Dembo, reactor design): min 0.4x1^0.67 x7^-0.67 + 0.4x2^0.67 x8^-0.67 + 10
    - x1 - x2 s.t. 1 - 0.0588x5x7 - 0.1x1 >= 0, 1 - 0.0588x6x8 - 0.1x1 - 0.1x2 >= 0,
    1 - 4x3/x5 - 2x3^-0.71/x5 - 0.0588x3^-1.3 x7 >= 0,
    1 - 4x4/x6 - 2x4^-0.71/x6 - 0.0588x4^-1.3 x8 >= 0, 1 <= f(x) <= 4.2,
    0.1 <= x <= 10."""
    f = 0.4 * x1**0.67 * x7**-0.67 + 0.4 * x2**0.67 * x8**-0.67 + 10 - x1 - x2
    return f, [
        _ge(1 - 0.0588 * x5 * x7 - 0.1 * x1),
        _ge(1 - 0.0588 * x6 * x8 - 0.1 * x1 - 0.1 * x2),
        _ge(1 - 4 * x3 / x5 - 2 * x3**-0.71 / x5 - 0.0588 * x3**-1.3 * x7),
        _ge(1 - 4 * x4 / x6 - 2 * x4**-0.71 / x6 - 0.0588 * x4**-1.3 * x8),
        _range(1, f, 4.2),
    ]


@_hs(
    106,
    x0=[5000, 5000, 5000, 200, 350, 150, 225, 425],
    f_star=7049.248020529,
    x_star=[
        579.306684425, 1359.97066805, 5109.97066805, 182.017699581, 295.601173278,
        217.982300419, 286.416526303, 395.601173278
    ],
    lb=[100, 1000, 1000, 10, 10, 10, 10, 10],
    ub=[10000, 10000, 10000, 1000, 1000, 1000, 1000, 1000],
)
def _hs106(x1, x2, x3, x4, x5, x6, x7, x8):
    """HS106 (Avriel-Williams, heat exchanger design): min x1 + x2 + x3 s.t.
    1 - 0.0025(x4 + x6) >= 0, 1 - 0.0025(x5 + x7 - x4) >= 0, 1 - 0.01(x8 - x5) >= 0,
    x1x6 - 833.33252x4 - 100x1 + 83333.333 >= 0, x2x7 - 1250x5 - x2x4 + 1250x4 >= 0,
    x3x8 - 1250000 - x3x5 + 2500x5 >= 0, bounds in the collection (badly scaled).
    The 1981 book prints f* = 7049.330923; the 2009 report gives the better value
    7049.248021 (reproduced here to 1e-10)."""
    return x1 + x2 + x3, [
        _ge(1 - 0.0025 * (x4 + x6)),
        _ge(1 - 0.0025 * (x5 + x7 - x4)),
        _ge(1 - 0.01 * (x8 - x5)),
        _ge(x1 * x6 - 833.33252 * x4 - 100 * x1 + 83333.333),
        _ge(x2 * x7 - 1250 * x5 - x2 * x4 + 1250 * x4),
        _ge(x3 * x8 - 1250000 - x3 * x5 + 2500 * x5),
    ]


@_hs(
    108,
    x0=[1] * 9,
    f_star=-0.5 * _SQ3,
    x_star=[
        0.88412920981, 0.467242485613, 0.0374207426367, 0.999299598729, 0.88412920981,
        0.467242485613, 0.0374207426367, 0.999299598729, 0
    ],
    lb=[None] * 8 + [0],
)
def _hs108(x1, x2, x3, x4, x5, x6, x7, x8, x9):
    """HS108 (Pearson, largest hexagon): min -0.5(x1x4 - x2x3 + x3x9 - x5x9 + x5x8 - x6x7)
    s.t. 1 - x3^2 - x4^2 >= 0, 1 - x9^2 >= 0, 1 - x5^2 - x6^2 >= 0, 1 - x1^2 - (x2-x9)^2 >= 0,
    1 - (x1-x5)^2 - (x2-x6)^2 >= 0, 1 - (x1-x7)^2 - (x2-x8)^2 >= 0,
    1 - (x3-x5)^2 - (x4-x6)^2 >= 0, 1 - (x3-x7)^2 - (x4-x8)^2 >= 0, 1 - x7^2 - (x8-x9)^2 >= 0,
    x1x4 - x2x3 >= 0, x3x9 >= 0, -x5x9 >= 0, x5x8 - x6x7 >= 0, x9 >= 0."""
    f = -0.5 * (x1 * x4 - x2 * x3 + x3 * x9 - x5 * x9 + x5 * x8 - x6 * x7)
    return f, [
        _ge(1 - x3**2 - x4**2),
        _ge(1 - x9**2),
        _ge(1 - x5**2 - x6**2),
        _ge(1 - x1**2 - (x2 - x9) ** 2),
        _ge(1 - (x1 - x5) ** 2 - (x2 - x6) ** 2),
        _ge(1 - (x1 - x7) ** 2 - (x2 - x8) ** 2),
        _ge(1 - (x3 - x5) ** 2 - (x4 - x6) ** 2),
        _ge(1 - (x3 - x7) ** 2 - (x4 - x8) ** 2),
        _ge(1 - x7**2 - (x8 - x9) ** 2),
        _ge(x1 * x4 - x2 * x3),
        _ge(x3 * x9),
        _ge(-x5 * x9),
        _ge(x5 * x8 - x6 * x7),
    ]


@_hs(
    113,
    x0=[2, 3, 5, 5, 1, 2, 7, 3, 6, 10],
    f_star=24.3062091,
    x_star=[
        2.17199638966, 2.36368292982, 8.77392573392, 5.09598449972, 0.99065479847,
        1.43057407707, 1.3216442429, 9.82872583566, 8.2800919731, 8.37592730392
    ],
)  # fmt: skip
def _hs113(x1, x2, x3, x4, x5, x6, x7, x8, x9, x10):
    """HS113 (Asaadi, Charalambous; Wong No. 2): min x1^2 + x2^2 + x1x2 - 14x1 - 16x2
    + (x3-10)^2 + 4(x4-5)^2 + (x5-3)^2 + 2(x6-1)^2 + 5x7^2 + 7(x8-11)^2 + 2(x9-10)^2
    + (x10-7)^2 + 45 s.t. 105 - 4x1 - 5x2 + 3x7 - 9x8 >= 0, -10x1 + 8x2 + 17x7 - 2x8 >= 0,
    8x1 - 2x2 - 5x9 + 2x10 + 12 >= 0, -3(x1-2)^2 - 4(x2-3)^2 - 2x3^2 + 7x4 + 120 >= 0,
    -5x1^2 - 8x2 - (x3-6)^2 + 2x4 + 40 >= 0, -0.5(x1-8)^2 - 2(x2-4)^2 - 3x5^2 + x6 + 30 >= 0,
    -x1^2 - 2(x2-2)^2 + 2x1x2 - 14x5 + 6x6 >= 0, 3x1 - 6x2 - 12(x9-8)^2 + 7x10 >= 0."""
    f = (
        x1**2 + x2**2 + x1 * x2 - 14 * x1 - 16 * x2 + (x3 - 10) ** 2 + 4 * (x4 - 5) ** 2
        + (x5 - 3) ** 2 + 2 * (x6 - 1) ** 2 + 5 * x7**2 + 7 * (x8 - 11) ** 2
        + 2 * (x9 - 10) ** 2 + (x10 - 7) ** 2 + 45
    )  # fmt: skip
    return f, [
        _ge(105 - 4 * x1 - 5 * x2 + 3 * x7 - 9 * x8),
        _ge(-10 * x1 + 8 * x2 + 17 * x7 - 2 * x8),
        _ge(8 * x1 - 2 * x2 - 5 * x9 + 2 * x10 + 12),
        _ge(-3 * (x1 - 2) ** 2 - 4 * (x2 - 3) ** 2 - 2 * x3**2 + 7 * x4 + 120),
        _ge(-5 * x1**2 - 8 * x2 - (x3 - 6) ** 2 + 2 * x4 + 40),
        _ge(-0.5 * (x1 - 8) ** 2 - 2 * (x2 - 4) ** 2 - 3 * x5**2 + x6 + 30),
        _ge(-(x1**2) - 2 * (x2 - 2) ** 2 + 2 * x1 * x2 - 14 * x5 + 6 * x6),
        _ge(3 * x1 - 6 * x2 - 12 * (x9 - 8) ** 2 + 7 * x10),
    ]


@_hs(
    114,
    x0=[1745, 12000, 110, 3048, 1974, 89.2, 92.8, 8, 3.6, 145],
    f_star=-1768.80696,
    x_star=[
        1698.09568219, 15818.7300002, 54.1022672648, 3031.22596901, 2000, 90.115364778,
        95, 10.4933604078, 1.56163636363, 153.535353535
    ],
    lb=[1e-5] * 5 + [85, 90, 3, 1.2, 145],
    ub=[2000, 16000, 120, 5000, 2000, 93, 95, 12, 4, 162],
)  # fmt: skip
def _hs114(x1, x2, x3, x4, x5, x6, x7, x8, x9, x10):
    """HS114 (Bracken-McCormick, alkylation process): min 5.04x1 + 0.035x2 + 10x3 + 3.36x5
    - 0.063x4x7 s.t. g1 = 35.82 - 0.222x10 - bx9 >= 0, g2 = -133 + 3x7 - ax10 >= 0,
    -g1 + x9(1/b - b) >= 0, -g2 + (1/a - a)x10 >= 0,
    g5 = 1.12x1 + 0.13167x1x8 - 0.00667x1x8^2 - ax4 >= 0,
    g6 = 57.425 + 1.098x8 - 0.038x8^2 + 0.325x6 - ax7 >= 0, -g5 + (1/a - a)x4 >= 0,
    -g6 + (1/a - a)x7 >= 0, 1.22x4 - x1 - x5 = 0, 98000x3/(x4x9 + 1000x3) - x6 = 0,
    (x2 + x5)/x1 - x8 = 0, a = 0.99, b = 0.9, bounds in the collection."""
    a, b = 0.99, 0.9
    g1 = 35.82 - 0.222 * x10 - b * x9
    g2 = -133 + 3 * x7 - a * x10
    g5 = 1.12 * x1 + 0.13167 * x1 * x8 - 0.00667 * x1 * x8**2 - a * x4
    g6 = 57.425 + 1.098 * x8 - 0.038 * x8**2 + 0.325 * x6 - a * x7
    f = 5.04 * x1 + 0.035 * x2 + 10 * x3 + 3.36 * x5 - 0.063 * x4 * x7
    return f, [
        _ge(g1),
        _ge(g2),
        _ge(-g1 + x9 * (1 / b - b)),
        _ge(-g2 + (1 / a - a) * x10),
        _ge(g5),
        _ge(g6),
        _ge(-g5 + (1 / a - a) * x4),
        _ge(-g6 + (1 / a - a) * x7),
        _eq(1.22 * x4 - x1 - x5),
        _eq(98000 * x3 / (x4 * x9 + 1000 * x3) - x6),
        _eq((x2 + x5) / x1 - x8),
    ]


@_hs(
    116,
    x0=[0.5, 0.8, 0.9, 0.1, 0.14, 0.5, 489, 80, 650, 450, 150, 150, 150],
    f_star=97.58750956,
    x_star=[
        0.803773157377, 0.899985800673, 0.970982435485, 0.1, 0.190813176216,
        0.460654782866, 574.077573583, 74.0775735828, 500.016160169, 0.1, 20.2330906974,
        77.3476899273, 0.00672893339536
    ],
    lb=[0.1, 0.1, 0.1, 1e-4, 0.1, 0.1, 0.1, 0.1, 500, 0.1, 1, 1e-4, 1e-4],
    ub=[1, 1, 1, 0.1, 0.9, 0.9, 1000, 1000, 1000, 500, 150, 150, 150],
)  # fmt: skip
def _hs116(x1, x2, x3, x4, x5, x6, x7, x8, x9, x10, x11, x12, x13):
    """HS116 (Dembo, 3-stage membrane separation): min x11 + x12 + x13 s.t. x3 - x2 >= 0,
    x2 - x1 >= 0, 1 - 0.002x7 + 0.002x8 >= 0, x11 + x12 + x13 - 50 >= 0,
    250 - x11 - x12 - x13 >= 0, x13 - 1.262626x10 + 1.231059x3x10 >= 0,
    x5 - 0.03475x2 - 0.975x2x5 + 0.00975x2^2 >= 0, x6 - 0.03475x3 - 0.975x3x6 + 0.00975x3^2 >= 0,
    x4 - 0.03475x1 - 0.975x1x4 + 0.00975x1^2 >= 0, x12 - 1.262626x9 + 1.231059x2x9 >= 0,
    x11 - 1.262626x8 + 1.231059x1x8 >= 0, x5x7 - x1x8 - x4x7 + x4x8 >= 0,
    1 - 0.002(x2x9 + x5x8 - x1x8 - x6x9) - x5 - x6 >= 0,
    x2x9 - x3x10 - x6x9 - 500x2 + 500x6 + x2x10 >= 0, x2 - 0.9 - 0.002(x2x10 - x3x10) >= 0,
    bounds in the collection (badly scaled). The 1981 book prints f* = 97.588409; the
    2009 report gives the better value 97.5875096 (reproduced here)."""
    return x11 + x12 + x13, [
        _ge(x3 - x2),
        _ge(x2 - x1),
        _ge(1 - 0.002 * x7 + 0.002 * x8),
        _ge(x11 + x12 + x13 - 50),
        _ge(250 - x11 - x12 - x13),
        _ge(x13 - 1.262626 * x10 + 1.231059 * x3 * x10),
        _ge(x5 - 0.03475 * x2 - 0.975 * x2 * x5 + 0.00975 * x2**2),
        _ge(x6 - 0.03475 * x3 - 0.975 * x3 * x6 + 0.00975 * x3**2),
        _ge(x4 - 0.03475 * x1 - 0.975 * x1 * x4 + 0.00975 * x1**2),
        _ge(x12 - 1.262626 * x9 + 1.231059 * x2 * x9),
        _ge(x11 - 1.262626 * x8 + 1.231059 * x1 * x8),
        _ge(x5 * x7 - x1 * x8 - x4 * x7 + x4 * x8),
        _ge(1 - 0.002 * (x2 * x9 + x5 * x8 - x1 * x8 - x6 * x9) - x5 - x6),
        _ge(x2 * x9 - x3 * x10 - x6 * x9 - 500 * x2 + 500 * x6 + x2 * x10),
        _ge(x2 - 0.9 - 0.002 * (x2 * x10 - x3 * x10)),
    ]


@_hs(
    117,
    x0=[0.001] * 6 + [60] + [0.001] * 8,
    f_star=32.34867897,
    x_star=[
        0, 0, 5.17404856977, 0, 3.06110723398, 11.8395451972, 0, 0, 0.103894080955, 0,
        0.299999058498, 0.333467956332, 0.399999981147, 0.428310710854, 0.223964493426
    ],
    lb=[0] * 15,
)  # fmt: skip
def _hs117(*x):
    """HS117 (Colville No. 2, dual of HS86): min -sum_i b_i x_i + sum_kj c_kj x_{10+k} x_{10+j}
    + 2 sum_j d_j x_{10+j}^3 s.t. 2 sum_k c_kj x_{10+k} + 3 d_j x_{10+j}^2 + e_j
    - sum_k a_kj x_k >= 0 (j = 1..5), x >= 0; data as in HS86."""
    y, z = x[:10], x[10:]
    f = -sum(_COLVILLE_B[i] * y[i] for i in range(10))
    f = f + sum(_COLVILLE_C[k, j] * z[k] * z[j] for k in range(5) for j in range(5))
    f = f + 2 * sum(_COLVILLE_D[j] * z[j] ** 3 for j in range(5))
    cons = [
        _ge(
            2 * sum(_COLVILLE_C[k, j] * z[k] for k in range(5))
            + 3 * _COLVILLE_D[j] * z[j] ** 2
            + _COLVILLE_E[j]
            - sum(_COLVILLE_A[k, j] * y[k] for k in range(10))
        )
        for j in range(5)
    ]
    return f, cons


@_hs(
    118,
    x0=[20, 55, 15, 20, 60, 20, 20, 60, 20, 20, 60, 20, 20, 60, 20],
    f_star=664.8204500,
    x_star=[8, 49, 3, 1, 56, 0, 1, 63, 6, 3, 70, 12, 5, 77, 18],
    lb=[8, 43, 3] + [0] * 12,
    ub=[21, 57, 16] + [90, 120, 60] * 4,
)
def _hs118(*x):
    """HS118 (Bartholomew-Biggs): min sum_{k=0}^{4} (2.3x_{3k+1} + 0.0001x_{3k+1}^2
    + 1.7x_{3k+2} + 0.0001x_{3k+2}^2 + 2.2x_{3k+3} + 0.00015x_{3k+3}^2) s.t.
    0 <= x_{3j+1} - x_{3j-2} + 7 <= 13, 0 <= x_{3j+2} - x_{3j-1} + 7 <= 14,
    0 <= x_{3j+3} - x_{3j} + 7 <= 13 (j = 1..4), x1 + x2 + x3 - 60 >= 0,
    x4 + x5 + x6 - 50 >= 0, x7 + x8 + x9 - 70 >= 0, x10 + x11 + x12 - 85 >= 0,
    x13 + x14 + x15 - 100 >= 0, bounds in the collection."""
    v = (None,) + x  # 1-based like the book
    f = sum(
        2.3 * v[3 * k + 1] + 0.0001 * v[3 * k + 1] ** 2 + 1.7 * v[3 * k + 2]
        + 0.0001 * v[3 * k + 2] ** 2 + 2.2 * v[3 * k + 3] + 0.00015 * v[3 * k + 3] ** 2
        for k in range(5)
    )  # fmt: skip
    cons = []
    for j in range(1, 5):
        cons += [
            _range(0, v[3 * j + 1] - v[3 * j - 2] + 7, 13),
            _range(0, v[3 * j + 2] - v[3 * j - 1] + 7, 14),
            _range(0, v[3 * j + 3] - v[3 * j] + 7, 13),
        ]
    for k, rhs in enumerate((60, 50, 70, 85, 100)):
        cons.append(_ge(v[3 * k + 1] + v[3 * k + 2] + v[3 * k + 3] - rhs))
    return f, cons
