r"""The boundary faces of a 3D body: the surface geometry of 3D two-body (mortar) contact.

A boundary of a body discretized with linear tetrahedra is a set of flat three-node
triangles; :func:`boundary_faces` gathers them in the reference configuration with their
nodes, DOFs, outward unit normals and areas (:class:`Faces`). The mortar integrals over
pairs of slave and master faces are in :mod:`alcontact.contact.kinematics._mortar3d`; the
point queries of the :class:`~alcontact.contact.BodySurface` protocol (closest point, signed
distance) use the same triangles as a :class:`~alcontact.contact.MeshedSurface`.

Quadratic faces (P2 tetrahedra: six-node triangles) are refused: the dual (biorthogonal)
basis of the six-node triangle has vertex functions whose integrals vanish
(:math:`\int N_{vertex} = 0`), so the diagonal mortar matrix ``D`` would be singular; a dual
quadratic mortar needs a modified basis (Popp, Wohlmuth, Gee & Wall, "Dual quadratic mortar
finite element methods for 3D finite deformation contact", SIAM J. Sci. Comput. 34, 2012),
which is not implemented.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ...errors import InputError


@dataclass(frozen=True)
class Faces:
    """The flat three-node boundary triangles of a 3D body's boundary, reference configuration.

    Attributes
    ----------
    points : ndarray (m, 3)
        The boundary nodes, in the order of ``body.node_dofs(name)``.
    dofs : ndarray of int (m, 3)
        Their DOFs in the body's own numbering.
    nodes : ndarray of int (s, 3)
        The three node indices (into ``points``) of every face, counter-clockwise seen from outside
        (the face normal :math:`(x_1 - x_0)\\times(x_2 - x_0)` points out of the body).
    normals : ndarray (s, 3)
        Outward unit normal of every face.
    areas : ndarray (s,)
    """

    points: np.ndarray
    dofs: np.ndarray
    nodes: np.ndarray
    normals: np.ndarray
    areas: np.ndarray

    @cached_property
    def centroids(self) -> np.ndarray:
        """Face centroids ``(s, 3)``."""
        return self.points[self.nodes].mean(axis=1)

    @cached_property
    def radii(self) -> np.ndarray:
        """Distance from each face's centroid to its farthest vertex ``(s,)``."""
        return np.linalg.norm(self.points[self.nodes] - self.centroids[:, None, :], axis=2).max(axis=1)

    @property
    def sizes(self) -> np.ndarray:
        r"""Element size of every face, :math:`\sqrt{2A}` (the size the contact systems use as ``h``)."""
        return np.sqrt(2.0 * self.areas)

    def node_normals(self) -> np.ndarray:
        """Unit normal at each node: the area-weighted mean of the normals of its faces (``(m, 3)``)."""
        acc = np.zeros_like(self.points)
        for k in range(self.nodes.shape[1]):
            np.add.at(acc, self.nodes[:, k], self.normals * self.areas[:, None])
        norm = np.linalg.norm(acc, axis=1, keepdims=True)
        return acc / np.where(norm > 0, norm, 1.0)

    def integrals(self) -> np.ndarray:
        r""":math:`D_j = \int N_j\,ds` of every node (a third of the area of each of its faces)."""
        D = np.zeros(self.points.shape[0])
        for k in range(3):
            np.add.at(D, self.nodes[:, k], self.areas / 3.0)
        return D


def boundary_faces(body: Any, name: str) -> Faces:
    """:class:`Faces` of boundary ``name`` of a 3D body of linear tetrahedra.

    Raises
    ------
    alcontact.errors.InputError
        The body is not 3D, or not P1 (module doc: quadratic faces have no dual basis with a
        non-singular ``D``).
    alcontact.errors.MeshError
        No boundary of that name (the message lists the known ones).
    """
    if getattr(body, "dim", None) != 3:
        raise InputError(f"boundary_faces: the body of boundary {name!r} is {getattr(body, 'dim', '?')}D; "
                         "3D faces need a 3D body.")
    order = getattr(body, "order", 1)
    if order != 1:
        raise InputError(f"3D mortar contact between bodies is available for linear tetrahedra (order=1); the body "
                         f"of boundary {name!r} has order={order}: the dual basis of a quadratic (six-node) face "
                         "has vertex functions of zero integral, so the mortar matrix D would be singular. Use "
                         "order=1 for both bodies (refine the mesh near the contact instead).")
    facets = body.facets(name)
    mesh = body.mesh
    pts, dofs = body.node_dofs(name)
    where = -np.ones(body.ndofs, dtype=np.int64)
    where[dofs[:, 0]] = np.arange(dofs.shape[0])
    verts = mesh.facets[:, facets]  # (3, s)
    nodes = where[body.dof_map[body.scalar_dofs.nodal_dofs[0][verts], 0]].T.copy()  # (s, 3)
    x0, x1, x2 = (pts[nodes[:, k]] for k in range(3))
    cr = np.cross(x1 - x0, x2 - x0)
    dbl = np.linalg.norm(cr, axis=1)
    n = cr / np.where(dbl > 0, dbl, 1.0)[:, None]
    cells = mesh.f2t[0, facets]
    centroid = mesh.p[:, mesh.t[:, cells]].mean(axis=1).T  # (s, 3)
    inward = np.einsum("ij,ij->i", centroid - (x0 + x1 + x2) / 3.0, n) > 0
    n[inward] *= -1.0
    nodes[inward] = nodes[inward][:, [0, 2, 1]]  # counter-clockwise seen from outside
    return Faces(pts, dofs, nodes, n, 0.5 * dbl)
