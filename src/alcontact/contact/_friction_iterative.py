r"""Coulomb friction without a factorization: full-space Newton with AMG-preconditioned Krylov solves.

The frictional problem of :mod:`alcontact.contact._friction_discrete` (small
deformation (6.15)-(6.22), same points, tangent bases, held tangent directions,
candidates and load history) solved in the space of the free DOFs :math:`x`
instead of being condensed on the contact points, for meshes whose factor does
not fit in memory (the same reason as the frictionless
:mod:`alcontact.contact._iterative`). With the local kinematics of the candidate
points :math:`y = (g, u_T) = y^{fix}(t) + B x` (rows :math:`-\nu_i^T` and
:math:`T_i^T` on the free DOFs; :math:`y^{fix}` the reference gaps and the
prescribed displacements) and the load :math:`b(t) = f_f - K_{fd} u_d` on the free
DOFs, each AL subproblem (6.2a) of Algorithms 6.2 / 6.4 is

.. math::

    F(x) = K x - b(t) + B^T (w \circ t(y(x))) = 0, \qquad
    J = K + B^T \operatorname{diag}(w_i\, \partial t_i/\partial y_i)\, B ,

with :math:`t = (t_N, t_T)` the normal law and the return mapping (6.47)-(6.50)
of :func:`~alcontact.contact._friction_laws.local_law` at the multipliers
:math:`(\lambda_N, \lambda_T)` (the same function as the condensed path). It is
:math:`K u = f + P^T E R` of the condensed path written in :math:`x` (the force on
the body is :math:`E_i R_i = -B_i^T R_i`), so both paths solve the same discrete
problem. The outer iterations, the multiplier updates (6.2b)/(6.2c) (family-P:
:math:`\lambda_N \leftarrow p'(g/\eta, \lambda_N)`) and the stopping test
(:func:`~alcontact.contact._friction._measures`) are the one AL loop
:func:`~alcontact.contact._friction._step_al`, here on the system :class:`_FullCtx`
(unknowns :math:`x`); the load step (:class:`~alcontact.contact._friction._StepPath`:
candidates, equilibrium of a held body), step control, cut-backs and statuses are
those of :mod:`alcontact.contact._friction` too.

Each subproblem is solved by the one Newton driver of the contact algorithms
(:func:`~alcontact.contact._newton.newton`, system :class:`_FullSpaceFriction`), as the
frictionless :func:`~alcontact.contact._iterative.full_newton`: inexact steps with the
same forcing terms and tolerance floor, AMG hierarchy rebuilt when the Krylov solves
slow down (:class:`_AmortizedPreconditioner`), backtracking on the potential
:math:`\Pi = \tfrac12 x^TKx - b^Tx + \sum_i w_i(\psi_N(g_i) + \phi_T(u_{T,i}))` when the
disc radius is the fixed :math:`\mu\lambda_N` (``radius="multiplier"``, the
default: :math:`J` is symmetric, the Krylov method is CG), on the residual norm
otherwise (``radius="traction"``: the coupling :math:`\partial t_T/\partial g` makes
:math:`J` unsymmetric in slip, the Krylov method is GMRES). The preconditioner is a
smoothed-aggregation hierarchy of the symmetric positive semi-definite part of
:math:`J` (per-point blocks of :math:`\partial t/\partial y` symmetrized, negative
eigenvalues dropped) plus the contact springs below, with the rigid-body modes as
near-null space.

The multiplier update is first order on this path, a declared property of its system
(:attr:`_FullCtx.second_order` is false: ``multiplier_update="newton"`` needs the dense
sensitivity of the condensed subproblem, :math:`c d \times c d` with one solve per
column): the fixed point, hence the solution, is the same.

Body held by the obstacle. When the supports leave rigid motions free, springs
:math:`\kappa = E'/h` on all free components of the contact points touching the
obstacle (the choice of :meth:`FrictionalContact._stabilize`) make
:math:`\tilde K = K + S` regular. The residual and the Newton matrix above use the
physical :math:`K` (the spring-shifted law of the condensed path gives the same
equations); :math:`\tilde K` gives the contact-free solution that selects the
candidates, and :math:`S` is added to every preconditioner matrix, so the AMG
hierarchy never sees a singular matrix. A step is accepted only in global
equilibrium, and :meth:`FrictionalContact.slides_away` reports a body that the
obstacle and friction cannot hold, as on the direct path.

The semi-smooth Newton reference (``algorithm="ssn"``) works on the condensed
multipliers: on this path the compliance :math:`A` of the candidates is built with
one AMG-preconditioned CG solve per candidate DOF (relative tolerance 1e-10), then
the steps are those of the direct path. It is meant as the reference on small and
moderate contact zones; large ones should use the AL algorithms.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import scipy.sparse as sp

from .. import linalg as _linalg
from ..errors import InputError
from ..linalg import krylov
from ._friction import _CondensedPath, _Point, _PointSystem, _step_ssn, _StepOut, _StepPath, \
    register_friction_strategy
from ._friction_discrete import FrictionalContact
from ._friction_laws import local_law, tangential_energy
from ._iterative import _FORCING_MAX, _FORCING_MIN, _FORCING_SLOW, _FORCING_START, _NEWTON_TOL_FLOOR, \
    _REBUILD_FACTOR, _Preconditioner, free_rigid_motions, springs_hold
from ._newton import LineSearch, NewtonResult, NewtonSettings, newton

__all__ = ["IterativeFrictionalContact", "advance"]

logger = logging.getLogger(__name__)

#: restart length and restart count of GMRES (unsymmetric Newton matrices)
_GMRES_RESTART = 200
_GMRES_MAXITER = 25
#: a per-point tangent block counts as symmetric below this relative asymmetry
_SYM_TOL = 1e-12


class IterativeFrictionalContact(FrictionalContact):
    """The frictional problem of a :class:`ContactProblem` in the full space of the free DOFs.

    The setup of :class:`FrictionalContact` (points, normals, tangent bases, held
    directions :attr:`tfree`, weights, candidates, element size, contact springs of a
    held body), whose methods it shares (local kinematics, sliding-away test,
    equilibrium defect); its factorization hook (:meth:`_factor_of`) builds the AMG
    "factorization" of :math:`\\tilde K` (:class:`alcontact.linalg.AMGSolver`: each
    solve runs preconditioned CG) and checks the rigid motions instead. The condensed
    compliance ``A`` is built only for the semi-smooth Newton reference (:meth:`condense`).

    Attributes
    ----------
    free : ndarray of int
        Free DOFs.
    K : scipy.sparse.csr_matrix
        Stiffness on the free DOFs (physical: without the contact springs).
    S : scipy.sparse.csr_matrix or None
        Contact springs on the free DOFs of a body held by the obstacle.
    Bl : scipy.sparse.csr_matrix (m d, n_free)
        Local kinematics :math:`y_i = y^{fix}_i + B_i x` (row ``i d`` the gap, then :math:`u_T`).
    Z : ndarray (n_free, k) or None
        Rigid motions left free by the supports (body held by the obstacle).
    linear_solves, cg_iterations, amg_setups : int
        Krylov solves (Newton steps, contact-free solutions, and with :meth:`condense` the
        compliance columns), Newton Krylov iterations (``stats`` adds those of ``factor``),
        hierarchies built.
    """

    def __init__(self, problem, history, *, margin: float = 0.25, solver: _linalg.SolverChoice | None = None):
        t0 = time.perf_counter()
        model = problem.model
        # the approximate solver whose factors precondition the Krylov solves (alcontact.linalg.select_solver)
        self.solver = _linalg.select_solver("amg", dim=model.dim, ndofs=model.ndofs) if solver is None else solver
        self.condensed = False  # the compliance A is built only for the semi-smooth Newton reference
        self.S = self.Z = self.ZSZ = None  # contact springs of a held body (_spring_matrix, _factor_of)
        # the setup of the direct path; its factorization hook builds the AMG hierarchy (_factor_of)
        super().__init__(problem, history, margin=margin, linear_solver=self.solver.name)
        model = self.model
        free = self.free = self._free
        self.K = self._K[free][:, free].tocsr()
        self.K_abs = abs(self.K).tocsr()  # round-off bound of the residual
        self.R = model._free_rigid_modes(free)  # near-null space of the hierarchies (that of ``factor``)
        self.hints = _linalg.MatrixHints(dim=model.dim, near_null=lambda: self.R)
        self.factor_K = self.factor.factor
        self.cg_iterations = 0
        self.amg_setups = 1
        self.amg_seconds = self.factor_seconds
        self.b_parts = np.stack([self.factor.rhs(load, fv) for fv, load in zip(self.fv_parts, self.loads)])
        # y = y_fix(t) + Bl x: rows -E_i^T P_i (P_i: the free DOFs of point i, the row operator of the direct path)
        self.Bl = (_block_matrix(-np.transpose(self.E, (0, 2, 1))) @ self._G).tocsr()
        self.Bl.eliminate_zeros()
        self.yfix_parts = np.stack([self._local(self.factor.expand(np.zeros(free.size), fv))
                                    for fv in self.fv_parts])
        self.precond = _AmortizedPreconditioner(self)
        self.setup_seconds = time.perf_counter() - t0

    # ------------------------------------------------------------------ the hooks of the direct path's setup
    def _schur_request(self, problem, margin: float) -> dict:
        """No Schur block: nothing is factorized on this path."""
        return {}

    def _factor_of(self, matrix=None):
        r"""The AMG "factorization" of :math:`K` (``matrix``: :math:`\tilde K = K + S` of a held body).

        Instead of a checked factorization, the check is on the rigid motions: the supports
        restrain them (``model.check_restrained``), or the springs :math:`S` of
        :meth:`FrictionalContact._stabilize` on the touching points stop every motion :math:`r`
        the supports leave free (:math:`r^T S r > 0` on that space, relative to the largest
        spring energy of a unit motion: :func:`~alcontact.contact._iterative.springs_hold`).

        Raises
        ------
        InputError
            When a rigid motion is left free (:meth:`FrictionalContact._stabilize` then says
            what to do).
        """
        model = self.model
        if matrix is None:
            model.check_restrained(self.fixed)
            self._K = model.stiffness()
        else:
            self.Z = free_rigid_motions(model, self.fixed, self._free)
            self.ZSZ = springs_hold(self.Z, self.S)
            if self.ZSZ is None:
                raise InputError("the contact springs do not stop the rigid motions left free by the supports.")
        return model.factorize(self.fixed, matrix=self._K if matrix is None else matrix, check=False,
                               backend=self.solver.name, reuse=False)

    def _spring_matrix(self, near: np.ndarray, kappa: float) -> sp.csr_matrix:
        """The springs of :meth:`FrictionalContact._spring_matrix`; kept on the free DOFs as ``S``."""
        springs = super()._spring_matrix(near, kappa)
        self.S = springs.tocsr()[self._free][:, self._free].tocsr()
        return springs

    # ------------------------------------------------------------------ candidates
    def add(self, new: np.ndarray) -> np.ndarray:
        """Add candidate points; the condensed compliance only after :meth:`condense`."""
        if self.condensed:
            return super().add(new)
        new = self._new_points(new)
        self.cand = np.concatenate([self.cand, new])
        return new

    def condense(self) -> None:
        """Build the compliance ``A`` of the candidates (one AMG-CG solve per candidate DOF)."""
        if self.condensed:
            return
        cand, self.cand = self.cand, np.empty(0, dtype=np.int64)
        self.condensed = True
        super().add(cand)
        logger.info("semi-smooth Newton reference on the AMG path: compliance of %d candidate points by %s solves",
                    cand.size, self.solver.name)

    # ------------------------------------------------------------------ full-space pieces
    def rows(self, cand: np.ndarray) -> sp.csr_matrix:
        """Rows of :attr:`Bl` of the points ``cand`` (point-major, ``d`` each)."""
        d = self.dim
        return self.Bl[(cand[:, None] * d + np.arange(d)).ravel()].tocsr()

    def load(self, t: float) -> np.ndarray:
        """Load :math:`b(t) = f_f - K_{fd} u_d` on the free DOFs."""
        return self.amplitudes(t) @ self.b_parts

    def y_fix(self, t: float) -> np.ndarray:
        """Local kinematics ``(m, d)`` of ``x = 0`` (reference gaps and prescribed displacements)."""
        y = np.tensordot(self.amplitudes(t), self.yfix_parts, axes=1)
        y[:, 0] += self.gap0
        return y

    def expand_at(self, t: float, x: np.ndarray) -> np.ndarray:
        """Full displacement of the free values ``x`` at time ``t``."""
        return self.factor.expand(x, self.amplitudes(t) @ self.fv_parts)

    def krylov(self, J, rhs, M, *, rtol: float, symmetric: bool):
        """CG (``symmetric``) or GMRES for ``J x = rhs`` to ``|r| <= rtol |rhs|``; counted."""
        if symmetric:
            x, nit, info = krylov.cg(J, rhs, M, rtol=rtol, maxiter=5000)
        else:
            x, nit, info = krylov.gmres(J, rhs, M, rtol=rtol, restart=_GMRES_RESTART, maxiter=_GMRES_MAXITER)
        self.linear_solves += 1
        self.cg_iterations += nit
        if info != 0:
            logger.warning("%s stopped after %d iterations without reaching rtol %.1e", "CG" if symmetric else
                           "GMRES", nit, rtol)
        return x, nit

    def stats(self) -> dict:
        """Solver counters for the solution's ``extra``."""
        # the Krylov iterations of the solver's own solves (the contact-free solutions, the compliance of the
        # semi-smooth Newton reference), where its factor counts them (the AMG factor's CG)
        inner = int(getattr(self.factor.factor, "iterations", 0))
        return {"linear_solver": "amg", "backend": self.solver.name, "cg_iterations": int(self.cg_iterations + inner),
                "amg_setups": int(self.amg_setups), "krylov_solves": int(self.linear_solves)}


