r"""Krylov methods and the preconditioners that approximate solvers offer them.

An *approximate* solver (:attr:`SolverChoice.exact <alcontact.linalg.SolverChoice>` false:
registered with ``kind="iterative"``, e.g. ``"amg"``) is used inside a preconditioned Krylov
loop: its factor of a matrix, applied as an operator, preconditions CG (symmetric positive
definite systems) or GMRES (unsymmetric ones). What the contact paths ask of a factor goes
through the functions of this module, which read the optional facilities a factor declares:

``preconditioner()``
    the operator to apply inside the Krylov loop (the AMG factor: one V-cycle); without it,
    :meth:`~alcontact.linalg.Factor.solve` itself (an inner solve to the solver's own tolerance);
``gmres_preconditioner()``
    the operator to apply inside GMRES when it differs from ``preconditioner()`` (the block-triangular
    preconditioner of a saddle-point matrix, where ``preconditioner()`` is the block-diagonal one MINRES needs);
``updated(J, delta)``
    the factor of :math:`J = A + \Delta` for a small symmetric term :math:`\Delta`, reusing the
    setup of :math:`A` (the AMG factor: :func:`~alcontact.linalg._amg.updated_hierarchy`); without
    it, a new factorization of :math:`J`;
``reflected(J, delta, Bs, overwrite=...)``
    the factor of :math:`QJQ` with the Householder reflections :math:`Q` that put each row of
    ``Bs`` on one coordinate (:func:`~alcontact.linalg._amg.reflected_hierarchy`), for springs
    that dominate their node; without it, nothing (the caller uses :func:`updated_factor`);
``levels``
    levels of a multigrid hierarchy (reported in ``solution.extra``).

:func:`add_on_pattern` forms :math:`A + \Delta` on the index arrays of ``A`` (the Newton matrices of the
full-space contact paths). The Krylov loops count their iterations: :func:`cg` and :func:`gmres` (SciPy's methods),
:func:`pcg`, a preconditioned CG that reports negative curvature (an indefinite matrix)
instead of iterating on, and :func:`minres`, preconditioned MINRES for symmetric indefinite
(saddle-point) matrices with a symmetric positive definite preconditioner. :func:`approximate_solve`
is a rough solve at a small fraction of the cost of a factorization (CG with an unsmoothed
aggregation V-cycle to a loose tolerance), for what only needs the shape of a solution (which
contact points a load moves towards the obstacle); :func:`principal_submatrix` restricts a matrix
to its free rows and columns in one pass.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator
from scipy.sparse.linalg import cg as _scipy_cg
from scipy.sparse.linalg import gmres as _scipy_gmres

from ._amg import add_on_pattern, plain_aggregation
from ._base import Factor, LinearSolver, MatrixHints

__all__ = ["cg", "gmres", "pcg", "minres", "preconditioner", "gmres_preconditioner", "updated_factor",
           "reflected_factor", "hierarchy_levels", "add_on_pattern", "approximate_solve", "principal_submatrix"]


def cg(A, b: np.ndarray, M=None, *, rtol: float, atol: float = 0.0, x0=None, maxiter: int = 5000):
    """SciPy's preconditioned CG for ``A x = b`` until ``|r| <= max(rtol |b|, atol)``.

    Returns
    -------
    x : ndarray
    iterations : int
    info : int
        SciPy's flag: 0 converged, > 0 stopped at ``maxiter``.
    """
    it = [0]

    def count(_xk):
        it[0] += 1

    x, info = _scipy_cg(A, b, x0=x0, rtol=rtol, atol=atol, M=M, maxiter=maxiter, callback=count)
    return x, it[0], info


def gmres(A, b: np.ndarray, M=None, *, rtol: float, restart: int, maxiter: int):
    """SciPy's restarted GMRES for ``A x = b`` until ``|r| <= rtol |b|``; returns ``(x, iterations, info)``."""
    it = [0]

    def count(_):
        it[0] += 1

    x, info = _scipy_gmres(A, b, rtol=rtol, atol=0.0, M=M, restart=restart, maxiter=maxiter, callback=count,
                           callback_type="pr_norm")
    return x, it[0], info


