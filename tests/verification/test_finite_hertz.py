r"""Finite-deformation contact of a neo-Hookean block indented by a rigid cylinder (Hertz setting).

The meshes are those of :func:`alcontact.problems.hertz.hertz_2d` (coarse level), the body
a neo-Hookean :class:`~alcontact.fem.hyperelastic.Hyperelastic` with the same E, nu; the
cylinder starts touching the block and is moved down by the Hertz approach
:math:`\delta` over the load steps (``obstacle_path``).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from _helpers import assert_quadratic_pairs
from alcontact.contact import Support, obstacles, solve, solve_finite
from alcontact.fem.hyperelastic import Hyperelastic
from alcontact.problems import hertz


def _finite(problem):
    body = Hyperelastic(problem.model.mesh, problem.model.material, order=problem.model.order)
    return dataclasses.replace(problem, model=body, kinematics="finite")


def _press(delta):
    return lambda t: np.array([0.0, delta * (1.0 - t)])


@pytest.mark.parametrize("algorithm", ["ssn", "simo-laursen"])
def test_small_load_limit_equals_small_deformation(algorithm):
    r"""At :math:`\delta/R = 10^{-4}` the finite-deformation solution equals the small-deformation one.

    Reference: the small-deformation (linear elastic, linearized gap) solution on the same
    mesh; the nonlinear terms are of the order of the contact strain :math:`a/R \approx
    0.007`, their effect on force and contact half-width is required below 1e-3 relative.
    """
    small = hertz.hertz_2d(n_per_a=4, a_target=0.0726, growth=1.3)
    delta = small.meta["delta"]
    assert abs(delta / 10.0 - 1e-4) < 2e-6
    ref = solve(small, "ssn")
    assert ref.status > 0
    fs = solve_finite(_finite(small), algorithm, steps=2, obstacle_path=_press(delta))
    assert fs.success, fs.message
    sol = fs.solution
    assert abs(sol.normal_force / ref.normal_force - 1.0) <= 1e-3
    assert abs(sol.contact_half_width() / ref.contact_half_width() - 1.0) <= 1e-3


def _quadratic_pairs(log):
    """Pairs (e_k, e_k+1) near the solution.

    The final monotone run of the residuals (after the last increase, i.e. once the
    active set has settled), with e_k <= 1e-2 and e_k+1 above the round-off floor 1e-10.
    """
    start = 0
    for k in range(1, len(log)):
        if log[k] > log[k - 1]:
            start = k
    tail = log[start:]
    return [(a, b) for a, b in zip(tail[:-1], tail[1:]) if a <= 1e-2 and b >= 1e-10]


@pytest.mark.parametrize("algorithm", ["ssn", "simo-laursen"])
def test_newton_converges_quadratically(algorithm):
    r"""Ratio test on every Newton solve (reference active-set steps, Algorithm 6.1 subproblems).

    Near the solution, quadratic convergence means :math:`e_{k+1} \le C e_k^2` with a
    moderate constant; linear or superlinear convergence would give
    :math:`e_{k+1}/e_k^2 \to \infty` and an order estimate :math:`\log e_{k+1}/\log e_k`
    near 1. Asserted for every pair with :math:`e_k \le 10^{-2}` in the final monotone run
    above the round-off floor: :math:`e_{k+1}/e_k^2 \le 10^3` and
    :math:`\log e_{k+1}/\log e_k \ge 1.5`, with at least 2 such pairs (curved obstacle:
    without the curvature term of the tangent this fails).
    """
    problem = _finite(hertz.hertz_2d(n_per_a=4, growth=1.3))
    # every subproblem to newton_tol (inexact ones stop after one or two quadratic steps), and the
    # tangent predictor (step 2 of the secant predictor starts too close for two pairs)
    fs = solve_finite(problem, algorithm, steps=2, obstacle_path=_press(problem.meta["delta"]), subproblems="exact",
                      predictor="tangent")
    assert fs.success, fs.message
    pairs = [p for log in fs.extra["residual_log"] for p in _quadratic_pairs(log)]
    assert_quadratic_pairs(pairs)


@pytest.mark.parametrize("algorithm", ["ssn", "simo-laursen"])
def test_objectivity_under_rigid_rotation(algorithm):
    """The problem rotated by 90 degrees (body, supports, obstacle, its path) gives the same reaction.

    Reference: the unrotated solution; the magnitudes of the resultant contact force agree
    within 1e-8 relative, and the rotated resultant is the rotated original one.
    """
    problem = _finite(hertz.hertz_2d(n_per_a=4, growth=1.3))
    delta = problem.meta["delta"]
    fs = solve_finite(problem, algorithm, steps=2, obstacle_path=_press(delta))
    rot = np.array([[0.0, -1.0], [1.0, 0.0]])
    mesh = problem.model.mesh
    mesh_r = dataclasses.replace(mesh, doflocs=rot @ mesh.doflocs)
    body_r = Hyperelastic(mesh_r, problem.model.material)
    ob = problem.obstacle
    rotated = dataclasses.replace(
        problem, model=body_r, obstacle=obstacles.Circle(center=rot @ np.asarray(ob.center), radius=ob.radius),
        supports=(Support("bottom"), Support("left", components=(1,))))
    fr = solve_finite(rotated, algorithm, steps=2, obstacle_path=lambda t: rot @ _press(delta)(t))
    assert fs.success and fr.success
    f0, f1 = fs.solution.total_contact_force, fr.solution.total_contact_force
    assert abs(np.linalg.norm(f1) / np.linalg.norm(f0) - 1.0) <= 1e-8
    assert np.linalg.norm(f1 - rot @ f0) <= 1e-8 * np.linalg.norm(f0)
