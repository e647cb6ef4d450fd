r"""Plane geometry of 3D mortar integrals: the intersection of two convex polygons and its quadrature.

The mortar integrals over a pair of slave and master faces (:mod:`._mortar3d`) run over the
part of the slave face that the master face covers once both are projected onto a common
plane (the slave face's own plane, for a flat slave face): the intersection of two convex
polygons in that plane (Puso & Laursen, 2004, Comput. Methods Appl. Mech. Engrg. 193:601-629;
Popp, Gee & Wall, 2009, Int. J. Numer. Meth. Engng 79:1354-1391).

:func:`clip_convex` computes it for many pairs at once (vectorized over the pairs): the
intersection of two convex polygons is the convex polygon whose vertices are the vertices of
each polygon inside the other and the crossing points of their edges; they are gathered with a
validity mask and sorted by angle about their mean, which lies inside the (convex) polygon.
This is the polygon that Sutherland-Hodgman clipping gives, obtained without a loop over the
clipping edges, so that all pairs are handled by the same array operations. Coincident points
(matching meshes: vertices on vertices, edges on edges) appear more than once; they only add
fan triangles of zero area.

:func:`fan_quadrature` splits each polygon into the triangles (centroid, vertex i, vertex
i+1) and puts a Gauss rule on each (:data:`TRIANGLE_RULES`, Strang & Fix 1973 / Dunavant 1985
symmetric rules, exact for polynomials up to the stated degree): a product of two affine
functions (a P1 dual function times a P1 master function) is integrated exactly by the
degree-2 rule.
"""

from __future__ import annotations

import numpy as np

#: symmetric Gauss rules on a triangle: degree -> (barycentric points (q, 3), weights (q,) summing to 1)
TRIANGLE_RULES = {
    1: (np.array([[1 / 3, 1 / 3, 1 / 3]]), np.array([1.0])),
    2: (np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]), np.full(3, 1 / 3)),
    4: (np.array([[0.108103018168070, 0.445948490915965, 0.445948490915965],
                  [0.445948490915965, 0.108103018168070, 0.445948490915965],
                  [0.445948490915965, 0.445948490915965, 0.108103018168070],
                  [0.816847572980459, 0.091576213509771, 0.091576213509771],
                  [0.091576213509771, 0.816847572980459, 0.091576213509771],
                  [0.091576213509771, 0.091576213509771, 0.816847572980459]]),
        np.array([0.223381589678011] * 3 + [0.109951743655322] * 3)),
}


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z-component of the cross product of plane vectors (``(..., 2)``)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def signed_area(poly: np.ndarray) -> np.ndarray:
    """Signed area of polygons ``(p, n, 2)`` (positive when counter-clockwise)."""
    return 0.5 * np.sum(_cross(poly, np.roll(poly, -1, axis=1)), axis=1)


def _inside(points: np.ndarray, poly: np.ndarray, tol: np.ndarray) -> np.ndarray:
    """``(p, k)``: which of ``points`` ``(p, k, 2)`` lie in the counter-clockwise convex ``poly`` ``(p, n, 2)``."""
    edge = np.roll(poly, -1, axis=1) - poly  # (p, n, 2)
    rel = points[:, :, None, :] - poly[:, None, :, :]  # (p, k, n, 2)
    side = _cross(edge[:, None, :, :], rel)  # (p, k, n), >= 0 inside
    return np.all(side >= -tol[:, None, None] * np.linalg.norm(edge, axis=2)[:, None, :], axis=2)


