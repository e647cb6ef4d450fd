"""Large sliding with Coulomb friction at finite deformation converges like Newton (issue 18).

Ironing (:func:`alcontact.problems.ironing.ironing`): a rigid cylinder of radius R = 1 pressed
0.2 R into a neo-Hookean block (E = 1000, nu = 0.3, plane strain, P1, h = 0.1) in 4 steps,
then slid by 1.5 R in steps of 0.05 R (30 sliding steps), Coulomb friction mu = 0.3, solved by
the semi-smooth Newton reference ``ssn`` (:func:`alcontact.contact.solve_finite_friction`).
Before the fix (issue 18: Alart-Curnier parameter c = E'/h instead of the AL penalty
100 E'/h) the stick-to-slip transition took 65, 49 and 41 Newton iterations in the first three
sliding steps, with a cut-back.

Promises guarded here (the issue's targets; measured on this mesh, in brackets):
- <= 8 Newton iterations per sliding step on average (<= 12 in any step, the frictionless
  bound), no cut-back [3.4 mean, max 5];
- at every slipping point |t_T| = mu t_N to 1e-8 relative [<= 5e-16], at every sticking point
  |t_T| <= mu t_N;
- stick/slip states do not flip back and forth between the Newton iterates of an accepted
  step: no point returns to a state it had left once the contact zone slides as a whole
  (after the stick-to-slip transition, the first 0.25 R of travel) [none; one point in the
  second sliding step goes slip -> stick -> slip, measured and bounded below];
- every accepted step is in equilibrium with the tractions it reports (normal and
  tangential): the residual recomputed here from the returned displacement and tractions is
  below 1e-9 of the largest nodal contact force.

Algorithm 6.2 (Simo-Laursen with Coulomb, ``simo-laursen``) on the same case, with the
second-order multiplier update at finite deformation (before: first-order updates (6.2b)/(6.2c)
only, 11-13 outer iterations and 33.4 Newton per sliding step, max 73; ``docs/benchmarks/
ironing_friction_2d.md``):
- with its default ``penalty_scale`` (10 for Algorithm 6.2 with friction at finite deformation,
  :data:`alcontact.contact.algorithms._coulomb.FINITE_AL_DEFAULTS`; recorded in
  ``extra["penalty_scale"]``) and with ``penalty_scale = 10`` given: <= 8 Newton per sliding step
  on average (the issue's target), no cut-back [6.37 mean over these 30 steps, max 22]; with
  ``penalty_scale = 100`` given (the default before): <= 12 [9.8, max 61 at the stick-to-slip
  transition];
- <= 4 outer iterations in every sliding step (the second-order update took effect) [3];
- the Coulomb law at slipping and sticking points and equilibrium as above, and the forces and
  displacements of every step equal the semi-smooth Newton reference's within 1e-9 relative
  [<= 2e-12]: both solve the same discrete problem, the penalty only changes the path.
"""

import numpy as np
import pytest

from alcontact.contact import solve_finite_friction
from alcontact.contact.obstacles import translate
from alcontact.problems.ironing import ironing, ironing_schedule

MU = 0.3
SLIP, STICK = 2, 1  # FiniteFrictionStep.states (alcontact.contact.laws._coulomb)


@pytest.fixture(scope="module")
def run():
    problem = ironing(2, 10, slide=1.5)
    times, path = ironing_schedule(problem)
    sol = solve_finite_friction(problem, MU, "ssn", steps=times, obstacle_path=path)
    return problem, path, sol


#: Algorithm 6.2's runs: name -> options
AL_RUNS = {"default": {}, "penalty_scale=10": {"penalty_scale": 10.0}, "penalty_scale=100": {"penalty_scale": 100.0}}


@pytest.fixture(scope="module")
def al_runs(run):
    problem, path, _ = run
    times, _ = ironing_schedule(problem)
    return {name: solve_finite_friction(problem, MU, "simo-laursen", steps=times, obstacle_path=path, **opts)
            for name, opts in AL_RUNS.items()}


def _sliding(problem, sol):
    return [s for s in sol.steps if s.t > problem.meta["press_steps"]]


def test_newton_per_sliding_step(run):
    problem, _, sol = run
    assert sol.status > 0, sol.message
    steps = _sliding(problem, sol)
    assert len(steps) == problem.meta["slide_steps"] == 30
    newton = np.array([s.newton_iterations for s in steps])
    assert newton.mean() <= 8.0 and newton.max() <= 12, newton
    assert all(s.cutbacks == 0 for s in sol.steps)


