"""Several contact pairs of which one or more joins two bodies (2D mortar, small deformation).

References, each stated in its test:

- three blocks stacked (two mortar pairs, non-matching meshes), a uniform pressure on the top: the contact
  patch test on both interfaces (the stress is uniaxial in every block, the interface pressure is the applied
  one at every slave node; Taylor & Papadopoulos 1991), 1e-8 relative;
- a block on a deformable base pressed by a rigid plate (a mortar pair and a rigid pair), laterally free:
  uniform uniaxial stress through both blocks, plane strain, compatibility of the approach d:
  p = d / ((1 - nu1^2) H1 / E1 + (1 - nu2^2) H2 / E2), 1e-8 relative, on both interfaces;
- three blocks, the top one dragged: it slides on the middle one (the pair of smaller mu), all its nodes on
  the Coulomb circle, so that pair's Q = mu N (1e-8); the middle block, held by its two contacts only, sticks
  on the base and carries the same tangential force (its equilibrium, 1e-8); each pair's forces balance.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import BodySurface, Boundary, ContactPair, ContactProblem, Pressure, Support, obstacles, solve
from alcontact.contact.laws import SLIP
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.problems.two_body_friction import drag_history

ALGS = ("simo-laursen", "family-p", "ssn")


def _block(y0: float, y1: float, n: int, E: float, nu: float, x=(0.0, 1.0)) -> LinearElasticity:
    return LinearElasticity(meshes.rectangle(x[0], x[1], y0, y1, n, n), Material(E=E, nu=nu, plane="strain"))


def _stack_of_three():
    b0, b1, b2 = _block(0, 1, 2, 1000.0, 0.3), _block(1, 2, 3, 500.0, 0.2), _block(2, 3, 5, 800.0, 0.25)
    pairs = [ContactPair(Boundary(b1, "bottom"), BodySurface(b0, "top")),
             ContactPair(Boundary(b2, "bottom"), BodySurface(b1, "top"))]
    return ContactProblem(bodies=[b0, b1, b2], pairs=pairs, loads=[Pressure("body2/top", 10.0)],
                          supports=[Support("body0/bottom", components=[1])]
                          + [Support(f"body{k}/left", components=[0]) for k in range(3)])


@pytest.mark.parametrize("linear_solver", ["direct", "amg"])
@pytest.mark.parametrize("algorithm", ALGS + ("penalty",))
def test_three_stacked_blocks_pass_the_patch_test_on_both_interfaces(algorithm, linear_solver):
    prob = _stack_of_three()
    sol = solve(prob, algorithm, options={"linear_solver": linear_solver})
    assert sol.result.success, sol.result.message
    owner = prob.pair_of_points()
    assert set(owner.tolist()) == {0, 1} and np.all(sol.active)
    np.testing.assert_allclose(sol.pressure, 10.0, rtol=1e-8)
    assert sol.extra["contact_force_balance"] <= 1e-10
    for entry in sol.extra["pair_balance"]:
        np.testing.assert_allclose(entry["slave_force"], [0.0, 10.0], atol=1e-8 * 10.0)
        np.testing.assert_allclose(entry["master_force"], [0.0, -10.0], atol=1e-8 * 10.0)
    assert sol.equilibrium().free_residual <= 1e-8


@pytest.mark.parametrize("linear_solver", ["direct", "amg"])
@pytest.mark.parametrize("algorithm", ALGS)
def test_block_on_a_deformable_base_pressed_by_a_rigid_plate(algorithm, linear_solver):
    E1, nu1, E2, nu2, d = 1000.0, 0.3, 500.0, 0.2, 0.01
    base, block = _block(0, 1, 3, E1, nu1), _block(1, 2, 4, E2, nu2)
    plate = obstacles.make("half-space", point=[0.0, 2.0 - d], normal=[0.0, -1.0])
    prob = ContactProblem(bodies=[base, block], pairs=[ContactPair(Boundary(block, "bottom"), BodySurface(base, "top")),
                                                       ContactPair(Boundary(block, "top"), plate)],
                          supports=[Support("body0/bottom", components=[1]), Support("body0/left", components=[0]),
                                    Support("body1/left", components=[0])])
    exact = d / ((1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2)
    sol = solve(prob, algorithm, options={"linear_solver": linear_solver})
    assert sol.result.success, sol.result.message
    np.testing.assert_allclose(sol.pressure, exact, rtol=1e-8)
    forces = sol.pair_contact_forces()  # on the block: pushed up by the base, down by the plate
    np.testing.assert_allclose(forces, [[0.0, exact], [0.0, -exact]], atol=1e-8 * exact)
    balance = sol.extra["pair_balance"]
    assert balance[1] is None and balance[0]["balance"] <= 1e-10  # the plate's reaction is not in the model


@pytest.mark.parametrize("linear_solver", ["direct", "amg"])
@pytest.mark.parametrize("algorithm", ALGS)
def test_top_block_slides_on_the_pair_of_smaller_friction(algorithm, linear_solver):
    mat = Material(E=1000.0, nu=0.3, plane="strain")
    base = LinearElasticity(meshes.rectangle(-1.0, 1.0, 0.0, 0.5, 16, 4), mat)
    middle = LinearElasticity(meshes.rectangle(-0.75, 0.75, 0.5, 1.0, 13, 4), mat)
    top = LinearElasticity(meshes.rectangle(-0.5, 0.5, 1.0, 1.5, 9, 4), mat)
    mus = (0.5, 0.2)
    pairs = [ContactPair(Boundary(middle, "bottom"), BodySurface(base, "top"), friction=mus[0]),
             ContactPair(Boundary(top, "bottom"), BodySurface(middle, "top"), friction=mus[1])]
    prob = ContactProblem(bodies=[base, middle, top], pairs=pairs, supports=[Support("body0/bottom")])
    sol = solve(prob, algorithm, history=drag_history("body2/top", 0.005, 0.02, 4),
                options={"linear_solver": linear_solver})
    assert sol.result.success, sol.result.message
    owner, state = prob.pair_of_points(), sol.extra["state"]
    assert np.all(state[owner == 1] == SLIP) and not np.all(state[owner == 0] == SLIP)
    f = sol.pair_contact_forces()
    assert abs(f[1, 0]) == pytest.approx(mus[1] * f[1, 1], rel=1e-8)
    assert f[0, 0] == pytest.approx(f[1, 0], rel=1e-8) and abs(f[0, 0]) < mus[0] * f[0, 1]  # the middle in equilibrium
    assert sol.extra["contact_force_balance"] <= 1e-10


def test_a_rigid_body_with_unknown_pose_beside_other_pairs_is_refused():
    """Not supported yet (a RigidBody master is a pair on its own): an InputError that says so, not a state that
    fails its equilibrium check."""
    from alcontact.contact import RigidBody
    from alcontact.errors import InputError

    block = _block(1, 2, 4, 500.0, 0.2)
    plate = RigidBody(obstacles.make("half-space", point=[0.0, 2.0], normal=[0.0, -1.0]), [0.5, 2.0])
    floor = obstacles.make("half-space", point=[0.0, 1.0], normal=[0.0, 1.0])
    prob = ContactProblem(bodies=[block, plate], pairs=[ContactPair(Boundary(block, "bottom"), floor),
                                                        ContactPair(Boundary(block, "top"), plate)],
                          supports=[Support("body0/left", components=[0]),
                                    Support("body1", components=[0, 1, 2], value=(0.0, -0.01, 0.0))])
    with pytest.raises(InputError, match="on its own so far"):
        solve(prob, "ssn")
