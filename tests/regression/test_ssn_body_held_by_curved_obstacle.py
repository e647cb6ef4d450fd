"""Regression: the active-set reference ignored the contact springs of a body held only
by the obstacle.

On a flat obstacle the springs act at zero gap, so the error did not show; on a
circle the reference returned a contact force of 0.61 instead of the 5.0 the
pressure load requires (found while unifying the active-set loops of the direct and
AMG paths). Reference: equilibrium (total contact force = pressure x width) and a second,
independent algorithm's solution (1e-6 relative in displacement).
"""

import numpy as np
import pytest

from alcontact.contact import ContactProblem, Pressure, Support, solve
from alcontact.contact.obstacles import Circle
from alcontact.fem import LinearElasticity, Material, meshes


@pytest.mark.parametrize("algorithm,penalty", [("ssn", None), ("family-p", "exp-met1"), ("simo-laursen", None)])
def test_floating_block_on_circle(algorithm, penalty):
    model = LinearElasticity(meshes.rectangle(0, 1, 0, 0.5, 16, 8), Material(E=1000.0, nu=0.3))
    prob = ContactProblem(model, Circle(center=(0.5, -2.0), radius=2.0), "bottom",
                          supports=(Support("left", components=(0,)),), loads=(Pressure("top", 5.0),))
    sol = solve(prob, algorithm, penalty)
    assert sol.result.success, sol.result.message
    # vertical equilibrium: the obstacle carries the whole load 5.0 x 1.0 (normals tilt slightly)
    assert abs(sol.total_contact_force[1] - 5.0) <= 1e-6 * 5.0
    # an algorithm other than the one under test (a run is never its own reference)
    ref = solve(prob, "ssn" if algorithm != "ssn" else "simo-laursen")
    assert np.max(np.abs(sol.u - ref.u)) <= 1e-6 * np.max(np.abs(ref.u))
