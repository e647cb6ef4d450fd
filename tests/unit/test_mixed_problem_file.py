"""``[material] formulation`` in problem files: declared, checked, and what runs is what was configured."""

from __future__ import annotations

from pathlib import Path

import pytest

from alcontact.errors import ConfigError
from alcontact.fem import Hyperelastic, MixedHyperelastic
from alcontact.io.config import load_problem_text
from alcontact.io.schema import render_markdown

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "finite_half_cylinder.toml"


def _text(*, order=2, nu=0.3, formulation=None, kinematics="finite") -> str:
    text = EXAMPLE.read_text()
    text = text.replace('file = "half_cylinder.msh"', f'file = "half_cylinder.msh"\norder = {order}', 1)
    extra = f'\nformulation = "{formulation}"' if formulation else ""
    text = text.replace("nu = 0.3\n", f"nu = {nu}{extra}\n", 1)
    if kinematics != "finite":
        text = text.replace('kinematics = "finite"', f'kinematics = "{kinematics}"')
        text = text.replace('model = "neo-hookean"\n', 'model = "linear"\n')
    return text


def _model(text):
    return load_problem_text(text, base_dir=EXAMPLE.parent).problem.model


def test_explicit_formulations_take_effect():
    assert isinstance(_model(_text(formulation="mixed")), MixedHyperelastic)
    assert type(_model(_text(nu=0.4999, formulation="displacement"))) is Hyperelastic


def test_default_is_mixed_for_nearly_incompressible_p2():
    body = _model(_text(nu=0.4999))
    assert isinstance(body, MixedHyperelastic) and body.nu == 0.4999
    assert type(_model(_text(nu=0.45))) is Hyperelastic  # below 0.49: the displacement element
    assert type(_model(_text(order=1, nu=0.4999))) is Hyperelastic  # P1: Taylor-Hood needs P2


@pytest.mark.parametrize("kwargs, key, words", [
    (dict(order=1, formulation="mixed"), "mesh.order", ["order = 2"]),
    (dict(formulation="mixed", kinematics="small"), "material.formulation", ["'finite'", "'displacement'"]),
    (dict(formulation="mixd"), "formulation", ["mixed"]),
])
def test_bad_formulation_is_named(kwargs, key, words):
    with pytest.raises(ConfigError) as info:
        load_problem_text(_text(**kwargs), base_dir=EXAMPLE.parent)
    msg = str(info.value)
    assert key in msg and all(w in msg for w in words), msg


def test_documented():
    doc = render_markdown()
    assert "| `formulation`" in doc
    assert (EXAMPLE.parents[1] / "docs" / "problem-file.md").read_text() == doc  # regenerated


def test_run_nearly_incompressible_half_cylinder(tmp_path):
    """The example at nu = 0.4999, P2, default formulation: the mixed body runs, converges without
    cut-back in at most 8 Newton iterations per step (measured 4 4 4 4), and writes its stresses."""
    import json
    import shutil

    from _helpers import runner
    from alcontact.cli import app

    shutil.copy(EXAMPLE.parent / "half_cylinder.msh", tmp_path)
    p = tmp_path / "hc.toml"
    p.write_text(_text(nu=0.4999))
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", str(p), "--out", str(out)])
    assert result.exit_code == 0, result.output
    s = json.loads((out / "summary.json").read_text())
    assert s["formulation"] == "mixed" and s["status_code"] > 0
    assert max(s["step_newton_iterations"]) <= 8 and s["converged_steps"] == 4
    assert (out / "solution.vtu").is_file()


def test_mixed_body_of_revolution_is_refused_by_name():
    """The mixed body is Cartesian only: an axisymmetric mesh with ``formulation = 'mixed'`` is named, not run."""
    text = _text(formulation="mixed").replace('file = "half_cylinder.msh"', 'file = "half_cylinder.msh"\ngeometry = "axisymmetric"', 1)
    with pytest.raises(ConfigError) as info:
        load_problem_text(text, base_dir=EXAMPLE.parent)
    msg = str(info.value)
    assert "material.formulation" in msg and "axisymmetric" in msg and "'displacement'" in msg, msg
