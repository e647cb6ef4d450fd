"""PETSc linear solvers through petsc4py: KSP + GAMG (rigid-body near-null space) and MUMPS.

Nothing here imports petsc4py at module import: :func:`petsc` does, on first use, so
``import alcontact`` and the serial path never load PETSc or MPI. The solvers are
registered in :mod:`alcontact.linalg._registry` as ``"petsc"`` (iterative: CG, MINRES
or GMRES with GAMG) and ``"petsc-direct"`` (MUMPS, else SuperLU_dist, else PETSc's LU).

Install: Debian's ``python3-petsc4py`` (3.18, OpenMPI, with MUMPS, SuperLU_dist and
hypre) in the virtual environment ``.venv-mpi`` that ``make mpi`` creates (see the
README). PETSc options are data: a dict ``{"ksp_rtol": 1e-12, "pc_gamg_threshold":
0.02}`` (names without the leading dash) passed through to PETSc's options database
under a prefix private to each solver; an option PETSc did not use (a typo, or an option
of another solver) is reported as PETSc's ``-options_left`` does, as a logged warning
naming it (:func:`report_unused_options`; the command line prints it), checked after
the first solve so that options PETSc reads only while solving (``ksp_view``,
``ksp_converged_reason``) count as used.
"""

from __future__ import annotations

import ctypes
import itertools
import logging
import time

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ._base import MatrixHints

__all__ = ["MPI_SETUP_HINT", "PetscDirectSolver", "PetscKrylovSolver", "apply_options", "checked_options", "configure_ksp",
           "direct_package", "mg_hierarchy", "mg_smoothers", "near_null_space", "object_id", "petsc", "petsc_matrix",
           "report_unused_options", "unused_options"]

logger = logging.getLogger(__name__)

MPI_SETUP_HINT = ("run `make mpi` (installs python3-petsc4py, python3-mpi4py and OpenMPI with apt and creates "
                  ".venv-mpi), then use .venv-mpi/bin/python or .venv-mpi/bin/alcontact")

_PREFIX = itertools.count()


def petsc():
    """Import and initialize petsc4py; return its ``PETSc`` module.

    Raises
    ------
    InputError
        petsc4py is not installed or does not load (e.g. NumPy 2 against Debian's
        NumPy-1 build); the message gives the ``make mpi`` command.
    """
    try:
        import petsc4py

        if not petsc4py.__dict__.get("_alcontact_init"):
            petsc4py.init([])  # never the user's sys.argv: options come from data
            petsc4py._alcontact_init = True
        from petsc4py import PETSc
    except Exception as exc:  # ImportError, or "numpy.dtype size changed" from a NumPy-2 environment
        raise InputError(f"the PETSc backend needs petsc4py, which does not load here ({exc}); {MPI_SETUP_HINT}.") \
            from None
    return PETSc


def _libpetsc():
    """The PETSc shared library petsc4py is linked to (for the calls petsc4py 3.18 does not wrap)."""
    PETSc = petsc()
    return ctypes.CDLL(PETSc.__file__, mode=ctypes.RTLD_GLOBAL)


def checked_options(options) -> dict:
    """``options`` as a dict of PETSc option names (no leading dash) to values; InputError otherwise.

    A value is a string, a number or a boolean (``True``: a flag without value; ``False``:
    left out); a table, list or non-finite number is refused, naming the option.
    """
    if options is None:
        return {}
    if not isinstance(options, dict):
        raise InputError(f"PETSc options must be a table of name = value; got {type(options).__name__}.")
    for name, value in options.items():
        if not isinstance(name, str) or not name or name.startswith("-") or any(c.isspace() for c in name):
            raise InputError(f"PETSc option name {name!r}: give the name without the leading dash, e.g. 'ksp_rtol'.")
        ok = value is None or isinstance(value, (bool, str)) or (
            isinstance(value, (int, float, np.integer, np.floating)) and np.isfinite(value))
        if not ok or (isinstance(value, str) and any(c.isspace() for c in value)):
            raise InputError(f"PETSc option {name} = {value!r:.60}: a value is a string without spaces, a finite "
                             "number or true/false (true: a flag without value), e.g. ksp_rtol = 1e-10.")
    return dict(options)


def apply_options(options: dict | None) -> str:
    """Put ``options`` in PETSc's database under a fresh prefix; return the prefix.

    Parameters
    ----------
    options : dict or None
        ``{name: value}`` with names without the leading dash (``"ksp_rtol"``); ``True``
        is a flag without value, ``False`` or ``None`` leaves the option out.
    """
    PETSc = petsc()
    options = checked_options(options)
    prefix = f"alc{next(_PREFIX)}_"
    db = PETSc.Options()
    for name, value in options.items():
        if value is False or value is None:
            continue
        db.setValue(f"-{prefix}{name}", "" if value is True else str(value))
    return prefix


