"""The contact problem: bodies, contact pairs, supports, loads and loading histories.

A :class:`ContactProblem` holds the body (a discretized elastic or hyperelastic model),
its :class:`Support` s and loads (:class:`Traction`, :class:`Pressure`, :class:`BodyForce`),
the :class:`ContactPair` s (slave :class:`Boundary`, master: a rigid obstacle,
:mod:`alcontact.contact.masters`), the Coulomb coefficient and the kinematics
(``"small"``: linearized gap (6.15); ``"finite"``: gap at the current configuration).
A :class:`LoadHistory` (load cases times amplitudes, :class:`Ramp`) gives the problem at
each step time (:func:`problem_at`) for the incremental solves of section 6.2.

Public names
------------
ContactProblem, ContactPair, Boundary, Support, Traction, RigidLoad (force and moment on a rigid body), Pressure,
BodyForce, KINEMATICS,
merge_supports, LoadHistory, LoadCase, Ramp, problem_at
"""

from ._loading import LoadCase, LoadHistory, Ramp, problem_at
from ._problem import (KINEMATICS, BodyForce, Boundary, ContactPair, ContactProblem, Pressure, RigidLoad, Support,
                       Traction, merge_supports)

__all__ = ["ContactProblem", "ContactPair", "Boundary", "Support", "Traction", "RigidLoad", "Pressure", "BodyForce",
           "KINEMATICS", "merge_supports", "LoadHistory", "LoadCase", "Ramp", "problem_at"]
