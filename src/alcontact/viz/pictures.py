"""Pictures of the deformed body: coloured by contact pressure and by von Mises stress.

Rendered with Matplotlib alone (a dependency already; Agg canvas, no ``pyplot``, no
display needed): 2D bodies with :class:`matplotlib.tri.Triangulation`
(``tripcolor`` with Gouraud shading, the mesh drawn with ``triplot``), 3D bodies as
their boundary triangles in an ``mplot3d`` :class:`~mpl_toolkits.mplot3d.art3d.Poly3DCollection`.
Why not PyVista/VTK: a second, large rendering stack (and an off-screen OpenGL
context) for two fixed pictures per run; the VTU files are there for interactive views.

The fields are those of ``solution.vtu`` (:func:`alcontact.io.vtu.solution_point_data`):
vertex values of the L2-projected von Mises stress and the normal contact pressure
:math:`\\lambda_N \\ge 0` on the contact boundary (0 elsewhere).

Configuration drawn: :math:`x = X + s\\,u`. Finite-deformation runs use :math:`s = 1`
(the true deformed body); small-deformation runs magnify the displacement so that
its largest value is about 5 % of the body's size (:func:`displacement_scale`, a
1-2-5 number, never below 1), and the title says so.

Views: 2D, the whole body and a zoom on the contact zone with the mesh drawn (the
pressure view draws the contact boundary as a thick line coloured by the pressure).
3D, the pressure view looks at the touching faces from outside (along their outward
normals weighted by the pressure), the whole body and zoomed on the contact zone; the
von Mises view looks obliquely from the contact zone's side of the body (symmetry
planes, where the stress under the contact shows), whole and zoomed.
Large 3D meshes draw the :data:`MAX_FACES` boundary triangles nearest the contact
zone (the title says how many of how many).

Examples
--------
>>> from alcontact.problems import hertz                       # doctest: +SKIP
>>> from alcontact.contact import solve                        # doctest: +SKIP
>>> save_body_pictures(solve(hertz.hertz_2d(level=0)), ".")    # doctest: +SKIP
['body_pressure.png', 'body_von_mises.png']
"""

from __future__ import annotations

import logging
import math
import os
from pathlib import Path

import numpy as np

from .plots import _new_figure, _note_units, _units, save_figure

__all__ = ["PICTURE_FILES", "MAX_FACES", "displacement_scale", "body_figure", "save_body_pictures"]

logger = logging.getLogger(__name__)

#: File names written by :func:`save_body_pictures`: (pressure view, von Mises view).
PICTURE_FILES: tuple[str, str] = ("body_pressure.png", "body_von_mises.png")

#: Most boundary triangles drawn for a 3D body (the nearest to the contact zone are kept).
MAX_FACES = 40_000

_FIELDS = {"contact_pressure": "contact pressure", "von_mises": "von Mises stress"}


def displacement_scale(reference: np.ndarray, displacement: np.ndarray, finite: bool) -> float:
    """Magnification of the displacement in the picture.

    ``1`` at finite deformation; otherwise the 1-2-5 number nearest below
    :math:`0.05\\,\\mathrm{diam}/\\max|u|`, at least 1.

    Examples
    --------
    >>> X = np.array([[0.0, 0.0], [10.0, 0.0]]); u = np.array([[0.0, 0.0], [0.0, -0.01]])
    >>> displacement_scale(X, u, finite=False), displacement_scale(X, u, finite=True)
    (50.0, 1.0)
    """
    if finite:
        return 1.0
    umax = float(np.max(np.linalg.norm(displacement, axis=1))) if displacement.size else 0.0
    diam = float(np.linalg.norm(np.ptp(reference, axis=0)))
    if not (umax > 0.0 and np.isfinite(umax)) or diam <= 0.0:
        return 1.0
    raw = 0.05 * diam / umax
    if raw <= 1.0:
        return 1.0
    e = 10.0 ** math.floor(math.log10(raw))
    return float(max(m * e for m in (1.0, 2.0, 5.0) if m * e <= raw * (1 + 1e-12)))


