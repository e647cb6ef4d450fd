r"""Condensed contact systems (constant tangent, Delassus operator): frictionless and Coulomb.

Small deformation with the linearized gap (6.15): at contact point ``i``
(a DOF location of the candidate boundary, reference position :math:`X_i`)

.. math::

    g_i(u) = g^0_i - \nu_i \cdot u_i \le 0,

where :math:`g^0_i` is the signed gap of :math:`X_i` and :math:`\nu_i` the obstacle's
normal at its projection (pointing out of the obstacle). With ``B`` the matrix of
rows :math:`-\nu_i^T` on the DOFs of point ``i`` and ``w_i`` the tributary
length/area, the contact force on the body is :math:`-B^T (w \circ \lambda)` with
pressures :math:`\lambda \ge 0`, and equilibrium :math:`K u = f - B^T r`,
:math:`r = w\circ\lambda`, gives

.. math::

    u = u_{free} - K^{-1} B^T r, \qquad g = g_{free} - S r, \qquad S = B K^{-1} B^T .

``S`` (the Delassus operator, symmetric positive definite) couples only the
candidate points, so every algorithm works on vectors of the size of the contact
zone: the stiffness is factorized once and the displacement costs one more solve
at the end. This is the same discrete problem as the full one, not an approximation.

``S`` comes from the Schur complement when the solver has one (MKL PARDISO): the
factorization eliminates last the DOFs ``c`` of the contact-boundary points that can
become candidates (predicted gap within SCHUR_WINDOW element sizes of the candidate
threshold, chosen before the factorization from the gaps under the predicted contact-free
displacement, :meth:`CondensedContact._predicted_gaps`: the rigid motion the supports
prescribe, plus a rough solve, a few per cent of a factorization, of what the loads add; in 2D
under loads also the points closest to the obstacle) and returns
:math:`S_c = K_{cc} - K_{ci} K_{ii}^{-1} K_{ic}`, and since :math:`B` lives on those
DOFs, :math:`S = B_c (K^{-1})_{cc} B_c^T = B_c S_c^{-1} B_c^T` costs one dense Cholesky
of :math:`S_c` instead of one triangular solve pair per candidate. Other solvers build
the columns :math:`B K^{-1} B_j^T` with batched triangular solves; with a Schur block
the build is hybrid: solves only for candidates outside the block, whose rows on ``c``
also give their entries with the block points.

Candidates are the points whose free-solution gap exceeds ``-margin``; when many of them
fall outside the block (a prediction that missed them), the stiffness is factorized
again with the block of the free-solution gaps if that is cheaper than their solves
(:meth:`CondensedContact._reorder_for`); after a solve, points outside the set that
penetrate are added and the solve repeated.

The factorization, the springs of a body held only by the obstacle and the build of
the condensed operator live in :class:`CondensedContact`, for any row operator
:math:`G` with ``k`` rows per contact point: :math:`G = B` (``k = 1``) gives ``S`` here,
and the frictional :class:`~alcontact.contact.systems._condensed.FrictionalContact`
uses the same class with :math:`G = P` (``k = d``, every free component of a point),
:math:`C = P K^{-1} P^T`, so both paths share the points, the candidates, the backend
choice and the Schur block.

Discrete frictional contact condensed on all displacement components of the contact points.

Small deformation (6.15)-(6.22). At contact point ``i`` (reference position
:math:`X_i`, tributary length/area :math:`w_i`) with obstacle normal
:math:`\nu_i` (pointing out of the obstacle, evaluated at :math:`X_i`) and a
tangent basis :math:`T_i` (``d x (d-1)``, orthonormal, orthogonal to
:math:`\nu_i`), the local kinematic variables are

.. math::

    g_i = g^0_i - \nu_i\cdot u_i \;(\le 0 \text{ feasible}), \qquad
    u_{T,i} = T_i^T u_i ,

and the local nodal contact forces :math:`R_i = w_i (t_{N,i}, t_{T,i})` act on
the body as :math:`F_i = E_i R_i`, :math:`E_i = [\nu_i, -T_i]`: the pressure
pushes the body along :math:`\nu_i`, and :math:`t_T` is the tangential traction
in the dissertation's sign (the trial (6.47) :math:`t_T = t_{T,n} + \varepsilon_T\Delta u_T`
grows with the slip, so the force on the body, :math:`-w T t_T`, resists it).
Equilibrium :math:`K u = f(t) + P^T F` gives, with :math:`P` selecting the free
DOFs of the candidate points and :math:`C = P K^{-1} P^T`,

.. math::

    y = y_{free}(t) - A R, \qquad y_i = (g_i, u_{T,i}), \qquad
    A = E^T C E \quad(\text{symmetric, } dc \times dc),

which reduces to :math:`g = g_{free} - S r` of :mod:`alcontact.contact.systems._condensed`
when :math:`t_T = 0` (:math:`A_{NN} = S`). The setup is the frictionless one
(:class:`~alcontact.contact.systems._condensed.CondensedContact`: points, candidates, the one
factorization of the stiffness for the whole load history with its backend and Schur
block, the springs of a body held by the obstacle); ``C`` is its condensed operator for
the row operator :math:`P`: entries between points inside the Schur block come from the
Schur complement, the others cost one triangular solve per free candidate DOF.

Supported components. As in the frictionless :class:`~alcontact.contact.kinematics._points.ContactPoints`,
a point takes part in contact when its normal motion is not fully supported
(``movable``: :math:`\nu_i` has a component on a free DOF), whatever its other
components: a point on a symmetry plane is an ordinary contact point. ``P``
selects only its *free* DOFs (the rows and columns of ``C`` of supported DOFs
are zero: a force on a supported DOF goes into the support reaction), while
:math:`y_i` keeps the prescribed values of the supported components. A
supported axis :math:`e_k` lying in the tangent plane (:math:`\nu_{i,k} = 0`, e.g.
the normal of a symmetry plane) is made a tangent direction of :math:`T_i`
(:func:`tangent_bases` with ``held``); such a *held* tangent direction has no
compliance, its friction force is part of the support reaction, and the
Coulomb law acts on the free tangent directions (:attr:`FrictionalContact.tfree`).
"""

from __future__ import annotations

import dataclasses
import inspect
import logging
import time

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ...errors import InputError
from ...fem.elasticity import rigid_body_modes
from ...linalg import krylov
from ..algorithms._subproblem import solve_subproblem
from ..kinematics._mortar_tangent import mortar_local_rows
from ..kinematics._points import ContactPoints, _point_rows, tangent_bases
from ..problem._loading import LoadHistory, component_fields


logger = logging.getLogger(__name__)

