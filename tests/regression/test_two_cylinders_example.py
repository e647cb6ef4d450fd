"""examples/two_cylinders.py: two elastic cylinders of different materials, mortar contact (issue 23).

Reference: Hertz with the effective modulus and radius (Johnson 1985, eq. 4.45-4.47), half-width
and peak pressure within 2 %; action = reaction to 1e-10; the results folder carries the
balance and a VTU with both bodies (`body` field).
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "two_cylinders.py"


def test_two_cylinders_example(tmp_path):
    import meshio

    ns = runpy.run_path(str(EXAMPLE), run_name="two_cylinders_example")
    out = tmp_path / "res"
    res = ns["main"](str(out))
    assert res["success"]
    assert abs(res["a"]) <= 0.02 and abs(res["p0"]) <= 0.02, res
    assert res["balance"] <= 1e-10
    summary = json.loads((out / "summary.json").read_text())
    assert summary["contact_force_balance"] <= 1e-10 and summary["status"] == "converged"
    grid = meshio.read(out / "solution.vtu")
    assert set(np.unique(grid.point_data["body"])) == {0.0, 1.0}
