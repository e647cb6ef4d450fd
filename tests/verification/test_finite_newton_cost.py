r"""Cost of the finite-deformation Newton solves: iterations per load step and the reused analysis.

Problem: :func:`alcontact.problems.half_cylinder.half_cylinder` ``(n=8, order=2)``
(neo-Hookean, plane strain, 578 DOFs) pressed to :math:`\delta/R = 0.4` in 20 load steps,
the setting of ``benchmarks/finite.py`` on a coarse mesh.

References (measured, then asserted; the issue's target is at most 5 Newton systems per
load step on average for the reference and for Algorithm 6.1). The issue's target is the one
count asserted here (a documented promise); the finer counts below ("asserted: <= 4" and the
like) are recorded instead, each with its former bound, by ``benchmarks/newton_counts.py``
(``docs/benchmarks/newton_counts.md``). What stays asserted is what the options must do
(more solves with the tangent predictor, more Newton with exact subproblems, chord steps taken)
and the forces against the reference:

- reference ``ssn``: 3.25 Newton systems per load step; asserted: mean <= 5;
- Algorithm 6.1 (``simo-laursen``) with inexact subproblems (Newton tolerance
  ``min(1e-3 dlam, dlam**2)`` of the last multiplier change, the last one to
  ``newton_tol``) and the second-order multiplier update
  (:meth:`FiniteContact.multiplier_step`): 4.55 per step; asserted: mean <= 5. Every
  subproblem to ``newton_tol`` (option ``subproblems = "exact"``): 5.9 (asserted: more, same
  forces within 1e-8, the stopping tolerance); first-order (Macaulay) updates as well: more
  (11.2 at n=24, not asserted). All give the same force at every step within 1e-8 relative, and the
  reference's within 1e-6;
- the secant predictor (:meth:`FiniteContact.configure`: linear extrapolation of the state and
  the pressures from the last two converged steps, no assembly) with the entry rule of the
  starting active set (:meth:`FiniteContact.initial_active`), the primal correction of the
  dual step and the physical stopping test of Algorithm 6.1: 3.75 Newton and 3.80 assembly +
  solves per load step for both algorithms (the first step runs the tangent predictor);
  asserted: both means <= 4. With the tangent predictor (option ``predictor = "tangent"``): 3.25
  Newton but 4.25 assembly + solves per step (asserted: more assembly + solves, forces within 1e-9
  relative); without the primal correction Algorithm 6.1 needed 4.2 Newton per step (that variant
  was removed). On the n=24 mesh the entry rule takes the reference from 4.6 to 4.1 Newton per step
  (asserted, slow: <= 4.5);
- the entry rule on the secant prediction for Algorithm 6.1
  (:meth:`FiniteContact.entry_multipliers`: a point predicted to penetrate without predicted
  pressure that :meth:`FiniteContact.initial_active` keeps out of the starting set starts the
  first subproblem with zero traction, :math:`\lambda_i = -g_i/\eta_i`): on ``n=24`` pressed
  in 8 steps of the 20-step path (:math:`\delta/R = 0.16`) Algorithm 6.1 takes 6 Newton systems
  in step 1 (tangent predictor) and 4 in each later step, 4.25 on average (without the
  rule: 5.125, 5 per later step); asserted: mean <= 4.5 and <= 4 per step from step 2 on,
  forces within 1e-6 of the reference. Over the whole 20-step path on ``n=24`` (measured, not asserted, to keep the
  suite short): 4.15 (4.65 without);
- the semi-smooth dual step (the points the entry shift kept out that still penetrate after the
  first subproblem enter the active set of :meth:`FiniteContact.multiplier_step` and its primal
  correction): on ``n=8`` 3.65 Newton per step (3.75 without). At n=88 (62 658 DOFs)
  6.65 -> 5.45 (``docs/benchmarks/finite.md``);
- chord steps near convergence (a subproblem whose relative
  residual is already below 1e-9 takes its next correction with the factor at hand, one
  back-substitution and no assembly, counted in ``chord_steps`` and not as a Newton system):
  Algorithm 6.1 on ``n=8`` (20 steps) 3.10 Newton systems per step (3.65 without: the last
  subproblem of a step, started at 1e-10 relative by the primal correction, took a Newton
  system); asserted: mean <= 3.25 and chord steps recorded. At n=88
  (62 658 DOFs) 5.45 -> 4.75 (``docs/benchmarks/finite.md``);
- the entry rule on the tangent prediction of a first contact (in step 1 no point is pressed,
  the predictor has no springs and every predicted penetration was loaded): step 1 on ``n=8``
  takes 4 Newton systems for both algorithms (5 without); asserted: <= 4;
- a 3D case, :func:`alcontact.problems.hemisphere.hemisphere` ``(n=4, order=1)`` (375 DOFs,
  delta/R = 0.2 in 5 steps): both algorithms converge with at most 4 assembly + solves per
  step on average (measured 3.2 and 3.2) and the same force within 1e-6 relative;
- :class:`~alcontact.contact.systems._full_space.NewtonSolver` (MKL PARDISO, symmetric indefinite)
  solves symmetric positive definite and saddle-point systems to the residual of a
  direct solve (1e-10 relative asserted) and analyses a pattern once: the saddle-point
  matrix of the reference has one pattern for the whole run (a row per movable contact
  point), so the run needs at most two analyses, the tangent's and the saddle point's
  (asserted: analyses <= 2).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from alcontact.contact import solve_finite
from alcontact.contact.systems import NewtonSolver
from alcontact.problems.half_cylinder import half_cylinder

STEPS = 20


def test_reference_needs_at_most_five_newton_per_step(half_cylinder_8_ssn):
    """Mean Newton systems per load step of ``ssn`` <= 5 (module doc)."""
    mean = np.mean([s.newton_iterations for s in half_cylinder_8_ssn.steps])
    assert len(half_cylinder_8_ssn.steps) == STEPS
    assert mean <= 5.0, mean


def test_reference_analyses_once_per_candidate_set(half_cylinder_8_ssn):
    """The direct solver's symbolic analysis is reused inside a load step (module doc)."""
    extra = half_cylinder_8_ssn.solution.extra
    if extra["linear_solver"] != "mkl-pardiso":
        pytest.skip("MKL PARDISO not installed: SuperLU factorizes every system")
    assert extra["analyses"] <= STEPS + 1, extra["analyses"]
    assert extra["analyses"] <= 2, extra["analyses"]
    assert half_cylinder_8_ssn.solution.result.linear_solves > 3 * extra["analyses"]


