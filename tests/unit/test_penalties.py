"""Unit tests of alcontact.penalties, generated from the registry.

Every registered penalty (and every registered generator θ) is checked against
finite differences, and its declared properties (P1)-(P5) / (a)-(e) are checked
numerically in *both* directions: a claimed property must hold and an
unclaimed one must fail on the probe grid, so the declared facts are exact.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Iterator

import numpy as np
import pytest

from _helpers import USER_PENALTIES, user_penalties
from alcontact import errors
from alcontact import penalties as P

MUS = (0.3, 1.0, 4.0)
REQUIRED = {
    "exp-met1", "exp-met2", "log-met1", "log-met2", "quad-met1", "quad-met2", "rockafellar",
    "hestenes-powell", "exterior-quadratic", "log-barrier", "inverse-barrier",
}  # fmt: skip
EXPECTED_PROPERTIES = {
    "exp-met1": set(P.PROPERTY_LABELS),
    "exp-met2": set(P.PROPERTY_LABELS),
    "log-met1": set(P.PROPERTY_LABELS),
    "log-met2": set(P.PROPERTY_LABELS),
    "quad-met1": {"P1", "P2", "P3", "P4"},
    "quad-met2": {"P1", "P2", "P3", "P4"},
    "rockafellar": {"P1", "P3", "P4", "P5"},
    "hestenes-powell": {"P1", "P2", "P3", "P4"},
    "exterior-quadratic": {"P1", "P4", "P5"},
    "log-barrier": {"P2", "P4", "P5"},
    "inverse-barrier": {"P2", "P4", "P5"},
}


# -- user extensions, registered only while a test uses them ---------------
def frac_theta() -> P.Theta:
    """θ(y) = y / (1 - y): satisfies (a)-(e) with b = 1."""
    return P.Theta(
        "frac",
        lambda y: y / (1.0 - y),
        lambda y: 1.0 / (1.0 - y) ** 2,
        lambda y: 2.0 / (1.0 - y) ** 3,
        upper=1.0,
        doc="user generator y/(1-y)",
    )


@pytest.fixture
def user_registrations() -> Iterator[None]:
    with user_penalties(frac_theta()):
        yield


ALL = sorted(P.available()) + list(USER_PENALTIES)


@pytest.fixture(params=ALL)
def penalty(request: pytest.FixtureRequest) -> Iterator[P.Penalty]:
    """Every registered penalty plus the user-registered ones (cleaned up after)."""
    if request.param in USER_PENALTIES:
        request.getfixturevalue("user_registrations")
    yield P.make(request.param)


# -- numerical probes ------------------------------------------------------
U = np.array([1e-6, 1e-3, 0.05, 0.3, 1.0, 2.0, 5.0, 13.0, 30.0])


def scale_of(b: float) -> float:
    return max(1.0, abs(b)) if math.isfinite(b) else 1.0


def probe_grid(b: float) -> np.ndarray:
    """Increasing points inside (-inf, b), moderate enough to avoid under/overflow."""
    if math.isfinite(b):
        return np.sort(b - scale_of(b) * U)
    return np.concatenate([-U[::-1], [0.0], U])


def towards_b(b: float) -> np.ndarray:
    k = np.arange(1, 11, dtype=float)
    return b - scale_of(b) * 10.0**-k if math.isfinite(b) else 10.0**k


def fd_points(p: P.Penalty, mu: float) -> np.ndarray:
    b = float(p.domain_upper(mu))
    if math.isfinite(b):
        ys = b - scale_of(b) * np.array([0.07, 0.3, 1.0, 2.5, 6.0])
    else:
        ys = np.array([-2.5, -1.3, -0.4, 0.0, 0.35, 1.1, 2.2])
    kinks = [float(k) for k in getattr(p, "kinks", lambda mu: ())(mu)]
    return np.array([y for y in ys if all(abs(y - k) > 0.05 for k in kinks)])


def penalty_verdicts(p: P.Penalty, mu: float) -> set[str]:
    """Labels among (P1)-(P5) that hold numerically for this mu."""
    b = float(p.domain_upper(mu))
    held = set()
    p0, d0 = float(p.value(0.0, mu)), float(p.derivative(0.0, mu))
    if math.isfinite(p0) and abs(p0) <= 1e-12:
        held.add("P1")
    d = np.asarray(p.derivative(probe_grid(b), mu))
    if np.all(np.isfinite(d)) and np.all(np.diff(d) > 0):
        held.add("P2")
    if math.isfinite(d0) and abs(d0 - mu) <= 1e-12 * (1 + mu):
        held.add("P3")
    d4 = np.asarray(p.derivative(towards_b(b), mu))
    if np.all(d4[1:] >= d4[:-1]) and d4[-1] > 1e6:
        held.add("P4")
    d5 = np.asarray(p.derivative(np.array([-1e8, -1e10]), mu))
    if np.all(np.abs(d5) < 1e-6):
        held.add("P5")
    return held


def generator_verdicts(th: P.Generator) -> set[str]:
    """Labels among (a)-(e) of Definition 5.3 that hold numerically."""
    b = float(th.upper)
    grid = probe_grid(b)
    held = set()
    outside_inf = (not math.isfinite(b)) or np.all(np.isinf(th.value(np.array([b, b + 1.0]))))
    if b > 0 and np.all(np.isfinite(th.value(grid))) and outside_inf:
        held.add("a")
    d = np.asarray(th.derivative(grid))
    if np.all(np.isfinite(d)) and np.all(np.diff(d) > 0):
        held.add("b")
    dc = np.asarray(th.derivative(towards_b(b)))
    if np.all(dc[1:] >= dc[:-1]) and dc[-1] > 1e6:
        held.add("c")
    if np.all(np.abs(np.asarray(th.derivative(np.array([-1e8, -1e10])))) < 1e-6):
        held.add("d")
    if float(th.value(0.0)) == 0.0 and abs(float(th.derivative(0.0)) - 1.0) <= 1e-14:
        held.add("e")
    return held


def central(f, y: np.ndarray, mu: float) -> np.ndarray:
    h = 1e-6 * np.maximum(1.0, np.abs(y))
    return (np.asarray(f(y + h, mu)) - np.asarray(f(y - h, mu))) / (2 * h)


def check_finite_differences(p: P.Penalty) -> None:
    for mu in MUS:
        y = fd_points(p, mu)
        assert y.size >= 3
        np.testing.assert_allclose(central(p.value, y, mu), p.derivative(y, mu), rtol=1e-6, atol=1e-8)
        np.testing.assert_allclose(central(p.derivative, y, mu), p.second_derivative(y, mu), rtol=1e-6, atol=1e-8)


def check_claims_exact(p: P.Penalty) -> None:
    for mu in MUS:
        assert penalty_verdicts(p, mu) == set(p.properties), (p.name, mu)
    assert p.family_p == (set(p.properties) == set(P.PROPERTY_LABELS))


# -- generated tests over the registry -------------------------------------
def test_required_names_registered():
    assert REQUIRED <= set(P.available())
    assert P.available() == sorted(P.available())
    assert {"exp", "log", "quad"} <= set(P.thetas())


@pytest.mark.parametrize("name", sorted(EXPECTED_PROPERTIES))
def test_builtin_claims(name):
    p = P.make(name)
    assert set(p.properties) == EXPECTED_PROPERTIES[name]
    assert p.family_p is (name in {"exp-met1", "exp-met2", "log-met1", "log-met2"})


def test_finite_differences(penalty):
    check_finite_differences(penalty)


def test_declared_properties_are_exact(penalty):
    check_claims_exact(penalty)


def test_metadata(penalty):
    assert penalty.name in P.available()
    assert isinstance(penalty.doc, str) and penalty.doc and "\n" not in penalty.doc
    assert type(penalty).__doc__
    assert isinstance(penalty.family_p, bool)
    assert set(penalty.properties) <= set(P.PROPERTY_LABELS)
    assert isinstance(penalty, P.Penalty)
    assert P.describe()[penalty.name]
    assert penalty.twice_differentiable == (len(penalty.kinks(1.0)) == 0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        penalty.name = "other"  # type: ignore[misc]


def test_vectorized_broadcasting(penalty):
    mu = np.array([0.3, 1.0, 2.0, 4.0])
    b = np.asarray(penalty.domain_upper(mu))
    y = np.minimum(np.array([[-2.0], [-0.3], [0.1]]), b - 0.2)  # shape (3, 4), inside
    for method in (penalty.value, penalty.derivative, penalty.second_derivative):
        out = method(y, mu)
        assert out.shape == (3, 4) and out.dtype == np.float64
        scalar = [[float(method(y[i, j], mu[j])) for j in range(4)] for i in range(3)]
        np.testing.assert_allclose(out, scalar, rtol=1e-13)
    s = penalty.value(-0.5, 1.0)
    assert np.ndim(s) == 0 and isinstance(s, np.floating)


def test_outside_domain_is_inf_without_warning(penalty):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for mu in (0.5, 2.0):
            b = float(penalty.domain_upper(mu))
            ys = np.array([b, b + 0.5, 10 * abs(b) + 1e3, np.inf]) if math.isfinite(b) else np.array([np.inf])
            for method in (penalty.value, penalty.derivative, penalty.second_derivative):
                out = np.asarray(method(ys, mu))
                assert np.all(out == np.inf), (penalty.name, method.__name__, out)
            # far inside: no overflow warning either (the value may be inf)
            far = np.array([-1e300, -1e6, 0.0, min(1e6, b / 2) if math.isfinite(b) else 1e6])
            for method in (penalty.value, penalty.derivative, penalty.second_derivative):
                out = np.asarray(method(far, mu))
                assert not np.any(np.isnan(out)), (penalty.name, method.__name__, out)


# -- generators θ ----------------------------------------------------------
@pytest.mark.parametrize("name", P.thetas())
def test_generator_claims_exact(name):
    th = P.theta(name)
    assert generator_verdicts(th) == set(th.satisfies)
    assert set(th.satisfies) <= set(P.GENERATOR_LABELS)


@pytest.mark.parametrize("name", P.thetas())
def test_generator_finite_differences(name):
    th = P.theta(name)
    b = float(th.upper)
    y = b - scale_of(b) * np.array([0.07, 0.3, 1.0, 2.5]) if math.isfinite(b) else np.array([-2.0, -0.3, 0.0, 0.4, 1.7])
    h = 1e-6 * np.maximum(1.0, np.abs(y))
    np.testing.assert_allclose((th.value(y + h) - th.value(y - h)) / (2 * h), th.derivative(y), rtol=1e-6)
    np.testing.assert_allclose((th.derivative(y + h) - th.derivative(y - h)) / (2 * h), th.second_derivative(y), rtol=1e-6)


def test_builtin_generators():
    assert P.theta("exp").upper == math.inf and P.theta("exp").satisfies_d
    assert P.theta("log").upper == 1.0
    np.testing.assert_allclose(P.theta("exp").value(0.5), math.exp(0.5) - 1)  # (5.21)
    np.testing.assert_allclose(P.theta("log").value(0.5), -math.log(0.5))  # (5.22)
    np.testing.assert_allclose(P.theta("quad").value(3.0), 7.5)  # (5.27)


def test_quad_violates_d():
    q = P.theta("quad")
    assert not q.satisfies_d and not q.is_generator
    assert "d" not in generator_verdicts(q)
    d = np.asarray(q.derivative(np.array([-1e2, -1e4, -1e8])))
    assert np.all(np.diff(d) < 0) and d[-1] < -1e7  # θ' -> -inf


def test_quad_met2_multipliers_turn_negative():
    p = P.make("quad-met2")
    for mu in (0.5, 1.0, 3.0):
        assert p.derivative(-2.0 / mu, mu) < 0  # p' = mu (mu y + 1) < 0 for y < -1/mu
        assert p.derivative(-0.5 / mu, mu) > 0
    for name in ("exp-met2", "log-met2"):  # family P: p' > 0 everywhere
        assert np.all(np.asarray(P.make(name).derivative(np.linspace(-50, 0, 11), 1.0)) > 0)


# -- formulas and the (5.28) conventions ----------------------------------
def test_met_formulas():
    y, mu = np.linspace(-3, 0.4, 9), 2.0
    np.testing.assert_allclose(P.make("exp-met1").value(y, mu), mu * (np.exp(y) - 1))  # (5.24)
    np.testing.assert_allclose(P.make("exp-met2").value(y, mu), np.exp(mu * y) - 1)
    np.testing.assert_allclose(P.make("log-met1").value(y, mu), -mu * np.log(1 - y))
    np.testing.assert_allclose(P.make("log-met2").value(y, mu), -np.log(1 - mu * y))  # (5.26)
    np.testing.assert_allclose(P.make("quad-met2").value(y, mu), (mu * y) ** 2 / 2 + mu * y)
    np.testing.assert_allclose(P.make("log-met2").domain_upper(np.array([0.5, 4.0])), [2.0, 0.25])
    assert P.make("log-met2").domain_upper(0.0) == math.inf


def test_classical_conventions():
    eta = 0.25
    g = np.array([-3.0, -0.2, 0.0, 0.7])
    mu = np.array([0.5, 1.0, 2.0, 0.1])
    r = P.make("rockafellar")
    # (5.18)/(5.19) with eta_R = 1/(2 eta): eta_R g^2 + mu g if g >= -mu/(2 eta_R), else -mu^2/(4 eta_R)
    eta_r = 1 / (2 * eta)
    expected = np.where(g >= -mu / (2 * eta_r), eta_r * g**2 + mu * g, -(mu**2) / (4 * eta_r))
    np.testing.assert_allclose(eta * r.value(g / eta, mu), expected)
    np.testing.assert_allclose(r.derivative(g / eta, mu), np.maximum(0, mu + g / eta))
    hp = P.make("hestenes-powell")  # (5.13), (5.15) with rho = 1/eta
    np.testing.assert_allclose(eta * hp.value(g / eta, mu), mu * g + g**2 / (2 * eta))
    np.testing.assert_allclose(hp.derivative(g / eta, mu), mu + g / eta)
    ex = P.make("exterior-quadratic")  # (5.9) with t = 1/eta
    np.testing.assert_allclose(eta * ex.value(g / eta, mu), np.maximum(0, g) ** 2 / eta)
    neg = np.array([-3.0, -0.2])
    np.testing.assert_allclose(eta * P.make("log-barrier").value(neg / eta, 1.0), -eta * np.log(-neg) + eta * np.log(eta))
    np.testing.assert_allclose(eta * P.make("inverse-barrier").value(neg / eta, 1.0), -(eta**2) / neg)
    assert P.make("log-barrier").domain_upper(1.0) == 0.0


def test_met2_negative_mu_with_finite_bound_raises():
    with pytest.raises(errors.DomainError, match="mu"):
        P.make("log-met2").value(0.1, -1.0)
    assert np.isfinite(P.make("exp-met2").value(0.1, -1.0))  # b = inf: no bound to flip


def test_met1_zero_multiplier_gives_zero_not_nan():
    p = P.make("exp-met1")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert p.value(1e4, 0.0) == 0.0 and p.derivative(1e4, 0.0) == 0.0


# -- registry --------------------------------------------------------------
def test_unknown_name_lists_known():
    with pytest.raises(errors.UnknownNameError) as info:
        P.make("exp-met3")
    msg = str(info.value)
    assert all(n in msg for n in P.available()) and "exp-met1" in msg
    assert info.value.known == P.available()
    with pytest.raises(errors.UnknownNameError, match="exp"):
        P.theta("expo")


def test_make_rejects_unknown_params():
    with pytest.raises(errors.InputError, match="rockafellar"):
        P.make("rockafellar", eta=2.0)


def test_register_rejects_duplicates_and_bad_input():
    with pytest.raises(errors.InputError, match="already registered"):
        P.register("exp-met1", P.Rockafellar, doc="x")
    with pytest.raises(errors.InputError, match="callable"):
        P.register("not-callable", 3, doc="x")  # type: ignore[arg-type]
    with pytest.raises(errors.InputError, match="already registered"):
        P.register_theta("exp", P.theta("exp"))
    with pytest.raises(errors.InputError, match="lacks"):
        P.register_theta("bad", object())  # type: ignore[arg-type]
    assert "not-callable" not in P.available() and "bad" not in P.thetas()


def test_user_registration_is_picked_up_and_cleaned(user_registrations):
    names = set(P.available())
    assert {"frac-met1", "frac-met2", "user-softplus"} <= names
    assert P.theta("frac").upper == 1.0
    assert P.make("frac-met2").family_p and P.make("frac-met1").family_p
    assert not P.make("user-softplus").family_p
    assert float(P.make("frac-met2").domain_upper(4.0)) == 0.25
    for name in ("frac-met1", "frac-met2", "user-softplus"):
        check_finite_differences(P.make(name))
        check_claims_exact(P.make(name))
    assert generator_verdicts(P.theta("frac")) == set(P.GENERATOR_LABELS)


def test_unregister_cleans():
    P.register_theta("tmp", frac_theta())
    P.unregister_theta("tmp")
    assert "tmp-met1" not in P.available() and "tmp" not in P.thetas()
    with pytest.raises(errors.UnknownNameError):
        P.unregister("tmp-met1")
