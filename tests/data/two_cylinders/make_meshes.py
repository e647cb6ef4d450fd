"""Write the two meshes of :func:`alcontact.problems.two_body.hertz_cylinders` (level 1) as Gmsh 2.2 files.

The problem file ``two_cylinders.toml`` beside this script reads them; the regression test
``tests/regression/test_two_body_problem_file.py`` compares its run with the Python API's.
Run from the repository root::

    python tests/data/two_cylinders/make_meshes.py
"""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np

from alcontact.problems.two_body import hertz_cylinders

LEVEL = 1


def write(model, path: Path) -> None:
    """The P1 mesh of ``model`` with its boundaries as physical line groups and the body as a surface group."""
    mesh = model.mesh
    names = sorted(mesh.boundaries)
    lines, tags = [], []
    for k, name in enumerate(names):
        f = mesh.facets[:, mesh.boundaries[name]].T
        lines.append(f)
        tags.append(np.full(len(f), k + 1))
    body = len(names) + 1
    cells = [("line", np.vstack(lines)), ("triangle", mesh.t.T)]
    data = {"gmsh:physical": [np.concatenate(tags), np.full(mesh.t.shape[1], body)],
            "gmsh:geometrical": [np.concatenate(tags), np.full(mesh.t.shape[1], body)]}
    field = {n: np.array([k + 1, 1]) for k, n in enumerate(names)} | {"body": np.array([body, 2])}
    out = meshio.Mesh(np.asarray(mesh.p.T, dtype=float), cells, cell_data=data, field_data=field)
    meshio.write(path, out, file_format="gmsh22", binary=False)


if __name__ == "__main__":
    here = Path(__file__).parent
    lower, upper = hertz_cylinders(LEVEL).model.bodies
    write(lower, here / "lower.msh")
    write(upper, here / "upper.msh")
