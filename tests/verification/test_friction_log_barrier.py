r"""The barrier anchor with Coulomb friction (``log-barrier``, friction: :func:`step_barrier`).

Per load step the normal multipliers are held and the barrier parameter eta = mu / eps_N is driven to
zero (eps_N times ``alpha`` after every subproblem whose penetration or complementarity is above its
tolerance); the tangential part is Algorithm 6.2's return mapping with the coupled radius mu t_N.

References (analytical, the same as ``tests/verification/test_friction.py`` and
``tests/verification/test_finite_friction_log_barrier.py`` for Algorithms 6.2 / 6.4):

1. Block on a rigid plane below the Coulomb limit (Q = 0.4 mu N): every point sticks, no slip
   (|slip| <= 1e-9 of the imposed displacement).
2. Above it (Q = 3 mu N): every point slips and sum_i w_i |t_T,i| = mu N to 1e-8 relative (the coupled
   radius puts a slipping traction on the Coulomb circle exactly; the 1e-8 is the normal force's
   tolerance); the resultant Q = mu N (2D to 1e-8, 3D to 1e-4: local slip directions differ).
3. Finite deformation: a neo-Hookean block pressed by 20 % and slid far beyond the stick limit:
   every closed point slips and | |T| - mu N | <= 1e-8 mu N.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from alcontact.contact import ContactProblem, Ramp, Support, obstacles, solve_finite_friction, solve_friction
from alcontact.contact.algorithms import find_algorithm, step_barrier
from alcontact.contact.laws import OPEN, SLIP, STICK
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic
from alcontact.problems import friction as fp


def test_registered_with_friction_on_the_direct_paths():
    for kin in ("small", "finite"):
        entry = find_algorithm("log-barrier", friction=True, kinematics=kin)
        assert entry.run is step_barrier and entry.penalty_for(None) == "log-met1"
        assert entry.linear_solvers == ("direct",)


def test_block_sticks_below_coulomb_limit(caplog):
    """Reference 1; the barrier is what ran: eps_N grows between the subproblems of a step."""
    prob, hist = fp.block_on_plane(dim=2, n=8, shear_ratio=0.4)
    with caplog.at_level(logging.DEBUG, logger="alcontact.contact.algorithms._barrier"):
        sol = solve_friction(prob, hist, algorithm="log-barrier")
    assert sol.success, sol.message
    assert sol.algorithm == "log-barrier" and sol.penalty == "log-met1"
    f = sol.final
    assert np.all(f.state == STICK)
    assert np.max(np.abs(f.slip_total)) <= 1e-9 * prob.meta["d"]
    eps = [float(r.getMessage().split("eps_N ")[1].split()[0]) for r in caplog.records
           if r.getMessage().startswith("friction barrier outer")]
    assert len(eps) >= 2 and max(eps) >= 100 * min(eps)  # eta -> 0: at least two decades within the steps


@pytest.mark.parametrize("dim", [2, 3])
def test_block_slides_and_reaction_saturates(dim):
    """Reference 2."""
    prob, hist = fp.block_on_plane(dim=dim, n=8 if dim == 2 else 4, shear_ratio=3.0)
    sol = solve_friction(prob, hist, algorithm="log-barrier")
    assert sol.success, sol.message
    f = sol.final
    assert np.all(f.state == SLIP)
    muN = prob.friction * f.normal_force
    assert np.sum(sol.weights * np.linalg.norm(f.traction_t, axis=1)) == pytest.approx(muN, rel=1e-8)
    Q = np.linalg.norm(f.tangential_force)
    assert Q == pytest.approx(muN, rel=1e-8 if dim == 2 else 1e-4)
    assert Q <= muN * (1 + 1e-8)


@pytest.mark.slow
def test_finite_block_slides_with_mu_times_normal_force():
    """Reference 3 (4 x 4 neo-Hookean block, 4 pressing and 5 sliding steps; about 10 s: slow)."""
    mu = 0.3
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    problem = ContactProblem(Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain")),
                             obstacles.HalfSpace(point=(0.0, 0.0), normal=(0.0, 1.0)), "bottom",
                             supports=(Support("top"),), kinematics="finite")
    press, slide = Ramp((0.0, 0.5), (0.0, 0.2), hold_after=True), Ramp((0.5, 1.0), (0.0, 0.5))
    times = list(np.linspace(0.0, 0.5, 5)[1:]) + list(np.linspace(0.5, 1.0, 6)[1:])

    def path(t):
        return np.array([slide(t), press(t)])

    fs = solve_finite_friction(problem, mu, "log-barrier", steps=times, obstacle_path=path)
    assert fs.success, fs.message
    assert fs.extra["algorithm"] == "log-barrier"
    last = fs.steps[-1]
    closed = last.states != OPEN
    assert np.sum(closed) >= 4 and np.all(last.states[closed] == SLIP)
    assert abs(np.linalg.norm(last.tangential_force) - mu * last.normal_force) <= 1e-8 * mu * last.normal_force
