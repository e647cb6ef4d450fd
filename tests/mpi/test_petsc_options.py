"""PETSc options from the problem file and the Python API reach the KSP that runs in the contact solve;
a misspelled one is a warning the CLI prints; `alcontact run` under `mpirun -n 2` is refused clearly
(issue 24). Run in .venv-mpi by `make test`."""

from __future__ import annotations

import logging
import os
import subprocess
import sys
from pathlib import Path

import pytest

from alcontact import linalg
from alcontact.app import run_setup
from alcontact.io.config import load_problem_text

ROOT = Path(__file__).resolve().parents[2]

from ._mpi import mpirun

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "hertz_2d.toml"
ANCHOR = '[solver]\nalgorithm = "simo-laursen"\n'


def _file(solver_lines: str) -> str:
    text = EXAMPLE.read_text()
    assert ANCHOR in text
    return text.replace(ANCHOR, f"{ANCHOR}{solver_lines}\n")


@pytest.fixture
def ksp_factors(monkeypatch):
    """Every factor the PETSc Krylov solver makes (its KSP is read back)."""
    made = []
    factorize = linalg.PetscKrylovSolver.factorize

    def spy(self, matrix, hints=None):
        fac = factorize(self, matrix, hints)
        made.append(fac)
        return fac

    monkeypatch.setattr(linalg.PetscKrylovSolver, "factorize", spy)
    return made


def _run(petsc_options: str, factors: list):
    factors.clear()
    setup = load_problem_text(_file(f'linear_solver = "petsc"\npetsc_options = {{ {petsc_options} }}'))
    out = run_setup(setup)
    assert out.summary["status"] == "converged"
    assert factors, "the contact solve did not run PETSc's KSP"
    # what ran is recorded: the solver's registry name and the options it was given
    assert out.summary["linear_solver"] == "petsc" and out.summary["petsc_options"] == setup.petsc_options
    return out, list(factors)


def test_problem_file_options_take_effect_in_the_ksp_that_runs(ksp_factors):
    """Read back from the KSP objects of the contact solve: type, tolerance, preconditioner; and the
    Krylov iterations follow the tolerance (1e-2 needs fewer than 1e-10)."""
    loose, fl = _run('ksp_type = "cg", pc_type = "gamg", ksp_rtol = 1e-2', ksp_factors)
    tight, ft = _run('ksp_type = "cg", pc_type = "gamg", ksp_rtol = 1e-10', ksp_factors)
    for facs, rtol in ((fl, 1e-2), (ft, 1e-10)):
        for fac in facs:
            assert fac.ksp.getType() == "cg" and fac.ksp.getPC().getType() == "gamg"
            assert fac.ksp.getTolerances()[0] == pytest.approx(rtol)
    its = [sum(f.iterations for f in facs) / max(1, sum(f.solves for f in facs)) for facs in (fl, ft)]
    assert its[0] < its[1], its
    gmres, fg = _run('ksp_type = "gmres", ksp_rtol = 1e-8', ksp_factors)
    assert all(f.ksp.getType() == "gmres" for f in fg)
    plain = run_setup(load_problem_text(_file('linear_solver = "superlu"')))
    for out in (tight, gmres):  # the contact answer does not depend on how the preconditioner is tuned
        assert out.summary["total_contact_force"] == pytest.approx(plain.summary["total_contact_force"], rel=1e-6)


def test_python_api_options_take_effect(ksp_factors):
    from alcontact.contact import solve

    setup = load_problem_text(_file('linear_solver = "petsc"'))
    with linalg.backend_options({"ksp_rtol": 1e-7, "ksp_max_it": 500}):
        solution = solve(setup.problem, setup.algorithm, linear_solver="petsc")
    assert solution.success and ksp_factors
    assert all(f.ksp.getTolerances()[0] == pytest.approx(1e-7) and f.ksp.getTolerances()[3] == 500
               for f in ksp_factors)


def test_misspelled_option_is_a_warning_in_the_log(caplog):
    setup = load_problem_text(_file('linear_solver = "petsc"\npetsc_options = { ksp_rtoll = 1e-8 }'))
    with caplog.at_level(logging.WARNING, logger="alcontact"):
        out = run_setup(setup)
    assert out.summary["status"] == "converged"
    msgs = [r.getMessage() for r in caplog.records if "did not use" in r.getMessage()]
    assert len(msgs) == 1 and "'ksp_rtoll'" in msgs[0]


