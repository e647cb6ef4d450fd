r"""Finite-deformation contact on the AMG + CG path (``linear_solver="amg"``) against the direct path.

Problems: :func:`alcontact.problems.half_cylinder.half_cylinder` (plane strain, P1 ``n = 8``
and P2 ``n = 4``, pressed to :math:`\delta/R = 0.4` in 4 load steps) and
:func:`alcontact.problems.hemisphere.hemisphere` (3D quarter, P1 ``n = 4``, :math:`\delta/R =
0.2` in 3 steps). The AMG hierarchies are forced to several levels on these small meshes
(coarsest level at most 40 rows instead of 500), so that the V-cycle, not the coarse LU,
preconditions CG.

Reference: the same run on the direct path (MKL PARDISO factor of every Newton matrix).
CG tolerances of :class:`~alcontact.contact.systems._full_space.AMGNewtonSolver`: the Newton
steps to the Eisenstat-Walker forcing term (at least 1e-12 relative, at most 0.1), the products
of the dual multiplier step to 1e-2, the other solves (predictor) to 1e-10 relative; the Newton tolerance is the
default 1e-12. Asserted for Algorithm 6.1 (``simo-laursen``), Algorithm 6.3 with
``exp-met1`` and the pure penalty:

- the contact force of every load step and the final displacement within **1e-8 relative**
  of the direct path (measured: forces 1e-16 to 2.9e-9, displacements 1e-16 to 1.8e-9; the
  multipliers follow the inexact dual steps, the displacements the subproblems solved to 1e-12);
- the same load steps (no cut-back), and at most **2 more Newton iterations per load step on
  average** (measured: 0 to 1.0 more, simo-laursen on the half-cylinder P2, whose dual steps
  are inexact here);
- ``solution.extra["linear_solver"]`` names the solver that ran (its registry name).
"""

from __future__ import annotations

import numpy as np
import pytest

from alcontact import linalg
from alcontact.contact import solve_finite
from alcontact.contact.systems import _full_space as fi
from alcontact.problems.half_cylinder import half_cylinder
from alcontact.problems.hemisphere import hemisphere

CASES = {
    "cylinder-p1": (lambda: half_cylinder(8), 4),
    "cylinder-p2": (lambda: half_cylinder(4, order=2), 4),
    "hemisphere-p1": (lambda: hemisphere(4), 3),
}
ALGORITHMS = {"simo-laursen": ("simo-laursen", None), "exp-met1": ("family-p", "exp-met1"),
              "penalty": ("penalty", None)}
#: default-suite cases (the others are marked slow)
FAST = {("cylinder-p1", "simo-laursen"), ("cylinder-p2", "exp-met1"), ("hemisphere-p1", "simo-laursen"),
        ("cylinder-p1", "penalty")}

RUNS = [pytest.param(c, a, marks=() if (c, a) in FAST else pytest.mark.slow) for c in CASES for a in ALGORITHMS]


#: a registered AMG solver whose coarsest level has at most 40 rows (the built-in "amg": 500)
MULTILEVEL = "amg-multilevel"


@pytest.fixture
def multilevel():
    """Coarsest AMG level at most 40 rows: hierarchies of several levels on the small test meshes
    (a registered iterative solver, ``linear_solver = MULTILEVEL``)."""
    linalg.register_solver(MULTILEVEL, lambda: linalg.AMGSolver(max_coarse=40), kind="iterative")
    yield MULTILEVEL
    linalg.unregister_solver(MULTILEVEL)


def _amg_newton(fc, **kw):
    """The AMG + CG Newton solver of ``fc`` with the :data:`MULTILEVEL` solver."""
    solver = linalg.select_solver(MULTILEVEL, dim=fc.model.dim, ndofs=fc.model.ndofs)
    return fi.AMGNewtonSolver(fc, solver=solver, **kw)


