r"""Coulomb friction at finite deformation: slip on curved surfaces, consistency, 3D.

References (neo-Hookean bodies, E = 1000, nu = 0.3; plane strain in 2D):

1. *Slip on the surface* (2D ironing with a rigid circle of radius R = 0.5, large slide
   steps: the normal of a contact point turns by up to ~0.25 rad a step). The slip of a
   step is measured on the obstacle's surface: its length is the arc
   :math:`R\,|\Delta\varphi|` between the previous and the current surface point, where
   :math:`\varphi` is the polar angle of the obstacle normal at the point (the normal of a
   circle is radial, and a translation does not turn it). Pure geometry evaluated at the
   converged states: agreement to :math:`10^{-9} R`. The old chord measure
   :math:`R\sin|\Delta\varphi|` differs by :math:`\Delta\varphi^2/6` relative, which the test
   checks is far above that tolerance (it would fail). At every slipping point
   :math:`|t_T| = \mu t_N` within :math:`\mu\,` ``tol_multiplier`` :math:`p_{max}` (the AL
   stopping test), and the slip is tangent to the obstacle (:math:`|\Delta s\cdot\nu| \le 10^{-12}|\Delta s|`).
2. *Quadratic convergence* on that curved, frictional problem: the terminal pair of every
   Newton solve of the Alart-Curnier reference and of the Algorithm 6.2 subproblems (the last
   :math:`(e_k, e_{k+1})` with :math:`e_k \le 10^{-3}` above the round-off floor, once the
   stick/slip set is settled) passes the ratio test of the frictionless one
   (:mod:`tests.verification.test_finite_hertz`): :math:`e_{k+1} \le 10^3 e_k^2` and
   :math:`\log e_{k+1}/\log e_k \ge 1.5`. The arc's derivative changes the Jacobian by
   :math:`O(\theta^2)` only, so the consistency of the linearization is asserted directly as
   well: the Newton matrix equals central differences of the residual, and
   :func:`~alcontact.contact.obstacles.surface_slip` its own central differences.
3. *3D block on a plane* (2x2x1 cells, pressed by 20 %) pushed diagonally beyond the stick
   limit: at the end every contact point slips with :math:`|t_{T,i}| = \mu t_{N,i}` (within
   :math:`\mu\,` ``tol_multiplier`` :math:`p_{max}`, the AL stopping test) parallel to its slip
   (cosine :math:`\ge 1 - 10^{-9}`), and every traction is aligned with the plane's motion
   (cosine :math:`c_{min} \ge 1 - 10^{-5}`: the slip directions start skewed by the anisotropic
   tetrahedral mesh and align as the sliding goes on, :math:`1 - c_{min}` = 1.5e-2, 7.4e-4,
   5.7e-5, 5.1e-6 after 0.2, 0.3, 0.4, 0.5 of sliding, about tenfold per 0.1 whatever the
   step). Then :math:`c_{min}\mu N - b \le |T| \le \mu N + b`, :math:`b = \mu\,`
   ``tol_multiplier`` :math:`p_{max}\sum w` (as the 2D test), i.e. :math:`|T| = \mu N` to 1e-5 relative; T is
   tangent to the plane. After a small sideways motion some points stick and
   :math:`|T| < \mu N / 2` (the pressing itself makes the outer points slip outwards: lateral
   expansion of the coarse block, so "all stick" does not hold in 3D). For Algorithms 6.2,
   6.4 and the SSN reference.
4. *3D ironing* (rigid sphere R = 0.5 pressed 0.04 into a block and moved by 0.5): energy
   balance of the sliding phase, horizontal work (trapezoidal) = dissipation + change of
   stored energy within 1 % (the trapezoidal balance error on this mesh is -7.8 %, -1.1 %,
   -0.39 % for 4, 16, 24 slide steps; 24 are used). AL (Algorithm 6.2) = SSN to 1e-6
   relative on a shorter run, and mu = 1e-9 reproduces the frictionless 3D solution
   (:func:`~alcontact.contact.solve_finite`) to 1e-6 relative (both stop at relative
   tolerances 1e-8, friction changes the state by O(mu)).
"""

