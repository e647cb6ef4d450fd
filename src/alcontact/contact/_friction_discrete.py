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
when :math:`t_T = 0` (:math:`A_{NN} = S`). ``C`` costs one triangular solve per
candidate DOF; the stiffness is factorized once for the whole load history.

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

from ..errors import InputError
from ._loading import LoadHistory, component_fields

__all__ = ["FrictionalContact", "tangent_bases"]

logger = logging.getLogger(__name__)

_BATCH = 64


#: How the rigid-motion check names this path, and the path that works without supports.
_FRICTION_PATH = "The frictional solver (solve_friction; problem file: contact.friction > 0)"
_FRICTION_WAY_OUT = ("where the contact points touching the obstacle stop these motions, solve frictionless "
                     "(solve(problem); problem file: contact.friction = 0): its direct path lets them hold the body")


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


def _element_size(model, boundary, obstacle) -> float:
    """Median facet size of the contact boundary near the obstacle."""
    f = model.facets(boundary)
    p = model.mesh.p
    v = model.mesh.facets[:, f]
    if model.dim == 2:
        size = np.linalg.norm(p[:, v[1]] - p[:, v[0]], axis=0)
    else:
        size = np.sqrt(np.linalg.norm(np.cross((p[:, v[1]] - p[:, v[0]]).T, (p[:, v[2]] - p[:, v[0]]).T), axis=1))
    g = obstacle.gap(p[:, v].mean(axis=1).T)
    near = g >= np.quantile(g, 0.9) if g.size > 10 else np.ones(g.size, bool)
    return float(np.median(size[near]))


class FrictionalContact:
    """The condensed frictional problem of a :class:`ContactProblem` under a :class:`LoadHistory`.

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
    h : float
        Contact-zone element size.
    linear_solves : int
    """

    def __init__(self, problem, history: LoadHistory, *, margin: float = 0.25):
        t0 = time.perf_counter()
        self.problem, self.history = problem, history
        model = self.model = problem.model
        self.dim = model.dim
        self.fixed, parts = component_fields(problem, history)
        t_f = time.perf_counter()
        model.check_restrained(self.fixed, path=_FRICTION_PATH, alternative=_FRICTION_WAY_OUT,
                               contact=problem.contact_boundary)
        self.factor = model.factorize(self.fixed)
        self.factor_seconds = time.perf_counter() - t_f
        self.u_parts = np.stack([self.factor.solve_full(load, fv) for fv, load in parts])  # (ncomp, ndofs)
        self.linear_solves = len(parts)
        if not np.all(np.isfinite(self.u_parts)):
            raise InputError("the contact-free solution is not finite; check loads and supports.")

        pts, dofs = model.node_dofs(problem.contact_boundary)
        self.points, self.dofs = pts, dofs
        self.weights = model.boundary_weights(problem.contact_boundary)
        self.gap0, self.normals = problem.obstacle.evaluate(pts)
        free_pos = -np.ones(model.ndofs, dtype=np.int64)
        free_pos[self.factor.free] = np.arange(self.factor.free.size)
        self.pos = free_pos[dofs]  # (m, d)
        held = self.pos < 0
        self.tangents = tangent_bases(self.normals, held)
        self.E = np.concatenate([self.normals[:, :, None], -self.tangents], axis=2)  # (m, d, d)
        # free part of each local direction (E^T restricted to the free DOFs), as ContactPoints._setup_points
        free_part = np.linalg.norm(np.where(held[:, :, None], 0.0, self.E), axis=1)  # (m, d)
        self.movable = free_part[:, 0] > 1e-12
        self.tfree = free_part[:, 1:] > 1e-12
        # local kinematics of each load component: y_k = (-nu.u_k, T^T u_k)
        self.y_parts = np.stack([self._local(u) for u in self.u_parts])  # (ncomp, m, d)
        self.h = _element_size(model, problem.contact_boundary, problem.obstacle)

        gmax_t = np.max(np.stack([self.y_free(t)[:, 0] for t in history.times]), axis=0)
        # points with a fixed normal DOF cannot move off the obstacle: error if they penetrate
        bad = ~self.movable & (gmax_t > 1e-12 * self.h)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise InputError(
                f"contact point {pts[i].tolist()} is held by a Dirichlet condition in the normal direction but "
                f"penetrates the obstacle "
                f"by {gmax_t[i]:.3e} at some load step; move the obstacle or release that support.")
        self.max_free_penetration = float(np.max(np.where(self.movable, gmax_t, -np.inf), initial=-np.inf))
        self.gmax_t = gmax_t
        gmax = self.max_free_penetration
        if gmax > 0:
            thr = -max(margin * gmax, 1e-12 * self.h)
            cand = np.flatnonzero(self.movable & (gmax_t > thr))
        else:
            cand = np.empty(0, dtype=np.int64)
        self.cand = np.empty(0, dtype=np.int64)
        self.C = np.zeros((0, 0))
        self.A = np.zeros((0, 0))
        self.add(cand)
        self.setup_seconds = time.perf_counter() - t0

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

    def add(self, new: np.ndarray) -> np.ndarray:
        """Add candidate points (one triangular solve per DOF); returns the added ones."""
        new = np.setdiff1d(np.asarray(new, dtype=np.int64), self.cand)
        new = new[self.movable[new]]
        if new.size == 0:
            return new
        d = self.dim
        old = self.cand
        allc = np.concatenate([old, new])
        cols_pos = self.pos[new].ravel()
        all_pos = self.pos[allc].ravel()
        rows = all_pos >= 0  # supported DOFs keep zero rows and columns of C
        nf = self.factor.free.size
        X = np.zeros((all_pos.size, cols_pos.size))
        cols = np.flatnonzero(cols_pos >= 0)
        for s in range(0, cols.size, _BATCH):
            j = cols[s: s + _BATCH]
            rhs = np.zeros((nf, j.size))
            rhs[cols_pos[j], np.arange(j.size)] = 1.0
            X[np.ix_(rows, j)] = self.factor.solve(rhs)[all_pos[rows]]
            self.linear_solves += j.size
        n_old = old.size * d
        C = np.zeros((all_pos.size, all_pos.size))
        C[:n_old, :n_old] = self.C
        C[:, n_old:] = X
        C[n_old:, :n_old] = X[:n_old].T
        self.C = 0.5 * (C + C.T)
        self.cand = allc
        c = allc.size
        E = self.E[allc]
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
