"""Regression: Algorithm 6.4 with the modified log barriers failed at the first load step.

The Simo-Laursen predictor leaves points penetrating by lambda/eps_N, which is
exactly the domain bound of log-met1/log-met2 with the stiffness-matched scale,
so Newton started outside the domain ("non-finite residual at the start") and
every cut-back failed (found by benchmarks/friction.py on the Cattaneo-Mindlin case).
"""

import numpy as np
import pytest

from alcontact.contact import solve_friction
from alcontact.problems import friction as fp


@pytest.fixture(scope="module")
def mindlin():
    prob, hist = fp.cattaneo_mindlin_2d(n_per_a=6)
    return prob, hist, solve_friction(prob, hist, "ssn")


@pytest.mark.parametrize("penalty", ["log-met1", "log-met2"])
def test_log_penalties_converge_and_match_reference(mindlin, penalty):
    prob, hist, ref = mindlin
    sol = solve_friction(prob, hist, "family-p", penalty)
    assert sol.success, sol.message
    du = np.max(np.abs(sol.final.u - ref.final.u)) / np.max(np.abs(ref.final.u))
    assert du <= 1e-6
