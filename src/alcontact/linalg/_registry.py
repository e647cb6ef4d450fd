"""Registry of linear solvers and the one place that chooses the default."""

from __future__ import annotations

import contextlib
import contextvars
import importlib
import importlib.util
import logging
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import lru_cache

from ..errors import InputError, UnknownNameError
from ._base import MATRIX_TYPES, LinearSolver
from ._pardiso import PardisoSolver
from ._solvers import AMGSolver, CholmodSolver, SuperLUSolver

__all__ = [
    "AUTO_AMG_DOFS",
    "SolverChoice",
    "backend_options",
    "check_backend_options",
    "takes_backend_options",
    "select_solver",
    "available_solvers",
    "choose_solver",
    "describe_solvers",
    "is_installed",
    "make_solver",
    "register_solver",
    "registered_solvers",
    "solver_kind",
    "solver_matrix_types",
    "unregister_solver",
]

logger = logging.getLogger(__name__)

#: 3D problems above this many DOFs are solved without a factorization (AMG + CG) by
#: ``"auto"``: memory, not time, sets it (see :func:`choose_solver` for the measurements:
#: the PARDISO factor of 3D P1 takes 2.1 GB at 219k free DOFs and grows like n^1.5, while
#: the direct contact path is still 2-3 times faster than the AMG one there).
AUTO_AMG_DOFS = 250_000


@dataclass(frozen=True)
class _Entry:
    factory: Callable[..., LinearSolver]
    kind: str
    matrix_types: tuple[str, ...]  # matrix types it factorizes (MatrixHints.matrix_type)
    requires: str | None  # module that must import
    install: str | None  # how to get it
    doc: str
    lazy: bool = False  # probe ``requires`` without importing it (heavy packages: PETSc, MPI)
    backend_options: bool = False  # the factory takes ``options``, passed through to the backend (PETSc)


_SOLVERS: dict[str, _Entry] = {}


def register_solver(name: str, factory: Callable[..., LinearSolver], *, kind: str = "direct",
                    requires: str | None = None, install: str | None = None, doc: str = "",
                    overwrite: bool = False, matrix_types: tuple[str, ...] = ("spd",), lazy: bool = False,
                    backend_options: bool = False) -> None:
    """Register a linear solver under ``name``.

    Parameters
    ----------
    name : str
        Registry name (also accepted by the ``linear_solver`` option and by
        ``model.factorize(backend=...)``).
    factory : callable
        ``factory(**options)`` returns a :class:`~alcontact.linalg.LinearSolver`.
    kind : {"direct", "iterative"}
    requires : str, optional
        Python module the solver needs; when it does not import, the solver stays
        registered but :func:`make_solver` says how to install it.
    install : str, optional
        Install hint shown when ``requires`` is missing (e.g. ``"pip install pypardiso"``).
    doc : str
        One-line description.
    overwrite : bool
        Replace an existing entry instead of raising.
    matrix_types : tuple of str
        Values of :attr:`MatrixHints.matrix_type <alcontact.linalg.MatrixHints>` the solver
        factorizes (``"spd"``, ``"symmetric-indefinite"``, ``"unsymmetric"``).
    lazy : bool
        Check that ``requires`` is installed without importing it (``importlib.util.find_spec``):
        for packages whose import is heavy or starts a runtime (petsc4py initializes MPI), so that
        :func:`available_solvers` on the serial path never loads them. Whether it then loads is
        checked by the factory.
    backend_options : bool
        The factory takes ``options``, a dict passed through to the backend (PETSc's options
        database): inside a :func:`backend_options` block, :func:`make_solver` passes that
        block's options when the caller gives none.
    """
    if kind not in ("direct", "iterative"):
        raise InputError(f"linear solver kind={kind!r}; allowed: direct, iterative.")
    if name in _SOLVERS and not overwrite:
        raise InputError(f"linear solver {name!r} is already registered; pass overwrite=True to replace it.")
    if name in ("auto", "direct"):
        raise InputError(f"{name!r} is reserved for the automatic choice; register the solver under another name.")
    bad = [t for t in matrix_types if t not in MATRIX_TYPES]
    if bad or not matrix_types:
        raise InputError(f"matrix_types={tuple(matrix_types)!r}; allowed: {', '.join(MATRIX_TYPES)}.")
    _SOLVERS[name] = _Entry(factory, kind, tuple(matrix_types), requires, install, doc, lazy, bool(backend_options))
    _installed.cache_clear()


