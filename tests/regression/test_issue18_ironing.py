"""Large sliding at finite deformation converges like Newton (issue 18).

Ironing (:func:`alcontact.problems.ironing.ironing`): a rigid cylinder of radius R = 1 pressed
0.2 R into a neo-Hookean block (E = 1000, nu = 0.3, plane strain, P1, h = 0.1) in 4 steps,
then slid by 1.5 R in steps of 0.05 R (30 sliding steps), frictionless. Before the fix
(issue 18) the semi-smooth Newton reference took 9-11 Newton iterations per sliding step and
Algorithms 6.1 / 6.3 cut back every other step (64-421 Newton iterations in a step).

Promises guarded here (the issue's targets where met; measured on this mesh, in brackets):
- ``ssn`` and Algorithm 6.1: <= 6 Newton iterations per sliding step on average, <= 12 in any
  step, no cut-back [ssn 3.6 / max 5; 6.1 3.9 / max 5]; the same for Algorithm 6.3 with exp-met1
  [4.9 / max 5; 6.6 / max 10 without ``slide_start_reach``];
- every accepted step is in equilibrium: the residual recomputed here from the returned
  displacement and pressures (not the solver's own measure) is below 1e-9 of the largest nodal
  contact force [<= 3e-12];
- steady sliding (after 1 R of travel): the horizontal force stays below 1% of the vertical one
  and changes by less than 0.5% of it between steps as nodes enter and leave contact
  [0.65% and 0.47%].
"""

import numpy as np
import pytest

from alcontact.contact import solve_finite
from alcontact.contact.systems import FiniteContact
from alcontact.contact.obstacles import translate
from alcontact.problems.ironing import ironing, ironing_schedule


@pytest.fixture(scope="module")
def case():
    problem = ironing(2, 10, slide=1.5)
    times, path = ironing_schedule(problem)
    return problem, times, path


def _equilibrium(problem, path, step) -> float:
    """max |f_int - f_ext + B^T (w t_N)| on the free DOFs over the largest nodal contact force."""
    model = problem.model
    pts, dofs = model.node_dofs(problem.contact_boundary)
    w = np.asarray(model.boundary_weights(problem.contact_boundary), dtype=float)
    _, nu = translate(problem.obstacle, path(step.t)).evaluate(pts + step.u[dofs])
    f = np.asarray(model.internal_force(step.u), dtype=float) - np.asarray(problem.load_vector(), dtype=float)
    nodal = w * step.pressure
    np.add.at(f, dofs.ravel(), (-(nodal[:, None] * nu)).ravel())
    free = np.ones(model.ndofs, dtype=bool)
    free[np.asarray(problem.dirichlet()[0], dtype=np.int64)] = False
    return float(np.max(np.abs(f[free]))) / float(np.max(nodal))


def _sliding(problem, sol):
    return [s for s in sol.steps if s.t > problem.meta["press_steps"]]


@pytest.fixture(scope="module")
def ssn_run(case):
    problem, times, path = case
    return solve_finite(problem, "ssn", steps=times, obstacle_path=path)


@pytest.mark.parametrize("algorithm", ["ssn", pytest.param("simo-laursen", marks=pytest.mark.slow)])
def test_newton_per_sliding_step(case, ssn_run, algorithm):
    problem, times, path = case
    sol = ssn_run if algorithm == "ssn" else solve_finite(problem, algorithm, steps=times, obstacle_path=path)
    assert sol.status > 0, sol.message
    steps = _sliding(problem, sol)
    assert len(steps) == problem.meta["slide_steps"] == 30
    newton = np.array([s.newton_iterations for s in steps])
    assert newton.mean() <= 6.0 and newton.max() <= 12, newton
    assert all(s.cutbacks == 0 for s in sol.steps)
    for s in sol.steps:
        assert _equilibrium(problem, path, s) < 1e-9


def test_horizontal_force_smooth_in_steady_sliding(case, ssn_run):
    problem, _, _ = case
    steady = [s for s in _sliding(problem, ssn_run)
              if (s.t - problem.meta["press_steps"]) * problem.meta["slide_step"] >= 1.0]
    assert len(steady) >= 10
    fx = np.array([s.force[0] for s in steady])
    fy = np.abs(np.array([s.force[1] for s in steady]))
    assert np.all(np.abs(fx) < 0.01 * fy)
    assert np.all(np.abs(np.diff(fx)) < 0.005 * fy[1:])


