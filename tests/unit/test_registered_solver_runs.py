"""The solver named by ``linear_solver`` is the one that runs, on every path (issue 22).

A user-registered counting solver of kind ``"direct"`` (SciPy SuperLU underneath) and one of kind
``"iterative"`` (PyAMG smoothed aggregation underneath) are named on small and finite deformation,
frictionless and Coulomb solves. Each must be called (``factorize`` count > 0), be recorded in
``solution.extra`` (no system handed to a fallback solver), and give the answer of the built-in
direct solver.

Reference: the same solve with ``linear_solver="superlu"`` (built-in). Tolerance: displacements
within **1e-6** of ``max|u|`` (the approximate paths stop their Krylov solves at relative
residuals 1e-10 to 1e-13 and the Newton solves at 1e-11 to 1e-12; measured differences below 1e-8
here: 3e-14 to 4.5e-9); the exact counting solver factorizes with the same SuperLU, so its answer is the reference's
to round-off (asserted to 1e-10).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from alcontact import linalg
from alcontact.contact import (ContactProblem, ContactStatus, Ramp, Support, obstacles, solve, solve_finite,
                               solve_finite_friction, solve_friction)
from alcontact.errors import InputError
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic
from alcontact.problems import blocks
from alcontact.problems import friction as fp
from alcontact.problems.half_cylinder import half_cylinder

DIRECT, ITERATIVE = "test-counting-direct", "test-counting-iterative"
ALL_TYPES = ("spd", "symmetric-indefinite", "unsymmetric")
CALLS = {DIRECT: 0, ITERATIVE: 0}


class CountingDirect(linalg.SuperLUSolver):
    name = DIRECT

    def factorize(self, matrix, hints=None):
        CALLS[DIRECT] += 1
        return super().factorize(matrix, hints)


class CountingIterative(linalg.AMGSolver):
    name = ITERATIVE

    def factorize(self, matrix, hints=None):
        CALLS[ITERATIVE] += 1
        return super().factorize(matrix, hints)


@pytest.fixture
def counting():
    """Both counting solvers registered (and removed afterwards); the counts start at 0."""
    linalg.register_solver(DIRECT, CountingDirect, kind="direct", matrix_types=ALL_TYPES)
    linalg.register_solver(ITERATIVE, CountingIterative, kind="iterative")
    CALLS.update({DIRECT: 0, ITERATIVE: 0})
    yield CALLS
    linalg.unregister_solver(DIRECT)
    linalg.unregister_solver(ITERATIVE)


def _ironing():
    """2D neo-Hookean strip ironed by a rigid cylinder: pressed in 3 steps, slid in 4 (Coulomb mu = 0.3)."""
    mesh = meshes.rectangle(0.0, 2.0, 0.0, 0.5, 20, 4)
    problem = ContactProblem(Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain")),
                             obstacles.Circle(center=(0.5, 1.0), radius=0.5), "top", supports=(Support("bottom"),),
                             kinematics="finite")
    press = Ramp((0.0, 0.2), (0.0, -0.05), hold_after=True)
    slide = Ramp((0.2, 1.0), (0.0, 0.6))
    times = list(np.linspace(0.0, 0.2, 4)[1:]) + list(np.linspace(0.2, 1.0, 5)[1:])
    return problem, (lambda t: np.array([slide(t), press(t)])), times


def _small(linear_solver):
    sol = solve(blocks.signorini_block(n=4), "simo-laursen", linear_solver=linear_solver)
    assert sol.result.status > 0, sol.result.message
    return sol.u, sol.extra


def _small_friction(linear_solver):
    prob, hist = fp.cattaneo_mindlin_2d(4, size=5.0, normal_steps=1, tangential_steps=2)
    sol = solve_friction(prob, hist, linear_solver=linear_solver)
    assert sol.status == ContactStatus.CONVERGED, sol.message
    return sol.steps[-1].u, sol.extra


def _finite(linear_solver):
    fs = solve_finite(half_cylinder(4), "simo-laursen", steps=2, linear_solver=linear_solver)
    assert fs.success, fs.message
    return fs.solution.u, fs.solution.extra


def _finite_friction(linear_solver):
    problem, path, times = _ironing()
    fs = solve_finite_friction(problem, 0.3, "simo-laursen", steps=times, obstacle_path=path,
                               linear_solver=linear_solver)
    assert fs.success, fs.message
    return fs.u, fs.extra


PATHS = {"small": _small, "small-coulomb": _small_friction, "finite": _finite, "finite-coulomb": _finite_friction}
#: ``solution.extra["strategy"]`` of each path for an exact / an approximate solver
STRATEGY = {"small": ("condensed", "krylov"), "small-coulomb": ("condensed", "krylov"),
            "finite": ("full-space-newton",) * 2, "finite-coulomb": ("full-space-newton",) * 2}


@pytest.mark.parametrize("path", list(PATHS))
@pytest.mark.parametrize("which", [DIRECT, ITERATIVE])
def test_registered_solver_is_called_and_agrees(counting, path, which):
    run = PATHS[path]
    u_ref, _ = run("superlu")
    assert counting[which] == 0
    u, extra = run(which)
    assert counting[which] > 0, f"{which} was never called on the {path} path"
    # one key, one meaning on every path: the registry name of the solver that ran, and how it ran
    assert extra["linear_solver"] == which, extra
    assert extra["strategy"] == STRATEGY[path][which == ITERATIVE], extra
    assert extra.get("fallback_solves", 0) == 0 and extra.get("direct_fallbacks", 0) == 0  # no system went elsewhere
    # an approximate solver runs inside Krylov iterations (CG on the AMG paths, GMRES around its factor on
    # finite Coulomb); an exact one factorizes (the condensed or direct Newton strategy, no Krylov loop)
    krylov = extra.get("cg_iterations", 0) + extra.get("krylov_iterations", 0)
    assert (krylov > 0) == (which == ITERATIVE), extra
    tol = 1e-10 if which == DIRECT else 1e-6
    assert np.max(np.abs(u - u_ref)) <= tol * np.max(np.abs(u_ref))


@pytest.mark.parametrize("name", [n for n in ("superlu", "cholmod", "mkl-pardiso") if linalg.is_installed(n)])
def test_named_direct_solver_runs_at_finite_deformation(name):
    """At finite deformation ``linear_solver = <direct solver>`` is the solver of the Newton systems
    (``extra["linear_solver"]``), not the registry's default; the answer is PARDISO/"direct"'s to 1e-8
    relative. CHOLMOD factorizes SPD matrices only: a Newton matrix it refuses is solved by the SuperLU
    fallback, counted in ``fallback_solves``."""
    ref = solve_finite(half_cylinder(4), "simo-laursen", steps=2, linear_solver="direct")
    fs = solve_finite(half_cylinder(4), "simo-laursen", steps=2, linear_solver=name)
    assert fs.success, fs.message
    ex = fs.solution.extra
    assert ex["linear_solver"] == name and ex["strategy"] == "full-space-newton"
    if name != "cholmod":
        assert ex["fallback_solves"] == 0
    u_ref = ref.solution.u
    assert np.max(np.abs(fs.solution.u - u_ref)) <= 1e-8 * np.max(np.abs(u_ref))


def test_unknown_linear_solver_is_refused_with_the_names():
    with pytest.raises(InputError, match="linear_solver = 'no-such-solver'.*allowed: auto, direct"):
        linalg.select_solver("no-such-solver", dim=2, ndofs=10)


EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("example,anchor,strategy", [
    ("signorini_liftoff.toml", '[solver]\nalgorithm = "family-p"\n', ("condensed", "krylov")),
    ("finite_half_cylinder.toml", '[contact]\nboundary = "curved"\n', ("full-space-newton",) * 2),
])
@pytest.mark.parametrize("which", [DIRECT, ITERATIVE])
def test_summary_records_the_solver_that_ran(counting, tmp_path, example, anchor, strategy, which):
    """``summary.json`` of a problem-file run names the configured solver (registry name), how it ran and the
    PETSc options it got (none here); the solver was called."""
    from alcontact.app import run_setup
    from alcontact.io.config import load_problem_text

    text = (EXAMPLES / example).read_text()
    assert anchor in text
    if anchor.startswith("[contact]"):  # the finite example has no [solver] table
        text += f'\n[solver]\nlinear_solver = "{which}"\n'
    else:
        text = text.replace(anchor, f'{anchor}linear_solver = "{which}"\n')
    setup = load_problem_text(text, base_dir=EXAMPLES)
    out = run_setup(setup)
    assert out.summary["status"] == "converged"
    assert counting[which] > 0
    assert out.summary["linear_solver"] == which
    assert out.summary["linear_solver_strategy"] == strategy[which == ITERATIVE]
    assert out.summary["petsc_options"] == {}
