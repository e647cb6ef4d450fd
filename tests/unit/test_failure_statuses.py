"""Every failure status of the contact solvers and of ``optim.minimize`` is reached by some input.

Each case builds the smallest input that ends in one negative status and checks the
status, that ``success`` is false / the status is negative, that the message says what
to try, that a warning is logged, and that ``raise_for_status`` raises
``ConvergenceError``. A last test checks the tables cover every negative member of
``ContactStatus`` and ``optim.Status``, so a new failure status needs a test here.

Reaches inside the package: a fake algorithm registered for the test's duration in the private
registry table (``monkeypatch.setitem``) returning the private run record, so that nothing stays
registered after it.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import pytest

from _helpers import sq, sq_grad, sq_hess
from alcontact import penalties
from alcontact.contact import ContactProblem, ContactStatus, LoadCase, LoadHistory, Ramp, Support, solve, solve_friction
from alcontact.contact.problem import Pressure, Traction
from alcontact.contact.obstacles import HalfSpace
from alcontact.errors import ConvergenceError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.contact.algorithms import _frictionless as _algorithms
from alcontact.optim import Status, minimize
from alcontact.status import CONTACT_CODES, OPTIM_CODES
from alcontact.penalties import Rockafellar
from alcontact.problems.blocks import patch_block


@dataclasses.dataclass(frozen=True)
class _NaNPenalty(Rockafellar):
    """Rockafellar's penalty whose derivative is NaN at any penetration (a broken user penalty)."""

    name: str = "nan-after-contact"

    def _dp(self, y, mu):
        return np.where(y > 0, np.nan, np.maximum(0.0, mu + y))


@pytest.fixture
def nan_penalty():
    penalties.register("nan-after-contact", _NaNPenalty, doc="test penalty returning NaN in contact")
    yield "nan-after-contact"
    penalties.unregister("nan-after-contact")


def _no_contact():
    model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 2, 2), Material(E=100.0, nu=0.3))
    return ContactProblem(model, HalfSpace((0, -1.0), (0, 1)), "bottom", supports=(Support("top"),))


def _contact_cases():
    return {
        ContactStatus.NO_CONTACT: lambda pen: solve(_no_contact()),
        ContactStatus.MAXITER: lambda pen: solve(patch_block(2, 1, n=2), "simo-laursen", maxiter=1),
        ContactStatus.NEWTON_FAILED: lambda pen: solve(patch_block(2, 1, n=2), "simo-laursen", maxiter_newton=1,
                                                       newton_tol=1e-300),
        ContactStatus.NONFINITE: lambda pen: solve(patch_block(2, 1, n=2), "family-p", pen),
        ContactStatus.PENALTY_LIMIT: lambda pen: solve(patch_block(2, 1, n=2), "penalty", eps_max=1.0),
        ContactStatus.NOT_VERIFIED: lambda pen: solve(patch_block(2, 1, n=2), "claims-converged"),
        ContactStatus.UNBOUNDED: lambda pen: _FrictionResult(solve_friction(*_sliding_away())),
    }


def _sliding_away():
    """A block held only by friction on a plane, pushed sideways by 1.5 mu N: no static equilibrium."""
    model = LinearElasticity(meshes.rectangle(0, 1, 0, 0.5, 4, 2), Material(E=100.0, nu=0.0))
    prob = ContactProblem(model, HalfSpace((0, 0.0), (0, 1)), "bottom", friction=0.3)
    hist = LoadHistory((LoadCase(Pressure("top", 1.0), Ramp((0, 0.5), (0, 1), hold_after=True)),
                        LoadCase(Traction("top", (0.45, 0.0)), Ramp((0.5, 1.0), (0, 1)))), (0.5, 1.0))
    return prob, hist


@dataclasses.dataclass
class _FrictionResult:
    """The frictional solution seen through the ``.result`` of a frictionless one."""

    result: object


def _claims_converged(dc, opts, eps0, penalty_name):
    """An 'algorithm' that claims convergence with zero pressure (the body penetrates)."""
    r = dc.start()
    return _algorithms._Run(r, np.zeros(dc.cand.size), dc.gaps(r), ContactStatus.CONVERGED, "converged", 1, 1,
                            eps0, 0.0, [])


