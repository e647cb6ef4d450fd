"""examples/gmsh_punch.py builds a Gmsh mesh with physical groups and solves it (issue 20, item 6).

Gmsh is a dependency of the package (pyproject.toml), so this runs everywhere the tests run,
headless. Checked: the mesh file carries the named physical groups; the problem file that
the script writes validates and solves; the contact zone of the punch with a rounded corner
covers the flat bottom x in [0, b - r] and ends on the corner, x_max in (b - r, b), growing
with the load; the run is in global equilibrium (contact force = support reaction to 1e-8).
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
import pytest

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "gmsh_punch.py"


@pytest.fixture(scope="module")
def punch(tmp_path_factory):
    ns = runpy.run_path(str(EXAMPLE), run_name="gmsh_punch_example")
    out = tmp_path_factory.mktemp("punch")
    assert ns["main"](["--out", str(out), "--h", "0.02"]) == 0
    return ns, out


def test_gmsh_is_installed_with_the_package():
    import gmsh

    from importlib.metadata import requires

    assert any(r.split(">")[0].split("=")[0].strip() == "gmsh" for r in requires("alcontact"))
    assert gmsh.__version__


def test_mesh_has_the_physical_groups(punch):
    import meshio

    _, out = punch
    m = meshio.read(out / "punch.msh")
    assert {"contact", "top", "symmetry", "side", "body"} <= set(m.field_data)
    from alcontact.fem import meshes

    mesh = meshes.read(out / "punch.msh")
    assert {"contact", "top", "symmetry", "side"} <= set(mesh.boundaries)


def test_punch_contact_zone_covers_the_flat_part_and_ends_on_the_corner(punch):
    import json

    from alcontact.io import load_problem
    from alcontact.runner import run_setup

    ns, out = punch
    b, r = ns["B"], ns["R"]
    summary = json.loads((out / "results" / "summary.json").read_text())
    assert summary["status"] == "converged"
    assert summary["equilibrium_residual"] <= 1e-8
    res = run_setup(load_problem(out / "punch.toml"))  # the same problem, in memory, to read the frames
    ends = []
    for fr in res.frames:
        x = fr.points[:, 0]
        flat = x <= b - r + 1e-12
        assert fr.active[flat].all()  # every node of the flat bottom touches
        ends.append(x[fr.active].max())
    assert np.all(np.diff(ends) >= 0)  # the zone grows with the load
    assert b - r < ends[-1] < b  # and reaches onto the rounded corner, not to its end
