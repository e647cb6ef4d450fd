r"""Mortar weighted gaps between two bodies (2D, P1 or P2 straight segments, dual multipliers), small deformation.

For a slave boundary :math:`\Gamma_s` with shape functions :math:`N_j` and the dual
(biorthogonal) basis :math:`\Phi_j` (P1, on a segment with nodes ``a, b`` and parameter
:math:`\xi \in [0, 1]`: :math:`\Phi_a = 2 - 3\xi`, :math:`\Phi_b = 3\xi - 1`; P2:
:func:`dual_coefficients`; so that :math:`\int \Phi_j N_k\,ds = \delta_{jk} \int N_j\,ds`),
the weighted gap of slave node ``j`` is

.. math::

    \tilde g_j = \int_{\Gamma_s} \Phi_j\, (x_s - x_m\circ\chi)\cdot n_j \, ds
              = n_j \cdot \Big(D_j\, x_j - \sum_k M_{jk}\, y_k\Big), \qquad
    D_j = \int N_j\,ds, \quad M_{jk} = \int \Phi_j\, N^m_k\circ\chi \, ds,

with :math:`\chi` the projection of the slave segment onto the master segments (along the
slave segment's normal), :math:`x_j`, :math:`y_k` the current slave and master node
positions and :math:`n_j = -\nu_j` one unit normal per slave node: :math:`\nu_j` the master's
outward nodal normals averaged with the weights :math:`M_{jk}` (the master normal seen by node
``j``; constant over the support of :math:`\Phi_j`, which keeps ``D`` diagonal). Against a
flat master, :math:`g_j` is then exactly the distance of slave node ``j`` to the master line
(the integrand is linear on each slave segment), i.e. the node-to-surface gap (6.15) of a
rigid obstacle of the same shape: the rigid limit is exact. ``D`` is diagonal thanks to the dual basis, so the constraints stay one per slave
node and the nodal augmented Lagrangian of chapter 6 carries over: the normalized gap
:math:`g_j = \tilde g_j / D_j \le 0` (a length, feasible when non-positive) with the
tributary length :math:`w_j = D_j` as the weight of the pressure :math:`\lambda_j`. At small
deformation (:math:`x = X + u`) it is linear:

.. math::

    g = g^0 + B u, \qquad B_{j, s(j)} = n_j^T, \qquad B_{j, m(k)} = -\frac{M_{jk}}{c_j D_j}\, n_j^T ,

where :math:`c_j = \sum_k M_{jk} / D_j` is the part of node ``j``'s support covered by the
master (1 when covered; the master weights are divided by it so that a rigid translation of
both bodies never changes a gap). The contact force on the bodies is :math:`-B^T (w \circ
\lambda)`: on slave node ``j`` :math:`-w_j\lambda_j n_j`, on master node ``k``
:math:`\sum_j w_j \lambda_j (M_{jk}/\sum_l M_{jl})\, n_j`, so the forces on the two bodies sum
to zero exactly (action = reaction). A slave node whose support the master covers for less
than :data:`COVER_MIN` of its length (no master within the search distance) is *open*: its
gap is the search distance below zero and it cannot become a candidate.

Candidate master segments of each slave segment come from a :class:`scipy.spatial.cKDTree`
on the master segment midpoints (:math:`O(n \log n)` in the number of segments); at small
deformation the search runs once per solve. Segments whose normals do not face each other
(:math:`n_s \cdot n_m \ge 0`) are not paired.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ..masters._mortar import BodySurface, boundary_segments, shape_functions
from ._gap import GapEvaluation

#: a slave node counts as covered by the master when the master overlaps at least this part of its support
COVER_MIN = 0.5

_GAUSS_X = np.array([0.5 - np.sqrt(0.15), 0.5, 0.5 + np.sqrt(0.15)])  # 3-point Gauss on [0, 1]
_GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


@dataclass(frozen=True)
class MortarGap:
    """The linear weighted gap ``g = gap0 + B u`` of a two-body pair (module doc).

    Attributes
    ----------
    gap0 : ndarray (m,)
        Normalized weighted gaps of the slave nodes in the reference configuration.
    B : scipy.sparse.csr_matrix (m, ndofs)
        Gap operator on every DOF of the model (slave and master bodies).
    weights : ndarray (m,)
        :math:`D_j`, the slave tributary lengths.
    normals : ndarray (m, 2)
        :math:`\\nu_j = -n_j`, the master normal at each slave node, pointing out of the master towards
        the slave (the obstacle convention); the slave's own normal at an uncovered node.
    covered : ndarray of bool (m,)
        Slave nodes whose support the master covers (:data:`COVER_MIN`).
    h : float
        Median slave segment length near the master.
    master_dofs : ndarray of int (k, 2)
        DOFs of the master boundary nodes (model numbering).
    """

    gap0: np.ndarray
    B: sp.csr_matrix
    weights: np.ndarray
    normals: np.ndarray
    covered: np.ndarray
    h: float
    master_dofs: np.ndarray

    def contact_force(self, nodal: np.ndarray) -> np.ndarray:
        r"""Contact force vector :math:`-B^T r` on all DOFs for the nodal normal forces :math:`r = w\circ\lambda`."""
        return -(self.B.T @ np.asarray(nodal, dtype=float))


def _integrals(k: int) -> np.ndarray:
    """:math:`\\int_0^1 N_i\\,d\\xi` of the ``k`` shape functions of a segment (ends, then midpoint)."""
    return np.array([0.5, 0.5]) if k == 2 else np.array([1.0, 1.0, 4.0]) / 6.0


def dual_coefficients(k: int) -> np.ndarray:
    r"""``A`` with :math:`\Phi_i = \sum_k A_{ik} N_k` biorthogonal to the ``k`` shape functions of a segment.

    :math:`A = D \hat M^{-1}`, :math:`\hat M_{ik} = \int_0^1 N_i N_k\,d\xi`, :math:`D = \mathrm{diag}(\int_0^1
    N_i\,d\xi)`, so that :math:`\int \Phi_i N_k = \delta_{ik} \int N_i` and :math:`\sum_i \Phi_i = 1`.
    P1: :math:`\Phi_a = 2 - 3\xi`, :math:`\Phi_b = 3\xi - 1`.
    """
    xg, wg = np.polynomial.legendre.leggauss(4)
    xg, wg = 0.5 * (xg + 1.0), 0.5 * wg
    N = np.array(shape_functions(xg, k))  # (k, q)
    M = (N * wg) @ N.T
    return np.diag(_integrals(k)) @ np.linalg.inv(M)


def _offset(model, body) -> int:
    """First DOF of ``body`` in the numbering of ``model`` (the body itself, or a stack of bodies)."""
    if body is model:
        return 0
    for b, off in zip(getattr(model, "bodies", ()), getattr(model, "offsets", ())):
        if b is body:
            return int(off)
    raise ValueError("the body is not part of the model")


def mortar_gap(model, slave_body, slave_name: str, master: BodySurface) -> MortarGap:
    """The weighted gap (module doc) of the slave boundary against a :class:`BodySurface`.

    With ``master.method == "node-to-segment"`` the master point of slave node ``j`` is its
    closest point on the master segments (collocation at the slave nodes, :func:`_node_to_segment`)
    instead of the mortar integrals: the simpler discretization that does not pass the contact
    patch test on non-matching meshes.

    Parameters
    ----------
    model : alcontact.fem.LinearElasticity or alcontact.fem.MultiBody
        The discretized bodies (DOF numbering of ``B``).
    slave_body, slave_name
        The slave boundary (its body and the body's own boundary name).
    master : BodySurface
        The master boundary.
    """
    ss = boundary_segments(slave_body, slave_name)
    ms = master.segments
    extent = max(float(np.ptp(ss.points, axis=0).max()), float(np.ptp(ms.points, axis=0).max()))
    search = master.search_distance if master.search_distance is not None else 0.25 * extent
    D = np.zeros(ss.points.shape[0])  # D_j = int N_j ds, the tributary lengths
    for i, w in enumerate(_integrals(ss.nodes.shape[1])):
        np.add.at(D, ss.nodes[:, i], w * ss.lengths)
    if getattr(master, "method", "mortar") == "node-to-segment":
        P, covered = _node_to_segment(ss, ms, search)
    else:
        P, covered = _mortar_weights(ss, ms, search, D)
    return _assemble(model, slave_body, master, ss, ms, P, covered, D, search)


def _node_to_segment(ss, ms, search: float):
    """Collocation: each slave node's closest point on the facing master segments within ``search``."""
    m = ss.points.shape[0]
    ya, yb = ms.points[ms.ends[:, 0]], ms.points[ms.ends[:, 1]]
    radius = search + 0.5 * float(ms.lengths.max())
    cands = cKDTree(0.5 * (ya + yb)).query_ball_point(ss.points, r=radius)
    n_slave = ss.node_normals()
    rows, cols, vals = [], [], []
    covered = np.zeros(m, dtype=bool)
    for j, cand in enumerate(cands):
        c = np.asarray(cand, dtype=np.int64)
        c = c[ms.normals[c] @ n_slave[j] < 0.0] if c.size else c
        if c.size == 0:
            continue
        t = yb[c] - ya[c]
        eta = np.einsum("ij,ij->i", ss.points[j] - ya[c], t) / np.einsum("ij,ij->i", t, t)
        inside = (eta >= -1e-9) & (eta <= 1 + 1e-9)
        if not np.any(inside):
            continue
        c, eta = c[inside], np.clip(eta[inside], 0.0, 1.0)
        y = ya[c] + eta[:, None] * (yb[c] - ya[c])
        k = int(np.argmin(np.linalg.norm(ss.points[j] - y, axis=1)))
        N = shape_functions(np.array([eta[k]]), ms.nodes.shape[1])
        rows += [j] * len(N)
        cols += [int(n) for n in ms.nodes[c[k]]]
        vals += [float(v[0]) for v in N]
        covered[j] = True
    P = sp.csr_matrix((vals, (rows, cols)), shape=(m, ms.points.shape[0]))
    return P, covered


def _mortar_weights(ss, ms, search: float, D: np.ndarray):
    """The mortar matrix ``M`` (dual basis, segment-to-segment integrals) normalized by its row sums."""
    m, km = ss.points.shape[0], ms.points.shape[0]
    xa, xb = ss.points[ss.ends[:, 0]], ss.points[ss.ends[:, 1]]
    ya, yb = ms.points[ms.ends[:, 0]], ms.points[ms.ends[:, 1]]
    radius = search + 0.5 * (float(ss.lengths.max()) + float(ms.lengths.max()))
    tree = cKDTree(0.5 * (ya + yb))
    cands = tree.query_ball_point(0.5 * (xa + xb), r=radius)
    ks, km_loc = ss.nodes.shape[1], ms.nodes.shape[1]
    A = dual_coefficients(ks)
    rows, cols, vals = [], [], []
    for s, cand in enumerate(cands):
        if not cand:
            continue
        c = np.asarray(cand, dtype=np.int64)
        c = c[ms.normals[c] @ ss.normals[s] < 0.0]  # facing segments only
        if c.size == 0:
            continue
        L = ss.lengths[s]
        t = (xb[s] - xa[s]) / L
        xi_a = (ya[c] - xa[s]) @ t / L  # master ends projected on the slave segment (along its normal)
        xi_b = (yb[c] - xa[s]) @ t / L
        lo = np.maximum(0.0, np.minimum(xi_a, xi_b))
        hi = np.minimum(1.0, np.maximum(xi_a, xi_b))
        ok = (hi - lo > 1e-12) & (np.abs(xi_b - xi_a) > 1e-12)
        if not np.any(ok):
            continue
        c, xi_a, xi_b, lo, hi = c[ok], xi_a[ok], xi_b[ok], lo[ok], hi[ok]
        xq = lo[:, None] + (hi - lo)[:, None] * _GAUSS_X[None, :]  # (k, 3) slave parameters
        wq = (L * (hi - lo))[:, None] * _GAUSS_W[None, :]
        eta = (xq - xi_a[:, None]) / (xi_b - xi_a)[:, None]  # master parameter from end a to end b
        Ns = shape_functions(xq, ks)
        phi = [sum(A[i, k] * Ns[k] for k in range(ks)) for i in range(ks)]
        nm = shape_functions(eta, km_loc)
        for i in range(ks):
            for k in range(km_loc):
                rows.append(np.full(c.size, ss.nodes[s, i]))
                cols.append(ms.nodes[c, k])
                vals.append(np.sum(phi[i] * nm[k] * wq, axis=1))
    if rows:
        M = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(m, km))
    else:
        M = sp.csr_matrix((m, km))
    total = np.asarray(M.sum(axis=1)).ravel()
    covered = total >= COVER_MIN * D
    scale = np.where(covered, 1.0 / np.where(covered, total, 1.0), 0.0)
    return sp.diags(scale) @ M, covered  # rows of covered nodes sum to 1: a weighted master point per slave node