class _AmortizedPreconditioner(_Preconditioner):
    """:class:`~alcontact.contact._iterative._Preconditioner` whose slow-down rebuild must pay for itself.

    A Krylov solve slower than ``1.5 * rate_ref + 1`` iterations per digit marks the
    hierarchy stale only once the iterations spent above the reference rate since the
    last build cost more time than that build took. Each outer iteration of
    Algorithm 6.2 changes the stick/slip sets a little and the Krylov solves of a
    frictional step are short (5-15 iterations), so the plain rule rebuilt the
    hierarchy at nearly every outer iteration: 16 builds for 76 solves on the 3D
    sphere benchmark at 17k DOFs, most of the solve time.
    """

    def __init__(self, ic):
        super().__init__(ic)
        self.excess = 0.0
        self.build_seconds = ic.amg_seconds

    def get(self, J, kmax: float = 0.0):
        n0, t0 = self.ic.amg_setups, time.perf_counter()
        M = super().get(J, kmax)
        if self.ic.amg_setups > n0:
            self.build_seconds = time.perf_counter() - t0
            self.excess = 0.0
        return M

    def record(self, iterations: int, rtol: float, seconds: float = 0.0) -> None:
        digits = max(np.log10(1.0 / max(rtol, 1e-16)), 1.0)
        if self.rate_ref is None:
            self.rate_ref = iterations / digits
            return
        self.excess += max(iterations - self.rate_ref * digits, 0.0) * seconds / max(iterations, 1)
        if iterations / digits > _REBUILD_FACTOR * self.rate_ref + 1.0 and self.excess > self.build_seconds:
            self.stale = True


