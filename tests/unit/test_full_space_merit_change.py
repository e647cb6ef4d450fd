"""The potential change of the factorization-free subproblem (:meth:`_FullSpaceSubproblem.merit_change`).

Reference: the difference of the two values of :math:`\\Pi(x) = \\tfrac12 x^TKx - b^Tx + \\sum_j w_j p(g_j)`
on a small 2D Hertz model (4.5k free DOFs), where the values carry little round-off: the two agree to
1e-9 of the largest term of :math:`\\Pi`, for a Newton-sized and a large step and for two penalty laws.

Reaches inside the package: unit test of the private subproblem class of ``contact.systems._krylov``
(and the private law factory of ``contact.laws._normal``).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact.systems import IterativeContact
from alcontact.contact.systems._krylov import _FullSpaceSubproblem
from alcontact.contact.laws._normal import make_law
from alcontact.penalties import make
from alcontact.problems import hertz


@pytest.mark.parametrize("penalty", ["log-met1", "exp-met1"])
@pytest.mark.parametrize("size", [1e-6, 1e-2])
def test_merit_change_is_the_difference_of_the_potentials(penalty, size):
    ic = IterativeContact(hertz.hertz_2d(n_per_a=16, growth=1.15))
    x0 = 1e-3 * np.random.default_rng(0).standard_normal(ic.x_free.size)
    law = make_law(make(penalty), np.full(ic.cand.size, 1.0))  # eta = 1: every trial gap in the domain
    lam = np.full(ic.cand.size, 1.0)
    sub = _FullSpaceSubproblem(ic, law, lam, 1e-10)
    rng = np.random.default_rng(1)
    d = size * 1e-3 * rng.standard_normal(x0.size)
    a, b = sub.evaluate(x0), sub.evaluate(x0 + d)
    exact = sub.merit_change(a, b, sub.merit(a), sub.merit(b))
    terms = 0.5 * float(np.abs(x0) @ np.abs(ic.K @ x0)) + float(np.abs(ic.b) @ np.abs(x0))
    assert np.isfinite(exact)
    assert abs(exact - (sub.merit(b) - sub.merit(a))) <= 1e-13 * terms
