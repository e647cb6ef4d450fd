r"""Newton systems solved by CG preconditioned by an approximate solver, with an inexact-Newton forcing term.

:class:`NewtonKrylovSolver` solves the symmetric Newton systems :math:`J(x_k)\,\Delta x = -R(x_k)`
of a nonlinear solve (and a few more with the same matrix) without a factorization:

* **preconditioned CG** (:func:`~alcontact.linalg.krylov.pcg`) on :math:`J` with the factor of an
  approximate solver (AMG: a smoothed-aggregation V-cycle), whose near-null space the caller
  supplies at every setup (the finite-deformation contact path: the rigid-body modes of the
  *current* configuration);
* **reuse**: one factor preconditions the Newton matrices of many iterations and load steps; it
  is rebuilt (from the current :math:`J`) when a solve needs more than
  ``rebuild_factor * rate_ref + 1`` CG iterations per decimal digit of residual reduction
  (``rebuild_factor`` 1, measured: ``_REBUILD_FACTOR``), ``rate_ref`` the rate of the first solve
  after the last build, or when CG stops at ``maxiter``;
* **dual step**: :meth:`NewtonKrylovSolver.resolve` solves with the last matrix to 1e-2
  (measured at ``_RESOLVE_RTOL``; the other solves to 1e-10);
* **inexact Newton**: the CG tolerance of a Newton step is the forcing term
  :math:`\eta_k = \min\bigl(\eta_{max},\ \max(\gamma (\|F_k\|/\|F_{k-1}\|)^2,\ \gamma\eta_{k-1}^2),\
  \|F_k\|_{rel}\bigr)` (Eisenstat-Walker choice 2 with its safeguard, capped by the relative
  residual so that the local convergence stays quadratic);
* **saddle-point** :math:`J` (a mixed u-p body, ``saddle``: :class:`~alcontact.linalg.SaddlePoint`):
  MINRES (:func:`~alcontact.linalg.krylov.minres`) instead of CG, preconditioned by the
  block-diagonal factor of :mod:`alcontact.linalg._saddle` (the approximate solver's hierarchy of the
  displacement block, the Schur diagonal on the pressure rows); its tolerances are relative residuals in
  the preconditioner's norm, the rest (reuse, forcing, dual step) as for CG;
* **indefinite** :math:`J`: CG detects negative curvature :math:`p^T J p \le 0`; that system is
  then solved by a symmetric-indefinite factorization (:class:`~alcontact.linalg.SequenceSolver`,
  a logged warning that names ``linear_solver = "direct"``, counted in ``direct_fallbacks``), or
  with ``fallback=False`` the Newton step fails (:class:`numpy.linalg.LinAlgError`).

The measurements quoted below are those of the finite-deformation contact path
(:mod:`alcontact.contact.systems._full_space`).
"""

from __future__ import annotations

import logging
import time

import numpy as np

from . import krylov
from ._base import MatrixHints
from ._registry import SolverChoice
from ._sequence import SequenceSolver

__all__ = ["NewtonKrylovSolver"]

logger = logging.getLogger(__name__)

