"""One sparse factorization of a condensed SPD matrix, reused for many solves."""

from __future__ import annotations

import dataclasses
import logging
import time

import numpy as np
import scipy.sparse as sp

from alcontact.errors import InputError
from alcontact.linalg import MatrixHints, make_solver, registered_solvers

__all__ = ["Factorization", "BACKENDS", "nested_dissection"]

#: names accepted as ``backend``: ``"auto"`` and the solvers registered at import
#: (see :mod:`alcontact.linalg`; solvers registered later are accepted too)
BACKENDS = ("auto", *registered_solvers())


logger = logging.getLogger(__name__)

#: ``check=True`` solves ``K_ff x = K_ff 1`` and flags the matrix singular if ``|x - 1| > CHECK_TOL``.
CHECK_TOL = 1e-4


def _ranges(starts: np.ndarray, lens: np.ndarray) -> np.ndarray:
    """Concatenation of ``arange(s, s + l)`` for all pairs, vectorized."""
    total = int(lens.sum())
    if total == 0:
        return np.empty(0, dtype=np.int64)
    offs = np.repeat(starts - np.concatenate([[0], np.cumsum(lens)[:-1]]), lens)
    return offs + np.arange(total)


_PERMC = ("MMD_AT_PLUS_A", "MMD_ATA", "COLAMD", "NATURAL")


def _matrix(value, what: str):
    """``value`` as a CSR matrix of floats; :class:`InputError` naming ``what`` otherwise."""
    try:
        if np.iscomplexobj(value.data if sp.issparse(value) else value):
            raise TypeError("complex")
        A = sp.csr_matrix(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{what}: expected a square scipy.sparse matrix (or array) of numbers, got "
                         f"{type(value).__name__}.") from None
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise InputError(f"{what}: expected a square matrix, got shape {A.shape}.")
    return A


def _indices(value, what: str) -> np.ndarray:
    """``value`` as sorted unique DOF indices; :class:`InputError` naming ``what`` for non-integers."""
    try:
        arr = np.asarray(value) if not isinstance(value, (str, bytes, dict, set)) and value is not None else None
    except (TypeError, ValueError, OverflowError):
        arr = None
    if arr is None or arr.dtype == object or (arr.size and not np.issubdtype(arr.dtype, np.integer)):
        raise InputError(f"{what}: expected a list of integer DOF indices, got {type(value).__name__}.")
    return np.unique(arr.astype(np.int64).ravel())