from __future__ import annotations

import numpy as np
import pytest

from _helpers import assert_quadratic_pairs, assert_same_finite_solution
from alcontact.contact import ContactProblem, FrictionOptions, Ramp, Support, obstacles, solve_finite
from alcontact.contact import solve_finite_friction
from alcontact.contact.laws import OPEN, SLIP, STICK
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic

MAT2 = Material(E=1000.0, nu=0.3, plane="strain")
MAT3 = Material(E=1000.0, nu=0.3)
RADIUS = 0.5


def _ironing_2d():
    mesh = meshes.rectangle(0.0, 2.0, 0.0, 0.5, 20, 4)
    problem = ContactProblem(Hyperelastic(mesh, MAT2), obstacles.Circle(center=(0.5, 0.5 + RADIUS), radius=RADIUS),
                             "top", supports=(Support("bottom"),), kinematics="finite")
    press = Ramp((0.0, 0.2), (0.0, -0.05), hold_after=True)
    slide = Ramp((0.2, 1.0), (0.0, 0.6))
    times = list(np.linspace(0.0, 0.2, 4)[1:]) + list(np.linspace(0.2, 1.0, 5)[1:])
    return problem, (lambda t: np.array([slide(t), press(t)])), times


def _polar(normals):
    return np.arctan2(normals[:, 1], normals[:, 0])


@pytest.mark.parametrize("algorithm", ["simo-laursen", "ssn"])
def test_slip_is_the_arc_on_the_obstacle(algorithm):
    """Reference 1 (module doc): |slip| = R |dphi| to 1e-9 R; |t_T| = mu t_N at slipping points."""
    mu = 0.3
    problem, path, times = _ironing_2d()
    fs = solve_finite_friction(problem, mu, algorithm, steps=times, obstacle_path=path)
    assert fs.success, fs.message
    bound = mu * FrictionOptions().tol_multiplier * float(np.max([np.max(s.pressure) for s in fs.steps]))
    k0 = int(np.flatnonzero(np.isclose(fs.times, 0.2))[0])
    checked, chord_gap = 0, 0.0
    for prev, step in zip(fs.steps[k0:-1], fs.steps[k0 + 1:]):
        closed = step.states != OPEN
        dphi = np.angle(np.exp(1j * (_polar(step.normals) - _polar(prev.normals))))[closed]
        arc = RADIUS * np.abs(dphi)
        length = np.linalg.norm(step.slip[closed], axis=1)
        assert np.max(np.abs(length - arc)) <= 1e-9 * RADIUS
        normal_part = np.abs(np.einsum("ij,ij->i", step.slip[closed], step.normals[closed]))
        assert np.all(normal_part <= 1e-12 * np.maximum(length, 1e-300))
        chord_gap = max(chord_gap, float(np.max(arc - RADIUS * np.sin(np.abs(dphi)))))
        sliding = step.states == SLIP
        tT = np.linalg.norm(step.traction_t[sliding], axis=1)
        assert np.all(np.abs(tT - mu * step.pressure[sliding]) <= 1.01 * bound)
        checked += int(np.sum(sliding))
    assert checked >= 10
    assert chord_gap >= 1e4 * 1e-9 * RADIUS  # the chord measure would fail the arc test by far


def _terminal_pair(log):
    """The last pair (e_k, e_k+1) of a Newton solve with e_k <= 1e-3 and e_k+1 above the round-off floor 1e-10."""
    pairs = [(a, b) for a, b in zip(log[:-1], log[1:]) if a <= 1e-3 and b >= 1e-10]
    return pairs[-1:]


@pytest.mark.parametrize("algorithm", ["ssn", "simo-laursen"])
def test_newton_converges_quadratically_on_curved_sliding(algorithm):
    """Reference 2 (module doc): terminal pairs e_k+1 <= 1e3 e_k^2, order >= 1.5; >= 2 pairs."""
    problem, path, times = _ironing_2d()
    fs = solve_finite_friction(problem, 0.3, algorithm, steps=times, obstacle_path=path)
    assert fs.success, fs.message
    pairs = [p for log in fs.extra["residual_log"] for p in _terminal_pair(log)]
    assert_quadratic_pairs(pairs)