def unregister_solver(name: str) -> None:
    """Remove a registered solver (:class:`UnknownNameError` if absent)."""
    if name not in _SOLVERS:
        raise UnknownNameError("linear solver", name, list(_SOLVERS))
    del _SOLVERS[name]
    _installed.cache_clear()


def registered_solvers() -> list[str]:
    """Sorted names of all registered solvers, installed or not."""
    return sorted(_SOLVERS)


def _entry(name: str):
    """The registry entry of ``name`` (:class:`UnknownNameError` listing the names, also for a non-string)."""
    entry = _SOLVERS.get(name) if isinstance(name, str) else None
    if entry is None:
        raise UnknownNameError("linear solver", name, list(_SOLVERS))
    return entry


def is_installed(name: str) -> bool:
    """Whether the package the solver ``name`` needs imports (cached; ``is_installed.cache_clear()``)."""
    _entry(name)  # before the cache, which would hash an unhashable name
    return _installed(name)


@lru_cache(maxsize=None)
def _installed(name: str) -> bool:
    entry = _entry(name)
    if entry.requires is None:
        return True
    if entry.lazy:
        try:
            return importlib.util.find_spec(entry.requires) is not None
        except (ImportError, ValueError):
            return False
    try:
        importlib.import_module(entry.requires)
    except Exception:  # ImportError, or a binary module that fails to load
        return False
    return True


is_installed.cache_clear = _installed.cache_clear  # type: ignore[attr-defined]


def available_solvers() -> list[str]:
    """Sorted names of the registered solvers whose packages are installed.

    Examples
    --------
    >>> "superlu" in available_solvers()
    True
    """
    return [n for n in registered_solvers() if is_installed(n)]


def describe_solvers() -> dict[str, dict]:
    """Name -> ``{"kind", "installed", "install", "doc"}`` for every registered solver."""
    return {n: {"kind": e.kind, "installed": is_installed(n), "install": e.install, "doc": e.doc}
            for n, e in sorted(_SOLVERS.items())}


def solver_kind(name: str) -> str:
    """``"direct"`` or ``"iterative"`` for a registered name."""
    entry = _entry(name)
    return entry.kind


def make_solver(name: str, **options) -> LinearSolver:
    """Build the solver registered as ``name``.

    Raises
    ------
    UnknownNameError
        ``name`` is not registered (the message lists the registered names).
    InputError
        The solver's package is not installed (the message says what to install), or
        ``options`` do not fit it.

    Examples
    --------
    >>> make_solver("superlu").kind
    'direct'
    """
    entry = _entry(name)
    if not is_installed(name):
        raise InputError(
            f"linear solver {name!r} is not installed: {entry.install or 'install ' + str(entry.requires)}; "
            f"installed solvers: {', '.join(available_solvers())}."
        )
    scoped = _BACKEND_OPTIONS.get()
    if entry.backend_options and scoped is not None and "options" not in options:
        options = {**options, "options": dict(scoped.options)}
        scoped.used_by.add(name)
    try:
        return entry.factory(**options)
    except TypeError as exc:
        raise InputError(f"linear solver {name!r} does not take options {sorted(options)}: {exc}") from exc


class _Scoped:
    """The options of one :func:`backend_options` block and the solvers that took them."""

    def __init__(self, options: dict):
        self.options, self.used_by = options, set()


_BACKEND_OPTIONS: contextvars.ContextVar[_Scoped | None] = contextvars.ContextVar("alcontact_backend_options",
                                                                                  default=None)


def takes_backend_options(name: str) -> bool:
    """Whether the solver registered as ``name`` takes backend options (``register_solver(backend_options=True)``)."""
    return _entry(name).backend_options


def check_backend_options(options) -> dict:
    """``options`` checked as backend (PETSc) options: a dict of names without the leading dash to strings,
    finite numbers or booleans; :class:`InputError` naming the bad entry otherwise. Imports no backend."""
    from ._petsc import checked_options

    return checked_options(options)


