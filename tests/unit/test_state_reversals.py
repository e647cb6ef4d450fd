"""Counting stick/slip reversals between Newton iterates (issue 18, ``FiniteFrictionStep.state_reversals``).

Reaches inside the package: unit test of the private counting helper ``state_reversals`` of
``contact.algorithms._coulomb``.
"""

import numpy as np

from alcontact.contact.algorithms._coulomb import state_reversals

O, T, S = 0, 1, 2  # OPEN, STICK, SLIP


def test_reversals_counted_per_point():
    history = [np.array([T, T, O, S]), np.array([S, S, T, S]), np.array([S, T, S, S]), np.array([S, T, T, S])]
    # point 0: T S S S (none); point 1: T S T T (one); point 2: O T S T (T again: one); point 3: constant
    assert state_reversals(history) == 2


def test_repeats_and_short_histories_are_not_reversals():
    assert state_reversals([np.array([T]), np.array([S])]) == 0
    assert state_reversals([np.array([T]), np.array([T]), np.array([S]), np.array([S]), np.array([O])]) == 0
    assert state_reversals([np.array([S]), np.array([T]), np.array([T]), np.array([S])]) == 1
