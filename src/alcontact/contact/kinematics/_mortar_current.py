r"""The mortar weighted gap between two bodies in the current configuration (2D, P1, finite deformation).

The gap of :mod:`alcontact.contact.kinematics._mortar` measured at the current positions
:math:`x = X + u` of both bodies instead of the reference ones. Slave node ``j`` (current
position :math:`x_j`) has the weighted gap

.. math::

    \tilde g_j = \int_{\Gamma_s} \Phi_j\, (x_s - x_m\circ\chi)\cdot n_j\, ds
               = n_j \cdot \Big(D_j x_j - \sum_k M_{jk}\, y_k\Big), \qquad
    M_{jk} = \int_{\Gamma_s} \Phi_j\, N^m_k\circ\chi\, ds ,

all quantities of the current configuration: the slave segments' current lengths in
:math:`ds`, the projection :math:`\chi` of each current slave segment onto the current master
segments along the slave segment's normal (the mortar segment end points are the slave ends and
the projections of the master ends, clipped to the segment), the dual basis
:math:`\Phi_a = 2 - 3\xi`, :math:`\Phi_b = 3\xi - 1` on the slave segment, the master nodes'
current positions :math:`y_k`, and the normal :math:`n_j = -\nu_j/|\nu_j|`,
:math:`\nu_j = \sum_k M_{jk}\,\nu^m_k`, with :math:`\nu^m_k` the master's current nodal normals
(the normalized sum of the normals of the master segments at node ``k``). As at small
deformation, the constraint is the normalized gap

.. math::

    g_j = n_j\cdot(x_j - \bar y_j), \qquad \bar y_j = \frac{\sum_k M_{jk} y_k}{\sum_k M_{jk}} ,

feasible when :math:`g_j \le 0`, with the *reference* tributary length
:math:`w_j = D^0_j = \int_{\Gamma_s^0} N_j\, dS` as the weight of its multiplier (a nominal
pressure): the contact virtual work is :math:`\sum_j w_j \lambda_j\, \delta g_j`. At
:math:`u = 0` the gap is the small-deformation one, :math:`g(0) = g^0`.

Consistent linearization. Every quantity above is a smooth function of the current
coordinates of one slave segment's ends and of one master segment's ends and their neighbours
(the nodal normals), between the events where a mortar segment end changes from a slave end to
a projected master end. The derivatives are exact: the segment-to-segment integrals are
written once on second-order jets (:class:`~alcontact.contact.kinematics._jet.Jet`: value,
gradient and Hessian with respect to the 12 local coordinates, exact 2-point Gauss quadrature
of the quadratic integrands) and so is the nodal gap of the integrated quantities
:math:`z_j = (S_j, Y_j, V_j, x_j)` (:math:`S_j = \sum_k M_{jk}`, :math:`Y_j = \sum_k M_{jk}y_k`,
:math:`V_j = \sum_k M_{jk}\nu^m_k`). The chain rule then gives the constraint rows and the
curvature term of the Newton matrix,

.. math::

    \frac{\partial g_j}{\partial q} = \frac{\partial g_j}{\partial z_j}\frac{\partial z_j}{\partial q}, \qquad
    \sum_j c_j \frac{\partial^2 g_j}{\partial q^2}
      = J^T \operatorname{diag}\Big(c_j \frac{\partial^2 g_j}{\partial z_j^2}\Big) J
        + \sum_{\text{pairs}} \sum_j c_j \frac{\partial g_j}{\partial z_j}\cdot\frac{\partial^2 z_j^{pair}}{\partial q^2},

:math:`J = \partial z/\partial q`: the variation of the projection (the mortar segment end
points and the master parameter of every quadrature point), of the slave segment length, of
the master nodal normals and of the mortar weights are all in it, so Newton's method on a
subproblem converges quadratically (``tests/unit/test_contact_kinematics.py`` checks the rows
and the curvature against central differences).

Action = reaction: :math:`g_j` depends on differences of positions only and the master weights
of every slave node sum to one, so :math:`\sum_q \partial g_j/\partial q` over all DOFs of one
direction vanishes and the contact forces :math:`-G^T(w\circ t_N)` on the two bodies sum to zero
to round-off, on curved interfaces too (:meth:`CurrentMortarGap.contact_force`).

Large sliding: the candidate master segments of every slave segment come from a
:class:`scipy.spatial.cKDTree` on the current master segment midpoints, rebuilt at every
evaluation (every Newton iteration and line-search trial), within the search distance and
:data:`_REACH` slave element sizes; only facing segments (:math:`n_s\cdot n_m < 0`) are paired. A slave node whose support the current master covers
for less than :data:`~alcontact.contact.kinematics._mortar.COVER_MIN` of its current length
is open: its gap is the search distance below zero and its row is empty.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ...errors import InputError
from ..masters._mortar import boundary_segments
from ._gap import CurrentGap
from ._jet import Jet
from ._mortar import COVER_MIN, _integrals, _offset

#: 2-point Gauss rule on [0, 1]: exact for the quadratic integrands of P1 segments
_GAUSS_X = np.array([0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)])
_GAUSS_W = np.array([0.5, 0.5])
#: integrated quantities of a slave node: S, Y (2), V (2), then its own position x (2)
_NZ = 7
#: candidate master segments lie within this many slave element sizes of a slave segment (and within the
#: search distance): the search is redone at every evaluation, so it only has to reach as far as the
#: contact zone moves in one Newton iteration, and the pairs stay O(n) on long interfaces
_REACH = 10.0


def _rot(t0, t1):
    """The segment normal before orientation: :math:`(t_1, -t_0)` of the tangent :math:`t`."""
    return t1, -t0


def _orientation(seg) -> np.ndarray:
    """``+1`` where the outward normal of a segment is ``rot(end1 - end0) / L``, else ``-1``."""
    x0, x1 = seg.points[seg.ends[:, 0]], seg.points[seg.ends[:, 1]]
    n0, n1 = _rot(*(x1 - x0).T)
    return np.where(n0 * seg.normals[:, 0] + n1 * seg.normals[:, 1] >= 0.0, 1.0, -1.0)


def _neighbours(seg, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For every end of every segment: the other node of the node's other segment and that segment's orientation.

    Returns ``(other, sign)`` of shape ``(s, 2)``: at end ``e`` of segment ``m`` (node ``c``), the
    other segment at ``c`` has the outward normal ``sign * rot(y_other - y_c) / |y_other - y_c|``;
    ``other = -1`` and ``sign = 0`` where ``c`` ends the polyline.
    """
    s = seg.ends.shape[0]
    at: dict[int, list[tuple[int, int]]] = {}
    for m in range(s):
        for e in (0, 1):
            at.setdefault(int(seg.ends[m, e]), []).append((m, e))
    other = -np.ones((s, 2), dtype=np.int64)
    sign = np.zeros((s, 2))
    for m in range(s):
        for e in (0, 1):
            c = int(seg.ends[m, e])
            rest = [(m2, e2) for m2, e2 in at[c] if m2 != m]
            if len(rest) != 1:
                continue  # the end of the polyline (or a non-manifold node: one segment's normal)
            m2, e2 = rest[0]
            other[m, e] = seg.ends[m2, 1 - e2]
            # rot(y_end1 - y_end0) of segment m2 is +rot(y_other - y_c) when c is its end 0
            sign[m, e] = sigma[m2] * (1.0 if e2 == 0 else -1.0)
    return other, sign


