"""The factorization-free path (linear_solver="amg") solves the same discrete problem as the direct one."""

from __future__ import annotations

import pytest

from _helpers import assert_same_contact_solution
from alcontact.contact import ContactOptions, ContactStatus, solve
from alcontact.linalg import AUTO_AMG_DOFS, select_solver
from alcontact.errors import InputError
from alcontact.problems import blocks, hertz


PROBLEMS = {
    "patch-2d": lambda: blocks.patch_block(2, n=6),
    "signorini-2d": lambda: blocks.signorini_block(n=8),
    "patch-3d": lambda: blocks.patch_block(3, n=4),
    "hertz-3d": lambda: hertz.hertz_3d(0),
}
VARIANTS = [("simo-laursen", None), ("family-p", "exp-met1"), ("ssn", None)]


@pytest.fixture(scope="module")
def problems():
    return {k: f() for k, f in PROBLEMS.items()}


@pytest.mark.parametrize("algorithm,penalty", VARIANTS)
@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n == "hertz-3d" else n  # 10-30 s each
                                  for n in PROBLEMS])
def test_amg_agrees_with_direct(problems, name, algorithm, penalty):
    prob = problems[name]
    direct = solve(prob, algorithm, penalty, linear_solver="direct")
    amg = solve(prob, algorithm, penalty, linear_solver="amg")
    assert_same_contact_solution(amg, direct, 1e-6)
    # no factorization; the CG solves and their iterations are counted
    assert amg.result.factorizations == 0
    assert amg.result.linear_solves >= 1 and amg.extra["cg_iterations"] >= amg.result.linear_solves - 1
    assert amg.extra["linear_solver"] == "amg" and amg.timings["linear_solve_s"] > 0


def test_penalty_runs_on_amg_path(problems):
    prob = problems["signorini-2d"]
    direct = solve(prob, "penalty", linear_solver="direct")
    amg = solve(prob, "penalty", linear_solver="amg")
    assert amg.result.success
    assert abs(amg.normal_force / direct.normal_force - 1) <= 1e-6


def test_linear_solver_option_is_validated():
    with pytest.raises(InputError, match="linear_solver"):
        ContactOptions(linear_solver="cholesky").validate()
    with pytest.raises(InputError, match="linear_solver"):
        solve(blocks.patch_block(2, n=2), "simo-laursen", linear_solver="lu")
    for name in ("auto", "direct", "amg"):
        assert ContactOptions(linear_solver=name).validate().linear_solver == name


def test_auto_chooses_amg_only_for_large_3d():
    """``select_solver`` is the one rule: "auto" is approximate (AMG, a Krylov path) only for 3D above
    AUTO_AMG_DOFS; "direct" always factorizes; a name runs that solver."""
    def exact(name, dim, ndofs):
        return select_solver(name, dim=dim, ndofs=ndofs).exact

    assert select_solver("auto", dim=3, ndofs=AUTO_AMG_DOFS + 1).name == "amg"
    assert not exact("auto", 3, AUTO_AMG_DOFS + 1)
    assert exact("auto", 3, AUTO_AMG_DOFS)
    assert exact("auto", 2, 10 * AUTO_AMG_DOFS)
    assert exact("direct", 3, 10 * AUTO_AMG_DOFS)
    assert not exact("amg", 2, 10)
    assert select_solver("superlu", dim=3, ndofs=10 * AUTO_AMG_DOFS).name == "superlu"


def test_amg_failure_branches_are_reported():
    far = blocks.signorini_block(n=4, gap=1.0)
    sol = solve(far, "simo-laursen", linear_solver="amg")
    assert sol.status == ContactStatus.NO_CONTACT and "never reaches" in sol.result.message
    sol = solve(blocks.signorini_block(n=4), "simo-laursen", linear_solver="amg", maxiter=1)
    assert sol.status == ContactStatus.MAXITER
    sol = solve(blocks.signorini_block(n=4), "simo-laursen", linear_solver="amg", maxiter_newton=1)
    assert sol.status == ContactStatus.NEWTON_FAILED


def test_released_geometry_caches_are_rebuilt_on_demand():
    """``release_geometry`` (called by the AMG setup once the contact points exist, to free
    about 620 B/DOF on large 3D meshes) drops the facet bases and the mesh mapping; whatever
    needs them afterwards (post-processing, the next solve) rebuilds them: same answer."""
    prob = blocks.signorini_block(n=8)
    first = solve(prob, "simo-laursen", linear_solver="amg")
    model = prob.model
    assert [k for k in model._facet_cache if isinstance(k, tuple) and k[0] == "fb"]
    model.release_geometry()
    assert not [k for k in model._facet_cache if isinstance(k, tuple) and k[0] == "fb"]
    assert not hasattr(model.mesh, "_cached_mapping")
    again = solve(prob, "simo-laursen", linear_solver="amg")
    assert_same_contact_solution(again, first, 1e-10)
    assert again.contact_half_width() == pytest.approx(first.contact_half_width(), rel=1e-10)
