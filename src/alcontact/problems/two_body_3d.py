r"""Two deformable bodies in contact in 3D (linear tetrahedra): stacked blocks and an elastic sphere on a block.

Both are solved with the 3D mortar pair of :class:`~alcontact.contact.BodySurface` (the
master is the lower body's top, :mod:`alcontact.contact.kinematics._mortar3d`) and a
:class:`~alcontact.fem.MultiBody` of the two bodies ``body0`` (lower) and ``body1`` (upper):
boundaries ``"body0/top"``, ``"body1/bottom"``, ...

- :func:`stacked_blocks_3d`: the contact patch test. Two blocks with non-matching meshes
  under a uniform pressure ``p`` on the top: the stress is uniaxial in both blocks and the
  interface pressure is ``p`` at every slave node (Taylor & Papadopoulos, 1991; Puso &
  Laursen, 2004, for 3D mortar).
- :func:`sphere_on_block`: an elastic sphere of radius :math:`R` pressed on an elastic
  block (Johnson, *Contact Mechanics*, 1985, eq. 4.22-4.23 with the effective modulus)

  .. math::

      \frac1{E^*} = \frac{1-\nu_1^2}{E_1} + \frac{1-\nu_2^2}{E_2}, \qquad
      a = \Big(\frac{3PR}{4E^*}\Big)^{1/3}, \qquad p_0 = \frac{3P}{2\pi a^2}.

  As for :func:`alcontact.problems.hertz.hertz_3d`, a quarter model ``x, y >= 0`` (symmetry
  planes ``left`` ``x = 0`` and ``front`` ``y = 0``); the sphere is modelled near the contact
  by a block of size ``size * a`` (Hertz's half-space) whose bottom has the sphere's
  paraboloid :math:`r^2/(2R)`; the reference is that of the load the model carries (four
  times its contact force).
- :func:`rigid_limit_sphere`: the same elastic sphere on a rigid flat and on a flat block
  ``stiffening`` times stiffer (the rigid limit of the mortar pair).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import skfem

from ..contact import BodySurface, Boundary, ContactPair, ContactProblem, Pressure, Support
from ..fem import LinearElasticity, Material, meshes
from .hertz import LEVELS_3D, HertzReference, mesh_spec

__all__ = ["stacked_blocks_3d", "sphere_on_block", "rigid_limit_sphere"]


def _box(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> skfem.MeshTet:
    """Tetrahedral tensor mesh of the grid ``x`` by ``y`` by ``z`` with boundaries left/right/front/back/bottom/top."""
    mesh = skfem.MeshTet.init_tensor(x, y, z)
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    tol = 1e-9 * max(np.ptp(x), np.ptp(y), np.ptp(z))
    sides = {"left": (0, x[0]), "right": (0, x[-1]), "front": (1, y[0]), "back": (1, y[-1]),
             "bottom": (2, z[0]), "top": (2, z[-1])}
    return mesh.with_boundaries({n: bf[np.abs(mid[a] - v) <= tol] for n, (a, v) in sides.items()})


def _symmetry(body: str) -> list[Support]:
    """Rollers on the symmetry planes ``x = 0`` (``left``) and ``y = 0`` (``front``) of ``body``."""
    return [Support(f"{body}/left", components=[0]), Support(f"{body}/front", components=[1])]


def stacked_blocks_3d(n_base: int = 2, n_top: int = 3, *, pressure: float = 10.0, E=(1000.0, 500.0),
                      nu=(0.3, 0.2), width: float = 1.0, height: float = 1.0,
                      distort: float = 0.0, seed: int = 0) -> ContactProblem:
    """Contact patch test in 3D: a block of ``n_top`` cells per side on one of ``n_base``.

    The base ``[0, width]^2 x [0, height]`` stands on rollers (``u_z = 0`` on its bottom); the top
    block ``[0, width]^2 x [height, 2 height]`` is held by the contact only (its vertical motion), a
    uniform ``pressure`` pushes its top down; rollers on ``left`` and ``front`` of both blocks.
    Slave: the top block's bottom; master: the base's top. The exact interface pressure is
    ``pressure``. ``distort``: the nodes inside the slave face move in its plane by up to
    ``distort`` times the cell size (random, ``seed``), so that the faces meet at general angles.
    """
    base = LinearElasticity(_box(*(np.linspace(0, width, n_base + 1),) * 2, np.linspace(0, height, n_base + 1)),
                            Material(E=E[0], nu=nu[0]))
    mesh = _box(*(np.linspace(0, width, n_top + 1),) * 2, np.linspace(height, 2 * height, n_top + 1))
    if distort:
        p = np.array(mesh.p, dtype=float)
        tol = 1e-9 * width
        inner = ((np.abs(p[2] - height) <= tol) & (p[0] > tol) & (p[0] < width - tol) & (p[1] > tol)
                 & (p[1] < width - tol))
        rng = np.random.default_rng(seed)
        p[:2, inner] += distort * (width / n_top) * rng.uniform(-1.0, 1.0, size=(2, int(inner.sum())))
        mesh = dataclasses.replace(mesh, doflocs=p)
    top = LinearElasticity(mesh, Material(E=E[1], nu=nu[1]))
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))
    return ContactProblem(bodies=[base, top], pairs=[pair],
                          supports=[Support("body0/bottom", components=[2]), *_symmetry("body0"), *_symmetry("body1")],
                          loads=[Pressure("body1/top", pressure)],
                          name=f"stacked blocks 3D {n_base}:{n_top}" + (f", distorted {distort:g}" if distort else ""),
                          meta={"pressure_exact": float(pressure)})


def _curved(mesh: skfem.MeshTet, radius: float, depth: float) -> skfem.MeshTet:
    """``mesh`` with its face ``z = 0`` bent up to the paraboloid ``r^2 / (2 radius)``, fading to 0 at ``z = depth``.

    Beyond ``r = radius / 2``, far from any contact, the profile continues along its tangent cone.
    """
    p = np.array(mesh.doflocs, dtype=float)
    fade = np.clip(1.0 - p[2] / depth, 0.0, 1.0)
    rc = 0.5 * radius
    r = np.hypot(p[0], p[1])
    profile = np.where(r <= rc, r ** 2 / (2.0 * radius), rc ** 2 / (2.0 * radius) + rc / radius * (r - rc))
    p[2] += profile * fade
    return dataclasses.replace(mesh, doflocs=p)


def _axes(n_per_a: float, a: float, size: float, growth: float):
    """Graded axes of the quarter block of :func:`alcontact.problems.hertz.hertz_3d`: x, y in [0, L], z in [-H, 0]."""
    md = mesh_spec(3, n_per_a, 1, a_target=a, size=size, growth=growth)
    m = meshes.box(*md["bounds"], *md["cells"], refine=md["refine"])
    return np.unique(m.p[0]), np.unique(m.p[1]), np.unique(m.p[2])


def _sphere(n_per_a: float, a: float, size: float, growth: float, radius: float) -> skfem.MeshTet:
    """The sphere's block ``[0, L]^2 x [0, H]``, fine near the bottom centre, bottom bent to the paraboloid."""
    x, y, z = _axes(n_per_a, a, size, growth)
    return _curved(_box(x, y, -z[::-1]), radius, size * a)


