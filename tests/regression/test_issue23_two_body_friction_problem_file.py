"""Issue 23: Coulomb friction between two bodies from a problem file (``examples/two_body_friction.toml``).

The file is the block of :func:`alcontact.problems.two_body_friction.dragged_block` (n = 8) as two
``[[body]]`` tables with ``[contact] friction``. Checked: the file gives the Python API's solution
(every nodal displacement, difference 0 measured, 1e-12 asserted); the block slides, so the
tangential force equals the Coulomb limit mu N (reference: Coulomb's law at full slip, every
slave node on the circle; 1e-8); the forces on the base are equal and opposite (action = reaction,
1e-10); the VTU carries the slip and the stick/slip state; ``alcontact check`` names the friction,
and a bad coefficient is a ConfigError naming the key.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

from alcontact.app import run_setup
from alcontact.contact import solve
from alcontact.errors import ConfigError
from alcontact.io import load_problem
from alcontact.io.config import load_problem_text
from alcontact.problems import two_body_friction as tbf

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "two_body_friction.toml"


def test_two_body_friction_file_equals_the_api_and_slides_with_q_equal_mu_n(tmp_path):
    setup = load_problem(EXAMPLE)
    assert setup.friction == 0.3 and "Coulomb mu=0.3" in setup.summary_line()
    res = run_setup(setup, tmp_path / "res")
    s = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert s["status"] == "converged", s["message"]
    prob, hist = tbf.dragged_block(n=8)
    ref = solve(prob, setup.algorithm, history=hist)
    assert ref.result.success
    np.testing.assert_allclose(res.frames[-1].u, ref.u, rtol=0, atol=1e-12 * np.abs(ref.u).max())
    assert s["slip_points"] == prob.model.node_dofs(prob.contact_boundary)[0].shape[0] and s["stick_points"] == 0
    assert s["tangential_force"] == pytest.approx(s["coulomb_limit"], rel=1e-8)
    assert s["coulomb_limit"] == pytest.approx(0.3 * s["total_contact_force"], rel=1e-12)
    slave, master = np.array(s["slave_contact_force"]), np.array(s["master_contact_force"])
    assert s["contact_force_balance"] <= 1e-10 and np.linalg.norm(slave + master) <= 1e-10 * np.linalg.norm(slave)
    assert s["equilibrium_residual"] <= 1e-8
    pair = s["pair_contact_forces"][0]
    assert pair["friction"] == 0.3 and pair["tangential_force"][0] == pytest.approx(slave[0], rel=1e-12)
    assert pair["master_force"] == s["master_contact_force"] and pair["force_balance"] <= 1e-10
    grid = meshio.read(tmp_path / "res" / "solution.vtu")
    state, body = grid.point_data["contact_state"], grid.point_data["body"]
    assert np.all(state[body == 0] == -1) and set(np.unique(state[body == 1]).tolist()) == {-1.0, 2.0}
    assert np.max(np.abs(grid.point_data["slip"][body == 1])) > 0


def test_a_negative_two_body_friction_is_named():
    with pytest.raises(ConfigError) as info:
        load_problem_text(EXAMPLE.read_text().replace("friction = 0.3", "friction = -0.3"), base_dir=EXAMPLE.parent)
    assert "contact.friction" in str(info.value)


def test_cattaneo_mindlin_between_two_bodies_from_a_problem_file(tmp_path):
    """``[reference] kind = "cattaneo-mindlin"`` with ``[[body]]``: the two identical cylinders of
    :func:`~alcontact.problems.two_body_friction.cattaneo_mindlin_cylinders` (32 elements per a; its meshes written
    as one Gmsh file, a physical group per body) as a problem file: summary.json's stick half-width against Johnson's c = a sqrt(1 - Q/(mu P))
    with the pair's E*, R is that of tests/verification/test_two_body_friction.py on the same meshes (-1.48 %;
    the reference's tolerance 2 %)."""
    sys.path.insert(0, str(EXAMPLE.parent))
    from two_cylinders_mesh import write_bodies  # the Gmsh writer of examples/two_cylinders.toml's mesh

    prob, _ = tbf.cattaneo_mindlin_cylinders(n_per_a=32)
    write_bodies(list(prob.model.bodies), ["lower", "upper"], tmp_path / "cm.msh")
    delta, s = prob.meta["delta"], prob.meta["s"]
    text = f'''[problem]
name = "two-body-mindlin"
description = "Two identical cylinders pressed, then sheared into partial slip."

[[body]]
mesh = {{ generator = "file", file = "cm.msh", group = "lower" }}
material = {{ E = 200e3, nu = 0.3, plane = "strain" }}

[[body]]
mesh = {{ generator = "file", file = "cm.msh", group = "upper" }}
material = {{ E = 200e3, nu = 0.3, plane = "strain" }}

[contact]
boundary = "body1/bottom"
master = "body0/top"
friction = 0.3

[[support]]
boundary = "body0/bottom"

[[support]]
boundary = "body1/top"
components = [1]
value = {-delta!r}
ramp = [[0.0, 0.0], [0.5, 1.0]]

[[support]]
boundary = "body1/top"
components = [0]
value = {s!r}
ramp = [[0.5, 0.0], [1.0, 1.0]]
tangential = true

[loading]
steps = 4
friction_ramp = [[0.5, 0.0], [0.500000001, 1.0]]

[solver]
algorithm = "ssn"

[reference]
kind = "cattaneo-mindlin"
radius = 10.0
center = [0.0, 0.0]
'''
    (tmp_path / "cm.toml").write_text(text)
    setup = load_problem(tmp_path / "cm.toml")
    assert setup.mindlin is not None and setup.mindlin.hertz.e_star == pytest.approx(prob.reference.hertz.e_star)
    res = run_setup(setup)  # the summary only (no results folder)
    summary = res.summary
    assert summary["status"] == "converged", summary["message"]
    assert abs(summary["stick_half_width_error_pct"]) <= 2.0
    assert summary["stick_half_width_error_pct"] == pytest.approx(-1.48, abs=0.1)
