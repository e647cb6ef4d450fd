"""Curved second-order meshes (issue 25): reading Gmsh triangle6/tetra10, the isoparametric P2 body,
the check of second-order elements whose map inverts, VTU output.

References: the exact area of the quarter disc (pi/4) and the exact sphere/circle for the edge nodes;
the patch test (a linear displacement is represented exactly by isoparametric P2, so its interior
nodal forces vanish); the Jacobian of the P2 triangle map computed here from the textbook shape
functions (independent of scikit-fem's mapping).
"""

from __future__ import annotations

import numpy as np
import pytest
import skfem

from _gmsh import msh_text
from _helpers import assert_check_rejects, runner
from alcontact.cli import app
from alcontact.errors import MeshError
from alcontact.fem import Hyperelastic, LinearElasticity, Material, meshes
from alcontact.fem.quality import check_mesh_quality, curved_jacobian_ratio, is_curved

MAT = Material(E=1000.0, nu=0.3, plane="strain")


def _quarter_disc(path, *, order: int = 2, h: float = 0.3):
    """Gmsh quarter disc of radius 1 centred at (0, 1): groups curved, symmetry, top, body."""
    import gmsh

    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        geo = gmsh.model.geo
        c, a, b = geo.addPoint(0, 1, 0, h), geo.addPoint(-1, 1, 0, h), geo.addPoint(0, 0, 0, h)
        arc, l1, l2 = geo.addCircleArc(a, c, b), geo.addLine(b, c), geo.addLine(c, a)
        s = geo.addPlaneSurface([geo.addCurveLoop([arc, l1, l2])])
        geo.synchronize()
        for name, d, tags in (("curved", 1, [arc]), ("symmetry", 1, [l1]), ("top", 1, [l2]), ("body", 2, [s])):
            gmsh.model.setPhysicalName(d, gmsh.model.addPhysicalGroup(d, tags), name)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(order)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


@pytest.fixture(scope="module")
def disc(tmp_path_factory):
    return meshes.read(_quarter_disc(tmp_path_factory.mktemp("disc") / "disc.msh"))


def test_triangle6_is_read_curved_with_its_physical_groups(disc):
    assert isinstance(disc, skfem.MeshTri2) and is_curved(disc)
    assert set(disc.boundaries) == {"curved", "symmetry", "top"} and set(disc.subdomains) == {"body"}
    body = LinearElasticity(disc, MAT, order=2)
    pts, _ = body.node_dofs("curved")
    assert np.abs(np.linalg.norm(pts - [0.0, 1.0], axis=1) - 1.0).max() <= 1e-12  # edge nodes on the circle
    # the DOF locations are the mesh's nodes, in scikit-fem's numbering
    assert np.array_equal(body.scalar_doflocs, skfem.Basis(disc, body.scalar_element).doflocs)
    # isoparametric area: pi/4 to O(h^4) (the straight P1 mesh on the same vertices misses O(h^2))
    area2 = float(Hyperelastic(disc, MAT, order=2).quadrature_basis.dx.sum())
    p1 = Hyperelastic(disc, MAT, order=1)
    area1 = float(p1.quadrature_basis.dx.sum())
    assert abs(area2 - np.pi / 4) <= 2e-5 < 5e-3 <= abs(area1 - np.pi / 4)
    assert isinstance(p1.mesh, skfem.MeshTri1) and p1.ndofs == 2 * disc.nvertices
    # boundary weights sum to the arc length (pi/2) to O(h^4)
    assert abs(body.boundary_weights("curved").sum() - np.pi / 2) <= 1e-4