_BATCH = 64
#: largest Schur block (DOFs) asked of the factorization: the dense block costs 8 n^2 bytes
#: and an n^3/3 Cholesky; beyond it the contact-boundary points closest to the obstacle are kept
SCHUR_MAX_DOFS = 3000
#: smaller models are factorized without a Schur block (factorization and the one batch of
#: candidate solves are cheap there; the force balance keeps the round-off of the plain factor)
SCHUR_MIN_DOFS = 10_000
#: width of the Schur block beyond the candidate threshold, in element sizes of the contact zone
#: (reference gaps): the whole 3D contact boundary made the factorization ~55 % dearer than a plain one.
#: Measured (3D P1 Hertz 36k DOFs, CPU s of the contact solve over one linear solve, ssn / exp-met1):
#: window 0: 72 block DOFs, 1.09 / 1.08; 0.5: 152, 1.10 / 1.13; 1: 217, 1.09 / 1.22; 2: 339,
#: 1.34 / 1.24; 4: 522, 1.45 / 1.42 (every candidate inside the block in all of them). Half an
#: element keeps a margin for loads that widen the contact zone (a candidate outside the block costs
#: one triangular solve pair); in 2D the block is the candidates' DOFs (+-2) for any window.
SCHUR_WINDOW = 0.5
#: in 2D the contact boundary is a line and a Schur block of its points costs the factorization next to
#: nothing (2D P1 Hertz, CPU s of factorization + solve: 120k DOFs 0.61 without a block, 0.66 with all
#: 265 top points; 277k 1.60 / 1.60 with 265 of 457): where loads (or supports that deform the body) act,
#: the block also takes the movable points closest to the obstacle up to this many DOFs, and when that is
#: every movable point the rough solve of the prediction is skipped (in 2D it costs 1.3-4 linear solves:
#: 2D Hertz under a body force, 100k-984k DOFs, 2.4-5.7 linear solves per contact solve with it against
#: 1.2-1.4 with this block). Not where the prediction is exact (no load, the supports one rigid motion):
#: there it only enlarges the dense block (2D P2 half disc, 224k DOFs: 1,888 block DOFs for 149
#: candidates, 1.25-1.38 linear solves with it, 1.03-1.18 without; ``docs/benchmarks/hertz_disc``).
#: 1200 left 247 of the 847 candidates of the 984k-DOF Hertz mesh under a body force outside (a second
#: factorization: 2.37 linear solves), so the whole cap.
SCHUR_2D_DOFS = SCHUR_MAX_DOFS
#: time of one right-hand side in a batch of triangular solves over the time of a single solve
#: (MKL PARDISO, 64 columns, measured: 2D P1 120k DOFs 0.60, 3D P1 39k DOFs 0.23)
SOLVE_COLUMN_COST = 0.5
#: relative least-squares residual below which the prescribed values of the supports are one rigid
#: motion (:meth:`CondensedContact._predicted_gaps`)
RIGID_FIT_TOL = 1e-8
#: relative residual of the rough solve that predicts, before the factorization, what the loads (and
#: supports that deform the body) add to the rigid motion of the supports (:meth:`CondensedContact._predicted_gaps`,
#: :func:`alcontact.linalg.krylov.approximate_solve`). Measured, 3D Hertz under a body force (symmetric V-cycle;
#: the forward/backward one of linalg._amg.plain_aggregation gives 0.0146 h at 39k, 0.0031 h at 78k): largest gap
#: error of the contact points 0.0155 h (P1 39k DOFs, 12 CG iterations), 0.0135 h (P1 111k, 10), 0.003 h (P2 78k,
#: 15), against the block's window of SCHUR_WINDOW = 0.5 h; 0.3 gave 0.018-0.054 h, 0.03 0.002-0.007 h
PREDICTION_RTOL = 0.1


