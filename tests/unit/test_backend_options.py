"""Backend (PETSc) options: from the problem file's ``[solver.petsc_options]`` and the Python API to the
solver that runs, checked without PETSc by a solver registered with ``backend_options=True`` that records
what it received (tests/mpi/test_petsc_options.py runs the same with PETSc's KSP); and ``alcontact run``
started as several MPI ranks (issue 24, bad input)."""

from __future__ import annotations

import logging
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from alcontact import linalg
from alcontact.app import run_problem, run_setup
from alcontact.cli import app
from alcontact.errors import ConfigError, InputError
from alcontact.io.config import load_problem_text

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "hertz_2d.toml"


@pytest.fixture
def recording_solver():
    """Register "recording": SuperLU whose factory records the ``options`` it was built with."""
    seen: list = []

    def factory(options=None):
        seen.append(options)
        return linalg.SuperLUSolver()

    linalg.register_solver("recording", factory, backend_options=True, doc="test: records its options")
    try:
        yield seen
    finally:
        linalg.unregister_solver("recording")


def _file(solver_lines: str) -> str:
    text = EXAMPLE.read_text()
    assert '[solver]\nalgorithm = "simo-laursen"\n' in text  # the anchor the edits below rely on
    return text.replace('[solver]\nalgorithm = "simo-laursen"\n', f'[solver]\nalgorithm = "simo-laursen"\n{solver_lines}\n')


def test_backend_options_reach_the_solver_named_and_only_it(recording_solver):
    with linalg.backend_options({"ksp_rtol": 1e-9, "ksp_monitor": True}):
        linalg.select_solver("recording", dim=2, ndofs=10)
        linalg.make_solver("superlu")  # takes no backend options: built as usual
        linalg.make_solver("recording", options={"ksp_rtol": 1e-3})  # explicit options win
    linalg.make_solver("recording")  # outside the block: none
    assert recording_solver == [{"ksp_rtol": 1e-9, "ksp_monitor": True}, {"ksp_rtol": 1e-3}, None]
    assert linalg.takes_backend_options("recording") and not linalg.takes_backend_options("superlu")
    assert linalg.takes_backend_options("petsc") and linalg.takes_backend_options("petsc-direct")


def test_backend_options_no_solver_took_is_a_warning(caplog):
    with caplog.at_level(logging.WARNING, logger="alcontact"):
        with linalg.backend_options({"ksp_rtol": 1e-9}):
            linalg.make_solver("superlu")
    assert "no linear solver that takes them ran" in caplog.text and "ksp_rtol" in caplog.text


@pytest.mark.parametrize("options, match", [
    ({"-ksp_rtol": 1e-9}, "leading dash"),
    ({"ksp rtol": 1e-9}, "leading dash"),
    ({"ksp_rtol": [1, 2]}, "ksp_rtol"),
    ({"ksp_rtol": float("nan")}, "ksp_rtol"),
    ({"pc_type": "ga mg"}, "pc_type"),
    (["ksp_rtol"], "table of name = value"),
])
def test_bad_backend_options_are_refused_by_name(options, match):
    with pytest.raises(InputError, match=match):
        with linalg.backend_options(options):
            pass