def test_tetra10_is_read_curved(tmp_path):
    import runpy
    from pathlib import Path

    ns = runpy.run_path(str(Path(__file__).resolve().parents[2] / "examples" / "gmsh_curved_ball.py"),
                        run_name="ball")
    mesh = meshes.read(ns["build_mesh"](tmp_path / "ball.msh", h=0.2))
    assert isinstance(mesh, skfem.MeshTet2)
    assert {"curved", "top", "symmetry_x", "symmetry_z"} <= set(mesh.boundaries)
    body = Hyperelastic(mesh, Material(E=1000.0, nu=0.3), order=2)
    pts, _ = body.node_dofs("curved")
    assert np.abs(np.linalg.norm(pts - [0.0, 1.0, 0.0], axis=1) - 1.0).max() <= 1e-6  # on the sphere
    # quarter of a hemisphere of radius 1 (measured relative errors, h = 0.2, 85 elements: P2 curved
    # 4.1e-4, the straight P1 mesh on the same vertices 5.4e-2)
    vol = float(body.quadrature_basis.dx.sum())
    vol1 = float(Hyperelastic(mesh, Material(E=1000.0, nu=0.3), order=1).quadrature_basis.dx.sum())
    assert abs(vol - np.pi / 6) <= 1e-3 * np.pi / 6 < 1e-2 * np.pi / 6 <= abs(vol1 - np.pi / 6)
    # 3D P2 nodal weights: the areas of the curved faces (sum: the quarter hemisphere's pi/2; 2.7e-4 measured)
    assert abs(body.boundary_weights("curved").sum() - np.pi / 2) <= 1e-3 * np.pi / 2


def test_quadratic_quadrilaterals_are_refused(tmp_path):
    import meshio

    m = meshio.Mesh(np.array([[0, 0], [1, 0], [1, 1], [0, 1], [.5, 0], [1, .5], [.5, 1], [0, .5], [.5, .5]], float),
                    [("quad9", np.arange(9)[None, :])])
    meshio.write(tmp_path / "q.msh", m, file_format="gmsh22", binary=False)
    with pytest.raises(MeshError, match="triangle6, tetra10"):
        meshes.read(tmp_path / "q.msh")


def test_first_and_second_order_cells_mixed_are_refused(tmp_path):
    """Gmsh-file fuzzing: triangles plus one degenerate triangle6 crashed the curved reader (ValueError)."""
    import meshio

    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [.5, 0], [1, .5], [.5, .5]], float)
    m = meshio.Mesh(pts, [("triangle", np.array([[0, 1, 2], [0, 2, 3]])), ("triangle6", np.zeros((1, 6), int))])
    meshio.write(tmp_path / "mixed.msh", m, file_format="gmsh22", binary=False)
    with pytest.raises(MeshError, match="both triangle and triangle6 cells"):
        meshes.read(tmp_path / "mixed.msh")


@pytest.mark.parametrize("mesh", [meshes.rectangle(0, 1, 0, 1, 3, 3), meshes.box(0, 1, 0, 1, 0, 1, 2, 2, 2)])
def test_patch_test_on_a_curved_mesh(mesh):
    """A linear displacement on a mesh with moved interior edge nodes: no interior nodal force."""
    cls = skfem.MeshTri2 if mesh.dim() == 2 else skfem.MeshTet2
    m2 = cls.from_mesh(mesh)
    x = np.array(m2.doflocs)
    rng = np.random.default_rng(0)
    nv = mesh.nvertices
    inner = np.flatnonzero(np.all((x[:, nv:] > 1e-9) & (x[:, nv:] < 1 - 1e-9), axis=0)) + nv
    x[:, inner] += 0.04 * rng.standard_normal((x.shape[0], inner.size)) / 3  # curved, still valid
    m2 = type(m2)(x, m2.t)
    m2 = m2.with_boundaries({"all": lambda p: np.ones(p.shape[1], dtype=bool)})
    assert curved_jacobian_ratio(m2).min() > 0.2
    d = mesh.dim()
    A = 1e-3 * (np.arange(d * d).reshape(d, d) + 1.0)
    body = LinearElasticity(m2, Material(E=1000.0, nu=0.3), order=2)
    u = body.interpolate(lambda p: np.einsum("ij,j...->i...", A, p))
    f = body.stiffness() @ u
    free = np.setdiff1d(np.arange(body.ndofs), body.node_dofs("all")[1].ravel())
    assert free.size and np.abs(f[free]).max() <= 1e-10 * np.abs(f).max()
    hyper = Hyperelastic(m2, Material(E=1000.0, nu=0.3), order=2)  # homogeneous F: no interior force either
    fh = hyper.internal_force(u)
    assert np.abs(fh[free]).max() <= 1e-10 * np.abs(fh).max()


