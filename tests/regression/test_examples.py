"""Every problem file of examples/ loads, solves on its (coarse) mesh and gives the expected key numbers.

Tolerances are stated per example; the meshes are the files' own (coarse, a few seconds each).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from alcontact.io.config import load_problem
from alcontact.runner import run_setup

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
NAMES = ["hertz_2d", "hertz_3d", "flat_punch", "signorini_liftoff", "sliding_block", "cattaneo_mindlin",
         "finite_half_cylinder", "finite_ironing", "finite_ironing_friction", "finite_mooney_rivlin",
         "rubber_ball_axisym", "seal_oring", "two_cylinders"]


def _run(name):
    setup = load_problem(EXAMPLES / f"{name}.toml")
    res = run_setup(setup)
    assert res.summary["status"] == "converged", res.summary["message"]
    # global equilibrium: contact force + applied loads + support reactions = 0 (tests/verification/test_equilibrium.py)
    assert res.summary["equilibrium_residual"] <= 1e-8, res.summary["equilibrium_residual"]
    return setup, res


def test_all_examples_are_tested():
    assert sorted(p.stem for p in EXAMPLES.glob("*.toml")) == sorted(NAMES)


@pytest.mark.parametrize("name", ["hertz_2d", "hertz_3d"])
def test_hertz_width_and_peak_pressure_within_5_percent(name):
    _, res = _run(name)
    s = res.summary
    assert s["contact_half_width"] == pytest.approx(s["contact_half_width_exact"], rel=0.05)
    assert s["peak_pressure"] == pytest.approx(s["peak_pressure_exact"], rel=0.05)


def test_flat_punch_equilibrium_and_linear_load_curve():
    setup, res = _run("flat_punch")
    model = setup.problem.model
    assert len(res.frames) == 4
    final = res.frames[-1]
    # reaction of the pushed bottom (y components) balances the contact force: K u = f_contact + reactions
    _, dofs = model.node_dofs("bottom")
    reaction_y = float(np.sum((model.stiffness() @ final.u)[dofs[:, 1]]))
    force_y = float(final.total_contact_force[1])
    assert force_y < 0  # the punch pushes the body down
    assert reaction_y == pytest.approx(-force_y, rel=1e-6)
    # the contact zone is the punch face: the force grows linearly with the prescribed displacement
    n = np.array([f.normal_force for f in res.frames])
    t = np.array([f.extra["t"] for f in res.frames])
    assert n / t == pytest.approx(np.full(4, n[-1] / t[-1]), rel=1e-3)
    # the punch edge x = 1 bounds the contact zone
    pts = final.points[final.active]
    assert pts[:, 0].max() <= 1.0 + 1e-9 and pts[:, 0].min() == pytest.approx(0.0)


def test_signorini_partial_contact_near_the_free_end():
    setup, res = _run("signorini_liftoff")
    sol = res.frames[-1]
    x = sol.points[:, 0]
    active = sol.active
    assert 0 < active.sum() < active.size  # partial contact: lift-off near the clamp
    assert active[np.argmax(x)]  # the free end touches
    assert not np.any(active & (x < 1.0))  # no contact next to the clamp
    x_first = x[active].min()
    assert np.all(active[x > x_first + 1e-9])  # one contact zone reaching the free end
    assert sol.normal_force > 0


def test_sliding_block_tangential_reaction_is_mu_times_normal():
    setup, res = _run("sliding_block")
    s = res.summary
    assert s["slip_points"] == res.frames[-1].points.shape[0] and s["stick_points"] == 0
    assert s["tangential_force"] == pytest.approx(0.3 * s["model_contact_force"], rel=1e-6)
    # before shearing (t = 0.5) there is no tangential force
    half = next(f for f in res.frames if abs(f.extra["t"] - 0.5) < 1e-12)
    assert np.linalg.norm(half.extra["tangential_force"]) <= 1e-8 * half.normal_force


def test_cattaneo_mindlin_partial_slip():
    """Coarse mesh (16 elements per a), circular obstacle: a within 5 %, p0 within 7 %, c within 25 %."""
    setup, res = _run("cattaneo_mindlin")
    s = res.summary
    assert s["contact_half_width"] == pytest.approx(s["contact_half_width_exact"], rel=0.05)
    assert s["peak_pressure"] == pytest.approx(s["peak_pressure_exact"], rel=0.07)
    ratio = s["tangential_force"] / s["coulomb_limit"]
    assert 0.3 < ratio < 0.8  # partial slip: Q < mu P
    assert s["stick_points"] > 0 and s["slip_points"] > 0
    assert s["stick_half_width"] == pytest.approx(s["stick_half_width_exact"], rel=0.25)


def test_finite_half_cylinder_equals_the_python_api():
    """The problem file runs exactly the Python API's problem: ``half_cylinder(n=6, delta=0.2)`` solved by
    ``solve_finite`` in 4 steps. Same step times, Newton iterations and contact force per step (to 1e-9
    relative: the same arithmetic on a mesh read back from 17-digit text), and the neo-Hookean force at
    delta/R = 0.2 exceeds the small-strain one-step-linear extrapolation of the first step (stiffening by
    the growing contact width)."""
    from alcontact.contact import solve_finite
    from alcontact.problems.half_cylinder import half_cylinder

    setup, res = _run("finite_half_cylinder")
    s = res.summary
    api = solve_finite(half_cylinder(n=6, delta=0.2), steps=4)
    assert api.success
    assert s["step_times"] == pytest.approx(list(api.times), abs=1e-15)
    assert s["step_newton_iterations"] == [st.newton_iterations for st in api.steps]
    np.testing.assert_allclose(s["step_contact_force"], api.forces, rtol=1e-9, atol=1e-9 * abs(api.forces).max())
    np.testing.assert_allclose(res.frames[-1].u, api.u, rtol=0, atol=1e-9)
    f = api.forces[:, 1]
    assert f[-1] > 4 * f[0]  # the force grows faster than the approach: Hertz-like stiffening
    assert s["cutbacks"] == 0 and len(res.frames) == 4


def test_finite_mooney_rivlin_runs_the_law_of_the_file_and_equals_the_python_api():
    """The Mooney-Rivlin example runs the law and constants of its file (c10 = 0.5, c01 = 0.1, E derived
    as 2 mu0 (1 + nu) = 3.48) and gives the Python API's steps and forces (to 1e-9 relative) for
    ``half_cylinder(n=6, delta=0.3)`` with ``MooneyRivlin(0.5, 0.1)``; the same law written as a user
    ``energy`` in the file gives the same forces (1e-9); the force grows faster than the approach."""
    from alcontact.contact import solve_finite
    from alcontact.fem import EnergyExpression, MooneyRivlin
    from alcontact.io.config import load_problem_text
    from alcontact.problems.half_cylinder import half_cylinder

    setup, res = _run("finite_mooney_rivlin")
    body = setup.problem.model
    assert isinstance(body.law, MooneyRivlin) and (body.law.c10, body.law.c01) == (0.5, 0.1)
    assert body.material.E == pytest.approx(3.48, rel=1e-14) and body.material.nu == 0.45
    s = res.summary
    assert s["cutbacks"] == 0 and len(res.frames) == 6
    api = solve_finite(half_cylinder(n=6, delta=0.3, E=3.48, nu=0.45, model=MooneyRivlin(0.5, 0.1)), steps=6)
    assert api.success
    assert s["step_newton_iterations"] == [st.newton_iterations for st in api.steps]
    np.testing.assert_allclose(s["step_contact_force"], api.forces, rtol=1e-9, atol=1e-9 * abs(api.forces).max())
    f = api.forces[:, 1]
    assert f[-1] > 6 * f[0]

    text = (EXAMPLES / "finite_mooney_rivlin.toml").read_text(encoding="utf-8")
    K = 3.48 / (3 * (1 - 2 * 0.45))
    user = text.replace('model = "mooney-rivlin"\nnu = 0.45\nparameters = { c10 = 0.5, c01 = 0.1 }',
                        'energy = "c10*(I1b-3) + c01*(I2b-3) + K/2*(J-1)**2"\n'
                        f'parameters = {{ c10 = 0.5, c01 = 0.1, K = {K!r} }}')
    assert user != text
    usetup = load_problem_text(user, base_dir=EXAMPLES)
    assert isinstance(usetup.problem.model.law, EnergyExpression)
    assert usetup.problem.model.material.nu == pytest.approx(0.45, rel=1e-12)
    ures = run_setup(usetup)
    assert ures.summary["status"] == "converged"
    np.testing.assert_allclose(ures.summary["step_contact_force"], s["step_contact_force"], rtol=1e-9,
                               atol=1e-9 * abs(api.forces).max())


def test_finite_ironing_contact_follows_the_moving_cylinder():
    """Ironing (frictionless, finite deformation): once the strip is pushed up (t >= 0.25) the cylinder
    slides along a translation-invariant strip, so the normal force is the steady ironing force: within
    2 % of its value at t = 0.25 at every later step; the force along the motion is positive (the cylinder
    pushes the bulge ahead of it); the loaded zone's force centroid (deformed positions) is at the
    cylinder's x = 0.8 + 2 t to within one element (h = 0.25)."""
    setup, res = _run("finite_ironing")
    s = res.summary
    assert s["step_times"] == pytest.approx([0.125 * k for k in range(1, 9)], abs=1e-12)
    f = np.array(s["step_contact_force"])
    steady = np.array(s["step_times"]) >= 0.25 - 1e-12
    assert f[steady, 1] == pytest.approx(np.full(steady.sum(), f[1, 1]), rel=0.02)
    assert np.all(f[steady, 0] > 0)
    _, dofs = setup.problem.model.node_dofs("top")
    for fr in res.frames:
        x = fr.points[:, 0] + fr.u[dofs[:, 0]]
        w = fr.weights * fr.pressure
        assert w.sum() > 0
        assert float(np.sum(w * x) / w.sum()) == pytest.approx(0.8 + 2.0 * fr.extra["t"], abs=0.25)