def clip_convex(a: np.ndarray, b: np.ndarray, *, rtol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """Intersections of the counter-clockwise convex polygons ``a[i]`` and ``b[i]`` (module doc).

    Parameters
    ----------
    a : ndarray (p, na, 2)
    b : ndarray (p, nb, 2)
        Convex polygons, counter-clockwise.
    rtol : float
        Tolerance of the inside and crossing tests, relative to the size of ``a``.

    Returns
    -------
    poly : ndarray (p, k, 2)
        The vertices of each intersection, counter-clockwise, the valid ones first.
    valid : ndarray of bool (p, k)
        Which rows of ``poly`` are vertices (fewer than three: the polygons do not overlap).
    """
    p, na, nb = a.shape[0], a.shape[1], b.shape[1]
    size = np.max(np.linalg.norm(a - a.mean(axis=1, keepdims=True), axis=2), axis=1)  # (p,)
    tol = rtol * np.where(size > 0, size, 1.0)
    in_a = _inside(a, b, tol)  # vertices of a inside b
    in_b = _inside(b, a, tol)
    # crossing points of edge i of a and edge j of b
    da = np.roll(a, -1, axis=1) - a  # (p, na, 2)
    db = np.roll(b, -1, axis=1) - b
    den = _cross(da[:, :, None, :], db[:, None, :, :])  # (p, na, nb)
    rel = b[:, None, :, :] - a[:, :, None, :]  # (p, na, nb, 2)
    scale = np.linalg.norm(da, axis=2)[:, :, None] * np.linalg.norm(db, axis=2)[:, None, :]
    ok = np.abs(den) > 1e-14 * scale
    safe = np.where(ok, den, 1.0)
    s = _cross(rel, db[:, None, :, :]) / safe
    t = _cross(rel, da[:, :, None, :]) / safe
    eps = rtol
    ok &= (s >= -eps) & (s <= 1 + eps) & (t >= -eps) & (t <= 1 + eps)
    cross_pts = a[:, :, None, :] + np.clip(s, 0.0, 1.0)[..., None] * da[:, :, None, :]
    pts = np.concatenate([a, b, cross_pts.reshape(p, na * nb, 2)], axis=1)
    valid = np.concatenate([in_a, in_b, ok.reshape(p, na * nb)], axis=1)
    count = valid.sum(axis=1)
    centre = np.einsum("pk,pkj->pj", valid.astype(float), pts) / np.maximum(count, 1)[:, None]
    rel = pts - centre[:, None, :]
    angle = np.where(valid, np.arctan2(rel[..., 1], rel[..., 0]), np.inf)
    order = np.argsort(angle, axis=1, kind="stable")
    pts = np.take_along_axis(pts, order[..., None], axis=1)
    valid = np.take_along_axis(valid, order, axis=1)
    valid &= (count >= 3)[:, None]
    keep = int(valid.sum(axis=1).max(initial=0))
    return pts[:, :keep], valid[:, :keep]


def fan_quadrature(poly: np.ndarray, valid: np.ndarray, degree: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Quadrature points and weights on the polygons of :func:`clip_convex` (fan from the vertices' mean).

    Returns
    -------
    x : ndarray (p, k * q, 2)
        Points (q points of the rule :data:`TRIANGLE_RULES` ``[degree]`` on each of the ``k`` fan triangles).
    w : ndarray (p, k * q)
        Weights: the triangle's area times the rule's weight; zero on the padding rows.
    """
    bary, wq = TRIANGLE_RULES[degree]
    p, k = valid.shape
    if k == 0:
        return np.zeros((p, 0, 2)), np.zeros((p, 0))
    count = valid.sum(axis=1)
    centre = np.einsum("pk,pkj->pj", valid.astype(float), poly) / np.maximum(count, 1)[:, None]
    nxt = (np.arange(k)[None, :] + 1) % np.maximum(count, 1)[:, None]  # next valid vertex, cyclically
    v1 = poly
    v2 = np.take_along_axis(poly, nxt[..., None], axis=1)
    area = 0.5 * _cross(v1 - centre[:, None, :], v2 - centre[:, None, :])  # (p, k), >= 0 (counter-clockwise)
    area = np.where(valid, np.maximum(area, 0.0), 0.0)
    x = (bary[None, None, :, 0, None] * centre[:, None, None, :] + bary[None, None, :, 1, None] * v1[:, :, None, :]
         + bary[None, None, :, 2, None] * v2[:, :, None, :])  # (p, k, q, 2)
    w = area[:, :, None] * wq[None, None, :]
    return x.reshape(p, -1, 2), w.reshape(p, -1)