# ----------------------------------------------------------------------
def _block_matrix(D: np.ndarray) -> sp.csr_matrix:
    """Sparse block-diagonal matrix of ``(c, d, d)`` blocks (point-major)."""
    c, d, _ = D.shape
    base = np.arange(c)[:, None, None] * d
    r = np.broadcast_to(base + np.arange(d)[None, :, None], D.shape)
    k = np.broadcast_to(base + np.arange(d)[None, None, :], D.shape)
    return sp.csr_matrix((D.ravel(), (r.ravel(), k.ravel())), shape=(c * d, c * d))


def _psd_part(D: np.ndarray) -> np.ndarray:
    """Symmetric part of each block with its negative eigenvalues dropped (preconditioner)."""
    sym = 0.5 * (D + np.transpose(D, (0, 2, 1)))
    if sym.shape[0] == 0:
        return sym
    lam, V = np.linalg.eigh(sym)
    return np.einsum("cij,cj,ckj->cik", V, np.maximum(lam, 0.0), V)


@dataclass
class _FullCtx:
    """One load step on the AMG path: candidates, previous state, load and options."""

    fc: IterativeFrictionalContact
    Bc: sp.csr_matrix  # (c d, n_free)
    yfix: np.ndarray  # (c, d)
    b: np.ndarray
    w: np.ndarray
    lamN: np.ndarray
    lamT: np.ndarray
    uTn: np.ndarray
    x0: np.ndarray
    x_free: np.ndarray  # contact-free solution at t (with the springs of a held body)
    eps_n: float
    eps_t: float
    mu: float
    opts: object
    tfree: np.ndarray

    label: ClassVar[str] = "friction AL (AMG)"
    #: first-order multiplier updates (6.2b)/(6.2c) only: the second-order update needs the dense
    #: sensitivity of the condensed subproblem (c d x c d, one solve per column); same fixed point
    second_order: ClassVar[bool] = False
    #: the family-P predictor gives lambda_N only and is not counted (_friction._step_al)
    full_predictor: ClassVar[bool] = False

    @property
    def c(self):
        return self.yfix.shape[0]

    @property
    def d(self):
        return self.yfix.shape[1]

    def y(self, x):
        return self.yfix + (self.Bc @ x).reshape(self.yfix.shape)

    # the _friction._ALSystem of the free displacements x
    @property
    def start(self):
        return self.x0.copy()

    def subproblem(self, law, lamN, lamT, x, coupled: bool = False) -> NewtonResult:
        """Subproblem (6.2a) by :func:`friction_newton` (``coupled`` is never asked: first-order updates)."""
        return friction_newton(self, law, lamN, lamT, x, tol=self.opts.newton_tol, maxiter=self.opts.maxiter_newton)

    def iterate(self, out):
        return out.x

    def inside_domain(self, law, lamN, x):
        """Start for barrier-type penalties: scale the contact part ``x - x_free`` up until every gap is inside."""
        bound = law.gap_bound(lamN)
        s = 0.5
        while np.any(self.y(x)[:, 0] >= 0.99 * bound) and s < 1e6:
            trial = self.x_free + (1.0 + s) * (x - self.x_free)
            if not np.any(self.y(trial)[:, 0] >= 0.99 * bound):
                return trial
            s *= 2
        return x

    def forces(self, x, t):
        return self.w[:, None] * t