def test_problem_file_petsc_options_reach_the_contact_solve(recording_solver):
    """``[solver] petsc_options`` (inline table) and ``[solver.petsc_options]`` are one table; the solver
    built inside the contact solve receives it, and the answer is SuperLU's (the recording solver is SuperLU)."""
    inline = load_problem_text(_file('linear_solver = "recording"\n'
                                     'petsc_options = { ksp_type = "cg", pc_type = "gamg", ksp_rtol = 1e-10 }'))
    table = load_problem_text(_file('linear_solver = "recording"\n[solver.petsc_options]\nksp_type = "cg"\n'
                                    'pc_type = "gamg"\nksp_rtol = 1e-10'))
    want = {"ksp_type": "cg", "pc_type": "gamg", "ksp_rtol": 1e-10}
    assert inline.petsc_options == want and table.petsc_options == want
    out = run_setup(inline)
    assert recording_solver and all(o == want for o in recording_solver)
    plain = run_setup(load_problem_text(_file('linear_solver = "superlu"')))
    assert out.summary["status"] == plain.summary["status"] == "converged"
    assert out.summary["total_contact_force"] == pytest.approx(plain.summary["total_contact_force"], rel=1e-12)
    # the Python API: run_setup(petsc_options=...) replaces the file's
    recording_solver.clear()
    run_setup(inline, petsc_options={"ksp_rtol": 1e-6})
    assert recording_solver and all(o == {"ksp_rtol": 1e-6} for o in recording_solver)


def test_run_problem_passes_petsc_options(recording_solver):
    solution, _ = run_problem("hertz-2d", level=0, linear_solver="recording", petsc_options={"ksp_max_it": 50})
    assert solution.success
    assert recording_solver and all(o == {"ksp_max_it": 50} for o in recording_solver)


@pytest.mark.parametrize("lines, match", [
    ('petsc_options = { ksp_rtol = 1e-10 }', "linear_solver = 'auto' does not run PETSc"),
    ('linear_solver = "superlu"\npetsc_options = { ksp_rtol = 1e-10 }', "linear_solver = 'superlu' does not run"),
    ('linear_solver = "recording"\npetsc_options = { ksp_rtol = [1, 2] }', "ksp_rtol"),
    ('linear_solver = "recording"\npetsc_options = { "-ksp_rtol" = 1e-10 }', "leading dash"),
])
def test_problem_file_bad_petsc_options_name_the_key(recording_solver, lines, match):
    with pytest.raises(ConfigError) as info:
        load_problem_text(_file(lines))
    msg = str(info.value)
    assert "solver.petsc_options" in msg and match in msg


def test_petsc_options_are_in_the_generated_reference():
    from alcontact.io import schema

    doc = (Path(__file__).resolve().parents[2] / "docs" / "problem-file.md").read_text()
    assert "[solver.petsc_options]" in doc
    assert doc == schema.render_markdown()


# ------------------------------------------------------------- `alcontact run` under an MPI launcher
@pytest.mark.parametrize("rank", [0, 1])
def test_run_as_several_mpi_ranks_without_the_mpi_extras_names_make_mpi(tmp_path, monkeypatch, rank):
    """What `mpirun -n 2 .venv/bin/alcontact run` sees (OpenMPI's variables; mpi4py and petsc4py missing):
    rank 0 says what to do, every rank exits with the usage code, no results folder is written."""
    monkeypatch.setenv("OMPI_COMM_WORLD_SIZE", "2")
    monkeypatch.setenv("OMPI_COMM_WORLD_RANK", str(rank))
    monkeypatch.setitem(sys.modules, "mpi4py", None)
    monkeypatch.setitem(sys.modules, "petsc4py", None)
    res = CliRunner().invoke(app, ["run", "--out", str(tmp_path / "r")])
    assert res.exit_code == 2
    out = " ".join((res.stdout + (res.stderr if res.stderr_bytes is not None else "")).split())
    if rank == 0:
        assert "make mpi" in out and "2 processes" in out and "mpi4py and petsc4py not installed" in out
    else:
        assert "error" not in out
    assert not (tmp_path / "r").exists()


def test_run_as_one_process_is_not_refused(monkeypatch):
    from alcontact.distributed import check_launch, launch_size

    monkeypatch.setenv("PMI_SIZE", "1")
    monkeypatch.setenv("PMI_RANK", "0")
    assert launch_size() == 1
    check_launch("alcontact run")  # no error
    monkeypatch.setenv("PMI_SIZE", "3")
    with pytest.raises(InputError, match="3 processes"):
        check_launch("alcontact run")
    assert np.isfinite(launch_size())
