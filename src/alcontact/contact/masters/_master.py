r"""The master side of a contact pair: what the contact kinematics measures a slave point against.

A :class:`~alcontact.contact.ContactPair` presses the points of a *slave* boundary (a
boundary of a discretized body) against a *master*. Today every master is a rigid
obstacle of :mod:`alcontact.contact.obstacles` (the registry, :func:`~alcontact.contact.obstacles.translate`
and :func:`~alcontact.contact.obstacles.move` placements included); a deformable body's
surface is the master that the two-body (mortar) contact of the next issue adds. Both
answer the same questions, listed member by member in :class:`Master`, so the contact
kinematics (the linearized gap (6.15) at small deformation, the current-configuration gap,
its gradient and Hessian at finite deformation, the slip of Coulomb friction) is written
once against this protocol.

Sign convention (eq. 6.15 and the reading notes): the gap :math:`g_N(x) \le 0` is feasible
(no penetration); :math:`g_N(x) > 0` is the penetration depth. The normal
:math:`\nu = -\nabla g_N` points out of the master into the region where the slave may be.

Every point argument ``x`` is an array of shape ``(m, d)`` of slave points in the
*current* configuration (:math:`x = X + u`; at small deformation the reference points,
the gap being linearized there).
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray


FloatArray = NDArray[np.float64]


@runtime_checkable
class Master(Protocol):
    r"""What the contact kinematics needs from the master side of a :class:`~alcontact.contact.ContactPair`.

    Every rigid obstacle of :mod:`alcontact.contact.obstacles` satisfies it (checked over the
    obstacle registry by ``tests/unit/test_master_protocol.py``). A deformable surface
    implements the same members with ``rigid = False``; the algorithms then also
    differentiate the gap with respect to that body's degrees of freedom.

    Members
    -------
    dim
        Space dimension of the master (2 or 3); ``None`` when it adapts to the body's
        (a user gap function written for any dimension).
    name
        Registry name of the kind of master (``"circle"``, ``"half-space"``, ...), used in
        results and reports.
    rigid
        ``True`` when the master's position does not depend on the unknowns: a rigid
        obstacle, fixed or placed along a prescribed path (the load stepping places it at
        each step time with :func:`~alcontact.contact.obstacles.translate` /
        :func:`~alcontact.contact.obstacles.move`). ``False`` for a master that moves with a
        body's displacement (a deformable surface): not supported yet, refused by
        :class:`~alcontact.contact.ContactProblem`.
    describe()
        One line with the defining parameters, for messages and reports.
    check_dim(d)
        Raise :class:`~alcontact.errors.InputError` unless the master can meet a ``d``-D body.
    evaluate(x)
        ``(gap, normal)`` at the points ``x`` in one pass: the signed gap :math:`g_N`, shape
        ``(m,)``, and the unit normal :math:`\nu = -\nabla g_N`, shape ``(m, d)``. The gap
        (6.15) and its gradient; what every algorithm evaluates at every iteration.
    gap(x)
        :math:`g_N(x)`, shape ``(m,)``: ``< 0`` free, ``> 0`` penetration depth.
    normal(x)
        :math:`\nu(x) = -\nabla g_N(x)`, shape ``(m, d)``.
    project(x)
        Closest point :math:`\bar x = x + g_N(x)\,\nu(x)` of the master surface, shape
        ``(m, d)``: where the contact force acts on the master, and the surface point that
        the Coulomb slip is measured from (the frictional finite-deformation path).
    gap_hessian(x)
        :math:`H = \nabla^2 g_N = -\partial\nu/\partial x`, shape ``(m, d, d)``: the
        derivative of the normal for the consistent linearization of the finite path
        (the curvature term of the tangent).
    surface_slip(x, y_prev, *, jacobian=True)
        Slip vector on the master's surface from the previous surface point ``y_prev`` to
        the projection of ``x`` (tangent at the projection, length = distance travelled on
        the surface), and its Jacobian in ``x`` (``(m, d, d)``, or ``None`` when
        ``jacobian=False``): the incremental slip of Coulomb friction at finite deformation.
    bounding_box(d)
        ``(lo, hi)``, each of shape ``(d,)``: an axis-aligned box that contains the master
        surface, ``-inf`` / ``+inf`` along the directions in which it is unbounded (a
        half-space, a cylinder, a user gap function). For candidate search: a slave point
        far outside the box cannot touch this master.

    Examples
    --------
    >>> from alcontact.contact import Master, obstacles
    >>> ob = obstacles.make("circle", center=[0.0, 2.0], radius=1.0)
    >>> isinstance(ob, Master), ob.rigid
    (True, True)
    >>> ob.bounding_box(2)
    (array([-1.,  1.]), array([1., 3.]))
    """

    @property
    def dim(self) -> int | None: ...

    @property
    def name(self) -> str: ...

    @property
    def rigid(self) -> bool: ...

    def describe(self) -> str: ...

    def check_dim(self, d: int) -> None: ...

    def evaluate(self, x: ArrayLike) -> tuple[FloatArray, FloatArray]: ...

    def gap(self, x: ArrayLike) -> FloatArray: ...

    def normal(self, x: ArrayLike) -> FloatArray: ...

    def project(self, x: ArrayLike) -> FloatArray: ...

    def gap_hessian(self, x: ArrayLike) -> FloatArray: ...

    def surface_slip(self, x: ArrayLike, y_prev: ArrayLike, *,
                     jacobian: bool = True) -> tuple[FloatArray, FloatArray | None]: ...

    def bounding_box(self, d: int) -> tuple[FloatArray, FloatArray]: ...
