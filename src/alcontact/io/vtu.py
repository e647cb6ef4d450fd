"""VTU output of a contact solution (read with ParaView, meshio, PyVista).

One unstructured grid on the mesh vertices (linear triangles or tetrahedra;
for P2 models the vertex values of the quadratic fields are written, the edge
midpoint values are dropped). A P2 model on a curved second-order mesh
(``MeshTri2``/``MeshTet2``) is written with all its nodes as ``triangle6``/``tetra10``
cells instead, so that the curved boundary shows. Points are 3D (``z = 0`` in 2D).

Configuration: small-deformation runs are written on the reference mesh (use
ParaView's "Warp By Vector" with ``displacement`` to see the deformed shape).
Finite-deformation runs (``problem.kinematics == "finite"``) are written in the
**deformed configuration**: the points are :math:`x = X + u` and the field
``reference_position`` holds :math:`X` (so do not warp them again); ``gap`` is the
gap at the current position, ``stress`` the Cauchy stress.

Point fields (:data:`POINT_FIELDS`):

``displacement`` (n, 3)
    Displacement vector (third component 0 in 2D).
``contact_pressure`` (n,)
    Normal contact pressure :math:`\\lambda_N \\ge 0` on the contact boundary,
    **0 elsewhere** (no contact traction there).
``gap`` (n,)
    Gap (linearized (6.15) at small deformation, at x = X + u at finite) on the contact boundary (<= 0 feasible, > 0 penetration),
    **NaN elsewhere** (not defined off the contact boundary).
``contact_active`` (n,)
    1 where the point is in contact, 0 elsewhere.
``von_mises`` (n,)
    Von Mises stress of the L2-projected nodal stresses (plane strain includes ``zz``).
``stress`` (n, 6)
    L2-projected nodal stress tensor in ParaView's symmetric-tensor order
    ``xx, yy, zz, xy, yz, xz`` (2D: ``zz`` is the out-of-plane stress, ``yz = xz = 0``).

Several bodies (a :class:`~alcontact.fem.MultiBody`, two-body contact) are written as one grid with
the point field ``body`` (the index of the body each point belongs to; filter by it in ParaView
with "Threshold"); the contact fields are those of the slave boundary and, on the master body's
boundary, the master-side pressure and gap of the mortar pair (the slave nodal forces and gaps
carried by the mortar weights, :mod:`alcontact.contact.solution._sides`); ``0`` / NaN on the other
bodies. A rigid body has no grid (its pose and forces are in ``summary.json``, ``rigid_bodies``).

Frictional runs add (:data:`FRICTION_FIELDS`, from ``solution.extra``):

``slip`` (n, 3)
    Slip accumulated over the load steps so far (tangential, global components),
    0 off the contact boundary.
``slip_increment`` (n, 3)
    Slip of the last load step.
``contact_state`` (n,)
    0 open, 1 stick, 2 slip on the contact boundary; -1 elsewhere.

A load-stepped run writes one VTU per step and a ParaView collection
(:func:`write_pvd`) pointing to them with the pseudo-times as time values.

Examples
--------
>>> from alcontact.problems import hertz                     # doctest: +SKIP
>>> from alcontact.contact import solve                      # doctest: +SKIP
>>> write_solution_vtu("solution.vtu", solve(hertz.hertz_2d(level=0)))  # doctest: +SKIP
"""

from __future__ import annotations

import logging
import os
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..fem.quality import is_curved
from .results import atomic_path

__all__ = ["POINT_FIELDS", "FRICTION_FIELDS", "solution_point_data", "write_solution_vtu", "write_pvd"]

logger = logging.getLogger(__name__)

#: Names of the point fields written by :func:`write_solution_vtu`.
POINT_FIELDS: tuple[str, ...] = ("displacement", "contact_pressure", "gap", "contact_active", "von_mises", "stress")

#: Extra point fields of frictional runs.
FRICTION_FIELDS: tuple[str, ...] = ("slip", "slip_increment", "contact_state")

