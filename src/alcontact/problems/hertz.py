r"""Hertz contact problems with their analytical references.

2D (plane strain): a rigid cylinder of radius R pressed into an elastic block by a
prescribed approach :math:`\delta`. For a total load P per unit thickness
(Johnson, *Contact Mechanics*, 1985, eq. 4.45-4.47),

.. math::

    a = \sqrt{\frac{4PR}{\pi E^*}}, \qquad p_0 = \frac{2P}{\pi a}, \qquad
    p(x) = p_0\sqrt{1 - x^2/a^2}, \qquad E^* = \frac{E}{1-\nu^2}.

3D: a rigid sphere of radius R (Johnson eq. 4.22-4.23),

.. math::

    a = \left(\frac{3PR}{4E^*}\right)^{1/3}, \qquad p_0 = \frac{3P}{2\pi a^2}.

The problems are displacement controlled (``drive``, :data:`DRIVES`: the approach comes
from the obstacle's position, from a prescribed displacement of the block's bottom, a
bonded platen, from a body force, from a pressure on a body held only by the obstacle, or
from a mix); the "exact" width and peak pressure
are those of the half-space under the load the finite element model carries
(its total contact force), so they are exact for that load as long as the block
is large compared with ``a`` (here 20 a). Symmetry: the 2D model is the half
``x >= 0``, the 3D model the quarter ``x, y >= 0``; the reference uses the total
load (2 resp. 4 times the model's contact force).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..contact import BodyForce, ContactProblem, Pressure, Support
from ..contact.obstacles import Circle, HalfSpace, Sphere
from ..errors import UnknownNameError
from ..fem import LinearElasticity, Material, meshes
from .half_cylinder import disc_mesh

__all__ = ["HertzReference", "hertz_2d", "hertz_3d", "hertz_axisym", "hertz_disc", "LEVELS_2D", "LEVELS_3D",
           "LEVELS_AXISYM", "mesh_spec", "DRIVES", "DISC_DRIVES"]


@dataclass(frozen=True)
class HertzReference:
    """Analytical Hertz solution for a rigid cylinder (2D) or sphere (3D) on a half-space."""

    kind: str  # "cylinder" or "sphere"
    radius: float
    e_star: float
    symmetry: float  # total load / model load

    #: the analytical pressure is the profile p0 sqrt(1 - r^2/a^2): estimators fit it
    hertz_profile = True

    def load(self, model_force: float) -> float:
        return self.symmetry * model_force

    def half_width(self, load: float) -> float:
        if self.kind == "cylinder":
            return math.sqrt(4 * load * self.radius / (math.pi * self.e_star))
        return (3 * load * self.radius / (4 * self.e_star)) ** (1 / 3)

    def peak_pressure(self, load: float) -> float:
        a = self.half_width(load)
        if self.kind == "cylinder":
            return 2 * load / (math.pi * a)
        return 3 * load / (2 * math.pi * a * a)

    def pressure(self, r, load: float) -> np.ndarray:
        a, p0 = self.half_width(load), self.peak_pressure(load)
        r = np.asarray(r, dtype=float)
        return p0 * np.sqrt(np.clip(1 - (r / a) ** 2, 0.0, None))


#: elements per contact half-width ``a`` on the fine zone, by refinement level
LEVELS_2D = (8, 16, 32, 64, 128, 256)
LEVELS_3D = (4, 6, 8, 12, 16, 24)
LEVELS_AXISYM = LEVELS_2D


#: what moves the block into contact (``drive`` of :func:`hertz_2d` / :func:`hertz_3d`); the approach
#: :math:`\delta` is the same for every drive (for ``force`` and ``pressure`` an estimate, see :func:`_drive`)
DRIVES = {
    "obstacle": "the obstacle placed delta into the block, bottom fixed",
    "platen": "obstacle touching the block; the bottom (a bonded platen) pushed up by delta",
    "force": "obstacle touching the block, bottom fixed; an upward body force that lifts the top by about delta",
    "pressure": "obstacle touching the block, bottom on rollers (held by the obstacle only); a pressure on the "
                "bottom with the Hertz load of the intended half-width",
    "mix": "a third of delta from each of obstacle, platen and body force",
}


def _drive(drive: str, dim: int, delta: float, e_prime: float, height: float, load: float, width: float):
    r"""Obstacle approach, supports and loads of a ``drive`` of :data:`DRIVES`.

    The body force :math:`b = 2E'\delta_b/H^2` lifts the top of a column of height ``H``
    with a fixed bottom by :math:`\delta_b` under uniaxial strain; the block's top centre
    moves 0.91-0.98 of that (measured, 2D and 3D meshes of this module). The pressure
    drive carries ``load`` (the model's share of the Hertz load of ``a_target``) on the
    bottom of side ``width``.
    """
    if not isinstance(drive, str) or drive not in DRIVES:
        raise UnknownNameError("drive", str(drive), list(DRIVES))
    up = dim - 1
    tangential = tuple(range(up))
    sym = (Support("left", components=(0,)),) + ((Support("front", components=(1,)),) if dim == 3 else ())
    share = {"obstacle": (1, 0, 0), "platen": (0, 1, 0), "force": (0, 0, 1), "mix": (1 / 3, 1 / 3, 1 / 3),
             "pressure": (0, 0, 0)}[drive]
    if drive == "pressure":
        return 0.0, (Support("bottom", components=tangential),) + sym, (Pressure("bottom", load / width ** up),)
    supports = (Support("bottom", components=tangential), Support("bottom", components=(up,), value=share[1] * delta))
    loads = ()
    if share[2]:
        b = np.zeros(dim)
        b[up] = 2 * e_prime * share[2] * delta / height ** 2
        loads = (BodyForce(tuple(b)),)
    if not share[1]:
        supports = (Support("bottom"),)
    return share[0] * delta, supports + sym, loads


def mesh_spec(dim: int, n_per_a: int, order: int = 1, *, a_target: float = 1.0, size: float | None = None,
              growth: float | None = None) -> dict:
    """Arguments of the graded block mesh of :func:`hertz_2d` (``dim=2``) or :func:`hertz_3d` (``dim=3``).

    A ``[mesh]`` table (``bounds``, ``cells``, ``refine``) as a problem file
    writes it, so that :mod:`alcontact.io.preflight` can count the nodes before
    anything is meshed (``alcontact run --problem NAME --level L``).
    """
    from .._options import VALUE_RANGE, Option, check_args

    dim, n_per_a, order, a_target, size, growth = check_args("mesh_spec", [
        (Option("dim", "int", 2, "Dimension.", low=2, high=3), dim),
        (Option("n_per_a", "float", 8, "Elements per a.", low=0.01, high=4096), n_per_a),
        (Option("order", "int", 1, "Order.", low=1, high=2), order),
        (Option("a_target", "float", 1.0, "Half-width.", low=VALUE_RANGE[0], high=VALUE_RANGE[1]), a_target),
        (Option("size", "float", None, "Block size / a.", low=1.0, high=1e6, low_open=True), size),
        (Option("growth", "float", None, "Grading ratio.", low=1.0, high=10.0), growth)])
    a = a_target
    if dim == 2:
        L = H = (20.0 if size is None else size) * a
        return dict(bounds=[0.0, L, -H, 0.0], cells=[8, 8],
                    refine=dict(center=[0.0, 0.0], h_min=a / n_per_a / order, width=1.6 * a, depth=1.0 * a,
                                growth=1.15 if growth is None else growth))
    L = H = (12.0 if size is None else size) * a
    return dict(bounds=[0.0, L, 0.0, L, -H, 0.0], cells=[4, 4, 4],
                refine=dict(center=[0.0, 0.0, 0.0], h_min=a / n_per_a / order, width=1.5 * a, depth=1.0 * a,
                            growth=1.3 if growth is None else growth))


def _checked(where: str, levels: tuple, level, order, n_per_a, radius, a_target, size, growth, *, integer: bool):
    """The arguments of :func:`hertz_2d` / :func:`hertz_3d` checked (InputError naming the parameter and the fix)."""
    from .._options import VALUE_RANGE, Option, check_args

    lo, hi = VALUE_RANGE
    return check_args(where, [
        (Option("level", "int", 1, "Refinement level.", low=0, high=len(levels) - 1), level),
        (Option("order", "int", 1, "Polynomial order.", low=1, high=2), order),
        (Option("n_per_a", "int" if integer else "float", None, "Elements per a.", low=1, high=4096), n_per_a),
        (Option("radius", "float", 10.0, "Radius.", low=lo, high=hi), radius),
        (Option("a_target", "float", 1.0, "Contact half-width.", low=lo, high=hi), a_target),
        (Option("size", "float", 20.0, "Block size in units of a.", low=1.0, high=1e6, low_open=True), size),
        (Option("growth", "float", 1.15, "Grading ratio.", low=1.0, high=10.0), growth),
    ])


def hertz_2d(level: int = 1, *, order: int = 1, E: float = 200e3, nu: float = 0.3, radius: float = 10.0,
             a_target: float = 1.0, size: float = 20.0, n_per_a: int | None = None,
             growth: float = 1.15, drive: str = "obstacle") -> ContactProblem:
    """Rigid cylinder on an elastic block, plane strain, half model ``x >= 0``.

    Parameters
    ----------
    level : int
        Refinement level (index into :data:`LEVELS_2D`: elements per ``a``).
    order : {1, 2}
    E, nu : float
        Young's modulus (e.g. MPa) and Poisson's ratio.
    radius : float
        Cylinder radius R (mm); ``a_target / radius`` is about 0.1.
    a_target : float
        Intended contact half-width; sets the approach and the fine zone.
    size : float
        Block width (half model) and depth in units of ``a_target``.
    n_per_a : int, optional
        Overrides ``level``.
    growth : float
        Size ratio of neighbouring elements away from the fine zone (closer to 1 = more DOFs).
    drive : str
        What moves the block into contact, one of :data:`DRIVES`.
    """
    level, order, n_per_a, radius, a_target, size, growth = _checked("hertz_2d", LEVELS_2D, level, order, n_per_a,
                                                                     radius, a_target, size, growth, integer=True)
    mat = Material(E=E, nu=nu, plane="strain")
    e_star = mat.plane_strain_modulus
    n = n_per_a or LEVELS_2D[level]
    a = a_target
    L = H = size * a
    h = a / n
    md = mesh_spec(2, n, order, a_target=a, size=size, growth=growth)
    mesh = meshes.rectangle(*md["bounds"], *md["cells"], refine=md["refine"])
    model = LinearElasticity(mesh, mat, order=order)
    # approach giving a ~ a_target for this block (calibrated once, see docs/verification.md)
    load = math.pi * a * a * e_star / (4 * radius)
    delta = 2 * load / (math.pi * e_star) * (math.log(2 * H / a) + 0.1)
    approach, supports, loads = _drive(drive, 2, delta, e_star, H, load / 2, L)
    obstacle = Circle(center=(0.0, radius - approach), radius=radius)
    ref = HertzReference("cylinder", radius, e_star, symmetry=2.0)
    return ContactProblem(
        model=model,
        obstacle=obstacle,
        contact_boundary="top",
        supports=supports,
        loads=loads,
        name=f"hertz-2d (R={radius:g}, {n} elements per a, P{order})" + ("" if drive == "obstacle" else f", {drive}"),
        reference=ref,
        meta={"delta": delta, "h": h, "symmetry_axis": 0, "center": (0.0, 0.0), "drive": drive},
    )


def hertz_3d(level: int = 1, *, order: int = 1, E: float = 200e3, nu: float = 0.3, radius: float = 10.0,
             a_target: float = 1.0, size: float = 12.0, n_per_a: float | None = None,
             growth: float = 1.3, drive: str = "obstacle") -> ContactProblem:
    """Rigid sphere on an elastic block, quarter model ``x, y >= 0`` (parameters as :func:`hertz_2d`, ``drive`` included;
    ``n_per_a`` may be fractional, e.g. 1.5 for a P2 sweep between 1 and 2 elements per ``a``)."""
    level, order, n_per_a, radius, a_target, size, growth = _checked("hertz_3d", LEVELS_3D, level, order, n_per_a,
                                                                     radius, a_target, size, growth, integer=False)
    mat = Material(E=E, nu=nu)
    e_star = mat.plane_strain_modulus
    n = n_per_a or LEVELS_3D[level]
    a = a_target
    L = H = size * a
    h = a / n
    md = mesh_spec(3, n, order, a_target=a, size=size, growth=growth)
    mesh = meshes.box(*md["bounds"], *md["cells"], refine=md["refine"])
    model = LinearElasticity(mesh, mat, order=order)
    delta = a * a / radius
    load = 4 * a ** 3 * e_star / (3 * radius)  # Hertz load of the half-width a (Johnson 4.22)
    approach, supports, loads = _drive(drive, 3, delta, e_star, H, load / 4, L)
    obstacle = Sphere(center=(0.0, 0.0, radius - approach), radius=radius)
    ref = HertzReference("sphere", radius, e_star, symmetry=4.0)
    return ContactProblem(
        model=model,
        obstacle=obstacle,
        contact_boundary="top",
        supports=supports,
        loads=loads,
        name=f"hertz-3d (R={radius:g}, {n} elements per a, P{order})" + ("" if drive == "obstacle" else f", {drive}"),
        reference=ref,
        meta={"delta": delta, "h": h, "symmetry_axis": 0, "center": (0.0, 0.0), "drive": drive},
    )


def hertz_axisym(level: int = 1, *, order: int = 1, E: float = 200e3, nu: float = 0.3, radius: float = 10.0,
                 a_target: float = 1.0, size: float = 20.0, n_per_a: int | None = None,
                 growth: float = 1.15) -> ContactProblem:
    r"""Rigid sphere on an elastic cylinder as a body of revolution (``geometry="axisymmetric"``).

    The r-z half cross-section ``0 <= r <= size a``, ``-size a <= z <= 0`` of the graded mesh of
    :func:`hertz_2d` (the same levels, :data:`LEVELS_AXISYM`), bottom fixed, :math:`u_r = 0` on
    the axis ``r = 0`` (the boundary ``"left"``); the obstacle is the circle of radius R in the
    r-z plane, i.e. the sphere. The approach is the half-space one, :math:`\delta = a^2/R`
    (Johnson eq. 4.23). Forces are totals over the revolution, so the reference takes the
    model's force as the load (``symmetry = 1``): Johnson eq. 4.22-4.23,
    :math:`a = (3PR/4E^*)^{1/3}`, :math:`p_0 = 3P/(2\pi a^2)`. Parameters as :func:`hertz_2d`.
    """
    level, order, n_per_a, radius, a_target, size, growth = _checked("hertz_axisym", LEVELS_AXISYM, level, order,
                                                                     n_per_a, radius, a_target, size, growth,
                                                                     integer=True)
    mat = Material(E=E, nu=nu)
    e_star = mat.plane_strain_modulus
    n = n_per_a or LEVELS_AXISYM[level]
    a = a_target
    md = mesh_spec(2, n, order, a_target=a, size=size, growth=growth)
    mesh = meshes.rectangle(*md["bounds"], *md["cells"], refine=md["refine"])
    model = LinearElasticity(mesh, mat, order=order, geometry="axisymmetric")
    delta = a * a / radius
    return ContactProblem(
        model=model,
        obstacle=Circle(center=(0.0, radius - delta), radius=radius),
        contact_boundary="top",
        supports=(Support("bottom"), Support("left", components=(0,))),
        name=f"hertz-axisym (R={radius:g}, {n} elements per a, P{order})",
        reference=HertzReference("sphere", radius, e_star, symmetry=1.0),
        meta={"delta": delta, "h": a / n, "symmetry_axis": 0, "center": (0.0, 0.0), "drive": "obstacle"},
    )


#: what presses the half disc of :func:`hertz_disc` on the plane
DISC_DRIVES = {
    "platen": "the flat face bonded to a platen pushed down by delta, the plane fixed",
    "obstacle": "the flat face fixed, the plane moved up by delta",
}


def hertz_disc(n: int = 118, *, order: int = 2, E: float = 200e3, nu: float = 0.3, radius: float = 10.0,
               delta: float | None = None, drive: str = "platen", curved: bool = True) -> ContactProblem:
    r"""An elastic half disc pressed on a rigid plane, plane strain, the whole half disc (no symmetry plane).

    The half disc of radius :math:`R` lies with its flat face on top (:math:`y = R`) and its curved
    face on the plane :math:`y = 0`, touching it at the origin, meshed by the elliptical-grid map of
    :func:`alcontact.problems.half_cylinder.disc_mesh` (``2n`` by ``n`` cells of the rectangle
    :math:`[-1, 1] \times [0, 1]`, uniform: about :math:`16 n^2` DOFs with P2, 224k at the default
    ``n``; for P2 a second-order mesh whose boundary edges lie on the circle unless ``curved`` is
    False). ``drive`` (:data:`DISC_DRIVES`): a bonded platen, :math:`u = (0, -\delta)` on the flat face
    with the plane fixed, or the flat face fixed and the plane moved up by :math:`\delta`; both give
    the same contact (the two differ by a rigid translation of everything).

    Reference (Johnson, *Contact Mechanics*, 1985, eq. 4.45-4.47): a cylinder of radius :math:`R` on
    a rigid plane under the load :math:`P` per unit thickness, :math:`a = \sqrt{4PR/(\pi E^*)}`,
    :math:`E^* = E/(1-\nu^2)`, for :math:`a \ll R` (the load is the model's contact force, symmetry 1).
    The default :math:`\delta = 0.02 R` gives :math:`a/R` about 0.1.
    """
    from .._options import VALUE_RANGE, Option, check_args

    lo, hi = VALUE_RANGE
    n, order, radius = check_args("hertz_disc", [
        (Option("n", "int", 118, "Cells across the half disc's radius.", low=2, high=4096), n),
        (Option("order", "int", 2, "Polynomial order.", low=1, high=2), order),
        (Option("radius", "float", 10.0, "Radius.", low=lo, high=hi), radius)])
    if not isinstance(drive, str) or drive not in DISC_DRIVES:
        raise UnknownNameError("drive", str(drive), list(DISC_DRIVES))
    delta = 0.02 * radius if delta is None else delta
    (delta,) = check_args("hertz_disc", [(Option("delta", "float", 0.02 * radius, "Approach.", low=0.0,
                                                  high=0.5 * radius, low_open=True), delta)])
    mat = Material(E=E, nu=nu, plane="strain")
    mesh = disc_mesh(-1.0, 2 * n, n, radius=radius, second_order=order == 2 and curved)
    tol = 1e-9 * radius
    mesh = mesh.with_boundaries({"top": lambda x: x[1] > radius - tol, "curved": lambda x: x[1] < radius - tol})
    model = LinearElasticity(mesh, mat, order=order)
    if drive == "platen":
        supports = (Support("top", components=(0,)), Support("top", components=(1,), value=-delta))
        plane = HalfSpace([0.0, 0.0], [0.0, 1.0])
    else:
        supports = (Support("top"),)
        plane = HalfSpace([0.0, delta], [0.0, 1.0])
    return ContactProblem(
        model=model,
        obstacle=plane,
        contact_boundary="curved",
        supports=supports,
        name=f"hertz-disc (R={radius:g}, n={n}, P{order}, {drive})",
        reference=HertzReference("cylinder", radius, mat.plane_strain_modulus, symmetry=1.0),
        meta={"delta": delta, "h": radius / (np.sqrt(2.0) * n), "symmetry_axis": 0, "center": (0.0, 0.0),
              "drive": drive},
    )
