"""Several contact pairs and meshed surfaces from problem files and files on disk; their bad input.

What is checked: ``[[pair]]`` tables add contact pairs that ran (the pair forces in
summary.json, equal and opposite for the squeezed block of ``tests/data/squeezed_block.toml``,
whose closed form is p = E / (1 - nu^2) 2d / H); a ``surface`` obstacle read from an STL
file or a Gmsh physical group is the surface that was written; and every bad input is an
InputError (a ConfigError from a problem file) naming the key: a missing file, an
unreadable STL, a group not in the file (with the available names), a 3D surface for a 2D
body, an inconsistent orientation, a [[pair]] on a missing boundary or at finite kinematics.
"""

from __future__ import annotations

import json
from pathlib import Path

import meshio
import numpy as np
import pytest

from alcontact.app import run_setup
from alcontact.contact import obstacles
from alcontact.errors import ConfigError, InputError
from alcontact.io import load_problem
from alcontact.io.config import load_problem_text

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "tests" / "data" / "squeezed_block.toml"


def test_squeezed_block_example_reports_equal_and_opposite_pair_forces(tmp_path):
    setup = load_problem(EXAMPLE)
    assert len(setup.problem.pairs) == 2 and [p.slave.name for p in setup.problem.pairs] == ["bottom", "top"]
    run_setup(setup, tmp_path / "res")
    s = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert s["status"] == "converged"
    f = [np.array(p["force"]) for p in s["pair_contact_forces"]]
    exact = 1000.0 / (1 - 0.3**2) * 2 * 0.01 / 1.0  # times the unit width of each face
    np.testing.assert_allclose(f[0], [0.0, exact], rtol=1e-10, atol=1e-10 * exact)
    assert np.linalg.norm(f[0] + f[1]) <= 1e-10 * exact
    assert [p["slave"] for p in s["pair_contact_forces"]] == ["bottom", "top"]


def _text(extra: str = "", kin: str = "") -> str:
    return EXAMPLE.read_text().replace('[contact]\nboundary = "bottom"\n', f'[contact]\nboundary = "bottom"\n{kin}') \
        + extra


def test_a_pair_on_a_missing_boundary_is_named():
    with pytest.raises(ConfigError) as info:
        load_problem_text(_text().replace('[[pair]]                               # the upper plate against the '
                                          'top face\nboundary = "top"', '[[pair]]\nboundary = "lid"'))
    msg = str(info.value)
    assert "pair[1].boundary" in msg and "'lid'" in msg and "top" in msg


def test_a_pair_with_an_unknown_obstacle_parameter_is_named():
    with pytest.raises(ConfigError) as info:
        load_problem_text(_text().replace("normal = [0.0, -1.0]", "normal = [0.0, -1.0]\nradius = 2.0"))
    assert "pair[1].radius" in str(info.value)


def _finite_text(extra_contact: str = "") -> str:
    return _text(kin=f'kinematics = "finite"\n{extra_contact}').replace(
        "[material]\nE = 1000.0\nnu = 0.3", '[material]\nE = 1000.0\nnu = 0.3\nmodel = "neo-hookean"')


def test_pairs_at_finite_kinematics_load_frictionless():
    setup = load_problem_text(_finite_text())
    assert setup.finite and len(setup.problem.pairs) == 2


def test_frictional_pairs_at_finite_kinematics_are_refused():
    with pytest.raises(ConfigError) as info:
        load_problem_text(_finite_text("friction = 0.2\n"))
    msg = str(info.value)
    assert "pair:" in msg and "contact.friction > 0" in msg and "kinematics = 'small'" in msg


# ----------------------------------------------------------------------------------- files
def _tri_plane(z: float = 0.0):
    V = np.array([[-2.0, -2.0, z], [2.0, -2.0, z], [2.0, 2.0, z], [-2.0, 2.0, z]])
    return V, np.array([[0, 1, 2], [0, 2, 3]])


def test_surface_from_an_stl_file(tmp_path):
    V, F = _tri_plane(0.25)
    meshio.write(tmp_path / "plane.stl", meshio.Mesh(V, [("triangle", F)]))
    ob = obstacles.make("surface", file=str(tmp_path / "plane.stl"))
    assert ob.dim == 3 and "plane.stl" in ob.describe()
    x = np.array([[0.3, -0.1, 1.0], [0.0, 0.0, 0.0]])
    np.testing.assert_allclose(ob.gap(x), [-0.75, 0.25], rtol=1e-7)  # STL stores single precision
    np.testing.assert_allclose(ob.normal(x), [[0, 0, 1], [0, 0, 1]], atol=1e-12)


def _gmsh_file(path: Path) -> None:
    """A 2D Gmsh file: a square of two triangles ("body"), its top edge ("lid") and a polyline ("groove")."""
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [-1, -1, 0], [0, -2, 0], [1, -1, 0]], float)
    cells = [("triangle", np.array([[0, 1, 2], [0, 2, 3]])), ("line", np.array([[2, 3]])),
             ("line", np.array([[6, 5], [5, 4]]))]
    meshio.write(path, meshio.Mesh(pts, cells, cell_data={"gmsh:physical": [np.array([1, 1]), np.array([2]),
                                                                             np.array([3, 3])],
                                                           "gmsh:geometrical": [np.array([1, 1]), np.array([2]),
                                                                                np.array([3, 3])]},
                                   field_data={"body": np.array([1, 2]), "lid": np.array([2, 1]),
                                               "groove": np.array([3, 1])}),
                 file_format="gmsh22", binary=False)