def unused_options(prefix: str, options: dict | None) -> list[str]:
    """Names of ``options`` (given under ``prefix``) that PETSc has not read so far (``PetscOptionsUsed``)."""
    petsc()
    lib = _libpetsc()
    lib.PetscOptionsUsed.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_int)]
    lib.PetscOptionsUsed.restype = ctypes.c_int
    unused = []
    for name, value in (options or {}).items():
        if value is False or value is None:
            continue
        flag = ctypes.c_int(0)
        if lib.PetscOptionsUsed(None, f"{prefix}{name}".encode(), ctypes.byref(flag)) != 0:
            raise InputError(f"PETSc could not check option {name!r}.")
        if not flag.value:
            unused.append(name)
    return unused


def report_unused_options(prefix: str, options: dict | None, *, reported: set | None = None) -> list[str]:
    """Log a warning naming every option of ``options`` PETSc did not use; clear them from its database.

    PETSc's own ``-options_left`` report (``WARNING! There are options you set that were not
    used!``), made a warning of the ``alcontact`` logger, which the command line prints: a
    misspelled option would otherwise be ignored silently. Called once PETSc has read what
    it will read (after the first solve).

    Parameters
    ----------
    prefix : str
        The prefix :func:`apply_options` returned.
    options : dict or None
        The options given.
    reported : set, optional
        Names already reported (by another factorization of the same solver): not repeated;
        the names reported here are added to it.

    Returns
    -------
    list of str
        The unused names (also those reported before).
    """
    PETSc = petsc()
    unused = unused_options(prefix, options)
    db = PETSc.Options()
    for name in (options or {}):  # leave nothing behind in the global database
        if db.hasName(f"-{prefix}{name}"):
            db.delValue(f"-{prefix}{name}")
    new = [u for u in unused if reported is None or u not in reported]
    if new:
        logger.warning("PETSc did not use the option(s) %s (misspelled, or not for this solver): see the options of "
                       "KSP, PC and the chosen preconditioner in the PETSc manual, e.g. 'ksp_rtol', 'ksp_max_it', "
                       "'pc_gamg_threshold'.", ", ".join(repr(u) for u in new))
        if reported is not None:
            reported.update(new)
    return unused


def object_id(obj) -> int:
    """PETSc's unique id of a PETSc object (``PetscObjectGetId``; petsc4py 3.18 does not wrap it)."""
    lib = _libpetsc()
    lib.PetscObjectGetId.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_int64)]
    lib.PetscObjectGetId.restype = ctypes.c_int
    out = ctypes.c_int64(0)
    if lib.PetscObjectGetId(ctypes.c_void_p(obj.handle), ctypes.byref(out)) != 0:
        raise InputError("PETSc could not give the id of an object.")
    return int(out.value)


def mg_hierarchy(ksp) -> tuple[int, ...]:
    """Ids of the prolongators of the multigrid preconditioner of ``ksp``, finest last (``()`` for another PC).

    Two solves ran with the same hierarchy when they give the same tuple: PCGAMG with
    ``pc_gamg_reuse_interpolation`` keeps these objects and recomputes only the Galerkin
    coarse operators; a hierarchy built from scratch has new prolongators.
    """
    pc = ksp.getPC()
    if pc.getType() not in ("gamg", "mg"):
        return ()
    return tuple(object_id(pc.getMGInterpolation(level)) for level in range(1, pc.getMGLevels()))


def mg_smoothers(ksp) -> list[str]:
    """PC type of each level's smoother of the multigrid preconditioner of ``ksp``, coarsest first."""
    pc = ksp.getPC()
    if pc.getType() not in ("gamg", "mg"):
        return []
    return [pc.getMGSmoother(level).getPC().getType() for level in range(pc.getMGLevels())]


def petsc_matrix(matrix, comm=None):
    """A sequential PETSc ``AIJ`` matrix with the values of the scipy ``matrix`` (copied)."""
    PETSc = petsc()
    A = sp.csr_matrix(matrix, dtype=float)
    A.sort_indices()
    M = PETSc.Mat().createAIJ(size=A.shape, csr=(A.indptr.astype(PETSc.IntType), A.indices.astype(PETSc.IntType),
                                                 A.data), comm=comm or PETSc.COMM_SELF)
    M.assemble()
    return M


