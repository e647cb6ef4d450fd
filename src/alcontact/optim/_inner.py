"""Inner solvers for the unconstrained subproblems (SL) of Algorithms 5.1-5.4 (registry).

``"newton"``: modified Newton with Armijo backtracking (and, for small dense
Hessians, a second-order test with a negative-curvature step); ``"trust-region"``:
Newton with the exact trust-region step from an eigendecomposition (dense), falling
back to ``"newton"`` for sparse Hessians. Subproblems with a box
``lower <= x <= upper`` (``sub.lower``/``sub.upper`` not None; bounds of method
``"al"``) are solved by Bertsekas' projected Newton method
(:meth:`Newton.solve_box`) whichever solver is chosen.

A subproblem object provides ``value(x)`` (``+inf`` outside the domain of a
barrier-type penalty or where a callback returns NaN), ``gradient(x)``
(returning the gradient and the scale used to normalise its norm),
``hessian(x)`` (dense array or SciPy sparse matrix) and ``max_step(x, d)``
(fraction-to-boundary step bound from the linearised constraints), and
``lower``/``upper`` (the box, or None).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import InputError, UnknownNameError
from ..status import Status
from ._problem import NonFiniteValue

__all__ = ["InnerResult", "make_inner", "available_inner_solvers"]

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class InnerResult:
    """Outcome of one subproblem solve.

    ``status`` is one of ``"converged"``, ``"maxiter"``, ``"line-search"``,
    ``"small-step"``, ``"unbounded"``, ``"nonfinite"``; :attr:`code` is its entry
    in the project's status table (:data:`alcontact.status.INNER_REASONS`).
    """

    x: np.ndarray
    value: float
    nit: int
    status: str
    measure: float
    nonfinite: str | None = None

    @property
    def code(self) -> Status:
        """The reason as a member of :class:`alcontact.status.Status`."""
        return Status.from_inner(self.status)

    @property
    def ok(self) -> bool:
        """Whether the subproblem counts as solved (a positive :attr:`code`)."""
        return self.code > 0


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
    neg_tol : float
        Second-order test for dense Hessians with ``n <= max_dense``: a point with a
        small gradient is accepted only if the smallest eigenvalue of ``H`` is
        ``>= -neg_tol * max(1, max|eig|)``; otherwise the solver takes a
        backtracking step along the eigenvector of that eigenvalue (a direction of
        negative curvature, More & Sorensen 1979) and goes on. This escapes saddle
        points where the gradient vanishes by symmetry (HS33: ``x2 = 0``), which no
        Newton direction from a positive definite modification can leave.
    max_dense : int
        Largest ``n`` for that eigenvalue test (0 switches it off).
    eps_active : float
        Box subproblems (:meth:`solve_box`): the threshold :math:`\\varepsilon` of the
        :math:`\\varepsilon`-active set (distance to a bound, in the units of ``x``).
    """

    name = "newton"

    def __init__(self, c1: float = 1e-4, max_backtracks: int = 60, shift: float = 1e-8,
                 neg_tol: float = 1e-6, max_dense: int = 400, eps_active: float = 1e-3):
        if not 0 < c1 < 0.5:
            raise InputError(f"inner solver 'newton': c1 = {c1!r} must lie in (0, 0.5)")
        if not eps_active >= 0:
            raise InputError(f"inner solver 'newton': eps_active = {eps_active!r} must be "
                             ">= 0")
        self.c1, self.max_backtracks, self.shift = float(c1), int(max_backtracks), float(shift)
        self.neg_tol, self.max_dense = float(neg_tol), int(max_dense)
        self.eps_active = float(eps_active)

    def _negative_curvature(self, sub, x, fx, g):
        """A step along the most negative curvature, or None at a second-order point."""
        if x.size > self.max_dense:
            return None
        H = sub.hessian(x)
        if sp.issparse(H):
            return None
        lam, Q = np.linalg.eigh(0.5 * (H + H.T))
        if not lam[0] < -self.neg_tol * max(1.0, float(np.max(np.abs(lam)))):
            return None
        d = Q[:, 0] if g @ Q[:, 0] <= 0 else -Q[:, 0]
        d = d * max(1.0, float(np.linalg.norm(x)))
        slope, curv = float(g @ d), float(d @ (H @ d))
        alpha = min(1.0, sub.max_step(x, d))
        for _ in range(self.max_backtracks):
            xt = x + alpha * d
            ft = sub.value(xt)
            if ft < fx + self.c1 * (alpha * slope + 0.5 * alpha * alpha * curv):
                return xt, ft
            alpha *= 0.5
        return None

    def solve(self, sub, x, tol, maxiter) -> InnerResult:
        """Minimize ``sub`` from ``x`` until the scaled gradient norm is <= ``tol``.

        A subproblem with a box (``sub.lower`` not None) is solved on the box by
        :meth:`solve_box`.
        """
        if getattr(sub, "lower", None) is not None:
            return self.solve_box(sub, x, tol, maxiter)
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
                    step = self._negative_curvature(sub, x, fx, g) if it < maxiter else None
                    if step is None:
                        return InnerResult(x, fx, it, "converged", measure)
                    x, fx = step
                    continue
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

    # ------------------------------------------------------------------ box
    def _box_curvature(self, sub, x, fx, g, lo, hi):
        """Projected step along the most negative curvature of ``H``, or None.

        The eigenvector belongs to ``H`` on all variables that are not fixed
        (``l_i < u_i``), including those on a bound: at a bound where the gradient
        of a violated constraint vanishes (HS33: ``x3 = 0`` and ``x3^2 >= x1^2 + x2^2``)
        the penalty's curvature is the only force that can move the variable off it.
        The trial points are ``P(x + alpha d)`` for both signs of ``d`` (an uphill sign
        starts beyond the zero of the quadratic model), accepted when the actual
        decrease beats ``c1`` times the model's. None at a
        second-order point (within ``neg_tol``), for sparse Hessians and for
        ``n > max_dense``.
        """
        idx = np.flatnonzero(lo < hi)
        if idx.size == 0 or x.size > self.max_dense:
            return None
        H = sub.hessian(x)
        if sp.issparse(H):
            return None
        HF = H[np.ix_(idx, idx)]
        lam, Q = np.linalg.eigh(0.5 * (HF + HF.T))
        if not lam[0] < -self.neg_tol * max(1.0, float(np.max(np.abs(lam)))):
            return None
        q = Q[:, 0] if g[idx] @ Q[:, 0] <= 0 else -Q[:, 0]
        for sign in (1.0, -1.0):
            d = np.zeros_like(x)
            d[idx] = sign * q * max(1.0, float(np.linalg.norm(x)))
            # uphill start (g^T d > 0): begin beyond the zero of the model along d
            gd, curv = float(g @ d), float(d @ (H @ d))
            alpha = max(1.0, -4.0 * gd / curv) if gd > 0 else 1.0
            alpha = min(alpha, sub.max_step(x, d))
            for _ in range(self.max_backtracks):
                xt = np.minimum(np.maximum(x + alpha * d, lo), hi)
                s = xt - x
                model = float(g @ s + 0.5 * s @ (H @ s))
                if model < 0:
                    ft = sub.value(xt)
                    if ft < fx + self.c1 * model:
                        return xt, ft
                alpha *= 0.5
        return None

    def _box_search(self, sub, x, fx, g, d, slope, ia, lo, hi, scale, measure):
        """Backtracking on the projected path ``P(x + alpha d)``; ``(None, None)`` on failure.

        With ``slope`` (Newton step on the free variables ``F``, scaled gradient step
        on the active ones ``ia``) the sufficient decrease is Bertsekas' (1982)
        ``alpha g_F^T d_F + g_A^T (x_A(alpha) - x_A)``; with ``slope=None`` (projected
        gradient) it is ``g^T (x(alpha) - x)``.
        """
        alpha = min(1.0, sub.max_step(x, d))
        for _ in range(self.max_backtracks):
            xt = np.minimum(np.maximum(x + alpha * d, lo), hi)
            ft = sub.value(xt)
            if slope is None:
                pred = float(g @ (xt - x))
            else:
                pred = alpha * slope + float(g[ia] @ (xt[ia] - x[ia]))
            if ft <= fx + self.c1 * pred and (slope is not None or pred < 0):
                return xt, ft
            if math.isfinite(ft) and abs(ft - fx) <= 100 * _EPS * max(1.0, abs(fx)):
                gt, _ = sub.gradient(xt)
                mt = _norm_inf(xt - np.minimum(np.maximum(xt - gt / scale, lo), hi))
                if mt < measure:
                    return xt, ft
            alpha *= 0.5 if math.isfinite(ft) else 0.25
        return None, None

    def solve_box(self, sub, x, tol, maxiter) -> InnerResult:
        """Minimize ``sub`` on the box ``sub.lower <= x <= sub.upper`` (projected Newton).

        Bertsekas' projected Newton method (SIAM J. Control Optim. 20, 1982) as
        used for the box-constrained AL subproblems of LANCELOT and ALGENCAN:
        with the normalised gradient :math:`\\hat g = \\nabla L / s` the stopping
        measure is the projected-gradient norm

        .. math:: \\|x - P(x - \\hat g)\\|_\\infty \\le \\text{tol},

        the :math:`\\varepsilon`-active set is :math:`\\{i: x_i \\le l_i +
        \\varepsilon_k,\\ g_i > 0\\} \\cup \\{i: x_i \\ge u_i - \\varepsilon_k,\\ g_i < 0\\}`
        with :math:`\\varepsilon_k = \\min(\\varepsilon, \\text{measure})`; the free
        variables take the modified Newton step of the reduced Hessian
        :math:`H_{FF}` (dense Cholesky or sparse LU with shifts, as :meth:`solve`),
        the active ones the diagonally scaled gradient step
        :math:`-g_i/\\max(H_{ii}, \\beta)`. The trial point is projected,
        :math:`x(\\alpha) = P(x + \\alpha d)`, and accepted by Bertsekas' Armijo rule
        :math:`L(x(\\alpha)) \\le L(x) + c_1 (\\alpha g_F^T d_F + g_A^T (x_A(\\alpha) - x_A))`.
        Every iterate lies in the box; variables reach their bounds exactly.
        A point with a small measure must also pass a negative-curvature test
        (:meth:`_box_curvature`; dense, ``n <= max_dense``).
        """
        lo, hi = np.asarray(sub.lower, float), np.asarray(sub.upper, float)
        x = np.minimum(np.maximum(np.array(x, dtype=float), lo), hi)
        fixed = lo == hi
        it = 0
        try:
            fx = sub.value(x)
            if not math.isfinite(fx):
                return InnerResult(x, fx, 0, "nonfinite", math.inf, sub.last_nonfinite)
            measure = math.inf
            for it in range(maxiter + 1):
                g, scale = sub.gradient(x)
                gs = g / scale
                measure = _norm_inf(x - np.minimum(np.maximum(x - gs, lo), hi))
                eps = min(self.eps_active, measure)
                active = fixed | ((x <= lo + eps) & (g > 0)) | ((x >= hi - eps) & (g < 0))
                free = ~active
                if measure <= tol:
                    step = self._box_curvature(sub, x, fx, g, lo, hi) \
                        if it < maxiter else None
                    if step is None:
                        return InnerResult(x, fx, it, "converged", measure)
                    x, fx = step
                    continue
                if it == maxiter:
                    return InnerResult(x, fx, it, "maxiter", measure)
                H = sub.hessian(x)
                d = np.zeros_like(x)
                idx = np.flatnonzero(free)
                if sp.issparse(H):
                    H = H.tocsr()
                    hdiag = H.diagonal()
                else:
                    hdiag = np.diag(H)
                beta = self.shift * max(1.0, float(np.max(np.abs(hdiag))))
                slope = 0.0
                if idx.size:
                    gF = g[idx]
                    if sp.issparse(H):
                        HF = H[idx][:, idx]
                        dF, _ = _sparse_direction(HF, gF, beta)
                    else:
                        dF, _ = _dense_direction(H[np.ix_(idx, idx)], gF, beta)
                    slope = float(gF @ dF)
                    if not slope < 0:
                        dF, slope = -gF, -float(gF @ gF)
                    d[idx] = dF
                ia = np.flatnonzero(active & ~fixed)
                d[ia] = -g[ia] / np.maximum(hdiag[ia], beta)
                sub.last_nonfinite = None
                xt, ft = self._box_search(sub, x, fx, g, d, slope, ia, lo, hi, scale,
                                          measure)
                if xt is None:
                    # projected gradient path (Bertsekas 1976), when the Newton path of
                    # a nearly singular reduced Hessian is too long for the backtracking
                    d = np.where(fixed, 0.0, -g)
                    xt, ft = self._box_search(sub, x, fx, g, d, None, None, lo, hi,
                                              scale, measure)
                if xt is None:
                    return InnerResult(x, fx, it, "line-search", measure,
                                       sub.last_nonfinite)
                step = _norm_inf(xt - x)
                x, fx = xt, ft
                if fx < sub.unbounded_below:
                    return InnerResult(x, fx, it + 1, "unbounded", measure)
                if step <= 4 * _EPS * max(1.0, _norm_inf(x)):
                    g, scale = sub.gradient(x)
                    measure = _norm_inf(x - np.minimum(np.maximum(x - g / scale, lo), hi))
                    status = "converged" if measure <= tol else "small-step"
                    return InnerResult(x, fx, it + 1, status, measure)
        except NonFiniteValue as exc:
            return InnerResult(x, math.nan, it, "nonfinite", math.inf, exc.callback)
        return InnerResult(x, fx, maxiter, "maxiter", measure)  # pragma: no cover