def _fd_jacobian(fun, x, h):
    cols = [(fun(x + h * e) - fun(x - h * e)) / (2 * h) for e in np.eye(x.size)]
    return np.stack(cols, axis=-1)


_OBSTACLES = [
    obstacles.HalfSpace(point=(0.0, 0.0, 0.0), normal=(0.0, 0.3, 1.0)),
    obstacles.Circle(center=(0.0, 0.0), radius=1.0),
    obstacles.Circle(center=(0.0, 0.0), radius=1.0, inside=True),
    obstacles.Sphere(center=(0.0, 0.0, 0.0), radius=2.0),
    obstacles.Cylinder(center=(0.0, 0.0, 0.0), axis=(0.0, 1.0, 1.0), radius=1.5),
    obstacles.translate(obstacles.Sphere(center=(0.0, 0.0, 0.0), radius=2.0), (0.3, 0.0, 0.1)),
    obstacles.UserObstacle(gap=lambda x: 1.0 - np.linalg.norm(x, axis=1), dim=3),
]


@pytest.mark.parametrize("ob", _OBSTACLES, ids=lambda ob: ob.describe()[:30])
def test_surface_slip_geodesic_and_jacobian(ob):
    r"""surface_slip: tangent, geodesic length, and its Jacobian equals central differences.

    References: the slip is tangent at the projection (:math:`|\Delta s\cdot\nu| \le 10^{-13}`,
    :math:`10^{-9}` for the user obstacle whose normal is a finite difference);
    on a ball its length is :math:`R\theta` (great circle), on a cylinder
    :math:`\sqrt{(a\cdot b)^2 + (R\theta)^2}` (unrolled surface), on a plane the chord, each to
    :math:`10^{-12}`. The Jacobian matches central differences (step 1e-6, truncation and
    round-off ~1e-9) to 1e-7 relative for analytic obstacles, to 1e-4 for the user
    obstacle (its normal and Hessian are themselves finite differences).
    """
    rng = np.random.default_rng(7)
    d = ob.dim or 3
    x = rng.normal(size=(6, d))
    x *= (1.3 / np.linalg.norm(x, axis=1))[:, None]
    y_prev = ob.project(x + 0.3 * rng.normal(size=(6, d)))
    slip, jac = obstacles.surface_slip(ob, x, y_prev)
    nu = ob.normal(x)
    user = isinstance(ob, obstacles.UserObstacle)  # normal and Hessian by finite differences
    assert np.max(np.abs(np.einsum("ij,ij->i", slip, nu))) <= (1e-9 if user else 1e-13)
    base = getattr(ob, "base", ob)
    shift = getattr(ob, "offset", np.zeros(d))
    if isinstance(base, (obstacles.Circle, obstacles.Sphere)):
        e1 = (ob.project(x) - shift - base.center) / base.radius
        e0 = (y_prev - shift - base.center) / base.radius
        arc = base.radius * np.arccos(np.clip(np.einsum("ij,ij->i", e0, e1), -1.0, 1.0))
        assert np.max(np.abs(np.linalg.norm(slip, axis=1) - arc)) <= 1e-12
    elif isinstance(base, obstacles.Cylinder):
        a = base.axis
        w1, w0 = ob.project(x) - base.center, y_prev - base.center
        r1 = w1 - np.outer(w1 @ a, a)
        r0 = w0 - np.outer(w0 @ a, a)
        theta = np.arccos(np.clip(np.einsum("ij,ij->i", r0, r1) / base.radius**2, -1.0, 1.0))
        geodesic = np.hypot((w1 - w0) @ a, base.radius * theta)
        assert np.max(np.abs(np.linalg.norm(slip, axis=1) - geodesic)) <= 1e-12
    elif isinstance(base, obstacles.HalfSpace):
        assert np.max(np.abs(np.linalg.norm(slip, axis=1) - np.linalg.norm(ob.project(x) - y_prev, axis=1))) <= 1e-12
    fd = np.stack([_fd_jacobian(lambda p: obstacles.surface_slip(ob, p[None], y_prev[i:i + 1], jacobian=False)[0][0],
                                x[i], 1e-6) for i in range(x.shape[0])])
    tol = 1e-4 if user else 1e-7
    assert np.max(np.abs(jac - fd)) <= tol * np.max(np.abs(jac))


