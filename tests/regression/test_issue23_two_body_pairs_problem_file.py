"""Issue 23: several contact pairs with several bodies from a problem file (``[[body]]`` with ``[[pair]]``).

``tests/data/block_base_plate.toml``: a block on a deformable base ([contact], a mortar pair) pressed by a rigid
plate (a [[pair]] on the block's top). Reference: the closed form in the file's header (uniaxial stress through
both blocks), p = d / ((1 - nu0^2) H0 / E0 + (1 - nu1^2) H1 / E1), 1e-8 at every slave node of both pairs; the
pair forces in summary.json are equal and opposite. A [[pair]] may also join two bodies (``master``) with its own
friction; every bad [[pair]] is a ConfigError naming the key.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from alcontact.app import run_setup
from alcontact.contact import BodySurface
from alcontact.errors import ConfigError
from alcontact.io import load_problem
from alcontact.io.config import load_problem_text

FILE = Path(__file__).resolve().parents[1] / "data" / "block_base_plate.toml"
EXACT = 0.01 / ((1 - 0.3 ** 2) / 1000.0 + (1 - 0.2 ** 2) / 500.0)
PLATE = 'type = "half-space"\npoint = [0.0, 1.99]\nnormal = [0.0, -1.0]\n'


def test_block_on_a_base_pressed_by_a_plate_from_a_problem_file(tmp_path):
    setup = load_problem(FILE)
    prob = setup.problem
    assert len(prob.bodies) == 2 and [prob.slave_name(p) for p in prob.pairs] == ["body1/bottom", "body1/top"]
    assert isinstance(prob.pairs[0].master, BodySurface) and prob.pairs[1].rigid
    res = run_setup(setup, tmp_path / "res")
    s = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert s["status"] == "converged", s["message"]
    np.testing.assert_allclose(res.frames[-1].pressure, EXACT, rtol=1e-8)
    f = [np.array(p["force"]) for p in s["pair_contact_forces"]]
    np.testing.assert_allclose(f[0], [0.0, EXACT], atol=1e-8 * EXACT)
    assert np.linalg.norm(f[0] + f[1]) <= 1e-10 * EXACT
    assert [p["slave"] for p in s["pair_contact_forces"]] == ["body1/bottom", "body1/top"]
    assert s["contact_force_balance"] <= 1e-10
    first, plate = s["pair_contact_forces"]  # the base's side of the mortar pair; none for the rigid plate
    np.testing.assert_allclose(first["master_force"], -f[0], atol=1e-10 * EXACT)
    assert first["force_balance"] <= 1e-10 and "master_force" not in plate


def _three_blocks(extra: str = "") -> str:
    """The file with a third block on top, pressed by the plate, joined to the block by a [[pair]] with master."""
    text = FILE.read_text().replace('[[pair]]\nboundary = "body1/top"\n' + PLATE, "")
    text = text.replace("\n[contact]\n", '\n[[body]]\nmesh = { generator = "rectangle", bounds = [0.0, 1.0, 2.0, '
                                         '3.0], cells = [5, 5] }\nmaterial = { E = 800.0, nu = 0.25, plane = '
                                         '"strain" }\n\n[contact]\n')
    return text + ('\n[[pair]]\nboundary = "body2/bottom"\nmaster = "body1/top"\n' + extra +
                   '\n[[pair]]\nboundary = "body2/top"\n' + PLATE.replace("1.99", "2.99") +
                   '\n[[support]]\nboundary = "body2/left"\ncomponents = [0]\n')


def test_a_pair_between_two_bodies_from_a_problem_file(tmp_path):
    """Three blocks: two mortar pairs ([contact] and a [[pair]] with master) and the plate; the closed form with
    the three layers in series."""
    setup = load_problem_text(_three_blocks(), base_dir=FILE.parent)
    assert [type(p.master).__name__ for p in setup.problem.pairs] == ["BodySurface", "BodySurface", "HalfSpace"]
    res = run_setup(setup)
    assert res.summary["status"] == "converged", res.summary["message"]
    exact = 0.01 / ((1 - 0.3 ** 2) / 1000.0 + (1 - 0.2 ** 2) / 500.0 + (1 - 0.25 ** 2) / 800.0)
    np.testing.assert_allclose(res.frames[-1].pressure, exact, rtol=1e-8)


def test_a_pair_between_two_bodies_takes_its_own_friction():
    setup = load_problem_text(_three_blocks("friction = 0.3\n"), base_dir=FILE.parent)
    assert [p.friction for p in setup.problem.pairs] == [0.0, 0.3, 0.0] and setup.friction == 0.3


@pytest.mark.parametrize("edit, key, text", [
    (lambda t: t.replace('boundary = "body1/top"\ntype', 'boundary = "body1/topp"\ntype'), "pair[1].boundary",
     "no body has the boundary 'body1/topp'"),
    (lambda t: t.replace('type = "half-space"\npoint = [0.0, 1.99]\nnormal = [0.0, -1.0]\n', ""), "pair[1].type",
     "missing (required)"),
    (lambda t: t.replace('type = "half-space"', 'master = "body0/top"\ntype = "half-space"'), "pair[1]",
     "a pair has one master"),
    (lambda t: t.replace('type = "half-space"\npoint = [0.0, 1.99]\nnormal = [0.0, -1.0]\n',
                         'master = "body1/top"\n'), "pair[1].master", "the same boundary as the slave"),
    (lambda t: t.replace('type = "half-space"\npoint = [0.0, 1.99]\nnormal = [0.0, -1.0]\n',
                         'master = "body3/top"\n'), "pair[1].master", "there is no body 'body3'"),
    (lambda t: t.replace("normal = [0.0, -1.0]\n", "normal = [0.0, -1.0]\nfriction = -1.0\n"), "pair[1].friction",
     "out of range"),
])
def test_bad_pairs_with_bodies_are_named(edit, key, text):
    with pytest.raises(ConfigError) as info:
        load_problem_text(edit(FILE.read_text()), base_dir=FILE.parent)
    assert f"{key}" in str(info.value) and text in str(info.value), str(info.value)


def test_a_master_without_bodies_is_refused():
    """A [[pair]] with master in a one-body file (no [[body]] tables) names the key and the way out."""
    text = (Path(__file__).resolve().parents[1] / "data" / "squeezed_block.toml").read_text()
    text = text.replace('type = "half-space"\npoint = [0.0, 0.99]\nnormal = [0.0, -1.0]', 'master = "bottom"')
    with pytest.raises(ConfigError) as info:
        load_problem_text(text)
    assert "pair[1].master" in str(info.value) and "needs [[body]] tables" in str(info.value)