def _body_data(solution):
    """Reference points (n, dim), displacement (n, dim), cells, point fields, contact facets, finite flag."""
    from ..io.vtu import solution_point_data

    problem = solution.problem
    model = problem.model
    dim = int(model.dim)
    points, cells, pd = solution_point_data(solution, deformed=False)
    cb = problem.contact_boundary
    if hasattr(model, "bodies") and hasattr(model, "locate"):  # several bodies, stacked body after body
        i, cb = model.locate(cb)
        mesh = model.bodies[i].mesh
        shift = sum(b.mesh.nvertices for b in model.bodies[:i] if b.mesh is not None)  # a rigid body: no mesh
    else:
        mesh, shift = model.mesh, 0
    names = mesh.boundaries or {}
    facets = mesh.facets[:, names[cb]] + shift if cb in names else np.zeros((dim, 0), dtype=np.int64)
    finite = getattr(problem, "kinematics", "small") == "finite"
    conn = cells[0][1]
    if conn.shape[1] == 6:  # curved triangle6 (v0 v1 v2 m01 m12 m20): four sub-triangles through the edge nodes
        conn = conn[:, [0, 3, 5, 3, 1, 4, 5, 4, 2, 3, 4, 5]].reshape(-1, 3)
    elif conn.shape[1] == 10:  # curved tetra10: its vertices (the vertex numbers are the mesh's)
        conn = conn[:, :4]
    return points[:, :dim], pd["displacement"][:, :dim], conn, pd, np.asarray(facets), finite, mesh


def _zoom_box(x: np.ndarray, pressure: np.ndarray, contact_nodes: np.ndarray, body_lo, body_hi):
    """Window (lo, hi) around the contact zone: 3x its extent (at least 1/8 of the body), inside the body's box."""
    on = contact_nodes[pressure[contact_nodes] > 0] if contact_nodes.size else contact_nodes
    if on.size == 0:
        on = contact_nodes
    if on.size == 0:
        return body_lo, body_hi
    lo, hi = x[on].min(axis=0), x[on].max(axis=0)
    c = 0.5 * (lo + hi)
    half = max(1.5 * float(np.max(hi - lo)), float(np.max(body_hi - body_lo)) / 16.0)
    return np.maximum(c - half, body_lo - 0.02 * half), np.minimum(c + half, body_hi + 0.02 * half)


def _colorbar(fig, mappable, ax, label: str) -> None:
    fig.colorbar(mappable, ax=ax, label=label, shrink=0.85)


def _draw_2d(fig, axes, x, tri, field, values, contact_pressure, facets, unit):
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize
    from matplotlib.tri import Triangulation

    pressure = contact_pressure if field == "contact_pressure" else None
    tr = Triangulation(x[:, 0], x[:, 1], tri)
    contact_nodes = np.unique(facets) if facets.size else np.zeros(0, dtype=np.int64)
    lo, hi = x.min(axis=0), x.max(axis=0)
    zlo, zhi = _zoom_box(x, contact_pressure, contact_nodes, lo, hi)  # both views zoom on the contact zone
    label = f"{_FIELDS[field]} ({unit})"
    for k, ax in enumerate(axes):
        zoom = k == 1
        if zoom:  # the triangles that reach into the window (drawing all of a large mesh is slow)
            xt = x[tri]
            keep = np.all(xt.max(axis=1) >= zlo, axis=1) & np.all(xt.min(axis=1) <= zhi, axis=1)
            sub = Triangulation(x[:, 0], x[:, 1], tri[keep]) if keep.any() else tr
        else:
            sub = tr
        edges = zoom or tri.shape[0] <= 4000  # the whole mesh of a fine body would be a grey blot
        if pressure is None:
            m = ax.tripcolor(sub, values, shading="gouraud", cmap="viridis",
                             vmin=float(values.min()), vmax=float(values.max()))
            if edges:
                ax.triplot(sub, color="k" if zoom else "0.2", lw=0.25 if zoom else 0.15, alpha=0.6)
            if k == len(axes) - 1:
                _colorbar(fig, m, axes, label)
        else:
            ax.tripcolor(sub, np.ones(x.shape[0]), shading="flat", cmap="Greys", vmin=0.0, vmax=4.0)  # light grey body
            if edges:
                ax.triplot(sub, color="0.45", lw=0.3 if zoom else 0.15, alpha=0.7)
            seg = x[facets.T]  # (m, 2, 2)
            norm = Normalize(0.0, max(float(values.max()), 1e-300))
            lc = LineCollection(seg, array=values[facets].mean(axis=0), cmap="inferno_r", norm=norm,
                                linewidths=4.0 if zoom else 2.5)
            ax.add_collection(lc)
            if zoom:
                on = contact_nodes[values[contact_nodes] > 0]
                ax.scatter(x[on, 0], x[on, 1], c=values[on], cmap="inferno_r", norm=norm, s=10, zorder=3,
                           edgecolors="k", linewidths=0.3)
            if k == len(axes) - 1:
                _colorbar(fig, lc, axes, label)
        if zoom:
            ax.set_xlim(zlo[0], zhi[0])
            ax.set_ylim(zlo[1], zhi[1])
        ax.set_aspect("equal")
        ax.set_title("near the contact zone (mesh)" if zoom else "whole body", fontsize="small")