def nested_dissection(points: np.ndarray, adjacency, leaf_size: int = 64) -> np.ndarray:
    """Geometric nested-dissection ordering of a mesh graph.

    Recursively splits the node set at the median of its longest coordinate
    extent; the nodes of the lower half adjacent to the upper half form the
    separator, numbered after both halves. On 3D meshes this gives SuperLU a
    fill several times smaller than its built-in orderings (see
    :class:`Factorization`).

    Parameters
    ----------
    points : numpy.ndarray, shape (n, dim)
        Node coordinates.
    adjacency : scipy.sparse matrix, shape (n, n)
        Symmetric node graph (any nonzero = edge).
    leaf_size : int
        Sets of at most this many nodes are not split further.

    Returns
    -------
    numpy.ndarray of int, shape (n,)
        ``perm[new] = old``.
    """
    A = _matrix(adjacency, "nested_dissection: adjacency")
    try:
        points = np.asarray(points, dtype=float)
    except (TypeError, ValueError, OverflowError):
        points = None
    if points is None or points.ndim != 2 or points.shape[0] != A.shape[0] or not np.all(np.isfinite(points)):
        raise InputError(f"nested_dissection: points must be a finite (n, dim) array with n = {A.shape[0]} rows "
                         "(one per node of the adjacency).")
    if not (isinstance(leaf_size, (int, np.integer)) and not isinstance(leaf_size, bool) and leaf_size >= 1):
        raise InputError(f"nested_dissection: leaf_size = {leaf_size!r:.40}: expected an integer >= 1.")
    n = points.shape[0]
    indptr, indices = A.indptr, A.indices
    stamp = np.full(n, -1, dtype=np.int64)
    upper = np.zeros(n, dtype=bool)
    out: list[np.ndarray] = []
    stack: list[tuple[np.ndarray, bool]] = [(np.arange(n), False)]
    cid = 0
    while stack:  # iterative post-order: children first, separator after
        idx, expanded = stack.pop()
        if expanded or idx.size <= leaf_size:
            out.append(idx)
            continue
        c = points[idx, int(np.argmax(np.ptp(points[idx], axis=0)))]
        k = idx.size // 2
        low = c < np.partition(c, k)[k]
        if not (idx.size // 8 <= low.sum() <= idx.size - idx.size // 8):  # many ties: split by rank
            low = np.zeros(idx.size, dtype=bool)
            low[np.argpartition(c, k)[:k]] = True
        left, right = idx[low], idx[~low]
        cid += 1
        stamp[idx] = cid
        upper[left] = False
        upper[right] = True
        lens = indptr[left + 1] - indptr[left]
        cols = indices[_ranges(indptr[left], lens)]
        hit = (stamp[cols] == cid) & upper[cols]
        is_sep = np.zeros(left.size, dtype=bool)
        is_sep[np.repeat(np.arange(left.size), lens)[hit]] = True
        stack.append((left[is_sep], True))
        stack.append((right, False))
        stack.append((left[~is_sep], False))
    return np.concatenate(out) if out else np.empty(0, dtype=np.int64)


class Factorization:
    r"""Factor of :math:`K_{ff}`, the matrix restricted to the free DOFs, reused for many solves.

    With ``u_d`` prescribed on the fixed DOFs, :math:`K u = f` reduces to

    .. math::
        K_{ff} u_f = f_f - K_{fd} u_d .

    The matrix is symmetric positive definite after condensation; the factor comes
    from the linear solver registered as ``backend`` (:mod:`alcontact.linalg`).
    With SuperLU (no pivoting, ``SymmetricMode``) the fill-reducing ordering is
    ``permc_spec`` unless a permutation ``perm`` is given (e.g.
    :func:`nested_dissection`, several times less fill in 3D).

    Parameters
    ----------
    matrix : scipy.sparse matrix, shape (n, n)
        Symmetric matrix (e.g. the stiffness).
    fixed : array_like of int
        Indices of the prescribed DOFs (duplicates are ignored).
    permc_spec : str
        Built-in ordering (SuperLU's column ordering) when ``perm`` is None; solvers
        without a choice of orderings ignore it.
    perm : array_like of int, optional
        Symmetric ordering of the *free* DOFs (``perm[new] = position in free``) for the
        solvers that take one (SuperLU); the others order the matrix themselves.
    check : bool
        Raise :class:`~alcontact.errors.InputError` if the matrix is
        numerically singular: one extra solve of :math:`K_{ff}x = K_{ff}\mathbf 1`
        must return :math:`\mathbf 1` to ``CHECK_TOL``.
    backend : str
        A registry name of :func:`alcontact.linalg.registered_solvers` (default
        ``"superlu"``).
    hints : alcontact.linalg.MatrixHints, optional
        Ordering / near-null space of the condensed matrix for the solvers that use them.

    Attributes
    ----------
    n : int
        Size of the full system.
    free, fixed : numpy.ndarray of int
        Sorted free and fixed DOF indices.
    K_ff : scipy.sparse.csc_matrix
        Condensed matrix (original numbering of the free DOFs).
    K_fd : scipy.sparse.csr_matrix
        Coupling block used by :meth:`rhs`.
    factor : alcontact.linalg.Factor
        The solver's factor.
    backend : str
        Registry name of the solver.
    factor_seconds : float
        Wall time of the factorization.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> K = sp.diags([[-1.0] * 3, [2.0] * 4, [-1.0] * 3], [-1, 0, 1]).tocsr()
    >>> fac = Factorization(K, [0, 3])
    >>> u = fac.solve_full(np.zeros(4), fixed_values=[0.0, 3.0])
    >>> bool(np.allclose(u, [0, 1, 2, 3]))
    True
    """

    def __init__(self, matrix, fixed, *, permc_spec: str = "MMD_AT_PLUS_A", perm=None, check: bool = True,
                 backend: str = "superlu", hints: MatrixHints | None = None):
        A = _matrix(matrix, "Factorization")
        n = A.shape[0]
        if A.shape != (n, n):
            raise InputError(f"matrix must be square; got shape {A.shape}.")
        fixed = _indices(fixed, "Factorization: fixed")
        if not isinstance(permc_spec, str) or permc_spec not in _PERMC:
            raise InputError(f"Factorization: permc_spec = {permc_spec!r:.40}: expected one of {', '.join(_PERMC)}.")
        if not isinstance(backend, str):
            raise InputError(f"Factorization: backend = {backend!r:.40}: expected the name of a linear solver, "
                             "e.g. 'superlu'.")
        if fixed.size and (fixed[0] < 0 or fixed[-1] >= n):
            raise InputError(f"fixed DOF indices must lie in [0, {n}); got min {fixed[0]}, max {fixed[-1]}.")
        mask = np.ones(n, dtype=bool)
        mask[fixed] = False
        self.n = n
        self.fixed = fixed
        self.free = np.flatnonzero(mask)
        rows = A[self.free]
        self.K_ff = rows[:, self.free].tocsc()
        self.K_fd = rows[:, self.fixed].tocsr()
        solver = make_solver(backend)
        self.backend = backend
        if perm is not None:
            perm = np.asarray(perm, dtype=np.int64)
            if perm.shape != (self.free.size,) or not np.array_equal(np.sort(perm), np.arange(self.free.size)):
                raise InputError(f"perm must be a permutation of range({self.free.size}) (the free DOFs).")
        hints = dataclasses.replace(hints or MatrixHints(), ordering_name=permc_spec,
                                    **({"ordering": lambda: perm} if perm is not None else {}))
        t0 = time.perf_counter()
        self.factor = solver.factorize(self.K_ff, hints) if self.free.size else None
        #: the ordering used (solvers that order the matrix themselves report their name)
        self.ordering = getattr(self.factor, "ordering", backend)
        self.factor_seconds = time.perf_counter() - t0
        if check:
            self._check()
        logger.debug(
            "factorized %d free DOFs (%d fixed, %s, ordering %s) in %.3f s, factor nnz=%d",
            self.free.size, self.fixed.size, self.backend, self.ordering, self.factor_seconds, self.nnz,
        )

    def _check(self) -> None:
        if self.free.size == 0:
            return
        x = self.solve(self.K_ff @ np.ones(self.free.size))
        err = float(np.max(np.abs(x - 1.0))) if np.all(np.isfinite(x)) else np.inf
        if not err <= CHECK_TOL:
            raise InputError(
                f"the condensed matrix ({self.free.size} free DOFs) is singular or not positive "
                f"definite (test solve error {err:.1e}); add Dirichlet conditions that restrain "
                "every rigid-body motion."
            )

    @property
    def nnz(self) -> int:
        """Number of nonzeros of the factor (-1 when the solver does not report it)."""
        return int(self.factor.nnz) if self.factor is not None else 0

    @property
    def memory_bytes(self) -> int | None:
        """Memory of the factor as reported by the solver (None if unknown)."""
        return self.factor.memory_bytes if self.factor is not None else 0

    def solve(self, rhs) -> np.ndarray:
        """Solve :math:`K_{ff} x = r`; ``rhs`` of shape ``(n_free,)`` or ``(n_free, k)``."""
        r = np.asarray(rhs, dtype=float)
        if r.ndim not in (1, 2) or r.shape[0] != self.free.size:
            raise InputError(f"rhs must have shape ({self.free.size},) or ({self.free.size}, k); got {r.shape}.")
        if self.factor is None:
            return np.zeros_like(r)
        return self.factor.solve(r)

    def condense(self, vec) -> np.ndarray:
        """Restrict a full vector (or ``(n, k)`` array) to the free DOFs."""
        return np.asarray(vec)[self.free]

    def rhs(self, load, fixed_values=None) -> np.ndarray:
        r"""Condensed right-hand side :math:`f_f - K_{fd} u_d`.

        ``fixed_values`` aligned with :attr:`fixed` (``None`` = zeros).
        """
        f = np.asarray(load, dtype=float)
        if f.shape[0] != self.n:
            raise InputError(f"load must have length {self.n}; got shape {f.shape}.")
        r = f[self.free]
        if fixed_values is not None and self.fixed.size:
            kd = self.K_fd @ np.asarray(fixed_values, dtype=float)
            r = r - (kd[:, None] if (r.ndim == 2 and kd.ndim == 1) else kd)
        return r

    def expand(self, x_free, fixed_values=None) -> np.ndarray:
        """Full vector from free values and the prescribed ones (``None`` = zeros)."""
        x_free = np.asarray(x_free, dtype=float)
        u = np.zeros((self.n,) + x_free.shape[1:])
        u[self.free] = x_free
        if fixed_values is not None and self.fixed.size:
            ud = np.asarray(fixed_values, dtype=float)
            u[self.fixed] = ud[:, None] if (x_free.ndim == 2 and ud.ndim == 1) else ud
        return u

    def solve_full(self, load, fixed_values=None) -> np.ndarray:
        """Full solution of :math:`K u = f` with ``u[fixed] = fixed_values``."""
        return self.expand(self.solve(self.rhs(load, fixed_values)), fixed_values)
