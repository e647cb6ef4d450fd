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


BALL = EXAMPLE.parent / "rubber_ball_axisym.toml"


def _ball_text(nu, formulation=None):
    extra = f'\nformulation = "{formulation}"' if formulation else ""
    return BALL.read_text().replace("nu = 0.3\n", f"nu = {nu}{extra}\n", 1)


def test_mixed_body_of_revolution_takes_effect():
    """An axisymmetric (curved second-order) mesh with ``formulation = 'mixed'`` builds the mixed body of
    revolution on the curved map (both were refused before the mixed body had the hoop terms and the
    isoparametric map); nearly incompressible, the default is the mixed one too."""
    from skfem import MeshTri2

    for nu, form in ((0.3, "mixed"), (0.4999, None), (0.5, None)):
        body = load_problem_text(_ball_text(nu, form), base_dir=BALL.parent).problem.model
        assert isinstance(body, MixedHyperelastic) and body.axisymmetric and body.nu == nu
        assert type(body.mesh) is MeshTri2
    body = load_problem_text(_ball_text(0.45), base_dir=BALL.parent).problem.model
    assert type(body) is Hyperelastic and body.axisymmetric


def test_exactly_incompressible_from_a_problem_file():
    """``nu = 0.5`` reaches the mixed body unchanged (infinite bulk modulus, Lagrange-multiplier pressure)."""
    for form in (None, "mixed"):
        body = _model(_text(nu=0.5, formulation=form))
        assert isinstance(body, MixedHyperelastic) and body.nu == 0.5 and body.kappa == float("inf")


@pytest.mark.parametrize("kwargs, words", [
    (dict(nu=0.5, formulation="displacement"), ["material.nu", "0.5", "'mixed'", "0.4999"]),
    (dict(nu=0.5, order=1), ["material.nu", "0.5", "mesh.order = 2", "0.4999"]),
    (dict(nu=0.5, kinematics="small"), ["material.nu", "'finite'", "mesh.volumetric = 'p0'"]),
])
def test_exactly_incompressible_refused_where_it_cannot_work(kwargs, words):
    with pytest.raises(ConfigError) as info:
        load_problem_text(_text(**kwargs), base_dir=EXAMPLE.parent)
    msg = str(info.value)
    assert all(w in msg for w in words), msg
    assert "Traceback" not in msg


def test_run_exactly_incompressible_half_cylinder(tmp_path):
    """The example at nu = 0.5 (default formulation: mixed) runs and converges without cut-back in at most
    8 Newton iterations per step; the summary records the mixed formulation."""
    import json
    import shutil

    from _helpers import runner
    from alcontact.cli import app

    shutil.copy(EXAMPLE.parent / "half_cylinder.msh", tmp_path)
    p = tmp_path / "hc.toml"
    p.write_text(_text(nu=0.5))
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", str(p), "--out", str(out)])
    assert result.exit_code == 0, result.output
    s = json.loads((out / "summary.json").read_text())
    assert s["formulation"] == "mixed" and s["status_code"] > 0
    assert max(s["step_newton_iterations"]) <= 8 and s["converged_steps"] == 4


def test_run_nearly_incompressible_ball_axisymmetric(tmp_path):
    """The axisymmetric rubber-ball example (curved P2 mesh) at nu = 0.4999: the mixed body of revolution in
    contact converges in all ten steps without cut-back, at most 8 Newton iterations per step (measured
    4 4 4 3 7 4 4 4 3 3), forces reported in total and per radian."""
    import json
    import shutil

    from _helpers import runner
    from alcontact.cli import app

    shutil.copy(BALL.parent / "rubber_ball_axisym.msh", tmp_path)
    p = tmp_path / "ball.toml"
    p.write_text(_ball_text(0.4999))
    out = tmp_path / "results"
    result = runner.invoke(app, ["run", str(p), "--out", str(out)])
    assert result.exit_code == 0, result.output
    s = json.loads((out / "summary.json").read_text())
    assert s["formulation"] == "mixed" and s["status_code"] > 0 and s["converged_steps"] == 10
    assert max(s["step_newton_iterations"]) <= 8 and sum(s["step_cutbacks"]) == 0
    total, per_radian = s["total_contact_force"], s["total_contact_force_per_radian"]
    assert abs(total - 2 * 3.141592653589793 * per_radian) <= 1e-9 * abs(total)