@pytest.mark.parametrize("case,algorithm", RUNS)
def test_amg_path_reproduces_the_direct_path(multilevel, case, algorithm):
    """Forces and displacements within 1e-8 relative, same steps, Newton within +2 per step (module doc)."""
    make, steps = CASES[case]
    alg, pen = ALGORITHMS[algorithm]
    direct = solve_finite(make(), alg, pen, steps=steps, linear_solver="direct")
    amg = solve_finite(make(), alg, pen, steps=steps, linear_solver=multilevel)
    assert direct.success, direct.message
    assert amg.success, amg.message
    assert linalg.solver_kind(direct.solution.extra["linear_solver"]) == "direct"
    ex = amg.solution.extra
    assert ex["linear_solver"] == MULTILEVEL and ex["strategy"] == direct.solution.extra["strategy"] == "full-space-newton"
    assert ex["amg_levels"] >= 2 and ex["amg_setups"] >= 1 and ex["cg_iterations"] > 0
    assert ex["direct_fallbacks"] == 0
    # same load steps, no cut-back
    assert np.array_equal(amg.times, direct.times)
    assert all(s.cutbacks == 0 for s in amg.steps)
    # force of every step and final displacement
    f_ref = direct.forces[:, 1]
    assert np.all(f_ref > 0)
    assert np.max(np.abs(amg.forces - direct.forces)) <= 1e-8 * np.max(np.abs(f_ref))
    assert np.max(np.abs(amg.forces[:, 1] - f_ref) / f_ref) <= 1e-8
    u_ref = direct.solution.u
    assert np.max(np.abs(amg.solution.u - u_ref)) <= 1e-8 * np.max(np.abs(u_ref))
    # Newton iterations: at most 2 more per load step on average
    n_dir = sum(s.newton_iterations for s in direct.steps)
    n_amg = sum(s.newton_iterations for s in amg.steps)
    assert (n_amg - n_dir) / len(direct.steps) <= 2.0, (n_amg, n_dir)


def test_hierarchy_is_reused_across_newton_iterations(multilevel):
    """One AMG hierarchy serves several Newton systems: setups <= half the Newton iterations
    (half-cylinder P1 n = 8, simo-laursen, 4 steps; measured 5 setups for 21 Newton steps)."""
    fs = solve_finite(half_cylinder(8), "simo-laursen", steps=4, linear_solver=multilevel)
    assert fs.success, fs.message
    ex = fs.solution.extra
    assert 1 <= ex["amg_setups"] <= ex["newton_total"] / 2
    assert ex["cg_solves"] > ex["amg_setups"]


def test_ssn_has_no_amg_path():
    """The semi-smooth reference solves saddle-point systems: ``linear_solver="amg"`` is refused,
    naming the option and the way out."""
    from alcontact.errors import InputError

    with pytest.raises(InputError) as err:
        solve_finite(half_cylinder(4), "ssn", steps=2, linear_solver="amg")
    msg = str(err.value)
    assert "linear_solver = 'amg'" in msg and "'ssn' has no AMG path" in msg and "'direct'" in msg


def test_registry_lists_the_finite_amg_path():
    """Registry: penalty, simo-laursen and family-p run on ``direct, amg`` at finite deformation; ssn on ``direct``."""
    from alcontact.contact.algorithms import describe_algorithms, find_algorithm

    for name in ("penalty", "simo-laursen", "family-p"):
        assert find_algorithm(name, kinematics="finite").linear_solvers == ("direct", "amg")
    assert find_algorithm("ssn", kinematics="finite").linear_solvers == ("direct",)
    docs = describe_algorithms(friction=False)
    assert docs["simo-laursen"].endswith("[small: direct, amg; finite: direct, amg]")
    assert docs["ssn"].endswith("[small: direct, amg; finite: direct]")


def _fc(n=4):
    from alcontact.contact.systems import FiniteContact

    return FiniteContact(half_cylinder(n))


def _spd_and_indefinite(fc):
    import scipy.sparse as sp

    K = fc._tangent_free(np.zeros(fc.model.ndofs))
    shift = 0.5 * float(sp.linalg.eigsh(K, k=1, which="LA", return_eigenvectors=False)[0])
    return K, (K - shift * sp.identity(K.shape[0])).tocsr()


