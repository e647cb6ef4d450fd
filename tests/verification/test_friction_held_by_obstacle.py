"""A body held only by the obstacle with friction (issue 9): force-controlled block on a rigid plane, no supports.

An elastic block (nu = 0) on a rigid plane is pressed by a pressure P on its top (t in [0, 0.5])
and then pushed sideways by a tangential traction Q (t in [0.5, 1]); no support holds it, so the
normal contact and the friction are what stop its rigid motions (the frictional solver adds
contact springs on all components of the touching points and shifts the law by them, an exact
rewriting, ``FrictionalContact._stabilize``).

Analytical reference (statics of the rigid-body motions, Coulomb's law): the obstacle carries
N = P A and the tangential force Q A (A the top area), so Q A / (mu N) = Q / (mu P) as applied;
below 1 every point sticks (nu = 0: uniform shear, no slip at the edges at Q = mu P / 2),
above 1 there is no static equilibrium: the body slides away, reported as ``UNBOUNDED``
with the way out (prescribe the sliding displacement, or add a support).
"""

from __future__ import annotations

import numpy as np
import pytest

from _helpers import HELD_MU, HELD_P, held_block, held_block_toml, runner
from alcontact.cli import app
from alcontact.contact import ContactProblem, ContactStatus
from alcontact.contact import solve_friction
from alcontact.contact.laws import STICK
from alcontact.contact.problem import LoadCase, LoadHistory, Ramp
from alcontact.contact.problem import Traction

ALGS = ("simo-laursen", "family-p", "ssn")
MU, P = HELD_MU, HELD_P


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("alg", ALGS)
def test_force_controlled_block_sticks_below_the_coulomb_limit(alg, dim):
    """Q = mu P / 2, no support: converged, every point sticks, N = P A and the tangential force
    = Q A (relative 1e-9, so Q A / (mu N) = 0.5 as applied), global equilibrium residual <= 1e-8."""
    prob, hist, area, q = held_block(dim, 0.5)
    sol = solve_friction(prob, hist, algorithm=alg)
    assert sol.status == ContactStatus.CONVERGED, sol.message
    f = sol.final
    assert f.t == 1.0
    closed = f.pressure > 0
    assert np.all(f.state[closed] == STICK) and closed.sum() >= 3
    assert abs(f.normal_force - P * area) <= 1e-9 * P * area
    # the obstacle's tangential force on the body balances the applied traction
    assert np.allclose(f.tangential_force, -q * area, rtol=0, atol=1e-9 * P * area)
    assert abs(np.linalg.norm(f.tangential_force) / (MU * f.normal_force) - 0.5) <= 1e-9
    for step in sol.steps:
        eq = sol.equilibrium(step)
        assert eq.residual <= 1e-8 and eq.free_residual <= 1e-8, (step.t, eq)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("alg", ALGS)
def test_force_controlled_block_beyond_the_coulomb_limit_slides_away(alg, dim):
    """Q = 1.5 mu P: the steps up to t = 0.75 (traction 0.75 mu P) converge in equilibrium (residual
    <= 1e-8); at t = 1 (Q A = 1.5 mu N) the status is UNBOUNDED, no exception, and the message gives
    the tangential load 1.5 mu P A and the friction limit mu P A, says the body slides away and what
    to do."""
    prob, hist, area, _ = held_block(dim, 1.5)
    sol = solve_friction(prob, hist, algorithm=alg)
    assert sol.status == ContactStatus.UNBOUNDED and sol.status < 0
    msg = sol.message
    assert "t=1" in msg and "slides away" in msg and "no static equilibrium" in msg
    assert "prescribe the sliding displacement" in msg and "add a support" in msg
    assert f"{MU * P * area:.4g}" in msg and f"{1.5 * MU * P * area:.4g}" in msg
    assert [s.t for s in sol.steps] == [0.25, 0.5, 0.75]
    assert all(sol.equilibrium(s).residual <= 1e-8 for s in sol.steps)


def test_loads_pulling_the_body_off_the_obstacle_are_reported():
    """A suction (negative pressure) on a block with no support: nothing can hold it, UNBOUNDED."""
    prob, hist, _, _ = held_block(2, 0.0, pressure=-P)
    sol = solve_friction(prob, hist, algorithm="ssn")
    assert sol.status == ContactStatus.UNBOUNDED
    assert "pull the body off the obstacle" in sol.message and "add a support" in sol.message


