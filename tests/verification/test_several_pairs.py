"""Several contact pairs on one body: a block squeezed between two rigid plates.

Reference (closed form): a block of height ``H`` between two rigid planes that each
approach it by ``d`` (frictionless, laterally free: sigma_xx = 0) is in uniform uniaxial
stress along y. Plane strain: ``p = E / (1 - nu^2) * 2 d / H``; 3D (sigma_xx = sigma_zz = 0):
``p = E * 2 d / H``. The augmented Lagrangian algorithms and the semi-smooth Newton
reference reproduce it (3D: the plates squeeze along z) to 1e-10 relative on the direct path (1e-8 on the AMG/Krylov path,
whose solves stop at a relative residual); the pure penalty (6.10) is off by its
penalty error and is checked against the same number to 1e-6. The two pairs' forces
balance (action = reaction through the body) to 1e-10 of their size. Each pair keeps its own Coulomb coefficient:
at full slip each pair's tangential force is its own mu times its normal force (1e-8).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import (Boundary, ContactPair, ContactProblem, LoadCase, LoadHistory, Ramp, Support, obstacles,
                               solve)
from alcontact.contact.laws import SLIP
from alcontact.contact.masters._stacked import StackedMaster
from alcontact.errors import InputError
from alcontact.fem import LinearElasticity, Material, meshes

E, NU, H, D = 1000.0, 0.3, 1.0, 0.01


def _squeeze(dim: int, friction: float = 0.0) -> ContactProblem:
    if dim == 2:
        body = LinearElasticity(meshes.rectangle(0.0, 1.0, 0.0, H, 4, 4), Material(E=E, nu=NU, plane="strain"))
        lo = obstacles.make("half-space", point=[0.0, D], normal=[0.0, 1.0])
        hi = obstacles.make("half-space", point=[0.0, H - D], normal=[0.0, -1.0])
        supports = [Support("left", components=[0])]
    else:
        body = LinearElasticity(meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, H, 2, 2, 2), Material(E=E, nu=NU))
        lo = obstacles.make("half-space", point=[0.0, 0.0, D], normal=[0.0, 0.0, 1.0])
        hi = obstacles.make("half-space", point=[0.0, 0.0, H - D], normal=[0.0, 0.0, -1.0])
        supports = [Support("left", components=[0]), Support("front", components=[1])]
    pairs = [ContactPair(Boundary(body, "bottom"), lo, friction=friction),
             ContactPair(Boundary(body, "top"), hi, friction=friction)]
    return ContactProblem(bodies=[body], pairs=pairs, supports=supports, name="squeeze")


def _exact(dim: int) -> float:
    return (E / (1 - NU**2) if dim == 2 else E) * 2 * D / H


@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn", "penalty"])
@pytest.mark.parametrize("linear_solver", ["direct", "amg"])
def test_block_between_two_plates_is_in_uniaxial_stress(algorithm, linear_solver):
    prob = _squeeze(2)
    sol = solve(prob, algorithm=algorithm, options={"linear_solver": linear_solver})
    assert sol.result.status > 0, sol.result.message
    tol = 1e-6 if algorithm == "penalty" else (1e-10 if linear_solver == "direct" else 1e-8)
    np.testing.assert_allclose(sol.pressure, _exact(2), rtol=tol)
    owner = prob.pair_of_points()
    assert set(owner.tolist()) == {0, 1} and np.all(sol.active)  # both pairs' points, all in contact
    forces = sol.pair_contact_forces()
    assert forces.shape == (2, 2)
    np.testing.assert_array_equal(sol.frames[-1].pair_forces, forces)  # the same on the solution's frame
    np.testing.assert_allclose(forces[0], [0.0, _exact(2) * 1.0], rtol=tol, atol=1e-9 * _exact(2))
    assert np.linalg.norm(forces[0] + forces[1]) <= 1e-10 * np.linalg.norm(forces[0])


def test_block_between_two_plates_3d():
    sol = solve(_squeeze(3), algorithm="simo-laursen")
    assert sol.result.status > 0, sol.result.message
    np.testing.assert_allclose(sol.pressure, _exact(3), rtol=1e-10)
    f = sol.pair_contact_forces()
    assert np.linalg.norm(f[0] + f[1]) <= 1e-10 * np.linalg.norm(f[0])


def test_each_pair_is_measured_against_its_own_master():
    prob = _squeeze(2)
    pts, _ = prob.slave_nodes()
    g = prob.obstacle.gap(pts)
    owner = prob.pair_of_points()
    np.testing.assert_allclose(g[owner == 0], D)  # bottom points penetrate the lower plate by d
    np.testing.assert_allclose(g[owner == 1], D)  # top points the upper one
    np.testing.assert_allclose(prob.slave_weights().sum(), 2.0)  # two unit-length faces


@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn"])
def test_two_frictional_pairs_run_every_coulomb_algorithm(algorithm):
    """Same coefficient on both pairs: the Coulomb paths run on the stacked points; the normal forces
    balance and every algorithm gives the same state (to its tolerance)."""
    ref = solve(_squeeze(2, friction=0.2), algorithm="ssn")
    sol = solve(_squeeze(2, friction=0.2), algorithm=algorithm)
    assert sol.result.status > 0 and ref.result.status > 0
    f = sol.pair_contact_forces()
    assert abs(f[0, 1] + f[1, 1]) <= 1e-10 * abs(f[0, 1])
    assert f[0, 1] > _exact(2)  # friction holds the faces: stiffer than the free uniaxial state
    np.testing.assert_allclose(f, ref.pair_contact_forces(), rtol=1e-6, atol=1e-8 * abs(f[0, 1]))


def test_stacked_master_needs_the_points_of_every_pair():
    prob = _squeeze(2)
    pts, _ = prob.slave_nodes()
    assert isinstance(prob.obstacle, StackedMaster)
    with pytest.raises(InputError, match="stacked points of all pairs"):
        prob.obstacle.gap(pts[:3])


@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn", "penalty"])
def test_seal_pressed_by_a_cover_into_a_meshed_groove(algorithm):
    """A block held only by its two pairs: a rigid cover 0.02 into its top face and a meshed non-convex
    V-groove (obstacle ``surface``) under its bottom. No supports: the pair forces balance each other
    (1e-10 of their size, the groove's horizontal component included), and the groove gives the
    solution of the analytic V (the larger of the two wall gaps, exact where the body is) to 1e-10."""
    body = LinearElasticity(meshes.rectangle(-1.0, 1.0, 0.0, 1.0, 8, 4), Material(E=E, nu=NU))
    cover = obstacles.make("half-space", point=[0.0, 0.98], normal=[0.0, -1.0])
    groove = obstacles.make("surface", vertices=[[2.0, 0.5], [0.0, -0.5], [-2.0, 0.5]], facets=[[0, 1], [1, 2]])
    nl, nr = np.array([0.5, 1.0]) / np.sqrt(1.25), np.array([-0.5, 1.0]) / np.sqrt(1.25)
    walls = obstacles.UserObstacle(
        lambda x: np.maximum(-(x - [0.0, -0.5]) @ nl, -(x - [0.0, -0.5]) @ nr), dim=2,
        normal=lambda x: np.where(((-(x - [0.0, -0.5]) @ nl) >= (-(x - [0.0, -0.5]) @ nr))[:, None], nl, nr))
    sols = [solve(ContactProblem(bodies=[body], pairs=[ContactPair(Boundary(body, "bottom"), ob),
                                                       ContactPair(Boundary(body, "top"), cover)]), algorithm)
            for ob in (groove, walls)]
    a, b = sols
    assert a.result.status > 0 and b.result.status > 0, a.result.message
    f = a.pair_contact_forces()
    assert f[1, 1] < 0 < f[0, 1]  # the cover pushes down, the groove up
    assert np.linalg.norm(f[0] + f[1]) <= 1e-10 * np.linalg.norm(f[0])
    assert float(np.abs(a.u - b.u).max()) <= 1e-10 * float(np.abs(b.u).max())


@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn", "penalty"])
def test_two_pairs_at_finite_deformation_match_the_supported_block(algorithm):
    """Finite deformation (neo-Hookean, plane strain): a block clamped at its bottom, pressed 0.05 by a
    plate on its top (pair 1) and bulging into a frictionless rigid wall on its right (pair 2; the top-right
    node is in both pairs). Every right-face node presses the wall, so the reference is the same block with
    the top pair only and u_x = 0 on its right face (a support): the same displacement (1e-7 relative: the
    wall's gap is met to the solver's tolerance; family-p and ssn reach 2e-15) and top force, and the wall
    pair's force is horizontal."""
    from alcontact.fem import Hyperelastic

    def body():
        return Hyperelastic(meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4), Material(E=E, nu=NU, plane="strain"))

    plate = obstacles.make("half-space", point=[0.0, 0.95], normal=[0.0, -1.0])
    wall = obstacles.make("half-space", point=[1.0, 0.0], normal=[-1.0, 0.0])
    b = body()
    two = ContactProblem(bodies=[b], pairs=[ContactPair(Boundary(b, "top"), plate),
                                            ContactPair(Boundary(b, "right"), wall)],
                         supports=[Support("bottom")], kinematics="finite")
    ref_body = body()
    one = ContactProblem(ref_body, plate, "top", supports=[Support("bottom"), Support("right", components=[0])],
                         kinematics="finite")
    a, r = solve(two, algorithm, steps=4), solve(one, algorithm, steps=4)
    assert a.result.status > 0 and r.result.status > 0, a.result.message
    assert float(np.abs(a.u - r.u).max()) <= 1e-7 * float(np.abs(r.u).max())
    f = a.pair_contact_forces()
    np.testing.assert_allclose(f[0], r.pair_contact_forces()[0], rtol=1e-7)
    assert f[1, 0] < 0 and abs(f[1, 1]) <= 1e-12 * abs(f[1, 0])
    assert a.result.newton_iterations <= r.result.newton_iterations + 1


