r"""A neo-Hookean hemisphere pressed onto a rigid plane (finite deformation, 3D).

The 3D companion of :mod:`alcontact.problems.half_cylinder`: a hemisphere of radius
:math:`R` with its flat face on top (:math:`y = R`) and its curved face on the plane
:math:`y = 0`, touching it at the origin. One quarter is modelled, :math:`x \le 0`,
:math:`z \ge 0` (symmetry faces ``"symmetry_x"``, :math:`u_x = 0`, and ``"symmetry_z"``,
:math:`u_z = 0`); it is the unit ball's octant meshed by the elliptical-grid map of the
unit cube,

.. math::

    (a, b, c) \mapsto R\,\bigl(a\sqrt{1 - \tfrac{b^2}{2} - \tfrac{c^2}{2} + \tfrac{b^2c^2}{3}},\;
    b\sqrt{1 - \tfrac{a^2}{2} - \tfrac{c^2}{2} + \tfrac{a^2c^2}{3}},\;
    c\sqrt{1 - \tfrac{a^2}{2} - \tfrac{b^2}{2} + \tfrac{a^2b^2}{3}}\bigr),

rotated by 180 degrees about the :math:`z` axis and shifted up by :math:`R`. For P2 the
mesh is of second order by default: the edge nodes of the spherical face are projected
onto the sphere (the others stay at the edge midpoints), so the contact surface is curved. The flat
face (``"top"``) is pushed down by :math:`\delta` (``u_y = -\delta``, lateral motion
free): with :func:`alcontact.contact.solve` (``steps=``) the approach is ramped over the load
steps. The contact boundary is ``"curved"``. A benchmark case (no closed-form reference
at finite deformation; for small :math:`\delta/R` the force tends to Hertz's
:math:`F = \tfrac{4}{3} E^* R^{1/2} \delta^{3/2}` of the whole sphere, a quarter of it here).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import skfem

from ..contact import ContactProblem, Support
from ..contact.obstacles import HalfSpace
from ..fem import Material, meshes
from ..fem.hyperelastic import Hyperelastic

__all__ = ["hemisphere", "hemisphere_axisym"]


def _curved(mesh, radius: float, tol: float):
    """Second-order mesh: edge midpoints, those of the spherical boundary projected onto the sphere.

    (The elliptical-grid map itself is singular along the images of the cube's edges, and its
    quadratic interpolation inverts elements there; the projection of the boundary nodes alone
    keeps every element map valid: :func:`alcontact.fem.quality.curved_jacobian_ratio`.)
    """
    m2 = skfem.MeshTet2.from_mesh(mesh)  # straight: the edge nodes at the midpoints
    x = np.array(m2.doflocs, dtype=float)
    nv = mesh.nvertices
    centre = np.array([0.0, radius, 0.0])
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    sphere = bf[(mid[1] < radius - tol) & (mid[0] < -tol) & (mid[2] > tol)]
    edges = np.unique(mesh.f2e[:, sphere])
    d = x[:, nv + edges] - centre[:, None]
    x[:, nv + edges] = centre[:, None] + radius * d / np.linalg.norm(d, axis=0)
    return dataclasses.replace(m2, doflocs=x)


def hemisphere(n: int = 6, *, order: int = 1, radius: float = 1.0, delta: float = 0.2,
               E: float = 1000.0, nu: float = 0.3, model: str = "neo-hookean",
               curved: bool = True) -> ContactProblem:
    """Quarter of a hemisphere on a rigid plane, pressed down by ``delta`` (module doc).

    Parameters
    ----------
    n : int
        Cells per side of the mapped cube (``6 n^3`` tetrahedra; P1 has ``3 (n+1)^3`` DOFs).
    order : {1, 2}
    radius, delta : float
        Radius :math:`R` and final approach :math:`\\delta` of the flat face.
    E, nu : float
        Elastic constants.
    model : str
        Hyperelastic law (:func:`alcontact.fem.available_materials`).
    curved : bool
        With ``order=2``: a second-order mesh (``MeshTet2``) whose edge nodes on the
        spherical face are projected onto the sphere (isoparametric P2, default; interior
        edge nodes at the midpoints); ``False`` gives straight-sided P2 elements on the
        same vertices.
    """
    cube = meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, 1.0, n, n, n)
    a, b, c = cube.doflocs
    X = a * np.sqrt(np.maximum(1.0 - b**2 / 2 - c**2 / 2 + b**2 * c**2 / 3, 0.0))
    Y = b * np.sqrt(np.maximum(1.0 - a**2 / 2 - c**2 / 2 + a**2 * c**2 / 3, 0.0))
    Z = c * np.sqrt(np.maximum(1.0 - a**2 / 2 - b**2 / 2 + a**2 * b**2 / 3, 0.0))
    p = np.vstack([-radius * X, radius * (1.0 - Y), radius * Z])  # rotation about z keeps the orientation
    mesh = dataclasses.replace(cube, doflocs=p, _boundaries=None)
    tol = 1e-9 * radius
    if order == 2 and curved:
        mesh = _curved(mesh, radius, tol)
    mesh = mesh.with_boundaries({
        "top": lambda x: x[1] > radius - tol,
        "symmetry_x": lambda x: x[0] > -tol,
        "symmetry_z": lambda x: x[2] < tol,
        "curved": lambda x: (x[1] < radius - tol) & (x[0] < -tol) & (x[2] > tol),
    })
    body = Hyperelastic(mesh, Material(E=E, nu=nu), order=order, model=model)
    return ContactProblem(
        model=body,
        obstacle=HalfSpace([0.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        contact_boundary="curved",
        supports=(Support("symmetry_x", components=(0,)), Support("symmetry_z", components=(2,)),
                  Support("top", components=(1,), value=-delta)),
        name=f"hemisphere quarter (R={radius:g}, delta/R={delta / radius:g}, n={n}, P{order}, {model})",
        kinematics="finite",
        meta={"radius": radius, "delta": delta, "n": n, "curved": bool(order == 2 and curved)},
    )


def hemisphere_axisym(n: int = 12, *, order: int = 1, radius: float = 1.0, delta: float = 0.2,
                      E: float = 1000.0, nu: float = 0.3, model: str = "neo-hookean",
                      curved: bool = True) -> ContactProblem:
    r"""The hemisphere of :func:`hemisphere` as a body of revolution (``geometry="axisymmetric"``).

    The quarter disc :math:`r = x \in [0, R]`, :math:`y \in [0, R]`, :math:`r^2 + (y - R)^2 \le R^2`
    in the r-z half-plane, meshed by the 2D elliptical-grid map of the unit square
    :math:`(a, b) \mapsto R\,(b\sqrt{1 - a^2/2},\; 1 - a\sqrt{1 - b^2/2})` (``2 n^2``
    triangles; P2: a second-order mesh with the edge nodes of the arc on the circle when
    ``curved``). Boundaries ``"top"`` (pushed down by ``delta``), ``"axis"`` (:math:`u_r = 0`,
    imposed by the body) and ``"curved"`` (contact). The force is the total over the
    revolution: four times the quarter model's of :func:`hemisphere`. Parameters as :func:`hemisphere`.
    """
    sq = meshes.rectangle(0.0, 1.0, 0.0, 1.0, n, n)
    a, b = sq.doflocs
    r = radius * b * np.sqrt(np.maximum(1.0 - a**2 / 2, 0.0))
    y = radius * (1.0 - a * np.sqrt(np.maximum(1.0 - b**2 / 2, 0.0)))  # (a, b) -> (b, -a): a rotation
    mesh = dataclasses.replace(sq, doflocs=np.vstack([r, y]), _boundaries=None)
    tol = 1e-9 * radius
    if order == 2 and curved:
        m2 = skfem.MeshTri2.from_mesh(mesh)
        x = np.array(m2.doflocs, dtype=float)
        bf = mesh.boundary_facets()
        mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
        arc = bf[(mid[1] < radius - tol) & (mid[0] > tol)]
        centre = np.array([0.0, radius])
        d = x[:, mesh.nvertices + arc] - centre[:, None]
        x[:, mesh.nvertices + arc] = centre[:, None] + radius * d / np.linalg.norm(d, axis=0)
        mesh = dataclasses.replace(m2, doflocs=x)
    mesh = mesh.with_boundaries({
        "top": lambda x: x[1] > radius - tol,
        "axis": lambda x: x[0] < tol,
        "curved": lambda x: (x[1] < radius - tol) & (x[0] > tol),
    })
    body = Hyperelastic(mesh, Material(E=E, nu=nu), order=order, model=model, geometry="axisymmetric")
    return ContactProblem(
        model=body,
        obstacle=HalfSpace([0.0, 0.0], [0.0, 1.0]),
        contact_boundary="curved",
        supports=(Support("axis", components=(0,)), Support("top", components=(1,), value=-delta)),
        name=f"hemisphere axisymmetric (R={radius:g}, delta/R={delta / radius:g}, n={n}, P{order}, {model})",
        kinematics="finite",
        meta={"radius": radius, "delta": delta, "n": n, "curved": bool(order == 2 and curved)},
    )
