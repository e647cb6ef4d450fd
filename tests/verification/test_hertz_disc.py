"""The elastic half disc on a rigid plane (``hertz_disc``), driven by a platen or by the plane.

Reference: Johnson, *Contact Mechanics* (1985), eq. 4.45-4.47, a cylinder of radius R on a rigid
plane under the load P per unit thickness (the model's contact force): a = sqrt(4PR/(pi E*)),
p0 = 2P/(pi a), E* = E/(1-nu^2), valid for a << R (here a/R = 0.12: the finite disc and the platen
change a by O((a/R)^2), about 1 %). Tolerances: a within 2 % (the nodal half-width of 16 cells per
radius, P2: measured 0.05 %), p0 within 3 % (measured 0.5 %).

The two drives are one problem translated rigidly (the plane's gap is linear in x): force, a and
p0 agree to 1e-8 (measured 1e-14).
"""

import pytest

from alcontact.contact import solve
from alcontact.errors import InputError, UnknownNameError
from alcontact.problems import hertz


@pytest.fixture(scope="module")
def runs():
    out = {}
    for drive in hertz.DISC_DRIVES:
        prob = hertz.hertz_disc(16, drive=drive)
        sol = solve(prob, "ssn")
        assert sol.result.success, sol.result.message
        out[drive] = (prob, sol)
    return out


def test_half_disc_matches_hertz(runs):
    prob, sol = runs["platen"]
    ref = prob.reference
    P = ref.load(sol.normal_force)
    a = sol.contact_half_width(axis=0, center=prob.meta["center"])
    assert abs(a / ref.half_width(P) - 1) <= 0.02
    assert abs(sol.peak_pressure / ref.peak_pressure(P) - 1) <= 0.03
    assert 0.08 <= a / 10.0 <= 0.16  # the default approach gives a/R about 0.1


def test_platen_and_plane_drives_give_the_same_contact(runs):
    (_, pl), (_, ob) = runs["platen"], runs["obstacle"]
    assert abs(pl.normal_force / ob.normal_force - 1) <= 1e-8
    assert abs(pl.peak_pressure / ob.peak_pressure - 1) <= 1e-8


def test_half_disc_mesh_is_the_whole_half_disc():
    prob = hertz.hertz_disc(8, order=2)
    x = prob.model.mesh.p
    assert abs(x[0].min() + 10.0) < 1e-12 and abs(x[0].max() - 10.0) < 1e-12  # -R <= x <= R, no symmetry plane
    assert abs(x[1].min()) < 1e-12 and abs(x[1].max() - 10.0) < 1e-12
    assert prob.model.ndofs == 2 * (4 * 8 + 1) * (2 * 8 + 1)  # P2 nodes of the 2n x n grid


def test_half_disc_bad_arguments():
    with pytest.raises(UnknownNameError, match="drive"):
        hertz.hertz_disc(4, drive="force")
    with pytest.raises(InputError, match="delta"):
        hertz.hertz_disc(4, delta=-1.0)