def near_null_space(modes: np.ndarray, rows: tuple[int, int] | None = None, comm=None):
    """PETSc ``NullSpace`` of the columns of ``modes`` (shape ``(n_local, k)``), orthonormalized.

    PETSc wants orthonormal vectors; the rigid-body modes (3 in 2D, 6 in 3D, from
    :func:`alcontact.fem.elasticity.rigid_body_modes`) are orthonormalized globally
    (Gram-Schmidt with global dot products, so it works on distributed vectors).
    """
    PETSc = petsc()
    comm = comm or PETSc.COMM_SELF
    B = np.asarray(modes, dtype=float)
    vecs = []
    for j in range(B.shape[1]):
        v = PETSc.Vec().createMPI((B.shape[0], PETSc.DECIDE), comm=comm) if comm.getSize() > 1 \
            else PETSc.Vec().createSeq(B.shape[0], comm=comm)
        v.setArray(B[:, j].copy())
        for w in vecs:
            v.axpy(-v.dot(w), w)
        nrm = v.norm()
        if nrm < 1e-12:
            continue  # a mode lost to the Dirichlet rows
        v.scale(1.0 / nrm)
        vecs.append(v)
    return PETSc.NullSpace().create(vectors=vecs, comm=comm)


class _KSPFactor:
    """A configured KSP: :meth:`solve` runs it for each right-hand side."""

    def __init__(self, name, ksp, M, n, seconds, exact, options=None, reported=None):
        self.name, self._ksp, self._M, self.n = name, ksp, M, n
        #: the PETSc options given, checked for unused ones after the first solve (then None)
        self._options, self._reported = options, reported
        self.factor_seconds = seconds
        self.exact = exact
        self.iterations = 0  # Krylov iterations, all solves together
        self.solves = 0
        self.last_iterations = 0
        self.last_reason = 0

    @property
    def ksp(self):
        """The PETSc KSP object (for callers that want its settings or monitors)."""
        return self._ksp

    @property
    def nnz(self) -> int:
        return -1

    @property
    def memory_bytes(self) -> int | None:
        return None

    def _one(self, b: np.ndarray) -> np.ndarray:
        x, r = self._M.createVecs()
        r.setArray(np.ascontiguousarray(b, dtype=float))
        self._ksp.solve(r, x)
        self.last_iterations = int(self._ksp.getIterationNumber())
        self.last_reason = int(self._ksp.getConvergedReason())
        self.iterations += self.last_iterations
        self.solves += 1
        if self._options is not None:  # PETSc has read every option it will read: report the others
            report_unused_options(self._ksp.getOptionsPrefix() or "", self._options, reported=self._reported)
            self._options = None
        if self.last_reason < 0:
            raise InputError(f"PETSc KSP {self._ksp.getType()} with PC {self._ksp.getPC().getType()} did not "
                             f"converge (reason {self.last_reason}, {self.last_iterations} iterations): the matrix "
                             "may be singular or indefinite; restrain every rigid-body motion, or pass options "
                             "(ksp_type, pc_type, ksp_max_it) that fit the matrix.")
        return x.getArray().copy()

    def solve(self, rhs) -> np.ndarray:
        r = np.asarray(rhs, dtype=float)
        if r.ndim not in (1, 2) or r.shape[0] != self.n:
            raise InputError(f"rhs must have shape ({self.n},) or ({self.n}, k); got {r.shape}.")
        if r.ndim == 1:
            return self._one(r)
        return np.column_stack([self._one(r[:, j]) for j in range(r.shape[1])]) if r.shape[1] else r.copy()


_KRYLOV_FOR = {"spd": "cg", "symmetric-indefinite": "minres", "unsymmetric": "gmres"}


def configure_ksp(M, *, ksp_type: str, pc_type: str, rtol: float, options: dict | None,
                  near_null=None, factor_solver: str | None = None, defer_check: bool = False):
    """A KSP on the PETSc matrix ``M`` set from arguments, then from ``options`` (which win).

    Returns the set-up KSP. Options PETSc did not use are reported by
    :func:`report_unused_options` (a logged warning) after the set-up, or, with
    ``defer_check``, by the caller after its first solve (the KSP's options prefix is
    ``ksp.getOptionsPrefix()``). A set-up that fails raises :class:`InputError` naming the
    options PETSc did not use.
    """
    PETSc = petsc()
    ksp = PETSc.KSP().create(comm=M.getComm())
    ksp.setOperators(M)
    ksp.setType(ksp_type)
    ksp.getPC().setType(pc_type)
    if factor_solver is not None:
        ksp.getPC().setFactorSolverType(factor_solver)
    ksp.setTolerances(rtol=rtol, atol=0.0, max_it=10_000)
    # rtol means the true residual ||b - A x|| / ||b|| (as for the other solvers of the registry),
    # not PETSc's default preconditioned norm: CG monitors it directly, GMRES preconditions on the right
    if ksp_type == "cg":
        ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
    elif ksp_type in ("gmres", "fgmres"):
        ksp.setPCSide(PETSc.PC.Side.RIGHT)
    if near_null is not None:
        M.setNearNullSpace(near_null)
    prefix = apply_options(options)
    ksp.setOptionsPrefix(prefix)
    try:
        ksp.setFromOptions()
        ksp.setUp()
    except PETSc.Error as exc:
        unused = unused_options(prefix, options)
        report_unused_options(prefix, options, reported=set(unused))  # clears the database; named below
        hint = f" (PETSc did not use {', '.join(map(repr, unused))}: misspelled?)" if unused else ""
        raise InputError(f"PETSc could not set up KSP {ksp_type} / PC {pc_type} with options {options or {}}{hint}: "
                         f"{exc}; the matrix may be singular (restrain every rigid-body motion).") from None
    if not defer_check:
        report_unused_options(prefix, options)
    return ksp