@pytest.mark.parametrize("linear_solver", ["direct", "amg"])
@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn"])
def test_each_pair_slides_with_its_own_friction_coefficient(algorithm, linear_solver):
    """A block squeezed between two plates (bottom pair mu = 0.1, top pair mu = 0.4), then pulled sideways by its
    left face until both faces slide. Reference (Coulomb's law at full slip): every sliding point carries
    |t_T| = mu t_N of its own pair, so each pair's tangential force is mu_pair times the normal force of its
    sliding points, to 1e-8 (the two left corners are held in x by the pull: their friction goes into the
    support reaction, and they are the only points that do not slide)."""
    prob = _squeeze(2)
    body = prob.model
    lo, hi = (p.master for p in prob.pairs)
    mus = (0.1, 0.4)
    prob = ContactProblem(bodies=[body], pairs=[ContactPair(Boundary(body, "bottom"), lo, friction=mus[0]),
                                                ContactPair(Boundary(body, "top"), hi, friction=mus[1])])
    pull = LoadCase(Support("left", components=(0,), value=0.05), Ramp((0.5, 1.0), (0.0, 1.0)), tangential=True)
    sol = solve(prob, algorithm, history=LoadHistory((pull,), LoadHistory.uniform(4)),
                options={"linear_solver": linear_solver})
    assert sol.result.success, sol.result.message
    owner, state = prob.pair_of_points(), sol.extra["state"]
    on_left = np.isclose(sol.points[:, 0], 0.0)
    assert np.all(state[~on_left] == SLIP)
    forces = sol.pair_contact_forces()
    for k, mu in enumerate(mus):
        sliding = (owner == k) & (state == SLIP)
        N = float(np.sum(sol.normal_nodal_forces[sliding]))
        assert abs(forces[k, 0]) == pytest.approx(mu * N, rel=1e-8)
    assert abs(forces[0, 0]) < abs(forces[1, 0])  # the rougher plate holds more
