"""Patch test and Signorini block: every algorithm against exact / reference solutions.

References
----------
- Patch test: uniaxial stress, exact pressure ``E/(1-nu^2) d/H`` (plane strain) or
  ``E d/H`` (3D), uniform along the contact face; tolerance 1e-6 relative (1e-5 for
  the pure penalty, which carries its penetration ``<= tol_penetration * h``). 3D P2
  reports the pressure recovered from the nodal forces by the boundary mass matrix.
- Signorini cantilever with lift-off: the semi-smooth Newton reference solves the
  discrete problem exactly; every algorithm must match it to 1e-6 relative in
  displacement (max norm) and total contact force.
"""

import numpy as np
import pytest

from alcontact.contact import contact_penalties, solve
from alcontact.problems.blocks import patch_block, signorini_block

ALGORITHMS = [("ssn", None), ("penalty", None), ("simo-laursen", None)] + [
    ("family-p", p) for p in ("exp-met1", "exp-met2", "log-met1", "log-met2", "quad-met2", "rockafellar")
]


@pytest.mark.parametrize("dim,order", [(2, 1), (2, 2), (3, 1), (3, 2)])
@pytest.mark.parametrize("algorithm,penalty", ALGORITHMS)
def test_patch_uniform_pressure(dim, order, algorithm, penalty):
    prob = patch_block(dim, order, n=3 if dim == 3 else 4)
    sol = solve(prob, algorithm, penalty)
    assert sol.result.success, sol.result.message
    p_exact = prob.meta["pressure_exact"]
    assert np.all(sol.active), "the whole face must be in contact"
    # the pure penalty is exact only up to its penetration (tol_penetration = 1e-8 h, reached
    # at penalties ~1e6 E/h whose round-off shows at 1e-6): 1e-5 for it, 1e-6 for the others
    rtol = 1e-5 if algorithm == "penalty" else 1e-6
    np.testing.assert_allclose(sol.pressure, p_exact, rtol=rtol)
    width = 1.0
    area = width if dim == 2 else width * width
    np.testing.assert_allclose(sol.normal_force, p_exact * area, rtol=rtol)


def test_contact_penalties_cover_family_p():
    names = contact_penalties()
    for name in ("exp-met1", "exp-met2", "log-met1", "log-met2", "quad-met2", "rockafellar"):
        assert name in names
    assert "log-barrier" not in names and "hestenes-powell" not in names


@pytest.fixture(scope="module")
def signorini():
    prob = signorini_block()
    ref = solve(prob, "ssn")
    assert ref.result.success
    return prob, ref


@pytest.mark.parametrize("algorithm,penalty", ALGORITHMS[1:])
def test_signorini_agrees_with_ssn(signorini, algorithm, penalty):
    prob, ref = signorini
    # partial lift-off: some but not all bottom points are in contact
    assert 0 < ref.active.sum() < ref.active.size
    sol = solve(prob, algorithm, penalty)
    assert sol.result.success, sol.result.message
    du = np.max(np.abs(sol.u - ref.u)) / np.max(np.abs(ref.u))
    df = abs(sol.normal_force - ref.normal_force) / ref.normal_force
    assert du <= 1e-6
    assert df <= 1e-6
    np.testing.assert_array_equal(sol.active, ref.active)


def test_stiffer_penalty_approaches_al(signorini):
    """Consistency: the pure penalty error decreases like 1/eps_N towards the AL solution."""
    prob, ref = signorini
    errs = []
    for scale in (1.0, 10.0, 100.0):
        sol = solve(prob, "penalty", penalty_scale=scale, alpha=2.0, maxiter=1, tol_penetration=1e-30)
        errs.append(abs(sol.normal_force - ref.normal_force) / ref.normal_force)
    assert errs[0] > errs[1] > errs[2]
    assert errs[1] / errs[2] > 5  # first order in 1/eps


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("algorithm,penalty", ALGORITHMS)
def test_block_held_only_by_the_obstacle(order, algorithm, penalty):
    """Pressure-loaded block with no vertical support: the obstacle alone holds it.

    Reference: equilibrium, the contact pressure equals the applied pressure (5.0)
    uniformly (1e-6; 1e-5 for the pure penalty).
    """
    from alcontact.contact import ContactProblem, Pressure, Support
    from alcontact.contact.obstacles import HalfSpace
    from alcontact.fem import LinearElasticity, Material, meshes

    model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 4, 4), Material(E=1000.0, nu=0.3), order=order)
    prob = ContactProblem(model, HalfSpace((0, 0), (0, 1)), "bottom", supports=(Support("left", components=(0,)),),
                          loads=(Pressure("top", 5.0),))
    sol = solve(prob, algorithm, penalty)
    assert sol.result.success, sol.result.message
    rtol = 1e-5 if algorithm == "penalty" else 1e-6
    assert np.all(sol.active)
    np.testing.assert_allclose(sol.pressure, 5.0, rtol=rtol)
