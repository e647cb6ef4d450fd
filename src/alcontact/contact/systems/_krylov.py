r"""Full-space contact systems at small deformation with AMG-preconditioned Krylov solves: frictionless and Coulomb.

For large 3D meshes the sparse factor of the stiffness does not fit in memory
(3D Hertz: 158M factor nonzeros at 110k DOFs, about 30 GB at 1.2M), so the
condensation of :mod:`alcontact.contact.systems._condensed` (one factorization, one
triangular solve per contact candidate) is out of reach. This module solves the
same discrete problem in the full space of the free DOFs :math:`x`:

.. math::

    \Pi(x) = \tfrac12 x^T K x - b^T x + \sum_i w_i\,\psi_i(g_i(x)), \qquad
    g(x) = g^{fix} + B x ,

with :math:`b = f_f - K_{fd} u_d`, ``B`` the rows :math:`-\nu_i^T` of the contact
points on the free DOFs and :math:`g^{fix}` the gaps of :math:`x = 0` (the
prescribed displacements only). Each subproblem (S) of Algorithms 6.1 / 6.3
(same laws :math:`t_N = p'(g/\eta, \lambda)` and scales :math:`\eta` as
:mod:`alcontact.contact.laws._normal`) is solved by Newton's method on

.. math::

    R(x) = K x - b + B^T (w \circ t_N(g(x))) = 0, \qquad
    J = K + B^T \operatorname{diag}(w \circ dt_N/dg)\, B ,

globalized by backtracking on :math:`\Pi` (the full-space form of the energy of
:mod:`alcontact.contact.algorithms._subproblem`; on the equilibrium manifold both Newton steps
coincide). Every Newton system is solved by the conjugate gradient method,
preconditioned by a PyAMG smoothed-aggregation hierarchy with the rigid-body
modes as near-null space; inexact Newton with forcing term
:math:`\min(\eta_k, \rho_k)` (:math:`\rho_k` the relative residual), tightened in the
last step to reach the Newton tolerance, which is ``max(newton_tol, 1e-11)`` here
(CG solves and round-off in :math:`Kx` do not reach the direct path's 1e-12 reliably),
or the round-off bound of the residual where that is larger (:func:`_residual_floor`:
the pure penalty at large :math:`\varepsilon_N`). :math:`\eta_k` starts at 1e-3 and
drops tenfold (to 1e-6) after a damped step or a residual decrease below a factor 2:
after a multiplier or penalty update the residual sits on the stiff contact
directions, and a loose first CG step (1 iteration at forcing 0.1) moved contact
points across the kink, after which the backtracking took steps of 1e-2 to 1e-5 for
several Newton iterations (measured on the 3D P2 Hertz case at 22k DOFs, pure penalty).
``B^T W D B`` is block diagonal (one ``d x d`` block per contact point), but its
entries are about ``penalty_scale`` times those of ``K``: with the hierarchy of
:math:`K` alone CG needed about 3 times more iterations (measured on the 3D Hertz
problem at 110k DOFs: 614 against 193 for Algorithm 6.1), and a fresh hierarchy for
every :math:`J` costs about one linear solve each (the setup is 50-85 % of the
reference solve). So every :math:`J` gets the hierarchy of :func:`~alcontact.linalg._amg.updated_hierarchy`:
the prolongators of the hierarchy of :math:`K`, built once, with the Galerkin coarse
operators of :math:`J` (the contact term only touches the coarse DOFs next to the
contact zone); it preconditions as well as a fresh setup (tests/unit/test_fem_assembly.py).
Springs that dominate the stiffness of their node (the default penalty on the 3D P2 Hertz
mesh already; the pure penalty raises it 1e5-fold) are moved onto one coordinate each by
Householder reflections at their nodes (:func:`~alcontact.linalg._amg.reflected_hierarchy`), where they no longer
couple the DOFs that the pointwise Gauss-Seidel smoother relaxes one by one: with the plain
update the CG iterations per Newton step grew with the penalty (3D P2
Hertz, 9k DOFs, pure penalty: 968 CG iterations, 117-201 per Newton step at the last three
penalties; with the reflections 210, at most 25 per step).
Forcing terms 1e-2 and 1e-3 cost more CG iterations in total (235, 246) than 0.1.
Since the Newton systems are solved inexactly, a subproblem takes more Newton
iterations than the exact condensed Newton (which ends in one step once the active
set is right); the CG iterations are the measure of work here.

The reference linear solve (``timings["linear_solve_s"]``) is the AMG setup for
:math:`K` plus one CG solve to 1e-10 of the contact-free problem, or, when that has
no load (displacements driven by the obstacle), of a unit pressure on the contact
boundary.

The outer loops mirror :func:`~alcontact.contact.algorithms._frictionless.run_penalty`,
:func:`~alcontact.contact.algorithms._frictionless.run_al` and
:func:`~alcontact.contact.algorithms._frictionless.run_ssn` line by line, with the displacement
instead of the condensed contact forces as state, and the same candidate set,
stopping measures and history. The semi-smooth Newton reference enforces
:math:`g_A = 0` on each active set by an inner augmented Lagrangian (Uzawa)
iteration with penalty :math:`c = \varepsilon_N`, whose error contracts by about
:math:`1/(1 + c\,\lambda_{min}(W S_{AA})) \approx 1/100` per CG solve.

Counters: ``linear_solves`` counts CG solves, ``cg_iterations`` their iterations,
``amg_setups`` the hierarchies built from scratch, ``amg_updates`` the Galerkin
updates of :func:`~alcontact.linalg._amg.updated_hierarchy`.

Memory: ``K`` on the free DOFs is extracted in one pass (:func:`~alcontact.linalg.krylov.principal_submatrix`)
and the model's stiffness is dropped again if the setup assembled it; every :math:`J`
shares the index arrays of ``K`` (:func:`~alcontact.linalg.krylov.add_on_pattern`); the round-off bound of the residual
reads :math:`|K|` in row chunks.

Coulomb friction without a factorization: full-space Newton with AMG-preconditioned Krylov solves.

The frictional problem of :mod:`alcontact.contact.systems._condensed` (small
deformation (6.15)-(6.22), same points, tangent bases, held tangent directions,
candidates and load history) solved in the space of the free DOFs :math:`x`
instead of being condensed on the contact points, for meshes whose factor does
not fit in memory (the same reason as the frictionless
:mod:`alcontact.contact.systems._krylov`). With the local kinematics of the candidate
points :math:`y = (g, u_T) = y^{fix}(t) + B x` (rows :math:`-\nu_i^T` and
:math:`T_i^T` on the free DOFs; :math:`y^{fix}` the reference gaps and the
prescribed displacements) and the load :math:`b(t) = f_f - K_{fd} u_d` on the free
DOFs, each AL subproblem (6.2a) of Algorithms 6.2 / 6.4 is

.. math::

    F(x) = K x - b(t) + B^T (w \circ t(y(x))) = 0, \qquad
    J = K + B^T \operatorname{diag}(w_i\, \partial t_i/\partial y_i)\, B ,

with :math:`t = (t_N, t_T)` the normal law and the return mapping (6.47)-(6.50)
of :func:`~alcontact.contact.laws._coulomb.local_law` at the multipliers
:math:`(\lambda_N, \lambda_T)` (the same function as the condensed path). It is
:math:`K u = f + P^T E R` of the condensed path written in :math:`x` (the force on
the body is :math:`E_i R_i = -B_i^T R_i`), so both paths solve the same discrete
problem. The outer iterations, the multiplier updates (6.2b)/(6.2c) (family-P:
:math:`\lambda_N \leftarrow p'(g/\eta, \lambda_N)`) and the stopping test
(:func:`~alcontact.contact.algorithms._coulomb._measures`) are the one AL loop
:func:`~alcontact.contact.algorithms._coulomb._step_al`, here on the system :class:`_FullCtx`
(unknowns :math:`x`); the load step (:class:`~alcontact.contact.stepping._coulomb._StepPath`:
candidates, equilibrium of a held body), step control, cut-backs and statuses are
those of :mod:`alcontact.contact.algorithms._coulomb` too.

Each subproblem is solved by the one Newton driver of the contact algorithms
(:func:`~alcontact.contact.algorithms._subproblem.newton`, system :class:`_FullSpaceFriction`), as the
frictionless :func:`~alcontact.contact.systems._krylov.full_newton`: inexact steps with the
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

from ... import linalg as _linalg
from ...errors import InputError
from ...fem.elasticity import rigid_body_modes
from ...linalg import MatrixHints, krylov
from ...linalg.krylov import principal_submatrix
from ..algorithms._subproblem import (LineSearch, NewtonOutcome, NewtonResult, NewtonSettings, NewtonSystem,
                                      _Point, _PointSystem, newton, subproblem_outcome)
from ..kinematics._points import ContactPoints
from ..laws._coulomb import local_law, tangential_energy
from ._condensed import FrictionalContact


logger = logging.getLogger(__name__)

#: ``linear_solver="auto"`` switches to AMG for 3D problems above this many DOFs; the rule
#: lives in :func:`alcontact.linalg.choose_solver`
AUTO_AMG_DOFS = _linalg.AUTO_AMG_DOFS
#: relative CG tolerance of the reference linear elastic solve (and of the free solution)
_REF_RTOL = 1e-10
#: largest forcing term of the inexact Newton steps (CG relative tolerance)
_FORCING_MAX = 0.1
#: forcing factor after a damped step or a slow residual decrease, and the smallest forcing term
_FORCING_SLOW = 0.1
_FORCING_START = 1e-3
_FORCING_MIN = 1e-6
#: CG iterations per digit above ``_REBUILD_FACTOR * rate_after_build + 1`` trigger an AMG rebuild
_REBUILD_FACTOR = 1.5
#: relative multiplier update ending the inner Uzawa iteration of the semi-smooth Newton reference
_UZAWA_TOL = 1e-8
#: CG tolerance of an Uzawa step relative to the right-hand side change of the last multiplier update
_UZAWA_FORCING = 1e-3
#: relative multiplier update at which the inner Uzawa iteration may stop when the active set
#: is about to change (the step only decides the next active set; the last one is solved to
#: :data:`_UZAWA_TOL`)
_UZAWA_LOOSE = 1e-2
#: Uzawa updates of one active-set solve of the semi-smooth Newton reference (its budget)
_UZAWA_MAXITER = 60
#: Newton tolerance cannot go below what inexact CG solves and round-off in K x reach
_NEWTON_TOL_FLOOR = 1e-11
#: a hierarchy is rebuilt when the largest contact stiffness grew by more than this factor
_REBUILD_STIFFNESS = 5.0
#: above this many free DOFs the subproblems of Algorithms 6.1 / 6.3 are solved inexactly
#: (:attr:`IterativeContact.inexact_subproblems`): where ``linear_solver="auto"`` picks this path
INEXACT_DOFS = AUTO_AMG_DOFS
#: Newton tolerance of the first inexact subproblem of a solve on the factorization-free paths (serial and
#: distributed), not finite deformation's 1e-2, which left the first multiplier update (and the dual step on
#: it) too far off: 2D P1 Hertz 984k DOFs, Algorithm 6.1 took 8 outer iterations against the direct path's 5
#: (6 with this value); with the inexact mode forced on 2D 120k, 1e-2 -> 1e-4: Algorithm 6.1 8 -> 6 outer,
#: 456 -> 392 CG iterations, 15.1 -> 9.4 s CPU; exp-met1, log-met2, quad-met2 6 -> 5 (CG within 3 %); 2D 59k
#: 6.1 7 -> 6, exp-met1 7 -> 5; 3D P1 39k 6.1 6 / 6 (254 -> 201 CG), log-met2 and quad-met2 6 -> 5
#: (docs/benchmarks/amg_paths.md)
INEXACT_FIRST_TOL = 1e-4


#: a contact point whose spring :math:`k_i` exceeds this many times the normal stiffness of its
#: node in ``K`` gets its own coordinate (:func:`~alcontact.linalg._amg.reflected_hierarchy`)
_STIFF_RATIO = 10.0


def _stiff_points(K, Bc, k) -> np.ndarray:
    r"""Mask of the contact points whose spring dominates the stiffness of their node.

    The spring :math:`k_i (B_i x)^2` has stiffness :math:`k_i |B_i|^2` along the unit normal;
    the node's own normal stiffness is :math:`B_i K B_i^T / |B_i|^2`. Points with a ratio above
    :data:`_STIFF_RATIO` are stiff. Only rows with disjoint supports (one point per node, as
    :class:`~alcontact.contact.kinematics._points.ContactPoints` builds ``B``) are eligible; otherwise
    no point is.
    """
    Bc = sp.csr_matrix(Bc)
    if Bc.shape[0] == 0 or np.unique(Bc.indices).size != Bc.nnz:  # rows share a DOF
        return np.zeros(Bc.shape[0], dtype=bool)
    n2 = np.asarray(Bc.multiply(Bc).sum(axis=1)).ravel()
    kn = np.asarray((Bc @ K).multiply(Bc).sum(axis=1)).ravel()
    ok = (n2 > 0) & (kn > 0)
    ratio = np.zeros_like(n2)
    ratio[ok] = k[ok] * n2[ok] ** 2 / kn[ok]
    return ratio > _STIFF_RATIO


class _Preconditioner:
    """AMG preconditioner of the Newton matrices ``J = K + B_c^T diag(k) B_c``.

    With the contact term ``delta`` (as :func:`full_newton` passes it, through
    :meth:`solve`) each matrix gets the hierarchy of :func:`~alcontact.linalg._amg.updated_hierarchy`: the
    prolongators of the hierarchy of ``K`` (built once, in the setup) with Galerkin coarse
    operators of ``J``, counted in ``amg_updates``; with springs that dominate their node,
    the reflected one of :func:`~alcontact.linalg._amg.reflected_hierarchy`. A fresh setup per slow solve cost
    about one linear solve each and
    preconditioned no better (3D P1 Hertz, 38k DOFs: simo-laursen 295 CG iterations with
    6 fresh setups, 160 with updates only). Without ``delta`` (callers that do not know
    the contact term) a fresh factor of the solver (``solver.factorize``, counted in ``amg_setups``) is built
    when the scheme is stale: when a solve needs more than ``1.5 * rate_ref + 1`` CG
    iterations per decimal digit (``rate_ref``: the first solve after a build), or the
    largest contact stiffness grew by more than :data:`_REBUILD_STIFFNESS`.
    """

    def __init__(self, ic):
        self.ic = ic
        self.factor = ic.factor_K
        self.rate_ref = None
        self.stale = False
        self.k_built = 0.0

    def release(self) -> None:
        """Forget the hierarchy of the last matrix (frees it before the next one is built)."""
        self.factor = self.ic.factor_K

    def get(self, J, kmax: float = 0.0, delta=None):
        """Preconditioner for ``J``; ``kmax`` is its largest contact stiffness ``w_i dt_N/dg``.

        ``delta`` is ``J - K`` (the contact term): with it, the hierarchy of ``K`` is
        updated for ``J`` (:func:`~alcontact.linalg._amg.updated_hierarchy`).
        """
        if delta is not None:
            self.factor = self.ic.updated(J, delta)
            return krylov.preconditioner(self.factor)
        if self.k_built > 0 and kmax > _REBUILD_STIFFNESS * self.k_built:
            self.stale = True
        if self.stale:
            self.k_built = kmax
            self.factor = None
            t0 = time.perf_counter()
            S = getattr(self.ic, "S", None)  # contact springs of a body held by the obstacle
            self.factor = self.ic.solver.factorize(J if S is None else (J + S).tocsr(), self.ic.hints)
            self.ic.amg_setups += 1
            self.ic.amg_seconds += time.perf_counter() - t0
            self.rate_ref = None
            self.stale = False
        return krylov.preconditioner(self.factor)

    def solve(self, J, rhs, *, rtol: float, delta, Bc, k):
        r"""``J dx = rhs`` by CG (counted, recorded), :math:`J = K + B_c^T \operatorname{diag}(k) B_c`.

        Without stiff springs (:func:`_stiff_points`) the preconditioner is that of :meth:`get`.
        With them, CG runs in the reflected coordinates :math:`y = Q\,dx` on :math:`QJQ` with the
        hierarchy of :func:`~alcontact.linalg._amg.reflected_hierarchy` (same residual norms: :math:`Q` is orthogonal).
        ``J`` must be a fresh matrix (:meth:`IterativeContact.with_contact`): it is overwritten by
        :math:`QJQ`, so that no second copy of the matrix is held.
        """
        stiff = _stiff_points(self.ic.K, Bc, k)
        reflected = None
        if np.any(stiff) and J is not self.ic.K:
            t0 = time.perf_counter()
            reflected = krylov.reflected_factor(self.ic.factor_K, J, delta, sp.csr_matrix(Bc)[stiff], overwrite=True)
            if reflected is not None:  # a solver without the reflected update: the plain update below
                self.ic.amg_updates += 1
                self.ic.amg_seconds += time.perf_counter() - t0
        if reflected is not None:
            self.factor, E = reflected
            y, nit = self.ic.pcg(self.factor.A, rhs + E @ rhs, krylov.preconditioner(self.factor), rtol=rtol)
            dx = y + E @ y
        else:
            M = self.get(J, float(np.max(k, initial=0.0)), delta=delta)
            dx, nit = self.ic.pcg(J, rhs, M, rtol=rtol)
        self.record(nit, rtol)
        return dx, nit

    def record(self, iterations: int, rtol: float) -> None:
        digits = max(np.log10(1.0 / max(rtol, 1e-16)), 1.0)
        rate = iterations / digits
        if self.rate_ref is None:
            self.rate_ref = rate
        elif rate > _REBUILD_FACTOR * self.rate_ref + 1.0:
            self.stale = True


class IterativeContact(ContactPoints):
    """Frictionless contact problem in the full space of the free DOFs (no factorization).

    Same points, weights, normals, gaps, candidates and element size ``h`` as
    :class:`~alcontact.contact.systems._condensed.DiscreteContact`, without the Delassus
    operator.

    Attributes
    ----------
    K : scipy.sparse.csr_matrix
        Stiffness on the free DOFs.
    b : ndarray
        Load on the free DOFs, :math:`f_f - K_{fd} u_d`.
    B : scipy.sparse.csr_matrix (m, n_free)
        Rows :math:`-\\nu_i^T` of all contact-boundary points.
    g_fix : ndarray (m,)
        Gaps of ``x = 0``, so that ``g(x) = g_fix + B x``.
    x_free : ndarray
        Contact-free solution on the free DOFs.
    linear_solves, cg_iterations, amg_setups : int
        CG solves, their iterations, AMG hierarchies built (factors of the solver made from scratch).
    solver : alcontact.linalg.SolverChoice
        The approximate solver whose factors precondition CG (default: ``"amg"``).
    factor_K : alcontact.linalg.Factor
        Its factor of ``K`` (of ``K + S`` for a body held by the obstacle).
    reference_seconds : float
        AMG setup for ``K`` plus one CG solve of a linear elastic problem of this mesh.
    """

    #: how the linear systems are solved (``solution.extra["strategy"]``): Krylov iterations in the full space
    strategy = "krylov"

    def __init__(self, problem, *, margin: float = 0.25, solver: _linalg.SolverChoice | None = None):
        t0 = time.perf_counter()
        self._setup_problem(problem)
        model = self.model
        # the approximate solver whose factors precondition the Krylov solves (alcontact.linalg.select_solver)
        self.solver = _linalg.select_solver("amg", dim=model.dim, ndofs=model.ndofs) if solver is None else solver
        self.hints = MatrixHints(dim=model.dim, near_null=lambda: self.R)
        n = model.ndofs
        mask = np.ones(n, dtype=bool)
        mask[self.fixed] = False
        self.free = np.flatnonzero(mask)
        self.S = None  # contact springs of a body held by the obstacle (_stabilize)
        try:
            model.check_restrained(self.fixed, contact=problem.contact_boundary)
        except InputError as exc:
            self._setup_points(problem, self.free)
            self._stabilize(exc)
        # a stiffness assembled here is dropped from the model again once K_ff is extracted
        # (memory: the model's cache is left as it was found)
        assembled_here = getattr(model, "_stiffness", True) is None
        t_asm = time.perf_counter()
        Kfull = model.stiffness()
        self.assembly_seconds = time.perf_counter() - t_asm if assembled_here else 0.0
        ud = np.zeros(n)
        ud[self.fixed] = self.fixed_values
        self.b = (self.load - Kfull @ ud)[self.free]
        # force scale of the Newton residuals (_FullSpaceSubproblem.measure): the applied loads, not
        # the coupling -K_fd u_d of the prescribed values, which a platen makes large
        self.load_scale = float(np.max(np.abs(self.load[self.free]), initial=0.0))
        del ud
        self.K = principal_submatrix(Kfull, mask)
        del Kfull
        if assembled_here:
            model.clear_stiffness()
        R = _rigid_modes(model)
        self.R = np.ascontiguousarray(R[self.free])
        del R
        self.linear_solves = 0
        self.cg_iterations = 0
        self.amg_setups = 0
        self.amg_updates = 0
        self.amg_seconds = 0.0
        self.precond = None

        self._setup_points(problem, self.free)
        w = self.weights
        self.g_fix = self.all_gaps(self.expand(np.zeros(self.free.size)))
        _release_geometry(model)

        # AMG of K and the reference linear solve: the free solution when there is a
        # load, else (displacement driven by the obstacle) a unit pressure on the contact boundary
        t_ref, c_ref = time.perf_counter(), time.process_time()
        Kt = self.K if self.S is None else (self.K + self.S).tocsr()
        self.factor_K = self.solver.factorize(Kt, self.hints)
        self.amg_setups += 1
        self.factor_seconds = time.perf_counter() - t_ref
        self.amg_seconds += self.factor_seconds
        has_load = float(np.linalg.norm(self.b)) > 0
        rhs = self.b if has_load else self.B.T @ w
        x_ref, self.reference_cg_iterations = self.pcg(Kt, rhs, krylov.preconditioner(self.factor_K), rtol=_REF_RTOL)
        self.reference_seconds = time.perf_counter() - t_ref
        self.reference_cpu_seconds = time.process_time() - c_ref  # the same, in CPU time (shared machines)
        self.solve_seconds = self.reference_seconds - self.factor_seconds
        self.x_free = x_ref if has_load else np.zeros(self.free.size)
        self.u_free = self.expand(self.x_free)
        if not np.all(np.isfinite(self.u_free)):
            raise InputError("the contact-free solution is not finite; check loads and supports.")
        # same gaps, element size and candidate rule as the direct path
        self._setup_candidates(self.u_free, margin)
        self.precond = _Preconditioner(self)
        self.setup_seconds = time.perf_counter() - t0

    def _stabilize(self, exc: InputError) -> None:
        r"""Springs :math:`S = \kappa B_s^T W_s B_s` on the touching points of a body held by the obstacle.

        The points (within half an element of the closest one) and :math:`\kappa = E'/h`
        are those of :meth:`DiscreteContact._stabilize <alcontact.contact.systems._condensed.DiscreteContact._stabilize>`.
        The residual keeps the physical :math:`K` (no shifted law is needed in the full
        space); :math:`K + S` gives the contact-free solution (the start and the
        candidates, as on the direct path) and :math:`S` is added to every AMG
        hierarchy (:class:`_Preconditioner`), which then never sees a singular matrix.

        Raises
        ------
        InputError
            When no point touches the obstacle, or the springs on the touching points
            do not stop the rigid motions that the supports leave free.
        """
        model = self.model
        h = self._element_size()
        g0 = np.where(self.movable, self.gap0, -np.inf)
        gmax = float(g0.max(initial=-np.inf))
        if not np.any(self.movable) or gmax < -0.5 * h:
            raise InputError(f"{exc} The body does not touch the obstacle either (closest gap {-gmax:.3g}), so "
                             "nothing restrains it: add supports or move the obstacle into contact.") from None
        near = np.flatnonzero(self.movable & (g0 >= gmax - 0.5 * h))
        mat = model.material
        kappa = (mat.E if (model.dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus) / h
        Bs = self.B[near]
        S = (Bs.T @ sp.diags(kappa * self.weights[near]) @ Bs).tocsr()
        if springs_hold(free_rigid_motions(model, self.fixed, self.free), S) is None:
            raise InputError(f"{exc} The contact points touching the obstacle do not restrain that motion either: "
                             "add supports (e.g. fix a tangential component) so that every rigid motion is "
                             "stopped.") from None
        self.S = S
        logger.info("body held by the obstacle only: springs on %d contact points (AMG path)", near.size)

    # ------------------------------------------------------------------
    def pcg(self, A, rhs, M, *, rtol: float, atol: float = 0.0, x0=None, maxiter: int = 5000):
        """Preconditioned CG for ``A x = rhs`` until ``|r| <= max(rtol |rhs|, atol)``; counted."""
        x, nit, info = krylov.cg(A, rhs, M, rtol=rtol, atol=atol, x0=x0, maxiter=maxiter)
        self.linear_solves += 1
        self.cg_iterations += nit
        if info != 0:
            logger.warning("CG stopped after %d iterations without reaching rtol %.1e", nit, rtol)
        return x, nit

    def updated(self, J, delta):
        r"""The solver's factor of :math:`J = K + \Delta` from that of ``K``
        (:func:`alcontact.linalg.krylov.updated_factor`:
        the AMG hierarchy of ``K`` with Galerkin coarse operators of ``J``, counted in ``amg_updates``; a
        solver without that update factorizes ``J``, counted in ``amg_setups``)."""
        t0 = time.perf_counter()
        factor, reused = krylov.updated_factor(self.solver, self.factor_K, J, delta, self.hints)
        if reused:
            self.amg_updates += 1
        else:
            self.amg_setups += 1
        self.amg_seconds += time.perf_counter() - t0
        return factor

    def contact_delta(self, Bc, k):
        """The contact term ``Bc^T diag(k) Bc`` (block diagonal, one block per contact point)."""
        return (Bc.T @ sp.diags(k) @ Bc).tocsr()

    def with_contact(self, delta):
        """``K + delta`` on the index arrays of ``K`` (the hierarchy of the last matrix is released first)."""
        if self.precond is not None:
            self.precond.release()
        return krylov.add_on_pattern(self.K, delta)

    # ------------------------------------------- interface of the outer loops
    # (see DiscreteContact; the state here is the free displacement x)
    factorizations = 0

    #: the first inexact subproblem's Newton tolerance (:data:`INEXACT_FIRST_TOL`)
    inexact_first_tol = INEXACT_FIRST_TOL

    @property
    def inexact_subproblems(self) -> bool:
        """Solve (S) of Algorithms 6.1 / 6.3 inexactly: above :data:`INEXACT_DOFS` free DOFs.

        :func:`~alcontact.contact.algorithms._frictionless.run_al` then sets the Newton tolerance of each
        subproblem from the last multiplier change and stops only after one solved to
        ``newton_tol``. Every CG iteration costs a V-cycle on the whole mesh, and early
        subproblems solved to 1e-11 are mostly wasted (3D P1 Hertz, 38k DOFs: simo-laursen
        160 -> 110 CG iterations, exp-met1 165 -> 117, contact force equal to 1e-12); the
        outer loop may take one iteration more than the direct path. Smaller problems are
        solved exactly and take the direct path's outer iterations.
        """
        return self.K.shape[0] > INEXACT_DOFS

    def start(self) -> np.ndarray:
        return self.x_free.copy()

    def gaps(self, x: np.ndarray) -> np.ndarray:
        return self.g_fix[self.cand] + self.B[self.cand] @ x

    def scale_forces(self, x: np.ndarray, factor: float) -> np.ndarray:
        """Contact forces scaled by ``factor``: ``x_free + factor (x - x_free)`` (linearity)."""
        return self.x_free + factor * (x - self.x_free)

    def subproblem(self, law, lam, x0, *, tol: float, maxiter: int):
        return full_newton(self, law, lam, x0, tol=tol, maxiter=maxiter)

    def solve_active(self, active, lam, x, c):
        """Active-set step of :func:`run_ssn`: :math:`g_A = 0` by an inner AL (:func:`_equality_solve`).

        A set that the step changes is solved only to :data:`_UZAWA_LOOSE` (its multipliers
        and gaps only decide the next set); the set that repeats, which ``run_ssn`` accepts,
        to :data:`_UZAWA_TOL` (3D P1 Hertz, 128k DOFs: 159 -> 99 CG iterations, same outer
        iterations and contact force).
        """
        A = np.flatnonzero(active)
        lam_new = np.zeros(self.cand.size)
        if A.size:
            def moves(xa, mu):  # the outer step's next active set, (lam + c g) > 0, differs
                lam_next = np.zeros(self.cand.size)
                lam_next[A] = mu
                return not np.array_equal((lam_next + c * self.gaps(xa)) > 0, active)

            x, mu, g_a, used = _equality_solve(self, A, np.maximum(lam[A], 0.0), c, x, moves=moves)
            lam_new[A] = mu
            # an inner iteration stopped at its budget fails the run (run_ssn), whatever its active set
            self.active_converged = used <= _UZAWA_MAXITER
            self.active_residual = float(np.max(np.abs(c * g_a), initial=0.0)) / max(float(np.max(np.abs(mu),
                                                                                                 initial=0.0)), 1e-300)
        else:
            x = self.x_free.copy()
            self.active_converged = True
        return x, lam_new, self.gaps(x)

    def final_displacement(self, x: np.ndarray) -> np.ndarray:
        return self.expand(x)

    def timings(self) -> dict:
        return {"setup_s": self.setup_seconds, "factor_s": 0.0, "amg_setup_s": self.amg_seconds,
                "linear_solve_s": self.reference_seconds, "linear_solve_cpu_s": self.reference_cpu_seconds,
                "assembly_s": self.assembly_seconds}

    def extra(self) -> dict:
        return {"linear_solver": self.solver.name, "strategy": self.strategy, "cg_iterations": int(self.cg_iterations),
                "amg_setups": int(self.amg_setups),
                "amg_updates": int(self.amg_updates),
                "reference_cg_iterations": int(self.reference_cg_iterations),
                "amg_aggregation": getattr(self.factor_K, "aggregation", None)}


# ----------------------------------------------------------------------
class _FullSpaceSubproblem(NewtonSystem):
    """Subproblem (S) in the free DOFs (module doc): :math:`R(x) = Kx - b + B^T(w \\circ t_N(g(x)))`.

    State ``(g, t, Kx, R, Pi)``. The relative residual is :math:`\\max|R|` over the largest
    applied load or contact force (not over :math:`\\max|b|`: the term :math:`-K_{fd} u_d` of a
    prescribed support motion, a platen, is no force on the body and can exceed the contact
    forces by orders of magnitude; measured against it a Newton residual below tolerance left
    gap errors whose multiplier change :math:`\\varepsilon_N \\delta g` stalled Algorithm 6.1
    above ``tol_multiplier``: 3D P2 Hertz 9k DOFs driven by a platen, ``tol_multiplier`` 1e-11,
    40 outer iterations at a change of 1.5e-10 to 2.7e-10 with 0 Newton steps each, against 9 on
    the direct path); the tolerance is raised to the round-off bound of :math:`R`
    (:func:`_residual_floor`). Each step is an inexact CG solve with the AMG preconditioner
    and the forcing terms of the module doc.
    """

    def __init__(self, ic, law, lam, tol):
        self.ic, self.law, self.lam, self.tol = ic, law, lam, tol
        cand = ic.cand
        self.Bc = ic.B[cand]
        self.BcT = self.Bc.T.tocsr()
        self.w = ic.weights[cand]
        self.gfix = ic.g_fix[cand]
        self.Bc_abs = abs(self.Bc).tocsr()
        self.bscale = ic.load_scale
        self.bscale_lifted = float(np.max(np.abs(ic.b), initial=0.0))
        self.scale = None
        self.fscale = 1e-300
        self.forcing = _FORCING_START
        self.tol_k = tol

    def evaluate(self, x):
        ic, law, lam = self.ic, self.law, self.lam
        Kx = ic.K @ x
        g = self.gfix + self.Bc @ x
        t = law.traction(g, lam)
        pi = 0.5 * float(x @ Kx) - float(ic.b @ x) + float(np.sum(self.w * law.energy(g, lam)))
        return g, t, Kx, Kx - ic.b + self.BcT @ (self.w * t), pi, x

    def residual(self, state):
        return state[3]

    def merit(self, state):
        return state[4]

    def slope(self, x, state, dx):
        return float(state[3] @ dx)

    def merit_change(self, state, trial, merit, trial_merit):
        r""":math:`\Pi(x_t) - \Pi(x) = \Delta^T(Kx - b) + \tfrac12 \Delta^T(Kx_t - Kx)
        + \sum_j w_j (p(g_{t,j}) - p(g_j))`, :math:`\Delta = x_t - x`: no difference of the large terms of :math:`\Pi`. On the 2D P1 Hertz mesh of
        984k DOFs the difference of the two values of :math:`\Pi` read +7e-9 for a log-met1 Newton step that
        lowered the residual 57-fold (its quadratic model: -1e-11), so every step was cut back to a
        round-off-sized length and the subproblem stopped at its budget (NEWTON_FAILED)."""
        g, _, Kx, _, _, x = state
        gt, _, Kxt, _, _, xt = trial
        d = xt - x
        de = self.law.energy(gt, self.lam) - self.law.energy(g, self.lam)
        return float(d @ (Kx - self.ic.b) + 0.5 * float(d @ (Kxt - Kx)) + np.sum(self.w * de))

    def measure(self, state):
        wt = float(np.max(np.abs(self.w * state[1]), initial=0.0))
        if self.scale is None:  # neither contact forces nor loads: the right-hand side with the supports
            self.scale = max(wt, self.bscale) or self.bscale_lifted
        self.fscale = max(self.scale, wt, 1e-300)
        return float(np.max(np.abs(state[3]), initial=0.0)) / self.fscale

    def tolerance(self, state, tol):
        # the residual cannot be computed more accurately than its round-off (large penalties)
        g, t, _, _, _, x = state
        D = self.law.stiffness(g, self.lam)
        floor = _residual_floor(self.ic.K, self.Bc_abs, x, self.ic.b, self.w, t, D, self.gfix)
        self.tol_k = max(tol, floor / self.fscale)
        return self.tol_k

    def step(self, x, state, history):
        ic = self.ic
        res = history[-1].residual
        if len(history) > 1:
            last = history[-2]
            if last.step < 1.0 or last.full_step or res > 0.5 * last.residual:
                # the last (inexact) step was cut back or reduced the residual too little: on the
                # stiff contact directions a loose CG step is a poor Newton direction; tighten
                self.forcing = max(_FORCING_SLOW * self.forcing, _FORCING_MIN)
        D = self.law.stiffness(state[0], self.lam)
        delta = ic.contact_delta(self.Bc, self.w * D)
        J = ic.with_contact(delta)
        # inexact Newton: forcing min(forcing, res), tight enough in the last step to reach tol
        rtol = float(np.clip(max(min(self.forcing, res), 0.1 * self.tol_k / res), 1e-14, _FORCING_MAX))
        dx, nit = ic.precond.solve(J, -state[3], rtol=rtol, delta=delta, Bc=self.Bc, k=self.w * D)
        logger.debug("Newton %d: residual %.2e, CG rtol %.1e, %d CG iterations", len(history), res, rtol, nit)
        return dx

    def negligible(self, x, state, dx):
        return float(np.max(np.abs(dx), initial=0.0)) <= 1e-14 * max(float(np.max(np.abs(x), initial=0.0)), 1e-300)


#: line search of the frictionless full-space Newton: Armijo on the potential, or a decrease of
#: :math:`\|R\|_2` where the potential rose by at most 1e-12 of itself (its round-off; :func:`full_newton`)
_FULL_NEWTON = NewtonSettings(LineSearch(halvings=60, residual_decrease=True, residual_merit_slack=1e-12))


def full_newton(ic, law, lam, x0, *, tol=1e-12, maxiter=60) -> NewtonOutcome:
    r"""Solve :math:`R(x) = 0` (module doc) by inexact globalized Newton with AMG-CG (:func:`~._newton.newton`).

    The line search (:data:`_FULL_NEWTON`) accepts a step by Armijo on the potential :math:`\Pi`
    or by a decrease of :math:`\|R\|_2` where :math:`\Pi` rose by at most 1e-12 of itself. In
    the full space :math:`\Pi = 	frac12 x^TKx - b^Tx + \dots` is a sum of terms much larger than
    the decrease a Newton step near the solution brings, so Armijo alone accepted only steps
    of 2^-20 or so (the change of :math:`\Pi` within its round-off) and the residual stalled: 2D P1
    Hertz 10k DOFs, Algorithm 6.1 on the AMG path, 37 and 49 Newton steps at a residual of 3.4e-6
    and 7.7e-8 in two outer iterations (100 Newton in all, NEWTON_FAILED with other AMG
    hierarchies; exp-met1 and log-met2 NEWTON_FAILED), against 15 on the direct path; with the
    residual test 16 Newton (exp-met1 20, log-met2 22; direct 22 and 24), the direct path's
    outer iterations, the 3D P2 counts unchanged.
    """
    tol = max(tol, _NEWTON_TOL_FLOOR)
    out = newton(_FullSpaceSubproblem(ic, law, lam, tol), x0, tol=tol, maxiter=maxiter, settings=_FULL_NEWTON)
    return subproblem_outcome(out, out.state[0], out.state[1])


def _release_geometry(model) -> None:
    """Let the model drop its geometry caches (:meth:`LinearElasticity.release_geometry`), if it has any.

    They held about 620 bytes per DOF through every solve on the graded 3D Hertz mesh (fine
    boundary facets: the facet mappings at the quadrature points, plus the affine map of
    every element), 1/3 of the resident memory of the solve.
    """
    release = getattr(model, "release_geometry", None)
    if release is not None:
        release()


def _abs_matvec(A, v: np.ndarray, rows: int = 1 << 16) -> np.ndarray:
    """``|A| v`` for a CSR matrix, in row chunks (no copy of the whole data array)."""
    out = np.empty(A.shape[0])
    for s in range(0, A.shape[0], rows):
        e = min(s + rows, A.shape[0])
        a, z = int(A.indptr[s]), int(A.indptr[e])
        blk = sp.csr_matrix((np.abs(A.data[a:z]), A.indices[a:z], A.indptr[s : e + 1] - a), shape=(e - s, A.shape[1]))
        out[s:e] = blk @ v
    return out


def _residual_floor(K, Bc_abs, x, b, w, t, D, gfix) -> float:
    r"""Round-off bound of :math:`\max|R(x)|`: ``10 u (|K||x| + |b| + |B|^T w (|t| + D (|g^{fix}| + |B||x|)))``.

    ``u`` is the unit round-off; the last term is the error of the tractions of a
    penalty of stiffness ``D`` from the rounding of the gaps (it dominates for the pure
    penalty at :math:`\varepsilon_N` of 1e4 times the initial one and more).
    """
    ax = np.abs(x)
    gerr = np.abs(gfix) + Bc_abs @ ax
    bound = _abs_matvec(K, ax) + np.abs(b) + Bc_abs.T @ (w * (np.abs(t) + D * gerr))
    return 10.0 * np.finfo(float).eps * float(np.max(bound, initial=0.0))


# ---------------------------------------------------------------------- active-set reference

def _equality_solve(ic, A, mu, c, x0, *, maxiter=None, moves=None):
    r"""Solve the contact problem with :math:`g_A = 0` on the candidates ``A`` (inner AL / Uzawa).

    Minimizes :math:`\Pi_0(x) + \sum_{i\in A} w_i(\mu_i g_i + \tfrac c2 g_i^2)`, a linear
    system with the matrix :math:`K + c B_A^T W_A B_A` (CG to 1e-12 of its right-hand side),
    then :math:`\mu \leftarrow \mu + c g_A`, until the update is below
    :data:`_UZAWA_TOL` times the largest multiplier (the error contracts by about 1/100 per
    update, so the multipliers are then accurate to about 1e-10), or stops decreasing (the
    round-off floor of the CG solves). Returns ``(x, mu, g_A, updates)``; ``updates`` is
    ``maxiter + 1`` when the iteration stopped at its budget (``maxiter``, default
    :data:`_UZAWA_MAXITER`) without converging.

    ``moves(x, mu)``, when given, says whether the active set of the outer iteration changes
    at this state; once the update is below :data:`_UZAWA_LOOSE` and it does, the iteration
    stops there: that step only decides the next active set, and the set the outer
    iteration accepts (the one that repeats) is always solved to :data:`_UZAWA_TOL`.
    """
    BA = ic.B[ic.cand[A]]
    wA = ic.weights[ic.cand[A]]
    gfA = ic.g_fix[ic.cand[A]]
    delta = ic.contact_delta(BA, c * wA)
    J = ic.with_contact(delta)
    M = krylov.preconditioner(ic.updated(J, delta))  # the hierarchy of K with Galerkin coarse operators of J
    maxiter = _UZAWA_MAXITER if maxiter is None else int(maxiter)
    x = x0
    mu = mu.copy()
    prev = np.inf
    change = None  # norm of the right-hand side change of the last multiplier update
    for j in range(1, maxiter + 1):
        rhs = ic.b - BA.T @ (wA * (mu + c * gfA))
        res0 = float(np.linalg.norm(rhs - J @ x))
        # inexact Uzawa: the CG solve only needs to be accurate to a fraction of the last update
        # (the multipliers move by about 1/100 of it next; the first solve: of the initial
        # residual); the floor is the exact solve, which the last updates reach
        target = max(1e-12 * max(float(np.linalg.norm(rhs)), 1e-300),
                     _UZAWA_FORCING * (res0 if change is None else change))
        if res0 > target:
            x, _ = ic.pcg(J, rhs, M, rtol=0.0, atol=target, x0=x)
        g = gfA + BA @ x
        step = float(np.max(np.abs(c * g), initial=0.0))
        change = float(np.linalg.norm(BA.T @ (wA * (c * g))))
        mu = mu + c * g
        rel = step / max(float(np.max(np.abs(mu), initial=0.0)), 1e-300)
        logger.debug("Uzawa %d: relative update %.1e", j, rel)
        if rel <= _UZAWA_TOL:
            return x, mu, g, j
        if moves is not None and rel <= _UZAWA_LOOSE and moves(x, mu):
            logger.debug("Uzawa stops at %.1e: the active set changes", rel)
            return x, mu, g, j
        if rel > 0.5 * prev and rel <= 1e3 * _UZAWA_TOL:
            logger.debug("Uzawa update stagnates at %.1e (round-off of the CG solves)", rel)
            return x, mu, g, j
        prev = rel
    logger.warning("active-set equality solve stopped after %d Uzawa updates (last relative update %.1e)",
                   maxiter, rel)
    return x, mu, g, maxiter + 1  # more than maxiter: stopped at its budget, not converged


def _rigid_modes(model) -> np.ndarray:
    """Rigid-body modes ``(ndofs, k)`` of the model: its own (``model.rigid_modes()``, one set per body of a
    :class:`~alcontact.fem.MultiBody`) or those of all its nodes as one body."""
    if hasattr(model, "rigid_modes"):
        return model.rigid_modes()
    pts_all, dofs_all = model.all_node_dofs()
    modes, _ = rigid_body_modes(pts_all)
    R = np.zeros((model.ndofs, modes.shape[-1]))
    R[dofs_all.ravel()] = modes.reshape(-1, modes.shape[-1])
    return R


def _near_null(model, free: np.ndarray) -> np.ndarray:
    """Rigid-body modes on the free DOFs ``(free.size, k)``: the body's own (of its geometry, as its factorization
    takes them) or, for several bodies (:class:`~alcontact.fem.MultiBody`), each body's (:func:`_rigid_modes`)."""
    own = getattr(model, "_free_rigid_modes", None)
    return own(free) if own is not None else np.ascontiguousarray(_rigid_modes(model)[free])


