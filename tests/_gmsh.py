"""Gmsh 2.2 ASCII text of small meshes, for the tests of the mesh reader (regression and fuzz tests).

``tests/`` is on ``sys.path`` (see ``tests/_helpers.py``): ``from _gmsh import msh_text``.
"""

from __future__ import annotations

import numpy as np

from alcontact.fem import meshes

#: Gmsh element type numbers (Gmsh manual, "MSH file format version 2")
GMSH_TYPES = {"line": 1, "triangle": 2, "quad": 3, "tetra": 4, "hexahedron": 5, "point": 15, "line3": 8,
              "triangle6": 9}


def square(n: int = 4):
    """The unit square in ``n x n`` cells: ``(points (N, 3), triangles (T, 3), boundary lines by name)``."""
    m = meshes.rectangle(0.0, 1.0, 0.0, 1.0, n, n)
    pts = np.column_stack([m.p.T, np.zeros(m.nvertices)])
    lines = {name: m.facets[:, f].T for name, f in m.boundaries.items()}
    return pts, m.t.T.copy(), lines


def msh_text(points, blocks, names) -> str:
    """Gmsh 2.2 ASCII file.

    Parameters
    ----------
    points : (N, 3) array_like
        Node coordinates (written with ``repr``: ``nan``, ``inf`` as Python spells them).
    blocks : list of (type, physical tag, (E, k) connectivity, 0-based)
        Element blocks; ``type`` a key of :data:`GMSH_TYPES`.
    names : list of (dimension, tag, name)
        The ``$PhysicalNames`` entries (``None``: no section at all).
    """
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat"]
    if names is not None:
        out += ["$PhysicalNames", str(len(names)), *(f'{d} {t} "{n}"' for d, t, n in names), "$EndPhysicalNames"]
    out += ["$Nodes", str(len(points))]
    out += [f"{i + 1} {' '.join(repr(float(x)) for x in p)}" for i, p in enumerate(points)]
    out += ["$EndNodes"]
    rows, k = [], 0
    for typ, tag, conn in blocks:
        for e in np.asarray(conn, dtype=int):
            k += 1
            rows.append(f"{k} {GMSH_TYPES[typ]} 2 {tag} {tag} {' '.join(str(int(v) + 1) for v in e)}")
    out += ["$Elements", str(len(rows)), *rows, "$EndElements", ""]
    return "\n".join(out)


def square_msh(n: int = 4, *, names=None, points=None, triangles=None) -> str:
    """The unit square with physical lines left/right/bottom/top (tags 1-4) and the body (tag 5)."""
    pts, tri, lines = square(n)
    order = ["left", "right", "bottom", "top"]
    blocks = [("line", k + 1, lines[name]) for k, name in enumerate(order)]
    blocks.append(("triangle", 5, tri if triangles is None else triangles))
    if names is None:
        names = [(1, k + 1, name) for k, name in enumerate(order)] + [(2, 5, "body")]
    return msh_text(pts if points is None else points, blocks, names)


#: A problem file for a Gmsh file "body.msh" of :func:`square_msh` (pressed by a plane from above).
SQUARE_PROBLEM = """
[mesh]
generator = "file"
file = "body.msh"
[material]
E = 1000.0
nu = 0.3
[[support]]
boundary = "bottom"
[obstacle]
type = "half-space"
point = [0.0, 0.99]
normal = [0.0, -1.0]
[contact]
boundary = "top"
"""