@pytest.mark.parametrize("turn", [1.2, 2.5, -2.9])
def test_surface_slip_beyond_a_quarter_turn(turn):
    """Arc beyond pi/2: on a circle (R = 0.7) and a cylinder the slip length is R |turn| (1e-12), FD Jacobian (1e-7)."""
    circle = obstacles.Circle(center=(0.1, -0.2), radius=0.7)
    cyl = obstacles.Cylinder(center=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), radius=0.7)
    for ob, x, y_prev, extra in (
            (circle, np.array([[0.1 + 0.75, -0.2]]),
             np.array([[0.1 + 0.7 * np.cos(turn), -0.2 - 0.7 * np.sin(turn)]]), 0.0),
            (cyl, np.array([[0.75, 0.0, 0.3]]), np.array([[0.7 * np.cos(turn), -0.7 * np.sin(turn), 0.1]]), 0.2)):
        slip, jac = obstacles.surface_slip(ob, x, y_prev)
        assert abs(np.linalg.norm(slip[0]) - np.hypot(0.7 * abs(turn), extra)) <= 1e-12
        fd = _fd_jacobian(lambda p: obstacles.surface_slip(ob, p[None], y_prev, jacobian=False)[0][0], x[0], 1e-6)
        assert np.max(np.abs(jac[0] - fd)) <= 1e-7 * np.max(np.abs(jac[0]))


def test_transport_tangent_rotates_into_the_new_tangent_plane():
    """transport_tangent keeps lengths, lands in the new tangent plane (1e-14) and is the 2D rotation."""
    rng = np.random.default_rng(3)
    n0 = rng.normal(size=(5, 3))
    n0 /= np.linalg.norm(n0, axis=1)[:, None]
    n1 = rng.normal(size=(5, 3))
    n1 /= np.linalg.norm(n1, axis=1)[:, None]
    t = rng.normal(size=(5, 3))
    t -= np.einsum("ij,ij->i", t, n0)[:, None] * n0
    r = obstacles.transport_tangent(t, n0, n1)
    assert np.max(np.abs(np.einsum("ij,ij->i", r, n1))) <= 1e-14
    assert np.max(np.abs(np.linalg.norm(r, axis=1) - np.linalg.norm(t, axis=1))) <= 1e-14
    # the component along the rotation axis n0 x n1 is kept
    k = np.cross(n0, n1)
    assert np.max(np.abs(np.einsum("ij,ij->i", r - t, k))) <= 1e-14
    r2 = obstacles.transport_tangent(np.array([[0.0, 2.0]]), np.array([[1.0, 0.0]]), np.array([[0.0, 1.0]]))
    assert np.allclose(r2, [[-2.0, 0.0]], atol=1e-15)


