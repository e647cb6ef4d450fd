"""Sequences of symmetric systems (Newton iterations): one registry solver, analyses kept by pattern.

:class:`SequenceSolver` solves ``A_k x = b_k`` for a sequence of matrices whose sparsity
patterns repeat (the Newton matrices of the finite-deformation path). It asks the
registry for a solver that handles the matrix type (:func:`~alcontact.linalg.choose_solver`
with ``matrix_type``), keeps the factors of the last few patterns, and refactorizes a
known pattern numerically only when the factor offers ``refactorize`` (MKL PARDISO:
phase 22 on the kept analysis). A solution whose residual is not at round-off level, or a
refused factorization, goes to the fallback solver (SuperLU with partial pivoting), which
raises :class:`numpy.linalg.LinAlgError` for a singular matrix.

This module also holds the MKL PARDISO factor of a real symmetric matrix with a kept
symbolic analysis (``mtype`` 2 or -2), :class:`PardisoSymmetricFactor`.
"""

from __future__ import annotations

import ctypes
import logging
import time

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ._base import MatrixHints
from ._solvers import PardisoHandle

__all__ = ["MATRIX_TYPES", "PardisoSymmetricFactor", "SequenceSolver"]

logger = logging.getLogger(__name__)

#: matrix types of :attr:`MatrixHints.matrix_type <alcontact.linalg.MatrixHints>`
MATRIX_TYPES = ("spd", "symmetric-indefinite", "unsymmetric")

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
        from ._solvers import _mkl_pardiso

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
            from ._solvers import _PARDISO_ERRORS

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


def _pattern(A: sp.csr_matrix) -> tuple:
    return A.shape[0], A.indptr, A.indices


class SequenceSolver:
    r"""Solve a sequence of linear systems with a registry solver, keeping analyses by pattern.

    Parameters
    ----------
    name : str, optional
        Registry name of the solver (:func:`~alcontact.linalg.make_solver`); ``None``,
        ``"auto"`` or ``"direct"``: :func:`~alcontact.linalg.choose_solver` for exact
        solvers of ``matrix_type``.
    matrix_type : {"spd", "symmetric-indefinite", "unsymmetric"}
        What the matrices are; handed to the solver as :attr:`MatrixHints.matrix_type`.
    keep : int
        Factors of this many most recent sparsity patterns are kept; a factor with a
        ``refactorize`` method is then refactorized numerically for a known pattern.
    fallback : str
        Registry solver used when the first one refuses a matrix or its solution's
        residual exceeds ``1e-8 (max|A| max|x| + max|b|)``.

    Attributes
    ----------
    analyses, factorizations : int
        Symbolic analyses and numerical factorizations of the kept (refactorizable) factors.
    backend : str
        Registry name of the first solver.
    """

    def __init__(self, name: str | None = None, *, matrix_type: str = "symmetric-indefinite", keep: int = 3,
                 fallback: str = "superlu"):
        from ._registry import choose_solver, make_solver

        from alcontact._options import is_integer, require

        if not isinstance(matrix_type, str) or matrix_type not in MATRIX_TYPES:
            raise InputError(f"matrix_type={matrix_type!r}; allowed: {', '.join(MATRIX_TYPES)}.")
        require("SequenceSolver", "keep", keep, is_integer(keep) and keep >= 1,
                "the number of factors to keep, an integer >= 1")
        if name is None or (isinstance(name, str) and name in ("auto", "direct")):
            name = choose_solver(2, 0, allow_iterative=False, matrix_type=matrix_type)
        self.hints = MatrixHints(matrix_type=matrix_type)
        self.backend = name
        self._solver = make_solver(name)
        self._fallback = make_solver(fallback)
        self.keep = int(keep)
        self.analyses = 0
        self.factorizations = 0
        self._kept: list[tuple[tuple, object]] = []  # (pattern, factor), most recent first
        self._last = None

    def release(self) -> None:
        """Drop the kept factors (the next call analyses again)."""
        for _, f in self._kept:
            if hasattr(f, "release"):
                f.release()
        self._kept = []
        self._last = None

    def _factor(self, A: sp.csr_matrix):
        key = _pattern(A)
        for k, (pat, f) in enumerate(self._kept):
            if pat[0] == key[0] and np.array_equal(pat[1], key[1]) and np.array_equal(pat[2], key[2]):
                self._kept.insert(0, self._kept.pop(k))
                f.refactorize(A)
                self.factorizations += 1
                return f
        f = self._solver.factorize(A, self.hints)
        if hasattr(f, "refactorize"):
            self.analyses += 1
            self.factorizations += 1
            self._kept.insert(0, ((key[0], key[1].copy(), key[2].copy()), f))
            while len(self._kept) > self.keep:
                old = self._kept.pop()[1]
                if hasattr(old, "release"):
                    old.release()
        return f

    def solve(self, A, rhs: np.ndarray) -> np.ndarray:
        """Solve ``A x = rhs``; :class:`numpy.linalg.LinAlgError` when ``A`` is singular."""
        rhs = np.asarray(rhs, dtype=float)
        self._last = None
        A = sp.csr_matrix(A)
        if not A.has_canonical_format:  # a copy: the caller's matrix stays as given
            A = A.copy()
            A.sum_duplicates()
        if A.shape[0]:
            try:
                f = self._factor(A)
                x = f.solve(rhs)
            except InputError as exc:
                logger.debug("%s refused the matrix (%s); %s solves it", self.backend, exc, self._fallback.name)
            else:
                r = A @ x - rhs
                amax = float(np.max(np.abs(A.data), initial=0.0))
                bound = 1e-8 * (amax * float(np.max(np.abs(x), initial=0.0)) + float(np.max(np.abs(rhs), initial=0.0)))
                if np.all(np.isfinite(x)) and float(np.max(np.abs(r), initial=0.0)) <= bound:
                    self._last = f
                    return x
                logger.debug("%s solution not at round-off level; %s solves this system",
                             self.backend, self._fallback.name)
        try:
            f = self._fallback.factorize(A, self.hints)
        except InputError as exc:
            raise np.linalg.LinAlgError(str(exc)) from exc
        self._last = f
        return f.solve(rhs)

    def resolve(self, rhs: np.ndarray) -> np.ndarray | None:
        """Solve with the factor of the last :meth:`solve` (no factorization); ``None`` when there is none."""
        f = self._last
        b = np.ascontiguousarray(rhs, dtype=float)
        if f is None or f.n != b.shape[0] or not getattr(f, "alive", True):
            return None
        try:
            return f.solve(b)
        except InputError:
            return None
