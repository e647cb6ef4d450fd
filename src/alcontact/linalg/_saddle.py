r"""Block-diagonal preconditioner of symmetric saddle-point matrices (mixed u-p bodies).

A symmetric saddle-point matrix

.. math::
    \mathcal A = \begin{bmatrix} A & B^T \\ B & -C \end{bmatrix},
    \qquad A \succ 0, \quad C \succeq 0,

(the Newton matrices of a mixed displacement-pressure body: :math:`A` the displacement
block with the contact terms, :math:`B` the linearized volume constraint, :math:`C =
M_p/\kappa`, zero at :math:`\nu = 1/2`) is indefinite, so CG does not apply; MINRES does,
with a symmetric positive definite preconditioner. The classical one is block diagonal
(Silvester and Wathen 1994; Elman, Silvester and Wathen, *Finite Elements and Fast Iterative
Solvers*, 2nd ed. 2014, section 4.2 and chapter 9 for the nearly incompressible case):

.. math::
    \mathcal P^{-1} = \begin{bmatrix} \tilde A^{-1} & 0 \\ 0 & \tilde S^{-1} \end{bmatrix},
    \qquad \tilde S \approx S = C + B A^{-1} B^T,

with :math:`\tilde A^{-1}` one V-cycle of an algebraic multigrid hierarchy of :math:`A`
(any approximate solver of the registry) and :math:`\tilde S` a positive diagonal given
by the caller (:class:`SaddlePoint`; for Taylor-Hood elasticity the lumped pressure mass
matrix scaled by :math:`1/\mu + 1/\kappa`, spectrally equivalent to :math:`S` independently
of the mesh size and of :math:`\kappa`, inf-sup stability). MINRES iterations then depend on
the quality of :math:`\tilde A^{-1}` and on the inf-sup constant only; no matrix of the
size of :math:`\mathcal A` is factorized.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator

from ..errors import InputError
from ._base import MatrixHints

__all__ = ["SaddlePoint", "block_factor"]


@dataclass(frozen=True)
class SaddlePoint:
    r"""The block structure of a symmetric saddle-point matrix and the diagonal of its Schur approximation.

    Attributes
    ----------
    primal : int
        The first ``primal`` rows and columns are the block :math:`A` (displacements); the
        rest are the constraint block (pressures).
    schur : numpy.ndarray
        Positive diagonal :math:`\tilde S` approximating :math:`C + B A^{-1} B^T`, one entry per
        constraint row (module doc).
    label : str
        What :math:`\tilde S` is, for ``solution.extra`` (e.g. ``"lumped pressure mass (1/mu + 1/kappa)"``).
    """

    primal: int
    schur: np.ndarray
    label: str = "diagonal Schur approximation"

    def __post_init__(self):
        if isinstance(self.primal, bool) or not isinstance(self.primal, (int, np.integer)) or self.primal < 0:
            raise InputError(f"SaddlePoint.primal={self.primal!r:.60} must be an integer >= 0 (rows of the primal "
                             "block).")
        try:
            s = np.asarray(self.schur, dtype=float)
        except (TypeError, ValueError, OverflowError):
            s = None
        if s is None or s.ndim != 1 or not s.size or not np.all(np.isfinite(s)) or not np.all(s > 0.0):
            raise InputError("SaddlePoint.schur must be a non-empty 1-D array of finite positive numbers (the diagonal "
                             "of the Schur complement approximation).")
        if not isinstance(self.label, str):
            raise InputError(f"SaddlePoint.label={self.label!r:.60} must be a string.")
        object.__setattr__(self, "primal", int(self.primal))
        object.__setattr__(self, "schur", s)

    @property
    def n(self) -> int:
        """Size of the whole matrix."""
        return int(self.primal) + int(self.schur.size)


class _BlockFactor:
    r"""Block-diagonal preconditioner :math:`\operatorname{diag}(\tilde A^{-1}, \tilde S^{-1})` (module doc).

    ``exact`` is False: :meth:`preconditioner` is applied inside MINRES, :meth:`gmres_preconditioner`
    (block triangular) inside GMRES; :meth:`solve` runs MINRES on the whole matrix to ``rtol``.
    """

    exact = False
    nnz = -1

    def __init__(self, matrix, primal_factor, saddle: SaddlePoint, seconds: float, rtol: float, maxiter: int):
        self.A = matrix
        self.n = matrix.shape[0]
        self.name = primal_factor.name
        self.primal = primal_factor
        self.saddle = saddle
        self.factor_seconds = seconds
        self.rtol, self.maxiter = float(rtol), int(maxiter)
        self._sinv = 1.0 / saddle.schur
        self.iterations = 0

    @property
    def levels(self) -> int:
        """Levels of the primal block's hierarchy (1 for a solver without levels)."""
        return int(getattr(self.primal, "levels", 1))

    @property
    def memory_bytes(self) -> int | None:
        """Memory of the primal block's factor plus the Schur diagonal."""
        m = self.primal.memory_bytes
        return None if m is None else int(m) + self._sinv.nbytes

    def preconditioner(self) -> LinearOperator:
        """:math:`\\operatorname{diag}(\\tilde A^{-1}, \\tilde S^{-1})` as a linear operator (one V-cycle on the
        primal rows)."""
        from . import krylov

        m = int(self.saddle.primal)
        inner = krylov.preconditioner(self.primal)
        sinv = self._sinv

        def apply(r):
            r = np.asarray(r, dtype=float)
            if r.ndim == 2:
                return np.column_stack([apply(r[:, j]) for j in range(r.shape[1])])
            z = np.empty_like(r)
            z[:m] = inner @ r[:m]
            z[m:] = sinv * r[m:]
            return z

        return LinearOperator((self.n, self.n), matvec=apply, matmat=apply, dtype=float)

    def gmres_preconditioner(self) -> LinearOperator:
        r"""The block upper-triangular preconditioner for GMRES (right or left, any matrix of this structure).

        :math:`\mathcal P_T = [\tilde A, A_{12}; 0, -\tilde S]` with :math:`A_{12}` the upper right block of the
        factorized matrix (:math:`B^T`, or its unsymmetric counterpart in a frictional Newton matrix):
        :math:`z_2 = -\tilde S^{-1} r_2`, :math:`z_1 = \tilde A^{-1}(r_1 - A_{12} z_2)`. With the exact
        :math:`A` and :math:`S` the preconditioned matrix has the single eigenvalue 1 and a minimal
        polynomial of degree 2 (Murphy, Golub and Wathen 2000; Elman, Silvester and Wathen 2014,
        section 9.2), so GMRES needs a fraction of the iterations it takes with the block-diagonal one
        (which suits MINRES on symmetric matrices only).
        """
        from . import krylov

        m = int(self.saddle.primal)
        inner = krylov.preconditioner(self.primal)
        A12 = self.A[:m, m:].tocsr()
        sinv = self._sinv

        def apply(r):
            r = np.asarray(r, dtype=float)
            if r.ndim == 2:
                return np.column_stack([apply(r[:, j]) for j in range(r.shape[1])])
            z = np.empty_like(r)
            z[m:] = -sinv * r[m:]
            z[:m] = inner @ (r[:m] - A12 @ z[m:])
            return z

        return LinearOperator((self.n, self.n), matvec=apply, matmat=apply, dtype=float)

    def solve(self, rhs) -> np.ndarray:
        """MINRES on the saddle-point matrix to :attr:`rtol` (in the preconditioner's norm, :func:`~.krylov.minres`)."""
        from . import krylov

        b = np.asarray(rhs, dtype=float)
        if b.ndim == 2:
            return np.column_stack([self.solve(b[:, j]) for j in range(b.shape[1])]) if b.shape[1] else b.copy()
        x, nit, _ = krylov.minres(self.A, b, self.preconditioner(), self.rtol, self.maxiter)
        self.iterations += nit
        return x


