"""MKL PARDISO (``pypardiso`` wheels) called through ctypes: the SPD factor with an optional Schur
block (:class:`PardisoSolver`) and the pivoting factor whose symbolic analysis is kept for
numerical refactorizations (:class:`PardisoSymmetricFactor`, the Newton matrices of the finite path).
"""

from __future__ import annotations

import ctypes
import time

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ._base import MatrixHints
from ._solvers import _check_rhs, _singular

__all__ = ["PardisoSolver", "PardisoSymmetricFactor", "PardisoHandle"]


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
            return PardisoSymmetricFactor(matrix, hints.matrix_type)
        return _PardisoFactor(matrix, schur=hints.schur if hints is not None else None)


#: PARDISO's ``mtype`` per matrix type (real symmetric positive definite / indefinite, real unsymmetric)
_PARDISO_MTYPE = {"spd": 2, "symmetric-indefinite": -2, "unsymmetric": 11}


def _upper_with_diagonal(A, upper: bool = True) -> sp.csr_matrix:
    """Upper triangle (``upper``; else the whole matrix) with every diagonal entry stored (PARDISO's input)."""
    C = sp.coo_matrix(A)
    n = C.shape[0]
    keep = C.row <= C.col if upper else np.ones(C.nnz, dtype=bool)
    diag = np.arange(n)
    U = sp.csr_matrix((np.concatenate([C.data[keep], np.zeros(n)]),
                       (np.concatenate([C.row[keep], diag]), np.concatenate([C.col[keep], diag]))),
                      shape=(n, n))
    U.sum_duplicates()
    return U


def _check_square(where: str, A) -> None:
    """An InputError unless ``A`` is a square real matrix (SciPy sparse or a 2-D NumPy array)."""
    ok = (sp.issparse(A) or isinstance(A, np.ndarray)) and A.ndim == 2 and A.shape[0] == A.shape[1] \
        and A.dtype.kind in "iuf"
    if not ok:
        from alcontact._options import show

        raise InputError(f"{where}: matrix = {show(A)}: expected a square real matrix (scipy.sparse or a 2-D "
                         f"NumPy array), got {type(A).__name__}.")


def _canonical_csr(A) -> bool:
    return sp.issparse(A) and A.format == "csr" and bool(A.has_canonical_format)


def _same_arrays(a: np.ndarray, b: np.ndarray) -> bool:
    return a is b or (a.shape == b.shape and np.array_equal(a, b))