class _FullSpaceFriction(_PointSystem):
    r"""Subproblem (6.2a) in the free DOFs (module doc): :math:`F(x) = Kx - b + B^T(w \circ t(y(x)))`.

    The frictional counterpart of :class:`~alcontact.contact._iterative._FullSpaceSubproblem`:
    relative residual :math:`\max|F|` over the largest load or contact force (of the start,
    or the current iterate where larger); tolerance raised to the round-off bound of
    :math:`F`; each step an inexact Krylov solve (CG for a symmetric :math:`J`, else GMRES)
    with the AMG preconditioner, the forcing terms of :mod:`alcontact.contact._iterative`
    (tightened after a damped step or a slow residual decrease) and its rebuild rule
    (:class:`_AmortizedPreconditioner`). The merit is the potential :math:`\Pi` (module
    doc) for the fixed disc radius :math:`\mu\lambda_N`; without a potential (coupled radius)
    the line search asks for a decrease of :math:`|F|` (:data:`_WITH_POTENTIAL`,
    :data:`_NO_POTENTIAL`). State: :class:`~alcontact.contact._friction._Point` with
    ``aux = (y, t, Dy, state)``.
    """

    def __init__(self, ctx: _FullCtx, law, lamN, lamT):
        self.ctx, self.law, self.lamN, self.lamT = ctx, law, lamN, lamT
        self.rho = ctx.mu * np.maximum(lamN, 0.0) if ctx.opts.radius == "multiplier" else None
        self.BcT = ctx.Bc.T.tocsr()
        self.Babs = abs(ctx.Bc).tocsr()
        self.bscale = float(np.max(np.abs(ctx.b), initial=0.0))
        self.scale = None
        self.fscale = 1e-300
        self.forcing = _FORCING_START
        self.tol_k = 0.0

    def evaluate(self, x):
        ctx, law, fc = self.ctx, self.law, self.ctx.fc
        y = ctx.y(x)
        t, Dy, _, st = local_law(law, self.lamN, self.lamT, y, ctx.uTn, ctx.eps_t, ctx.mu, rho=self.rho,
                                 tfree=ctx.tfree)
        Kx = fc.K @ x
        F = Kx - ctx.b + self.BcT @ (ctx.w[:, None] * t).ravel()
        energy = 0.0
        if self.rho is not None:
            e = law.energy(y[:, 0], self.lamN) + tangential_energy(self.lamT, y[:, 1:], ctx.uTn, ctx.eps_t,
                                                                   self.rho, ctx.tfree)
            energy = 0.5 * float(x @ Kx) - float(ctx.b @ x) + float(np.sum(ctx.w * e))
        return _Point(x, F, (y, t, Dy, st), energy)

    def slope(self, x, state, dx):
        return float(state.F @ dx)  # the gradient of Pi is F

    def measure(self, state):
        wt = float(np.max(np.abs(self.ctx.w[:, None] * state.aux[1]), initial=0.0))
        if self.scale is None:
            self.scale = max(wt, self.bscale)
        self.fscale = max(self.scale, wt, 1e-300)
        return float(np.max(np.abs(state.F), initial=0.0)) / self.fscale

    def tolerance(self, state, tol):
        # round-off bound of F: 10 u (|K||x| + |b| + |B|^T w (|t| + |Dy| (|y_fix| + |B||x|)))
        ctx = self.ctx
        x, (_, t, Dy, _) = state.x, state.aux
        ax = np.abs(x)
        yerr = np.abs(ctx.yfix) + (self.Babs @ ax).reshape(ctx.c, ctx.d)
        terr = np.abs(t) + np.einsum("cij,cj->ci", np.abs(Dy), yerr)
        bound = ctx.fc.K_abs @ ax + np.abs(ctx.b) + self.Babs.T @ (ctx.w[:, None] * terr).ravel()
        floor = 10.0 * np.finfo(float).eps * float(np.max(bound, initial=0.0))
        self.tol_k = max(tol, floor / self.fscale)
        return self.tol_k

    def step(self, x, state, history):
        ctx, fc = self.ctx, self.ctx.fc
        res = history[-1].residual
        if len(history) > 1:
            last = history[-2]
            if last.step < 1.0 or last.full_step or res > 0.5 * last.residual:
                self.forcing = max(_FORCING_SLOW * self.forcing, _FORCING_MIN)  # as _FullSpaceSubproblem.step
        WD = ctx.w[:, None, None] * state.aux[2]
        J = (fc.K + self.BcT @ _block_matrix(WD) @ ctx.Bc).tocsr()
        asym = float(np.max(np.abs(WD - np.transpose(WD, (0, 2, 1))), initial=0.0))
        symmetric = asym <= _SYM_TOL * max(float(np.max(np.abs(WD), initial=0.0)), 1e-300)
        P = J if symmetric else (fc.K + self.BcT @ _block_matrix(_psd_part(WD)) @ ctx.Bc).tocsr()
        if fc.S is not None:  # (the preconditioner adds the springs S to P)
            J = _held_rigid_motions(fc, J, ctx.Bc, WD)
        # inexact Newton: forcing min(forcing, res), tight enough in the last step to reach the tolerance
        rtol = float(np.clip(max(min(self.forcing, res), 0.1 * self.tol_k / res), 1e-14, _FORCING_MAX))
        M = fc.precond.get(P, float(np.max(np.abs(WD), initial=0.0)))
        t_k = time.perf_counter()
        dx, nit = fc.krylov(J, -state.F, M, rtol=rtol, symmetric=symmetric)
        fc.precond.record(nit, rtol, time.perf_counter() - t_k)
        logger.debug("friction Newton (AMG) %d: residual %.2e, %s rtol %.1e, %d iterations", len(history), res,
                     "CG" if symmetric else "GMRES", rtol, nit)
        return dx

    def negligible(self, x, state, dx):
        return float(np.max(np.abs(dx), initial=0.0)) <= 1e-14 * max(float(np.max(np.abs(x), initial=0.0)), 1e-300)


