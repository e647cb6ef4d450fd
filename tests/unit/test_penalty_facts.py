"""Declared penalty facts checked against the penalties' numerical behaviour.

Generated from the registry (plus user registrations), so a new penalty is covered
automatically: each fact an algorithm branches on (``needs_multiplier_safeguard``,
``freezes_at_zero``, ``equality_only``, ``usable_for_contact``, kinks, ``eta_min``,
``minimizer``) must agree with what ``p``, ``p'`` and ``p''`` do on a probe grid, and
the one Matioli safeguard (:func:`alcontact.penalties.safeguarded`) must give
``p' >= 0`` while leaving ``p`` unchanged right of its minimizer.

Reaches inside the package: ``optim._safeguards``, ``optim._minimize`` and ``optim._outer``: each
fact is checked against the internal branch that reads it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
from scipy.optimize import NonlinearConstraint

from alcontact import errors
from alcontact import penalties as P
from alcontact.contact import contact_penalties
from alcontact.contact.laws import freezes_at_zero, make_law
from alcontact.optim import Options, Status, minimize
from alcontact.optim._safeguards import safeguard_penalty

MUS = (0.3, 1.0, 4.0)


# -- user penalties ----------------------------------------------------------
@dataclass(frozen=True)
class ShiftedQuad(P.PenaltyBase):
    """User MET-1-like penalty p = mu (y^2/2 + y) declaring its facts itself."""

    name: str = "user-shifted-quad"
    doc: str = "user quadratic mu*(y^2/2 + y)"
    properties: ClassVar[frozenset[str]] = frozenset({"P1", "P2", "P3", "P4"})
    freezes_at_zero: ClassVar[bool] = True
    eta_min: ClassVar[float | None] = 1e-20

    def _p(self, y, mu):
        return mu * y * (0.5 * y + 1.0)

    def _dp(self, y, mu):
        return mu * (y + 1.0)

    def _d2p(self, y, mu):
        return mu * np.ones_like(y)


class PlainPenalty:
    """A protocol-only penalty (no PenaltyBase): p = mu (exp(y) - 1), declares nothing."""

    name = "user-plain-exp"
    doc = "protocol-only exponential MET 1"
    properties = frozenset({"P1", "P2", "P3", "P4", "P5"})
    family_p = True

    def value(self, y, mu):
        return np.asarray(mu, float) * np.expm1(np.asarray(y, float))

    def derivative(self, y, mu):
        return np.asarray(mu, float) * np.exp(np.asarray(y, float))

    def second_derivative(self, y, mu):
        return np.asarray(mu, float) * np.exp(np.asarray(y, float))

    def domain_upper(self, mu):
        return np.full(np.shape(mu), math.inf)[()]


USER = ("user-shifted-quad", "user-plain-exp")


@pytest.fixture
def user_penalties() -> Iterator[None]:
    P.register("user-shifted-quad", ShiftedQuad, doc=ShiftedQuad.doc)
    P.register("user-plain-exp", PlainPenalty, doc=PlainPenalty.doc)
    try:
        yield
    finally:
        P.unregister("user-shifted-quad")
        P.unregister("user-plain-exp")


@pytest.fixture(params=sorted(P.available()) + list(USER))
def penalty(request: pytest.FixtureRequest):
    if request.param in USER:
        request.getfixturevalue("user_penalties")
    return P.make(request.param)


def grid(pen, mu: float) -> np.ndarray:
    """Points inside the domain (-inf, b(mu)), from -40 up to near b."""
    b = float(pen.domain_upper(mu))
    top = b - 1e-3 * max(1.0, abs(b)) if math.isfinite(b) else 8.0
    return np.linspace(-40.0, top, 4001)


# -- facts against numbers ----------------------------------------------------
def test_facts_are_typed(penalty):
    f = P.facts(penalty)
    for name in ("family_p", "equality_only", "usable_for_contact", "freezes_at_zero",
                 "needs_multiplier_safeguard", "twice_differentiable"):
        assert isinstance(getattr(f, name), bool), name
    assert f.eta_min is None or 0.0 < f.eta_min < 1e-12
    assert f.properties == frozenset(penalty.properties)


def test_safeguard_fact_matches_sign_of_derivative(penalty):
    """needs_multiplier_safeguard <=> min p'(y, mu) < 0 on the grid (inequality penalties);
    an equality-only penalty has multipliers of both signs: p' < 0 somewhere."""
    f = P.facts(penalty)
    negative = any(float(np.min(penalty.derivative(grid(penalty, mu), mu))) < 0.0 for mu in MUS)
    if f.equality_only:
        assert negative and not f.needs_multiplier_safeguard and not f.usable_for_contact
    else:
        assert f.needs_multiplier_safeguard == negative


