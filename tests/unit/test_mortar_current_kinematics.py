r"""The mortar gap between two bodies at the current configuration (finite deformation, 2D P1).

References: the definitions of :mod:`alcontact.contact.kinematics._mortar_current`.

- At :math:`u = 0` the gap and the multiplier weights are those of the small-deformation mortar gap
  (:class:`~alcontact.contact.kinematics.MortarKinematics`), to round-off (1e-13), at the slave nodes
  within 5 element sizes of the master (the search of the current gap reaches 10).
- The constraint rows are the derivative of the gaps and the curvature term
  :math:`\sum_j c_j \partial^2 g_j/\partial x^2` the derivative of :math:`G^T c`: central differences
  (step 1e-6), relative 1e-6 and 1e-5 of the largest entry, at a state of large deformation and large
  sliding on a curved interface (the upper cylinder slid by a quarter of the contact zone's width across
  several master segments, random displacements of 1 % of the element size on top).
- Invariance under rigid motions of both bodies (the gap depends on relative positions only): a
  translation leaves the gaps unchanged (1e-13 of the element size), so every row of the gradient sums
  to zero over the DOFs of one direction (1e-12 of its largest entry) -- the discrete statement of
  action = reaction; a rotation of both bodies leaves the gaps unchanged (1e-12 h).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact import BodySurface, Boundary, ContactPair, ContactProblem, Support
from alcontact.contact.kinematics import ContactKinematics, CurrentMortarGap, MortarKinematics
from alcontact.errors import InputError
from alcontact.fem import Hyperelastic, Material
from alcontact.problems import two_body


@pytest.fixture(scope="module")
def pair():
    prob = two_body.hertz_cylinders(0, kinematics="finite")
    model = prob.model
    pts, dofs = prob.slave_nodes()
    fixed, _ = prob.dirichlet()
    mask = np.ones(model.ndofs, bool)
    mask[fixed] = False
    free = np.flatnonzero(mask)
    fp = -np.ones(model.ndofs, dtype=np.int64)
    fp[free] = np.arange(free.size)
    p = prob.pairs[0]
    kin = CurrentMortarGap(model, p.slave.body, p.slave.name, p.master, pts, dofs, fp[dofs], free)
    return prob, kin, free


def _state(prob, kin, free, seed=3):
    """Large sliding of the upper body plus small random displacements (module doc)."""
    model = prob.model
    rng = np.random.default_rng(seed)
    u = np.zeros(model.ndofs)
    u[free] = 0.01 * kin.h * rng.standard_normal(free.size)
    top = np.arange(model.offsets[1], model.offsets[2])
    u[top[0::2]] += 0.25
    u[top[1::2]] -= prob.meta["delta"]
    return u


def test_protocol_and_the_small_deformation_gap_at_the_reference(pair):
    prob, kin, free = pair
    assert isinstance(kin, ContactKinematics)
    assert (kin.configuration, kin.pointwise) == ("current", False)
    p = prob.pairs[0]
    from alcontact.contact.kinematics._mortar import mortar_gap  # the small-deformation weighted gap

    mg = mortar_gap(prob.model, p.slave.body, p.slave.name, p.master)
    small = MortarKinematics(mg, kin.points, kin.dofs, kin.pos, p.master, free)
    zero = np.zeros(prob.model.ndofs)
    # within the search's reach (10 slave element sizes; the small-deformation gap searches a quarter of the
    # boundaries' extent once): the nodes that may come into contact
    near = small.gaps(zero) > -5.0 * kin.h
    assert near.sum() >= 10
    np.testing.assert_allclose(kin.gaps(zero)[near], small.gaps(zero)[near], rtol=0, atol=1e-13 * kin.h)
    np.testing.assert_array_equal(kin.weights, mg.weights)
    ev = kin.evaluate(zero, hessian=True)
    both = near & mg.covered
    np.testing.assert_allclose(ev.normals[both], mg.normals[both], rtol=0, atol=1e-13)
    assert ev.gradient().shape == (kin.points.shape[0], free.size)


def test_gradient_and_curvature_are_the_derivatives_of_the_gap(pair):
    prob, kin, free = pair
    u = _state(prob, kin, free)
    ev = kin.evaluate(u, hessian=True)
    rows = np.flatnonzero(ev.g > -2.0 * kin.h)  # the slave nodes near the master
    assert rows.size >= 8
    G = ev.gradient().toarray()
    cols = np.unique(np.nonzero(G[rows])[1])
    rng = np.random.default_rng(4)
    c = np.zeros(kin.points.shape[0])
    c[rows] = rng.standard_normal(rows.size)
    C = kin.evaluate(u, hessian=True).curvature(c).toarray()
    h = 1e-6
    Gfd = np.zeros((rows.size, cols.size))
    Cfd = np.zeros((free.size, cols.size))
    for k, col in enumerate(cols):
        up, um = u.copy(), u.copy()
        up[free[col]] += h
        um[free[col]] -= h
        Gfd[:, k] = (kin.gaps(up)[rows] - kin.gaps(um)[rows]) / (2 * h)
        Cfd[:, k] = (kin.evaluate(up).gradient().T @ c - kin.evaluate(um).gradient().T @ c) / (2 * h)
    assert np.abs(G[np.ix_(rows, cols)] - Gfd).max() <= 1e-6 * np.abs(G).max()
    assert np.abs(C[:, cols] - Cfd).max() <= 1e-5 * np.abs(C).max()
    assert np.abs(C - C.T).max() <= 1e-12 * np.abs(C).max()  # a Hessian
    # the curvature is not negligible here: without it Newton would converge linearly
    assert np.abs(C).max() > 1e-2 * np.abs(c).max() / kin.h


def test_rigid_motions_of_both_bodies_leave_the_gaps_unchanged(pair):
    prob, kin, free = pair
    model = prob.model
    u = _state(prob, kin, free)
    g = kin.gaps(u)
    pts, dofs = model.all_node_dofs()
    x = pts + u[dofs]
    for shift in ([0.3, -0.2], [-1.0, 0.5]):
        v = u.copy()
        v[dofs] += np.asarray(shift)
        np.testing.assert_allclose(kin.gaps(v), g, rtol=0, atol=1e-13 * max(1.0, np.abs(g).max()))
    th = 0.3
    Q = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    v = u.copy()
    v[dofs] = x @ Q.T - pts
    np.testing.assert_allclose(kin.gaps(v), g, rtol=0, atol=1e-12 * max(1.0, np.abs(g).max()))
    # every row sums to zero per direction over all DOFs: the contact forces -G^T r balance (action = reaction)
    near = np.flatnonzero(g > -2.0 * kin.h)
    for j in near:
        e = np.zeros(kin.points.shape[0])
        e[j] = 1.0
        f = kin.contact_force(u, e)  # -dg_j/dq on every DOF of the model
        scale = np.abs(f).max()
        for comp in range(2):
            assert abs(f[dofs[:, comp]].sum()) <= 1e-12 * scale
    r = np.abs(np.random.default_rng(0).standard_normal(kin.points.shape[0]))
    fs, fm = kin.side_forces(u, np.where(kin.gaps(u) > -2 * kin.h, r, 0.0))
    assert np.linalg.norm(fs + fm) <= 1e-12 * np.linalg.norm(fs)


def test_p2_bodies_are_refused_with_the_way_out():
    prob = two_body.compressed_blocks(2, 3)
    base, top = (Hyperelastic(b.mesh, Material(E=1000.0, nu=0.3, plane="strain"), order=2) for b in prob.bodies)
    problem = ContactProblem(bodies=[base, top], pairs=[ContactPair(Boundary(top, "bottom"), BodySurface(base, "top"))],
                             kinematics="finite",
                             supports=[Support("body0/bottom"), Support("body1/top"), Support("body1/left")])
    from alcontact.contact import solve

    with pytest.raises(InputError, match="P1 bodies.*order=2"):
        solve(problem, "ssn", steps=1)
