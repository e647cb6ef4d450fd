"""Sparse linear solvers behind one protocol, a registry, and one default rule.

A :class:`LinearSolver` factorizes a symmetric positive definite matrix and returns
a :class:`Factor` whose ``solve`` accepts one or many right-hand sides. Solvers are
looked up by name (:func:`make_solver`); :func:`choose_solver` is the single place
where the default is decided (from the dimension and size of the problem and from
what is installed), and :func:`select_solver` the one place where a ``linear_solver``
option becomes the solver that runs (a :class:`SolverChoice`: the solver object and
whether it factorizes exactly or preconditions a Krylov loop, :mod:`.krylov`). The
registry names are also the values of the ``linear_solver`` option, besides ``"auto"``
and ``"direct"``.

Built-in names: ``"mkl-pardiso"`` (Intel MKL PARDISO via ``pypardiso``),
``"cholmod"`` (SuiteSparse via ``cholespy``), ``"superlu"`` (SciPy), ``"amg"``
(PyAMG smoothed aggregation + CG; approximate), and, with petsc4py (``make mpi``),
``"petsc"`` (PETSc KSP CG + GAMG with the rigid-body near-null space; PETSc options
passed through: :func:`backend_options`) and ``"petsc-direct"`` (MUMPS); petsc4py is imported only when one of
these is built (:func:`petsc`), never by ``import alcontact``. :class:`SequenceSolver` solves a
sequence of symmetric (possibly indefinite) systems with one of them, keeping the
analysis of each recent sparsity pattern (the Newton solves of the finite path). A
:class:`SaddlePoint` in :attr:`MatrixHints.saddle` marks a symmetric saddle-point matrix (a mixed
u-p body): ``"amg"`` then builds the block-diagonal preconditioner of :mod:`._saddle` (its hierarchy
on the displacement block) for MINRES (:func:`krylov.minres`) instead of a hierarchy of the whole matrix.

Examples
--------
>>> import scipy.sparse as sp, numpy as np
>>> A = sp.diags([[-1.0] * 3, [2.0] * 4, [-1.0] * 3], [-1, 0, 1]).tocsr()
>>> x = make_solver("superlu").factorize(A).solve(np.ones(4))
>>> bool(np.allclose(A @ x, 1.0))
True
"""

from ._base import MATRIX_TYPES, Factor, LinearSolver, MatrixHints
from ._registry import (
    AUTO_AMG_DOFS,
    DIRECT_PREFERENCE,
    SolverChoice,
    available_solvers,
    backend_options,
    check_backend_options,
    choose_solver,
    describe_solvers,
    is_installed,
    make_solver,
    register_solver,
    registered_solvers,
    select_solver,
    solver_kind,
    solver_matrix_types,
    takes_backend_options,
    unregister_solver,
)
from ._petsc import (
    MPI_SETUP_HINT,
    PetscDirectSolver,
    PetscKrylovSolver,
    configure_ksp,
    direct_package,
    mg_hierarchy,
    mg_smoothers,
    near_null_space,
    petsc,
    report_unused_options,
)
from ._pardiso import PardisoSolver, PardisoSymmetricFactor
from ._sequence import SequenceSolver
from ._saddle import SaddlePoint
from ._newton_krylov import NewtonKrylovSolver
from ._solvers import AMGSolver, CholmodSolver, SuperLUSolver
from . import krylov

__all__ = [
    "AUTO_AMG_DOFS",
    "AMGSolver",
    "CholmodSolver",
    "DIRECT_PREFERENCE",
    "Factor",
    "LinearSolver",
    "MATRIX_TYPES",
    "MPI_SETUP_HINT",
    "MatrixHints",
    "NewtonKrylovSolver",
    "PardisoSolver",
    "PardisoSymmetricFactor",
    "PetscDirectSolver",
    "PetscKrylovSolver",
    "SaddlePoint",
    "SequenceSolver",
    "SolverChoice",
    "SuperLUSolver",
    "available_solvers",
    "backend_options",
    "check_backend_options",
    "choose_solver",
    "configure_ksp",
    "describe_solvers",
    "direct_package",
    "is_installed",
    "krylov",
    "make_solver",
    "mg_hierarchy",
    "mg_smoothers",
    "near_null_space",
    "petsc",
    "register_solver",
    "report_unused_options",
    "registered_solvers",
    "select_solver",
    "solver_kind",
    "solver_matrix_types",
    "takes_backend_options",
    "unregister_solver",
]
