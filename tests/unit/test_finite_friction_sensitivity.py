"""The sensitivity of the finite-deformation frictional subproblem (second-order update of Algorithm 6.2).

:meth:`alcontact.contact.algorithms._coulomb._FiniteALCtx.sensitivity` gives
:math:`M = I - dt/d\\lambda` of the multiplier map :math:`\\lambda \\mapsto t(\\lambda)` (the tractions at
the subproblem's solution) and :math:`Z = dx/d\\lambda`. Reference: central differences of that map,
each column from two subproblems solved to ``newton_tol`` at :math:`\\lambda \\pm h e_j`
(h = 1e-6 of the largest pressure), at a sliding step of the 2D ironing case (h = 0.1, mu = 0.3).
Tolerance 1e-4 of the largest entry: the quotient's truncation error is O(h^2) where the stick/slip
states do not change, its noise about ``newton_tol / 2e-6`` = 5e-6 (subproblems solved to 1e-11 relative);
measured 3.6e-6 [a wrong term of the sensitivity is off by 1e-1 or more]; the columns of the normal multipliers
that are zero (the kink of the radius mu max(lambda_N, 0)) are left out. The blocked back-substitutions
(``_SENSITIVITY_BLOCK`` smaller than the number of multipliers, ``Z`` an operator) give the same
matrices to round-off.
"""

import numpy as np
import pytest

from alcontact.contact import solve_finite_friction
from alcontact.contact.algorithms import _coulomb as F
from alcontact.problems.ironing import ironing, ironing_schedule


def _fd(ctx, law, lamN, lamT, z):
    lam = np.concatenate([lamN[:, None], lamT], axis=1)
    h = 1e-6 * float(np.max(lamN))
    cols = []
    for j in range(lam.size):
        ts = []
        for sgn in (1.0, -1.0):
            lj = lam.ravel().copy()
            lj[j] += sgn * h
            lj = lj.reshape(lam.shape)
            out = ctx.subproblem(law, lj[:, 0], lj[:, 1:], z)
            assert out.converged, out.message
            ts.append(out.state.aux[1].ravel())
        cols.append((ts[0] - ts[1]) / (2 * h))
    return np.array(cols).T


@pytest.fixture(scope="module")
def captured():
    """At the first second-order update of a sliding step with the fixed radius (inside the solve, where the
    step's system holds that step's data): the sensitivity, its blocked version and the difference quotients."""
    problem = ironing(2, 10, slide=0.1)
    times, path = ironing_schedule(problem)
    good = F._second_order_update
    got = {}

    def record(ctx, law, lamN, lamT, state, z, coupled=False):
        if not got and not coupled and ctx.fc.offset[0] > 0:  # the cylinder has moved sideways
            got["sens"] = ctx.sensitivity(law, lamN, lamT, state)
            v = np.linspace(-1.0, 1.0, got["sens"][0].shape[0])
            got["v"], got["zv"] = v, got["sens"][2] @ v
            saved = F._SENSITIVITY_BLOCK
            F._SENSITIVITY_BLOCK = 7
            try:
                got["blocked"] = ctx.sensitivity(law, lamN, lamT, state)
                got["zbv"] = got["blocked"][2] @ v
            finally:
                F._SENSITIVITY_BLOCK = saved
            got["fd"] = _fd(ctx, law, lamN, lamT, z)
            got["nz"], got["lamN"] = z.size, lamN.copy()
        return good(ctx, law, lamN, lamT, state, z, coupled)

    F._second_order_update = record
    try:
        sol = solve_finite_friction(problem, 0.3, "simo-laursen", steps=times, obstacle_path=path)
    finally:
        F._second_order_update = good
    assert sol.status > 0, sol.message
    assert got, "no second-order update in a sliding step"
    return got


def test_sensitivity_matches_central_differences(captured):
    M, Ty, Z = captured["sens"]
    assert Ty is None and Z.shape == (captured["nz"], M.shape[0])
    dt = np.eye(M.shape[0]) - M
    ref = captured["fd"]
    # a point with lambda_N = 0 sits on the kink of its radius mu max(lambda_N, 0): the difference quotient
    # across it is the mean of the one-sided derivatives, the sensitivity takes the one of lambda_N <= 0
    lamN = captured["lamN"]
    nl = M.shape[0] // lamN.size
    kink = np.zeros(M.shape[0], dtype=bool)
    kink[::nl] = lamN <= 0
    assert kink.sum() < lamN.size  # most points are pressed
    assert np.max(np.abs(ref[:, ~kink])) > 1e-2  # a non-trivial map
    err = np.max(np.abs(dt - ref)[:, ~kink])
    assert err <= 1e-4 * np.max(np.abs(ref)), err


def test_blocked_back_substitutions_give_the_same_matrices(captured):
    M = captured["sens"][0]
    Mb, _, Zb = captured["blocked"]
    assert not isinstance(Zb, np.ndarray)  # an operator beyond one block
    assert np.max(np.abs(Mb - M)) <= 1e-10 * np.max(np.abs(M))
    zv = captured["zv"]
    assert np.max(np.abs(captured["zbv"] - zv)) <= 1e-10 * np.max(np.abs(zv))
