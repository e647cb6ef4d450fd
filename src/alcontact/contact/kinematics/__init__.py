"""Contact kinematics at small deformation: the linearized gap (6.15) and its data.

.. math::

    g_i(u) = g^0_i - \\nu_i \\cdot u_i \\le 0 \\quad\\text{(no penetration)},

at every contact point ``i`` of the slave boundary, with the signed gap :math:`g^0_i` of
its reference position and the master's normal :math:`\\nu_i`. :class:`ContactPoints`
holds the points, normals, tributary weights, the constraint matrix ``B`` (rows
:math:`-\\nu_i^T`) and the candidate selection shared by every contact system
(:mod:`alcontact.contact.systems`); :func:`tangent_bases` gives the tangent directions
of the Coulomb law (section 6.2). The gap at finite deformation, its gradient and Hessian
are computed in the current configuration by
:class:`~alcontact.contact.systems.FiniteContact` (one Newton matrix per iteration,
whose fixed structure is :class:`~alcontact.contact.systems.NewtonLayout`).

Public names
------------
ContactPoints, tangent_bases
"""

from ._points import ContactPoints, tangent_bases

__all__ = ["ContactPoints", "tangent_bases"]
