r"""Rigid obstacles described by a signed gap (signed distance), its normal and Hessian.

Sign convention (Sant'Ana 2005, ch. 3 gauge :math:`h` and eq. 6.15): the contact
constraint is :math:`g_N \le 0`, feasible when non-positive. The *admissible region*
:math:`D` is where the body may be; the obstacle occupies its complement. For a point
:math:`x`

.. math::

    \operatorname{gap}(x) =
    \begin{cases}
      -\operatorname{dist}(x, \partial D) & x \in D \text{ (free)},\\
      +\operatorname{dist}(x, \partial D) & x \notin D \text{ (penetration depth)},
    \end{cases}

which is the signed version of the gap (6.8) recommended in the reading notes (the
unsigned (6.8) can never release a node). With :math:`\bar x` the closest point of the
obstacle surface and :math:`n` the unit normal there, pointing *out of the obstacle into
the admissible region*,

.. math::

    n(x) = -\nabla \operatorname{gap}(x), \qquad
    x = \bar x - \operatorname{gap}(x)\, n(x), \qquad
    H(x) = \nabla^2 \operatorname{gap}(x).

Every method is vectorized: ``x`` has shape ``(m, d)``; ``gap`` returns ``(m,)``,
``normal`` and ``project`` ``(m, d)``, ``gap_hessian`` ``(m, d, d)``.

Obstacles are registered by name (:func:`available`, :func:`docs`, :func:`make`,
:func:`register`)::

    >>> import numpy as np
    >>> ob = make("sphere", center=[0.0, 0.0, 1.5], radius=1.0)
    >>> ob.gap(np.array([[0.0, 0.0, 0.0]]))   # 0.5 below the ball: free, gap < 0
    array([-0.5])
    >>> ob.normal(np.array([[0.0, 0.0, 0.0]]))
    array([[ 0.,  0., -1.]])

Where the distance function has a kink (centre of a ball, medial axis of a polytope)
the returned normal is one of the one-sided gradients, chosen deterministically; it is
never NaN.
"""

from __future__ import annotations

import abc
import inspect
import itertools
import math
from alcontact._options import VALUE_RANGE, is_integer, show
from alcontact.errors import InputError, NonFiniteError, UnknownNameError
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray


FloatArray = NDArray[np.float64]

_EPS = float(np.finfo(float).eps)
#: Relative radius below which a point counts as the centre of a ball/cylinder
#: (normal chosen deterministically, Hessian set to zero instead of ~1/r).
_CENTER_TOL = 1e-12


# --------------------------------------------------------------------------- protocol


@runtime_checkable
class Obstacle(Protocol):
    """The geometry of a rigid obstacle (see the module docstring).

    :class:`alcontact.contact.Master` is the full protocol of the master side of a contact
    pair (this one plus ``rigid``, ``surface_slip`` and ``bounding_box``); every obstacle
    of this module satisfies it.
    """

    @property
    def dim(self) -> int | None: ...

    @property
    def name(self) -> str: ...

    def describe(self) -> str: ...

    def check_dim(self, d: int) -> None: ...

    def gap(self, x: ArrayLike) -> FloatArray: ...

    def normal(self, x: ArrayLike) -> FloatArray: ...

    def evaluate(self, x: ArrayLike) -> tuple[FloatArray, FloatArray]: ...

    def project(self, x: ArrayLike) -> FloatArray: ...

    def gap_hessian(self, x: ArrayLike) -> FloatArray: ...


# --------------------------------------------------------------------------- validation


def _fmt(v: NDArray[Any]) -> str:
    return "(" + ", ".join(f"{float(t):.6g}" for t in np.ravel(v)) + ")"


def _readonly(a: NDArray[Any]) -> NDArray[Any]:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


#: Largest coordinate or radius magnitude, and smallest radius, an obstacle accepts: gaps and
#: distances square them, which must stay finite in double precision (:data:`~alcontact._options.VALUE_RANGE`).
_SMALLEST, _LARGEST = VALUE_RANGE

_UNITS = "express the lengths in other units (e.g. m instead of mm), the mesh alike"


