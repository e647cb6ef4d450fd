"""Issue 23 (problem files and outputs): a problem file with two ``[[body]]`` tables and a two-body pair.

``examples/two_cylinders.toml`` is the problem of ``examples/two_cylinders.py``,
:func:`alcontact.problems.two_body.hertz_cylinders` at level 0, written as a problem file: both
bodies are read from one Gmsh file, ``examples/two_cylinders.msh`` (one physical group of
triangles per body, ``[body.mesh] group``; written by ``examples/two_cylinders_mesh.py`` from the
Python API's meshes). References: the Python API's solution of the same problem (1e-10 relative:
the same equations and node order), and Hertz with the effective modulus and radius (Johnson,
Contact Mechanics, eq. 4.45-4.47) within 2 %, the tolerance of
``tests/verification/test_two_body_mortar.py``. ``alcontact check`` names the key of each
bad pair, and bodies of different dimensions.
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.errors import ConfigError
from alcontact.io.config import load_problem_text
from alcontact.io.preflight import check_problem
from alcontact.problems.two_body import hertz_cylinders

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
LEVEL = runpy.run_path(str(EXAMPLES / "two_cylinders_mesh.py"))["LEVEL"]
TOML = (EXAMPLES / "two_cylinders.toml").read_text(encoding="utf-8")
LOWER = 'mesh = { generator = "file", file = "two_cylinders.msh", group = "lower" }'
UPPER = 'mesh = { generator = "file", file = "two_cylinders.msh", group = "upper" }'


@pytest.fixture(scope="module")
def folder():
    """The folder of the problem file and its mesh."""
    return EXAMPLES


def test_committed_mesh_is_what_the_script_writes(tmp_path):
    from alcontact.fem import meshes

    ns = runpy.run_path(str(EXAMPLES / "two_cylinders_mesh.py"))
    fresh, committed = meshes.read(ns["main"](tmp_path / "m.msh")), meshes.read(EXAMPLES / "two_cylinders.msh")
    assert np.array_equal(fresh.p, committed.p) and np.array_equal(fresh.t, committed.t)
    assert sorted(committed.subdomains) == ["lower", "upper"]


def test_each_group_is_one_body_with_its_own_boundaries(folder):
    """``select_group``: the cells of one physical group, with the part of every boundary group on it."""
    from alcontact.fem import meshes

    whole = meshes.read(folder / "two_cylinders.msh")
    api = hertz_cylinders(LEVEL).model.bodies
    for name, body in zip(("lower", "upper"), api):
        part = meshes.select_group(whole, name)
        assert np.array_equal(part.p, body.mesh.p) and np.array_equal(part.t, body.mesh.t)
        for b in ("top", "bottom", "left", "right"):
            got = {tuple(sorted(f)) for f in part.facets[:, part.boundaries[b]].T}
            want = {tuple(sorted(f)) for f in body.mesh.facets[:, body.mesh.boundaries[b]].T}
            assert got == want, (name, b)


def test_two_cylinders_file_matches_python_api_and_hertz(folder):
    setup = check_problem(folder / "two_cylinders.toml").setup
    model = setup.problem.model
    assert len(model.bodies) == 2 and [b.material.E for b in model.bodies] == [200e3, 70e3]
    sol = solve(setup.problem, setup.algorithm)
    api = hertz_cylinders(LEVEL)
    ref_sol = solve(api, "ssn")
    assert sol.result.success and ref_sol.result.success
    assert abs(sol.normal_force - ref_sol.normal_force) <= 1e-10 * abs(ref_sol.normal_force)
    assert abs(sol.peak_pressure_nodal_max - ref_sol.peak_pressure_nodal_max) <= 1e-10 * ref_sol.peak_pressure_nodal_max
    a_file = sol.contact_half_width(axis=0, center=(0.0, 0.0))
    assert abs(a_file - ref_sol.contact_half_width(axis=0, center=(0.0, 0.0))) <= 1e-10 * a_file
    # the displacement of every node, matched by position (the Gmsh files keep the node order of the meshes)
    for bf, ba, uf, ua in zip(model.bodies, api.model.bodies, model.split(sol.u), api.model.split(ref_sol.u)):
        assert np.allclose(bf.mesh.p, ba.mesh.p, rtol=0, atol=1e-14)
        assert np.max(np.abs(uf - ua)) <= 1e-10 * np.max(np.abs(ua))
    # Hertz with E* of both bodies (the file's [reference]: radius 10 = 1 / (1/20 + 1/20))
    ref = setup.reference
    assert ref.e_star == pytest.approx(api.reference.e_star, rel=1e-14)
    P = ref.load(sol.normal_force)
    assert abs(a_file / ref.half_width(P) - 1) <= 0.02
    assert abs(sol.peak_pressure_nodal_max / ref.peak_pressure(P) - 1) <= 0.02
    assert sol.extra["contact_force_balance"] <= 1e-10


def _issues(text: str, folder: Path) -> dict[str, str]:
    with pytest.raises(ConfigError) as exc:
        load_problem_text(text, base_dir=folder)
    return {i.path: i.message for i in exc.value.issues}


@pytest.mark.parametrize("key, old, new, says", [
    ("contact.master", 'master = "body0/top"', 'master = "body0/topp"', "Did you mean 'body0/top'"),
    ("contact.master", 'master = "body0/top"', 'master = "body2/top"', "there is no body 'body2'"),
    ("contact.boundary", 'boundary = "body1/bottom"  # the slave', 'boundary = "body1/bot"', "no body has"),
    ("contact.master", 'master = "body0/top"', 'master = "body1/bottom"', "the same boundary as the slave"),
    ("contact.boundary", 'boundary = "body1/bottom"  # the slave', 'boundary = "bottom"', "ambiguous, body0 and body1"),
    ("contact.master", 'master = "body0/top"\n', '\n', "missing"),
    ("support[1].boundary", 'boundary = "body0/bottom"', 'boundary = "body0/botom"', "body0/bottom"),
    ("body[2].material.nu", "nu = 0.35", "nu = 0.7", "0.7"),
    ("obstacle", "[contact]", '[obstacle]\ntype = "circle"\ncenter = [0.0, 0.0]\nradius = 1.0\n\n[contact]',
     "given together with [[body]]"),
])
def test_two_body_pair_errors_name_the_key(folder, key, old, new, says):
    assert old in TOML
    issues = _issues(TOML.replace(old, new, 1), folder)
    assert key in issues, issues
    assert says in issues[key], issues[key]


@pytest.mark.parametrize("key, old, new, says", [
    ("body[1].mesh.group", 'group = "lower"', 'group = "lowr"', "its physical groups of surfaces: lower, upper"),
    ("body[1].mesh.group", LOWER, 'mesh = { generator = "rectangle", bounds = [0, 1, -1, 0], cells = [2, 2], '
                                  'group = "lower" }', "not used with generator = 'rectangle'"),
])
def test_bad_mesh_group_is_named(folder, key, old, new, says):
    issues = _issues(TOML.replace(old, new, 1), folder)
    assert key in issues, issues
    assert says in issues[key], issues[key]


def test_bodies_of_different_dimensions_are_refused(folder):
    text = TOML.replace(LOWER, 'mesh = { generator = "box", bounds = [0, 1, 0, 1, -1, 0], cells = [1, 1, 1] }')
    issues = _issues(text, folder)
    assert "body" in issues and "different dimensions" in issues["body"], issues
    assert "body0: 3D" in issues["body"] and "body1: 2D" in issues["body"]


PER_BODY = """
[problem]
name = "two-cylinders, supports per body"

