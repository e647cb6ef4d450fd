r"""The common base of the contact systems: contact points, candidates, declared capabilities.

At contact point ``i`` (a DOF location of the candidate boundary, reference position
:math:`X_i`, tributary length/area :math:`w_i`) the systems measure the gap with a
:class:`~alcontact.contact.kinematics.ContactKinematics` object they hold as ``kinematics``:
at small deformation the linearized gap (6.15)

.. math::

    g_i(u) = g^0_i - \nu_i \cdot u_i \le 0

(:class:`~alcontact.contact.kinematics.LinearizedGap`; :class:`ContactPoints` keeps its
reference gaps ``gap0``, normals and constant constraint rows ``B``, rows
:math:`-\nu_i^T` on the free DOFs of point ``i``), at finite deformation the gap in the current
configuration (:class:`~alcontact.contact.kinematics.CurrentGap`, set up by
:class:`~alcontact.contact.systems.FiniteContact`). :class:`ContactPoints` also selects the
candidates and holds the "not available" values of the optional members of
:class:`~alcontact.contact.systems.ContactSystem`; :func:`tangent_bases` gives the orthonormal
tangent directions of the Coulomb law (section 6.2) at each point.
"""

from __future__ import annotations

import logging

import numpy as np

from ...errors import InputError
from ._gap import LinearizedGap
from ..masters._rigid_body import RigidBody
from ._mortar import MortarKinematics, mortar_gap
from ._mortar3d import mortar_gap_3d
from ._rigid_body import rigid_body_gap
from ._stacked_gap import stacked_gap


logger = logging.getLogger(__name__)


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


#: initial overlap of two bodies (in element sizes of the slave) beyond which a warning names it
OVERLAP_TOL = 1e-3


def _one_pair_gap(problem, pair):
    """The linear gap operator of one pair whose master moves with the unknowns: a body's surface (mortar) or a
    rigid body (its pose)."""
    if isinstance(pair.slave.body, RigidBody):
        raise InputError("the slave of a contact pair is a boundary of a deformable body; a rigid body "
                         "(contact.RigidBody) is a master: ContactPair(Boundary(body, 'top'), rigid_body).")
    if isinstance(pair.master, RigidBody):  # a rigid body whose pose is unknown (kinematics._rigid_body)
        if pair.friction > 0:
            raise InputError(f"friction = {pair.friction:g} against a rigid body whose pose is solved for "
                             "(contact.RigidBody): not supported yet; use friction = 0, or a rigid obstacle moved "
                             "along a path (obstacles.move) for friction.")
        h = _element_size(pair.slave.body, pair.slave.name, pair.master)
        return rigid_body_gap(problem.model, pair.slave.body, pair.slave.name, pair.master, h)
    if pair.master.dim == 3 and pair.friction > 0:
        raise InputError(f"friction = {pair.friction:g} between two 3D bodies: two-body Coulomb friction is 2D so far; "
                         "use friction = 0 in 3D.")
    weighted = mortar_gap_3d if pair.master.dim == 3 else mortar_gap
    return weighted(problem.model, pair.slave.body, pair.slave.name, pair.master)


def pair_gap(problem, check=None):
    """The linear gap operator (a :class:`~alcontact.contact.kinematics._mortar.MortarGap`) of a problem whose pair
    has a master that moves with the unknowns: a body's surface (mortar: segment-to-segment in 2D, face-to-face in
    3D, :mod:`._mortar3d`) or a rigid body (its pose); ``None``
    against a rigid obstacle. With several pairs of which one moves, the gaps of all of them stacked into one
    (:func:`~alcontact.contact.kinematics._stacked_gap.stacked_gap`; ``check(name, pair, gap)`` is called with
    each moving pair's own). Nothing logged (:func:`mortar_of` adds the warnings of a solve). At finite
    deformation: the gaps of the reference configuration (the start of a finite run, whose current gap
    equals it at u = 0; what ``alcontact check`` reads)."""
    if all(p.rigid for p in problem.pairs):
        return None
    if len(problem.pairs) > 1:
        if any(isinstance(p.master, RigidBody) for p in problem.pairs):
            raise InputError("a rigid body whose pose is solved for (contact.RigidBody) is the master of a pair on "
                             "its own so far; beside other pairs give it as a rigid obstacle moved by the load "
                             "steps, or solve its pair alone.")
        return stacked_gap(problem, lambda p: _element_size(p.slave.body, p.slave.name, p.master),
                           lambda p: _one_pair_gap(problem, p), check)
    return _one_pair_gap(problem, problem.pairs[0])


