r"""Mesh quality: inverted (folded) and degenerate elements of triangle and tetrahedron meshes.

A finite element mesh must cover the body once: every element has a non-zero
measure and all elements have the same orientation (the sign of the Jacobian
:math:`\det \partial x / \partial \xi`). A *tangled* mesh, where some elements
are turned inside out, still assembles a regular stiffness matrix but describes
a body that overlaps itself, so the solve "converges" to wrong forces; a
*degenerate* element (zero or nearly zero area/volume) makes the stiffness
singular or useless.

The check does not rely on the vertex order stored in the mesh (scikit-fem
sorts the vertices of triangles, which loses their orientation). It tests every
interior facet instead: in a valid mesh the two elements sharing a facet lie
on opposite sides of it. A facet whose two opposite vertices lie on the same
side is *folded*. The elements connected without crossing a folded facet have
one orientation; crossing a fold flips it. The orientation held by most
elements is the body's, elements of the other orientation are reported as
inverted.

Examples
--------
>>> from alcontact.fem import meshes
>>> from alcontact.fem.quality import check_mesh_quality, mesh_quality
>>> m = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
>>> check_mesh_quality(m)                  # raises MeshError on a bad mesh
>>> mesh_quality(m).ok
True
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import scipy.sparse as sp
import skfem
from scipy.sparse.csgraph import connected_components

from alcontact.errors import MeshError

__all__ = ["MeshQuality", "mesh_quality", "check_mesh_quality", "element_measures", "curved_jacobian_ratio",
           "CurvedMapping", "element_mapping", "is_curved", "DEGENERATE_RATIO", "CURVED_CHECK_INTORDER"]

logger = logging.getLogger(__name__)

#: An element is degenerate when its area/volume is at most this fraction of
#: (longest edge)^dim (an equilateral triangle has 0.43, a regular tetrahedron 0.12;
#: a 1 x 1e-8 sliver triangle 5e-9).
DEGENERATE_RATIO = 1e-8

#: Elements named in an error message (the count is always given).
_SHOWN = 5


@dataclasses.dataclass(frozen=True)
class MeshQuality:
    """Result of :func:`mesh_quality`.

    Attributes
    ----------
    inverted : ndarray of int
        Elements whose orientation is opposite to that of most elements.
    curved_inverted : ndarray of int
        Second-order (curved) elements whose isoparametric map has a Jacobian of the
        wrong sign or zero at a quadrature point or a node (:func:`curved_jacobian_ratio`).
    min_jacobian_ratio : float
        Smallest ratio of the curved element's Jacobian to its straight element's
        (1 for straight meshes).
    degenerate : ndarray of int
        Elements with zero or near-zero measure (see :data:`DEGENERATE_RATIO`).
    folded_facets : ndarray of int
        Interior facets whose two elements lie on the same side.
    centroids : ndarray, shape (nelements, dim)
        Element centroids (for messages).
    min_ratio : float
        Smallest measure / (longest edge)^dim over the elements.
    """

    inverted: np.ndarray
    degenerate: np.ndarray
    folded_facets: np.ndarray
    centroids: np.ndarray
    min_ratio: float
    curved_inverted: np.ndarray = dataclasses.field(default_factory=lambda: np.empty(0, dtype=np.int64))
    min_jacobian_ratio: float = 1.0

    @property
    def ok(self) -> bool:
        return self.inverted.size == 0 and self.degenerate.size == 0 and self.curved_inverted.size == 0

    def message(self, label: str = "the mesh") -> str:
        """What is wrong (element indices and centroids) and the way out; ``""`` when :attr:`ok`."""
        parts = []
        if self.degenerate.size:
            parts.append(
                f"{label} has {self.degenerate.size} degenerate element(s) (zero or near-zero area/volume, "
                f"below {DEGENERATE_RATIO:g} x longest edge^dim): {self._where(self.degenerate)}. Remove "
                "duplicate or collinear/coplanar nodes and re-mesh (in Gmsh: Mesh > Optimize, or "
                "Geometry.Tolerance)."
            )
        if self.inverted.size:
            parts.append(
                f"{label} has {self.inverted.size} inverted element(s) (turned inside out: negative Jacobian "
                f"relative to the other {self.centroids.shape[0] - self.inverted.size} elements; the mesh "
                f"overlaps itself across {self.folded_facets.size} folded facet(s) and would give wrong "
                f"forces): {self._where(self.inverted)}. Re-mesh the body, or undo the node moves that "
                "folded these elements."
            )
        if self.curved_inverted.size:
            parts.append(
                f"{label} has {self.curved_inverted.size} second-order element(s) whose edge nodes make the "
                f"element map invert (Jacobian <= 0 at a quadrature point or node; smallest Jacobian / straight "
                f"element's = {self.min_jacobian_ratio:.3g}): {self._where(self.curved_inverted)}. Move the "
                "edge nodes back towards the edge midpoints (in Gmsh: Mesh.HighOrderOptimize = 2, or a finer "
                "mesh along the curved boundary), or read the mesh with order 1."
            )
        return " ".join(parts)

    def _where(self, elements: np.ndarray) -> str:
        shown = ", ".join(
            f"element {int(e)} at {np.round(self.centroids[e], 6).tolist()}" for e in elements[:_SHOWN]
        )
        more = f" and {elements.size - _SHOWN} more" if elements.size > _SHOWN else ""
        return shown + more


def element_measures(mesh) -> np.ndarray:
    """Signed area (2D) or volume (3D) of every element, for the vertex order stored in ``mesh.t``.

    The sign alone means nothing for scikit-fem triangles (their vertices are
    stored sorted); see :func:`mesh_quality` for the orientation test.
    """
    p, t = np.asarray(mesh.p, dtype=float), np.asarray(mesh.t)
    dim = p.shape[0]
    e = [p[:, t[k]] - p[:, t[0]] for k in range(1, dim + 1)]  # (dim, nel) each
    if dim == 2:
        return 0.5 * (e[0][0] * e[1][1] - e[0][1] * e[1][0])
    if dim == 3:
        return np.einsum("ij,ij->j", e[0], np.cross(e[1], e[2], axis=0)) / 6.0
    raise MeshError(f"mesh quality is defined for triangle and tetrahedron meshes; got a {dim}D mesh.")


def _longest_edge(p: np.ndarray, t: np.ndarray) -> np.ndarray:
    nv = t.shape[0]
    out = np.zeros(t.shape[1])
    for a in range(nv):
        for b in range(a + 1, nv):
            out = np.maximum(out, np.linalg.norm(p[:, t[a]] - p[:, t[b]], axis=0))
    return out


def _facet_side(p: np.ndarray, fv: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Signed distance-like side of points ``x`` (dim, n) from facets ``fv`` (dim, n) (vertex indices)."""
    dim = p.shape[0]
    a = p[:, fv[0]]
    if dim == 2:
        d = p[:, fv[1]] - a
        n = np.stack([-d[1], d[0]])
    else:
        n = np.cross(p[:, fv[1]] - a, p[:, fv[2]] - a, axis=0)
    return np.einsum("ij,ij->j", n, x - a)


