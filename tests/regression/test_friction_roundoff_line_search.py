"""The frictional barrier anchor at finite deformation reaches its round-off floor without failing (issue 26).

Before: on ``examples/finite_ironing_friction.toml`` the ``log-barrier`` anchor (held normal multipliers,
``eps_N`` raised to 4.4e7) started a subproblem after a tangential multiplier update at a relative residual
of 2.6e-10 that no Newton step lowers (the residual is round-off of the stiff barrier); the line search
failed, the load step was cut back to the smallest increment and the run stopped at t = 0.033. The
frictional Newton settings now count a failed line search below their stall level (1e-9) as converged
(``NewtonSettings.stall_on_failed_search``), as their stall test does.

Checked: the run converges at every load step, and its final normal contact force is that of the
semi-smooth Newton reference on the same discrete problem within 1e-7 relative (the barrier's
penetration error is first order in 1/eps_N: 1.4e-9 h here; measured difference 1.0e-9).
"""

from pathlib import Path

import numpy as np

from alcontact.contact import solve
from alcontact.io.config import load_problem
from alcontact.problems.ironing import ironing, ironing_schedule
from alcontact.runner import run_setup

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "finite_ironing_friction.toml"


def test_frictional_barrier_converges_on_the_finite_ironing_example():
    setup = load_problem(EXAMPLE)
    barrier = run_setup(setup, algorithm="log-barrier").summary
    assert barrier["status"] == "converged", barrier["message"]
    ssn = run_setup(setup, algorithm="ssn").summary
    assert ssn["status"] == "converged", ssn["message"]
    fb, fs = barrier["total_contact_force"], ssn["total_contact_force"]
    assert abs(fb - fs) <= 1e-7 * abs(fs), (fb, fs)


def test_frictional_barrier_floor_scales_with_its_penalty():
    """The study's frictional ironing (572 DOFs) with the barrier anchor at ``penalty_scale`` 10.

    Before: the first load step failed at the smallest increment, the line search of the fifth outer
    iteration failing at a relative residual of 6.2e-9, above the fixed stall level 1e-9 but at the
    round-off of the barrier's raised penalty (``eps_N`` 1e5 times its start). The frictional subproblem's
    stall level is now ``max(1e-9, floor)`` with the round-off floor of the contact forces (absolute
    coordinates times the largest contact stiffness), as the frictionless subproblem's. Checked: every
    step converged and verified, and the final contact force equals the semi-smooth Newton reference's
    within 1e-7 relative (measured 6.9e-10).
    """
    problem = ironing(n=6, slide=0.5, slide_step=0.125, press_steps=2)
    times, path = ironing_schedule(problem)
    barrier = solve(problem, "log-barrier", friction=0.3, steps=times, obstacle_path=path, penalty_scale=10.0)
    assert barrier.status.success, barrier.record.message
    ssn = solve(problem, "ssn", friction=0.3, steps=times, obstacle_path=path)
    assert ssn.status.success, ssn.record.message
    fb, fs = np.asarray(barrier.record.steps[-1].force), np.asarray(ssn.record.steps[-1].force)
    assert np.linalg.norm(fb - fs) <= 1e-7 * np.linalg.norm(fs), (fb, fs)
