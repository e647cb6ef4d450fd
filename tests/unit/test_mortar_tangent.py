"""The tangential mortar operator (``alcontact.contact.kinematics._mortar_tangent``, a private module: the rows it
builds are no public name; the systems take them, and tests/verification/test_two_body_friction.py checks the
solutions they give).

Checked: the rows measure the relative displacement of each slave node and its mortar master point (a rigid
translation of both bodies moves no local variable; a tangential motion of the slave gives u_T = its size, of
the master -its size); against a rigid obstacle the same construction gives the node-to-surface rows
``[-nu^T; T^T]``; a gap operator without the node-block structure is refused.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from alcontact.contact.kinematics import tangent_bases
from alcontact.contact.kinematics._mortar import mortar_gap  # the pair's weighted gaps (no public name)
from alcontact.contact.kinematics._mortar_tangent import mortar_local_rows
from alcontact.problems import two_body, two_body_friction as tbf


def _rows(prob):
    pair = prob.pairs[0]
    mg = mortar_gap(prob.model, pair.slave.body, pair.slave.name, pair.master)
    _, dofs = prob.model.node_dofs(prob.contact_boundary)
    T = tangent_bases(mg.normals)
    return mg, dofs, T, mortar_local_rows(mg.B, mg.normals, T, np.vstack([dofs, mg.master_dofs]))


@pytest.mark.parametrize("make", [lambda: two_body.stacked_blocks(2, 3), lambda: two_body.stacked_blocks(3, 7, order=2),
                                  lambda: tbf.cattaneo_mindlin_cylinders(n_per_a=4, size=4, master_ratio=0.75)[0]])
def test_local_rows_measure_the_relative_displacement_of_the_two_surfaces(make):
    prob = make()
    mg, dofs, T, L = _rows(prob)
    m, d = dofs.shape
    assert L.shape == (m * d, prob.model.ndofs)
    np.testing.assert_array_equal(L[::d].toarray(), mg.B.toarray())  # row 0 of each node: the weighted gap
    cov = np.repeat(mg.covered, d)
    pts, all_dofs = prob.model.all_node_dofs()
    for axis in range(d):  # a rigid translation of both bodies moves no gap and no slip
        u = np.zeros(prob.model.ndofs)
        u[all_dofs[:, axis]] = 1.0
        assert np.max(np.abs((L @ u)[cov])) <= 1e-12
    # the slave alone moved along each node's tangent: u_T = 1 at that node (covered ones)
    slave = np.zeros(prob.model.ndofs)
    j = int(np.flatnonzero(mg.covered)[len(np.flatnonzero(mg.covered)) // 2])
    slave[dofs[j]] = T[j, :, 0]
    y = (L @ slave).reshape(m, d)
    assert y[j, 1] == pytest.approx(1.0, abs=1e-12) and abs(y[j, 0]) <= 1e-12
    # the master body translated along the tangent of node j: u_T = -1 there
    master = np.zeros(prob.model.ndofs)
    body = prob.model.bodies.index(prob.pairs[0].master.body)
    lo, hi = prob.model.offsets[body], prob.model.offsets[body + 1]
    on_master = (all_dofs[:, 0] >= lo) & (all_dofs[:, 0] < hi)
    for axis in range(d):
        master[all_dofs[on_master, axis]] = T[j, axis, 0]
    y = (L @ master).reshape(m, d)
    assert y[j, 1] == pytest.approx(-1.0, abs=1e-12)


def test_against_a_rigid_obstacle_the_rows_are_the_node_to_surface_ones():
    """The same construction on the rows -nu_i^T of the linearized gap (6.15) gives [-nu^T; T^T] on each point."""
    nu = np.array([[0.0, 1.0], [0.6, 0.8], [-0.8, 0.6]])
    dofs = np.array([[0, 1], [2, 3], [4, 5]])
    B = sp.csr_matrix((-nu.ravel(), (np.repeat(np.arange(3), 2), dofs.ravel())), shape=(3, 6))
    T = tangent_bases(nu)
    L = mortar_local_rows(B, nu, T, dofs).toarray()
    for i in range(3):
        np.testing.assert_allclose(L[2 * i, dofs[i]], -nu[i], atol=1e-15)
        np.testing.assert_allclose(L[2 * i + 1, dofs[i]], T[i, :, 0], atol=1e-15)


def test_a_gap_operator_off_the_normal_is_refused():
    nu = np.array([[0.0, 1.0]])
    B = sp.csr_matrix(np.array([[0.3, -1.0]]))  # not c * n^T
    with pytest.raises(ValueError, match="not a weighted small-deformation gap"):
        mortar_local_rows(B, nu, tangent_bases(nu), np.array([[0, 1]]))