def is_curved(mesh) -> bool:
    """Whether ``mesh`` is a second-order (isoparametric) simplex mesh, ``MeshTri2`` or ``MeshTet2``.

    Its ``doflocs`` hold the vertices, then one node per edge (2D: facet) that need not be
    the edge midpoint: the element map is the quadratic interpolant of these nodes, so
    boundary edges/faces follow the curved geometry. (For these meshes scikit-fem's
    ``mesh.p`` is the whole ``doflocs``; ``mesh.t`` indexes the vertices only.)
    """
    return isinstance(mesh, (skfem.MeshTri2, skfem.MeshTet2))


class CurvedMapping(skfem.MappingIsoparametric):
    """scikit-fem's isoparametric map of a curved mesh, with an inverse that stops at round-off.

    :meth:`invF` (global point -> reference coordinates, used by facet bases and point probes)
    is scikit-fem's Newton iteration, but scikit-fem asks every element's step to fall below
    an absolute 1e-12, which round-off alone can exceed on fine meshes (half-cylinder P2
    with 80 or 112 elements per radius: steps 5.5e-5, 2.5e-8, 3.3e-12, then 1-5e-12 for ever).
    Here the iteration stops once the step is below 1e-10 (the point just computed is then
    exact to about the square of that, the iteration being quadratic) or once it no longer
    decreases (its round-off floor, reached after quadratic convergence below 1e-8).
    """

    def invF(self, x, tind=None, newton_max_iters=50, newton_tol=1e-10):
        """Reference coordinates of the global points ``x`` (shape ``(d, nelems, npoints)``)."""
        X = np.zeros(x.shape) + 0.5
        previous = np.inf
        for _ in range(newton_max_iters):
            dX = np.einsum("ijkl,jkl->ikl", self.invDF(X, tind), x - self.F(X, tind))
            X = np.clip(X + dX, 0.0, 1.0)
            step = float(np.max(np.linalg.norm(dX, 1, (0, 2)), initial=0.0))
            if step < newton_tol or (step < 1e-8 and step >= previous):
                return X
            previous = step
        raise MeshError(f"the inverse of the curved element map did not converge (last Newton step {step:.1e} "
                        f"in reference coordinates): check the mesh's second-order nodes with `alcontact check`.")