def free_rigid_motions(model, fixed: np.ndarray, free: np.ndarray) -> np.ndarray:
    """Rigid motions ``(free.size, k)`` on the free DOFs that vanish on every fixed DOF (``k`` may be 0)."""
    R = _rigid_modes(model)
    if fixed.size:
        _, sv, vt = np.linalg.svd(R[fixed], full_matrices=True)
        rank = int(np.sum(sv > 1e-10 * max(float(sv.max(initial=0.0)), 1e-300)))
    else:
        vt, rank = np.eye(R.shape[1]), 0
    return R[free] @ vt[rank:].T


def springs_hold(Z: np.ndarray, S) -> np.ndarray | None:
    r""":math:`Z^T S Z` when the springs ``S`` stop every motion of ``Z`` (positive definite to 1e-8), else None."""
    G = Z.T @ (S @ Z)
    ev = np.linalg.eigvalsh(0.5 * (G + G.T))
    return G if ev.size and ev.min() > 1e-8 * max(float(ev.max()), 1e-300) else None


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

    #: how the linear systems are solved (``solution.extra["strategy"]``): Krylov iterations in the full space
    strategy = "krylov"

    def __init__(self, problem, history, *, margin: float = 0.25, solver: _linalg.SolverChoice | None = None):
        t0 = time.perf_counter()
        model = problem.model
        # the approximate solver whose factors precondition the Krylov solves (alcontact.linalg.select_solver)
        self.solver = _linalg.select_solver("amg", dim=model.dim, ndofs=model.ndofs) if solver is None else solver
        self.condensed = False  # the compliance A is built only for the semi-smooth Newton reference
        self.S = self.Z = self.ZSZ = None  # contact springs of a held body (_spring_matrix, _factor_of)
        # the setup of the direct path; its factorization hook builds the AMG hierarchy (_factor_of)
        super().__init__(problem, history, margin=margin, linear_solver=self.solver.name)
        self.factorizations = 0  # an AMG hierarchy, no factorization (counted in amg_setups)
        model = self.model
        free = self.free = self._free
        self.K = self._K[free][:, free].tocsr()
        self.K_abs = abs(self.K).tocsr()  # round-off bound of the residual
        self.R = _near_null(model, free)  # near-null space of the hierarchies (that of ``factor``)
        self.hints = _linalg.MatrixHints(dim=model.dim, near_null=lambda: self.R)
        self.factor_K = self.factor.factor
        self.cg_iterations = 0
        self.amg_setups = 1
        self.amg_seconds = self.factor_seconds
        self.b_parts = np.stack([self.factor.rhs(load, fv) for fv, load in zip(self.fv_parts, self.loads)])
        # y = y_fix(t) + Bl x: rows -E_i^T P_i (P_i: the free DOFs of point i, the row operator of the direct path),
        # between two bodies the mortar rows of the weighted gap and the relative tangential displacement
        self.Bl = self.local_rows()
        self.Bl.eliminate_zeros()
        self.yfix_parts = np.stack([self._local(self.factor.expand(np.zeros(free.size), fv))
                                    for fv in self.fv_parts])
        self.precond = _AmortizedPreconditioner(self)
        self.setup_seconds = time.perf_counter() - t0

    # ------------------------------------------------------------------ the hooks of the direct path's setup
    def _schur_request(self, problem, margin: float, matrix=None) -> dict:
        """No Schur block: nothing is factorized on this path."""
        return {}

    def _factor_of(self, matrix=None):
        r"""The AMG "factorization" of :math:`K` (``matrix``: :math:`\tilde K = K + S` of a held body).

        Instead of a checked factorization, the check is on the rigid motions: the supports
        restrain them (``model.check_restrained``), or the springs :math:`S` of
        :meth:`FrictionalContact._stabilize` on the touching points stop every motion :math:`r`
        the supports leave free (:math:`r^T S r > 0` on that space, relative to the largest
        spring energy of a unit motion: :func:`~alcontact.contact.systems._krylov.springs_hold`).

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

    def load_scale(self, t: float) -> float:
        r"""Largest applied load :math:`\max|f_f(t)|` on the free DOFs: the force scale of the Newton residuals
        (:class:`_FullSpaceFriction`), without the coupling :math:`-K_{fd} u_d` of the prescribed values."""
        return float(np.max(np.abs((self.amplitudes(t) @ self.loads)[self.free]), initial=0.0))

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
        return {"linear_solver": self.solver.name, "strategy": self.strategy,
                "cg_iterations": int(self.cg_iterations + inner),
                "amg_setups": int(self.amg_setups), "krylov_solves": int(self.linear_solves),
                "amg_aggregation": getattr(self.factor.factor, "aggregation", None)}


class _AmortizedPreconditioner(_Preconditioner):
    """:class:`~alcontact.contact.systems._krylov._Preconditioner` whose slow-down rebuild must pay for itself.

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
    mu: float | np.ndarray  # one coefficient, or one per candidate (pairs with their own)
    opts: object
    tfree: np.ndarray
    #: largest applied load on the free DOFs at t (without the coupling -K_fd u_d of the prescribed values)
    load_scale: float = 0.0

    label: ClassVar[str] = "friction AL (AMG)"
    #: first-order multiplier updates (6.2b)/(6.2c) only: the second-order update needs the dense
    #: sensitivity of the condensed subproblem (c d x c d, one solve per column); same fixed point
    second_order: ClassVar[bool] = False
    #: no tangent predictor either (it comes from the second-order update's sensitivity)
    tangent_predictor: ClassVar[bool] = False
    #: the family-P predictor gives lambda_N only and is not counted (_friction._step_al)
    full_predictor: ClassVar[bool] = False
    #: the last subproblem keeps the fixed radius (its coupled radius needs the second-order update)
    final_coupled: ClassVar[bool] = False

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

    def sensitivity(self, law, lamN, lamT, state, coupled: bool = False):
        """Not available (``None``): first-order updates only (:attr:`second_order`), so never asked."""
        return None


