"""``mpirun -n N alcontact run problem.toml``: the distributed contact path from a problem file.

Reference: the serial ``alcontact run`` of the same file (examples/hertz_2d.toml, default linear
solver). With ``linear_solver = "petsc-direct"`` the distributed run on 2 ranks gives the same
contact force (``model_contact_force``, the sum of w * lambda), the same largest nodal pressure and
the same displacement at every node of the VTU pieces (ghost nodes included) to 1e-8 relative;
a misspelt PETSc option is reported once by name.
The pieces are one per rank, listed by ``solution.pvtu``; ``summary.json`` and ``report.md``
are written once. What is not distributed yet is refused with one message and the usage exit code.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ._mpi import MPI_ENV

ROOT = Path(__file__).resolve().parents[2]
CLI = str(Path(sys.executable).parent / "alcontact")


def _mpirun(n: int, *args: str, cwd: Path, timeout: float = 240.0) -> subprocess.CompletedProcess:
    env = dict(os.environ, **MPI_ENV)
    return subprocess.run(["mpirun", "-n", str(n), "--oversubscribe", CLI, *args], capture_output=True, text=True,
                          timeout=timeout, env=env, cwd=cwd)


def _with_solver(tmp_path: Path, name: str, extra: str = "") -> Path:
    text = (ROOT / "examples" / "hertz_2d.toml").read_text()
    assert "\n[solver]\n" in text
    path = tmp_path / f"hertz_{name}.toml"
    path.write_text(text.replace("\n[solver]\n", f'\n[solver]\nlinear_solver = "{name}"\n{extra}', 1))
    return path


def test_mpirun_alcontact_run_gives_the_serial_answer(tmp_path):
    import meshio

    serial = subprocess.run([CLI, "run", str(ROOT / "examples" / "hertz_2d.toml"), "--out", "serial", "-q"],
                            capture_output=True, text=True, timeout=240, cwd=tmp_path)
    assert serial.returncode == 0, serial.stderr
    # a misspelt PETSc option (ksp_rtoll) runs and is reported once, by name (PETSc's unused-option check)
    toml = _with_solver(tmp_path, "petsc-direct", "petsc_options = { ksp_rtoll = 1e-9 }\n")
    proc = _mpirun(2, "run", str(toml), "--out", "dist", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    a = json.loads((tmp_path / "serial" / "summary.json").read_text())
    b = json.loads((tmp_path / "dist" / "summary.json").read_text())
    assert b["status"] == "converged" and b["ranks"] == 2 and b["linear_solver"] == "petsc-direct"
    assert b["model_contact_force"] == pytest.approx(a["model_contact_force"], rel=1e-8)
    assert b["peak_pressure_nodal_max"] == pytest.approx(a["peak_pressure_nodal_max"], rel=1e-8)
    assert b["equilibrium"]["residual"] <= 1e-8 and b["equilibrium"]["balance"] <= 1e-8
    assert "converged" in proc.stdout and proc.stdout.count("converged") == 1  # rank 0 prints, once
    assert (proc.stdout + proc.stderr).count("ksp_rtoll") == 1, proc.stdout + proc.stderr
    assert b["petsc_options"] == {"ksp_rtoll": 1e-9}
    # the pieces: one per rank, listed by the .pvtu, the displacement the serial one at every node
    files = sorted(p.name for p in (tmp_path / "dist").iterdir())
    assert files == ["report.md", "solution.pvd", "solution.pvtu", "solution_0.vtu", "solution_1.vtu",
                     "summary.json"]
    pvtu = (tmp_path / "dist" / "solution.pvtu").read_text()
    assert 'Source="solution_0.vtu"' in pvtu and 'Source="solution_1.vtu"' in pvtu
    ref = meshio.read(tmp_path / "serial" / "solution.vtu")
    u_ref = {tuple(np.round(x, 12)): u for x, u in zip(ref.points, ref.point_data["displacement"])}
    scale = float(np.max(np.abs(ref.point_data["displacement"])))
    seen = set()
    for piece in ("solution_0.vtu", "solution_1.vtu"):
        m = meshio.read(tmp_path / "dist" / piece)
        for x, u in zip(m.points, m.point_data["displacement"]):
            key = tuple(np.round(x, 12))
            assert np.max(np.abs(u - u_ref[key])) <= 1e-8 * scale
            seen.add(key)
    assert seen == set(u_ref)  # the pieces cover the mesh


@pytest.mark.parametrize("args,expect", [
    (("run", str(ROOT / "examples" / "finite_half_cylinder.toml"), "--out", "r"), "finite deformation"),
    (("run", "--out", "r"), "without a problem file"),
])
def test_what_is_not_distributed_is_refused_once(tmp_path, args, expect):
    proc = _mpirun(2, *args, cwd=tmp_path, timeout=120)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    text = proc.stdout + proc.stderr
    errors = [line for line in text.splitlines() if line.startswith("error")]
    assert len(errors) == 1, text
    assert expect in " ".join(text.split())
    assert "Traceback" not in text
    assert not (tmp_path / "r").exists()


def test_mpirun_alcontact_run_with_load_steps(tmp_path):
    """The flat punch of examples/flat_punch.toml (four load steps, semi-smooth Newton) on 2 ranks: one entry per
    step in summary.json, each step's contact force the serial run's to 1e-8 (reference: the serial ``alcontact
    run`` of the same file, its ``steps.csv``), and a ``.pvd`` over the four steps' ``.pvtu`` files, each listing
    one piece per rank."""
    import csv

    punch = str(ROOT / "examples" / "flat_punch.toml")
    serial = subprocess.run([CLI, "run", punch, "--out", "serial", "-q"], capture_output=True, text=True, timeout=240,
                            cwd=tmp_path)
    assert serial.returncode == 0, serial.stderr
    proc = _mpirun(2, "run", punch, "--out", "dist", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    b = json.loads((tmp_path / "dist" / "summary.json").read_text())
    assert b["status"] == "converged" and b["ranks"] == 2 and len(b["steps"]) == 4
    with open(tmp_path / "serial" / "steps.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 4
    key = "force_y"
    for row, step in zip(rows, b["steps"]):
        assert step["status"] == "converged"
        assert float(row["t"]) == pytest.approx(step["t"], rel=1e-12)
        assert step["contact_force_vector"][1] == pytest.approx(float(row[key]), rel=1e-8)
    pvd = (tmp_path / "dist" / "solution.pvd").read_text()
    for k in range(1, 5):
        assert f"steps/solution_{k:04d}.pvtu" in pvd
        pvtu = (tmp_path / "dist" / "steps" / f"solution_{k:04d}.pvtu").read_text()
        assert f'Source="solution_{k:04d}_0.vtu"' in pvtu and f'Source="solution_{k:04d}_1.vtu"' in pvtu
        assert (tmp_path / "dist" / "steps" / f"solution_{k:04d}_1.vtu").is_file()


def test_mpirun_alcontact_run_with_friction(tmp_path):
    """The sliding block of examples/sliding_block.toml (Coulomb, mu = 0.3, eight steps) on 2 ranks: every step's
    normal force and tangential force magnitude equal the serial run's (its ``steps.csv``) to 1e-8, the last two
    steps slide (|T| = mu N, Coulomb), and each step has one VTU piece per rank."""
    import csv

    block = str(ROOT / "examples" / "sliding_block.toml")
    serial = subprocess.run([CLI, "run", block, "--out", "serial", "-q"], capture_output=True, text=True, timeout=240,
                            cwd=tmp_path)
    assert serial.returncode == 0, serial.stderr
    proc = _mpirun(2, "run", block, "--out", "dist", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    b = json.loads((tmp_path / "dist" / "summary.json").read_text())
    assert b["status"] == "converged" and b["ranks"] == 2 and b["friction"] == 0.3 and len(b["steps"]) == 8
    with open(tmp_path / "serial" / "steps.csv") as fh:
        rows = list(csv.DictReader(fh))
    for row, step in zip(rows, b["steps"], strict=True):
        assert float(row["t"]) == pytest.approx(step["t"], rel=1e-12)
        assert step["normal_force"] == pytest.approx(float(row["normal_force"]), rel=1e-8)
        n = float(row["normal_force"])
        assert abs(np.linalg.norm(step["tangential_force"]) - float(row["tangential_force"])) <= 1e-8 * n
    for step in b["steps"][-2:]:
        assert np.linalg.norm(step["tangential_force"]) == pytest.approx(0.3 * step["normal_force"], rel=1e-8)
    for k in range(1, 9):
        assert (tmp_path / "dist" / "steps" / f"solution_{k:04d}_1.vtu").is_file()
