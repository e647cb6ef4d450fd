"""Fixtures shared by the verification tests.

The half-cylinder of ``benchmarks/finite.py`` on its coarse mesh (``n = 8``, P2, 578 DOFs,
pressed to delta/R = 0.4 in 20 load steps) and its reference solution by ``ssn``: the
Newton-cost tests of Algorithm 6.1 (``test_finite_newton_cost.py``) and of the penalty /
Algorithm 6.3 starts (``test_finite_met_penalty_cost.py``) measure against the same run,
solved once per test process.
"""

import pytest

#: load steps of the half-cylinder runs
HALF_CYLINDER_STEPS = 20


@pytest.fixture(scope="session")
def half_cylinder_8():
    from alcontact.problems.half_cylinder import half_cylinder

    # straight-sided P2, the mesh on which the Newton costs of these tests were measured (P2 is
    # curved by default since issue 25: tests/verification/test_curved_p2.py covers that one)
    return half_cylinder(8, order=2, curved=False)


@pytest.fixture(scope="session")
def half_cylinder_8_ssn(half_cylinder_8):
    from alcontact.contact import solve_finite

    fs = solve_finite(half_cylinder_8, "ssn", steps=HALF_CYLINDER_STEPS)
    assert fs.success, fs.message
    return fs