@pytest.fixture(scope="module")
def algorithm_6_1(half_cylinder_8):
    fs = solve_finite(half_cylinder_8, "simo-laursen", steps=STEPS)
    assert fs.success, fs.message
    return fs


def test_algorithm_6_1_needs_at_most_five_newton_per_step(algorithm_6_1, half_cylinder_8_ssn):
    """Algorithm 6.1: mean <= 5 Newton per step, forces of the reference within 1e-6 (module doc)."""
    fs = algorithm_6_1
    mean = np.mean([s.newton_iterations for s in fs.steps])
    assert mean <= 5.0, mean
    ref = half_cylinder_8_ssn.forces[:, 1]
    assert np.max(np.abs(fs.forces[:, 1] - ref) / ref) <= 1e-6


@pytest.mark.slow
def test_exact_subproblems_cost_more(half_cylinder_8, algorithm_6_1):
    """Option ``subproblems = "exact"``: more Newton per step, same forces within 1e-8 (module doc).

    1e-8 is the stopping tolerance: the exact run stops step 3 at a penetration of 5.1e-9 h
    (tolerance 1e-8 h), its force 3.7e-9 relative from the inexact one.
    """
    fs = algorithm_6_1
    mean = np.mean([s.newton_iterations for s in fs.steps])
    exact = solve_finite(half_cylinder_8, "simo-laursen", steps=STEPS, subproblems="exact")
    assert exact.success, exact.message
    assert np.mean([s.newton_iterations for s in exact.steps]) > mean
    assert np.max(np.abs(fs.forces[:, 1] - exact.forces[:, 1]) / exact.forces[:, 1]) <= 1e-8


