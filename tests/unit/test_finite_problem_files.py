"""Finite deformation in problem files: ``[contact] kinematics``, ``[material] model``, ``[obstacle] path``.

Bad input is refused by ``alcontact check`` and ``alcontact run`` with exit code 2 and a
message naming the key and the way out, before anything is solved or written; a load
step that drives the body through the obstacle is cut back with a message and ends
with exit code 1. A run writes the deformed configuration of every step, the
reaction-force curve and the per-step Newton iterations.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import meshio
import numpy as np
import pytest

from _helpers import assert_check_rejects, flat, runner
from alcontact.cli import app
from alcontact.fem import meshes

from test_mesh_quality import _moved, _write_msh

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EXAMPLE = (EXAMPLES / "finite_half_cylinder.toml").read_text(encoding="utf-8")

KIN = '\nkinematics = "finite"\n'  # the key line (the comments mention it too)


def _file(tmp_path: Path, text: str) -> Path:
    shutil.copy(EXAMPLES / "half_cylinder.msh", tmp_path / "half_cylinder.msh")
    p = tmp_path / "p.toml"
    p.write_text(text, encoding="utf-8")
    return p


def _tangled(tmp_path: Path) -> str:
    good = meshes.rectangle(0, 1, 0, 1, 6, 6)
    bad, _ = _moved(good, (0.5, 0.5), np.array([0.22, 0.1]))
    _write_msh(tmp_path / "tangled.msh", bad, good.boundaries)
    return ('[mesh]\ngenerator = "file"\nfile = "tangled.msh"\n[material]\nE = 1000.0\nnu = 0.3\n'
            'model = "neo-hookean"\n[[support]]\nboundary = "bottom"\n[obstacle]\ntype = "half-space"\n'
            'point = [0.0, 1.001]\nnormal = [0.0, -1.0]\n[contact]\nboundary = "top"\nkinematics = "finite"\n')


CASES = {
    "nu": (lambda tmp: EXAMPLE.replace("nu = 0.3", "nu = 0.5"),  # exactly incompressible: mixed P2 body only
           ["material.nu = 0.5", "mixed", "mesh.order = 2", "use nu < 0.5"]),
    "nu-above-half": (lambda tmp: EXAMPLE.replace("nu = 0.3", "nu = 0.6"),
                      ["material.nu = 0.6", "out of range, must be in (-1, 0.5]"]),
    "model": (lambda tmp: EXAMPLE.replace('model = "neo-hookean"', 'model = "neo-hooke"'),
              ["material.model = 'neo-hooke'", "Did you mean 'neo-hookean'?", "'saint-venant-kirchhoff'"]),
    "kinematics": (lambda tmp: EXAMPLE.replace(KIN, '\nkinematics = "large"\n'),
                   ["contact.kinematics = 'large'", "Allowed: 'small', 'finite'"]),
    "linear-finite": (lambda tmp: EXAMPLE.replace('model = "neo-hookean"', 'model = "linear"'),
                      ["material.model = 'linear'", "needs a hyperelastic law", "model = 'neo-hookean'"]),
    "hyper-small": (lambda tmp: EXAMPLE.replace(KIN, '\nkinematics = "small"\n'),
                    ["contact.kinematics = 'small'", "'neo-hookean' needs kinematics = 'finite'",
                     "material.model = 'linear'"]),
    "friction-ramp": (lambda tmp: EXAMPLE.replace(KIN, KIN + 'friction = 0.2\n')
                      .replace("steps = 4", "steps = 4\nfriction_ramp = [[0.0, 0.0], [1.0, 1.0]]"),
                      ["loading.friction_ramp", "not available with contact.kinematics = 'finite'",
                       "remove friction_ramp"]),
    "plane": (lambda tmp: EXAMPLE.replace("nu = 0.3", 'nu = 0.3\nplane = "stress"'),
              ["material.plane = 'stress'", "plane strain only", "plane = 'strain'"]),
    "path-small": (lambda tmp: EXAMPLE.replace('model = "neo-hookean"', 'model = "linear"')
                   .replace(KIN, '\nkinematics = "small"\n')
                   .replace("normal = [0.0, 1.0]", "normal = [0.0, 1.0]\npath = [0.0, 0.1]"),
                   ["obstacle.path", "needs contact.kinematics = 'finite'", "remove path"]),
    "path-length": (lambda tmp: EXAMPLE.replace("normal = [0.0, 1.0]", "normal = [0.0, 1.0]\npath = [0.0, 0.1, 0.0]"),
                    ["obstacle.path = [0.0, 0.1, 0.0]", "needs 2 numbers"]),
    "cutbacks": (lambda tmp: EXAMPLE.replace("steps = 4", "steps = 4\nmax_cutbacks = -1"),
                 ["loading.max_cutbacks = -1", "out of range, must be in [0, 20]"]),
    "tangled": (_tangled, ["mesh.file = 'tangled.msh'", "1 inverted element(s)"]),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_check_refuses_bad_finite_input_naming_the_key(tmp_path, case):
    make, expected = CASES[case]
    p = _file(tmp_path, make(tmp_path))
    result = runner.invoke(app, ["check", str(p)])
    assert_check_rejects(result, expected)


@pytest.mark.parametrize("case", ["nu", "model", "kinematics", "tangled"])
def test_run_refuses_bad_finite_input_and_writes_nothing(tmp_path, case):
    make, expected = CASES[case]
    p = _file(tmp_path, make(tmp_path))
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", str(p), "--out", str(out)])
    assert result.exit_code == 2 and expected[0] in flat(result.stderr), result.output
    assert not out.exists()


def test_check_counts_newton_iterations_of_every_step(tmp_path):
    p = _file(tmp_path, EXAMPLE)
    result = runner.invoke(app, ["check", str(p)])
    msg = flat(result.output)
    assert result.exit_code == 0, result.output
    assert "finite deformation (neo-hookean)" in msg
    # the solver time of a finite run: steps x measured tangent units per step (io/time_calibration.json)
    assert "4 load steps x ~" in msg and "tangent assembly + solve units per frictionless" in msg


def test_run_writes_the_deformed_configuration_and_the_reaction_force_curve(tmp_path):
    p = _file(tmp_path, EXAMPLE)
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", str(p), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "Newton iterations per step" in result.output
    s = json.loads((out / "summary.json").read_text())
    for f in ("solution.pvd", "reaction_force.csv", "reaction_force.png", "steps.csv", "summary.json"):
        assert f in s["files"] and (out / f).is_file()
    assert s["kinematics"] == "finite" and s["material_model"] == "neo-hookean"
    assert s["step_times"] == [0.25, 0.5, 0.75, 1.0]
    assert len(s["step_newton_iterations"]) == 4 and all(k >= 1 for k in s["step_newton_iterations"])
    assert s["newton_iterations"] == sum(s["step_newton_iterations"])
    assert s["final_contact_force"] == s["step_contact_force"][-1]
    assert s["equilibrium_residual"] < 1e-8
    # every step's VTU holds the deformed points x = X + u (top face pushed down by t * 0.2)
    pvd = (out / "solution.pvd").read_text()
    assert pvd.count("<DataSet") == 4
    for k, t in enumerate(s["step_times"]):
        m = meshio.read(out / "steps" / f"solution_{k + 1:04d}.vtu")
        X, u = m.point_data["reference_position"], m.point_data["displacement"]
        np.testing.assert_allclose(m.points, X + u, rtol=0, atol=1e-12)
        top = np.isclose(X[:, 1], 1.0)
        np.testing.assert_allclose(m.points[top, 1], 1.0 - 0.2 * t, rtol=0, atol=1e-12)
        assert m.points[:, 1].min() >= -1e-8  # nothing below the plane y = 0
    # the reaction-force curve: the support reactions balance the contact force at every step
    rows = (out / "reaction_force.csv").read_text().splitlines()
    head = rows[0].split(",")
    assert head[:2] == ["step", "t"] and "u_top_y" in head and "reaction_y" in head
    vals = np.array([[float(x) for x in r.split(",")] for r in rows[1:]])
    ry, fy, uy = (vals[:, head.index(c)] for c in ("reaction_y", "force_y", "u_top_y"))
    np.testing.assert_allclose(ry, -fy, rtol=1e-8)
    np.testing.assert_allclose(uy, -0.2 * vals[:, 1], rtol=1e-12)
    assert np.all(np.diff(fy) > 0)  # pressed further, pushed back harder


def test_step_through_the_obstacle_is_cut_back_with_a_message(tmp_path):
    """The plane moves up by 1.2 R in one step, through the fixed top face y = R: the step is cut back,
    the smallest increment fails, the run ends with a negative status, the message and exit code 1."""
    text = (EXAMPLE.replace("steps = 4", "steps = 1\nmax_cutbacks = 1").replace("value = -0.2", "value = 0.0")
            .replace("normal = [0.0, 1.0]", "normal = [0.0, 1.0]\npath = [0.0, 1.2]"))
    p = _file(tmp_path, text)
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", str(p), "--out", str(out)])
    msg = flat(result.stderr)
    assert result.exit_code == 1, result.output
    assert "not converged (newton-failed)" in msg and "use more load steps" in msg
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "newton-failed" and s["cutbacks"] >= 1
    assert s["message"].startswith("stopped at t=0.5 of t=1")
    assert s["obstacle_path"] == [0.0, 1.2]


def test_without_a_ramp_every_load_grows_in_proportion_to_t(tmp_path):
    """No ``ramp``: the nonzero support value is ramped linearly (same steps as the explicit ramp, to 1e-10)."""
    from alcontact.io.config import load_problem_text
    from alcontact.runner import run_setup

    ramped = run_setup(load_problem_text(EXAMPLE, base_dir=EXAMPLES)).summary
    plain = run_setup(load_problem_text(EXAMPLE.replace("ramp = [[0.0, 0.0], [1.0, 1.0]]\n", ""),
                                        base_dir=EXAMPLES)).summary
    assert plain["status"] == "converged"
    np.testing.assert_allclose(plain["step_contact_force"], ramped["step_contact_force"], rtol=1e-10, atol=1e-10)


IRONING = (EXAMPLES / "finite_ironing_friction.toml").read_text(encoding="utf-8")


def test_frictional_finite_run_writes_slip_states_and_the_tangential_reaction(tmp_path):
    """``friction = 0.3`` with ``kinematics = "finite"`` runs (the ironing example on 8 x 2 elements, 4
    steps): the folder of a finite run (deformed configuration x = X + u to 1e-12 in every step's VTU, with
    the slip and stick/slip state fields), the per-step Newton iterations and dissipation (>= 0, summed in
    ``dissipation`` to 1e-12), and the tangential component in ``reaction_force.csv``: support reaction =
    -contact force to 1e-8 relative in both components at every step (global equilibrium)."""
    text = IRONING.replace("cells = [16, 4]", "cells = [8, 2]").replace("steps = 16", "steps = 4")
    p = tmp_path / "p.toml"
    p.write_text(text, encoding="utf-8")
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", str(p), "--out", str(out)])
    assert result.exit_code == 0, result.output
    s = json.loads((out / "summary.json").read_text())
    for f in ("solution.pvd", "reaction_force.csv", "reaction_force.png", "steps.csv", "summary.json"):
        assert f in s["files"] and (out / f).is_file()
    assert s["kinematics"] == "finite" and s["friction"] == 0.3 and s["status"] == "converged"
    assert s["step_times"] == [0.25, 0.5, 0.75, 1.0]
    assert len(s["step_newton_iterations"]) == 4 and all(k >= 1 for k in s["step_newton_iterations"])
    assert s["newton_iterations"] == sum(s["step_newton_iterations"])
    assert all(d >= 0 for d in s["step_dissipation"]) and s["dissipation"] > 0
    assert s["dissipation"] == pytest.approx(sum(s["step_dissipation"]), rel=1e-12)
    assert s["slip_points"] >= 1
    assert (out / "solution.pvd").read_text().count("<DataSet") == 4
    for k in range(4):
        m = meshio.read(out / "steps" / f"solution_{k + 1:04d}.vtu")
        X, u = m.point_data["reference_position"], m.point_data["displacement"]
        np.testing.assert_allclose(m.points, X + u, rtol=0, atol=1e-12)
        state = m.point_data["contact_state"]
        assert set(np.unique(state)) <= {-1.0, 0.0, 1.0, 2.0} and np.any(state > 0)
        assert m.point_data["slip"].shape[1] == 3
    rows = (out / "reaction_force.csv").read_text().splitlines()
    head = rows[0].split(",")
    vals = np.array([[float(x) for x in r.split(",")] for r in rows[1:]])
    for c in ("x", "y"):
        r, f = vals[:, head.index(f"reaction_{c}")], vals[:, head.index(f"force_{c}")]
        np.testing.assert_allclose(r, -f, rtol=1e-8, atol=1e-8 * np.abs(f).max())
    assert np.all(vals[1:, head.index("force_x")] > 0)  # the cylinder drags the strip along +x

