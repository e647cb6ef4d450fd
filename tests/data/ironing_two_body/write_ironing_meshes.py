"""Write the meshes of :func:`alcontact.problems.two_body.ironing_two_body` (``n = 10``) as Gmsh 2.2 files.

The problem file ``ironing_two_body.toml`` beside this script reads them (``block.msh``, ``punch.msh``);
``tests/regression/test_issue23_finite_two_body_problem_file.py`` compares its run with the Python
API's. Run from the repository root::

    python tests/data/ironing_two_body/write_ironing_meshes.py
"""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np

from alcontact.problems.two_body import ironing_two_body

#: the parameters of the problem file: 10 elements per unit length on the block, slid by one radius
PARAMETERS = {"n": 10, "slide": 1.0}


def write(model, path: Path) -> None:
    """The P1 mesh of ``model`` with its boundaries as physical line groups and the body as a surface group."""
    mesh = model.mesh
    names = sorted(mesh.boundaries)
    lines = [mesh.facets[:, mesh.boundaries[n]].T for n in names]
    tags = np.concatenate([np.full(len(f), k + 1) for k, f in enumerate(lines)])
    body = len(names) + 1
    cells = [("line", np.vstack(lines)), ("triangle", mesh.t.T)]
    data = {"gmsh:physical": [tags, np.full(mesh.t.shape[1], body)],
            "gmsh:geometrical": [tags, np.full(mesh.t.shape[1], body)]}
    field = {n: np.array([k + 1, 1]) for k, n in enumerate(names)} | {"body": np.array([body, 2])}
    meshio.write(path, meshio.Mesh(np.asarray(mesh.p.T, dtype=float), cells, cell_data=data, field_data=field),
                 file_format="gmsh22", binary=False)


def write_meshes(folder: Path) -> None:
    """``block.msh`` (``body0``) and ``punch.msh`` (``body1``) of the problem file's problem into ``folder``."""
    block, punch = ironing_two_body(**PARAMETERS).bodies
    write(block, Path(folder) / "block.msh")
    write(punch, Path(folder) / "punch.msh")


if __name__ == "__main__":
    write_meshes(Path(__file__).parent)
