"""Sequences of symmetric systems (Newton iterations): one registry solver, analyses kept by pattern.

:class:`SequenceSolver` solves ``A_k x = b_k`` for a sequence of matrices whose sparsity
patterns repeat (the Newton matrices of the finite-deformation path). It asks the
registry for a solver that handles the matrix type (:func:`~alcontact.linalg.choose_solver`
with ``matrix_type``), keeps the factors of the last few patterns, and refactorizes a
known pattern numerically only when the factor offers ``refactorize`` (MKL PARDISO:
phase 22 on the kept analysis). A solution whose residual is not at round-off level, or a
refused factorization, goes to the fallback solver (SuperLU with partial pivoting), which
raises :class:`numpy.linalg.LinAlgError` for a singular matrix.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from . import krylov
from ._base import MATRIX_TYPES, MatrixHints
from ._registry import choose_solver, make_solver, solver_kind

__all__ = ["SequenceSolver"]

logger = logging.getLogger(__name__)

def _pattern(A: sp.csr_matrix) -> tuple:
    return A.shape[0], A.indptr, A.indices


#: relative residual of the Krylov loop around an approximate solver (then the round-off check of
#: :meth:`SequenceSolver.solve` decides)
_KRYLOV_RTOL = 1e-13
_KRYLOV_RESTART = 200
_KRYLOV_MAXITER = 5


class _KrylovFactor:
    """An approximate solver's factor of ``A`` used as the preconditioner of GMRES on ``A`` (any matrix type)."""

    exact = False

    def __init__(self, A, factor):
        self.name, self.n, self.A, self.factor = factor.name, A.shape[0], A, factor
        self._M = krylov.gmres_preconditioner(factor)
        self.iterations = 0

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        b = np.asarray(rhs, dtype=float)
        if b.ndim == 2:
            return np.column_stack([self.solve(b[:, j]) for j in range(b.shape[1])]) if b.shape[1] else b.copy()
        x, nit, _ = krylov.gmres(self.A, b, self._M, rtol=_KRYLOV_RTOL, restart=_KRYLOV_RESTART,
                                 maxiter=_KRYLOV_MAXITER)
        self.iterations += nit
        return x


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
    near_null : callable, optional
        ``near_null() -> (n, k)``: the near-null space handed to an approximate solver
        (:attr:`MatrixHints.near_null <alcontact.linalg.MatrixHints>`; the rigid-body modes).
    saddle : alcontact.linalg.SaddlePoint, optional
        The matrices are saddle-point matrices with these blocks (a mixed u-p body): an
        approximate solver then preconditions GMRES block-diagonally (:mod:`alcontact.linalg._saddle`).

    Attributes
    ----------
    analyses, factorizations : int
        Symbolic analyses and numerical factorizations of the kept (refactorizable) factors.
    backend : str
        Registry name of the first solver.
    requested : str
        ``name`` as given (``"auto"`` when None).
    exact : bool
        Whether the first solver factorizes exactly (registered with ``kind="direct"``).
    fallback_solves : int
        Systems solved by the fallback solver (refused by the first one, or not at round-off level).
    krylov_iterations : int
        GMRES iterations of an approximate first solver (``kind="iterative"``: its factor of each
        matrix preconditions GMRES to a relative residual of 1e-13, then the round-off check applies).
    """

    def __init__(self, name: str | None = None, *, matrix_type: str = "symmetric-indefinite", keep: int = 3,
                 fallback: str = "superlu", near_null=None, saddle=None):
        from alcontact._options import is_integer, require

        if not isinstance(matrix_type, str) or matrix_type not in MATRIX_TYPES:
            raise InputError(f"matrix_type={matrix_type!r}; allowed: {', '.join(MATRIX_TYPES)}.")
        require("SequenceSolver", "keep", keep, is_integer(keep) and keep >= 1,
                "the number of factors to keep, an integer >= 1")
        self.requested = "auto" if name is None else name
        if name is None or (isinstance(name, str) and name in ("auto", "direct")):
            name = choose_solver(2, 0, allow_iterative=False, matrix_type=matrix_type)
        self.hints = MatrixHints(matrix_type=matrix_type, near_null=near_null, saddle=saddle)
        self.backend = name
        self._solver = make_solver(name)
        self.exact = solver_kind(name) == "direct"
        self._approximate = not self.exact
        self.fallback_solves = 0
        self.krylov_iterations = 0
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
        if self._approximate:  # a preconditioner: GMRES on A around it
            return _KrylovFactor(A, f)
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
                it0 = f.iterations if isinstance(f, _KrylovFactor) else 0
                x = f.solve(rhs)
                if isinstance(f, _KrylovFactor):
                    self.krylov_iterations += f.iterations - it0
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
        self.fallback_solves += A.shape[0] > 0
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
