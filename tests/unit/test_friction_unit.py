"""Unit tests of the frictional contact pieces: return mapping, tangents, load history, errors.

Reaches inside the package: unit tests of the private Coulomb pieces (return mapping, tangents) of
``contact.algorithms._coulomb``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from alcontact.contact import ContactStatus, Support
from alcontact.contact.algorithms import find_algorithm, register
from alcontact.contact.algorithms import FrictionOptions, friction_algorithms
from alcontact.contact import solve_friction
from alcontact.contact.kinematics import tangent_bases
from alcontact.contact.laws import OPEN, SLIP, STICK, Macaulay, local_law, tangential_energy
from alcontact.contact.problem import LoadCase, LoadHistory, Ramp
from alcontact.errors import ConvergenceError, InputError, UnknownNameError
from alcontact.problems import friction as fp


def _fd(fun, x, h=1e-7):
    cols = []
    for j in range(x.size):
        e = np.zeros_like(x)
        e.flat[j] = h
        cols.append((fun(x + e) - fun(x - e)) / (2 * h))
    return np.stack(cols, axis=-1)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("case", ["stick", "slip", "open"])
def test_local_law_tangent_matches_finite_differences(d, case):
    rng = np.random.default_rng(3 + d)
    law = Macaulay(50.0)
    lamN = np.array([1.0])
    lamT = rng.normal(size=(1, d - 1)) * 0.05
    uTn = np.zeros((1, d - 1))
    du = {"stick": 1e-4, "slip": 0.05, "open": 0.05}[case]
    g = {"stick": 0.01, "slip": 0.01, "open": -1.0}[case]
    y = np.concatenate([[g], rng.normal(size=d - 1) * du])[None]
    mu, eps_t = 0.3, 40.0
    t, Dy, Dl, st = local_law(law, lamN, lamT, y, uTn, eps_t, mu, with_lam=True)
    assert st[0] == {"stick": STICK, "slip": SLIP, "open": OPEN}[case]
    fy = lambda v: local_law(law, lamN, lamT, v.reshape(1, d), uTn, eps_t, mu)[0].ravel()  # noqa: E731
    np.testing.assert_allclose(Dy[0], _fd(fy, y.ravel()), atol=1e-5)
    lam = np.concatenate([lamN, lamT[0]])
    fl = lambda v: local_law(law, v[:1], v[None, 1:], y, uTn, eps_t, mu)[0].ravel()  # noqa: E731
    np.testing.assert_allclose(Dl[0], _fd(fl, lam), atol=1e-5)
    if case == "slip":  # returned onto the Coulomb circle (corrected 6.49)
        assert np.linalg.norm(t[0, 1:]) == pytest.approx(mu * t[0, 0])


def test_zero_trial_with_zero_radius_is_safe():
    law = Macaulay(1.0)
    t, Dy, _, st = local_law(law, np.zeros(2), np.zeros((2, 1)), np.array([[-1.0, 0.0], [0.0, 0.0]]),
                             np.zeros((2, 1)), 10.0, 0.5)
    assert np.all(np.isfinite(t)) and np.all(np.isfinite(Dy))
    assert np.all(st == OPEN) and np.all(t == 0)


def test_tangential_energy_gradient_is_projected_traction():
    rng = np.random.default_rng(0)
    lamT, uTn = rng.normal(size=(4, 2)), np.zeros((4, 2))
    rho = np.array([0.1, 5.0, 0.0, 1.0])
    uT = rng.normal(size=(4, 2)) * 0.1
    grad = _fd(lambda v: tangential_energy(lamT, v.reshape(4, 2), uTn, 10.0, rho).sum(), uT.ravel()).reshape(4, 2)
    t = local_law(Macaulay(1.0), np.ones(4), lamT, np.concatenate([np.zeros((4, 1)), uT], 1), uTn, 10.0, 1.0,
                  rho=rho)[0][:, 1:]
    np.testing.assert_allclose(grad, t, atol=1e-6)


@pytest.mark.parametrize("d", [2, 3])
def test_tangent_bases_orthonormal(d):
    rng = np.random.default_rng(1)
    nu = rng.normal(size=(20, d)) * 0.1
    nu[:, -1] -= 1.0
    nu /= np.linalg.norm(nu, axis=1, keepdims=True)
    T = tangent_bases(nu)
    assert T.shape == (20, d, d - 1)
    np.testing.assert_allclose(np.einsum("ij,ijk->ik", nu, T), 0.0, atol=1e-14)
    np.testing.assert_allclose(np.einsum("ijk,ijl->ikl", T, T), np.broadcast_to(np.eye(d - 1), (20, d - 1, d - 1)),
                               atol=1e-14)


def test_ramp_and_history_errors():
    r = Ramp((0.0, 0.5), (0.0, 1.0))
    assert r(0.25) == pytest.approx(0.5)
    with pytest.raises(InputError, match="not defined at t=0.75"):
        r(0.75)
    case = LoadCase(Support("top", components=(1,), value=-1e-3), r, name="push")
    with pytest.raises(InputError, match="not defined at step 2"):
        LoadHistory((case,), (0.5, 1.0))
    with pytest.raises(InputError, match="increasing"):
        LoadHistory((case,), (0.5, 0.25))
    with pytest.raises(InputError, match="not finite"):
        LoadHistory((LoadCase(case.item, lambda t: float("nan")),), (0.5,))
    with pytest.raises(InputError):
        Ramp((0.0, 0.0), (1.0, 2.0))
    with pytest.raises(InputError):
        LoadCase("top", r)


def test_tangential_load_before_contact_is_an_error():
    prob, hist = fp.block_on_plane(dim=2, n=4)
    early = LoadCase(hist.cases[1].item, Ramp((0.0, 1.0), (0.0, 1.0)), tangential=True, name="early shear")
    bad = LoadHistory((hist.cases[0], early), hist.times)
    with pytest.raises(InputError, match="early shear.*no point is in contact"):
        solve_friction(prob, bad)


def test_input_errors():
    prob, hist = fp.block_on_plane(dim=2, n=4)
    with pytest.raises(InputError, match="friction coefficient"):
        solve_friction(prob, hist, friction=-0.1)
    with pytest.raises(UnknownNameError):
        solve_friction(prob, hist, algorithm="simo-laursn")
    with pytest.raises(InputError, match="unknown friction option"):
        solve_friction(prob, hist, tol_penetraton=1e-6)
    with pytest.raises(InputError, match="uses the 'rockafellar' penalty"):
        solve_friction(prob, hist, algorithm="simo-laursen", penalty="exp-met1")
    with pytest.raises(InputError, match="cutback_factor"):
        FrictionOptions(cutback_factor=1.5).validate()
    assert set(friction_algorithms()) == {"family-p", "simo-laursen", "ssn", "log-barrier"}


def test_failed_step_is_cut_back_then_reported():
    prob, hist = fp.block_on_plane(dim=2, n=4, shear_ratio=3.0)
    sol = solve_friction(prob, hist, maxiter=1, max_cutbacks=2)
    assert sol.status < 0
    assert sol.cutbacks == 3
    assert "cut-backs" in sol.message
    with pytest.raises(ConvergenceError):
        sol.raise_for_status()


def test_cut_back_recovers_and_keeps_steps():
    import alcontact.contact.algorithms._coulomb as F

    entry = find_algorithm("simo-laursen", friction=True)
    real = entry.run
    calls = {"n": 0}

    def flaky(ctx, pen):  # the first two attempts of the shearing phase fail
        if calls["n"] < 2 and np.max(np.abs(ctx.yf[:, 1:] - ctx.uTn)) > 1e-12:
            calls["n"] += 1
            return F._StepOut(False, "injected failure", ctx.R0, ctx.R0, 1, 0, ContactStatus.NEWTON_FAILED)
        return real(ctx, pen)

    register(dataclasses.replace(entry, run=flaky))  # a failing stand-in through the public registry
    try:
        prob, hist = fp.block_on_plane(dim=2, n=4, shear_ratio=3.0)
        sol = solve_friction(prob, hist, steps=(0.5, 1.0), max_cutbacks=4)
    finally:
        register(entry)
    assert find_algorithm("simo-laursen", friction=True) is entry
    assert sol.success, sol.message
    assert calls["n"] == 2 and sol.cutbacks == 2
    assert [s.t for s in sol.requested_steps] == [0.5, 1.0]
    # two halvings of the increment 0.5 -> 1.0: converged sub-steps at 0.625 and 0.75 are kept
    np.testing.assert_allclose(sol.times, [0.5, 0.625, 0.75, 1.0])
    assert sol.final.cutbacks == 2


def test_steps_override_and_counters():
    prob, hist = fp.block_on_plane(dim=2, n=4)
    sol = solve_friction(prob, hist, steps=4, algorithm="family-p")
    assert sol.success
    assert len(sol.steps) == 4 and sol.times[-1] == 1.0
    assert sol.newton_iterations > 0 and sol.outer_iterations > 0
    assert sol.normal_forces.shape == (4,) and sol.tangential_forces.shape == (4, 2)
