"""The built-in solvers: SuperLU, CHOLMOD (cholespy), MKL PARDISO (pypardiso), PyAMG + CG.

Each class implements :class:`~alcontact.linalg._base.LinearSolver`; its
``factorize`` returns a :class:`~alcontact.linalg._base.Factor`. Import of the
optional packages happens in ``factorize`` (and in :func:`installed` checks of
the registry), so the module imports without them.
"""

from __future__ import annotations

import ctypes
import logging
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import cg, splu

from ..errors import InputError
from ._base import MatrixHints

__all__ = ["SuperLUSolver", "CholmodSolver", "PardisoSolver", "AMGSolver"]

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


# ---------------------------------------------------------------------- MKL PARDISO
_PARDISO_ERRORS = {
    -1: "input inconsistent", -2: "not enough memory", -3: "reordering problem",
    -4: "zero pivot (matrix not positive definite)", -7: "diagonal matrix is singular",
    -8: "32-bit integer overflow", -9: "not enough memory for out-of-core",
}


_MKL_PARDISO = []


def _mkl_pardiso():
    """The ``pardiso`` entry of ``mkl_rt``, looked up once per process.

    :class:`pypardiso.PyPardisoSolver` finds the library by globbing the environment's
    folders, which costs most of a factorization of a 10k-DOF matrix when repeated.
    """
    if not _MKL_PARDISO:
        import pypardiso

        # the instance pypardiso makes on import has located the library already (a second one globs again)
        solver = getattr(pypardiso, "ps", None)
        if getattr(solver, "_mkl_pardiso", None) is None:
            solver = pypardiso.PyPardisoSolver()
        _MKL_PARDISO.append(solver)  # kept: it holds the library handle
    return _MKL_PARDISO[0]._mkl_pardiso


class PardisoHandle:
    """What every MKL PARDISO factor offers on top of its ``_run(phase, b, x)`` call:
    the solve phase (33) and the sizes PARDISO reports in ``_iparm``."""

    @property
    def nnz(self) -> int:
        return int(self._iparm[17])

    @property
    def memory_bytes(self) -> int:
        """Peak of PARDISO's analysis and factorization memory (``iparm(15..17)``, KiB)."""
        ip = self._iparm
        return 1024 * int(max(ip[14], ip[15] + ip[16]))

    def solve(self, rhs) -> np.ndarray:
        r = _check_rhs(rhs, self.n)
        b = np.asfortranarray(r, dtype=np.float64)
        x = np.zeros_like(b, order="F")
        if b.size:
            self._run(33, b, x)
        return np.ascontiguousarray(x)


