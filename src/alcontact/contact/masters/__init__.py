"""Masters of a contact pair: the :class:`Master` protocol and the rigid obstacles.

A master gives, for points :math:`x` of the slave boundary, the signed gap
:math:`g(x) \\le 0` feasible (chapter 6: the obstacle's signed distance, negative outside the
obstacle) and the outward unit normal :math:`\\nu(x)` at the projection; the gap of a
contact point is (6.15) at small deformation and :math:`g(x + u)` at finite deformation.
The rigid obstacles (:mod:`alcontact.contact.masters.obstacles`: planes, spheres,
cylinders, polygons, convex hulls, rigid motions) implement it; they are also importable as
:mod:`alcontact.contact.obstacles`.

Public names
------------
Master, obstacles, BodySurface (a boundary of another body: the deformable master of two-body contact)
"""

from . import obstacles
from ._master import Master
from ._mortar import BodySurface

__all__ = ["BodySurface", "Master", "obstacles"]
