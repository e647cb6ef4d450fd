"""Unit tests of the saddle-point pieces of ``alcontact.linalg``: ``krylov.minres``, ``SaddlePoint`` and the
block preconditioners ``"amg"`` builds for a matrix marked ``MatrixHints(saddle=...)``.

References: a direct solve of the same matrix (``numpy.linalg.solve``); MINRES in exact arithmetic ends in
at most ``n`` iterations on an ``n x n`` system (Paige and Saunders 1975), and the block-triangular
preconditioner with the exact blocks makes GMRES converge in 2 iterations (Murphy, Golub and Wathen 2000).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from alcontact.errors import InputError
from alcontact.linalg import MatrixHints, SaddlePoint, krylov, make_solver


def _saddle(m=40, k=12, seed=0, c=0.0):
    """A random sparse symmetric saddle-point matrix [[A, B^T], [B, -c I]] with A SPD and B of full rank."""
    rng = np.random.default_rng(seed)
    L = sp.random(m, m, density=0.1, random_state=seed) + sp.eye(m)
    A = (L @ L.T + m * sp.eye(m)).tocsr()
    B = sp.csr_matrix(rng.standard_normal((k, m)))
    K = sp.bmat([[A, B.T], [B, -c * sp.eye(k) if c else None]], format="csr")
    S = (B @ np.linalg.inv(A.toarray()) @ B.T.toarray()) + c * np.eye(k)
    return K, A, B, S


@pytest.mark.parametrize("c", [0.0, 0.3])
def test_minres_solves_a_saddle_point_system_as_the_direct_solve(c):
    K, A, _, S = _saddle(c=c)
    n = K.shape[0]
    b = np.random.default_rng(1).standard_normal(n)
    # SPD block-diagonal preconditioner with the exact blocks
    Ainv, Sinv = np.linalg.inv(A.toarray()), np.linalg.inv(S)
    M = sp.block_diag([sp.csr_matrix(Ainv), sp.csr_matrix(Sinv)]).tocsr()
    x, it, why = krylov.minres(K, b, M, 1e-12, 500)
    ref = np.linalg.solve(K.toarray(), b)
    assert why == ""
    assert np.max(np.abs(x - ref)) <= 1e-9 * np.max(np.abs(ref))
    # exact blocks: the preconditioned matrix has the 3 eigenvalues 1, (1 +- sqrt 5)/2 (c = 0)
    assert it <= (4 if c == 0.0 else n)
    # without a preconditioner: at most n iterations (plus round-off)
    x2, it2, why2 = krylov.minres(K, b, sp.eye(n), 1e-10, 4 * n)
    assert why2 == "" and np.max(np.abs(x2 - ref)) <= 1e-7 * np.max(np.abs(ref))


def test_minres_reports_an_indefinite_preconditioner_and_maxiter():
    K, *_ = _saddle()
    n = K.shape[0]
    b = np.ones(n)
    _, _, why = krylov.minres(K, b, -sp.eye(n), 1e-10, 50)
    assert why == "indefinite preconditioner"
    _, it, why = krylov.minres(K, b, sp.eye(n), 1e-14, 3)
    assert (it, why) == (3, "maxiter")
    x, it, why = krylov.minres(K, np.zeros(n), sp.eye(n), 1e-10, 3)
    assert (it, why) == (0, "") and not np.any(x)


def test_saddle_point_validates_its_blocks():
    with pytest.raises(InputError, match="positive"):
        SaddlePoint(3, np.array([1.0, 0.0]))
    with pytest.raises(InputError, match="primal"):
        SaddlePoint(-1, np.array([1.0]))
    assert SaddlePoint(3, [1.0, 2.0]).n == 5


def test_amg_on_a_marked_saddle_point_matrix_builds_the_block_preconditioner():
    """``make_solver("amg").factorize(K, MatrixHints(saddle=...))``: a hierarchy of the primal block only, MINRES
    solves to its tolerance, and GMRES with the block-triangular variant needs 2 iterations when the blocks are
    exact (a primal block below AMG's coarse size is factorized exactly by its coarsest level)."""
    K, A, _, S = _saddle(m=60, k=15, c=0.0)
    saddle = SaddlePoint(60, np.diag(S).copy())
    f = make_solver("amg").factorize(K, MatrixHints(saddle=saddle))
    assert not f.exact and f.name == "amg" and f.primal.A.shape == (60, 60)
    b = np.random.default_rng(2).standard_normal(K.shape[0])
    ref = np.linalg.solve(K.toarray(), b)
    x = f.solve(b)
    assert np.max(np.abs(x - ref)) <= 1e-7 * np.max(np.abs(ref))
    assert f.iterations > 0  # its solves ran MINRES


def test_block_triangular_preconditioner_with_exact_blocks_makes_gmres_converge_in_two_iterations():
    """A = a I and B with orthogonal rows: S = B B^T / a is diagonal, so SaddlePoint(schur=diag S) is exact and the
    primal block (below AMG's coarse size) is factorized exactly: GMRES ends in 2 iterations (+1 for round-off)."""
    m, k, a = 30, 6, 3.0
    Q, _ = np.linalg.qr(np.random.default_rng(3).standard_normal((m, k)))
    B = sp.csr_matrix((Q * np.arange(1.0, k + 1.0)).T)
    K = sp.bmat([[a * sp.eye(m), B.T], [B, None]], format="csr")
    S = np.diag((B @ B.T).toarray()) / a
    f = make_solver("amg").factorize(K, MatrixHints(saddle=SaddlePoint(m, S)))
    b = np.random.default_rng(4).standard_normal(m + k)
    x, it, info = krylov.gmres(K, b, krylov.gmres_preconditioner(f), rtol=1e-10, restart=50, maxiter=5)
    assert info == 0 and it <= 3
    assert np.max(np.abs(K @ x - b)) <= 1e-8 * np.max(np.abs(b))
    # the block-diagonal one (for MINRES) is another operator: GMRES needs more iterations with it
    _, it_diag, _ = krylov.gmres(K, b, krylov.preconditioner(f), rtol=1e-10, restart=50, maxiter=5)
    assert it_diag > it


def test_saddle_point_factor_refuses_a_matrix_of_another_size():
    K, *_ = _saddle(m=20, k=5)
    with pytest.raises(InputError, match="saddle-point matrix of shape"):
        make_solver("amg").factorize(K, MatrixHints(saddle=SaddlePoint(19, np.ones(5))))
