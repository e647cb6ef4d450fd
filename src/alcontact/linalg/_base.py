"""Protocols of the linear-solver layer: a solver factorizes, its factor solves."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

__all__ = ["Factor", "LinearSolver", "MATRIX_TYPES", "MatrixHints"]

#: matrix types of :attr:`MatrixHints.matrix_type`
MATRIX_TYPES = ("spd", "symmetric-indefinite", "unsymmetric")


@dataclass(frozen=True)
class MatrixHints:
    """Optional knowledge about a matrix that some solvers use (each computed on demand).

    Attributes
    ----------
    dim : int or None
        Space dimension of the mesh the matrix comes from.
    ordering : callable or None
        ``ordering() -> perm``: a fill-reducing symmetric permutation of the matrix
        (``perm[new] = old``), e.g. the geometric nested dissection of the mesh;
        used by solvers whose own orderings are poor (SuperLU in 3D).
    near_null : callable or None
        ``near_null() -> B`` of shape ``(n, k)``: the near-null space of the
        operator (rigid-body modes for elasticity); used by algebraic multigrid.
    ordering_name : str or None
        Name of a built-in ordering for solvers that offer several (SuperLU's
        ``permc_spec``), used when ``ordering`` is None.
    schur : numpy.ndarray of int or None
        Rows/columns of the matrix to eliminate last. A solver with a Schur facility
        (MKL PARDISO) then exposes the dense Schur complement of that block on its factor
        as ``schur_complement`` (with ``schur_indices``); the others ignore it.
    matrix_type : {"spd", "symmetric-indefinite", "unsymmetric"}
        What the matrix is. ``"symmetric-indefinite"`` (saddle-point and Newton matrices
        that may lose definiteness) makes MKL PARDISO pivot (Bunch-Kaufman, ``mtype=-2``)
        and SuperLU use partial pivoting; ``"unsymmetric"`` (the consistent Newton matrices
        of friction) makes PARDISO factorize the whole matrix (LU, ``mtype=11``); solvers registered for SPD matrices only
        (CHOLMOD, AMG) are not chosen for it (:func:`~alcontact.linalg.choose_solver`).
    saddle : SaddlePoint or None
        The matrix is a symmetric saddle-point matrix with these blocks (the Newton matrices of a
        mixed u-p body: :class:`~alcontact.linalg.SaddlePoint`, the displacement rows first). An
        approximate solver (AMG) then returns the block-diagonal preconditioner of
        :mod:`alcontact.linalg._saddle` (its hierarchy on the displacement block, the given
        Schur diagonal on the pressure rows) for MINRES, instead of a hierarchy of the whole
        indefinite matrix; ``near_null`` then has a row per row of the whole matrix. Direct
        solvers ignore it.
    """

    dim: int | None = None
    ordering: Callable[[], np.ndarray] | None = None
    near_null: Callable[[], np.ndarray] | None = None
    ordering_name: str | None = None
    schur: np.ndarray | None = None
    matrix_type: str = "spd"
    saddle: object | None = None


@runtime_checkable
class Factor(Protocol):
    """A factorized (or, for iterative solvers, preconditioned) SPD matrix.

    Attributes
    ----------
    name : str
        Registry name of the solver that made it.
    n : int
        Size of the matrix.
    nnz : int
        Nonzeros of the factor (``-1`` when the library does not report it).
    memory_bytes : int or None
        Memory held by the factor as reported by the library (None if unknown).
    factor_seconds : float
        Wall time of the factorization (or preconditioner setup).
    exact : bool
        False for iterative solvers, whose :meth:`solve` reaches a tolerance only.

    Notes
    -----
    A factor of an iterative solver may also offer what the Krylov paths use
    (:mod:`alcontact.linalg.krylov`): ``preconditioner()`` (the operator applied inside CG or
    GMRES; default: :meth:`solve`), ``updated(J, delta)`` (the factor of ``A + delta`` reusing
    this setup; default: a new factorization), ``reflected(J, delta, Bs, overwrite=...)`` and
    ``levels``. Contact code never asks which solver made a factor.
    """

    name: str
    n: int
    factor_seconds: float
    exact: bool

    @property
    def nnz(self) -> int: ...

    @property
    def memory_bytes(self) -> int | None: ...

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """Solve ``A x = rhs`` for ``rhs`` of shape ``(n,)`` or ``(n, k)``."""
        ...


@runtime_checkable
class LinearSolver(Protocol):
    """A sparse solver for symmetric positive definite matrices.

    Attributes
    ----------
    name : str
        Registry name.
    kind : {"direct", "iterative"}
        ``"iterative"`` solvers give approximate solves (to a tolerance); the contact paths use
        their factors as preconditioners of Krylov methods
        (:attr:`SolverChoice.exact <alcontact.linalg.SolverChoice>`, :func:`~alcontact.linalg.select_solver`).
    """

    name: str
    kind: str

    def factorize(self, matrix, hints: MatrixHints | None = None) -> Factor:
        """Factorize the SPD ``matrix`` (scipy sparse, ``n x n``).

        Raises
        ------
        alcontact.errors.InputError
            If the matrix is singular or not positive definite.
        """
        ...