def element_mapping(mesh):
    """The element map of ``mesh``: :class:`CurvedMapping` for a curved mesh, else scikit-fem's own."""
    if is_curved(mesh):
        return CurvedMapping(mesh, mesh.elem(), mesh.bndelem)
    return mesh.mapping()


#: Quadrature degree at whose points the Jacobian of a curved element is checked (besides its nodes).
CURVED_CHECK_INTORDER = 4


def curved_jacobian_ratio(mesh) -> np.ndarray:
    r"""Jacobian of the isoparametric map over that of the straight element, per element and point.

    For a second-order mesh (``MeshTri2``/``MeshTet2``) the element map
    :math:`x(\xi) = \sum_a x_a N_a(\xi)` is quadratic; its Jacobian
    :math:`\det \partial x/\partial \xi` is evaluated at the quadrature points of degree
    :data:`CURVED_CHECK_INTORDER` and at the element's nodes (vertices and edge nodes),
    and divided by the constant Jacobian of the straight element on the same vertices.
    A valid curved element has ratios > 0 (1 everywhere when the edge nodes are the
    midpoints); a ratio <= 0 means the map folds over.

    Returns
    -------
    ndarray, shape (nelements, npoints)
    """
    from skfem.quadrature import get_quadrature

    X, _ = get_quadrature(mesh.refdom, CURVED_CHECK_INTORDER)
    nodes = mesh.elem().doflocs.T  # reference coordinates of the element's nodes, (dim, nloc)
    pts = np.hstack([X, nodes])
    jac = np.asarray(mesh.mapping().detDF(pts))  # (nel, npts)
    dim = mesh.dim()
    straight = element_measures(mesh) * (2.0 if dim == 2 else 6.0)  # detDF of the affine map, same vertex order
    with np.errstate(divide="ignore", invalid="ignore"):
        return jac / straight[:, None]


