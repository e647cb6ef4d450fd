r"""Rigidly rotating obstacles at finite deformation (``obstacle_path`` returning a RigidMotion).

References (neo-Hookean bodies, plane strain, E = 1000, nu = 0.3):

1. *Placement*: :class:`~alcontact.contact.obstacles.Moved` equals the obstacle built at the
   moved place (gap, normal, Hessian, projection to 1e-14; a rotated half-space is a
   half-space with the rotated normal through the moved point, a rotated cylinder the
   cylinder with the rotated axis), its surface slip is the rotated one (1e-13) with a
   Jacobian equal to central differences (1e-7 relative), and
   :func:`~alcontact.contact.obstacles.frame` composes placements.
2. *Frictionless path independence*: a hyperelastic body without friction has a potential,
   so its equilibrium depends on the final obstacle placement only. A clamped block pressed
   by a plane that rotates by 0.1 rad about a point while it moves up gives the same final
   displacement and contact force as the plane placed at its final tilt and only moved
   (both solvers stop at relative tolerances 1e-8): to 1e-6 relative.
3. *Rotating roller with friction*: a circle (R = 0.5) pressed 0.05 into a block, then turned
   about its own centre by 0.8 rad. Slip on the roller's surface: the point of the roller a
   contact point touches is at polar angle :math:`\psi - \varphi` in the roller's frame
   (:math:`\psi` the polar angle of the normal, :math:`\varphi` the rotation), so each step's
   slip length is :math:`R\,|\Delta\psi - \Delta\varphi|`, to :math:`10^{-9} R`; every
   contact point slips with :math:`|t_T| = \mu t_N` (within :math:`\mu\,` ``tol_multiplier``
   :math:`p_{max}`); the friction drags the body along the surface motion (+x). Energy
   balance of the turning phase: the work of the roller on the body,
   :math:`\int P\,d\varphi` with :math:`P = -R\sum_i w_i\, t_{T,i}\cdot\nu_i^\perp` (the force
   on the body times the surface velocity :math:`R\nu^\perp` per unit rotation, trapezoidal)
   equals the dissipation plus the change of stored energy within 1 % (the trapezoidal error
   comes from the jump of the power in the first turning step: -3.5 %, -0.70 %, -0.24 %,
   -0.21 % for 8, 16, 24, 32 steps; 16 are used). Algorithm 6.2 and
   the semi-smooth Newton reference agree to 1e-6 relative.
"""

from __future__ import annotations

import numpy as np
import pytest

from _helpers import assert_same_finite_solution
from alcontact.contact import ContactProblem, FrictionOptions, Ramp, Support, obstacles, solve_finite
from alcontact.contact import solve_finite_friction
from alcontact.contact.laws import OPEN, SLIP
from alcontact.errors import InputError
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic

MAT = Material(E=1000.0, nu=0.3, plane="strain")
RADIUS = 0.5


def _fd(fun, x, h=1e-6):
    return np.stack([(fun(x + h * e) - fun(x - h * e)) / (2 * h) for e in np.eye(x.size)], axis=-1)