def _vector(value: Any, name: str, dims: tuple[int, ...] = (2, 3), *, bounded: bool = True) -> FloatArray:
    """A finite 1-D parameter vector whose length is one of ``dims`` (entries at most ``_LARGEST`` if ``bounded``)."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"{name} must be a vector of numbers (one per axis), got {show(value)}") from exc
    if arr.ndim != 1 or arr.shape[0] not in dims:
        want = " or ".join(f"({d},)" for d in dims)
        raise InputError(f"{name} must have shape {want} (one entry per axis), got shape {arr.shape}: {show(value)}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite, got {_fmt(arr)}; give every entry as a number")
    if bounded and arr.size and float(np.max(np.abs(arr))) > _LARGEST:
        raise InputError(f"{name} = {_fmt(arr)}: entries larger than {_LARGEST:g} in magnitude overflow when the "
                         f"gaps are computed (distances are squared); {_UNITS}")
    return _readonly(arr)


def _unit(value: Any, name: str, dims: tuple[int, ...] = (2, 3)) -> FloatArray:
    """``value / |value|``, computed without overflow or underflow for any finite non-zero vector."""
    arr = _vector(value, name, dims, bounded=False)
    big = float(np.max(np.abs(arr))) if arr.size else 0.0
    if not big > 0.0:
        example = "[0.0, 0.0, 1.0]" if dims == (3,) else "[0.0, 1.0]"
        raise InputError(f"{name} must be a non-zero vector (it gives a direction), got {_fmt(arr)}; e.g. "
                         f"{name}={example}")
    scaled = arr / big  # entries in [-1, 1]: the norm cannot overflow
    return _readonly(scaled / float(np.linalg.norm(scaled)))


def _flag(value: Any, name: str) -> bool:
    """``value`` as a bool; an :class:`InputError` naming ``name`` for anything but true or false."""
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} must be true or false, got {value!r}")
    return bool(value)


def _positive(value: Any, name: str) -> float:
    if isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} = {show(value)}: must be a positive number, not a bool")
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"{name} = {show(value)}: must be a finite positive number, e.g. {name}=1.0") from exc
    if not (math.isfinite(v) and v > 0.0):
        raise InputError(f"{name} = {show(value)}: must be finite and > 0, e.g. {name}=1.0")
    if not _SMALLEST <= v <= _LARGEST:
        raise InputError(f"{name} = {v:g}: outside {_SMALLEST:g} .. {_LARGEST:g}, where gaps, normals and "
                         f"curvatures stay finite in double precision; {_UNITS}")
    return v


def _points(x: ArrayLike, dim: int | None) -> FloatArray:
    """Validate evaluation points: shape ``(m, dim)``, finite."""
    want = f"(m, {dim})" if dim is not None else "(m, d)"
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"x must be an array of shape {want}, got {type(x).__name__}") from exc
    if arr.ndim != 2 or (dim is not None and arr.shape[1] != dim) or arr.shape[1] < 1:
        raise InputError(
            f"x must have shape {want} (one point per row; use x.reshape(1, -1) for a "
            f"single point), got shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(arr), axis=1))[0])
        raise InputError(f"x must be finite; row {bad} is {_fmt(arr[bad])}")
    return arr


def _safe_unit_rows(v: FloatArray, r: FloatArray, degenerate: NDArray[np.bool_],
                    fallback: FloatArray) -> FloatArray:
    """``v / r`` row-wise, with ``fallback`` on degenerate rows (no division by ~0)."""
    e = v / np.where(degenerate, 1.0, r)[:, None]
    e[degenerate] = fallback
    return e


# --------------------------------------------------------------------------- base class


class _ObstacleBase(abc.ABC):
    """Shared validation and derived methods; subclasses implement ``_gap_normal``."""

    @property
    @abc.abstractmethod
    def dim(self) -> int | None:
        """Space dimension (2 or 3); ``None`` for a user obstacle of any dimension."""

    @property
    @abc.abstractmethod
    def name(self) -> str:
        """Registry name of this kind of obstacle."""

    @abc.abstractmethod
    def describe(self) -> str:
        """One-line description with the defining parameters, for messages."""

    @abc.abstractmethod
    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]: ...

    @abc.abstractmethod
    def _hessian(self, x: FloatArray) -> FloatArray: ...

    @property
    def rigid(self) -> bool:
        """``True``: a rigid obstacle's position never depends on the unknowns (:class:`~alcontact.contact.Master`)."""
        return True

    def bounding_box(self, d: int) -> tuple[FloatArray, FloatArray]:
        """Axis-aligned box ``(lo, hi)``, each of shape ``(d,)``, that contains the obstacle's surface.

        ``-inf`` / ``+inf`` along the directions in which the surface is unbounded (a
        half-space not normal to an axis, a cylinder along its axis, a user gap function).
        Candidate search: a point far outside the box cannot touch the obstacle.

        Examples
        --------
        >>> Circle(center=[0.0, 2.0], radius=1.0).bounding_box(2)
        (array([-1.,  1.]), array([1., 3.]))
        """
        if not (is_integer(d) and d in (2, 3)):
            raise InputError(f"bounding_box: d = {show(d)}: expected the space dimension, 2 or 3.")
        self.check_dim(d)
        lo, hi = self._extent(int(d))
        return np.array(lo, dtype=float), np.array(hi, dtype=float)

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        """``(lo, hi)`` of :meth:`bounding_box`; unbounded unless a subclass knows better."""
        return np.full(d, -np.inf), np.full(d, np.inf)

    def check_dim(self, d: int) -> None:
        """Raise :class:`InputError` unless the obstacle can be used with a ``d``-D body."""
        if self.dim is not None and int(d) != self.dim:
            raise InputError(
                f"obstacle {self.describe()} is {self.dim}D but the body is {d}D; "
                f"use an obstacle of dimension {d} (see `alcontact list`)"
            )

    def evaluate(self, x: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``(gap(x), normal(x))`` in one pass (cheaper than two calls for polytopes)."""
        return self._gap_normal(_points(x, self.dim))

    def gap(self, x: ArrayLike) -> FloatArray:
        """Signed gap, shape ``(m,)``: ``< 0`` free, ``> 0`` penetration depth."""
        return self.evaluate(x)[0]

    def normal(self, x: ArrayLike) -> FloatArray:
        """Unit normal ``-grad gap``, shape ``(m, d)``, out of the obstacle."""
        return self.evaluate(x)[1]

    def project(self, x: ArrayLike) -> FloatArray:
        """Closest point of the obstacle surface, shape ``(m, d)``: ``x + gap * normal``."""
        pts = _points(x, self.dim)
        g, n = self._gap_normal(pts)
        return pts + g[:, None] * n

    def gap_hessian(self, x: ArrayLike) -> FloatArray:
        """Hessian of the gap, shape ``(m, d, d)`` (``= -d normal / dx``)."""
        return self._hessian(_points(x, self.dim))

    def surface_slip(self, x: ArrayLike, y_prev: ArrayLike, *,
                     jacobian: bool = True) -> tuple[FloatArray, FloatArray | None]:
        r"""Slip on the surface from ``y_prev`` to the projection of ``x`` (:func:`surface_slip`).

        Default (any signed distance): the chord from ``y_prev`` to ``x`` projected onto
        the tangent plane at the projection of ``x``, :math:`\Delta s = P\,(x - y_{prev})`,
        :math:`P = I - \nu\nu^T`. Since :math:`P(x - \bar x) = 0` this is the tangential part
        of the chord between the two surface points: a first-order consistent measure of the
        path on the surface (exact for a plane; relative error :math:`\theta^2/6` when the
        normal turns by :math:`\theta`).
        """
        pts = _points(x, self.dim)
        return _chord_slip(self, pts, _previous(y_prev, pts), jacobian)


# --------------------------------------------------------------------------- half-space


@dataclass(frozen=True, eq=False)
class HalfSpace(_ObstacleBase):
    r"""Obstacle occupying :math:`\{x : (x - p)\cdot n < 0\}`; free space is on the side of ``n``.

    Parameters
    ----------
    point : array_like, shape (d,)
        A point of the obstacle surface, ``d`` = 2 or 3 (the dimension is inferred).
    normal : array_like, shape (d,)
        Normal pointing from the obstacle into free space; normalized here.

    Notes
    -----
    :math:`\operatorname{gap}(x) = -(x - p)\cdot n`, normal :math:`n`, Hessian 0.

    Examples
    --------
    >>> HalfSpace(point=[0.0, 0.0], normal=[0.0, 2.0]).gap([[1.0, -0.25]])
    array([0.25])
    """

    point: FloatArray
    normal_vector: FloatArray

    def __init__(self, point: ArrayLike, normal: ArrayLike) -> None:
        p = _vector(point, "point")
        n = _unit(normal, "normal")
        if n.shape != p.shape:
            raise InputError(
                f"normal must have shape {p.shape} like point, got shape {n.shape}"
            )
        object.__setattr__(self, "point", p)
        object.__setattr__(self, "normal_vector", n)

    @property
    def dim(self) -> int:
        return int(self.point.shape[0])

    @property
    def name(self) -> str:
        return "half-space"

    def describe(self) -> str:
        return (f"half-space through {_fmt(self.point)} "
                f"with free-side normal {_fmt(self.normal_vector)}")

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        g = -(x - self.point) @ self.normal_vector
        return g, np.broadcast_to(self.normal_vector, x.shape).copy()

    def _hessian(self, x: FloatArray) -> FloatArray:
        return np.zeros((x.shape[0], self.dim, self.dim))

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        # the plane is bounded along axis i only when it is normal to e_i (n = +-e_i)
        n, p = self.normal_vector, self.point
        bounded = np.array([np.count_nonzero(np.delete(n, i)) == 0 for i in range(d)])
        return np.where(bounded, p, -np.inf), np.where(bounded, p, np.inf)


# --------------------------------------------------------------------------- balls


@dataclass(frozen=True, eq=False)
class _Ball(_ObstacleBase):
    r"""Ball of radius :math:`R` centred at :math:`c`, indenter or cavity.

    With :math:`r = |x - c|` and :math:`e = (x - c)/r`:

    * indenter (solid ball, body outside): gap :math:`R - r`, normal :math:`e`,
      Hessian :math:`-(I - e e^T)/r`;
    * cavity (``inside=True``, body inside): gap :math:`r - R`, normal :math:`-e`,
      Hessian :math:`+(I - e e^T)/r`.

    At the centre (:math:`r \le 10^{-12} R`) the normal uses :math:`e = e_1` (first basis
    vector) and the Hessian is returned as 0 (the true one is unbounded there).
    """

    center: FloatArray
    radius: float
    inside: bool = False

    _dims: ClassVar[tuple[int, ...]] = (2, 3)
    _kind: ClassVar[str] = "ball"

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _vector(self.center, "center", self._dims))
        object.__setattr__(self, "radius", _positive(self.radius, "radius"))
        object.__setattr__(self, "inside", _flag(self.inside, "inside"))

    @property
    def dim(self) -> int:
        return int(self.center.shape[0])

    @property
    def name(self) -> str:
        return self._kind + ("-cavity" if self.inside else "")

    def describe(self) -> str:
        role = "cavity (body inside)" if self.inside else "indenter (body outside)"
        return f"{self._kind} {role}, center {_fmt(self.center)}, radius {self.radius:.6g}"

    def _radial(self, x: FloatArray) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
        v = x - self.center
        r = np.linalg.norm(v, axis=1)
        deg = r <= _CENTER_TOL * self.radius
        fallback = np.eye(self.dim)[0]
        return r, _safe_unit_rows(v, r, deg, fallback), deg

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        r, e, _ = self._radial(x)
        if self.inside:
            return r - self.radius, -e
        return self.radius - r, e

    def project(self, x: ArrayLike) -> FloatArray:
        pts = _points(x, self.dim)
        _, e, _ = self._radial(pts)
        return self.center + self.radius * e

    def _hessian(self, x: FloatArray) -> FloatArray:
        r, e, deg = self._radial(x)
        proj = np.eye(self.dim) - e[:, :, None] * e[:, None, :]
        h = proj / np.where(deg, 1.0, r)[:, None, None]
        h[deg] = 0.0
        return h if self.inside else -h

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        return self.center - self.radius, self.center + self.radius

    def surface_slip(self, x: ArrayLike, y_prev: ArrayLike, *,
                     jacobian: bool = True) -> tuple[FloatArray, FloatArray | None]:
        r"""Geodesic slip on the sphere/circle: the great-circle arc as a tangent vector.

        With :math:`\theta` the angle between the radii to ``y_prev`` and to the projection
        of ``x``: :math:`\Delta s = \frac{\theta}{\sin\theta} P (x - y_{prev})`, of length
        :math:`R\theta` (:func:`_arc_scale`).
        """
        pts = _points(x, self.dim)
        yp = _previous(y_prev, pts)
        slip, jac = _chord_slip(self, pts, yp, jacobian)
        r, e, deg = self._radial(pts)
        cos = np.einsum("ij,ij->i", e, yp - self.center) / self.radius
        return _arc_scale(slip, jac, self.radius, np.zeros((self.dim, self.dim)), pts - yp,
                          np.where(deg, self.radius, r), cos)


class Sphere(_Ball):
    """Sphere in 3D: solid indenter, or cavity with ``inside=True`` (``center``, ``radius``).

    Examples
    --------
    >>> Sphere(center=[0, 0, 0], radius=1.0).gap([[0.0, 0.0, 3.0]])
    array([-2.])
    >>> Sphere(center=[0, 0, 0], radius=1.0, inside=True).gap([[0.0, 0.0, 0.5]])
    array([-0.5])
    """

    _dims = (3,)
    _kind = "sphere"


class Circle(_Ball):
    """Circle (disc) in 2D: solid indenter, or cavity with ``inside=True``.

    Examples
    --------
    >>> Circle(center=[0, 0], radius=1.0).normal([[0.0, 2.0]])
    array([[0., 1.]])
    """

    _dims = (2,)
    _kind = "circle"


# --------------------------------------------------------------------------- cylinder


@dataclass(frozen=True, eq=False)
class Cylinder(_ObstacleBase):
    r"""Infinite circular cylinder in 3D (axis through ``center`` along ``axis``).

    With :math:`w = (I - a a^T)(x - c)`, :math:`r = |w|`, :math:`e = w / r`: indenter gap
    :math:`R - r`, normal :math:`e`, Hessian :math:`-(I - a a^T - e e^T)/r`; cavity
    (``inside=True``) flips the signs. On the axis the normal uses a fixed unit vector
    perpendicular to the axis and the Hessian is 0.

    Examples
    --------
    >>> Cylinder(center=[0, 0, 0], axis=[0, 0, 1], radius=1.0).gap([[3.0, 0.0, 7.0]])
    array([-2.])
    """

    center: FloatArray
    axis: FloatArray
    radius: float
    inside: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _vector(self.center, "center", (3,)))
        object.__setattr__(self, "axis", _unit(self.axis, "axis", (3,)))
        object.__setattr__(self, "radius", _positive(self.radius, "radius"))
        object.__setattr__(self, "inside", _flag(self.inside, "inside"))

    @property
    def dim(self) -> int:
        return 3

    @property
    def name(self) -> str:
        return "cylinder-cavity" if self.inside else "cylinder"

    def describe(self) -> str:
        role = "cavity (body inside)" if self.inside else "indenter (body outside)"
        return (f"cylinder {role}, axis through {_fmt(self.center)} along {_fmt(self.axis)}, "
                f"radius {self.radius:.6g}")

    def _perp(self) -> FloatArray:
        a = self.axis
        k = int(np.argmin(np.abs(a)))
        u = np.eye(3)[k] - a[k] * a
        return u / np.linalg.norm(u)

    def _radial(self, x: FloatArray) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
        v = x - self.center
        w = v - (v @ self.axis)[:, None] * self.axis
        r = np.linalg.norm(w, axis=1)
        deg = r <= _CENTER_TOL * self.radius
        return r, _safe_unit_rows(w, r, deg, self._perp()), deg

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        r, e, _ = self._radial(x)
        if self.inside:
            return r - self.radius, -e
        return self.radius - r, e

    def _hessian(self, x: FloatArray) -> FloatArray:
        r, e, deg = self._radial(x)
        a = self.axis
        proj = np.eye(3) - np.outer(a, a) - e[:, :, None] * e[:, None, :]
        h = proj / np.where(deg, 1.0, r)[:, None, None]
        h[deg] = 0.0
        return h if self.inside else -h

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        # unbounded along every axis the cylinder's axis is not perpendicular to; else centre +- R
        bounded = self.axis == 0.0
        return (np.where(bounded, self.center - self.radius, -np.inf),
                np.where(bounded, self.center + self.radius, np.inf))

    def surface_slip(self, x: ArrayLike, y_prev: ArrayLike, *,
                     jacobian: bool = True) -> tuple[FloatArray, FloatArray | None]:
        r"""Geodesic slip on the cylinder (a developable surface): axial part plus arc.

        :math:`\Delta s = (a\cdot b)\,a + \frac{\theta}{\sin\theta}(P - aa^T)\,b`,
        :math:`b = x - y_{prev}`, :math:`\theta` the angle about the axis between the two
        surface points (unrolled, the surface is a plane and the geodesic a straight line).
        """
        pts = _points(x, 3)
        yp = _previous(y_prev, pts)
        slip, jac = _chord_slip(self, pts, yp, jacobian)
        r, e, deg = self._radial(pts)
        cos = np.einsum("ij,ij->i", e, yp - self.center) / self.radius  # e is normal to the axis
        return _arc_scale(slip, jac, self.radius, np.outer(self.axis, self.axis), pts - yp,
                          np.where(deg, self.radius, r), cos)


# --------------------------------------------------------------------------- polytope

_KIND_FACE, _KIND_EDGE, _KIND_VERTEX = 0, 1, 2


def _dedupe_rows(a: FloatArray, tol: float) -> FloatArray:
    keep: list[FloatArray] = []
    for row in a:
        if not any(np.max(np.abs(row - k)) <= tol for k in keep):
            keep.append(row)
    return np.array(keep)


def _vertex_array(vertices: Any, dim: int) -> FloatArray:
    """Finite ``(n, dim)`` vertex array with at least ``dim + 1`` rows, else InputError."""
    try:
        v = np.asarray(vertices, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"vertices must be an array of shape (n, {dim}), got {vertices!r}") from exc
    if v.ndim != 2 or v.shape[1] != dim or v.shape[0] < dim + 1:
        raise InputError(f"vertices must have shape (n, {dim}) with n >= {dim + 1}, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        k = int(np.flatnonzero(~np.all(np.isfinite(v), axis=1))[0])
        raise InputError(f"vertices must be finite; vertex {k} is {_fmt(v[k])}")
    if float(np.max(np.abs(v))) > _LARGEST:
        k = int(np.argmax(np.max(np.abs(v), axis=1)))
        raise InputError(f"vertices: vertex {k} = {_fmt(v[k])} has coordinates larger than {_LARGEST:g} in "
                         f"magnitude, which overflow when gaps are computed; {_UNITS}")
    return v


def _polygon_halfspaces(vertices: Any) -> tuple[FloatArray, FloatArray]:
    """Outward face normals and offsets of a counter-clockwise convex polygon."""
    v = _vertex_array(vertices, 2)
    edges = np.roll(v, -1, axis=0) - v
    lengths = np.linalg.norm(edges, axis=1)
    scale = float(np.max(np.ptp(v, axis=0)))
    if np.any(lengths <= 1e-12 * max(scale, 1e-300)):
        k = int(np.argmin(lengths))
        raise InputError(f"vertices {k} and {(k + 1) % len(v)} coincide; remove the duplicate")
    nxt = np.roll(edges, -1, axis=0)
    cross = edges[:, 0] * nxt[:, 1] - edges[:, 1] * nxt[:, 0]
    turn = np.arctan2(cross, np.einsum("ij,ij->i", edges, nxt))
    tol = 1e-12 * scale * scale
    if np.all(cross < -tol):
        raise InputError("vertices are clockwise; give them counter-clockwise (reverse the order)")
    if np.any(cross <= tol) or abs(float(np.sum(turn)) - 2 * math.pi) > 1e-6:
        k = int(np.argmin(cross))
        raise InputError(
            f"vertices do not form a strictly convex counter-clockwise polygon "
            f"(turn at vertex {(k + 1) % len(v)} is not a left turn, or the boundary "
            f"winds more than once); give the convex hull in counter-clockwise order"
        )
    normals = np.column_stack([edges[:, 1], -edges[:, 0]]) / lengths[:, None]
    offsets = np.einsum("ij,ij->i", normals, v)
    return normals, offsets


def _hull_halfspaces(vertices: Any) -> tuple[FloatArray, FloatArray]:
    from scipy.spatial import ConvexHull, QhullError

    v = _vertex_array(vertices, 3)
    try:
        hull = ConvexHull(v)
    except QhullError as exc:
        raise InputError(
            "vertices span no volume (all coplanar or repeated); give at least four "
            "points not in one plane"
        ) from exc
    eq = hull.equations  # n . x + off <= 0 inside
    return eq[:, :3], -eq[:, 3]


@dataclass(frozen=True, eq=False)
class ConvexPolytope(_ObstacleBase):
    r"""Bounded convex polygon (2D) or polyhedron (3D) obstacle :math:`\{x : A x \le b\}`.

    The *obstacle* occupies the polytope; the body lives outside it. Rows of ``A`` are
    normalized (``A``, ``b`` hold the normalized data), duplicate rows are dropped.

    Notes
    -----
    Inside (penetration): :math:`\operatorname{gap} = \min_i (b_i - a_i\cdot x)` with
    :math:`|a_i| = 1`, normal :math:`a_i` of the nearest face, Hessian 0. Outside:
    :math:`\operatorname{gap} = -|x - \bar x|` with the exact Euclidean projection
    :math:`\bar x` onto the polytope, found as the nearest of the candidate points on the
    faces (plane foot points that satisfy every other constraint to rounding), the edges
    (3D) and the vertices; every candidate is a point of the polytope, so none can
    undercut the distance. Normal :math:`(x - \bar x)/|x - \bar x|`. The Hessian outside is 0 in
    face regions, :math:`-(I - t t^T - n n^T)/\operatorname{dist}` near an edge of
    direction :math:`t` and :math:`-(I - n n^T)/\operatorname{dist}` near a vertex.
    Vertices and edges are found once at construction (cost grows like the number of
    faces squared times the number of vertices; fine for tens of faces).

    Examples
    --------
    >>> sq = ConvexPolytope.from_vertices([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> sq.gap([[2.0, 2.0], [0.5, 0.6]]).round(6)
    array([-1.414214,  0.4     ])
    """

    A: FloatArray
    b: FloatArray
    vertices: FloatArray = field(init=False, repr=False)
    edges: FloatArray = field(init=False, repr=False)
    _scale: float = field(init=False, repr=False)

    def __post_init__(self) -> None:
        try:
            a = np.asarray(self.A, dtype=float)
            b = np.asarray(self.b, dtype=float)
        except (TypeError, ValueError, OverflowError) as exc:
            raise InputError(f"A and b must be numeric arrays; got A={self.A!r}, b={self.b!r}") from exc
        if a.ndim != 2 or a.shape[1] not in (2, 3):
            raise InputError(f"A must have shape (k, 2) or (k, 3), got shape {a.shape}")
        d = a.shape[1]
        if b.shape != (a.shape[0],):
            raise InputError(f"b must have shape ({a.shape[0]},) to match A, got shape {b.shape}")
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            raise InputError("A and b must be finite")
        big = np.max(np.abs(a), axis=1)
        if np.any(big == 0.0):
            raise InputError(f"row {int(np.argmin(big))} of A is zero; every face needs a normal")
        a_in, a = a, a / big[:, None]  # rows scaled to max |entry| = 1: their norms cannot overflow
        norms = np.linalg.norm(a, axis=1)
        with np.errstate(over="ignore"):
            offsets = (b / big) / norms  # distance of each face plane from the origin
        if not np.all(np.abs(offsets) <= _LARGEST):
            k = int(np.argmax(~(np.abs(offsets) <= _LARGEST)))
            raise InputError(f"face {k} of A x <= b (A[{k}] = {_fmt(a_in[k])}, b[{k}] = {float(b[k]):g}) lies "
                             f"farther than {_LARGEST:g} from the origin, which overflows when gaps are computed; "
                             f"{_UNITS}")
        ab = np.column_stack([a / norms[:, None], offsets])
        ab = _dedupe_rows(ab, 1e-12 * max(1.0, float(np.max(np.abs(ab)))))
        a, b = ab[:, :d], ab[:, d]
        if a.shape[0] < d + 1:
            raise InputError(
                f"a bounded {d}D polytope needs at least {d + 1} faces, got {a.shape[0]}; "
                "use half-space for a single plane"
            )
        center = self._chebyshev(a, b)
        verts = self._vertices(a, b, center)
        scale = float(np.max(np.linalg.norm(verts - center, axis=1)))
        tol = 1e-9 * scale
        active = np.abs(verts @ a.T - b) <= tol  # (V, k)
        edges: list[FloatArray] = []
        if d == 3:
            for i, j in itertools.combinations(range(a.shape[0]), 2):
                on = np.flatnonzero(active[:, i] & active[:, j])
                if on.size < 2:
                    continue
                t = np.cross(a[i], a[j])
                if np.linalg.norm(t) <= 1e-12:
                    continue
                s = verts[on] @ t
                p0, p1 = verts[on[np.argmin(s)]], verts[on[np.argmax(s)]]
                if np.linalg.norm(p1 - p0) > tol:
                    edges.append(np.stack([p0, p1]))
        object.__setattr__(self, "A", _readonly(a))
        object.__setattr__(self, "b", _readonly(b))
        object.__setattr__(self, "vertices", _readonly(verts))
        object.__setattr__(self, "edges", _readonly(np.array(edges).reshape(-1, 2, d)))
        object.__setattr__(self, "_scale", scale)

    # ---- construction helpers
    @staticmethod
    def _chebyshev(a: FloatArray, b: FloatArray) -> FloatArray:
        from scipy.optimize import linprog

        d = a.shape[1]
        # max t s.t. a_i x + t <= b_i (|a_i| = 1): centre of the largest inscribed ball.
        res = linprog(np.r_[np.zeros(d), -1.0], A_ub=np.column_stack([a, np.ones(len(b))]),
                      b_ub=b, bounds=[(None, None)] * d + [(0.0, None)], method="highs")
        scale = max(1.0, float(np.max(np.abs(b))))
        if res.status == 3:
            raise InputError("the polytope A x <= b is unbounded; add faces that close it")
        if res.status != 0 or -res.fun <= 1e-12 * scale:
            raise InputError(
                "the polytope A x <= b is empty or flat (no interior point); check the signs "
                "of A and b (the obstacle is {x : A x <= b})"
            )
        for k in range(d):
            for sgn in (1.0, -1.0):
                c = np.zeros(d)
                c[k] = -sgn
                r = linprog(c, A_ub=a, b_ub=b, bounds=[(None, None)] * d, method="highs")
                if r.status == 3:
                    raise InputError(
                        "the polytope A x <= b is unbounded; add faces that close it "
                        "(use half-space for a single plane)"
                    )
        return np.asarray(res.x[:d])

    @staticmethod
    def _vertices(a: FloatArray, b: FloatArray, center: FloatArray) -> FloatArray:
        from scipy.spatial import HalfspaceIntersection, QhullError

        try:
            hs = HalfspaceIntersection(np.column_stack([a, -b]), center)
        except QhullError as exc:  # pragma: no cover - guarded by the LP checks
            raise InputError(f"cannot compute the vertices of A x <= b: {exc}") from exc
        pts = hs.intersections
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        scale = max(1.0, float(np.max(np.abs(pts))))
        return _dedupe_rows(pts, 1e-10 * scale)

    @classmethod
    def from_vertices(cls, vertices: ArrayLike) -> ConvexPolytope:
        """Polygon from counter-clockwise vertices (2D; strict convexity is checked) or
        polyhedron as the convex hull of points (3D)."""
        if np.ndim(vertices) == 2 and np.shape(vertices)[1] == 3:
            a, b = _hull_halfspaces(vertices)
        else:
            a, b = _polygon_halfspaces(vertices)
        return cls(a, b)

    # ---- protocol
    @property
    def dim(self) -> int:
        return int(self.A.shape[1])

    @property
    def name(self) -> str:
        return "convex-polygon" if self.dim == 2 else "convex-polyhedron"

    def describe(self) -> str:
        lo, hi = self.vertices.min(axis=0), self.vertices.max(axis=0)
        kind = "polygon" if self.dim == 2 else "polyhedron"
        return (f"convex {kind} with {self.A.shape[0]} faces and {len(self.vertices)} vertices, "
                f"bounding box {_fmt(lo)}-{_fmt(hi)}")

    def _outside(
        self, x: FloatArray
    ) -> tuple[FloatArray, FloatArray, NDArray[np.intp], FloatArray]:
        """Exact projection of outside points: distance, unit normal, feature kind, edge dir."""
        a, b, d = self.A, self.b, self.dim
        m, k = x.shape[0], a.shape[0]
        b_big = float(np.max(np.abs(b)))
        dist = np.empty(m)
        nrm = np.empty((m, d))
        kind = np.empty(m, dtype=np.intp)
        tdir = np.zeros((m, d))
        e0 = self.edges[:, 0, :]
        ed = self.edges[:, 1, :] - e0
        ed_len2 = np.einsum("ij,ij->i", ed, ed)
        chunk = max(1, 2**20 // max(1, k * k + len(ed) + len(self.vertices)))
        for lo in range(0, m, chunk):
            xs = x[lo:lo + chunk]
            n_ = xs.shape[0]
            # faces: foot points on each plane that satisfy all constraints. Every candidate
            # must be a point of the polytope: its distance is then an upper bound of the true
            # one, and the minimum is the distance. The feasibility test therefore only allows
            # the rounding error of ``foot @ a.T - b`` (a few eps times |x| + |b| + size); a
            # looser one accepts feet outside a neighbouring face near an edge and
            # underestimates the distance by up to that tolerance (a real face foot rejected
            # by rounding only moves the minimum to a nearby edge or vertex point, a
            # second-order change).
            s = xs @ a.T - b  # (n, k)
            foot = xs[:, None, :] - s[:, :, None] * a[None, :, :]
            tol = 32.0 * _EPS * (np.linalg.norm(xs, axis=1) + b_big + self._scale)
            feas = np.all(foot @ a.T - b <= tol[:, None, None], axis=2)
            cand_pts = [foot]
            # |x - foot| = |s|. Not restricted to s > 0 (the planes x lies beyond): x is
            # outside because the caller's ``x @ a.T - b`` had a positive entry, and this
            # product of a different block of rows may round that entry to <= 0; a face
            # dropped then leaves only farther edge or vertex points (in 2D: vertices).
            cand_d = [np.where(feas, np.abs(s), np.inf)]
            cand_kind = [np.full(k, _KIND_FACE)]
            cand_t = [np.zeros((k, d))]
            if len(ed):
                t = np.einsum("nej,ej->ne", xs[:, None, :] - e0[None], ed) / ed_len2
                interior = (t > 0.0) & (t < 1.0)
                p = e0[None] + np.clip(t, 0.0, 1.0)[:, :, None] * ed[None]
                cand_pts.append(p)
                dist_e = np.linalg.norm(xs[:, None, :] - p, axis=2)
                cand_d.append(np.where(interior, dist_e, np.inf))
                cand_kind.append(np.full(len(ed), _KIND_EDGE))
                cand_t.append(ed / np.sqrt(ed_len2)[:, None])
            vv = np.broadcast_to(self.vertices[None], (n_,) + self.vertices.shape)
            cand_pts.append(vv)
            cand_d.append(np.linalg.norm(xs[:, None, :] - vv, axis=2))
            cand_kind.append(np.full(len(self.vertices), _KIND_VERTEX))
            cand_t.append(np.zeros((len(self.vertices), d)))
            dd = np.concatenate(cand_d, axis=1)
            best = np.argmin(dd, axis=1)
            rows = np.arange(n_)
            r = dd[rows, best]
            kd = np.concatenate(cand_kind)[best]
            diff = xs - np.concatenate(cand_pts, axis=1)[rows, best]
            # Face regions: the face normal exactly. Near an edge/vertex, (x - p)/|x - p|,
            # except for points so close that this direction is rounding noise: there the
            # most violated face normal (an element of the normal cone) is used.
            iface = np.argmax(s, axis=1)
            flat = (kd == _KIND_FACE) | (r <= 1e-12 * self._scale)
            n_blk = diff / np.where(flat, 1.0, r)[:, None]
            n_blk[flat] = a[iface[flat]]
            face_hit = kd == _KIND_FACE
            n_blk[face_hit] = a[best[face_hit]]  # faces are the first k candidates
            kd[flat] = _KIND_FACE
            dist[lo:lo + n_] = r
            nrm[lo:lo + n_] = n_blk
            kind[lo:lo + n_] = kd
            tdir[lo:lo + n_] = np.concatenate(cand_t, axis=0)[best]
        return dist, nrm, kind, tdir

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        s = x @ self.A.T - self.b
        imax = np.argmax(s, axis=1) if s.size else np.zeros(0, dtype=np.intp)
        smax = s[np.arange(x.shape[0]), imax]
        gap = -smax
        n = self.A[imax].copy()
        out = smax > 0.0
        if np.any(out):
            dist, nrm, _, _ = self._outside(x[out])
            gap[out] = -dist
            n[out] = nrm
        return gap, n

    def _hessian(self, x: FloatArray) -> FloatArray:
        d = self.dim
        h = np.zeros((x.shape[0], d, d))
        s = x @ self.A.T - self.b
        out = np.max(s, axis=1) > 0.0 if s.size else np.zeros(0, dtype=bool)
        if np.any(out):
            dist, n, kind, t = self._outside(x[out])
            proj = np.eye(d) - n[:, :, None] * n[:, None, :]
            edge = kind == _KIND_EDGE
            proj[edge] -= t[edge, :, None] * t[edge, None, :]
            face = kind == _KIND_FACE  # flat: zero curvature (and dist may underflow)
            proj[face] = 0.0
            h[out] = -proj / np.where(face, 1.0, dist)[:, None, None]
        return h


@dataclass(frozen=True, eq=False)
class ConvexPolytopeCavity(ConvexPolytope):
    r"""Convex polygon (2D) or polyhedron (3D) cavity :math:`\{x : A x \le b\}`: the body lives *inside* it.

    The obstacle is the complement of :class:`ConvexPolytope`'s, so its signed distance is minus the
    polytope's: inside (free), :math:`\operatorname{gap} = \max_i (a_i\cdot x - b_i) \le 0` with the
    normal :math:`-a_i` of the nearest face (pointing into the cavity) and Hessian 0; outside
    (penetration), the exact Euclidean distance to the polytope with the normal back towards it and
    the Hessian :math:`+(I - n n^T)/\operatorname{dist}` near a vertex (its edge form in 3D). A
    rectangular groove with its cover, a die, a closed gland: one rigid master for several walls.

    Examples
    --------
    >>> box = ConvexPolytopeCavity.from_vertices([[0, 0], [2, 0], [2, 1], [0, 1]])
    >>> box.gap([[0.5, 0.6], [2.5, 0.5]]).round(6)
    array([-0.4,  0.5])
    >>> box.normal([[0.5, 0.6]]).round(6) + 0.0  # the top face's: back into the cavity
    array([[ 0., -1.]])
    """

    @property
    def name(self) -> str:
        return "convex-polygon-cavity" if self.dim == 2 else "convex-polyhedron-cavity"

    def describe(self) -> str:
        return super().describe().replace("convex ", "cavity (body inside) of the convex ", 1)

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        g, n = super()._gap_normal(x)
        return -g, -n

    def _hessian(self, x: FloatArray) -> FloatArray:
        return -super()._hessian(x)


# --------------------------------------------------------------------------- user obstacle


@dataclass(frozen=True, eq=False, init=False)
class UserObstacle(_ObstacleBase):
    r"""Obstacle from a user-supplied signed gap (negative in free space).

    Parameters
    ----------
    gap : callable
        ``gap(x)`` with ``x`` of shape ``(m, d)`` returning shape ``(m,)``; should be a
        signed distance (:math:`|\nabla \operatorname{gap}| = 1`), else ``project`` is
        only approximate and the normal is not unit.
    normal : callable, optional
        ``normal(x) -> (m, d)``, must equal :math:`-\nabla \operatorname{gap}`. Default:
        central differences of ``gap`` with step :math:`\varepsilon^{1/3} L`.
    hessian : callable, optional
        ``hessian(x) -> (m, d, d)``. Default: central differences of ``normal`` (step
        :math:`\varepsilon^{1/3} L`) when given, else second differences of ``gap``
        (step :math:`\varepsilon^{1/4} L`), symmetrized.
    dim : int, optional
        Space dimension; ``None`` accepts any.
    length_scale : float
        Geometric length :math:`L` (e.g. radius of curvature) that scales the
        finite-difference steps.
    label : str
        Text used by :meth:`describe`.

    Notes
    -----
    The normal is not renormalized, so it stays the exact gradient of ``gap`` and
    consistent with the Hessian. ``project(x) = x + gap(x) normal(x)`` is exact for planes
    and balls but only first-order accurate for general signed distances.

    Examples
    --------
    >>> ob = UserObstacle(gap=lambda x: x[:, 1] - 1.0, dim=2)   # obstacle y > 1
    >>> ob.normal([[0.0, 0.0]]).round(8)
    array([[-0., -1.]])
    """

    gap_fn: Callable[[FloatArray], Any]
    normal_fn: Callable[[FloatArray], Any] | None
    hessian_fn: Callable[[FloatArray], Any] | None
    user_dim: int | None
    length_scale: float
    label: str

    def __init__(self, gap: Callable[[FloatArray], Any],
                 normal: Callable[[FloatArray], Any] | None = None,
                 hessian: Callable[[FloatArray], Any] | None = None,
                 dim: int | None = None, length_scale: float = 1.0,
                 label: str = "user-defined gap") -> None:
        if not callable(gap):
            raise InputError(f"gap must be a callable gap(x) -> (m,), got {gap!r}")
        for nm, fn in (("normal", normal), ("hessian", hessian)):
            if fn is not None and not callable(fn):
                raise InputError(f"{nm} must be a callable or omitted, got {fn!r}")
        if dim is not None and (isinstance(dim, (bool, np.ndarray)) or not is_integer(dim) or dim not in (1, 2, 3)):
            raise InputError(f"dim must be 1, 2, 3 or omitted, got {dim!r}")
        object.__setattr__(self, "gap_fn", gap)
        object.__setattr__(self, "normal_fn", normal)
        object.__setattr__(self, "hessian_fn", hessian)
        object.__setattr__(self, "user_dim", None if dim is None else int(dim))
        object.__setattr__(self, "length_scale", _positive(length_scale, "length_scale"))
        object.__setattr__(self, "label", str(label))

    @property
    def dim(self) -> int | None:
        return self.user_dim

    @property
    def name(self) -> str:
        return "user"

    def describe(self) -> str:
        dim = f"{self.dim}D " if self.dim is not None else ""
        return f"user obstacle ({dim}{self.label}, length scale {self.length_scale:.6g})"

    # ---- checked calls to the user's functions
    def _call(self, fn: Callable[[FloatArray], Any], what: str, x: FloatArray,
              shape: tuple[int, ...]) -> FloatArray:
        out = np.asarray(fn(x), dtype=float)
        if out.shape != shape:
            raise InputError(
                f"user obstacle {what}(x) must return shape {shape} for x of shape "
                f"{x.shape}, got shape {out.shape}"
            )
        if not np.all(np.isfinite(out)):
            raise NonFiniteError(f"user obstacle {what}(x) returned NaN or infinity")
        return out

    def _g(self, x: FloatArray) -> FloatArray:
        return self._call(self.gap_fn, "gap", x, (x.shape[0],))

    def _n(self, x: FloatArray) -> FloatArray:
        if self.normal_fn is not None:
            return self._call(self.normal_fn, "normal", x, x.shape)
        m, d = x.shape
        h = _EPS ** (1 / 3) * self.length_scale
        steps = h * np.eye(d)
        xs = np.concatenate([x[:, None, :] + steps, x[:, None, :] - steps], axis=1)
        g = self._g(xs.reshape(-1, d)).reshape(m, 2 * d)
        return -(g[:, :d] - g[:, d:]) / (2 * h)

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        return self._g(x), self._n(x)

    def _hessian(self, x: FloatArray) -> FloatArray:
        m, d = x.shape
        if self.hessian_fn is not None:
            return self._call(self.hessian_fn, "hessian", x, (m, d, d))
        eye = np.eye(d)
        if self.normal_fn is not None:
            h = _EPS ** (1 / 3) * self.length_scale
            xs = np.concatenate([x[:, None, :] + h * eye, x[:, None, :] - h * eye], axis=1)
            n = self._n(xs.reshape(-1, d)).reshape(m, 2 * d, d)
            jac = (n[:, :d, :] - n[:, d:, :]) / (2 * h)  # jac[:, j, i] = d n_i / d x_j
            hess = -jac
        else:
            h = _EPS ** (1 / 4) * self.length_scale
            pairs = [(j, k) for j in range(d) for k in range(j, d)]
            offs = np.array([s1 * eye[j] + s2 * eye[k] for j, k in pairs
                             for s1, s2 in ((1, 1), (1, -1), (-1, 1), (-1, -1))]) * h
            g = self._g((x[:, None, :] + offs[None]).reshape(-1, d)).reshape(m, len(pairs), 4)
            vals = (g[:, :, 0] - g[:, :, 1] - g[:, :, 2] + g[:, :, 3]) / (4 * h * h)
            hess = np.empty((m, d, d))
            for p, (j, k) in enumerate(pairs):
                hess[:, j, k] = hess[:, k, j] = vals[:, p]
        return 0.5 * (hess + np.swapaxes(hess, 1, 2))


# --------------------------------------------------------------------------- slip on the surface


def surface_slip(obstacle: Any, x: ArrayLike, y_prev: ArrayLike, *,
                 jacobian: bool = True) -> tuple[FloatArray, FloatArray | None]:
    r"""Slip vector on the obstacle's surface from the surface point ``y_prev`` to the projection of ``x``.

    Parameters
    ----------
    obstacle : Obstacle
        Its ``surface_slip`` method is used when it has one (the built-in obstacles do:
        the geodesic for balls and cylinders, exact for planes); otherwise the default of
        :meth:`_ObstacleBase.surface_slip` (the chord projected onto the current tangent plane,
        first-order consistent), so user obstacles following only :class:`Obstacle` work.
    x : array_like (m, d)
        Current points.
    y_prev : array_like (m, d)
        Previous surface points (projections), in the same frame as ``x``.
    jacobian : bool
        Also return :math:`\partial \Delta s / \partial x`.

    Returns
    -------
    slip : ndarray (m, d)
        Tangent to the obstacle at the projection of ``x``, pointing along the motion from
        ``y_prev``; its length is the distance travelled on the surface.
    jac : ndarray (m, d, d) or None
    """
    method = getattr(obstacle, "surface_slip", None)
    if method is not None:
        return method(x, y_prev, jacobian=jacobian)
    _check_obstacle(obstacle, "surface_slip")
    pts = _point_rows(x, "surface_slip: x")
    prev = _point_rows(y_prev, "surface_slip: y_prev")
    if prev.shape != pts.shape:
        raise InputError(f"surface_slip: y_prev has shape {prev.shape}, x has {pts.shape}; give one previous "
                         "surface point per point of x.")
    return _chord_slip(obstacle, pts, prev, jacobian)


def _chord_slip(ob: Any, x: FloatArray, y_prev: FloatArray,
                jacobian: bool) -> tuple[FloatArray, FloatArray | None]:
    r"""Tangential projection of the chord, :math:`P(x - y_{prev})`, and its Jacobian in ``x``.

    :math:`\partial(Pb)/\partial x = P + (\nu\cdot b) H + \nu (H b)^T` with
    :math:`\partial\nu/\partial x = -H`.
    """
    _, nu = ob.evaluate(x)
    b = x - y_prev
    nb = np.einsum("ij,ij->i", nu, b)
    slip = b - nb[:, None] * nu
    if not jacobian:
        return slip, None
    d = x.shape[1]
    H = np.asarray(ob.gap_hessian(x), dtype=float)
    P = np.eye(d)[None] - nu[:, :, None] * nu[:, None, :]
    Hb = np.einsum("ijk,ik->ij", H, b)
    return slip, P + nb[:, None, None] * H + nu[:, :, None] * Hb[:, None, :]


def _arc_scale(slip: FloatArray, jac: FloatArray | None, radius: float, axial: FloatArray,
               b: FloatArray, r: FloatArray, cos: FloatArray) -> tuple[FloatArray, FloatArray | None]:
    r"""Scale the circumferential part of the chord slip :math:`Pb` to the arc, with the Jacobian.

    ``axial`` is the projector :math:`A = aa^T` onto a cylinder axis (0 for balls), ``r`` the
    radial distance of :math:`x` from the centre (axis) and ``cos`` :math:`= e\cdot e_{prev}`,
    the cosine of the angle :math:`\theta` between the radial directions of :math:`x` and of
    the previous surface point. The circumferential part :math:`c = Pb - Ab = -R(P - A)e_{prev}`
    has length :math:`R\sin\theta`; with :math:`\theta = \operatorname{atan2}(|c|/R, \cos\theta)`
    (any turn below :math:`\pi`) the arc is :math:`f(\theta)\,c`, :math:`f = \theta/\sin\theta`.
    From :math:`d\theta = \cos\theta\,d(\sin\theta) - \sin\theta\,d(\cos\theta)` and
    :math:`\partial\cos\theta/\partial x = -c^T/(Rr)`,

    .. math::

        \frac{\partial (f c)}{\partial x} = f\,C + \frac{q(\theta)}{R\,r}\,c\,c^T,
        \qquad C = \frac{\partial c}{\partial x} = \frac{\partial (Pb)}{\partial x} - A,
        \qquad q = \frac{f'(\theta)}{\sin\theta} = \frac{\sin\theta - \theta\cos\theta}{\sin^3\theta}

    (using :math:`c^T C = (R\cos\theta/r)\,c^T`, which holds because the previous point lies on
    the surface; series :math:`f = 1 + \theta^2/6`, :math:`q = 1/3 + 2\theta^2/15` below
    :math:`\theta = 10^{-3}`).
    """
    ab = b @ axial
    c = slip - ab
    s = np.linalg.norm(c, axis=1) / radius
    theta = np.arctan2(s, cos)
    small = theta < 1e-3
    th = np.where(small, 1.0, theta)
    sn = np.where(small, 1.0, s)
    f = np.where(small, 1.0 + theta**2 / 6.0, th / sn)  # |f c| = R theta
    out = ab + f[:, None] * c
    if jac is None:
        return out, None
    q = np.where(small, 1.0 / 3.0 + 2.0 * theta**2 / 15.0, (sn - th * np.cos(th)) / sn**3)
    C = jac - axial[None]
    coef = q / (radius * r)
    return out, axial[None] + f[:, None, None] * C + coef[:, None, None] * c[:, :, None] * c[:, None, :]


def transport_tangent(t: ArrayLike, n_from: ArrayLike, n_to: ArrayLike) -> FloatArray:
    r"""Rotate tangent vectors ``t`` (m, d) from the tangent planes of ``n_from`` to those of ``n_to``.

    The minimal rotation taking :math:`n_0` to :math:`n_1` (about :math:`n_0\times n_1` in
    3D, Rodrigues' formula :math:`R = I + [k]_\times + [k]_\times^2/(1 + n_0\cdot n_1)`,
    :math:`k = n_0\times n_1`; in 2D the rotation by the angle between them). It is the
    parallel transport along the geodesic for a plane, a sphere/circle and a cylinder
    (whose normals turn about the axis); for a general surface a first-order transport.
    Lengths are kept. Opposite normals (a turn by :math:`\pi`) leave ``t`` unchanged.
    """
    t, n0, n1 = (_point_rows(v, f"transport_tangent: {nm}") for v, nm in ((t, "t"), (n_from, "n_from"), (n_to, "n_to")))
    if not (t.shape == n0.shape == n1.shape):
        raise InputError(f"transport_tangent: t, n_from and n_to must have one shape (m, 2) or (m, 3); got "
                         f"{t.shape}, {n0.shape}, {n1.shape}.")
    cosv = np.einsum("ij,ij->i", n0, n1)
    ok = cosv > -1.0 + 1e-12
    den = np.where(ok, 1.0 + cosv, 1.0)
    if t.shape[1] == 2:
        sinv = n0[:, 0] * n1[:, 1] - n0[:, 1] * n1[:, 0]
        cs, sn = np.where(ok, cosv, 1.0), np.where(ok, sinv, 0.0)
        return np.stack([cs * t[:, 0] - sn * t[:, 1], sn * t[:, 0] + cs * t[:, 1]], axis=1)
    k = np.cross(n0, n1)
    kt = np.cross(k, t)
    out = t + kt + np.cross(k, kt) / den[:, None]
    return np.where(ok[:, None], out, t)


# --------------------------------------------------------------------------- moving obstacles


class _PlacedObstacle(_ObstacleBase):
    """An obstacle ``base`` placed elsewhere (:class:`Translated`, :class:`Moved`): same dimension and name."""

    base: Any

    @property
    def dim(self) -> int | None:
        return self.base.dim

    @property
    def name(self) -> str:
        return self.base.name


@dataclass(frozen=True, eq=False)
class Translated(_PlacedObstacle):
    r"""An obstacle moved rigidly by ``offset``: the occupied set is :math:`\{y + c : y \in O\}`.

    .. math::

        \operatorname{gap}(x) = \operatorname{gap}_O(x - c), \quad
        n(x) = n_O(x - c), \quad H(x) = H_O(x - c), \quad
        \bar x = \bar x_O(x - c) + c .

    Used by finite-deformation load stepping (:func:`alcontact.contact.solve`)
    for an obstacle moving along a prescribed path; build it with :func:`translate`.

    Examples
    --------
    >>> ob = translate(Circle(center=[0.0, 1.0], radius=0.5), [2.0, 0.0])
    >>> ob.gap([[2.0, 0.0]])
    array([-0.5])
    """

    base: Any
    offset: FloatArray

    def __post_init__(self) -> None:
        _check_obstacle(self.base, "Translated", "base")
        dims = (self.base.dim,) if self.base.dim is not None else (2, 3)
        object.__setattr__(self, "offset", _readonly(_vector(self.offset, "offset", dims)))

    def describe(self) -> str:
        return f"{self.base.describe()}, translated by {_fmt(self.offset)}"

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        return self.base.evaluate(x - self.offset)

    def project(self, x: ArrayLike) -> FloatArray:
        pts = _points(x, self.dim)
        return self.base.project(pts - self.offset) + self.offset

    def _hessian(self, x: FloatArray) -> FloatArray:
        return self.base.gap_hessian(x - self.offset)

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        lo, hi = _base_extent(self.base, d)
        return lo + self.offset, hi + self.offset

    def surface_slip(self, x: ArrayLike, y_prev: ArrayLike, *,
                     jacobian: bool = True) -> tuple[FloatArray, FloatArray | None]:
        """:func:`surface_slip` of the base obstacle in its own frame (a translation keeps tangents)."""
        pts = _points(x, self.dim)
        yp = _previous(y_prev, pts)
        return surface_slip(self.base, pts - self.offset, yp - self.offset, jacobian=jacobian)


def _base_extent(base: Any, d: int) -> tuple[FloatArray, FloatArray]:
    """Bounding box of the base of a placed obstacle; unbounded for a user object without one."""
    if isinstance(base, _ObstacleBase):
        return base.bounding_box(d)
    return np.full(d, -np.inf), np.full(d, np.inf)


def _check_obstacle(obstacle: Any, where: str, name: str = "obstacle") -> None:
    """:class:`InputError` unless ``obstacle`` is an obstacle (``evaluate``, ``dim``, ``describe``)."""
    if not (callable(getattr(obstacle, "evaluate", None)) and hasattr(obstacle, "dim")
            and callable(getattr(obstacle, "describe", None))):
        raise InputError(f"{where}: {name} = {show(obstacle)}: expected an obstacle, e.g. "
                         "alcontact.contact.obstacles.make('circle', center=..., radius=...).")


def _previous(y_prev: Any, pts: FloatArray) -> FloatArray:
    """The previous surface points of ``surface_slip``: one finite row per point of ``pts``."""
    try:
        prev = np.asarray(y_prev, dtype=float)
    except (TypeError, ValueError, OverflowError):
        prev = None
    if prev is None or prev.shape != pts.shape or not np.all(np.isfinite(prev)):
        raise InputError(f"y_prev = {show(y_prev)}: expected a finite array of shape {pts.shape} (one previous "
                         "surface point per point of x).")
    return prev


def _point_rows(value: Any, what: str) -> FloatArray:
    """A finite ``(m, 2)`` or ``(m, 3)`` float array; :class:`InputError` naming ``what`` otherwise."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        arr = None
    if arr is None or arr.ndim != 2 or arr.shape[1] not in (2, 3) or not np.all(np.isfinite(arr)):
        raise InputError(f"{what} = {show(value)}: expected a finite (m, 2) or (m, 3) array.")
    return arr


def translate(obstacle: Obstacle, offset: ArrayLike) -> Obstacle:
    """``obstacle`` moved rigidly by ``offset`` (offsets of a :class:`Translated` add up)."""
    _check_obstacle(obstacle, "translate")
    if isinstance(obstacle, Translated):
        return Translated(obstacle.base, obstacle.offset + _vector(offset, "offset", (obstacle.offset.size,)))
    return Translated(obstacle, offset)


@dataclass(frozen=True, eq=False, init=False)
class RigidMotion:
    r"""A rigid placement :math:`x = Q\,y + b` of an obstacle (rotation :math:`Q`, then translation).

    ``obstacle_path(t)`` of the finite-deformation solvers may return one instead of a
    translation vector: the obstacle is then placed by :func:`move`. Build it with
    :meth:`about` (rotation by an angle about a centre, plus a translation).

    Parameters
    ----------
    rotation : array_like (d, d)
        Proper orthogonal matrix :math:`Q` (checked to 1e-10).
    offset : array_like (d,)
        Translation :math:`b`.
    """

    rotation: FloatArray
    offset: FloatArray

    def __init__(self, rotation: ArrayLike, offset: ArrayLike) -> None:
        b = _vector(offset, "offset")
        try:
            q = np.asarray(rotation, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"rotation must be a {b.size}x{b.size} matrix of numbers; got {show(rotation)}") from None
        d = b.size
        if q.shape != (d, d) or not np.all(np.isfinite(q)):
            raise InputError(f"rotation must be a finite {d}x{d} matrix like offset has {d} components; "
                             f"got shape {q.shape}")
        if np.max(np.abs(q.T @ q - np.eye(d))) > 1e-10 or np.linalg.det(q) <= 0:
            raise InputError("rotation must be a proper orthogonal matrix (Q^T Q = I, det Q = 1); "
                             "build it with RigidMotion.about(center, angle, axis)")
        object.__setattr__(self, "rotation", _readonly(q))
        object.__setattr__(self, "offset", _readonly(b))

    @classmethod
    def about(cls, center: ArrayLike, angle: float, axis: ArrayLike | None = None,
              offset: ArrayLike | None = None) -> RigidMotion:
        r"""Rotation by ``angle`` (radians, counter-clockwise about ``axis``) about ``center``, then ``offset``.

        :math:`x = Q(y - p) + p + c`; in 2D no ``axis``, in 3D a unit ``axis`` (Rodrigues'
        formula :math:`Q = I + \sin\varphi\,[a]_\times + (1 - \cos\varphi)[a]_\times^2`).
        """
        p = _vector(center, "center")
        if not (isinstance(angle, (int, float, np.floating, np.integer)) and math.isfinite(float(angle))):
            raise InputError(f"angle = {angle!r} must be a finite number of radians")
        phi = float(angle)
        if p.size == 2:
            if axis is not None:
                raise InputError("axis is for 3D rotations; omit it in 2D (rotation in the plane)")
            q = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
        else:
            if axis is None:
                raise InputError("a 3D rotation needs axis=(ax, ay, az)")
            a = _unit(axis, "axis", (3,))
            k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
            q = np.eye(3) + math.sin(phi) * k + (1.0 - math.cos(phi)) * (k @ k)
        c = np.zeros(p.size) if offset is None else _vector(offset, "offset", (p.size,))
        return cls(q, p - q @ p + c)


@dataclass(frozen=True, eq=False)
class Moved(_PlacedObstacle):
    r"""An obstacle placed rigidly by a :class:`RigidMotion` :math:`x = Q y + b`.

    .. math::

        \operatorname{gap}(x) = \operatorname{gap}_O(y), \quad n(x) = Q\,n_O(y), \quad
        H(x) = Q H_O(y) Q^T, \quad \bar x = Q\,\bar y_O(y) + b, \qquad y = Q^T(x - b).

    Build it with :func:`move`; :func:`frame` returns its placement.
    """

    base: Any
    motion: RigidMotion

    def __post_init__(self) -> None:
        _check_obstacle(self.base, "Moved", "base")
        if not isinstance(self.motion, RigidMotion):
            raise InputError(f"Moved: motion = {show(self.motion)}: expected a RigidMotion (RigidMotion(rotation, "
                             "offset) or RigidMotion.about(...)).")
        if self.base.dim is not None and self.motion.offset.size != self.base.dim:
            raise InputError(f"the rigid motion is {self.motion.offset.size}D but the obstacle "
                             f"{self.base.describe()} is {self.base.dim}D")

    def describe(self) -> str:
        return (f"{self.base.describe()}, rotated by {_fmt(self.motion.rotation.ravel())} "
                f"and translated by {_fmt(self.motion.offset)}")

    def _local(self, x: FloatArray) -> FloatArray:
        return (x - self.motion.offset) @ self.motion.rotation

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        g, n = self.base.evaluate(self._local(x))
        return g, n @ self.motion.rotation.T

    def project(self, x: ArrayLike) -> FloatArray:
        pts = _points(x, self.dim)
        return self.base.project(self._local(pts)) @ self.motion.rotation.T + self.motion.offset

    def _hessian(self, x: FloatArray) -> FloatArray:
        q = self.motion.rotation
        return np.einsum("ij,mjk,lk->mil", q, self.base.gap_hessian(self._local(x)), q)

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        # box of the rotated box: half-widths |Q| h (0 * inf = 0: an axis the rotation does not mix in)
        lo, hi = _base_extent(self.base, d)
        finite = np.isfinite(lo) & np.isfinite(hi)
        lo, hi = np.where(finite, lo, 0.0), np.where(finite, hi, 0.0)
        mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
        q = np.abs(self.motion.rotation)
        h = q @ half + np.where(q[:, ~finite].any(axis=1), np.inf, 0.0)
        c = self.motion.rotation @ mid + self.motion.offset
        return c - h, c + h

    def surface_slip(self, x: ArrayLike, y_prev: ArrayLike, *,
                     jacobian: bool = True) -> tuple[FloatArray, FloatArray | None]:
        """:func:`surface_slip` of the base obstacle in its own frame, rotated back.

        Slip :math:`Q\\,\\Delta s_O(y; y_{prev})`, Jacobian :math:`Q J_O Q^T`.
        """
        pts = _points(x, self.dim)
        yp = _previous(y_prev, pts)
        q = self.motion.rotation
        slip, jac = surface_slip(self.base, self._local(pts), self._local(yp), jacobian=jacobian)
        if jac is not None:
            jac = np.einsum("ij,mjk,lk->mil", q, jac, q)
        return slip @ q.T, jac


def move(obstacle: Obstacle, motion: RigidMotion) -> Obstacle:
    """``obstacle`` placed by the rigid ``motion``.

    A :class:`Moved` obstacle; a translation-only motion gives :func:`translate`.
    """
    if not isinstance(motion, RigidMotion):
        raise InputError(f"motion must be an obstacles.RigidMotion, got {type(motion).__name__}")
    if np.array_equal(motion.rotation, np.eye(motion.offset.size)):
        return translate(obstacle, motion.offset)
    return Moved(obstacle, motion)


def frame(obstacle: Any, dim: int | None = None) -> tuple[FloatArray, FloatArray]:
    r"""Placement :math:`(Q, b)` of an obstacle: a point :math:`y` of its own frame is at :math:`Qy + b`.

    :class:`Moved` and :class:`Translated` compose their motion with their base's frame;
    any other obstacle (user obstacles included) is at rest in its own frame,
    :math:`(I, 0)`; ``dim`` is used when the obstacle has no dimension of its own.
    """
    _check_obstacle(obstacle, "frame")
    if dim is not None and not (is_integer(dim) and dim in (2, 3)):
        raise InputError(f"frame: dim = {show(dim)}: expected 2, 3 or None.")
    if isinstance(obstacle, (Moved, Translated)):
        qb, bb = frame(obstacle.base, dim)
        if isinstance(obstacle, Moved):
            q, b = np.asarray(obstacle.motion.rotation), np.asarray(obstacle.motion.offset)
        else:
            q, b = np.eye(obstacle.offset.size), np.asarray(obstacle.offset)
        return q @ qb, q @ bb + b
    d = obstacle.dim if obstacle.dim is not None else dim
    if d is None:
        raise InputError(f"obstacle {obstacle.describe()} has no dimension; pass dim= to frame()")
    return np.eye(d), np.zeros(d)


# --------------------------------------------------------------------------- registry


@dataclass(frozen=True)
class _Entry:
    factory: Callable[..., Obstacle]
    doc: str


_REGISTRY: dict[str, _Entry] = {}


def register(name: str, factory: Callable[..., Obstacle], doc: str = "",
             *, replace: bool = False) -> None:
    """Register an obstacle factory under ``name`` (keyword parameters only).

    ``doc`` is the one-line description shown by ``alcontact list``. Registering an
    existing name raises :class:`InputError` unless ``replace=True``.
    """
    if not isinstance(name, str) or not name:
        raise InputError(f"obstacle name must be a non-empty string, got {name!r}")
    if not callable(factory):
        raise InputError(f"factory for obstacle {name!r} must be callable, got {factory!r}")
    if name in _REGISTRY and not replace:
        raise InputError(f"obstacle {name!r} is already registered; pass replace=True to override")
    text = doc.strip() or inspect.getdoc(factory) or ""
    line = text.splitlines()[0] if text else ""
    _REGISTRY[name] = _Entry(factory, line)


def available() -> list[str]:
    """Sorted names of the registered obstacles."""
    return sorted(_REGISTRY)


def docs() -> dict[str, str]:
    """``{name: one-line doc}`` for every registered obstacle, sorted by name."""
    return {k: _REGISTRY[k].doc for k in sorted(_REGISTRY)}


def signature(name: str) -> inspect.Signature:
    """The signature of the factory registered as ``name``: the parameters :func:`make` accepts.

    Parameters without a default are required (the problem-file loader checks an
    ``[obstacle]`` table against it before building).

    Raises
    ------
    UnknownNameError
        ``name`` is not registered (the message lists the known names).

    Examples
    --------
    >>> list(signature("half-space").parameters)
    ['point', 'normal']
    """
    try:
        return inspect.signature(_REGISTRY[name].factory)
    except (KeyError, TypeError):
        raise UnknownNameError("obstacle", name, list(_REGISTRY)) from None


def make(name: str, **params: Any) -> Obstacle:
    """Build the obstacle registered as ``name`` from keyword parameters.

    Raises
    ------
    UnknownNameError
        ``name`` is not registered (the message lists the known names).
    InputError
        A parameter is missing, unexpected or invalid.

    Examples
    --------
    >>> make("half-space", point=[0, 0], normal=[0, 1]).gap([[0.0, -0.5]])
    array([0.5])
    """
    try:
        entry = _REGISTRY[name]
    except (KeyError, TypeError):
        raise UnknownNameError("obstacle", name, list(_REGISTRY)) from None
    sig = inspect.signature(entry.factory)
    try:
        sig.bind(**params)
    except TypeError as exc:
        accepted = ", ".join(p for p in sig.parameters)
        raise InputError(f"obstacle {name!r}: {exc}; accepted parameters: {accepted}") from None
    return entry.factory(**params)


def _polytope_factory(d: int, cls: type[ConvexPolytope] = ConvexPolytope) -> Callable[..., ConvexPolytope]:
    def factory(vertices: ArrayLike | None = None, A: ArrayLike | None = None,
                b: ArrayLike | None = None) -> ConvexPolytope:
        kind = ("convex-polygon" if d == 2 else "convex-polyhedron") + ("-cavity" if cls is not ConvexPolytope else "")
        if (vertices is None) == (A is None and b is None) or (A is None) != (b is None):
            raise InputError(f"{kind} needs either vertices or both A and b")
        if vertices is not None:
            v = np.asarray(vertices, dtype=float)
            if v.ndim != 2 or v.shape[1] != d:
                raise InputError(
                    f"vertices of a {kind} must have shape (n, {d}), got shape {v.shape}")
            return cls.from_vertices(v)
        if np.ndim(A) != 2 or np.shape(A)[1] != d:
            raise InputError(f"A of a {kind} must have shape (k, {d}), got shape {np.shape(A)}")
        return cls(A, b)

    return factory


def _ball_factory(cls: type[_Ball], inside: bool) -> Callable[..., _Ball]:
    def factory(center: ArrayLike, radius: float) -> _Ball:
        return cls(center=center, radius=radius, inside=inside)

    return factory


def _cylinder_factory(inside: bool) -> Callable[..., Cylinder]:
    def factory(center: ArrayLike, axis: ArrayLike, radius: float) -> Cylinder:
        return Cylinder(center=center, axis=axis, radius=radius, inside=inside)

    return factory


def _register_builtin() -> None:
    entries: Mapping[str, tuple[Callable[..., Obstacle], str]] = {
        "half-space": (
            HalfSpace, "plane obstacle {(x - point).normal < 0} (2D/3D): point, normal"),
        "sphere": (
            _ball_factory(Sphere, False), "solid ball indenter, body outside (3D): center, radius"),
        "sphere-cavity": (
            _ball_factory(Sphere, True), "spherical cavity, body inside (3D): center, radius"),
        "circle": (
            _ball_factory(Circle, False), "solid disc indenter, body outside (2D): center, radius"),
        "circle-cavity": (
            _ball_factory(Circle, True), "circular cavity, body inside (2D): center, radius"),
        "cylinder": (
            _cylinder_factory(False), "infinite cylinder indenter (3D): center, axis, radius"),
        "cylinder-cavity": (
            _cylinder_factory(True),
            "infinite cylindrical cavity, body inside (3D): center, axis, radius"),
        "convex-polygon": (
            _polytope_factory(2),
            "convex polygon obstacle (2D): ccw vertices, or A, b with A x <= b"),
        "convex-polyhedron": (
            _polytope_factory(3),
            "convex polyhedron obstacle (3D): vertices (convex hull), or A, b with A x <= b"),
        "convex-polygon-cavity": (
            _polytope_factory(2, ConvexPolytopeCavity),
            "convex polygonal cavity, body inside (2D; e.g. a groove with its cover): ccw vertices, or A, b"),
        "convex-polyhedron-cavity": (
            _polytope_factory(3, ConvexPolytopeCavity),
            "convex polyhedral cavity, body inside (3D): vertices (convex hull), or A, b with A x <= b"),
        "user": (
            UserObstacle,
            "user signed gap (> 0 inside the obstacle): gap, optional normal, hessian, dim, "
            "length_scale"),
    }
    for nm, (factory, doc) in entries.items():
        register(nm, factory, doc=doc)


_register_builtin()
