r"""Discrete frictionless contact condensed on the contact points.

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
threshold, chosen before the factorization from the gaps under the rigid motion the
supports prescribe, :meth:`CondensedContact._predicted_gaps`; in 2D also the points closest
to the obstacle) and returns
:math:`S_c = K_{cc} - K_{ci} K_{ii}^{-1} K_{ic}`, and since :math:`B` lives on those
DOFs, :math:`S = B_c (K^{-1})_{cc} B_c^T = B_c S_c^{-1} B_c^T` costs one dense Cholesky
of :math:`S_c` instead of one triangular solve pair per candidate. Other solvers build
the columns :math:`B K^{-1} B_j^T` with batched triangular solves; with a Schur block
the build is hybrid: solves only for candidates outside the block, whose rows on ``c``
also give their entries with the block points.

Candidates are the points whose free-solution gap exceeds ``-margin``; when many of them
fall outside the block (loads, supports that deform the body), the stiffness is factorized
again with the block of the free-solution gaps if that is cheaper than their solves
(:meth:`CondensedContact._reorder_for`); after a solve, points outside the set that
penetrate are added and the solve repeated.

The factorization, the springs of a body held only by the obstacle and the build of
the condensed operator live in :class:`CondensedContact`, for any row operator
:math:`G` with ``k`` rows per contact point: :math:`G = B` (``k = 1``) gives ``S`` here,
and the frictional :class:`~alcontact.contact._friction_discrete.FrictionalContact`
uses the same class with :math:`G = P` (``k = d``, every free component of a point),
:math:`C = P K^{-1} P^T`, so both paths share the points, the candidates, the backend
choice and the Schur block.
"""

from __future__ import annotations

import dataclasses
import inspect
import logging
import time

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..errors import InputError
from ..fem.elasticity import rigid_body_modes
from ._newton import solve_subproblem

__all__ = ["ContactPoints", "CondensedContact", "DiscreteContact"]

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
#: 265 top points; 277k 1.60 / 1.60 with 265 of 457): the block also takes the movable points closest to
#: the obstacle (predicted gaps) up to this many DOFs, so loads that lift the body need no other block.
#: 1200 left 247 of the 847 candidates of the 984k-DOF Hertz mesh under a body force outside (a second
#: factorization: 2.37 linear solves); the obstacle drive of that mesh runs with a block of about 1700
#: DOFs at 1.12-1.17 linear solves, so the whole cap
SCHUR_2D_DOFS = SCHUR_MAX_DOFS
#: time of one right-hand side in a batch of triangular solves over the time of a single solve
#: (MKL PARDISO, 64 columns, measured: 2D P1 120k DOFs 0.60, 3D P1 39k DOFs 0.23)
SOLVE_COLUMN_COST = 0.5
#: relative least-squares residual below which the prescribed values of the supports are one rigid
#: motion (:meth:`CondensedContact._predicted_gaps`)
RIGID_FIT_TOL = 1e-8


def _element_size(model, boundary: str, obstacle) -> float:
    """Median facet size of the contact boundary near the obstacle (the facets closest to it set the scale)."""
    f = model.facets(boundary)
    p = model.mesh.p
    v = model.mesh.facets[:, f]
    if model.dim == 2:
        size = np.linalg.norm(p[:, v[1]] - p[:, v[0]], axis=0)
    else:
        size = np.sqrt(np.linalg.norm(np.cross((p[:, v[1]] - p[:, v[0]]).T, (p[:, v[2]] - p[:, v[0]]).T), axis=1))
    g = obstacle.gap(p[:, v].mean(axis=1).T)
    # facets closest to the obstacle set the scale (graded meshes are fine there)
    near = g >= np.quantile(g, 0.9) if g.size > 10 else np.ones(g.size, bool)
    return float(np.median(size[near]))


def _point_rows(points: np.ndarray, k: int) -> np.ndarray:
    """Rows ``i*k .. i*k + k - 1`` of every point ``i`` (point-major)."""
    return (np.asarray(points, dtype=np.int64)[:, None] * k + np.arange(k)).ravel()


