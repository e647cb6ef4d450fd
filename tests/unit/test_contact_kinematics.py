r"""The contact kinematics objects: one interface for the linearized (6.15) and the current gap.

References: the definitions of :mod:`alcontact.contact.kinematics`. The gradient of
:class:`CurrentGap` is the derivative of its gaps (central differences, relative 1e-6) and
its curvature term :math:`\sum_i c_i \partial^2 g_i/\partial x^2` the derivative of
:math:`G^T c` (central differences, relative 1e-5); :class:`LinearizedGap` is the
linearization of :class:`CurrentGap` at :math:`u = 0` (equal value and gradient there, a
difference of second order in :math:`u`: ratio 4 +- 0.2 when :math:`u` halves). The systems
hold a kinematics object and take their gaps and constraint rows from it, and a kinematics
that declares ``pointwise = False`` (the way a mortar gap plugs in) gives the same Newton
matrix and subproblem solution through its sparse gradient and curvature alone.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact import penalties
from alcontact.contact import ContactProblem, Pressure, Support, obstacles
from alcontact.contact.kinematics import ContactKinematics, CurrentGap, GapEvaluation, LinearizedGap
from alcontact.contact.laws import make_law
from alcontact.contact.systems import DiscreteContact, FiniteContact
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic


def _points(dim=2):
    """Three points near a curved master; point 1 has its second DOF supported (pos -1)."""
    if dim == 2:
        master = obstacles.make("circle", center=[0.0, 1.2], radius=1.0)
        pts = np.array([[-0.3, 0.1], [0.0, 0.15], [0.25, 0.05]])
    else:
        master = obstacles.make("sphere", center=[0.0, 0.0, 1.2], radius=1.0)
        pts = np.array([[-0.3, 0.1, 0.1], [0.0, 0.0, 0.15], [0.2, -0.1, 0.05]])
    m = pts.shape[0]
    dofs = np.arange(m * dim).reshape(m, dim)
    pos = dofs.copy()
    pos[1, -1] = -1
    pos[2:] -= 1  # the free numbering skips the supported DOF
    return pts, dofs, pos, master, m * dim - 1


def _free(u, dofs, pos):
    """The free DOF values of a full displacement (by the free positions)."""
    x = np.zeros(int(pos.max()) + 1)
    keep = pos >= 0
    x[pos[keep]] = u[dofs[keep]]
    return x


@pytest.mark.parametrize("dim", [2, 3])
def test_both_satisfy_the_protocol_and_declare_their_configuration(dim):
    pts, dofs, pos, master, nf = _points(dim)
    small, finite = LinearizedGap(pts, dofs, pos, master, nf), CurrentGap(pts, dofs, pos, master, nf)
    assert isinstance(small, ContactKinematics) and isinstance(finite, ContactKinematics)
    assert (small.configuration, finite.configuration) == ("reference", "current")
    assert small.pointwise and finite.pointwise
    ev = finite.evaluate(np.zeros(dofs.size), np.array([0, 2]), hessian=True)
    assert isinstance(ev, GapEvaluation)
    assert ev.g.shape == (2,) and ev.normals.shape == (2, dim) and ev.hessian.shape == (2, dim, dim)
    assert ev.gradient().shape == (2, nf) and ev.curvature(np.ones(2)).shape == (nf, nf)


@pytest.mark.parametrize("dim", [2, 3])
def test_current_gap_gradient_and_curvature_are_its_derivatives(dim):
    pts, dofs, pos, master, nf = _points(dim)
    kin = CurrentGap(pts, dofs, pos, master, nf)
    rng = np.random.default_rng(1)
    u = 0.02 * rng.standard_normal(dofs.size)
    u[dofs[1, -1]] = 0.01  # a prescribed value on the supported DOF
    idx = np.arange(pts.shape[0])
    c = np.array([1.0, -0.5, 2.0])
    ev = kin.evaluate(u, idx, hessian=True)
    G, C = ev.gradient().toarray(), ev.curvature(c).toarray()
    h = 1e-6
    for k in range(nf):
        j = np.flatnonzero((pos == k).ravel())[0]  # the DOF of free position k
        up, um = u.copy(), u.copy()
        up[j] += h
        um[j] -= h
        dg = (kin.gaps(up, idx) - kin.gaps(um, idx)) / (2 * h)
        np.testing.assert_allclose(G[:, k], dg, rtol=1e-6, atol=1e-9)
        dGc = (kin.evaluate(up, idx).gradient().T @ c - kin.evaluate(um, idx).gradient().T @ c) / (2 * h)
        np.testing.assert_allclose(C[:, k], dGc, rtol=1e-5, atol=1e-7)
    # a supported DOF has no column: the row of point 1 has d - 1 entries
    assert ev.gradient()[1].nnz == dim - 1


@pytest.mark.parametrize("dim", [2, 3])
def test_linearized_gap_is_the_linearization_of_the_current_gap(dim):
    pts, dofs, pos, master, nf = _points(dim)
    small, finite = LinearizedGap(pts, dofs, pos, master, nf), CurrentGap(pts, dofs, pos, master, nf)
    zero = np.zeros(dofs.size)
    np.testing.assert_array_equal(small.gaps(zero), finite.gaps(zero))
    np.testing.assert_array_equal(small.evaluate(zero).gradient().toarray(), finite.evaluate(zero).gradient().toarray())
    # the linearized gap is affine: its gradient is the same at any u, its Hessian zero
    u = 0.05 * np.random.default_rng(2).standard_normal(dofs.size)
    u[dofs[1, -1]] = 0.0  # no prescribed value: the gap is g0 + G x
    ev = small.evaluate(u, np.arange(3), hessian=True)
    np.testing.assert_array_equal(ev.gradient().toarray(), small.rows.toarray())
    assert not np.any(ev.hessian) and ev.curvature(np.ones(3)).nnz == 0
    np.testing.assert_allclose(small.gaps(u), small.gap0 + small.rows @ _free(u, dofs, pos), rtol=1e-14, atol=1e-15)
    # the difference is of second order: it drops by 4 when u halves
    e1 = np.max(np.abs(finite.gaps(u) - small.gaps(u)))
    e2 = np.max(np.abs(finite.gaps(u / 2) - small.gaps(u / 2)))
    assert e1 > 1e-6 and abs(e1 / e2 - 4.0) < 0.2


def test_masked_gradient_keeps_the_pattern():
    pts, dofs, pos, master, nf = _points()
    ev = CurrentGap(pts, dofs, pos, master, nf).evaluate(np.zeros(dofs.size))
    on = np.array([True, False, True])
    full, masked = ev.gradient(), ev.gradient(on)
    assert masked.nnz == full.nnz  # zeros stored explicitly
    dense = full.toarray()
    dense[1] = 0.0
    np.testing.assert_array_equal(masked.toarray(), dense)


def test_against_measures_the_same_points_against_another_master():
    pts, dofs, pos, master, nf = _points()
    kin = CurrentGap(pts, dofs, pos, master, nf)
    moved = obstacles.translate(master, [0.0, -0.1])
    other = kin.against(moved)
    assert type(other) is CurrentGap and other.master is moved and kin.master is master
    np.testing.assert_allclose(other.gaps(np.zeros(dofs.size)), moved.gap(pts), rtol=0, atol=0)


def _finite_system():
    mesh = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    body = Hyperelastic(mesh, Material(E=100.0, nu=0.3, plane="strain"), order=2)
    obstacle = obstacles.Circle(center=(0.5, 1.35), radius=0.4)
    problem = ContactProblem(body, obstacle, "top", supports=(Support("bottom"),), kinematics="finite")
    return FiniteContact(problem), problem


def test_systems_hold_their_kinematics():
    """Small deformation: the linearized gap; finite: the current gap, whose master the load steps move."""
    body = LinearElasticity(meshes.rectangle(0.0, 1.0, 0.0, 0.5, 6, 3), Material(E=1000.0, nu=0.3))
    plane = obstacles.make("half-space", point=[0.0, 0.0], normal=[0.0, 1.0])
    problem = ContactProblem(body, plane, "bottom", supports=[Support("left", components=[0])],
                             loads=[Pressure("top", 1.0)])
    small = DiscreteContact(problem)
    assert isinstance(small.kinematics, LinearizedGap) and small.kinematics.master is plane
    u = np.zeros(body.ndofs)
    u[small.dofs[:, 1]] = -0.01
    np.testing.assert_array_equal(small.all_gaps(u), small.kinematics.gaps(u))
    np.testing.assert_array_equal(small.B.toarray(), small.kinematics.rows.toarray())

    fc, fproblem = _finite_system()
    assert isinstance(fc.kinematics, CurrentGap) and fc.kinematics.configuration == "current"
    moved = obstacles.translate(fproblem.obstacle, [0.0, -0.05])
    fc.configure(fc.fixed_values, fc.load, moved, fc.x0)
    assert fc.obstacle is moved and fc.kinematics.master is moved
    np.testing.assert_array_equal(fc.gaps(fc.x0), moved.gap(fc.points[fc.cand]))


class _Coupled:
    """The current gap seen as a kinematics that couples points (``pointwise = False``): only its sparse
    gradient and curvature are used, as a mortar gap would give them."""

    pointwise = False
    configuration = "current"

    def __init__(self, inner):
        self.inner = inner
        self.points, self.dofs, self.pos, self.master = inner.points, inner.dofs, inner.pos, inner.master

    def gaps(self, u, idx=None):
        return self.inner.gaps(u, idx)

    def evaluate(self, u, idx=None, *, hessian=False):
        return self.inner.evaluate(u, idx, hessian=hessian)

    def against(self, master):
        return _Coupled(self.inner.against(master))

    def current(self, u, idx=None):
        return self.inner.current(u, idx)


def test_a_coupling_kinematics_plugs_in_through_its_sparse_rows():
    """Newton matrix and subproblem (S) of a finite system with a ``pointwise = False`` kinematics equal the
    pointwise ones (matrix to 1e-13 relative, solution to 1e-10): the general sparse path of the system."""
    fc, _ = _finite_system()
    fc.cand = np.flatnonzero(fc.movable)
    x = 0.005 * np.random.default_rng(0).standard_normal(fc.free.size)
    law = make_law(penalties.make("rockafellar"), np.full(fc.cand.size, 0.04))
    lam = np.full(fc.cand.size, 10.0)
    J_point = fc.jacobian(law, lam, x)
    R_point = fc.residual(law, lam, x)
    out_point = fc.subproblem(law, lam, fc.x0, tol=1e-10, maxiter=30)

    fc2, _ = _finite_system()
    fc2.cand = fc.cand.copy()
    fc2.kinematics = _Coupled(fc2.kinematics)
    J = fc2.jacobian(law, lam, x)
    assert not fc2._layout.built_here(J)  # not the fixed point-block structure: the sparse sum
    scale = abs(J_point).max()
    assert abs(J - J_point).max() <= 1e-13 * scale
    np.testing.assert_allclose(fc2.residual(law, lam, x), R_point, rtol=0, atol=1e-13 * np.abs(R_point).max())
    out = fc2.subproblem(law, lam, fc2.x0, tol=1e-10, maxiter=30)
    assert out.converged and out_point.converged
    np.testing.assert_allclose(out.state, out_point.state, rtol=0, atol=1e-10 * np.abs(out_point.state).max())


def test_one_subproblem_at_small_and_finite_deformation():
    """Subproblem (S) of Algorithm 6.1 is one problem: the full-space Newton of finite deformation holding the
    linearized gap (6.15) solves it as the condensed small-deformation system does (displacements and gaps
    to 1e-8 relative; a linear elastic cantilever pressed onto a plane with the Macaulay law)."""
    body = LinearElasticity(meshes.rectangle(0.0, 1.0, 0.0, 0.25, 16, 4), Material(E=1000.0, nu=0.3))
    plane = obstacles.make("half-space", point=[0.0, -0.01], normal=[0.0, 1.0])
    problem = ContactProblem(body, plane, "bottom", supports=[Support("left")], loads=[Pressure("top", 2.0)])
    small = DiscreteContact(problem)
    full = FiniteContact(problem, kinematics=LinearizedGap)
    assert full.kinematics.configuration == "reference" and small.cand.size > 3
    full.cand = small.cand.copy()
    law = make_law(penalties.make("rockafellar"), np.full(small.cand.size, 1e-5))  # eps_N = 1e5
    lam = np.full(small.cand.size, 1.0)
    out_small = small.subproblem(law, lam, small.start(), tol=1e-12, maxiter=50)
    out_full = full.subproblem(law, lam, full.start(), tol=1e-12, maxiter=50)
    assert out_small.converged and out_full.converged and np.any(out_full.t > 0)
    u_small, u_full = small.final_displacement(out_small.state), full.final_displacement(out_full.state)
    np.testing.assert_allclose(u_full, u_small, rtol=0, atol=1e-8 * np.abs(u_small).max())
    np.testing.assert_allclose(out_full.g, out_small.g, rtol=0, atol=1e-8 * np.abs(u_small).max())
