r"""A deformable master: a boundary of a discretized body (two-body contact; 2D P1 or P2 straight edges, 3D P1).

:class:`BodySurface` is the master side of a :class:`~alcontact.contact.ContactPair` between
two bodies: its position moves with that body's displacement (``rigid = False``), so the gap
of a slave point depends on both bodies' degrees of freedom. The contact constraints are the
mortar weighted gaps of :mod:`alcontact.contact.kinematics._mortar` (2D) and
:mod:`alcontact.contact.kinematics._mortar3d` (3D) (one per slave node, dual multipliers); this
module holds the master's geometry: its segments (2D) or triangles (3D,
:mod:`alcontact.contact.masters._faces`) in the reference configuration with their outward unit
normals, and the members of the :class:`~alcontact.contact.Master` protocol evaluated on that
polyline or triangulation (closest point, signed distance), which the checks before a solve and
the reports use.

Sign convention (6.15): :math:`g \le 0` is feasible; the normal :math:`\nu` points out of the
master body into the region the slave may occupy.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from ..._options import VALUE_RANGE, Option, check_args
from ...errors import InputError, UnknownNameError
from ...fem.quality import is_curved
from ._faces import boundary_faces
from ._surface import MeshedSurface


#: discretizations of the gap between two bodies (``BodySurface(method=...)``)
METHODS = {
    "mortar": "segment-to-segment mortar weighted gap, dual (biorthogonal) multipliers: one constraint per slave "
              "node, passes the contact patch test on non-matching meshes (default)",
    "node-to-segment": "collocation: each slave node against its closest master point (fails the contact patch "
                       "test on non-matching meshes; for comparison)",
}


@dataclass(frozen=True)
class Segments:
    """The straight boundary segments of a body's boundary (2D, P1 or P2), reference configuration.

    Attributes
    ----------
    points : ndarray (m, 2)
        The boundary nodes, in the order of ``body.node_dofs(name)``.
    dofs : ndarray of int (m, 2)
        Their DOFs in the body's own numbering.
    ends : ndarray of int (s, 2)
        The two node indices (into ``points``) of every segment.
    normals : ndarray (s, 2)
        Outward unit normal of every segment (out of the body).
    lengths : ndarray (s,)
    nodes : ndarray of int (s, k)
        The nodes of every segment: its two ends (P1, ``k = 2``), then its midpoint (P2, ``k = 3``).
    """

    points: np.ndarray
    dofs: np.ndarray
    ends: np.ndarray
    normals: np.ndarray
    lengths: np.ndarray
    nodes: np.ndarray

    def node_normals(self) -> np.ndarray:
        """Unit normal at each node: the normalized sum of the normals of its segments (``(m, 2)``)."""
        acc = np.zeros_like(self.points)
        for k in range(self.nodes.shape[1]):
            np.add.at(acc, self.nodes[:, k], self.normals)
        norm = np.linalg.norm(acc, axis=1, keepdims=True)
        return acc / np.where(norm > 0, norm, 1.0)


def shape_functions(xi: np.ndarray, k: int) -> tuple[np.ndarray, ...]:
    """Lagrange shape functions of a segment at parameters ``xi`` in [0, 1]: ends, then midpoint (``k = 3``)."""
    if k == 2:
        return 1.0 - xi, xi
    return (1.0 - xi) * (1.0 - 2.0 * xi), xi * (2.0 * xi - 1.0), 4.0 * xi * (1.0 - xi)


def boundary_segments(body: Any, name: str) -> Segments:
    """:class:`Segments` of boundary ``name`` of a 2D P1 or P2 body (straight edges).

    Raises
    ------
    alcontact.errors.InputError
        The body is not 2D, a body of revolution, or P2 on a curved (second-order) mesh (mortar
        contact is 2D with straight edges for now).
    alcontact.errors.MeshError
        No boundary of that name (the message lists the known ones).
    """
    if getattr(body, "dim", None) != 2:
        raise InputError(f"mortar contact between bodies is available in 2D; the body of boundary {name!r} is "
                         f"{getattr(body, 'dim', '?')}D.")
    order = getattr(body, "order", 1)
    if order not in (1, 2) or (order == 2 and is_curved(body.mesh)):
        raise InputError(f"mortar contact between bodies is available for P1 and P2 bodies with straight edges; "
                         f"the body of boundary {name!r} has order={order} on a "
                         f"{'curved' if is_curved(body.mesh) else 'straight'} mesh: use order=1.")
    if getattr(body, "axisymmetric", False):
        raise InputError(f"mortar contact between bodies is available for Cartesian bodies; the body of boundary "
                         f"{name!r} is axisymmetric.")
    facets = body.facets(name)
    mesh = body.mesh
    pts, dofs = body.node_dofs(name)
    where = {int(d): i for i, d in enumerate(dofs[:, 0])}
    verts = mesh.facets[:, facets]  # (2, s)
    vdof = body.dof_map[body.scalar_dofs.nodal_dofs[0][verts], 0]  # (2, s)
    ends = np.array([[where[int(a)], where[int(b)]] for a, b in vdof.T], dtype=np.int64).reshape(-1, 2)
    nodes = ends
    if order == 2:  # the edge midpoints
        mdof = body.dof_map[body.scalar_dofs.facet_dofs[0][facets], 0]
        nodes = np.column_stack([ends, [where[int(d)] for d in mdof]]).astype(np.int64)
    x0, x1 = pts[ends[:, 0]], pts[ends[:, 1]]
    t = x1 - x0
    lengths = np.linalg.norm(t, axis=1)
    n = np.stack([t[:, 1], -t[:, 0]], axis=1) / lengths[:, None]
    cells = mesh.f2t[0, facets]
    centroid = mesh.p[:, mesh.t[:, cells]].mean(axis=1).T  # (s, 2)
    inward = np.einsum("ij,ij->i", centroid - 0.5 * (x0 + x1), n) > 0
    n[inward] *= -1.0
    return Segments(pts, dofs, ends, n, lengths, nodes)


class BodySurface:
    r"""The boundary ``name`` of a discretized body as the master of a contact pair (deformable).

    Parameters
    ----------
    body : alcontact.fem.LinearElasticity
        A 2D P1 or P2 body with straight edges, or a 3D body of linear tetrahedra (the master body).
    name : str
        One of its boundary names.
    search_distance : float, optional
        Master segments farther than this from a slave segment are not candidates of the
        mortar integrals (:mod:`alcontact.contact.kinematics._mortar`); default a quarter of the
        larger of the two boundaries' extents. A slave node with no candidate master segment
        over its support is open (it cannot come into contact).
    method : {"mortar", "node-to-segment"}
        The discretization of the gap (:data:`METHODS`): the mortar weighted gap with dual
        multipliers (default), or collocation at the slave nodes (each node's closest master point),
        the simpler one that fails the contact patch test on non-matching meshes (2D only).

    Notes
    -----
    The protocol's point queries (:meth:`evaluate`, :meth:`gap`, :meth:`project`) use the
    reference polyline: closest point on the segments, :math:`g = -(x - \bar x)\cdot\nu`,
    :math:`\nu` the outward normal of the closest segment; in 3D the reference triangles as a
    :class:`~alcontact.contact.MeshedSurface` (signed distance, facet normals). The contact
    constraints themselves are the mortar weighted gaps, which also move with the master body.

    Examples
    --------
    >>> from alcontact.fem import LinearElasticity, Material, meshes
    >>> base = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=1.0, nu=0.3))
    >>> top = BodySurface(base, "top")
    >>> top.rigid, top.gap([[0.5, 1.25]]).round(6).tolist()
    (False, [-0.25])
    """

    rigid = False
    name = "body-surface"

    def __init__(self, body: Any, name: str, *, search_distance: float | None = None, method: str = "mortar"):
        if not (hasattr(body, "facets") and hasattr(body, "node_dofs") and hasattr(body, "dim")):
            raise InputError(f"BodySurface: body = {type(body).__name__}: expected a discretized body "
                             "(alcontact.fem.LinearElasticity).")
        if not isinstance(name, str):
            raise InputError(f"BodySurface: name = {name!r:.40}: expected the name of a boundary of the body.")
        if not isinstance(method, str) or method not in METHODS:
            raise UnknownNameError("method", method, list(METHODS))
        (search_distance,) = check_args("BodySurface", [
            (Option("search_distance", "float", None, "Search distance of the master segments (None: default).",
                    low=0.0, high=VALUE_RANGE[1], low_open=True), search_distance)])
        self.body = body
        self.boundary = name
        self.search_distance = None if search_distance is None else float(search_distance)
        self.method = method
        #: the reference segments (2D) or triangles (3D, :class:`~alcontact.contact.masters._faces.Faces`)
        self.segments = self.faces = None
        if getattr(body, "dim", None) == 3:
            if method != "mortar":
                raise InputError(f"BodySurface: method = {method!r} is available in 2D; between 3D bodies the gap "
                                 "is the mortar one: use method='mortar'.")
            self.faces = boundary_faces(body, name)
            self._surface = MeshedSurface(self.faces.points, self.faces.nodes, source=f"boundary {name!r}")
        else:
            self.segments = boundary_segments(body, name)
            self._tree = cKDTree(0.5 * (self.segments.points[self.segments.ends[:, 0]]
                                        + self.segments.points[self.segments.ends[:, 1]]))

    @property
    def dim(self) -> int:
        return 3 if self.faces is not None else 2

    def describe(self) -> str:
        how = "" if self.method == "mortar" else f", {self.method}"
        count = (f"{self.faces.nodes.shape[0]} triangles" if self.faces is not None
                 else f"{self.segments.ends.shape[0]} segments")
        return f"the boundary {self.boundary!r} of a deformable body ({count}{how})"

    def check_dim(self, d: int) -> None:
        if d != self.dim:
            raise InputError(f"BodySurface: the master {self.boundary!r} is {self.dim}D; the slave body is {d}D.")

    # ------------------------------------------------------------ point queries on the reference polyline
    def _closest(self, x) -> tuple[np.ndarray, np.ndarray]:
        """Closest points on the polyline and the outward normal of their segment."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        s = self.segments
        a, b = s.points[s.ends[:, 0]], s.points[s.ends[:, 1]]
        k = min(8, a.shape[0])
        _, near = self._tree.query(x, k=k)
        near = np.asarray(near).reshape(x.shape[0], k)
        pa, pb = a[near], b[near]  # (m, k, 2)
        t = pb - pa
        tt = np.einsum("mkj,mkj->mk", t, t)
        xi = np.clip(np.einsum("mkj,mkj->mk", x[:, None, :] - pa, t) / tt, 0.0, 1.0)
        y = pa + xi[..., None] * t
        dist = np.linalg.norm(x[:, None, :] - y, axis=2)
        best = np.argmin(dist, axis=1)
        rows = np.arange(x.shape[0])
        return y[rows, best], s.normals[near[rows, best]]

    def evaluate(self, x):
        """``(gap, normal)``: :math:`g = -(x - \\bar x)\\cdot\\nu` and the outward normal :math:`\\nu` of the closest
        segment (3D: the signed distance to the reference triangles and its normal, as a
        :class:`~alcontact.contact.MeshedSurface`)."""
        if self.faces is not None:
            return self._surface.evaluate(x)
        x = np.atleast_2d(np.asarray(x, dtype=float))
        y, nu = self._closest(x)
        return -np.einsum("ij,ij->i", x - y, nu), nu

    def gap(self, x):
        return self.evaluate(x)[0]

    def normal(self, x):
        return self.evaluate(x)[1]

    def project(self, x):
        if self.faces is not None:
            return self._surface.project(x)
        return self._closest(x)[0]

    def gap_hessian(self, x):
        """Zero: the reference polyline (triangulation) is flat between its nodes."""
        return np.zeros((np.atleast_2d(x).shape[0], self.dim, self.dim))

    def surface_slip(self, x, y_prev, *, jacobian: bool = True):
        """Slip from ``y_prev`` to the projection of ``x`` (straight segments); Jacobian the tangent projector."""
        y = self.project(x)
        nu = self.normal(x)
        jac = (np.eye(self.dim)[None] - nu[:, :, None] * nu[:, None, :]) if jacobian else None
        return y - np.asarray(y_prev, dtype=float), jac

    def bounding_box(self, d: int):
        p = (self.faces if self.faces is not None else self.segments).points
        return p.min(axis=0), p.max(axis=0)
