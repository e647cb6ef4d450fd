r"""The geometry of a body: Cartesian, or a body of revolution in the r-z half-plane.

``"cartesian"``: the mesh coordinates are x, y (2D, with :attr:`Material.plane`) or x, y, z.

``"axisymmetric"``: a 2D mesh in the half-plane :math:`r = x \ge 0`, :math:`z = y`, revolved about
the z axis (torsion-free). The displacement is :math:`(u_r, u_z)`; the strain has the hoop component

.. math::
    \varepsilon = \begin{pmatrix} \partial_r u_r & \tfrac12(\partial_z u_r + \partial_r u_z) & 0 \\
    \cdot & \partial_z u_z & 0 \\ 0 & 0 & u_r / r \end{pmatrix},

and every volume and boundary integral carries the weight :math:`2\pi r`
(:math:`dV = 2\pi r\,dr\,dz`, :math:`dA = 2\pi r\,ds`): stiffness, loads and the contact boundary weights
are those of the whole body of revolution, so forces are totals (2π integrated; per radian: divide
by 2π). On the axis :math:`r = 0` the radial displacement vanishes: the body prescribes
:math:`u_r = 0` there itself (:attr:`axis_dofs`), and a support that prescribes another value is refused.
The rigid motions of a body of revolution reduce to the translation along z.
"""

from __future__ import annotations

import numpy as np

from alcontact._options import show
from alcontact.errors import InputError

__all__ = ["GEOMETRIES", "AXISYMMETRIC", "check_geometry", "axis_points", "TWO_PI"]

#: the geometries a body accepts (``geometry=`` of the bodies, ``[mesh] geometry`` of a problem file)
GEOMETRIES = ("cartesian", "axisymmetric")
AXISYMMETRIC = "axisymmetric"
TWO_PI = 2.0 * np.pi


def check_geometry(geometry, dim: int, points: np.ndarray, *, plane: str = "strain") -> str:
    """``geometry`` checked against the mesh: an :class:`InputError` naming the key and the way out.

    Parameters
    ----------
    geometry : str
        One of :data:`GEOMETRIES`.
    dim : int
        Space dimension of the mesh.
    points : ndarray (dim, n)
        Mesh nodes (axisymmetric: the radius ``points[0]`` must be ``>= 0``).
    plane : str
        The material's 2D assumption (axisymmetric bodies take the 3D constants: ``"strain"`` only).
    """
    if not isinstance(geometry, str) or geometry not in GEOMETRIES:
        raise InputError(f"geometry={show(geometry)} is not known; use one of {', '.join(map(repr, GEOMETRIES))}.")
    if isinstance(dim, bool) or not isinstance(dim, (int, np.integer)) or dim not in (1, 2, 3):
        raise InputError(f"check_geometry: dim = {show(dim)} must be the space dimension of the mesh, 2 or 3.")
    if geometry != AXISYMMETRIC:
        return geometry
    if dim != 2:
        raise InputError(f"geometry='axisymmetric' needs a 2D mesh in the r-z half-plane (r = x >= 0); this mesh "
                         f"is {dim}D. Use geometry='cartesian' for a 3D mesh, or mesh the half cross-section.")
    if not isinstance(plane, str) or plane != "strain":
        raise InputError(f"material plane={show(plane)} does not apply to geometry='axisymmetric' (a body of "
                         "revolution has the hoop strain u_r/r, not a plane assumption); leave plane='strain'.")
    try:
        r = np.asarray(points, dtype=float)
    except (TypeError, ValueError, OverflowError):
        r = None
    if r is None or r.ndim != 2 or r.shape[0] != 2 or r.shape[1] == 0 or not np.all(np.isfinite(r)):
        raise InputError(f"geometry='axisymmetric': points = {show(points)} must be the (2, n) finite mesh "
                         "coordinates (x = r, y = z).")
    r = r[0]
    tol = 1e-12 * max(float(np.ptp(r)), 1e-300)
    if np.min(r) < -tol:
        raise InputError(f"geometry='axisymmetric': the mesh reaches r = x = {float(np.min(r)):g} < 0; an "
                         "axisymmetric mesh lies in the half-plane x >= 0 (x is the radius, y the axis). "
                         "Shift or cut the mesh so that x >= 0.")
    return geometry


def axis_points(r: np.ndarray, extent: float) -> np.ndarray:
    """Boolean mask of the radii ``r`` on the axis (``|r| <= 1e-12 * extent``)."""
    return np.abs(np.asarray(r, dtype=float)) <= 1e-12 * max(extent, 1e-300)
