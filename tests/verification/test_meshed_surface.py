"""A meshed rigid surface master (obstacle ``"surface"``): polylines and triangulations, convex or not.

References and tolerances:

- a meshed plane is the analytic plane: the same gap, normal and zero Hessian, hence the
  same contact solution as ``half-space`` to 1e-10 relative (Signorini cantilever with
  lift-off in 2D; the 3D patch block, whose exact pressure is ``E d / H``-type closed form);
- a finely meshed circle (the lower arc of the Hertz cylinder, vertices on the circle)
  converges to the analytic circle's solution as the facet count N grows. Measured on
  ``hertz_2d(level=1)`` (4664 DOFs), relative max-norm difference of the displacement:
  N = 64: 1.9e-3, 128: 6.8e-4, 256: 3.1e-4, 512: 1.5e-4, 1024: 7.0e-5, 2048: 3.1e-5 —
  first order in 1/N, set by the facet normals (piecewise constant, their angle error is
  O(1/N)); the total contact force converges faster (8.3e-4 at N = 64, 1.7e-6 at N = 1024).
  Checked: observed rate >= 0.9 over N = 128, 256, 512 and, at N = 1024, contact force and
  half-width within 1e-4 of the analytic circle's;
- a non-convex V-shaped groove: a block pressed into it touches both walls; in the region
  where the body is, the distance to the V is the smaller distance to its two walls, so the
  solution equals that of the analytic ``UserObstacle(max(g_left, g_right))`` to 1e-10.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from alcontact.contact import ContactProblem, Support, obstacles, solve
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.problems import blocks, hertz


def _rel(a, b) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


def test_meshed_plane_gives_the_half_space_solution_2d():
    base = blocks.signorini_block(n=4)
    gap = -base.obstacle.point[1]
    x = np.linspace(-1.0, 5.0, 8)  # segments walked in -x: free side (the right of the walk) is +y
    V = np.column_stack([x[::-1], np.full(x.size, -gap)])
    F = np.column_stack([np.arange(x.size - 1), np.arange(1, x.size)])
    meshed = dataclasses.replace(base, obstacle=obstacles.make("surface", vertices=V, facets=F))
    for alg in ("simo-laursen", "ssn"):
        a, b = solve(base, alg), solve(meshed, alg)
        assert a.result.status > 0 and b.result.status > 0
        assert 0 < np.count_nonzero(b.active) < b.points.shape[0]  # lift-off: part of the face in contact
        assert _rel(b.u, a.u) <= 1e-10 and _rel(b.pressure, a.pressure) <= 1e-10
        np.testing.assert_array_equal(a.active, b.active)


def test_meshed_plane_gives_the_half_space_solution_3d():
    base = blocks.patch_block(dim=3, n=2)
    n = 4
    g = np.linspace(-1.0, 2.0, n)
    X, Y = np.meshgrid(g, g, indexing="ij")
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(n * n)])
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])  # counter-clockwise from +z
    meshed = dataclasses.replace(base, obstacle=obstacles.make("surface", vertices=V, facets=F))
    ra, rb = solve(base, "simo-laursen"), solve(meshed, "simo-laursen")
    assert ra.result.status > 0 and rb.result.status > 0
    assert _rel(rb.u, ra.u) <= 1e-10
    np.testing.assert_allclose(rb.pressure, base.meta["pressure_exact"], rtol=1e-10)


def _arc(center, radius, n):
    th = np.linspace(-np.pi / 2 - 0.5, -np.pi / 2 + 0.5, n + 1)  # counter-clockwise: a solid disc, body outside
    V = np.asarray(center) + radius * np.column_stack([np.cos(th), np.sin(th)])
    return obstacles.make("surface", vertices=V, facets=np.column_stack([np.arange(n), np.arange(1, n + 1)]))


def test_finely_meshed_circle_converges_to_the_analytic_circle():
    base = hertz.hertz_2d(level=1)
    ref = solve(base, "simo-laursen")
    assert ref.result.status > 0
    c, R = base.obstacle.center, base.obstacle.radius
    errs = {}
    for n in (128, 256, 512, 1024):
        sol = solve(dataclasses.replace(base, obstacle=_arc(c, R, n)), "simo-laursen")
        assert sol.result.status > 0
        errs[n] = (_rel(sol.u, ref.u), sol)
    rates = [np.log2(errs[n][0] / errs[2 * n][0]) for n in (128, 256)]
    assert min(rates) >= 0.9, rates
    fine = errs[1024][1]
    assert abs(fine.normal_force / ref.normal_force - 1) <= 1e-4
    assert abs(fine.contact_half_width() / ref.contact_half_width() - 1) <= 1e-4


@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn", "penalty"])
def test_block_pressed_into_a_v_groove(algorithm):
    """Non-convex master: the V y = -0.5 + 0.5|x| (free side above) holds a block's two bottom corners."""
    V = [[2.0, 0.5], [0.0, -0.5], [-2.0, 0.5]]  # walked right to left: free side (right of the walk) up
    groove = obstacles.make("surface", vertices=V, facets=[[0, 1], [1, 2]])
    nl, nr = np.array([0.5, 1.0]) / np.sqrt(1.25), np.array([-0.5, 1.0]) / np.sqrt(1.25)  # left, right wall
    # in the region of the block the distance to the V is the smaller distance to its two wall lines
    walls = obstacles.UserObstacle(
        lambda x: np.maximum(-(x - [0.0, -0.5]) @ nl, -(x - [0.0, -0.5]) @ nr), dim=2,
        normal=lambda x: np.where(((-(x - [0.0, -0.5]) @ nl) >= (-(x - [0.0, -0.5]) @ nr))[:, None], nl, nr))
    body = LinearElasticity(meshes.rectangle(-1.0, 1.0, 0.0, 1.0, 8, 4), Material(E=1000.0, nu=0.3))
    supports = [Support("top", components=[1], value=-0.02), Support("top", components=[0])]
    sols = [solve(ContactProblem(body, ob, "bottom", supports=supports), algorithm) for ob in (groove, walls)]
    a, b = sols
    assert a.result.status > 0 and b.result.status > 0, a.result.message
    assert np.count_nonzero(a.active) >= 2
    assert _rel(a.u, b.u) <= 1e-10
    f = a.contact_point_forces()
    left, right = a.points[:, 0] < 0, a.points[:, 0] > 0
    # each wall pushes along its own normal
    np.testing.assert_allclose(f[left].sum(axis=0)[0] / f[left].sum(axis=0)[1], nl[0] / nl[1], rtol=1e-8)
    np.testing.assert_allclose(f[right].sum(axis=0)[0] / f[right].sum(axis=0)[1], nr[0] / nr[1], rtol=1e-8)