class PetscKrylovSolver:
    """PETSc KSP (CG for SPD, MINRES for symmetric indefinite, GMRES otherwise) with GAMG.

    The near-null space of GAMG is the rigid-body modes from the node coordinates
    (``MatrixHints.near_null``: 3 modes in 2D, 6 in 3D), orthonormalized.

    Parameters
    ----------
    rtol : float
        Relative residual of each solve (``ksp_rtol``; ``options`` may override it).
    ksp_type, pc_type : str, optional
        PETSc KSP and PC types; default from the matrix type and ``"gamg"``.
    options : dict, optional
        PETSc options passed through, names without the dash (``{"pc_gamg_threshold": 0.02}``);
        a name PETSc does not use is logged as a warning after the first solve
        (:func:`report_unused_options`, once per name and solver).

    Examples
    --------
    >>> solver = PetscKrylovSolver(options={"ksp_max_it": 200})  # doctest: +SKIP
    """

    name = "petsc"
    kind = "iterative"

    def __init__(self, rtol: float = 1e-10, ksp_type: str | None = None, pc_type: str = "gamg",
                 options: dict | None = None):
        petsc()  # fail here, with the set-up command, when petsc4py is missing
        if not (0.0 < float(rtol) < 1.0):
            raise InputError(f"rtol={rtol!r}; allowed: 0 < rtol < 1.")
        self.rtol, self.ksp_type, self.pc_type = float(rtol), ksp_type, pc_type
        self.options = checked_options(options)
        self.unused: set[str] = set()  # options PETSc did not use (reported once each)

    def factorize(self, matrix, hints: MatrixHints | None = None) -> _KSPFactor:
        hints = hints or MatrixHints()
        t0 = time.perf_counter()
        M = petsc_matrix(matrix)
        null = near_null_space(hints.near_null()) if (hints.near_null is not None and self.pc_type == "gamg") else None
        ksp = configure_ksp(M, ksp_type=self.ksp_type or _KRYLOV_FOR[hints.matrix_type], pc_type=self.pc_type,
                            rtol=self.rtol, options=self.options, near_null=null, defer_check=True)
        return _KSPFactor(self.name, ksp, M, M.getSize()[0], time.perf_counter() - t0, exact=False,
                          options=self.options, reported=self.unused)


def direct_package() -> str:
    """The first of MUMPS, SuperLU_dist and PETSc's own LU that the installed PETSc has."""
    PETSc = petsc()
    for pkg in ("mumps", "superlu_dist"):
        if PETSc.Sys.hasExternalPackage(pkg):
            return pkg
    return "petsc"


class PetscDirectSolver:
    """PETSc LU through MUMPS (or SuperLU_dist, or PETSc's own LU when neither is built in).

    Parameters
    ----------
    package : str, optional
        ``"mumps"``, ``"superlu_dist"`` or ``"petsc"``; default :func:`direct_package`.
    options : dict, optional
        PETSc options passed through (``{"mat_mumps_icntl_14": 50}``); unused ones are logged
        as a warning after the first solve.
    """

    name = "petsc-direct"
    kind = "direct"

    def __init__(self, package: str | None = None, options: dict | None = None):
        PETSc = petsc()
        if package is not None and package != "petsc" and not PETSc.Sys.hasExternalPackage(package):
            raise InputError(f"package={package!r}: this PETSc was built without it; available: "
                             f"{direct_package()!r} (see PETSc.Sys.hasExternalPackage).")
        self.package = package or direct_package()
        self.options = checked_options(options)
        self.unused: set[str] = set()  # options PETSc did not use (reported once each)

    def factorize(self, matrix, hints: MatrixHints | None = None) -> _KSPFactor:
        hints = hints or MatrixHints()
        t0 = time.perf_counter()
        M = petsc_matrix(matrix)
        pc = "cholesky" if (hints.matrix_type == "spd" and self.package == "mumps") else "lu"
        ksp = configure_ksp(M, ksp_type="preonly", pc_type=pc, rtol=1e-12, options=self.options,
                            factor_solver=self.package, defer_check=True)
        return _KSPFactor(self.name, ksp, M, M.getSize()[0], time.perf_counter() - t0, exact=True,
                          options=self.options, reported=self.unused)
