"""Mesh quality: inverted (folded) and degenerate elements, found by index and centroid."""

from __future__ import annotations

import numpy as np
import pytest
import skfem

from alcontact.errors import ConfigError, MeshError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.fem.quality import DEGENERATE_RATIO, check_mesh_quality, element_measures, mesh_quality
from alcontact.io.config import load_problem

MAT = Material(E=1.0, nu=0.3)


def _moved(mesh, target, shift):
    """Copy of ``mesh`` (same connectivity) with the node nearest ``target`` moved by ``shift``."""
    p = mesh.p.copy()
    i = int(np.argmin(np.linalg.norm(p.T - np.asarray(target), axis=1)))
    p[:, i] += shift
    return type(mesh)(p, mesh.t), i


def _flipped(before, after):
    """Ground truth: elements whose signed measure (same stored vertex order) changed sign."""
    return np.flatnonzero(np.sign(element_measures(before)) != np.sign(element_measures(after)))


@pytest.mark.parametrize("mesh", [meshes.rectangle(0, 2, 0, 1, 8, 4), meshes.box(0, 1, 0, 1, 0, 1, 3, 3, 3),
                                  meshes.rectangle(-1, 1, 0, 1, 6, 3, refine=dict(center=(0, 1), h_min=0.01,
                                                                                  width=0.1, depth=0.05))])
def test_valid_meshes_pass(mesh):
    q = check_mesh_quality(mesh)
    assert q.ok and q.inverted.size == 0 and q.degenerate.size == 0 and q.folded_facets.size == 0
    assert q.min_ratio > DEGENERATE_RATIO


@pytest.mark.parametrize("mesh, target, shift", [
    (meshes.rectangle(0, 1, 0, 1, 10, 10), (0.5, 0.5), (0.25, 0.13)),
    (meshes.rectangle(0, 1, 0, 1, 10, 10), (0.3, 0.7), (-0.17, -0.21)),
    (meshes.box(0, 1, 0, 1, 0, 1, 6, 6, 6), (0.5, 0.5, 0.5), (0.3, 0.2, 0.1)),
])
def test_inverted_elements_are_the_ones_that_flipped(mesh, target, shift):
    bad, _ = _moved(mesh, target, np.asarray(shift))
    truth = _flipped(mesh, bad)
    assert truth.size > 0  # the move does tangle the mesh
    q = mesh_quality(bad)
    assert np.array_equal(np.sort(q.inverted), truth)
    assert q.degenerate.size == 0 and q.folded_facets.size > 0
    msg = q.message()
    assert f"{truth.size} inverted element(s)" in msg and f"element {truth[0]} at " in msg
    assert str(np.round(q.centroids[truth[0]], 6).tolist()) in msg and "Re-mesh" in msg


def test_degenerate_elements_named():
    mesh = meshes.rectangle(0, 1, 0, 1, 6, 6)
    p = mesh.p.copy()
    a = int(np.argmin(np.linalg.norm(p.T - [0.5, 0.5], axis=1)))
    b = int(np.argmin(np.linalg.norm(p.T - [0.5 + 1 / 6, 0.5], axis=1)))
    p[:, b] = p[:, a]  # two nodes at one place: the elements sharing edge a-b have zero area
    bad = skfem.MeshTri(p, mesh.t)
    truth = np.flatnonzero(np.abs(element_measures(bad)) == 0.0)
    assert truth.size == 2
    q = mesh_quality(bad)
    assert np.array_equal(q.degenerate, truth)
    with pytest.raises(MeshError, match=r"2 degenerate element\(s\).*element %d at" % truth[0]):
        check_mesh_quality(bad)


def test_linear_elasticity_refuses_a_tangled_mesh():
    bad, _ = _moved(meshes.rectangle(0, 1, 0, 1, 8, 8), (0.5, 0.5), np.array([0.2, 0.15]))
    with pytest.raises(MeshError, match="inverted element"):
        LinearElasticity(bad, MAT)
    LinearElasticity(meshes.rectangle(0, 1, 0, 1, 8, 8), MAT)  # the untangled mesh is fine


def _write_msh(path, mesh, boundaries, *, body: bool = True):
    """Gmsh 2.2 ASCII file of a triangle mesh: boundaries as physical lines, the body as 'body' (optional)."""
    names = sorted(boundaries)
    lines, tag = [], 0
    for k, name in enumerate(names):
        for f in boundaries[name]:
            tag += 1
            a, b = mesh.facets[:, f] + 1
            lines.append(f"{tag} 1 2 {k + 1} {k + 1} {a} {b}")
    if body:
        for e in range(mesh.nelements):
            tag += 1
            a, b, c = mesh.t[:, e] + 1
            lines.append(f"{tag} 2 2 {len(names) + 1} 100 {a} {b} {c}")
    phys = [f'1 {k + 1} "{n}"' for k, n in enumerate(names)] + ([f'2 {len(names) + 1} "body"'] if body else [])
    nodes = [f"{i + 1} {x:.17g} {y:.17g} 0" for i, (x, y) in enumerate(mesh.p.T)]
    path.write_text("\n".join(["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(phys)),
                               *phys, "$EndPhysicalNames", "$Nodes", str(len(nodes)), *nodes, "$EndNodes",
                               "$Elements", str(len(lines)), *lines, "$EndElements", ""]))
    return path


_FILE_PROBLEM = """
[mesh]
generator = "file"
file = "{name}"
[material]
E = 1000.0
nu = 0.3
[[support]]
boundary = "bottom"
[obstacle]
type = "half-space"
point = [0.0, 1.001]
normal = [0.0, -1.0]
[contact]
boundary = "top"
"""


def test_gmsh_file_with_a_tangled_mesh_is_refused(tmp_path):
    good = meshes.rectangle(0, 1, 0, 1, 6, 6)
    bad, _ = _moved(good, (0.5, 0.5), np.array([0.22, 0.1]))
    truth = _flipped(good, bad)
    msh = _write_msh(tmp_path / "tangled.msh", bad, good.boundaries)
    mesh = meshes.read(msh)
    with pytest.raises(MeshError, match=f"{truth.size} inverted element"):
        LinearElasticity(mesh, MAT)
    (tmp_path / "p.toml").write_text(_FILE_PROBLEM.format(name="tangled.msh"))
    with pytest.raises(ConfigError, match=f"{truth.size} inverted element"):
        load_problem(tmp_path / "p.toml")
    _write_msh(tmp_path / "fine.msh", good, good.boundaries)
    (tmp_path / "q.toml").write_text(_FILE_PROBLEM.format(name="fine.msh"))
    assert load_problem(tmp_path / "q.toml").problem.model.mesh.nelements == good.nelements
