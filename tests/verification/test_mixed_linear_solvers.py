"""Verification: the mixed u-p body on every registered linear-solver path (issue "rubber parts").

The mixed body's Newton matrices are saddle-point systems (symmetric indefinite; at ``nu = 0.5``
the pressure block is zero). Reference: the same problem on the default direct path
(``linear_solver = "direct"``, a symmetric-indefinite factorization), itself verified against closed
forms in ``test_mixed_incompressible.py`` and ``test_mixed_contact.py``.

- Every installed exact solver (``mkl-pardiso``, ``cholmod``, ``superlu``, ``direct``, ``auto``)
  gives the contact force and the displacement of the direct path to 1e-8 (relative; measured
  <= 7e-16), and the solution reports the solver that ran.
- The approximate path (``linear_solver = "amg"``): MINRES with the block-diagonal preconditioner
  (AMG on the displacement block, the scaled lumped pressure mass on the pressure rows;
  ``alcontact.linalg._saddle``) for the three augmented-Lagrangian algorithms at ``nu = 0.4999`` and
  ``0.5``: contact force within 1e-9 and displacement within 1e-7 of the direct path (relative; the
  Newton tolerance floor of inexact solves is 1e-11; measured force <= 7e-11, displacement
  <= 1.5e-8 at n = 8..32). The option took effect: ``linear_solver`` is ``"amg"``, the Krylov method
  ``"minres"``, and no registry factorization ran (the direct solvers' ``factorize`` is counted: 0 calls;
  no direct fallback). The same at ``nu = 0.5`` on the 3D quarter hemisphere (curved tetra10) and the
  hemisphere of revolution (axisymmetric mixed body).
- Coulomb friction (the ``factor-gmres`` path: GMRES with the block-triangular variant around each
  matrix) gives the direct path's forces to 1e-8 with no fallback factorization.
- The reference ``ssn`` has no AMG path: ``amg`` is refused with the way out, as for any body.
- A problem file with ``formulation = "mixed"`` and ``linear_solver = "amg"`` runs, and ``summary.json``
  says ``amg`` / ``minres``.
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


@pytest.fixture
def factorizations(monkeypatch):
    """Calls of every registry direct solver's ``factorize`` (a hidden factorization would show here)."""
    from alcontact import linalg

    calls = []
    for cls in (linalg.SuperLUSolver, linalg.PardisoSolver, linalg.CholmodSolver):
        orig = cls.factorize

        def counted(self, *args, _orig=orig, **kw):
            calls.append(self.name)
            return _orig(self, *args, **kw)

        monkeypatch.setattr(cls, "factorize", counted)
    return calls


def _amg_problem(nu, n=8):
    base = half_cylinder(n, order=2, curved=True, nu=0.3, delta=0.4)
    return dataclasses.replace(base, model=MixedHyperelastic(base.model.mesh, E=1000.0, nu=nu))


@pytest.mark.parametrize("nu", [0.4999, 0.5])
@pytest.mark.parametrize("algorithm", ["simo-laursen", pytest.param("family-p", marks=pytest.mark.slow),
                                       pytest.param("penalty", marks=pytest.mark.slow)])
def test_amg_on_a_mixed_body_gives_the_direct_answer_without_a_factorization(algorithm, nu, factorizations):
    ref = contact.solve(_amg_problem(nu), algorithm, steps=8, options={"linear_solver": "direct"})
    assert int(ref.result.status) > 0, ref.result.message
    factorizations.clear()
    sol = contact.solve(_amg_problem(nu), algorithm, steps=8, options={"linear_solver": "amg"})
    assert int(sol.result.status) > 0, sol.result.message
    assert factorizations == []  # no registry factorization: the option took effect
    ex = sol.extra
    assert ex["linear_solver"] == "amg" and ex["krylov"] == "minres"
    assert ex["direct_fallbacks"] == 0 and ex["amg_setups"] >= 1 and ex["cg_iterations"] > 0
    f0 = ref.total_contact_force[1]
    assert abs(sol.total_contact_force[1] - f0) <= 1e-9 * f0, (sol.total_contact_force, f0)
    assert np.max(np.abs(sol.u - ref.u)) <= 1e-7 * np.max(np.abs(ref.u))


@pytest.mark.parametrize("geometry", ["3d", "axisymmetric"])
def test_amg_on_an_incompressible_3d_and_axisymmetric_body_gives_the_direct_answer(geometry, factorizations):
    """nu = 0.5, the neo-Hookean hemisphere pressed to delta/R = 0.25: the 3D quarter (curved tetra10, n = 3) and
    the body of revolution (n = 8); measured force 9.8e-12 / 1.4e-10, displacement 6.9e-10 / 1.3e-9."""
    from alcontact.problems.hemisphere import hemisphere, hemisphere_axisym

    def problem():
        base = hemisphere(3, order=2, delta=0.25) if geometry == "3d" else hemisphere_axisym(8, order=2, delta=0.25)
        return dataclasses.replace(base, model=MixedHyperelastic(
            base.model.mesh, E=1000.0, nu=0.5, geometry="cartesian" if geometry == "3d" else "axisymmetric"))

    ref = contact.solve(problem(), "simo-laursen", steps=5, options={"linear_solver": "direct"})
    factorizations.clear()
    sol = contact.solve(problem(), "simo-laursen", steps=5, options={"linear_solver": "amg"})
    assert int(ref.result.status) > 0 and int(sol.result.status) > 0, (ref.result.message, sol.result.message)
    assert factorizations == [] and sol.extra["krylov"] == "minres" and sol.extra["direct_fallbacks"] == 0
    f0 = ref.total_contact_force[1]
    assert f0 > 0 and abs(sol.total_contact_force[1] - f0) <= 1e-9 * f0
    assert np.max(np.abs(sol.u - ref.u)) <= 1e-7 * np.max(np.abs(ref.u))


