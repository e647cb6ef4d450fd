"""Issue 23: a problem file with three ``[[body]]`` tables and two two-body pairs (``[contact]`` and ``[[pair]]``).

``tests/data/seal/seal.toml`` is :func:`alcontact.problems.two_body.seal` (``n = 8``) as a problem file
(its meshes are the Python API's, written as Gmsh 4.1 files by ``write_seal_meshes.py``, whose physical line
groups keep the cord's interior symmetry lines). Reference: the Python API's solution of the same
problem (1e-10 relative on the pair forces, the pressures and every nodal displacement: the same
equations). ``alcontact check`` names the key of a ``[[pair]]`` that cannot run.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.errors import ConfigError
from alcontact.io.preflight import check_problem
from alcontact.problems.two_body import seal

DATA = Path(__file__).resolve().parents[1] / "data" / "seal"
sys.path.insert(0, str(DATA))
from write_seal_meshes import PARAMETERS  # noqa: E402
from write_seal_meshes import write_meshes as write_seal_meshes  # noqa: E402

TOML = (DATA / "seal.toml").read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("seal")
    write_seal_meshes(out)
    (out / "seal.toml").write_text(TOML, encoding="utf-8")
    return out


def test_file_equals_the_python_api(folder):
    setup = check_problem(folder / "seal.toml").setup
    problem = setup.problem
    assert problem.kinematics == "finite" and len(problem.bodies) == 3 and len(problem.pairs) == 2
    sol = solve(problem, setup.algorithm, history=setup.history, steps=setup.times)
    ref = solve(seal(**PARAMETERS), "ssn", steps=8)
    assert sol.result.success and ref.result.success, (sol.result.message, ref.result.message)
    np.testing.assert_allclose(sol.pair_contact_forces(), ref.pair_contact_forces(), rtol=0,
                               atol=1e-10 * np.abs(ref.pair_contact_forces()).max())
    np.testing.assert_allclose(sol.pressure, ref.pressure, rtol=0, atol=1e-10 * ref.pressure.max())
    np.testing.assert_allclose(sol.u, ref.u, rtol=0, atol=1e-10 * np.abs(ref.u).max())
    assert sol.extra["contact_force_balance"] <= 1e-10


def _errors(folder: Path, text: str) -> str:
    path = folder / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ConfigError) as err:
        check_problem(path)
    return str(err.value)


def test_check_names_the_pair_that_cannot_run(folder):
    missing = TOML.replace('master = "body2/bottom"', 'master = "body2/lid"')
    msg = _errors(folder, missing)
    assert "pair[1].master = 'body2/lid'" in msg and "body2/bottom" in msg  # the known boundaries listed
    rigid = TOML.replace('master = "body2/bottom"', 'type = "half-space"\npoint = [0.0, 1.0]\nnormal = [0.0, -1.0]')
    assert "pair[1].type" in _errors(folder, rigid)
    same = TOML.replace('boundary = "body0/upper"', 'boundary = "body2/bottom"')
    assert "pair[1].master" in _errors(folder, same)
