"""The contact problem as data: body, supports, loads, obstacle, contact boundary.

A :class:`ContactProblem` holds no solver state; :func:`alcontact.contact.solve`
turns it into a discrete problem and runs one of the registered algorithms.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import InputError, UnknownNameError

__all__ = ["Support", "Traction", "Pressure", "BodyForce", "ContactProblem", "merge_supports", "KINEMATICS"]

#: Contact kinematics a problem can ask for (see :class:`ContactProblem`)
KINEMATICS = {
    "small": "small deformation: linearized gap (6.15) at the reference configuration, condensed solve",
    "finite": "finite deformation: gap at x = X + u, load steps, full-space Newton (needs a nonlinear body)",
}


def _numbers(value: Any) -> bool:
    """A finite real number or a non-empty 1-D list of them (not a bool, not a string)."""
    if isinstance(value, (bool, str, bytes)) or value is None:
        return False
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return False
    return a.ndim <= 1 and a.size >= 1 and bool(np.all(np.isfinite(a))) and a.dtype != object


def _is_real(value: Any) -> bool:
    return _numbers(value) and np.ndim(value) == 0


def _bad(kind: str, field_: str, value: Any, want: str) -> InputError:
    try:  # not alcontact._options.show: that module imports this one
        text = repr(value) if not (isinstance(value, int) and abs(value) > 10**40) else "<a huge integer>"
    except (RecursionError, ValueError):
        text = f"<{type(value).__name__}>"
    text = text if len(text) <= 60 else text[:57] + "..."
    return InputError(f"{kind}: {field_} = {text}: expected {want}, got {type(value).__name__}.")


def _check_boundary(kind: str, boundary: Any) -> None:
    if not isinstance(boundary, str):
        raise _bad(kind, "boundary", boundary, "the name of a boundary of the mesh (a string), e.g. 'top'")


@dataclass(frozen=True)
class Support:
    """Dirichlet condition ``u_c = value`` on a named boundary.

    Parameters
    ----------
    boundary : str
        Boundary name of the mesh.
    components : sequence of int, optional
        Displacement components (0 = x, 1 = y, 2 = z); ``None`` = all.
    value : float or callable
        Prescribed value, or ``x -> (dim, m)`` array.
    """

    boundary: str
    components: tuple[int, ...] | None = None
    value: float | Callable[..., Any] = 0.0

    def __post_init__(self) -> None:
        _check_boundary("Support", self.boundary)
        comps = self.components
        if comps is not None and (isinstance(comps, (str, bytes, bool)) or not np.iterable(comps) or not all(
                isinstance(c, (int, np.integer)) and not isinstance(c, bool) and 0 <= c <= 2 for c in comps)):
            raise _bad("Support", "components", comps, "None (all) or a list of components 0, 1, 2, e.g. [0]")
        if not (callable(self.value) or _numbers(self.value)):
            raise _bad("Support", "value", self.value, "a finite number, a list of them (one per component) or "
                                                      "a callable x -> (dim, m) array")


@dataclass(frozen=True)
class Traction:
    """Surface traction vector (force per unit area) on a named boundary."""

    boundary: str
    vector: tuple[float, ...] | Callable[..., Any]

    def __post_init__(self) -> None:
        _check_boundary("Traction", self.boundary)
        if not (callable(self.vector) or (_numbers(self.vector) and np.ndim(self.vector) == 1)):
            raise _bad("Traction", "vector", self.vector, "a list of finite numbers (one per direction) or a "
                                                          "callable x -> (dim, m) array")


@dataclass(frozen=True)
class Pressure:
    """Normal pressure on a named boundary; positive pushes into the body."""

    boundary: str
    value: float

    def __post_init__(self) -> None:
        _check_boundary("Pressure", self.boundary)
        if not (callable(self.value) or _is_real(self.value)):
            raise _bad("Pressure", "value", self.value, "a finite number (positive pushes into the body) or a "
                                                        "callable x -> (m,) array")


@dataclass(frozen=True)
class BodyForce:
    """Body force density (force per unit volume)."""

    vector: tuple[float, ...] | Callable[..., Any]

    def __post_init__(self) -> None:
        if not (callable(self.vector) or (_numbers(self.vector) and np.ndim(self.vector) == 1)):
            raise _bad("BodyForce", "vector", self.vector, "a list of finite numbers (one per direction) or a "
                                                           "callable x -> (dim, m) array")


@dataclass(frozen=True)
class ContactProblem:
    """Elastic body against a rigid obstacle (small deformation, ch. 6.2, or finite deformation).

    Parameters
    ----------
    model : alcontact.fem.LinearElasticity
        Discretized body.
    obstacle : Obstacle
        Rigid obstacle (see :mod:`alcontact.contact.obstacles`).
    contact_boundary : str
        Name of the candidate contact boundary :math:`\\Gamma`.
    supports : sequence of Support
    loads : sequence of Traction, Pressure or BodyForce
    friction : float
        Coulomb coefficient (0 = frictionless).
    name : str
        Label used in reports.
    reference : object, optional
        Analytical reference (e.g. :class:`alcontact.problems.hertz.HertzReference`).
    kinematics : {"small", "finite"}
        ``"small"`` (default): linearized gap (6.15). ``"finite"``: gap at the current
        position, solved in load steps by :func:`alcontact.contact.solve_finite`; needs a
        geometrically nonlinear body (a hyperelastic one), a linear body is refused.
    """

    model: Any
    obstacle: Any
    contact_boundary: str
    supports: Sequence[Support] = ()
    loads: Sequence[Any] = ()
    friction: float = 0.0
    name: str = "contact"
    reference: Any = None
    meta: dict = field(default_factory=dict)
    kinematics: str = "small"

    def __post_init__(self) -> None:
        self._check_types()
        if self.kinematics not in KINEMATICS:
            raise UnknownNameError("kinematics", self.kinematics, list(KINEMATICS))
        if self.kinematics == "finite" and getattr(self.model, "linear", False):
            raise InputError(
                f"kinematics='finite' needs a geometrically nonlinear body; got {type(self.model).__name__} "
                "(linear, small strains: a finite-deformation gap with it is not finite deformation). "
                "Use a hyperelastic body (alcontact.fem.hyperelastic) or kinematics='small'."
            )
        if not np.isfinite(self.friction) or self.friction < 0:
            raise InputError(
                f"friction coefficient must be >= 0; got {self.friction!r}. Use 0 for frictionless contact."
            )
        self.model.facets(self.contact_boundary)  # MeshError naming the known boundaries
        for s in self.supports:
            self.model.facets(s.boundary)
        for ld in self.loads:
            if hasattr(ld, "boundary"):
                self.model.facets(ld.boundary)
        self.obstacle.check_dim(self.model.dim)
        self.dirichlet()  # InputError on two supports prescribing different values to one DOF

    def _check_types(self) -> None:
        """Wrong types of the fields: an :class:`InputError` naming the field and the fix (not an AttributeError)."""
        kind = "ContactProblem"
        if not (hasattr(self.model, "facets") and hasattr(self.model, "dim") and hasattr(self.model, "ndofs")):
            raise _bad(kind, "model", self.model, "a discretized body: alcontact.fem.LinearElasticity(mesh, "
                                                  "material) or a hyperelastic alcontact.fem.Body")
        if not (hasattr(self.obstacle, "evaluate") and hasattr(self.obstacle, "check_dim")):
            raise _bad(kind, "obstacle", self.obstacle, "a rigid obstacle, e.g. alcontact.contact.obstacles."
                                                        "make('half-space', point=..., normal=...)")
        if not isinstance(self.contact_boundary, str):
            raise _bad(kind, "contact_boundary", self.contact_boundary, "the name of a boundary of the mesh")
        for name, items, types, example in (("supports", self.supports, (Support,), "[Support('bottom')]"),
                                            ("loads", self.loads, (Traction, Pressure, BodyForce),
                                             "[Pressure('top', 1.0)]")):
            if isinstance(items, types):
                raise InputError(f"{kind}: {name} = {type(items).__name__}(...): expected a list; wrap the single "
                                 f"item in a list, e.g. {name}={example}.")
            if isinstance(items, (str, bytes, dict, np.ndarray)) or not np.iterable(items):
                raise _bad(kind, name, items, f"a list of {' / '.join(t.__name__ for t in types)}, e.g. {example}")
            for i, item in enumerate(items):
                if not isinstance(item, types):
                    raise _bad(kind, f"{name}[{i}]", item, f"a {' / '.join(t.__name__ for t in types)}")
        if not _is_real(self.friction) or abs(float(self.friction)) > 1e100:
            raise _bad(kind, "friction", self.friction, "a finite number in [0, 1e100] (0 = frictionless)")
        if not isinstance(self.name, str):
            raise _bad(kind, "name", self.name, "a string")
        if not isinstance(self.kinematics, str):
            raise _bad(kind, "kinematics", self.kinematics, f"one of {', '.join(map(repr, KINEMATICS))}")
        if not isinstance(self.meta, dict):
            raise _bad(kind, "meta", self.meta, "a dict")

    # ------------------------------------------------------------ assembly
    def dirichlet(self) -> tuple[np.ndarray, np.ndarray]:
        """Fixed DOFs and their values.

        A DOF prescribed by several supports must get the same value from each
        (to a relative ``1e-9``); the first value is kept.

        Raises
        ------
        alcontact.errors.InputError
            Two supports prescribe different values to the same component of a
            node; the message names both boundaries, the component, the node and
            the values.
        """
        return merge_supports(self.model, self.supports)

    def load_vector(self) -> np.ndarray:
        """Assembled external load vector."""
        f = np.zeros(self.model.ndofs)
        for ld in self.loads:
            if isinstance(ld, Traction):
                f += self.model.traction_load(ld.boundary, ld.vector)
            elif isinstance(ld, Pressure):
                f += self.model.pressure_load(ld.boundary, ld.value)
            elif isinstance(ld, BodyForce):
                f += self.model.body_load(ld.vector)
            else:
                raise InputError(f"unknown load {ld!r}; use Traction, Pressure or BodyForce.")
        return f


_AXES = "xyz"


def merge_supports(model, supports: Sequence[Support], labels: Sequence[str] | None = None,
                   *, scales: Sequence[float] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Fixed DOFs and values of ``supports``; an error if two of them disagree on a DOF.

    Parameters
    ----------
    model : alcontact.fem.LinearElasticity
    supports : sequence of Support
    labels : sequence of str, optional
        Names of the supports in messages (default ``support on 'BOUNDARY'``),
        e.g. the key paths of a problem file (``support[2]``).
    scales : sequence of float, optional
        Amplitude of each support (ramped supports at one step time); default 1.

    Returns
    -------
    dofs : ndarray of int
        Sorted fixed DOFs.
    values : ndarray
        Their prescribed values.

    Raises
    ------
    alcontact.errors.InputError
        Two supports prescribe different values (beyond a relative ``1e-9`` of
        the largest prescribed value) to the same component of a node.
    """
    if not supports:
        return _with_axis(model, np.empty(0, dtype=np.int64), np.empty(0))
    labels = list(labels) if labels is not None else [f"support on {s.boundary!r}" for s in supports]
    scales = list(scales) if scales is not None else [1.0] * len(supports)
    dofs_l, vals_l, own_l = [], [], []
    for k, s in enumerate(supports):
        d, v = model.dirichlet(s.boundary, None if s.components is None else list(s.components), s.value)
        dofs_l.append(d)
        vals_l.append(scales[k] * v)
        own_l.append(np.full(d.size, k))
    dofs = np.concatenate(dofs_l)
    vals = np.concatenate(vals_l)
    owner = np.concatenate(own_l)
    order = np.argsort(dofs, kind="stable")  # first prescription first among equal DOFs
    dofs, vals, owner = dofs[order], vals[order], owner[order]
    uniq, first = np.unique(dofs, return_index=True)
    ref = vals[first][np.searchsorted(uniq, dofs)]
    scale = max(float(np.max(np.abs(vals), initial=0.0)), 1e-300)
    bad = np.flatnonzero(np.abs(vals - ref) > 1e-9 * scale)
    if bad.size:
        j = int(bad[0])
        i = int(first[np.searchsorted(uniq, dofs[j])])
        dof = int(dofs[j])
        pts, dmap = model.all_node_dofs()
        node, comp = np.argwhere(dmap == dof)[0]
        a, b = supports[owner[i]], supports[owner[j]]
        n_bad = np.unique(dofs[bad]).size
        raise InputError(
            f"{labels[owner[i]]} and {labels[owner[j]]} prescribe different values to component {comp} "
            f"({_AXES[comp]}) at node {np.round(pts[node], 6).tolist()}: {vals[i]:g} on {a.boundary!r} and "
            f"{vals[j]:g} on {b.boundary!r} ({n_bad} DOF(s) in conflict). Make the values agree, or restrict "
            "one support to other components (components = [...]) so that the boundaries do not overlap."
        )
    return _with_axis(model, uniq, vals[first])


def _with_axis(model, dofs: np.ndarray, vals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``dofs, vals`` plus the body's own zero DOFs: :math:`u_r = 0` on the axis of a body of revolution
    (``model.axis_dofs``, empty for a Cartesian body; a support prescribing another value there is refused
    by ``model.dirichlet``)."""
    axis = np.setdiff1d(np.asarray(model.axis_dofs, dtype=np.int64), dofs)
    if axis.size == 0:
        return dofs, vals
    out = np.concatenate([dofs, axis])
    order = np.argsort(out, kind="stable")
    return out[order], np.concatenate([vals, np.zeros(axis.size)])[order]
