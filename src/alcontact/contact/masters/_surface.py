r"""A meshed rigid surface master: a polyline (2D) or a triangulated surface (3D), convex or not.

The surface is given by its vertices and facets (segments in 2D, triangles in 3D), from
Python, from an STL file, or from a Gmsh physical group (both read with meshio). It is
registered as the obstacle ``"surface"``.

Gap and normal (the choice, and why)
------------------------------------
The gap is the exact **signed Euclidean distance** to the facets (sign convention of
(6.15): :math:`g \le 0` on the free side),

.. math::

    g(x) = -s(x)\,\lVert x - c(x)\rVert, \qquad
    \nu(x) = -\nabla g = s(x)\,\frac{x - c(x)}{\lVert x - c(x)\rVert},

with :math:`c(x)` the closest point of the surface (closest-point projection over the
candidate facets of a :class:`scipy.spatial.cKDTree` on facet centroids, then the exact
point-segment / point-triangle distance) and the sign :math:`s = \operatorname{sign}
((x - c)\cdot n_c)` taken from the angle-weighted *pseudo-normal* :math:`n_c` of the
feature that holds :math:`c` (the facet normal inside a facet; the mean of the adjacent
facet normals on an edge; the angle-weighted mean at a vertex — Bærentzen & Aanæs 2005,
which makes the sign right everywhere for a consistently oriented surface).

So the gap is continuous (Lipschitz) everywhere; inside a facet's normal prism the normal
is that facet's normal and the gap is linear (a meshed plane *is* the analytic plane: same
gap, normal and a zero Hessian); near a vertex or an edge the normal turns with the
direction from the closest point, exactly as the analytic distance of a polygon does
(continuous on the free side of a convex corner). No smoothing of the facet normals is
applied: a smoothed normal would not be the gradient of the gap, and the consistent
linearization of the finite path needs :math:`\nu = -\nabla g` and
:math:`H = \nabla^2 g`. The Hessian is therefore zero inside facets and the curvature of the
distance to the feature elsewhere: :math:`H = -s\,(I - e e^T)/d` at a vertex,
:math:`H = -s\,(I - e e^T - t t^T)/d` on a 3D edge of direction :math:`t`
(:math:`e = (x - c)/d`, :math:`d = \lVert x - c \rVert`); set to zero where
:math:`d` is below round-off. Where the closest point is not unique (the medial axis: the
bisector of a concave corner), the gap has a kink and the normal is one of the one-sided
gradients, chosen deterministically.

An open surface (a polyline with two ends, a triangulation with a border) separates space
only near itself: a point whose closest point is on the border takes the side of the border
facets, and behind the border the sign flips across the facet's plane. Let the surface reach
well beyond where the body can touch it.

Orientation
-----------
The free side is the side the facet normals point to: the normal of a segment
:math:`a \to b` is the tangent turned clockwise, :math:`(t_y, -t_x)/|t|` (a
counter-clockwise polygon is a solid obstacle, the body outside); the normal of a triangle
:math:`(a, b, c)` is :math:`(b - a)\times(c - a)` normalized (the STL convention: outward
of a closed solid). A surface whose neighbouring facets disagree (a segment reversed, a
triangle wound the other way: an edge walked twice in the same direction) is refused with
an :class:`~alcontact.errors.InputError` naming the facets; so is a non-manifold one
(three facets on an edge, a vertex of three segments).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from ..._options import show
from ...errors import InputError
from . import obstacles
from .obstacles import FloatArray, _ObstacleBase

_TINY = 1e-14  # relative distance below which a point is on the surface (normal: the pseudo-normal)


def _unit(v: FloatArray) -> FloatArray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


@dataclass(frozen=True, eq=False)
class MeshedSurface(_ObstacleBase):
    r"""Rigid master given by a polyline (2D, segments) or a triangulated surface (3D, triangles).

    Parameters
    ----------
    vertices : array_like, shape (n, d)
        Vertex coordinates, ``d`` = 2 (polyline) or 3 (triangles).
    facets : array_like of int, shape (k, d)
        Vertex indices of each segment (2D) or triangle (3D); the orientation sets the free
        side (see the module docstring).
    source : str, optional
        Where the surface comes from, for messages (a file name and group).

    Examples
    --------
    A V-shaped groove (non-convex), free side above:

    >>> ob = MeshedSurface([[-2.0, 1.0], [0.0, 0.0], [2.0, 1.0]], [[2, 1], [1, 0]])
    >>> ob.gap([[0.0, 0.5], [0.0, -0.5]])  # above the bottom (closest: a wall), below it (the vertex)
    array([-0.4472136,  0.5      ])
    """

    vertices: Any
    facets: Any
    source: str = ""

    def __post_init__(self) -> None:
        want_v = "the vertex coordinates, an array of shape (n, 2) (a polyline) or (n, 3) (triangles), n >= 2"
        try:
            v = np.array(self.vertices, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"surface: vertices = {show(self.vertices)}: expected {want_v}.") from None
        if v.ndim != 2 or v.shape[1] not in (2, 3) or v.shape[0] < 2 or not np.all(np.isfinite(v)):
            raise InputError(f"surface: vertices = {show(self.vertices)}: expected {want_v}, finite.")
        d = v.shape[1]
        want_f = (f"integer vertex indices of shape (k, {d}): the {'segments' if d == 2 else 'triangles'} of a "
                  f"{d}D surface, k >= 1")
        try:
            f = np.array(self.facets)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"surface: facets = {show(self.facets)}: expected {want_f}.") from None
        if f.ndim != 2 or f.shape[1] != d or f.shape[0] < 1 or not (np.issubdtype(f.dtype, np.integer) or (
                np.issubdtype(f.dtype, np.floating) and np.all(np.isfinite(f)) and np.all(f == np.round(f)))):
            raise InputError(f"surface: facets = {show(self.facets)}: expected {want_f}.")
        f = f.astype(np.int64)
        if f.min() < 0 or f.max() >= v.shape[0]:
            bad = int(f.max()) if f.max() >= v.shape[0] else int(f.min())
            raise InputError(f"surface: facets = {show(self.facets)}: vertex index {bad} is outside 0 .. "
                             f"{v.shape[0] - 1} (the rows of vertices, numbered from 0).")
        set_ = object.__setattr__
        set_(self, "vertices", v)
        set_(self, "facets", f)
        a = v[f[:, 0]]
        if d == 2:
            t = v[f[:, 1]] - a
            size = np.linalg.norm(t, axis=1)
            normals = np.stack([t[:, 1], -t[:, 0]], axis=1)
        else:
            cr = np.cross(v[f[:, 1]] - a, v[f[:, 2]] - a)
            size = np.linalg.norm(cr, axis=1)
            normals = cr
        if np.any(size <= 1e-12 * max(float(np.ptp(v, axis=0).max()), 1e-300)):
            k = int(np.flatnonzero(size <= 1e-12 * max(float(np.ptp(v, axis=0).max()), 1e-300))[0])
            raise InputError(f"surface{self._where()}: facet {k} (vertices {f[k].tolist()}) is degenerate (zero "
                             "length or area); remove it from the surface mesh.")
        object.__setattr__(self, "normals", _unit(normals))
        self._check_orientation()
        self._pseudo()
        object.__setattr__(self, "centroids", v[f].mean(axis=1))
        object.__setattr__(self, "radius", float(np.max(np.linalg.norm(v[f] - self.centroids[:, None, :], axis=2))))
        object.__setattr__(self, "tree", cKDTree(self.centroids))
        object.__setattr__(self, "scale", float(np.ptp(v, axis=0).max()))
        for key, value in vars(self).items():  # immutable, as every obstacle
            if isinstance(value, np.ndarray):
                value.flags.writeable = False

    # ------------------------------------------------------------ construction checks
    def _where(self) -> str:
        return f" ({self.source})" if self.source else ""

    def _check_orientation(self) -> None:
        """Neighbouring facets agree on the orientation; the surface is a manifold."""
        f = self.facets
        d = f.shape[1]
        if d == 2:
            for col, what in ((0, "starts"), (1, "ends")):
                vals, first, counts = np.unique(f[:, col], return_index=True, return_counts=True)
                if np.any(counts > 1):
                    vtx = int(vals[np.argmax(counts > 1)])
                    ks = np.flatnonzero(f[:, col] == vtx)[:2].tolist()
                    raise InputError(
                        f"surface{self._where()}: segments {ks[0]} and {ks[1]} both {what[:-1]} at vertex {vtx} "
                        f"{self.vertices[vtx].tolist()}: the polyline's orientation is inconsistent (or three "
                        "segments meet there). Orient every segment the same way along the curve (the free side "
                        "is on the right of the walking direction; reverse the segments that disagree).")
            return
        edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        owner = np.tile(np.arange(f.shape[0]), 3)
        key = np.sort(edges, axis=1)
        _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        inv = inv.ravel()
        if np.any(counts > 2):
            e = int(np.argmax(counts > 2))
            ks = owner[inv == e][:3].tolist()
            raise InputError(f"surface{self._where()}: triangles {ks} share one edge (a non-manifold surface); give "
                             "a surface in which every edge belongs to at most two triangles.")
        _, dcount = np.unique(edges, axis=0, return_counts=True)
        if np.any(dcount > 1):
            uniq, inv2 = np.unique(edges, axis=0, return_inverse=True)
            bad = int(np.argmax(dcount > 1))
            ks = owner[inv2.ravel() == bad][:2].tolist()
            raise InputError(
                f"surface{self._where()}: triangles {ks[0]} and {ks[1]} walk their common edge "
                f"{uniq[bad].tolist()} in the same direction: the surface's orientation is inconsistent. Wind "
                "every triangle the same way (counter-clockwise seen from the free side, the STL convention) and "
                "write the file again.")

    def _pseudo(self) -> None:
        """Angle-weighted pseudo-normals of the vertices and (3D) the edges, for the sign of the gap."""
        v, f, n = self.vertices, self.facets, self.normals
        d = v.shape[1]
        vn = np.zeros_like(v)
        if d == 2:
            np.add.at(vn, f[:, 0], n)
            np.add.at(vn, f[:, 1], n)
            object.__setattr__(self, "vertex_normals", _unit(vn))
            return
        for i in range(3):
            a, b, c = v[f[:, i]], v[f[:, (i + 1) % 3]], v[f[:, (i + 2) % 3]]
            e1, e2 = _unit(b - a), _unit(c - a)
            ang = np.arccos(np.clip(np.einsum("ij,ij->i", e1, e2), -1.0, 1.0))
            np.add.at(vn, f[:, i], ang[:, None] * n)
        object.__setattr__(self, "vertex_normals", _unit(vn))
        edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        key = np.sort(edges, axis=1)
        uniq, inv = np.unique(key, axis=0, return_inverse=True)
        en = np.zeros((uniq.shape[0], 3))
        np.add.at(en, inv.ravel(), np.tile(n, (3, 1)))
        object.__setattr__(self, "_edge_keys", uniq)
        object.__setattr__(self, "edge_normals", _unit(en))
        # edge index of (facet, local edge i: vertices i, i+1)
        object.__setattr__(self, "_facet_edge", inv.ravel().reshape(3, -1).T)

    # ------------------------------------------------------------ the master protocol
    @property
    def dim(self) -> int:
        return int(self.vertices.shape[1])

    @property
    def name(self) -> str:
        return "surface"

    def describe(self) -> str:
        kind = "polyline" if self.dim == 2 else "triangulated surface"
        src = f" from {self.source}" if self.source else ""
        return f"meshed {kind}{src} ({self.facets.shape[0]} facets)"

    def check_dim(self, d: int) -> None:
        if int(d) != self.dim:
            have = "a 2D polyline (segments)" if self.dim == 2 else "a 3D triangulated surface"
            want = ("a polyline: line elements, e.g. a Gmsh physical group of curves" if int(d) == 2
                    else "a triangulated surface: an STL file or a Gmsh physical group of surfaces")
            raise InputError(f"obstacle {self.describe()} is {have} but the body is {d}D; a {d}D body needs {want}.")

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def _closest(self, x: FloatArray):
        """Closest point of the surface to each row of ``x``: ``(c, facet, feature, local)``.

        ``feature`` is 0 (inside the facet), 1 (on an edge; ``local`` its local index, the
        edge from local vertex ``local`` to the next) or 2 (at a vertex; ``local`` its local index).
        """
        m = x.shape[0]
        if m == 0:
            e = np.zeros(0, dtype=np.int64)
            return np.zeros((0, self.dim)), e, e, e, np.zeros(0)
        k = min(4, self.facets.shape[0])
        _, near = self.tree.query(x, k=k)
        near = np.asarray(near).reshape(m, k)
        best = self._distance(x, near.ravel(), np.repeat(np.arange(m), k))
        dist = best[0].reshape(m, k)
        j = np.argmin(dist, axis=1)
        bound = dist[np.arange(m), j] + self.radius * (1 + 1e-12) + 1e-300
        # every facet whose centroid is within (best distance + facet radius) may be closer
        lists = self.tree.query_ball_point(x, bound)
        rows = np.repeat(np.arange(m), [len(li) for li in lists])
        cand = np.fromiter((c for li in lists for c in li), dtype=np.int64, count=rows.size)
        dd, cc, feat, loc = self._distance(x, cand, rows)
        order = np.lexsort((cand, dd, rows))  # per point: smallest distance, then lowest facet index
        rows_o = rows[order]
        first = order[np.r_[True, rows_o[1:] != rows_o[:-1]]]
        return cc[first], cand[first], feat[first], loc[first], dd[first]

    def _distance(self, x: FloatArray, facet: np.ndarray, row: np.ndarray):
        """Exact distance from ``x[row]`` to ``facet`` (vectorized); closest point and its feature."""
        p = x[row]
        v = self.vertices[self.facets[facet]]
        if self.dim == 2:
            a, b = v[:, 0], v[:, 1]
            t = b - a
            s = np.einsum("ij,ij->i", p - a, t) / np.einsum("ij,ij->i", t, t)
            feat = np.where((s >= 0) & (s <= 1), 0, 2)  # ties (a point on a prism's side) to the facet
            loc = np.where(s >= 1, 1, 0)
            s = np.clip(s, 0.0, 1.0)
            c = a + s[:, None] * t
        else:
            c, feat, loc = _closest_on_triangles(p, v[:, 0], v[:, 1], v[:, 2])
        return np.linalg.norm(p - c, axis=1), c, feat, loc

    def _features(self, x: FloatArray):
        c, facet, feat, loc, dist = self._closest(x)
        # pseudo-normal of the feature holding c: the sign of the gap
        if self.dim == 2:
            pn = np.where((feat == 0)[:, None], self.normals[facet],
                          self.vertex_normals[self.facets[facet, loc]])
        else:
            pn = self.normals[facet].copy()
            on_edge = feat == 1
            pn[on_edge] = self.edge_normals[self._facet_edge[facet[on_edge], loc[on_edge]]]
            at_v = feat == 2
            pn[at_v] = self.vertex_normals[self.facets[facet[at_v], loc[at_v]]]
        diff = x - c
        tiny = dist <= _TINY * max(self.scale, 1.0)
        e = np.where(tiny[:, None], pn, diff / np.where(tiny, 1.0, dist)[:, None])
        side = np.einsum("ij,ij->i", diff, pn)
        s = np.where(tiny | (side >= 0), 1.0, -1.0)
        return c, facet, feat, loc, dist, s, e

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        _, facet, feat, _, dist, s, e = self._features(x)
        nu = s[:, None] * e
        inside = feat == 0  # exactly the facet normal inside a facet (a meshed plane is the plane)
        nu[inside] = self.normals[facet[inside]]
        return -s * dist, nu

    def project(self, x: ArrayLike) -> FloatArray:
        from .obstacles import _points

        return self._features(_points(x, self.dim))[0]

    def _hessian(self, x: FloatArray) -> FloatArray:
        _, facet, feat, loc, dist, s, e = self._features(x)
        m, d = x.shape
        H = np.zeros((m, d, d))
        curved = (feat > 0) & (dist > _TINY * max(self.scale, 1.0))
        if not np.any(curved):
            return H
        P = np.eye(d)[None] - e[:, :, None] * e[:, None, :]
        if d == 3:
            on_edge = curved & (feat == 1)
            f = self.facets[facet[on_edge]]
            i = loc[on_edge]
            t = _unit(self.vertices[f[np.arange(f.shape[0]), (i + 1) % 3]] - self.vertices[f[np.arange(f.shape[0]), i]])
            P[on_edge] -= t[:, :, None] * t[:, None, :]
        H[curved] = -(s[curved] / dist[curved])[:, None, None] * P[curved]
        return H


def _closest_on_triangles(p: FloatArray, a: FloatArray, b: FloatArray, c: FloatArray):
    """Closest point of triangles ``(a, b, c)`` to ``p`` (rows; Ericson, *Real-Time Collision Detection* 5.1.5).

    Returns ``(point, feature, local)``: feature 0 inside, 1 on edge ``local`` (local
    vertices ``local, local+1``), 2 at vertex ``local``.
    """
    dot = lambda u, v: np.einsum("ij,ij->i", u, v)  # noqa: E731
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = dot(ab, ap), dot(ac, ap)
    bp = p - b
    d3, d4 = dot(ab, bp), dot(ac, bp)
    cp = p - c
    d5, d6 = dot(ab, cp), dot(ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    m = p.shape[0]
    out = np.empty_like(p)
    feat = np.full(m, -1)
    loc = np.zeros(m, dtype=np.int64)
    done = np.zeros(m, bool)

    def put(mask, point, f, i):
        sel = mask & ~done
        out[sel] = point[sel]
        feat[sel] = f
        loc[sel] = i
        done[sel] = True

    # strict inequalities: a point on the border of two regions goes to the higher-dimensional feature
    # (the face before an edge, an edge before a vertex), so that a flat triangulation is a plane to the
    # last bit (zero Hessian) also above its vertices and edges
    with np.errstate(divide="ignore", invalid="ignore"):
        put((d1 < 0) & (d2 < 0), a, 2, 0)
        put((d3 > 0) & (d4 < d3), b, 2, 1)
        put((d6 > 0) & (d5 < d6), c, 2, 2)
        v = d1 / (d1 - d3)
        put((vc < 0) & (d1 >= 0) & (d3 <= 0), a + v[:, None] * ab, 1, 0)
        w = d2 / (d2 - d6)
        put((vb < 0) & (d2 >= 0) & (d6 <= 0), a + w[:, None] * ac, 1, 2)
        w2 = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        put((va < 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0), b + w2[:, None] * (c - b), 1, 1)
        denom = 1.0 / (va + vb + vc)
        v3, w3 = vb * denom, vc * denom
        put(np.ones(m, bool), a + v3[:, None] * ab + w3[:, None] * ac, 0, 0)
    return out, feat, loc


# --------------------------------------------------------------------------- reading
def _read(file: Any, group: Any) -> tuple[FloatArray, np.ndarray, str]:
    """Vertices, facets and a source label from an STL or Gmsh file (meshio)."""
    import contextlib
    import io
    import warnings

    import meshio

    if not isinstance(file, (str, Path)):
        raise InputError(f"surface: file = {file!r}: expected the path of an STL or Gmsh file (a string).")
    path = Path(file)
    if not path.is_file():
        raise InputError(f"surface: file = '{path}': no such file (a relative path is read from the problem "
                         "file's folder); check the name, or give an absolute path.")
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()), \
                warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # meshio's binary-size probe of an ASCII STL overflows
            mesh = meshio.read(str(path))
    except (Exception, SystemExit) as exc:  # meshio raises many kinds (ReadError, ValueError, struct.error, exit)
        raise InputError(f"surface: file = '{path}': could not be read as a surface mesh ({type(exc).__name__}: "
                         f"{exc}); give an STL file (ASCII or binary) or a Gmsh .msh file.") from None
    pts = np.asarray(mesh.points, dtype=float)
    kinds = {"line": 2, "triangle": 3}
    if group is not None:
        if not isinstance(group, str):
            raise InputError(f"surface: group = {group!r}: expected the name of a physical group (a string).")
        fd = dict(getattr(mesh, "field_data", {}) or {})
        if group not in fd:
            names = ", ".join(sorted(fd)) or "(none: the file has no named physical groups)"
            raise InputError(f"surface: group = {group!r}: no physical group of that name in '{path}'; available: "
                             f"{names}.")
        tag = int(np.ravel(fd[group])[0])
        phys = mesh.cell_data.get("gmsh:physical")
        blocks = []
        for k, cb in enumerate(mesh.cells):
            if cb.type in kinds and phys is not None:
                blocks.append(np.asarray(cb.data)[np.asarray(phys[k]) == tag])
        facets = [b for b in blocks if b.size]
        label = f"{path.name}, group {group!r}"
    else:
        facets = [np.asarray(cb.data) for cb in mesh.cells if cb.type in kinds and len(cb.data)]
        label = path.name
    if not facets:
        raise InputError(f"surface: '{label}' holds no line or triangle elements: give a polyline (2D) or a "
                         "triangulated surface (3D).")
    widths = {f.shape[1] for f in facets}
    if len(widths) > 1:
        raise InputError(f"surface: '{label}' mixes line and triangle elements; select one surface with group = "
                         "'NAME' (a Gmsh physical group).")
    fac = np.concatenate(facets).astype(np.int64)
    d = fac.shape[1]
    if d == 2:  # a polyline: the plane of the 2D body (z = 0 in the file)
        if pts.shape[1] == 3 and np.any(np.abs(pts[np.unique(fac), 2]) > 1e-12 * max(np.ptp(pts), 1.0)):
            raise InputError(f"surface: '{label}' is a curve outside the plane z = 0; a 2D body needs a polyline "
                             "in the xy-plane.")
        pts = pts[:, :2]
    elif pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(pts.shape[0])])
    used = np.unique(fac)  # keep only the vertices of the surface (a Gmsh file holds the whole model)
    renum = -np.ones(pts.shape[0], dtype=np.int64)
    renum[used] = np.arange(used.size)
    return pts[used], renum[fac], label


def surface(file: str | None = None, group: str | None = None, vertices: ArrayLike | None = None,
            facets: ArrayLike | None = None) -> MeshedSurface:
    """Meshed rigid surface (polyline 2D / triangles 3D, non-convex allowed): ``file`` (STL or Gmsh, with an
    optional physical ``group``) or ``vertices`` and ``facets``."""
    if (file is None) == (vertices is None and facets is None):
        raise InputError("surface: give either file (an STL or Gmsh file, with an optional group) or vertices and "
                         "facets (not both, not neither).")
    if file is not None:
        v, f, label = _read(file, group)
        return MeshedSurface(v, f, source=label)
    if group is not None:
        raise InputError(f"surface: group = {show(group)}: selects a physical group of a Gmsh file; give file as "
                         "well, or remove group.")
    if vertices is None or facets is None:
        raise InputError("surface: vertices and facets go together: give both (facets: vertex indices of each "
                         "segment / triangle).")
    return MeshedSurface(vertices, facets)


obstacles.register("surface", surface, doc="meshed rigid surface, non-convex allowed (2D polyline / 3D triangles): "
                                           "file (STL or Gmsh) and group, or vertices and facets")
