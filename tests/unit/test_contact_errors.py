"""Bad input to the frictionless contact solver: clear errors or failed statuses."""

import logging

import numpy as np
import pytest

from alcontact import penalties
from alcontact.contact import ContactProblem, ContactStatus, Support, solve
from alcontact.contact.obstacles import Circle, HalfSpace
from alcontact.errors import ConvergenceError, InputError, MeshError, UnknownNameError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.problems.blocks import patch_block, signorini_block


def _model():
    return LinearElasticity(meshes.rectangle(0, 1, 0, 1, 4, 4), Material(E=100.0, nu=0.3))


def test_unknown_contact_boundary_lists_known_names():
    with pytest.raises(MeshError, match="known: bottom, left, right, top"):
        ContactProblem(_model(), HalfSpace((0, 0), (0, 1)), "botom")


def test_obstacle_never_reached_is_a_failed_status(caplog):
    model = _model()
    prob = ContactProblem(model, HalfSpace((0, -1.0), (0, 1)), "bottom",
                          supports=(Support("top"),))
    with caplog.at_level(logging.WARNING):
        sol = solve(prob)
    assert sol.result.status == ContactStatus.NO_CONTACT
    assert "never reaches the obstacle" in sol.result.message and "move the obstacle" in sol.result.message
    assert "never reaches" in caplog.text
    with pytest.raises(ConvergenceError):
        sol.result.raise_for_status()


def test_unrestrained_body_names_the_free_motion():
    model = _model()
    prob = ContactProblem(model, HalfSpace((0, 0), (0, 1)), "bottom", supports=(Support("top", components=(1,)),))
    with pytest.raises(InputError, match="rigid-body"):
        solve(prob)


@pytest.mark.parametrize("E,nu,match", [(0.0, 0.3, "E"), (-1.0, 0.3, "E"), (1.0, 0.5, "nu"), (1.0, -1.0, "nu")])
def test_bad_material(E, nu, match):
    with pytest.raises(InputError, match=match):
        Material(E=E, nu=nu)


def test_wrong_obstacle_dimension():
    with pytest.raises(InputError):
        ContactProblem(_model(), HalfSpace((0, 0, 0), (0, 0, 1)), "bottom")


def test_unknown_algorithm_and_penalty():
    prob = patch_block(2, 1, n=2)
    with pytest.raises(UnknownNameError, match="simo-laursen"):
        solve(prob, "simo-lausen")
    with pytest.raises(UnknownNameError, match="exp-met1"):
        solve(prob, "family-p", "exp-met3")
    with pytest.raises(InputError, match="family-p"):
        solve(prob, "simo-laursen", "exp-met1")
    with pytest.raises(InputError, match="unknown contact option"):
        solve(prob, penalty_scal=3)
    with pytest.raises(InputError, match="tau"):
        solve(prob, tau=2.0)


def test_penalty_that_yields_nan_fails_with_reason():
    class NaNPenalty:
        name = "nan-test"
        properties = frozenset({"P1", "P2", "P3", "P4", "P5"})
        family_p = True

        def value(self, y, mu):
            return np.full(np.shape(y), np.nan)

        derivative = second_derivative = value

        def domain_upper(self, mu):
            return np.full(np.shape(mu), np.inf)

    penalties.register("nan-test", lambda: NaNPenalty(), doc="returns NaN (test)")
    try:
        sol = solve(patch_block(2, 1, n=2), "family-p", "nan-test")
    finally:
        penalties.unregister("nan-test")
    assert sol.result.status < 0
    assert "NaN" in sol.result.message


def test_maxiter_is_reported_with_advice():
    sol = solve(signorini_block(n=4), "simo-laursen", maxiter=1, penalty_scale=1.0)
    assert sol.result.status == ContactStatus.MAXITER
    assert "maxiter" in sol.result.message


def test_dirichlet_point_penetrating_is_an_error():
    model = _model()
    prob = ContactProblem(model, Circle(center=(0.5, -0.9), radius=1.0), "bottom", supports=(Support("bottom"),))
    with pytest.raises(InputError, match="penetrates"):
        solve(prob)


def test_body_not_touching_and_unsupported_says_so():
    model = _model()
    prob = ContactProblem(model, HalfSpace((0, -0.5), (0, 1)), "bottom", supports=(Support("left", components=(0,)),))
    with pytest.raises(InputError, match="does not touch the obstacle"):
        solve(prob)


def test_contact_cannot_restrain_tangential_motion():
    model = _model()
    prob = ContactProblem(model, HalfSpace((0, 0), (0, 1)), "bottom")
    with pytest.raises(InputError, match="do not restrain that motion"):
        solve(prob)
