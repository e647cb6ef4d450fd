"""Inner solvers for the unconstrained subproblems (SL) of Algorithms 5.1-5.4 (registry).

A subproblem object provides ``value(x)`` (``+inf`` outside the domain of a
barrier-type penalty or where a callback returns NaN), ``gradient(x)``
(returning the gradient and the scale used to normalise its norm),
``hessian(x)`` (dense array or SciPy sparse matrix) and ``max_step(x, d)``
(fraction-to-boundary step bound from the linearised constraints).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import InputError, UnknownNameError
from ._problem import NonFiniteValue

__all__ = ["InnerResult", "make_inner", "available_inner_solvers"]

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class InnerResult:
    """Outcome of one subproblem solve.

    ``status`` is one of ``"converged"``, ``"maxiter"``, ``"line-search"``,
    ``"small-step"``, ``"unbounded"``, ``"nonfinite"``.
    """

    x: np.ndarray
    value: float
    nit: int
    status: str
    measure: float
    nonfinite: str | None = None

    @property
    def ok(self) -> bool:
        return self.status in ("converged", "small-step")


def _norm_inf(v):
    return float(np.max(np.abs(v))) if v.size else 0.0


def _dense_direction(H, g, beta):
    """Modified Newton direction: Cholesky of ``H + tau I`` (Nocedal & Wright, Alg. 3.3)."""
    n = g.size
    diag = np.diag(H)
    dmin = float(np.min(diag))
    tau = 0.0 if dmin > 0 else -dmin + beta
    eye = np.eye(n)
    for _ in range(80):
        try:
            c = sla.cho_factor(H + tau * eye if tau else H, check_finite=False)
            d = -sla.cho_solve(c, g, check_finite=False)
            if np.all(np.isfinite(d)):
                return d, tau
        except (np.linalg.LinAlgError, ValueError):
            pass
        tau = max(2.0 * tau, beta)
    return -g, math.inf


def _sparse_direction(H, g, beta):
    """Modified Newton direction for sparse ``H``: LU of ``H + tau I``.

    Without a sparse Cholesky the test for a usable shift is that the direction
    is a descent direction with positive curvature ``d^T H d > 0``.
    """
    n = g.size
    H = H.tocsc()
    diag = H.diagonal()
    dmin = float(np.min(diag))
    tau = 0.0 if dmin > 0 else -dmin + beta
    eye = sp.identity(n, format="csc")
    gn = np.linalg.norm(g)
    for _ in range(80):
        try:
            M = (H + tau * eye) if tau else H
            d = -spla.splu(M.tocsc()).solve(g)
            if np.all(np.isfinite(d)):
                dn = np.linalg.norm(d)
                curv = float(d @ (H @ d))
                if g @ d < -1e-12 * gn * dn and curv > 0:
                    return d, tau
        except (RuntimeError, ValueError):
            pass
        tau = max(2.0 * tau, beta)
    return -g, math.inf


class Newton:
    """Newton's method with Hessian modification and Armijo backtracking.

    The direction solves :math:`(\\nabla^2 L + \\tau I) d = -\\nabla L` with the
    smallest tried shift :math:`\\tau \\ge 0` that makes the matrix positive
    definite (dense: Cholesky; sparse: LU plus a descent/curvature test).
    The step starts at ``min(1, fraction-to-boundary bound)`` and is halved
    until :math:`L(x + \\alpha d) \\le L(x) + c_1 \\alpha \\nabla L^T d`;
    ``L = +inf`` outside the domain of a barrier-type penalty, so iterates
    stay inside it.

    Parameters
    ----------
    c1 : float
        Armijo constant.
    max_backtracks : int
        Bound on the step halvings per iteration.
    shift : float
        Relative size of the first Hessian shift (times ``max(1, max|diag H|)``).
    """

    name = "newton"

    def __init__(self, c1: float = 1e-4, max_backtracks: int = 60, shift: float = 1e-8):
        if not 0 < c1 < 0.5:
            raise InputError(f"inner solver 'newton': c1 = {c1!r} must lie in (0, 0.5)")
        self.c1, self.max_backtracks, self.shift = float(c1), int(max_backtracks), float(shift)

    def solve(self, sub, x, tol, maxiter) -> InnerResult:
        """Minimize ``sub`` from ``x`` until the scaled gradient norm is <= ``tol``."""
        x = np.array(x, dtype=float)
        it = 0
        try:
            fx = sub.value(x)
            if not math.isfinite(fx):
                return InnerResult(x, fx, 0, "nonfinite", math.inf, sub.last_nonfinite)
            measure = math.inf
            for it in range(maxiter + 1):
                g, scale = sub.gradient(x)
                measure = _norm_inf(g) / scale
                if measure <= tol:
                    return InnerResult(x, fx, it, "converged", measure)
                if it == maxiter:
                    return InnerResult(x, fx, it, "maxiter", measure)
                H = sub.hessian(x)
                if sp.issparse(H):
                    beta = self.shift * max(1.0, float(np.max(np.abs(H.diagonal()))))
                    d, _ = _sparse_direction(H, g, beta)
                else:
                    beta = self.shift * max(1.0, float(np.max(np.abs(np.diag(H)))))
                    d, _ = _dense_direction(H, g, beta)
                slope = float(g @ d)
                if not slope < 0:
                    d, slope = -g, -float(g @ g)
                alpha = min(1.0, sub.max_step(x, d))
                accepted = False
                sub.last_nonfinite = None
                for _ in range(self.max_backtracks):
                    xt = x + alpha * d
                    ft = sub.value(xt)
                    if ft <= fx + self.c1 * alpha * slope:
                        accepted = True
                        break
                    if math.isfinite(ft) and abs(ft - fx) <= 100 * _EPS * max(1.0, abs(fx)):
                        # roundoff level: accept if the gradient decreases
                        gt, _ = sub.gradient(xt)
                        if _norm_inf(gt) < _norm_inf(g):
                            accepted = True
                            break
                    alpha *= 0.5 if math.isfinite(ft) else 0.25
                if not accepted:
                    # non-finite trial values are only a failed line search; a NaN at
                    # an accepted iterate (gradient/Hessian) is fatal (raised below)
                    return InnerResult(x, fx, it, "line-search", measure,
                                       sub.last_nonfinite)
                step = _norm_inf(xt - x)
                x, fx = xt, ft
                if fx < sub.unbounded_below:
                    return InnerResult(x, fx, it + 1, "unbounded", measure)
                if step <= 4 * _EPS * max(1.0, _norm_inf(x)):
                    g, scale = sub.gradient(x)
                    measure = _norm_inf(g) / scale
                    status = "converged" if measure <= tol else "small-step"
                    return InnerResult(x, fx, it + 1, status, measure)
        except NonFiniteValue as exc:
            return InnerResult(x, math.nan, it, "nonfinite", math.inf, exc.callback)
        return InnerResult(x, fx, maxiter, "maxiter", measure)  # pragma: no cover


_REGISTRY = {"newton": Newton}


def available_inner_solvers() -> list[str]:
    """Names of the registered inner solvers."""
    return sorted(_REGISTRY)


def make_inner(name: str, **params):
    """Build an inner solver by registry name (``"newton"``)."""
    try:
        cls = _REGISTRY[name]
    except (KeyError, TypeError):
        raise UnknownNameError("inner solver", name, list(_REGISTRY)) from None
    try:
        return cls(**params)
    except TypeError as exc:
        raise InputError(f"inner solver {name!r}: bad parameters {sorted(params)}: "
                         f"{exc}") from None