class CondensedContact(ContactPoints):
    r"""Contact points on one factorization of the stiffness: the setup of every condensed problem.

    Shared by the frictionless :class:`DiscreteContact` (:math:`S = B K^{-1} B^T`) and the
    frictional :class:`~alcontact.contact.systems._condensed.FrictionalContact`
    (:math:`C = P K^{-1} P^T` on all free components of the candidates): the
    factorization (backend, Schur block, the cache of ``model.factorize``), the springs
    of a body held only by the obstacle (:meth:`_stabilize`) and the condensed operator
    :math:`G K^{-1} G^T` of a row operator :math:`G` with :attr:`rows_per_point` rows per
    point (:meth:`_row_operator`), built by :meth:`_condensed` from the Schur complement
    and triangular solves (module doc).
    """

    #: how the linear systems are solved (``solution.extra["strategy"]``): condensed on the contact points
    strategy = "condensed"

    #: rows of the row operator G per contact point
    rows_per_point = 1

    #: factorizations of the stiffness this setup made (:meth:`_factorize`: 0 when the model's cached
    #: factor was reused, 2 when :meth:`_reorder_for` factorized again)
    factorizations = 1

    def _factorize(self, problem, margin: float, linear_solver: str) -> None:
        """Points, then the factorization of the stiffness (with springs when the supports leave it singular).

        Sets ``factor``, ``spring``, ``factorizations``, ``factor_seconds``; ``_schur_kw``
        (the Schur block asked for) and ``linear_solver``.
        """
        model = self.model
        self.spring = None  # contact-point springs of a body held only by the obstacle
        self.linear_solver = linear_solver  # registry name (alcontact.linalg) or "auto"
        mask = np.ones(model.ndofs, dtype=bool)
        mask[self.fixed] = False
        self._free = np.flatnonzero(mask)  # the free numbering of model.factorize
        self._setup_points(problem, self._free)
        t_fac, c_fac = time.perf_counter(), time.process_time()
        n_fac = getattr(model, "factorization_count", None)
        self._margin = margin
        self.prediction = "none"  # how the Schur block was chosen (:meth:`_predicted_gaps`)
        self.prediction_iterations = 0
        self.prediction_seconds = self._prediction_cpu = 0.0
        self._schur_kw = self._schur_request(problem, margin)
        try:  # checks the rigid motions first
            self.factor = self._factor_of()
        except InputError as exc:
            self._stabilize(exc)  # raises unless the obstacle restrains the free motions
        if n_fac is not None:  # 0 when the model reused its factorization (same supports, e.g. load steps)
            self.factorizations = model.factorization_count - n_fac
        self.factor_seconds = time.perf_counter() - t_fac - self.prediction_seconds
        # CPU seconds (the refactorization rule of _reorder_for: wall seconds follow the machine's load)
        self._factor_cpu = time.process_time() - c_fac - self._prediction_cpu

    def _stabilize(self, exc: InputError) -> None:
        r"""Factorize :math:`\tilde K = K + \kappa\, G_s^T W_s G_s` for a body held only by the obstacle.

        The supports leave a rigid motion free (``exc`` says which). If the contact
        points closest to the obstacle (within half an element of the closest one)
        restrain it, springs :math:`\kappa = E'/h` on those points (:meth:`_spring_matrix`:
        on their normal motion without friction, on all their free components with
        it) make the matrix regular, and the contact law is shifted by the same
        springs, an exact rewriting of the equilibrium (:meth:`DiscreteContact.subproblem`,
        :meth:`alcontact.contact.systems._condensed.FrictionalContact._stabilize`).
        Sets ``spring = (points, kappa)``. Otherwise the error says that neither the
        supports nor the obstacle restrain the body.
        """
        model = self.model
        h = self._element_size()
        g0 = np.where(self.movable, self.gap0, -np.inf)
        near = np.flatnonzero(self.movable & (g0 >= g0.max() - 0.5 * h)) if np.any(self.movable) else []
        if len(near) == 0 or g0.max() < -0.5 * h:
            raise InputError(
                f"{exc} The body does not touch the obstacle either (closest gap {-g0.max():.3g}), so nothing "
                "restrains it: add supports or move the obstacle into contact."
            ) from None
        mat = model.material
        kappa = (mat.E if (model.dim == 2 and mat.plane == "stress") else mat.plane_strain_modulus) / h
        near = np.asarray(near, dtype=np.int64)
        self._K = model.stiffness()
        try:
            self._stabilized = self._K + self._spring_matrix(near, kappa)
            # the block predicted with the springs (the loads of a body held by the obstacle press it on them)
            self._schur_kw = self._schur_request(self.problem, self._margin, matrix=self._stabilized)
            self.factor = self._factor_of(self._stabilized)
        except InputError:
            raise InputError(
                f"{exc} The contact points touching the obstacle do not restrain that motion either: "
                "add supports (e.g. fix a tangential component) so that every rigid motion is stopped."
            ) from None
        self.spring = (near, kappa)
        logger.info("body held by the obstacle only: springs on %d contact points", len(near))

    def _factor_of(self, matrix=None):
        """The factorization of the stiffness, or of ``matrix`` (with the springs of :meth:`_stabilize`).

        Checked: an :class:`~alcontact.errors.InputError` when the matrix leaves a rigid motion
        free. The factorization-free frictional path
        (:class:`~alcontact.contact.systems._krylov.IterativeFrictionalContact`) builds an
        AMG hierarchy here instead.
        """
        return self.model.factorize(self.fixed, matrix=matrix, check=True, backend=self.linear_solver,
                                    **self._schur_kw)

    def prediction_stats(self) -> dict:
        """How the Schur block was chosen, for the solution's ``extra``: ``schur_prediction`` (``"none"``: no block;
        else :attr:`prediction` of :meth:`_predicted_gaps`) and the CG iterations of its rough solves."""
        return {"schur_prediction": self.prediction if self._schur_kw else "none",
                "prediction_cg_iterations": int(self.prediction_iterations)}

    def _spring_matrix(self, near: np.ndarray, kappa: float) -> sp.csr_matrix:
        r"""Springs :math:`\kappa w_i \nu_i\nu_i^T` on the normal motion of the points ``near`` (full numbering)."""
        Bs = self.B[near]
        add = (Bs.T @ sp.diags(kappa * self.weights[near]) @ Bs).tocsr()
        return _expand_free(add, self._free, self.model.ndofs)

    def _row_operator(self) -> sp.csr_matrix:
        """The row operator ``G`` (``rows_per_point`` rows per point, point-major, on the free DOFs)."""
        return self.B

    def _prediction_parts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(values, loads, amplitudes)`` of the states the solve reaches: each state is the sum over the parts
        ``k`` of ``amplitudes[s, k]`` times part ``k`` (prescribed values ``values[k]`` of the supported DOFs
        ``fixed``, load ``loads[k]`` on every DOF). Here one state, one part: the problem's supports and loads."""
        values = np.zeros(self.fixed.size) if self.fixed_values is None else np.asarray(self.fixed_values, float)
        return values[None], np.asarray(self.load, dtype=float)[None], np.ones((1, 1))

    def _predicted_gaps(self, matrix=None) -> np.ndarray:
        r"""Gaps (6.15) of the contact points under the predicted contact-free displacement, before factorizing.

        The Schur block is chosen before the factorization, the contact-free displacement
        :math:`u_{free}` is known only after it. Its prediction, per part of the states
        (:meth:`_prediction_parts`: prescribed values :math:`\bar u`, load :math:`f`):

        * the rigid motion of the supports: with :math:`R` the rigid modes, :math:`a = \arg\min
          \|R_f a - \bar u\|` over the supported DOFs. When the fit is exact (relative residual
          below :data:`RIGID_FIT_TOL`: a bonded platen, every support moved together), :math:`u = R a`
          satisfies every support and :math:`K R a = 0`, so without a load it *is* the contact-free
          displacement of the part, at no cost;
        * otherwise (a load, or supports that deform the body) :math:`u = u^0 + \delta u`, with
          :math:`u^0 = R a` on the free DOFs and :math:`\bar u` on the supported ones, and
          :math:`K_{ff}\,\delta u = (f - K u^0)_f` solved roughly
          (:func:`~alcontact.linalg.krylov.approximate_solve`: CG with an unsmoothed aggregation
          V-cycle to :data:`PREDICTION_RTOL`; ``matrix``: the stiffness with the contact springs of a
          body held by the obstacle, :meth:`_stabilize`). Skipped when the block of the rigid
          prediction holds every movable point already (a 2D contact line within
          :data:`SCHUR_2D_DOFS`), and when the supports alone leave a rigid motion free (the springs
          are not known yet: :meth:`_stabilize` predicts again with them).

        .. math::

            g^{pred}_i = g^0_i - \nu_i \cdot u_i ,

        the largest over the states. ``prediction`` records what ran: ``"exact"`` (no load, the
        supports one rigid motion), ``"rough solve"`` (``prediction_iterations`` CG iterations,
        ``prediction_seconds``), ``"whole boundary"`` (the block holds every movable point),
        ``"rigid part"`` (the rough solve was skipped: a body held by the obstacle before its
        springs are known). The block is checked against the contact-free solution once it is
        known (:meth:`_reorder_for`). Two bodies (a mortar pair) without loads: each body's own
        rigid motion (:meth:`_predicted_mortar_gaps`, ``"rigid motions"``); with loads, or supports
        that deform a body, the gaps of the reference configuration (``"reference"``).
        """
        g0 = self.gap0
        values, loads, amps = self._prediction_parts()
        if self.mortar is not None:
            states = [a @ values for a in amps] if values.size else []
            if np.any(loads) or not any(np.any(v) for v in states):
                self.prediction = "reference"
                return g0
            g = self._predicted_mortar_gaps(states)
            self.prediction = "reference" if g is g0 else "rigid motions"
            return g
        if not np.any(values) and not np.any(loads):
            self.prediction = "exact"
            return g0
        model = self.model
        pts, dmap = model.all_node_dofs()
        modes_of = getattr(model, "_rigid_modes", None)  # a body of revolution has fewer rigid motions
        modes, _ = modes_of(pts) if modes_of is not None else rigid_body_modes(pts)
        R = np.zeros((model.ndofs, modes.shape[-1]))
        R[dmap.ravel()] = modes.reshape(-1, modes.shape[-1])
        Rf = R[self.fixed]
        cdofs = self.dofs.ravel()
        un = np.zeros((values.shape[0], g0.size))  # normal displacement nu . u of each part at the contact points
        rough = []
        for k, (v, f) in enumerate(zip(values, loads)):
            a = np.linalg.lstsq(Rf, v, rcond=None)[0] if v.size else np.zeros(R.shape[1])
            rigid = np.linalg.norm(Rf @ a - v) <= RIGID_FIT_TOL * max(np.linalg.norm(v), 1e-300)
            un[k] = np.einsum("ij,ij->i", self.normals, (R[cdofs] @ a).reshape(g0.size, self.dim))
            if not (rigid and not np.any(f)):
                rough.append((k, a, v, f))
        g = np.max(g0 - amps @ un, axis=0)
        if not rough:
            self.prediction = "exact"
            return g
        self.prediction = "rigid part"  # not exact: the 2D block takes the closest points (_block_points)
        if self._block_points(g, self._margin).size == np.count_nonzero(self.pos.max(axis=1) >= 0):
            self.prediction = "whole boundary"  # the block holds every movable point: nothing to choose
            return g
        self.prediction = "rigid part"
        if matrix is None:
            try:
                model.check_restrained(self.fixed)
            except InputError:  # held by the obstacle: predicted again with the springs (_stabilize)
                return g
        t0, c0 = time.perf_counter(), time.process_time()
        mask = np.ones(model.ndofs, dtype=bool)
        mask[self.fixed] = False
        Kfull = model.stiffness() if matrix is None else matrix
        Kff = krylov.principal_submatrix(Kfull, mask)
        near_null = R[self._free]
        for k, a, v, f in rough:
            u = R @ a
            u[self.fixed] = v
            du, nit = krylov.approximate_solve(Kff, (f - Kfull @ u)[self._free], near_null, rtol=PREDICTION_RTOL)
            u[self._free] += du
            un[k] = np.einsum("ij,ij->i", self.normals, u[self.dofs])
            self.prediction_iterations += nit
        del Kff
        self.prediction = "rough solve"
        self.prediction_seconds += time.perf_counter() - t0
        self._prediction_cpu += time.process_time() - c0
        return np.max(g0 - amps @ un, axis=0)

    def _predicted_mortar_gaps(self, states: list[np.ndarray]) -> np.ndarray:
        r"""Predicted gaps of a two-body (mortar) pair: :math:`g^0 + B \sum_b R_b a_b`.

        :math:`a_b` fits the rigid modes :math:`R_b` of body ``b`` to the values its supported DOFs
        take (as :meth:`_predicted_gaps` does for one body; a sphere pushed by its top onto a fixed
        block moves as a whole, the block not at all). :math:`g^0` when a body has no supports (held
        by the contact only), its supports are not one rigid motion, or both sides are one body.
        """
        g0 = self.gap0
        model = self.model
        if not hasattr(model, "bodies"):
            return g0
        offsets = np.asarray(model.offsets)
        R = model.rigid_modes()  # block by block: the columns of body b vanish outside it
        owner = np.searchsorted(offsets[1:], self.fixed, side="right")
        out = np.full(g0.shape, -np.inf)
        for v in states:
            u = np.zeros(model.ndofs)
            for b in range(len(model.bodies)):
                mine = owner == b
                rows = slice(int(offsets[b]), int(offsets[b + 1]))
                cols = np.flatnonzero(np.any(R[rows] != 0.0, axis=0))
                if not np.any(mine):
                    return g0
                Rf = R[self.fixed[mine]][:, cols]
                a = np.linalg.lstsq(Rf, v[mine], rcond=None)[0]
                if np.linalg.norm(Rf @ a - v[mine]) > RIGID_FIT_TOL * max(np.linalg.norm(v), 1e-300):
                    return g0
                u[rows] = R[rows][:, cols] @ a
            out = np.maximum(out, g0 + self.mortar.B @ u)
        return out

    def _schur_request(self, problem, margin: float, matrix=None) -> dict:
        r"""``schur=`` keyword for ``model.factorize``: the free DOFs of the points that can become candidates.

        Known before the factorization, from the predicted gaps :math:`g^0` of
        :meth:`_predicted_gaps` (the gaps under the rigid motion the supports prescribe plus a
        rough solve of what the loads add; ``matrix``: the stiffness with the springs of a body
        held by the obstacle): with :math:`g^0_{max}` the largest one, the block holds the points with

        .. math::

            g^0_i \ge \min(g^0_{max}, 0) - \text{margin}\,\max(g^0_{max}, 0) - c\,h,

        ``h`` the element size at the contact zone and :math:`c` = :data:`SCHUR_WINDOW`, i.e.
        the candidate threshold of :meth:`_select_candidates` widened by :data:`SCHUR_WINDOW` element sizes
        for the error of the prediction; in 2D, unless the prediction is exact, also the movable points
        closest to the obstacle up to :data:`SCHUR_2D_DOFS` DOFs. Candidates found later outside the block get triangular
        solves (:meth:`_condensed`) or a new factorization (:meth:`_reorder_for`). At most
        :data:`SCHUR_MAX_DOFS` DOFs (the points
        closest to the obstacle). Empty when the model's ``factorize`` takes no Schur block
        or the model has fewer than :data:`SCHUR_MIN_DOFS` DOFs.
        """
        model = self.model
        if model.ndofs < SCHUR_MIN_DOFS or "schur" not in inspect.signature(model.factorize).parameters:
            return {}
        return self._schur_block(self._predicted_gaps(matrix), margin)

    def _block_points(self, g0: np.ndarray, margin: float) -> np.ndarray:
        """The points of the Schur block of :meth:`_schur_request` for the predicted gaps ``g0`` (sorted)."""
        movable = (self.pos >= 0).any(axis=1)
        if not np.any(movable):
            return np.empty(0, dtype=np.int64)
        gtop = float(np.max(g0[movable]))
        thr = min(gtop, 0.0) - margin * max(gtop, 0.0) - SCHUR_WINDOW * self._element_size()
        near = np.flatnonzero(movable & (g0 >= thr))
        if self.dim == 2 and self.prediction != "exact" and near.size < SCHUR_2D_DOFS // 2:  # loads: the closest too
            closest = np.flatnonzero(movable)
            closest = closest[np.argsort(-g0[closest], kind="stable")[: SCHUR_2D_DOFS // 2]]
            near = np.union1d(near, closest)
        npts = SCHUR_MAX_DOFS // self.dim
        if near.size > npts:
            near = np.sort(near[np.argsort(-g0[near], kind="stable")[:npts]])
        return near

    def _schur_block(self, g0: np.ndarray, margin: float) -> dict:
        """``schur=`` keyword of the points whose gap ``g0`` lies within the window of :meth:`_schur_request`."""
        # the points of _setup_points (same problem): their DOFs, free ones (pos >= 0)
        dofs = self.dofs
        keep = self.pos >= 0
        near = self._block_points(g0, margin)
        if near.size == 0:
            return {}
        if self.mortar is not None:  # a two-body row lives on the slave node's and the master nodes' DOFs
            return {"schur": np.unique(self.mortar.B[near].indices)}
        return {"schur": np.unique(dofs[near][keep[near]])}

    def _setup_schur(self) -> None:
        r"""The row operator and the Cholesky factor of the Schur complement :math:`S_c` when there is one.

        Sets ``self._G`` (:meth:`_row_operator`) and ``self._schur`` to ``(L, Gs, inside)``:
        ``L`` the Cholesky factor of :math:`S_c`, ``Gs`` the columns of ``G`` on the Schur
        DOFs, ``inside[r]`` whether the point of row ``r`` has all its free DOFs in the
        block; None without a Schur complement.
        """
        self._G = self._row_operator()
        self._schur = None
        inner = getattr(self.factor, "factor", None)
        Sc = getattr(inner, "schur_complement", None)
        if Sc is None or not self._schur_kw:
            return
        idx = inner.schur_indices  # positions in the free numbering, as G's columns
        try:
            L = sla.cho_factor(Sc, lower=True, check_finite=False)
        except np.linalg.LinAlgError:
            logger.warning("the Schur complement of the contact DOFs is not positive definite; building the "
                           "condensed operator with triangular solves instead")
            return
        G, k = self._G, self.rows_per_point
        Gs = G[:, idx].tocsr()
        rows_inside = Gs.getnnz(axis=1) == G.getnnz(axis=1)
        inside = np.repeat(rows_inside.reshape(-1, k).all(axis=1), k)
        self._schur = (L, Gs, inside)
        self._xc_rows = np.empty(0, dtype=np.int64)  # rows of outside-block candidates with kept solves
        self._xc = np.empty((idx.size, 0))

    def _start_candidates(self, cand: np.ndarray, gaps: np.ndarray | None = None) -> None:
        """The Schur block, then the candidates ``cand`` and the spring points added (:meth:`_add_candidates`).

        ``gaps`` are the gaps of the contact-free solution the candidates were chosen from;
        with them the block is checked against the candidates (:meth:`_reorder_for`).
        """
        if self.spring is not None:  # the spring points must stay candidates (shifted law on them)
            cand = np.union1d(cand, self.spring[0])
        self._setup_schur()
        if gaps is not None:
            self._reorder_for(cand, gaps)
        self.cand = np.empty(0, dtype=np.int64)
        self._add_candidates(cand)

    def _reorder_for(self, cand: np.ndarray, gaps: np.ndarray) -> None:
        r"""Factorize again with the Schur block of the contact-free gaps when that is cheaper than solves.

        The block of :meth:`_schur_request` comes from the gaps that the supports' motion
        predicts (:meth:`_predicted_gaps`); loads and supports that deform the body can
        move other points into contact. Each candidate row outside the block costs a
        triangular solve pair (:meth:`_condensed`), about :data:`SOLVE_COLUMN_COST` times
        the single solve of the contact-free displacement (batched right-hand sides); when
        those columns together would take longer than the factorization did, the stiffness
        is factorized again with the block of ``gaps`` (the gaps of the contact-free
        solution: the prediction made exact), counted in ``factorizations``. The factor of
        the same matrix solves the same systems, so the contact-free solution stands.

        The times compared are CPU seconds of the process: on a shared machine the wall-clock
        ratio of the factorization to one solve followed the load (3D P1 39k DOFs: 800 at a load
        average of 14 on 2 cores, against about 55 in CPU seconds), so the choice, and with it
        the counts of factorizations and solves, changed from run to run. A factor reused from
        the model's cache has no CPU time here; its own (wall) factorization time stands in.
        """
        schur = self._schur
        if schur is None:
            return
        G, k = self._G, self.rows_per_point
        rows = _point_rows(cand, k)
        nout = int(np.count_nonzero(~schur[2][rows] & (G.getnnz(axis=1)[rows] > 0)))
        t_solve = self._solve_cpu
        # what a factorization costs (a factor reused from the model's cache took ~0 s here)
        t_factor = self._factor_cpu if self.factorizations else getattr(self.factor, "factor_seconds", 0.0)
        if nout == 0 or nout * SOLVE_COLUMN_COST * t_solve <= t_factor:
            return
        block = self._schur_block(gaps, self._margin)
        if not block or np.array_equal(block["schur"], self._schur_kw.get("schur")):
            return
        logger.info("%d candidate rows lie outside the Schur block of the predicted gaps; factorizing again "
                    "with the block of the contact-free gaps", nout)
        t_fac, c_fac = time.perf_counter(), time.process_time()
        self._schur_kw = block
        self.factor = self._factor_of(None if self.spring is None else self._stabilized)  # same matrix
        self.factorizations += 1
        self.factor_seconds += time.perf_counter() - t_fac
        self._factor_cpu += time.process_time() - c_fac
        self._setup_schur()

    def _condensed(self, M: np.ndarray, new: np.ndarray) -> np.ndarray:
        r""":math:`G K^{-1} G^T` on the candidates' rows: ``M`` (the old candidates') extended by the points ``new``.

        ``new`` are the last entries of ``self.cand`` (hybrid build). Rows of points inside
        the Schur block: :math:`G_i S_c^{-1} G_j^T` between two of them (no triangular
        solve). Rows of points outside: one triangular solve pair each (batched),
        :math:`X_j = K^{-1} G_j^T`, giving their whole column :math:`G X_j`; the rows of
        :math:`X_j` on the Schur DOFs are kept, so a block point added later gets its
        entries with the outside points as :math:`X_{j,c}^T G_{c,i}^T` without another solve.
        Zero rows (a supported DOF of :math:`P`) get no solve and zero entries.
        """
        G, k = self._G, self.rows_per_point
        rows_all = _point_rows(self.cand, k)
        rows_new = _point_rows(new, k)
        schur = self._schur
        inside = schur[2] if schur is not None else np.zeros(G.shape[0], dtype=bool)
        cols = np.zeros((rows_all.size, rows_new.size))
        jout = np.flatnonzero(~inside[rows_new] & (G.getnnz(axis=1)[rows_new] > 0))
        for s in range(0, jout.size, _BATCH):
            j = jout[s : s + _BATCH]
            X = self.factor.solve(G[rows_new[j]].T.toarray())
            cols[:, j] = G[rows_all] @ X
            self.linear_solves += j.size
            if schur is not None:  # rows on the Schur DOFs, for block points added later
                self._xc_rows = np.concatenate([self._xc_rows, rows_new[j]])
                self._xc = np.hstack([self._xc, X[self.factor.factor.schur_indices]])
        jin = np.flatnonzero(inside[rows_new])
        if jin.size:
            L, Gs, _ = schur
            GsT = Gs[rows_new[jin]].T.toarray()
            Z = sla.cho_solve(L, GsT, check_finite=False)
            ain = inside[rows_all]
            cols[np.ix_(ain, jin)] = Gs[rows_all[ain]] @ Z
            if not np.all(ain):  # entries with the rows outside the block, from their kept solves
                where = {r: i for i, r in enumerate(self._xc_rows)}
                out = rows_all[~ain]
                kept = np.array([r in where for r in out])
                block = self._xc[:, [where.get(r, 0) for r in out]].T @ GsT
                cols[np.ix_(~ain, jin)] = np.where(kept[:, None], block, 0.0)  # zero rows: no solve, no entry
        nold = rows_all.size - rows_new.size
        out = np.zeros((rows_all.size, rows_all.size))
        out[:nold, :nold] = M
        out[:, nold:] = cols
        out[nold:, :nold] = cols[:nold].T
        return 0.5 * (out + out.T)


class DiscreteContact(CondensedContact):
    """Condensed frictionless contact problem built from a :class:`ContactProblem`.

    Attributes
    ----------
    points : ndarray (m, d)
        Reference positions of all contact-boundary points.
    dofs : ndarray (m, d)
        Their global DOFs.
    weights : ndarray (m,)
        Tributary lengths (2D) / areas (3D).
    normals : ndarray (m, d)
        Obstacle normals :math:`\\nu_i` (pointing out of the obstacle).
    gap0 : ndarray (m,)
        Signed gaps of the reference positions.
    g_free : ndarray (m,)
        Gaps of the contact-free solution.
    cand : ndarray of int
        Indices (into the m points) of the current candidates.
    S : ndarray (c, c)
        Delassus operator on the candidates.
    h : float
        Characteristic element size on the contact zone.
    linear_solves : int
        Triangular solve pairs with the stiffness factor so far.
    """

    def __init__(self, problem, *, margin: float = 0.25, linear_solver: str = "auto"):
        t0 = time.perf_counter()
        self._setup_problem(problem)
        self._factorize(problem, margin, linear_solver)
        t_sol, c_sol = time.perf_counter(), time.process_time()
        self.u_free = self.factor.solve_full(self.load, self.fixed_values)
        self.solve_seconds = time.perf_counter() - t_sol
        self._solve_cpu = time.process_time() - c_sol
        self.linear_solves = 1
        if not np.all(np.isfinite(self.u_free)):
            raise InputError("the contact-free solution is not finite; check loads and supports.")

        self._setup_candidates(self.u_free, margin)
        self.S = np.zeros((0, 0))
        self._start_candidates(self.cand, self.g_free)
        self.setup_seconds = time.perf_counter() - t0

    def _add_candidates(self, new: np.ndarray) -> None:
        self._add_columns(new)

    def _add_columns(self, new: np.ndarray) -> None:
        """Extend ``cand`` and the Delassus operator ``S`` with the points ``new`` (:meth:`_condensed`)."""
        new = self._new_points(new)
        if new.size == 0:
            return
        self.cand = np.concatenate([self.cand, new])
        self.S = self._condensed(self.S, new)

    # ------------------------------------------- interface of the outer loops
    # (shared with the factorization-free path of _iterative.py; the state is r here)

    def start(self) -> np.ndarray:
        """State of the contact-free solution (no contact forces)."""
        return np.zeros(self.cand.size)

    def scale_forces(self, r: np.ndarray, factor: float) -> np.ndarray:
        """State with the contact forces multiplied by ``factor``."""
        return r * factor

    def subproblem(self, law, lam, r0, *, tol: float, maxiter: int):
        """Solve subproblem (S) for fixed multipliers (condensed Newton, :mod:`._newton`).

        With contact springs (:meth:`_stabilize`) the Newton iteration runs on the
        shifted law and the outcome reports the physical traction :math:`t(g)`.
        """
        if self.spring is None:
            return solve_subproblem(self, law, lam, r0, tol=tol, maxiter=maxiter)
        shifted = _SpringShiftedLaw(law, self._spring_stiffness(), self.gap0[self.cand])
        out = solve_subproblem(self, shifted, lam, r0, tol=tol, maxiter=maxiter)
        return dataclasses.replace(out, t=law.traction(out.g, lam))

    def _spring_stiffness(self) -> np.ndarray:
        """Spring stiffness per candidate (0 without springs, see :meth:`_stabilize`)."""
        if self.spring is None:
            return np.zeros(self.cand.size)
        return np.where(np.isin(self.cand, self.spring[0]), self.spring[1], 0.0)

    def solve_active(self, active, lam, r, c):
        r"""Active-set step of :func:`run_ssn`: :math:`g_A = 0`, zero pressure off ``A``.

        Rows of ``A``: :math:`(S r)_i = g^{free}_i`; other rows: the physical force
        :math:`r_i + \kappa_i w_i (g_i - g^0_i)` vanishes (just :math:`r_i = 0`
        without contact springs). Returns the state, the pressures and the gaps.
        """
        S, w = self.S, self.weights[self.cand]
        gfree, g0 = self.g_free[self.cand], self.gap0[self.cand]
        kw = self._spring_stiffness() * w
        if self.spring is None and r.size:  # r = 0 off A: Cholesky of S_AA on the active rows only
            r = np.zeros(r.size)
            if np.any(active):
                try:
                    c = sla.cho_factor(S[np.ix_(active, active)], lower=True, check_finite=False)
                except np.linalg.LinAlgError:  # dependent rows: the caller reports a singular active set
                    raise np.linalg.LinAlgError("singular active-set system") from None
                r[active] = sla.cho_solve(c, gfree[active], check_finite=False)
            g = gfree - S @ r
            return r, r / w, g
        M = np.where(active[:, None], S, np.eye(S.shape[0]) - kw[:, None] * S)
        rhs = np.where(active, gfree, -kw * (gfree - g0))
        r = np.linalg.solve(M, rhs) if r.size else r
        g = gfree - S @ r
        return r, (r + kw * (g - g0)) / w, g

    def final_displacement(self, r: np.ndarray) -> np.ndarray:
        """Full displacement of a state (one solve)."""
        return self.displacement(r)

    def applied_pressure(self, out) -> np.ndarray:
        r"""Pressures of the contact forces that :meth:`final_displacement` of ``out.r`` carries.

        The displacement is :math:`u = u_{free} - K^{-1}B^T r` with the final iterate
        :math:`r`, while :math:`\lambda` (the multipliers, or :math:`t_N(g(r))` for the pure
        penalty) differs from :math:`r/w` by the Newton residual or the last multiplier
        change. Reporting :math:`r/w` makes the reported nodal forces exactly the forces in
        equilibrium with ``u`` (a pure penalty at :math:`\varepsilon_N \sim 10^{13}` stops at
        a Newton residual of ~1e-8 relative, its round-off floor, which otherwise shows up as
        an equilibrium error of that size). With contact springs (a body held by the
        obstacle) :math:`r` is the spring-shifted force; the physical force that ``u`` carries is
        :math:`r_i + \kappa_i w_i (g_i - g^0_i)` at the pressed points (as :meth:`solve_active`
        reports it; at an open point the two terms cancel to round-off, and its zero is kept), where
        :math:`\lambda = t_N(g)` of a pure penalty at :math:`\varepsilon_N \sim 4\cdot 10^9` is
        5e-11 off equilibrium (the held block of ``tests/verification/test_contact_patch_signorini.py``).
        """
        lam = out.lam
        if out.r.size == lam.size and np.all(np.isfinite(out.r)):
            w = self.weights[self.cand[: lam.size]]
            if self.spring is None:
                return out.r / w
            if lam.size == self.cand.size:  # at the pressed points (open ones: the spring force cancels to 0)
                kw = self._spring_stiffness() * w
                return np.where(lam > 0, (out.r + kw * (self.gaps(out.r) - self.gap0[self.cand])) / w, lam)
        return lam

    def timings(self) -> dict:
        # linear_solve_s: one factorization + one solve, also when the factor was reused (factor_s ~ 0);
        # factor_s: every factorization of the solve (two when _reorder_for factorized again)
        one = self.factor_seconds / max(self.factorizations, 1)
        return {"setup_s": self.setup_seconds, "factor_s": self.factor_seconds,
                "prediction_s": self.prediction_seconds,
                "linear_solve_s": max(one, self.factor.factor_seconds) + self.solve_seconds}

    def extra(self) -> dict:
        return {"linear_solver": self.factor.backend, "strategy": self.strategy, **self.prediction_stats()}

    # ------------------------------------------------------------------
    def gaps(self, r: np.ndarray) -> np.ndarray:
        """Candidate gaps ``g_free - S r`` for nodal forces ``r`` on the candidates."""
        return self.g_free[self.cand] - self.S @ r

    def displacement(self, r: np.ndarray) -> np.ndarray:
        """Full displacement ``u_free - K^{-1} B^T r`` (one solve)."""
        rhs = self.B[self.cand].T @ r
        du = self.factor.expand(self.factor.solve(rhs))
        self.linear_solves += 1
        return self.u_free - du


def _block_diagonal(D: np.ndarray) -> sp.csr_matrix:
    """Sparse block-diagonal matrix of ``(c, d, d)`` blocks (point-major)."""
    c, d, _ = D.shape
    base = np.arange(c)[:, None, None] * d
    r = np.broadcast_to(base + np.arange(d)[None, :, None], D.shape)
    k = np.broadcast_to(base + np.arange(d)[None, None, :], D.shape)
    return sp.csr_matrix((D.ravel(), (r.ravel(), k.ravel())), shape=(c * d, c * d))


def _expand_free(A_free, free: np.ndarray, n: int) -> sp.csr_matrix:
    """Embed a matrix on the free DOFs into the full ``n x n`` numbering."""
    A = A_free.tocoo()
    return sp.csr_matrix((A.data, (free[A.row], free[A.col])), shape=(n, n))


@dataclasses.dataclass(frozen=True)
class _SpringShiftedLaw:
    r"""Law minus the contact springs of a stabilized body: :math:`t(g) - \kappa (g - g^0)`."""

    law: object
    kappa: np.ndarray
    g0: np.ndarray

    def traction(self, g, lam):
        return self.law.traction(g, lam) - self.kappa * (g - self.g0)

    def stiffness(self, g, lam):
        return self.law.stiffness(g, lam) - self.kappa

    def energy(self, g, lam):
        return self.law.energy(g, lam) - 0.5 * self.kappa * (g - self.g0) ** 2

    def gap_bound(self, lam):
        return self.law.gap_bound(lam)


class FrictionalContact(CondensedContact):
    """The condensed frictional problem of a :class:`ContactProblem` under a :class:`LoadHistory`.

    The frictionless setup extended (:class:`~alcontact.contact.systems._condensed.CondensedContact`:
    the same points, weights, normals, movable points, candidate selection, factorization
    with its cache and Schur block, springs of a body held by the obstacle, and the
    condensed operator build); what friction adds: the tangent bases, the held tangent
    directions, the load components of the history and the compliance on all free
    components, :math:`C = P K^{-1} P^T` (the row operator :math:`P` selects the free DOFs
    of a point, :attr:`rows_per_point` = ``d``), rotated to :math:`A = E^T C E`.

    Attributes
    ----------
    points, dofs, weights, normals, gap0 : arrays over the ``m`` contact-boundary points
    tangents : ndarray (m, d, d-1)
        Tangent bases :math:`T_i`.
    movable : ndarray of bool (m,)
        Points whose normal motion is not fully supported (may be candidates).
    tfree : ndarray of bool (m, d-1)
        Tangent directions in which the point can move (False: held by a support).
    cand : ndarray of int
        Candidate points (movable, may touch at some step).
    A : ndarray (c*d, c*d)
        Condensed compliance in local coordinates, point-major (``i*d + k``,
        ``k = 0`` normal).
    spring : tuple (points, kappa) or None
        Contact springs of a body held only by the obstacle (:meth:`_stabilize`);
        ``kappa`` (m,) holds their stiffness per point (0 elsewhere).
    h : float
        Contact-zone element size.
    linear_solves : int
    """

    def stats(self) -> dict:
        """Solver counters for the solution's ``extra``: how the Schur block was predicted (the AMG path has its own)."""
        return self.prediction_stats()

    def __init__(self, problem, history: LoadHistory, *, margin: float = 0.25, linear_solver: str = "auto"):
        t0 = time.perf_counter()
        self.history = history
        fixed, parts = component_fields(problem, history)
        self._setup_model(problem, fixed)
        self.loads = np.stack([load for _, load in parts])  # (ncomp, ndofs), for the sliding-away test
        self.fv_parts = np.stack([fv for fv, _ in parts])  # (ncomp, nfixed) prescribed values per component
        self._factorize(problem, margin, linear_solver)  # points, factorization, springs (CondensedContact)
        self.h = self._element_size()
        self.kappa = np.zeros(self.points.shape[0])  # contact springs of a body held by the obstacle (_stabilize)
        if self.spring is not None:
            self.kappa[self.spring[0]] = self.spring[1]
        t_sol, c_sol = time.perf_counter(), time.process_time()
        self.u_parts = np.stack([self.factor.solve_full(load, fv) for fv, load in parts])  # (ncomp, ndofs)
        self.solve_seconds = (time.perf_counter() - t_sol) / len(parts)  # one solve
        self._solve_cpu = (time.process_time() - c_sol) / len(parts)
        self.linear_solves = len(parts)
        if not np.all(np.isfinite(self.u_parts)):
            raise InputError("the contact-free solution is not finite; check loads and supports.")

        held = self.pos < 0
        self.tangents = tangent_bases(self.normals, held)
        self.E = np.concatenate([self.normals[:, :, None], -self.tangents], axis=2)  # (m, d, d)
        if self.mortar is None:
            # free part of each tangent direction (E^T restricted to the free DOFs; column 0 gives ``movable``)
            free_part = np.linalg.norm(np.where(held[:, :, None], 0.0, self.E), axis=1)  # (m, d)
        else:  # two bodies: the relative slip is held only where no DOF of its row is free
            Lf = self._mortar_rows()[:, self._free]
            free_part = np.sqrt(np.asarray(Lf.multiply(Lf).sum(axis=1)).ravel()).reshape(self.points.shape)
        self.tfree = free_part[:, 1:] > 1e-12
        # local kinematics of each load component: y_k = (-nu.u_k, T^T u_k)
        self.y_parts = np.stack([self._local(u) for u in self.u_parts])  # (ncomp, m, d)

        # points with a fixed normal DOF cannot move off the obstacle: error if they penetrate at some step
        self.gmax_t = np.max(np.stack([self.y_free(t)[:, 0] for t in history.times]), axis=0)
        cand = self._select_candidates(self.gmax_t, margin, pinned_tol=1e-12 * self.h, when=" at some load step")
        self.C = np.zeros((0, 0))
        self.A = np.zeros((0, 0))
        self._start_candidates(cand, self.gmax_t)  # CondensedContact: Schur block, spring points, add()
        self.setup_seconds = time.perf_counter() - t0

    def _prediction_parts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The load components of the history (prescribed values, loads) and their amplitudes at every load
        step: the Schur block sees the supports' motion and the loads of every step."""
        return self.fv_parts, self.loads, np.stack([self.amplitudes(t) for t in self.history.times])

    @property
    def rows_per_point(self) -> int:
        """``d``: the row operator :math:`P` has one row per displacement component of a point."""
        return self.dim

    def _mortar_rows(self) -> sp.csr_matrix:
        r"""Rows :math:`L` ``(m d, ndofs)`` of the local kinematics :math:`y = y^0 + L u` of a two-body pair.

        The weighted gap and the relative tangential displacement of each slave node and its mortar
        master point (:func:`~alcontact.contact.kinematics._mortar_tangent.mortar_local_rows`, on the
        tangent bases :attr:`tangents`); built once, when first asked (the springs of a body held by
        the contact ask before the tangents are set).
        """
        if getattr(self, "_L", None) is None:
            tangents = tangent_bases(self.normals, self.pos < 0)  # the bases __init__ keeps as ``tangents``
            self._L = mortar_local_rows(self.mortar.B, self.mortar.normals, tangents,
                                        np.vstack([self.dofs, self.mortar.master_dofs]))
        return self._L

    def local_rows(self) -> sp.csr_matrix:
        r"""The rows of :math:`y = y^{fix} + L_f x` on the free DOFs ``x`` (``(m d, n_free)``, point-major, row
        ``i d`` the gap): :math:`-E_i^T P_i` against a rigid master, the mortar rows :meth:`_mortar_rows` between
        two bodies. The contact force on the free DOFs is :math:`-L_f^T R`."""
        if self.mortar is not None:
            return self._mortar_rows()[:, self._free].tocsr()
        return (_block_diagonal(-np.transpose(self.E, (0, 2, 1))) @ self._row_operator()).tocsr()

    def _row_operator(self) -> sp.csr_matrix:
        """:math:`P`: row ``i*d + k`` selects free DOF ``k`` of point ``i`` (a zero row when it is supported).

        Between two bodies the local rows themselves (:meth:`local_rows`): their compliance is ``A``."""
        if self.mortar is not None:
            return self.local_rows()
        m, d = self.pos.shape
        pos = self.pos.ravel()
        keep = pos >= 0
        rows = np.arange(m * d)
        return sp.csr_matrix((np.ones(int(keep.sum())), (rows[keep], pos[keep])), shape=(m * d, self._free.size))

    # ------------------------------------------------------------------ body held by the obstacle
    def _stabilize(self, exc: InputError) -> None:
        r"""Factorize :math:`\tilde K = K + \sum_{i\in S} \kappa w_i P_i^T P_i` for a body held only by the obstacle.

        The supports leave a rigid motion free (``exc`` says which). If the
        contact points closest to the obstacle (set :math:`S`, within half an
        element of the closest one) can restrain it, springs :math:`\kappa = E'/h`
        on *all* free components of those points (:meth:`_spring_matrix`) make the
        matrix regular (:meth:`CondensedContact._stabilize
        <alcontact.contact.systems._condensed.CondensedContact._stabilize>` chooses the points).
        The frictional law on them is shifted by the same springs,
        :math:`\tilde t = t - \kappa\,(y - y^0)`, :math:`y^0 = (g^0, 0)`
        (:meth:`spring_traction`): since :math:`E_i = [\nu_i, -T_i]` is orthogonal,
        :math:`\kappa w P^T u = P^T E\, \kappa w E^T u` and
        :math:`E^T u_i = -(y_i - y^0_i)`, so :math:`K u = f + P^T E R` is exactly
        :math:`\tilde K u = f + P^T E \tilde R`, :math:`\tilde R = w\tilde t`. The
        condensed operators (``A``, ``y_free``) are those of :math:`\tilde K`; the
        reported tractions are the physical :math:`t`. Whether the obstacle and
        friction can hold the loads is a property of the solution: see
        :meth:`slides_away`.

        Raises
        ------
        InputError
            When no contact point touches the obstacle, or the touching points do
            not restrain the free motions either.
        """
        super()._stabilize(exc)

    def _spring_matrix(self, near: np.ndarray, kappa: float) -> sp.csr_matrix:
        r"""Springs :math:`\kappa w_i` on every free component of the points ``near`` (full numbering).

        Between two bodies the springs act on the local kinematics, :math:`\kappa L_s^T W_s L_s` (the rows of
        the points ``near``): the same exact rewriting :math:`\tilde t = t - \kappa (y - y^0)`."""
        if self.mortar is not None:
            Ls = self._mortar_rows()[_point_rows(near, self.dim)][:, self._free]
            add = (Ls.T @ sp.diags(np.repeat(kappa * self.weights[near], self.dim)) @ Ls).tocsr()
            return _expand_free(add, self._free, self.model.ndofs)
        ndofs = self.model.ndofs
        dofs = self.dofs[near].ravel()
        keep = self.pos[near].ravel() >= 0
        diag = np.zeros(ndofs)
        np.add.at(diag, dofs[keep], np.repeat(kappa * self.weights[near], self.dim)[keep])
        return sp.diags(diag)

    def spring_traction(self, y: np.ndarray) -> np.ndarray:
        r"""Spring part :math:`\kappa (y - y^0)` ``(c, d)`` of the shifted law on the candidates (0 off springs)."""
        if self.spring is None:
            return np.zeros_like(y)
        k = self.kappa[self.cand]
        dy = y.copy()
        dy[:, 0] -= self.gap0[self.cand]
        dy[:, 1:] = np.where(self.tfree[self.cand], dy[:, 1:], 0.0)  # held directions carry no contact force
        return k[:, None] * dy

    def spring_tangent(self) -> np.ndarray:
        r""":math:`\partial(\kappa (y - y^0))/\partial y` ``(c, d, d)`` on the candidates (diagonal)."""
        c, d = self.ncand, self.dim
        D = np.zeros((c, d, d))
        if self.spring is not None:
            mask = np.concatenate([np.ones((c, 1)), self.tfree[self.cand]], axis=1)
            D[:, np.arange(d), np.arange(d)] = self.kappa[self.cand][:, None] * mask
        return D

    def spring_energy(self, y: np.ndarray) -> np.ndarray:
        r""":math:`\tfrac12\kappa |y - y^0|^2` ``(c,)`` (its gradient is :meth:`spring_traction`)."""
        if self.spring is None:
            return np.zeros(y.shape[0])
        f = self.spring_traction(y)
        k = np.where(self.kappa[self.cand] > 0, self.kappa[self.cand], 1.0)
        return 0.5 * np.sum(f * f, axis=1) / k

    def frozen_start(self, t_prev: float, t: float, R_prev: np.ndarray, closed: np.ndarray) -> np.ndarray | None:
        r"""Start of a step of a body held by the obstacle: the forces that keep the closed points where they were.

        On the closed candidates (``closed``, bool over the candidates: those in
        contact at :math:`t_n`; ``None`` when there is none),
        :math:`R^0_c = R_{n,c} + A_{cc}^{-1}(y_{free}(t) - y_{free}(t_n))_c` gives
        :math:`y_c(R^0) = y_{n,c}` (no slip increment, every closed point sticks),
        on the components with compliance (held directions and the other
        candidates keep ``R_prev``). Started from :math:`R_n`, the tangential rigid
        motion that the springs allow under a new tangential load would make every
        point slip in the first iterate, where the Newton matrix is singular
        (nothing but friction holds the body). ``None`` without springs or when
        the block is singular.
        """
        if self.spring is None or self.ncand == 0:
            return None
        if not np.any(closed):
            return None
        dy = (self.y_free(t) - self.y_free(t_prev))[self.cand].ravel()
        act = (np.diag(self.A) > 0) & np.repeat(closed, self.dim)
        R0 = np.array(R_prev, dtype=float).ravel()
        try:
            R0[act] += np.linalg.solve(self.A[np.ix_(act, act)], dy[act])
        except np.linalg.LinAlgError:
            return None
        return R0.reshape(R_prev.shape) if np.all(np.isfinite(R0)) else None

    def equilibrium_defect(self, t: float, u: np.ndarray, R: np.ndarray) -> float:
        r"""Relative equilibrium residual :math:`\max|K u - f(t) - P^T E R|` on the free DOFs.

        ``R`` (m, d): physical local nodal contact forces :math:`w\,t`. The
        spring-shifted problem (:meth:`_stabilize`) is an exact rewriting only where
        it has a solution: near a lost equilibrium (the body sliding, lifting or
        turning away) the shifted Newton iteration can stop on a far-away iterate
        whose residual is small relative to its own size, so a step of a
        stabilized body is accepted only when this is small. Scale: the largest
        of the load and the contact force entries.
        """
        f = self.amplitudes(t) @ self.loads
        fc = np.zeros(self.model.ndofs)
        if self.mortar is None:
            np.add.at(fc, self.dofs.ravel(), np.einsum("ijk,ik->ij", self.E, R).ravel())
        else:
            fc = -(self._mortar_rows().T @ np.asarray(R, dtype=float).ravel())
        res = self._K @ u - f - fc
        free = np.ones(self.model.ndofs, dtype=bool)
        free[self.fixed] = False
        scale = max(float(np.max(np.abs(f), initial=0.0)), float(np.max(np.abs(fc), initial=0.0)), 1e-300)
        return float(np.max(np.abs(res[free]), initial=0.0)) / scale

    def slides_away(self, t: float, mu: float) -> str | None:
        r"""Why a body held only by the obstacle has no static equilibrium at ``t`` (``None``: it may have one).

        Necessary condition on the rigid translations left free by the supports
        (axes with no prescribed DOF), for a flat contact zone (one normal
        :math:`\nu` at all spring points): the load resultant :math:`F` must press
        the body on the obstacle, :math:`N = -F\cdot\nu \ge 0`, when the normal
        translation is free, and its free tangential part :math:`Q` must not
        exceed the largest friction force :math:`\mu N` (Coulomb:
        :math:`\sum_i w_i |t_{T,i}| \le \mu \sum_i w_i t_{N,i}`). Otherwise the
        body slides (or lifts) away: a static problem has no solution.
        """
        if self.spring is None or self.mortar is not None:  # (against a flat rigid obstacle only)
            return None
        nu = self.normals[self.spring[0]]
        nbar = nu.mean(axis=0)
        if np.max(np.abs(nu - nbar)) > 1e-9:
            return None
        nbar = nbar / np.linalg.norm(nbar)
        d = self.dim
        comp = np.empty(self.model.ndofs, dtype=np.int64)
        _, all_dofs = self.model.all_node_dofs()
        for k in range(d):
            comp[all_dofs[:, k]] = k
        fixed_axes = set(np.unique(comp[self.fixed]).tolist())
        V = np.eye(d)[:, [k for k in range(d) if k not in fixed_axes]]  # free translations (d, r)
        if V.shape[1] == 0 or np.linalg.norm(V @ (V.T @ nbar) - nbar) > 1e-9:
            return None  # the normal translation is held by a support: N is not known from the loads
        f = self.amplitudes(t) @ self.loads
        F = np.array([f[comp == k].sum() for k in range(d)])
        N = -float(F @ nbar)
        Q = V @ (V.T @ F) + N * nbar
        q = float(np.linalg.norm(Q))
        scale = max(float(np.linalg.norm(F)), 1e-300)
        if N < -1e-9 * scale:
            return (f"at t={t:g} the loads pull the body off the obstacle (resultant {-N:.4g} away from it) and no "
                    "support holds it: there is no static equilibrium; add a support or reverse the load")
        if q > mu * N + 1e-9 * scale:
            return (f"at t={t:g} the body slides away: the tangential load {q:.4g} exceeds the largest friction "
                    f"force mu N = {mu:g} x {N:.4g} = {mu * N:.4g} and no support stops the sliding, so there is no "
                    "static equilibrium; prescribe the sliding displacement instead of the force (a ramped support "
                    "in the sliding direction), or add a support that stops the sliding")
        return None

    # ------------------------------------------------------------------
    def contact_force_points(self, tN: np.ndarray, tT: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r"""``(dofs, forces)``, each ``(k, d)``: the contact force on the bodies of the tractions ``tN`` ``(m,)``,
        ``tT`` ``(m, d-1)`` per node it acts on: :math:`w_i (t_{N,i}\nu_i - T_i t_{T,i})` on the contact points
        against a rigid master; :math:`-L^T R`, :math:`R = w\,(t_N, t_T)`, on the slave and master nodes of a
        two-body pair."""
        w = self.weights
        if self.mortar is None:
            shear = -np.einsum("ijk,ik->ij", self.tangents, tT)
            return self.dofs, w[:, None] * (tN[:, None] * self.normals + shear)
        R = w[:, None] * np.concatenate([tN[:, None], tT], axis=1)
        fc = -(self._mortar_rows().T @ R.ravel())
        nodes = np.unique(np.vstack([self.dofs, self.mortar.master_dofs]), axis=0)
        return nodes, fc[nodes]

    def _local(self, u: np.ndarray) -> np.ndarray:
        if self.mortar is not None:  # the weighted gap (without g0) and the relative tangential displacement
            return (self._mortar_rows() @ u).reshape(self.points.shape)
        ui = u[self.dofs]  # (m, d)
        yn = -np.einsum("ij,ij->i", self.normals, ui)
        yt = np.einsum("ijk,ij->ik", self.tangents, ui)
        return np.concatenate([yn[:, None], yt], axis=1)

    def amplitudes(self, t: float) -> np.ndarray:
        return np.concatenate([[1.0], self.history.amplitudes(t)])

    def u_free(self, t: float) -> np.ndarray:
        return self.amplitudes(t) @ self.u_parts

    def y_free(self, t: float) -> np.ndarray:
        """Contact-free local kinematics ``(m, d)``: column 0 the gap, then ``u_T``."""
        y = np.tensordot(self.amplitudes(t), self.y_parts, axes=1)
        y[:, 0] += self.gap0
        return y

    @property
    def ncand(self) -> int:
        return int(self.cand.size)

    def _add_candidates(self, new: np.ndarray) -> None:
        self.add(new)

    def add(self, new: np.ndarray) -> np.ndarray:
        """Add candidate points (one triangular solve per free DOF outside the Schur block); returns the added ones."""
        new = self._new_points(new)
        if new.size == 0:
            return new
        self.cand = np.concatenate([self.cand, new])
        self.C = self._condensed(self.C, new)  # P K^-1 P^T (CondensedContact)
        if self.mortar is not None:  # the row operator is the local one (L K^-1 L^T)
            self.A = 0.5 * (self.C + self.C.T)
            return new
        c, d = self.cand.size, self.dim
        E = self.E[self.cand]
        C4 = self.C.reshape(c, d, c, d)
        A = np.einsum("iak,iajb,jbl->ikjl", E, C4, E).reshape(c * d, c * d)
        self.A = 0.5 * (A + A.T)
        return new

    def displacement(self, t: float, R: np.ndarray) -> np.ndarray:
        """Full displacement for local forces ``R`` (c, d) on the candidates (one solve)."""
        u = self.u_free(t)
        if self.ncand == 0:
            return u
        if self.mortar is not None:  # -L^T R on both bodies
            rhs = -(self._G[_point_rows(self.cand, self.dim)].T @ np.asarray(R, dtype=float).ravel())
            u = u + self.factor.expand(self.factor.solve(rhs))
            self.linear_solves += 1
            return u
        F = np.einsum("ijk,ik->ij", self.E[self.cand], R)  # global forces on the body
        rhs = np.zeros(self.factor.free.size)
        pos = self.pos[self.cand].ravel()
        free = pos >= 0  # force components on supported DOFs go into the support reaction
        np.add.at(rhs, pos[free], F.ravel()[free])
        u = u + self.factor.expand(self.factor.solve(rhs))
        self.linear_solves += 1
        return u

    def all_local(self, u: np.ndarray) -> np.ndarray:
        """Local kinematics ``(m, d)`` (gap, u_T) of every contact-boundary point."""
        y = self._local(u)
        y[:, 0] += self.gap0
        return y
