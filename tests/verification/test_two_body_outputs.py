"""Both sides of a pair between two bodies in the outputs: master-side pressure and gap, force on each body.

Reference: the contact patch test (two stacked blocks, non-matching meshes, a uniform pressure
``p`` on top: the interface pressure is ``p`` everywhere, the closed form of
``tests/verification/test_two_body_mortar.py``). The master-side pressure carries the slave
nodal forces by the mortar weights, ``p_m,k = sum_j P_jk w_j lambda_j / D_m,k``; since the dual
basis sums to one, ``sum_j P_jk w_j = D_m,k`` for a master node covered by the slave, so the
master side is ``p`` at every master node to 1e-10 relative (P1 and P2, 2:3 and 3:7), and the
master-side gap is zero to round-off. The forces on the two bodies are equal and opposite to
1e-12 relative and equal ``p`` times the width. The results folder carries both sides: the VTU
(the master body's boundary vertices), ``interface_pressure.png``, ``summary.json``
(``contact_pairs``, ``body_contact_forces``) and ``report.md`` (its "Contact pairs" section).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.problems.two_body import stacked_blocks

P = 10.0


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("ratio", [(2, 3), (3, 7)])
def test_master_side_pressure_is_the_patch_pressure(order, ratio):
    problem = stacked_blocks(*ratio, pressure=P, order=order)
    sol = solve(problem, "ssn")
    assert sol.result.status > 0, sol.result.message
    side = sol.extra["master_side"]
    assert side["boundary"] == "top" and side["points"].shape[0] == problem.model.bodies[0].node_dofs("top")[0].shape[0]
    np.testing.assert_allclose(side["pressure"], P, rtol=1e-10)
    assert np.max(np.abs(side["gap"])) <= 1e-12
    forces = sol.extra["body_contact_forces"]
    f0, f1 = np.array(forces["body0"]), np.array(forces["body1"])
    assert np.linalg.norm(f0 + f1) <= 1e-12 * np.linalg.norm(f1)
    np.testing.assert_allclose(f1, [0.0, P * 1.0], rtol=1e-10, atol=1e-10 * P)  # width 1
    (pair,) = sol.extra["contact_pairs"]
    assert pair["slave"] == "body1/bottom" and pair["master"] == "body0/top"
    assert pair["contact_force_balance"] <= 1e-12


def test_results_folder_shows_both_sides(tmp_path):
    import meshio

    from alcontact.app import run_setup
    from alcontact.io.config import load_problem

    example = Path(__file__).resolve().parents[2] / "examples" / "two_cylinders.toml"
    res = tmp_path / "res"
    run_setup(load_problem(example), res)
    grid = meshio.read(res / "solution.vtu")
    body, p = grid.point_data["body"], grid.point_data["contact_pressure"]
    assert p[body == 0].max() > 0 and p[body == 1].max() > 0  # the master body carries its side of the pressure
    summary = json.loads((res / "summary.json").read_text())
    # the total force on the master side equals the slave's: Hertz's P on both
    pair = summary["contact_pairs"][0]
    assert pair["contact_force_balance"] <= 1e-12
    assert set(summary["body_contact_forces"]) == {"body0", "body1"}
    assert (res / "interface_pressure.png").is_file() and "interface_pressure.png" in summary["files"]
    report = (res / "report.md").read_text()
    assert "## Contact pairs" in report and "`body1/bottom` | `body0/top`" in report