def pcg(A, b: np.ndarray, M, rtol: float, maxiter: int):
    r"""Preconditioned CG for ``A x = b`` until ``|r| <= rtol |b|``, stopping at negative curvature.

    Returns ``(x, iterations, why)`` with ``why`` ``""`` (converged), ``"negative curvature"``
    (:math:`p^T A p \le 0`: ``A`` is not positive definite), ``"indefinite preconditioner"``
    or ``"maxiter"``.
    """
    x = np.zeros_like(b)
    nb = float(np.linalg.norm(b))
    if nb == 0.0:
        return x, 0, ""
    r = b.copy()
    z = M @ r
    rz = float(r @ z)
    if not rz > 0.0:
        return x, 0, "indefinite preconditioner"
    p = z.copy()
    for k in range(1, maxiter + 1):
        Ap = A @ p
        pAp = float(p @ Ap)
        if not pAp > 0.0:
            return x, k, "negative curvature"
        a = rz / pAp
        x += a * p
        r -= a * Ap
        if float(np.linalg.norm(r)) <= rtol * nb:
            return x, k, ""
        z = M @ r
        rz_new = float(r @ z)
        if not rz_new > 0.0:
            return x, k, "indefinite preconditioner"
        p = z + (rz_new / rz) * p
        rz = rz_new
    return x, maxiter, "maxiter"


def minres(A, b: np.ndarray, M, rtol: float, maxiter: int):
    r"""Preconditioned MINRES for the symmetric (indefinite) ``A x = b`` with the SPD preconditioner ``M``.

    The Lanczos process of :math:`M^{-1/2} A M^{-1/2}` (Paige and Saunders 1975; Elman,
    Silvester and Wathen, *Finite Elements and Fast Iterative Solvers*, 2nd ed. 2014,
    Algorithm 4.1), ``M`` applied as ``M @ r`` (the approximate inverse: one block-diagonal
    preconditioner application per iteration). Each iteration minimizes the residual in the
    norm of the preconditioner, :math:`\|r\|_{M} = (r^T M r)^{1/2}`, which MINRES gets for free;
    it stops when :math:`\|r_k\|_M \le rtol\,\|b\|_M`. That norm weighs each block of a
    saddle-point system by its own scale (the force rows by the inverse stiffness, the
    constraint rows by the inverse Schur complement), where the Euclidean norm would see only
    the block with the larger numbers.

    Returns ``(x, iterations, why)`` with ``why`` ``""`` (converged), ``"indefinite
    preconditioner"`` (:math:`r^T M r < 0`: ``M`` is not positive definite) or ``"maxiter"``.
    """
    b = np.asarray(b, dtype=float)
    x = np.zeros_like(b)
    r1 = b.copy()
    y = np.asarray(M @ r1, dtype=float)
    bb = float(r1 @ y)
    if bb == 0.0 and not np.any(b):
        return x, 0, ""
    if not bb > 0.0:
        return x, 0, "indefinite preconditioner"
    beta1 = beta = float(np.sqrt(bb))
    r2 = r1.copy()
    w = np.zeros_like(b)
    w2 = np.zeros_like(b)
    old_beta = eps = dbar = 0.0
    phibar, cs, sn = beta1, -1.0, 0.0
    for k in range(1, maxiter + 1):
        v = y / beta
        y = np.asarray(A @ v, dtype=float)
        if k > 1:
            y -= (beta / old_beta) * r1
        alpha = float(v @ y)
        y -= (alpha / beta) * r2
        r1, r2 = r2, y
        y = np.asarray(M @ r2, dtype=float)
        old_beta = beta
        bb = float(r2 @ y)
        if bb < 0.0:
            return x, k, "indefinite preconditioner"
        beta = float(np.sqrt(bb))
        # the QR factorization of the Lanczos tridiagonal by Givens rotations
        old_eps = eps
        delta = cs * dbar + sn * alpha
        gbar = sn * dbar - cs * alpha
        eps = sn * beta
        dbar = -cs * beta
        gamma = float(np.hypot(gbar, beta))
        if gamma == 0.0:  # an exact breakdown with a singular tridiagonal: no further progress
            return x, k, "maxiter"
        cs, sn = gbar / gamma, beta / gamma
        phi = cs * phibar
        phibar = sn * phibar
        w1, w2 = w2, w
        w = (v - old_eps * w1 - delta * w2) / gamma
        x += phi * w
        if phibar <= rtol * beta1 or beta == 0.0:
            return x, k, ""
    return x, maxiter, "maxiter"


