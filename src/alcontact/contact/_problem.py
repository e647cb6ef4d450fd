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


@dataclass(frozen=True)
class Traction:
    """Surface traction vector (force per unit area) on a named boundary."""

    boundary: str
    vector: tuple[float, ...] | Callable[..., Any]


@dataclass(frozen=True)
class Pressure:
    """Normal pressure on a named boundary; positive pushes into the body."""

    boundary: str
    value: float


@dataclass(frozen=True)
class BodyForce:
    """Body force density (force per unit volume)."""

    vector: tuple[float, ...] | Callable[..., Any]


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
        return np.empty(0, dtype=np.int64), np.empty(0)
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
    return uniq, vals[first]