def _face_normals(x, faces):
    a, b, c = x[faces[:, 0]], x[faces[:, 1]], x[faces[:, 2]]
    n = np.cross(b - a, c - a)
    return n


def _outward_boundary_faces(mesh, x):
    """Boundary triangles (nf, 3) of a tetrahedral mesh, oriented outward (reference configuration)."""
    bf = mesh.boundary_facets()
    faces = mesh.facets[:, bf].T.copy()
    # the tetrahedron of each boundary facet: its fourth vertex is inside
    t2f = mesh.f2t[0, bf]
    tets = mesh.t[:, t2f].T
    inner = tets.sum(axis=1) - faces.sum(axis=1)  # the vertex of the tetrahedron not on the facet
    n = _face_normals(x, faces)
    flip = np.einsum("ij,ij->i", n, x[inner] - x[faces[:, 0]]) > 0
    faces[flip] = faces[flip][:, [0, 2, 1]]
    return faces


def _view_angles(d):
    d = d / max(float(np.linalg.norm(d)), 1e-300)
    return math.degrees(math.asin(float(np.clip(d[2], -1, 1)))), math.degrees(math.atan2(d[1], d[0]))


def _draw_3d(fig, x, X, mesh, field, values, pressure, facets, unit):
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    faces = _outward_boundary_faces(mesh, X)
    contact = {tuple(sorted(f)) for f in facets.T} if facets.size else set()
    is_contact = np.array([tuple(sorted(f)) in contact for f in faces], dtype=bool) if contact else \
        np.zeros(faces.shape[0], dtype=bool)
    # look at the touching faces from outside: their normals weighted by the pressure (all contact faces if none)
    cf = faces[is_contact]
    ncf = _face_normals(x, cf) if cf.size else np.zeros((0, 3))
    weight = pressure[cf].mean(axis=1) if cf.size else np.zeros(0)
    weight = weight if np.any(weight > 0) else np.ones(len(cf))
    normal = (weight[:, None] * ncf).sum(axis=0) if ncf.size else np.array([0.0, 0.0, 1.0])
    if not np.linalg.norm(normal) > 0:
        normal = np.array([0.0, 0.0, 1.0])
    normal = normal / max(float(np.linalg.norm(normal)), 1e-300)
    cnodes = np.unique(facets) if facets.size else np.zeros(0, dtype=np.int64)
    lo, hi = x.min(axis=0), x.max(axis=0)
    zlo, zhi = _zoom_box(x, pressure, cnodes, lo, hi)
    centre = 0.5 * (zlo + zhi)
    # oblique camera: from the contact zone's side of the body (shows symmetry planes and the stress under it)
    side = centre - 0.5 * (lo + hi)
    side = side - np.dot(side, normal) * normal
    if np.linalg.norm(side) < 1e-12 * max(float(np.max(hi - lo)), 1e-300):
        side = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    oblique = normal + 1.2 * side / np.linalg.norm(side)
    total = faces.shape[0]
    if total > MAX_FACES:  # keep the faces nearest the contact zone
        dist = np.linalg.norm(x[faces].mean(axis=1) - centre, axis=1)
        keep = np.argsort(dist)[:MAX_FACES]
        faces, is_contact = faces[keep], is_contact[keep]
    fv = values[faces].mean(axis=1)
    if field == "contact_pressure":
        norm = Normalize(0.0, max(float(values.max()), 1e-300))
        cmap = _cmap("inferno_r")
        colors = np.tile(np.array([0.85, 0.85, 0.85, 1.0]), (faces.shape[0], 1))
        colors[is_contact] = cmap(norm(fv[is_contact]))
        views = [("whole body, seen from outside the contact face", normal, False),
                 ("near the contact zone (mesh)", normal, True)]
    else:
        norm = Normalize(float(values.min()), max(float(values.max()), float(values.min()) + 1e-300))
        cmap = _cmap("viridis")
        colors = cmap(norm(fv))
        views = [("whole body, oblique", oblique, False), ("near the contact zone (mesh)", oblique, True)]
    cen = x[faces].mean(axis=1)
    inside = np.all((cen >= zlo) & (cen <= zhi), axis=1)
    axes = []
    for k, (name, direction, zoom) in enumerate(views):
        ax = fig.add_subplot(1, len(views), k + 1, projection="3d")
        sel = inside if zoom and inside.any() else np.ones(faces.shape[0], dtype=bool)
        a, b = (zlo, zhi) if zoom and inside.any() else (lo, hi)
        edges = zoom or total < 6000
        pc = Poly3DCollection(x[faces[sel]], facecolors=colors[sel], edgecolors=(0, 0, 0, 0.3) if edges else "none",
                              linewidths=0.2)
        ax.add_collection3d(pc)
        half, mid = 0.5 * float(np.max(b - a)), 0.5 * (a + b)
        for setlim, i in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
            setlim(mid[i] - half, mid[i] + half)
        ax.set_box_aspect((1, 1, 1))
        elev, azim = _view_angles(direction)
        ax.view_init(elev=elev, azim=azim)
        for axis, lab in ((ax.xaxis, "x"), (ax.yaxis, "y"), (ax.zaxis, "z")):
            axis.set_label_text(lab, fontsize="small")
        ax.tick_params(labelsize="xx-small")
        ax.set_title(name, fontsize="small")
        axes.append(ax)
    fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=axes, label=f"{_FIELDS[field]} ({unit})", shrink=0.7)
    return total, faces.shape[0]


