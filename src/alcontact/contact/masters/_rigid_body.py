r"""A rigid body with a reference point: a master whose motion is prescribed or solved for.

A :class:`RigidBody` is a rigid shape (any rigid master: an analytic obstacle of
:mod:`alcontact.contact.obstacles` or a meshed surface) attached to a reference point
:math:`X_0`. Its position is given by :math:`d_r` degrees of freedom, the translation
:math:`c` of the reference point and the rotation :math:`\theta` about it (small
deformation: the rotation is linearized, like the strains of the bodies),

.. math::

    q = (c, \theta), \qquad x(X) = X + c + \theta \times (X - X_0), \qquad
    d_r = 3 \text{ in 2D } (c_x, c_y, \theta_z), \quad 6 \text{ in 3D } (c, \theta_x, \theta_y, \theta_z).

Each component of :math:`q` is either prescribed (a :class:`~alcontact.contact.Support` on
the body: ``Support("punch", components=[1], value=-0.01)``, components ``0..d-1`` the
translation, ``d..`` the rotation) or an unknown solved with the contact problem, the body
then loaded by a force and a moment on its reference point
(:class:`~alcontact.contact.RigidLoad`). The rigid body is one more block of the bodies'
:class:`~alcontact.fem.MultiBody`: :math:`d_r` DOFs with no stiffness, whose equilibrium
equations are those of the rigid body,

.. math::

    F + \sum_i F^c_i = 0, \qquad M + \sum_i (x_i - X_0) \times F^c_i = 0,

with :math:`F, M` the applied force and moment and :math:`F^c_i` the contact forces on it.
The gap of a slave point against the moving shape, linearized at the reference
configuration (6.15), couples the slave point's DOFs and :math:`q`
(:mod:`alcontact.contact.kinematics._rigid_body`). Prescribed components carry a reaction
(the force and moment the drive applies), reported per step.

The body satisfies the :class:`~alcontact.contact.Master` protocol (evaluated on the shape
at its reference pose, ``rigid = False``: it moves with the unknowns) and offers the members
:class:`~alcontact.fem.MultiBody` needs from a body (DOFs, one boundary ``"reference"``,
supports, loads, a zero stiffness, its rigid modes).
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
import scipy.sparse as sp

from ...errors import InputError, MeshError
from . import obstacles

#: the one boundary of a rigid body: its reference point (supports and loads act there)
REFERENCE = "reference"

_AXES = "xyz"


def dof_names(dim: int) -> list[str]:
    """Names of the :math:`d_r` DOFs of a rigid body: ``u_x, u_y, rot_z`` (2D), ``u_x .. rot_z`` (3D)."""
    if dim == 2:
        return ["u_x", "u_y", "rot_z"]
    return ["u_x", "u_y", "u_z", "rot_x", "rot_y", "rot_z"]


def cross_rows(r: np.ndarray, nu: np.ndarray) -> np.ndarray:
    r""":math:`r_i \times \nu_i` per row: ``(m,)`` in 2D (the out-of-plane component), ``(m, 3)`` in 3D."""
    if r.shape[1] == 2:
        return r[:, 0] * nu[:, 1] - r[:, 1] * nu[:, 0]
    return np.cross(r, nu)


class RigidBody:
    r"""A rigid shape with a reference point, driven by prescribed motion or by a force and a moment (module doc).

    Parameters
    ----------
    shape : Master
        The body's surface in its reference pose: a rigid obstacle (analytic,
        :func:`alcontact.contact.obstacles.make`, or a meshed ``"surface"``). Slave points
        are pressed against it as against that obstacle.
    reference : array_like (d,)
        The reference point :math:`X_0` (where the force and the moment act, the centre of
        the rotation).

    Attributes
    ----------
    dim : int
    ndofs : int
        :math:`d_r`: 3 in 2D, 6 in 3D.
    reference : ndarray (d,)
    shape : Master

    Examples
    --------
    >>> from alcontact.contact import obstacles
    >>> punch = RigidBody(obstacles.make("half-space", point=[0.0, 1.0], normal=[0.0, -1.0]), [0.0, 1.0])
    >>> punch.ndofs, punch.rigid, punch.gap([[0.0, 0.9]]).round(6).tolist()
    (3, False, [-0.1])
    """

    #: the master moves with the unknowns (its DOFs)
    rigid = False
    #: what the body adds to the bodies' equations is linear (a zero stiffness): the condensed path applies
    linear = True
    axisymmetric = False
    #: a rigid body has no material; the penalty scales come from the deformable bodies
    material = None
    order = 1
    name = "rigid-body"

    def __init__(self, shape: Any, reference: Any):
        if not (hasattr(shape, "evaluate") and hasattr(shape, "check_dim")):
            raise InputError(f"RigidBody: shape = {type(shape).__name__}: expected a rigid obstacle, e.g. "
                             "alcontact.contact.obstacles.make('circle', center=..., radius=...).")
        if not getattr(shape, "rigid", True):
            raise InputError(f"RigidBody: shape = {shape.describe()} is not rigid: the shape of a rigid body is a "
                             "rigid obstacle (analytic or a meshed 'surface').")
        try:
            ref = np.asarray(reference, dtype=float)
        except (TypeError, ValueError, OverflowError):
            ref = np.array([np.nan])
        if ref.ndim != 1 or ref.size not in (2, 3) or not np.all(np.isfinite(ref)):
            raise InputError(f"RigidBody: reference = {reference!r:.60}: expected the reference point, 2 or 3 finite "
                             "numbers.")
        shape.check_dim(ref.size)
        self.shape = shape
        self.reference = ref
        self.reference.setflags(write=False)
        self.dim = int(ref.size)
        self.ndofs = 3 if self.dim == 2 else 6
        self._zero = sp.csr_matrix((self.ndofs, self.ndofs))

    # ------------------------------------------------------------ what MultiBody needs from a body
    @property
    def mesh(self) -> None:
        """A rigid body has no mesh (its shape is a master)."""
        return None

    @property
    def boundary_names(self) -> list[str]:
        """The one boundary, :data:`REFERENCE` (the reference point)."""
        return [REFERENCE]

    @property
    def dof_names(self) -> list[str]:
        """Names of the DOFs: translation components, then rotation(s) (:func:`dof_names`)."""
        return dof_names(self.dim)

    def _check_name(self, name: str) -> None:
        if name != REFERENCE:
            raise MeshError(f"boundary {name!r} not found; a rigid body has one, {REFERENCE!r} (its reference "
                            "point, where supports and loads act).")

    def facets(self, name: str) -> np.ndarray:
        self._check_name(name)
        return np.zeros(1, dtype=np.int64)

    def node_dofs(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """The reference point and its translation DOFs (``(1, d)`` each)."""
        self._check_name(name)
        return self.all_node_dofs()

    def all_node_dofs(self) -> tuple[np.ndarray, np.ndarray]:
        """The reference point and its translation DOFs; the rotation DOFs are no displacement components."""
        return self.reference[None, :].copy(), np.arange(self.dim, dtype=np.int64)[None, :]

    @property
    def translation_dofs(self) -> np.ndarray:
        return np.arange(self.dim, dtype=np.int64)

    @property
    def rotation_dofs(self) -> np.ndarray:
        return np.arange(self.dim, self.ndofs, dtype=np.int64)

    @property
    def axis_dofs(self) -> np.ndarray:
        return np.empty(0, dtype=np.int64)

    def boundary_weights(self, name: str) -> np.ndarray:
        self._check_name(name)
        return np.ones(1)

    def boundary_pressure(self, name: str, forces) -> np.ndarray:
        self._check_name(name)
        return np.asarray(forces, dtype=float)

    def _components(self, components: Sequence[int] | None) -> list[int]:
        comps = list(range(self.ndofs)) if components is None else [int(c) for c in components]
        if any(not 0 <= c < self.ndofs for c in comps) or len(set(comps)) != len(comps):
            names = ", ".join(f"{k} = {n}" for k, n in enumerate(self.dof_names))
            raise InputError(f"components {list(components)!r} invalid for a rigid body: use distinct indices in "
                             f"0..{self.ndofs - 1} ({names}).")
        return comps

    def dirichlet(self, name: str, components: Sequence[int] | None = None, value: Any = 0.0):
        """Prescribed DOFs and values: ``components`` of :attr:`dof_names` (default all).

        ``value``: one number for every chosen component, or :attr:`ndofs` numbers (the whole
        motion ``(c, theta)``, of which the chosen components are taken). Rotations in radians.
        """
        self._check_name(name)
        comps = self._components(components)
        if callable(value):
            raise InputError("a rigid body's prescribed motion is numbers (translation, rotation), not a callable.")
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError, OverflowError):
            arr = np.array([np.nan])
        if arr.ndim == 0:
            vals = np.full(len(comps), float(arr))
        elif arr.shape == (self.ndofs,):
            vals = arr[comps]
        elif arr.shape == (len(comps),) and components is not None:
            vals = arr
        else:
            raise InputError(f"a rigid body's prescribed value must be a number, {self.ndofs} numbers "
                             f"({', '.join(self.dof_names)}) or one per component; got {value!r:.60}.")
        if not np.all(np.isfinite(vals)):
            raise InputError("the prescribed motion of a rigid body contains NaN or infinity.")
        return np.asarray(comps, dtype=np.int64), vals

    def traction_load(self, name: str, vector) -> np.ndarray:
        r"""The generalized load of a force and a moment on the reference point: ``vector`` = ``(F, M)``.

        2D: :math:`(F_x, F_y, M_z)`; 3D: :math:`(F_x, F_y, F_z, M_x, M_y, M_z)`
        (:class:`~alcontact.contact.RigidLoad`).
        """
        self._check_name(name)
        if callable(vector):
            raise InputError("the load on a rigid body is numbers (force, moment), not a callable.")
        try:
            v = np.asarray(vector, dtype=float).ravel()
        except (TypeError, ValueError, OverflowError):
            v = np.array([np.nan])
        if v.size != self.ndofs or not np.all(np.isfinite(v)):
            raise InputError(f"the load on a rigid body is {self.ndofs} finite numbers (force and moment: "
                             f"{', '.join(n.replace('u_', 'F_').replace('rot_', 'M_') for n in self.dof_names)}); "
                             f"got {vector!r:.60}.")
        return v.copy()

    def pressure_load(self, name: str, p) -> np.ndarray:
        raise InputError("a pressure on a rigid body: load it with a force and a moment on its reference point, "
                         "RigidLoad(body, force=..., moment=...).")

    def body_load(self, f) -> np.ndarray:
        """Zero: a rigid body has no volume here (load its reference point with a :class:`RigidLoad`)."""
        return np.zeros(self.ndofs)

    def stiffness(self) -> sp.csr_matrix:
        """Zero: a rigid body stores no strain energy (its equations are its equilibrium)."""
        return self._zero

    def clear_stiffness(self) -> None:
        return None

    def internal_force(self, u) -> np.ndarray:
        return np.zeros(self.ndofs)

    def energy(self, u) -> float:
        return 0.0

    strain_energy = energy

    def rigid_modes(self) -> np.ndarray:
        """Every DOF is a rigid motion: the identity ``(ndofs, ndofs)``."""
        return np.eye(self.ndofs)

    def check_restrained(self, dirichlet_dofs, **kw) -> None:
        """Raise :class:`InputError` unless every DOF is prescribed (otherwise only contact can hold the body)."""
        fixed = set(np.asarray(dirichlet_dofs, dtype=np.int64).ravel().tolist())
        free = [n for k, n in enumerate(self.dof_names) if k not in fixed]
        if free:
            raise InputError(f"the rigid body's {', '.join(free)} are not prescribed (force driven): only the contact "
                             "can hold it there.")

    # ------------------------------------------------------------ the pose
    def motion(self, q) -> "obstacles.RigidMotion":
        r"""The rigid placement of the pose ``q`` (:math:`d_r` numbers): rotation about :math:`X_0`, then :math:`c`.

        The exact rotation of the angle(s) :math:`\theta` (for drawing the moved shape; the
        contact kinematics uses its linearization).
        """
        q = np.asarray(q, dtype=float).ravel()
        c, th = q[: self.dim], q[self.dim:]
        if self.dim == 2:
            return obstacles.RigidMotion.about(self.reference, float(th[0]), offset=c)
        angle = float(np.linalg.norm(th))
        if angle == 0.0:
            return obstacles.RigidMotion(np.eye(3), c)
        return obstacles.RigidMotion.about(self.reference, angle, axis=th / angle, offset=c)

    def placed(self, q) -> Any:
        """The shape at the pose ``q``."""
        return obstacles.move(self.shape, self.motion(q))

    # ------------------------------------------------------------ the Master protocol, at the reference pose
    @property
    def body(self) -> "RigidBody":
        """The body whose DOFs move this master: itself."""
        return self

    def describe(self) -> str:
        ref = ", ".join(f"{x:g}" for x in self.reference)
        return f"a rigid body ({self.shape.describe()}) with reference point ({ref})"

    def check_dim(self, d: int) -> None:
        if d != self.dim:
            raise InputError(f"RigidBody: the rigid body is {self.dim}D (its reference point); the slave body is "
                             f"{d}D.")

    def evaluate(self, x):
        return self.shape.evaluate(x)

    def gap(self, x):
        return self.shape.gap(x)

    def normal(self, x):
        return self.shape.normal(x)

    def project(self, x):
        return self.shape.project(x)

    def gap_hessian(self, x):
        return self.shape.gap_hessian(x)

    def surface_slip(self, x, y_prev, *, jacobian: bool = True):
        return self.shape.surface_slip(x, y_prev, jacobian=jacobian)

    def bounding_box(self, d: int):
        return self.shape.bounding_box(d)
