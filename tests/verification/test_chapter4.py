"""Chapter 4 verification: observed convergence rates of the model problems.

* 1D model (4.1)-(4.2), linear elements: rate 2 in L2 and 1 in the H1 seminorm.
* 2D two-material problem (4.30)-(4.33) with the corrected Robin weak form
  (4.45): rate 2 in L2 and 1 in H1 (P1); the misprinted sign of (4.42) does
  not converge to the manufactured solution.

Tolerance on every observed rate: 0.1.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.errors import InputError
from alcontact.fem.model_problems import (
    TwoMaterialProblem,
    exact_1d,
    observed_rates,
    solve_1d,
    solve_two_material,
)

RATE_TOL = 0.1


def test_exact_1d_solves_the_model():
    x = np.linspace(0.0, 1.0, 11)
    u, du = exact_1d(x)
    assert abs(u[0]) < 1e-15 and abs(u[-1]) < 1e-15
    # -u'' + u = x  with  u'' = -sinh(x)/sinh(1)
    assert np.allclose(np.sinh(x) / np.sinh(1.0) + u, x)


def test_1d_rates():
    results = [solve_1d(n) for n in (8, 16, 32, 64)]
    h = [r.h for r in results]
    l2 = observed_rates(h, [r.error_l2 for r in results])
    h1 = observed_rates(h, [r.error_h1 for r in results])
    assert np.all(np.abs(l2 - 2.0) < RATE_TOL), l2
    assert np.all(np.abs(h1 - 1.0) < RATE_TOL), h1
    assert results[-1].error_l2 < 2e-5


def test_manufactured_solution_has_continuous_flux():
    prob = TwoMaterialProblem(k_a=1.0, k_b=10.0)
    y = np.linspace(0.0, 1.0, 7)
    left = np.array([np.full_like(y, 0.5 - 1e-9), y])
    right = np.array([np.full_like(y, 0.5 + 1e-9), y])
    (ul, gl), (ur, gr) = prob.exact(left), prob.exact(right)
    assert np.allclose(ul, ur, atol=1e-8)
    assert np.allclose(prob.k(left) * gl[0], prob.k(right) * gr[0], atol=1e-7)


def test_two_material_rates_corrected_weak_form():
    results = [solve_two_material(n) for n in (8, 16, 32, 64)]
    h = [r.h for r in results]
    l2 = observed_rates(h, [r.error_l2 for r in results])
    h1 = observed_rates(h, [r.error_h1 for r in results])
    assert np.all(np.abs(l2 - 2.0) < RATE_TOL), l2
    assert np.all(np.abs(h1 - 1.0) < RATE_TOL), h1


def test_printed_sign_of_4_42_does_not_converge():
    """Erratum: the Robin terms with a minus sign solve a different problem."""
    ns = (8, 16, 32)
    wrong = [solve_two_material(n, robin_sign=-1).error_l2 for n in ns]
    right = [solve_two_material(n, robin_sign=+1).error_l2 for n in ns]
    assert min(wrong) > 1e-2  # stalls at O(1e-2 .. 1e-1)
    assert wrong[-1] > 0.8 * wrong[0]  # no decrease with h
    assert wrong[-1] > 100 * right[-1]


def test_input_validation():
    with pytest.raises(InputError, match="even"):
        solve_two_material(7)
    with pytest.raises(InputError, match="robin_sign"):
        solve_two_material(8, robin_sign=0)
    with pytest.raises(InputError, match="k_a"):
        TwoMaterialProblem(k_a=-1.0)
    with pytest.raises(InputError, match="integer"):
        solve_1d(0)
