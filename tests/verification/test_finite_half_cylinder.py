r"""A neo-Hookean half-cylinder pressed onto a rigid plane to :math:`\delta/R = 0.4` in load steps.

Problem: :func:`alcontact.problems.half_cylinder.half_cylinder` (plane strain, P1).

References:

- algorithm agreement: the semi-smooth Newton reference (``ssn``, exact discrete
  solution); every other algorithm (pure penalty, Algorithm 6.1, Algorithm 6.3 with every
  contact penalty) reproduces its contact force at every load step within 1e-6 relative;
- mesh convergence: the force curve :math:`F(\delta)` at the 8 load steps converges under
  uniform refinement (``n`` = 4, 8, 16, 32, 64 measured: max-norm differences of
  successive curves 6.40, 2.39, 0.599, 0.138, observed rates 1.42, 2.00, 2.11); asserted:
  observed rate >= 1.25 between the levels 4-8-16 (pre-asymptotic) and >= 1.75 between
  8-16-32 (slow).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import contact_penalties, solve_finite
from alcontact.problems.half_cylinder import half_cylinder

STEPS = 8
_FAST = {"simo-laursen": None, "penalty": None, "exp-met1": None}
RUNS = ([("simo-laursen", None), ("penalty", None)]
        + [pytest.param("family-p", p, marks=() if p in _FAST else pytest.mark.slow) for p in contact_penalties()])


@pytest.fixture(scope="module")
def reference():
    fs = solve_finite(half_cylinder(4), "ssn", steps=STEPS)
    assert fs.success, fs.message
    return fs


@pytest.mark.parametrize("algorithm,penalty", RUNS)
def test_algorithms_agree_with_reference(reference, algorithm, penalty):
    """Force at every step within 1e-6 relative of the ssn reference (module doc)."""
    fs = solve_finite(half_cylinder(4), algorithm, penalty, steps=STEPS)
    assert fs.success, fs.message
    assert np.allclose(fs.times, reference.times)
    ref = reference.forces[:, 1]
    assert np.max(np.abs(fs.forces[:, 1] - ref) / ref) <= 1e-6
    assert reference.solution.result.penetration <= 1e-8


def _rates(levels):
    curves = [solve_finite(half_cylinder(n), "ssn", steps=STEPS).forces[:, 1] for n in levels]
    diffs = [float(np.max(np.abs(b - a))) for a, b in zip(curves[:-1], curves[1:])]
    return [np.log2(d0 / d1) for d0, d1 in zip(diffs[:-1], diffs[1:])]


def test_force_curve_converges_under_refinement():
    """Observed convergence rate of F(delta) >= 1.25 for n = 4, 8, 16 (module doc)."""
    rates = _rates([4, 8, 16])
    assert min(rates) >= 1.25, rates


@pytest.mark.slow
def test_force_curve_converges_under_refinement_fine():
    """Observed rate >= 1.75 for n = 8, 16, 32 (module doc)."""
    rates = _rates([8, 16, 32])
    assert min(rates) >= 1.75, rates
