"""Pre-flight checks: everything `run` would reject is found by `check` before solving."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest

from alcontact.contact import ContactProblem, Support
from alcontact.contact.obstacles import make as make_obstacle
from alcontact.errors import ConfigError, InputError
from alcontact.fem import LinearElasticity, Material, meshes
from alcontact.io import preflight
from alcontact.io.config import load_problem
from alcontact.io.preflight import MAX_DOFS, check_problem, estimate_size, exact_size, machine_memory
from alcontact.runner import run_setup

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

# a block on a rigid plane, pressed by a pressure on its top; x fixed on the left side:
# the supports leave the vertical translation and the rotation to the obstacle
BLOCK = """
[problem]
name = "held"
[mesh]
generator = "rectangle"
bounds = [-1.0, 1.0, 0.0, 0.5]
cells = [8, 2]
[material]
E = 1000.0
nu = 0.3
[[support]]
boundary = "left"
components = [0]
[[load]]
type = "pressure"
boundary = "top"
value = 1.0
[obstacle]
type = "half-space"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[contact]
boundary = "bottom"
"""


def _file(tmp_path, text: str, name: str = "p.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def _issues(exc) -> dict[str, str]:
    return {i.path: i.message for i in exc.value.issues}


# ------------------------------------------------------------------ size
@pytest.mark.parametrize("text, key, value", [
    (BLOCK + "[mesh.refine]\ncenter = [0.0, 0.5]\nh_min = 1e-5\nwidth = 0.5\ndepth = 0.3\n",
     "mesh.refine.h_min", "1e-05"),
    (BLOCK.replace("cells = [8, 2]", "cells = [3000, 3000]"), "mesh.cells", "[3000, 3000]"),
])
def test_huge_meshes_are_refused_before_meshing(tmp_path, monkeypatch, text, key, value):
    def no_mesh(*args, **kwargs):
        raise AssertionError("the mesh must not be built")

    monkeypatch.setattr(meshes, "rectangle", no_mesh)
    t0 = time.perf_counter()
    with pytest.raises(ConfigError) as exc:
        check_problem(_file(tmp_path, text))
    assert time.perf_counter() - t0 < 5.0
    msg = _issues(exc)[key]
    assert msg.startswith(f"= {value}:") and f"more than {MAX_DOFS:,} DOFs" in msg and "coarser mesh" in msg


def test_memory_limit_gives_the_amg_way_out_in_3d():
    setup = load_problem(EXAMPLES / "hertz_3d.toml")
    est = exact_size(setup)
    assert est.linear_solver == "direct"
    with pytest.raises(ConfigError) as exc:
        check_problem(EXAMPLES / "hertz_3d.toml", memory=0.5 * est.memory_bytes)
    msg = _issues(exc)["mesh.refine.h_min"]
    assert "of memory" in msg and "linear_solver = 'amg'" in msg and "coarser mesh" in msg
    assert check_problem(EXAMPLES / "hertz_3d.toml", memory=4 * est.memory_bytes).size.ndofs == est.ndofs


@pytest.mark.parametrize("generator, bounds, cells, refine, order", [
    ("rectangle", [0.0, 2.0, 0.0, 1.0], [7, 5], None, 1),
    ("rectangle", [0.0, 2.0, 0.0, 1.0], [7, 5], None, 2),
    ("rectangle", [-20.0, 20.0, -20.0, 0.0], [8, 8], "center = [0.0, 0.0]\nh_min = 0.1\nwidth = 1.6\n"
     "depth = 1.0\ngrowth = 1.15", 1),
    ("box", [0.0, 1.0, 0.0, 1.0, 0.0, 0.5], [4, 3, 2], None, 1),
    ("box", [-2.0, 2.0, -2.0, 2.0, -2.0, 0.0], [3, 3, 3], "center = [0.0, 0.0, 0.0]\nh_min = 0.2\n"
     "width = 0.5\ndepth = 0.4", 1),
])
def test_estimate_before_meshing_counts_the_mesh(tmp_path, generator, bounds, cells, refine, order):
    """Counted from the 1D axes: exact vertex/element counts for P1, P2 nodes within 1 % (Euler)."""
    dim = 2 if generator == "rectangle" else 3
    text = (f'[mesh]\ngenerator = "{generator}"\nbounds = {bounds}\ncells = {cells}\norder = {order}\n'
            + (f"[mesh.refine]\n{refine}\n" if refine else ""))
    from alcontact.io.config import validate_data
    import tomllib

    data, issues = validate_data(tomllib.loads(text))
    assert not [i for i in issues if i.path.startswith("mesh")]
    est = estimate_size(data)
    fn = meshes.rectangle if dim == 2 else meshes.box
    r = None
    if refine:
        r = {k: v for k, v in data["mesh"]["refine"].items() if v is not None}
    mesh = fn(*bounds, *cells, refine=r)
    model = LinearElasticity(mesh, Material(E=1.0, nu=0.3), order=order)
    assert est.elements == mesh.nelements
    if order == 1:
        assert est.ndofs == model.ndofs
    else:
        assert abs(est.ndofs - model.ndofs) <= 0.01 * model.ndofs
    assert est.dim == dim and not est.exact and est.memory_bytes > 0 and est.seconds > 0


def test_gmsh_header_counts(tmp_path):
    from test_mesh_quality import _write_msh

    good = meshes.rectangle(0, 1, 0, 1, 5, 4)
    _write_msh(tmp_path / "m.msh", good, good.boundaries)
    nodes, elements = preflight._gmsh_header_counts(tmp_path / "m.msh")
    nbnd = sum(len(v) for v in good.boundaries.values())
    assert nodes == good.nvertices and elements == good.nelements + nbnd


def test_machine_memory():
    total, available = machine_memory()
    assert math.isfinite(total) and 0 < available <= total


# ------------------------------------------------------------------ rigidity on each path
@pytest.mark.parametrize("solver", ["direct", "amg"])
def test_body_held_by_the_obstacle_passes_on_each_path_and_solves(tmp_path, solver):
    extra = "" if solver == "direct" else "[solver]\nlinear_solver = \"amg\"\n"
    report = check_problem(_file(tmp_path, BLOCK + extra))
    assert report.size.linear_solver == solver
    out = run_setup(report.setup, None)
    assert out.summary["status"] == "converged"


@pytest.mark.parametrize("extra, key, way", [
    ("[solver]\nlinear_solver = \"amg\"\n", "support", "components = [1]"),  # obstacle out of reach
    ("", "support", "components = [1]"),  # friction, obstacle out of reach: see the replace below
])
def test_paths_that_cannot_use_the_obstacle(tmp_path, extra, key, way):
    text = BLOCK + extra
    if not extra:  # friction: the obstacle holds the body (see test_friction_held_by_obstacle) only when touching
        text = text.replace('boundary = "bottom"', 'boundary = "bottom"\nfriction = 0.3')
    text = text.replace("point = [0.0, 0.0]", "point = [0.0, -1.0]")
    p = _file(tmp_path, text)
    with pytest.raises(ConfigError) as exc:
        check_problem(p)
    msg = _issues(exc)[key]
    assert "translation y" in msg and way in msg and "[[support]]" in msg
    # what `run` would do without the check: fail on a singular stiffness
    with pytest.raises(InputError, match="singular"):
        run_setup(load_problem(p), None)


def test_nothing_holds_the_body(tmp_path):
    p = _file(tmp_path, BLOCK.replace("components = [0]", "components = [1]"))
    with pytest.raises(ConfigError) as exc:
        check_problem(p)
    msg = _issues(exc)["support"]
    assert "translation x" in msg and "nothing holds the body" in msg and "components = [0]" in msg
    with pytest.raises(InputError, match="singular"):
        run_setup(load_problem(p), None)


# ------------------------------------------------------------------ supports
def _block_problem(*supports):
    model = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 4, 4), Material(E=1.0, nu=0.3))
    ob = make_obstacle("half-space", point=(0.0, -0.01), normal=(0.0, 1.0))
    return ContactProblem(model, ob, "bottom", supports=supports)


def test_conflicting_supports_name_both_boundaries_component_and_values():
    with pytest.raises(InputError) as exc:
        _block_problem(Support("left", (0,), 0.0), Support("bottom", (0, 1), 0.25))
    msg = str(exc.value)
    assert "'left'" in msg and "'bottom'" in msg and "component 0 (x)" in msg
    assert "0 on 'left'" in msg and "0.25 on 'bottom'" in msg and "[0.0, 0.0]" in msg


def test_same_value_twice_is_fine():
    prob = _block_problem(Support("left", (0,), 0.0), Support("bottom"), Support("bottom", (0,), 0.0),
                          Support("top", (1,), -0.01), Support("top", None, (0.0, -0.01)))
    dofs, vals = prob.dirichlet()
    assert np.unique(dofs).size == dofs.size
    pts, dmap = prob.model.all_node_dofs()
    corner = dmap[int(np.argmin(np.linalg.norm(pts - [0.0, 1.0], axis=1)))]  # on 'top' and 'left'
    assert np.allclose(vals[np.searchsorted(dofs, corner)], [0.0, -0.01])


def test_conflicting_supports_in_a_problem_file(tmp_path):
    p = _file(tmp_path, BLOCK + '[[support]]\nboundary = "bottom"\ncomponents = [0]\nvalue = 0.1\n')
    with pytest.raises(ConfigError, match=r"'left'.*'bottom'.*component 0 \(x\).*0 on 'left' and 0.1 on 'bottom'"):
        check_problem(p)


def test_ramped_support_conflicting_with_a_fixed_one(tmp_path):
    p = _file(tmp_path, BLOCK + '[[support]]\nboundary = "bottom"\ncomponents = [0]\nvalue = 0.1\n'
                                "ramp = [[0.0, 0.0], [1.0, 1.0]]\n[loading]\nsteps = 2\n")
    with pytest.raises(ConfigError) as exc:
        check_problem(p)
    msg = _issues(exc)["support"]
    assert "at step time t = 0.5" in msg and "support[1]" in msg and "support[2]" in msg and "0.05" in msg


# ------------------------------------------------------------------ number ranges
def test_overflowing_young_modulus(tmp_path):
    p = _file(tmp_path, BLOCK.replace("E = 1000.0", "E = 1e308"))
    with pytest.raises(ConfigError) as exc:
        check_problem(p)
    msg = _issues(exc)["material.E"]
    assert msg.startswith("= 1e+308") and "units" in msg and "rigid" not in msg


def test_overflowing_load(tmp_path):
    p = _file(tmp_path, BLOCK.replace("value = 1.0", "value = 1e200"))
    with pytest.raises(ConfigError) as exc:
        check_problem(p)
    assert _issues(exc)["load[1].value"].startswith("= 1e+200")


# ------------------------------------------------------------------ Gmsh file without a body
def test_gmsh_file_without_a_physical_group_for_the_body(tmp_path):
    from test_mesh_quality import _FILE_PROBLEM, _write_msh

    good = meshes.rectangle(0, 1, 0, 1, 4, 4)
    _write_msh(tmp_path / "lines.msh", good, good.boundaries, body=False)
    with pytest.raises(ConfigError) as exc:
        check_problem(_file(tmp_path, _FILE_PROBLEM.format(name="lines.msh")))
    msg = _issues(exc)["mesh.file"]
    assert msg.startswith("= 'lines.msh'") and "'bottom', 'left', 'right', 'top'" in msg
    assert "Physical Surface" in msg and "save_all" in msg


def test_examples_pass():
    for f in sorted(EXAMPLES.glob("*.toml")):
        report = check_problem(f)
        assert report.size.exact and report.size.ndofs == report.setup.problem.model.ndofs


def test_contact_points_held_inside_the_obstacle(tmp_path):
    text = BLOCK.replace("point = [0.0, 0.0]", "point = [0.0, 0.02]") + '[[support]]\nboundary = "bottom"\n'
    p = _file(tmp_path, text)
    with pytest.raises(ConfigError) as exc:
        check_problem(p)
    msg = _issues(exc)["support"]
    assert "9 contact point(s) of 'bottom'" in msg and "by 0.02" in msg and "move the obstacle" in msg
    with pytest.raises(InputError, match="penetrates the obstacle"):  # what run does without the check
        run_setup(load_problem(p), None)