def test_surface_from_a_gmsh_physical_group(tmp_path):
    _gmsh_file(tmp_path / "m.msh")
    ob = obstacles.make("surface", file=str(tmp_path / "m.msh"), group="groove")
    assert ob.dim == 2 and ob.facets.shape == (2, 2)  # only the group's segments, renumbered
    np.testing.assert_allclose(ob.gap([[0.0, 0.0]]), [-np.sqrt(2.0)], rtol=1e-12)  # above the V's vertex (0, -2)
    np.testing.assert_allclose(ob.gap([[0.0, -3.0]]), [1.0], rtol=1e-12)


@pytest.mark.parametrize("case, params, texts", [
    ("missing file", lambda p: dict(file=str(p / "nope.stl")), ["file = ", "nope.stl", "no such file"]),
    ("unreadable STL", lambda p: dict(file=str(p / "bad.stl")), ["bad.stl", "could not be read", "STL"]),
    ("unknown group", lambda p: dict(file=str(p / "m.msh"), group="lids"),
     ["group = 'lids'", "available: body, groove, lid"]),
    ("group without file", lambda p: dict(vertices=[[0, 0], [1, 0]], facets=[[0, 1]], group="lid"),
     ["group", "give file"]),
    ("both", lambda p: dict(file=str(p / "m.msh"), vertices=[[0, 0], [1, 0]], facets=[[0, 1]]), ["either file"]),
    ("reversed segment", lambda p: dict(vertices=[[0, 0], [1, 0], [2, 0]], facets=[[0, 1], [2, 1]]),
     ["segments 0 and 1", "vertex 1", "inconsistent"]),
    ("reversed triangle", lambda p: dict(vertices=_tri_plane()[0], facets=[[0, 1, 2], [0, 3, 2]]),
     ["triangles 0 and 1", "same direction", "inconsistent"]),
    ("degenerate facet", lambda p: dict(vertices=[[0, 0], [1, 0], [1, 0]], facets=[[0, 1], [1, 2]]),
     ["facet 1", "degenerate"]),
])
def test_bad_surfaces_are_input_errors_naming_the_key(tmp_path, case, params, texts):
    (tmp_path / "bad.stl").write_bytes(b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0\nendsolid\n")
    _gmsh_file(tmp_path / "m.msh")
    with pytest.raises(InputError) as info:
        obstacles.make("surface", **params(tmp_path))
    msg = str(info.value)
    assert all(t in msg for t in texts), msg


def test_a_3d_surface_for_a_2d_body_is_refused_from_a_problem_file(tmp_path):
    V, F = _tri_plane()
    meshio.write(tmp_path / "plane.stl", meshio.Mesh(V, [("triangle", F)]))
    text = EXAMPLE.read_text().replace('type = "half-space"\npoint = [0.0, 0.01]\nnormal = [0.0, 1.0]',
                                       'type = "surface"\nfile = "plane.stl"')
    (tmp_path / "p.toml").write_text(text)
    with pytest.raises(ConfigError) as info:
        load_problem(tmp_path / "p.toml")
    msg = str(info.value)
    assert "obstacle.type" in msg and "3D triangulated surface" in msg and "body is 2D" in msg


def test_a_surface_file_is_read_relative_to_the_problem_file(tmp_path):
    """The squeezed block with its lower plate a meshed polyline in a Gmsh file next to the problem file."""
    pts = np.array([[3.0, 0.01, 0.0], [0.5, 0.01, 0.0], [-2.0, 0.01, 0.0]])
    meshio.write(tmp_path / "plate.msh", meshio.Mesh(pts, [("line", np.array([[0, 1], [1, 2]]))],
                                                     cell_data={"gmsh:physical": [np.array([7, 7])],
                                                                "gmsh:geometrical": [np.array([7, 7])]},
                                                     field_data={"plate": np.array([7, 1])}),
                 file_format="gmsh22", binary=False)
    text = EXAMPLE.read_text().replace('type = "half-space"\npoint = [0.0, 0.01]\nnormal = [0.0, 1.0]',
                                       'type = "surface"\nfile = "plate.msh"\ngroup = "plate"')
    (tmp_path / "p.toml").write_text(text)
    setup = load_problem(tmp_path / "p.toml")
    ref = load_problem(EXAMPLE)
    from alcontact.contact import solve

    a, b = solve(setup.problem, "simo-laursen"), solve(ref.problem, "simo-laursen")
    assert a.result.status > 0
    np.testing.assert_allclose(a.u, b.u, rtol=0, atol=1e-12 * np.abs(b.u).max())


def test_frictional_pairs_report_the_force_of_each_pair_at_every_step(tmp_path):
    """[contact] friction applies to every pair: the Coulomb path runs over the load steps, and every
    step's pair forces are in summary.json (normal parts equal and opposite) and on the frames."""
    text = EXAMPLE.read_text().replace('[contact]\nboundary = "bottom"\n',
                                       '[contact]\nboundary = "bottom"\nfriction = 0.2\n')
    text += '\n[loading]\nsteps = 2\n'
    (tmp_path / "p.toml").write_text(text)
    setup = load_problem(tmp_path / "p.toml")
    assert setup.friction == 0.2 and all(p.friction == 0.2 for p in setup.problem.pairs)
    res = run_setup(setup, tmp_path / "res")
    s = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert s["status"] == "converged"
    steps = np.array(s["step_pair_contact_forces"])
    assert steps.shape == (len(res.frames), 2, 2)
    np.testing.assert_allclose(steps[-1], res.frames[-1].pair_contact_forces(), rtol=1e-12)
    np.testing.assert_allclose(steps[-1], s_final := np.array([p["force"] for p in s["pair_contact_forces"]]),
                               rtol=1e-12)
    assert abs(s_final[0, 1] + s_final[1, 1]) <= 1e-10 * abs(s_final[0, 1])


_UPPER = 'boundary = "top"\ntype = "half-space"\npoint = [0.0, 0.99]\nnormal = [0.0, -1.0]'


@pytest.mark.parametrize("surface, key, text", [
    ('file = "nope.stl"', "pair[1].file", "= 'nope.stl': no such file"),
    ("file = 3", "pair[1].file", "= 3: expected the path"),
    ("vertices = [[0, 1], [1, 1]]\nfacets = [[0, 5]]", "pair[1].facets", "vertex index 5 is outside 0 .. 1"),
    ('vertices = "abc"\nfacets = [[0, 1]]', "pair[1].vertices", "= 'abc': expected the vertex coordinates"),
    ("vertices = [[0, 1], [1, 1], [2, 1]]\nfacets = [[0, 1], [2, 1]]", "pair[1]", "inconsistent"),
])
def test_bad_surface_in_a_problem_file_is_keyed_by_its_parameter(surface, key, text):
    with pytest.raises(ConfigError) as info:
        load_problem_text(EXAMPLE.read_text().replace(_UPPER, f'boundary = "top"\ntype = "surface"\n{surface}'))
    lines = [ln.strip() for ln in str(info.value).splitlines()]
    assert any(ln.startswith((f"{key} ", f"{key}:")) and text in ln for ln in lines), str(info.value)


def test_each_pair_takes_its_own_friction_coefficient(tmp_path):
    """``[[pair]] friction`` is that pair's coefficient (the others keep ``[contact] friction``); the run is frictional
    when one pair is, the check line names both coefficients, and summary.json reports each pair's coefficient,
    normal force and tangential force, the tangential force within the pair's Coulomb limit mu N."""
    text = EXAMPLE.read_text().replace('[contact]\nboundary = "bottom"\n',
                                       '[contact]\nboundary = "bottom"\nfriction = 0.1\n')
    text = text.replace(_UPPER, _UPPER + "\nfriction = 0.4")
    text = text.replace('[[support]]\nboundary = "left"                      # holds the block sideways; the plates '
                        'hold it vertically\ncomponents = [0]\n',
                        '[[support]]\nboundary = "left"\ncomponents = [0]\nvalue = 0.05\n'
                        'ramp = [[0.5, 0.0], [1.0, 1.0]]\ntangential = true\n')
    text += '\n[loading]\nsteps = 4\n'
    (tmp_path / "p.toml").write_text(text)
    setup = load_problem(tmp_path / "p.toml")
    assert [p.friction for p in setup.problem.pairs] == [0.1, 0.4] and setup.friction == 0.4
    assert "Coulomb mu=0.1/0.4" in setup.summary_line()
    run_setup(setup, tmp_path / "res")
    s = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert s["status"] == "converged" and s["pair_friction"] == [0.1, 0.4]
    pairs = s["pair_contact_forces"]
    assert [p["friction"] for p in pairs] == [0.1, 0.4]
    for p in pairs:  # both faces slide: each pair's tangential force is near (below: the held corners) mu N
        q = abs(p["tangential_force"][0])
        assert 0.7 * p["friction"] * p["normal_force"] < q <= p["friction"] * p["normal_force"] * (1 + 1e-9)
        np.testing.assert_allclose(p["force"][0], p["tangential_force"][0], rtol=1e-12)
    assert s["coulomb_limit"] == pytest.approx(sum(p["friction"] * p["normal_force"] for p in pairs), rel=1e-12)


def test_a_negative_pair_friction_is_named():
    with pytest.raises(ConfigError) as info:
        load_problem_text(_text().replace(_UPPER, _UPPER + "\nfriction = -0.1"))
    assert "pair[1].friction" in str(info.value)


def test_a_frictional_pair_at_finite_kinematics_is_refused():
    with pytest.raises(ConfigError) as info:
        load_problem_text(_finite_text().replace(_UPPER, _UPPER + "\nfriction = 0.2"))
    msg = str(info.value)
    assert "pair[1].friction > 0" in msg and "kinematics = 'small'" in msg
