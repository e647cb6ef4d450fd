"""Unit tests of alcontact.fem.meshes: structured meshes, grading, reading Gmsh files."""

from __future__ import annotations

import sys
import time

import meshio
import numpy as np
import pytest
import skfem

from alcontact.errors import InputError, MeshError
from alcontact.fem import meshes


def _facet_measure(mesh, facets):
    p = mesh.p[:, mesh.facets[:, facets]]
    if mesh.dim() == 2:
        return float(np.linalg.norm(p[:, 1] - p[:, 0], axis=0).sum())
    return float(0.5 * np.linalg.norm(np.cross((p[:, 1] - p[:, 0]).T, (p[:, 2] - p[:, 0]).T), axis=1).sum())


def test_rectangle_boundaries_and_counts():
    m = meshes.rectangle(-1.0, 2.0, 0.0, 1.5, 6, 3)
    assert isinstance(m, skfem.MeshTri)
    assert sorted(m.boundaries) == ["bottom", "left", "right", "top"]
    assert m.nvertices == 7 * 4
    assert len(m.boundaries["bottom"]) == 6 and len(m.boundaries["left"]) == 3
    assert _facet_measure(m, m.boundaries["top"]) == pytest.approx(3.0)
    assert _facet_measure(m, m.boundaries["right"]) == pytest.approx(1.5)
    # every boundary facet belongs to exactly one named side
    named = np.concatenate([m.boundaries[k] for k in m.boundaries])
    assert np.array_equal(np.sort(named), np.sort(m.boundary_facets()))
    assert np.allclose(m.p[1, m.facets[:, m.boundaries["top"]]], 1.5)


def test_box_boundaries():
    m = meshes.box(0.0, 2.0, 0.0, 1.0, -1.0, 0.0, 4, 2, 3)
    assert isinstance(m, skfem.MeshTet)
    assert sorted(m.boundaries) == ["back", "bottom", "front", "left", "right", "top"]
    expected = {"left": 1.0, "right": 1.0, "front": 2.0, "back": 2.0, "bottom": 2.0, "top": 2.0}
    for name, area in expected.items():
        assert _facet_measure(m, m.boundaries[name]) == pytest.approx(area), name
    assert np.allclose(m.p[2, m.facets[:, m.boundaries["top"]]], 0.0)
    assert np.allclose(m.p[1, m.facets[:, m.boundaries["front"]]], 0.0)
    assert len(m.boundaries["top"]) == 2 * 4 * 2


def test_interval():
    m = meshes.interval(0.0, 2.0, 8)
    assert isinstance(m, skfem.MeshLine)
    assert m.nvertices == 9
    assert sorted(m.boundaries) == ["left", "right"]


def test_graded_axis_properties():
    x = meshes.graded_axis(-2.0, 2.0, -0.1, 0.1, 0.01, 1.2, 0.5)
    assert x[0] == -2.0 and x[-1] == 2.0
    h = np.diff(x)
    assert np.all(h > 0)
    fine = (x[:-1] >= -0.1 - 1e-12) & (x[1:] <= 0.1 + 1e-12)
    assert np.allclose(h[fine], 0.01)
    assert h.max() <= 1.5 * 0.5 + 1e-12
    ratios = h[1:] / h[:-1]
    # geometric growth except at the merged last cell of each side
    assert np.all(ratios[1:-1] <= 1.2 + 1e-9) and np.all(ratios[1:-1] >= 1 / 1.2 - 1e-9)


def test_rectangle_refine_toward_top_point():
    refine = dict(center=(0.0, 1.0), h_min=0.005, width=0.05, depth=0.02, growth=1.25)
    m = meshes.rectangle(-1.0, 1.0, 0.0, 1.0, 10, 10, refine=refine)
    xs, ys = np.unique(m.p[0]), np.unique(m.p[1])
    assert xs[0] == -1.0 and xs[-1] == 1.0 and ys[0] == 0.0 and ys[-1] == 1.0
    hx = np.diff(xs[(xs >= -0.05 - 1e-12) & (xs <= 0.05 + 1e-12)])
    hy = np.diff(ys[ys >= 0.98 - 1e-12])
    assert np.allclose(hx, 0.005) and np.allclose(hy, 0.005)
    assert np.diff(xs).max() <= 1.5 * 0.2 + 1e-12  # cap from nx
    assert sorted(m.boundaries) == ["bottom", "left", "right", "top"]
    assert _facet_measure(m, m.boundaries["top"]) == pytest.approx(2.0)


def test_box_refine():
    refine = dict(center=(0.5, 0.5, 1.0), h_min=0.02, width=0.05, depth=0.04)
    m = meshes.box(0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 4, 4, 4, refine=refine)
    zs = np.unique(m.p[2])
    assert np.allclose(np.diff(zs[zs >= 0.96 - 1e-12]), 0.02)
    assert _facet_measure(m, m.boundaries["top"]) == pytest.approx(1.0)


def test_large_rectangle_is_fast():
    t0 = time.perf_counter()
    m = meshes.rectangle(0.0, 1.0, 0.0, 1.0, 500, 499)
    elapsed = time.perf_counter() - t0
    assert m.nvertices == 501 * 500
    assert elapsed < 5.0


