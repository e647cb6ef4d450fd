"""The built-in solvers: SuperLU, CHOLMOD (cholespy), PyAMG + CG (MKL PARDISO: :mod:`._pardiso`).

Each class implements :class:`~alcontact.linalg._base.LinearSolver`; its
``factorize`` returns a :class:`~alcontact.linalg._base.Factor`. Import of the
optional packages happens in ``factorize`` (and in :func:`installed` checks of
the registry), so the module imports without them.
"""

from __future__ import annotations

import logging
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import cg, splu

from ..errors import InputError
from ._base import MatrixHints

__all__ = ["SuperLUSolver", "CholmodSolver", "AMGSolver"]

logger = logging.getLogger(__name__)


def _singular(n: int, detail: str) -> InputError:
    return InputError(
        f"the condensed matrix ({n} free DOFs) is singular or not positive definite ({detail}); "
        "add Dirichlet conditions that restrain every rigid-body motion."
    )


def _check_rhs(rhs, n: int) -> np.ndarray:
    r = np.asarray(rhs, dtype=float)
    if r.ndim not in (1, 2) or r.shape[0] != n:
        raise InputError(f"rhs must have shape ({n},) or ({n}, k); got {r.shape}.")
    return r


# ---------------------------------------------------------------------- SuperLU
class _SuperLUFactor:
    exact = True

    def __init__(self, lu, perm, n, seconds, ordering):
        self.name = "superlu"
        self._lu, self._perm, self.n = lu, perm, n
        self.factor_seconds = seconds
        self.ordering = ordering

    @property
    def nnz(self) -> int:
        return int(self._lu.nnz)

    @property
    def memory_bytes(self) -> int:
        """Values and row indices of L and U (8 + 4 bytes per nonzero)."""
        return 12 * int(self._lu.nnz)

    def solve(self, rhs) -> np.ndarray:
        r = _check_rhs(rhs, self.n)
        if self._perm is None:
            return self._lu.solve(np.ascontiguousarray(r) if r.ndim == 1 else np.asfortranarray(r))
        rp = r[self._perm]
        y = self._lu.solve(np.ascontiguousarray(rp) if r.ndim == 1 else np.asfortranarray(rp))
        x = np.empty_like(y)
        x[self._perm] = y
        return x