def test_moved_obstacle_is_the_obstacle_at_its_place():
    """Reference 1 (module doc): Moved = obstacle built in place (1e-14), slip Jacobian = FD (1e-7)."""
    motion = obstacles.RigidMotion.about((0.5, 0.0), 0.3, offset=(0.1, 0.2))
    plane = obstacles.HalfSpace(point=(0.0, 0.0), normal=(0.0, 1.0))
    moved = obstacles.move(plane, motion)
    q, b = motion.rotation, motion.offset
    direct = obstacles.HalfSpace(point=b, normal=q @ np.array([0.0, 1.0]))
    x = np.random.default_rng(1).normal(size=(7, 2))
    for f in ("gap", "normal", "gap_hessian", "project"):
        assert np.max(np.abs(getattr(moved, f)(x) - getattr(direct, f)(x))) <= 1e-14
    ball = obstacles.move(obstacles.Circle(center=(0.2, 0.1), radius=RADIUS), motion)
    center = q @ np.array([0.2, 0.1]) + b
    disc = obstacles.Circle(center=center, radius=RADIUS)
    x = center + 0.7 * np.random.default_rng(2).normal(size=(5, 2))
    for f in ("gap", "normal", "gap_hessian", "project"):
        assert np.max(np.abs(getattr(ball, f)(x) - getattr(disc, f)(x))) <= 1e-14
    y_prev = disc.project(x + 0.2)
    slip, jac = obstacles.surface_slip(ball, x, y_prev)
    slip_d, _ = obstacles.surface_slip(disc, x, y_prev)
    assert np.max(np.abs(slip - slip_d)) <= 1e-14
    fd = np.stack([_fd(lambda p: obstacles.surface_slip(ball, p[None], y_prev[i:i + 1], jacobian=False)[0][0], x[i])
                   for i in range(x.shape[0])])
    assert np.max(np.abs(jac - fd)) <= 1e-7 * np.max(np.abs(jac))
    # 3D: a cylinder rotated about a tilted axis is the cylinder with the rotated axis and centre
    m3 = obstacles.RigidMotion.about((0.1, 0.2, 0.3), 0.7, axis=(1.0, 1.0, 0.5), offset=(0.0, 0.1, -0.2))
    cyl = obstacles.Cylinder(center=(0.0, 0.0, 1.0), axis=(0.0, 1.0, 0.0), radius=RADIUS)
    q3, b3 = m3.rotation, m3.offset
    cyl_moved = obstacles.move(cyl, m3)
    cyl_direct = obstacles.Cylinder(center=q3 @ np.array([0.0, 0.0, 1.0]) + b3, axis=q3 @ np.array([0.0, 1.0, 0.0]),
                                    radius=RADIUS)
    x3 = cyl_direct.center + 0.8 * np.random.default_rng(4).normal(size=(6, 3))
    for f in ("gap", "normal", "gap_hessian", "project"):
        assert np.max(np.abs(getattr(cyl_moved, f)(x3) - getattr(cyl_direct, f)(x3))) <= 1e-14
    y3 = cyl_direct.project(x3 + 0.2)
    s_m, j_m = obstacles.surface_slip(cyl_moved, x3, y3)
    s_d, j_d = obstacles.surface_slip(cyl_direct, x3, y3)
    assert np.max(np.abs(s_m - s_d)) <= 1e-13 and np.max(np.abs(j_m - j_d)) <= 1e-12 * np.max(np.abs(j_d))
    # frame composition: move(translate(O, c), M) places y at Q (y + c) + b
    q2, b2 = obstacles.frame(obstacles.move(obstacles.translate(plane, (0.3, 0.0)), motion))
    assert np.allclose(q2, q, atol=1e-15) and np.allclose(b2, q @ np.array([0.3, 0.0]) + b, atol=1e-15)
    with pytest.raises(InputError, match="axis"):
        obstacles.RigidMotion.about((0.0, 0.0, 0.0), 0.1)
    with pytest.raises(InputError, match="orthogonal"):
        obstacles.RigidMotion(np.diag([1.0, 2.0]), (0.0, 0.0))


def _block(obstacle):
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    return ContactProblem(Hyperelastic(mesh, MAT), obstacle, "bottom", supports=(Support("top"),),
                          kinematics="finite")


def test_frictionless_rotation_is_path_independent():
    """Reference 2 (module doc): rotating-plane path = final-tilt plane only moved, to 1e-6 (u and force)."""
    plane = obstacles.HalfSpace(point=(0.0, -0.05), normal=(0.0, 1.0))
    pivot, angle, lift = (0.5, -0.05), 0.1, np.array([0.0, 0.2])

    def rotating(t):
        return obstacles.RigidMotion.about(pivot, angle * t, offset=lift * t)

    tilted = obstacles.move(plane, obstacles.RigidMotion.about(pivot, angle))
    f_rot = solve_finite(_block(plane), "ssn", steps=4, obstacle_path=rotating)
    f_ref = solve_finite(_block(tilted), "ssn", steps=4, obstacle_path=lambda t: lift * t)
    assert f_rot.success and f_ref.success, (f_rot.message, f_ref.message)
    assert np.max(np.abs(f_rot.u - f_ref.u)) <= 1e-6 * np.max(np.abs(f_ref.u))
    assert np.max(np.abs(f_rot.forces[-1] - f_ref.forces[-1])) <= 1e-6 * np.max(np.abs(f_ref.forces[-1]))
    assert abs(f_ref.forces[-1][0]) > 1e-2 * abs(f_ref.forces[-1][1])  # the tilt matters