def sphere_on_block(level: int = 0, *, E=(200e3, 70e3), nu=(0.3, 0.35), radius: float = 10.0,
                    a_target: float = 1.0, size: float = 12.0, master_ratio: float = 0.75, growth: float = 1.3,
                    n_per_a: float | None = None) -> ContactProblem:
    """An elastic sphere on an elastic block, quarter model ``x, y >= 0`` (module doc).

    Parameters
    ----------
    level : int
        Refinement level (:data:`alcontact.problems.hertz.LEVELS_3D`: elements per ``a`` on the slave).
    E, nu : pair of float
        Constants of the block (``body0``, the master) and of the sphere (``body1``, the slave).
    radius : float
        The sphere's radius :math:`R` (the block is flat).
    a_target : float
        Intended contact radius: sets the approach, the fine zone and the block size.
    size : float
        Width and depth of each block in units of ``a_target``.
    master_ratio : float
        Elements per ``a`` of the master over the slave's (non-matching meshes).
    growth : float
        Grading ratio away from the contact.
    n_per_a : float, optional
        Overrides ``level``.
    """
    (E1, E2), (nu1, nu2) = E, nu
    e_star = 1.0 / ((1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2)
    n = float(n_per_a) if n_per_a is not None else LEVELS_3D[level]
    a = a_target
    x, y, z = _axes(max(1.0, master_ratio * n), a, size, growth)
    block = LinearElasticity(_box(x, y, z), Material(E=E1, nu=nu1))
    sphere = LinearElasticity(_sphere(n, a, size, growth, radius), Material(E=E2, nu=nu2))
    delta = a * a / radius  # Hertz's approach of two half-spaces at the contact radius a (Johnson 4.23)
    pair = ContactPair(Boundary(sphere, "bottom"), BodySurface(block, "top"))
    supports = [Support("body0/bottom"), *_symmetry("body0"), *_symmetry("body1"),
                Support("body1/top", components=[2], value=-delta)]
    ref = HertzReference("sphere", radius, e_star, symmetry=4.0)
    meta = {"delta": delta, "h": a / n, "symmetry_axis": 0, "center": (0.0, 0.0, 0.0), "e_star": e_star,
            "radius": radius}
    return ContactProblem(bodies=[block, sphere], pairs=[pair], supports=supports, reference=ref, meta=meta,
                          name=f"elastic sphere on a block (R={radius:g}, E*={e_star:g}, {n:g} elements per a)")


def rigid_limit_sphere(level: int = 0, *, E: float = 200e3, nu: float = 0.3, radius: float = 10.0,
                       stiffening: float = 1e6, a_target: float = 1.0, size: float = 12.0, growth: float = 1.3,
                       n_per_a: float | None = None):
    """An elastic sphere on a flat: the flat rigid, and the flat an elastic block ``stiffening`` times stiffer.

    Returns ``(rigid, elastic)``. The sphere is modelled as in :func:`sphere_on_block` (the slave,
    its top pushed down by the approach, rollers on its symmetry planes). ``rigid``: the flat is the
    half-space ``z <= 0`` (node-to-surface gaps (6.15)); ``elastic``: the block ``[0, size a]^2 x
    [-size a, 0]`` of modulus ``stiffening * E`` with the sphere's own grid, fixed at its bottom, the
    master of a mortar pair. Against a flat master the mortar gap is the node-to-surface one
    (:mod:`alcontact.contact.kinematics._mortar3d`), so the elastic pair tends to the rigid one as
    ``stiffening`` grows, the difference being the block's compliance.
    """
    from ..contact import obstacles

    n = float(n_per_a) if n_per_a is not None else LEVELS_3D[level]
    a = a_target
    mat = Material(E=E, nu=nu)
    delta = a * a / radius
    x, y, z = _axes(n, a, size, growth)
    sphere_mesh = _curved(_box(x, y, -z[::-1]), radius, size * a)
    drive = [Support("left", components=[0]), Support("front", components=[1]),
             Support("top", components=[2], value=-delta)]
    rigid = ContactProblem(model=LinearElasticity(sphere_mesh, mat),
                           obstacle=obstacles.make("half-space", point=[0.0, 0.0, 0.0], normal=[0.0, 0.0, 1.0]),
                           contact_boundary="bottom", supports=drive, name="elastic sphere on a rigid flat")
    sphere = LinearElasticity(sphere_mesh, mat)
    block = LinearElasticity(_box(x, y, z), Material(E=stiffening * E, nu=nu))
    pair = ContactPair(Boundary(sphere, "bottom"), BodySurface(block, "top"))
    elastic = ContactProblem(bodies=[block, sphere], pairs=[pair],
                             supports=[Support("body0/bottom"), *_symmetry("body0"), *_symmetry("body1"),
                                       Support("body1/top", components=[2], value=-delta)],
                             name=f"elastic sphere on a flat block {stiffening:g} times stiffer")
    return rigid, elastic
