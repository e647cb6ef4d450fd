r"""A neo-Hookean half-cylinder pressed onto a rigid plane (finite deformation, plane strain).

The half-cylinder of radius :math:`R` lies with its flat face on top (:math:`y = R`) and
its curved face on the plane :math:`y = 0`, touching it at the origin; the half model
:math:`x \le 0` (symmetry face ``"symmetry"``, :math:`u_x = 0`) is meshed by the
elliptical-grid map of the unit square onto the quarter disc,

.. math::

    (\xi, \eta) \mapsto R\,\bigl(\xi\sqrt{1 - \eta^2/2},\; \eta\sqrt{1 - \xi^2/2}\bigr),

rotated by 180 degrees and shifted up by :math:`R`. For P2 the mesh is of second
order by default (the map applied to the edge midpoints too): the boundary edges are
arcs of the isoparametric map through three points of the circle. The flat face (``"top"``) is pushed
down by :math:`\delta` (``u_y = -\delta``, lateral motion free): with
:func:`alcontact.contact.solve` (``steps=``) the approach is ramped over the load steps.
The contact boundary is ``"curved"``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import skfem

from ..contact import ContactProblem, Support
from ..contact.obstacles import HalfSpace
from ..fem import Material, meshes
from ..fem.hyperelastic import Hyperelastic

__all__ = ["half_cylinder"]


def disc_mesh(xi0: float, nx: int, ny: int, *, radius: float, second_order: bool):
    r"""The elliptical-grid map (module doc) of the triangle mesh of ``[xi0, 1] x [0, 1]`` (``nx`` by ``ny`` cells).

    ``xi0 = 0`` gives the quarter disc :math:`x \le 0` of the half-cylinder, ``xi0 = -1`` the
    whole half disc; rotated by 180 degrees and shifted up by :math:`R`: the flat face on top
    (:math:`y = R`), the curved face below, touching :math:`y = 0` at the origin. With
    ``second_order`` a ``MeshTri2`` whose edge midpoints are mapped too (boundary edges on the circle).
    """
    sq = meshes.rectangle(xi0, 1.0, 0.0, 1.0, nx, ny)
    if second_order:  # the map of the edge midpoints: the boundary ones land on the circle
        sq = skfem.MeshTri2.from_mesh(sq)
    xi, eta = sq.doflocs
    X = radius * xi * np.sqrt(1.0 - eta**2 / 2.0)
    Y = radius * eta * np.sqrt(1.0 - xi**2 / 2.0)
    p = np.vstack([-X, radius - Y])  # rotation by 180 degrees keeps the orientation
    return dataclasses.replace(sq, doflocs=p, _boundaries=None)


def half_cylinder(n: int = 8, *, order: int = 1, radius: float = 1.0, delta: float = 0.4,
                  E: float = 1000.0, nu: float = 0.3, model: str = "neo-hookean",
                  curved: bool = True) -> ContactProblem:
    """Half-cylinder on a rigid plane, pressed down by ``delta`` (module doc).

    Parameters
    ----------
    n : int
        Elements per side of the mapped square (``2 n^2`` triangles).
    order : {1, 2}
    radius, delta : float
        Radius :math:`R` and final approach :math:`\\delta` of the flat face.
    E, nu : float
        Elastic constants (plane strain).
    model : str
        Hyperelastic law (:func:`alcontact.fem.available_materials`).
    curved : bool
        With ``order=2``: a second-order mesh (``MeshTri2``) whose edge nodes are mapped
        too, so that the boundary edges lie on the circle (isoparametric P2, default);
        ``False`` gives straight-sided P2 elements on the same vertices.
    """
    mesh = disc_mesh(0.0, n, n, radius=radius, second_order=order == 2 and curved)
    tol = 1e-9 * radius
    mesh = mesh.with_boundaries({
        "top": lambda x: x[1] > radius - tol,
        "symmetry": lambda x: x[0] > -tol,
        "curved": lambda x: (x[1] < radius - tol) & (x[0] < -tol),
    })
    body = Hyperelastic(mesh, Material(E=E, nu=nu, plane="strain"), order=order, model=model)
    return ContactProblem(
        model=body,
        obstacle=HalfSpace([0.0, 0.0], [0.0, 1.0]),
        contact_boundary="curved",
        supports=(Support("symmetry", components=(0,)), Support("top", components=(1,), value=-delta)),
        name=f"half-cylinder (R={radius:g}, delta/R={delta / radius:g}, n={n}, P{order}, {model})",
        kinematics="finite",
        meta={"radius": radius, "delta": delta, "n": n, "curved": bool(order == 2 and curved)},
    )
