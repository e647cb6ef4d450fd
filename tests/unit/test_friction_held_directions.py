"""Unit tests: tangent directions held by a support (symmetry planes) in the frictional law and frame."""

import numpy as np
import pytest

from alcontact.contact.kinematics import tangent_bases
from alcontact.contact.laws import Macaulay, local_law, tangential_energy


@pytest.mark.parametrize("case", ["stick", "slip"])
def test_held_direction_carries_no_traction_and_law_acts_on_free_ones(case):
    """3D point with T_1 held: t_T1 = 0, no derivative, and the free direction obeys the Coulomb law alone."""
    law = Macaulay(10.0)
    lamN, lamT = np.array([1.0]), np.array([[0.7, 0.1]])
    y = np.array([[0.01, 5.0, 0.02 if case == "stick" else 0.5]])
    uTn = np.zeros((1, 2))
    tfree = np.array([[False, True]])
    t, Dy, Dl, st = local_law(law, lamN, lamT, y, uTn, 1.0, 0.5, with_lam=True, tfree=tfree)
    assert t[0, 1] == 0.0
    assert np.all(Dy[0, 1, :] == 0.0) and np.all(Dy[0, :, 1] == 0.0) and np.all(Dl[0, 1, :] == 0.0)
    z = lamT[0, 1] + (y[0, 2] - uTn[0, 1])
    tN = 1.0 + 10.0 * 0.01
    expected = z if abs(z) <= 0.5 * tN else 0.5 * tN * np.sign(z)
    assert t[0, 2] == pytest.approx(expected, rel=1e-14)
    assert (st[0] == 1) == (case == "stick")
    e_all = tangential_energy(lamT, y[:, 1:], uTn, 1.0, np.array([0.5]))
    e_free = tangential_energy(lamT, y[:, 1:], uTn, 1.0, np.array([0.5]), tfree)
    assert e_free[0] < e_all[0]


def test_tangent_bases_align_with_held_axes():
    """A supported axis in the tangent plane becomes T_1; both held axes span the tangent plane at an apex."""
    nu = np.array([[0.0, 0.6, -0.8], [0.6, 0.0, -0.8], [0.0, 0.0, -1.0], [0.6, 0.0, -0.8]])
    held = np.array([[True, False, False], [False, True, False], [True, True, False], [True, False, False]])
    T = tangent_bases(nu, held)
    assert np.allclose(T[0, :, 0], [1, 0, 0])
    assert np.allclose(np.abs(T[1, :, 0]), [0, 1, 0])
    assert np.allclose(np.abs(T[2, :, 0]), [1, 0, 0]) and np.allclose(np.abs(T[2, :, 1]), [0, 1, 0])
    # a held axis with a normal component (oblique support) does not change the basis
    assert np.allclose(T[3], tangent_bases(nu[3:])[0])
    assert np.allclose(np.einsum("mdk,mdl->mkl", T, T), np.eye(2)[None])