def test_coulomb_law_at_slipping_and_sticking_points(run):
    problem, _, sol = run
    slipping = 0
    for s in sol.steps:
        tt = np.linalg.norm(s.traction_t, axis=1)
        bound = MU * s.pressure
        slip = s.states == SLIP
        stick = s.states == STICK
        slipping += int(slip.sum())
        assert np.all(np.abs(tt[slip] - bound[slip]) <= 1e-8 * bound[slip]), s.t
        assert np.all(tt[stick] <= bound[stick] * (1.0 + 1e-8)), s.t
        assert np.all(s.pressure[slip | stick] > 0)
    # the test has something to check: the contact zone slips in steady sliding
    steady = [s for s in _sliding(problem, sol) if (s.t - problem.meta["press_steps"]) * problem.meta["slide_step"] > 0.25]
    assert all(np.count_nonzero(s.states == SLIP) >= 5 for s in steady)
    assert slipping > 100


def test_no_stick_slip_flip_flop(run):
    problem, _, sol = run
    steps = _sliding(problem, sol)
    assert all(s.state_reversals is not None for s in steps)  # ssn tracks them
    travel = lambda s: (s.t - problem.meta["press_steps"]) * problem.meta["slide_step"]  # noqa: E731
    assert [s.state_reversals for s in steps if travel(s) > 0.25] == [0] * sum(travel(s) > 0.25 for s in steps)
    # the stick-to-slip transition: at most one point, once, in the whole run's sliding
    assert sum(s.state_reversals for s in steps) <= 1


def test_equilibrium_with_reported_tractions(run):
    problem, path, sol = run
    model = problem.model
    pts, dofs = model.node_dofs(problem.contact_boundary)
    w = np.asarray(model.boundary_weights(problem.contact_boundary), dtype=float)
    free = np.ones(model.ndofs, dtype=bool)
    free[np.asarray(problem.dirichlet()[0], dtype=np.int64)] = False
    load = np.asarray(problem.load_vector(), dtype=float)
    for s in sol.steps:
        _, nu = translate(problem.obstacle, path(s.t)).evaluate(pts + s.u[dofs])
        f = np.asarray(model.internal_force(s.u), dtype=float) - load
        # the obstacle's force on the body: w (t_N nu - t_T)
        contact = w[:, None] * (s.pressure[:, None] * nu - s.traction_t)
        np.add.at(f, dofs.ravel(), (-contact).ravel())
        assert float(np.max(np.abs(f[free]))) < 1e-9 * float(np.max(w * s.pressure)), s.t


def _equilibrium_residual(problem, path, step) -> float:
    """Largest free-DOF residual of ``f_int - f_ext - w (t_N nu - t_T)`` over the largest nodal contact force."""
    model = problem.model
    pts, dofs = model.node_dofs(problem.contact_boundary)
    w = np.asarray(model.boundary_weights(problem.contact_boundary), dtype=float)
    free = np.ones(model.ndofs, dtype=bool)
    free[np.asarray(problem.dirichlet()[0], dtype=np.int64)] = False
    _, nu = translate(problem.obstacle, path(step.t)).evaluate(pts + step.u[dofs])
    f = np.asarray(model.internal_force(step.u), dtype=float) - np.asarray(problem.load_vector(), dtype=float)
    np.add.at(f, dofs.ravel(), (-(w[:, None] * (step.pressure[:, None] * nu - step.traction_t))).ravel())
    return float(np.max(np.abs(f[free]))) / float(np.max(w * step.pressure))


@pytest.mark.slow
def test_algorithm_62_newton_per_sliding_step(run, al_runs):
    problem = run[0]
    eps = {name: sol.extra["eps_n"] for name, sol in al_runs.items()}
    # the algorithm's default is 10 and a given value wins (the option took effect both ways)
    assert {name: sol.extra["penalty_scale"] for name, sol in al_runs.items()} == {
        "default": 10.0, "penalty_scale=10": 10.0, "penalty_scale=100": 100.0}
    assert eps["penalty_scale=10"] == eps["default"]
    assert eps["penalty_scale=100"] == pytest.approx(eps["default"] * 10.0, rel=1e-12)
    bounds = {"default": 8.0, "penalty_scale=10": 8.0, "penalty_scale=100": 12.0}
    for name, sol in al_runs.items():
        assert sol.status > 0, (name, sol.message)
        steps = _sliding(problem, sol)
        assert len(steps) == 30
        newton = np.array([s.newton_iterations for s in steps])
        assert newton.mean() <= bounds[name], (name, newton)
        assert all(s.cutbacks == 0 for s in sol.steps), name
        # the second-order multiplier update at finite deformation: 2-4 outer iterations, not 11-13
        assert max(s.outer_iterations for s in steps) <= 4, (name, [s.outer_iterations for s in steps])