def test_cg_solves_an_spd_system_to_its_tolerance(multilevel):
    """A solve of the stiffness matrix (SPD) reaches the CG tolerance 1e-10 relative (residual 2-norm),
    a re-solve with the same matrix (dual step) 1e-2."""
    fc = _fc(8)
    solver = _amg_newton(fc)
    K, _ = _spd_and_indefinite(fc)
    b = np.random.default_rng(0).standard_normal(K.shape[0])
    x = solver.solve(K, b)
    assert np.linalg.norm(K @ x - b) <= 1e-10 * np.linalg.norm(b)
    y = solver.resolve(b)  # the same matrix again (the dual step of Algorithm 6.1)
    assert np.linalg.norm(K @ y - b) <= 1e-2 * np.linalg.norm(b)
    assert solver.info()["direct_fallbacks"] == 0


def test_indefinite_newton_matrix_falls_back_to_direct_or_fails_the_step(multilevel, caplog):
    """Negative curvature in CG (an indefinite matrix: K shifted by half its largest eigenvalue):
    with the fallback the system is solved by the direct factorization (residual 1e-8 relative,
    counted, a warning naming linear_solver = 'direct'); without it the Newton step fails
    (LinAlgError: the load step is cut back)."""
    fc = _fc(8)
    _, A = _spd_and_indefinite(fc)
    b = np.random.default_rng(1).standard_normal(A.shape[0])
    solver = _amg_newton(fc)
    with caplog.at_level("WARNING", logger="alcontact.contact.systems._full_space"):
        x = solver.solve(A, b)
    assert np.linalg.norm(A @ x - b) <= 1e-8 * np.linalg.norm(b)
    assert solver.info()["direct_fallbacks"] == 1
    assert "linear_solver = 'direct'" in caplog.text
    strict = _amg_newton(fc, fallback=False)
    with pytest.raises(np.linalg.LinAlgError, match="linear_solver = 'direct'"):
        strict.solve(A, b)


def test_forcing_terms_are_loose_far_from_the_solution_and_tight_near_it():
    """Eisenstat-Walker forcing (module doc of _finite_iterative): the first step of a run gets 1e-3,
    after a contraction c the EW choice 2 value 0.9 c^2, but never more than the relative residual
    (quadratic local convergence) and never below 1e-12."""
    from alcontact.optim import NewtonRecord

    solver = fi.AMGNewtonSolver(_fc())
    first = solver.forcing([NewtonRecord(1.0)])
    assert first == pytest.approx(1e-3)
    solver._eta = first
    eta = solver.forcing([NewtonRecord(1.0, step=1.0), NewtonRecord(0.1)])
    assert eta == pytest.approx(0.9 * 0.1**2)
    solver._eta = eta
    near = solver.forcing([NewtonRecord(1e-4, step=1.0), NewtonRecord(1e-9)])
    assert near == pytest.approx(0.9 * (1e-9 / 1e-4) ** 2)
    solver._eta = 1e-4
    capped = solver.forcing([NewtonRecord(1e-2, step=1.0), NewtonRecord(1e-3)])  # EW 9e-3 > residual 1e-3
    assert capped == pytest.approx(1e-3)
    assert solver.forcing([NewtonRecord(1e-15, step=1.0), NewtonRecord(1e-16)]) == pytest.approx(1e-12)


def test_near_null_modes_follow_the_current_configuration():
    """The rigid-body modes are those of X + u at the step's start. After a rigid rotation by 90
    degrees (2D, neo-Hookean half-cylinder), the tangent K_T(u) maps the rotation mode of the current
    configuration to round-off (|K_T m| <= 1e-8 |K_T| |m|), while the reference configuration's
    rotation mode is no longer in its kernel (|K_T m| >= 1e-2 |K_T| |m|)."""
    import types

    model = half_cylinder(4).model
    pts, dofs = model.all_node_dofs()
    c = pts.mean(axis=0)
    rot = np.array([[0.0, -1.0], [1.0, 0.0]])
    u = np.zeros(model.ndofs)
    u[dofs] = (pts - c) @ rot.T + c - pts
    stub = types.SimpleNamespace(model=model, free=np.arange(model.ndofs), u_free=u)
    cur = fi.AMGNewtonSolver(stub).near_null()[:, -1]
    ref = fi.AMGNewtonSolver(stub, modes="reference").near_null()[:, -1]
    K = model.tangent(u).tocsr()
    scale = abs(K).max()
    assert np.linalg.norm(K @ cur) <= 1e-8 * scale * np.linalg.norm(cur)
    assert np.linalg.norm(K @ ref) >= 1e-2 * scale * np.linalg.norm(ref)
