"""MET 1 and MET 2 in contact: the variant takes effect, and why the default scaling makes them one law.

MET 1 (5.23) ``p = mu theta(y)`` and MET 2 (5.25) ``p = theta(mu y)`` give
``p'_1(y, mu) = mu theta'(y)`` and ``p'_2(y, mu) = mu theta'(mu y)``. The contact law is
``t_N = p'(g/eta, lambda)`` with ``eta`` chosen so that the stiffness at zero gap is ``eps_N``:
``eta = p''(0, lambda_ref)/eps_N``, i.e. ``eta_1 = lambda_ref theta''(0)/eps_N`` and
``eta_2 = lambda_ref**2 theta''(0)/eps_N``. Then

    t_1 = lambda theta'(g eps_N / (lambda_ref theta''(0))),
    t_2 = lambda theta'((lambda/lambda_ref) g eps_N / (lambda_ref theta''(0))),

which coincide for every ``g`` exactly when ``lambda_ref = lambda``: ``eta_scaling = "adaptive"``
(the default, recomputed from the current multipliers every outer iteration) makes MET 1 and MET 2
the same traction law, hence the same iterates and counts (the study's identical MET 1 / MET 2
rows). With ``eta_scaling = "fixed"`` (``lambda_ref`` = the initial multipliers) they differ by the
factor ``lambda/lambda_ref`` inside ``theta'``; from a start far from the solution (``initial =
"uniform"``) their multiplier sequences part from the second outer iteration, which shows that the
configured variant is the one that runs. From the default penalty start ``lambda_ref`` is already
close to the solution's pressures, so even fixed scaling gives the same counts on 2D Hertz.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact import penalties
from alcontact.contact import solve
from alcontact.contact.laws import eta_for_stiffness, make_law
from alcontact.problems.hertz import hertz_2d

GENERATORS = ["exp", "log", "quad"]


def _laws(theta, lam_ref, eps):
    p1, p2 = penalties.make(f"{theta}-met1"), penalties.make(f"{theta}-met2")
    return (make_law(p1, eta_for_stiffness(p1, lam_ref, eps)), make_law(p2, eta_for_stiffness(p2, lam_ref, eps)))


@pytest.mark.parametrize("theta", GENERATORS)
def test_adaptive_scaling_makes_met1_and_met2_one_law(theta):
    rng = np.random.default_rng(7)
    lam = 10.0 ** rng.uniform(-3, 3, 200)
    eps = 3.7e4
    law1, law2 = _laws(theta, lam, eps)
    # gaps inside both domains (the log barrier's bound is eta_1 = lam/eps for both)
    g = -rng.uniform(-0.9, 5.0, lam.size) * lam / eps
    t1, t2 = law1.traction(g, lam), law2.traction(g, lam)
    # Matioli's quadratic is safeguarded to max(0, p') (zero for y < -1); the others are positive
    assert np.all(t1 >= 0) and np.count_nonzero(t1) > lam.size // 3
    np.testing.assert_allclose(t2, t1, rtol=1e-13, atol=0)
    np.testing.assert_allclose(law2.stiffness(g, lam), law1.stiffness(g, lam), rtol=1e-12, atol=0)
    np.testing.assert_allclose(law2.gap_bound(lam), law1.gap_bound(lam), rtol=1e-14)


@pytest.mark.parametrize("theta", GENERATORS)
def test_fixed_scaling_differs_where_the_multiplier_moved(theta):
    rng = np.random.default_rng(8)
    lam_ref = 10.0 ** rng.uniform(-1, 1, 50)
    lam = 3.0 * lam_ref  # the multipliers moved since eta was fixed
    eps = 1.0e3
    law1, law2 = _laws(theta, lam_ref, eps)
    g = 0.1 * lam_ref / eps
    t1, t2 = law1.traction(g, lam), law2.traction(g, lam)
    # MET 2 sees the argument lam/lam_ref = 3 times larger: a larger traction for g > 0 (theta' increasing)
    assert np.all(t2 > t1 * (1 + 1e-3))
    # at lam == lam_ref the two agree (the first subproblem is the same)
    np.testing.assert_allclose(law2.traction(g, lam_ref), law1.traction(g, lam_ref), rtol=1e-13)


def _hertz(penalty, scaling):
    return solve(hertz_2d(n_per_a=2), "family-p", penalty,
                 {"eta_scaling": scaling, "initial": "uniform", "maxiter": 4})


def test_configured_met_variant_runs_fixed_scaling_parts_the_sequences():
    r1, r2 = _hertz("exp-met1", "fixed").result, _hertz("exp-met2", "fixed").result
    assert (r1.penalty, r2.penalty) == ("exp-met1", "exp-met2")
    d1 = [h.multiplier_change for h in r1.history]
    d2 = [h.multiplier_change for h in r2.history]
    # the first subproblem is the same law (lambda = lambda_ref): the same first multiplier change
    assert d1[0] == pytest.approx(d2[0], rel=1e-9)
    # from the second on they differ (measured: 3.28 and 0.0236 of p_ref)
    assert abs(d1[1] - d2[1]) > 0.5 * max(d1[1], d2[1])


def test_adaptive_scaling_gives_the_same_sequence():
    r1, r2 = _hertz("exp-met1", "adaptive").result, _hertz("exp-met2", "adaptive").result
    assert (r1.penalty, r2.penalty) == ("exp-met1", "exp-met2")
    assert [h.newton_iterations for h in r1.history] == [h.newton_iterations for h in r2.history]
    np.testing.assert_allclose([h.multiplier_change for h in r2.history],
                               [h.multiplier_change for h in r1.history], rtol=1e-8)
