"""Newton-KKT polish on the active set identified by the augmented Lagrangian loop.

Once the outer loop has identified the active set :math:`\\mathcal A` (the same
estimate :math:`\\{i : \\bar\\mu_i > -g_i\\}` in two consecutive outer
iterations), a few Newton iterations on the KKT system of ``f`` and the active
constraints

.. math::

    \\begin{bmatrix} \\nabla^2_{xx}\\ell & J_{\\mathcal A}^T \\\\ J_{\\mathcal A} & 0
    \\end{bmatrix}
    \\begin{bmatrix} d \\\\ y^+ \\end{bmatrix} =
    -\\begin{bmatrix} \\nabla f \\\\ c_{\\mathcal A} \\end{bmatrix},
    \\qquad \\ell = f + y^T c_{\\mathcal A},

converge quadratically to the KKT point (the standard acceleration of AL codes:
ALGENCAN's Newton-KKT "acceleration", Birgin & Martinez 2012; LANCELOT's final
phase). The polished point is accepted only if it satisfies *all* KKT tolerances
(C1)-(C4) (multipliers of the active inequalities >= 0, inactive ones feasible)
and the Hessian of the Lagrangian is positive semidefinite on the tangent space of
the strongly active constraints (dense problems); otherwise the AL iterate is kept.
Every evaluation and linear solve counts in the result's counters.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ._problem import NonFiniteValue

__all__ = ["kkt_polish"]


def _solve(K, rhs, sparse):
    if sparse:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                sol = spla.spsolve(sp.csc_matrix(K), rhs)
            except (RuntimeError, ValueError):
                return None
    else:
        try:
            sol = sla.solve(K, rhs, assume_a="sym", check_finite=False)
        except (np.linalg.LinAlgError, ValueError, sla.LinAlgWarning):
            sol = np.linalg.lstsq(K, rhs, rcond=None)[0]
    sol = np.asarray(sol, float).ravel()
    return sol if np.all(np.isfinite(sol)) else None


def _second_order_ok(W, J, y, n_ineq):
    """Lagrangian Hessian PSD on the null space of the strongly active rows (dense)."""
    strong = np.ones(J.shape[0], dtype=bool)
    if n_ineq:
        ya = np.abs(y[:n_ineq])
        strong[:n_ineq] = ya > 1e-8 * max(1.0, float(np.max(ya)))
    Js = J[strong]
    if Js.shape[0]:
        u, s, vt = np.linalg.svd(Js)
        rank = int(np.sum(s > 1e-10 * max(1.0, s[0] if s.size else 1.0)))
        Z = vt[rank:].T
    else:
        Z = np.eye(W.shape[0])
    if Z.shape[1] == 0:
        return True
    R = Z.T @ W @ Z
    lmin = float(np.linalg.eigvalsh(0.5 * (R + R.T))[0])
    return lmin >= -1e-8 * max(1.0, float(np.max(np.abs(np.diag(W)))))


def kkt_polish(nlp, x, g, mu, lam, opts, kkt_measures, maxiter, box_fixed=None):
    """Newton-KKT iterations on the active set ``mu > -g``.

    ``box_fixed = (at_lower, at_upper)`` (boolean arrays) names the variables whose
    bound of the box ``nlp.lower <= x <= nlp.upper`` is active: they are set to that
    bound and kept there (the Newton-KKT system is solved for the other variables;
    their bound multipliers are read from the gradient by ``kkt_measures``), and
    every iterate is projected into the box, so a polished point never leaves it.

    Returns ``(accepted, x, mu, lam, (stat, feas, comp, g, h), iterations)``; on
    rejection the input point is returned unchanged.
    """
    m, p, n = nlp.m, nlp.p, nlp.n
    A = np.flatnonzero(mu > -g)
    xk = np.array(x, dtype=float)
    F = np.arange(n)
    if box_fixed is not None:
        at_lo, at_up = box_fixed
        xk[at_lo] = nlp.lower[at_lo]
        xk[at_up] = nlp.upper[at_up]
        F = np.flatnonzero(~(at_lo | at_up))
    y = np.concatenate([np.maximum(mu[A], 0.0), lam])
    it = 0
    max_dense = 2000
    try:
        for it in range(maxiter + 1):
            mu_full = np.zeros(m)
            mu_full[A] = y[:A.size]
            lam_k = y[A.size:]
            if it > 0:
                # a (slightly) negative multiplier is clipped; the measures then say
                # honestly whether the point is still stationary
                mu_full = np.maximum(mu_full, 0.0)
                stat, feas, comp, gk, hk = kkt_measures(nlp, xk, mu_full, lam_k)
                if stat <= opts.gtol and feas <= opts.feas_tol and comp <= opts.ctol:
                    if not nlp.sparse and n <= max_dense:
                        Jg, Jh = nlp.jacobians(xk)
                        J = np.vstack([Jg[A], Jh])
                        W = nlp.hess_f(xk, sparse=False)
                        Hc = nlp.constraint_hessian(xk, mu_full, lam_k)
                        if Hc is not None:
                            W = W + (Hc.toarray() if sp.issparse(Hc) else Hc)
                        # fixed bound variables: second order on the free ones
                        # (an active bound with a zero multiplier is not checked)
                        if not _second_order_ok(W[np.ix_(F, F)], J[:, F], y, A.size):
                            return False, x, mu, lam, None, it
                    return True, xk, mu_full, lam_k, (stat, feas, comp, gk, hk), it
            if it == maxiter:
                break
            gf = nlp.grad(xk)
            gk, hk = nlp.constraints(xk)
            Jg, Jh = nlp.jacobians(xk)
            H = nlp.hess_f(xk, sparse=nlp.sparse)
            Hc = nlp.constraint_hessian(xk, mu_full, lam_k)
            nf = F.size
            if nlp.sparse:
                J = sp.vstack([Jg[A], Jh]).tocsr()
                W = H + (sp.csr_matrix(Hc) if Hc is not None else 0)
                if nf < n:
                    W, J = sp.csr_matrix(W)[F][:, F], J[:, F]
                K = sp.bmat([[W, J.T], [J, None]], format="csc")
            else:
                J = np.vstack([Jg[A], Jh])
                W = H + (Hc.toarray() if sp.issparse(Hc) else Hc) if Hc is not None else H
                if nf < n:
                    W, J = W[np.ix_(F, F)], J[:, F]
                q = J.shape[0]
                K = np.block([[W, J.T], [J, np.zeros((q, q))]])
            rhs = -np.concatenate([gf[F], gk[A], hk])
            sol = _solve(K, rhs, nlp.sparse)
            if sol is None:
                return False, x, mu, lam, None, it + 1
            d = np.zeros(n)
            d[F], y = sol[:nf], sol[nf:]
            if not np.all(np.isfinite(d)) or \
                    np.max(np.abs(d)) > 1e3 * max(1.0, float(np.max(np.abs(xk)))):
                return False, x, mu, lam, None, it + 1
            xk = nlp.project(xk + d)
    except (NonFiniteValue, np.linalg.LinAlgError, ValueError, FloatingPointError):
        return False, x, mu, lam, None, it + 1
    return False, x, mu, lam, None, it
