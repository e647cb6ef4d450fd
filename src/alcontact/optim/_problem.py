"""The nonlinear program: SciPy-style callables and constraints in internal form.

Converts ``fun``/``jac``/``hess`` and SciPy's :class:`~scipy.optimize.NonlinearConstraint`,
:class:`~scipy.optimize.LinearConstraint` and :class:`~scipy.optimize.Bounds` into

.. math:: \\min f(x) \\quad\\text{s.t.}\\quad g(x) \\le 0,\\; h(x) = 0

(the dissertation's convention, problem (P) of section 5.1.1 and (P1) of 5.1.2):
``lb == ub`` gives an equality ``c - ub = 0``; a finite ``ub`` gives ``c - ub <= 0``;
a finite ``lb`` gives ``lb - c <= 0``; infinite sides are skipped.
Counts evaluations, caches the last point, replaces missing derivatives by finite
differences and turns non-finite callback output into :class:`NonFiniteValue`.

Optional automatic scaling (:meth:`NLP.set_scaling`, ALGENCAN's rule, Birgin &
Martinez 2014, sec. 12.5): the public evaluations return
:math:`s_f f`, :math:`s_i g_i`, :math:`s_j h_j` with
:math:`s_f = 1/\\max(1, \\|\\nabla f(x_0)\\|_\\infty)` and
:math:`s_i = 1/\\max(1, \\|\\nabla c_i(x_0)\\|_\\infty)`; ``f_unscaled`` and
:meth:`NLP.unscale` give the original units (multipliers
:math:`\\mu_i = \\mu^s_i s_i / s_f`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.optimize import Bounds, LinearConstraint, NonlinearConstraint

from ..errors import InputError

__all__ = ["NLP", "NonFiniteValue"]

_EPS = np.finfo(float).eps


class NonFiniteValue(Exception):
    """Internal signal: a callback returned NaN/inf (``callback`` names it)."""

    def __init__(self, callback: str):
        super().__init__(f"non-finite value from {callback}")
        self.callback = callback


def _check(value, name):
    data = value.data if sp.issparse(value) else value
    if not np.all(np.isfinite(data)):
        raise NonFiniteValue(name)
    return value


def _guard(name, fn, *args):
    """Call a user callback with NumPy warnings silenced; arithmetic errors -> non-finite."""
    try:
        with np.errstate(all="ignore"):
            return fn(*args)
    except (ArithmeticError, FloatingPointError) as exc:
        raise NonFiniteValue(f"{name} ({type(exc).__name__}: {exc})") from None


def _is_callable_derivative(obj) -> bool:
    return callable(obj) and not isinstance(obj, (str, bytes))


def _as_matrix(a, sparse: bool, shape):
    if sp.issparse(a):
        a = a.tocsr() if sparse else a.toarray()
    else:
        a = np.atleast_2d(np.asarray(a, dtype=float))
        if sparse:
            a = sp.csr_matrix(a)
    if a.shape != shape:
        raise InputError(f"matrix of shape {a.shape} where {shape} was expected")
    return a


@dataclass
class _Block:
    """One user constraint object ``lb <= c(x) <= ub``."""

    name: str
    fun: object
    jac: object  # callable or None (finite differences)
    hess: object  # callable, None (finite differences) or "linear"
    lb: np.ndarray
    ub: np.ndarray
    iu: np.ndarray  # rows with finite ub (and lb != ub) -> c - ub <= 0
    il: np.ndarray  # rows with finite lb (and lb != ub) -> lb - c <= 0
    ie: np.ndarray  # rows with lb == ub -> c - ub = 0
    A: object = None  # constant Jacobian for linear blocks
    is_bounds: bool = False


class NLP:
    """Internal problem ``min f s.t. g <= 0, h = 0`` with counters and caches.

    Parameters
    ----------
    fun, x0, jac, hess, constraints, bounds
        As in :func:`alcontact.optim.minimize`.
    box : bool
        False: the bounds become the last constraint block (rows of ``g``/``h``).
        True: they are kept apart as the box ``lower <= x <= upper`` (attributes
        ``lower``/``upper``, ``-inf``/``inf`` where absent) for an inner solver that
        keeps them exactly; ``g``/``h`` then hold the general constraints only.
    """

    def __init__(self, fun, x0, jac=None, hess=None, constraints=(), bounds=None,
                 box=False):
        try:
            x0 = np.asarray(x0, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"x0 must be a 1-D array of numbers; got {type(x0).__name__} {x0!r:.60}") from None
        if x0.ndim != 1:
            if x0.ndim == 0:
                x0 = x0.reshape(1)
            else:
                raise InputError(f"x0 must be a 1-D array; got shape {x0.shape}")
        if x0.size == 0:
            raise InputError("x0 is empty; give at least one variable")
        if not np.all(np.isfinite(x0)):
            raise InputError("x0 contains NaN or infinity")
        if not callable(fun):
            raise InputError(f"fun must be callable, got {type(fun).__name__}")
        self.n = n = x0.size
        self.x0_clipped = False
        if box and bounds is not None:
            # the box is kept exactly: no callback is ever evaluated outside it
            bb = self._make_bounds(bounds)
            if bb is not None:
                xc = np.minimum(np.maximum(x0, bb.lb), bb.ub)
                self.x0_clipped = not np.array_equal(xc, x0)
                x0 = xc
        self.x0 = x0
        self._fun = fun
        self.fun_returns_grad = jac is True
        self._jac = jac if _is_callable_derivative(jac) else None
        self.grad_is_fd = not (self.fun_returns_grad or self._jac is not None)
        self._hess = hess if _is_callable_derivative(hess) else None
        self.hess_is_fd = self._hess is None
        self.nfev = self.njev = self.nhev = self.ncev = 0
        self._cache_f = (None, None, None)
        self._cache_c = (None, None)
        self._cache_j = (None, None)

        self.f_scale = 1.0  # see set_scaling
        # f, grad and Hessian at x0: validate sizes; non-finite -> NonFiniteValue
        g0 = self.grad(x0)
        if g0.shape != (n,):
            raise InputError(f"the gradient has shape {g0.shape} but x0 has {n} entries")
        h0 = None
        if self._hess is not None:
            h0 = self.hess_f(x0, sparse=None)
            if h0.shape != (n, n):
                raise InputError(f"the Hessian has shape {h0.shape} but x0 has {n} "
                                 f"entries; expected ({n}, {n})")

        self.blocks: list[_Block] = []
        self.bounds_block: _Block | None = None
        cons = constraints
        if cons is None:
            cons = ()
        if isinstance(cons, (NonlinearConstraint, LinearConstraint, dict)):
            cons = (cons,)
        if isinstance(cons, (str, bytes, np.ndarray)) or not np.iterable(cons):
            raise InputError(f"constraints must be a constraint (NonlinearConstraint, LinearConstraint, dict) or a "
                             f"list of them; got {type(cons).__name__} {cons!r:.60}")
        sparse = h0 is not None and sp.issparse(h0)
        for i, c in enumerate(cons):
            block, is_sparse = self._make_block(c, i, x0)
            sparse = sparse or is_sparse
            self.blocks.append(block)
        self.lower = self.upper = None
        if bounds is not None:
            self.bounds_block = self._make_bounds(bounds)
            if self.bounds_block is not None:
                if box:
                    self.lower = self.bounds_block.lb.copy()
                    self.upper = self.bounds_block.ub.copy()
                else:
                    self.blocks.append(self.bounds_block)
        self.sparse = bool(sparse)

        # offsets of each block in g and h
        mi = pe = 0
        self._offsets = []
        for b in self.blocks:
            self._offsets.append((mi, pe))
            mi += b.iu.size + b.il.size
            pe += b.ie.size
        self.m, self.p = mi, pe
        for b in self.blocks:
            if b.A is not None:
                b.A = _as_matrix(b.A, self.sparse, (b.lb.size, n))
        self.f_scale = 1.0
        self.g_scale = np.ones(self.m)
        self.h_scale = np.ones(self.p)

    # ---------------------------------------------------------------- scaling
    def set_scaling(self, x=None):
        """Scale ``f`` and every constraint by ``1/max(1, |gradient at x|_inf)``.

        ``x`` defaults to ``x0``. Variable bounds have unit gradients and keep
        scale 1. Returns ``(f_scale, g_scale, h_scale)``.
        """
        x = self.x0 if x is None else np.asarray(x, dtype=float)
        self.f_scale = 1.0
        self.g_scale, self.h_scale = np.ones(self.m), np.ones(self.p)
        self._cache_j = (None, None)
        gf = self._grad_raw(x)
        Jg, Jh = self.jacobians(x)

        def rows(J):
            if J.shape[0] == 0:
                return np.zeros(0)
            if sp.issparse(J):
                return np.asarray(abs(J).max(axis=1).toarray()).ravel()
            return np.max(np.abs(J), axis=1)

        self.f_scale = 1.0 / max(1.0, float(np.max(np.abs(gf))))
        self.g_scale = 1.0 / np.maximum(1.0, rows(Jg))
        self.h_scale = 1.0 / np.maximum(1.0, rows(Jh))
        self._cache_j = (None, None)
        return self.f_scale, self.g_scale, self.h_scale

    @property
    def scaled(self) -> bool:
        """Whether :meth:`set_scaling` changed any scale factor."""
        return bool(self.f_scale != 1.0 or np.any(self.g_scale != 1.0)
                    or np.any(self.h_scale != 1.0))

    def f_unscaled(self, x):
        """Objective in the user's units."""
        return self._eval_fun(x)[0]

    def unscale(self, g, h, mu, lam):
        """Constraint values and multipliers of the scaled problem in the user's units."""
        return (np.asarray(g) / self.g_scale, np.asarray(h) / self.h_scale,
                np.asarray(mu) * self.g_scale / self.f_scale,
                np.asarray(lam) * self.h_scale / self.f_scale)

    @property
    def has_box(self) -> bool:
        """Whether the bounds are kept as a box (``lower``/``upper``), not in ``g``/``h``."""
        return self.lower is not None

    def project(self, x):
        """Projection onto the box (identity without one)."""
        if self.lower is None:
            return x
        return np.minimum(np.maximum(x, self.lower), self.upper)

    # ------------------------------------------------------------------ setup
    def _make_block(self, c, i, x0):
        name = f"constraints[{i}]"
        if isinstance(c, dict):  # SciPy's legacy {'type': 'ineq'|'eq', 'fun', 'jac'}
            kind = c.get("type")
            if kind not in ("ineq", "eq") or "fun" not in c:
                raise InputError(f"{name}: a dict constraint needs 'type' ('ineq' or "
                                 f"'eq') and 'fun'; got keys {sorted(c)}")
            args = tuple(c.get("args", ()))
            fn = c["fun"]
            jc = c.get("jac")
            fun = (lambda x, fn=fn, a=args: fn(x, *a))
            jac = (lambda x, jc=jc, a=args: jc(x, *a)) if callable(jc) else "2-point"
            lb, ub = (0.0, np.inf) if kind == "ineq" else (0.0, 0.0)
            c = NonlinearConstraint(fun, lb, ub, jac=jac)
        if isinstance(c, LinearConstraint):
            A = c.A
            if not sp.issparse(A):
                A = np.atleast_2d(np.asarray(A, dtype=float))
            if A.ndim != 2 or A.shape[1] != self.n:
                raise InputError(f"{name}: LinearConstraint.A has shape {A.shape} but x0 "
                                 f"has {self.n} entries; A needs {self.n} columns")
            k = A.shape[0]
            lb, ub = self._bounds_arrays(c.lb, c.ub, k, name)
            if sp.issparse(A) and not np.all(np.isfinite(A.data)) or \
                    not sp.issparse(A) and not np.all(np.isfinite(A)):
                raise InputError(f"{name}: LinearConstraint.A contains NaN or infinity")
            Ad = A
            fun = (lambda x, A=Ad: np.asarray(A @ x, dtype=float).ravel())
            blk = _Block(name, fun, None, "linear", lb, ub, *self._split(lb, ub), A=A)
            return blk, sp.issparse(A)
        if isinstance(c, NonlinearConstraint):
            jac = c.jac if _is_callable_derivative(c.jac) else None
            hess = c.hess if _is_callable_derivative(c.hess) else None
            try:
                c0 = np.atleast_1d(np.asarray(c.fun(x0), dtype=float))
            except (TypeError, ValueError) as exc:
                raise InputError(f"{name}: fun(x0) failed: {exc}") from exc
            self.ncev += 1
            if c0.ndim != 1:
                raise InputError(f"{name}: fun(x0) must return a 1-D array; got shape "
                                 f"{c0.shape}")
            if not np.all(np.isfinite(c0)):
                raise NonFiniteValue(f"{name}.fun at x0")
            k = c0.size
            lb, ub = self._bounds_arrays(c.lb, c.ub, k, name)
            is_sparse = False
            if jac is not None:
                J0 = jac(x0)
                if sp.issparse(J0):
                    is_sparse = True
                else:
                    J0 = np.atleast_2d(np.asarray(J0, dtype=float))
                    if k == 1 and J0.shape == (1, self.n) or J0.shape == (self.n, 1) and k == 1:
                        J0 = J0.reshape(1, self.n)
                if J0.shape != (k, self.n):
                    raise InputError(f"{name}: jac(x0) has shape {J0.shape}; expected "
                                     f"({k}, {self.n}) (constraints x variables)")
            fun = (lambda x, fn=c.fun: np.atleast_1d(np.asarray(fn(x), dtype=float)))
            return _Block(name, fun, jac, hess, lb, ub, *self._split(lb, ub)), is_sparse
        raise InputError(f"{name}: expected a NonlinearConstraint, LinearConstraint or "
                         f"dict, got {type(c).__name__}")

    def _make_bounds(self, bounds):
        n = self.n
        if isinstance(bounds, Bounds):
            lb, ub = bounds.lb, bounds.ub
        else:
            try:
                pairs = [(-np.inf if a is None else a, np.inf if b is None else b)
                         for a, b in bounds]
            except (TypeError, ValueError) as exc:
                raise InputError("bounds must be a scipy.optimize.Bounds or a sequence "
                                 "of (lb, ub) pairs") from exc
            if len(pairs) != n:
                raise InputError(f"bounds has {len(pairs)} (lb, ub) pairs but x0 has "
                                 f"{n} entries")
            lb, ub = (np.array(v, dtype=float) for v in zip(*pairs))
        lb, ub = self._bounds_arrays(lb, ub, n, "bounds")
        iu, il, ie = self._split(lb, ub)
        if iu.size + il.size + ie.size == 0:
            return None
        A = sp.identity(n, format="csr")
        fun = (lambda x: np.array(x, dtype=float))
        return _Block("bounds", fun, None, "linear", lb, ub, iu, il, ie, A=A,
                      is_bounds=True)

    @staticmethod
    def _bounds_arrays(lb, ub, k, name):
        out = []
        for side, v in (("lb", lb), ("ub", ub)):
            a = np.asarray(v, dtype=float)
            if a.size == 1:
                a = np.full(k, float(a.ravel()[0]))
            elif a.shape != (k,):
                raise InputError(f"{name}: {side} has {a.size} entries but the constraint "
                                 f"has {k} components")
            if np.any(np.isnan(a)):
                raise InputError(f"{name}: {side} contains NaN")
            out.append(a)
        lb, ub = out
        bad = np.flatnonzero(lb > ub)
        if bad.size:
            i = bad[0]
            raise InputError(f"{name}: lb[{i}] = {lb[i]} > ub[{i}] = {ub[i]}; swap them")
        if np.any(lb == np.inf) or np.any(ub == -np.inf):
            raise InputError(f"{name}: lb = +inf or ub = -inf leaves no feasible point")
        return lb, ub

    @staticmethod
    def _split(lb, ub):
        eq = lb == ub
        iu = np.flatnonzero(np.isfinite(ub) & ~eq)
        il = np.flatnonzero(np.isfinite(lb) & ~eq)
        ie = np.flatnonzero(eq)
        return iu, il, ie

    def project_into_bounds(self, push: float = 0.0) -> bool:
        """Move ``x0`` into the variable bounds; True if it moved.

        ``push = 0`` clips (as SciPy does). ``push > 0`` moves every entry at least
        ``min(push max(1, |bound|), push (ub - lb))`` inside its bounds, IPOPT's
        rule with ``bound_push = bound_frac = push`` (Wachter & Biegler 2006,
        sec. 3.6); entries already that far inside do not move.
        """
        b = self.bounds_block
        if b is None:
            return False
        lo, hi = b.lb.copy(), b.ub.copy()
        if push > 0:
            with np.errstate(invalid="ignore"):
                width = np.where(np.isfinite(hi - lo), hi - lo, np.inf)
                pl = np.minimum(push * np.maximum(1.0, np.abs(lo)), push * width)
                pu = np.minimum(push * np.maximum(1.0, np.abs(hi)), push * width)
            fin_l, fin_u = np.isfinite(lo), np.isfinite(hi)
            lo[fin_l] = lo[fin_l] + pl[fin_l]
            hi[fin_u] = hi[fin_u] - pu[fin_u]
            eq = b.lb == b.ub  # fixed variables stay at their value
            lo[eq], hi[eq] = b.lb[eq], b.ub[eq]
        x = np.minimum(np.maximum(self.x0, lo), hi)
        if np.array_equal(x, self.x0):
            return False
        self.x0 = x
        return True

    # ------------------------------------------------------------- objective
    def _eval_fun(self, x):
        cx, cf, cg = self._cache_f
        if cx is not None and np.array_equal(cx, x):
            return cf, cg
        self.nfev += 1
        out = _guard("fun", self._fun, x)
        if self.fun_returns_grad:
            try:
                f, g = out
            except (TypeError, ValueError):
                raise InputError(f"jac=True: fun must return the pair (f, gradient); it returned "
                                 f"{type(out).__name__} {out!r:.40}. Return both, or pass jac=None or a callable."
                                 ) from None
            self.njev += 1
            g = np.asarray(g, dtype=float).ravel()
        else:
            f, g = out, None
        try:
            f = float(np.asarray(f).item()) if np.ndim(f) else float(f)
        except (TypeError, ValueError) as exc:
            raise InputError(f"fun must return a scalar; got {out!r:.80}") from exc
        if not np.isfinite(f):
            raise NonFiniteValue("fun")
        if g is not None:
            _check(g, "fun (gradient part)")
        self._cache_f = (x.copy(), f, g)
        return f, g

    def f(self, x):
        """Objective value, scaled (raises :class:`NonFiniteValue` on NaN/inf)."""
        return self.f_scale * self._eval_fun(x)[0]

    def grad(self, x):
        """Objective gradient (scaled), exact or by central differences."""
        g = self._grad_raw(x)
        return g if self.f_scale == 1.0 else self.f_scale * g

    def _grad_raw(self, x):
        if self.fun_returns_grad:
            return self._eval_fun(x)[1]
        if self._jac is not None:
            self.njev += 1
            g = np.asarray(_guard("jac", self._jac, x), dtype=float).ravel()
            return _check(g, "jac")
        return self._fd_grad(x)

    def _fd_grad(self, x):
        h = _EPS ** (1 / 3) * np.maximum(1.0, np.abs(x))
        g = np.empty(self.n)
        xp = x.copy()
        for i in range(self.n):
            xp[i] = x[i] + h[i]
            fp = self._fun_raw(xp)
            xp[i] = x[i] - h[i]
            fm = self._fun_raw(xp)
            xp[i] = x[i]
            g[i] = (fp - fm) / (2 * h[i])
        return _check(g, "fun (finite-difference gradient)")

    def _fun_raw(self, x):
        self.nfev += 1
        out = _guard("fun", self._fun, x)
        f = out[0] if self.fun_returns_grad else out
        return float(np.asarray(f).item()) if np.ndim(f) else float(f)

    def hess_f(self, x, sparse=False):
        """Objective Hessian, scaled (dense or CSR; ``sparse=None`` keeps the user's type)."""
        H = self._hess_raw(x, sparse)
        return H if self.f_scale == 1.0 else self.f_scale * H

    def _hess_raw(self, x, sparse):
        if self._hess is not None:
            self.nhev += 1
            H = _guard("hess", self._hess, x)
            if not sp.issparse(H):
                H = np.atleast_2d(np.asarray(H, dtype=float))
            _check(H, "hess")
        else:
            H = self._fd_jacobian_of(self._grad_raw, x, self.n, "hess (finite differences)")
            H = 0.5 * (H + H.T)
        if sparse is None:
            return H
        if sparse:
            return H.tocsr() if sp.issparse(H) else sp.csr_matrix(H)
        return H.toarray() if sp.issparse(H) else H

    def _fd_jacobian_of(self, vecfun, x, k, name):
        """Central-difference Jacobian (k x n) of a vector function."""
        step = (_EPS ** (1 / 3) if not self.grad_is_fd else 1e-4)
        h = step * np.maximum(1.0, np.abs(x))
        J = np.empty((k, self.n))
        xp = x.copy()
        for i in range(self.n):
            xp[i] = x[i] + h[i]
            vp = np.asarray(_guard(name, vecfun, xp), dtype=float)
            xp[i] = x[i] - h[i]
            vm = np.asarray(_guard(name, vecfun, xp), dtype=float)
            xp[i] = x[i]
            J[:, i] = (vp - vm) / (2 * h[i])
        return _check(J, name)

    # ----------------------------------------------------------- constraints
    def _block_values(self, x):
        cx, vals = self._cache_c
        if cx is not None and np.array_equal(cx, x):
            return vals
        self.ncev += 1
        vals = []
        for b in self.blocks:
            c = _guard(f"{b.name}.fun", b.fun, x)
            if c.shape != b.lb.shape:
                raise InputError(f"{b.name}: fun returned {c.size} values, expected "
                                 f"{b.lb.size}")
            vals.append(_check(c, f"{b.name}.fun"))
        self._cache_c = (x.copy(), vals)
        return vals

    def constraints(self, x):
        """Return ``(g, h)`` at ``x`` (scaled)."""
        vals = self._block_values(x)
        g = np.empty(self.m)
        h = np.empty(self.p)
        for b, c, (oi, oe) in zip(self.blocks, vals, self._offsets):
            nu, nl = b.iu.size, b.il.size
            g[oi:oi + nu] = c[b.iu] - b.ub[b.iu]
            g[oi + nu:oi + nu + nl] = b.lb[b.il] - c[b.il]
            h[oe:oe + b.ie.size] = c[b.ie] - b.ub[b.ie]
        if self.m:
            g *= self.g_scale
        if self.p:
            h *= self.h_scale
        return g, h

    def _block_jac(self, b, x):
        if b.A is not None:
            return b.A
        if b.jac is not None:
            J = _guard(f"{b.name}.jac", b.jac, x)
            if sp.issparse(J):
                J = J.tocsr() if self.sparse else J.toarray()
            else:
                J = np.asarray(J, dtype=float).reshape(b.lb.size, self.n)
                if self.sparse:
                    J = sp.csr_matrix(J)
            return _check(J, f"{b.name}.jac")
        J = self._fd_jacobian_of(b.fun, x, b.lb.size, f"{b.name}.fun (finite differences)")
        return sp.csr_matrix(J) if self.sparse else J

    def jacobians(self, x):
        """Return ``(Jg, Jh)``, shapes (m, n) and (p, n), dense or CSR."""
        cx, val = self._cache_j
        if cx is not None and np.array_equal(cx, x):
            return val
        gi, hi = [], []
        for b in self.blocks:
            J = self._block_jac(b, x)
            gi.append(J[b.iu])
            gi.append(-J[b.il])
            hi.append(J[b.ie])
        stack = sp.vstack if self.sparse else np.vstack
        empty = (sp.csr_matrix((0, self.n)) if self.sparse else np.zeros((0, self.n)))
        Jg = stack(gi).tocsr() if self.sparse and gi else (stack(gi) if gi else empty)
        Jh = stack(hi).tocsr() if self.sparse and hi else (stack(hi) if hi else empty)
        if np.any(self.g_scale != 1.0):
            Jg = (sp.diags(self.g_scale) @ Jg).tocsr() if self.sparse else \
                self.g_scale[:, None] * Jg
        if np.any(self.h_scale != 1.0):
            Jh = (sp.diags(self.h_scale) @ Jh).tocsr() if self.sparse else \
                self.h_scale[:, None] * Jh
        val = (Jg, Jh)
        self._cache_j = (x.copy(), val)
        return val

    def block_weights(self, wg, wh):
        """Map weights on the unscaled ``g``/``h`` to weights on each block's ``c``."""
        out = []
        for b, (oi, oe) in zip(self.blocks, self._offsets):
            v = np.zeros(b.lb.size)
            nu, nl = b.iu.size, b.il.size
            np.add.at(v, b.iu, wg[oi:oi + nu])
            np.subtract.at(v, b.il, wg[oi + nu:oi + nu + nl])
            np.add.at(v, b.ie, wh[oe:oe + b.ie.size])
            out.append(v)
        return out

    def constraint_hessian(self, x, wg, wh):
        """:math:`\\sum_i w_i \\nabla^2 c_i(x)` over nonlinear blocks (scaled), or None."""
        total = None
        wg = np.asarray(wg, float) * self.g_scale
        wh = np.asarray(wh, float) * self.h_scale
        for b, v in zip(self.blocks, self.block_weights(wg, wh)):
            if isinstance(b.hess, str) or not np.any(v):
                continue
            if b.hess is not None:
                H = _guard(f"{b.name}.hess", b.hess, x, v)
                if not sp.issparse(H):
                    H = np.atleast_2d(np.asarray(H, dtype=float))
                _check(H, f"{b.name}.hess")
            else:
                def jtv(z, b=b, v=v):
                    J = self._block_jac(b, z)
                    return np.asarray(J.T @ v).ravel()
                H = self._fd_jacobian_of(jtv, x, self.n,
                                         f"{b.name}.jac (finite-difference Hessian)")
                H = 0.5 * (H + H.T)
            if H.shape != (self.n, self.n):
                raise InputError(f"{b.name}: hess(x, v) has shape {H.shape}; expected "
                                 f"({self.n}, {self.n})")
            total = H if total is None else total + H
        return total

    @property
    def has_fd(self) -> bool:
        """Whether any derivative is computed by finite differences."""
        return (self.grad_is_fd or self.hess_is_fd or
                any(b.A is None and (b.jac is None or b.hess is None) for b in self.blocks))

    def describe(self, i: int, equality: bool = False) -> str:
        """Human-readable origin of internal inequality (or equality) ``i``."""
        for b, (oi, oe) in zip(self.blocks, self._offsets):
            if equality:
                if oe <= i < oe + b.ie.size:
                    return f"{b.name} component {b.ie[i - oe]} (lb == ub)"
                continue
            nu, nl = b.iu.size, b.il.size
            if oi <= i < oi + nu:
                return f"{b.name} component {b.iu[i - oi]} (upper bound)"
            if oi + nu <= i < oi + nu + nl:
                return f"{b.name} component {b.il[i - oi - nu]} (lower bound)"
        return f"constraint {i}"