def _roller():
    mesh = meshes.rectangle(0.0, 2.0, 0.0, 0.5, 20, 4)
    center = np.array([1.0, 0.5 + RADIUS])
    problem = ContactProblem(Hyperelastic(mesh, MAT), obstacles.Circle(center=center, radius=RADIUS), "top",
                             supports=(Support("bottom"),), kinematics="finite")
    press = Ramp((0.0, 0.2), (0.0, -0.05), hold_after=True)
    turn = Ramp((0.2, 1.0), (0.0, 0.8))

    def path(t):
        return obstacles.RigidMotion.about(center, turn(t), offset=(0.0, press(t)))

    return problem, path, turn


@pytest.mark.parametrize("algorithm", ["ssn"])
def test_rotating_roller_slip_and_energy(algorithm):
    """Reference 3 (module doc): slip = R |dpsi - dphi| (1e-9 R), |t_T| = mu t_N, energy within 1 % (16 steps)."""
    mu = 0.3
    problem, path, turn = _roller()
    times = list(np.linspace(0.0, 0.2, 4)[1:]) + list(np.linspace(0.2, 1.0, 17)[1:])
    fs = solve_finite_friction(problem, mu, algorithm, steps=times, obstacle_path=path)
    assert fs.success, fs.message
    w = fs.extra["weights"]
    k0 = int(np.flatnonzero(np.isclose(fs.times, 0.2))[0])
    bound = mu * FrictionOptions().tol_multiplier * float(np.max([np.max(s.pressure) for s in fs.steps]))
    phi = np.array([turn(s.t) for s in fs.steps])
    power = []
    for k, step in enumerate(fs.steps):
        perp = np.stack([-step.normals[:, 1], step.normals[:, 0]], axis=1)
        power.append(-RADIUS * float(np.sum(w * np.einsum("ij,ij->i", step.traction_t, perp))))
        if k <= k0:
            continue
        prev = fs.steps[k - 1]
        closed = step.states != OPEN
        psi = np.arctan2(step.normals[:, 1], step.normals[:, 0])
        psi0 = np.arctan2(prev.normals[:, 1], prev.normals[:, 0])
        rel = np.angle(np.exp(1j * (psi - psi0 - (phi[k] - phi[k - 1]))))[closed]
        assert np.max(np.abs(np.linalg.norm(step.slip[closed], axis=1) - RADIUS * np.abs(rel))) <= 1e-9 * RADIUS
        assert np.all(step.states[closed] == SLIP)
        tT = np.linalg.norm(step.traction_t[closed], axis=1)
        assert np.all(np.abs(tT - mu * step.pressure[closed]) <= 1.01 * bound)
    last = fs.steps[-1]
    assert np.sum(last.states != OPEN) >= 3
    assert last.tangential_force[0] > 0.9 * mu * last.normal_force  # dragged along +x by the roller
    work = sum(0.5 * (power[k] + power[k + 1]) * (phi[k + 1] - phi[k]) for k in range(k0, len(power) - 1))
    stored = last.stored_energy - fs.steps[k0].stored_energy
    dissipation = sum(s.dissipation for s in fs.steps[k0 + 1:])
    assert dissipation > 0.9 * work > 0
    assert abs(work - dissipation - stored) <= 1e-2 * abs(work)


def test_rotating_roller_al_matches_ssn():
    """Reference 3 (module doc): Algorithm 6.2 = SSN on the rotating roller, 1e-6 relative (u and forces)."""
    problem, path, _ = _roller()
    times = [0.1, 0.2, 0.4, 0.6]
    fa = solve_finite_friction(problem, 0.3, "simo-laursen", steps=times, obstacle_path=path)
    fr = solve_finite_friction(problem, 0.3, "ssn", steps=times, obstacle_path=path)
    assert fa.success and fr.success, (fa.message, fr.message)
    assert_same_finite_solution(fa, fr, 1e-6)
    assert np.any(fr.steps[-1].states == SLIP)
