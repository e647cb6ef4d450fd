"""The L2 Hertz fit :func:`alcontact.contact.solution.fit_hertz_field` on synthetic fields (no solve)."""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact.solution import fit_hertz_field
from alcontact.errors import InputError


def _disc_quadrature(n=400, r_max=2.0):
    """Midpoint quadrature of a quarter disc of radius r_max in polar coordinates: radii, weights."""
    dr = r_max / n
    r = (np.arange(n) + 0.5) * dr
    return r, 0.5 * np.pi * r * dr


def test_both_amplitudes_recover_an_exact_hertz_profile():
    """Field p0 sqrt(1 - r^2/a^2) with p0 = 3, a = 1.2: both fits return p0 and a within 1e-3."""
    r_q, dx = _disc_quadrature()
    v = 3.0 * np.sqrt(np.clip(1.0 - (r_q / 1.2) ** 2, 0.0, None))
    r_n = np.linspace(0.0, 2.0, 17)
    p_n = 3.0 * np.sqrt(np.clip(1.0 - (r_n / 1.2) ** 2, 0.0, None))
    for amplitude in ("free", "load"):
        fit = fit_hertz_field(r_q, dx, v, r_n, p_n, amplitude=amplitude)
        assert fit.p0 == pytest.approx(3.0, rel=1e-3) and fit.a == pytest.approx(1.2, rel=1e-3), (amplitude, fit)


def test_load_matched_profile_carries_the_field_load():
    """For a field that is not a Hertz profile (uniform 1 on r < 1), the load-matched fit's
    profile integrates to the field's load (relative 1e-9); the free fit's does not."""
    r_q, dx = _disc_quadrature()
    v = (r_q < 1.0).astype(float)
    r_n = np.linspace(0.0, 2.0, 17)
    p_n = (r_n < 1.0).astype(float)
    load = float(np.sum(dx * v))

    def carried(fit):
        return fit.p0 * float(np.sum(dx * np.sqrt(np.clip(1.0 - (r_q / fit.a) ** 2, 0.0, None))))

    assert carried(fit_hertz_field(r_q, dx, v, r_n, p_n, amplitude="load")) == pytest.approx(load, rel=1e-9)
    assert abs(carried(fit_hertz_field(r_q, dx, v, r_n, p_n)) / load - 1.0) > 1e-3


def test_unknown_amplitude_names_the_choices():
    r_q, dx = _disc_quadrature(20)
    with pytest.raises(InputError, match="amplitude = 'peak'.*free.*load"):
        fit_hertz_field(r_q, dx, np.ones_like(r_q), np.ones(3), np.ones(3), amplitude="peak")