class SuperLUSolver:
    """SciPy's SuperLU run as a symmetric solver (no pivoting, ``SymmetricMode``).

    With ``hints.matrix_type`` ``"symmetric-indefinite"`` or ``"unsymmetric"`` it pivots
    (partial pivoting, the general LU).

    Parameters
    ----------
    permc_spec : str
        SuperLU column ordering used when no ordering is given (``MMD_AT_PLUS_A``,
        SuperLU's best on these matrices in 2D); ``hints.ordering_name`` overrides it.
    use_ordering : bool
        Use ``hints.ordering`` (the mesh's nested dissection) when given: several
        times less fill than SuperLU's own orderings in 3D.
    """

    name = "superlu"
    kind = "direct"

    def __init__(self, permc_spec: str = "MMD_AT_PLUS_A", use_ordering: bool = True):
        self.permc_spec = permc_spec
        self.use_ordering = use_ordering

    def factorize(self, matrix, hints: MatrixHints | None = None) -> _SuperLUFactor:
        A = sp.csc_matrix(matrix)
        n = A.shape[0]
        perm = None
        if self.use_ordering and hints is not None and hints.ordering is not None:
            perm = hints.ordering()
        permc = (hints.ordering_name if hints is not None else None) or self.permc_spec
        if perm is not None:
            perm = np.asarray(perm, dtype=np.int64)
            if perm.shape != (n,) or not np.array_equal(np.sort(perm), np.arange(n)):
                raise InputError(f"perm must be a permutation of range({n}) (the free DOFs).")
            A = A[perm][:, perm].tocsc()
            permc = "NATURAL"
        pivoting = hints is not None and hints.matrix_type != "spd"
        t0 = time.perf_counter()
        try:
            if pivoting:  # symmetric indefinite or unsymmetric: partial pivoting (no symmetric mode)
                lu = splu(A, permc_spec=permc)
            else:
                lu = splu(A, permc_spec=permc, diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise _singular(n, str(exc)) from exc
        return _SuperLUFactor(lu, perm, n, time.perf_counter() - t0, "given" if perm is not None else permc)


# ---------------------------------------------------------------------- CHOLMOD
class _CholmodFactor:
    exact = True
    nnz = -1  # cholespy does not report the factor size
    memory_bytes = None

    def __init__(self, chol, n, seconds):
        self.name = "cholmod"
        self._chol, self.n, self.factor_seconds = chol, n, seconds

    def solve(self, rhs) -> np.ndarray:
        b = np.ascontiguousarray(_check_rhs(rhs, self.n), dtype=np.float64)
        x = np.zeros_like(b)
        if b.size:
            self._chol.solve(b, x)
        return x


class CholmodSolver:
    """Supernodal Cholesky of SuiteSparse CHOLMOD through the ``cholespy`` wheels (own AMD/METIS ordering)."""

    name = "cholmod"
    kind = "direct"

    def factorize(self, matrix, hints: MatrixHints | None = None) -> _CholmodFactor:
        import cholespy

        K = sp.csr_matrix(matrix)
        K.sort_indices()
        n = K.shape[0]
        t0 = time.perf_counter()
        try:
            chol = cholespy.CholeskySolverD(
                n, K.indptr.astype(np.int32), K.indices.astype(np.int32),
                np.ascontiguousarray(K.data, dtype=np.float64), cholespy.MatrixType.CSR,
            )
        except Exception as exc:  # CHOLMOD refuses a matrix that is not positive definite
            raise _singular(n, str(exc)) from exc
        return _CholmodFactor(chol, n, time.perf_counter() - t0)


# ---------------------------------------------------------------------- AMG + CG
class _AMGFactor:
    """Smoothed-aggregation hierarchy; :meth:`solve` runs preconditioned CG to ``rtol``."""

    exact = False
    nnz = -1

    def __init__(self, A, ml, seconds, rtol, maxiter, name: str = "amg", aggregation: str = "pattern"):
        self.name = name
        #: how the hierarchy's aggregates were formed (:data:`alcontact.linalg._amg.AGGREGATIONS`)
        self.aggregation = aggregation
        self.A, self.ml, self.n = A, ml, A.shape[0]
        self.factor_seconds = seconds
        self.rtol, self.maxiter = rtol, maxiter
        self.iterations = 0
        self.solves = 0

    @property
    def levels(self) -> int:
        """Levels of the hierarchy."""
        return len(self.ml.levels)

    def preconditioner(self):
        """One V-cycle of the hierarchy as a :class:`scipy.sparse.linalg.LinearOperator` (for a Krylov method)."""
        return self.ml.aspreconditioner(cycle="V")

    def updated(self, J, delta) -> _AMGFactor:
        r"""The factor of :math:`J = A + \Delta` on this hierarchy's prolongators
        (:func:`~alcontact.linalg._amg.updated_hierarchy`: Galerkin coarse operators of ``J``, no new setup)."""
        from ._amg import updated_hierarchy

        t0 = time.perf_counter()
        ml = updated_hierarchy(self.ml, J, delta)
        return _AMGFactor(J, ml, time.perf_counter() - t0, self.rtol, self.maxiter, self.name, self.aggregation)

    def reflected(self, J, delta, Bs, *, overwrite: bool = False):
        r"""``(factor of QJQ, Q - I)``: :func:`~alcontact.linalg._amg.reflected_hierarchy` for the stiff rows ``Bs``.

        The factor's matrix :attr:`A` is :math:`\hat J = QJQ` (``J`` itself, overwritten, with ``overwrite``).
        """
        from ._amg import reflected_hierarchy

        t0 = time.perf_counter()
        ml, E = reflected_hierarchy(self.ml, J, delta, Bs, overwrite=overwrite)
        return (_AMGFactor(ml.levels[0].A, ml, time.perf_counter() - t0, self.rtol, self.maxiter, self.name,
                           self.aggregation), E)

    @property
    def memory_bytes(self) -> int:
        """Matrices of the hierarchy (values and indices; a restriction that is a view of ``P`` counted once)."""
        total = 0
        for lvl in self.ml.levels:
            for name in ("A", "P", "R"):
                M = getattr(lvl, name, None)
                if name == "R" and sp.issparse(M) and sp.issparse(getattr(lvl, "P", None)) \
                        and np.shares_memory(M.data, lvl.P.data):
                    continue
                if M is not None and sp.issparse(M):
                    total += M.data.nbytes + M.indices.nbytes + M.indptr.nbytes
        return total

    def _one(self, b: np.ndarray) -> np.ndarray:
        if not np.any(b):
            return np.zeros_like(b)
        it = [0]

        def count(_xk):
            it[0] += 1

        x, info = cg(self.A, b, rtol=self.rtol, M=self.ml.aspreconditioner(cycle="V"), maxiter=self.maxiter,
                     callback=count)
        self.iterations += it[0]
        self.solves += 1
        if info != 0:
            logger.warning("AMG-preconditioned CG stopped after %d iterations without reaching rtol %.1e; "
                           "use a direct solver (linear_solver='direct') for this matrix", it[0], self.rtol)
        return x

    def solve(self, rhs) -> np.ndarray:
        r = _check_rhs(rhs, self.n)
        if r.ndim == 1:
            return self._one(r)
        return np.column_stack([self._one(r[:, j]) for j in range(r.shape[1])]) if r.shape[1] else r.copy()


class AMGSolver:
    """PyAMG smoothed aggregation with the rigid-body near-null space, as a CG preconditioner.

    An approximate "factorization": the setup builds the hierarchy, each solve runs
    preconditioned CG until the residual drops by ``rtol``.

    On a saddle-point matrix (``hints.saddle``, :class:`~alcontact.linalg.SaddlePoint`: the Newton
    matrices of a mixed u-p body) the hierarchy is built on the displacement block only and
    :meth:`factorize` returns the block-diagonal preconditioner of :mod:`alcontact.linalg._saddle`
    (a V-cycle on the displacements, the Schur diagonal on the pressures), whose solves run MINRES.

    Parameters
    ----------
    rtol : float
        Relative residual of each CG solve.
    maxiter : int
        CG iteration limit per right-hand side (a warning is logged when reached).
    max_coarse : int
        Rows of the coarsest level (solved by sparse LU); smaller values give more levels.
    aggregation : {"auto", "pattern", "strength"}
        How the aggregates of the first level are formed
        (:func:`~alcontact.linalg._amg.smoothed_aggregation`): ``"pattern"`` every matrix entry
        connects (PyAMG's default, memory-lean); ``"strength"`` only strong entries, with an
        energy-minimizing prolongator, for meshes of stretched elements; ``"auto"``
        ``"strength"`` for a 2D mesh (``hints.dim == 2``: the graded 2D Hertz meshes have
        elements up to 1,429 times longer than wide, and CG to 1e-10 took 1,399 iterations
        with ``"pattern"`` against 15 at 984k DOFs), ``"pattern"`` otherwise (3D P1 Hertz
        105k: 27 iterations either way, operator complexity 1.7 against 19). The factor
        records the one used (``factor.aggregation``).
    """

    name = "amg"
    kind = "iterative"

    def __init__(self, rtol: float = 1e-10, maxiter: int = 5000, max_coarse: int = 500, aggregation: str = "auto"):
        from alcontact._options import is_integer, require

        from ._amg import AGGREGATIONS

        require("AMGSolver", "max_coarse", max_coarse, is_integer(max_coarse) and max_coarse >= 1,
                "an integer >= 1 (rows of the coarsest level)")
        require("AMGSolver", "aggregation", aggregation, aggregation in ("auto", *AGGREGATIONS),
                "one of auto, " + ", ".join(AGGREGATIONS))
        self.rtol, self.maxiter, self.max_coarse = rtol, maxiter, int(max_coarse)
        self.aggregation = aggregation

    def aggregation_for(self, hints: MatrixHints | None) -> str:
        """The aggregation :meth:`factorize` uses for a matrix with these hints (resolves ``"auto"``)."""
        if self.aggregation != "auto":
            return self.aggregation
        return "strength" if (hints is not None and hints.dim == 2) else "pattern"

    def factorize(self, matrix, hints: MatrixHints | None = None):
        from ._amg import smoothed_aggregation

        if hints is not None and hints.saddle is not None:
            from ._saddle import block_factor

            return block_factor(self, matrix, hints, rtol=self.rtol, maxiter=self.maxiter)
        A = sp.csr_matrix(matrix)
        B = hints.near_null() if (hints is not None and hints.near_null is not None) else None
        t0 = time.perf_counter()
        # sparse LU on the coarsest level: the coarsening of graded 3D meshes can stop well above
        # max_coarse (a 1752-row coarse level for the 3D sphere friction benchmark at 17k DOFs), where
        # PyAMG's default dense pseudo-inverse took 6.2 s per hierarchy (70 % of that run) against 0.3 s
        # for splu. The first level is built by blocks of rows (module doc of ._amg): 3D P1 Hertz, 188k
        # DOFs, setup peak 940 instead of 1,750 bytes per DOF above A, same CG iterations.
        aggregation = self.aggregation_for(hints)
        ml = smoothed_aggregation(A, B, max_coarse=self.max_coarse, coarse_solver="splu", aggregation=aggregation)
        return _AMGFactor(A, ml, time.perf_counter() - t0, self.rtol, self.maxiter, self.name, aggregation)