def test_finite_ironing_with_friction_slides_at_the_coulomb_limit_and_balances_energy():
    """Ironing with Coulomb friction (mu = 0.3, finite deformation, 16 steps, 12 of them sliding by half an
    element). References, in the steady sliding phase (t > 0.25):

    - Coulomb's law at slip: every pressed point slips, so sum_i w_i |t_T,i| = mu sum_i w_i t_N,i within
      mu tol_multiplier p_max sum(w) (the AL stopping test: |t_T| = mu lambda_N and |t_N - lambda_N| <=
      tol_multiplier p_max; factor 1.01 for round-off), as tests/verification/test_finite_friction.py;
    - the friction force on the strip points along the motion (+x) with the Coulomb magnitude: its x
      component is between 0.9 mu N (the contact normals at the pressed points lean at most ~25 degrees
      from the vertical) and mu N;
    - energy balance: work of the indenter's horizontal force on the strip (trapezoidal rule over the
      steps) = frictional dissipation + change of the stored energy within 5 % of the work (the
      trapezoidal error of 12 sliding steps of h/2 on this coarse mesh: 3.3 %; it converges with the step,
      see test_finite_friction.py::test_ironing_energy_balance), with dissipation > 0.9 x work;
    - the results folder of a finite frictionless run plus the friction: per-step Newton iterations,
      dissipation, stick/slip counts, the tangential reaction in reaction_force.csv.
    """
    from alcontact.contact import FrictionOptions
    from alcontact.contact.laws import SLIP

    setup, res = _run("finite_ironing_friction")
    s = res.summary
    fs = res.raw
    mu = 0.3
    assert s["step_times"] == pytest.approx([0.0625 * k for k in range(1, 17)], abs=1e-12)
    assert len(s["step_newton_iterations"]) == 16 and min(s["step_newton_iterations"]) > 0
    w = fs.extra["weights"]
    tol = FrictionOptions().tol_multiplier
    steady = [st for st in fs.steps if st.t > 0.25 + 1e-12]
    assert len(steady) == 12
    for st in steady:
        pressed = st.pressure > 0
        assert pressed.sum() >= 2 and np.all(st.states[pressed] == SLIP)
        friction = float(np.sum(w * np.linalg.norm(st.traction_t, axis=1)))
        bound = mu * tol * float(np.max(st.pressure)) * float(np.sum(w))
        assert abs(friction - mu * st.normal_force) <= 1.01 * bound
        assert 0.9 * mu * st.normal_force <= st.tangential_force[0] <= mu * st.normal_force * (1 + 1e-9)
    # energy balance of the sliding phase
    t = np.array(s["step_times"])
    F = np.array(s["step_contact_force"])
    c = np.array(s["step_obstacle_offset"])
    k0 = int(np.flatnonzero(np.isclose(t, 0.25))[0])
    work = sum(0.5 * (F[k, 0] + F[k + 1, 0]) * (c[k + 1, 0] - c[k, 0]) for k in range(k0, len(t) - 1))
    stored = s["step_stored_energy"][-1] - s["step_stored_energy"][k0]
    dissipation = sum(s["step_dissipation"][k0 + 1:])
    assert dissipation > 0.9 * work > 0
    assert abs(work - dissipation - stored) <= 0.05 * work
    assert s["dissipation"] == pytest.approx(sum(s["step_dissipation"]), rel=1e-12)
    assert s["slip_points"] >= 2 and s["stick_points"] == 0
    # the support reaction balances the contact force, tangential component included
    final = res.frames[-1]
    assert final.equilibrium().reaction[0] == pytest.approx(-F[-1, 0], rel=1e-8)



