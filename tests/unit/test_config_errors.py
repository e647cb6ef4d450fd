"""Problem files with mistakes: each is reported at load time with its key path, the value and the fix."""

from __future__ import annotations

import pytest

from _helpers import flat
from alcontact.errors import ConfigError
from alcontact.io.config import load_problem, load_problem_text

BASE = """
[problem]
name = "tiny"

[mesh]
generator = "rectangle"
bounds = [0.0, 1.0, 0.0, 1.0]
cells = [2, 2]

[material]
E = 1000.0
nu = 0.3

[[support]]
boundary = "top"
components = [1]
value = -0.01

[[support]]
boundary = "left"
components = [0]

[obstacle]
type = "half-space"
point = [0.0, 0.0]
normal = [0.0, 1.0]

[contact]
boundary = "bottom"

[solver]
algorithm = "simo-laursen"
"""


def test_base_file_is_valid():
    setup = load_problem_text(BASE)
    assert setup.problem.model.dim == 2 and setup.times == (1.0,)


def _sub(old: str, new: str) -> str:
    assert old in BASE
    return BASE.replace(old, new)


# (id, file text, fragments the message must contain)
CASES = [
    ("toml-syntax", BASE + "\n[solver\n", ["not valid TOML"]),
    ("unknown-table", BASE + "\n[solvr]\nmaxiter = 3\n", ["solvr:", "unknown table [solvr]", "Did you mean 'solver'"]),
    ("unknown-key", BASE + "penalty_scal = 10.0\n",
     ["solver.penalty_scal", "unknown key in [solver]", "Did you mean 'penalty_scale'"]),
    ("type-str-for-int", BASE + 'maxiter = "ten"\n',
     ["solver.maxiter", "'ten'", "expected an integer", "without quotes"]),
    ("float-for-int", BASE + "maxiter = 10.5\n", ["solver.maxiter", "10.5", "whole number"]),
    ("out-of-range", BASE + "penalty_scale = -1.0\n", ["solver.penalty_scale", "-1.0", "out of range", "> 0"]),
    # nu = 0.5 is the exactly incompressible solid: the mixed body only (finite kinematics, P2)
    ("nu-half", _sub("nu = 0.3", "nu = 0.5"), ["material.nu", "0.5", "mixed", "use nu < 0.5"]),
    ("nu-above-half", _sub("nu = 0.3", "nu = 0.6"), ["material.nu", "0.6", "out of range", "(-1, 0.5]"]),
    ("E-zero", _sub("E = 1000.0", "E = 0"), ["material.E", "out of range", "> 0"]),
    ("E-inf", _sub("E = 1000.0", "E = inf"), ["material.E", "finite"]),
    ("bad-choice", _sub('algorithm = "simo-laursen"', 'algorithm = "simo-laursn"'),
     ["solver.algorithm", "'simo-laursn'", "Did you mean 'simo-laursen'", "Allowed:"]),
    ("bad-penalty", BASE + 'penalty = "exp-met3"\n', ["solver.penalty", "'exp-met3'", "Allowed:"]),
    ("penalty-without-family-p", BASE + 'penalty = "log-met2"\n',
     ["solver.penalty", "uses its own penalty", "family-p"]),
    ("missing-table", _sub('[contact]\nboundary = "bottom"\n', ""), ["missing table [contact]"]),
    ("missing-key", _sub('boundary = "bottom"', 'friction = 0.0'), ["contact.boundary", "missing (required)"]),
    ("contact-boundary-unknown", _sub('boundary = "bottom"', 'boundary = "botom"'),
     ["contact.boundary", "'botom'", "no boundary", "Did you mean 'bottom'", "bottom, left, right, top"]),
    ("support-boundary-unknown", _sub('boundary = "left"', 'boundary = "lefft"'),
     ["support[2].boundary", "Did you mean 'left'"]),
    ("component-out-of-range", _sub("components = [0]", "components = [2]"),
     ["support[2].components", "[2]", "0..1"]),
    ("support-value-length", _sub("value = -0.01", "value = [0.0, -0.01, 0.0]"),
     ["support[1].value", "needs a number or 1 (one per listed component) or 2 numbers"]),
    ("single-table-for-array", _sub('[[support]]\nboundary = "left"\ncomponents = [0]\n', "")
     .replace("[[support]]", "[support]"), ["support:", "write each entry as [[support]]"]),
    ("bounds-length", _sub("bounds = [0.0, 1.0, 0.0, 1.0]", "bounds = [0.0, 1.0, 0.0, 1.0, 0.0, 1.0]"),
     ["mesh.bounds", "'rectangle' needs 4 entries"]),
    ("bounds-empty-range", _sub("bounds = [0.0, 1.0, 0.0, 1.0]", "bounds = [1.0, 0.0, 0.0, 1.0]"),
     ["mesh.bounds", "x range", "lower < upper"]),
    ("mesh-order", _sub("cells = [2, 2]", "cells = [2, 2]\norder = 3"), ["mesh.order", "= 3", "in [1, 2]"]),
    ("refine-missing-key", _sub("cells = [2, 2]", "cells = [2, 2]\nrefine = { center = [0.5, 1.0], width = 0.1, "
                                                  "depth = 0.1 }"),
     ["mesh.refine.h_min", "missing (required)"]),
    ("mesh-file-missing", _sub('generator = "rectangle"\nbounds = [0.0, 1.0, 0.0, 1.0]\ncells = [2, 2]',
                               'generator = "file"\nfile = "nowhere.msh"'),
     ["mesh.file", "'nowhere.msh'", "does not exist"]),
    ("obstacle-unknown", _sub('type = "half-space"', 'type = "half-spce"'),
     ["obstacle.type", "unknown obstacle", "Did you mean 'half-space'"]),
    ("obstacle-unknown-param", _sub("normal = [0.0, 1.0]", "normal = [0.0, 1.0]\nradius = 2.0"),
     ["obstacle.radius", "unknown parameter of obstacle 'half-space'", "Accepted: normal, point"]),
    ("obstacle-param-typo", _sub("normal = [0.0, 1.0]", "normall = [0.0, 1.0]"),
     ["obstacle.normall", "Did you mean 'normal'", "obstacle.normal", "missing"]),
    ("obstacle-wrong-dim", _sub('type = "half-space"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]',
                                'type = "sphere"\ncenter = [0.0, 0.0, 2.0]\nradius = 1.0'),
     ["obstacle.type", "'sphere'", "2D"]),
    ("obstacle-user", _sub('type = "half-space"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]', 'type = "user"'),
     ["obstacle.type", "'user'", "data only"]),
    ("obstacle-bad-value", _sub("normal = [0.0, 1.0]", "normal = [0.0, 0.0]"), ["obstacle", "half-space"]),
    ("traction-vector-length", BASE + '\n[[load]]\ntype = "traction"\nboundary = "right"\nvector = [1.0, 0.0, 0.0]\n',
     ["load[1].vector", "needs 2 numbers"]),
    ("pressure-without-value", BASE + '\n[[load]]\ntype = "pressure"\nboundary = "right"\n',
     ["load[1].value", "missing", "pressure"]),
    ("load-type", BASE + '\n[[load]]\ntype = "presure"\nboundary = "right"\nvalue = 1.0\n',
     ["load[1].type", "Did you mean 'pressure'"]),
    ("times-not-increasing", BASE + "\n[loading]\ntimes = [0.5, 0.25, 1.0]\n",
     ["loading.times", "strictly increasing"]),
    ("ramp-malformed", _sub("value = -0.01", "value = -0.01\nramp = [[0.0, 0.0], [0.0, 1.0]]"),
     ["support[1].ramp", "increase strictly"]),
    ("ramp-not-pairs", _sub("value = -0.01", "value = -0.01\nramp = [0.0, 1.0]"),
     ["support[1].ramp", "[t, factor] pairs"]),
    ("friction-negative", _sub('boundary = "bottom"', 'boundary = "bottom"\nfriction = -0.1'),
     ["contact.friction", "-0.1", ">= 0"]),
    ("friction-with-penalty-algorithm", _sub('boundary = "bottom"', 'boundary = "bottom"\nfriction = 0.3')
     .replace('algorithm = "simo-laursen"', 'algorithm = "penalty"'),
     ["solver.algorithm", "not available with friction"]),
    ("friction-option-range", BASE + "\n[solver.friction]\ncutback_factor = 1.5\n",
     ["solver.friction.cutback_factor", "in (0, 1)"]),
    ("bool-type", BASE + '\n[output]\nvtu = "yes"\n', ["output.vtu", "true or false"]),
    ("region-not-in-mesh", BASE + '\n[[material.region]]\nname = "steel"\nE = 1000.0\nnu = 0.3\n',
     ["material.region[1].name", "no region 'steel'", "Mesh regions: (none)"]),
    ("reference-without-radius", BASE + '\n[reference]\nkind = "hertz"\n', ["reference.radius", "missing"]),
]


