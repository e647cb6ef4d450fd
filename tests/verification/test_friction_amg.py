"""Friction on the AMG path (issue 9): full-space Newton with AMG-preconditioned Krylov solves.

Reference: the direct (condensed) path of the same discrete problem. Both paths solve the
same equations (:mod:`alcontact.contact.systems._krylov`), so every converged step must
agree: displacements within 1e-6 of the largest displacement, pressures and tangential
tractions within 1e-6 of the largest pressure (the Newton tolerance is 1e-11 and the CG
solves stop at 1e-10, so the observed differences are about 1e-9), and the same
open/stick/slip state at every point.

Bodies held only by the obstacle: the analytical reference of
``test_friction_held_by_obstacle`` (statics of the rigid motions and Coulomb's law: the
obstacle carries N = P A and the tangential force Q A; below Q = mu P every point sticks,
beyond it there is no static equilibrium, status UNBOUNDED).

Reaches inside the package: once, to lower ``linalg._registry.AUTO_AMG_DOFS`` (the size at which
``linear_solver = "auto"`` picks AMG, no option) so that ``auto`` reaches the AMG path on a small
model.
"""

from __future__ import annotations

import json
import logging

import numpy as np
import pytest

from _helpers import HELD_MU, HELD_P, assert_same_friction_steps, held_block, held_block_toml, runner
from alcontact import linalg
from alcontact.cli import app
from alcontact.contact import ContactStatus
from alcontact.contact import solve_friction
from alcontact.contact.laws import SLIP, STICK
from alcontact.problems import friction as fp

MU, P = HELD_MU, HELD_P
RTOL = 1e-6


def _curved(dim: int):
    """Rigid cylinder (2D) / sphere (3D) pressed, then sheared below mu P: stick and slip zones."""
    if dim == 2:
        return fp.cattaneo_mindlin_2d(4, size=5.0, normal_steps=1, tangential_steps=2)
    return fp.sphere_shear_3d(2, size=3.0, normal_steps=1, tangential_steps=2)


def _assert_same(direct, amg):
    assert direct.status == ContactStatus.CONVERGED, direct.message
    assert amg.status == ContactStatus.CONVERGED, amg.message
    assert amg.extra["linear_solver"] == "amg" and linalg.solver_kind(direct.extra["linear_solver"]) == "direct"
    assert amg.extra["strategy"] == "krylov" and direct.extra["strategy"] == "condensed"
    assert [s.t for s in amg.steps] == [s.t for s in direct.steps]
    assert_same_friction_steps(amg, direct, RTOL, displacements=True)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("alg", ["simo-laursen", "ssn"])
def test_amg_path_matches_the_direct_path_with_stick_and_slip(dim, alg):
    """Algorithm 6.2 and the Alart-Curnier reference, 2D and 3D, partial slip: the AMG path agrees
    with the direct path to 1e-6 (relative, module doc) at every step, with stick and slip points."""
    prob, hist = _curved(dim)
    direct = solve_friction(prob, hist, algorithm=alg, linear_solver="direct")
    amg = solve_friction(prob, hist, algorithm=alg, linear_solver="amg")
    _assert_same(direct, amg)
    state = amg.final.state
    assert np.sum(state == STICK) >= 2 and np.sum(state == SLIP) >= 2


def test_amg_path_family_p_matches_the_direct_path():
    """Algorithm 6.4 (family-P, exp-met1) on the AMG path, 3D partial slip: the direct path's solution
    to 1e-6 (2D: the held block below)."""
    prob, hist = _curved(3)
    _assert_same(solve_friction(prob, hist, algorithm="family-p", linear_solver="direct"),
                 solve_friction(prob, hist, algorithm="family-p", linear_solver="amg"))