def mesh_quality(mesh) -> MeshQuality:
    """Find the inverted and degenerate elements of a triangle or tetrahedron mesh.

    Parameters
    ----------
    mesh : skfem.MeshTri, skfem.MeshTet, skfem.MeshTri2 or skfem.MeshTet2
        Simplex mesh; of a second-order mesh the straight elements on its vertices are
        checked as for a linear one, and the curved map by :func:`curved_jacobian_ratio`.

    Returns
    -------
    MeshQuality
    """
    p, t = np.asarray(mesh.p, dtype=float), np.asarray(mesh.t)  # second order: p has the edge nodes too
    dim, nel = p.shape[0], t.shape[1]
    if t.shape[0] != dim + 1:
        raise MeshError(f"mesh quality needs linear triangles or tetrahedra; got {t.shape[0]} vertices per element.")
    if not np.all(np.isfinite(p)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(p), axis=0))[0])
        raise MeshError(f"the mesh has non-finite node coordinates (node {bad}: {p[:, bad].tolist()}); "
                        "fix or re-export the mesh file.")
    centroids = p[:, t].mean(axis=1).T
    vol = np.abs(element_measures(mesh))
    with np.errstate(divide="ignore", invalid="ignore", under="ignore"):  # 0/0 for collapsed elements: degenerate
        ratio = vol / np.maximum(_longest_edge(p, t), np.finfo(float).tiny) ** dim
    ratio = np.where(vol > 0, np.nan_to_num(ratio, nan=0.0), 0.0)
    degenerate = np.flatnonzero(ratio <= DEGENERATE_RATIO)

    # interior facets and their two elements
    f2t = np.asarray(mesh.f2t)
    inner = np.flatnonzero(f2t[1] >= 0)
    ea, eb = f2t[0, inner], f2t[1, inner]
    fv = np.asarray(mesh.facets)[:, inner]
    fsum = fv.sum(axis=0)
    opp_a = t[:, ea].sum(axis=0) - fsum  # the vertex of each element not on the facet
    opp_b = t[:, eb].sum(axis=0) - fsum
    sa = _facet_side(p, fv, p[:, opp_a])
    sb = _facet_side(p, fv, p[:, opp_b])
    good = np.ones(nel, dtype=bool)
    good[degenerate] = False
    usable = good[ea] & good[eb]
    folded = usable & (sa * sb > 0)
    folded_facets = inner[folded]

    inverted = np.empty(0, dtype=np.int64)
    if folded_facets.size:
        keep = usable & ~folded
        graph = sp.coo_matrix((np.ones(int(keep.sum())), (ea[keep], eb[keep])), shape=(nel, nel))
        ncomp, label = connected_components(graph, directed=False)
        # two-colour the components: crossing a folded facet flips the orientation
        ca, cb = label[ea[folded]], label[eb[folded]]
        adj = sp.coo_matrix((np.ones(ca.size), (ca, cb)), shape=(ncomp, ncomp)).tocsr()
        adj = ((adj + adj.T) > 0).tocsr()
        colour = np.full(ncomp, -1, dtype=np.int64)
        consistent = True
        for start in np.unique(np.concatenate([ca, cb])):
            if colour[start] >= 0:
                continue
            colour[start] = 0
            stack = [int(start)]
            while stack:
                c = stack.pop()
                for nb in adj.indices[adj.indptr[c]:adj.indptr[c + 1]]:
                    if colour[nb] < 0:
                        colour[nb] = 1 - colour[c]
                        stack.append(int(nb))
                    elif colour[nb] == colour[c]:
                        consistent = False
        colour[colour < 0] = 0  # components without folds keep the colour of the majority below
        el_colour = colour[label]
        el_colour[~good] = -1
        n1, n0 = int(np.sum(el_colour == 1)), int(np.sum(el_colour == 0))
        minority = 1 if n1 <= n0 else 0
        if consistent:
            inverted = np.flatnonzero(el_colour == minority)
        else:  # no consistent orientation: report the elements around the folds
            inverted = np.unique(np.concatenate([ea[folded], eb[folded]]))
    curved = np.empty(0, dtype=np.int64)
    min_jac = 1.0
    if is_curved(mesh):  # second-order nodes: check the curved map of the valid elements
        r = curved_jacobian_ratio(mesh)
        r[~good] = 1.0
        bad = ~(r > 0.0)
        curved = np.setdiff1d(np.flatnonzero(bad.any(axis=1)), inverted)
        min_jac = float(np.nanmin(np.where(np.isfinite(r), r, 1.0), initial=1.0))
    return MeshQuality(inverted=inverted.astype(np.int64), degenerate=degenerate.astype(np.int64),
                       folded_facets=folded_facets.astype(np.int64), centroids=centroids,
                       min_ratio=float(ratio.min(initial=np.inf)), curved_inverted=curved.astype(np.int64),
                       min_jacobian_ratio=min_jac)


def check_mesh_quality(mesh, label: str = "the mesh") -> MeshQuality:
    """Raise :class:`~alcontact.errors.MeshError` naming the inverted/degenerate elements, else return the report.

    Parameters
    ----------
    mesh : skfem.MeshTri or skfem.MeshTet
    label : str
        How the message names the mesh (e.g. the file).
    """
    q = mesh_quality(mesh)
    if not q.ok:
        raise MeshError(q.message(label))
    return q
