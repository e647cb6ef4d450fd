r"""Frictional contact test problems with analytical references (section 6.2).

``block_on_plane``
    An elastic block (2D plane strain or 3D) resting on a rigid half-space,
    pressed by a prescribed displacement of its top (first half of the load
    history), then sheared by a prescribed tangential displacement of the top
    (second half). With :math:`\nu = 0` the normal phase gives a uniform
    pressure and no shear; in full stick the shear is nearly uniform. Full
    sliding needs :math:`Q = \mu N` for *every* pressure distribution, which is
    the exact check: the tangential reaction saturates at :math:`\mu N`.

``cattaneo_mindlin_2d``
    A rigid cylinder (radius R) on a full-width elastic block (plane strain,
    :math:`\nu` close to 1/2 so that the normal and tangential problems
    decouple), loaded by moving the block's bottom: up by :math:`\delta` (normal
    phase, Hertz), then sideways (tangential phase). Cattaneo-Mindlin (Johnson,
    *Contact Mechanics*, 1985, section 7.1): for :math:`Q < \mu P` the contact
    :math:`|x| < a` has a central stick zone :math:`|x| < c`,

    .. math::

        \frac{c}{a} = \sqrt{1 - \frac{Q}{\mu P}}, \qquad
        q(x) = \mu p_0\left[\sqrt{1 - x^2/a^2} - \frac{c}{a}\sqrt{1 - x^2/c^2}\right]
        \ (|x| < c), \qquad q(x) = \mu p_0 \sqrt{1 - x^2/a^2}\ (c \le |x| < a).

    P and Q are the contact resultants the finite element model carries, and
    ``a``, ``p0`` the Hertz values for that P (see :mod:`alcontact.problems.hertz`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..contact import ContactProblem, LoadCase, LoadHistory, Ramp, Support
from ..contact.obstacles import Circle, HalfSpace, UserObstacle
from ..fem import LinearElasticity, Material, meshes
from .hertz import HertzReference

__all__ = ["block_on_plane", "cattaneo_mindlin_2d", "sphere_shear_3d", "MindlinReference"]


def block_on_plane(dim: int = 2, *, n: int = 8, E: float = 1000.0, nu: float = 0.0, width: float = 2.0,
                   height: float = 0.5, strain: float = 0.01, mu: float = 0.3, shear_ratio: float = 0.5,
                   direction=None, unload: bool = False, steps: int = 8):
    r"""Block on a rigid half-space, pressed then sheared through its top.

    Parameters
    ----------
    dim : {2, 3}
    n : int
        Elements across the width (the height gets ``max(2, n*height/width)``).
    E, nu : float
        Material; ``nu = 0`` keeps the normal phase free of shear.
    width, height : float
        Block ``[-w/2, w/2]^{d-1} x [0, height]``.
    strain : float
        Normal approach of the top over the height: top displacement
        :math:`-d`, :math:`d = \text{strain}\cdot\text{height}`.
    mu : float
        Friction coefficient stored in the problem.
    shear_ratio : float
        Tangential top displacement :math:`s` over :math:`s^* = \mu\, d\, E/G`,
        the displacement that brings a uniformly sheared block to :math:`Q = \mu N`
        (:math:`G = E/(2(1+\nu))`): below about 1 the block sticks, well above
        it slides.
    direction : sequence of d-1 floats, optional
        Tangential direction in the plane (3D default ``(1, 1)/sqrt 2``).
    unload : bool
        Shear up over ``t`` in [0.5, 0.75] and back to 0 over [0.75, 1].
    steps : int
        Number of equal load steps of the history.

    Returns
    -------
    problem : ContactProblem
    history : LoadHistory
    """
    from .._options import VALUE_RANGE, Option, check_args

    lo, hi = VALUE_RANGE
    dim, n, width, height, strain, mu, shear_ratio, steps = check_args("block_on_plane", [
        (Option("dim", "int", 2, "Dimension.", low=2, high=3), dim),
        (Option("n", "int", 8, "Cells across.", low=1, high=1000), n),
        (Option("width", "float", 2.0, "Width.", low=lo, high=hi), width),
        (Option("height", "float", 0.5, "Height.", low=lo, high=hi), height),
        (Option("strain", "float", 0.01, "Compression.", low=-hi, high=hi), strain),
        (Option("mu", "float", 0.3, "Friction coefficient.", low=0.0, high=hi), mu),
        (Option("shear_ratio", "float", 0.5, "Shear / limit.", low=-hi, high=hi), shear_ratio),
        (Option("steps", "int", 8, "Load steps.", low=1, high=100_000), steps)])
    mat = Material(E=E, nu=nu, plane="strain")
    half = 0.5 * width
    nz = max(2, int(round(n * height / width)))
    if dim == 2:
        mesh = meshes.rectangle(-half, half, 0.0, height, n, nz)
        normal = (0.0, 1.0)
        tdir = np.array([1.0]) if direction is None else np.asarray(direction, float)
    elif dim == 3:
        mesh = meshes.box(-half, half, -half, half, 0.0, height, n, n, nz)
        normal = (0.0, 0.0, 1.0)
        tdir = np.array([1.0, 1.0]) / math.sqrt(2) if direction is None else np.asarray(direction, float)
    else:
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    tdir = tdir / np.linalg.norm(tdir)
    model = LinearElasticity(mesh, mat)
    obstacle = HalfSpace(point=(0.0,) * dim, normal=normal)
    d = strain * height
    G = E / (2 * (1 + nu))
    s_star = mu * d * E / G  # tau = G s/H = mu p = mu E d/H (nu = 0 in plane strain)
    s = shear_ratio * s_star
    push = np.zeros(dim)
    push[-1] = -d
    shear = np.zeros(dim)
    shear[:-1] = s * tdir
    press = LoadCase(Support("top", components=(dim - 1,), value=tuple(push.tolist())),
                     Ramp((0.0, 0.5), (0.0, 1.0), hold_after=True), name="normal approach")
    if unload:
        amp = Ramp((0.5, 0.75, 1.0), (0.0, 1.0, 0.0))
    else:
        amp = Ramp((0.5, 1.0), (0.0, 1.0))
    tang = LoadCase(Support("top", components=tuple(range(dim - 1)), value=tuple(shear.tolist())), amp,
                    tangential=True, name="tangential displacement")
    problem = ContactProblem(
        model=model, obstacle=obstacle, contact_boundary="bottom", supports=(), friction=mu,
        name=f"block on plane ({dim}D, n={n}, mu={mu:g})",
        meta={"d": d, "s": s, "s_star": s_star, "direction": tdir, "height": height, "width": width},
    )
    return problem, LoadHistory((press, tang), LoadHistory.uniform(steps))


@dataclass(frozen=True)
class MindlinReference:
    """Cattaneo-Mindlin partial slip for a cylinder (plane strain), given P, Q and mu."""

    hertz: HertzReference
    mu: float

    def half_width(self, P: float) -> float:
        return self.hertz.half_width(P)

    def stick_half_width(self, P: float, Q: float) -> float:
        return self.half_width(P) * math.sqrt(max(0.0, 1.0 - abs(Q) / (self.mu * P)))

    def shear(self, x, P: float, Q: float) -> np.ndarray:
        """Magnitude of the shear traction :math:`q(x)` (same sign as Q on the body)."""
        a, p0 = self.hertz.half_width(P), self.hertz.peak_pressure(P)
        c = self.stick_half_width(P, Q)
        x = np.asarray(x, dtype=float)
        q = self.mu * p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0.0, None))
        if c > 0:
            q = q - np.where(np.abs(x) < c, self.mu * p0 * (c / a) * np.sqrt(np.clip(1 - (x / c) ** 2, 0, None)), 0.0)
        return q


def _parabolic_cylinder(radius: float) -> UserObstacle:
    return UserObstacle(
        gap=lambda x: x[:, 1] - x[:, 0] ** 2 / (2.0 * radius),
        normal=lambda x: np.broadcast_to(np.array([0.0, -1.0]), x.shape).copy(),
        dim=2, length_scale=radius, label=f"parabolic cylinder R={radius:g} (Hertz approximation)")


def cattaneo_mindlin_2d(n_per_a: int = 16, *, E: float = 200e3, nu: float = 0.49, radius: float = 10.0,
                        a_target: float = 1.0, size: float = 20.0, mu: float = 0.3, q_ratio: float = 0.5,
                        normal_steps: int = 4, tangential_steps: int = 4, order: int = 1,
                        geometry: str = "parabolic", frictionless_approach: bool = True,
                        volumetric: str = "full", growth: float = 1.15):
    r"""Rigid cylinder on a full-width block: Hertz normal load, then a tangential load Q < mu P.

    The block ``[-L, L] x [-H, 0]`` (``L = H = size * a_target``) touches the
    cylinder at the origin; its bottom moves up by :math:`\delta` over
    ``t`` in [0, 0.5] (the same approach as :func:`alcontact.problems.hertz.hertz_2d`),
    then sideways by :math:`s` over [0.5, 1]. :math:`s` is estimated from the
    full-stick compliance to give :math:`Q \approx` ``q_ratio`` :math:`\mu P`; the
    reference uses the Q and P the model actually carries.

    ``frictionless_approach=True`` (default) applies the normal phase with
    :math:`\\mu = 0` (friction factor of the history 0 until ``t = 0.5``): the
    Cattaneo-Mindlin hypothesis that the normal load creates no shear. With
    friction during the approach, linear triangles at :math:`\\nu = 0.49` (and also
    P2) lock and give spurious oscillating tangential surface displacements,
    which stick points keep as a locked-in shear of up to about 0.5 :math:`\\mu p_0`.

    Element order: at :math:`\nu = 0.49` linear triangles (``order=1``) lock
    volumetrically, which shrinks the stick zone: measured :math:`c/a - (c/a)_{exact}`
    = -0.152, -0.120, -0.068, -0.034 at 8, 16, 32, 64 elements per ``a`` (first
    order in h), independent of the number of tangential steps. Quadratic
    elements (``order=2``) converge like :math:`h^{1.7}`: -0.079, -0.021, -0.007 at
    4, 8, 16 elements per ``a`` (shear traction L2 error 0.128 at 8, 0.080 at 16),
    so use ``order=2`` for accuracy.

    Friction from the first step (``frictionless_approach=False``): the hypothesis
    holds for :math:`\nu = 1/2` in a half-plane. Use ``order=2, volumetric="p0"``
    (the locking-free P2-P0 element of :class:`~alcontact.fem.LinearElasticity`;
    standard P2 at :math:`\nu = 0.4999` gives a shear L2 error of 2.06),
    :math:`\nu = 0.4999` (at 0.49 the Goodman coupling leaves 0.13) and a large
    block: under the normal load the surface of a finite block stretches by about
    :math:`P/(E L)`, which stick points keep (shear error 0.20, 0.074, 0.051, 0.045 at
    ``size`` = 20, 80, 320, 1280, 16 elements per ``a``). With ``size=1280, growth=1.3``:
    :math:`c/a` error +0.0004, +0.0003, +0.0058 and shear L2 error 0.085, 0.045, 0.024
    at 8, 16, 32 elements per ``a`` (1 normal + 1 tangential step).
    ``volumetric`` is passed to :class:`~alcontact.fem.LinearElasticity`; ``growth`` is
    the size ratio of neighbouring elements of the graded mesh.

    ``geometry="parabolic"`` (default) is Hertz's own approximation: gap
    :math:`y - x^2/(2R)` along the fixed direction :math:`-e_y`, so the pressure
    acts vertically as in the half-space theory. With ``"circle"`` the obstacle
    normals tilt by :math:`x/R`; the horizontal components of the pressure
    (of order :math:`p\,a/R`) then add a locked-in antisymmetric shear during the
    normal phase, which the Cattaneo-Mindlin solution neglects.

    Returns
    -------
    problem : ContactProblem
        ``problem.reference`` is a :class:`MindlinReference`.
    history : LoadHistory
    """
    from .._options import VALUE_RANGE, Option, check_args

    lo, hi = VALUE_RANGE
    n_per_a, radius, a_target, size, mu, q_ratio, normal_steps, tangential_steps, order, growth = check_args(
        "cattaneo_mindlin_2d", [
            (Option("n_per_a", "float", 16, "Elements per a.", low=0.01, high=4096), n_per_a),
            (Option("radius", "float", 10.0, "Radius.", low=lo, high=hi), radius),
            (Option("a_target", "float", 1.0, "Half-width.", low=lo, high=hi), a_target),
            (Option("size", "float", 20.0, "Block size / a.", low=1.0, high=1e6, low_open=True), size),
            (Option("mu", "float", 0.3, "Friction coefficient.", low=0.0, high=hi), mu),
            (Option("q_ratio", "float", 0.5, "Q / (mu P).", low=-hi, high=hi), q_ratio),
            (Option("normal_steps", "int", 4, "Normal steps.", low=1, high=100_000), normal_steps),
            (Option("tangential_steps", "int", 4, "Tangential steps.", low=1, high=100_000), tangential_steps),
            (Option("order", "int", 1, "Order.", low=1, high=2), order),
            (Option("growth", "float", 1.15, "Grading ratio.", low=1.0, high=10.0), growth)])
    if not isinstance(geometry, str) or geometry not in ("parabolic", "circle"):
        from ..errors import InputError

        raise InputError(f"cattaneo_mindlin_2d: geometry = {geometry!r:.40}: expected 'parabolic' or 'circle'.")
    mat = Material(E=E, nu=nu, plane="strain")
    e_star = mat.plane_strain_modulus
    a = a_target
    L = H = size * a
    h = a / n_per_a
    mesh = meshes.rectangle(-L, L, -H, 0.0, 16, 8,
                            refine=dict(center=(0.0, 0.0), h_min=h, width=1.6 * a, depth=1.0 * a,
                                        growth=growth))
    model = LinearElasticity(mesh, mat, order=order, volumetric=volumetric)
    P = math.pi * a * a * e_star / (4 * radius)
    delta = 2 * P / (math.pi * e_star) * (math.log(2 * H / a) + 0.1)
    # full-stick tangential compliance ~ normal compliance for nu -> 1/2; partial slip softens it (x1.8, calibrated)
    s = 1.8 * q_ratio * mu * P * 2 / (math.pi * e_star) * (math.log(2 * H / a) + 0.1)
    if geometry == "parabolic":
        obstacle = _parabolic_cylinder(radius)
    elif geometry == "circle":
        obstacle = Circle(center=(0.0, radius), radius=radius)
    else:
        raise ValueError(f"geometry must be 'parabolic' or 'circle'; got {geometry!r}")
    t_half = 0.5
    times = tuple(np.linspace(0, t_half, normal_steps + 1)[1:]) + tuple(
        np.linspace(t_half, 1.0, tangential_steps + 1)[1:])
    press = LoadCase(Support("bottom", components=(1,), value=delta), Ramp((0.0, t_half), (0.0, 1.0),
                                                                           hold_after=True), name="approach")
    shear = LoadCase(Support("bottom", components=(0,), value=s), Ramp((t_half, 1.0), (0.0, 1.0)),
                     tangential=True, name="tangential displacement")
    ref = MindlinReference(HertzReference("cylinder", radius, e_star, symmetry=1.0), mu)
    problem = ContactProblem(
        model=model, obstacle=obstacle, contact_boundary="top", supports=(), friction=mu,
        name=f"cattaneo-mindlin-2d (R={radius:g}, {n_per_a} elements per a, mu={mu:g})", reference=ref,
        meta={"delta": delta, "s": s, "h": h},
    )
    fric = Ramp((t_half, t_half + 1e-9), (0.0, 1.0), hold_after=True) if frictionless_approach else None
    return problem, LoadHistory((press, shear), times, fric)


def sphere_shear_3d(n_per_a: int = 4, *, E: float = 200e3, nu: float = 0.3, radius: float = 10.0,
                    a_target: float = 1.0, size: float = 8.0, mu: float = 0.3, q_ratio: float = 0.5,
                    normal_steps: int = 2, tangential_steps: int = 3, growth: float = 1.3):
    r"""Rigid sphere on a block (half model ``y >= 0``): normal approach, then a tangential load along x.

    The block ``[-L, L] x [0, L] x [-H, 0]`` touches the sphere (centre
    ``(0, 0, R)``) at the origin; symmetry ``u_y = 0`` on ``y = 0``. Its bottom
    moves up by :math:`\delta = a^2/R` (Hertz) over ``t`` in [0, 0.5], then along
    x by :math:`s` over [0.5, 1], with friction from ``t = 0.5`` on (as in
    :func:`cattaneo_mindlin_2d`). ``s`` is a rough estimate giving
    :math:`Q \approx` ``q_ratio`` :math:`\mu P`; used by ``benchmarks/friction.py``.

    Returns
    -------
    problem : ContactProblem
    history : LoadHistory
    """
    from ..contact.obstacles import Sphere

    mat = Material(E=E, nu=nu)
    a = a_target
    L = H = size * a
    h = a / n_per_a
    mesh = meshes.box(-L, L, 0.0, L, -H, 0.0, 8, 4, 4,
                      refine=dict(center=(0.0, 0.0, 0.0), h_min=h, width=1.5 * a, depth=1.0 * a, growth=growth))
    model = LinearElasticity(mesh, mat)
    delta = a * a / radius
    G = E / (2 * (1 + nu))
    P = 4 * mat.plane_strain_modulus * a ** 3 / (3 * radius)
    s = q_ratio * mu * P * (2 - nu) / (8 * G * a) * 1.5
    t_half = 0.5
    times = tuple(np.linspace(0, t_half, normal_steps + 1)[1:]) + tuple(
        np.linspace(t_half, 1.0, tangential_steps + 1)[1:])
    press = LoadCase(Support("bottom", components=(2,), value=delta), Ramp((0.0, t_half), (0.0, 1.0),
                                                                           hold_after=True), name="approach")
    shear = LoadCase(Support("bottom", components=(0,), value=s), Ramp((t_half, 1.0), (0.0, 1.0)),
                     tangential=True, name="tangential displacement")
    problem = ContactProblem(
        model=model, obstacle=Sphere(center=(0.0, 0.0, radius), radius=radius), contact_boundary="top",
        supports=(Support("front", components=(1,)),), friction=mu,
        name=f"sphere-shear-3d (R={radius:g}, {n_per_a} elements per a, mu={mu:g})",
        meta={"delta": delta, "s": s, "h": h},
    )
    fric = Ramp((t_half, t_half + 1e-9), (0.0, 1.0), hold_after=True)
    return problem, LoadHistory((press, shear), times, fric)