def test_coupled_disc_radius_takes_gmres_and_matches(caplog):
    """``radius="traction"``: the Newton matrix is unsymmetric in slip, the Krylov method is GMRES;
    the solution is the direct path's to 1e-6."""
    prob, hist = _curved(3)
    direct = solve_friction(prob, hist, linear_solver="direct", radius="traction")
    with caplog.at_level(logging.DEBUG, logger="alcontact.contact.systems._krylov"):
        amg = solve_friction(prob, hist, linear_solver="amg", radius="traction")
    assert any("GMRES" in r.getMessage() for r in caplog.records)
    _assert_same(direct, amg)


def test_auto_picks_the_amg_path_for_large_3d_models(monkeypatch):
    """``linear_solver="auto"`` follows :func:`alcontact.linalg.choose_solver` (threshold lowered here)."""
    import alcontact.linalg._registry as reg

    prob, hist, *_ = held_block(3, 0.5)
    assert solve_friction(prob, hist).extra["strategy"] == "condensed"
    monkeypatch.setattr(reg, "AUTO_AMG_DOFS", prob.model.ndofs - 1)
    sol = solve_friction(prob, hist)
    assert sol.status == ContactStatus.CONVERGED and sol.extra["linear_solver"] == "amg"
    assert sol.extra["strategy"] == "krylov"
    assert sol.extra["cg_iterations"] > 0 and sol.extra["amg_setups"] >= 1


# ---------------------------------------------------------------------- held by the obstacle
@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("alg", ["simo-laursen", "family-p", "ssn"])
def test_force_controlled_block_held_by_the_obstacle_on_the_amg_path(alg, dim):
    """No support, Q = mu P / 2: converged, every closed point sticks, N = P A and the tangential
    force -Q A (relative 1e-9), equilibrium residual <= 1e-8 at every step; the direct path's
    solution to 1e-6. Q = 1.5 mu P: UNBOUNDED at t = 1 with the sliding-away message, as the
    direct path."""
    prob, hist, area, _ = held_block(dim, 0.5)
    direct = solve_friction(prob, hist, algorithm=alg, linear_solver="direct")
    sol = solve_friction(prob, hist, algorithm=alg, linear_solver="amg")
    _assert_same(direct, sol)
    f = sol.final
    assert f.t == 1.0 and np.all(f.state[f.pressure > 0] == STICK) and np.sum(f.pressure > 0) >= 3
    assert abs(f.normal_force - P * area) <= 1e-9 * P * area
    q = 0.5 * MU * P * area
    assert abs(np.linalg.norm(f.tangential_force) - q) <= 1e-9 * P * area
    assert all(sol.equilibrium(s).residual <= 1e-8 for s in sol.steps)

    prob, hist, *_ = held_block(dim, 1.5)
    away = solve_friction(prob, hist, algorithm=alg, linear_solver="amg")
    assert away.status == ContactStatus.UNBOUNDED, away.message
    assert "slides away" in away.message and "t=1" in away.message
    assert [s.t for s in away.steps] == [0.25, 0.5, 0.75]
    assert all(away.equilibrium(s).residual <= 1e-8 for s in away.steps)


def test_problem_file_on_the_amg_path_check_and_run(tmp_path):
    """A 3D force-controlled block with friction and no support, ``linear_solver = "amg"``: ``check``
    accepts it (AMG size model) and ``run`` converges below the Coulomb limit (beyond it: the
    UNBOUNDED status of the test above, reported by ``run`` as in ``test_friction_held_by_obstacle``)."""
    p = tmp_path / "p.toml"
    p.write_text(held_block_toml(3, 0.5 * MU * P / np.sqrt(2.0)) + '[solver]\nlinear_solver = "amg"\n'
                 + "[output]\nvtu = false\nseries = false\nplots = false\n")
    result = runner.invoke(app, ["check", str(p)])
    assert result.exit_code == 0 and "amg linear solver" in " ".join(result.output.split()), result.output
    result = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "ok")])
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "ok" / "summary.json").read_text())
    assert summary["status"] == "converged" and abs(summary["total_contact_force"] - 4 * P) <= 1e-9 * 4 * P