def test_slide_predictor_took_effect_and_is_what_makes_ssn_fast(case):
    """The option ran: with ``predictor = "auto"`` sliding steps start from the carried state
    (``predictor_used == "slide"``); with ``predictor = "tangent"`` none does, and the same problem
    needs more Newton iterations (the behaviour before issue 18) and reaches the same forces."""
    problem, times, path = case
    short = times[:10]  # 4 pressing + 6 sliding steps
    used = []

    class Recording(FiniteContact):
        def configure(self, *args, **kwargs):
            super().configure(*args, **kwargs)
            used.append(self.predictor_used)

    import alcontact.contact.stepping._frictionless as stepping

    original = stepping.FiniteContact
    stepping.FiniteContact = Recording
    try:
        on = solve_finite(problem, "ssn", steps=short, obstacle_path=path)
        used_on = list(used)
        off = solve_finite(problem, "ssn", steps=short, obstacle_path=path, predictor="tangent")
        used_off = used[len(used_on):]
    finally:
        stepping.FiniteContact = original
    assert on.status > 0 and off.status > 0
    assert used_on.count("slide") >= 6
    assert "slide" not in used_off and "secant" not in used_off
    n_on = sum(s.newton_iterations for s in _sliding(problem, on))
    n_off = sum(s.newton_iterations for s in _sliding(problem, off))
    assert n_on < n_off
    np.testing.assert_allclose(on.forces, off.forces, rtol=1e-8, atol=1e-8 * np.abs(on.forces).max())


def test_consistent_slide_multipliers_took_effect(case):
    """After a slide prediction the first subproblem's multipliers make the Macaulay traction at the predicted
    state equal the carried pressures (to round-off)."""
    from alcontact import penalties
    from alcontact.contact.laws import make_law

    problem, times, path = case
    sol = solve_finite(problem, "ssn", steps=times[:5], obstacle_path=path)
    dc = FiniteContact(problem)
    last = sol.steps[-1]
    x = last.u[dc.free]
    dc.configure(dc.fixed_values, dc.load, translate(problem.obstacle, path(times[4])), x)
    dc.accept(last.pressure)
    dc.configure(dc.fixed_values, dc.load, translate(problem.obstacle, path(times[5])), x, predictor_stiffness=1e4)
    assert dc.predictor_used == "slide"
    lam = dc.initial_multipliers()
    law = make_law(penalties.make("rockafellar"), np.full(dc.cand.size, 1e-4))
    g = dc.gaps(dc.start())
    pressed = lam > 0
    assert pressed.sum() >= 3 and np.any(np.abs(g[pressed]) > 1e-6)
    shifted = dc.entry_multipliers(lam, law)
    np.testing.assert_allclose(law.traction(g, shifted)[pressed], lam[pressed], rtol=1e-12,
                               atol=1e-12 * lam.max())


def test_exp_met1_newton_per_sliding_step(case):
    """Algorithm 6.3 with exp-met1 on the same mesh: <= 6 Newton per sliding step on average, <= 12 in any step,
    no cut-back, every step in equilibrium (target of issue 18; 6.5 / max 8-10 before ``slide_start_reach``)."""
    problem, times, path = case
    sol = solve_finite(problem, "family-p", "exp-met1", steps=times, obstacle_path=path)
    assert sol.status > 0, sol.message
    steps = _sliding(problem, sol)
    assert len(steps) == 30
    newton = np.array([s.newton_iterations for s in steps])
    assert newton.mean() <= 6.0 and newton.max() <= 12, newton
    assert all(s.cutbacks == 0 for s in sol.steps)
    for s in sol.steps:
        assert _equilibrium(problem, path, s) < 1e-9


def test_slide_start_reach_took_effect(case):
    """At Algorithm 6.3's penalty start a pressed point open by more than ``slide_start_reach`` h at the
    predicted state keeps its carried pressure as multiplier (Macaulay traction zero there); the nearer pressed
    points get the consistent shift; outside the penalty start (Algorithm 6.1) every pressed point is shifted."""
    from alcontact import penalties
    from alcontact.contact.laws import make_law

    problem, times, path = case
    # the second sliding step: the obstacle has moved by a whole element, the next step's carried pressures reach
    # two points beyond the contact edges (open by 0.06 h and 0.09 h at the predicted state)
    sol = solve_finite(problem, "ssn", steps=times[:6], obstacle_path=path)

    def predicted(**options):
        dc = FiniteContact(problem, **options)
        last = sol.steps[-1]
        x = last.u[dc.free]
        dc.configure(dc.fixed_values, dc.load, translate(problem.obstacle, path(times[5])), x)
        dc.accept(last.pressure)
        dc.configure(dc.fixed_values, dc.load, translate(problem.obstacle, path(times[6])), x,
                     predictor_stiffness=1e4)
        assert dc.predictor_used == "slide"
        return dc

    dc = predicted()
    lam = dc.initial_multipliers()
    law = make_law(penalties.make("rockafellar"), np.full(dc.cand.size, 1e-4))
    g = dc.gaps(dc.start())
    reach = dc.slide_start_reach * dc.h
    far = (lam > 0) & (g < -reach)
    near = (lam > 0) & (g > -reach)
    assert far.any() and near.sum() >= 3
    start = dc.entry_multipliers(lam, law, penalty_start=True)
    np.testing.assert_array_equal(start[far], lam[far])
    assert np.all(law.traction(g, start)[far] == 0.0)
    np.testing.assert_allclose(law.traction(g, start)[near], lam[near], rtol=1e-12, atol=1e-12 * lam.max())
    everywhere = dc.entry_multipliers(lam, law)
    np.testing.assert_allclose(law.traction(g, everywhere)[far], lam[far], rtol=1e-12, atol=1e-12 * lam.max())
    # a reach beyond the candidate margin (2 h): every pressed point is shifted at the penalty start as well
    wide = predicted(slide_start_reach=10.0)
    np.testing.assert_array_equal(wide.initial_multipliers(), lam)
    np.testing.assert_array_equal(wide.entry_multipliers(lam, law, penalty_start=True), everywhere)


