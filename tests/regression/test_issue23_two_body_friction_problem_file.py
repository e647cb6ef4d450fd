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
    grid = meshio.read(tmp_path / "res" / "solution.vtu")
    state, body = grid.point_data["contact_state"], grid.point_data["body"]
    assert np.all(state[body == 0] == -1) and set(np.unique(state[body == 1]).tolist()) == {-1.0, 2.0}
    assert np.max(np.abs(grid.point_data["slip"][body == 1])) > 0


def test_a_negative_two_body_friction_is_named():
    with pytest.raises(ConfigError) as info:
        load_problem_text(EXAMPLE.read_text().replace("friction = 0.3", "friction = -0.3"), base_dir=EXAMPLE.parent)
    assert "contact.friction" in str(info.value)
