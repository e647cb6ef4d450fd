"""How the AMG solver forms its first aggregates (``AMGSolver(aggregation=...)``), and that the choice took effect.

The graded 2D Hertz meshes (``hertz_2d(growth=1.15)``) have elements many times longer than wide.
Aggregating on the whole matrix pattern (``"pattern"``, PyAMG's default strength threshold 0)
joins DOFs across the thin direction of those elements, and preconditioned CG needs more
iterations as the mesh is refined; aggregating on the strong couplings only (``"strength"``,
with the energy-minimizing prolongator) keeps the count flat. Measured here (CG to 1e-10 on the
free stiffness, rigid-body near-null space): 72 and 154 iterations at 4.5k and 10.5k DOFs with
``"pattern"``, 12 and 13 with ``"strength"``. The bounds below (at most 20 for ``"strength"``, a
growth of at least 1.5 times and at least 3 times more iterations for ``"pattern"``) leave room for
round-off and PyAMG versions, not for the difference between the two rules.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse.linalg import cg

from alcontact.contact import solve
from alcontact.contact.systems import IterativeContact
from alcontact.errors import InputError
from alcontact.linalg import MatrixHints, make_solver
from alcontact.problems import hertz


def _cg_iterations(K, factor) -> int:
    b = K @ np.linspace(-1.0, 1.0, K.shape[0])
    it = [0]
    _, info = cg(K, b, rtol=1e-10, M=factor.preconditioner(), maxiter=5000,
                 callback=lambda _x: it.__setitem__(0, it[0] + 1))
    assert info == 0
    return it[0]


@pytest.fixture(scope="module")
def stretched():
    """Free stiffness and rigid-body modes of two graded 2D Hertz meshes (4.5k and 10.5k free DOFs)."""
    out = []
    for n in (16, 32):
        ic = IterativeContact(hertz.hertz_2d(n_per_a=n, growth=1.15))
        out.append((ic.K, ic.R))
    return out


def test_strength_aggregation_keeps_cg_flat_on_stretched_2d_elements(stretched):
    counts = {}
    for agg in ("pattern", "strength"):
        counts[agg] = []
        for K, R in stretched:
            f = make_solver("amg", aggregation=agg).factorize(K, MatrixHints(dim=2, near_null=lambda R=R: R))
            assert f.aggregation == agg
            counts[agg].append(_cg_iterations(K, f))
    assert max(counts["strength"]) <= 20, counts
    assert counts["pattern"][1] >= 1.5 * counts["pattern"][0], counts
    assert all(p >= 3 * s for p, s in zip(counts["pattern"], counts["strength"])), counts


def test_auto_picks_strength_in_2d_and_pattern_otherwise(stretched):
    K, R = stretched[0]
    solver = make_solver("amg")
    assert solver.aggregation == "auto"
    assert solver.factorize(K, MatrixHints(dim=2, near_null=lambda: R)).aggregation == "strength"
    assert solver.factorize(K, MatrixHints(dim=3, near_null=lambda: R)).aggregation == "pattern"
    assert solver.factorize(K).aggregation == "pattern"


@pytest.mark.parametrize("problem, expected", [
    (lambda: hertz.hertz_2d(n_per_a=8, growth=1.15), "strength"),
    (lambda: hertz.hertz_3d(n_per_a=1, growth=1.6, size=6.0), "pattern"),
])
def test_the_contact_solve_reports_the_aggregation_it_ran(problem, expected):
    sol = solve(problem(), "simo-laursen", linear_solver="amg")
    assert sol.result.status.label == "converged"
    assert sol.extra["linear_solver"] == "amg"
    assert sol.extra["amg_aggregation"] == expected


def test_an_unknown_aggregation_is_refused_by_name():
    with pytest.raises(InputError, match="aggregation"):
        make_solver("amg", aggregation="geometric")
