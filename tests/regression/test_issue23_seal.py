"""Issue 23: a seal, a neo-Hookean cord squeezed between two deformable plates (two two-body pairs).

:func:`alcontact.problems.two_body.seal` (``n = 8``: cord radius R = 1, E = 10, nu = 0.45, 64 boundary
segments; plates E = 1000, nu = 0.3, non-matching meshes), squeezed by 20 % of the diameter in 8 load
steps at finite deformation, frictionless: two mortar pairs at the current configuration, the cord the
slave of both. Promises guarded here (measured, in brackets):

- every frictionless algorithm converges without cut-back; ``ssn`` takes <= 6 Newton iterations per
  step on average [3.5];
- action = reaction in each pair: its forces on the cord and on its plate sum to zero to 1e-10 of
  the pair's force (``contact_force_balance``, the worst pair) [1e-15];
- the discrete problem is invariant under the half turn about the cord's centre (the meshes and the
  squeeze are), so the two pairs' forces are opposite to 1e-8 relative [1e-15]; the horizontal force of
  a pair is below 1e-5 of its vertical one (the meshes are not mirror-symmetric: the triangles'
  diagonals) [1.7e-6];
- the same cord and plates as linear elastic bodies at small deformation (the stacked linear mortar
  rows of both pairs, ``kinematics._stacked_gap``) solve too, with action = reaction in each pair.
"""

import numpy as np
import pytest

from alcontact.contact import ContactProblem, solve
from alcontact.fem import LinearElasticity
from alcontact.problems import two_body


@pytest.fixture(scope="module")
def problem():
    return two_body.seal(8)


@pytest.mark.parametrize("algorithm,penalty", [("ssn", None), ("simo-laursen", None), ("family-p", "exp-met1")])
def test_seal_converges_and_balances_each_pair(problem, algorithm, penalty):
    sol = solve(problem, algorithm, penalty, steps=8)
    assert sol.result.success, sol.result.message
    assert sol.extra["kinematics"] == "finite" and len(sol.frames) == 8  # no cut-back
    newton = np.array([f.newton_iterations for f in sol.frames])
    if algorithm == "ssn":
        assert newton.mean() <= 6.0, newton
    assert sol.extra["contact_force_balance"] <= 1e-10
    lower, upper = sol.pair_contact_forces()
    assert lower[1] > 0 > upper[1]  # each plate pushes the cord towards the other
    np.testing.assert_allclose(lower, -upper, rtol=0, atol=1e-8 * abs(lower[1]))
    assert abs(lower[0]) <= 1e-5 * abs(lower[1])


def test_several_two_body_pairs_at_small_deformation_solve_and_balance(problem):
    """The small-deformation path takes the two pairs stacked (it once refused them): converged, each pair's
    forces on the cord and on its plate sum to zero (1e-10 of its force), the plates push the cord apart."""
    bodies = [LinearElasticity(b.mesh, b.material) for b in problem.bodies]
    from alcontact.contact import BodySurface, Boundary, ContactPair

    pairs = [ContactPair(Boundary(bodies[0], "lower"), BodySurface(bodies[1], "top")),
             ContactPair(Boundary(bodies[0], "upper"), BodySurface(bodies[2], "bottom"))]
    small = ContactProblem(bodies=bodies, pairs=pairs, supports=problem.supports)
    sol = solve(small, "ssn")
    assert sol.result.success, sol.result.message
    assert small.kinematics == "small"
    assert sol.extra["contact_force_balance"] <= 1e-10
    lower, upper = sol.pair_contact_forces()
    assert lower[1] > 0 > upper[1]
