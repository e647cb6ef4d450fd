r"""Mortar weighted gaps between two 3D bodies (linear triangles, dual multipliers), small deformation.

The weighted gap of slave node ``j`` is that of :mod:`._mortar` on surfaces:

.. math::

    \tilde g_j = \int_{\Gamma_s} \Phi_j\, (x_s - x_m\circ\chi)\cdot n_j \, dA
              = n_j \cdot \Big(D_j\, x_j - \sum_k M_{jk}\, y_k\Big), \qquad
    D_j = \int N_j\,dA, \quad M_{jk} = \int \Phi_j\, N^m_k\circ\chi \, dA,

with the dual (biorthogonal) basis of the three-node slave triangle (Wohlmuth, 2000, SIAM J.
Numer. Anal. 38:989-1012; Popp, Gee & Wall, 2009, Int. J. Numer. Meth. Engng 79:1354-1391)

.. math::

    \Phi_i = 4 N_i - 1 \qquad (\Phi = A N,\ A = D \hat M^{-1}), \qquad
    \int_T \Phi_i N_k \,dA = \delta_{ik} \int_T N_i\,dA = \delta_{ik}\,\frac{|T|}{3},

so that ``D`` is diagonal and the constraints stay one per slave node; :math:`\chi` maps a
point of the slave face to the master face along the slave face's normal. Each integral
runs over the faces' common part: the master face is projected onto the slave face's plane
(along its normal), the two triangles are clipped (:func:`._clipping.clip_convex`) and the
clipped polygon is integrated by a fan of triangles with the degree-2 Gauss rule
(:func:`._clipping.fan_quadrature`), exact here (affine :math:`\Phi_j` times affine
:math:`N^m_k\circ\chi` on flat faces). From ``M`` and ``D`` on, everything is as in 2D
(:mod:`._mortar`): the rows of ``M`` are divided by their sums (a weighted master point per
slave node; the sum is :math:`D_j` where the master covers node ``j``'s support), the normal
:math:`n_j` is minus the master's nodal normals averaged with those weights, a node whose
support the master covers for less than :data:`._mortar.COVER_MIN` is open, and

.. math::

    g = g^0 + B u, \qquad B_{j, s(j)} = n_j^T, \qquad B_{j, m(k)} = -\frac{M_{jk}}{\sum_l M_{jl}}\, n_j^T ,

whose forces :math:`-B^T (w\circ\lambda)` on the two bodies sum to zero exactly. Against a flat
master (the contact patch test) :math:`g_j` is the distance of node ``j`` to the master plane,
so a uniform pressure is transmitted exactly on non-matching meshes.

Candidate master faces (:func:`face_pairs`) come from a :class:`scipy.spatial.cKDTree` on the
master face centroids, built once per solve (small deformation): the nearest master faces of
each slave face's centroid give its closest master point (exact point-triangle distance); a
slave face farther than the search distance from the master has no candidates; the others
query a ball about the point where their normal meets the master: radius 1.5 times the sum
of the slave face's radius (divided by the cosine between the normals: its shadow on an
inclined master) and the largest radius of the master faces nearest that point (a graded
mesh changes its size slowly); of those, the pairs whose bounding boxes in the slave
face's plane overlap. Each query is :math:`O(\log n)`, so the search is :math:`O(n \log n)` in the
number of faces (measured in ``docs/benchmarks/two_body.md``); a test compares it with all
pairs clipped on the graded meshes of the sphere on a block.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ..masters._faces import Faces, boundary_faces
from ..masters._surface import _closest_on_triangles
from ._clipping import clip_convex, fan_quadrature
from ._mortar import COVER_MIN, MortarGap, _offset

#: faces pair when their normals face each other, :math:`n_s\cdot n_m < -` this (a master face seen edge-on
#: projects onto the slave plane with no area)
FACING_MIN = 1e-8

#: face pairs integrated per block of arrays (bounds the memory of the vectorized clipping)
CHUNK = 20_000


def dual_coefficients_triangle() -> np.ndarray:
    r"""``A`` with :math:`\Phi_i = \sum_k A_{ik} N_k` biorthogonal to the linear triangle's shape functions.

    :math:`A = D\hat M^{-1}`, :math:`\hat M_{ik} = \int_T N_i N_k / |T| = (1 + \delta_{ik})/12`,
    :math:`D = \mathrm{diag}(1/3)`: :math:`A = 4I - \mathbf{1}\mathbf{1}^T`, i.e. :math:`\Phi_i = 4N_i - 1`.
    """
    M = (np.ones((3, 3)) + np.eye(3)) / 12.0
    return np.diag(np.full(3, 1.0 / 3.0)) @ np.linalg.inv(M)


def face_pairs(ss: Faces, ms: Faces, search: float) -> tuple[np.ndarray, np.ndarray]:
    """Candidate (slave face, master face) pairs: facing faces near the slave faces' normal projections (module doc)."""
    ns, nm = ss.nodes.shape[0], ms.nodes.shape[0]
    if ns == 0 or nm == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    cs, rs = ss.centroids, ss.radii
    cm, rm = ms.centroids, ms.radii
    tree = cKDTree(cm)
    k = min(8, nm)
    _, near = tree.query(cs, k=k)
    near = np.asarray(near).reshape(ns, k)
    tri = ms.points[ms.nodes[near.ravel()]]  # (ns k, 3, 3)
    y, _, _ = _closest_on_triangles(np.repeat(cs, k, axis=0), tri[:, 0], tri[:, 1], tri[:, 2])
    dist = np.linalg.norm(np.repeat(cs, k, axis=0) - y, axis=1).reshape(ns, k)
    best = np.argmin(dist, axis=1)
    rows = np.arange(ns)
    d, f = dist[rows, best], near[rows, best]
    y = y.reshape(ns, k, 3)[rows, best]
    close = d <= search + rs
    # where the slave normal through the centroid meets the plane of the closest master face
    nf = ms.normals[f]
    cosang = np.einsum("ij,ij->i", ss.normals, nf)
    t = np.einsum("ij,ij->i", y - cs, nf) / np.where(cosang < -0.1, cosang, -1.0)
    q = np.where((cosang < -0.1)[:, None], cs + t[:, None] * ss.normals, y)
    which = np.flatnonzero(close)
    if which.size == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    q = q[which]
    # the master faces there: radius from the largest of the nearest ones (graded meshes change size slowly)
    _, around = tree.query(q, k=k)
    local = rm[np.asarray(around).reshape(which.size, k)].max(axis=1)
    stretch = 1.0 / np.maximum(-cosang[which], 0.1)  # the slave face's shadow on an inclined master
    radius = 1.5 * (stretch * rs[which] + local)
    lists = tree.query_ball_point(q, radius, return_sorted=False)
    counts = np.fromiter((len(li) for li in lists), dtype=np.int64, count=len(lists))
    s_idx = np.repeat(which, counts)
    m_idx = np.fromiter((c for li in lists for c in li), dtype=np.int64, count=int(counts.sum()))
    facing = np.einsum("ij,ij->i", ss.normals[s_idx], ms.normals[m_idx]) < -FACING_MIN
    s_idx, m_idx = s_idx[facing], m_idx[facing]
    keep = np.zeros(s_idx.size, dtype=bool)
    for lo in range(0, s_idx.size, CHUNK):  # the boxes of the two faces in the slave plane overlap
        s, m = s_idx[lo:lo + CHUNK], m_idx[lo:lo + CHUNK]
        slave, master = _in_slave_plane(ss, ms, s, m)
        tol = 1e-9 * ss.radii[s][:, None]
        lo_s, hi_s = _box(slave)
        lo_m, hi_m = _box(master)
        keep[lo:lo + CHUNK] = np.all((hi_m >= lo_s - tol) & (lo_m <= hi_s + tol), axis=1)
    return s_idx[keep], m_idx[keep]