def _tr_step(lam, Q, g, radius):
    """Exact trust-region step from ``H = Q diag(lam) Q^T`` (Nocedal & Wright, Alg. 4.3).

    Solves :math:`\\min_p g^Tp + \\tfrac12 p^THp` s.t. :math:`\\|p\\|_2 \\le \\Delta`
    through the secular equation :math:`1/\\|p(\\sigma)\\| = 1/\\Delta` with
    :math:`p(\\sigma) = -(H + \\sigma I)^{-1} g`, including the hard case (``g``
    orthogonal to the eigenvectors of the smallest eigenvalue), where the step
    follows the direction of most negative curvature to the boundary.
    """
    gt = Q.T @ g
    lmin = float(lam[0])
    hscale = max(1.0, float(np.max(np.abs(lam))))
    if lmin > 1e-14 * hscale:
        p = -(gt / lam)
        if np.linalg.norm(p) <= radius:
            return Q @ p
    lo = max(0.0, -lmin)
    tiny = 1e-12 * hscale
    near = np.abs(lam - lmin) <= tiny
    rest = ~near
    gnorm = float(np.linalg.norm(gt))

    def pnorm(sig):
        return float(np.sqrt(np.sum((gt / (lam + sig)) ** 2)))

    if lmin <= tiny and np.linalg.norm(gt[near]) <= 1e-10 * max(gnorm, _EPS):
        # hard case candidate: sigma = -lmin; does the regular part fit inside?
        pr = np.zeros_like(gt)
        pr[rest] = -gt[rest] / (lam[rest] + lo)
        pn = float(np.linalg.norm(pr))
        if pn <= radius:
            tau = math.sqrt(max(radius * radius - pn * pn, 0.0))
            z = np.zeros_like(gt)
            z[int(np.flatnonzero(near)[0])] = 1.0
            p = Q @ (pr + tau * z)
            if g @ p > 0:  # same model value either way; prefer descent
                p = Q @ (pr - tau * z)
            return p
    # regular case: Newton on phi(s) = 1/|p(s)| - 1/radius from the left (monotone)
    sig = lo + max(tiny, 1e-12 * lo)
    if gnorm == 0.0:
        return np.zeros_like(g)
    hi = gnorm / radius + lo
    for _ in range(100):
        w = gt / (lam + sig)
        pn = float(np.sqrt(np.sum(w * w)))
        if abs(pn - radius) <= 1e-6 * radius:
            break
        if pn < radius:
            hi = min(hi, sig)
        dphi = float(np.sum(w * w / (lam + sig))) / pn ** 3
        step = (1.0 / pn - 1.0 / radius) / dphi if dphi > 0 else math.inf
        new = sig - step
        if not (lo < new < hi) or not math.isfinite(new):
            new = 0.5 * (max(sig, lo) + hi) if pn > radius else 0.5 * (lo + sig)
        sig = new
    return -(Q @ (gt / (lam + sig)))


