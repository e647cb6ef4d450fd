"""Write the three meshes of :func:`alcontact.problems.two_body.seal` (``n = 8``) as Gmsh 4.1 files.

The problem file ``seal.toml`` beside this script reads them (``cord.msh``, ``lower.msh``, ``upper.msh``);
``tests/regression/test_issue23_seal_problem_file.py`` compares its run with the Python API's. Run from
the repository root::

    python tests/data/seal/write_seal_meshes.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from alcontact.problems.two_body import seal

#: the parameters of the problem file
PARAMETERS = {"n": 8}



def write(model, path: Path) -> None:
    """The P1 mesh of ``model`` as a Gmsh 4.1 file (the ``gmsh`` API): its boundaries (the cord's interior
    symmetry lines included, which Gmsh 4.1 physical groups keep) as physical line groups, the body as a
    physical surface."""
    import gmsh

    mesh = model.mesh
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(path.stem)
        surf = gmsh.model.addDiscreteEntity(2)
        n = mesh.p.shape[1]
        coords = np.vstack([mesh.p, np.zeros(n)]).T.ravel()
        gmsh.model.mesh.addNodes(2, surf, np.arange(1, n + 1), coords)
        gmsh.model.mesh.addElementsByType(surf, 2, [], (mesh.t.T + 1).ravel())  # 2: 3-node triangles
        for name in sorted(mesh.boundaries):
            curve = gmsh.model.addDiscreteEntity(1)
            gmsh.model.mesh.addElementsByType(curve, 1, [], (mesh.facets[:, mesh.boundaries[name]].T + 1).ravel())
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [curve]), name)
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [surf]), "body")
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def write_meshes(folder: Path) -> None:
    """``cord.msh`` (``body0``), ``lower.msh`` (``body1``) and ``upper.msh`` (``body2``) into ``folder``."""
    for body, name in zip(seal(**PARAMETERS).bodies, ("cord", "lower", "upper")):
        write(body, Path(folder) / f"{name}.msh")


if __name__ == "__main__":
    write_meshes(Path(__file__).parent)