def test_rubber_ball_axisym_equals_the_python_api():
    """The axisymmetric rubber ball runs the Python API's problem, ``hemisphere_axisym(n=12, order=2,
    delta=0.25)`` solved by ``solve_finite`` in 10 steps, on the mesh written from it (triangle6, 17-digit
    text): the same Newton iterations and contact force per step (1e-9 relative); the body is axisymmetric."""
    from alcontact.contact import solve_finite
    from alcontact.problems.hemisphere import hemisphere_axisym

    setup, res = _run("rubber_ball_axisym")
    s = res.summary
    assert setup.problem.model.axisymmetric
    api = solve_finite(hemisphere_axisym(12, order=2, delta=0.25), steps=10)
    assert api.success
    assert s["step_newton_iterations"] == [st.newton_iterations for st in api.steps]
    np.testing.assert_allclose(s["step_contact_force"], api.forces, rtol=1e-9, atol=1e-9 * abs(api.forces).max())
    assert s["cutbacks"] == 0 and len(res.frames) == 10


def test_seal_oring_mixed_axisymmetric_squeeze_without_cutback():
    """The O-ring in its groove (issue 25): nu = 0.4999 Mooney-Rivlin, mixed u-p body of revolution on the
    curved mesh, squeezed 25 % by the cover in ten steps: at most 8 Newton iterations per step and no
    cut-back (measured 6 6 4 3 4 3 3 4 3 3); the cover (axial force) and the outer wall (radial force,
    inwards) both carry load, the axial force grows at every step."""
    setup, res = _run("seal_oring")
    s = res.summary
    body = setup.problem.model
    assert s["formulation"] == "mixed" and body.axisymmetric and body.nu == 0.4999
    assert type(body.mesh).__name__ == "MeshTri2"
    from alcontact.problems.oring import oring_mesh  # the file is written from it (the example's header)

    np.testing.assert_allclose(body.mesh.doflocs, oring_mesh(8).doflocs, rtol=0, atol=1e-14)
    assert s["cutbacks"] == 0 and len(s["step_newton_iterations"]) == 10
    assert max(s["step_newton_iterations"]) <= 8, s["step_newton_iterations"]
    fz = np.array([f[1] for f in s["step_contact_force"]])
    assert np.all(np.diff(fz) < 0) and fz[0] < 0  # the cover pushes down (-z), more at every step
    fr, fz_end = s["final_contact_force"]
    assert fr < -0.01 * abs(fz_end)  # the outer wall pushes the ring inwards


def test_two_cylinders_from_one_gmsh_file_match_hertz():
    """Two bodies read from one Gmsh file (a physical group each): Hertz with E* within 2 %, action = reaction."""
    setup, res = _run("two_cylinders")
    assert len(setup.problem.model.bodies) == 2
    s = res.summary
    assert s["contact_half_width"] == pytest.approx(s["contact_half_width_exact"], rel=0.02)
    assert s["peak_pressure"] == pytest.approx(s["peak_pressure_exact"], rel=0.02)
    assert s["contact_force_balance"] <= 1e-10
