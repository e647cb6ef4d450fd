"""Unit tests of the result verifier: a wrong state never leaves a solver as ``converged``.

Reaches inside the package: unit test of ``contact._verify.verified_status`` (invariants to status),
and fake algorithms registered for the test's duration in the private registry table
(``monkeypatch.setitem``) returning the private run records, so that nothing stays registered after
it.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from alcontact.contact import ContactStatus, solve, solve_friction
from alcontact.contact.algorithms import _coulomb as _friction
from alcontact.contact.algorithms import _frictionless as _algorithms
from alcontact.contact import check_state
from alcontact.contact._verify import verified_status
from alcontact.problems import friction as fp
from alcontact.problems import hertz

H = 0.1
TOL = 1e-8


def _check(gap, p, **kw):
    return check_state(np.asarray(gap, float), np.asarray(p, float), H, tol_penetration=TOL,
                       tol_complementarity=TOL, **kw)


def test_correct_frictionless_state_passes():
    c = _check([0.0, 0.0, -0.05], [2.0, 1.0, 0.0])
    assert c.ok
    assert verified_status(ContactStatus.CONVERGED, "converged", c) == (ContactStatus.CONVERGED, "converged")


@pytest.mark.parametrize("gap, p, measure", [
    ([0.0, 0.006 * H, -0.05], [2.0, 0.0, 0.0], "penetration"),  # 0.6 % of h inside the obstacle
    ([0.0, 0.0, -0.05], [2.0, 1.0, 0.3], "complementarity"),  # pressure on an open point
    ([0.0, 0.0, -0.05], [2.0, -0.1, 0.0], "complementarity"),  # tensile contact pressure
    ([0.0, np.nan, -0.05], [2.0, 1.0, 0.0], "finite"),
])
def test_wrong_frictionless_state_flips_status(gap, p, measure, caplog):
    c = _check(gap, p)
    assert set(c.failed) == {measure}
    with caplog.at_level(logging.WARNING, logger="alcontact.contact._verify"):
        status, msg = verified_status(ContactStatus.CONVERGED, "converged", c)
    assert status == ContactStatus.NOT_VERIFIED and status < 0
    assert measure in msg and "tolerance" in msg and "try" in msg
    assert any(measure in r.getMessage() for r in caplog.records if r.levelno == logging.WARNING)


def test_negative_status_is_kept():
    c = _check([1.0], [0.0])
    assert verified_status(ContactStatus.MAXITER, "max", c) == (ContactStatus.MAXITER, "max")


# 2D frictional states: (t_N, t_T, du_T) at two points, mu = 0.5
_STICK = dict(p=[1.0, 0.8], tT=[[0.3], [-0.1]], du=[[0.0], [0.0]])
_SLIP = dict(p=[1.0, 0.8], tT=[[0.5], [-0.4]], du=[[0.02], [-0.3 * H]])


@pytest.mark.parametrize("state", [_STICK, _SLIP])
def test_coulomb_states_pass(state):
    c = _check([0.0, 0.0], state["p"], traction_t=state["tT"], slip=state["du"], mu=0.5)
    assert c.ok, c.failed


@pytest.mark.parametrize("tT, du, measure", [
    ([[0.6], [-0.1]], [[0.0], [0.0]], "coulomb"),  # |t_T| = 0.6 > mu t_N = 0.5
    ([[0.3], [-0.1]], [[0.01], [0.0]], "slip"),  # slips although |t_T| < mu t_N
    ([[-0.5], [-0.4]], [[0.01], [-0.03]], "slip"),  # saturated but t_T against the slip (force along it)
])
def test_wrong_friction_state_flips_status(tT, du, measure):
    c = _check([0.0, 0.0], [1.0, 0.8], traction_t=tT, slip=du, mu=0.5)
    assert set(c.failed) == {measure}
    status, msg = verified_status(ContactStatus.CONVERGED, "converged", c)
    assert status == ContactStatus.NOT_VERIFIED and measure in msg


def _fake_frictionless(dc, opts, eps0, penalty_name):
    """An 'algorithm' that claims convergence with zero pressure (the body penetrates)."""
    r = dc.start()
    return _algorithms._Run(r, np.zeros(dc.cand.size), dc.gaps(r), ContactStatus.CONVERGED, "converged", 1, 1,
                            eps0, 0.0, [])


def test_solve_does_not_report_a_wrong_state_as_converged(monkeypatch, caplog):
    fake = _algorithms.Algorithm("fake", _fake_frictionless, "wrong on purpose")
    monkeypatch.setitem(_algorithms._REGISTRY, fake.key, fake)
    with caplog.at_level(logging.WARNING):
        sol = solve(hertz.hertz_2d(0, n_per_a=4), "fake")
    assert sol.status == ContactStatus.NOT_VERIFIED
    assert "penetration" in sol.result.message
    assert any("verification" in r.getMessage() for r in caplog.records)


def _fake_step(ctx, penalty_name):
    """A frictional step that claims convergence with no contact forces."""
    zero = np.zeros((ctx.c, ctx.d))
    return _friction._StepOut(True, "converged", zero, zero, 1, 1)


def test_solve_friction_does_not_report_a_wrong_state_as_converged(monkeypatch):
    fake = _algorithms.Algorithm("fake", _fake_step, "wrong on purpose", friction=True, penalty="rockafellar")
    monkeypatch.setitem(_algorithms._REGISTRY, fake.key, fake)
    prob, hist = fp.block_on_plane(dim=2, n=4)
    sol = solve_friction(prob, hist.with_times((0.25, 0.5)), "fake")
    assert sol.status == ContactStatus.NOT_VERIFIED and not sol.success
    # a step that fails verification is cut back, never accepted: no step, the failure names the measure
    assert len(sol.steps) == 0 and sol.cutbacks > 0
    assert "penetration" in sol.message and "fails verification" in sol.message