def test_freezes_fact_matches_derivative_at_zero_multiplier(penalty):
    """freezes_at_zero <=> p'(y, 0) == 0 for every y of the grid (inside b(0))."""
    y = grid(penalty, 0.0)
    with np.errstate(all="ignore"):
        d = np.asarray(penalty.derivative(y, np.zeros_like(y)), float)
    assert P.facts(penalty).freezes_at_zero == bool(np.all(d == 0.0))
    assert freezes_at_zero(penalty) == P.facts(penalty).freezes_at_zero


#: Facts of the built-ins from the dissertation: Hestenes-Powell (5.13) is for equalities,
#: MET 1 (5.23) / MET 2 (5.25) multipliers freeze at 0, Matioli's quadratic (5.27)
#: needs the safeguard, the inverse barrier (5.3) needs eta far below 1e-12.
BUILTIN_FACTS = {
    "hestenes-powell": {"equality_only": True},
    "quad-met1": {"needs_multiplier_safeguard": True, "freezes_at_zero": True},
    "quad-met2": {"needs_multiplier_safeguard": True, "freezes_at_zero": True},
    "exp-met1": {"freezes_at_zero": True}, "exp-met2": {"freezes_at_zero": True},
    "log-met1": {"freezes_at_zero": True, "eta0_factor": 0.1}, "log-met2": {"freezes_at_zero": True},
    "inverse-barrier": {"eta_min": 1e-24, "uses_multiplier": False},
    "log-barrier": {"uses_multiplier": False}, "exterior-quadratic": {"uses_multiplier": False},
}  # fmt: skip
DEFAULTS = {"equality_only": False, "needs_multiplier_safeguard": False, "freezes_at_zero": False,
            "eta_min": None, "uses_multiplier": True, "eta0_factor": 1.0}


@pytest.mark.parametrize("name", sorted(P.available()))
def test_builtin_facts(name):
    f = P.facts(P.make(name))
    for key, default in DEFAULTS.items():
        assert getattr(f, key) == BUILTIN_FACTS.get(name, {}).get(key, default), (name, key)


def test_uses_multiplier_and_domain_facts(penalty):
    """uses_multiplier <=> p(y, mu) changes with mu on the grid; bounded_domain <=> b(1) finite."""
    f = P.facts(penalty)
    y = grid(penalty, 4.0)  # the smallest domain of the MUS for MET 2
    changes = any(not np.array_equal(penalty.value(y, a), penalty.value(y, b)) for a, b in [(0.3, 1.0), (1.0, 4.0)])
    assert f.uses_multiplier == changes
    assert f.bounded_domain == math.isfinite(float(penalty.domain_upper(1.0)))


def test_optim_methods_take_penalties_by_their_facts(user_penalties):
    """Algorithm 5.4 takes the multiplier penalties for inequalities, 5.1 the barriers, 5.2 the
    exterior penalty, 5.3 Hestenes-Powell -- the former name lists, now derived from the facts
    (so user penalties are placed by what they declare)."""
    from alcontact.optim._minimize import _accepted
    from alcontact.optim._outer import METHODS

    expected = {
        "al": {"exp-met1", "exp-met2", "log-met1", "log-met2", "quad-met1", "quad-met2", "rockafellar",
               "user-shifted-quad", "user-plain-exp"},
        "barrier": {"log-barrier", "inverse-barrier"},
        "exterior-penalty": {"exterior-quadratic"},
        "hestenes-powell": {"hestenes-powell"},
    }
    for method, names in expected.items():
        assert set(_accepted(METHODS[method])) == names, method
    with pytest.raises(errors.InputError, match="allowed: inverse-barrier, log-barrier"):
        _barrier_run("exp-met1", None)


