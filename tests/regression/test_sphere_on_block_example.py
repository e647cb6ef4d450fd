"""examples/sphere_on_block.toml: an elastic sphere on an elastic block, 3D mortar contact (issue 23).

The sphere is the lower quarter of a hemisphere (R = 10 mm) meshed by Gmsh from
``examples/sphere_on_block.geo``, the block a generated graded box; the meshes do not match.
References: Hertz with the effective modulus (Johnson, Contact Mechanics, 1985, eq. 4.22-4.23,
1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2) for the load the model carries: contact radius and peak
pressure within 2 % (measured -1.1 % and +1.3 %, free fit of the pressure field; a/R = 0.1, so
the hemisphere is not Hertz's paraboloid to about 1 %); action = reaction to 1e-10; every
frictionless algorithm converges to the same pressures (1e-6 of the peak); ``alcontact check``
accepts the file and names the key of a 3D body asked for P2 elements.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from alcontact.cli import app
from alcontact.contact import solve
from alcontact.errors import ConfigError
from alcontact.io.config import load_problem_text
from alcontact.io.preflight import check_problem

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FILE = EXAMPLES / "sphere_on_block.toml"


@pytest.fixture(scope="module")
def setup():
    return check_problem(FILE).setup


@pytest.fixture(scope="module")
def solution(setup):
    return solve(setup.problem, setup.algorithm)


def test_sphere_on_block_file_is_a_3d_two_body_problem(setup):
    model = setup.problem.model
    assert len(model.bodies) == 2 and model.dim == 3
    assert [b.material.E for b in model.bodies] == [200e3, 70e3]
    pair = setup.problem.pairs[0]
    assert pair.rigid is False and pair.master.dim == 3 and pair.slave.body is model.bodies[1]
    e_star = 1.0 / ((1 - 0.3 ** 2) / 200e3 + (1 - 0.35 ** 2) / 70e3)
    assert setup.reference.kind == "sphere" and setup.reference.e_star == pytest.approx(e_star, rel=1e-14)


def test_sphere_on_block_hertz_and_action_reaction(setup, solution):
    sol = solution
    assert sol.result.success, sol.result.message
    assert sol.result.algorithm == setup.algorithm == "ssn"
    ref = setup.reference
    P = ref.load(sol.normal_force)
    a = sol.contact_half_width(center=(0.0, 0.0, 0.0))
    assert 0.08 < ref.half_width(P) / ref.radius < 0.12
    assert abs(a / ref.half_width(P) - 1) <= 0.02
    assert abs(sol.peak_pressure / ref.peak_pressure(P) - 1) <= 0.02
    fs, fm = np.asarray(sol.extra["slave_contact_force"]), np.asarray(sol.extra["master_contact_force"])
    assert fs[2] > 0 and np.linalg.norm(fs + fm) <= 1e-10 * np.linalg.norm(fs)


@pytest.mark.parametrize("algorithm,penalty", [("simo-laursen", None), ("family-p", "exp-met1"),
                                               ("family-p", "log-met2"), ("penalty", None)])
def test_sphere_on_block_every_frictionless_algorithm(setup, solution, algorithm, penalty):
    sol = solve(setup.problem, algorithm, penalty)
    assert sol.result.success and sol.result.algorithm == algorithm, sol.result.message
    # the pure penalty's pressures differ by its penetration (eps_N finite): the same to 1e-3
    tol = 1e-3 if algorithm == "penalty" else 1e-6
    np.testing.assert_allclose(sol.pressure, solution.pressure, atol=tol * solution.pressure.max())
    assert sol.extra["contact_force_balance"] <= 1e-10


def test_check_accepts_the_example():
    res = CliRunner().invoke(app, ["check", str(FILE)])
    assert res.exit_code == 0, res.output
    assert "2 bodies, 3D" in " ".join(res.stdout.split())


@pytest.mark.slow
def test_run_writes_the_results_folder(tmp_path):
    out = tmp_path / "res"
    res = CliRunner().invoke(app, ["run", str(FILE), "--out", str(out), "-q"])
    assert res.exit_code == 0, res.output
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "converged" and summary["dim"] == 3
    assert summary["contact_force_balance"] <= 1e-10


def test_p2_bodies_in_3d_are_refused_naming_the_key():
    text = FILE.read_text(encoding="utf-8").replace('generator = "box"\n', 'generator = "box"\norder = 2\n')
    assert "order = 2" in text
    with pytest.raises(ConfigError) as exc:
        load_problem_text(text, base_dir=EXAMPLES)
    issues = {i.path: i.message for i in exc.value.issues}
    assert "body[1].mesh.order" in issues and "order = 1" in issues["body[1].mesh.order"], issues
