"""Two deformable bodies, 3D mortar contact (linear triangles, dual multipliers): verification.

References and tolerances:

- contact patch test (Taylor & Papadopoulos, 1991; in 3D for mortar: Puso & Laursen, 2004):
  two stacked blocks with non-matching meshes (1:1, 2:3, 3:7, 7:3, and 3:7 with the
  slave face's nodes moved at random in its plane) under a uniform pressure p on the top: the
  stress is uniaxial and the interface pressure equals p at every slave node. The mortar
  weighted gap passes it exactly, so the tolerance is 1e-8 relative for the penalty-free
  algorithms (6.1, 6.3 with every registered contact penalty, ssn). The pure penalty (6.10) gets
  the same pressure (the top block is held by the contact only, so the pressure is statically
  determined); what a penalty cannot give is zero penetration: its gap is p / eps_N at every node
  (1e-8 relative);
- action = reaction: the contact forces on the slave and master bodies sum to zero (1e-10
  relative), and the slave's equals the applied load p * area (1e-10);
- Hertz (Johnson, Contact Mechanics, 1985, eq. 4.22-4.23 with 1/E* = (1-nu1^2)/E1 +
  (1-nu2^2)/E2): an elastic sphere (E 70e3, nu 0.35, R 10) on an elastic block (E 200e3,
  nu 0.3), quarter model, a/R about 0.1: contact radius (load-matched fit of the pressure
  field) and peak pressure (the nodal maximum) within 2 % from 6 elements per a, both errors
  decreasing from 4 to 6 elements per a (default suite) and the radius's on to 8 and 12 (slow).
  Measured: a -1.44 / -0.99 / -0.78 / -0.58 / -0.35 %, p0 -2.33 / -0.28 / +0.16 / +0.09 / +0.13 %
  at 4 / 6 / 8 / 12 / 16 elements per a (18k to 221k DOFs): the radius converges at first order
  (rate 1.0 from 4 to 16); p0 is within 0.2 % from 8 per a;
- rigid limit: the sphere on a flat block 1e6 times stiffer gives the pressures and
  displacements of the same sphere on the rigid flat (node-to-surface gaps (6.15)) within 1e-4;
- the factorization-free path (AMG + Krylov, block rigid modes per body) gives the direct
  path's pressures within 1e-6 relative.
"""

import math

import numpy as np
import pytest

from alcontact.contact import contact_penalties, solve
from alcontact.problems import two_body_3d

PATCH_ALGORITHMS = [("simo-laursen", None), ("family-p", "exp-met1"), ("ssn", None)]
PATCH_CASES = [((2, 2), 0.0), ((2, 3), 0.0), ((3, 7), 0.0), ((7, 3), 0.0), ((3, 7), 0.3)]


@pytest.mark.parametrize("ratio,distort", PATCH_CASES)
@pytest.mark.parametrize("algorithm,penalty", PATCH_ALGORITHMS)
def test_patch_test_non_matching_3d(ratio, distort, algorithm, penalty):
    prob = two_body_3d.stacked_blocks_3d(*ratio, pressure=10.0, distort=distort)
    sol = solve(prob, algorithm, penalty)
    assert sol.result.success, sol.result.message
    assert sol.result.algorithm == algorithm  # what was asked is what ran
    assert sol.pressure.size == (ratio[1] + 1) ** 2  # every node of the slave (top block's bottom)
    np.testing.assert_allclose(sol.pressure, prob.meta["pressure_exact"], rtol=1e-8, atol=0.0)
    assert sol.extra["contact_force_balance"] <= 1e-10


@pytest.mark.parametrize("penalty", contact_penalties())
def test_patch_test_every_family_p_penalty_3d(penalty):
    """Algorithm 6.3 with every registered penalty usable for contact, on the 3:7 meshes."""
    prob = two_body_3d.stacked_blocks_3d(3, 7, pressure=10.0)
    sol = solve(prob, "family-p", penalty)
    assert sol.result.success, sol.result.message
    assert sol.result.penalty == penalty
    np.testing.assert_allclose(sol.pressure, prob.meta["pressure_exact"], rtol=1e-8, atol=0.0)


@pytest.mark.parametrize("ratio", [(2, 3), (3, 7)])
def test_patch_test_pure_penalty_3d(ratio):
    """The pure penalty: exact pressure (statically determined), penetration p / eps_N at every node."""
    prob = two_body_3d.stacked_blocks_3d(*ratio, pressure=10.0)
    sol = solve(prob, "penalty")
    assert sol.result.success and sol.result.algorithm == "penalty"
    np.testing.assert_allclose(sol.pressure, 10.0, rtol=1e-8, atol=0.0)
    np.testing.assert_allclose(sol.gap, 10.0 / sol.result.eps_n, rtol=1e-8, atol=0.0)


@pytest.mark.parametrize("ratio", [(2, 3), (3, 7)])
def test_patch_test_action_reaction_3d(ratio):
    prob = two_body_3d.stacked_blocks_3d(*ratio, pressure=10.0, width=2.0)
    sol = solve(prob, "ssn")
    fs = np.asarray(sol.extra["slave_contact_force"])
    fm = np.asarray(sol.extra["master_contact_force"])
    # the top block is held by the contact only: the slave carries the applied load p * width^2
    np.testing.assert_allclose(fs, [0.0, 0.0, 10.0 * 4.0], rtol=1e-10, atol=1e-10 * 40.0)
    assert np.linalg.norm(fs + fm) <= 1e-10 * np.linalg.norm(fs)


