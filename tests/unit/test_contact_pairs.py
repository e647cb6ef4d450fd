"""``ContactProblem(bodies=[...], pairs=[ContactPair(...)])`` and the single-body shorthand.

Reference: the shorthand ``ContactProblem(model, obstacle, contact_boundary, ...)`` of the
same body; the pair form must give the same solution to the last bit (``array_equal``) on
the small frictionless, small Coulomb and finite-deformation paths. What is not supported
yet (several bodies, several pairs, a deformable master) is refused with an InputError
that names it and points to the architecture page.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from alcontact.contact import (Boundary, ContactPair, ContactProblem, Master, Support, obstacles, solve,
                               solve_finite, solve_friction)
from alcontact.errors import InputError
from alcontact.fem import Hyperelastic, Material, meshes
from alcontact.problems import friction, hertz


def _pair_form(short: ContactProblem) -> ContactProblem:
    """The same problem written with bodies and pairs."""
    body = short.model
    pair = ContactPair(slave=Boundary(body, short.contact_boundary), master=short.obstacle, friction=short.friction)
    return ContactProblem(bodies=[body], pairs=[pair], supports=short.supports, loads=short.loads, name=short.name,
                          reference=short.reference, meta=short.meta, kinematics=short.kinematics)


def _finite_block() -> ContactProblem:
    body = Hyperelastic(meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4), Material(E=1000.0, nu=0.3, plane="strain"))
    return ContactProblem(body, obstacles.HalfSpace((0.0, 0.0), (0.0, 1.0)), "bottom",
                          supports=[Support("top", (1,), -0.02), Support("left", (0,))], kinematics="finite")


# ------------------------------------------------------------------------------------------ same numbers
@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "ssn"])
def test_pair_form_gives_the_shorthand_solution_small_frictionless(algorithm):
    a = solve(hertz.hertz_2d(level=0), algorithm)
    b = solve(_pair_form(hertz.hertz_2d(level=0)), algorithm)  # a fresh body: nothing shared with a
    assert a.result.status > 0
    np.testing.assert_array_equal(a.u, b.u)
    np.testing.assert_array_equal(a.pressure, b.pressure)
    assert (a.result.outer_iterations, a.result.newton_iterations, a.result.linear_solves) == \
        (b.result.outer_iterations, b.result.newton_iterations, b.result.linear_solves)


def test_pair_form_gives_the_shorthand_solution_coulomb():
    prob_a, hist_a = friction.block_on_plane(dim=2, n=4)
    prob_b, hist_b = friction.block_on_plane(dim=2, n=4)
    assert prob_a.friction > 0
    a = solve_friction(prob_a, hist_a)
    b = solve_friction(_pair_form(prob_b), hist_b)
    assert b.friction == prob_a.friction  # the pair's coefficient is the one that ran
    for sa, sb in zip(a.steps, b.steps, strict=True):
        np.testing.assert_array_equal(sa.u, sb.u)
        np.testing.assert_array_equal(sa.traction_t, sb.traction_t)


def test_pair_form_gives_the_shorthand_solution_finite():
    a = solve_finite(_finite_block(), steps=2)
    b = solve_finite(_pair_form(_finite_block()), steps=2)
    assert a.status > 0
    np.testing.assert_array_equal(a.u, b.u)
    assert [s.newton_iterations for s in a.steps] == [s.newton_iterations for s in b.steps]


# ------------------------------------------------------------------------------------------ structure
def test_views_of_the_one_body_and_pair():
    short = hertz.hertz_2d(level=0)
    assert short.bodies == (short.model,)
    (pair,) = short.pairs
    assert pair.slave.body is short.model and pair.slave.name == short.contact_boundary == "top"
    assert pair.master is short.obstacle and isinstance(pair.master, Master) and pair.rigid
    assert pair.friction == short.friction == 0.0
    full = _pair_form(short)
    assert full.model is short.model and full.obstacle is short.obstacle
    assert isinstance(full.bodies, tuple) and isinstance(full.pairs, tuple)
    assert full == short  # same body, same master, same boundary and coefficient: equal problems
    assert full != dataclasses.replace(short, friction=0.1)


def test_problem_is_frozen():
    problem = _pair_form(hertz.hertz_2d(level=0))
    for name, value in (("bodies", ()), ("pairs", ()), ("model", None), ("obstacle", None), ("friction", 0.5)):
        with pytest.raises((dataclasses.FrozenInstanceError, AttributeError)):
            setattr(problem, name, value)
    with pytest.raises(dataclasses.FrozenInstanceError):
        problem.pairs[0].friction = 0.5


def test_replace_with_a_shorthand_argument_edits_the_one_pair():
    problem = _pair_form(hertz.hertz_2d(level=0))
    other = obstacles.make("circle", center=[0.0, 12.0], radius=10.0)
    moved = dataclasses.replace(problem, obstacle=other, friction=0.25)
    assert moved.obstacle is other and moved.pairs[0].master is other
    assert moved.friction == moved.pairs[0].friction == 0.25
    assert moved.model is problem.model and moved.contact_boundary == "top"
    assert problem.obstacle is not other and problem.friction == 0.0  # the original is unchanged
    same = dataclasses.replace(problem, name="renamed")
    assert same.pairs[0] is problem.pairs[0]


# ------------------------------------------------------------------------------------------ refusals
class _DeformableSurface:
    """A master that moves with a body (``rigid = False``), otherwise a plane: what issue-23 masters declare."""

    def __init__(self) -> None:
        self._plane = obstacles.HalfSpace((0.0, 0.0), (0.0, 1.0))

    rigid = False
    dim = 2
    name = "surface"

    def describe(self) -> str:
        return "surface of a deformable body"

    def __getattr__(self, item):
        return getattr(self._plane, item)


def _parts():
    short = hertz.hertz_2d(level=0)
    return short.model, ContactPair(Boundary(short.model, "top"), short.obstacle), short


def test_two_bodies_without_a_pair_between_them_are_refused():
    body, pair, short = _parts()
    with pytest.raises(InputError) as info:
        ContactProblem(bodies=[body, hertz.hertz_2d(level=0).model], pairs=[pair], supports=short.supports)
    msg = str(info.value)
    assert "2 bodies" in msg and "no pair joins" in msg and "BodySurface" in msg and "docs/architecture.md" in msg


def test_two_pairs_keep_their_own_friction_coefficients():
    body, pair, short = _parts()
    second = ContactPair(Boundary(body, "bottom"), obstacles.make("half-space", point=[0, -20], normal=[0, 1]),
                         friction=0.3)
    prob = ContactProblem(bodies=[body], pairs=[pair, second], supports=short.supports)
    owner = prob.pair_of_points()
    np.testing.assert_array_equal(prob.point_friction(), np.where(owner == 0, 0.0, 0.3))


def test_shorthand_friction_with_two_pairs_is_refused():
    body, pair, short = _parts()
    second = ContactPair(Boundary(body, "bottom"), obstacles.make("half-space", point=[0, -20], normal=[0, 1]))
    with pytest.raises(InputError, match="friction given with several pairs"):
        ContactProblem(bodies=[body], pairs=[pair, second], supports=short.supports, friction=0.2)


def _two_finite_pairs(friction=0.0):
    body = Hyperelastic(meshes.rectangle(0.0, 1.0, 0.0, 1.0, 2, 2), Material(E=1000.0, nu=0.3, plane="strain"))
    pairs = [ContactPair(Boundary(body, "bottom"), obstacles.HalfSpace((0.0, 0.0), (0.0, 1.0)), friction=friction),
             ContactPair(Boundary(body, "top"), obstacles.HalfSpace((0.0, 1.0), (0.0, -1.0)), friction=friction)]
    return ContactProblem(bodies=[body], pairs=pairs, supports=[Support("left")], kinematics="finite")


def test_two_frictional_pairs_at_finite_deformation_are_refused():
    with pytest.raises(InputError) as info:
        _two_finite_pairs(friction=0.2)
    msg = str(info.value)
    assert "2 contact pairs with friction" in msg and "kinematics='small'" in msg


@pytest.mark.parametrize("kwargs, text", [(dict(friction=0.2), "friction 0"),
                                          (dict(obstacle_path=lambda t: [0.0, -0.01 * t]), "no obstacle_path")])
def test_two_pairs_at_finite_deformation_refuse_friction_and_a_moving_master_in_solve(kwargs, text):
    with pytest.raises(InputError, match=text):
        solve(_two_finite_pairs(), "simo-laursen", steps=2, **kwargs)


def test_a_deformable_master_of_no_body_is_refused():
    body, _, short = _parts()
    surface = _DeformableSurface()
    assert isinstance(surface, Master) and not surface.rigid
    pair = ContactPair(Boundary(body, "top"), surface)
    with pytest.raises(InputError) as info:
        ContactProblem(bodies=[body], pairs=[pair], supports=short.supports)
    msg = str(info.value)
    assert "surface of a deformable body" in msg and "not rigid" in msg and "BodySurface" in msg
    assert "docs/architecture.md" in msg


@pytest.mark.parametrize("case, texts", [
    ("foreign slave", ["pairs[0].slave", "not in bodies"]),
    ("no bodies", ["bodies = []", "at least one"]),
    ("no pairs", ["pairs = []", "at least one"]),
    ("bare pair", ["pairs = ContactPair(...)", "wrap the single item in a list"]),
    ("bare body", ["bodies = LinearElasticity(...)", "wrap the single item in a list"]),
    ("not a pair", ["pairs[0]", "ContactPair(slave=Boundary(body, name)"]),
    ("not a body", ["bodies[0]", "a discretized body"]),
    ("missing shorthand", ["missing obstacle, contact_boundary", "ContactProblem(bodies=[body]"]),
    ("bodies only", ["bodies given without pairs", "needs both"]),
    ("slave name", ["ContactPair: slave", "Boundary(body, 'contact')"]),
    ("master", ["ContactPair: master", "obstacles.make"]),
    ("negative friction", ["friction coefficient must be >= 0"]),
    ("boundary name", ["boundary 'topp' not found", "known"]),
])
def test_bad_pair_forms_name_the_argument(case, texts):
    from alcontact.errors import AlcontactError

    body, pair, short = _parts()
    calls = {
        "foreign slave": lambda: ContactProblem(bodies=[body], pairs=[ContactPair(
            Boundary(hertz.hertz_2d(level=0).model, "top"), short.obstacle)]),
        "no bodies": lambda: ContactProblem(bodies=[], pairs=[pair]),
        "no pairs": lambda: ContactProblem(bodies=[body], pairs=[]),
        "bare pair": lambda: ContactProblem(bodies=[body], pairs=pair),
        "bare body": lambda: ContactProblem(bodies=body, pairs=[pair]),
        "not a pair": lambda: ContactProblem(bodies=[body], pairs=[(body, short.obstacle)]),
        "not a body": lambda: ContactProblem(bodies=["mesh.msh"], pairs=[pair]),
        "missing shorthand": lambda: ContactProblem(body),
        "bodies only": lambda: ContactProblem(bodies=[body], supports=short.supports),
        "slave name": lambda: ContactPair("top", short.obstacle),
        "master": lambda: ContactPair(Boundary(body, "top"), "circle"),
        "negative friction": lambda: ContactPair(Boundary(body, "top"), short.obstacle, friction=-0.1),
        "boundary name": lambda: ContactProblem(bodies=[body], pairs=[ContactPair(Boundary(body, "topp"),
                                                                                  short.obstacle)]),
    }
    with pytest.raises(AlcontactError) as info:
        calls[case]()
    for t in texts:
        assert t in str(info.value), str(info.value)
