"""The automatic ``penalty_scale`` is the algorithm's (issue 18) and a given value wins.

Algorithms 6.2 and 6.4 with Coulomb friction at finite deformation default to ``penalty_scale = 10``
(the stiff 100 costs Newton iterations in the first subproblem of each sliding step,
``docs/benchmarks/ironing_friction_2d.md``; Algorithm 6.4 since issue 18's second wave); every other
algorithm keeps 100. The value that ran
is recorded in ``FiniteFrictionSolution.extra["penalty_scale"]`` and the penalty stiffness
follows it (``eps_n = penalty_scale E'/h``).
"""

import pytest

from alcontact.contact import ContactOptions, FrictionOptions, solve_finite_friction
from alcontact.contact.algorithms import Algorithm, algorithms
from alcontact.problems.ironing import ironing, ironing_schedule


def test_declared_default_is_automatic():
    assert ContactOptions().penalty_scale is None and FrictionOptions().penalty_scale is None


@pytest.mark.parametrize("entry", algorithms(friction=False, kinematics="small")
                         + algorithms(friction=False, kinematics="finite")
                         + algorithms(friction=True, kinematics="small")
                         + algorithms(friction=True, kinematics="finite"),
                         ids=lambda e: f"{e.name}-{'friction' if e.friction else 'frictionless'}-{e.kinematics}")
def test_each_algorithm_resolves_its_default(entry):
    cls = FrictionOptions if entry.friction else ContactOptions
    expected = 10.0 if (entry.friction, entry.kinematics) == (True, "finite") and entry.name in (
        "simo-laursen", "family-p") else 100.0
    assert cls().resolved(entry).penalty_scale == expected
    assert cls(penalty_scale=3.0).resolved(entry).penalty_scale == 3.0  # a given value is kept


def test_an_entry_without_defaults_gets_100():
    entry = Algorithm("no-defaults", lambda *a: None, "registered without defaults")
    assert ContactOptions().resolved(entry).penalty_scale == 100.0


def test_finite_coulomb_al_runs_with_the_default_and_a_given_value():
    problem = ironing(2, 4, slide=0.1, press_steps=2)
    times, path = ironing_schedule(problem)
    runs = {scale: solve_finite_friction(problem, 0.3, "simo-laursen", steps=times[:3], obstacle_path=path,
                                         **({} if scale is None else {"penalty_scale": scale}))
            for scale in (None, 100.0)}
    assert all(sol.status > 0 for sol in runs.values()), [sol.message for sol in runs.values()]
    assert runs[None].extra["penalty_scale"] == 10.0
    assert runs[100.0].extra["penalty_scale"] == 100.0
    assert runs[100.0].extra["eps_n"] == pytest.approx(10.0 * runs[None].extra["eps_n"], rel=1e-12)
    ref = solve_finite_friction(problem, 0.3, "ssn", steps=times[:3], obstacle_path=path)
    assert ref.extra["penalty_scale"] == 100.0  # the reference keeps 100 (its parameter is E'/h, not the penalty)
    p4 = solve_finite_friction(problem, 0.3, "family-p", steps=times[:3], obstacle_path=path)
    assert p4.status > 0 and p4.extra["penalty_scale"] == 10.0  # Algorithm 6.4 too
    given = solve_finite_friction(problem, 0.3, "simo-laursen", steps=times[:3], obstacle_path=path, eps_n=5e4)
    assert given.extra["penalty_scale"] is None and given.extra["eps_n"] == 5e4  # eps_n given: no scale ran
