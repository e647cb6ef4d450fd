"""The contact path's direct wing factorizes with ``linear_solver = "petsc-direct"`` (MUMPS).

Reference: the same problem file (examples/hertz_2d.toml) with the default linear solver; the
contact half-width and peak pressure agree to 1e-8 relative (both solve the same condensed
systems exactly). "petsc" (iterative) is refused by the problem file: the contact path's
factorization-free wing would run PyAMG, not it.
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
from alcontact.linalg import PetscDirectSolver
from alcontact.cli import main
calls = []
_orig = PetscDirectSolver.factorize
PetscDirectSolver.factorize = lambda self, *a, **k: calls.append(1) or _orig(self, *a, **k)
sys.argv = ["alcontact", "run", sys.argv[1], "--out", sys.argv[2], "--force"]
try:
    main()
except SystemExit as e:
    if e.code:
        raise
print("petsc-direct factorizations:", len(calls))
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


def test_petsc_iterative_is_refused_by_the_problem_file(tmp_path):
    proc = _run(_with_solver(tmp_path, "petsc"), tmp_path / "r")
    assert proc.returncode != 0
    assert "linear_solver" in proc.stdout + proc.stderr and "petsc-direct" in proc.stdout + proc.stderr
    assert "Traceback" not in proc.stdout + proc.stderr
