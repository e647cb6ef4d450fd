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
problem; the outer iterations, the multiplier updates (6.2b)/(6.2c) (family-P:
:math:`\lambda_N \leftarrow p'(g/\eta, \lambda_N)`), the stopping test
(:func:`~alcontact.contact._friction._measures`), the step control, cut-backs and
statuses are those of :mod:`alcontact.contact._friction`.

Newton's method follows :func:`~alcontact.contact._iterative.full_newton` step by
step: inexact steps with the same forcing terms and tolerance floor, AMG hierarchy
rebuilt when the Krylov solves slow down (:class:`~alcontact.contact._iterative._Preconditioner`),
backtracking on the potential
:math:`\Pi = \tfrac12 x^TKx - b^Tx + \sum_i w_i(\psi_N(g_i) + \phi_T(u_{T,i}))` when the
disc radius is the fixed :math:`\mu\lambda_N` (``radius="multiplier"``, the
default: :math:`J` is symmetric, the Krylov method is CG), on the residual norm
otherwise (``radius="traction"``: the coupling :math:`\partial t_T/\partial g` makes
:math:`J` unsymmetric in slip, the Krylov method is GMRES). The preconditioner is a
smoothed-aggregation hierarchy of the symmetric positive semi-definite part of
:math:`J` (per-point blocks of :math:`\partial t/\partial y` symmetrized, negative
eigenvalues dropped) plus the contact springs below, with the rigid-body modes as
near-null space.

The multiplier update is first order on this path (``multiplier_update="newton"``
needs the dense sensitivity of the condensed subproblem, :math:`c d \times c d`
with one solve per column): the fixed point, hence the solution, is the same.

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

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import cg, gmres

from .. import penalties as _pen
from ..errors import InputError
from ..fem.elasticity import rigid_body_modes
from ._friction import (_EQUILIBRIUM_TOL, _advance, _measures, _NewtonOut, _norm, _step_ssn, _StepOut)
from ._friction_discrete import FrictionalContact, _element_size, tangent_bases
from ._friction_laws import local_law, tangential_energy
from ._iterative import _FORCING_MAX, _FORCING_MIN, _FORCING_SLOW, _FORCING_START, _NEWTON_TOL_FLOOR, \
    _REBUILD_FACTOR, _Preconditioner, free_rigid_motions, springs_hold
from ._laws import eta_for_stiffness, freezes_at_zero, make_law
from ._loading import component_fields
from ._solution import ContactStatus

__all__ = ["IterativeFrictionalContact", "advance"]

logger = logging.getLogger(__name__)

#: restart length and restart count of GMRES (unsymmetric Newton matrices)
_GMRES_RESTART = 200
_GMRES_MAXITER = 25
#: a per-point tangent block counts as symmetric below this relative asymmetry
_SYM_TOL = 1e-12


