r"""Newton's method for one contact subproblem, in the condensed variables.

For fixed multipliers :math:`\lambda` the subproblem (S) of Algorithms 6.1 / 6.3
is the minimization of the potential energy plus the penalty energy. On the
manifold of equilibrium states :math:`u = u_{free} - K^{-1}B^T r` it reads

.. math::

    \Pi(r) = \tfrac12 r^T S r + \sum_i w_i\, \psi_i(g_i), \qquad g = g_{free} - S r,

whose stationarity :math:`r = w \circ t_N(g)` is the equilibrium of the body with
the penalized contact traction. Newton's step solves
:math:`(I + W D S)\,\Delta r = -(r - w\circ t_N)` with :math:`D = \mathrm{diag}(dt_N/dg)`;
it is exactly the full-space Newton step, restricted to the contact points.
Globalized by backtracking (Armijo) on :math:`\Pi`, which is ``+inf`` outside the
domain of barrier-type penalties, so iterates stay inside it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

__all__ = ["NewtonOutcome", "newton_step", "solve_subproblem"]


@dataclass(frozen=True)
class NewtonOutcome:
    """Outcome of one subproblem (S), for either linear-solver path.

    ``state`` is the iterate of the outer loops: the contact forces ``r`` of the
    condensed path, the free displacement ``x`` of the AMG path.
    """

    state: np.ndarray
    g: np.ndarray
    t: np.ndarray
    iterations: int
    converged: bool
    residual: float
    reason: str


#: rows whose coupling ``wd_i * max|S|`` is below this are decoupled (``dr_i = -F_i``): far below round-off
_DECOUPLED = 1e-200


def newton_step(S, wd, F) -> np.ndarray:
    r"""Newton correction: solve :math:`(I + \mathrm{diag}(wd)\,S)\,\Delta r = -F`.

    With :math:`wd \ge 0` (every law of family P and the Macaulay law) the system is
    solved in its symmetric form. Rows with :math:`wd_i = 0` (points off contact under a
    Macaulay law, or whose coupling is below round-off) give :math:`\Delta r_i = -F_i`;
    on the others, ``P``,

    .. math::

        (\mathrm{diag}(1/wd_P) + S_{PP})\,\Delta r_P = -F_P / wd_P - S_{PZ}\,\Delta r_Z,

    a symmetric positive definite system (``S`` is) solved by Cholesky on the ``|P|``
    rows only: a third of the LU of the whole matrix when every row is coupled, less when
    part of the candidates is off contact. A negative ``wd_i`` (contact springs of a body
    held only by the obstacle) or a Cholesky that fails falls back to the LU of the whole
    matrix.
    """
    n = F.size
    smax = float(np.max(np.abs(np.diagonal(S)), initial=0.0))
    if n and np.all(wd >= 0):
        P = wd * smax > _DECOUPLED
        dr = -np.asarray(F, dtype=float).copy()
        if not np.any(P):
            return dr
        Z = ~P
        A = S[np.ix_(P, P)]
        A[np.diag_indices_from(A)] += 1.0 / wd[P]
        rhs = dr[P] / wd[P]
        if np.any(Z):
            rhs -= S[np.ix_(P, Z)] @ dr[Z]
        try:
            c = sla.cho_factor(A, lower=True, check_finite=True)
        except np.linalg.LinAlgError:
            pass  # not positive definite to round-off: the LU below
        else:
            dr[P] = sla.cho_solve(c, rhs, check_finite=False)
            return dr
    J = S * wd[:, None]
    J[np.diag_indices_from(J)] += 1.0
    return sla.solve(J, -F, check_finite=True)


def solve_subproblem(dc, law, lam, r0, *, tol=1e-12, maxiter=60) -> NewtonOutcome:
    """Solve ``r = w t_N(g_free - S r; lam)`` by globalized Newton (see module doc)."""
    S = dc.S
    w = dc.weights[dc.cand]
    gfree = dc.g_free[dc.cand]
    r = np.array(r0, dtype=float)

    def merit(r_):
        g_ = gfree - S @ r_
        e = law.energy(g_, lam)
        return 0.5 * r_ @ (S @ r_) + float(np.sum(w * e)), g_

    pi, g = merit(r)
    if np.isnan(pi) or np.any(np.isnan(law.traction(g, lam))):
        return NewtonOutcome(r, g, law.traction(g, lam), 0, False, np.nan, "the penalty returned NaN")
    if not np.isfinite(pi):
        return NewtonOutcome(r, g, law.traction(g, lam), 0, False, np.inf, "start outside the penalty domain")
    scale = None
    prev_res = np.inf
    for it in range(1, maxiter + 1):
        t = law.traction(g, lam)
        F = r - w * t
        if scale is None:
            scale = max(float(np.max(np.abs(w * t), initial=0.0)), float(np.max(np.abs(r), initial=0.0)))
        fscale = max(scale, float(np.max(np.abs(r), initial=0.0)), 1e-300)
        res = float(np.max(np.abs(F), initial=0.0)) / fscale
        if res <= tol:
            return NewtonOutcome(r, g, t, it - 1, True, res, "converged")
        if res <= 1e-8 and res > 0.5 * prev_res:
            # stagnation at the round-off floor of the (ill-conditioned) system: cond(I + WDS) * 1e-16
            return NewtonOutcome(r, g, t, it - 1, True, res, "converged (residual at round-off level)")
        prev_res = res
        D = law.stiffness(g, lam)
        try:
            with warnings.catch_warnings():  # ill-conditioning shows in the residual test above, not as a warning
                warnings.simplefilter("ignore", sla.LinAlgWarning)
                dr = newton_step(S, w * D, F)
        except (sla.LinAlgError, ValueError):
            return NewtonOutcome(r, g, t, it, False, res, "singular Newton matrix")
        if float(np.max(np.abs(dr), initial=0.0)) <= 1e-13 * fscale:
            # the Newton correction is at round-off level: the residual cannot drop further
            return NewtonOutcome(r, g, t, it, True, res, "converged (step at round-off level)")
        slope = float((S @ F) @ dr)  # directional derivative of Pi: grad Pi = S F
        alpha = 1.0
        accepted = False
        for _ in range(60):
            r_try = r + alpha * dr
            pi_try, g_try = merit(r_try)
            if np.isfinite(pi_try) and pi_try <= pi + 1e-4 * alpha * min(slope, 0.0) + 1e-14 * abs(pi):
                accepted = True
                break
            alpha *= 0.5
        if not accepted:
            # the merit function is flat to round-off: accept a full step if it reduces the residual
            r_try = r + dr
            pi_try, g_try = merit(r_try)
            t_try = law.traction(g_try, lam)
            if not (np.isfinite(pi_try) and np.max(np.abs(r_try - w * t_try)) < np.max(np.abs(F))):
                return NewtonOutcome(r, g, t, it, False, res, "line search failed")
        r, g, pi = r_try, g_try, pi_try
    t = law.traction(g, lam)
    res = float(np.max(np.abs(r - w * t), initial=0.0)) / max(scale or 0.0, 1e-300)
    return NewtonOutcome(r, g, t, maxiter, res <= tol, res, "maximum Newton iterations")