def test_usable_for_contact_fact():
    """contact_penalties() is exactly the registered penalties declaring the fact, which by
    default is (P1), (P3), (P4) and not equality-only (the claims are checked numerically
    in test_penalties.py)."""
    names = [n for n in P.available() if P.facts(P.make(n)).usable_for_contact]
    assert contact_penalties() == names
    for n in P.available():
        f = P.facts(P.make(n))
        assert f.usable_for_contact == ({"P1", "P3", "P4"} <= f.properties and not f.equality_only)


def test_user_penalties_reach_contact_through_facts(user_penalties):
    assert {"user-shifted-quad", "user-plain-exp"} <= set(contact_penalties())
    declared = P.facts(P.make("user-shifted-quad"))
    assert declared.freezes_at_zero and declared.eta_min == 1e-20 and declared.needs_multiplier_safeguard
    plain = P.facts(P.make("user-plain-exp"))  # defaults: freezes probed, safeguard from (P5)
    assert plain.freezes_at_zero and not plain.needs_multiplier_safeguard and plain.generator is None


def test_kinks_are_where_second_derivative_jumps(penalty):
    """A declared kink k of a non-C^2 penalty: |p''(k+d) - p''(k-d)| > 0.1 (p'' jumps by
    at least mu there for every built-in); a C^2 penalty declares none."""
    kinks = getattr(penalty, "kinks", lambda mu: ())
    if P.facts(penalty).twice_differentiable:
        assert len(kinks(1.0)) == 0
        return
    for mu in MUS:
        for k in kinks(mu):
            k = float(k)
            jump = abs(float(penalty.second_derivative(k + 1e-6, mu)) - float(penalty.second_derivative(k - 1e-6, mu)))
            assert jump > 0.1, (penalty.name, mu, k)


def test_minimizer_is_the_zero_of_the_derivative(penalty):
    """For penalties needing the safeguard: p'(y*) = 0 to 1e-12 relative to p'(y* +- 1),
    p' < 0 left and > 0 right of y*; the bisection default agrees with the declared one."""
    if not P.facts(penalty).needs_multiplier_safeguard:
        return
    for mu in MUS:
        ys = float(penalty.minimizer(mu))
        scale = float(abs(penalty.derivative(ys + 1.0, mu)))
        assert abs(float(penalty.derivative(ys, mu))) <= 1e-12 * scale
        assert float(penalty.derivative(ys - 1e-3, mu)) < 0 < float(penalty.derivative(ys + 1e-3, mu))
        assert float(P.minimizer_by_bisection(penalty, mu)) == pytest.approx(ys, rel=1e-12, abs=1e-14)


def test_safeguarded_penalty_numbers(penalty):
    """safeguarded(p): p' -> max(0, p'), p unchanged right of y*, constant p(y*) left of it;
    derivatives match central differences (h = 1e-6, rtol 1e-5) away from the kink; the
    facts of the result: no further safeguard, (P5) gained, (P2) lost."""
    s = P.safeguarded(penalty)
    if not P.facts(penalty).needs_multiplier_safeguard:
        assert s is penalty
        return
    assert isinstance(s, P.Safeguarded) and s.name == penalty.name
    f = P.facts(s)
    assert not f.needs_multiplier_safeguard and "P5" in f.properties and "P2" not in f.properties
    assert f.freezes_at_zero == P.facts(penalty).freezes_at_zero
    for mu in MUS:
        y = grid(penalty, mu)
        ys = float(s.minimizer(mu))
        d = np.asarray(s.derivative(y, mu))
        assert np.all(d >= 0.0)
        np.testing.assert_allclose(d, np.maximum(0.0, penalty.derivative(y, mu)), rtol=1e-13, atol=1e-300)
        right, left = y[y > ys], y[y < ys]
        np.testing.assert_array_equal(s.value(right, mu), penalty.value(right, mu))
        np.testing.assert_allclose(s.value(left, mu), float(penalty.value(ys, mu)), rtol=1e-13)
        assert np.all(np.asarray(s.second_derivative(left, mu)) == 0.0)
        h = 1e-6
        pts = np.array([ys - 2.0, ys - 0.5, ys + 0.5, ys + 2.0])
        fd1 = (np.asarray(s.value(pts + h, mu)) - np.asarray(s.value(pts - h, mu))) / (2 * h)
        fd2 = (np.asarray(s.derivative(pts + h, mu)) - np.asarray(s.derivative(pts - h, mu))) / (2 * h)
        np.testing.assert_allclose(fd1, s.derivative(pts, mu), rtol=1e-5, atol=1e-7)
        np.testing.assert_allclose(fd2, s.second_derivative(pts, mu), rtol=1e-5, atol=1e-7)


