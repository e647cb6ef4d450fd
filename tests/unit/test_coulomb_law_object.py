"""The Coulomb law object (tangential part of a contact law): its disc radius and its checks.

Reference: the definitions of section 6.2 (module doc of :mod:`alcontact.contact.laws`): the
disc radius is :math:`\\mu t_N` (``radius = "traction"``) or :math:`\\mu\\langle\\lambda_N\\rangle`
(``"multiplier"``), exactly; the return mapping with that radius projects the trial traction
onto the disc (stick inside, :math:`|t_T| = \\rho` on slip).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact.laws import CoulombLaw, return_mapping
from alcontact.errors import InputError


def test_disc_radius_of_both_choices():
    tN, lamN = np.array([2.0, 0.5, 0.0]), np.array([1.0, -1.0, 3.0])
    coupled = CoulombLaw(0.4, 10.0)
    assert coupled.coupled and coupled.radius == "traction"
    np.testing.assert_array_equal(coupled.disc_radius(tN, lamN), 0.4 * tN)
    fixed = coupled.with_radius("multiplier")
    assert not fixed.coupled and fixed.eps_t == 10.0 and fixed.mu == 0.4
    np.testing.assert_array_equal(fixed.disc_radius(tN, lamN), 0.4 * np.maximum(lamN, 0.0))
    assert coupled.with_radius("traction", eps_t=3.0).eps_t == 3.0


def test_radius_drives_the_return_mapping():
    law = CoulombLaw(0.5, 1.0)
    z = np.array([[0.2, 0.0], [3.0, 4.0]])
    rho = law.disc_radius(np.array([1.0, 1.0]), None)
    tT, opened, stick, slip, _, _ = return_mapping(z, rho)
    assert stick.tolist() == [True, False] and slip.tolist() == [False, True] and not opened.any()
    np.testing.assert_allclose(np.linalg.norm(tT[1]), 0.5, rtol=1e-15)
    np.testing.assert_array_equal(tT[0], z[0])


def test_unknown_radius_is_an_input_error_naming_it():
    with pytest.raises(InputError, match=r"radius = 'disc'.*traction, multiplier"):
        CoulombLaw(0.3, 1.0, "disc")
