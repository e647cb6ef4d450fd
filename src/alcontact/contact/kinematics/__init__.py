"""Contact kinematics: the gap of the slave points against a master, its gradient and Hessian.

One interface, :class:`ContactKinematics` (a :class:`typing.Protocol`), for the two
configurations of chapter 6, evaluated against any :class:`~alcontact.contact.Master`:

.. math::

    g_i(u) = g^0_i - \\nu_i \\cdot u_i \\ \\text{(6.15)}, \\qquad
    g_i(u) = \\operatorname{gap}(X_i + u_i),

the gap linearized at the reference configuration (:class:`LinearizedGap`, small
deformation) and the gap at the current configuration (:class:`CurrentGap`, finite
deformation), with :math:`g \\le 0` feasible (no penetration). :meth:`ContactKinematics.evaluate` gives a
:class:`GapEvaluation`: the gaps, the master's normals, the constraint rows
:math:`\\partial g/\\partial x` on the free DOFs (a sparse matrix: a gap may couple several
points, as a mortar gap does) and the curvature term :math:`\\sum_i c_i \\partial^2 g_i/\\partial x^2`.
Every contact system (:mod:`alcontact.contact.systems`) holds one and takes its gaps and
constraint rows from it. :class:`ContactPoints` is the common base of the systems (their
points, the candidate selection, the declared "not available" members of
:class:`~alcontact.contact.systems.ContactSystem`); :func:`tangent_bases` gives the tangent
directions of the Coulomb law (section 6.2).

Public names
------------
ContactKinematics, LinearizedGap, CurrentGap, MortarKinematics, CurrentMortarGap, GapEvaluation, ContactPoints,
tangent_bases
"""

from ._gap import ContactKinematics, CurrentGap, GapEvaluation, LinearizedGap
from ._mortar import MortarKinematics
from ._mortar_current import CurrentMortarGap
from ._points import ContactPoints, tangent_bases

__all__ = ["ContactKinematics", "LinearizedGap", "CurrentGap", "MortarKinematics", "CurrentMortarGap", "GapEvaluation",
           "ContactPoints", "tangent_bases"]
