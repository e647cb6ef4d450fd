"""The contact solve runs the PETSc solver the problem file names (``linear_solver``).

``"petsc-direct"`` (MUMPS) factorizes the condensed problem; ``"petsc"`` (KSP + GAMG, an
iterative solver) preconditions the full-space CG solves (:func:`alcontact.linalg.select_solver`).
Reference: the same problem file (examples/hertz_2d.toml) with the default linear solver; the
contact half-width and peak pressure agree to 1e-8 relative with petsc-direct (both solve the same
condensed systems exactly) and to 1e-6 with petsc (Newton and CG tolerances of the Krylov path,
1e-11 and the KSP's 1e-10).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


#: runs the CLI in a process that counts the factorizations of PETSc's direct solver (printed last)
COUNTING = """
import sys
from alcontact.linalg import PetscDirectSolver, PetscKrylovSolver
from alcontact.cli import main
calls = []
_direct, _krylov = PetscDirectSolver.factorize, PetscKrylovSolver.factorize
PetscDirectSolver.factorize = lambda self, *a, **k: calls.append(1) or _direct(self, *a, **k)
PetscKrylovSolver.factorize = lambda self, *a, **k: calls.append(1) or _krylov(self, *a, **k)
sys.argv = ["alcontact", "run", sys.argv[1], "--out", sys.argv[2], "--force"]
try:
    main()
except SystemExit as e:
    if e.code:
        raise
print("petsc factorizations:", len(calls))
"""


def _run(toml: Path, out: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", COUNTING, str(toml), str(out)],
                          capture_output=True, text=True, timeout=300)


def _with_solver(tmp_path: Path, name: str) -> Path:
    text = (ROOT / "examples" / "hertz_2d.toml").read_text()
    assert "\n[solver]\n" in text
    path = tmp_path / f"hertz_{name}.toml"
    path.write_text(text.replace("\n[solver]\n", f'\n[solver]\nlinear_solver = "{name}"\n', 1))
    return path


def test_petsc_direct_in_a_problem_file_gives_the_default_answer(tmp_path):
    runs = {}
    for tag, toml in (("default", ROOT / "examples" / "hertz_2d.toml"),
                      ("petsc-direct", _with_solver(tmp_path, "petsc-direct"))):
        proc = _run(toml, tmp_path / tag)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        runs[tag] = json.loads((tmp_path / tag / "summary.json").read_text())
        count = int(proc.stdout.strip().splitlines()[-1].split(":")[1])
        assert (count > 0) == (tag == "petsc-direct")  # the option took effect, and only there
    a, b = runs["default"], runs["petsc-direct"]
    assert b["status"] == "converged"
    for key in ("contact_half_width", "peak_pressure"):
        assert b[key] == pytest.approx(a[key], rel=1e-8)


def test_petsc_iterative_in_a_problem_file_runs_petsc(tmp_path):
    """``linear_solver = "petsc"`` is the solver that runs (it used to be refused: the Krylov path ran
    PyAMG whatever was named); its answer is the default one to 1e-6 relative."""
    runs = {}
    for tag, toml in (("default", ROOT / "examples" / "hertz_2d.toml"), ("petsc", _with_solver(tmp_path, "petsc"))):
        proc = _run(toml, tmp_path / tag)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        runs[tag] = json.loads((tmp_path / tag / "summary.json").read_text())
        count = int(proc.stdout.strip().splitlines()[-1].split(":")[1])
        assert (count > 0) == (tag == "petsc")
    a, b = runs["default"], runs["petsc"]
    assert b["status"] == "converged"
    for key in ("contact_half_width", "peak_pressure"):
        assert b[key] == pytest.approx(a[key], rel=1e-6)