class ContactPoints:
    """Contact points of a problem: geometry, linearized gaps (6.15), candidates.

    Shared by the condensed direct paths (:class:`CondensedContact`: frictionless
    :class:`DiscreteContact`, frictional
    :class:`~alcontact.contact._friction_discrete.FrictionalContact`), the
    factorization-free one (:class:`~alcontact.contact._iterative.IterativeContact`)
    and finite deformation. Subclasses call :meth:`_setup_points` with their free
    DOFs, then :meth:`_setup_candidates` (or :meth:`_select_candidates`).

    It also holds the *not available* values of the optional members of
    :class:`~alcontact.contact.system.ContactSystem` (no warm start, the plain semi-smooth
    rule, no multiplier shift, no second-order update); a model with the capability overrides them.
    """

    # ---- ContactSystem: declared capabilities, "not available" on a model without them
    inexact_subproblems = False
    physical_stopping = False
    warm_penalty_start = False
    penalty_continuation = False
    carried_stiffness: float | None = None
    active_converged = True
    active_residual = float("nan")

    def initial_multipliers(self) -> np.ndarray:
        """No warm start: zero multipliers on the candidates (:class:`~alcontact.contact.system.ContactSystem`)."""
        return np.zeros(self.cand.size)

    def initial_active(self, lam: np.ndarray, g: np.ndarray, c: float) -> np.ndarray:
        r"""The semi-smooth rule :math:`\lambda + c\,g > 0` (no prediction of the entering points)."""
        return (np.asarray(lam, dtype=float) + c * np.asarray(g, dtype=float)) > 0

    def entry_multipliers(self, lam: np.ndarray, law, *, penalty_start: bool = False) -> np.ndarray:
        """``lam`` unchanged: no prediction of the points entering contact."""
        return lam

    def multiplier_step(self, law, lam: np.ndarray, out):
        """``None``: no second-order multiplier update (the first-order one (6.13) / (6.66) runs)."""
        return None

    def start_multiplier_step(self, law, lam: np.ndarray, out):
        """``None``: no warm penalty start of Algorithm 6.3."""
        return None

    def _setup_problem(self, problem) -> None:
        """Model, supports and load of ``problem``."""
        self._setup_model(problem, *problem.dirichlet())
        self.load = problem.load_vector()

    def _setup_model(self, problem, fixed: np.ndarray, fixed_values: np.ndarray | None = None) -> None:
        """Problem, model, dimension and the supported DOFs ``fixed`` (with their values)."""
        self.problem = problem
        self.model = problem.model
        self.dim = self.model.dim
        self.fixed, self.fixed_values = fixed, fixed_values

    def applied_pressure(self, out) -> np.ndarray:
        """Pressures the solution reports for the final run ``out``: its multipliers."""
        return out.lam

    def expand(self, x: np.ndarray) -> np.ndarray:
        """Full displacement from the values ``x`` of the free DOFs and the prescribed values."""
        u = np.zeros(self.model.ndofs)
        u[self.free] = x
        if self.fixed.size:
            u[self.fixed] = self.fixed_values
        return u

    def _setup_points(self, problem, free: np.ndarray) -> None:
        """Points, DOFs, weights, obstacle normals and gaps; ``pos``, ``B`` and ``movable`` for the DOFs ``free``.

        ``pos`` (m, d): position of each point DOF in the free numbering (-1 when
        supported); ``B``: rows :math:`-\\nu_i^T` on the free DOFs; ``movable``: the
        normal motion is not fully supported (the point may be a candidate).
        """
        model = problem.model
        pts, dofs = model.node_dofs(problem.contact_boundary)
        w = model.boundary_weights(problem.contact_boundary)
        gap0, nu = problem.obstacle.evaluate(pts)
        self.points, self.dofs, self.weights = pts, dofs, w
        self.normals, self.gap0 = nu, gap0
        # position of each DOF in the free vector (-1 when fixed)
        free_pos = -np.ones(model.ndofs, dtype=np.int64)
        free_pos[free] = np.arange(free.size)
        pos = free_pos[dofs]  # (m, d)
        self.pos = pos
        coef = np.where(pos >= 0, -nu, 0.0)
        self.movable = np.linalg.norm(coef, axis=1) > 1e-12
        m = pts.shape[0]
        rows = np.repeat(np.arange(m), self.dim)
        cols = pos.ravel()
        keep = cols >= 0
        self.B = sp.csr_matrix((coef.ravel()[keep], (rows[keep], cols[keep])), shape=(m, free.size))

    def _setup_candidates(self, u_free: np.ndarray, margin: float) -> None:
        self.g_free = self.all_gaps(u_free)
        self.h = self._element_size()
        self.cand = self._select_candidates(self.g_free, margin)

    def _select_candidates(self, g: np.ndarray, margin: float, *, pinned_tol: float = 0.0,
                           when: str = "") -> np.ndarray:
        """Candidate points: movable, with ``g`` above ``-margin`` times the largest free penetration.

        ``g`` are the gaps of the contact-free solution (their maximum over the load
        steps with a history); sets ``max_free_penetration``.

        Raises
        ------
        InputError
            A point whose normal motion is supported penetrates (``g > pinned_tol``);
            ``when`` completes the message (``" at some load step"``).
        """
        pinned = ~self.movable & (g > pinned_tol)
        if np.any(pinned):
            i = int(np.flatnonzero(pinned)[0])
            raise InputError(
                f"contact point {self.points[i].tolist()} is held by a Dirichlet condition in the normal "
                f"direction but penetrates the obstacle by {g[i]:.3e}{when}; move the obstacle "
                "or release that support."
            )
        gmax = float(np.max(g[self.movable], initial=-np.inf))
        self.max_free_penetration = gmax
        if gmax > 0:
            thr = -max(margin * gmax, 1e-12 * self.h)
            return np.flatnonzero(self.movable & (g > thr))
        return np.empty(0, dtype=np.int64)

    def _element_size(self) -> float:
        """Median facet size of the contact boundary near the obstacle (kept for the same obstacle and boundary)."""
        key = (self.model, self.problem.obstacle, self.problem.contact_boundary)
        cached = getattr(self, "_h_of", None)
        if cached is None or cached[0][0] is not key[0] or cached[0][1] is not key[1] or cached[0][2] != key[2]:
            cached = self._h_of = (key, _element_size(key[0], key[2], key[1]))
        return cached[1]

    def all_gaps(self, u: np.ndarray) -> np.ndarray:
        """Linearized gaps (6.15) of every contact-boundary point for displacement ``u``."""
        return self.gap0 - np.einsum("ij,ij->i", self.normals, u[self.dofs])

    def extend(self, g_all: np.ndarray, tol: float) -> np.ndarray:
        """Add the non-candidate points whose gap exceeds ``tol``; return the added ones."""
        outside = np.ones(self.points.shape[0], bool)
        outside[self.cand] = False
        add = np.flatnonzero(outside & self.movable & (g_all > tol))
        if add.size:
            logger.info("adding %d contact candidates that penetrate", add.size)
            self._add_candidates(add)
        return add

    def _add_candidates(self, new: np.ndarray) -> None:
        self.cand = np.concatenate([self.cand, new])

    def _new_points(self, new: np.ndarray) -> np.ndarray:
        """The movable points of ``new`` that are not candidates yet (sorted)."""
        new = np.setdiff1d(np.asarray(new, dtype=np.int64), self.cand)
        return new[self.movable[new]]


