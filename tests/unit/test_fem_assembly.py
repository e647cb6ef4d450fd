"""Chunked stiffness assembly (fem._assembly) and the sparse helpers of the AMG contact path.

Reaches inside the package: unit tests of the chunked assembly ``fem._assembly`` and the sparse
helpers of ``contact.systems._krylov``.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
import scipy.sparse as sp
from skfem import Basis, BilinearForm, asm
from skfem.helpers import ddot, sym_grad, trace

from alcontact.contact.systems._krylov import _abs_matvec
from alcontact.linalg.krylov import principal_submatrix
from alcontact.linalg import MatrixHints, krylov, make_solver
from alcontact.linalg.krylov import add_on_pattern
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.fem._assembly import elasticity_stiffness
from alcontact.problems import hertz


def _skfem_stiffness(model):
    """Reference: scikit-fem's asm of the same bilinear form, symmetrized (the former implementation)."""
    lam, mu = model.lam, model.mu

    @BilinearForm
    def a(u, v, w):
        eu, ev = sym_grad(u), sym_grad(v)
        return 2.0 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev)

    K = asm(a, Basis(model.mesh, model.element, intorder=max(1, 2 * (model.order - 1)))).tocsr()
    return (0.5 * (K + K.T)).tocsr()


MESHES = {
    "tet": lambda: meshes.box(0, 1, 0, 2, 0, 1, 3, 4, 2),
    "graded-tet": lambda: hertz.hertz_3d(n_per_a=1, growth=3.0).model.mesh,
    "tri": lambda: meshes.rectangle(0, 1, 0, 2, 4, 5),
}


@pytest.mark.parametrize("mesh", list(MESHES))
@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_stiffness_equals_skfem_assembly(mesh, order, plane):
    """K equals scikit-fem's assembly to 1e-14 of its largest entry, is exactly symmetric, sorted.

    Reference: ``skfem.asm`` of :math:`2\\mu\\,\\varepsilon:\\varepsilon + \\lambda\\,tr\\,tr` (the
    implementation before the chunked assembly). For P1 the sparsity patterns are identical
    (structural zeros of axis-aligned tensor meshes come out exactly zero in both).
    """
    model = LinearElasticity(MESHES[mesh](), Material(E=3.0, nu=0.3, plane=plane), order=order)
    K = model.stiffness()
    K0 = _skfem_stiffness(model)
    assert K.shape == K0.shape == (model.ndofs, model.ndofs)
    assert abs(K - K0).max() <= 1e-14 * abs(K0).max()
    assert abs(K - K.T).max() == 0.0
    assert K.has_sorted_indices
    if order == 1:
        assert K.nnz == K0.nnz


@pytest.mark.parametrize("order", [1, 2])
def test_dof_locations_and_numbering_match_skfem_basis(order):
    """The DOF data computed without a quadrature equal those of scikit-fem's Basis exactly."""
    model = LinearElasticity(MESHES["graded-tet"](), Material(E=1.0, nu=0.25), order=order)
    sb = Basis(model.mesh, model.scalar_element)
    assert np.array_equal(model.scalar_doflocs, sb.doflocs)
    assert model.ndofs == Basis(model.mesh, model.element).N
    assert np.array_equal(model.scalar_basis.element_dofs, sb.element_dofs)
    for name in model.boundary_names:
        expected = np.unique(sb.get_dofs(model.facets(name)).flatten())
        pts, dofs = model.node_dofs(name)
        assert np.array_equal(dofs, model.dof_map[expected])
        assert np.array_equal(pts, sb.doflocs[:, expected].T)


def test_chunk_size_does_not_change_the_matrix():
    """Chunks of 7 elements give the default assembly to 1e-15 of the largest entry (P2 tetrahedra)."""
    model = LinearElasticity(MESHES["tet"](), Material(E=2.0, nu=0.3), order=2)
    args = (model.mesh, model.scalar_element, model.scalar_dofs.element_dofs, int(model.scalar_dofs.N),
            model.lam, model.mu)
    K1 = elasticity_stiffness(*args, intorder=2)
    K2 = elasticity_stiffness(*args, intorder=2, chunk_entries=7 * 30 * 30 * 9)
    assert abs(K1 - K2).max() <= 1e-15 * abs(K1).max()


def test_non_interleaved_numbering_is_permuted():
    """With a permuted ``dof_map`` the stiffness is the permuted matrix (exactly)."""
    mat = Material(E=1.0, nu=0.3)
    ref = LinearElasticity(MESHES["tet"](), mat, order=1)
    K_ref = ref.stiffness()
    model = LinearElasticity(MESHES["tet"](), mat, order=1)
    dm = ref.dof_map.copy()
    dm[:, [0, 2]] = dm[:, [2, 0]]  # components x and z swapped in the vector numbering
    model.dof_map = dm  # the cached property, replaced before the assembly
    perm = np.empty(model.ndofs, dtype=np.int64)
    perm[dm.ravel()] = ref.dof_map.ravel()  # new DOF -> interleaved DOF
    assert abs(model.stiffness() - K_ref[perm][:, perm]).max() == 0.0