class TrustRegion:
    """Newton trust-region method with the exact subproblem solve for dense Hessians.

    Each step minimises the quadratic model :math:`g^Tp + \\tfrac12 p^T H p` in the
    ball :math:`\\|p\\|_2 \\le \\Delta` from the eigendecomposition of ``H``
    (Moré & Sorensen; Nocedal & Wright, sec. 4.3), so indefinite Hessians give steps
    along negative curvature, and the radius controls the step length where the
    model is poor (no jumps into far, flat regions). The radius follows the ratio
    :math:`\\rho` of actual to predicted decrease (shrink to ``|p|/4`` when
    :math:`\\rho < 1/4`, double when :math:`\\rho > 3/4` on the boundary); a step is
    accepted when :math:`\\rho > \\eta_1`.

    Second-order stop: a point with a small gradient is a solution only if the
    smallest eigenvalue of ``H`` is ``>= -neg_tol * max(1, max|eig|)``; otherwise the
    solver steps along the eigenvector of that eigenvalue (escaping saddle points
    such as the symmetric one of HS33, where the gradient component is exactly 0).

    Sparse Hessians, or ``n > max_dense``, are handled by :class:`Newton`
    (line search, Hessian shifts).

    Parameters
    ----------
    eta1 : float
        Acceptance threshold on the ratio, in (0, 1/4).
    neg_tol : float
        Relative tolerance on negative eigenvalues at a stationary point.
    max_dense : int
        Largest ``n`` for the dense eigendecomposition.
    max_rejections : int
        Bound on consecutive radius reductions per iteration.
    """

    name = "trust-region"

    def __init__(self, eta1: float = 1e-4, neg_tol: float = 1e-6, max_dense: int = 400,
                 max_rejections: int = 60):
        if not 0 < eta1 < 0.25:
            raise InputError(f"inner solver 'trust-region': eta1 = {eta1!r} must lie in "
                             "(0, 0.25)")
        self.eta1, self.neg_tol = float(eta1), float(neg_tol)
        self.max_dense, self.max_rejections = int(max_dense), int(max_rejections)
        self._fallback = Newton()

    def solve(self, sub, x, tol, maxiter) -> InnerResult:
        """Minimize ``sub`` from ``x`` until the scaled gradient norm is <= ``tol``
        and the Hessian has no significantly negative eigenvalue (a subproblem with
        a box goes to :meth:`Newton.solve_box`)."""
        if getattr(sub, "lower", None) is not None:
            return self._fallback.solve_box(sub, x, tol, maxiter)
        x = np.array(x, dtype=float)
        it = 0
        radius = None
        try:
            fx = sub.value(x)
            if not math.isfinite(fx):
                return InnerResult(x, fx, 0, "nonfinite", math.inf, sub.last_nonfinite)
            measure = math.inf
            for it in range(maxiter + 1):
                g, scale = sub.gradient(x)
                measure = _norm_inf(g) / scale
                small = measure <= tol
                if small and x.size > self.max_dense:
                    return InnerResult(x, fx, it, "converged", measure)
                if it == maxiter and not small:
                    return InnerResult(x, fx, it, "maxiter", measure)
                H = sub.hessian(x)
                if sp.issparse(H) or x.size > self.max_dense:
                    return self._continue_newton(sub, x, tol, maxiter, it)
                lam, Q = np.linalg.eigh(0.5 * (H + H.T))
                hmax = max(1.0, float(np.max(np.abs(lam))))
                negative = lam[0] < -self.neg_tol * hmax
                if small and not negative:
                    return InnerResult(x, fx, it, "converged", measure)
                if it == maxiter:
                    return InnerResult(x, fx, it, "maxiter", measure)
                if radius is None:
                    radius = self._initial_radius(lam, Q, g, x)
                if small:
                    # saddle: step along the most negative curvature direction
                    q = Q[:, 0]
                    d = -q if g @ q > 0 else q
                    steps = (lambda r, d=d: r * d)
                else:
                    steps = (lambda r: _tr_step(lam, Q, g, r))
                sub.last_nonfinite = None
                xt, ft, radius, pnorm = self._ratio_test(sub, x, fx, g, H, steps, radius)
                if xt is None:
                    if small:  # negative curvature below roundoff: a second-order point
                        return InnerResult(x, fx, it, "converged", measure)
                    status = "small-step" if math.isfinite(fx) else "line-search"
                    if sub.last_nonfinite is not None or pnorm > 1e-8 * max(
                            1.0, float(np.linalg.norm(x))):
                        status = "line-search"
                    return InnerResult(x, fx, it, status, measure, sub.last_nonfinite)
                x, fx = xt, ft
                if fx < sub.unbounded_below:
                    return InnerResult(x, fx, it + 1, "unbounded", measure)
        except NonFiniteValue as exc:
            return InnerResult(x, math.nan, it, "nonfinite", math.inf, exc.callback)
        return InnerResult(x, fx, maxiter, "maxiter", measure)  # pragma: no cover

    def _ratio_test(self, sub, x, fx, g, H, steps, radius):
        """Trial steps ``steps(radius)`` with the radius updated by the ratio :math:`\\rho` (class doc).

        Returns ``(x_trial, f_trial, radius, |p|)`` of the accepted step (:math:`\\rho > \\eta_1`,
        or a value flat to round-off with a smaller gradient), or ``(None, None, radius, |p|)``
        when no step is accepted: the model predicts no decrease, the step is at round-off
        level, or ``max_rejections`` reductions failed.
        """
        pnorm = math.nan
        for _ in range(self.max_rejections):
            p = steps(radius)
            bound = sub.max_step(x, p)
            if bound < 1.0:
                p = bound * p
            pnorm = float(np.linalg.norm(p))
            pred = float(g @ p + 0.5 * p @ (H @ p))
            if not pred < 0 or pnorm <= 4 * _EPS * max(1.0, float(np.linalg.norm(x))):
                break
            xt = x + p
            ft = sub.value(xt)
            rho = (ft - fx) / pred if math.isfinite(ft) else -math.inf
            if rho < 0.25:
                radius = 0.25 * pnorm
            elif rho > 0.75 and pnorm >= 0.99 * radius:
                radius = 2.0 * radius
            if rho > self.eta1:
                return xt, ft, radius, pnorm
            if math.isfinite(ft) and abs(ft - fx) <= 100 * _EPS * max(1.0, abs(fx)):
                gt, _ = sub.gradient(xt)
                if _norm_inf(gt) < _norm_inf(g):
                    return xt, ft, radius, pnorm
        return None, None, radius, pnorm

    @staticmethod
    def _initial_radius(lam, Q, g, x):
        """The Newton step length if ``H`` is positive definite, else ``max(1, |x|)``."""
        if lam[0] > 0:
            return max(float(np.linalg.norm((Q.T @ g) / lam)), 1e-8)
        return max(1.0, float(np.linalg.norm(x)))

    def _continue_newton(self, sub, x, tol, maxiter, it):
        res = self._fallback.solve(sub, x, tol, max(maxiter - it, 1))
        return InnerResult(res.x, res.value, res.nit + it, res.status, res.measure,
                           res.nonfinite)


_REGISTRY = {"newton": Newton, "trust-region": TrustRegion}


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