def block_factor(solver, matrix, hints: MatrixHints, *, rtol: float = 1e-10, maxiter: int = 5000) -> _BlockFactor:
    r"""The block-diagonal preconditioner of the saddle-point ``matrix`` described by ``hints.saddle``.

    ``solver`` (an approximate registry solver, e.g. :class:`~alcontact.linalg.AMGSolver`)
    factorizes the primal block :math:`A` (the leading ``hints.saddle.primal`` rows and columns)
    with the near-null space ``hints.near_null()`` restricted to those rows; the constraint block
    is preconditioned by the inverse of ``hints.saddle.schur``.

    Raises
    ------
    InputError
        The sizes of ``matrix`` and ``hints.saddle`` disagree.
    """
    saddle = hints.saddle
    A = sp.csr_matrix(matrix)
    if A.shape != (saddle.n, saddle.n):
        raise InputError(f"saddle-point matrix of shape {A.shape}, but its blocks describe {saddle.n} rows "
                         f"({saddle.primal} primal + {saddle.schur.size} constraints).")
    m = int(saddle.primal)
    near = hints.near_null
    primal_hints = MatrixHints(dim=hints.dim, ordering_name=hints.ordering_name, matrix_type="spd",
                               near_null=(lambda: np.asarray(near(), dtype=float)[:m]) if near is not None else None)
    t0 = time.perf_counter()
    primal = solver.factorize(A[:m, :m].tocsr(), primal_hints)
    return _BlockFactor(A, primal, saddle, time.perf_counter() - t0, rtol, maxiter)
