r"""The contact pair between two bodies before any solve: reference gaps, overlap, facing, what holds each body.

What ``alcontact check`` needs to refuse or warn about a problem of several bodies without
solving it (:func:`pair_start`): the reference gaps of the slave points against the moving
master (the mortar weighted gaps of a body's surface, the gaps against a rigid body's shape),
the deepest overlap and where, the distance between the surfaces, whether the master faces the
slave at all, and the free rigid motions of the bodies that neither the supports nor the
touching contact points stop (:meth:`PairStart.free_motions`, the linearized test that the
factorization of a condensed solve makes).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ...errors import InputError
from ..masters._mortar import BodySurface, boundary_segments
from ..masters._rigid_body import RigidBody
from ._points import OVERLAP_TOL, pair_gap

#: touching points: within this many slave element sizes of the closest one (as a condensed solve finds them)
TOUCH = 0.5


@dataclass(frozen=True)
class PairStart:
    """The pair of a problem of several bodies in the reference configuration (module doc).

    Attributes
    ----------
    label : str
        ``"<slave boundary> / <master>"`` for messages.
    points : ndarray (m, d)
        The slave points.
    gaps : ndarray (m,)
        Their reference gaps (``> 0``: overlap); ``-inf`` where no master lies within the search distance.
    covered : ndarray of bool (m,)
    h : float
        Slave element size near the master.
    B : scipy.sparse.csr_matrix (m, ndofs)
        The constant gap operator :math:`g = g^0 + B u`.
    facing_away : bool
        Master segments lie within the search distance of the slave but none faces it (their outward
        normals point away from the slave's): the master is the wrong side of its body.
    overlap_tol : float
        Overlap (length) below which the bodies count as touching.
    """

    label: str
    points: np.ndarray
    gaps: np.ndarray
    covered: np.ndarray
    h: float
    B: sp.csr_matrix
    facing_away: bool
    overlap_tol: float

    @property
    def deepest(self) -> tuple[float, np.ndarray] | None:
        """``(overlap, slave point)`` of the deepest reference overlap, ``None`` when nothing is covered."""
        if not np.any(self.covered):
            return None
        i = int(np.argmax(np.where(self.covered, self.gaps, -np.inf)))
        return float(self.gaps[i]), self.points[i]

    def touching(self) -> np.ndarray:
        """The slave points within :data:`TOUCH` element sizes of the closest one, when that one is within
        :data:`TOUCH` element sizes of the master (the contact may hold the bodies there)."""
        g = np.where(self.covered, self.gaps, -np.inf)
        if not np.any(self.covered) or g.max() < -TOUCH * self.h:
            return np.empty(0, dtype=np.int64)
        return np.flatnonzero(self.covered & (g >= g.max() - TOUCH * self.h))

    def free_motions(self, model, fixed) -> list[tuple[int, list[str]]]:
        """``[(body index, names of its free motions)]``: rigid motions of the bodies of ``model`` (a
        :class:`~alcontact.fem.MultiBody`) that vanish on the ``fixed`` DOFs and do not change the gap of any
        touching slave point (frictionless contact holds the normal motion only)."""
        R, owner, names = _modes(model)
        rows = [R[np.asarray(fixed, dtype=np.int64)]]
        near = self.touching()
        if near.size:
            rows.append(np.asarray(self.B[near] @ R))
        C = np.vstack(rows)
        scale = np.abs(C).max(initial=0.0)
        _, sv, vt = np.linalg.svd(C, full_matrices=True)
        rank = int(np.sum(sv > 1e-10 * max(scale, 1e-300) * max(C.shape)))
        null = vt[rank:]  # (k, K) free combinations of the modes
        out = []
        for b in range(len(model.bodies)):
            cols = np.flatnonzero(owner == b)
            part = null[:, cols]
            if np.max(np.abs(part), initial=0.0) <= 1e-8:
                continue
            _, s2, v2 = np.linalg.svd(part, full_matrices=False)
            free = [names[cols[int(np.argmax(np.abs(v)))]] for v, s in zip(v2, s2) if s > 1e-8]
            out.append((b, sorted(set(free), key=free.index)))
        return out


def _modes(model):
    """Rigid modes of every body (``(ndofs, K)``), the body of each column, and a name per column."""
    R = model.rigid_modes()
    body_of = model.body_of_dofs()
    owner = np.array([body_of[int(np.flatnonzero(R[:, j])[0])] for j in range(R.shape[1])])
    standard = ["u_x", "u_y", "rot_z"] if model.dim == 2 else ["u_x", "u_y", "u_z", "rot_x", "rot_y", "rot_z"]
    names = []
    for b, body in enumerate(model.bodies):
        k = int(np.sum(owner == b))
        own = body.dof_names if isinstance(body, RigidBody) else standard
        names += own if len(own) == k else [f"mode {j + 1}" for j in range(k)]
    return R, owner, names


def _faces_away(pair, search: float) -> bool:
    """Master segments within ``search`` of the slave's, none facing them (``n_m . n_s >= 0`` for all)."""
    ss, ms = boundary_segments(pair.slave.body, pair.slave.name), pair.master.segments
    mid_s = 0.5 * (ss.points[ss.ends[:, 0]] + ss.points[ss.ends[:, 1]])
    mid_m = 0.5 * (ms.points[ms.ends[:, 0]] + ms.points[ms.ends[:, 1]])
    radius = search + 0.5 * (float(ss.lengths.max()) + float(ms.lengths.max()))
    near = cKDTree(mid_m).query_ball_point(mid_s, r=radius)
    pairs = [(s, c) for s, cand in enumerate(near) for c in cand]
    if not pairs:
        return False
    s, c = np.array(pairs).T
    return bool(np.all(np.einsum("ij,ij->i", ss.normals[s], ms.normals[c]) >= 0.0))


def pair_start(problem) -> PairStart | None:
    """:class:`PairStart` of a problem whose pair has a master that moves (a body's surface, a rigid body);
    ``None`` for a rigid obstacle.

    Raises
    ------
    alcontact.errors.InputError
        What the gap operator refuses (finite kinematics, a 3D or curved mortar pair).
    """
    from ..problem._problem import ContactProblem

    if not isinstance(problem, ContactProblem):
        raise InputError(f"pair_start: problem = {type(problem).__name__}: expected a ContactProblem.")
    mg = pair_gap(problem)
    if mg is None:
        return None
    pair = problem.pairs[0]
    pts, _ = pair.slave.body.node_dofs(pair.slave.name)
    facing_away = False
    if isinstance(pair.master, BodySurface) and not np.any(mg.covered):
        ext = max(float(np.ptp(pts, axis=0).max()), float(np.ptp(pair.master.segments.points, axis=0).max()))
        search = pair.master.search_distance if pair.master.search_distance is not None else 0.25 * ext
        facing_away = _faces_away(pair, search)
    return PairStart(label=f"{problem.contact_boundary!r} on {pair.master.describe()}", points=pts,
                     gaps=np.where(mg.covered, mg.gap0, -np.inf), covered=mg.covered, h=mg.h, B=mg.B,
                     facing_away=facing_away, overlap_tol=OVERLAP_TOL * mg.h)
