"""Property-based checks (Hypothesis) of Definitions 5.2 and 5.3.

Generated from the registry: every registered penalty is checked for each
property it claims (``p.properties``; all of them when ``p.family_p``), and
every registered generator θ for each of (a)-(e) it claims.  A user generator
and a user penalty are registered for the duration of their cases only.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from _helpers import USER_PENALTIES, user_penalties
from alcontact import penalties as P

SETTINGS = settings(max_examples=60, deadline=None, derandomize=True)
MU = st.floats(0.05, 20.0)
U = st.floats(1e-4, 30.0)  # distance into the domain, in units of max(1, |b|)


def _frac() -> P.Theta:
    return P.Theta("frac", lambda y: y / (1 - y), lambda y: (1 - y) ** -2.0, lambda y: 2 * (1 - y) ** -3.0, upper=1.0)


USER = USER_PENALTIES
ALL = sorted(P.available()) + list(USER)
THETAS = sorted(P.thetas()) + ["frac"]


@contextlib.contextmanager
def registered(name: str) -> Iterator[None]:
    """Register the user extensions when ``name`` needs them; always clean up."""
    if name not in USER and name != "frac":
        yield
        return
    with user_penalties(_frac()):
        yield


def claims(p: P.Penalty, label: str) -> bool:
    return p.family_p or label in p.properties


def inside(b: float, u: float) -> float:
    """A point at distance ``u * max(1, |b|)`` left of ``b`` (or in [-30, 30] when b = inf)."""
    if math.isfinite(b):
        return b - max(1.0, abs(b)) * u
    return 30.0 - 2.0 * u


def _run(name: str, label: str, check) -> None:
    with registered(name):
        p = P.make(name)
        if not claims(p, label):
            pytest.skip(f"{name} does not claim {label}")
        check(p)


@pytest.mark.parametrize("name", ALL)
def test_p1_vanishes_at_origin(name):
    @SETTINGS
    @given(mu=MU)
    def check(p, mu):
        assert abs(float(p.value(0.0, mu))) <= 1e-12

    _run(name, "P1", lambda p: check(p))


@pytest.mark.parametrize("name", ALL)
def test_p2_strictly_convex(name):
    @SETTINGS
    @given(mu=MU, u1=U, u2=U, t=st.floats(0.01, 0.99))
    def check(p, mu, u1, u2, t):
        b = float(p.domain_upper(mu))
        y1, y2 = sorted((inside(b, u1), inside(b, u2)))
        assume(y2 - y1 > 1e-6 * (1.0 + abs(y1) + abs(y2)))
        d1, d2 = float(p.derivative(y1, mu)), float(p.derivative(y2, mu))
        assert d1 < d2  # derivative strictly increasing
        ym = t * y1 + (1 - t) * y2
        p1, p2, pm = (float(p.value(y, mu)) for y in (y1, y2, ym))
        assert pm <= t * p1 + (1 - t) * p2 + 1e-9 * (1 + abs(p1) + abs(p2))
        assert float(p.second_derivative(ym, mu)) >= 0.0

    _run(name, "P2", lambda p: check(p))


@pytest.mark.parametrize("name", ALL)
def test_p3_slope_is_multiplier(name):
    @SETTINGS
    @given(mu=MU)
    def check(p, mu):
        assert float(p.derivative(0.0, mu)) == pytest.approx(mu, rel=1e-12)

    _run(name, "P3", lambda p: check(p))


@pytest.mark.parametrize("name", ALL)
def test_p4_coercive_at_b(name):
    @SETTINGS
    @given(mu=MU, big=st.floats(1.0, 1e6))
    def check(p, mu, big):
        b = float(p.domain_upper(mu))
        k = np.arange(1, 13, dtype=float)
        ys = b - max(1.0, abs(b)) * 10.0**-k if math.isfinite(b) else 10.0**k
        d = np.asarray(p.derivative(ys, mu))
        assert np.all(d[1:] >= d[:-1])
        assert d[-1] > big  # eventually exceeds any bound

    _run(name, "P4", lambda p: check(p))


@pytest.mark.parametrize("name", ALL)
def test_p5_vanishing_slope_at_minus_infinity(name):
    @SETTINGS
    @given(mu=MU, eps=st.floats(1e-6, 1.0))
    def check(p, mu, eps):
        d = np.abs(np.asarray(p.derivative(-(10.0 ** np.arange(2, 13, dtype=float)), mu)))
        assert np.all(d[1:] <= d[:-1] + 1e-300)
        assert d[-1] < eps

    _run(name, "P5", lambda p: check(p))


@pytest.mark.parametrize("name", ALL)
def test_family_p_multiplier_estimate_nonnegative(name):
    """(P2)+(P5) give p' >= 0: the update mu <- p'(g/eta, mu) keeps (C3)."""

    @SETTINGS
    @given(mu=MU, u=U)
    def check(p, mu, u):
        b = float(p.domain_upper(mu))
        assert float(p.derivative(inside(b, u), mu)) >= 0.0

    with registered(name):
        p = P.make(name)
        if not {"P2", "P5"} <= set(p.properties):
            pytest.skip(f"{name} does not claim (P2) and (P5)")
        check(p)


@pytest.mark.parametrize("name", ALL)
def test_vectorized_equals_scalar(name):
    @SETTINGS
    @given(mu=st.lists(MU, min_size=1, max_size=5), u=st.lists(U, min_size=1, max_size=4))
    def check(p, mu, u):
        mu_a = np.array(mu)
        b = np.asarray(p.domain_upper(mu_a))
        y = np.array([[inside(float(np.min(b)), ui)] for ui in u])
        for method in (p.value, p.derivative, p.second_derivative):
            out = method(y, mu_a)
            assert out.shape == (len(u), len(mu))
            for i in range(len(u)):
                for j in range(len(mu)):
                    # equal up to rounding (SIMD array kernels may differ by an ulp)
                    assert out[i, j] == pytest.approx(float(method(y[i, 0], mu_a[j])), rel=1e-13, abs=1e-300)

    with registered(name):
        check(P.make(name))


@pytest.mark.parametrize("name", THETAS)
def test_generator_properties(name):
    @SETTINGS
    @given(u1=U, u2=U)
    def check(th, u1, u2):
        b = float(th.upper)
        y1, y2 = sorted((inside(b, u1), inside(b, u2)))
        assume(y2 - y1 > 1e-6 * (1.0 + abs(y1) + abs(y2)))
        if "a" in th.satisfies:
            assert b > 0 and np.isfinite(th.value(y1)) and np.isfinite(th.value(y2))
        if "b" in th.satisfies:
            assert float(th.derivative(y1)) < float(th.derivative(y2))

    with registered(name):
        th = P.theta(name)
        if "e" in th.satisfies:
            assert float(th.value(0.0)) == 0.0 and float(th.derivative(0.0)) == pytest.approx(1.0, rel=1e-14)
        b = float(th.upper)
        if "c" in th.satisfies:
            ys = b - max(1.0, abs(b)) * 10.0 ** -np.arange(1, 13.0) if math.isfinite(b) else 10.0 ** np.arange(1, 13.0)
            assert float(th.derivative(ys[-1])) > 1e6
        if "d" in th.satisfies:
            assert abs(float(th.derivative(-1e12))) < 1e-6
        else:
            assert float(th.derivative(-1e12)) < -1e6  # the built-in violator (quad) goes to -inf
        check(th)


def test_user_registration_cleans_up():
    with registered("frac-met1"):
        assert "frac-met1" in P.available() and "frac" in P.thetas()
    assert "frac-met1" not in P.available() and "frac" not in P.thetas()
    assert "user-softplus" not in P.available()