#: CG tolerance of solves that are not Newton steps (predictor, dual step, barrier scaling)
_RTOL = 1e-10
#: CG tolerance of :meth:`NewtonKrylovSolver.resolve`: the products :math:`J^{-1} B_A^T v` of the dual step of
#: Algorithm 6.1 (a multiplier estimate that the outer loop checks; on the direct path back-substitutions,
#: here a CG solve each, most of the CG iterations of a run). Measured (simo-laursen; Newton steps, CG
#: iterations of the run, CPU s) for 1e-6 / 1e-2: hemisphere P1 n = 8, 4 steps: 17, 1200, 1.67 / 19, 556,
#: 1.28; n = 10, 5 steps: 21, 2089, 4.94 / 25, 1027, 3.11 (1e-3: 25, 1291, 3.70; no dual step: 32 Newton,
#: 2.20 s); half-cylinder P1 n = 32, 8 steps: 44, 2547, 2.56 / 45, 1347, 1.58. Forces within 3.2e-10 of
#: the direct path in every case
_RESOLVE_RTOL = 1e-2
#: largest forcing term of a Newton step (CG relative tolerance far from the solution)
_FORCING_MAX = 0.1
#: a Newton step that reduced the residual by less than this factor (or was damped) tightens the
#: next forcing term by ``_FORCING_SLOW``
_SLOW = 0.5
_FORCING_SLOW = 0.1
#: the first Newton step of a solve gets this factor times the residual contraction of the last
#: solve's first step as its forcing term
_FIRST_FACTOR = 0.1
#: forcing term of the first step of a run (before any contraction was observed)
_FORCING_START = 1e-3
#: Eisenstat-Walker choice 2: eta = gamma (|F_k| / |F_k-1|)^2
_EW_GAMMA = 0.9
#: smallest CG tolerance (round-off of J x for the penalty stiffnesses of the contact terms)
_FORCING_MIN = 1e-12
#: CG iterations per digit above ``_REBUILD_FACTOR * rate_ref + 1`` mark the hierarchy stale. Measured
#: (simo-laursen, CPU s of the run / CG iterations per Newton step / setups), factor 0 (rebuild at almost
#: every solve), 1, 2, 4, never: hemisphere P1 n = 8 (2187 DOFs, 4 steps) 1.76/19.9/10, 1.59/15.1/6,
#: 1.91/19.5/4, 2.15/36.0/2, 3.07/53.7/1; half-cylinder P1 n = 32 (8 steps) 1.68/16.1/20, 1.95/18.6/14,
#: 2.49/26.4/7, 2.55/34.0/4, 7.07/97.0/1. A 3D setup costs more CG iterations than a 2D one: 1
_REBUILD_FACTOR = 1.0
#: CG iteration limit of one solve (the hierarchy is rebuilt and the solve repeated once)
_MAXITER = 1000
#: MINRES iteration limit of one solve of a saddle-point system (several times CG's count on the
#: displacement block alone: ``docs/benchmarks/mixed_amg.md``)
_MAXITER_SADDLE = 4000



