r"""Discrete frictional contact condensed on all displacement components of the contact points.

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

which reduces to :math:`g = g_{free} - S r` of :mod:`alcontact.contact._discrete`
when :math:`t_T = 0` (:math:`A_{NN} = S`). The setup is the frictionless one
(:class:`~alcontact.contact._discrete.CondensedContact`: points, candidates, the one
factorization of the stiffness for the whole load history with its backend and Schur
block, the springs of a body held by the obstacle); ``C`` is its condensed operator for
the row operator :math:`P`: entries between points inside the Schur block come from the
Schur complement, the others cost one triangular solve per free candidate DOF.

Supported components. As in the frictionless :class:`~alcontact.contact._discrete.ContactPoints`,
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

import logging
import time

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ._discrete import CondensedContact
from ._loading import LoadHistory, component_fields

__all__ = ["FrictionalContact", "tangent_bases"]

logger = logging.getLogger(__name__)


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


class FrictionalContact(CondensedContact):
    """The condensed frictional problem of a :class:`ContactProblem` under a :class:`LoadHistory`.

    The frictionless setup extended (:class:`~alcontact.contact._discrete.CondensedContact`:
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
        """Solver counters for the solution's ``extra``: none on the direct path (the AMG path adds its own)."""
        return {}

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
        t_sol = time.perf_counter()
        self.u_parts = np.stack([self.factor.solve_full(load, fv) for fv, load in parts])  # (ncomp, ndofs)
        self.solve_seconds = (time.perf_counter() - t_sol) / len(parts)  # one solve
        self.linear_solves = len(parts)
        if not np.all(np.isfinite(self.u_parts)):
            raise InputError("the contact-free solution is not finite; check loads and supports.")

        held = self.pos < 0
        self.tangents = tangent_bases(self.normals, held)
        self.E = np.concatenate([self.normals[:, :, None], -self.tangents], axis=2)  # (m, d, d)
        # free part of each tangent direction (E^T restricted to the free DOFs; column 0 gives ``movable``)
        free_part = np.linalg.norm(np.where(held[:, :, None], 0.0, self.E), axis=1)  # (m, d)
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

    def _prescribed_states(self) -> list[np.ndarray]:
        """Values of the supported DOFs at every load step (the Schur block sees the supports' motion)."""
        return [self.amplitudes(t) @ self.fv_parts for t in self.history.times]

    @property
    def rows_per_point(self) -> int:
        """``d``: the row operator :math:`P` has one row per displacement component of a point."""
        return self.dim

    def _row_operator(self) -> sp.csr_matrix:
        """:math:`P`: row ``i*d + k`` selects free DOF ``k`` of point ``i`` (a zero row when it is supported)."""
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
        <alcontact.contact._discrete.CondensedContact._stabilize>` chooses the points).
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
        r"""Springs :math:`\kappa w_i` on every free component of the points ``near`` (full numbering)."""
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
        np.add.at(fc, self.dofs.ravel(), np.einsum("ijk,ik->ij", self.E, R).ravel())
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
        if self.spring is None:
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
    def _local(self, u: np.ndarray) -> np.ndarray:
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
