r"""Algorithm 6.4 with the log-barrier ``log-met1`` at finite deformation (friction).

Problem: a unit neo-Hookean block (plane strain, E = 1000, nu = 0.3, 4 x 4 P1), top clamped,
pressed by 20 % onto a rigid plane that then moves sideways by 0.5, far beyond the stick
limit (mu = 0.3): 4 pressing and 5 sliding load steps (the sliding block of
``tests/verification/test_finite_friction.py``).

References:

1. Coulomb's law once every point slips: the AL stopping test bounds the multiplier change
   by ``tol_multiplier`` p_max and a slipping point carries |t_T| = mu lambda_N, so
   | |T| - mu N | <= mu tol_multiplier p_max sum(w) (factor 1.01 for round-off).
2. The Alart-Curnier semi-smooth Newton reference (``ssn``) solves the same time-discrete
   law exactly; the AL stops at relative tolerances 1e-8, so reaction forces and
   displacements agree to 1e-6 relative at every step.

What this guards: the barrier start of the finite frictional step
(:meth:`~alcontact.contact.algorithms._coulomb._FiniteALCtx.inside_domain`, the contact forces of
the Simo-Laursen predictor scaled up until every gap lies inside the barrier's domain). Without
it the first log-met1 subproblem started outside the domain and every load step failed with
non-finite tractions.
"""

from __future__ import annotations

import numpy as np

from _helpers import assert_same_finite_solution
from alcontact.contact import ContactProblem, FrictionOptions, Ramp, Support, obstacles, solve_finite_friction
from alcontact.contact.laws import OPEN, SLIP
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic


def test_log_met1_block_slides_with_mu_times_normal_force_as_the_reference():
    """References 1 and 2 (module doc)."""
    mu = 0.3
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    problem = ContactProblem(Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain")),
                             obstacles.HalfSpace(point=(0.0, 0.0), normal=(0.0, 1.0)), "bottom",
                             supports=(Support("top"),), kinematics="finite")
    press, slide = Ramp((0.0, 0.5), (0.0, 0.2), hold_after=True), Ramp((0.5, 1.0), (0.0, 0.5))
    times = list(np.linspace(0.0, 0.5, 5)[1:]) + list(np.linspace(0.5, 1.0, 6)[1:])

    def path(t):
        return np.array([slide(t), press(t)])

    fs = solve_finite_friction(problem, mu, "family-p", "log-met1", steps=times, obstacle_path=path)
    ref = solve_finite_friction(problem, mu, "ssn", steps=times, obstacle_path=path)
    assert fs.success and ref.success, (fs.message, ref.message)
    assert fs.extra["cutbacks"] == 0
    last = fs.steps[-1]
    closed = last.states != OPEN
    assert np.sum(closed) >= 4 and np.all(last.states[closed] == SLIP)
    bound = mu * FrictionOptions().tol_multiplier * float(np.max(fs.pressure)) * float(np.sum(fs.extra["weights"]))
    assert abs(np.linalg.norm(last.tangential_force) - mu * last.normal_force) <= 1.01 * bound
    assert_same_finite_solution(fs, ref, 1e-6)