def _assemble(model, slave_body, master, ss, ms, P, covered, D, search: float) -> MortarGap:
    """:class:`MortarGap` of the master weights ``P`` (rows summing to 1 on the ``covered`` slave nodes)."""
    m = ss.points.shape[0]
    off_s, off_m = _offset(model, slave_body), _offset(model, master.body)
    n_node = ss.node_normals()
    y_bar = P @ ms.points  # (m, 2)
    nu = P @ ms.node_normals()  # the master normal carried to each slave node
    norm = np.linalg.norm(nu, axis=1, keepdims=True)
    n_node = np.where(covered[:, None] & (norm > 0), -nu / np.where(norm > 0, norm, 1.0), n_node)
    gap0 = np.where(covered, np.einsum("ij,ij->i", ss.points - y_bar, n_node), -search)
    # B: n_j on the slave node's DOFs, -P_jk n_j on the master nodes' DOFs
    ndofs = int(model.ndofs)
    j_s = np.flatnonzero(covered)
    r_s = np.repeat(j_s, 2)
    c_s = (ss.dofs[j_s] + off_s).ravel()
    v_s = n_node[j_s].ravel()
    Pc = P.tocoo()
    r_m = np.repeat(Pc.row, 2)
    c_m = (ms.dofs[Pc.col] + off_m).ravel()
    v_m = (-Pc.data[:, None] * n_node[Pc.row]).ravel()
    B = sp.csr_matrix((np.concatenate([v_s, v_m]), (np.concatenate([r_s, r_m]), np.concatenate([c_s, c_m]))),
                      shape=(m, ndofs))
    B.sum_duplicates()
    near = covered if np.any(covered) else np.ones(m, bool)
    seg_near = near[ss.ends].any(axis=1)
    h = float(np.median(ss.lengths[seg_near]))
    return MortarGap(gap0=gap0, B=B, weights=D, normals=-n_node, covered=covered, h=h,
                     master_dofs=ms.dofs + off_m)