_CELL_TYPES = {(2, 3): "triangle", (3, 4): "tetra"}
_CURVED_CELL_TYPES = {"triangle": "triangle6", "tetra": "tetra10"}


def _contact_scalar_dofs(solution) -> np.ndarray:
    """Scalar DOF index of each contact point of ``solution`` (same order as ``solution.points``)."""
    problem = solution.problem
    model = problem.model
    pts, dofs = problem.slave_nodes()
    if pts.shape != solution.points.shape or not np.allclose(pts, solution.points):
        raise InputError(
            "the solution's contact points do not match the contact boundary "
            f"{problem.contact_boundary!r} of its problem; was the solution built from another problem?"
        )
    scalar_of_vector = np.empty(model.ndofs, dtype=np.int64)
    dmap = model.dof_map
    scalar_of_vector[dmap[:, 0]] = np.arange(dmap.shape[0])
    return scalar_of_vector[dofs[:, 0]]


def solution_point_data(solution, deformed: bool | None = None
                        ) -> tuple[np.ndarray, list[tuple[str, np.ndarray]], dict[str, np.ndarray]]:
    """Vertex coordinates, cells and point fields of a contact solution.

    Parameters
    ----------
    solution : alcontact.contact.ContactSolution
    deformed : bool, optional
        Write the deformed points :math:`X + u` and a ``reference_position`` field;
        default: for finite-deformation problems only (module doc).

    Returns
    -------
    points : ndarray (n_vertices, 3)
    cells : list of (cell type, connectivity)
    point_data : dict
        The fields of :data:`POINT_FIELDS`, one value (row) per vertex.
    """
    from .._options import require

    require("solution_point_data", "solution", solution, hasattr(solution, "u") and hasattr(
        getattr(solution, "problem", None), "model"), "a solution of alcontact.contact.solve (a ContactSolution)")
    require("solution_point_data", "deformed", deformed, deformed is None or isinstance(deformed, (bool, np.bool_)),
            "None, True or False")
    model = solution.problem.model
    if hasattr(model, "bodies") and hasattr(model, "split"):  # several bodies: one grid, a `body` field
        return _bodies_point_data(solution, deformed)
    mesh = model.mesh
    dim = model.dim
    cell_type = _CELL_TYPES.get((dim, mesh.t.shape[0]))
    if cell_type is None:
        raise InputError(f"VTU output supports triangle and tetrahedron meshes; got {type(mesh).__name__}.")

    if is_curved(mesh) and model.order == 2:
        # curved (isoparametric) P2: every node is a point of a second-order cell, so the
        # curved boundary shows as such; scikit-fem's local P2 node order (vertices, then
        # edges 01, 12, 02[, 03, 13, 23]) is VTK's for triangle6/tetra10
        cell_type = _CURVED_CELL_TYPES[cell_type]
        vertex_dof = np.arange(model.dof_map.shape[0], dtype=np.int64)
        conn = np.asarray(model.scalar_dofs.element_dofs, dtype=np.int64).T
        coords = model.scalar_doflocs
    else:
        # scalar DOF carrying the value at each vertex (P1: all DOFs, P2: the vertex ones)
        vertex_dof = np.asarray(model.scalar_basis.nodal_dofs[0], dtype=np.int64)
        conn = np.asarray(mesh.t, dtype=np.int64).T
        coords = np.asarray(mesh.p, dtype=float)[:, : mesh.nvertices]
    nverts = vertex_dof.size
    vertex_of_scalar = -np.ones(model.dof_map.shape[0], dtype=np.int64)
    vertex_of_scalar[vertex_dof] = np.arange(nverts)

    points = np.zeros((nverts, 3))
    points[:, :dim] = coords.T

    u = np.asarray(solution.u, dtype=float)
    disp = np.zeros((nverts, 3))
    disp[:, :dim] = u[model.dof_map[vertex_dof]]

    pressure = np.zeros(nverts)
    gap = np.full(nverts, np.nan)
    active = np.zeros(nverts)
    cv = vertex_of_scalar[_contact_scalar_dofs(solution)]
    on_vertex = cv >= 0  # P2 edge midpoints have no vertex
    pressure[cv[on_vertex]] = solution.pressure[on_vertex]
    gap[cv[on_vertex]] = solution.gap[on_vertex]
    active[cv[on_vertex]] = solution.active[on_vertex].astype(float)

    von_mises = np.asarray(model.von_mises(u))[vertex_dof]
    sig = np.asarray(model.stress(u, include_zz=True))[vertex_dof]
    stress = np.zeros((nverts, 6))
    if dim == 2:  # columns xx, yy, xy, zz
        stress[:, 0], stress[:, 1], stress[:, 3], stress[:, 2] = sig.T
    else:  # columns xx, yy, zz, yz, xz, xy
        stress[:, [0, 1, 2, 4, 5, 3]] = sig

    if deformed is None:
        deformed = getattr(solution.problem, "kinematics", "small") == "finite"
    point_data = {}
    if deformed:
        point_data["reference_position"] = points.copy()
        points = points + disp
    point_data |= {
        "displacement": disp,
        "contact_pressure": pressure,
        "gap": gap,
        "contact_active": active,
        "von_mises": von_mises,
        "stress": stress,
    }
    extra = getattr(solution, "extra", None) or {}
    if "state" in extra:
        for name, key in (("slip", "slip"), ("slip_increment", "slip_increment")):
            vec = np.zeros((nverts, 3))
            vals = np.asarray(extra[key], dtype=float).reshape(len(cv), -1)
            vec[cv[on_vertex], : vals.shape[1]] = vals[on_vertex]
            point_data[name] = vec
        state = np.full(nverts, -1.0)
        state[cv[on_vertex]] = np.asarray(extra["state"], dtype=float)[on_vertex]
        point_data["contact_state"] = state
    cells = [(cell_type, np.ascontiguousarray(conn))]
    return points, cells, point_data