def _cmap(name):
    import matplotlib

    return matplotlib.colormaps[name]


def body_figure(solution, field: str = "contact_pressure", *, units=None, title: str | None = None, _data=None):
    """Picture of the deformed body coloured by ``field``.

    Parameters
    ----------
    solution : ContactSolution
        A solution (or load-step frame) with ``problem``, ``u`` and the contact fields.
    field : {"contact_pressure", "von_mises"}
        Colour: the contact pressure on the contact boundary (the rest of the body grey)
        or the von Mises stress of the whole body.
    units : alcontact.viz.Units, optional
        Stress unit of the colour bar.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..errors import InputError

    if field not in _FIELDS:
        raise InputError(f"body_figure: field = {field!r} is not one of {', '.join(_FIELDS)}.")
    X, u, cells, pd, facets, finite, mesh = _body_data(solution) if _data is None else _data
    dim = X.shape[1]
    scale = displacement_scale(X, u, finite)
    x = X + scale * u
    values = np.nan_to_num(np.asarray(pd[field], dtype=float))
    pressure = np.asarray(pd["contact_pressure"], dtype=float)
    uu = _units(units)
    how = "deformed body" if scale == 1.0 else f"deformed body, displacement x {scale:g}"
    if dim == 2:
        fig = _new_figure((9.6, 4.4))
        axes = fig.subplots(1, 2)
        _draw_2d(fig, axes, x, cells, field, values, pressure, facets, uu.pressure)
        for ax in axes:
            ax.set_xlabel(f"x ({uu.length})")
            ax.set_ylabel(f"y ({uu.length})")
            ax.tick_params(labelsize="x-small")
        extra = ""
    else:
        fig = _new_figure((9.6, 5.0))
        total, drawn = _draw_3d(fig, x, X, mesh, field, values, pressure, facets, uu.pressure)
        extra = "" if drawn == total else f" ({drawn} of {total} boundary triangles, nearest the contact zone)"
    fig.suptitle((title + ": " if title else "") + f"{_FIELDS[field]}, {how}{extra}", fontsize="medium")
    _note_units(fig, uu)
    return fig


def save_body_pictures(solution, folder: str | os.PathLike, *, units=None, title: str | None = None,
                       dpi: int = 100) -> list[str]:
    """Write :data:`PICTURE_FILES` (pressure view, von Mises view) into ``folder``; return their names."""
    folder = Path(folder)
    data = _body_data(solution)  # the stress projection once for both pictures
    for name, field in zip(PICTURE_FILES, ("contact_pressure", "von_mises")):
        save_figure(body_figure(solution, field, units=units, title=title, _data=data), folder / name, dpi=dpi)
    logger.debug("wrote %s in %s", ", ".join(PICTURE_FILES), folder)
    return list(PICTURE_FILES)