def mortar_of(problem):
    """The :class:`~alcontact.contact.kinematics._mortar.MortarGap` of a problem whose pair has a deformable
    master (``None`` against a rigid one), :func:`pair_gap`, with a warning when a pair cannot come into contact
    or the bodies overlap at the start."""
    if len(problem.pairs) > 1:
        return pair_gap(problem, lambda name, pair, mg: _check_mortar(problem, name, pair, mg))
    mg = pair_gap(problem)
    if mg is None:
        return None
    return _check_mortar(problem, problem.contact_boundary, problem.pairs[0], mg)


def _check_mortar(problem, name: str, pair, mg):
    """``mg``, the weighted gaps of ``pair`` (slave boundary ``name`` of the model), after the warnings of a pair
    that cannot come into contact or whose bodies overlap at the start."""
    where = f"contact pair {name!r} / {pair.master.describe()}"
    if not np.any(mg.covered):
        logger.warning("%s: no slave node has a master segment or face within the search distance, so the pair cannot "
                       "come into contact; check the boundaries, or give BodySurface(..., search_distance=...)", where)
    else:
        g = np.where(mg.covered, mg.gap0, -np.inf)
        i = int(np.argmax(g))
        if g[i] > OVERLAP_TOL * mg.h:
            pts, _ = problem.model.node_dofs(name)
            logger.warning("%s: the bodies overlap at the start by %.3g at slave node %s (%.2g element sizes); "
                           "check the geometry, or expect the contact to push them apart", where, g[i],
                           np.round(pts[i], 6).tolist(), g[i] / mg.h)
    return mg


def _point_rows(points: np.ndarray, k: int) -> np.ndarray:
    """Rows ``i*k .. i*k + k - 1`` of every point ``i`` (point-major)."""
    return (np.asarray(points, dtype=np.int64)[:, None] * k + np.arange(k)).ravel()