@pytest.mark.parametrize("text, fragments", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_file_is_reported(tmp_path, text, fragments):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_problem(path)
    msg = flat(str(info.value))
    assert "nothing was solved" in msg
    for frag in fragments:
        assert frag in msg, f"{frag!r} not in {msg!r}"


def test_enough_distinct_cases():
    assert len({c[0] for c in CASES}) >= 25


def test_all_errors_are_collected_together(tmp_path):
    text = (_sub("nu = 0.3", "nu = 0.7").replace('boundary = "bottom"', 'boundary = "bottm"')
            + "penalty_scale = 0\nmaxiter = 0\n")
    path = tmp_path / "many.toml"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_problem(path)
    paths = [i.path for i in info.value.issues]
    assert {"material.nu", "solver.penalty_scale", "solver.maxiter"} <= set(paths)
    assert str(path) in str(info.value) and "3 errors" in str(info.value) or "4 errors" in str(info.value)


def test_missing_problem_file(tmp_path):
    with pytest.raises(ConfigError, match="does not exist"):
        load_problem(tmp_path / "nope.toml")


def test_unreadable_mesh_file(tmp_path):
    (tmp_path / "body.msh").write_text("this is not a mesh\n")
    text = _sub('generator = "rectangle"\nbounds = [0.0, 1.0, 0.0, 1.0]\ncells = [2, 2]',
                'generator = "file"\nfile = "body.msh"')
    path = tmp_path / "p.toml"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_problem(path)
    msg = flat(str(info.value))
    assert "mesh.file = 'body.msh'" in msg and "cannot read mesh file" in msg


def test_gmsh_file_with_regions(tmp_path):
    """A Gmsh mesh with physical groups: boundaries by name, a region with the body's material is accepted."""
    import meshio  # a dependency: a missing meshio is a failure, not a skip
    import numpy as np

    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    cells = [("triangle", np.array([[0, 1, 2], [0, 2, 3]])), ("line", np.array([[0, 1], [2, 3]]))]
    m = meshio.Mesh(np.c_[pts, np.zeros(4)], cells,
                    cell_data={"gmsh:physical": [np.array([1, 1]), np.array([2, 3])],
                               "gmsh:geometrical": [np.array([1, 1]), np.array([1, 2])]},
                    field_data={"body": np.array([1, 2]), "base": np.array([2, 1]), "lid": np.array([3, 1])})
    meshio.write(tmp_path / "sq.msh", m, file_format="gmsh22", binary=False)
    text = (BASE.replace('generator = "rectangle"\nbounds = [0.0, 1.0, 0.0, 1.0]\ncells = [2, 2]',
                         'generator = "file"\nfile = "sq.msh"')
            .replace('boundary = "top"', 'boundary = "lid"').replace('boundary = "bottom"', 'boundary = "base"')
            .replace('[[support]]\nboundary = "left"\ncomponents = [0]\n', "")
            + '\n[[material.region]]\nname = "body"\nE = 1000.0\nnu = 0.3\n')
    path = tmp_path / "p.toml"
    path.write_text(text)
    setup = load_problem(path)
    assert setup.problem.contact_boundary == "base"
    path.write_text(text.replace("nu = 0.3\n", "nu = 0.2\n").replace("[material]\nE = 1000.0\nnu = 0.2",
                                                                      "[material]\nE = 1000.0\nnu = 0.3"))
    with pytest.raises(ConfigError, match="not supported yet"):
        load_problem(path)