@pytest.mark.parametrize("use_pardiso", [True, False])
@pytest.mark.parametrize("saddle", [False, True])
def test_newton_solver_matches_a_direct_solve(saddle, use_pardiso):
    """Residual of NewtonSolver <= 1e-10 relative on SPD and saddle-point systems; one analysis per pattern."""
    rng = np.random.default_rng(3)
    n = 300
    A = sp.random(n, n, 0.02, random_state=4)
    A = (A + A.T + 8.0 * sp.eye(n)).tocsr()
    if saddle:
        B = sp.random(12, n, 0.05, random_state=5) + sp.eye(12, n)
        A = sp.bmat([[A, B.T], [B, None]], format="csc")
    solver = NewtonSolver(use_pardiso=use_pardiso)
    for scale in (1.0, 2.0, 0.5):
        M = A * scale
        b = rng.standard_normal(M.shape[0])
        x = solver.solve(M, b)
        assert np.max(np.abs(M @ x - b)) <= 1e-10 * np.max(np.abs(b))
    if solver.backend == "mkl-pardiso":
        assert solver.analyses == 1 and solver.factorizations == 3
    else:
        assert solver.analyses == 0 and solver.factorizations == 0


def test_newton_solver_reports_a_singular_matrix():
    """A zero matrix raises numpy.linalg.LinAlgError (the Newton loops turn it into a failed status)."""
    Z = sp.csr_matrix((5, 5))
    with pytest.raises(np.linalg.LinAlgError):
        NewtonSolver().solve(Z, np.ones(5))


def _mean(fs, what):
    return float(np.mean([getattr(s, what) for s in fs.steps]))


@pytest.mark.parametrize("algorithm", ["ssn", "simo-laursen"])
def test_tangent_predictor_costs_more_solves(half_cylinder_8, half_cylinder_8_ssn, algorithm_6_1, algorithm):
    """Option ``predictor = "tangent"`` instead of the secant predictor: more assembly + solves per step,
    forces within 1e-9 (module doc)."""
    fs = half_cylinder_8_ssn if algorithm == "ssn" else algorithm_6_1
    tangent = solve_finite(half_cylinder_8, algorithm, steps=STEPS, predictor="tangent")
    assert tangent.success, tangent.message
    assert _mean(tangent, "linear_solves") > _mean(fs, "linear_solves")
    assert np.max(np.abs(fs.forces[:, 1] - tangent.forces[:, 1]) / tangent.forces[:, 1]) <= 1e-9


def test_hemisphere_3d_algorithms_agree():
    """3D hemisphere quarter (module doc): both algorithms converge, same force to 1e-6 (their assembly + solves
    per step: ``benchmarks/newton_counts.py``)."""
    from alcontact.problems.hemisphere import hemisphere

    prob = hemisphere(4, order=1)
    runs = [solve_finite(prob, alg, steps=5) for alg in ("ssn", "simo-laursen")]
    for fs in runs:
        assert fs.success, fs.message
        assert len(fs.steps) == 5
    f_ref, f_al = runs[0].forces[:, 1], runs[1].forces[:, 1]
    assert np.all(f_ref > 0)
    assert np.max(np.abs(f_al - f_ref) / f_ref) <= 1e-6


def test_entry_rule_on_the_prediction_keeps_algorithm_6_1_on_the_reference():
    """n=24, 8 of the 20 steps: Algorithm 6.1 converges with the reference's forces within 1e-6 (module doc; its
    Newton per step: ``benchmarks/newton_counts.py --full``)."""
    prob = half_cylinder(24, order=2, delta=0.4 * 8 / STEPS, curved=False)  # as measured (conftest)
    ruled = solve_finite(prob, "simo-laursen", steps=8)
    assert ruled.success, ruled.message
    assert len(ruled.steps) == 8
    ref = solve_finite(prob, "ssn", steps=8)
    assert ref.success, ref.message
    assert np.max(np.abs(ruled.forces[:, 1] - ref.forces[:, 1]) / ref.forces[:, 1]) <= 1e-6



def test_chord_steps_near_convergence_are_taken(algorithm_6_1):
    """Algorithm 6.1 takes chord steps below 1e-9 relative on n=8 (module doc).

    Reference: the fixture run (measured 3.10 Newton systems per step, 20 steps, some chord
    steps; 3.65 without chord steps, a variant since removed). Asserted: chord steps recorded (the
    Newton systems per step, formerly asserted <= 3.25: ``benchmarks/newton_counts.py``).
    """
    assert algorithm_6_1.solution.extra["chord_steps"] > 0