class ContactPoints:
    """Contact points of a problem: geometry, linearized gaps (6.15), candidates.

    Shared by the condensed direct paths (:class:`CondensedContact`: frictionless
    :class:`DiscreteContact`, frictional
    :class:`~alcontact.contact.systems._condensed.FrictionalContact`), the
    factorization-free one (:class:`~alcontact.contact.systems._krylov.IterativeContact`)
    and finite deformation. Subclasses call :meth:`_setup_points` with their free
    DOFs, then :meth:`_setup_candidates` (or :meth:`_select_candidates`).

    It also holds the *not available* values of the optional members of
    :class:`~alcontact.contact.systems._protocol.ContactSystem` (no warm start, the plain semi-smooth
    rule, no multiplier shift, no second-order update); a model with the capability overrides them.
    """

    # ---- ContactSystem: declared capabilities, "not available" on a model without them
    inexact_subproblems = False
    #: Newton tolerance of the first inexact subproblem (finite deformation's, tuned on the ironing of issue 18)
    inexact_first_tol = 1e-2
    #: the weighted gaps of a pair with a deformable master (:func:`mortar_of`); None against a rigid one
    mortar = None
    physical_stopping = False
    warm_penalty_start = False
    penalty_continuation = False
    carried_stiffness: float | None = None
    active_converged = True
    active_residual = float("nan")

    def initial_multipliers(self) -> np.ndarray:
        """No warm start: zero multipliers on the candidates (:class:`~alcontact.contact.systems._protocol.ContactSystem`)."""
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
        """Points, DOFs, weights and the linearized gap (6.15) (``kinematics``) for the DOFs ``free``.

        ``pos`` (m, d): position of each point DOF in the free numbering (-1 when
        supported); ``gap0``, ``normals``, ``B``: the reference gaps, normals and constraint
        rows :math:`-\\nu_i^T` of the kinematics (constant: its configuration is the reference
        one); ``movable``: the normal motion is not fully supported (the point may be a candidate).
        """
        model = problem.model
        pts, dofs = problem.slave_nodes()  # every pair's slave points, stacked in the pairs' order
        self.mortar = mortar_of(problem)
        # position of each DOF in the free vector (-1 when fixed)
        free_pos = -np.ones(model.ndofs, dtype=np.int64)
        free_pos[free] = np.arange(free.size)
        pos = free_pos[dofs]  # (m, d)
        #: the linearized gap (6.15) against the master, or a deformable master's mortar gap
        #: (:class:`~alcontact.contact.kinematics.ContactKinematics`)
        if self.mortar is None:
            self.kinematics = kin = LinearizedGap(pts, dofs, pos, problem.obstacle, free.size)
            w = problem.slave_weights()
        else:  # the weighted gaps couple both bodies (kinematics._mortar)
            self.kinematics = kin = MortarKinematics(self.mortar, pts, dofs, pos, problem.obstacle, free)
            w = self.mortar.weights
        # its configuration is the reference one: gaps, normals and constraint rows at u = 0 hold for every u
        ref = kin.evaluate(np.zeros(model.ndofs))
        self.points, self.dofs, self.weights = pts, dofs, w
        self.normals, self.gap0, self.pos, self.B = ref.normals, ref.g, pos, ref.gradient()
        self.movable = np.linalg.norm(np.where(pos >= 0, -ref.normals, 0.0), axis=1) > 1e-12
        if self.mortar is not None:
            self.movable = self.mortar.covered & (self.B.getnnz(axis=1) > 0)

    def force_points(self, nodal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r"""``(dofs, forces)``, each ``(k, d)``: the contact force on the bodies of the normal nodal forces
        ``nodal`` (:math:`r = w\circ\lambda`), per node it acts on: :math:`r_i \nu_i` on the contact points
        against a rigid master; with a master that moves with the unknowns (:math:`-B^T r`), on every DOF
        of the gap operator ``B`` (slave and master nodes of a mortar pair, the rigid body's translation and
        rotation DOFs), then ``(n,)`` each."""
        nodal = np.asarray(nodal, dtype=float)
        if self.mortar is None:
            return self.dofs, nodal[:, None] * self.normals
        fc = self.mortar.contact_force(nodal)
        cols = np.unique(self.mortar.B.indices).astype(np.int64)
        return cols, fc[cols]

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
        if self.mortar is not None:
            return self.mortar.h
        key = (self.model, self.problem.obstacle, self.problem.contact_boundary)
        cached = getattr(self, "_h_of", None)
        if cached is None or cached[0][0] is not key[0] or cached[0][1] is not key[1] or cached[0][2] != key[2]:
            cached = self._h_of = (key, min(_element_size(key[0], p.slave.name, p.master)
                                            for p in self.problem.pairs))
        return cached[1]

    def all_gaps(self, u: np.ndarray) -> np.ndarray:
        """Linearized gaps (6.15) of every contact-boundary point for displacement ``u``."""
        return self.kinematics.gaps(u)

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


def tangent_bases(normals: np.ndarray, held: np.ndarray | None = None) -> np.ndarray:
    """Orthonormal tangent bases ``T`` of shape ``(m, d, d-1)`` for unit normals ``(m, d)``.

    One reference axis ``e`` (the global axis least aligned with the mean
    normal) is projected on every tangent plane, so neighbouring points of a
    curved obstacle get consistent, smoothly varying bases; points where ``e``
    is nearly normal use the next axis. 3D: ``T_2 = nu x T_1``.

    ``held`` (bool ``(m, d)``, optional) marks supported global axes of each
    point. A held axis orthogonal to the normal (to round-off) becomes the first
    tangent of that point, so that the supported tangential motion is one
    tangent direction exactly (in 3D, ``T_2 = nu x e_k`` is then the other held
    axis too when both tangential axes are supported).
    """
    nu = np.asarray(normals, dtype=float)
    m, d = nu.shape
    mean = nu.mean(axis=0) if m else np.eye(d)[-1]
    order = np.argsort(np.abs(mean))
    e = np.zeros((m, d))
    e[:, order[0]] = 1.0
    bad = np.abs(nu[:, order[0]]) > 0.9
    e[bad] = 0.0
    e[bad, order[1]] = 1.0
    if held is not None:
        tangential = np.asarray(held, bool) & (np.abs(nu) <= 1e-12)
        rows = np.flatnonzero(tangential.any(axis=1))
        e[rows] = 0.0
        e[rows, np.argmax(tangential[rows], axis=1)] = 1.0
    t1 = e - np.einsum("ij,ij->i", e, nu)[:, None] * nu
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    if d == 2:
        return t1[:, :, None]
    t2 = np.cross(nu, t1)
    return np.stack([t1, t2], axis=2)