@pytest.mark.parametrize("linear_solver", ["superlu", "amg"])
def test_patch_test_linear_solver_paths_3d(linear_solver):
    prob = two_body_3d.stacked_blocks_3d(3, 7)
    sol = solve(prob, "ssn", linear_solver=linear_solver)
    assert sol.result.success, sol.result.message
    assert sol.extra["linear_solver"] == linear_solver
    np.testing.assert_allclose(sol.pressure, prob.meta["pressure_exact"], rtol=1e-8, atol=0.0)


def _hertz_errors(prob, sol):
    ref = prob.reference
    P = ref.load(sol.normal_force)
    a_ex, p0_ex = ref.half_width(P), ref.peak_pressure(P)
    a = sol.contact_half_width(center=prob.meta["center"])
    return {"a": a / a_ex - 1, "p0": sol.peak_pressure_nodal_max / p0_ex - 1, "a_over_R": a_ex / ref.radius,
            "balance": sol.extra["contact_force_balance"], "dofs": prob.model.ndofs,
            "linear_solves": sol.result.linear_solves, "strategy": sol.extra["strategy"]}


def _sphere(level):
    prob = two_body_3d.sphere_on_block(level)
    sol = solve(prob, "ssn")
    assert sol.result.success, sol.result.message
    return _hertz_errors(prob, sol)


@pytest.fixture(scope="module")
def spheres():
    return [_sphere(level) for level in (0, 1)]


def test_hertz_sphere_on_block_within_2_percent(spheres):
    """Measured: a -1.44 / -0.99 %, p0 -2.33 / -0.28 % at 4 / 6 elements per a (18k / 39k DOFs)."""
    for e in spheres:
        assert 0.08 < e["a_over_R"] < 0.12
        assert abs(e["a"]) <= 0.02, spheres
    assert abs(spheres[1]["p0"]) <= 0.02, spheres


def test_hertz_sphere_on_block_converges(spheres):
    assert abs(spheres[1]["a"]) < abs(spheres[0]["a"]), spheres
    assert abs(spheres[1]["p0"]) < abs(spheres[0]["p0"]), spheres
    assert all(e["balance"] <= 1e-10 for e in spheres), spheres


@pytest.mark.slow
def test_hertz_sphere_on_block_converges_fine():
    """6, 8 and 12 elements per a: radius and peak pressure within 2 %, the radius's error decreasing
    (measured: see the module doc). The condensed direct path's Schur block holds the contact zone (the
    sphere's supports move it as a whole: predicted gaps per body), so every solve costs two linear
    solves (it took 97, column solves outside the block, at 12 per a with the reference gaps)."""
    errs = [_sphere(level) for level in (1, 2, 3)]
    assert all(e["strategy"] == "condensed" and e["linear_solves"] <= 2 for e in errs), errs
    assert all(abs(e["a"]) <= 0.02 and abs(e["p0"]) <= 0.02 for e in errs), errs
    a = [abs(e["a"]) for e in errs]
    assert a[0] > a[1] > a[2], errs
    rate = math.log(a[0] / a[2]) / math.log(12 / 6)
    assert rate > 0.5, (rate, errs)


def test_rigid_limit_3d():
    rigid, elastic = two_body_3d.rigid_limit_sphere(0, stiffening=1e6)
    sr, se = solve(rigid, "ssn"), solve(elastic, "ssn")
    assert sr.result.success and se.result.success
    assert np.max(np.abs(se.pressure - sr.pressure)) <= 1e-4 * sr.pressure.max()
    u_sphere = elastic.model.split(se.u)[1]
    assert np.max(np.abs(u_sphere - sr.u)) <= 1e-4 * np.max(np.abs(sr.u))
    # a softer block is farther from the rigid solution: the comparison sees the block's compliance
    _, soft = two_body_3d.rigid_limit_sphere(0, stiffening=1e2)
    ss = solve(soft, "ssn")
    assert np.max(np.abs(ss.pressure - sr.pressure)) > 1e-3 * sr.pressure.max()


@pytest.mark.parametrize("algorithm,penalty", [("ssn", None), ("family-p", "exp-met1")])
def test_sphere_on_block_amg_path_agrees(algorithm, penalty):
    """Measured: 5e-10 (ssn), 1e-10 (6.3 exp-met1) relative to the direct path's pressures."""
    prob = two_body_3d.sphere_on_block(0)
    ref = solve(prob, "ssn")
    sol = solve(prob, algorithm, penalty, linear_solver="amg")
    assert sol.result.success, sol.result.message
    assert sol.extra["strategy"] == "krylov" and sol.extra["linear_solver"] == "amg"
    np.testing.assert_allclose(sol.pressure, ref.pressure, atol=1e-6 * ref.pressure.max())
    assert sol.extra["contact_force_balance"] <= 1e-10