class IterativeFrictionalContact(FrictionalContact):
    """The frictional problem of a :class:`ContactProblem` in the full space of the free DOFs.

    Same points, normals, tangent bases, held directions (:attr:`tfree`), weights,
    candidates, element size and contact springs as :class:`FrictionalContact`,
    whose methods it shares (local kinematics, sliding-away test, equilibrium
    defect); ``factor`` is the AMG "factorization" of :math:`\\tilde K`
    (:class:`alcontact.linalg.AMGSolver`: each solve runs preconditioned CG).
    The condensed compliance ``A`` is built only for the semi-smooth Newton
    reference (:meth:`condense`).

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

    def __init__(self, problem, history, *, margin: float = 0.25):
        t0 = time.perf_counter()
        self.problem, self.history = problem, history
        model = self.model = problem.model
        self.dim = d = model.dim
        self.fixed, parts = component_fields(problem, history)
        self.loads = np.stack([load for _, load in parts])
        self.fv_parts = np.stack([fv for fv, _ in parts])  # (ncomp, nfixed)
        pts, dofs = model.node_dofs(problem.contact_boundary)
        self.points, self.dofs = pts, dofs
        self.weights = model.boundary_weights(problem.contact_boundary)
        self.gap0, self.normals = problem.obstacle.evaluate(pts)
        self.h = _element_size(model, problem.contact_boundary, problem.obstacle)
        self.kappa = np.zeros(pts.shape[0])
        self.spring = None
        self.condensed = False
        self.linear_solves = self.cg_iterations = self.amg_setups = 0
        self.amg_seconds = 0.0
        self._K = model.stiffness()
        mask = np.ones(model.ndofs, dtype=bool)
        mask[self.fixed] = False
        self.free = np.flatnonzero(mask)
        rows = self._K[self.free]
        self.K = rows[:, self.free].tocsr()
        del rows
        pts_all, dofs_all = model.all_node_dofs()
        modes, _ = rigid_body_modes(pts_all)
        R = np.zeros((model.ndofs, modes.shape[-1]))
        R[dofs_all.ravel()] = modes.reshape(-1, modes.shape[-1])
        self.R = np.ascontiguousarray(R[self.free])
        self.K_abs = abs(self.K).tocsr()  # round-off bound of the residual
        self.S = self.Z = self.ZSZ = None
        try:
            model.check_restrained(self.fixed)
            Kt = self._K
        except InputError as exc:
            Kt = self._stabilize_springs(exc)
        t_f = time.perf_counter()
        self.factor = model.factorize(self.fixed, matrix=Kt, check=False, backend="amg", reuse=False)
        self.factor_seconds = time.perf_counter() - t_f
        self.ml_K = self.factor.factor.ml
        self.amg_setups += 1
        self.amg_seconds += self.factor_seconds
        self.b_parts = np.stack([self.factor.rhs(load, fv) for fv, load in parts])  # (ncomp, nfree)
        self.u_parts = np.stack([self.factor.solve_full(load, fv) for fv, load in parts])
        self.linear_solves += len(parts)
        if not np.all(np.isfinite(self.u_parts)):
            raise InputError("the contact-free solution is not finite; check loads and supports.")

        free_pos = -np.ones(model.ndofs, dtype=np.int64)
        free_pos[self.free] = np.arange(self.free.size)
        self.pos = free_pos[dofs]
        held = self.pos < 0
        self.tangents = tangent_bases(self.normals, held)
        self.E = np.concatenate([self.normals[:, :, None], -self.tangents], axis=2)
        free_part = np.linalg.norm(np.where(held[:, :, None], 0.0, self.E), axis=1)
        self.movable = free_part[:, 0] > 1e-12
        self.tfree = free_part[:, 1:] > 1e-12
        self.y_parts = np.stack([self._local(u) for u in self.u_parts])
        # y = y_fix(t) + Bl x: rows -E_i^T on the free DOFs of point i
        m = pts.shape[0]
        coef = -np.transpose(self.E, (0, 2, 1))  # (m, d local, d global)
        r = np.broadcast_to((np.arange(m)[:, None] * d + np.arange(d))[:, :, None], (m, d, d))
        c = np.broadcast_to(self.pos[:, None, :], (m, d, d))
        keep = (c >= 0) & (np.abs(coef) > 0)
        self.Bl = sp.csr_matrix((coef[keep], (r[keep], c[keep])), shape=(m * d, self.free.size))
        self.yfix_parts = np.stack([self._local(self.factor.expand(np.zeros(self.free.size), fv))
                                    for fv in self.fv_parts])

        gmax_t = np.max(np.stack([self.y_free(t)[:, 0] for t in history.times]), axis=0)
        bad = ~self.movable & (gmax_t > 1e-12 * self.h)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise InputError(
                f"contact point {pts[i].tolist()} is held by a Dirichlet condition in the normal direction but "
                f"penetrates the obstacle by {gmax_t[i]:.3e} at some load step; move the obstacle or release that "
                "support.")
        self.max_free_penetration = float(np.max(np.where(self.movable, gmax_t, -np.inf), initial=-np.inf))
        self.gmax_t = gmax_t
        gmax = self.max_free_penetration
        if gmax > 0:
            thr = -max(margin * gmax, 1e-12 * self.h)
            cand = np.flatnonzero(self.movable & (gmax_t > thr))
        else:
            cand = np.empty(0, dtype=np.int64)
        if self.spring is not None:
            cand = np.union1d(cand, self.spring)
        self.cand = np.empty(0, dtype=np.int64)
        self.C = np.zeros((0, 0))
        self.A = np.zeros((0, 0))
        self.add(cand)
        self.precond = _AmortizedPreconditioner(self)
        self.setup_seconds = time.perf_counter() - t0

    # ------------------------------------------------------------------ body held by the obstacle
    def _stabilize_springs(self, exc: InputError):
        r"""Springs :math:`\kappa w_i` on all free components of the touching points; returns :math:`\tilde K`.

        The points and :math:`\kappa = E'/h` are those of
        :meth:`FrictionalContact._stabilize`. Instead of a factorization, the check
        is on the rigid motions :math:`r` left free by the supports: the springs must
        stop all of them (:math:`r^T S r > 0` on that space, relative to the largest
        spring energy of a unit motion).

        Raises
        ------
        InputError
            When no contact point touches the obstacle, or the touching points do
            not restrain the free motions either.
        """
        model = self.model
        free = np.ones(model.ndofs, dtype=bool)
        free[self.fixed] = False
        movable = np.linalg.norm(np.where(free[self.dofs], self.normals, 0.0), axis=1) > 1e-12
        g0 = np.where(movable, self.gap0, -np.inf)
        gmax = float(g0.max(initial=-np.inf))
        if not np.any(movable) or gmax < -0.5 * self.h:
            raise InputError(
                f"{exc} The body does not touch the obstacle either (closest gap {-gmax:.3g}), so nothing "
                "restrains it: add supports or move the obstacle into contact.") from None
        near = np.flatnonzero(movable & (g0 >= gmax - 0.5 * self.h))
        mat = model.material
        kappa = (mat.E if (model.dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus) / self.h
        dofs = self.dofs[near].ravel()
        keep = free[dofs]
        diag = np.zeros(model.ndofs)
        np.add.at(diag, dofs[keep], np.repeat(kappa * self.weights[near], model.dim)[keep])
        Z = free_rigid_motions(model, self.fixed, self.free)
        S = sp.diags(diag[self.free]).tocsr()
        G = springs_hold(Z, S)
        if G is None:
            raise InputError(
                f"{exc} The contact points touching the obstacle do not restrain that motion either: add supports "
                "(e.g. fix a tangential component) so that every rigid motion is stopped.") from None
        self.spring = near.astype(np.int64)
        self.kappa[near] = kappa
        self.S, self.Z, self.ZSZ = S, Z, G
        logger.info("body held by the obstacle only: springs (normal and tangential) on %d contact points "
                    "(AMG path)", near.size)
        return (self._K + sp.diags(diag)).tocsr()

    # ------------------------------------------------------------------ candidates
    def add(self, new: np.ndarray) -> np.ndarray:
        """Add candidate points; the condensed compliance only after :meth:`condense`."""
        if self.condensed:
            return super().add(new)
        new = np.setdiff1d(np.asarray(new, dtype=np.int64), self.cand)
        new = new[self.movable[new]]
        self.cand = np.concatenate([self.cand, new])
        return new

    def condense(self) -> None:
        """Build the compliance ``A`` of the candidates (one AMG-CG solve per candidate DOF)."""
        if self.condensed:
            return
        cand, self.cand = self.cand, np.empty(0, dtype=np.int64)
        self.condensed = True
        solves = self.factor.factor.solves
        super().add(cand)
        logger.info("semi-smooth Newton reference on the AMG path: compliance of %d candidate points by %d CG "
                    "solves", cand.size, self.factor.factor.solves - solves)

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
        it = [0]

        def count(_):
            it[0] += 1

        if symmetric:
            x, info = cg(J, rhs, rtol=rtol, atol=0.0, M=M, maxiter=5000, callback=count)
        else:
            x, info = gmres(J, rhs, rtol=rtol, atol=0.0, M=M, restart=_GMRES_RESTART, maxiter=_GMRES_MAXITER,
                            callback=count, callback_type="pr_norm")
        self.linear_solves += 1
        self.cg_iterations += it[0]
        if info != 0:
            logger.warning("%s stopped after %d iterations without reaching rtol %.1e", "CG" if symmetric else
                           "GMRES", it[0], rtol)
        return x, it[0]

    def stats(self) -> dict:
        """Solver counters for the solution's ``extra``."""
        f = self.factor.factor
        return {"linear_solver": "amg", "cg_iterations": int(self.cg_iterations + f.iterations),
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

    @property
    def c(self):
        return self.yfix.shape[0]

    @property
    def d(self):
        return self.yfix.shape[1]

    def y(self, x):
        return self.yfix + (self.Bc @ x).reshape(self.yfix.shape)


def friction_newton(ctx: _FullCtx, law, lamN, lamT, x0, *, tol: float, maxiter: int) -> _NewtonOut:
    r"""Solve the subproblem :math:`F(x) = 0` (module doc) by inexact globalized Newton with AMG-Krylov.

    Same structure as :func:`~alcontact.contact._iterative.full_newton`: relative
    residual :math:`\max|F| / \max(|b|, |w t|)`, tolerance ``max(tol, 1e-11)`` or
    the round-off bound of the residual, forcing terms, preconditioner rebuilds and
    backtracking (on :math:`\Pi` for ``radius="multiplier"``, else on :math:`|F|`).
    ``aux`` of the outcome is ``(y, t, Dy, state)`` at the final iterate.
    """
    fc, c, d, w = ctx.fc, ctx.c, ctx.d, ctx.w
    tol = max(tol, _NEWTON_TOL_FLOOR)
    rho = ctx.mu * np.maximum(lamN, 0.0) if ctx.opts.radius == "multiplier" else None
    K, b, Bc = fc.K, ctx.b, ctx.Bc
    BcT = Bc.T.tocsr()
    Kabs = fc.K_abs
    Babs = abs(Bc).tocsr()
    wd = np.repeat(w, d)

    def state(x_):
        y_ = ctx.y(x_)
        t_, Dy_, _, st_ = local_law(law, lamN, lamT, y_, ctx.uTn, ctx.eps_t, ctx.mu, rho=rho, tfree=ctx.tfree)
        Kx_ = K @ x_
        F_ = Kx_ - b + BcT @ (w[:, None] * t_).ravel()
        return F_, (y_, t_, Dy_, st_), Kx_

    def merit(x_, aux_, Kx_):
        if rho is None:  # no potential: the line search works on the residual norm
            return None
        y_ = aux_[0]
        e = law.energy(y_[:, 0], lamN) + tangential_energy(lamT, y_[:, 1:], ctx.uTn, ctx.eps_t, rho, ctx.tfree)
        return 0.5 * float(x_ @ Kx_) - float(b @ x_) + float(np.sum(w * e))

    x = np.array(x0, dtype=float)
    F, aux, Kx = state(x)
    if not np.all(np.isfinite(F)):
        return _NewtonOut(x, aux, 0, False, np.inf, "non-finite residual at the start")
    pi = merit(x, aux, Kx)
    if rho is not None and not np.isfinite(pi):
        return _NewtonOut(x, aux, 0, False, np.inf, "start outside the penalty domain")
    bscale = float(np.max(np.abs(b), initial=0.0))
    scale = max(float(np.max(np.abs(w[:, None] * aux[1]), initial=0.0)), bscale)
    prev_res = np.inf
    forcing = _FORCING_START
    alpha = 1.0
    res = np.inf
    for it in range(1, maxiter + 2):
        y, t, Dy, _ = aux
        fscale = max(scale, float(np.max(np.abs(w[:, None] * t), initial=0.0)), 1e-300)
        res = float(np.max(np.abs(F), initial=0.0)) / fscale
        # round-off bound of F: 10 u (|K||x| + |b| + |B|^T w (|t| + |Dy| (|y_fix| + |B||x|)))
        yerr = (np.abs(ctx.yfix) + (Babs @ np.abs(x)).reshape(c, d))
        terr = np.abs(t) + np.einsum("cij,cj->ci", np.abs(Dy), yerr)
        floor = 10.0 * np.finfo(float).eps * float(np.max(Kabs @ np.abs(x) + np.abs(b)
                                                          + Babs.T @ (w[:, None] * terr).ravel(), initial=0.0))
        tol_k = max(tol, floor / fscale)
        if res <= tol_k:
            return _NewtonOut(x, aux, it - 1, True, res, "converged")
        if res <= 1e-8 and res > 0.5 * prev_res:
            return _NewtonOut(x, aux, it - 1, True, res, "converged (residual at round-off level)")
        if it > maxiter:
            break
        if it > 1 and (alpha < 1.0 or res > 0.5 * prev_res):
            forcing = max(_FORCING_SLOW * forcing, _FORCING_MIN)
        prev_res = res
        WD = w[:, None, None] * Dy
        J = (K + BcT @ _block_matrix(WD) @ Bc).tocsr()
        asym = float(np.max(np.abs(WD - np.transpose(WD, (0, 2, 1))), initial=0.0))
        symmetric = asym <= _SYM_TOL * max(float(np.max(np.abs(WD), initial=0.0)), 1e-300)
        P = J if symmetric else (K + BcT @ _block_matrix(_psd_part(WD)) @ Bc).tocsr()
        if fc.S is not None:  # (the preconditioner adds the springs S to P)
            J = _held_rigid_motions(fc, J, Bc, WD)
        rtol = float(np.clip(max(min(forcing, res), 0.1 * tol_k / res), 1e-14, _FORCING_MAX))
        M = fc.precond.get(P, float(np.max(np.abs(WD), initial=0.0)))
        t_k = time.perf_counter()
        dx, nit = fc.krylov(J, -F, M, rtol=rtol, symmetric=symmetric)
        fc.precond.record(nit, rtol, time.perf_counter() - t_k)
        if not np.all(np.isfinite(dx)):
            return _NewtonOut(x, aux, it, False, res, "non-finite Newton step")
        if float(np.max(np.abs(dx), initial=0.0)) <= 1e-14 * max(float(np.max(np.abs(x), initial=0.0)), 1e-300):
            return _NewtonOut(x, aux, it, res <= 1e3 * tol, res, "step at round-off level")
        nF = _norm(F)
        slope = float(F @ dx)  # the gradient of Pi is F
        alpha, accepted = 1.0, False
        for _ in range(60):
            x_try = x + alpha * dx
            F_try, aux_try, Kx_try = state(x_try)
            if rho is not None:
                pi_try = merit(x_try, aux_try, Kx_try)
                ok = np.isfinite(pi_try) and pi_try <= pi + 1e-4 * alpha * min(slope, 0.0) + 1e-14 * abs(pi)
            else:
                pi_try = None
                ok = bool(np.all(np.isfinite(F_try))) and _norm(F_try) <= (1.0 - 1e-4 * alpha) * nF
            if ok:
                accepted = True
                break
            alpha *= 0.5
        if not accepted:  # potential flat to round-off: take the full step if it reduces the residual
            x_try = x + dx
            F_try, aux_try, Kx_try = state(x_try)
            if not (np.all(np.isfinite(F_try)) and np.max(np.abs(F_try)) < np.max(np.abs(F))):
                return _NewtonOut(x, aux, it, False, res, "line search failed")
            pi_try = merit(x_try, aux_try, Kx_try) if rho is not None else None
            alpha = 0.5
        logger.debug("friction Newton (AMG) %d: residual %.2e, %s rtol %.1e, %d iterations, step %.3g", it, res,
                     "CG" if symmetric else "GMRES", rtol, nit, alpha)
        x, F, aux, Kx, pi = x_try, F_try, aux_try, Kx_try, pi_try
    return _NewtonOut(x, aux, maxiter, False, res, "maximum Newton iterations")


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


def _inside_domain(ctx: _FullCtx, law, lamN, x):
    """Start for barrier-type penalties: scale the contact part ``x - x_free`` up until every gap is inside."""
    bound = law.gap_bound(lamN)
    s = 0.5
    while np.any(ctx.y(x)[:, 0] >= 0.99 * bound) and s < 1e6:
        trial = ctx.x_free + (1.0 + s) * (x - ctx.x_free)
        if not np.any(ctx.y(trial)[:, 0] >= 0.99 * bound):
            return trial
        s *= 2
    return x


def _step_al(ctx: _FullCtx, penalty_name: str):
    """Algorithms 6.2 / 6.4 for one load step in the full space (first-order multiplier updates).

    Line by line :func:`alcontact.contact._friction._step_al` with the displacement as
    state. Returns ``(_StepOut, x)``.
    """
    opts = ctx.opts
    lamN, lamT = ctx.lamN.copy(), ctx.lamT.copy()
    x = ctx.x0.copy()
    newton = 0
    macaulay = make_law(_pen.make("rockafellar"), np.full(ctx.c, 1.0 / ctx.eps_n))
    pen = _pen.make(penalty_name)
    family_p = freezes_at_zero(pen)
    nt = dict(tol=opts.newton_tol, maxiter=opts.maxiter_newton)
    if family_p:  # predictor: one Simo-Laursen subproblem gives multipliers for points entering contact
        out = friction_newton(ctx, macaulay, lamN, lamT, x, **nt)
        newton += out.iterations
        if out.converged:
            x = out.x
            lamN = out.aux[1][:, 0].copy()
        pref = max(float(np.max(lamN, initial=0.0)), ctx.eps_n * ctx.fc.h * 1e-6)
        lamN = np.maximum(lamN, opts.multiplier_floor * pref)
        eta = eta_for_stiffness(pen, np.maximum(lamN, opts.eta_floor * pref), ctx.eps_n)
        law = make_law(pen, eta)
        x = _inside_domain(ctx, law, lamN, x)
    else:
        law = macaulay
    t = np.zeros((ctx.c, ctx.d))
    for k in range(1, opts.maxiter + 1):
        out = friction_newton(ctx, law, lamN, lamT, x, **nt)
        newton += out.iterations
        if not out.converged:
            return _StepOut(False, f"Newton failed in outer iteration {k}: {out.reason}", out.aux[1], out.aux[1],
                            k, newton, ContactStatus.NEWTON_FAILED), x
        x = out.x
        y, t, _, st = out.aux
        if not np.all(np.isfinite(t)):
            return _StepOut(False, f"non-finite tractions in outer iteration {k}", t, t, k, newton,
                            ContactStatus.NONFINITE), x
        pen_k, compl, dlam, stick_slip = _measures(ctx, t, y, st, lamN, lamT)
        logger.debug("friction AL (AMG) outer %d: pen=%.2e compl=%.2e dlam=%.2e stick-slip=%.2e newton=%d",
                     k, pen_k, compl, dlam, stick_slip, out.iterations)
        if (pen_k <= opts.tol_penetration and compl <= opts.tol_complementarity and dlam <= opts.tol_multiplier
                and stick_slip <= opts.tol_slip):
            return _StepOut(True, "converged", ctx.w[:, None] * t, t, k, newton), x
        # multiplier updates (6.2b)/(6.2c), resp. lambda_N <- p'(g/eta, lambda_N)
        lamN, lamT = t[:, 0].copy(), t[:, 1:].copy()
        if family_p:
            pref = max(float(np.max(lamN, initial=0.0)), 1e-300)
            lamN = np.maximum(lamN, opts.multiplier_floor * pref)
            if opts.eta_scaling == "adaptive":
                eta_new = eta_for_stiffness(pen, np.maximum(lamN, opts.eta_floor * pref), ctx.eps_n)
                bnd = eta_new * np.asarray(pen.domain_upper(lamN), dtype=float)
                eta = np.where(y[:, 0] < 0.99 * bnd, eta_new, eta)
                law = make_law(pen, eta)
    return _StepOut(False, f"maximum outer iterations ({opts.maxiter}) reached", ctx.w[:, None] * t, t,
                    opts.maxiter, newton, ContactStatus.MAXITER), x


def _advance_full(fc: IterativeFrictionalContact, prev, t: float, step_fn, pen_name, eps_n, eps_t, mu, opts):
    """One step from ``prev`` to ``t`` in the full space; the contract of :func:`_friction._advance`.

    Every step starts from the previous converged displacement (all closed points
    sticking, as :meth:`FrictionalContact.frozen_start` on the direct path).
    """
    outer = newton = 0
    d = fc.dim
    x_prev = prev.u[fc.free]
    for _attempt in range(8):
        cand = fc.cand
        c = cand.size
        if c == 0:
            x = fc.u_free(t)[fc.free]
            out = _StepOut(True, "no candidate points", np.zeros((0, d)), np.zeros((0, d)), 0, 0)
        else:
            ctx = _FullCtx(fc, fc.rows(cand), fc.y_fix(t)[cand], fc.load(t), fc.weights[cand],
                           prev.tN[cand].copy(), prev.tT[cand].copy(), prev.y[cand, 1:].copy(), x_prev,
                           fc.u_free(t)[fc.free], eps_n, eps_t, mu, opts, fc.tfree[cand])
            out, x = _step_al(ctx, pen_name)
            outer += out.outer
            newton += out.newton
            if not out.ok:
                return None, out, outer, newton
        u = fc.expand_at(t, x)
        y_all = fc.all_local(u)
        outside = np.ones(fc.points.shape[0], bool)
        outside[cand] = False
        add = fc.add(np.flatnonzero(outside & (y_all[:, 0] > opts.tol_penetration * fc.h)))
        if add.size:
            logger.info("t=%g: adding %d contact candidates that penetrate", t, add.size)
            x_prev = x
            continue
        m = fc.points.shape[0]
        tN = np.zeros(m)
        tT = np.zeros((m, d - 1))
        R = np.zeros((m, d))
        tN[cand], tT[cand], R[cand] = out.t[:, 0], out.t[:, 1:], out.R
        if fc.spring is not None:  # held by the obstacle: accept only a step in equilibrium
            defect = fc.equilibrium_defect(t, u, R)
            if not defect <= _EQUILIBRIUM_TOL:
                return None, _StepOut(False, f"no equilibrium found (relative residual {defect:.2e}): the obstacle "
                                             "and friction do not hold the body there", prev.R, prev.R, outer,
                                      newton, ContactStatus.NEWTON_FAILED), outer, newton
        return (u, y_all, tN, tT, R, None), out, outer, newton
    return None, _StepOut(False, "candidate set did not settle", prev.R, prev.R, 0, 0, ContactStatus.MAXITER), \
        outer, newton


def _advance_condensed(fc: IterativeFrictionalContact, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts):
    """The semi-smooth Newton reference: the direct path's step on the compliance built by AMG-CG solves."""
    fc.condense()
    return _advance(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts)


#: Step of each frictional step function on this path (default: the full-space AL step).
_STEP_PATHS = {_step_ssn: _advance_condensed}


def advance(fc: IterativeFrictionalContact, prev, t: float, step_fn, pen_name, eps_n, eps_t, mu, opts):
    """One load step on the AMG path (the contract of :func:`alcontact.contact._friction._advance`)."""
    return _STEP_PATHS.get(step_fn, _advance_full)(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu, opts)
