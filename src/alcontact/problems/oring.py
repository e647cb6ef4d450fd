r"""An O-ring seal squeezed in a rectangular groove by a flat cover (axisymmetric, nearly incompressible).

The cross-section of the ring (radius :math:`a`, centre at the radius :math:`R_c` from the axis) is a
disc in the r-z half-plane (``geometry = "axisymmetric"``: x is the radius, y the axis). The groove
(side walls at :math:`r_i`, :math:`r_o`, bottom) and the cover form a rectangular gland, every face rigid
and frictionless; the cover closes it by the squeeze :math:`\delta` (25 % of :math:`2a` for a static
seal). The gland and the ring are symmetric about the ring's mid-plane, and so is the solution (the
frictionless bottom and cover press the ring alike, the walls are vertical): the model is the upper
half of the cross-section, ``"cut"`` on the mid-plane with :math:`u_z = 0`, and the upper half of the
gland, one rigid ``convex-polygon-cavity`` master whose top face (the cover) moves down by
:math:`\delta / 2` (its vertical walls do not change under that translation). Contact is on ``"arc"``.

The mesh is the upper half disc, the image of :math:`[-1, 1] \times [0, 1]` (``2n x n`` squares, each
cut into two triangles) under the elliptical-grid map
:math:`(\xi, \eta) \mapsto (R_c + a\,\xi\sqrt{1 - \eta^2/2},\; a\,\eta\sqrt{1 - \xi^2/2})`; second order,
with the edge nodes of the arc projected onto the circle (the others at the edge midpoints), as
:func:`alcontact.problems.hemisphere.hemisphere_axisym`. :func:`write_msh` writes it as a Gmsh 2.2 file
(``triangle6``, ``line3``; physical names ``cut``, ``arc``, ``ring``), the mesh of
``examples/seal_oring.toml``.
"""

from __future__ import annotations

import dataclasses
import os

import numpy as np
import skfem


__all__ = ["oring_mesh", "write_msh"]


def _mirrored_grid(n: int) -> skfem.MeshTri:
    """:math:`[-1, 1] \times [0, 1]` in ``2n x n`` squares, cut along the diagonals that run towards the
    top corners (mirror-symmetric): the map's corners, where the boundary turns by 90 degrees onto
    the smooth circle, are then split into two triangles, none of which flattens (a 180-degree angle)."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n = {n!r} must be a positive integer.")
    i, j = np.meshgrid(np.arange(2 * n + 1), np.arange(n + 1), indexing="ij")
    p = np.vstack([-1.0 + i.ravel() / n, j.ravel() / n])
    node = np.arange((2 * n + 1) * (n + 1)).reshape(2 * n + 1, n + 1)
    tris = []
    for ci in range(2 * n):
        for cj in range(n):
            a, b, c, d = node[ci, cj], node[ci + 1, cj], node[ci + 1, cj + 1], node[ci, cj + 1]
            tris += [(a, b, c), (a, c, d)] if ci >= n else [(a, b, d), (b, c, d)]
    return skfem.MeshTri(p, np.array(tris, dtype=np.int64).T)


def oring_mesh(n: int = 8, *, section_radius: float = 1.0, ring_radius: float = 10.0) -> skfem.MeshTri2:
    """Second-order mesh of the upper half of the ring's cross-section (module doc).

    Parameters
    ----------
    n : int
        Elements across the half section's height (``4 n^2`` triangles).
    section_radius : float
        Radius :math:`a` of the cross-section (half the cord diameter).
    ring_radius : float
        Radius :math:`R_c > a` of the cross-section's centre from the axis.

    Returns
    -------
    skfem.MeshTri2
        With boundaries ``"cut"`` (the mid-plane :math:`z = 0`) and ``"arc"`` (the rest).
    """
    a, rc = float(section_radius), float(ring_radius)
    if not (a > 0 and rc > a):
        raise ValueError(f"need 0 < section_radius < ring_radius; got {a!r}, {rc!r}.")
    sq = _mirrored_grid(n)
    xi, eta = sq.doflocs
    r = rc + a * xi * np.sqrt(np.maximum(1.0 - eta**2 / 2.0, 0.0))
    z = a * eta * np.sqrt(np.maximum(1.0 - xi**2 / 2.0, 0.0))
    mesh = dataclasses.replace(sq, doflocs=np.vstack([r, z]), _boundaries=None)
    tol = 1e-9 * a
    m2 = skfem.MeshTri2.from_mesh(mesh)
    x = np.array(m2.doflocs, dtype=float)
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    arc = bf[mid[1] > tol]
    centre = np.array([rc, 0.0])
    d = x[:, mesh.nvertices + arc] - centre[:, None]
    x[:, mesh.nvertices + arc] = centre[:, None] + a * d / np.linalg.norm(d, axis=0)
    m2 = dataclasses.replace(m2, doflocs=x)
    return m2.with_boundaries({"cut": lambda p: p[1] < tol, "arc": lambda p: p[1] >= tol})


def write_msh(path: str | os.PathLike[str], n: int = 8, **kwargs) -> skfem.MeshTri2:
    """Write :func:`oring_mesh` as a Gmsh 2.2 ASCII file (17 significant digits) and return the mesh.

    Elements: ``line3`` on ``"cut"`` (tag 1) and ``"arc"`` (tag 2), ``triangle6`` for ``"ring"`` (tag 3),
    in Gmsh's node order (vertices, then the nodes of the edges 0-1, 1-2, 2-0).
    """
    mesh = oring_mesh(n, **kwargs)
    nv = int(mesh.t.max()) + 1
    edge_of = {tuple(sorted(map(int, e))): k for k, e in enumerate(mesh.facets.T)}
    tri = [[*map(int, t), *(nv + edge_of[tuple(sorted((int(t[i]), int(t[j]))))] for i, j in ((0, 1), (1, 2), (2, 0)))]
           for t in mesh.t.T]
    blocks = [(8, tag, [[int(mesh.facets[0, f]), int(mesh.facets[1, f]), nv + int(f)]
                        for f in mesh.boundaries[name]]) for tag, name in ((1, "cut"), (2, "arc"))]
    blocks.append((9, 3, tri))
    pts = mesh.doflocs
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "3",
           '1 1 "cut"', '1 2 "arc"', '2 3 "ring"', "$EndPhysicalNames", "$Nodes", str(pts.shape[1])]
    out += [f"{i + 1} {pts[0, i]:.17g} {pts[1, i]:.17g} 0" for i in range(pts.shape[1])]
    out += ["$EndNodes", "$Elements", str(sum(len(c) for _, _, c in blocks))]
    k = 0
    for typ, tag, conn in blocks:
        for e in conn:
            k += 1
            out.append(f"{k} {typ} 2 {tag} {tag} " + " ".join(str(v + 1) for v in e))
    out += ["$EndElements", ""]
    with open(path, "w", encoding="ascii") as fh:
        fh.write("\n".join(out))
    return mesh