class _PardisoFactor(PardisoHandle):
    """MKL PARDISO factor of the upper triangle (``mtype=2``, real SPD), called through ctypes.

    Uses the ``mkl_rt`` handle that :class:`pypardiso.PyPardisoSolver` locates, but calls the
    phases itself: pypardiso's ``solve`` hashes the whole matrix on every call to find out
    whether it is factorized, which costs more than a triangular solve pair here.

    With ``schur`` (indices of the matrix) those rows/columns are eliminated last and
    PARDISO returns the dense Schur complement :math:`S_c = K_{cc} - K_{ci} K_{ii}^{-1} K_{ic}`
    of the block (``iparm[35] = 2``: Schur complement and the factorization of the whole
    matrix, so :meth:`solve` stays a full solve), kept as :attr:`schur_complement`; then
    :math:`(K^{-1})_{cc} = S_c^{-1}` costs a dense factorization of size ``len(schur)``
    instead of ``len(schur)`` triangular solve pairs.

    Attributes
    ----------
    schur_indices : numpy.ndarray of int or None
        Sorted indices of the Schur block (None without ``schur``).
    schur_complement : numpy.ndarray or None
        Dense Schur complement on :attr:`schur_indices` (symmetric positive definite).
    """

    exact = True

    def __init__(self, matrix, schur=None):
        self.name = "mkl-pardiso"
        U = sp.triu(sp.csr_matrix(matrix), format="csr")
        U.sort_indices()
        self.n = U.shape[0]
        self._data = np.ascontiguousarray(U.data, dtype=np.float64)
        self._ia = (U.indptr + 1).astype(np.int32)
        self._ja = (U.indices + 1).astype(np.int32)
        if np.any(np.diff(self._ia) == 0):
            raise _singular(self.n, "empty row")
        self._call = _mkl_pardiso()
        self._pt = np.zeros(64, dtype=np.int64)
        self._iparm = np.zeros(64, dtype=np.int32)
        self._iparm[0] = 1   # no solver defaults: set below
        self._iparm[1] = 2   # METIS nested dissection
        self._iparm[7] = 0   # iterative refinement steps: automatic (none for SPD unless perturbed)
        self._iparm[9] = 8   # pivot perturbation 1e-8 (only for indefinite types)
        self._iparm[17] = -1  # report nnz of the factor
        self._iparm[34] = 0  # one-based indices
        self._perm = np.zeros(0, dtype=np.int32)
        self.schur_indices = self.schur_complement = None
        out = np.zeros((self.n, 1))
        if schur is not None:
            idx = np.unique(np.asarray(schur, dtype=np.int64).ravel())
            if idx.size and (idx[0] < 0 or idx[-1] >= self.n):
                raise InputError(f"schur indices must lie in [0, {self.n}); got min {idx[0]}, max {idx[-1]}.")
            if 0 < idx.size < self.n:  # PARDISO needs a nonempty interior block
                self._perm = np.zeros(self.n, dtype=np.int32)
                self._perm[idx] = 1
                self._iparm[35] = 2  # Schur complement + factorization of the whole matrix
                # two-level factorization: with the Schur block the classic one cost 10-15 % more than a
                # plain factorization (2D Hertz 10k DOFs, one thread: 36.8 against 32.3 ms; 28k: 115 against
                # 95 ms), the two-level one 32.0 and 99 ms (same Schur complement to 1e-15)
                self._iparm[23] = 1
                self.schur_indices = idx
                out = np.zeros((max(self.n, idx.size * idx.size), 1))
        self._alive = False
        t0 = time.perf_counter()
        self._run(12, np.zeros((self.n, 1)), out)
        self._alive = True
        self.factor_seconds = time.perf_counter() - t0
        if self.schur_indices is not None:  # row-major dense block (symmetric)
            ns = self.schur_indices.size
            S = out[: ns * ns, 0].reshape(ns, ns)
            self.schur_complement = 0.5 * (S + S.T)  # solves (phase 33) still use the whole factor

    def _run(self, phase: int, b: np.ndarray, x: np.ndarray) -> None:
        err = ctypes.c_int32(0)
        i32 = ctypes.POINTER(ctypes.c_int32)
        f64 = ctypes.POINTER(ctypes.c_double)
        nrhs = 1 if b.ndim == 1 else b.shape[1]
        self._call(
            self._pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
            ctypes.byref(ctypes.c_int32(1)), ctypes.byref(ctypes.c_int32(1)),
            ctypes.byref(ctypes.c_int32(2)), ctypes.byref(ctypes.c_int32(phase)),
            ctypes.byref(ctypes.c_int32(self.n)),
            self._data.ctypes.data_as(f64), self._ia.ctypes.data_as(i32), self._ja.ctypes.data_as(i32),
            self._perm.ctypes.data_as(i32), ctypes.byref(ctypes.c_int32(nrhs)),
            self._iparm.ctypes.data_as(i32), ctypes.byref(ctypes.c_int32(0)),
            b.ctypes.data_as(f64), x.ctypes.data_as(f64), ctypes.byref(err),
        )
        if err.value != 0:
            if phase != -1:
                self._release()
            raise _singular(self.n, f"PARDISO error {err.value}: {_PARDISO_ERRORS.get(err.value, 'see MKL docs')}")

    def _release(self) -> None:
        if self._alive:
            self._alive = False
            try:
                self._run(-1, np.zeros(1), np.zeros(1))
            except InputError:  # pragma: no cover - nothing left to free
                pass

    def __del__(self):
        try:
            self._release()
        except Exception:  # pragma: no cover - interpreter shutdown: the process frees it anyway
            pass


class PardisoSolver:
    """Intel MKL PARDISO (supernodal Cholesky, METIS ordering) through the ``pypardiso`` wheels.

    The MKL threads follow ``MKL_NUM_THREADS``. ``hints.schur`` asks for the dense Schur
    complement of those rows (see :class:`_PardisoFactor`). ``hints.matrix_type``
    ``"symmetric-indefinite"`` or ``"unsymmetric"`` gives a pivoting factor whose analysis is kept for
    ``refactorize`` (:class:`~alcontact.linalg.PardisoSymmetricFactor`).
    """

    name = "mkl-pardiso"
    kind = "direct"

    def factorize(self, matrix, hints: MatrixHints | None = None) -> _PardisoFactor:
        if hints is not None and hints.matrix_type != "spd":  # pivoting factor with a refactorize
            from ._sequence import PardisoSymmetricFactor

            return PardisoSymmetricFactor(matrix, hints.matrix_type)
        return _PardisoFactor(matrix, schur=hints.schur if hints is not None else None)


# ---------------------------------------------------------------------- AMG + CG
class _AMGFactor:
    """Smoothed-aggregation hierarchy; :meth:`solve` runs preconditioned CG to ``rtol``."""

    exact = False
    nnz = -1

    def __init__(self, A, ml, seconds, rtol, maxiter):
        self.name = "amg"
        self.A, self.ml, self.n = A, ml, A.shape[0]
        self.factor_seconds = seconds
        self.rtol, self.maxiter = rtol, maxiter
        self.iterations = 0
        self.solves = 0

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

    Parameters
    ----------
    rtol : float
        Relative residual of each CG solve.
    maxiter : int
        CG iteration limit per right-hand side (a warning is logged when reached).
    """

    name = "amg"
    kind = "iterative"

    def __init__(self, rtol: float = 1e-10, maxiter: int = 5000):
        self.rtol, self.maxiter = rtol, maxiter

    def factorize(self, matrix, hints: MatrixHints | None = None) -> _AMGFactor:
        from ._amg import smoothed_aggregation

        A = sp.csr_matrix(matrix)
        B = hints.near_null() if (hints is not None and hints.near_null is not None) else None
        t0 = time.perf_counter()
        # sparse LU on the coarsest level, first level built by blocks of rows: see
        # alcontact.contact._iterative._amg
        ml = smoothed_aggregation(A, B, max_coarse=500, coarse_solver="splu")
        return _AMGFactor(A, ml, time.perf_counter() - t0, self.rtol, self.maxiter)