def preconditioner(factor: Factor):
    """The operator applying ``factor`` inside a Krylov loop (module doc)."""
    own = getattr(factor, "preconditioner", None)
    if own is not None:
        return own()
    n = factor.n
    return LinearOperator((n, n), matvec=factor.solve, matmat=factor.solve, dtype=float)


def gmres_preconditioner(factor: Factor):
    """The operator applying ``factor`` inside GMRES: its ``gmres_preconditioner()`` where it offers one (the
    block-triangular preconditioner of a saddle-point matrix, :mod:`alcontact.linalg._saddle`), else
    :func:`preconditioner`."""
    own = getattr(factor, "gmres_preconditioner", None)
    return own() if own is not None else preconditioner(factor)


def updated_factor(solver: LinearSolver, factor: Factor, J, delta, hints: MatrixHints | None = None):
    r"""The factor of :math:`J = A + \Delta` given the factor of :math:`A` (module doc).

    Returns ``(factor_J, reused)``: ``reused`` is True when the setup of :math:`A` was reused
    (``factor.updated``), False for a new ``solver.factorize(J, hints)``.
    """
    own = getattr(factor, "updated", None)
    if own is not None:
        return own(J, delta), True
    return solver.factorize(J, hints), False


def reflected_factor(factor: Factor, J, delta, Bs, *, overwrite: bool = False):
    """``(factor of QJQ, Q - I)`` when ``factor`` offers the reflected update (module doc), else ``None``.

    The returned factor's ``A`` is the reflected matrix :math:`QJQ` the Krylov loop runs on.
    """
    own = getattr(factor, "reflected", None)
    return None if own is None else own(J, delta, Bs, overwrite=overwrite)


def hierarchy_levels(factor: Factor | None) -> int:
    """Levels of a multigrid factor's hierarchy; 0 without a factor, 1 for a factor without levels."""
    if factor is None:
        return 0
    return int(getattr(factor, "levels", 1))


def approximate_solve(A, b: np.ndarray, near_null=None, *, rtol: float, x0=None, maxiter: int = 200):
    r"""A rough solution of the symmetric positive definite system :math:`A x = b`, without a factorization.

    CG from ``x0`` (zero by default) preconditioned by one V-cycle of the unsmoothed aggregation
    hierarchy of ``A`` (:func:`~alcontact.linalg._amg.plain_aggregation`, with the near-null
    space ``near_null``, e.g. the rigid-body modes), until the residual falls by ``rtol``
    relative to that of ``x0``: :math:`|b - A x| \le` ``rtol`` :math:`|b - A x_0|`.

    Returns
    -------
    x : ndarray
    iterations : int
        CG iterations (``maxiter`` when the tolerance was not reached; ``x`` is the last iterate).
    """
    x0 = np.zeros_like(b) if x0 is None else np.asarray(x0, dtype=float)
    r0 = b - A @ x0
    if not np.any(r0):
        return x0.copy(), 0
    ml = plain_aggregation(A, near_null)
    dx, iterations, _ = cg(A, r0, ml.aspreconditioner(cycle="V"), rtol=rtol, maxiter=maxiter)
    return x0 + dx, iterations


def principal_submatrix(A, keep: np.ndarray) -> sp.csr_matrix:
    """``A[keep][:, keep]`` of a CSR matrix for a boolean mask, in one pass (sorted indices kept).

    Peak memory: the result plus one boolean per entry of ``A`` (the two-step slicing
    copies the kept rows first).
    """
    A = sp.csr_matrix(A)
    newpos = np.cumsum(keep) - 1
    rows = np.flatnonzero(keep)
    lens = np.diff(A.indptr)
    sel = np.repeat(keep, lens)
    sel &= keep[A.indices]
    # one padding entry: the start of trailing empty rows (== nnz) stays a valid reduceat index
    counts = np.add.reduceat(np.append(sel, False), A.indptr[:-1]) if A.nnz else np.zeros(A.shape[0], dtype=np.int64)
    counts[lens == 0] = 0  # reduceat returns the next row's first entry for empty rows
    indptr = np.zeros(rows.size + 1, dtype=np.int64)
    np.cumsum(counts[rows], out=indptr[1:])
    idx_t = np.int32 if max(indptr[-1], rows.size) < np.iinfo(np.int32).max else np.int64
    out = sp.csr_matrix((A.data[sel], newpos[A.indices[sel]].astype(idx_t), indptr.astype(idx_t)),
                        shape=(rows.size, rows.size))
    out.has_sorted_indices = A.has_sorted_indices
    return out
