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

from alcontact.io.config import load_problem
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
