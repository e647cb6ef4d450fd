"""Delassus operator from PARDISO's Schur complement versus the triangular-solve build.

Reaches inside the package: the Schur thresholds of ``contact.systems._condensed``
(``SCHUR_MIN_DOFS``, ``SCHUR_WINDOW``, ``SCHUR_MAX_DOFS``) are internal cost rules, no option; the
test sets them to reach (or avoid) the Schur path on a small model.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from alcontact.contact import solve
from alcontact.contact.systems import DiscreteContact
from alcontact.linalg import MatrixHints, is_installed, make_solver
from alcontact.problems import hertz

pytestmark = pytest.mark.skipif(not is_installed("mkl-pardiso"), reason="MKL PARDISO (pypardiso) missing")

CASES = {
    "2d-p1": lambda: hertz.hertz_2d(order=1, n_per_a=6, growth=1.3),
    "2d-p2": lambda: hertz.hertz_2d(order=2, n_per_a=4, growth=1.3),
    "3d-p1": lambda: hertz.hertz_3d(order=1, n_per_a=2, growth=1.5),
    "3d-p2": lambda: hertz.hertz_3d(order=2, n_per_a=1, growth=2.0, size=6.0),
}


@pytest.fixture(autouse=True)
def _schur_for_small_problems(monkeypatch):
    """These meshes are smaller than the default SCHUR_MIN_DOFS: lift the limit. The window is pinned
    at two element sizes so that the block holds non-candidate points for the ``extend`` checks."""
    import alcontact.contact.systems._condensed as discrete

    monkeypatch.setattr(discrete, "SCHUR_MIN_DOFS", 0)
    monkeypatch.setattr(discrete, "SCHUR_WINDOW", 2.0)


@pytest.mark.parametrize("case", list(CASES))
def test_schur_delassus_equals_triangular_solves(case):
    """S = B_c S_c^{-1} B_c^T (Schur complement) equals B K^{-1} B^T (triangular solves).

    Reference: the same operator built column by column with SuperLU triangular solves.
    Tolerance: relative 1e-9 in the max norm (round-off of two direct factorizations of
    the same SPD matrix); the Schur path must use no triangular solve for S.
    """
    prob = CASES[case]()
    schur = DiscreteContact(prob, linear_solver="mkl-pardiso")
    assert schur._schur is not None
    assert schur.linear_solves == 1  # only the contact-free solve
    prob.model.clear_factorization()
    tri = DiscreteContact(prob, linear_solver="superlu")
    assert tri._schur is None
    assert tri.linear_solves == 1 + tri.cand.size
    np.testing.assert_array_equal(schur.cand, tri.cand)
    assert schur.cand.size >= 3
    err = np.max(np.abs(schur.S - tri.S)) / np.max(np.abs(tri.S))
    assert err < 1e-9, err
    # added candidates (extend) inside the block come from the Schur complement too, cross terms included
    block = schur._schur[2]
    outside = np.setdiff1d(np.flatnonzero(schur.movable & block), schur.cand)[:4]
    assert outside.size >= 2
    schur._add_columns(outside)
    tri._add_columns(outside)
    assert schur.linear_solves == 1
    err = np.max(np.abs(schur.S - tri.S)) / np.max(np.abs(tri.S))
    assert err < 1e-9, err


def test_pardiso_schur_complement_and_full_solve():
    """PARDISO's Schur block equals K_cc - K_ci K_ii^{-1} K_ic, and solves stay full solves.

    Reference: the dense formula on a small SPD matrix (2D Laplacian plus identity);
    tolerance relative 1e-10; the solve residual ||Kx - b|| / ||b|| < 1e-10.
    """
    n1 = 12
    T = sp.diags([-np.ones(n1 - 1), 2 * np.ones(n1), -np.ones(n1 - 1)], [-1, 0, 1])
    K = (sp.kron(T, sp.eye(n1)) + sp.kron(sp.eye(n1), T) + sp.eye(n1 * n1)).tocsr()
    c = np.array([3, 17, 40, 41, 100, 143])
    fac = make_solver("mkl-pardiso").factorize(K, MatrixHints(schur=c))
    np.testing.assert_array_equal(fac.schur_indices, c)
    Kd = K.toarray()
    i = np.setdiff1d(np.arange(K.shape[0]), c)
    ref = Kd[np.ix_(c, c)] - Kd[np.ix_(c, i)] @ np.linalg.solve(Kd[np.ix_(i, i)], Kd[np.ix_(i, c)])
    assert np.max(np.abs(fac.schur_complement - ref)) < 1e-10 * np.max(np.abs(ref))
    b = np.random.default_rng(0).standard_normal((K.shape[0], 2))
    x = fac.solve(b)
    assert np.linalg.norm(K @ x - b) < 1e-10 * np.linalg.norm(b)


def test_schur_and_triangular_paths_give_the_same_contact_solution():
    """The full SSN solve gives the same pressures with PARDISO (Schur) and SuperLU (solves).

    Reference: the SuperLU run; tolerance relative 1e-8 on the peak pressure and the normal force.
    """
    prob = CASES["2d-p1"]()
    a = solve(prob, "ssn", None, linear_solver="mkl-pardiso")
    prob.model.clear_factorization()
    b = solve(prob, "ssn", None, linear_solver="superlu")
    assert a.result.status.label == b.result.status.label == "converged"
    assert a.result.linear_solves == 2 < b.result.linear_solves  # the Schur path ran
    assert a.peak_pressure == pytest.approx(b.peak_pressure, rel=1e-8)
    assert a.normal_force == pytest.approx(b.normal_force, rel=1e-8)


def test_small_models_are_factorized_without_schur_block(monkeypatch):
    """Below SCHUR_MIN_DOFS no Schur block is asked: triangular solves, one per candidate.

    Reference: one solve per candidate plus the contact-free solve (exact count).
    """
    import alcontact.contact.systems._condensed as discrete

    prob = CASES["2d-p1"]()
    monkeypatch.setattr(discrete, "SCHUR_MIN_DOFS", prob.model.ndofs + 1)
    dc = DiscreteContact(prob, linear_solver="mkl-pardiso")
    assert dc._schur is None and dc.factor.factor.schur_complement is None
    assert dc.linear_solves == 1 + dc.cand.size


def test_candidates_outside_a_capped_schur_block_fall_back_to_triangular_solves(monkeypatch):
    """A Schur block smaller than the candidate set: S still equals B K^{-1} B^T.

    With ``SCHUR_MAX_DOFS`` capped to 3 points, the candidates outside the block are built
    with triangular solves (one per candidate, hybrid build), the block keeps the points
    closest to the obstacle. Reference: the SuperLU triangular-solve build; tolerance relative 1e-9.
    """
    import alcontact.contact.systems._condensed as discrete

    prob = CASES["2d-p1"]()
    monkeypatch.setattr(discrete, "SCHUR_MAX_DOFS", 3 * prob.model.dim)
    capped = DiscreteContact(prob, linear_solver="mkl-pardiso")
    assert capped._schur is not None and int(np.sum(capped._schur[2])) == 3
    assert capped.linear_solves == 1 + capped.cand.size - 3  # solves only outside the block
    prob.model.clear_factorization()
    tri = DiscreteContact(prob, linear_solver="superlu")
    np.testing.assert_array_equal(capped.cand, tri.cand)
    assert np.max(np.abs(capped.S - tri.S)) < 1e-9 * np.max(np.abs(tri.S))


@pytest.mark.parametrize("case", ["2d-p1", "3d-p1"])
def test_hybrid_build_with_points_inside_and_outside_the_block(case, monkeypatch):
    """Hybrid S (block entries from S_c, the rest from kept solves) equals B K^{-1} B^T.

    The block holds every other initial candidate plus 3 non-candidates; the initial S mixes
    both kinds, then block points and outside points are added (``extend``), each time with
    one triangular solve per outside point only. Reference: the SuperLU triangular-solve
    build of the same candidate sequence; tolerance relative 1e-9 in the max norm.
    """
    prob = CASES[case]()
    tri = DiscreteContact(prob, linear_solver="superlu")
    prob.model.clear_factorization()
    rest = np.setdiff1d(np.flatnonzero(tri.movable), tri.cand)
    rest = rest[np.argsort(-tri.gap0[rest], kind="stable")]  # closest first
    block_pts = np.concatenate([tri.cand[::2], rest[:3]])
    free = np.ones(prob.model.ndofs, dtype=bool)
    free[tri.fixed] = False
    block_dofs = tri.dofs[block_pts].ravel()
    monkeypatch.setattr(DiscreteContact, "_schur_request",
                        lambda self, problem, margin: {"schur": np.unique(block_dofs[free[block_dofs]])})
    hyb = DiscreteContact(prob, linear_solver="mkl-pardiso")
    np.testing.assert_array_equal(hyb.cand, tri.cand)
    inside = hyb._schur[2]
    assert np.all(inside[block_pts]) and int(np.sum(inside)) == block_pts.size
    n_out = int(np.sum(~inside[hyb.cand]))
    assert 0 < n_out < hyb.cand.size
    assert hyb.linear_solves == 1 + n_out
    assert np.max(np.abs(hyb.S - tri.S)) < 1e-9 * np.max(np.abs(tri.S))
    for add, solves in ((rest[:3], 0), (rest[3:5], 2), (rest[5:6], 1)):  # block, outside, outside
        before = hyb.linear_solves
        hyb._add_columns(add)
        tri._add_columns(add)
        assert hyb.linear_solves == before + solves
        np.testing.assert_array_equal(hyb.cand, tri.cand)
        assert np.max(np.abs(hyb.S - tri.S)) < 1e-9 * np.max(np.abs(tri.S))