@pytest.mark.parametrize("radius", ["multiplier", "traction"])
def test_friction_jacobian_matches_finite_differences_on_a_curved_obstacle(radius):
    r"""The Newton matrix of the frictional subproblem is the derivative of its residual.

    Setting: the 2D ironing block under the pressed circle, the previous surface points of
    every other point moved along the circle by 0.15 rad (large slip on the curved surface),
    tangential multipliers below the Coulomb radius so that the others stick. Reference:
    central differences of the residual (step 1e-7, error ~1e-7 relative to the largest
    entry) for both Coulomb radii; asserted to 1e-5 relative.
    """
    from alcontact import penalties
    from alcontact.contact.systems import FiniteFrictionContact
    from alcontact.contact.laws import make_law
    from alcontact.contact.stepping._steps import _StepData

    problem, path, _ = _ironing_2d()
    data = _StepData(problem, None, path)
    dc = FiniteFrictionContact(problem, fixed=data.fixed)
    fv, load, ob = data(0.3)
    dc.configure(fv, load, ob, np.zeros(dc.free.size), predictor_stiffness=1e4)
    offset = np.asarray(path(0.3))
    u0 = dc.expand(np.zeros(dc.free.size))
    center = np.array([0.5, 0.5 + RADIUS])
    y = dc.obstacle.project(dc.points + u0[dc.dofs]) - offset - center
    angle = np.where(np.arange(y.shape[0]) % 2 == 0, 0.15, 0.0)  # every other point: no slip
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    turned = np.concatenate([c * y[:, :1] - s * y[:, 1:], s * y[:, :1] + c * y[:, 1:]], axis=1)
    dc.set_history(turned + center, 0.3, 2e4, radius)
    cand = dc.cand
    assert cand.size >= 3
    rng = np.random.default_rng(5)
    lamN = 50.0 * (1.0 + rng.random(cand.size))
    nu = dc.obstacle.normal(dc.points[cand] + u0[dc.dofs][cand])
    tang = np.stack([-nu[:, 1], nu[:, 0]], axis=1)
    lamT = (rng.random(cand.size) * 0.5 * lamN)[:, None] * tang
    law = make_law(penalties.make("rockafellar"), np.full(cand.size, 1.0 / 1e4))
    x = 1e-3 * rng.normal(size=dc.free.size)
    loc = dc.evaluate(law, lamN, lamT, x)
    assert np.any(loc.state == STICK) and np.any(loc.state == SLIP)
    J = dc.friction_jacobian(law, lamN, lamT, loc.u).toarray()
    fd = _fd_jacobian(lambda z: dc.evaluate(law, lamN, lamT, z).R, x, 1e-7)
    assert np.max(np.abs(J - fd)) <= 1e-5 * np.max(np.abs(J))


# --------------------------------------------------------------------------- 3D
def _block_3d():
    mesh = meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, 0.5, 2, 2, 1)
    problem = ContactProblem(Hyperelastic(mesh, MAT3), obstacles.HalfSpace(point=(0.0, 0.0, 0.0),
                                                                             normal=(0.0, 0.0, 1.0)),
                             "bottom", supports=(Support("top"),), kinematics="finite")
    press = Ramp((0.0, 0.5), (0.0, 0.1), hold_after=True)
    slide = Ramp((0.5, 1.0), (0.0, 0.5))
    direction = np.array([0.6, 0.8, 0.0])
    times = [0.25, 0.5, 0.505, 0.6, 0.7, 0.8, 0.9, 1.0]  # t = 0.505: the plane moved by 0.005, partial slip
    return problem, (lambda t: slide(t) * direction + np.array([0.0, 0.0, press(t)])), times, direction


@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn"])
def test_block_3d_slides_with_mu_times_normal_force(algorithm):
    """Reference 3 (module doc): full slip, |t_T,i| = mu t_N,i along the slip, |T| = mu N, T tangent."""
    mu = 0.3
    problem, path, times, direction = _block_3d()
    fs = solve_finite_friction(problem, mu, algorithm, steps=times, obstacle_path=path)
    assert fs.success, fs.message
    tol = FrictionOptions().tol_multiplier
    early = fs.steps[2]  # partial slip: the pressing already slid the outer points outwards
    assert np.any(early.states == STICK)
    assert np.linalg.norm(early.tangential_force) < 0.5 * mu * early.normal_force
    last = fs.steps[-1]
    closed = last.states != OPEN
    assert np.sum(closed) >= 9 and np.all(last.states[closed] == SLIP)
    p_max = float(np.max(last.pressure))
    tT = last.traction_t[closed]
    assert np.all(np.abs(np.linalg.norm(tT, axis=1) - mu * last.pressure[closed]) <= 1.01 * mu * tol * p_max)
    cosines = np.einsum("ij,ij->i", tT, last.slip[closed]) / (
        np.linalg.norm(tT, axis=1) * np.linalg.norm(last.slip[closed], axis=1))
    assert np.all(cosines >= 1.0 - 1e-9)
    T = last.tangential_force
    assert abs(T[2]) <= 1e-12 * np.linalg.norm(T)  # tangent to the plane
    # every point slides against the plane's motion (friction on the body along it)
    aligned = -(tT @ direction) / np.linalg.norm(tT, axis=1)
    assert np.min(aligned) >= 1.0 - 1e-5
    bound = mu * tol * p_max * float(np.sum(fs.extra["weights"]))
    assert np.linalg.norm(T) <= mu * last.normal_force + 1.01 * bound
    assert np.linalg.norm(T) >= np.min(aligned) * mu * last.normal_force - 1.01 * bound
    assert last.normal_force > 0.1 * 1000.0 * 0.2 * 0.5  # large strain (20 %): substantial


