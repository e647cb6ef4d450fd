r"""Two deformable bodies in contact (2D, plane strain): stacked blocks and two elastic cylinders.

Both are solved with the mortar pair of :class:`~alcontact.contact.BodySurface` (the master
is the lower body's top) and a :class:`~alcontact.fem.MultiBody` of the two bodies named
``"base"`` (lower) and ``"top"`` (upper): boundaries ``"base/top"``, ``"top/bottom"``, ...

- :func:`stacked_blocks`: the contact patch test. Two blocks with non-matching meshes,
  a uniform pressure ``p`` on the top: the stress is uniaxial in both blocks and the
  interface pressure is ``p`` at every slave node (Taylor & Papadopoulos, 1991; the
  mortar method passes it on non-matching meshes, node-to-segment does not).
- :func:`hertz_cylinders`: two elastic cylinders of radii :math:`R_1`, :math:`R_2` and
  different :math:`E`, :math:`\nu`, pressed together (Johnson, *Contact Mechanics*, 1985,
  sec. 4.3, eq. 4.45-4.47 with the effective radius and modulus)

  .. math::

      \frac1R = \frac1{R_1} + \frac1{R_2}, \qquad
      \frac1{E^*} = \frac{1-\nu_1^2}{E_1} + \frac{1-\nu_2^2}{E_2}, \qquad
      a = \sqrt{\frac{4PR}{\pi E^*}}, \qquad p_0 = \frac{2P}{\pi a}.

  As for :func:`alcontact.problems.hertz.hertz_2d`, each cylinder is modelled near the
  contact by a block of size ``size * a`` (Hertz's half-spaces) whose contact face has the
  cylinder's parabolic profile :math:`x^2 / (2R_i)`, half model ``x >= 0``; the reference is
  that of the load the model carries.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import skfem

from ..contact import BodySurface, Boundary, ContactPair, ContactProblem, Pressure, Support
from ..fem import LinearElasticity, Material, meshes
from .hertz import LEVELS_2D, HertzReference, mesh_spec

__all__ = ["stacked_blocks", "hertz_cylinders", "rigid_limit_pair"]


def _block(x: np.ndarray, y: np.ndarray) -> skfem.MeshTri:
    """Tensor mesh of the grid ``x`` by ``y`` with boundaries left, right, bottom, top."""
    mesh = skfem.MeshTri.init_tensor(x, y)
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    tol = 1e-9 * max(np.ptp(x), np.ptp(y))
    sides = {"left": (0, x[0]), "right": (0, x[-1]), "bottom": (1, y[0]), "top": (1, y[-1])}
    return mesh.with_boundaries({n: bf[np.abs(mid[a] - v) <= tol] for n, (a, v) in sides.items()})


def stacked_blocks(n_base: int = 2, n_top: int = 3, *, pressure: float = 10.0, E=(1000.0, 500.0), nu=(0.3, 0.2),
                   width: float = 1.0, height: float = 1.0, order: int = 1) -> ContactProblem:
    """Contact patch test: a block of ``n_top`` x ``n_top`` cells on one of ``n_base`` x ``n_base`` cells.

    The base ``[0, width] x [0, height]`` stands on rollers (``u_y = 0`` on its bottom); the top
    block ``[0, width] x [height, 2 height]`` is held by the contact only (its vertical motion), a
    uniform ``pressure`` pushes its top down; rollers ``u_x = 0`` on both left sides. Slave: the top
    block's bottom; master: the base's top. The exact interface pressure is ``pressure``. ``order``:
    P1 or P2 elements in both blocks.
    """
    base = LinearElasticity(_block(np.linspace(0, width, n_base + 1), np.linspace(0, height, n_base + 1)),
                            Material(E=E[0], nu=nu[0]), order=order)
    top = LinearElasticity(_block(np.linspace(0, width, n_top + 1), np.linspace(height, 2 * height, n_top + 1)),
                           Material(E=E[1], nu=nu[1]), order=order)
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))
    return ContactProblem(bodies=[base, top], pairs=[pair],
                          supports=[Support("body0/bottom", components=[1]), Support("body0/left", components=[0]),
                                    Support("body1/left", components=[0])],
                          loads=[Pressure("body1/top", pressure)],
                          name=f"stacked blocks {n_base}:{n_top}", meta={"pressure_exact": float(pressure)})


def _curved(mesh: skfem.MeshTri, radius: float, depth: float, sign: float) -> skfem.MeshTri:
    """``mesh`` with its face ``y = 0`` bent to the profile ``sign * x^2 / (2 radius)``, fading to 0 at ``|y| = depth``.

    Beyond ``|x| = radius / 2``, far from any contact, the profile continues along its tangent (so that
    the block's far corners keep their shape).
    """
    p = np.array(mesh.doflocs, dtype=float)
    fade = np.clip(1.0 - np.abs(p[1]) / depth, 0.0, 1.0)
    xc = 0.5 * radius
    x = np.abs(p[0])
    profile = np.where(x <= xc, x ** 2 / (2.0 * radius), xc ** 2 / (2.0 * radius) + xc / radius * (x - xc))
    p[1] += sign * profile * fade
    return dataclasses.replace(mesh, doflocs=p)


def hertz_cylinders(level: int = 1, *, E=(200e3, 70e3), nu=(0.3, 0.35), radii=(20.0, 20.0), a_target: float = 1.0,
                    size: float = 20.0, master_ratio: float = 0.75, growth: float = 1.15,
                    order: int = 1) -> ContactProblem:
    """Two elastic cylinders pressed together (plane strain, half model ``x >= 0``), module doc.

    Parameters
    ----------
    level : int
        Refinement level (:data:`alcontact.problems.hertz.LEVELS_2D`: elements per ``a`` on the slave).
    E, nu : pair of float
        Constants of the lower body (``"base"``, the master) and the upper one (``"top"``, the slave).
    radii : pair of float
        :math:`R_1` (lower) and :math:`R_2` (upper).
    a_target : float
        Intended half-width: sets the approach, the fine zone and the block size.
    size : float
        Block width and depth in units of ``a_target``.
    master_ratio : float
        Elements per ``a`` of the master over the slave's (non-matching meshes).
    growth : float
        Grading ratio away from the contact.
    order : {1, 2}
        P1 or P2 elements (straight edges; the fine zone keeps ``n / order`` elements per ``a``, so
        that P2 has the same nodes on the interface as P1).
    """
    (E1, E2), (nu1, nu2), (R1, R2) = E, nu, radii
    e_star = 1.0 / ((1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2)
    R = 1.0 / (1.0 / R1 + 1.0 / R2)
    n = LEVELS_2D[level]
    a = a_target
    H = size * a

    def grid(n_per_a):
        md = mesh_spec(2, n_per_a, order, a_target=a, size=size, growth=growth)
        m = meshes.rectangle(*md["bounds"], *md["cells"], refine=md["refine"])
        return np.unique(m.p[0]), np.unique(m.p[1])  # x in [0, H], y in [-H, 0], fine near (0, 0)

    xs, ys = grid(n)
    xm, ym = grid(max(1.0, master_ratio * n))
    base = LinearElasticity(_curved(_block(xm, ym), R1, H, -1.0), Material(E=E1, nu=nu1, plane="strain"),
                            order=order)
    top = LinearElasticity(_curved(_block(xs, -ys[::-1]), R2, H, +1.0), Material(E=E2, nu=nu2, plane="strain"),
                           order=order)
    load = math.pi * a * a * e_star / (4 * R)  # the full Hertz load of a_target
    delta = 2 * load / (math.pi * e_star) * (math.log(2 * H / a) + 0.1)
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))
    supports = [Support("body0/bottom"), Support("body0/left", components=[0]),
                Support("body1/left", components=[0]), Support("body1/top", components=[1], value=-delta)]
    ref = HertzReference("cylinder", R, e_star, symmetry=2.0)
    meta = {"delta": delta, "h": a / n, "symmetry_axis": 0, "center": (0.0, 0.0), "e_star": e_star, "radius": R}
    return ContactProblem(bodies=[base, top], pairs=[pair], supports=supports, reference=ref, meta=meta,
                          name=f"two elastic cylinders (R={R:g}, E*={e_star:g}, {n} elements per a, P{order})")


def rigid_limit_pair(level: int = 0, *, E: float = 200e3, nu: float = 0.3, radius: float = 10.0,
                     stiffening: float = 1e6, a_target: float = 1.0, size: float = 20.0):
    """An elastic cylinder on a flat base: the base rigid, and the base an elastic body ``stiffening`` times stiffer.

    Returns ``(rigid, elastic)``. The cylinder is modelled as in :func:`hertz_cylinders` (a block whose
    bottom has the profile :math:`x^2/(2R)`, half model ``x >= 0``, its top pushed down by the
    approach, ``u_x = 0`` on ``left``); it is the slave. ``rigid``: the base is the half-space
    ``y <= 0`` (a rigid obstacle, node-to-surface gaps (6.15)); ``elastic``: the base is the block
    ``[0, size a] x [-size a, 0]`` of modulus ``stiffening * E`` fixed at its bottom, the master of a
    mortar pair. Against a flat master the mortar gap is the node-to-surface one
    (:mod:`alcontact.contact.kinematics._mortar`), so the elastic pair tends to the rigid one as
    ``stiffening`` grows, the difference being the base's compliance.
    """
    from ..contact import obstacles

    n = LEVELS_2D[level]
    a = a_target
    H = size * a
    mat = Material(E=E, nu=nu, plane="strain")
    e_prime = mat.plane_strain_modulus
    load = math.pi * a * a * e_prime / (4 * radius)
    delta = 2 * load / (math.pi * e_prime) * (math.log(2 * H / a) + 0.1)
    md = mesh_spec(2, n, 1, a_target=a, size=size)
    m = meshes.rectangle(*md["bounds"], *md["cells"], refine=md["refine"])
    xs, ys = np.unique(m.p[0]), np.unique(m.p[1])
    cylinder = _curved(_block(xs, -ys[::-1]), radius, H, +1.0)
    drive = [Support("left", components=[0]), Support("top", components=[1], value=-delta)]
    rigid = ContactProblem(model=LinearElasticity(cylinder, mat),
                           obstacle=obstacles.make("half-space", point=[0.0, 0.0], normal=[0.0, 1.0]),
                           contact_boundary="bottom", supports=drive, name="elastic cylinder on a rigid flat")
    top = LinearElasticity(cylinder, mat)
    base = LinearElasticity(_block(xs, ys), Material(E=stiffening * E, nu=nu, plane="strain"))
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))
    elastic = ContactProblem(bodies=[base, top], pairs=[pair],
                             supports=[Support("body0/bottom"), Support("body0/left", components=[0]),
                                       Support("body1/left", components=[0]),
                                       Support("body1/top", components=[1], value=-delta)],
                             name=f"elastic cylinder on a flat base {stiffening:g} times stiffer")
    return rigid, elastic
