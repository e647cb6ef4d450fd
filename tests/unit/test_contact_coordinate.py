"""Issue 20, item 1: the abscissa of the pressure plot is monotone along curved contact boundaries.

Reference: the exact geometry of each body. Along a meridian of a ball (and around a ring of a
cylinder, or along the arc of a disc) the angle from the contact pole grows; the abscissa of
:func:`alcontact.viz.contact_coordinate` must grow with it, strictly (no two points of one meridian
share an abscissa), on the side facing the obstacle and past the fold on the far side. The old
abscissa (the coordinate direction of least extent taken as the contact normal) failed all three:
a ball's extents are equal in every direction, so the "flat" direction was arbitrary.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import skfem

from alcontact.contact.obstacles import HalfSpace
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.viz import contact_coordinate, loaded_half_width, pressure_figure

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _solution(mesh, boundary, obstacle, a=0.3, pole=None):
    """A contact 'solution' on ``boundary``: Hertz-like pressure within ``a`` of the obstacle-nearest point."""
    model = LinearElasticity(mesh, Material(E=1.0, nu=0.3))
    pts, _ = model.node_dofs(boundary)
    gap, normals = obstacle.evaluate(pts)
    pole = pts[int(np.argmax(gap))] if pole is None else np.asarray(pole, float)
    dist = np.linalg.norm(pts - pole, axis=1)
    p = np.clip(1.0 - (dist / a) ** 2, 0.0, None)
    return SimpleNamespace(problem=SimpleNamespace(model=model, contact_boundary=boundary, meta={}),
                           points=pts, pressure=p, normals=normals, gap=gap)


def _strictly_increasing(x, tol=1e-12):
    return bool(np.all(np.diff(x) > tol))


def _check_path(r, sel, param):
    """``r`` on the points ``sel`` grows strictly with ``param`` (their position along the boundary)."""
    order = np.argsort(param[sel])
    assert sel.sum() >= 4, "the path needs a few points"
    assert _strictly_increasing(r[sel][order]), np.column_stack([param[sel][order], r[sel][order]])


def test_sphere_meridians_front_and_back():
    """A whole ball on a plane: along each half meridian (plane y = 0) from the bottom pole to the top."""
    mesh = skfem.MeshTet.init_ball(nrefs=2).with_boundaries({"surface": lambda x: np.ones(x.shape[1], bool)})
    sol = _solution(mesh, "surface", HalfSpace([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]), pole=[0.0, 0.0, -1.0])
    r, label = contact_coordinate(sol)
    assert label.startswith("r ")
    x, y, z = sol.points.T
    theta = np.arccos(np.clip(-z / np.linalg.norm(sol.points, axis=1), -1, 1))  # angle from the bottom pole
    for side in (x > 1e-9, x < -1e-9):
        _check_path(r, (np.abs(y) < 1e-9) & side, theta)
    # on the loaded cap the abscissa is the exact chord radius R sin(theta) (R = 1): Hertz's r
    cap = theta < 0.5
    np.testing.assert_allclose(r[cap], np.sin(theta[cap]), atol=1e-12)
    # the old rule folded the far side back onto the contact zone: points with r < a but no pressure
    assert not np.any((r < 0.3) & (sol.pressure == 0) & (theta > np.pi / 2))


def _cylinder(n=6, length=1.0):
    """Cylinder of radius 1 about the z axis, z in [0, length]: the elliptical-grid map of a box."""
    cube = meshes.box(-1.0, 1.0, -1.0, 1.0, 0.0, length, 2 * n, 2 * n, n)
    cube = cube.with_boundaries({"lateral": lambda x: (np.abs(x[0]) > 1 - 1e-9) | (np.abs(x[1]) > 1 - 1e-9)})
    a, b, c = cube.doflocs
    X = a * np.sqrt(1.0 - b**2 / 2.0)
    Y = b * np.sqrt(1.0 - a**2 / 2.0)
    return dataclasses.replace(cube, doflocs=np.vstack([X, Y, c]))


def test_cylinder_rings_and_lines():
    """A cylinder lying on a plane (line contact at y = -1): around each ring and along the axis."""
    mesh = _cylinder()
    sol = _solution(mesh, "lateral", HalfSpace([0.0, -1.0, 0.0], [0.0, 1.0, 0.0]), pole=[0.0, -1.0, 0.5])
    r, _ = contact_coordinate(sol)
    x, y, z = sol.points.T
    theta = np.arccos(np.clip(-y / np.hypot(x, y), -1, 1))  # angle from the contact line
    for zk in np.unique(np.round(z, 9)):
        ring = np.abs(z - zk) < 1e-9
        for side in (x > 1e-9, x < -1e-9):
            _check_path(r, ring & side, theta)
    line = (np.abs(x) < 1e-9) & (y < 0) & (z >= 0.5 - 1e-9)  # the contact line, from the centre outward
    _check_path(r, line, z)


def test_gmsh_half_cylinder_arc():
    """The Gmsh body of examples/finite_half_cylinder.toml: the curved arc from the pole outward."""
    mesh = meshes.read(EXAMPLES / "half_cylinder.msh")
    sol = _solution(mesh, "curved", HalfSpace([0.0, 0.0], [0.0, 1.0]))
    r, label = contact_coordinate(sol)
    assert label.startswith("x ")
    x, y = sol.points.T
    theta = np.arctan2(-x, 1.0 - y)  # the disc's centre is (0, 1); the pole (0, 0)
    order = np.argsort(theta)
    assert _strictly_increasing(np.abs(r[order]))
    assert np.all(r[x < -1e-9] < 0)  # signed like +x: the half model lies at x <= 0


def test_disc_o_ring_both_halves_past_the_fold():
    """A whole disc (an O-ring section) on a plane: each half of the circle from the bottom to the top."""
    mesh = skfem.MeshTri.init_circle(nrefs=3).with_boundaries({"ring": lambda x: np.ones(x.shape[1], bool)})
    sol = _solution(mesh, "ring", HalfSpace([0.0, -1.0], [0.0, 1.0]), pole=[0.0, -1.0])
    r, _ = contact_coordinate(sol)
    x, y = sol.points.T
    theta = np.arccos(np.clip(-y / np.hypot(x, y), -1, 1))
    right, left = x > 1e-9, x < -1e-9
    _check_path(r, right, theta)
    _check_path(-r, left, theta)
    assert np.all(r[right] > 0) and np.all(r[left] < 0)
    # the loaded zone is symmetric about the pole: half its extent is |x| of its outermost node (R sin theta)
    loaded = sol.pressure > 0
    assert loaded.sum() >= 3
    np.testing.assert_allclose(loaded_half_width(sol), np.max(np.abs(x[loaded])), rtol=1e-12)


def test_pressure_plot_of_a_ball_is_a_profile_not_a_cloud():
    """The plotted points of the ball, in abscissa order, carry a pressure that falls away from the pole."""
    mesh = skfem.MeshTet.init_ball(nrefs=2).with_boundaries({"surface": lambda x: np.ones(x.shape[1], bool)})
    sol = _solution(mesh, "surface", HalfSpace([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]), pole=[0.0, 0.0, -1.0])
    sol.total_contact_force = np.zeros(3)
    sol.normal_force = 1.0
    sol.extra = {}
    sol.contact_half_width = lambda axis=0, center=None: loaded_half_width(sol)
    fig = pressure_figure(sol)
    xs, ps = fig.axes[0].get_lines()[0].get_data()  # the computed pressure (no reference)
    assert np.all(np.diff(xs) >= 0)
    assert np.all(np.diff(ps[xs > 0.05]) <= 1e-12)  # a Hertz-like cap: no zero pressure inside the zone


def _write_ball_msh(path: Path) -> Path:
    """The ball of :func:`test_sphere_meridians_front_and_back` as a Gmsh 2.2 file: 'surface' and 'body' groups."""
    ball = skfem.MeshTet.init_ball(nrefs=2)
    lines, tag = [], 0
    for f in ball.boundary_facets():
        tag += 1
        a, b, c = ball.facets[:, f] + 1
        lines.append(f"{tag} 2 2 1 1 {a} {b} {c}")
    for e in range(ball.nelements):
        tag += 1
        lines.append(f"{tag} 4 2 2 100 " + " ".join(str(i + 1) for i in ball.t[:, e]))
    nodes = [f"{i + 1} {x:.17g} {y:.17g} {z:.17g}" for i, (x, y, z) in enumerate(ball.p.T)]
    path.write_text("\n".join(["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "2",
                               '2 1 "surface"', '3 2 "body"', "$EndPhysicalNames", "$Nodes", str(len(nodes)), *nodes,
                               "$EndNodes", "$Elements", str(len(lines)), *lines, "$EndElements", ""]))
    return path


def test_gmsh_ball_meridians(tmp_path):
    """A 3D Gmsh body (a ball read from a .msh file with a physical surface group) on a plane."""
    mesh = meshes.read(_write_ball_msh(tmp_path / "ball.msh"))
    sol = _solution(mesh, "surface", HalfSpace([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]), pole=[0.0, 0.0, -1.0])
    r, _ = contact_coordinate(sol)
    x, y, z = sol.points.T
    theta = np.arccos(np.clip(-z / np.linalg.norm(sol.points, axis=1), -1, 1))
    for side in (x > 1e-9, x < -1e-9):
        _check_path(r, (np.abs(y) < 1e-9) & side, theta)