def _bodies_point_data(solution, deformed):
    """:func:`solution_point_data` of a solution of several bodies (:class:`alcontact.fem.MultiBody`).

    Each body's grid and fields as for one body (the contact fields on the slave boundary; ``0`` /
    NaN on the other bodies), stacked into one grid with the point field ``body`` (the body's index).
    """
    from types import SimpleNamespace

    problem = solution.problem
    model = problem.model
    pairs = getattr(problem, "pairs", ())
    # the slave boundaries of each body (several two-body pairs may have slaves on one body, e.g. a seal)
    names = [problem.slave_name(p) for p in pairs] if len(pairs) > 1 else [problem.contact_boundary]
    located = [model.locate(n) for n in names]
    owner = problem.pair_of_points() if len(pairs) > 1 else np.zeros(solution.points.shape[0], dtype=np.int64)
    kinematics = getattr(problem, "kinematics", "small")
    extra = {k: v for k, v in (getattr(solution, "extra", None) or {}).items() if k != "state"}
    side = extra.get("master_side")  # the master body's pressure and gap (contact.solution._sides)
    master = getattr(problem.pairs[0].master, "body", None) if side is not None else None
    points, conns, fields, index = [], [], [], []
    cell_type = None
    for i, (body, u) in enumerate(zip(model.bodies, model.split(solution.u))):
        if body.mesh is None:  # a rigid body: its pose is in summary.json and steps.csv, it has no grid
            continue
        mine = [k for k, (b, _) in enumerate(located) if b == i]
        if mine:  # the slave boundaries of this body (a seal's cord is the slave of two pairs)
            sel = np.isin(owner, mine)
            local = [located[k][1] for k in mine]

            def nodes(b=body, ns=tuple(local)):
                got = [b.node_dofs(n) for n in ns]
                return np.vstack([g[0] for g in got]), np.vstack([g[1] for g in got])

            view = SimpleNamespace(problem=SimpleNamespace(model=body, contact_boundary=local[0], kinematics=kinematics,
                                                           slave_nodes=nodes),
                                   u=u, points=solution.points[sel], pressure=solution.pressure[sel],
                                   gap=solution.gap[sel], active=solution.active[sel], extra=extra)
        elif body is master:  # the master side of the pair: pressure and gap carried by the mortar weights
            p_m, g_m = np.asarray(side["pressure"], dtype=float), np.asarray(side["gap"], dtype=float)
            view = SimpleNamespace(problem=SimpleNamespace(model=body, contact_boundary=side["boundary"],
                                                           kinematics=kinematics,
                                                           slave_nodes=lambda b=body, n=side["boundary"]:
                                                           b.node_dofs(n)),
                                   u=u, points=side["points"], pressure=p_m, gap=g_m,
                                   active=np.isfinite(g_m) & (p_m > 0), extra={})
        else:  # no contact field of its own: the first boundary, zero pressure, no gap
            name = body.boundary_names[0]
            pts, _ = body.node_dofs(name)
            m = pts.shape[0]
            view = SimpleNamespace(problem=SimpleNamespace(model=body, contact_boundary=name, kinematics=kinematics,
                                                           slave_nodes=lambda b=body, n=name: b.node_dofs(n)),
                                   u=u, points=pts, pressure=np.zeros(m), gap=np.full(m, np.nan),
                                   active=np.zeros(m, dtype=bool), extra={})
        p, cells, data = solution_point_data(view, deformed)
        if cell_type not in (None, cells[0][0]):
            raise InputError(f"VTU output of several bodies needs one cell type; got {cell_type} and {cells[0][0]}.")
        cell_type = cells[0][0]
        conns.append(cells[0][1] + sum(q.shape[0] for q in points))
        points.append(p)
        fields.append(data)
        index.append(np.full(p.shape[0], float(i)))
    point_data = {k: np.concatenate([f[k] for f in fields]) for k in fields[0]}
    point_data["body"] = np.concatenate(index)
    return np.vstack(points), [(cell_type, np.vstack(conns))], point_data


