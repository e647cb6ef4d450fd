"""Dense steps of the condensed frictionless path: Newton correction, active-set step, barrier start.

Reaches inside the package: unit tests of the private dense steps of ``contact.algorithms``
(``_first_push``, ``newton_step``).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.contact.algorithms._frictionless import _PUSH_MARGIN, _first_push
from alcontact.contact.systems import DiscreteContact
from alcontact.contact.algorithms._subproblem import newton_step
from alcontact.problems import hertz


def _spd(n, seed):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    return A @ A.T / n + 0.1 * np.eye(n)


@pytest.mark.parametrize("pattern", ["all-coupled", "some-zero", "all-zero", "negative", "tiny"])
def test_newton_step_equals_lu_of_the_whole_matrix(pattern):
    """The reduced symmetric solve equals ``solve(I + diag(wd) S, -F)``.

    Reference: LU of the whole matrix (numpy). Tolerance: relative 1e-10 in the max norm
    (round-off of two dense factorizations of a matrix with condition number below 1e5).
    """
    n = 40
    S = _spd(n, 1)
    rng = np.random.default_rng(2)
    wd = rng.uniform(0.1, 50.0, n)
    if pattern == "some-zero":
        wd[::3] = 0.0
    elif pattern == "all-zero":
        wd[:] = 0.0
    elif pattern == "negative":  # contact springs: not SPD, falls back to LU
        wd[5] = -0.2
    elif pattern == "tiny":  # coupling below round-off: decoupled rows
        wd[::4] = 1e-250
    F = rng.standard_normal(n)
    ref = np.linalg.solve(np.eye(n) + wd[:, None] * S, -F)
    dr = newton_step(S, wd, F)
    assert np.max(np.abs(dr - ref)) <= 1e-10 * np.max(np.abs(ref))


def test_active_set_step_on_active_rows_equals_full_system():
    """SSN step on the active rows only (Cholesky of S_AA) equals the full n x n system.

    Reference: rows of A: (S r)_i = g_free_i, other rows r_i = 0, solved as one dense
    system. Tolerance: relative 1e-10 (round-off).
    """
    dc = DiscreteContact(hertz.hertz_2d(order=1, n_per_a=6, growth=1.3))
    n = dc.cand.size
    assert n >= 4
    active = np.zeros(n, bool)
    active[: n // 2 + 1] = True
    r, lam, g = dc.solve_active(active, np.zeros(n), np.zeros(n), 1.0)
    gfree = dc.g_free[dc.cand]
    M = np.where(active[:, None], dc.S, np.eye(n))
    ref = np.linalg.solve(M, np.where(active, gfree, 0.0))
    assert np.max(np.abs(r - ref)) <= 1e-10 * np.max(np.abs(ref))
    np.testing.assert_allclose(lam, r / dc.weights[dc.cand], rtol=1e-14)
    assert np.max(np.abs(g[active])) <= 1e-10 * np.max(np.abs(gfree))


def test_first_push_closes_penetrations_with_margin():
    """The first barrier push closes every penetration outside the domain, with the safety factor.

    Reference: gaps affine in the scale, g(s) = g - s d. After the push, every point that was
    outside the domain has gap g - s d = g (1 - _PUSH_MARGIN) < 0 at the worst point, and the
    scale is the smallest such one times _PUSH_MARGIN (exact to 1e-14); no violation: 0.5.
    """
    g = np.array([2e-3, 1e-3, -1.0, 5e-4])
    d = np.array([0.1, 0.2, 0.3, -0.1])  # the last point moves away when pushed: not used
    bound = np.array([1e-4, 1e-4, 1.0, 1e3])
    s = _first_push(g, g - d, bound)
    assert s == pytest.approx(_PUSH_MARGIN * 2e-3 / 0.1, rel=1e-14)
    assert np.all((g - s * d)[:2] < 0)
    assert _first_push(np.array([-1.0, -2.0]), np.array([-1.5, -2.5]), np.array([1.0, 1.0])) == 0.5


def test_barrier_penalty_first_subproblem_starts_next_to_the_penalty_solution():
    """log-met2 on the small Hertz mesh: the solve agrees with SSN (the exact discrete solution) to
    1e-6 relative in the contact pressure. The Newton steps of the first MET 2 subproblem after the
    penalty start (formerly asserted at most 10; 15 with the former fixed 50 % push) are recorded by
    ``benchmarks/newton_counts.py``.
    """
    prob = hertz.hertz_2d(order=1, n_per_a=8, growth=1.3)
    met = solve(prob, "family-p", "log-met2")
    assert met.result.status.value > 0
    prob.model.clear_factorization()
    ref = solve(prob, "ssn")
    assert np.max(np.abs(met.pressure - ref.pressure)) <= 1e-6 * np.max(ref.pressure)