def _finite_block(obstacle, boundary="bottom", supports=None):
    from alcontact.fem import Hyperelastic

    body = Hyperelastic(meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4), Material(E=1000.0, nu=0.3, plane="strain"))
    supports = supports or [Support("top", (1,), -0.05), Support("left", (0,))]
    return ContactProblem(body, obstacle, boundary, supports=supports, kinematics="finite")


def test_meshed_plane_gives_the_half_space_solution_at_finite_deformation():
    """Finite path (current-configuration gap, its Hessian in the tangent): body nodes sit exactly above
    polyline vertices, where a flat polyline must still be a plane (zero Hessian): same Newton iterations."""
    x = np.linspace(-1.0, 2.0, 5)[::-1]  # vertex at x = 0.5, a node of the body's bottom face
    meshed = obstacles.make("surface", vertices=np.column_stack([x, 0 * x]),
                            facets=np.column_stack([np.arange(4), np.arange(1, 5)]))
    a = solve(_finite_block(obstacles.make("half-space", point=[0.0, 0.0], normal=[0.0, 1.0])), "simo-laursen",
              steps=2)
    b = solve(_finite_block(meshed), "simo-laursen", steps=2)
    assert a.result.status > 0 and b.result.status > 0
    assert b.result.newton_iterations == a.result.newton_iterations
    assert _rel(b.u, a.u) <= 1e-10


def test_meshed_circle_at_finite_deformation_converges_to_the_circle():
    """A neo-Hookean block indented by a rigid cylinder (R = 1, 0.08 deep) and by its meshed arc of N facets:
    contact force relative difference 9.4e-3 (N = 32), 2.1e-3 (64), 3.9e-4 (128), 2.3e-4 (256) measured;
    checked: <= 1e-3 at N = 128 and no more Newton iterations than the analytic circle's."""
    from alcontact.fem import Hyperelastic

    body = Hyperelastic(meshes.rectangle(-1.0, 1.0, 0.0, 1.0, 16, 8), Material(E=1000.0, nu=0.3, plane="strain"))
    c = np.array([0.0, 1.0 + 1.0 - 0.08])  # radius 1, 0.08 into the top face y = 1
    th = np.linspace(-np.pi / 2 - 1.2, -np.pi / 2 + 1.2, 129)
    arc = obstacles.make("surface", vertices=c + np.column_stack([np.cos(th), np.sin(th)]),
                         facets=np.column_stack([np.arange(128), np.arange(1, 129)]))
    sols = [solve(ContactProblem(body, ob, "top", supports=[Support("bottom")], kinematics="finite"),
                  "simo-laursen", steps=2) for ob in (obstacles.make("circle", center=c, radius=1.0), arc)]
    a, b = sols
    assert a.result.status > 0 and b.result.status > 0
    assert abs(b.normal_force / a.normal_force - 1) <= 1e-3
    assert b.result.newton_iterations <= a.result.newton_iterations
