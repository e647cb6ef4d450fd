"""Issue 18, case 6: the equilibrium residual read 1.0 (round-off over round-off) on converged runs whose
contact force is zero (3D Hertz with no bottom support: the sphere pushes the body away, a rigid
translation with no load, no reaction and no contact force).

The measure's scale now includes a stiffness times the displacement (``E' h^(d-2) max|u|``) and the
internal and applied forces, so it does not vanish with the contact force: reference value 0
(exact equilibrium), tolerance ``newton_tol`` = 1e-12.
"""

from __future__ import annotations

from pathlib import Path

from alcontact.io.config import load_problem_text
from alcontact.runner import run_setup

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "hertz_3d.toml"


def test_hertz_3d_without_bottom_support():
    text = EXAMPLE.read_text().replace('[[support]]\nboundary = "bottom"\n\n', "")
    assert 'boundary = "bottom"' not in text
    res = run_setup(load_problem_text(text, base_dir=EXAMPLE.parent))
    s = res.summary
    assert s["status"] == "converged", s["message"]
    assert s["model_contact_force"] == 0.0
    assert s["equilibrium_residual"] <= 1e-12 and s["equilibrium_free_residual"] <= 1e-12, (
        s["equilibrium_residual"], s["equilibrium_free_residual"])
