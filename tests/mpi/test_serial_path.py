"""The serial path loads no MPI: checked where petsc4py and mpi4py ARE installed (.venv-mpi)."""

from __future__ import annotations

import subprocess
import sys

PROBE = """
import sys
{body}
print(sorted({{m.split('.')[0] for m in sys.modules}} & {{'mpi4py', 'petsc4py'}}))
"""


def _loaded(body: str) -> str:
    proc = subprocess.run([sys.executable, "-c", PROBE.format(body=body)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip().splitlines()[-1]


def test_petsc_and_mpi_are_installed_here():
    """Control: in this environment both import, so the checks below can fail."""
    assert _loaded("import petsc4py, mpi4py") == "['mpi4py', 'petsc4py']"


def test_import_alcontact_and_the_registry_load_no_mpi():
    body = ("import alcontact, alcontact.linalg as L, alcontact.distributed, alcontact.cli\n"
            "assert 'petsc' in L.available_solvers(); L.describe_solvers(); L.choose_solver(3, 10**6)")
    assert _loaded(body) == "[]"


def test_make_run_loads_no_mpi(tmp_path):
    body = ("from alcontact.cli import main\n"
            f"sys.argv = ['alcontact', 'run', '--out', {str(tmp_path / 'r')!r}, '--force']\n"
            "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code")
    assert _loaded(body) == "[]"


def test_naming_the_petsc_solver_loads_it():
    assert "petsc4py" in _loaded("import alcontact.linalg as L; L.make_solver('petsc')")
