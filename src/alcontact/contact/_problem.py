"""The contact problem as data: body, supports, loads, obstacle, contact boundary.

A :class:`ContactProblem` holds no solver state; :func:`alcontact.contact.solve`
turns it into a discrete problem and runs one of the registered algorithms.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import InputError, UnknownNameError

__all__ = ["Support", "Traction", "Pressure", "BodyForce", "ContactProblem", "KINEMATICS"]

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

    # ------------------------------------------------------------ assembly
    def dirichlet(self) -> tuple[np.ndarray, np.ndarray]:
        """Fixed DOFs and their values (the last prescription of a DOF wins)."""
        pairs = [
            self.model.dirichlet(s.boundary, None if s.components is None else list(s.components), s.value)
            for s in self.supports
        ]
        if not pairs:
            return np.empty(0, dtype=np.int64), np.empty(0)
        dofs = np.concatenate([p[0] for p in pairs])
        vals = np.concatenate([p[1] for p in pairs])
        uniq, idx = np.unique(dofs[::-1], return_index=True)
        return uniq, vals[::-1][idx]

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
