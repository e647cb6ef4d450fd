"""Every frictionless algorithm converges on the factorization-free (AMG) path of a 3D P2 problem.

Reference: the direct path (one factorization, exact Newton on the condensed problem) on the
same mesh. Tolerances: the AMG path needs at most twice the direct path's outer iterations,
and its total contact force agrees with the direct one to a relative 1e-6 (the Newton
residuals of both paths are below 1e-8 of the contact forces).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.problems import hertz

pytest.importorskip("pyamg")

#: (algorithm, penalty) of every frictionless algorithm and the family-P penalties of issue 11
VARIANTS = [
    ("penalty", None),
    ("simo-laursen", None),
    ("family-p", "exp-met1"),
    ("family-p", "log-met1"),
    ("family-p", "log-met2"),
    ("family-p", "quad-met2"),
    ("family-p", "rockafellar"),
    ("ssn", None),
]


@pytest.fixture(scope="module")
def sphere_p2():
    """Rigid sphere on a quarter block of P2 tetrahedra (about 9k DOFs, candidates on P2 faces)."""
    return hertz.hertz_3d(order=2, n_per_a=1, growth=1.6, size=6.0)


@pytest.mark.slow  # 16 solves of a 9k-DOF 3D problem
@pytest.mark.parametrize("algorithm,penalty", VARIANTS)
def test_amg_path_converges_like_direct(sphere_p2, algorithm, penalty):
    direct = solve(sphere_p2, algorithm, penalty, linear_solver="direct")
    amg = solve(sphere_p2, algorithm, penalty, linear_solver="amg")
    assert direct.result.success, direct.result.message
    assert amg.result.success, amg.result.message
    assert amg.result.outer_iterations <= 2 * direct.result.outer_iterations
    f_ref = float(np.max(np.abs(direct.total_contact_force)))
    df = float(np.max(np.abs(amg.total_contact_force - direct.total_contact_force))) / f_ref
    assert df < 1e-6
    assert amg.result.factorizations == 0 and amg.extra["cg_iterations"] > 0