#: fixed disc radius: Armijo on the potential (the full step when it is flat to round-off if it reduces
#: max|F|); a correction at round-off level converges within 1e3 times the tolerance
_WITH_POTENTIAL = NewtonSettings(LineSearch(halvings=60), negligible_tol=1e3)
#: coupled disc radius (no potential): a decrease of |F|, the same full-step rule
_NO_POTENTIAL = NewtonSettings(LineSearch(halvings=60, merit=False, residual_decrease=True), negligible_tol=1e3)


def friction_newton(ctx: _FullCtx, law, lamN, lamT, x0, *, tol: float, maxiter: int) -> NewtonResult:
    """Solve the subproblem :math:`F(x) = 0` (module doc) by :func:`~alcontact.contact._newton.newton`.

    Inexact globalized Newton with AMG-Krylov steps (:class:`_FullSpaceFriction`), tolerance
    ``max(tol, 1e-11)`` (as :func:`~alcontact.contact._iterative.full_newton`) or the
    round-off bound of the residual; ``state.aux`` of the result is ``(y, t, Dy, state)``.
    """
    tol = max(tol, _NEWTON_TOL_FLOOR)
    system = _FullSpaceFriction(ctx, law, lamN, lamT)
    return newton(system, x0, tol=tol, maxiter=maxiter,
                  settings=_WITH_POTENTIAL if system.rho is not None else _NO_POTENTIAL)


