"""Issue 23 (rigid bodies in problem files): ``[obstacle]`` with a reference point is a rigid body.

``tests/data/tilted_punch.toml`` is a rigid flat punch, force and moment driven, on an elastic
block. References: the same problem built with the Python API (``RigidBody``, ``RigidLoad``,
``Support`` on its pose; the same equations: 1e-12 relative on every DOF), and the statics of the
rigid body in the results (contact force and moment = minus the applied ones, 1e-10). Every key
that does not fit is named by ``alcontact check`` (an error per key, nothing solved).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from alcontact.contact import (Boundary, ContactPair, ContactProblem, RigidBody, RigidLoad, Support, obstacles,
                               solve)
from alcontact.errors import ConfigError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.io.config import load_problem_text
from alcontact.io.preflight import check_problem

FILE = Path(__file__).resolve().parents[1] / "data" / "tilted_punch.toml"
TOML = FILE.read_text(encoding="utf-8")


def _api_problem():
    mesh = meshes.rectangle(-4.0, 4.0, -4.0, 0.0, 8, 4,
                            refine=dict(center=[0.0, 0.0], h_min=0.0625, width=1.5, depth=1.0, growth=1.2))
    block = LinearElasticity(mesh, Material(E=1000.0, nu=0.3))
    punch = RigidBody(obstacles.make("convex-polygon", vertices=[[-1, 0], [1, 0], [1, 2], [-1, 2]]), [0.0, 0.0])
    return ContactProblem(bodies=[block, punch], pairs=[ContactPair(Boundary(block, "top"), punch)],
                          supports=[Support("bottom"), Support("body1", components=[0])],
                          loads=[RigidLoad("body1", force=[0.0, -10.0], moment=1.0)])


def test_tilted_punch_file_equals_the_python_api():
    setup = check_problem(FILE).setup
    sol = solve(setup.problem, setup.algorithm)
    ref = solve(_api_problem(), "ssn")
    assert sol.result.success and ref.result.success
    assert np.max(np.abs(sol.u - ref.u)) <= 1e-12 * np.max(np.abs(ref.u))
    st = sol.extra["rigid_bodies"]["body1"]
    assert st["prescribed"] == ["u_x"] and st["rotation"][0] > 0  # a counter-clockwise moment turns it so
    np.testing.assert_allclose(st["contact_force"], [0.0, 10.0], atol=1e-10 * 10)
    np.testing.assert_allclose(st["contact_moment"], [-1.0], rtol=1e-10)


def test_results_folder_reports_the_rigid_body_per_step(tmp_path):
    from alcontact.app import run_setup

    text = TOML.replace("moment = 1.0 ", "moment = 1.0\nramp = [[0.0, 0.0], [1.0, 1.0]]\n") + "\n[loading]\nsteps = 2\n"
    setup = load_problem_text(text, base_dir=FILE.parent)
    run_setup(setup, tmp_path / "res")
    res = tmp_path / "res"
    summary = json.loads((res / "summary.json").read_text())
    assert summary["status"] == "converged"
    body = summary["rigid_bodies"]["body1"]
    np.testing.assert_allclose(body["applied_force"], [0.0, -10.0])
    np.testing.assert_allclose(body["contact_moment"], [-1.0], rtol=1e-10)
    assert summary["contact_force_balance"] <= 1e-12
    rows = (res / "reaction_force.csv").read_text().splitlines()
    head = rows[0].split(",")
    assert len(rows) == 3 and "rigid_body1_rot_z" in head and "rigid_body1_reaction_F_x" in head
    rot = [float(r.split(",")[head.index("rigid_body1_rot_z")]) for r in rows[1:]]
    assert rot[1] == pytest.approx(2 * rot[0], rel=1e-8)  # linear in the ramped load
    assert "rigid_body1_contact_M_z" in (res / "steps.csv").read_text().splitlines()[0]
    assert (res / "solution.vtu").exists() and (res / "solution.pvd").exists()


def _issues(text: str) -> dict[str, str]:
    with pytest.raises(ConfigError) as exc:
        load_problem_text(text, base_dir=FILE.parent)
    return {i.path: i.message for i in exc.value.issues}


@pytest.mark.parametrize("old, new, key, says", [
    ("reference = [0.0, 0.0]", "", "obstacle.reference", "needs its reference point"),
    ("reference = [0.0, 0.0]", "reference = [0.0, 0.0, 0.0]", "obstacle.reference", "the mesh is 2D"),
    ("force_y = -10.0", "force_y = -10.0\ndisplacement_y = -0.01", "obstacle.force_y", "either prescribed or loaded"),
    ("moment = 1.0", "moment_z = 1.0", "obstacle.moment_z", "not a key of a 2D rigid body; use moment"),
    ("moment = 1.0", "moment = 1.0\npath = [0.0, -0.1]", "obstacle.path", "remove path"),
    ('boundary = "top"', 'boundary = "top"\nfriction = 0.3', "contact.friction", "frictionless so far"),
    ('algorithm = "ssn"', 'algorithm = "ssn"\n\n[[pair]]\nboundary = "left"\ntype = "half-space"\n'
                          'point = [-4.0, 0.0]\nnormal = [1.0, 0.0]', "pair", "not supported yet"),
    ("reference = [0.0, 0.0]", "reference = [0.0, 0.0]\nramp = [[0.0, 0.0], [1.0]]", "obstacle.ramp", ""),
])
def test_bad_rigid_body_keys_are_named(old, new, key, says):
    assert old in TOML
    issues = _issues(TOML.replace(old, new, 1))
    assert key in issues, issues
    assert says in issues[key]


def test_rigid_body_at_finite_kinematics_is_refused():
    text = TOML.replace('boundary = "top"', 'boundary = "top"\nkinematics = "finite"').replace(
        "E = 1000.0", 'E = 1000.0\nmodel = "neo-hookean"')
    issues = _issues(text)
    assert "small deformation so far" in issues.get("contact.kinematics", ""), issues