@pytest.mark.slow
def test_amg_with_coulomb_friction_on_a_mixed_body_gives_the_direct_answer(factorizations):
    """The factor-gmres path of finite Coulomb friction (block-triangular preconditioner around each matrix)."""
    def problem():
        base = half_cylinder(4, order=2, curved=True, nu=0.3, delta=0.2)
        return dataclasses.replace(base, model=MixedHyperelastic(base.model.mesh, E=1000.0, nu=0.4999))

    ref = contact.solve(problem(), "simo-laursen", steps=4, friction=0.3, options={"linear_solver": "direct"})
    assert int(ref.result.status) > 0, ref.result.message
    factorizations.clear()
    sol = contact.solve(problem(), "simo-laursen", steps=4, friction=0.3, options={"linear_solver": "amg"})
    assert int(sol.result.status) > 0, sol.result.message
    assert factorizations == []  # GMRES met its round-off test on every system: no SuperLU fallback
    scale = abs(ref.total_contact_force[1])
    assert np.max(np.abs(sol.total_contact_force - ref.total_contact_force)) <= 1e-8 * scale
    assert np.max(np.abs(sol.u - ref.u)) <= 1e-8 * np.max(np.abs(ref.u))


def test_ssn_with_amg_on_a_mixed_body_is_refused_with_the_way_out():
    with pytest.raises(InputError) as err:
        contact.solve(_problem(0.4999), "ssn", steps=4, options={"linear_solver": "amg"})
    msg = str(err.value)
    assert "linear_solver = 'amg'" in msg and "'ssn'" in msg and "'direct'" in msg


def test_the_body_own_newton_runs_on_amg():
    """``MixedHyperelastic(linear_solver="amg").solve``: GMRES with the block-triangular preconditioner, the same
    answer as the direct factorization to 1e-8."""
    base = half_cylinder(4, order=2, curved=True, nu=0.3, delta=0.2)
    out = {}
    for name in ("direct", "amg"):
        m = MixedHyperelastic(base.model.mesh, E=1000.0, nu=0.5, linear_solver=name)
        out[name] = m.solve(m.traction_load("top", [0.0, -50.0]),
                            [m.dirichlet("symmetry", [0]), m.dirichlet("curved", [0, 1])], steps=2)
        assert (m.linear_solver_used == "amg") == (name == "amg")
    assert np.max(np.abs(out["amg"] - out["direct"])) <= 1e-8 * np.max(np.abs(out["direct"]))


def test_auto_chooses_a_direct_solver_for_a_mixed_body():
    sol = contact.solve(_problem(0.4999), "simo-laursen", steps=4, options={"linear_solver": "auto"})
    assert int(sol.result.status) > 0
    assert select_solver(sol.extra["linear_solver"], dim=2, ndofs=10, matrix_type="symmetric-indefinite").exact
    assert sol.extra.get("direct_fallbacks", 0) == 0


@pytest.mark.slow
def test_problem_file_mixed_with_amg_runs_and_says_so(tmp_path):
    """The finite half-cylinder example as a P2 mixed body at nu = 0.5: ``check`` passes, ``run`` on ``amg`` gives the
    forces of the direct run to 1e-8, and ``summary.json`` names ``amg`` / ``minres`` with no fallback."""
    import json
    import shutil
    from pathlib import Path

    from typer.testing import CliRunner

    from alcontact.cli import app

    ex = Path(__file__).resolve().parents[2] / "examples"
    shutil.copy(ex / "half_cylinder.msh", tmp_path / "half_cylinder.msh")
    text = (ex / "finite_half_cylinder.toml").read_text()
    text = text.replace('file = "half_cylinder.msh"', 'file = "half_cylinder.msh"\norder = 2').replace(
        "nu = 0.3", "nu = 0.5")
    runner = CliRunner()
    out = {}
    for name in ("direct", "amg"):
        p = tmp_path / f"{name}.toml"
        p.write_text(text + f'\n[solver]\nlinear_solver = "{name}"\n')
        check = runner.invoke(app, ["check", str(p)])
        assert check.exit_code == 0, check.output
        result = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / name)])
        assert result.exit_code == 0, result.output
        out[name] = json.loads((tmp_path / name / "summary.json").read_text())
    amg, direct = out["amg"], out["direct"]
    assert amg["formulation"] == "mixed"
    assert amg["linear_solver"] == "amg" and amg["krylov"] == "minres" and amg["direct_fallbacks"] == 0
    assert direct["linear_solver"] != "amg"
    fa, fd = np.array(amg["step_contact_force"]), np.array(direct["step_contact_force"])
    assert np.max(np.abs(fa[:, 1] - fd[:, 1]) / np.abs(fd[:, 1])) <= 1e-8


def test_a_mixed_body_at_small_kinematics_is_refused_with_the_way_out():
    """No small-deformation path has the mixed body's pressure unknowns: a clear error, not an AttributeError."""
    base = half_cylinder(4, order=2, curved=False, nu=0.3, delta=0.2)
    with pytest.raises(InputError, match="kinematics='finite'"):
        dataclasses.replace(base, model=MixedHyperelastic(base.model.mesh, E=1000.0, nu=0.4999), kinematics="small")