def _p2_jacobian(x, n=20):
    """det dx/dxi of a P2 triangle with nodes x (6, 2) (v0, v1, v2, m01, m12, m02) on a lattice of the
    reference triangle (n + 1 points per side), from the textbook shape functions."""
    out = []
    for i in range(n + 1):
        for j in range(n + 1 - i):
            xi, eta = i / n, j / n
            l0 = 1 - xi - eta
            # derivatives of N = (l0(2l0-1), xi(2xi-1), eta(2eta-1), 4 l0 xi, 4 xi eta, 4 l0 eta)
            dxi = np.array([1 - 4 * l0, 4 * xi - 1, 0, 4 * (l0 - xi), 4 * eta, -4 * eta])
            deta = np.array([1 - 4 * l0, 0, 4 * eta - 1, -4 * xi, 4 * xi, 4 * (l0 - eta)])
            out.append(np.linalg.det(np.stack([dxi @ x, deta @ x], axis=1)))
    return np.array(out)


def _bent(n=4):
    """A MeshTri2 square with one interior edge node pushed across most of its element, and that element."""
    base = meshes.rectangle(0, 1, 0, 1, n, n)
    m2 = skfem.MeshTri2.from_mesh(base)
    x = np.array(m2.doflocs)
    nv = base.nvertices
    e = 5
    fac = m2.t2f[0, e]  # a facet of element e (the P2 node of facet k is doflocs[nv + k])
    opposite = np.setdiff1d(m2.t[:, e], m2.facets[:, fac])[0]
    x[:, nv + fac] += 0.9 * (x[:, opposite] - x[:, nv + fac])
    bent = skfem.MeshTri2(x, m2.t)
    return bent.with_boundaries({"left": lambda p: p[0] < 1e-9, "right": lambda p: p[0] > 1 - 1e-9,
                                 "bottom": lambda p: p[1] < 1e-9, "top": lambda p: p[1] > 1 - 1e-9})


def test_inverted_second_order_elements_are_named():
    bent = _bent()
    dofs = skfem.Basis(bent, skfem.ElementTriP2()).element_dofs  # (6, nel): v0, v1, v2, m01, m12, m02
    truth = []
    for e in range(bent.nelements):
        x = bent.doflocs[:, dofs[:, e]].T
        straight = np.linalg.det(np.stack([x[1] - x[0], x[2] - x[0]], axis=1))
        if np.any(_p2_jacobian(x) * np.sign(straight) <= 0):
            truth.append(e)
    assert truth  # the move folds at least one element
    with pytest.raises(MeshError, match=rf"{len(truth)} second-order element\(s\).*element {truth[0]} at"):
        check_mesh_quality(bent)
    with pytest.raises(MeshError, match="Jacobian <= 0"):
        LinearElasticity(bent, MAT, order=2)
    LinearElasticity(bent, MAT, order=1)  # P1 uses the (valid) vertices only


def _write_msh_p2(path, mesh):
    """Gmsh 2.2 ASCII file of a MeshTri2: triangle6 body and line3 boundary groups (names sorted)."""
    basis = skfem.Basis(mesh, skfem.ElementTriP2())
    names = sorted(mesh.boundaries)
    blocks = [("line3", k + 1, np.column_stack([mesh.facets[:, f].T, basis.dofs.facet_dofs[0][f]]))
              for k, f in enumerate(mesh.boundaries[n] for n in names)]
    blocks.append(("triangle6", len(names) + 1, basis.element_dofs.T))  # v0 v1 v2 m01 m12 m02 (Gmsh order)
    phys = [(1, k + 1, n) for k, n in enumerate(names)] + [(2, len(names) + 1, "body")]
    points = np.column_stack([mesh.doflocs.T, np.zeros(mesh.doflocs.shape[1])])
    path.write_text(msh_text(points, blocks, phys))
    return path