@pytest.mark.slow
def test_algorithm_62_coulomb_law_equilibrium_and_reference(run, al_runs):
    problem, path, ref = run
    for name, sol in al_runs.items():
        slipping = 0
        for s, r in zip(sol.steps, ref.steps, strict=True):
            assert s.t == r.t
            tt = np.linalg.norm(s.traction_t, axis=1)
            bound = MU * s.pressure
            slip, stick = s.states == SLIP, s.states == STICK
            slipping += int(slip.sum())
            assert np.all(np.abs(tt[slip] - bound[slip]) <= 1e-8 * bound[slip]), (name, s.t)
            assert np.all(tt[stick] <= bound[stick] * (1.0 + 1e-8)), (name, s.t)
            assert _equilibrium_residual(problem, path, s) < 1e-9, (name, s.t)
            # the same discrete problem as the reference: same forces and displacements
            assert np.max(np.abs(s.force - r.force)) <= 1e-9 * np.max(np.abs(r.force)), (name, s.t)
            assert np.max(np.abs(s.u - r.u)) <= 1e-9 * np.max(np.abs(r.u)), (name, s.t)
        assert slipping > 100, name


def _travel(problem, s) -> float:
    return (s.t - problem.meta["press_steps"]) * problem.meta["slide_step"]


@pytest.mark.slow
def test_algorithm_62_no_stick_slip_flip_flop(run, al_runs):
    """The AL engine tracks the reversals over the Newton iterates of all the subproblems of a step: no
    point goes back and forth between stick and slip once the zone slides as a whole (after 0.25 R)."""
    problem = run[0]
    for name, sol in al_runs.items():
        steps = _sliding(problem, sol)
        assert all(s.state_reversals is not None and s.stick_slip_reversals is not None for s in steps), name
        late = [s.stick_slip_reversals for s in steps if _travel(problem, s) > 0.25]
        assert late == [0] * len(late), (name, late)


@pytest.fixture(scope="module")
def p4_run(run):
    problem, path, _ = run
    times, _ = ironing_schedule(problem)
    return solve_finite_friction(problem, MU, "family-p", steps=times, obstacle_path=path)


@pytest.mark.slow
def test_algorithm_64_default_newton_coulomb_law_and_reference(run, p4_run):
    """Algorithm 6.4 (family-P, its default penalty exp-met1) with its finite-deformation defaults
    (penalty_scale 10, second-order update): <= 8 Newton per sliding step on average, no cut-back, the slip law
    to 1e-8 at every slipping point pressed above 1e-14 of the largest pressure (exp-met1 keeps t_N ~ 1e-280 at
    open points, where |t_T| is compared on mu times the largest pressure), and the reference's forces."""
    problem, path, ref = run
    sol = p4_run
    assert sol.status > 0, sol.message
    assert sol.extra["penalty_scale"] == 10.0 and sol.extra["penalty"] == "exp-met1"
    steps = _sliding(problem, sol)
    assert len(steps) == 30 and all(s.cutbacks == 0 for s in sol.steps)
    newton = np.array([s.newton_iterations for s in steps])
    assert newton.mean() <= 8.0, newton
    assert max(s.outer_iterations for s in steps) <= 4
    for s, r in zip(sol.steps, ref.steps, strict=True):
        tt = np.linalg.norm(s.traction_t, axis=1)
        bound = MU * s.pressure
        scale = np.maximum(bound, 1e-14 * MU * float(np.max(s.pressure)))
        slip = s.states == SLIP
        assert np.all(np.abs(tt[slip] - bound[slip]) <= 1e-8 * scale[slip]), s.t
        assert _equilibrium_residual(problem, path, s) < 1e-9, s.t
        assert np.max(np.abs(s.force - r.force)) <= 1e-9 * np.max(np.abs(r.force)), s.t