def write_solution_vtu(path: str | os.PathLike, solution, *, deformed: bool | None = None) -> Path:
    """Write ``solution`` as a VTU file (atomically), fields :data:`POINT_FIELDS`.

    ``deformed``: points in the deformed configuration (default: finite-deformation
    problems only, see :func:`solution_point_data`).

    Returns
    -------
    Path
        ``path``.
    """
    import meshio  # imported here: only output needs it

    from .._options import is_path, require

    require("write_solution_vtu", "path", path, is_path(path), "a file path (str or pathlib.Path)")
    points, cells, point_data = solution_point_data(solution, deformed)
    out = meshio.Mesh(points, cells, point_data=point_data)
    path = Path(path)
    with atomic_path(path) as tmp:
        meshio.write(tmp, out, file_format="vtu")
    logger.info("wrote %s (%d points, %d cells)", path, points.shape[0], cells[0][1].shape[0])
    return path


def write_pvd(path: str | os.PathLike, entries) -> Path:
    """Write a ParaView collection (``.pvd``) of VTU files, atomically.

    Parameters
    ----------
    path : path-like
        The ``.pvd`` file.
    entries : iterable of (time, file)
        Pseudo-time and VTU path relative to the folder of ``path``.
    """
    from xml.sax.saxutils import quoteattr

    from .._options import is_real, require
    from .results import write_text_atomic

    ok = not isinstance(entries, (str, bytes, dict)) and np.iterable(entries)
    require("write_pvd", "entries", entries, ok, "a list of (time, file) pairs")
    entries = list(entries)
    for i, e in enumerate(entries):
        require("write_pvd", f"entries[{i}]", e, isinstance(e, (tuple, list)) and len(e) == 2 and is_real(e[0])
                and isinstance(e[1], (str, os.PathLike)), "a (time, file) pair: a number and a path")
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    for t, name in entries:
        lines.append(f'    <DataSet timestep="{float(t)!r}" group="" part="0" file={quoteattr(str(name))}/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    return write_text_atomic(path, "\n".join(lines))