def _box(tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper corners ``(p, 2)`` of the plane triangles ``tri`` ``(p, 3, 2)``."""
    return (np.minimum(np.minimum(tri[:, 0], tri[:, 1]), tri[:, 2]),
            np.maximum(np.maximum(tri[:, 0], tri[:, 1]), tri[:, 2]))


def _in_slave_plane(ss: Faces, ms: Faces, s_idx: np.ndarray, m_idx: np.ndarray):
    """The slave faces ``s_idx`` and the master faces ``m_idx`` projected onto the slave faces' planes.

    Returns the plane coordinates ``(p, 3, 2)`` of the slave face (counter-clockwise; origin at its first
    node, first axis along its first edge) and of the master face (its node order, so clockwise when the
    faces face each other).
    """
    x = ss.points[ss.nodes[s_idx]]  # (p, 3, 3)
    o = x[:, 0]
    e1 = x[:, 1] - o
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(ss.normals[s_idx], e1)

    def plane(y):
        rel = y - o[:, None, :]
        return np.stack([np.einsum("pkj,pj->pk", rel, e1), np.einsum("pkj,pj->pk", rel, e2)], axis=-1)

    return plane(x), plane(ms.points[ms.nodes[m_idx]])


def _barycentric(tri: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Barycentric coordinates ``(p, q, 3)`` of plane points ``x`` ``(p, q, 2)`` in triangles ``tri`` ``(p, 3, 2)``."""
    T = np.stack([tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]], axis=-1)  # (p, 2, 2)
    lam = np.einsum("pij,pqj->pqi", np.linalg.inv(T), x - tri[:, None, 0, :])  # (p, q, 2)
    return np.concatenate([1.0 - lam.sum(axis=-1, keepdims=True), lam], axis=-1)