def test_problem_file_check_accepts_and_run_solves(tmp_path):
    """``check`` accepts the unsupported block with friction and ``run`` converges (Q = mu P / 2);
    with Q = 1.5 mu P ``run`` ends with the sliding-away message, no traceback."""
    p = tmp_path / "p.toml"
    p.write_text(held_block_toml(2, 0.5 * MU * P))
    result = runner.invoke(app, ["check", str(p)])
    assert result.exit_code == 0, result.output
    result = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "ok")])
    assert result.exit_code == 0, result.output
    p.write_text(held_block_toml(2, 1.5 * MU * P))
    result = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "away")])
    text = " ".join(result.output.split())
    assert result.exit_code != 0 and "Traceback" not in text and "slides away" in text, result.output
    assert "prescribe that motion as a displacement" in text  # the advice of the runner for UNBOUNDED


def test_problem_file_friction_holds_the_free_translation(tmp_path):
    """Only y fixed on the left side: the x translation is left to the obstacle's friction; ``check``
    accepts it and ``run`` converges. With the obstacle two heights away nothing holds the body:
    ``check`` rejects it naming the free motion and a support."""
    p = tmp_path / "p.toml"
    text = held_block_toml(2, 0.5 * MU * P) + '[[support]]\nboundary = "left"\ncomponents = [1]\n'
    p.write_text(text)
    assert runner.invoke(app, ["check", str(p)]).exit_code == 0
    result = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "ok")])
    assert result.exit_code == 0, result.output
    p.write_text(text.replace("point = [0.0, 0.0]", "point = [0.0, -1.0]"))
    result = runner.invoke(app, ["check", str(p)])
    msg = " ".join(result.output.split())
    assert result.exit_code == 2 and "translation x" in msg and "nothing holds the body" in msg, result.output
    assert "[[support]]" in msg and "components = [0]" in msg


def _cylinder_pressed_by_forces(ratio: float):
    """The Cattaneo-Mindlin block of ``test_friction`` (coarse, 4 elements per a), but loaded by forces on its
    bottom, P (t in [0, 0.5]) then Q = ratio mu P (t in [0.5, 1]), with no support: a curved contact zone
    (a few points touch at first) holds the body."""
    import math

    from alcontact.problems import friction as fp

    prob, hist = fp.cattaneo_mindlin_2d(n_per_a=4, frictionless_approach=False, normal_steps=2, tangential_steps=2)
    length = 20.0  # the block is [-L, L] x [-L, 0], L = size * a_target
    P_total = math.pi * prob.model.material.plane_strain_modulus / (4 * 10.0)
    press = LoadCase(Traction("bottom", (0.0, P_total / (2 * length))), Ramp((0.0, 0.5), (0.0, 1.0), hold_after=True))
    shear = LoadCase(Traction("bottom", (ratio * MU * P_total / (2 * length), 0.0)), Ramp((0.5, 1.0), (0.0, 1.0)),
                     tangential=True)
    held = ContactProblem(model=prob.model, obstacle=prob.obstacle, contact_boundary="top", supports=(),
                          friction=MU)
    return held, LoadHistory((press, shear), hist.times), P_total


@pytest.mark.parametrize("alg", [
    "ssn", "family-p", pytest.param("simo-laursen", marks=pytest.mark.slow)])  # simo-laursen: ~6 s, cut-backs
def test_curved_contact_held_by_the_obstacle(alg):
    """Curved contact, no support, Q = mu P / 2: converged; the obstacle carries N = P and the tangential force
    Q (relative 1e-9) with stick and slip zones (Cattaneo-Mindlin), equilibrium residual <= 1e-8."""
    prob, hist, P_total = _cylinder_pressed_by_forces(0.5)
    sol = solve_friction(prob, hist, algorithm=alg)
    assert sol.status == ContactStatus.CONVERGED, sol.message
    f = sol.final
    assert f.t == 1.0
    assert abs(f.normal_force - P_total) <= 1e-9 * P_total
    assert abs(f.tangential_force[0] + 0.5 * MU * P_total) <= 1e-9 * P_total and f.tangential_force[1] == 0.0
    assert np.any(f.state == STICK)
    assert sol.equilibrium().residual <= 1e-8