def test_slide_start_reach_option_reaches_the_solve(case):
    """The option ``slide_start_reach`` of a solve is the one the model uses: with 10 (every pressed point
    shifted at the penalty start, the behaviour before the reach) exp-met1 takes more Newton iterations over
    the first sliding steps than with the default 0.05 (measured 6.55 / 5.00 per sliding step on the 2d-s
    ironing mesh, ``docs/benchmarks/ironing.md``), and ends at the same forces within 1e-8 of the largest."""
    problem, times, path = case
    short = times[:12]  # 4 pressing + 8 sliding steps
    runs = [solve_finite(problem, "family-p", "exp-met1", steps=short, obstacle_path=path, slide_start_reach=r)
            for r in (0.05, 10.0)]
    assert all(r.status > 0 for r in runs), [r.message for r in runs]
    n = [sum(s.newton_iterations for s in _sliding(problem, r)) for r in runs]
    assert n[0] < n[1], n
    np.testing.assert_allclose(runs[0].forces, runs[1].forces, rtol=0, atol=1e-8 * np.abs(runs[0].forces).max())


def test_inexact_entry_solve_of_the_penalty_start_took_effect(case):
    """Algorithm 6.3's penalty start solves its entry-shifted first subproblem to 1e-4 after a slide prediction
    (``_START_ENTRY_TOL``; the dual step, a second subproblem to ``newton_tol`` and a second dual step follow):
    with ``subproblems = "exact"`` (every solve to ``newton_tol``, the start's included) exp-met1 takes more
    Newton iterations over the first sliding steps, and both end at the same forces within 1e-8 of the largest
    (measured on the 2d-s ironing mesh, 40 sliding steps: 4.03 against 5.00 per step)."""
    problem, times, path = case
    short = times[:12]  # 4 pressing + 8 sliding steps
    runs = [solve_finite(problem, "family-p", "exp-met1", steps=short, obstacle_path=path, subproblems=mode)
            for mode in ("inexact", "exact")]
    assert all(r.status > 0 for r in runs), [r.message for r in runs]
    n = [sum(s.newton_iterations for s in _sliding(problem, r)) for r in runs]
    assert n[0] < n[1], n
    np.testing.assert_allclose(runs[0].forces, runs[1].forces, rtol=0, atol=1e-8 * np.abs(runs[0].forces).max())


@pytest.fixture(scope="module")
def case_3d():
    problem = ironing(3, 4, slide=1.0)  # the 3d-s benchmark mesh, 20 sliding steps of 0.05 R
    times, path = ironing_schedule(problem)
    return problem, times, path


@pytest.mark.slow  # five 3D runs, about 30 s together
@pytest.mark.parametrize("algorithm, penalty", [("ssn", None), ("simo-laursen", None), ("family-p", "exp-met1"),
                                                ("family-p", "log-met1"), ("family-p", "quad-met1")])
def test_3d_newton_per_sliding_step(case_3d, algorithm, penalty):
    """A sphere ploughing a block (3D half model, the 3d-s mesh of ``benchmarks/ironing.py``): every algorithm
    <= 6 Newton per sliding step on average and <= 12 in any step, no cut-back (the issue's target; before
    issue 18's last wave log-met1 took 6.55 / 11 here over 40 steps, exp/quad-met1 5.58 / 10; now 4.55 / 8 for
    all three, ``docs/benchmarks/ironing.md``), every step in equilibrium."""
    problem, times, path = case_3d
    sol = solve_finite(problem, algorithm, penalty, steps=times, obstacle_path=path)
    assert sol.status > 0, sol.message
    steps = _sliding(problem, sol)
    assert len(steps) == 20
    newton = np.array([s.newton_iterations for s in steps])
    assert newton.mean() <= 6.0 and newton.max() <= 12, newton
    assert all(s.cutbacks == 0 for s in sol.steps)
    for s in sol.steps:
        assert _equilibrium(problem, path, s) < 1e-9