def _ironing_3d(slide_steps: int):
    mesh = meshes.box(0.0, 1.2, 0.0, 0.6, 0.0, 0.3, 12, 6, 2)
    problem = ContactProblem(Hyperelastic(mesh, MAT3), obstacles.Sphere(center=(0.35, 0.3, 0.3 + RADIUS),
                                                                          radius=RADIUS),
                             "top", supports=(Support("bottom"),), kinematics="finite")
    press = Ramp((0.0, 0.2), (0.0, -0.04), hold_after=True)
    slide = Ramp((0.2, 1.0), (0.0, 0.5))
    times = list(np.linspace(0.0, 0.2, 4)[1:]) + list(np.linspace(0.2, 1.0, slide_steps + 1)[1:])
    return problem, (lambda t: np.array([slide(t), 0.0, press(t)])), times


def test_ironing_3d_energy_balance():
    """Reference 4 (module doc): W_horizontal = dissipation + change of stored energy within 1 % (24 steps)."""
    problem, path, times = _ironing_3d(24)
    fs = solve_finite_friction(problem, 0.3, "ssn", steps=times, obstacle_path=path)
    assert fs.success, fs.message
    F = fs.forces
    c = np.array([s.offset for s in fs.steps])
    k0 = int(np.flatnonzero(np.isclose(fs.times, 0.2))[0])
    work = sum(0.5 * (F[k, 0] + F[k + 1, 0]) * (c[k + 1, 0] - c[k, 0]) for k in range(k0, len(F) - 1))
    stored = fs.steps[-1].stored_energy - fs.steps[k0].stored_energy
    dissipation = sum(s.dissipation for s in fs.steps[k0 + 1:])
    assert min(int(np.sum(s.states != OPEN)) for s in fs.steps[k0:]) >= 6  # a contact patch, not a point
    assert dissipation > 0.9 * work > 0
    assert abs(work - dissipation - stored) <= 1e-2 * abs(work)
    assert all(s.dissipation >= -1e-9 * dissipation for s in fs.steps)


def test_ironing_3d_al_matches_ssn_and_mu_to_zero():
    """Reference 4 (module doc): Algorithm 6.2 = SSN and mu = 1e-9 = frictionless, both to 1e-6 relative."""
    problem, path, times = _ironing_3d(3)
    fa = solve_finite_friction(problem, 0.3, "simo-laursen", steps=times, obstacle_path=path)
    fr = solve_finite_friction(problem, 0.3, "ssn", steps=times, obstacle_path=path)
    assert fa.success and fr.success, (fa.message, fr.message)
    assert_same_finite_solution(fa, fr, 1e-6)
    assert np.any(fr.steps[-1].states == SLIP)
    f0 = solve_finite(problem, "ssn", steps=times, obstacle_path=path)
    f1 = solve_finite_friction(problem, 1e-9, "ssn", steps=times, obstacle_path=path)
    assert f0.success and f1.success, (f0.message, f1.message)
    assert np.max(np.abs(f1.u - f0.u)) <= 1e-6 * np.max(np.abs(f0.u))
    assert np.max(np.abs(f1.forces - f0.forces)) <= 1e-6 * np.max(np.abs(f0.forces))