def test_misspelled_option_is_printed_by_the_cli(tmp_path):
    problem = tmp_path / "p.toml"
    problem.write_text(_file('linear_solver = "petsc"\npetsc_options = { ksp_rtoll = 1e-8 }'))
    exe = Path(sys.executable).with_name("alcontact")
    proc = subprocess.run([str(exe), "run", str(problem), "--out", str(tmp_path / "r")], capture_output=True,
                          text=True, timeout=300, env=dict(os.environ, COLUMNS="200"))
    assert proc.returncode == 0, proc.stderr
    both = " ".join((proc.stdout + proc.stderr).split())
    assert both.count("ksp_rtoll") == 1 and "did not use" in both
    assert (tmp_path / "r" / "summary.json").exists()


CLI_UNDER_MPIRUN = """
import sys
if "--no-extras" in sys.argv:
    sys.argv.remove("--no-extras")
    sys.modules["mpi4py"] = sys.modules["petsc4py"] = None  # an environment without the MPI extras
from alcontact.cli import main
sys.argv = ["alcontact", "run", "--out", sys.argv[1]] + sys.argv[2:]
main()
"""


@pytest.mark.parametrize("extras", [False, True])
def test_alcontact_run_under_mpirun_is_refused_with_one_clear_message(tmp_path, extras):
    """`mpirun -n 2 alcontact run`: one message (rank 0), non-zero exit, no results folder, no hang.
    Without the MPI extras the message gives the `make mpi` command."""
    script = tmp_path / "cli.py"
    script.write_text(CLI_UNDER_MPIRUN)
    args = [str(tmp_path / "r")] + ([] if extras else ["--no-extras"])
    proc = mpirun(2, str(script), *args, timeout=120)
    text = " ".join((proc.stdout + proc.stderr).split())
    assert proc.returncode != 0
    assert text.count("error:") == 1, text
    assert "2 processes" in text
    assert ("make mpi" in text) != extras
    assert ("runs as one process" in text) == extras
    assert not (tmp_path / "r").exists()


DISTRIBUTED = """
import json, logging, sys
from alcontact.distributed import DistributedElasticity, run_ranks, world
from alcontact.fem import Material, meshes

logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(message)s")
comm = world()
mesh = meshes.rectangle(0, 3, 0, 1, 24, 8) if comm.rank == 0 else None
model = DistributedElasticity(mesh, Material(E=200.0, nu=0.3), comm=comm)
sol = run_ranks(model.solve, [0.0, -1.0], lambda x: x[0] < 1e-12, rtol=1e-13,
                options={"ksp_rtoll": 1e-3, "ksp_max_it": int(sys.argv[2])})
if comm.rank == 0:
    json.dump({"iterations": sol.iterations, "reason": sol.reason}, open(sys.argv[1], "w"))
"""


def test_distributed_solve_options_take_effect_and_a_typo_is_reported_once(tmp_path):
    """On 2 ranks: ksp_max_it = 3 stops CG at 3 iterations (the solve is then refused as not converged,
    on every rank, no hang); the misspelled ksp_rtoll is one warning (rank 0), with or without success."""
    import json

    script = tmp_path / "d.py"
    script.write_text(DISTRIBUTED)
    ok = mpirun(2, str(script), str(tmp_path / "ok.json"), "1000", timeout=120)
    assert ok.returncode == 0, ok.stderr
    res = json.loads((tmp_path / "ok.json").read_text())
    assert res["reason"] > 0 and res["iterations"] > 3
    assert ok.stderr.count("'ksp_rtoll'") == 1 and "did not use" in ok.stderr
    capped = mpirun(2, str(script), str(tmp_path / "capped.json"), "3", timeout=120)
    assert capped.returncode != 0 and "3 iterations" in capped.stderr
    assert not (tmp_path / "capped.json").exists()


def test_mpirun_with_a_problem_file_but_no_mpi_extras_gives_the_make_mpi_command(tmp_path):
    """`mpirun -n 2 alcontact run problem.toml` where mpi4py and petsc4py do not load: the distributed path cannot
    run, so every rank refuses with one message (rank 0) that gives the `make mpi` command; no results folder."""
    script = tmp_path / "cli.py"
    script.write_text(CLI_UNDER_MPIRUN)
    proc = mpirun(2, str(script), str(tmp_path / "r"), "--no-extras", str(ROOT / "examples" / "hertz_2d.toml"),
                  timeout=120)
    text = " ".join((proc.stdout + proc.stderr).split())
    assert proc.returncode != 0
    assert text.count("error:") == 1, text
    assert "make mpi" in text and "2 processes" in text
    assert "Traceback" not in text
    assert not (tmp_path / "r").exists()
