"""Masters of a contact pair: the :class:`Master` protocol and the rigid obstacles.

A master gives, for points :math:`x` of the slave boundary, the signed gap
:math:`g(x) \\le 0` feasible (chapter 6: the obstacle's signed distance, negative outside the
obstacle) and the outward unit normal :math:`\\nu(x)` at the projection; the gap of a
contact point is (6.15) at small deformation and :math:`g(x + u)` at finite deformation.
The rigid obstacles (:mod:`alcontact.contact.masters.obstacles`: planes, spheres,
cylinders, polygons, convex hulls, rigid motions) implement it; they are also importable as
:mod:`alcontact.contact.obstacles`. :class:`MeshedSurface` is a meshed rigid surface (a
polyline or a triangulation from an STL or Gmsh file, non-convex allowed), registered as
the obstacle ``"surface"``; :class:`StackedMaster` the master of the stacked contact points
of several contact pairs.

Public names
------------
Master, MeshedSurface, StackedMaster, obstacles, BodySurface (a boundary of another body: the deformable master of
two-body contact), RigidBody (a rigid shape with a reference point whose pose is prescribed or solved for)
"""

from . import obstacles
from ._master import Master
from ._mortar import BodySurface
from ._rigid_body import RigidBody
from ._stacked import StackedMaster
from ._surface import MeshedSurface  # registers the obstacle "surface"

__all__ = ["BodySurface", "Master", "MeshedSurface", "RigidBody", "StackedMaster", "obstacles"]
