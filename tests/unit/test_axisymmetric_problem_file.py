"""``[mesh] geometry = "axisymmetric"`` in problem files: declared, taking effect, refused where it cannot apply.

A body of revolution reports its forces as totals over the revolution; ``summary.json`` adds
them per radian (``<key>_per_radian = <key> / (2 pi)``).
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

from _helpers import assert_check_rejects, runner
from alcontact.cli import app
from alcontact.io import load_problem

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
BALL = (EXAMPLES / "rubber_ball_axisym.toml").read_text(encoding="utf-8")

#: a small-deformation Hertz sphere on an elastic cylinder, axisymmetric (linear elasticity)
HERTZ = """
[mesh]
generator = "rectangle"
bounds = [0.0, 10.0, -10.0, 0.0]
cells = [8, 8]
geometry = "axisymmetric"
[mesh.refine]
center = [0.0, 0.0]
h_min = 0.1
width = 1.6
depth = 1.0
growth = 1.3
[material]
E = 200e3
nu = 0.3
[[support]]
boundary = "bottom"
[obstacle]
type = "circle"
center = [0.0, 9.9]
radius = 10.0
[contact]
boundary = "top"
"""


def _file(tmp_path: Path, text: str) -> Path:
    shutil.copy(EXAMPLES / "rubber_ball_axisym.msh", tmp_path / "rubber_ball_axisym.msh")
    p = tmp_path / "p.toml"
    p.write_text(text, encoding="utf-8")
    return p


def test_the_example_builds_an_axisymmetric_hyperelastic_body(tmp_path):
    setup = load_problem(_file(tmp_path, BALL))
    model = setup.problem.model
    assert model.axisymmetric and type(model).__name__ == "Hyperelastic" and model.order == 2
    assert model.axis_dofs.size > 0 and set(model.axis_dofs) <= set(setup.problem.dirichlet()[0].tolist())


def test_geometry_defaults_to_cartesian(tmp_path):
    setup = load_problem(_file(tmp_path, HERTZ.replace('geometry = "axisymmetric"\n', "")))
    assert not setup.problem.model.axisymmetric and setup.problem.model.axis_dofs.size == 0


def test_summary_has_totals_and_per_radian_forces(tmp_path):
    out = tmp_path / "res"
    result = runner.invoke(app, ["run", str(_file(tmp_path, HERTZ)), "--out", str(out)])
    assert result.exit_code == 0, result.output
    s = json.loads((out / "summary.json").read_text())
    assert s["geometry"] == "axisymmetric" and s["status"] == "converged"
    assert s["total_contact_force_per_radian"] * 2 * math.pi == s["total_contact_force"]
    assert s["model_contact_force"] > 0
    assert s["contact_force_vector_per_radian"][1] * 2 * math.pi == s["contact_force_vector"][1]
    # the same file as a plane-strain body carries another force: the option took effect
    flat_out = tmp_path / "flat"
    plane = _file(tmp_path, HERTZ.replace('geometry = "axisymmetric"\n', ""))
    assert runner.invoke(app, ["run", str(plane), "--out", str(flat_out)]).exit_code == 0
    f = json.loads((flat_out / "summary.json").read_text())
    assert "geometry" not in f and abs(f["model_contact_force"] / s["model_contact_force"] - 1) > 0.5


def test_geometry_axisymmetric_is_refused_in_3d_naming_the_key(tmp_path):
    text = (HERTZ.replace('generator = "rectangle"', 'generator = "box"')
            .replace("bounds = [0.0, 10.0, -10.0, 0.0]", "bounds = [0.0, 10.0, 0.0, 10.0, -10.0, 0.0]")
            .replace("cells = [8, 8]", "cells = [2, 2, 2]").replace("center = [0.0, 0.0]\n", "center = [0.0, 0.0, 0.0]\n")
            .replace("center = [0.0, 9.9]", "center = [0.0, 0.0, 9.9]").replace('type = "circle"', 'type = "sphere"'))
    result = runner.invoke(app, ["check", str(_file(tmp_path, text))])
    assert_check_rejects(result, ["mesh.geometry", "geometry='axisymmetric' needs a 2D mesh", "this mesh is 3D"])


def test_bad_geometry_values_are_refused(tmp_path):
    result = runner.invoke(app, ["check", str(_file(tmp_path, HERTZ.replace('"axisymmetric"', '"axisymetric"')))])
    assert_check_rejects(result, ["mesh.geometry = 'axisymetric'", "'axisymmetric'"])
    neg = HERTZ.replace("bounds = [0.0, 10.0, -10.0, 0.0]", "bounds = [-1.0, 10.0, -10.0, 0.0]")
    result = runner.invoke(app, ["check", str(_file(tmp_path, neg))])
    assert_check_rejects(result, ["mesh.geometry", "x >= 0"])
