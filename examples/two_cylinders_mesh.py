"""Write ``two_cylinders.msh``: the two bodies of ``two_cylinders.toml`` in one Gmsh file, one physical group each.

The meshes are those of :func:`alcontact.problems.two_body.hertz_cylinders` (level 0): a steel
block (``lower``) and an aluminium block (``upper``) whose contact faces have the cylinders'
profiles. Each body is a physical group of triangles (``lower``, ``upper``); the boundary groups
``top``, ``bottom``, ``left``, ``right`` hold the facets of both bodies, so that each body read with
``[body.mesh] group = "..."`` gets its own part of them (``body0/top``, ``body1/bottom``, ...).

Run from the repository root (the committed file is what it writes)::

    python examples/two_cylinders_mesh.py [path]
"""

from __future__ import annotations

import sys
from pathlib import Path

import meshio
import numpy as np

from alcontact.problems.two_body import hertz_cylinders

LEVEL = 0
HERE = Path(__file__).resolve().parent


def write_bodies(models, names, path: Path) -> None:
    """One Gmsh 2.2 file (binary) of the P1 meshes of ``models``: a triangle group per body (``names``), the boundary
    groups of all bodies by boundary name (a name several bodies have is one group)."""
    points, tris, tri_tags, lines, line_tags = [], [], [], [], []
    boundary = sorted({b for m in models for b in m.mesh.boundaries})
    btag = {b: k + 1 for k, b in enumerate(boundary)}
    shift = 0
    for i, m in enumerate(models):
        mesh = m.mesh
        points.append(mesh.p.T)
        tris.append(mesh.t.T + shift)
        tri_tags.append(np.full(mesh.t.shape[1], len(boundary) + 1 + i))
        for b in sorted(mesh.boundaries):
            f = mesh.facets[:, mesh.boundaries[b]].T + shift
            lines.append(f)
            line_tags.append(np.full(len(f), btag[b]))
        shift += mesh.p.shape[1]
    cells = [("line", np.vstack(lines)), ("triangle", np.vstack(tris))]
    tags = [np.concatenate(line_tags), np.concatenate(tri_tags)]
    field = {b: np.array([t, 1]) for b, t in btag.items()}
    field.update({n: np.array([len(boundary) + 1 + i, 2]) for i, n in enumerate(names)})
    out = meshio.Mesh(np.vstack(points).astype(float), cells,
                      cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags}, field_data=field)
    meshio.write(path, out, file_format="gmsh22", binary=True)


def main(path: Path = HERE / "two_cylinders.msh") -> Path:
    lower, upper = hertz_cylinders(LEVEL).model.bodies
    write_bodies([lower, upper], ["lower", "upper"], Path(path))
    return Path(path)


if __name__ == "__main__":
    print(main(Path(sys.argv[1])) if len(sys.argv) > 1 else main())