class MortarKinematics:
    r"""The mortar weighted gap as a :class:`~alcontact.contact.kinematics.ContactKinematics`.

    Linearized at the reference configuration (small deformation), like
    :class:`~alcontact.contact.kinematics.LinearizedGap`, but not pointwise: the row of slave
    node ``j`` couples its own DOFs with those of the master segment nodes it sees
    (:math:`g = g^0 + B u`, module doc). No Hessian: the gap is linear in ``u``.

    Parameters
    ----------
    gap : MortarGap
        The pair's weighted gaps and gap operator on every DOF of the model.
    points, dofs, pos : ndarray
        The slave nodes, their DOFs and the DOFs' positions in the free vector (``-1`` when fixed).
    master : BodySurface
        The master surface.
    free : ndarray of int
        The free DOFs (columns of :meth:`evaluate`'s gradient).
    """

    configuration = "reference"
    pointwise = False

    def __init__(self, gap: MortarGap, points, dofs, pos, master, free: np.ndarray):
        self.mortar, self.points, self.dofs, self.pos, self.master = gap, points, dofs, pos, master
        self._rows = gap.B[:, free].tocsr()
        self._nfree = int(free.size)

    def gaps(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        if idx is None:
            return self.mortar.gap0 + self.mortar.B @ u
        return self.mortar.gap0[idx] + self.mortar.B[idx] @ u

    def evaluate(self, u: np.ndarray, idx: np.ndarray | None = None, *, hessian: bool = False) -> GapEvaluation:
        idx = np.arange(self.points.shape[0]) if idx is None else np.asarray(idx, dtype=np.int64)
        d = self.pos.shape[1]
        H = np.zeros((idx.size, d, d)) if hessian else None
        return GapEvaluation(idx, self.gaps(u, idx), self.mortar.normals[idx], H, self.pos[idx], self._nfree,
                             gradient=self._rows[idx])

    def current(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        if idx is None:
            return self.points + u[self.dofs]
        return self.points[idx] + u[self.dofs[idx]]

    def against(self, master):
        """A mortar gap is built for its master surface: another master needs a new pair."""
        raise ValueError("a mortar gap belongs to its master surface; build the pair again for another master")