def _pair_kernel(Z: np.ndarray, sigma: np.ndarray, sp_: np.ndarray, sq: np.ndarray, *, gradient: bool,
                 hessian: bool) -> list[Jet]:
    r"""Mortar integrals of slave segment ``(a, b)`` against master segment ``(c, d)`` (module doc), on jets.

    ``Z`` ``(P, 12)``: the current coordinates of :math:`x_a, x_b, y_p, y_c, y_d, y_q` (``p``, ``q`` the
    other neighbours of ``c`` and ``d``, for the nodal normals); ``sigma`` the master segment's orientation,
    ``sp_``, ``sq`` those of the neighbour segments (0 where there is none). Returns the 10 jets
    :math:`S_a, S_b, Y_{a,0}, Y_{a,1}, Y_{b,0}, Y_{b,1}, V_{a,0}, V_{a,1}, V_{b,0}, V_{b,1}`.
    """
    if gradient:
        v = Jet.variables(Z, hessian=hessian)
    else:  # values only: jets of no variable
        v = [Jet(Z[:, i].copy(), np.zeros((Z.shape[0], 0)), None) for i in range(Z.shape[1])]
    xa0, xa1, xb0, xb1, yp0, yp1, yc0, yc1, yd0, yd1, yq0, yq1 = v
    e0, e1 = xb0 - xa0, xb1 - xa1
    L2 = e0 * e0 + e1 * e1
    L = L2.sqrt()
    inv = L2.reciprocal()
    xic = ((yc0 - xa0) * e0 + (yc1 - xa1) * e1) * inv  # master ends projected on the slave segment
    xid = ((yd0 - xa0) * e0 + (yd1 - xa1) * e1) * inv
    first = xic.v <= xid.v
    mn, mx = Jet.where(first, xic, xid), Jet.where(first, xid, xic)
    lo = Jet.where(mn.v > 0.0, mn, Jet.constant(0.0, mn))
    hi = Jet.where(mx.v < 1.0, mx, Jet.constant(1.0, mx))
    span = hi - lo
    inv_d = (xid - xic).reciprocal()

    def unit(a0, a1):
        n = (a0 * a0 + a1 * a1).sqrt().reciprocal()
        return a0 * n, a1 * n

    t0, t1 = yd0 - yc0, yd1 - yc1
    nm0, nm1 = unit(*_rot(t0, t1))
    nm0, nm1 = nm0 * sigma, nm1 * sigma
    np0, np1 = unit(*_rot(yp0 - yc0, yp1 - yc1))
    nq0, nq1 = unit(*_rot(yq0 - yd0, yq1 - yd1))
    nuc = unit(nm0 + np0 * sp_, nm1 + np1 * sp_)  # master nodal normals at c and d
    nud = unit(nm0 + nq0 * sq, nm1 + nq1 * sq)
    Mac = Mad = Mbc = Mbd = None
    for xg, wg in zip(_GAUSS_X, _GAUSS_W):
        xq = lo + span * xg
        w = L * span * wg
        Nd = (xq - xic) * inv_d  # master parameter from c to d
        Nc = 1.0 - Nd
        wa, wb = (2.0 - 3.0 * xq) * w, (3.0 * xq - 1.0) * w  # dual basis times the measure
        terms = (wa * Nc, wa * Nd, wb * Nc, wb * Nd)
        if Mac is None:
            Mac, Mad, Mbc, Mbd = terms
        else:
            Mac, Mad, Mbc, Mbd = Mac + terms[0], Mad + terms[1], Mbc + terms[2], Mbd + terms[3]
    out = [Mac + Mad, Mbc + Mbd]
    for Mc, Md in ((Mac, Mad), (Mbc, Mbd)):
        out += [Mc * yc0 + Md * yd0, Mc * yc1 + Md * yd1]
    for Mc, Md in ((Mac, Mad), (Mbc, Mbd)):
        out += [Mc * nuc[0] + Md * nud[0], Mc * nuc[1] + Md * nud[1]]
    # order: S_a, S_b, Y_a0, Y_a1, Y_b0, Y_b1, V_a0, V_a1, V_b0, V_b1
    return out