def test_stiffness_assembly_memory_is_bounded_by_the_matrix():
    """Peak traced memory of the assembly is at most 3.5 times the CSR matrix (3D P1, ~12k DOFs).

    Chunks of 2**15 element-matrix entries (the default chunk, 2**21 entries, is a fixed
    16 MB of element blocks that would dominate at this size). The former scikit-fem
    assembly held 144 COO triplets (24 bytes each) per tetrahedron plus the basis
    values: about 12 times the matrix at this size, growing with the mesh.
    """
    model = hertz.hertz_3d(n_per_a=3, growth=1.2).model
    args = (model.mesh, model.scalar_element, model.scalar_dofs.element_dofs, int(model.scalar_dofs.N),
            model.lam, model.mu)
    tracemalloc.start()
    try:
        K = elasticity_stiffness(*args, intorder=1, chunk_entries=1 << 15)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    size = K.data.nbytes + K.indices.nbytes + K.indptr.nbytes
    assert model.ndofs > 10000
    assert peak <= 3.5 * size, (peak, size)


def test_principal_submatrix_and_abs_matvec():
    """One-pass extraction equals two-step slicing exactly; the chunked ``|A| v`` equals ``abs(A) @ v``."""
    rng = np.random.default_rng(0)
    A = sp.random(300, 300, density=0.05, random_state=1, format="csr")
    A = (A + A.T).tocsr()
    A.sort_indices()
    keep = rng.random(300) > 0.3
    keep[[0, 299]] = [False, True]
    S = principal_submatrix(A, keep)
    idx = np.flatnonzero(keep)
    S0 = A[idx][:, idx].tocsr()
    assert (S != S0).nnz == 0 and S.has_sorted_indices
    v = rng.standard_normal(300)
    assert np.array_equal(_abs_matvec(A, v, rows=17), abs(A) @ v)


def test_plus_in_pattern_and_outside():
    """``add_on_pattern`` equals scipy's sum, on the pattern of ``A`` when possible (shared indices) and otherwise."""
    A = sp.csr_matrix(np.array([[4.0, 1, 0], [1, 4, 0], [0, 0, 4]]))
    D = sp.csr_matrix(([2.0, 3.0], ([0, 1], [1, 1])), shape=(3, 3))
    S = add_on_pattern(A, D)
    assert np.shares_memory(S.indices, A.indices) and np.array_equal(S.toarray(), (A + D).toarray())
    D2 = sp.csr_matrix(([5.0], ([0], [2])), shape=(3, 3))  # outside the pattern
    assert np.array_equal(add_on_pattern(A, D2).toarray(), (A + D2).toarray())
    B = sp.bsr_matrix(sp.random(12, 12, density=0.6, random_state=3) + sp.eye(12), blocksize=(3, 3))
    B.sort_indices()
    D3 = sp.csr_matrix(([1.5, -2.0], ([4, 5], [4, 3])), shape=(12, 12))
    assert np.allclose(add_on_pattern(B, D3).toarray(), (B + D3).toarray(), rtol=0, atol=0)


def test_contact_hierarchy_preconditions_like_a_fresh_setup():
    """CG on ``K + contact springs`` with the updated hierarchy of ``K`` needs at most 1.3x + 2 the
    iterations of a fresh AMG setup of that matrix (3D P1 Hertz, 3.6k DOFs, springs 10 times the
    largest stiffness entry on the whole top face, random right-hand side, relative tolerance 1e-8;
    measured 85 against 83)."""
    from alcontact.contact.systems import IterativeContact

    prob = hertz.hertz_3d(n_per_a=2, growth=1.3)
    ic = IterativeContact(prob)
    k = 10.0 * float(ic.K.diagonal().max()) * np.ones(ic.B.shape[0]) / ic.weights.mean()
    delta = ic.contact_delta(ic.B, ic.weights * k)
    J = ic.with_contact(delta)
    assert abs(J - (ic.K + delta)).max() <= 1e-15 * abs(J).max()
    rhs = np.random.default_rng(2).standard_normal(J.shape[0])
    counts = []
    updated, reused = krylov.updated_factor(ic.solver.solver, ic.factor_K, J, delta)
    assert reused  # the AMG factor of K offers the Galerkin update
    fresh = make_solver("amg").factorize(J, MatrixHints(near_null=lambda: ic.R))
    for factor in (updated, fresh):
        _, it = ic.pcg(J, rhs, krylov.preconditioner(factor), rtol=1e-8)
        counts.append(it)
    assert counts[0] <= 1.3 * counts[1] + 2, counts
