"""The memory-lean smoothed-aggregation hierarchy (:func:`alcontact.linalg._amg.smoothed_aggregation`).

Reference: :func:`pyamg.smoothed_aggregation_solver` with the same options on the same
3D P1 elasticity matrix (the stiffness of the Hertz block on its free DOFs, rigid-body
modes as near-null space). Both draw the random start of the spectral-radius estimate
from ``numpy.random``, seeded identically, so the hierarchies agree to round-off:
level sizes and block patterns exactly, prolongators and coarse matrices to 1e-12
relative (the Galerkin product is summed in another order), CG iterations to 1e-10
within one iteration.

Reaches inside the package: unit test of the private module ``linalg._amg`` against PyAMG.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pyamg
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import cg

from alcontact.contact.systems import IterativeContact
from alcontact.linalg import make_solver
from alcontact.linalg._amg import RANDOM_SEED, SMOOTHER, smoothed_aggregation
from alcontact.problems import hertz


@pytest.fixture(scope="module")
def stiffness():
    """``K`` (about 11k free DOFs) and the rigid-body modes on the free DOFs."""
    ic = IterativeContact(hertz.hertz_3d(n_per_a=3, growth=1.2))
    return ic.K, ic.R


#: coarsest level: small enough for three levels at 11k DOFs
COARSE = 100


def _pyamg(K, R):
    return pyamg.smoothed_aggregation_solver(K, B=R, max_coarse=COARSE, coarse_solver="splu",
                                             presmoother=SMOOTHER, postsmoother=SMOOTHER)


def _cg_iterations(K, ml) -> int:
    b = K @ np.linspace(-1.0, 1.0, K.shape[0])
    it = [0]
    _, info = cg(K, b, rtol=1e-10, M=ml.aspreconditioner(cycle="V"), maxiter=500,
                 callback=lambda _x: it.__setitem__(0, it[0] + 1))
    assert info == 0
    return it[0]


def _rel(a, b) -> float:
    a, b = sp.csr_matrix(a), sp.csr_matrix(b)
    return float(abs(a - b).max() / abs(b).max())


@pytest.mark.parametrize("nnz_block", [1 << 20, 20_000])
def test_same_hierarchy_as_pyamg(stiffness, nnz_block):
    """Same levels as PyAMG to round-off (module doc), for one block and for many blocks of rows."""
    K, R = stiffness
    np.random.seed(RANDOM_SEED)  # the seed smoothed_aggregation builds its hierarchies under
    ref = _pyamg(K, R)
    ml = smoothed_aggregation(K, R, max_coarse=COARSE, nnz_block=nnz_block)
    assert [lv.A.shape for lv in ml.levels] == [lv.A.shape for lv in ref.levels]
    assert len(ml.levels) >= 3
    for lv, lr in zip(ml.levels[1:], ref.levels[1:]):
        assert lv.A.format == lr.A.format == "bsr" and lv.A.blocksize == lr.A.blocksize
        assert lv.A.nnz == lr.A.nnz  # the same block pattern: coarser aggregations read it
    assert _rel(ml.levels[0].P, ref.levels[0].P) < 1e-12
    assert _rel(ml.levels[1].A, ref.levels[1].A) < 1e-12
    assert abs(_cg_iterations(K, ml) - _cg_iterations(K, ref)) <= 1


def test_restriction_is_a_view_of_the_prolongator(stiffness):
    """``R = P^T`` of the first level shares the arrays of ``P``; ``memory_bytes`` counts them once."""
    K, R = stiffness
    ml = smoothed_aggregation(K, R)
    P, Rst = ml.levels[0].P, ml.levels[0].R
    assert np.shares_memory(Rst.data, P.data) and Rst.shape == (P.shape[1], P.shape[0])
    x = np.linspace(0.0, 1.0, K.shape[0])
    assert np.allclose(Rst @ x, sp.csr_matrix(P).T @ x, rtol=1e-14)
    f = make_solver("amg").factorize(K)
    own = sum(m.data.nbytes + m.indices.nbytes + m.indptr.nbytes for lv in f.ml.levels
              for m in [lv.A] + ([lv.P] if hasattr(lv, "P") else []) + ([lv.R] if hasattr(lv, "R") else [])
              if m is not None and not (m is getattr(lv, "R", None) and np.shares_memory(m.data, lv.P.data)))
    assert f.memory_bytes == own


def test_setup_memory_below_pyamg(stiffness):
    """Traced peak of the setup above ``K``: at most 65 % of PyAMG's, the hierarchy at most 80 %.

    Measured (11k DOFs, blocks of 1/8 of ``K``): about 50 % and 75 %; at 188k DOFs with the
    default blocks 940 against 1,750 and 560 against 730 bytes per DOF.
    """
    K, R = stiffness

    def traced(build):
        tracemalloc.start()
        base = tracemalloc.get_traced_memory()[0]
        ml = build()
        cur, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        del ml
        return peak - base, cur - base

    peak_ref, kept_ref = traced(lambda: _pyamg(K, R))
    peak, kept = traced(lambda: smoothed_aggregation(K, R, max_coarse=COARSE, nnz_block=K.nnz // 8))
    assert peak <= 0.65 * peak_ref
    assert kept <= 0.80 * kept_ref
