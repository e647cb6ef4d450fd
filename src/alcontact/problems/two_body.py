r"""Two deformable bodies in contact (2D, plane strain): stacked blocks and two elastic cylinders.

Both are solved with the mortar pair of :class:`~alcontact.contact.BodySurface` (the master
is the lower body's top) and a :class:`~alcontact.fem.MultiBody` of the two bodies named
``"base"`` (lower) and ``"top"`` (upper): boundaries ``"base/top"``, ``"top/bottom"``, ...

- :func:`stacked_blocks`: the contact patch test. Two blocks with non-matching meshes,
  a uniform pressure ``p`` on the top: the stress is uniaxial in both blocks and the
  interface pressure is ``p`` at every slave node (Taylor & Papadopoulos, 1991; the
  mortar method passes it on non-matching meshes, node-to-segment does not).
- :func:`compressed_blocks`: the contact patch test at finite deformation. Two neo-Hookean
  blocks of one material with non-matching meshes, the upper one's top pushed down (lateral
  motion free): both deform homogeneously, :math:`F = \operatorname{diag}(\lambda_1,
  \lambda_2)` with :math:`P_{11} = 0`, and the interface carries the nominal pressure
  :math:`-P_{22}` at every slave node while the interface nodes slide with the lateral
  expansion.
- :func:`ironing_two_body`: a neo-Hookean rounded punch pressed into a neo-Hookean block and
  slid along it (large sliding between two deformable bodies; the punch is the slave).
- :func:`seal`: a neo-Hookean cord (a disc in plane strain) squeezed between two deformable
  plates: two two-body pairs, the cord the slave of both.
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
from ..errors import InputError
from ..fem import Hyperelastic, LinearElasticity, Material, meshes
from .hertz import LEVELS_2D, HertzReference, mesh_spec

__all__ = ["stacked_blocks", "compressed_blocks", "hertz_cylinders", "rigid_limit_pair", "rigid_limit_punch",
           "ironing_two_body", "ironing_two_body_history", "seal"]


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
                    order: int = 1, kinematics: str = "small") -> ContactProblem:
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
    kinematics : {"small", "finite"}
        ``"finite"``: neo-Hookean bodies with the same initial moduli, the gap at the current
        configuration (P1 only).
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
    body = _body_class(kinematics)
    base = body(_curved(_block(xm, ym), R1, H, -1.0), Material(E=E1, nu=nu1, plane="strain"), order=order)
    top = body(_curved(_block(xs, -ys[::-1]), R2, H, +1.0), Material(E=E2, nu=nu2, plane="strain"), order=order)
    load = math.pi * a * a * e_star / (4 * R)  # the full Hertz load of a_target
    delta = 2 * load / (math.pi * e_star) * (math.log(2 * H / a) + 0.1)
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))
    supports = [Support("body0/bottom"), Support("body0/left", components=[0]),
                Support("body1/left", components=[0]), Support("body1/top", components=[1], value=-delta)]
    ref = HertzReference("cylinder", R, e_star, symmetry=2.0)
    meta = {"delta": delta, "h": a / n, "symmetry_axis": 0, "center": (0.0, 0.0), "e_star": e_star, "radius": R}
    return ContactProblem(bodies=[base, top], pairs=[pair], supports=supports, reference=ref, meta=meta,
                          kinematics=kinematics,
                          name=f"two elastic cylinders (R={R:g}, E*={e_star:g}, {n} elements per a, P{order})")


def _body_class(kinematics: str):
    """The body of a kinematics: linear elastic (``"small"``) or neo-Hookean (``"finite"``)."""
    if kinematics not in ("small", "finite"):
        raise InputError(f"kinematics = {kinematics!r}: expected 'small' or 'finite'.")
    return LinearElasticity if kinematics == "small" else Hyperelastic


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


def compressed_blocks(n_base: int = 2, n_top: int = 3, *, strain: float = 0.1, E: float = 1000.0, nu: float = 0.3,
                      width: float = 1.0, height: float = 1.0, kinematics: str = "finite") -> ContactProblem:
    r"""Contact patch test at finite deformation (module doc): two neo-Hookean blocks compressed together.

    The base ``[0, width] x [0, height]`` stands on rollers (``u_y = 0`` on its bottom), the upper block
    ``[0, width] x [height, 2 height]`` has its top pushed down by ``2 strain height`` (``u_y`` prescribed,
    lateral motion free); rollers ``u_x = 0`` on both left sides. Both blocks are of one material, so their
    lateral stretches are equal and the interface stays covered end to end. Slave: the upper block's bottom
    (``n_top`` segments), master: the base's top (``n_base`` segments). ``meta["stretch"]`` is the vertical
    stretch :math:`\lambda_2 = 1 - \text{strain}` of each block; the run is load-stepped
    (:func:`alcontact.contact.solve` with ``steps=``). ``kinematics="small"``: the same blocks linear
    elastic, the gap linearized at the reference configuration (the small-strain limit).
    """
    mat = Material(E=E, nu=nu, plane="strain")
    body = _body_class(kinematics)
    base = body(_block(np.linspace(0, width, n_base + 1), np.linspace(0, height, n_base + 1)), mat)
    top = body(_block(np.linspace(0, width, n_top + 1), np.linspace(height, 2 * height, n_top + 1)), mat)
    pair = ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))
    return ContactProblem(bodies=[base, top], pairs=[pair], kinematics=kinematics,
                          supports=[Support("body0/bottom", components=[1]), Support("body0/left", components=[0]),
                                    Support("body1/left", components=[0]),
                                    Support("body1/top", components=[1], value=-2.0 * strain * height)],
                          name=f"compressed blocks {n_base}:{n_top} (strain {strain:g})",
                          meta={"stretch": 1.0 - float(strain), "E": float(E), "nu": float(nu), "width": float(width)})


def _rounded_punch(radius: float, n: int, x0: float) -> skfem.MeshTri:
    """The punch ``[x0 - R, x0 + R] x [0, R]`` with ``2n x n`` cells, its bottom bent up to the profile
    ``x^2 / (2R)`` (tangent beyond ``|x| = R/2``, :func:`_curved`), touching ``y = 0`` at ``x0``."""
    m = _curved(_block(np.linspace(-radius, radius, 2 * n + 1), np.linspace(0.0, radius, n + 1)), radius, radius,
                +1.0)  # the face y = 0 bent up, fading to the flat top y = R
    p = np.array(m.doflocs, dtype=float)
    p[0] += x0
    m = dataclasses.replace(m, doflocs=p)
    bf = m.boundary_facets()
    mid = m.p[:, m.facets[:, bf]].mean(axis=1)
    tol = 1e-9 * radius
    top = bf[np.abs(mid[1] - radius) <= tol]
    side = bf[(np.abs(np.abs(mid[0] - x0) - radius) <= tol)]
    bottom = np.setdiff1d(bf, np.concatenate([top, side]))
    return m.with_boundaries({"top": top, "sides": side, "bottom": bottom})


def ironing_two_body(n: int = 10, *, radius: float = 1.0, depth: float = 0.2, slide: float = 3.0,
                     slide_step: float = 0.05, press_steps: int = 4, height: float = 2.0, margin: float = 1.5,
                     E=(1000.0, 1000.0), nu=(0.3, 0.3), punch_ratio: float = 1.4,
                     model: str = "neo-hookean") -> ContactProblem:
    """Ironing between two deformable bodies (module doc): a rounded punch on a block, frictionless.

    The block ``[0, L] x [-height, 0]`` (``L = 2 margin + slide``, ``n`` elements per unit length) is
    clamped at its bottom; its top is the master. The punch (:func:`_rounded_punch`: half-width and
    height ``radius``, bottom profile of radius ``radius``, ``punch_ratio * n`` elements per unit length:
    non-matching meshes) touches the block at ``x = margin`` at ``t = 0``; its top is driven: pressed down
    by ``depth`` in ``press_steps`` steps, then slid along ``x`` by ``slide_step`` per step
    (:func:`ironing_two_body_history`). Bodies ``body0`` (block, ``E[0]``, ``nu[0]``) and ``body1`` (punch);
    the punch's bottom is the slave. Frictionless steady sliding of elastic bodies dissipates nothing, so
    the horizontal force tends to zero far from the block's ends (no closed form at finite deformation).
    """
    length = 2.0 * margin + slide
    cells = lambda ext, k=1.0: max(1, int(round(ext * n * k)))  # noqa: E731
    block = Hyperelastic(_block(np.linspace(0.0, length, cells(length) + 1), np.linspace(-height, 0.0,
                                                                                         cells(height) + 1)),
                         Material(E=E[0], nu=nu[0], plane="strain"), model=model)
    punch = Hyperelastic(_rounded_punch(radius, cells(radius, punch_ratio), margin),
                         Material(E=E[1], nu=nu[1], plane="strain"), model=model)
    pair = ContactPair(Boundary(punch, "bottom"), BodySurface(block, "top", search_distance=0.5 * radius))
    slide_steps = int(round(slide / slide_step))
    return ContactProblem(
        bodies=[block, punch], pairs=[pair], kinematics="finite",
        supports=[Support("body0/bottom", components=[0, 1])],
        name=f"two-body ironing (R={radius:g}, depth={depth:g}, n={n}, {model})",
        meta={"radius": radius, "depth": float(depth), "n": n, "press_steps": int(press_steps),
              "slide_step": float(slide_step), "slide_steps": slide_steps, "x0": float(margin)})


def ironing_two_body_history(problem: ContactProblem):
    """``(history, times)`` of :func:`ironing_two_body`: steps ``1 .. press_steps`` press the punch's top down
    by ``depth``, the ``slide_steps`` after them slide it along ``x`` by ``slide_step`` each (for
    :func:`alcontact.contact.solve` with ``history=`` and ``steps=``)."""
    from ..contact import LoadCase, LoadHistory, Ramp

    meta = problem.meta
    npress, nslide = meta["press_steps"], meta["slide_steps"]
    end = float(npress + nslide)
    press = LoadCase(Support("body1/top", components=[1], value=-meta["depth"]),
                     Ramp((0.0, float(npress), end), (0.0, 1.0, 1.0)), name="press")
    slide = LoadCase(Support("body1/top", components=[0], value=meta["slide_step"] * nslide),
                     Ramp((0.0, float(npress), end), (0.0, 0.0, 1.0)), name="slide")
    times = tuple(float(k) for k in range(1, npress + nslide + 1))
    return LoadHistory((press, slide), times=times), times


def rigid_limit_punch(n: int = 10, *, radius: float = 1.0, depth: float = 0.2, E: float = 1000.0, nu: float = 0.3,
                      stiffening: float = 1e6, punch_ratio: float = 1.4):
    """The rounded punch of :func:`ironing_two_body` pressed by ``depth`` at finite deformation: on a rigid
    flat, and on an elastic base ``stiffening`` times stiffer. Returns ``(rigid, elastic)``.

    ``rigid``: the punch alone against the half-space ``y <= 0`` (node-to-surface gap at the current
    configuration); ``elastic``: the punch (``body1``, slave) on the neo-Hookean block
    ``[-2R, 2R] x [-R, 0]`` (``body0``, master, clamped at its bottom) of modulus ``stiffening * E``. The
    punch's top is pushed down by ``depth`` (lateral motion free) over the load steps of
    :func:`alcontact.contact.solve`. Against a flat master the mortar gap is the distance to its line, so
    the two tend to each other as ``stiffening`` grows (the difference is the base's compliance).
    """
    from ..contact import obstacles

    mat = Material(E=E, nu=nu, plane="strain")
    mesh = _rounded_punch(radius, max(1, int(round(radius * n * punch_ratio))), 0.0)
    drive = [Support("top", components=[1], value=-depth), Support("top", components=[0])]
    rigid = ContactProblem(model=Hyperelastic(mesh, mat),
                           obstacle=obstacles.make("half-space", point=[0.0, 0.0], normal=[0.0, 1.0]),
                           contact_boundary="bottom", supports=drive, kinematics="finite",
                           name="rounded punch on a rigid flat")
    cells = max(1, int(round(radius * n)))
    base = Hyperelastic(_block(np.linspace(-2 * radius, 2 * radius, 4 * cells + 1),
                               np.linspace(-radius, 0.0, cells + 1)),
                        Material(E=stiffening * E, nu=nu, plane="strain"))
    punch = Hyperelastic(mesh, mat)
    pair = ContactPair(Boundary(punch, "bottom"), BodySurface(base, "top", search_distance=0.5 * radius))
    elastic = ContactProblem(bodies=[base, punch], pairs=[pair], kinematics="finite",
                             supports=[Support("body0/bottom"), Support("body1/top", components=[1], value=-depth),
                                       Support("body1/top", components=[0])],
                             name=f"rounded punch on a flat base {stiffening:g} times stiffer")
    return rigid, elastic


def _disc(radius: float, n: int) -> skfem.MeshTri:
    r"""The disc of ``radius`` about the origin: the elliptical-grid map of the square :math:`[-1, 1]^2` with
    ``2n x 2n`` cells, :math:`(\xi, \eta) \mapsto R(\xi\sqrt{1 - \eta^2/2}, \eta\sqrt{1 - \xi^2/2})`.

    Boundaries ``"lower"`` and ``"upper"`` (the half circles below and above ``y = 0``) and two lines of
    interior facets, ``"vertical"`` (``x = 0``) and ``"horizontal"`` (``y = 0``), the images of the square's
    middle lines (the symmetry lines of a symmetric squeeze).
    """
    sq = skfem.MeshTri.init_tensor(np.linspace(-1.0, 1.0, 2 * n + 1), np.linspace(-1.0, 1.0, 2 * n + 1))
    xi, eta = sq.doflocs
    p = radius * np.vstack([xi * np.sqrt(1.0 - eta ** 2 / 2.0), eta * np.sqrt(1.0 - xi ** 2 / 2.0)])
    m = dataclasses.replace(sq, doflocs=p)
    bf = m.boundary_facets()
    mid = m.p[:, m.facets].mean(axis=1)
    ends = m.p[:, m.facets]  # (2, 2, nf)
    tol = 1e-9 * radius
    on_x = np.all(np.abs(ends[0]) <= tol, axis=0)
    on_y = np.all(np.abs(ends[1]) <= tol, axis=0)
    return m.with_boundaries({"lower": bf[mid[1, bf] < 0.0], "upper": bf[mid[1, bf] > 0.0],
                              "vertical": np.flatnonzero(on_x), "horizontal": np.flatnonzero(on_y)})


def seal(n: int = 8, *, radius: float = 1.0, squeeze: float = 0.2, E=(10.0, 1000.0), nu=(0.45, 0.3),
         plate_width: float = 1.5, plate_height: float = 0.5, plate_ratio: float = 0.6,
         model: str = "neo-hookean") -> ContactProblem:
    """A neo-Hookean cord squeezed between two deformable plates (plane strain, finite deformation, frictionless).

    The cord (``body0``, :func:`_disc`: radius ``radius``, ``2n x 2n`` mapped cells, ``E[0]``, ``nu[0]``) lies
    between a lower plate ``[-w, w] x [-R - t, -R]`` (``body1``) and an upper one ``[-w, w] x [R, R + t]``
    (``body2``; ``w = plate_width R``, ``t = plate_height R``, ``E[1]``, ``nu[1]``, ``plate_ratio`` times the
    cord's boundary element density: non-matching meshes), touching both at ``t = 0``. The plates' outer faces
    are moved towards each other by ``squeeze R`` each (the cord's diameter shortened by ``2 squeeze R``),
    proportionally over the load steps of :func:`alcontact.contact.solve`. Two pairs: the cord's ``lower``
    boundary against the lower plate's ``top``, its ``upper`` boundary against the upper plate's ``bottom``
    (the cord is the slave of both). The squeeze is symmetric about both axes, which holds the cord without
    supports of its own: ``u_x = 0`` on its vertical diameter and ``u_y = 0`` on its horizontal one (the
    symmetry lines, interior facets; exact for this loading).
    """
    cord = Hyperelastic(_disc(radius, n), Material(E=E[0], nu=nu[0], plane="strain"), model=model)
    w, t = plate_width * radius, plate_height * radius
    cells = max(2, int(round(plate_ratio * 2 * n * w / radius)))
    rows = max(1, int(round(cells * t / (2 * w))))
    mat = Material(E=E[1], nu=nu[1], plane="strain")
    lower = Hyperelastic(_block(np.linspace(-w, w, cells + 1), np.linspace(-radius - t, -radius, rows + 1)), mat,
                         model=model)
    upper = Hyperelastic(_block(np.linspace(-w, w, cells + 1), np.linspace(radius, radius + t, rows + 1)), mat,
                         model=model)
    d = float(squeeze) * radius
    pairs = [ContactPair(Boundary(cord, "lower"), BodySurface(lower, "top", search_distance=0.5 * radius)),
             ContactPair(Boundary(cord, "upper"), BodySurface(upper, "bottom", search_distance=0.5 * radius))]
    supports = [Support("body0/vertical", components=[0]), Support("body0/horizontal", components=[1]),
                Support("body1/bottom", value=(0.0, d)), Support("body2/top", value=(0.0, -d))]
    return ContactProblem(bodies=[cord, lower, upper], pairs=pairs, supports=supports, kinematics="finite",
                          name=f"cord squeezed between two plates (R={radius:g}, squeeze {2 * squeeze:g} D/2, n={n})",
                          meta={"radius": radius, "squeeze": float(squeeze), "n": n})
