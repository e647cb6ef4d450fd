"""Issue 23: a problem file with two hyperelastic ``[[body]]`` tables at ``kinematics = "finite"``.

``tests/data/ironing_two_body/ironing_two_body.toml`` is :func:`alcontact.problems.two_body.ironing_two_body`
(``n = 10``, slid by one radius in 20 steps after 4 pressing steps) as a problem file (its meshes are
those of the Python API, written as Gmsh files by ``write_ironing_meshes.py``; the two ramps of the punch's top
are the API's :func:`~alcontact.problems.two_body.ironing_two_body_history`). Reference: the Python API's
solution of the same problem (1e-10 relative on the forces, the pressures and every nodal displacement:
the same equations). ``alcontact check`` names the key of each combination that cannot run.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.errors import ConfigError
from alcontact.io.preflight import check_problem
from alcontact.problems.two_body import ironing_two_body_history

DATA = Path(__file__).resolve().parents[1] / "data" / "ironing_two_body"
sys.path.insert(0, str(DATA))
from write_ironing_meshes import PARAMETERS, write_meshes  # noqa: E402

TOML = (DATA / "ironing_two_body.toml").read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("ironing_two_body")
    write_meshes(out)
    (out / "ironing_two_body.toml").write_text(TOML, encoding="utf-8")
    return out


def test_file_equals_the_python_api(folder):
    from alcontact.problems.two_body import ironing_two_body

    setup = check_problem(folder / "ironing_two_body.toml").setup
    problem = setup.problem
    assert problem.kinematics == "finite" and len(problem.bodies) == 2
    assert [type(b).__name__ for b in problem.bodies] == ["Hyperelastic", "Hyperelastic"]
    sol = solve(problem, setup.algorithm, history=setup.history, steps=setup.times)
    api = ironing_two_body(**PARAMETERS)
    history, times = ironing_two_body_history(api)
    ref = solve(api, "ssn", history=history, steps=times)
    assert sol.result.success and ref.result.success, (sol.result.message, ref.result.message)
    assert len(sol.frames) == len(ref.frames) == 24
    for a, b in zip(sol.frames, ref.frames):
        np.testing.assert_allclose(a.contact_force, b.contact_force, rtol=0, atol=1e-10 * abs(b.contact_force[1]))
    np.testing.assert_allclose(sol.pressure, ref.pressure, rtol=0, atol=1e-10 * ref.pressure.max())
    np.testing.assert_allclose(sol.u, ref.u, rtol=0, atol=1e-10 * np.abs(ref.u).max())
    assert sol.extra["contact_force_balance"] <= 1e-10


def _check_errors(folder: Path, text: str) -> str:
    path = folder / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ConfigError) as err:
        check_problem(path)
    return str(err.value)


def test_check_names_what_cannot_run(folder):
    p2 = TOML.replace('mesh = { generator = "file", file = "punch.msh" }',
                      'mesh = { generator = "file", file = "punch.msh", order = 2 }')
    assert "body[2].mesh.order" in _check_errors(folder, p2)
    mat = 'material = { E = 1000.0, nu = 0.3, model = "neo-hookean" }'
    block, punch = TOML.split(mat)[1:]  # the text after each body's material line
    head = TOML.split(mat)[0]
    linear = head + mat.replace("neo-hookean", "linear") + block + mat + punch
    assert "body[1].material.model" in _check_errors(folder, linear)
    stress = head + mat + block + mat.replace(' }', ', plane = "stress" }') + punch
    assert "body[2].material.plane" in _check_errors(folder, stress)
    small = TOML.replace('kinematics = "finite"', 'kinematics = "small"')
    assert "body[1].material.model" in _check_errors(folder, small)  # a hyperelastic law needs finite kinematics