@pytest.mark.parametrize(
    "refine, match",
    [
        (dict(center=(0.0, 1.0), h_min=0.1, width=0.1), "missing"),
        (dict(center=(0.0, 1.0), h_min=0.1, width=0.1, depth=0.1, grow=1.2), "grow"),
        (dict(center=(0.0, 1.0), h_min=-0.1, width=0.1, depth=0.1), "h_min"),
        (dict(center=(0.0, 1.0), h_min=0.1, width=0.1, depth=0.1, growth=0.5), "growth"),
        (dict(center=(0.0,), h_min=0.1, width=0.1, depth=0.1), "center"),
    ],
)
def test_refine_validation(refine, match):
    with pytest.raises(InputError, match=match):
        meshes.rectangle(-1.0, 1.0, 0.0, 1.0, 4, 4, refine=refine)


def test_extent_validation():
    with pytest.raises(InputError, match="lower < upper"):
        meshes.rectangle(1.0, 0.0, 0.0, 1.0, 2, 2)
    with pytest.raises(InputError, match="integer"):
        meshes.box(0, 1, 0, 1, 0, 1, 2, 0, 2)


# ---------------------------------------------------------------- reading
def _write_tagged_square(path, file_format):
    """Two triangles on the unit square, physical groups 'bottom'/'top' (lines) and 'body' (cells)."""
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    cells = [("line", np.array([[0, 1], [2, 3]])), ("triangle", np.array([[0, 1, 2], [0, 2, 3]]))]
    phys = [np.array([1, 2]), np.array([3, 3])]
    mesh = meshio.Mesh(
        points,
        cells,
        cell_data={"gmsh:physical": phys, "gmsh:geometrical": phys},
        field_data={"bottom": np.array([1, 1]), "top": np.array([2, 1]), "body": np.array([3, 2])},
    )
    meshio.write(path, mesh, file_format=file_format, binary=False)


_MSH41 = """$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 "bottom"
1 2 "top"
2 3 "body"
$EndPhysicalNames
$Entities
0 2 1 0
1 0 0 0 1 0 0 1 1 0
2 0 1 0 1 1 0 1 2 0
1 0 0 0 1 1 0 1 3 2 1 2
$EndEntities
$Nodes
1 4 1 4
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
3 4 1 4
1 1 1 1
1 1 2
1 2 1 1
2 3 4
2 1 2 2
3 1 2 3
4 1 3 4
$EndElements
"""


@pytest.mark.parametrize("file_format", ["gmsh22", "msh41-by-hand"])
def test_read_msh_with_physical_groups(tmp_path, file_format):
    path = tmp_path / "square.msh"
    if file_format == "gmsh22":
        _write_tagged_square(path, file_format)
    else:  # what Gmsh 4 writes (ASCII), physical groups as cell sets
        path.write_text(_MSH41)
    m = meshes.read(path)
    assert isinstance(m, skfem.MeshTri)
    assert m.nelements == 2
    assert sorted(m.boundaries) == ["bottom", "top"]
    assert np.allclose(m.p[1, m.facets[:, m.boundaries["bottom"]]], 0.0)
    assert np.allclose(m.p[1, m.facets[:, m.boundaries["top"]]], 1.0)
    assert sorted(m.subdomains) == ["body"] and len(m.subdomains["body"]) == 2


def test_read_drops_unused_points(tmp_path):
    points = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [5.0, 5.0]])
    path = tmp_path / "orphan.msh"
    meshio.write(path, meshio.Mesh(points, [("triangle", np.array([[0, 1, 2]]))]), file_format="gmsh22",
                 binary=False)
    m = meshes.read(path)
    assert m.nvertices == 3


def test_read_missing_file(tmp_path):
    with pytest.raises(MeshError, match="does not exist"):
        meshes.read(tmp_path / "nope.msh")


def test_read_garbage_file(tmp_path):
    path = tmp_path / "bad.msh"
    path.write_text("this is not a mesh\n")
    with pytest.raises(MeshError, match="cannot read mesh file"):
        meshes.read(path)


def test_read_unsupported_cells(tmp_path):
    path = tmp_path / "quad.msh"
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    meshio.write(path, meshio.Mesh(points, [("quad", np.array([[0, 1, 2, 3]]))]), file_format="gmsh22",
                 binary=False)
    with pytest.raises(MeshError, match="quad"):
        meshes.read(path)


def test_read_geo_without_gmsh(tmp_path, monkeypatch):
    """gmsh is a dependency; an environment without it (a broken install) still gets the way out."""
    monkeypatch.setitem(sys.modules, "gmsh", None)  # `import gmsh` raises ImportError
    path = tmp_path / "a.geo"
    path.write_text("Point(1) = {0, 0, 0};\n")
    with pytest.raises(MeshError, match="pip install gmsh"):
        meshes.read(path)


def test_read_geo_is_meshed_by_gmsh(tmp_path):
    """A .geo script with physical groups becomes a triangle mesh with those boundary names (gmsh installed)."""
    path = tmp_path / "square.geo"
    path.write_text(
        "lc = 0.25;\nPoint(1) = {0, 0, 0, lc}; Point(2) = {1, 0, 0, lc}; Point(3) = {1, 1, 0, lc};\n"
        "Point(4) = {0, 1, 0, lc};\nLine(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
        "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
        'Physical Curve("bottom") = {1}; Physical Curve("top") = {3}; Physical Surface("body") = {1};\n'
    )
    mesh = meshes.read(path)
    assert isinstance(mesh, skfem.MeshTri) and mesh.t.shape[1] >= 16
    assert {"bottom", "top"} <= set(mesh.boundaries)
    assert np.allclose(mesh.p[1, np.unique(mesh.facets[:, mesh.boundaries["top"]])], 1.0)
