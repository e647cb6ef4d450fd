"""The frictional setup is the frictionless one extended (issue 9): one factorization path, one operator build.

``FrictionalContact`` derives from ``CondensedContact`` like ``DiscreteContact``: the same
points, candidates, factorization (backend, Schur block) and condensed-operator build, with
the row operator ``P`` (every free component of a point) instead of ``B`` (its normal).

Reaches inside the package: the Schur thresholds of ``contact.systems._condensed``
(``SCHUR_MIN_DOFS``, ``SCHUR_WINDOW``, ``SCHUR_MAX_DOFS``) are internal cost rules, no option; the
test sets them to reach the Schur path on a small model.
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact.contact.systems import CondensedContact, DiscreteContact
from alcontact.contact.systems import FrictionalContact
from alcontact.contact.problem import LoadHistory, problem_at
from alcontact.linalg import is_installed
from alcontact.problems import friction as fp

CASES = {
    "block-2d": lambda: fp.block_on_plane(dim=2, n=4),
    "mindlin-2d": lambda: fp.cattaneo_mindlin_2d(n_per_a=4),
    "sphere-3d-held": lambda: fp.sphere_shear_3d(n_per_a=2, growth=1.6),
}


def test_both_setups_share_the_condensed_base():
    assert issubclass(FrictionalContact, CondensedContact) and issubclass(DiscreteContact, CondensedContact)
    for name in ("_factorize", "_stabilize", "_setup_points", "_select_candidates", "_condensed", "_setup_schur"):
        assert name not in FrictionalContact.__dict__ or name == "_stabilize", name  # _stabilize: docs only


@pytest.mark.parametrize("case", list(CASES))
def test_normal_block_of_the_frictional_compliance_is_the_delassus_operator(case):
    """A_NN = S = B K^{-1} B^T on the same candidates (module doc of alcontact.contact.systems._condensed).

    Reference: the frictionless DiscreteContact of the problem at the last step time
    (``problem_at``: the same supported DOFs, so the same K), its S extended to the
    frictional candidates. Tolerance: relative 1e-12 in the max norm (two builds with one factor).
    """
    prob, hist = CASES[case]()
    fc = FrictionalContact(prob, hist)
    assert fc.ncand >= 3
    dc = DiscreteContact(problem_at(prob, hist, hist.times[-1]))
    np.testing.assert_array_equal(dc.points, fc.points)
    np.testing.assert_array_equal(dc.movable, fc.movable)
    dc._add_columns(fc.cand)
    where = {p: i for i, p in enumerate(dc.cand)}
    k = np.array([where[p] for p in fc.cand])
    S = dc.S[np.ix_(k, k)]
    d = fc.dim
    A_nn = fc.A[::d, ::d]
    assert np.max(np.abs(A_nn - S)) <= 1e-12 * np.max(np.abs(S))


def test_held_tangent_directions_get_no_solve_and_no_compliance():
    """sphere-3d: points on the symmetry plane y = 0 hold u_y; P has a zero row there.

    Reference: one triangular solve per free DOF of the candidates (plus one per load
    component), and zero rows/columns of A in the held tangent direction (exact).
    """
    prob, hist = CASES["sphere-3d-held"]()
    fc = FrictionalContact(prob, hist)
    free_dofs = int(np.sum(fc.pos[fc.cand] >= 0))
    assert free_dofs < fc.ncand * fc.dim  # some candidates hold a component
    assert fc.linear_solves == fc.u_parts.shape[0] + free_dofs
    held = ~fc.tfree[fc.cand]  # (c, d-1)
    assert np.any(held)
    rows = (np.arange(fc.ncand)[:, None] * fc.dim + 1 + np.arange(fc.dim - 1))[held]
    assert np.all(fc.A[rows] == 0.0) and np.all(fc.A[:, rows] == 0.0)


@pytest.mark.skipif(not is_installed("mkl-pardiso"), reason="MKL PARDISO (pypardiso) missing")
@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("cap", [None, 3])
def test_frictional_compliance_from_the_schur_complement(case, cap, monkeypatch):
    """A from PARDISO's Schur complement (the frictionless Schur path, now shared) equals the solve build.

    ``cap``: the Schur block capped to 3 points, so candidates outside it are built with
    triangular solves and their cross terms with the block from the kept solves (hybrid).
    Reference: the SuperLU triangular-solve build; tolerance relative 1e-9 in the max norm
    (round-off of two direct factorizations of the same SPD matrix).
    """
    import alcontact.contact.systems._condensed as discrete

    monkeypatch.setattr(discrete, "SCHUR_MIN_DOFS", 0)
    monkeypatch.setattr(discrete, "SCHUR_WINDOW", 2.0)  # a block wide enough to hold every candidate uncapped
    prob, hist = CASES[case]()
    if cap is not None:
        monkeypatch.setattr(discrete, "SCHUR_MAX_DOFS", cap * prob.model.dim)
    schur = FrictionalContact(prob, hist, linear_solver="mkl-pardiso")
    assert schur._schur is not None
    prob.model.clear_factorization()
    tri = FrictionalContact(prob, hist, linear_solver="superlu")
    assert tri._schur is None
    np.testing.assert_array_equal(schur.cand, tri.cand)
    inside = schur._schur[2].reshape(-1, schur.dim)[:, 0]
    n_out = int(np.sum(~inside[schur.cand]))
    if cap is None:
        assert n_out == 0 and schur.linear_solves == schur.u_parts.shape[0]  # no solve for the compliance
    else:
        assert 0 < n_out < schur.ncand
    assert np.max(np.abs(schur.A - tri.A)) < 1e-9 * np.max(np.abs(tri.A))
    # candidates added later (inside and outside the block) keep the equality
    rest = np.setdiff1d(np.flatnonzero(tri.movable), tri.cand)
    rest = rest[np.argsort(-tri.gap0[rest], kind="stable")][:4]
    schur.add(rest)
    tri.add(rest)
    np.testing.assert_array_equal(schur.cand, tri.cand)
    assert np.max(np.abs(schur.A - tri.A)) < 1e-9 * np.max(np.abs(tri.A))


def test_linear_solver_reaches_the_frictional_factorization():
    """The backend choice of the frictionless path now applies to the frictional setup too."""
    prob, hist = CASES["block-2d"]()
    fc = FrictionalContact(prob, hist, linear_solver="superlu")
    assert fc.factor.backend == "superlu"
    assert isinstance(hist, LoadHistory)