[[body]]
mesh = { generator = "file", file = "two_cylinders.msh", group = "lower" }
material = { E = 200e3, nu = 0.3 }
support = [{ boundary = "bottom" }, { boundary = "left", components = [0] }]

[[body]]
mesh = { generator = "file", file = "two_cylinders.msh", group = "upper" }
material = { E = 70e3, nu = 0.35 }
support = [{ boundary = "left", components = [0] },
           { boundary = "top", components = [1], value = -0.1894439727056968 }]

[contact]
boundary = "body1/bottom"
master = "body0/top"

[solver]
algorithm = "ssn"
"""


def test_supports_given_per_body_are_the_same_problem(folder):
    """``[[body.support]]`` names its body's boundaries bare: the same supports as ``"body<k>/<name>"``."""
    a = load_problem_text(PER_BODY, base_dir=folder)
    b = check_problem(folder / "two_cylinders.toml").setup
    assert sorted(s.boundary for s in a.problem.supports) == sorted(s.boundary for s in b.problem.supports)
    sa, sb = solve(a.problem, "ssn"), solve(b.problem, "ssn")
    assert sa.normal_force == pytest.approx(sb.normal_force, rel=1e-12)
    issues = _issues(PER_BODY.replace('{ boundary = "left", components = [0] }]',
                                      '{ boundary = "lft", components = [0] }]'), folder)
    assert "body[1].support[2].boundary" in issues and "Did you mean 'left'" in issues["body[1].support[2].boundary"]
    issues = _issues(PER_BODY.replace('algorithm = "ssn"', 'algorithm = "ssn"\n\n[[body.load]]\ntype = "body-force"\n'
                                                           'vector = [0.0, -1.0]'), folder)
    assert "body[2].load[1].type" in issues, issues
