"""Obstacles of revolution for axisymmetric bodies: a cone and a user profile, against closed forms.

In the r-z half-plane of a body of revolution (``geometry="axisymmetric"``), a ``half-space`` whose normal is
inclined to the axis is a cone with its apex on the axis, and a ``user`` gap is any profile of revolution.

- **Cone** (Sneddon 1965, Int. J. Engng Sci. 3, 47-57; Johnson, *Contact Mechanics*, 1985, sec. 5.3): a rigid
  cone whose surface makes the angle theta with the undeformed surface of an elastic half-space, pressed to the
  depth delta (small deformation, frictionless): ``P = (2/pi) E* delta^2 / tan(theta)``, contact radius
  ``a = (2/pi) delta / tan(theta)``. The model is the graded Hertz mesh (``hertz.mesh_spec``) of a cylinder of
  radius and depth ``size * a`` with a fixed bottom, P2. Sneddon's half-space is infinite and his theory is of
  first order in the slope; the model has the truncation (a stiffer body: the error falls with ``size``) and the
  linearized gap along the cone's normal (the radial displacement enters it with weight sin(theta); measured
  +0.42 % per degree at nu = 0.3). At theta = 1 deg, size 400: force within 1 % of Sneddon (measured +0.62 %),
  contact radius within 2 % (measured +1.5 %: one element at n = 8); the force error falls from size 50 to
  200 to 400 (measured +2.0 %, +0.81 %, +0.61 %).
- **User profile = sphere**: a ``UserObstacle`` whose gap is the signed distance of the same circle as a
  ``circle`` obstacle (the sphere) gives the sphere's force and displacement: with its exact normal to 1e-12
  (small deformation, Hertz; measured 0), with the default finite-difference normal and curvature to 1e-9
  (measured 5.5e-12 small, 1.1e-12 finite: the finite neo-Hookean hemisphere of revolution on a ball, which also
  uses the gap's curvature).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import ContactProblem, Support, solve
from alcontact.contact.obstacles import Circle, HalfSpace, UserObstacle
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.problems import hertz
from alcontact.problems.hemisphere import hemisphere_axisym

E, NU = 1000.0, 0.3


def _cone_solve(theta_deg: float, size: float, n: int = 8):
    theta = np.radians(theta_deg)
    mat = Material(E=E, nu=NU)
    a = 1.0
    delta = np.pi / 2 * a * np.tan(theta)  # Sneddon: a = (2/pi) delta / tan(theta)
    md = hertz.mesh_spec(2, n, 2, a_target=a, size=size, growth=1.15)
    mesh = meshes.rectangle(*md["bounds"], *md["cells"], refine=md["refine"])
    model = LinearElasticity(mesh, mat, order=2, geometry="axisymmetric")
    # apex at (0, -delta) on the axis; the obstacle is z > -delta + r tan(theta): its outward normal points down
    cone = HalfSpace([0.0, -delta], [np.sin(theta), -np.cos(theta)])
    sol = solve(ContactProblem(model=model, obstacle=cone, contact_boundary="top",
                               supports=(Support("bottom"), Support("left", components=(0,)))))
    assert sol.result.success, sol.result.message
    P = 2.0 / np.pi * mat.plane_strain_modulus * delta**2 / np.tan(theta)
    return sol.normal_force / P - 1.0, sol.contact_half_width(axis=0, center=(0.0, 0.0)) / a - 1.0


def test_cone_indenting_a_half_space_follows_sneddon():
    force, radius = _cone_solve(1.0, 400.0)
    assert abs(force) <= 0.01, force
    assert abs(radius) <= 0.02, radius


def test_cone_force_error_falls_with_the_size_of_the_truncated_half_space():
    errors = [_cone_solve(1.0, size)[0] for size in (50.0, 200.0, 400.0)]
    assert errors[0] > errors[1] > errors[2] > 0, errors  # the truncated body is stiffer


def _sphere_gap(center, radius):
    c = np.asarray(center, dtype=float)

    def gap(x):  # signed distance to the sphere's profile, > 0 inside the obstacle
        return radius - np.linalg.norm(np.asarray(x, dtype=float) - c, axis=1)

    def normal(x):  # -grad(gap): out of the obstacle
        d = np.asarray(x, dtype=float) - c
        return d / np.linalg.norm(d, axis=1, keepdims=True)

    return gap, normal


@pytest.mark.parametrize("exact_normal", [True, False])
def test_a_user_profile_equal_to_the_sphere_reproduces_it_at_small_deformation(exact_normal):
    prob = hertz.hertz_axisym(1)
    ref = solve(prob)
    circle = prob.obstacle
    gap, normal = _sphere_gap(circle.center, circle.radius)
    user = UserObstacle(gap=gap, normal=normal if exact_normal else None, dim=2, length_scale=circle.radius)
    sol = solve(ContactProblem(model=prob.model, obstacle=user, contact_boundary="top", supports=prob.supports))
    assert ref.result.success and sol.result.success
    tol = 1e-12 if exact_normal else 1e-9
    assert sol.normal_force == pytest.approx(ref.normal_force, rel=tol)
    assert np.max(np.abs(sol.u - ref.u)) <= tol * np.max(np.abs(ref.u))


def test_a_user_profile_equal_to_the_sphere_reproduces_it_at_finite_deformation():
    """The finite neo-Hookean hemisphere of revolution pressed onto a ball of radius 2 (the gap's curvature enters
    the Newton matrix: finite-difference Hessian of the user gap)."""
    base = hemisphere_axisym(6, order=2, delta=0.15)
    ball = Circle(center=(0.0, -2.0), radius=2.0)
    ref = solve(ContactProblem(model=base.model, obstacle=ball, contact_boundary="curved", supports=base.supports,
                               kinematics="finite"), "simo-laursen", steps=3)
    gap, _ = _sphere_gap(ball.center, ball.radius)
    user = UserObstacle(gap=gap, dim=2, length_scale=2.0)
    sol = solve(ContactProblem(model=base.model, obstacle=user, contact_boundary="curved", supports=base.supports,
                               kinematics="finite"), "simo-laursen", steps=3)
    assert ref.result.success and sol.result.success, (ref.result.message, sol.result.message)
    assert ref.total_contact_force[1] > 0
    assert sol.total_contact_force[1] == pytest.approx(ref.total_contact_force[1], rel=1e-9)
