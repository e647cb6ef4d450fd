"""A refine ``growth`` near the largest float with NumPy-scalar bounds must not overflow (problem-file fuzzing).

``alcontact.fem.meshes.graded_axis`` got ``b - hi`` as a NumPy scalar from the mesh generator, and the
number of geometric steps ``log1p(length (growth - 1) / h0)`` overflowed with a RuntimeWarning (an error
under the test settings) instead of reaching the cap ``h_max`` at once. Reference: with such a growth the
first step past the fine window is already capped, so the spacing outside is ``h_max``.
"""

from __future__ import annotations

import warnings

import numpy as np

from alcontact.fem import meshes


def test_huge_growth_caps_at_once():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        x = meshes.graded_axis(np.float64(-320.0), np.float64(320.0), -1.6, 1.6, 4.0, 1.3e308, 320.0)
    assert x[0] == -320.0 and x[-1] == 320.0 and np.all(np.diff(x) > 0)
    assert np.max(np.diff(x)) <= 320.0
