"""``[solver] linear_solver = "amg"`` with ``[contact] kinematics = "finite"`` in problem files.

The finite half-cylinder example (``examples/finite_half_cylinder.toml``, 4 load steps) runs on
the AMG + CG path when the problem file asks for it: ``summary.json`` names the path
(``linear_solver``) with its CG iterations and AMG setups, and the contact force of every
step equals that of the direct run within 1e-8 relative (the tolerance of
``tests/verification/test_finite_amg.py``). The semi-smooth reference ``ssn`` has no AMG
path: ``alcontact check`` refuses the file with exit code 2, naming the key and the way out.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from alcontact import linalg
from alcontact.cli import app

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EXAMPLE = (EXAMPLES / "finite_half_cylinder.toml").read_text(encoding="utf-8")

runner = CliRunner(env={"COLUMNS": "400", "NO_COLOR": "1"})


def _file(tmp_path: Path, solver: str) -> Path:
    shutil.copy(EXAMPLES / "half_cylinder.msh", tmp_path / "half_cylinder.msh")
    p = tmp_path / "p.toml"
    p.write_text(EXAMPLE + "\n[solver]\n" + solver, encoding="utf-8")
    return p


def _run(tmp_path: Path, solver: str, name: str) -> dict:
    out = tmp_path / name
    result = runner.invoke(app, ["run", str(_file(tmp_path, solver)), "--out", str(out)])
    assert result.exit_code == 0, result.output
    return json.loads((out / "summary.json").read_text())


def test_finite_problem_file_runs_on_the_amg_path(tmp_path):
    """Summary names the path; forces of every step within 1e-8 relative of the direct run (module doc)."""
    amg = _run(tmp_path, 'linear_solver = "amg"\n', "amg")
    direct = _run(tmp_path, 'linear_solver = "direct"\n', "direct")
    assert amg["linear_solver"] == "amg" and linalg.solver_kind(direct["linear_solver"]) == "direct"
    assert amg["linear_solver_strategy"] == direct["linear_solver_strategy"] == "full-space-newton"
    assert amg["cg_iterations"] > 0 and amg["amg_setups"] >= 1 and amg["direct_fallbacks"] == 0
    assert amg["step_times"] == direct["step_times"] == [0.25, 0.5, 0.75, 1.0]
    fa, fd = np.array(amg["step_contact_force"]), np.array(direct["step_contact_force"])
    assert np.max(np.abs(fa[:, 1] - fd[:, 1]) / np.abs(fd[:, 1])) <= 1e-8


def test_ssn_with_amg_is_refused_naming_the_key(tmp_path):
    """``algorithm = "ssn"`` with ``linear_solver = "amg"`` at finite kinematics: exit code 2, the key and 'direct'."""
    p = _file(tmp_path, 'algorithm = "ssn"\nlinear_solver = "amg"\n')
    result = runner.invoke(app, ["check", str(p)])
    msg = " ".join(result.output.split())
    assert result.exit_code == 2, result.output
    assert "linear_solver = 'amg'" in msg and "'ssn' has no AMG path" in msg and "'direct'" in msg


def test_list_shows_the_finite_amg_path():
    """``alcontact list algorithms``: the augmented-Lagrangian algorithms run on ``finite: direct, amg``, ssn on
    ``finite: direct``."""
    result = runner.invoke(app, ["list", "algorithms"])
    out = " ".join(result.output.split())
    assert result.exit_code == 0
    assert out.count("finite: direct, amg]") == 3 and "[small: direct, amg; finite: direct]" in out
