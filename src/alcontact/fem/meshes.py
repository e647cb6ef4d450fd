"""Structured meshes with named boundaries, and reading Gmsh meshes.

Every mesh returned here is a scikit-fem mesh whose ``mesh.boundaries`` is a
dict ``name -> facet indices`` (as :meth:`skfem.Mesh.with_boundaries` gives).

Grading (``refine=``) produces *tensor-product* coordinates: along each axis the
spacing is uniform (``h_min``) inside a window around the point of interest and
grows geometrically (factor ``growth``) outside it, capped at the uniform
spacing of the coarse grid (``(x1 - x0) / nx`` etc., or ``refine["h_max"]``).
Because the grid is a tensor product, fine spacing extends across the whole
domain in strips; for contact problems with a small contact zone at the top
this costs a few times more nodes than an unstructured graded mesh but builds
in milliseconds and scales to millions of nodes.

Examples
--------
>>> from alcontact.fem import meshes
>>> m = meshes.rectangle(0.0, 2.0, 0.0, 1.0, 8, 4)
>>> sorted(m.boundaries)
['bottom', 'left', 'right', 'top']
>>> g = meshes.rectangle(-1.0, 1.0, 0.0, 1.0, 10, 5,
...                      refine=dict(center=(0.0, 1.0), h_min=0.01, width=0.1, depth=0.05))
>>> bool(g.nvertices > m.nvertices)
True
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import logging
import math
import numbers
import os
import tempfile
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import skfem

from alcontact._options import show
from alcontact.errors import InputError, MeshError

__all__ = ["rectangle", "box", "interval", "read", "graded_axis", "MAX_CELLS_PER_AXIS", "MAX_VERTICES",
           "MAX_COORDINATE", "MIN_SPACING"]

logger = logging.getLogger(__name__)

_REFINE_KEYS = ("center", "h_min", "width", "depth", "growth", "h_max")


# ---------------------------------------------------------------------------
# one-dimensional coordinate generators
# ---------------------------------------------------------------------------
#: Most cells along one axis of a generated mesh (uniform or graded).
MAX_CELLS_PER_AXIS = 1_000_000
#: Most vertices of a generated mesh: a hard limit against absurd sizes, not a memory
#: model (``alcontact check`` estimates the memory a problem needs).
MAX_VERTICES = 20_000_000
#: Largest absolute coordinate of a generated mesh (element measures stay far from overflow).
MAX_COORDINATE = 1e30
#: Smallest element spacing of a generated mesh (element measures stay far from underflow).
MIN_SPACING = 1e-30
#: Smallest spacing relative to the largest absolute coordinate (neighbouring vertices stay distinct).
MIN_RELATIVE_SPACING = 1e-12


def _too_many(count: float, axis: str, what: str) -> None:
    if not count <= MAX_CELLS_PER_AXIS:  # also catches NaN
        fix = ("use a larger h_min (or h_max), a larger growth, a smaller width/depth" if what.startswith("refine")
               else "use fewer cells")
        raise InputError(f"{what} gives about {count:.3g} cells along {axis}; at most {MAX_CELLS_PER_AXIS} are "
                         f"allowed: {fix}.")


def _grow(length: float, h0: float, growth: float, h_max: float, axis: str = "x") -> np.ndarray:
    """Offsets in ``(0, length]`` with steps ``h0*growth**k`` capped at ``h_max``.

    The last offset is exactly ``length``; a final gap shorter than half the
    step it would have had is merged into the previous one.

    Raises
    ------
    InputError
        More than :data:`MAX_CELLS_PER_AXIS` steps would be needed.
    """
    if length <= 0.0:
        return np.empty(0)
    h_max = max(h_max, h0)
    if growth > 1.0:
        lg = math.log(growth)
        k_cap = math.log(h_max / h0) / lg
        # steps needed before the geometric sum passes length (+2: the result is the same as with k_cap)
        # Python floats: a huge growth gives inf here (NumPy scalars would warn of the overflow)
        n_geo = math.log1p(float(length) * (float(growth) - 1.0) / float(h0)) / lg + 2.0
        _too_many(min(k_cap, n_geo), axis, "refine (h_min, growth)")
        k_cap = max(0, int(math.ceil(min(k_cap, n_geo))))
        with np.errstate(over="ignore"):  # a huge growth overflows past the cap: min() gives h_max
            steps = np.minimum(h0 * growth ** np.arange(1, k_cap + 2), h_max)
    else:
        steps = np.array([h0])
    total = float(steps.sum())
    if total < length:  # fill the rest with the cap spacing
        fill = (length - total) / steps[-1]
        _too_many(fill + steps.size, axis, "refine (h_min, h_max, growth)")
        n_extra = int(math.ceil(fill)) + 1
        steps = np.concatenate([steps, np.full(n_extra, steps[-1])])
    offsets = np.cumsum(steps)
    keep = offsets < length
    offsets, steps = offsets[keep], steps[keep]
    if offsets.size and (length - offsets[-1]) < 0.5 * steps[-1]:
        offsets = offsets[:-1]
    return np.append(offsets, length)


def graded_axis(
    a: float,
    b: float,
    lo: float,
    hi: float,
    h_min: float,
    growth: float,
    h_max: float,
    axis: str = "x",
) -> np.ndarray:
    """Sorted coordinates on ``[a, b]``: uniform ``h_min`` on ``[lo, hi]``, graded outside.

    Parameters
    ----------
    a, b : float
        Axis end points, ``a < b``.
    lo, hi : float
        The fine window (clipped to ``[a, b]``); spacing there is ``h_min``
        (rounded down so that an integer number of cells fits). A window end
        closer than ``h_min / 2`` to an axis end is moved onto it, and a window
        shorter than ``h_min`` shrinks to a point, so that no cell is much
        smaller than ``h_min``.
    h_min : float
        Fine spacing, ``> 0``.
    growth : float
        Ratio of consecutive spacings outside the window, ``>= 1``.
    h_max : float
        Largest spacing.
    axis : str
        Name of the axis in error messages.

    Returns
    -------
    numpy.ndarray
        Strictly increasing coordinates with ``x[0] == a`` and ``x[-1] == b``.

    Raises
    ------
    InputError
        More than :data:`MAX_CELLS_PER_AXIS` cells along the axis.
    """
    from alcontact._options import Option, check_args

    big = MAX_COORDINATE
    a, b, lo, hi, h_min, growth, h_max = check_args("graded_axis", [
        (Option("a", "float", 0.0, "a", low=-big, high=big), a),
        (Option("b", "float", 0.0, "b", low=-big, high=big), b),
        (Option("lo", "float", 0.0, "lo", low=-big, high=big), lo),
        (Option("hi", "float", 0.0, "hi", low=-big, high=big), hi),
        (Option("h_min", "float", 0.0, "h_min", low=0.0, low_open=True, high=big), h_min),
        (Option("growth", "float", 1.2, "growth", low=1.0), growth),
        (Option("h_max", "float", 0.0, "h_max", low=0.0, low_open=True, high=big), h_max)])
    if not isinstance(axis, str):
        raise InputError(f"graded_axis: axis = {show(axis)}: expected a name such as 'x'.")
    lo, hi = max(lo, a), min(hi, b)
    if hi < lo:  # window outside the axis: grade from the nearest end
        lo = hi = min(max(lo, a), b)
    if 0.0 < lo - a < 0.5 * h_min:
        lo = a
    if 0.0 < b - hi < 0.5 * h_min:
        hi = b
    if 0.0 < hi - lo < h_min:  # a window shorter than one fine cell: a point (at an axis end if it touches one)
        lo = hi = b if hi == b else a if lo == a else 0.5 * (lo + hi)
    _too_many((hi - lo) / h_min, axis, "refine (h_min, width, depth)")
    n_fine = max(1, int(math.ceil((hi - lo) / h_min - 1e-9))) if hi > lo else 0
    fine = np.linspace(lo, hi, n_fine + 1) if n_fine else np.array([lo])
    h0 = (hi - lo) / n_fine if n_fine else h_min
    right = hi + _grow(b - hi, h0, growth, h_max, axis)
    left = lo - _grow(lo - a, h0, growth, h_max, axis)[::-1]
    x = np.concatenate([left, fine, right])
    x[0], x[-1] = a, b
    return x


def _check_refine(refine: Mapping[str, Any], dim: int) -> dict[str, Any]:
    if not isinstance(refine, Mapping):
        raise InputError(
            f"refine must be a dict with keys {', '.join(_REFINE_KEYS)}; got {type(refine).__name__}."
        )
    unknown = sorted(set(refine) - set(_REFINE_KEYS))
    if unknown:
        raise InputError(
            f"unknown refine key(s) {unknown}; allowed keys: {', '.join(_REFINE_KEYS)}."
        )
    missing = [k for k in ("center", "h_min", "width", "depth") if k not in refine]
    if missing:
        raise InputError(f"refine is missing key(s) {missing}; required: center, h_min, width, depth.")
    r = dict(refine)
    center = np.asarray(r["center"], dtype=float)
    if center.shape != (dim,) or not np.all(np.isfinite(center)):
        raise InputError(f"refine['center'] must be {dim} finite numbers; got {r['center']!r}.")
    r["center"] = center
    r.setdefault("growth", 1.2)
    for key, lower, strict in (("h_min", 0.0, True), ("width", 0.0, False),
                               ("depth", 0.0, False), ("growth", 1.0, False)):
        val = float(r[key])
        if not math.isfinite(val) or val < lower or (strict and val == lower):
            rel = ">" if strict else ">="
            raise InputError(f"refine[{key!r}] = {r[key]!r} is out of range; it must be finite and {rel} {lower}.")
        r[key] = val
    if "h_max" in r:
        if not (math.isfinite(float(r["h_max"])) and float(r["h_max"]) > 0):
            raise InputError(f"refine['h_max'] = {r['h_max']!r} must be finite and > 0.")
        r["h_max"] = float(r["h_max"])
    return r


def _finite(x) -> bool:
    """A finite number (an integer too large for a float is not)."""
    try:
        return math.isfinite(x)
    except OverflowError:
        return False


def _min_spacing(lo: float, hi: float) -> float:
    return max(MIN_SPACING, MIN_RELATIVE_SPACING * max(abs(lo), abs(hi)))


def _check_extent(names: str, lo: float, hi: float, n: int) -> None:
    if not all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in (lo, hi)):
        raise InputError(f"{names}: bounds must be numbers; got ({show(lo)}, {show(hi)}).")
    if not (_finite(lo) and _finite(hi) and hi > lo):
        raise InputError(f"{names}: need finite bounds with lower < upper; got ({lo}, {hi}).")
    if max(abs(lo), abs(hi)) > MAX_COORDINATE:
        raise InputError(f"{names}: bounds ({lo:g}, {hi:g}) exceed |coordinate| <= {MAX_COORDINATE:g}; "
                         "choose other length units (e.g. mm instead of m or the reverse).")
    if not (isinstance(n, numbers.Real) and not isinstance(n, bool) and _finite(n) and int(n) == n
            and 1 <= n <= MAX_CELLS_PER_AXIS):
        raise InputError(f"number of cells along {names} must be an integer in [1, {MAX_CELLS_PER_AXIS}]; "
                         f"got {show(n)}.")
    h = (hi - lo) / n
    if h < _min_spacing(lo, hi):
        raise InputError(f"{names}: {int(n)} cells on ({lo:g}, {hi:g}) are {h:.3g} wide, too small for the size "
                         f"of the coordinates (at least {_min_spacing(lo, hi):.3g}); use fewer cells or shift "
                         "the bounds toward 0.")


def _check_aspect(bounds, ns) -> None:
    """Every uniform spacing is distinguishable at the size of the largest coordinate or extent."""
    scale = max(max(abs(a), abs(b), b - a) for a, b in bounds)
    for ax, ((a, b), n) in enumerate(zip(bounds, ns)):
        h = (b - a) / n
        if h < MIN_RELATIVE_SPACING * scale:
            raise InputError(f"{'xyz'[ax]}: cells of {h:.3g} are too thin for a body of size {scale:.3g} (spacing "
                             f"at least {MIN_RELATIVE_SPACING:g} times the largest coordinate); use fewer cells along "
                             f"{'xyz'[ax]} or a less elongated body.")


def _check_vertices(coords: list[np.ndarray]) -> None:
    n = math.prod(c.size for c in coords)
    if n > MAX_VERTICES:
        raise InputError(f"the mesh would have {n:.3g} vertices ({' x '.join(str(c.size) for c in coords)}); at "
                         f"most {MAX_VERTICES:.3g} are allowed. Use fewer cells or a coarser refine (larger "
                         "h_min, growth, smaller width/depth).")


def _axes(bounds, ns, refine, top_axis):
    """Coordinates per axis; the refinement depth acts on ``top_axis`` (from the top down)."""
    dim = len(bounds)
    _check_aspect(bounds, ns)
    if refine is None:
        coords = [np.linspace(a, b, int(n) + 1) for (a, b), n in zip(bounds, ns)]
        _check_vertices(coords)
        return coords
    r = _check_refine(refine, dim)
    lo_all = min(a for a, _ in bounds)
    hi_all = max(b for _, b in bounds)
    floor = _min_spacing(lo_all, hi_all)
    for key in ("h_min",) + (("h_max",) if "h_max" in r else ()):
        if r[key] < floor:
            raise InputError(f"refine[{key!r}] = {r[key]!r} is too small for the size of the coordinates; it must "
                             f"be at least {floor:.3g}. Use a larger {key}.")
    if max(abs(float(c)) for c in r["center"]) > MAX_COORDINATE:
        raise InputError(f"refine['center'] = {r['center'].tolist()!r}: coordinates must satisfy "
                         f"|x| <= {MAX_COORDINATE:g}; put the center on the top face of the mesh.")
    coords = []
    for ax, ((a, b), n) in enumerate(zip(bounds, ns)):
        h_max = r.get("h_max", (b - a) / n)
        c = r["center"][ax]
        if ax == top_axis:
            lo, hi = c - r["depth"], b
        else:
            lo, hi = c - r["width"], c + r["width"]
        coords.append(graded_axis(a, b, lo, hi, r["h_min"], r["growth"], h_max, axis="xyz"[ax]))
    _check_vertices(coords)
    return coords


def _named(mesh, names_bounds, tol):
    """Name boundary facets by the coordinate of their midpoints (boundary facets only, vectorized)."""
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    return mesh.with_boundaries(
        {name: bf[np.abs(mid[axis] - value) <= tol] for name, (axis, value) in names_bounds.items()}
    )


# ---------------------------------------------------------------------------
# public constructors
# ---------------------------------------------------------------------------
def rectangle(
    x0: float,
    x1: float,
    y0: float,
    y1: float,
    nx: int,
    ny: int,
    *,
    refine: Mapping[str, Any] | None = None,
) -> skfem.MeshTri:
    """Triangulated rectangle ``[x0, x1] x [y0, y1]`` with named sides.

    Parameters
    ----------
    x0, x1, y0, y1 : float
        Extent.
    nx, ny : int
        Number of cells per direction (uniform mesh); with ``refine`` they only
        set the largest spacing ``(x1-x0)/nx`` and ``(y1-y0)/ny``.
    refine : dict, optional
        Grading toward a point on the top edge: ``center=(xc, yc)``, ``h_min``,
        ``width`` (half-width of the fine strip, ``|x - xc| <= width``),
        ``depth`` (fine for ``y >= yc - depth``), ``growth`` (default 1.2) and
        optionally ``h_max`` (overrides both caps).

    Returns
    -------
    skfem.MeshTri
        Mesh with boundaries ``"left"`` (x = x0), ``"right"`` (x = x1),
        ``"bottom"`` (y = y0), ``"top"`` (y = y1).
    """
    _check_extent("x", x0, x1, nx)
    _check_extent("y", y0, y1, ny)
    x, y = _axes([(x0, x1), (y0, y1)], [nx, ny], refine, top_axis=1)
    mesh = skfem.MeshTri.init_tensor(x, y)
    tol = 1e-9 * max(x1 - x0, y1 - y0)
    mesh = _named(mesh, {"left": (0, x0), "right": (0, x1), "bottom": (1, y0), "top": (1, y1)}, tol)
    logger.debug("rectangle mesh: %d vertices, %d triangles", mesh.nvertices, mesh.nelements)
    return mesh


def box(
    x0: float,
    x1: float,
    y0: float,
    y1: float,
    z0: float,
    z1: float,
    nx: int,
    ny: int,
    nz: int,
    *,
    refine: Mapping[str, Any] | None = None,
) -> skfem.MeshTet:
    """Tetrahedral box with named faces.

    Parameters
    ----------
    x0, x1, y0, y1, z0, z1 : float
        Extent.
    nx, ny, nz : int
        Cells per direction (uniform), or the caps of the spacing with ``refine``.
    refine : dict, optional
        As in :func:`rectangle` with ``center=(xc, yc, zc)`` on the top face:
        fine where ``|x-xc| <= width``, ``|y-yc| <= width`` and ``z >= zc - depth``.

    Returns
    -------
    skfem.MeshTet
        Boundaries ``"left"`` (x=x0), ``"right"`` (x=x1), ``"front"`` (y=y0),
        ``"back"`` (y=y1), ``"bottom"`` (z=z0), ``"top"`` (z=z1).
    """
    _check_extent("x", x0, x1, nx)
    _check_extent("y", y0, y1, ny)
    _check_extent("z", z0, z1, nz)
    x, y, z = _axes([(x0, x1), (y0, y1), (z0, z1)], [nx, ny, nz], refine, top_axis=2)
    mesh = skfem.MeshTet.init_tensor(x, y, z)
    tol = 1e-9 * max(x1 - x0, y1 - y0, z1 - z0)
    mesh = _named(
        mesh,
        {"left": (0, x0), "right": (0, x1), "front": (1, y0), "back": (1, y1),
         "bottom": (2, z0), "top": (2, z1)},
        tol,
    )
    logger.debug("box mesh: %d vertices, %d tetrahedra", mesh.nvertices, mesh.nelements)
    return mesh


def interval(x0: float, x1: float, n: int) -> skfem.MeshLine:
    """Uniform mesh of ``[x0, x1]`` with ``n`` cells; boundaries ``"left"``, ``"right"``."""
    _check_extent("x", x0, x1, n)
    mesh = skfem.MeshLine(np.linspace(x0, x1, int(n) + 1))
    tol = 1e-9 * (x1 - x0)
    return _named(mesh, {"left": (0, x0), "right": (0, x1)}, tol)


# ---------------------------------------------------------------------------
# reading
# ---------------------------------------------------------------------------
_SUPPORTED_CELLS = ("tetra", "triangle", "line")
_CELL_DIMS = {
    "tetra": 3, "tetra10": 3, "hexahedron": 3, "hexahedron20": 3, "hexahedron27": 3,
    "wedge": 3, "pyramid": 3, "triangle": 2, "triangle6": 2, "quad": 2, "quad8": 2,
    "quad9": 2, "line": 1, "line3": 1,
}


#: second-order Gmsh cells read as curved meshes, and the linear cell of their vertices
_SECOND_ORDER = {"triangle6": "triangle", "tetra10": "tetra", "line3": "line"}
_VERTICES = {"triangle": 3, "tetra": 4, "line": 2}
#: local edges of meshio's (VTK's) triangle6 / tetra10 cells, in the order of their edge nodes
_VTK_EDGES = {"triangle6": ((0, 1), (1, 2), (2, 0)),
              "tetra10": ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))}


def _split_second_order(m, path):
    """A meshio mesh with ``triangle6``/``tetra10`` cells as linear cells, plus what restores the edge nodes.

    Returns ``(linear, kind, block)`` with ``kind`` the second-order cell type and ``block``
    its connectivity (meshio's point indices), or ``(m, None, None)`` for a first-order mesh.
    Facet cells (``line3``, ``triangle6`` facets of ``tetra10``) become linear too, so that
    the physical groups are read as for a first-order mesh.
    """
    import meshio

    types = [c.type for c in m.cells]
    kind = "tetra10" if "tetra10" in types else ("triangle6" if "triangle6" in types else None)
    if kind is None:
        return m, None, None
    if _SECOND_ORDER[kind] in types:
        raise MeshError(f"mesh file {str(path)!r} has both {_SECOND_ORDER[kind]} and {kind} cells: a body is meshed with one "
                        "element order. Re-mesh it with one order (gmsh -order 1 or -order 2).")
    block = np.concatenate([c.data for c in m.cells if c.type == kind])
    cells = []
    for c in m.cells:
        if c.type in ("triangle6", "tetra10", "line3"):
            lin = _SECOND_ORDER[c.type]
            cells.append(meshio.CellBlock(lin, np.ascontiguousarray(c.data[:, : _VERTICES[lin]])))
        else:
            cells.append(c)
    linear = meshio.Mesh(m.points, cells, point_data=m.point_data, cell_data=m.cell_data,
                         field_data=m.field_data, cell_sets=m.cell_sets)
    return linear, kind, block


def _curved_mesh(mesh, points: np.ndarray, used: np.ndarray, kind: str, block: np.ndarray, path):
    """The second-order mesh (``MeshTri2``/``MeshTet2``) of ``mesh`` with the edge nodes of ``block``.

    ``mesh`` is the first-order mesh read from the same file (vertices ``points[used]``),
    ``block`` the ``triangle6``/``tetra10`` connectivity in meshio's point numbering.
    """
    cls = skfem.MeshTri2 if kind == "triangle6" else skfem.MeshTet2
    dim = mesh.dim()
    nv = mesh.nvertices
    new = np.full(points.shape[0], -1, dtype=np.int64)
    new[used] = np.arange(used.size)
    m2 = cls.from_mesh(mesh)
    edges = np.sort(np.asarray(mesh.facets if dim == 2 else mesh.edges), axis=0)  # the P2 edge DOFs, in order
    keys = edges[0].astype(np.int64) * nv + edges[1]
    order = np.argsort(keys)
    doflocs = np.array(m2.doflocs, dtype=float)
    for k, (a, b) in enumerate(_VTK_EDGES[kind]):
        va, vb = new[block[:, a]], new[block[:, b]]
        key = np.minimum(va, vb) * nv + np.maximum(va, vb)
        pos = np.searchsorted(keys, key, sorter=order)
        idx = order[np.minimum(pos, keys.size - 1)]
        if (va < 0).any() or (vb < 0).any() or not np.array_equal(keys[idx], key):
            raise MeshError(f"cannot read the second-order cells of {str(path)!r}: an edge node does not match "
                            "an edge of the mesh. Re-export the mesh from Gmsh (Mesh.SecondOrderIncomplete = 0).")
        doflocs[:, nv + idx] = points[block[:, _VERTICES[_SECOND_ORDER[kind]] + k], :dim].T
    return dataclasses.replace(m2, doflocs=doflocs, _boundaries=mesh._boundaries, _subdomains=mesh._subdomains)


def _mesh_geo(path: Path) -> Path:
    try:
        import gmsh  # type: ignore[import-not-found]
    except ImportError as exc:
        raise MeshError(
            f"cannot mesh {str(path)!r}: .geo files need the gmsh Python module; "
            "run `pip install gmsh`, or mesh it yourself and pass the .msh file."
        ) from exc
    fd, out = tempfile.mkstemp(suffix=".msh")
    os.close(fd)
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        gmsh.model.mesh.generate(gmsh.model.getDimension())
        gmsh.write(out)
    except Exception as exc:  # gmsh raises plain Exception
        raise MeshError(f"gmsh failed to mesh {str(path)!r}: {exc}. Check the .geo file.") from exc
    finally:
        gmsh.finalize()
    return Path(out)


def _drop_unused_points(m):
    """Remove points no cell uses (Gmsh keeps geometry points); renumbers all cell blocks."""
    import meshio

    used = np.unique(np.concatenate([c.data.ravel() for c in m.cells]))
    if used.size == len(m.points):
        return m
    new = np.full(len(m.points), -1, dtype=np.int64)
    new[used] = np.arange(used.size)
    cells = [meshio.CellBlock(c.type, new[c.data]) for c in m.cells]
    return meshio.Mesh(
        m.points[used], cells,
        point_data={k: v[used] for k, v in m.point_data.items()},
        cell_data=m.cell_data, field_data=m.field_data, cell_sets=m.cell_sets,
    )


_GROUP_FIX = ("give every physical group its own name in the .geo file, e.g. Physical Curve(\"top\", 1) = {...}; "
              "(Physical Surface/Volume for the body), then re-mesh")


def _physical_names(path: Path) -> list[tuple[int, int, str]]:
    """``(dimension, tag, name)`` of each entry of the ``$PhysicalNames`` section of a Gmsh file, in file order.

    meshio keeps one tag per name (a dict), so names given twice are read here from the
    section itself (ASCII in every Gmsh format, also in binary files).
    """
    if path.suffix.lower() != ".msh":
        return []
    raw = path.read_bytes()
    start = raw.find(b"$PhysicalNames")
    end = raw.find(b"$EndPhysicalNames", start)
    if start < 0 or end < 0:
        return []
    out = []
    for line in raw[start:end].decode("utf-8", errors="replace").splitlines()[2:]:
        parts = line.strip().split(maxsplit=2)
        if len(parts) == 3 and parts[0].lstrip("-").isdigit() and parts[1].lstrip("-").isdigit():
            out.append((int(parts[0]), int(parts[1]), parts[2].strip().strip('"')))
    return out


def _check_physical_groups(m, declared: list[tuple[int, int, str]], path) -> None:
    """Refuse physical groups that scikit-fem cannot name: no name, a name given twice, a tag with two names.

    scikit-fem looks a group's name up by its tag alone, so each used tag needs exactly one
    name and each name one tag.

    Raises
    ------
    MeshError
        Naming the file, the tags and names, and the way out.
    """
    where = f"mesh file {str(path)!r}"
    by_name: dict[str, list[tuple[int, int]]] = {}
    by_tag: dict[int, set[str]] = {}
    for dim, tag, name in declared:
        if not name:
            raise MeshError(f"{where}: physical group {tag} (dimension {dim}) has an empty name; {_GROUP_FIX}.")
        by_name.setdefault(name, []).append((dim, tag))
        by_tag.setdefault(tag, set()).add(name)
    twice = {n: g for n, g in by_name.items() if len(g) > 1}
    if twice:
        n, g = next(iter(sorted(twice.items())))
        groups = " and ".join(f"tag {tag} (dimension {dim})" for dim, tag in g)
        raise MeshError(f"{where}: the physical name {n!r} is given to {len(g)} groups ({groups}), so the "
                        f"boundaries and regions cannot be told apart; {_GROUP_FIX}, or merge the groups into one.")
    shared = {tag: names for tag, names in by_tag.items() if len(names) > 1}
    if shared:
        tag, names = next(iter(sorted(shared.items())))
        raise MeshError(f"{where}: physical tag {tag} is used by groups of different dimensions named "
                        f"{', '.join(map(repr, sorted(names)))}; scikit-fem finds a group by its tag, so give the "
                        "groups different tags (e.g. Physical Curve(\"top\", 1), Physical Surface(\"body\", 10)), "
                        "then re-mesh.")
    named = {int(v[0]) for v in (m.field_data or {}).values() if np.size(v) >= 1}
    used: set[int] = set()
    for block, tags in zip(m.cells, (m.cell_data or {}).get("gmsh:physical", [])):
        if _CELL_DIMS.get(block.type, 0) >= 1:
            used |= {int(x) for x in np.unique(np.asarray(tags))}
    unnamed = sorted(used - named - {0})
    if unnamed:
        raise MeshError(f"{where}: physical group(s) with tag {', '.join(map(str, unnamed))} have no name "
                        f"($PhysicalNames); boundaries and regions are found by name, so {_GROUP_FIX}.")


def _check_cells(m, kind: str, path) -> None:
    """Refuse coordinates that are not finite or too large, duplicate elements, and a 2D mesh off a plane z = const.

    Raises
    ------
    MeshError
        Naming the file, the node or element and the way out.
    """
    where = f"mesh file {str(path)!r}"
    pts = np.asarray(m.points, dtype=float)
    cells = next(c.data for c in m.cells if c.type == kind)
    bad = np.flatnonzero(~np.all(np.isfinite(pts), axis=1))
    if bad.size:
        raise MeshError(f"{where}: {bad.size} node(s) of the elements have coordinates that are not finite numbers "
                        f"(first: {pts[bad[0]].tolist()}); fix the $Nodes section or re-export the mesh from Gmsh.")
    big = float(np.max(np.abs(pts), initial=0.0))
    if big > MAX_COORDINATE:
        i = int(np.argmax(np.max(np.abs(pts), axis=1)))
        raise MeshError(f"{where}: the node at {pts[i].tolist()} has a coordinate of magnitude {big:.3g}, beyond "
                        f"{MAX_COORDINATE:g} "
                        "where element measures and stiffness entries stay finite in double precision; express "
                        "the lengths in other units (e.g. km instead of mm), the problem file alike.")
    dim = _CELL_DIMS[kind]
    if dim == 2 and pts.shape[1] > 2 and pts.shape[0]:  # a line mesh is refused later, with its own message
        extent = float(np.max(np.ptp(pts[:, :dim], axis=0), initial=0.0))
        z = pts[:, dim:]
        spread = float(np.max(np.ptp(z, axis=0), initial=0.0))
        if spread > 1e-9 * max(extent, 1e-300):
            i = int(np.argmax(np.max(np.abs(z - z[0]), axis=1)))
            raise MeshError(f"{where}: a {dim}D mesh ({kind} cells) whose nodes are not in one plane "
                            f"z = const (e.g. the node at {pts[i].tolist()}; z varies by {spread:.3g}); alcontact "
                            "would drop z and solve a distorted body. Mesh the body in the plane z = 0.")
        if np.any(z[0] != 0):
            logger.warning("%s: the %dD mesh lies in the plane z = %g; z is dropped.", path, dim, float(z[0, 0]))
    key = np.sort(np.asarray(cells), axis=1)
    _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    if np.any(counts > 1):
        dup = int(first[np.argmax(counts > 1)])
        twins = np.flatnonzero(np.all(key == key[dup], axis=1))
        raise MeshError(f"{where}: {int(np.sum(counts[counts > 1] - 1))} duplicate {kind} element(s) (first: "
                        f"{twins.size} elements on the nodes {np.round(pts[np.asarray(cells)[dup]], 6).tolist()}), "
                        "e.g. a surface in two physical groups; remove the duplicates (one physical group per "
                        "surface/volume, or Gmsh: Mesh > Coherence), then re-export.")


def read(path: str | os.PathLike[str]):
    """Read a Gmsh mesh with physical groups as named boundaries and subdomains.

    Parameters
    ----------
    path : str or path-like
        A ``.msh`` file (any format meshio reads; Gmsh 2.2 and 4.1 tested via
        meshio), or a ``.geo`` script meshed with the ``gmsh`` module if it is
        installed.

    Returns
    -------
    skfem.Mesh
        ``MeshTri`` (triangles), ``MeshTet`` (tetrahedra) or ``MeshLine``; for
        second-order Gmsh cells (``triangle6``, ``tetra10``) the curved ``MeshTri2`` or
        ``MeshTet2`` whose edge nodes are the file's (P2 bodies use its isoparametric
        map; P1 bodies its vertices). Physical groups of facets are in
        ``mesh.boundaries`` and of cells in ``mesh.subdomains``, keyed by the physical names.

    Raises
    ------
    alcontact.errors.MeshError
        Missing or unreadable file, no supported cell type (``triangle``/``tetra``/
        ``line`` cells and the second-order ``triangle6``/``tetra10``; not quadrilaterals
        or hexahedra), or a ``.geo`` file without ``gmsh`` installed.
    """
    import meshio
    from skfem.io.meshio import from_meshio

    if not isinstance(path, (str, os.PathLike)):
        raise MeshError(f"mesh file = {show(path)}: expected a path (str or pathlib.Path), got {type(path).__name__}.")
    p = Path(path)
    if not p.is_file():
        raise MeshError(f"mesh file {str(p)!r} does not exist; check the path (relative to {os.getcwd()!r}).")
    tmp = None
    if p.suffix.lower() == ".geo":
        tmp = p = _mesh_geo(p)
    try:
        sink = io.StringIO()
        try:  # meshio prints, and may call sys.exit, on unreadable files; NumPy warns on odd numbers
            with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink), warnings.catch_warnings(), \
                    np.errstate(all="ignore"):
                warnings.simplefilter("ignore")
                m = meshio.read(p, file_format="gmsh" if p.suffix.lower() == ".msh" else None)
                declared = _physical_names(p)
        except (Exception, SystemExit) as exc:  # meshio raises many types (ReadError, ValueError, ...)
            detail = str(exc) if not isinstance(exc, SystemExit) else sink.getvalue().strip()
            raise MeshError(
                f"cannot read mesh file {str(path)!r}: {detail or type(exc).__name__}. Export it "
                "from Gmsh as .msh (format 2.2 or 4.1)."
            ) from exc
    finally:
        if tmp is not None:
            tmp.unlink(missing_ok=True)
    points = np.asarray(m.points, dtype=float)
    m, second, block = _split_second_order(m, path)  # triangle6/tetra10: read the vertices, then add the edge nodes
    types = {c.type for c in m.cells}
    kind = next((t for t in _SUPPORTED_CELLS if t in types), None)
    dim = _CELL_DIMS.get(kind, 0)
    other = sorted(t for t in types if t not in _SUPPORTED_CELLS and _CELL_DIMS.get(t, 0) >= max(dim, 1))
    if kind is None or other:
        raise MeshError(
            f"mesh file {str(path)!r} has cell types {sorted(types)}; supported are linear "
            f"{', '.join(_SUPPORTED_CELLS)} cells and second-order triangle6, tetra10 cells. Re-mesh with "
            "triangles/tetrahedra (no recombination; gmsh -order 1 or -order 2)."
        )
    _check_physical_groups(m, declared, path)
    used = np.unique(np.concatenate([c.data.ravel() for c in m.cells]))
    m = _drop_unused_points(m)
    _check_cells(m, kind, path)
    try:
        mesh = from_meshio(m, force_meshio_type=kind)
    except Exception as exc:
        raise MeshError(f"cannot convert mesh {str(path)!r}: {exc}.") from exc
    # drop meshio's bookkeeping sets (gmsh:bounding_entities, ...)
    mesh = dataclasses.replace(
        mesh,
        _boundaries={k: v for k, v in (mesh.boundaries or {}).items() if not str(k).startswith("gmsh:")} or None,
        _subdomains={k: v for k, v in (mesh.subdomains or {}).items() if not str(k).startswith("gmsh:")} or None,
    )
    if second is not None:
        mesh = _curved_mesh(mesh, points, used, second, block, path)
    logger.info(
        "read %s: %s mesh, %d vertices, %d elements, boundaries %s, subdomains %s",
        path, type(mesh).__name__, mesh.nvertices, mesh.nelements,
        sorted(mesh.boundaries or {}), sorted(mesh.subdomains or {}),
    )
    return mesh


def select_group(mesh, group: str):
    """The part of ``mesh`` made of the cells of its physical group ``group``: one body of a mesh of several.

    A Gmsh file may hold several bodies, each a physical group of cells (surfaces in 2D, volumes
    in 3D) with its own boundary groups; two bodies that touch share the nodes of their common
    boundary in the file and get their own copies here (the contact pair between them starts
    closed, gap zero). The part keeps the facet groups (``mesh.boundaries``) that lie on its
    boundary, restricted to its facets; groups with none of them are dropped, so a boundary name
    used by several bodies (``"top"``) names each body's own part of it.

    Parameters
    ----------
    mesh : skfem.Mesh
        A mesh read by :func:`read` (first order).
    group : str
        The physical name of a cell group (``mesh.subdomains``).

    Raises
    ------
    alcontact.errors.MeshError
        No cell group of that name (the message lists the mesh's cell groups), or a second-order mesh.

    Examples
    --------
    >>> m = skfem.MeshTri.init_tensor(np.linspace(0, 2, 3), np.linspace(0, 1, 2))
    >>> m = m.with_subdomains({"left": lambda x: x[0] < 1}).with_boundaries({"bottom": lambda x: x[1] == 0})
    >>> part = select_group(m, "left")
    >>> part.nelements, sorted(part.boundaries)
    (2, ['bottom'])
    """
    cells = dict(mesh.subdomains or {})
    if group not in cells:
        raise MeshError(f"the mesh has no cell group {group!r}; its physical groups of "
                        f"{'surfaces' if mesh.dim() == 2 else 'volumes'}: {', '.join(sorted(cells)) or '(none)'}.")
    if isinstance(mesh, (skfem.MeshTri2, skfem.MeshTet2)):
        raise MeshError(f"group = {group!r} on a second-order (curved) mesh: selecting one body of it is not "
                        "supported; write each body to its own file, or mesh with first-order cells.")
    part = mesh.restrict(cells[group])
    outer = np.asarray(part.boundary_facets())
    boundaries = {k: np.intersect1d(v, outer) for k, v in (part.boundaries or {}).items()}
    return dataclasses.replace(part, _boundaries={k: v for k, v in boundaries.items() if v.size} or None,
                               _subdomains={group: np.arange(part.nelements)})
