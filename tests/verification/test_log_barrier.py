"""The barrier anchor ``log-barrier``: Polyak's modified log barrier with fixed multipliers, eta -> 0.

Reference: the semi-smooth Newton solution (``ssn``) of the same mesh, which solves the discrete
contact problem exactly (no penalty). The barrier stops on penetration <= 1e-8 h and complementarity
<= 1e-8 (the verified invariants); its traction error is first order in eta, so at that stop the
total contact force agrees with the reference to 1e-8 relative (measured 1.4e-10 on 2D Hertz,
1.4e-9 on the half-cylinder) and the peak pressure to 1e-7 (measured 1.3e-8).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import ContactStatus, solve
from alcontact.contact.algorithms import find_algorithm
from alcontact.problems.hertz import hertz_2d


@pytest.fixture(scope="module")
def ssn():
    return solve(hertz_2d(n_per_a=2), "ssn")


@pytest.mark.parametrize("linear_solver", ["direct", "amg"])
def test_converges_on_hertz_2d_to_the_ssn_force(ssn, linear_solver):
    sol = solve(hertz_2d(n_per_a=2), "log-barrier", None, {"linear_solver": linear_solver})
    res = sol.result
    assert sol.success and res.status == ContactStatus.CONVERGED
    assert res.penalty == "log-met1" and res.algorithm == "log-barrier"
    assert float(sol.normal_force) == pytest.approx(float(ssn.normal_force), rel=1e-8)
    assert float(sol.peak_pressure) == pytest.approx(float(ssn.peak_pressure), rel=1e-7)
    # the verified invariants, at the returned state
    assert res.penetration <= 1e-8 and res.complementarity <= 1e-8


def test_barrier_parameter_is_driven_to_zero_and_alpha_took_effect():
    runs = {a: solve(hertz_2d(n_per_a=2), "log-barrier", None, {"alpha": a}).result for a in (10.0, 100.0)}
    for alpha, res in runs.items():
        eps = [h.eps_n for h in res.history[1:]]  # after the penalty start (history entry 0)
        assert len(eps) >= 2
        # eta = mu / eps_N: eps_N grows by alpha after every subproblem, eta falls by alpha
        np.testing.assert_allclose(np.diff(np.log(eps)), np.log(alpha), rtol=1e-12)
        # penetration falls with eta (first order): by about alpha per subproblem
        pen = [h.penetration for h in res.history[2:]]
        assert all(b < a / (0.5 * alpha) for a, b in zip(pen, pen[1:]))
    assert runs[100.0].outer_iterations < runs[10.0].outer_iterations


def test_no_multiplier_update_unlike_algorithm_6_3():
    barrier = solve(hertz_2d(n_per_a=2), "log-barrier").result
    al = solve(hertz_2d(n_per_a=2), "family-p", "log-met1").result
    # the same start and the same first subproblem (same law, same multipliers, same eta) ...
    assert barrier.history[1].penetration == pytest.approx(al.history[1].penetration, rel=1e-10)
    # ... then Algorithm 6.3 updates the multipliers at fixed eps_N, the barrier raises eps_N instead
    assert len({h.eps_n for h in al.history}) == 1
    assert barrier.history[-1].eps_n > 100 * barrier.history[0].eps_n


def test_penalty_limit_and_maxiter_are_failures():
    lim = solve(hertz_2d(n_per_a=2), "log-barrier", None, {"eps_max": 10.0}).result
    assert lim.status == ContactStatus.PENALTY_LIMIT and int(lim.status) < 0
    assert "eps_max" in lim.message
    short = solve(hertz_2d(n_per_a=2), "log-barrier", None, {"maxiter": 1}).result
    assert short.status == ContactStatus.MAXITER


def test_registered_with_its_paths_and_fixed_penalty():
    small = find_algorithm("log-barrier")
    assert small.penalty == "log-met1" and set(small.linear_solvers) == {"direct", "amg"}
    assert find_algorithm("log-barrier", kinematics="finite").linear_solvers == ("direct",)
    with pytest.raises(Exception, match="log-met1"):
        solve(hertz_2d(n_per_a=2), "log-barrier", "exp-met1")


def test_finite_deformation_half_cylinder_matches_ssn():
    from alcontact.problems.half_cylinder import half_cylinder

    ref = solve(half_cylinder(n=4, delta=0.4), "ssn", None, {"penalty_scale": 1.0}, steps=8)
    sol = solve(half_cylinder(n=4, delta=0.4), "log-barrier", None, {"penalty_scale": 1.0}, steps=8)
    assert ref.success and sol.success
    assert float(sol.normal_force) == pytest.approx(float(ref.normal_force), rel=1e-8)
