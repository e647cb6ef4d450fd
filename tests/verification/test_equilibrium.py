"""Global equilibrium as an invariant of every solve.

Reference: summing the discrete equilibrium equations over all DOFs of each component
(a rigid translation does no internal work) gives :math:`F_c + F_{ext} + R = 0` exactly:
the contact force computed from the nodal contact forces plus the applied loads plus the
support reactions vanish. Tolerance: 1e-8 relative to the largest of the three (a
converged direct solve reaches about 1e-12), for 2D/3D, P1/P2, every frictionless
algorithm, the iterative linear solver, frictional solves, every built-in problem.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import available_algorithms, solve, solve_friction
from alcontact.problems import friction as fp
from alcontact.problems import hertz
from alcontact.runner import BUILTIN_PROBLEMS, build_problem, summarize

TOL = 1e-8

SMALL = {
    (2, 1): lambda: hertz.hertz_2d(order=1, n_per_a=4),
    (2, 2): lambda: hertz.hertz_2d(order=2, n_per_a=2),
    (3, 1): lambda: hertz.hertz_3d(order=1, n_per_a=2, size=6.0, growth=1.5),
    (3, 2): lambda: hertz.hertz_3d(order=2, n_per_a=1, size=4.0, growth=1.6),
}


def _check(sol, problem=None):
    eq = sol.equilibrium(problem)
    assert eq.residual <= TOL, eq
    # the reported resultant is the sum of the nodal forces the solver applied
    np.testing.assert_allclose(eq.contact_force, sol.total_contact_force, rtol=1e-12,
                               atol=1e-12 * np.linalg.norm(eq.contact_force))
    # and it is balanced by the supports (these problems carry no other load)
    np.testing.assert_allclose(-eq.reaction, eq.contact_force + eq.applied_load, rtol=0,
                               atol=TOL * np.linalg.norm(eq.contact_force))
    return eq


@pytest.mark.parametrize("key", sorted(SMALL), ids=lambda k: f"{k[0]}d-p{k[1]}")
@pytest.mark.parametrize("algorithm", available_algorithms())
def test_equilibrium_every_element_and_algorithm(key, algorithm):
    prob = SMALL[key]()
    sol = solve(prob, algorithm)
    assert sol.result.success, sol.result.message
    eq = _check(sol)
    assert np.linalg.norm(eq.contact_force) > 0
    # normal force: sum of the normal nodal forces (3D P2 included: not the recovered pressure times weights)
    assert sol.normal_force == pytest.approx(float(np.sum(sol.nodal_forces)), rel=1e-14)
    # and it is what the supports carry: the obstacle normals tilt by at most a/R ~ 0.1 here, so the
    # resultant differs from the sum of normal forces by well under 1 % (3D P2 used to report ~+20 %)
    assert sol.normal_force == pytest.approx(float(np.linalg.norm(eq.reaction)), rel=0.01)


def test_equilibrium_iterative_linear_solver():
    prob = SMALL[(2, 1)]()
    sol = solve(prob, linear_solver="amg")
    assert sol.result.success, sol.result.message
    _check(sol)


@pytest.mark.parametrize("name", sorted(BUILTIN_PROBLEMS))
def test_equilibrium_builtin_problems(name):
    prob = build_problem(name)
    sol = solve(prob)
    s = summarize(prob, sol, problem_name=name)
    assert s["equilibrium_residual"] <= TOL
    np.testing.assert_allclose(s["contact_force_from_nodal_forces"], s["contact_force_vector"], rtol=1e-12)
    assert s["model_contact_force"] == pytest.approx(float(np.sum(sol.nodal_forces)), rel=1e-14)


@pytest.mark.parametrize("dim", [2, 3])
def test_equilibrium_frictional_steps(dim):
    prob, hist = fp.block_on_plane(dim=dim, n=8 if dim == 2 else 3, shear_ratio=0.4 if dim == 2 else 3.0,
                                   steps=4)
    fsol = solve_friction(prob, hist)
    assert fsol.success, fsol.message
    for st in fsol.steps:
        eq = fsol.equilibrium(st)
        assert eq.residual <= TOL, (st.t, eq)
        np.testing.assert_allclose(eq.contact_force, st.contact_force, rtol=1e-10,
                                   atol=1e-10 * np.linalg.norm(eq.contact_force))
    # sheared: the tangential contact force is not zero and is balanced too
    assert np.linalg.norm(fsol.final.tangential_force) > 1e-3 * fsol.final.normal_force
