"""The PETSc linear solvers of the registry ("petsc", "petsc-direct") and their options.

The registry-generated tests of tests/unit/test_linalg.py also cover both solvers when
they run in .venv-mpi (make test does): residual <= 1e-10, singular matrix refused,
the same displacement as SuperLU.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from alcontact import linalg
from alcontact.errors import InputError
from alcontact.fem import LinearElasticity, Material, meshes


def _system():
    """Condensed 3D P1 stiffness of a clamped bar and its hints (rigid-body modes)."""
    model = LinearElasticity(meshes.box(0, 4, 0, 1, 0, 1, 16, 4, 4), Material(E=100.0, nu=0.3))
    dofs, _ = model.dirichlet("left")
    free = np.setdiff1d(np.arange(model.ndofs), dofs)
    K = model.stiffness()[free][:, free].tocsr()
    return K, linalg.MatrixHints(dim=3, near_null=lambda: model._free_rigid_modes(free))


def test_options_are_passed_through_and_take_effect():
    K, hints = _system()
    fac = linalg.make_solver("petsc", options={"ksp_type": "gmres", "ksp_rtol": 1e-6,
                                               "pc_gamg_threshold": 0.01}).factorize(K, hints)
    assert fac.ksp.getType() == "gmres"
    assert fac.ksp.getTolerances()[0] == pytest.approx(1e-6)
    b = np.ones(K.shape[0])
    x = fac.solve(b)
    assert np.linalg.norm(K @ x - b) <= 1e-6 * np.linalg.norm(b) * 1.0001


@pytest.mark.parametrize("name", ["petsc", "petsc-direct"])
def test_a_misspelled_option_is_a_warning_naming_it_once(caplog, name):
    """PETSc's unused-option report (-options_left) surfaced as a logged warning, once per solver,
    after the first solve; options used only while solving (ksp_converged_reason) are not reported."""
    K, hints = _system()
    solver = linalg.make_solver(name, options={"ksp_rtoll": 1e-6, "ksp_converged_reason": True})
    b = np.ones(K.shape[0])
    with caplog.at_level(logging.WARNING, logger="alcontact"):
        for i in range(2):  # two factorizations (Newton steps) of one solver: reported once
            fac = solver.factorize(K, hints)
            assert len(caplog.records) == i  # not before the first solve
            fac.solve(b)
            fac.solve(b)
    msgs = [r.getMessage() for r in caplog.records]
    assert len(msgs) == 1 and "'ksp_rtoll'" in msgs[0] and "did not use" in msgs[0]
    assert "ksp_converged_reason" not in msgs[0]
    assert solver.unused == {"ksp_rtoll"}
    assert np.linalg.norm(K @ fac.solve(b) - b) <= 1e-9 * np.linalg.norm(b)  # the solve itself is unaffected
    with pytest.raises(InputError, match="leading dash"):
        linalg.make_solver(name, options={"-ksp_rtol": 1e-6})


def test_gamg_uses_the_rigid_body_near_null_space():
    """Six rigid-body modes reach GAMG, and they cut the CG iterations (measured 3D bar)."""
    K, hints = _system()
    b = np.random.default_rng(0).standard_normal(K.shape[0])
    with_modes = linalg.make_solver("petsc").factorize(K, hints)
    null = with_modes.ksp.getOperators()[0].getNearNullSpace()
    assert len(null.getVecs()) == 6
    with_modes.solve(b)
    plain = linalg.make_solver("petsc").factorize(K, linalg.MatrixHints(dim=3))
    plain.solve(b)
    assert with_modes.last_iterations < plain.last_iterations


def test_non_convergence_is_an_error_not_a_silent_result():
    K, hints = _system()
    fac = linalg.make_solver("petsc", options={"ksp_max_it": 2}).factorize(K, hints)
    with pytest.raises(InputError, match="did not converge"):
        fac.solve(np.ones(K.shape[0]))


def test_direct_solver_uses_mumps_when_petsc_has_it():
    K, hints = _system()
    pkg = linalg.direct_package()
    assert pkg in ("mumps", "superlu_dist", "petsc")
    fac = linalg.make_solver("petsc-direct").factorize(K, hints)
    assert fac.ksp.getPC().getFactorSolverType() == pkg
    b = np.ones(K.shape[0])
    assert np.linalg.norm(K @ fac.solve(b) - b) <= 1e-10 * np.linalg.norm(b)
    with pytest.raises(InputError, match="built without"):
        linalg.make_solver("petsc-direct", package="pastix")