@contextlib.contextmanager
def backend_options(options: dict | None) -> Iterator[None]:
    """Pass ``options`` to the backend of every solver built in the block that takes them.

    The solvers registered with ``backend_options=True`` (``"petsc"`` and ``"petsc-direct"``:
    the options go to PETSc's options database, names without the leading dash) receive
    them wherever the contact solvers build them (:func:`select_solver`, :func:`make_solver`),
    on every path. This is how a problem file's ``[solver] petsc_options`` reach PETSc, and
    how the Python API passes them to :func:`alcontact.contact.solve`. Options given while
    no solver that takes them runs are not dropped silently: a warning says so at the end
    of the block.

    Parameters
    ----------
    options : dict or None
        ``{name: value}`` (``{"ksp_rtol": 1e-10, "pc_gamg_threshold": 0.02}``); strings,
        finite numbers or booleans. ``None`` or ``{}``: nothing to pass (the block is a no-op).

    Raises
    ------
    InputError
        A name with a leading dash or blanks, or a value that is not a string, a finite
        number or a boolean.

    Examples
    --------
    >>> with backend_options({"ksp_rtol": 1e-10}):  # doctest: +SKIP
    ...     solution = alcontact.contact.solve(problem, linear_solver="petsc")
    """
    options = check_backend_options(options)
    if not options:
        yield
        return
    scoped = _Scoped(options)
    token = _BACKEND_OPTIONS.set(scoped)
    try:
        yield
    finally:
        _BACKEND_OPTIONS.reset(token)
    if not scoped.used_by:
        logger.warning("the backend options %s were given, but no linear solver that takes them ran (they go to "
                       "linear_solver = %s); they had no effect.", sorted(options),
                       " or ".join(repr(n) for n, e in sorted(_SOLVERS.items()) if e.backend_options))


#: preference of the direct solvers, fastest first (see :func:`choose_solver`)
DIRECT_PREFERENCE = ("mkl-pardiso", "cholmod", "superlu")


def solver_matrix_types(name: str) -> tuple[str, ...]:
    """Matrix types (``"spd"``, ``"symmetric-indefinite"``, ``"unsymmetric"``) the solver ``name`` factorizes."""
    entry = _entry(name)
    return entry.matrix_types


def choose_solver(dim: int, ndofs: int, *, installed: list[str] | None = None,
                  allow_iterative: bool = True, matrix_type: str = "spd") -> str:
    """The default linear solver for a stiffness matrix: the ONE place that decides.

    Rules (measurements in ``docs/benchmarks/linear_solvers.md``: one thread, CPU seconds
    of factorization + one solve of the Hertz stiffness matrices):

    * 3D above :data:`AUTO_AMG_DOFS` = 250k DOFs: ``"amg"`` (no factorization). Measured
      with PARDISO (one thread, CPU s of factorization + one solve, peak memory of the
      factorization; 3D P1 Hertz): 141k DOFs 18.6 s / 1.0 GB, 229k DOFs 43.7 s / 2.1 GB,
      against AMG setup + CG to 1e-10 8.9 s / 0.04 GB and 16.0 s / 0.1 GB (3D P2: PARDISO
      33 s / 1.9 GB at 169k, AMG 42 s). One linear solve is cheaper with AMG from about 40k
      DOFs in 3D P1, but a contact solve is not: the condensed direct path costs 1.2-1.4
      linear solves (the Delassus operator from PARDISO's Schur complement,
      ``docs/benchmarks/hertz.md``), the AMG path 5-17 AMG solves (``amg_paths.md``,
      ``hertz_3d_1M.md``), so direct stays 2-3 times faster at 229k and the time
      crossover lies near 700k DOFs, where the factor would need about 12 GB. The
      threshold therefore keeps the factor at about 2-2.5 GB (peak resident set about
      4 GB); above it the factor's memory (~ n^1.5), not time, rules direct out.
      (Before PARDISO the threshold was 100k: 3D Hertz 111k, AMG path 10 s against 31 s
      for SuperLU with one triangular solve per contact candidate.)
    * otherwise the first installed of :data:`DIRECT_PREFERENCE`: MKL PARDISO, then
      CHOLMOD (the ``cholespy`` wheel links a reference BLAS), then SuperLU (always
      there; with the mesh's nested dissection in 3D). PARDISO against CHOLMOD /
      SuperLU: 2D P2 219k DOFs 2.7 s / 8.4 s / 5.4 s; 3D P2 36.5k DOFs 2.0 s /
      24 s / 5.9 s; 3D P2 77.8k DOFs 6.8 s (SuperLU: 271 s wall in an earlier
      measurement; AMG + CG to 1e-10: 9.3 s).

    Parameters
    ----------
    dim : int
        Space dimension.
    ndofs : int
        Number of DOFs of the model.
    installed : list of str, optional
        Names to choose from (default: :func:`available_solvers`).
    allow_iterative : bool
        False when the caller needs an exact factor (the condensed contact path).
    matrix_type : {"spd", "symmetric-indefinite", "unsymmetric"}
        Only solvers registered for this matrix type are chosen (the Newton matrices of
        the finite-deformation path are symmetric indefinite: PARDISO, then SuperLU).

    Returns
    -------
    str
        A registry name.
    """
    from alcontact._options import is_integer, require

    require("choose_solver", "dim", dim, is_integer(dim) and dim in (1, 2, 3), "1, 2 or 3")
    require("choose_solver", "ndofs", ndofs, is_integer(ndofs) and ndofs >= 0, "an integer >= 0")
    require("choose_solver", "installed", installed, installed is None or (
        isinstance(installed, (list, tuple)) and all(isinstance(n, str) for n in installed)),
        "None or a list of solver names")
    require("choose_solver", "allow_iterative", allow_iterative, isinstance(allow_iterative, bool), "True or False")
    require("choose_solver", "matrix_type", matrix_type, isinstance(matrix_type, str) and matrix_type in MATRIX_TYPES,
            f"one of {', '.join(MATRIX_TYPES)}")
    names = available_solvers() if installed is None else list(installed)
    names = [n for n in names if n not in _SOLVERS or matrix_type in _SOLVERS[n].matrix_types]
    if allow_iterative and dim == 3 and ndofs > AUTO_AMG_DOFS and "amg" in names:
        return "amg"
    for name in DIRECT_PREFERENCE:
        if name in names:
            return name
    return "superlu"