class CondensedContact(ContactPoints):
    r"""Contact points on one factorization of the stiffness: the setup of every condensed problem.

    Shared by the frictionless :class:`DiscreteContact` (:math:`S = B K^{-1} B^T`) and the
    frictional :class:`~alcontact.contact._friction_discrete.FrictionalContact`
    (:math:`C = P K^{-1} P^T` on all free components of the candidates): the
    factorization (backend, Schur block, the cache of ``model.factorize``), the springs
    of a body held only by the obstacle (:meth:`_stabilize`) and the condensed operator
    :math:`G K^{-1} G^T` of a row operator :math:`G` with :attr:`rows_per_point` rows per
    point (:meth:`_row_operator`), built by :meth:`_condensed` from the Schur complement
    and triangular solves (module doc).
    """

    #: rows of the row operator G per contact point
    rows_per_point = 1

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
        t_fac = time.perf_counter()
        n_fac = getattr(model, "factorization_count", None)
        self._margin = margin
        self._schur_kw = self._schur_request(problem, margin)
        try:  # checks the rigid motions first
            self.factor = self._factor_of()
        except InputError as exc:
            self._stabilize(exc)  # raises unless the obstacle restrains the free motions
        if n_fac is not None:  # 0 when the model reused its factorization (same supports, e.g. load steps)
            self.factorizations = model.factorization_count - n_fac
        self.factor_seconds = time.perf_counter() - t_fac

    def _stabilize(self, exc: InputError) -> None:
        r"""Factorize :math:`\tilde K = K + \kappa\, G_s^T W_s G_s` for a body held only by the obstacle.

        The supports leave a rigid motion free (``exc`` says which). If the contact
        points closest to the obstacle (within half an element of the closest one)
        restrain it, springs :math:`\kappa = E'/h` on those points (:meth:`_spring_matrix`:
        on their normal motion without friction, on all their free components with
        it) make the matrix regular, and the contact law is shifted by the same
        springs, an exact rewriting of the equilibrium (:meth:`DiscreteContact.subproblem`,
        :meth:`alcontact.contact._friction_discrete.FrictionalContact._stabilize`).
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
        (:class:`~alcontact.contact._friction_iterative.IterativeFrictionalContact`) builds an
        AMG hierarchy here instead.
        """
        return self.model.factorize(self.fixed, matrix=matrix, check=True, backend=self.linear_solver,
                                    **self._schur_kw)

    def _spring_matrix(self, near: np.ndarray, kappa: float) -> sp.csr_matrix:
        r"""Springs :math:`\kappa w_i \nu_i\nu_i^T` on the normal motion of the points ``near`` (full numbering)."""
        Bs = self.B[near]
        add = (Bs.T @ sp.diags(kappa * self.weights[near]) @ Bs).tocsr()
        return _expand_free(add, self._free, self.model.ndofs)

    def _row_operator(self) -> sp.csr_matrix:
        """The row operator ``G`` (``rows_per_point`` rows per point, point-major, on the free DOFs)."""
        return self.B

    def _prescribed_states(self) -> list[np.ndarray]:
        """Values of the supported DOFs ``fixed`` at the states the solve reaches (here the one state)."""
        return [] if self.fixed_values is None else [np.asarray(self.fixed_values, dtype=float)]

    def _predicted_gaps(self) -> np.ndarray:
        r"""Gaps (6.15) of the contact points under the displacement the supports prescribe, before factorizing.

        The contact-free displacement :math:`u_{free}` is not known before the factorization,
        but the part of it that moves the body into contact as a whole is: when the values
        :math:`\bar u` of the supported DOFs are one rigid motion :math:`R a` (a bonded platen
        pressing the body, every support moved together), :math:`u = R a` satisfies every
        support and :math:`K R a = 0`, so without loads it *is* the contact-free solution.
        With :math:`R_f`, :math:`R_c` the rigid modes on the supported and on the contact
        DOFs, :math:`a = \arg\min \|R_f a - \bar u\|` and, when the fit is exact (relative
        residual below :data:`RIGID_FIT_TOL`),

        .. math::

            g^{pred}_i = g^0_i - \nu_i \cdot (R_c a)_i ;

        otherwise (supports that deform the body) :math:`g^0`. With several states (load
        steps, :meth:`_prescribed_states`) the largest gap over them. Loads are not in the
        prediction; the block is checked against the contact-free solution once it is
        known (:meth:`_start_candidates`).
        """
        g0 = self.gap0
        states = [v for v in self._prescribed_states() if v.size]
        if not states or not any(np.any(v) for v in states):
            return g0
        pts, dmap = self.model.all_node_dofs()
        where = np.empty(self.model.ndofs, dtype=np.int64)
        where[dmap.ravel()] = np.arange(dmap.size)
        dofs = np.concatenate([self.fixed, self.dofs.ravel()])
        node, comp = np.divmod(where[dofs], self.dim)
        nodes, inv = np.unique(node, return_inverse=True)
        modes, _ = rigid_body_modes(pts[nodes])  # one frame for both sets
        R = modes[inv, comp]  # (len(dofs), n_modes)
        nf = self.fixed.size
        Rf, Rc = R[:nf], R[nf:]
        out = np.full(g0.shape, -np.inf)
        for v in states:
            a = np.linalg.lstsq(Rf, v, rcond=None)[0]
            rigid = np.linalg.norm(Rf @ a - v) <= RIGID_FIT_TOL * max(np.linalg.norm(v), 1e-300)
            g = g0 - np.einsum("ij,ij->i", self.normals, (Rc @ a).reshape(g0.size, self.dim)) if rigid else g0
            out = np.maximum(out, g)
        return out

    def _schur_request(self, problem, margin: float) -> dict:
        r"""``schur=`` keyword for ``model.factorize``: the free DOFs of the points that can become candidates.

        Known before the factorization, from the predicted gaps :math:`g^0` of
        :meth:`_predicted_gaps` (the reference gaps moved by the rigid motion the supports
        prescribe: the gaps of the contact-free solution without loads): with
        :math:`g^0_{max}` the largest one, the block holds the points with

        .. math::

            g^0_i \ge \min(g^0_{max}, 0) - \text{margin}\,\max(g^0_{max}, 0) - c\,h,

        ``h`` the element size at the contact zone and :math:`c` = :data:`SCHUR_WINDOW`, i.e.
        the candidate threshold of :meth:`_select_candidates` widened by :data:`SCHUR_WINDOW` element sizes
        for what the loads add; in 2D also the movable points closest to the obstacle up to
        :data:`SCHUR_2D_DOFS` DOFs. Candidates found later outside the block get triangular
        solves (:meth:`_condensed`) or a new factorization (:meth:`_reorder_for`). At most
        :data:`SCHUR_MAX_DOFS` DOFs (the points
        closest to the obstacle). Empty when the model's ``factorize`` takes no Schur block
        or the model has fewer than :data:`SCHUR_MIN_DOFS` DOFs.
        """
        model = self.model
        if model.ndofs < SCHUR_MIN_DOFS or "schur" not in inspect.signature(model.factorize).parameters:
            return {}
        return self._schur_block(self._predicted_gaps(), margin)

    def _schur_block(self, g0: np.ndarray, margin: float) -> dict:
        """``schur=`` keyword of the points whose gap ``g0`` lies within the window of :meth:`_schur_request`."""
        # the points of _setup_points (same problem): their DOFs, free ones (pos >= 0)
        dofs = self.dofs
        keep = self.pos >= 0
        movable = keep.any(axis=1)
        if not np.any(movable):
            return {}
        gtop = float(np.max(g0[movable]))
        thr = min(gtop, 0.0) - margin * max(gtop, 0.0) - SCHUR_WINDOW * self._element_size()
        near = np.flatnonzero(movable & (g0 >= thr))
        if self.dim == 2 and near.size < SCHUR_2D_DOFS // 2:  # a line of points: the closest ones too
            closest = np.flatnonzero(movable)
            closest = closest[np.argsort(-g0[closest], kind="stable")[: SCHUR_2D_DOFS // 2]]
            near = np.union1d(near, closest)
        npts = SCHUR_MAX_DOFS // self.dim
        if near.size > npts:
            near = near[np.argsort(-g0[near], kind="stable")[:npts]]
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
        """
        schur = self._schur
        if schur is None:
            return
        G, k = self._G, self.rows_per_point
        rows = _point_rows(cand, k)
        nout = int(np.count_nonzero(~schur[2][rows] & (G.getnnz(axis=1)[rows] > 0)))
        t_solve = getattr(self, "solve_seconds", 0.0)
        # what a factorization costs (a factor reused from the model's cache took ~0 s here)
        t_factor = max(self.factor_seconds, getattr(self.factor, "factor_seconds", 0.0))
        if nout == 0 or nout * SOLVE_COLUMN_COST * t_solve <= t_factor:
            return
        block = self._schur_block(gaps, self._margin)
        if not block or np.array_equal(block["schur"], self._schur_kw.get("schur")):
            return
        logger.info("%d candidate rows lie outside the Schur block of the predicted gaps; factorizing again "
                    "with the block of the contact-free gaps", nout)
        t_fac = time.perf_counter()
        self._schur_kw = block
        self.factor = self._factor_of(None if self.spring is None else self._stabilized)  # same matrix
        self.factorizations = getattr(self, "factorizations", 1) + 1
        self.factor_seconds += time.perf_counter() - t_fac
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
        t_sol = time.perf_counter()
        self.u_free = self.factor.solve_full(self.load, self.fixed_values)
        self.solve_seconds = time.perf_counter() - t_sol
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
    factorizations = 1

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
                "linear_solve_s": max(one, self.factor.factor_seconds) + self.solve_seconds}

    def extra(self) -> dict:
        return {"linear_solver": "direct", "backend": getattr(self.factor, "backend", "superlu")}

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