class NewtonKrylovSolver:
    r"""Newton systems by CG preconditioned by an approximate solver's factors, reused while they stay good.

    The surface of a Newton-system solver (module doc; that of
    :class:`~alcontact.contact.systems._full_space.NewtonSolver`): :meth:`newton_step` (inexact,
    Eisenstat-Walker forcing), :meth:`solve` (to ``rtol``), :meth:`resolve` (the last matrix
    again), :meth:`info`.

    Parameters
    ----------
    solver : alcontact.linalg.SolverChoice
        The approximate solver whose factors precondition CG (:func:`alcontact.linalg.select_solver`).
    near_null : callable, optional
        ``near_null() -> (n, k)`` near-null space handed to the solver (:attr:`MatrixHints.near_null
        <alcontact.linalg.MatrixHints>`), read at every setup (rigid-body modes of the current configuration).
    dim : int, optional
        Space dimension (:attr:`MatrixHints.dim <alcontact.linalg.MatrixHints>`).
    rtol : float
        CG tolerance of :meth:`solve` and :meth:`resolve`.
    forcing_max : float
        Largest forcing term of a Newton step.
    rebuild_factor : float, optional
        Hierarchy reuse rule (module doc); default ``_REBUILD_FACTOR``.
    fallback : bool
        Solve a system with negative curvature by the direct factorization (True) or fail the
        Newton step (False: the load step is cut back).
    saddle : alcontact.linalg.SaddlePoint, optional
        The Newton matrices are saddle-point matrices with these blocks (module doc): MINRES with the
        block-diagonal preconditioner instead of CG.

    Attributes
    ----------
    amg_setups, cg_iterations, cg_solves, newton_steps, direct_fallbacks : int
        Counters over the life of the object (``cg_iterations`` of Newton steps in ``newton_cg``).
    amg_seconds, cg_seconds : float
        Wall time of the hierarchy setups and of the CG iterations.
    """

    path = "amg"

    def __init__(self, solver: SolverChoice, *, near_null=None, dim: int | None = None, rtol: float = _RTOL,
                 forcing_max: float = _FORCING_MAX, rebuild_factor: float | None = None, fallback: bool = True,
                 saddle=None):
        rebuild_factor = _REBUILD_FACTOR if rebuild_factor is None else rebuild_factor
        self.solver = solver
        self.backend = solver.name
        self._hints = MatrixHints(dim=dim, near_null=near_null, saddle=saddle)
        #: the Krylov method: ``"minres"`` on saddle-point matrices, ``"cg"`` otherwise
        self.krylov = "cg" if saddle is None else "minres"
        self._maxiter = _MAXITER if saddle is None else _MAXITER_SADDLE
        self.rtol = float(rtol)
        self.resolve_rtol = _RESOLVE_RTOL
        self.forcing_max = float(forcing_max)
        self.rebuild_factor = float(rebuild_factor)
        self.fallback = bool(fallback)
        self.amg_setups = self.cg_iterations = self.cg_solves = 0
        self.newton_steps = self.newton_cg = self.direct_fallbacks = 0
        self.amg_seconds = self.cg_seconds = 0.0
        self._factor = None
        self._M = None
        self._rate_ref: float | None = None
        self._stale = True
        self._A = None
        self._direct: SequenceSolver | None = None
        self._last_direct = False
        self._eta = None
        self._first: list[float] = []  # residual contractions of the last solves' first steps
        self._warned = False

    @property
    def analyses(self) -> int:
        """Hierarchy setups (the direct solver's symbolic analyses count here on the direct path)."""
        return self.amg_setups

    # ------------------------------------------------------------------ hierarchy
    def _build(self, A) -> None:
        self._factor = self._M = None
        t0 = time.perf_counter()
        self._factor = self.solver.factorize(A, self._hints)
        self._M = krylov.preconditioner(self._factor)
        self.amg_seconds += time.perf_counter() - t0
        self.amg_setups += 1
        self._rate_ref = None
        self._stale = False

    def _record(self, iterations: int, rtol: float) -> None:
        rate = iterations / max(float(np.log10(1.0 / max(rtol, 1e-16))), 1.0)
        if self._rate_ref is None:
            self._rate_ref = rate
        elif rate > self.rebuild_factor * self._rate_ref + 1.0:
            self._stale = True

    # ------------------------------------------------------------------ solves
    def _krylov(self, A, rhs: np.ndarray, rtol: float):
        """``(x, iterations, why)`` of the Krylov method (:attr:`krylov`) with the current preconditioner."""
        method = krylov.minres if self.krylov == "minres" else krylov.pcg
        return method(A, rhs, self._M, rtol, self._maxiter)

    def _cg(self, A, rhs: np.ndarray, rtol: float) -> np.ndarray:
        A = A.tocsr()
        if self._stale or self._factor is None or self._factor.n != A.shape[0]:
            self._build(A)
        for attempt in range(2):
            t0 = time.perf_counter()
            x, nit, why = self._krylov(A, rhs, rtol)
            self.cg_seconds += time.perf_counter() - t0
            self.cg_iterations += nit
            self.cg_solves += 1
            if why == "maxiter" and attempt == 0:
                logger.debug("%s reached %d iterations (rtol %.1e); rebuilding the AMG hierarchy", self.krylov, nit,
                             rtol)
                self._build(A)
                continue
            break
        self._A = A
        self._last_direct = False
        if why in ("", "maxiter"):
            if why:
                logger.warning("%s stopped after %d iterations at relative residual above %.1e on a fresh AMG "
                               "hierarchy; the Newton step is inexact (use linear_solver = 'direct' if Newton "
                               "stalls)", self.krylov, nit, rtol)
            self._record(nit, rtol)
            return x
        return self._indefinite(A, rhs, why)

    def _indefinite(self, A, rhs, why: str) -> np.ndarray:
        """A system the Krylov method cannot solve (``why``): the direct factorization, or a failed Newton step."""
        advice = "use linear_solver = 'direct' (a symmetric-indefinite factorization) for this problem"
        what = ("Newton matrix not positive definite" if self.krylov == "cg"
                else "preconditioner of the saddle-point Newton matrix not positive definite")
        if not self.fallback:
            logger.warning("%s (%s: %s); the Newton step fails and the load step is cut back; %s", what,
                           self.krylov, why, advice)
            raise np.linalg.LinAlgError(f"{what} ({self.krylov}: {why}); {advice}")
        if not self._warned:
            logger.warning("%s (%s: %s): solved by a direct factorization (counted in direct_fallbacks); if this "
                           "repeats, %s", what, self.krylov, why, advice)
            self._warned = True
        if self._direct is None:  # the registry's symmetric-indefinite factorization
            self._direct = SequenceSolver(matrix_type="symmetric-indefinite")
        self.direct_fallbacks += 1
        x = self._direct.solve(A, rhs)
        self._last_direct = True
        self._stale = True  # the next matrix gets a fresh hierarchy
        return x

    def solve(self, A, rhs: np.ndarray) -> np.ndarray:
        """Solve ``A x = rhs`` by CG (MINRES on a saddle-point matrix) to :attr:`rtol` (AMG hierarchy reused while it
        stays good)."""
        return self._cg(A, np.asarray(rhs, dtype=float), self.rtol)

    def forcing(self, history) -> float:
        r"""CG tolerance of a Newton step (module doc): ``history`` the Newton records (``residual``, ``step``)."""
        res = float(history[-1].residual) if history else 1.0
        cap = self.forcing_max
        if len(history) > 1 and history[-2].residual > 0 and self._eta is not None:
            last = history[-2]
            eta = _EW_GAMMA * (res / float(last.residual)) ** 2
            guard = _EW_GAMMA * self._eta ** 2
            if guard > 0.1:
                eta = max(eta, guard)
            if last.step < 1.0 or res > _SLOW * float(last.residual):
                # a damped step or a slow decrease: the loose direction was poor on the stiff contact
                # directions (penalty stiffness), tighten
                cap = min(cap, _FORCING_SLOW * self._eta)
        elif self._first:
            # the first step of a solve: as contracting as the most contracting first step of the
            # last solves (a penalty increase or a multiplier update starts a nearly linear subproblem)
            eta = min(_FIRST_FACTOR * min(self._first), _FORCING_START)
        else:
            eta = _FORCING_START
        return float(np.clip(min(eta, res, cap), _FORCING_MIN, self.forcing_max))

    def newton_step(self, A, rhs: np.ndarray, history) -> np.ndarray:
        """The Newton correction ``A dx = rhs`` to the forcing term of :meth:`forcing` (inexact Newton)."""
        if len(history) == 2 and history[0].step == 1.0 and history[0].residual > 0 and self._eta:
            ratio = float(history[1].residual) / float(history[0].residual)
            # a contraction within 10x of the forcing term was set by CG, not by the nonlinearity:
            # the step's own contraction lies below; probe tighter
            self._first = (self._first + [ratio * (_FIRST_FACTOR ** 2 if ratio <= 10 * self._eta else 1.0)])[-8:]
        eta = self.forcing(history)
        self._eta = eta
        it0 = self.cg_iterations
        x = self._cg(A, np.asarray(rhs, dtype=float), eta)
        self.newton_steps += 1
        self.newton_cg += self.cg_iterations - it0
        logger.debug("Newton %d: residual %.2e, CG rtol %.1e, %d CG iterations", len(history),
                     history[-1].residual if history else np.nan, eta, self.cg_iterations - it0)
        return x

    def resolve(self, rhs: np.ndarray) -> np.ndarray | None:
        """Solve with the matrix of the last solve (to :attr:`rtol`); ``None`` when there is none."""
        if self._last_direct and self._direct is not None:
            return self._direct.resolve(rhs)
        b = np.asarray(rhs, dtype=float)
        if self._A is None or self._A.shape[0] != b.shape[0]:
            return None
        t0 = time.perf_counter()
        x, nit, why = self._krylov(self._A, b, self.resolve_rtol)
        self.cg_seconds += time.perf_counter() - t0
        self.cg_iterations += nit
        self.cg_solves += 1
        return x if why == "" else None

    def release(self) -> None:
        """Drop the hierarchy and the last matrix."""
        self._factor = self._M = self._A = None
        self._stale = True

    def info(self) -> dict:
        """Counters for ``solution.extra``: ``linear_solver`` (registry name of the solver), setups, CG iterations."""
        return {"linear_solver": self.backend, "krylov": self.krylov, "amg_setups": int(self.amg_setups),
                "analyses": int(self.amg_setups),
                "cg_iterations": int(self.cg_iterations), "cg_solves": int(self.cg_solves),
                "newton_cg_iterations": int(self.newton_cg),
                "cg_per_newton": self.newton_cg / self.newton_steps if self.newton_steps else 0.0,
                "direct_fallbacks": int(self.direct_fallbacks),
                "amg_levels": krylov.hierarchy_levels(self._factor), "amg_setup_s": float(self.amg_seconds),
                "cg_s": float(self.cg_seconds)}