class _FullSpaceFriction(_PointSystem):
    r"""Subproblem (6.2a) in the free DOFs (module doc): :math:`F(x) = Kx - b + B^T(w \circ t(y(x)))`.

    The frictional counterpart of :class:`~alcontact.contact.systems._krylov._FullSpaceSubproblem`:
    relative residual :math:`\max|F|` over the largest applied load or contact force (of the start,
    or the current iterate where larger; not over :math:`\max|b|`, whose coupling :math:`-K_{fd} u_d`
    of a platen stalled Algorithm 6.2 at ``tol_multiplier`` 1e-11: 3D P2 Hertz 9k DOFs, the first
    step failed after 6 cut-backs; with this scale 12 outer iterations, as the obstacle-driven
    problem); tolerance raised to the round-off bound of
    :math:`F`; each step an inexact Krylov solve (CG for a symmetric :math:`J`, else GMRES)
    with the AMG preconditioner, the forcing terms of :mod:`alcontact.contact.systems._krylov`
    (tightened after a damped step or a slow residual decrease) and its rebuild rule
    (:class:`_AmortizedPreconditioner`). The merit is the potential :math:`\Pi` (module
    doc) for the fixed disc radius :math:`\mu\lambda_N`; without a potential (coupled radius)
    the line search asks for a decrease of :math:`|F|` (:data:`_WITH_POTENTIAL`,
    :data:`_NO_POTENTIAL`). State: :class:`~alcontact.contact.algorithms._subproblem._Point` with
    ``aux = (y, t, Dy, state)``.
    """

    def __init__(self, ctx: _FullCtx, law, lamN, lamT):
        self.ctx, self.law, self.lamN, self.lamT = ctx, law, lamN, lamT
        self.rho = ctx.mu * np.maximum(lamN, 0.0) if ctx.opts.radius == "multiplier" else None
        self.BcT = ctx.Bc.T.tocsr()
        self.Babs = abs(ctx.Bc).tocsr()
        # force scale: the applied loads, not max|b| (see _FullSpaceSubproblem: a platen's -K_fd u_d is no force)
        self.bscale = ctx.load_scale
        self.bscale_lifted = float(np.max(np.abs(ctx.b), initial=0.0))
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
        if self.scale is None:  # neither contact forces nor loads: the right-hand side with the supports
            self.scale = max(wt, self.bscale) or self.bscale_lifted
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
    """Solve the subproblem :math:`F(x) = 0` (module doc) by :func:`~alcontact.contact.algorithms._subproblem.newton`.

    Inexact globalized Newton with AMG-Krylov steps (:class:`_FullSpaceFriction`), tolerance
    ``max(tol, 1e-11)`` (as :func:`~alcontact.contact.systems._krylov.full_newton`) or the
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