class PardisoSymmetricFactor(PardisoHandle):
    """MKL PARDISO factor of a real (symmetric or unsymmetric) matrix whose symbolic analysis is kept.

    The ordering (METIS) and symbolic factorization (phase 11) are done once; the
    numerical factorization (phase 22) runs again for every matrix of the same pattern
    given to :meth:`refactorize`. ``matrix_type="symmetric-indefinite"`` uses Bunch-Kaufman
    pivoting with 1e-8 pivot perturbation and automatic iterative refinement
    (``mtype=-2``); ``"spd"`` a Cholesky factorization (``mtype=2``); ``"unsymmetric"`` an
    LU factorization of the whole matrix with 1e-13 pivot perturbation (``mtype=11``).

    Raises
    ------
    alcontact.errors.InputError
        When PARDISO reports an error (the message gives its code).
    """

    exact = True

    def __init__(self, matrix, matrix_type: str = "symmetric-indefinite"):
        if not isinstance(matrix_type, str) or matrix_type not in _PARDISO_MTYPE:
            raise InputError(f"matrix_type={matrix_type!r}; allowed: {', '.join(_PARDISO_MTYPE)}.")
        _check_square("PardisoSymmetricFactor", matrix)
        self.name = "mkl-pardiso"
        self.matrix_type = matrix_type
        self._mtype = _PARDISO_MTYPE[matrix_type]
        self._upper = matrix_type != "unsymmetric"
        self._source = None
        if _canonical_csr(matrix):
            # where every entry of PARDISO's input sits in the CSR data of ``matrix``: a matrix of the same
            # pattern is refactorized by a gather (no triangle extraction and conversion per factorization)
            labels = sp.csr_matrix((np.arange(1, matrix.nnz + 1, dtype=float), matrix.indices, matrix.indptr),
                                   shape=matrix.shape)
            gather = _upper_with_diagonal(labels, self._upper).data.astype(np.int64) - 1
            self._source = (matrix.indptr.copy(), matrix.indices.copy(), gather, np.flatnonzero(gather < 0))
        U = _upper_with_diagonal(matrix, self._upper)
        self.n = U.shape[0]
        self._ia = (U.indptr + 1).astype(np.int32)
        self._ja = (U.indices + 1).astype(np.int32)
        self._data = np.ascontiguousarray(U.data, dtype=np.float64)
        self._call = _mkl_pardiso()
        self._pt = np.zeros(64, dtype=np.int64)
        self._iparm = np.zeros(64, dtype=np.int32)
        self._iparm[0] = 1    # no solver defaults: set below
        self._iparm[1] = 2    # METIS nested dissection ordering
        self._iparm[7] = 0    # iterative refinement: automatic (two steps after perturbed pivots)
        self._iparm[9] = 8 if self._upper else 13  # pivot perturbation 1e-8 (symmetric), 1e-13 (LU)
        self._iparm[10] = 0 if self._upper else 1   # LU: scaling and weighted matching
        self._iparm[12] = 0 if self._upper else 1
        self._iparm[17] = -1  # report nnz of the factor
        self._iparm[34] = 0   # one-based indices
        self._alive = False
        self.analyses = self.factorizations = 0
        t0 = time.perf_counter()
        self._run(11)
        self._alive = True
        self.analyses = 1
        self._run(22)
        self.factorizations = 1
        self.factor_seconds = time.perf_counter() - t0

    def _run(self, phase: int, b: np.ndarray | None = None, x: np.ndarray | None = None) -> None:
        b = np.zeros(1) if b is None else b
        x = np.zeros(1) if x is None else x
        err = ctypes.c_int32(0)
        i32 = ctypes.POINTER(ctypes.c_int32)
        f64 = ctypes.POINTER(ctypes.c_double)
        nrhs = 1 if b.ndim == 1 else b.shape[1]
        self._call(self._pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
                   ctypes.byref(ctypes.c_int32(1)), ctypes.byref(ctypes.c_int32(1)),
                   ctypes.byref(ctypes.c_int32(self._mtype)), ctypes.byref(ctypes.c_int32(phase)),
                   ctypes.byref(ctypes.c_int32(self.n)), self._data.ctypes.data_as(f64),
                   self._ia.ctypes.data_as(i32), self._ja.ctypes.data_as(i32),
                   np.zeros(0, dtype=np.int32).ctypes.data_as(i32),
                   ctypes.byref(ctypes.c_int32(nrhs)), self._iparm.ctypes.data_as(i32),
                   ctypes.byref(ctypes.c_int32(0)), b.ctypes.data_as(f64), x.ctypes.data_as(f64),
                   ctypes.byref(err))
        if err.value != 0 and phase != -1:
            raise InputError(f"MKL PARDISO phase {phase} failed on a {self.n}x{self.n} {self.matrix_type} matrix: "
                             f"error {err.value} ({_PARDISO_ERRORS.get(err.value, 'see the MKL documentation')}); "
                             "use another linear solver (e.g. 'superlu').")

    def _gathered(self, matrix) -> np.ndarray | None:
        """PARDISO's input data of ``matrix`` by the gather of the analysed CSR pattern, or ``None``
        when ``matrix`` is not a canonical CSR matrix of that pattern."""
        src = self._source
        if src is None or not _canonical_csr(matrix) or matrix.shape != (self.n, self.n):
            return None
        if not (_same_arrays(matrix.indptr, src[0]) and _same_arrays(matrix.indices, src[1])):
            return None
        data = np.asarray(matrix.data, dtype=np.float64)[src[2]]
        data[src[3]] = 0.0  # diagonal entries PARDISO needs but the matrix does not store
        return data

    def same_pattern(self, matrix) -> bool:
        """Whether ``matrix`` has the sparsity pattern this factor analysed."""
        if self._gathered(matrix) is not None:
            return True
        U = _upper_with_diagonal(matrix, self._upper)
        return (U.shape[0] == self.n and np.array_equal(U.indptr + 1, self._ia)
                and np.array_equal(U.indices + 1, self._ja))

    def refactorize(self, matrix) -> PardisoSymmetricFactor:
        """Numerical factorization of ``matrix`` (same pattern) on the kept analysis; returns self."""
        data = self._gathered(matrix)
        if data is None:
            U = _upper_with_diagonal(matrix, self._upper)
            if U.shape[0] != self.n or not (np.array_equal(U.indptr + 1, self._ia)
                                            and np.array_equal(U.indices + 1, self._ja)):
                raise InputError("refactorize needs a matrix with the analysed sparsity pattern; factorize it "
                                 "instead.")
            data = U.data
        self._data = np.ascontiguousarray(data, dtype=np.float64)
        t0 = time.perf_counter()
        self._run(22)
        self.factorizations += 1
        self.factor_seconds = time.perf_counter() - t0
        return self

    def release(self) -> None:
        """Free PARDISO's memory (the factor is unusable afterwards)."""
        if self._alive:
            self._alive = False
            self._run(-1)

    @property
    def alive(self) -> bool:
        return self._alive

    def __del__(self):
        try:
            self.release()
        except Exception:  # pragma: no cover - interpreter shutdown: the process frees it anyway
            pass