@dataclass(frozen=True)
class SolverChoice:
    """The linear solver that runs for a ``linear_solver`` option on a model, and what it can do.

    Made by :func:`select_solver`, the one place that turns the option into a solver; code
    outside :mod:`alcontact.linalg` asks this object what the solver can do
    (:attr:`exact`, :meth:`handles`) and never branches on its name or kind.

    Attributes
    ----------
    requested : str
        The option value (``"auto"``, ``"direct"`` or a registry name).
    name : str
        Registry name of the solver that runs (recorded in ``solution.extra``).
    solver : LinearSolver
        The solver object (built by the registry's factory).
    exact : bool
        True: it factorizes exactly (a direct solver; the condensed contact strategies
        and exact Newton steps use it). False: its solves are approximate (registered with
        ``kind="iterative"``) and it preconditions a Krylov outer loop
        (:mod:`alcontact.linalg.krylov`).
    matrix_types : tuple of str
        :data:`MATRIX_TYPES` it factorizes (``register_solver(..., matrix_types=...)``).
    """

    requested: str
    name: str
    solver: LinearSolver
    exact: bool
    matrix_types: tuple[str, ...]

    def handles(self, matrix_type: str) -> bool:
        """Whether the solver is registered for matrices of ``matrix_type``."""
        return matrix_type in self.matrix_types

    def factorize(self, matrix, hints=None):
        """``solver.factorize(matrix, hints)``: a :class:`~alcontact.linalg.Factor`."""
        return self.solver.factorize(matrix, hints)