def _held_rigid_motions(fc: IterativeFrictionalContact, J, Bc, WD):
    r"""Newton matrix of a body held by the obstacle, regular along the rigid motions contact does not hold.

    With :math:`Z` the rigid motions left free by the supports (:math:`K Z = 0`),
    contact stiffens them by :math:`G = Z^T B^T W D B Z`. Where the generalized
    eigenvalues of :math:`(G, Z^T S Z)` are below 1e-8 (open points at the first
    iterate of a load step, or zero-radius Coulomb discs: nothing holds that motion
    yet), :math:`J` is singular along :math:`Z_d = Z V_d`; the step is then taken
    with the springs on those motions only,
    :math:`J + S Z_d Z_d^T S` (:math:`V_d^T Z^T S Z V_d = I`), a rank-:math:`k`
    term. The residual is unchanged (exact), so the fixed point is too, and once
    contact holds every rigid motion the step is the exact Newton step again.
    """
    import scipy.linalg as sla
    from scipy.sparse.linalg import LinearOperator

    c, d = WD.shape[0], WD.shape[1]
    Zc = (Bc @ fc.Z).reshape(c, d, -1)
    sym = 0.5 * (WD + np.transpose(WD, (0, 2, 1)))
    G = np.einsum("cik,cij,cjl->kl", Zc, sym, Zc)
    lam, V = sla.eigh(0.5 * (G + G.T), fc.ZSZ)
    weak = lam <= 1e-8
    if not np.any(weak):
        return J
    SZ = fc.S @ (fc.Z @ V[:, weak])
    logger.debug("held body: %d rigid motion(s) not held by contact in this Newton step", int(weak.sum()))
    return LinearOperator(J.shape, matvec=lambda v: J @ v + SZ @ (SZ.T @ v), dtype=float)