def test_contact_and_optim_use_the_same_safeguard():
    """One implementation: the contact law of quad-met2 and optim's subproblem penalty
    are both penalties.Safeguarded with identical values; exp-met1 is only extrapolated
    (its generator, fact ``generator``), rockafellar is untouched."""
    quad = P.make("quad-met2")
    law = make_law(quad, np.ones(3))
    opt = safeguard_penalty(quad, extrapolate=True, cap=20.0)
    assert type(law.penalty) is type(opt) is P.Safeguarded
    y, mu = np.linspace(-10, 10, 41), 0.7
    np.testing.assert_array_equal(law.penalty.derivative(y, mu), opt.derivative(y, mu))
    exp = safeguard_penalty(P.make("exp-met1"), extrapolate=True, cap=20.0)
    assert isinstance(exp, P.Met1) and exp.name == "exp-met1" and "~q(20)" in exp.generator.name
    assert float(exp.derivative(30.0, 1.0)) == pytest.approx(math.exp(20) * 11.0)
    rock = P.make("rockafellar")
    assert safeguard_penalty(rock, extrapolate=True, cap=20.0) is rock


def test_with_generator_only_for_met():
    p = P.make("log-met2")
    q = p.with_generator(P.theta("exp"))
    assert isinstance(q, P.Met2) and q.name == "log-met2" and q.generator is P.theta("exp")
    with pytest.raises(errors.InputError, match="generator"):
        P.make("rockafellar").with_generator(P.theta("exp"))


def _barrier_run(penalty, options):
    con = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, -1.0)
    return minimize(lambda x: x @ x, [-1.0, -2.0], jac=lambda x: 2 * x, hess=lambda x: 2 * np.eye(2),
                    constraints=con, method="barrier", penalty=penalty, options=options)


def test_eta_min_fact_is_what_the_inverse_barrier_needs():
    """min |x|^2 s.t. x1 + x2 <= -1 (solution (-1/2, -1/2)) by the barrier method: the
    inverse barrier declares eta_min = 1e-24 and converges with it (|x - x*| <= 1e-6);
    held at the default floor 1e-12 its complementarity stalls near 1e-6 > ctol = 1e-8
    and it fails. The log barrier declares none and converges with the default."""
    assert P.facts(P.make("inverse-barrier")).eta_min == 1e-24
    assert P.facts(P.make("log-barrier")).eta_min is None
    ok = _barrier_run("inverse-barrier", None)
    assert ok.status == Status.CONVERGED_KKT and float(np.min(ok.eta)) < 1e-12
    np.testing.assert_allclose(ok.x, [-0.5, -0.5], atol=1e-6)
    assert _barrier_run("inverse-barrier", Options()).status == Status.CONVERGED_KKT
    held = _barrier_run("inverse-barrier", {"eta_min": 1e-12})
    assert held.status < 0 and held.complementarity > 1e-8
    assert _barrier_run("log-barrier", None).status == Status.CONVERGED_KKT


SRC = Path(__file__).resolve().parents[2] / "src" / "alcontact"
BUILTIN_NAMES = "|".join(re.escape(n) for n in sorted(P.available()))
NAME_TEST = re.compile(rf"""(==|!=)\s*["']({BUILTIN_NAMES})["']|["']({BUILTIN_NAMES})["']\s*(==|!=)""")
CLASS_TEST = re.compile(r"isinstance\([^)]*\b(Met1|Met2|Rockafellar|HestenesPowell|ExteriorQuadratic|LogBarrier|"
                        r"InverseBarrier|Safeguarded)\b")


def test_no_penalty_is_tested_by_name_or_class_in_the_library():
    """The algorithms read declared facts; no source file compares a penalty name or class."""
    hits = []
    for path in SRC.rglob("*.py"):
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if NAME_TEST.search(line) or CLASS_TEST.search(line):
                hits.append(f"{path.relative_to(SRC)}:{i}: {line.strip()}")
    assert not hits, "\n".join(hits)