_P2_FILE = """
[mesh]
generator = "file"
file = "{name}"
order = 2
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


def test_check_refuses_a_second_order_mesh_whose_map_inverts(tmp_path):
    bent = _bent()
    _write_msh_p2(tmp_path / "bent.msh", bent)
    read = meshes.read(tmp_path / "bent.msh")
    assert isinstance(read, skfem.MeshTri2) and np.allclose(read.doflocs, bent.doflocs)  # same numbering
    (tmp_path / "p.toml").write_text(_P2_FILE.format(name="bent.msh"))
    result = runner.invoke(app, ["check", str(tmp_path / "p.toml")])
    assert_check_rejects(result, ["mesh.file = 'bent.msh'", "second-order element(s)", "Jacobian <= 0",
                                  "element 5 at"])
    good = skfem.MeshTri2.from_mesh(meshes.rectangle(0, 1, 0, 1, 4, 4)).with_boundaries(
        {"bottom": lambda p: p[1] < 1e-9, "top": lambda p: p[1] > 1 - 1e-9})
    _write_msh_p2(tmp_path / "good.msh", good)
    (tmp_path / "q.toml").write_text(_P2_FILE.format(name="good.msh"))
    assert runner.invoke(app, ["check", str(tmp_path / "q.toml")]).exit_code == 0


def test_vtu_of_a_curved_p2_solution_has_second_order_cells(tmp_path):
    import meshio

    from alcontact.contact import solve_finite
    from alcontact.io import write_solution_vtu
    from alcontact.problems.half_cylinder import half_cylinder

    pb = half_cylinder(3, order=2, delta=0.1)
    assert is_curved(pb.model.mesh)
    fs = solve_finite(pb, "ssn", steps=1)
    m = meshio.read(write_solution_vtu(tmp_path / "s.vtu", fs.solution, deformed=False))
    assert [c.type for c in m.cells] == ["triangle6"] and m.points.shape[0] == pb.model.ndofs // 2
    pts, dofs = pb.model.node_dofs("curved")
    on = np.isin(np.arange(m.points.shape[0]), np.flatnonzero(np.linalg.norm(m.points[:, :2] - [0, 1], axis=1)
                                                               > 1 - 1e-12))
    assert on.sum() == len(pts)  # every contact node (vertex and edge node) is a point on the circle
    assert np.allclose(m.point_data["displacement"][:, :2], fs.solution.u[pb.model.dof_map])


def test_run_of_a_triangle6_file_writes_results_and_pictures(tmp_path):
    """A problem file on a triangle6 Gmsh mesh with order = 2 runs through the runner (VTU, figures)."""
    import json
    from pathlib import Path

    import meshio

    from alcontact.io import load_problem
    from alcontact.runner import run_setup

    _quarter_disc(tmp_path / "half_cylinder.msh", h=0.25)
    toml = (Path(__file__).resolve().parents[2] / "examples" / "finite_half_cylinder.toml").read_text()
    toml = toml.replace('file = "half_cylinder.msh"', 'file = "half_cylinder.msh"\norder = 2')
    toml = toml.replace('folder = "results-finite-half-cylinder"', 'folder = "res"').replace("steps = 4", "steps = 2")
    (tmp_path / "p.toml").write_text(toml)
    setup = load_problem(tmp_path / "p.toml")
    assert isinstance(setup.problem.model.mesh, skfem.MeshTri2) and setup.problem.model.order == 2
    run_setup(setup, tmp_path / "res")
    summary = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert summary["status"] == "converged"
    assert [c.type for c in meshio.read(tmp_path / "res" / "solution.vtu").cells] == ["triangle6"]
    assert (tmp_path / "res" / "body_pressure.png").stat().st_size > 0