class _FullSpacePath(_StepPath):
    """The AMG path's AL step: the loop of :func:`~alcontact.contact._friction._step_al` on :class:`_FullCtx`.

    Every step starts from the previous converged displacement (all closed points
    sticking, as :meth:`FrictionalContact.frozen_start` on the direct path), or from the
    last attempt's when candidates were added.
    """

    def context(self, fc: IterativeFrictionalContact, prev, t, last, step_fn, eps_n, eps_t, mu, opts):
        cand = fc.cand
        x0 = prev.u[fc.free] if last is None else last.z
        return _FullCtx(fc, fc.rows(cand), fc.y_fix(t)[cand], fc.load(t), fc.weights[cand], prev.tN[cand].copy(),
                        prev.tT[cand].copy(), prev.y[cand, 1:].copy(), x0, fc.u_free(t)[fc.free], eps_n, eps_t,
                        mu, opts, fc.tfree[cand]), 0

    def without_candidates(self, fc, t):
        d = fc.dim
        x = fc.u_free(t)[fc.free]
        return _StepOut(True, "no candidate points", np.zeros((0, d)), np.zeros((0, d)), 0, 0, z=x), \
            fc.expand_at(t, x)

    def displacement(self, fc, t, out):
        return fc.expand_at(t, out.z)


class _CondensedOnAMG(_CondensedPath):
    """The semi-smooth Newton reference: the direct path's step on the compliance built by AMG-CG solves."""

    def advance(self, fc: IterativeFrictionalContact, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts):
        fc.condense()
        return super().advance(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts)


#: Path of each frictional step function on the AMG path (default: the full-space AL step).
_STEP_PATHS = {_step_ssn: _CondensedOnAMG()}
_FULL_SPACE = _FullSpacePath()


def advance(fc: IterativeFrictionalContact, prev, t: float, step_fn, pen_name, eps_n, eps_t, mu, opts):
    """One load step on the AMG path (the contract of :meth:`alcontact.contact._friction._StepPath.advance`)."""
    return _STEP_PATHS.get(step_fn, _FULL_SPACE).advance(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts)


def _krylov_path(problem, history, opts, solver):
    """The full-space problem solved by Krylov methods preconditioned by the approximate ``solver``, and its step."""
    return IterativeFrictionalContact(problem, history, margin=opts.margin, solver=solver), advance


register_friction_strategy(False, _krylov_path)