def _node_kernel(z: np.ndarray, *, hessian: bool) -> Jet:
    r""":math:`g = n\cdot(x - Y/S)`, :math:`n = -V/|V|`, from ``z = (S, Y_0, Y_1, V_0, V_1, x_0, x_1)`` ``(m, 7)``."""
    S, Y0, Y1, V0, V1, x0, x1 = Jet.variables(z, hessian=hessian)
    iS = S.reciprocal()
    iV = (V0 * V0 + V1 * V1).sqrt().reciprocal()
    n0, n1 = -(V0 * iV), -(V1 * iV)
    return n0 * (x0 - Y0 * iS) + n1 * (x1 - Y1 * iS)


#: which integrated quantity of which slave end each output of :func:`_pair_kernel` is: (end, component of z)
_OUTPUTS = ((0, 0), (1, 0), (0, 1), (0, 2), (1, 1), (1, 2), (0, 3), (0, 4), (1, 3), (1, 4))


def _current_points(gap, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
    """Current positions ``X + u`` of the slave points of ``gap`` (all, or those of ``idx``): the ``current``
    member of :class:`CurrentMortarGap` and :class:`StackedMortarGap`."""
    if idx is None:
        return gap.points + u[gap.dofs]
    return gap.points[idx] + u[gap.dofs[idx]]


class _State:
    """Everything :class:`CurrentMortarGap` computed at one displacement."""

    def __init__(self, g, normals, covered, rows, cols, grads, z_jet, pair_jets, pair_nodes, pair_cols):
        self.g, self.normals, self.covered = g, normals, covered
        self.rows, self.cols, self.grads = rows, cols, grads  # the entries of J = dz/dq (full numbering)
        self.z_jet, self.pair_jets, self.pair_nodes, self.pair_cols = z_jet, pair_jets, pair_nodes, pair_cols
        self._J = None
        self._G = None

    def J(self, ndofs: int, m: int) -> sp.csr_matrix:
        if self._J is None:
            self._J = sp.csr_matrix((self.grads, (self.rows, self.cols)), shape=(_NZ * m, ndofs))
        return self._J

    def G(self, ndofs: int) -> sp.csr_matrix:
        """Constraint rows on every DOF of the model (all slave nodes; zero rows where open)."""
        if self._G is None:
            m = self.g.size
            fg = np.where(self.covered[:, None], self.z_jet.g, 0.0)
            Fg = sp.csr_matrix((fg.ravel(), (np.repeat(np.arange(m), _NZ), np.arange(_NZ * m))),
                               shape=(m, _NZ * m))
            self._G = (Fg @ self.J(ndofs, m)).tocsr()
        return self._G


class CurrentMortarGap:
    r"""The mortar weighted gap at the current configuration as a :class:`~alcontact.contact.kinematics.ContactKinematics`.

    Parameters
    ----------
    model : alcontact.fem.MultiBody
        The stacked bodies (DOF numbering of ``u``).
    slave_body, slave_name
        The slave boundary: its body (one of the model's) and that body's boundary name.
    master : BodySurface
        The master boundary (another body's).
    points, dofs, pos : ndarray
        The slave nodes (reference positions), their DOFs (model numbering) and the DOFs' positions in
        the free vector (-1 when supported).
    free : ndarray of int
        The free DOFs (columns of the constraint rows).

    Attributes
    ----------
    weights : ndarray (m,)
        The reference tributary lengths :math:`D^0_j` (the multipliers' weights).
    h : float
        Median reference slave segment length near the master (the contact element size).
    master_dofs, slave_dofs : ndarray of int (k, 2)
        DOFs of the master and slave boundary nodes (model numbering).
    evaluations : int
        Evaluations at a new displacement (each one contact search).
    """

    configuration = "current"
    pointwise = False

    def __init__(self, model, slave_body, slave_name: str, master, points, dofs, pos, free: np.ndarray):
        if int(model.dim) != 2:
            raise InputError(f"finite-deformation contact between two bodies is 2D so far; these bodies are "
                             f"{int(model.dim)}D: use kinematics='small' (3D mortar, linear elastic bodies).")
        for body, what in ((slave_body, "slave"), (master.body, "master")):
            if getattr(body, "order", 1) != 1:
                raise InputError(f"finite-deformation contact between two bodies is available for P1 bodies (straight "
                                 f"segments that stay straight); the {what} body has order={body.order}: use order=1 "
                                 "(or kinematics='small' with P2).")
        if getattr(master, "method", "mortar") != "mortar":
            raise InputError(f"finite-deformation contact between two bodies uses the mortar gap; the master "
                             f"{master.describe()} asks for method={master.method!r}: use method='mortar'.")
        self.model, self.master = model, master
        self.points = np.asarray(points, dtype=float)
        self.dofs = np.asarray(dofs, dtype=np.int64)
        self.pos = np.asarray(pos, dtype=np.int64)
        self.free = np.asarray(free, dtype=np.int64)
        self.ndofs = int(model.ndofs)
        self._free_pos = -np.ones(self.ndofs, dtype=np.int64)
        self._free_pos[self.free] = np.arange(self.free.size)
        ss, ms = boundary_segments(slave_body, slave_name), master.segments
        self._ss, self._ms = ss, ms
        self.slave_dofs = ss.dofs + _offset(model, slave_body)
        self.master_dofs = ms.dofs + _offset(model, master.body)
        if not np.array_equal(self.slave_dofs, self.dofs):
            raise ValueError("the slave nodes are not those of the slave boundary (order of node_dofs)")
        m = ss.points.shape[0]
        D = np.zeros(m)
        for i, w in enumerate(_integrals(2)):
            np.add.at(D, ss.ends[:, i], w * ss.lengths)
        self.weights = D
        extent = max(float(np.ptp(ss.points, axis=0).max()), float(np.ptp(ms.points, axis=0).max()))
        self.search = master.search_distance if master.search_distance is not None else 0.25 * extent
        self._sigma_s, self._sigma_m = _orientation(ss), _orientation(ms)
        self._other, self._other_sign = _neighbours(ms, self._sigma_m)
        self.evaluations = 0
        self._state: _State | None = None
        self._key: bytes | None = None
        self.h = float(np.median(ss.lengths))  # the search's reach until the contact zone's own size is known
        covered = self._state_at(np.zeros(self.ndofs), gradient=False).covered
        near = covered if np.any(covered) else np.ones(m, bool)
        self.h = float(np.median(ss.lengths[near[ss.ends].any(axis=1)]))
        self._state = self._key = None

    # ------------------------------------------------------------------ ContactKinematics
    def gaps(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        g = self._state_at(u, gradient=False).g
        return g.copy() if idx is None else g[np.asarray(idx, dtype=np.int64)]

    def evaluate(self, u: np.ndarray, idx: np.ndarray | None = None, *, hessian: bool = False):
        idx = np.arange(self.points.shape[0]) if idx is None else np.asarray(idx, dtype=np.int64)
        return _Evaluation(self, self._state_at(u, gradient=True, hessian=hessian), idx)

    current = _current_points

    def against(self, master):
        """This gap for its own master surface (the master of a two-body pair does not move by itself)."""
        if master is self.master:
            return self
        raise ValueError("a mortar gap belongs to its master surface; build the pair again for another master")

    # ------------------------------------------------------------------ contact forces
    def contact_force(self, u: np.ndarray, nodal: np.ndarray) -> np.ndarray:
        r"""Contact force :math:`-G^T r` on every DOF of the model at ``u`` for the nodal forces :math:`r = w\circ\lambda`."""
        G = self._state_at(u, gradient=True).G(self.ndofs)
        return -(G.T @ np.asarray(nodal, dtype=float))

    def force_points(self, u: np.ndarray, nodal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(dofs, forces)`` of :meth:`contact_force` on the slave and master nodes (each ``(k, 2)``)."""
        fc = self.contact_force(u, nodal)
        nodes = np.unique(np.vstack([self.slave_dofs, self.master_dofs]), axis=0)
        return nodes, fc[nodes]

    def side_forces(self, u: np.ndarray, nodal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Resultant contact forces ``(on the slave body, on the master body)``, each ``(2,)``."""
        fc = self.contact_force(u, nodal)
        return fc[self.slave_dofs].sum(axis=0), fc[self.master_dofs].sum(axis=0)

    # ------------------------------------------------------------------ the computation
    def _state_at(self, u: np.ndarray, *, gradient: bool, hessian: bool = False) -> _State:
        u = np.asarray(u, dtype=float)
        key = np.concatenate([u[self.slave_dofs].ravel(), u[self.master_dofs].ravel()]).tobytes()
        st = self._state
        if st is not None and self._key == key and (not gradient or st.z_jet.g.shape[1]) and \
                (not hessian or st.z_jet.h is not None):
            return st
        if key != self._key:
            self.evaluations += 1
        self._state = self._compute(u, gradient=gradient or hessian, hessian=hessian)
        self._key = key
        return self._state

    def _pairs(self, x: np.ndarray, y: np.ndarray):
        """Candidate ``(slave segment, master segment)`` pairs at the current positions, facing and overlapping."""
        ss, ms = self._ss, self._ms
        xa, xb = x[ss.ends[:, 0]], x[ss.ends[:, 1]]
        yc, yd = y[ms.ends[:, 0]], y[ms.ends[:, 1]]
        ls, lm = np.linalg.norm(xb - xa, axis=1), np.linalg.norm(yd - yc, axis=1)
        radius = min(self.search, _REACH * self.h) + 0.5 * (float(ls.max()) + float(lm.max()))
        cands = cKDTree(0.5 * (yc + yd)).query_ball_point(0.5 * (xa + xb), r=radius)
        s_idx = np.repeat(np.arange(len(cands)), [len(c) for c in cands])
        m_idx = np.concatenate([np.asarray(c, dtype=np.int64) for c in cands]) if s_idx.size else \
            np.empty(0, dtype=np.int64)
        ns = np.stack(_rot(*(xb - xa).T), axis=1) * (self._sigma_s / ls)[:, None]
        nm = np.stack(_rot(*(yd - yc).T), axis=1) * (self._sigma_m / lm)[:, None]
        facing = np.einsum("ij,ij->i", ns[s_idx], nm[m_idx]) < 0.0
        s_idx, m_idx = s_idx[facing], m_idx[facing]
        e = xb[s_idx] - xa[s_idx]
        L2 = np.einsum("ij,ij->i", e, e)
        xic = np.einsum("ij,ij->i", yc[m_idx] - xa[s_idx], e) / L2
        xid = np.einsum("ij,ij->i", yd[m_idx] - xa[s_idx], e) / L2
        lo = np.maximum(0.0, np.minimum(xic, xid))
        hi = np.minimum(1.0, np.maximum(xic, xid))
        ok = (hi - lo > 1e-12) & (np.abs(xid - xic) > 1e-12)
        return s_idx[ok], m_idx[ok]

    def _compute(self, u: np.ndarray, *, gradient: bool, hessian: bool) -> _State:
        ss, ms = self._ss, self._ms
        m = ss.points.shape[0]
        x = ss.points + u[self.slave_dofs]
        y = ms.points + u[self.master_dofs]
        s_idx, m_idx = self._pairs(x, y)
        c, d = ms.ends[m_idx, 0], ms.ends[m_idx, 1]
        p, q = self._other[m_idx, 0], self._other[m_idx, 1]
        sp_, sq = self._other_sign[m_idx, 0], self._other_sign[m_idx, 1]
        # a missing neighbour: any point off the segment's line (its normal is multiplied by 0)
        t = y[d] - y[c]
        yp = np.where((p >= 0)[:, None], y[np.maximum(p, 0)], y[c] + np.stack(_rot(*t.T), axis=1))
        yq = np.where((q >= 0)[:, None], y[np.maximum(q, 0)], y[d] + np.stack(_rot(*t.T), axis=1))
        a, b = ss.ends[s_idx, 0], ss.ends[s_idx, 1]
        Z = np.hstack([x[a], x[b], yp, y[c], y[d], yq])
        outs = _pair_kernel(Z, self._sigma_m[m_idx], sp_, sq, gradient=gradient, hessian=hessian)
        ends = (a, b)
        # the integrated quantities z_j of every slave node
        z = np.zeros((m, _NZ))
        for (e, comp), jet in zip(_OUTPUTS, outs):
            np.add.at(z[:, comp], ends[e], jet.v)
        z[:, 5:] = x
        D = np.zeros(m)
        lengths = np.linalg.norm(x[ss.ends[:, 1]] - x[ss.ends[:, 0]], axis=1)
        for i in (0, 1):
            np.add.at(D, ss.ends[:, i], 0.5 * lengths)
        vn = np.linalg.norm(z[:, 3:5], axis=1)
        covered = (z[:, 0] >= COVER_MIN * D) & (vn > 0.0)
        zsafe = np.where(covered[:, None], z, np.array([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]))
        z_jet = _node_kernel(zsafe, hessian=hessian) if gradient else \
            Jet(np.zeros(m), np.zeros((m, 0)), None)
        n_slave = self._slave_normals(x)
        normals = np.where(covered[:, None], zsafe[:, 3:5] / np.maximum(vn, 1e-300)[:, None], -n_slave)
        if gradient:
            g = np.where(covered, z_jet.v, -self.search)
        else:
            g = np.full(m, -self.search)
            zc = z[covered]
            nrm = -zc[:, 3:5] / vn[covered][:, None]
            g[covered] = np.einsum("ij,ij->i", nrm, zc[:, 5:] - zc[:, 1:3] / zc[:, :1])
        if not gradient:
            return _State(g, normals, covered, None, None, None, z_jet, None, None, None)
        # J = dz/dq: the pair outputs' gradients on their 12 local DOFs, and x_j itself
        loc_nodes = [(self.slave_dofs, a), (self.slave_dofs, b), (self.master_dofs, np.maximum(p, 0)),
                     (self.master_dofs, c), (self.master_dofs, d), (self.master_dofs, np.maximum(q, 0))]
        pair_cols = np.hstack([dofs[nodes] for dofs, nodes in loc_nodes])  # (P, 12) model DOFs
        rows, cols, vals = [], [], []
        for (e, comp), jet in zip(_OUTPUTS, outs):
            rows.append(np.repeat(_NZ * ends[e] + comp, 12))
            cols.append(pair_cols.ravel())
            vals.append(jet.g.ravel())
        rows.append(np.repeat(_NZ * np.arange(m), 2) + np.tile([5, 6], m))
        cols.append(self.slave_dofs.ravel())
        vals.append(np.ones(2 * m))
        return _State(g, normals, covered, np.concatenate(rows), np.concatenate(cols), np.concatenate(vals), z_jet,
                      outs if hessian else None, ends, pair_cols)

    def _slave_normals(self, x: np.ndarray) -> np.ndarray:
        """Current outward nodal normals of the slave boundary (of the uncovered nodes' rows)."""
        ss = self._ss
        t = x[ss.ends[:, 1]] - x[ss.ends[:, 0]]
        n = np.stack(_rot(*t.T), axis=1) * (self._sigma_s / np.linalg.norm(t, axis=1))[:, None]
        acc = np.zeros_like(x)
        for k in (0, 1):
            np.add.at(acc, ss.ends[:, k], n)
        return acc / np.maximum(np.linalg.norm(acc, axis=1, keepdims=True), 1e-300)

    def _curvature(self, st: _State, c_full: np.ndarray) -> sp.csr_matrix:
        r""":math:`\sum_j c_j \partial^2 g_j/\partial q^2` on the free DOFs (module doc)."""
        m, nf = c_full.size, self.free.size
        c_full = np.where(st.covered, c_full, 0.0)
        J = st.J(self.ndofs, m)[:, self.free]
        on = np.flatnonzero(c_full != 0.0)
        # J^T diag(c_j d2g/dz2) J: one 7 x 7 block per slave node
        blocks = c_full[on, None, None] * st.z_jet.h[on]
        r = (_NZ * on[:, None, None] + np.arange(_NZ)[None, :, None]) + np.zeros((1, 1, _NZ), dtype=np.int64)
        cc = np.swapaxes(r, 1, 2)
        F = sp.csr_matrix((blocks.ravel(), (r.ravel(), cc.ravel())), shape=(_NZ * m, _NZ * m))
        C = J.T @ F @ J
        # sum over pairs of c_j dg/dz . d2z/dq2 on the pairs' 12 local DOFs
        alpha = c_full[:, None] * st.z_jet.g  # (m, 7)
        H = None
        for (e, comp), jet in zip(_OUTPUTS, st.pair_jets):
            coef = alpha[st.pair_nodes[e], comp]
            H = jet.h * coef[:, None, None] if H is None else H + jet.h * coef[:, None, None]
        if H is not None and H.size:
            pc = self._free_pos[st.pair_cols]  # (P, 12) free positions, -1 where supported
            rr = np.repeat(pc, 12, axis=1).ravel()
            ccol = np.tile(pc, (1, 12)).ravel()
            vv = H.ravel()
            keep = (rr >= 0) & (ccol >= 0) & (vv != 0.0)
            C = C + sp.csr_matrix((vv[keep], (rr[keep], ccol[keep])), shape=(nf, nf))
        return C.tocsr()


class _Evaluation:
    """What :meth:`CurrentMortarGap.evaluate` returns (the members of :class:`~alcontact.contact.kinematics.GapEvaluation`)."""

    hessian = None  # not pointwise: the curvature is a sparse matrix (curvature())

    def __init__(self, kin: CurrentMortarGap, state: _State, idx: np.ndarray):
        self._kin, self._state, self.idx = kin, state, idx
        self.g = state.g[idx]
        self.normals = state.normals[idx]
        self._gradient = None

    def gradient(self, mask: np.ndarray | None = None) -> sp.csr_matrix:
        r"""Constraint rows :math:`\partial g_i/\partial x` of the points ``idx`` on the free DOFs (CSR)."""
        if self._gradient is None:
            self._gradient = self._state.G(self._kin.ndofs)[self.idx][:, self._kin.free].tocsr()
        if mask is None:
            return self._gradient
        return (sp.diags(np.asarray(mask, dtype=float)) @ self._gradient).tocsr()

    def curvature(self, c: np.ndarray) -> sp.csr_matrix:
        r""":math:`\sum_i c_i\,\partial^2 g_i/\partial x^2` on the free DOFs (needs ``hessian=True``)."""
        if self._state.z_jet.h is None:
            raise ValueError("curvature needs the gap Hessian: evaluate(..., hessian=True)")
        c_full = np.zeros(self._state.g.size)
        np.add.at(c_full, self.idx, np.asarray(c, dtype=float))
        return self._kin._curvature(self._state, c_full)


class _StackedEvaluation:
    """:class:`_Evaluation` of several pairs' points (:class:`StackedMortarGap`)."""

    hessian = None

    def __init__(self, parts, idx: np.ndarray, bounds: np.ndarray):
        self._parts, self.idx, self._bounds = parts, idx, bounds
        self.g = np.concatenate([p.g for p in parts])[idx]
        self.normals = np.concatenate([p.normals for p in parts])[idx]
        self._gradient = None

    def gradient(self, mask: np.ndarray | None = None) -> sp.csr_matrix:
        if self._gradient is None:
            self._gradient = sp.vstack([p.gradient() for p in self._parts]).tocsr()[self.idx]
        if mask is None:
            return self._gradient
        return (sp.diags(np.asarray(mask, dtype=float)) @ self._gradient).tocsr()

    def curvature(self, c: np.ndarray) -> sp.csr_matrix:
        c_full = np.zeros(int(self._bounds[-1]))
        np.add.at(c_full, self.idx, np.asarray(c, dtype=float))
        out = None
        for k, p in enumerate(self._parts):
            ck = c_full[self._bounds[k]:self._bounds[k + 1]]
            term = p.curvature(ck)
            out = term if out is None else out + term
        return out.tocsr()


class StackedMortarGap:
    r"""The mortar gaps of several two-body pairs at the current configuration, stacked in the pairs' order.

    A ring squeezed between two plates: one :class:`CurrentMortarGap` per pair (its slave boundary against its
    master surface), the points of pair 0 first (the order of
    :meth:`~alcontact.contact.ContactProblem.slave_nodes`). Gaps, normals and weights are the pairs' own
    concatenated, the constraint rows stacked, the curvature the sum of the pairs' (a
    :class:`~alcontact.contact.kinematics.ContactKinematics`, ``configuration = "current"``).

    Parameters
    ----------
    gaps : sequence of CurrentMortarGap
        One per pair, in the pairs' order.
    master : StackedMaster
        The problem's master of the stacked points.
    """

    configuration = "current"
    pointwise = False

    def __init__(self, gaps, master):
        self.parts = tuple(gaps)
        self.master = master
        self.points = np.vstack([g.points for g in self.parts])
        self.dofs = np.vstack([g.dofs for g in self.parts])
        self.pos = np.vstack([g.pos for g in self.parts])
        self.weights = np.concatenate([g.weights for g in self.parts])
        self.h = float(min(g.h for g in self.parts))
        self.bounds = np.concatenate([[0], np.cumsum([g.points.shape[0] for g in self.parts])]).astype(np.int64)
        self.slave_dofs = np.unique(np.vstack([g.slave_dofs for g in self.parts]), axis=0)
        self.master_dofs = np.unique(np.vstack([g.master_dofs for g in self.parts]), axis=0)

    def _split(self, v: np.ndarray):
        v = np.asarray(v, dtype=float)
        return [v[self.bounds[k]:self.bounds[k + 1]] for k in range(len(self.parts))]

    def gaps(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        g = np.concatenate([p.gaps(u) for p in self.parts])
        return g if idx is None else g[np.asarray(idx, dtype=np.int64)]

    def evaluate(self, u: np.ndarray, idx: np.ndarray | None = None, *, hessian: bool = False):
        idx = np.arange(self.points.shape[0]) if idx is None else np.asarray(idx, dtype=np.int64)
        return _StackedEvaluation([p.evaluate(u, hessian=hessian) for p in self.parts], idx, self.bounds)

    current = _current_points

    def against(self, master):
        """These gaps for their own masters (the masters of two-body pairs do not move by themselves)."""
        if master is self.master:
            return self
        raise ValueError("mortar gaps belong to their master surfaces; build the pairs again for other masters")

    def contact_force(self, u: np.ndarray, nodal: np.ndarray) -> np.ndarray:
        r"""Contact force :math:`-G^T r` of all pairs on every DOF of the model."""
        return sum(p.contact_force(u, r) for p, r in zip(self.parts, self._split(nodal)))

    def force_points(self, u: np.ndarray, nodal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(dofs, forces)`` of :meth:`contact_force` on the slave and master nodes of every pair."""
        fc = self.contact_force(u, nodal)
        nodes = np.unique(np.vstack([self.slave_dofs, self.master_dofs]), axis=0)
        return nodes, fc[nodes]

    def side_forces(self, u: np.ndarray, nodal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Resultants ``(on the slave sides, on the master sides)`` summed over the pairs."""
        per = self.pair_forces(u, nodal)
        return per[:, 0].sum(axis=0), per[:, 1].sum(axis=0)

    def pair_forces(self, u: np.ndarray, nodal: np.ndarray) -> np.ndarray:
        """``(n_pairs, 2, d)``: each pair's resultant contact force on its slave and on its master side."""
        return np.array([np.stack(p.side_forces(u, r)) for p, r in zip(self.parts, self._split(nodal))])


def current_kinematics(problem, free: np.ndarray):
    """The factory ``(points, dofs, pos, master, n_free) -> ContactKinematics`` of a problem at the current
    configuration (what :class:`~alcontact.contact.systems.FiniteContact` builds its kinematics with):
    :class:`~alcontact.contact.kinematics.CurrentGap` against rigid masters, :class:`CurrentMortarGap` for a
    pair between two bodies (its columns the ``free`` DOFs), :class:`StackedMortarGap` for several."""
    if all(p.rigid for p in problem.pairs):
        return CurrentGap
    model = problem.model
    pairs = problem.pairs

    def build(points, dofs, pos, master, nfree):
        if len(pairs) == 1:
            pair = pairs[0]
            return CurrentMortarGap(model, pair.slave.body, pair.slave.name, master, points, dofs, pos, free)
        owner = problem.pair_of_points()
        parts = [CurrentMortarGap(model, p.slave.body, p.slave.name, p.master, points[owner == k], dofs[owner == k],
                                  pos[owner == k], free) for k, p in enumerate(pairs)]
        return StackedMortarGap(parts, master)

    return build