def select_solver(linear_solver: str, *, dim: int, ndofs: int, matrix_type: str = "spd",
                  allow_iterative: bool = True) -> SolverChoice:
    """The solver of the ``linear_solver`` option for a model of dimension ``dim`` with ``ndofs`` DOFs.

    ``"auto"``: :func:`choose_solver`'s size rule (AMG for 3D models above :data:`AUTO_AMG_DOFS`
    DOFs, where the caller has a Krylov loop, ``allow_iterative``), else the fastest installed
    direct solver registered for ``matrix_type``; ``"direct"``: that direct solver; a registry
    name: that solver, whatever its kind (the one that runs on every path).

    Parameters
    ----------
    linear_solver : str
        ``"auto"``, ``"direct"`` or a name of :func:`registered_solvers`.
    dim, ndofs : int
        Space dimension and DOFs of the model (used by ``"auto"``).
    matrix_type : {"spd", "symmetric-indefinite", "unsymmetric"}
        The matrices the caller factorizes (``"auto"`` and ``"direct"`` choose the direct solver
        among those registered for them; a named solver is returned as named). The size rule of
        ``"auto"`` is that of SPD matrices: an approximate solver preconditions a Krylov loop.
    allow_iterative : bool
        False where the caller has no Krylov loop of its own: ``"auto"`` then chooses a direct solver.

    Raises
    ------
    InputError
        An unknown name (the message lists ``auto``, ``direct`` and the registered names) or
        a solver that is not installed.

    Examples
    --------
    >>> select_solver("superlu", dim=2, ndofs=100).exact
    True
    >>> select_solver("amg", dim=3, ndofs=100).exact
    False
    """
    from alcontact._options import is_integer, require

    require("select_solver", "dim", dim, is_integer(dim) and dim in (1, 2, 3), "1, 2 or 3")
    require("select_solver", "ndofs", ndofs, is_integer(ndofs) and ndofs >= 0, "an integer >= 0")
    require("select_solver", "matrix_type", matrix_type, isinstance(matrix_type, str) and matrix_type in MATRIX_TYPES,
            f"one of {', '.join(MATRIX_TYPES)}")
    require("select_solver", "allow_iterative", allow_iterative, isinstance(allow_iterative, bool), "True or False")
    if isinstance(linear_solver, str) and linear_solver in ("auto", "direct"):
        name = None
        if linear_solver == "auto" and allow_iterative:
            name = choose_solver(dim, ndofs)
            name = name if _entry(name).kind == "iterative" else None
        if name is None:
            name = choose_solver(dim, ndofs, allow_iterative=False, matrix_type=matrix_type)
    elif isinstance(linear_solver, str) and linear_solver in _SOLVERS:
        name = linear_solver
    else:
        raise InputError(f"linear_solver = {linear_solver!r:.60}: not a linear solver; allowed: auto, direct, "
                         f"{', '.join(registered_solvers())} (alcontact.linalg.register_solver adds others).")
    entry = _entry(name)
    return SolverChoice(linear_solver, name, make_solver(name), entry.kind == "direct", entry.matrix_types)


def _register_builtins() -> None:
    both = ("spd", "symmetric-indefinite", "unsymmetric")
    register_solver("superlu", SuperLUSolver, requires=None, matrix_types=both,
                    doc="SciPy SuperLU without pivoting; mesh nested-dissection ordering in 3D")
    register_solver("cholmod", CholmodSolver, requires="cholespy", install="pip install cholespy",
                    doc="SuiteSparse CHOLMOD supernodal Cholesky (cholespy wheels)")
    register_solver("mkl-pardiso", PardisoSolver, requires="pypardiso", matrix_types=both,
                    install="pip install pypardiso (Intel MKL; x86-64 only)",
                    doc="Intel MKL PARDISO supernodal Cholesky, METIS ordering (pypardiso wheels)")
    register_solver("amg", AMGSolver, kind="iterative", requires="pyamg", install="pip install pyamg",
                    doc="PyAMG smoothed aggregation (rigid-body modes) + CG to a relative tolerance")
    # PETSc (petsc4py) solvers: imported only when named; never chosen by "auto"
    petsc_hint = ("make mpi (Debian python3-petsc4py, python3-mpi4py and OpenMPI, in .venv-mpi); "
                  "then use .venv-mpi/bin/python")
    # GAMG is registered for SPD matrices only (its smoothers need a positive diagonal); indefinite
    # systems go to "petsc-direct", or to "petsc" with pc_type/ksp_type given in its options
    register_solver("petsc", _petsc_krylov, kind="iterative", requires="petsc4py", install=petsc_hint, lazy=True,
                    backend_options=True, doc="PETSc KSP (CG / MINRES / GMRES) + GAMG with the rigid-body near-null space; PETSc options")
    register_solver("petsc-direct", _petsc_direct, requires="petsc4py", install=petsc_hint, lazy=True,
                    backend_options=True, matrix_types=both, doc="PETSc LU / Cholesky through MUMPS (else SuperLU_dist); PETSc options")


def _petsc_krylov(**options):
    from ._petsc import PetscKrylovSolver  # lazy: petsc4py loads only when the solver is named

    return PetscKrylovSolver(**options)


def _petsc_direct(**options):
    from ._petsc import PetscDirectSolver

    return PetscDirectSolver(**options)


_register_builtins()