def pair_integrals(ss: Faces, ms: Faces, s_idx: np.ndarray, m_idx: np.ndarray) -> np.ndarray:
    r"""``(p, 3, 3)``: :math:`\int \Phi_i N^m_k\,dA` over the common part of each face pair (module doc).

    ``[p, i, k]``: slave node ``ss.nodes[s_idx[p], i]``, master node ``ms.nodes[m_idx[p], k]``.
    """
    A = dual_coefficients_triangle()
    out = np.zeros((s_idx.size, 3, 3))
    for lo in range(0, s_idx.size, CHUNK):
        s, m = s_idx[lo:lo + CHUNK], m_idx[lo:lo + CHUNK]
        slave, master = _in_slave_plane(ss, ms, s, m)
        # seen along the slave normal the facing master face turns clockwise: reverse it for the clipping
        rev = master[:, ::-1]
        poly, valid = clip_convex(slave, rev)
        x, w = fan_quadrature(poly, valid, degree=2)
        if x.shape[1] == 0:
            continue
        Ns = _barycentric(slave, x)  # (p, q, 3)
        Nm = _barycentric(master, x)
        phi = Ns @ A.T
        out[lo:lo + CHUNK] = np.einsum("pq,pqi,pqk->pik", w, phi, Nm)
    return out


def mortar_matrix(ss: Faces, ms: Faces, s_idx: np.ndarray, m_idx: np.ndarray) -> sp.csr_matrix:
    """The mortar matrix ``M`` ``(slave nodes, master nodes)`` of the face pairs (module doc)."""
    loc = pair_integrals(ss, ms, s_idx, m_idx)
    rows = np.repeat(ss.nodes[s_idx], 3, axis=1).ravel()  # [p, i, k] -> slave node i
    cols = np.tile(ms.nodes[m_idx], (1, 3)).ravel()  # -> master node k
    M = sp.csr_matrix((loc.ravel(), (rows, cols)), shape=(ss.points.shape[0], ms.points.shape[0]))
    M.sum_duplicates()
    M.eliminate_zeros()
    return M


def default_search(ss: Faces, ms: Faces) -> float:
    """A quarter of the larger of the two boundaries' extents (as in 2D)."""
    return 0.25 * max(float(np.ptp(ss.points, axis=0).max()), float(np.ptp(ms.points, axis=0).max()))


def mortar_gap_3d(model, slave_body, slave_name: str, master) -> MortarGap:
    """The weighted gap (module doc) of a 3D slave boundary against a 3D :class:`~alcontact.contact.BodySurface`.

    Parameters
    ----------
    model : alcontact.fem.LinearElasticity or alcontact.fem.MultiBody
        The discretized bodies (DOF numbering of ``B``).
    slave_body, slave_name
        The slave boundary (its body and the body's own boundary name).
    master : BodySurface
        The master boundary (3D).
    """
    ss, ms = boundary_faces(slave_body, slave_name), master.faces
    search = master.search_distance if master.search_distance is not None else default_search(ss, ms)
    s_idx, m_idx = face_pairs(ss, ms, search)
    M = mortar_matrix(ss, ms, s_idx, m_idx)
    D = ss.integrals()
    total = np.asarray(M.sum(axis=1)).ravel()
    covered = total >= COVER_MIN * D
    P = sp.diags(np.where(covered, 1.0 / np.where(covered, total, 1.0), 0.0)) @ M
    return weighted_gap(model, slave_body, master.body, ss, ms, P.tocsr(), covered, D, search)


def weighted_gap(model, slave_body, master_body, ss: Faces, ms: Faces, P: sp.csr_matrix, covered: np.ndarray,
                 D: np.ndarray, search: float) -> MortarGap:
    """:class:`~._mortar.MortarGap` of the master weights ``P`` (rows summing to 1 on the ``covered`` slave nodes)."""
    m, d = ss.points.shape
    off_s, off_m = _offset(model, slave_body), _offset(model, master_body)
    n_node = ss.node_normals()
    y_bar = P @ ms.points
    nu = P @ ms.node_normals()  # the master normal carried to each slave node
    norm = np.linalg.norm(nu, axis=1, keepdims=True)
    n_node = np.where(covered[:, None] & (norm > 0), -nu / np.where(norm > 0, norm, 1.0), n_node)
    gap0 = np.where(covered, np.einsum("ij,ij->i", ss.points - y_bar, n_node), -search)
    j_s = np.flatnonzero(covered)
    Pc = P.tocoo()
    rows = np.concatenate([np.repeat(j_s, d), np.repeat(Pc.row, d)])
    cols = np.concatenate([(ss.dofs[j_s] + off_s).ravel(), (ms.dofs[Pc.col] + off_m).ravel()])
    vals = np.concatenate([n_node[j_s].ravel(), (-Pc.data[:, None] * n_node[Pc.row]).ravel()])
    B = sp.csr_matrix((vals, (rows, cols)), shape=(m, int(model.ndofs)))
    B.sum_duplicates()
    near = covered if np.any(covered) else np.ones(m, bool)
    h = float(np.median(ss.sizes[near[ss.nodes].any(axis=1)]))
    return MortarGap(gap0=gap0, B=B, weights=D, normals=-n_node, covered=covered, h=h, master_dofs=ms.dofs + off_m)
