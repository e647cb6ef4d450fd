"""Verification: the mixed u-p body on every registered linear-solver path (issue "rubber parts").

The mixed body's Newton matrices are saddle-point systems (symmetric indefinite; at ``nu = 0.5``
the pressure block is zero). Reference: the same problem on the default direct path
(``linear_solver = "direct"``, a symmetric-indefinite factorization).

- Every installed exact solver (``mkl-pardiso``, ``cholmod``, ``superlu``, ``direct``, ``auto``)
  gives the contact force and the displacement of the direct path to 1e-8 (relative; measured
  <= 7e-16), and the solution reports the solver that ran.
- An approximate solver (``amg``) is refused before any work with an ``InputError`` that names
  ``linear_solver`` and the way out (before this check, the AMG-preconditioned CG met negative
  curvature and fell back to a factorization in 5 of 6 Newton systems: a configured solver that
  did not run).
- A problem file with ``formulation = "mixed"`` and ``linear_solver = "amg"``: the same error,
  no traceback, no results.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from alcontact import contact
from alcontact.errors import InputError
from alcontact.fem import MixedHyperelastic
from alcontact.linalg import registered_solvers, select_solver
from alcontact.problems.half_cylinder import half_cylinder


def _installed_exact():
    names = []
    for name in registered_solvers():
        try:
            choice = select_solver(name, dim=2, ndofs=100, matrix_type="symmetric-indefinite")
        except InputError:  # not installed here (petsc without MPI)
            continue
        if choice.exact:
            names.append(name)
    return names


def _problem(nu):
    base = half_cylinder(4, order=2, curved=False, nu=0.3, delta=0.2)
    return dataclasses.replace(base, model=MixedHyperelastic(base.model.mesh, E=1000.0, nu=nu))


@pytest.mark.parametrize("nu", [0.4999, 0.5])
@pytest.mark.parametrize("algorithm", ["simo-laursen", "ssn"])
def test_every_exact_solver_gives_the_direct_answer(algorithm, nu):
    ref = contact.solve(_problem(nu), algorithm, steps=4, options={"linear_solver": "direct"})
    assert int(ref.result.status) > 0, ref.result.message
    f0 = ref.total_contact_force[1]
    assert f0 > 0
    names = _installed_exact() + ["auto"]
    assert "superlu" in names
    for name in names:
        sol = contact.solve(_problem(nu), algorithm, steps=4, options={"linear_solver": name})
        assert int(sol.result.status) > 0, (name, sol.result.message)
        if name != "auto":
            assert sol.extra["linear_solver"] == name  # what was configured is what ran
        assert abs(sol.total_contact_force[1] - f0) <= 1e-8 * f0, (name, sol.total_contact_force, f0)
        assert np.max(np.abs(sol.u - ref.u)) <= 1e-8 * np.max(np.abs(ref.u)), name


@pytest.mark.parametrize("algorithm", ["simo-laursen", "family-p", "penalty"])
def test_amg_on_a_mixed_body_is_refused_with_the_way_out(algorithm):
    with pytest.raises(InputError) as err:
        contact.solve(_problem(0.4999), algorithm, steps=4, options={"linear_solver": "amg"})
    msg = str(err.value)
    assert "linear_solver = 'amg'" in msg and "mixed" in msg and "'direct'" in msg


def test_auto_chooses_a_direct_solver_for_a_mixed_body():
    sol = contact.solve(_problem(0.4999), "simo-laursen", steps=4, options={"linear_solver": "auto"})
    assert int(sol.result.status) > 0
    assert select_solver(sol.extra["linear_solver"], dim=2, ndofs=10, matrix_type="symmetric-indefinite").exact
    assert sol.extra.get("direct_fallbacks", 0) == 0


def test_problem_file_mixed_with_amg_is_refused_by_check_and_run(tmp_path):
    import shutil
    from pathlib import Path

    from typer.testing import CliRunner

    from alcontact.cli import app

    ex = Path(__file__).resolve().parents[2] / "examples"
    shutil.copy(ex / "seal_oring.msh", tmp_path / "seal_oring.msh")
    text = (ex / "seal_oring.toml").read_text().replace('folder = "results-seal-oring"', 'folder = "res"')
    p = tmp_path / "seal_oring.toml"
    p.write_text(text + '\n[solver]\nlinear_solver = "amg"\n')
    runner = CliRunner()
    for cmd in (["check", str(p)], ["run", str(p), "--out", str(tmp_path / "out")]):
        result = runner.invoke(app, cmd)
        out = " ".join(result.output.split())
        assert result.exit_code == 2, (cmd, result.output)
        assert "solver.linear_solver = 'amg'" in out and "mixed u-p body" in out and "'direct'" in out, out
        assert "Traceback" not in out
    assert not (tmp_path / "out").exists() and not (tmp_path / "res").exists()  # no partial output


def test_a_mixed_body_at_small_kinematics_is_refused_with_the_way_out():
    """No small-deformation path has the mixed body's pressure unknowns: a clear error, not an AttributeError."""
    base = half_cylinder(4, order=2, curved=False, nu=0.3, delta=0.2)
    with pytest.raises(InputError, match="kinematics='finite'"):
        dataclasses.replace(base, model=MixedHyperelastic(base.model.mesh, E=1000.0, nu=0.4999), kinematics="small")