@pytest.fixture(autouse=True)
def _wrong_algorithm(monkeypatch):
    fake = _algorithms.Algorithm("claims-converged", _claims_converged, "wrong on purpose")
    monkeypatch.setitem(_algorithms._REGISTRY, fake.key, fake)


@pytest.mark.parametrize("status", sorted(s for s in CONTACT_CODES if s < 0), ids=lambda s: s.name)
def test_contact_failure_status(status, nan_penalty, caplog):
    """Each negative ContactStatus: negative, logged with a hint, and raise_for_status raises."""
    with caplog.at_level(logging.WARNING, logger="alcontact"):
        sol = _contact_cases()[status](nan_penalty)
    res = sol.result
    assert res.status == status, (res.status, res.message)
    assert res.status < 0 and res.message
    assert any(r.levelno == logging.WARNING and status.label in r.getMessage() for r in caplog.records)
    with pytest.raises(ConvergenceError):
        res.raise_for_status()


def _optim_cases():
    at_least_1 = {"type": "ineq", "fun": lambda x: x[0] - 1.0, "jac": lambda x: np.array([1.0])}
    at_most_0 = {"type": "ineq", "fun": lambda x: -x[0], "jac": lambda x: np.array([-1.0])}
    at_most_1 = {"type": "ineq", "fun": lambda x: 1.0 - x[0], "jac": lambda x: np.array([-1.0])}
    half = {"type": "ineq", "fun": lambda x: -1.0 - x[0] - x[1], "jac": lambda x: np.array([-1.0, -1.0])}
    calls = {"n": 0}

    def nan_late(x):
        calls["n"] += 1
        return np.full(2, np.nan) if calls["n"] > 3 else 2 * x

    def no_descent(x):  # a gradient inconsistent with fun: Newton directions are not descent directions
        return -2 * x

    x2 = np.array([1.0, 2.0])
    return {
        Status.MAXITER: lambda: minimize(sq, x2, jac=sq_grad, hess=sq_hess, constraints=half,
                                         options={"maxiter": 1}),
        Status.INNER_FAILED: lambda: minimize(sq, x2, jac=no_descent, hess=lambda x: -2 * np.eye(2), constraints=half,
                                              penalty="rockafellar"),
        Status.NONFINITE: lambda: minimize(sq, x2, jac=nan_late, hess=sq_hess, constraints=half),
        # x >= 1 and x <= 0: infeasible, the penalty parameter runs into eta_min
        Status.PENALTY_LIMIT: lambda: minimize(lambda x: float(x[0] ** 2), np.array([0.5]), jac=lambda x: 2 * x,
                                               hess=lambda x: 2 * np.eye(1), constraints=[at_least_1, at_most_0]),
        # min x subject to x <= 1: unbounded below
        Status.UNBOUNDED: lambda: minimize(lambda x: float(x[0]), np.array([0.0]), jac=lambda x: np.ones(1),
                                           hess=lambda x: np.zeros((1, 1)), constraints=[at_most_1],
                                           options={"unbounded_below": -1e6}),
    }


@pytest.mark.parametrize("status", sorted(s for s in OPTIM_CODES if s < 0), ids=lambda s: s.name)
def test_optim_failure_status(status, caplog):
    """Each negative optim Status: not success, logged warning with what to try, raise_for_status raises."""
    with caplog.at_level(logging.WARNING, logger="alcontact.optim"):
        res = _optim_cases()[status]()
    assert res.status == status, (res.status, res.message)
    assert not res.success and "try" in res.message
    assert any(r.levelno == logging.WARNING for r in caplog.records)
    with pytest.raises(ConvergenceError, match=status.name):
        res.raise_for_status()


def test_every_failure_status_has_a_case():
    assert {s for s in CONTACT_CODES if s < 0} == set(_contact_cases())
    assert {s for s in OPTIM_CODES if s < 0} == set(_optim_cases())
    # every failure code of the one table belongs to contact or optim (or is an inner-solver reason)
    inner_only = {Status.LINE_SEARCH_FAILED}
    assert {s for s in Status if s < 0} == {s for s in CONTACT_CODES | OPTIM_CODES | inner_only if s < 0}
