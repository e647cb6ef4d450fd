"""Pictures of the deformed body (alcontact.viz.pictures, issue 20 item 8).

Each picture must exist, not be blank (pixel variance, many colours) and show what it
says: the pressure view carries the colours of its pressure colour map where the body
touches, the von Mises view those of its map; report.md embeds both; a problem-file run
writes them too. Rendering is headless (Agg canvas, no display).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from alcontact.contact import solve
from alcontact.problems import hertz
from alcontact.viz.pictures import PICTURE_FILES, body_figure, displacement_scale, save_body_pictures


def _image(path):
    from matplotlib.image import imread

    img = imread(path)[..., :3]  # RGB in [0, 1]
    return img


def _not_blank(img):
    colours = np.unique((img * 255).astype(np.uint8).reshape(-1, 3), axis=0)
    return float(img.var()), colours.shape[0]


def _has_colour(img, rgb, tol=0.02):
    return bool(np.any(np.all(np.abs(img - np.asarray(rgb)[None, None, :]) < tol, axis=2)))


@pytest.fixture(scope="module", params=["2d", "3d"])
def solution(request):
    prob = hertz.hertz_2d(level=0) if request.param == "2d" else hertz.hertz_3d(level=0)
    sol = solve(prob)
    assert sol.result.success
    return sol


def test_pictures_exist_and_are_not_blank(solution, tmp_path):
    names = save_body_pictures(solution, tmp_path, title="t")
    assert names == list(PICTURE_FILES)
    for name in names:
        var, ncol = _not_blank(_image(tmp_path / name))
        assert var > 1e-3 and ncol > 50, (name, var, ncol)


def test_pressure_view_is_coloured_by_the_pressure(solution, tmp_path):
    import matplotlib

    save_body_pictures(solution, tmp_path)
    pressure, mises = _image(tmp_path / PICTURE_FILES[0]), _image(tmp_path / PICTURE_FILES[1])
    dark_inferno = matplotlib.colormaps["inferno_r"](0.95)[:3]  # near the peak pressure
    yellow_viridis = matplotlib.colormaps["viridis"](1.0)[:3]  # the largest von Mises stress
    assert _has_colour(pressure, dark_inferno, tol=0.08)
    assert _has_colour(mises, yellow_viridis, tol=0.08)
    assert not _has_colour(pressure, yellow_viridis, tol=0.02)  # the maps are not mixed up


def test_small_deformation_is_magnified_and_says_so(solution):
    fig = body_figure(solution, "von_mises")
    title = fig.get_suptitle()
    model = solution.problem.model
    X = model.mesh.p.T
    s = displacement_scale(X, solution.u[model.dof_map[model.scalar_basis.nodal_dofs[0]]], finite=False)
    assert s > 1 and f"displacement x {s:g}" in title


def test_displacement_scale():
    X = np.array([[0.0, 0.0], [10.0, 0.0]])
    u = np.array([[0.0, 0.0], [0.0, -0.01]])
    assert displacement_scale(X, u, finite=False) == 50.0  # 0.05 * 10 / 0.01 = 50
    assert displacement_scale(X, 30 * u, finite=False) == 1.0  # already visible: never shrunk
    assert displacement_scale(X, u, finite=True) == 1.0
    assert displacement_scale(X, 0 * u, finite=False) == 1.0


def test_unknown_field_is_a_clear_error(solution):
    from alcontact.errors import InputError

    with pytest.raises(InputError, match="von_mises"):
        body_figure(solution, "pressure")


def test_problem_file_run_shows_the_pictures_in_the_report(tmp_path):
    from pathlib import Path

    from alcontact.io import load_problem
    from alcontact.runner import run_setup

    setup = load_problem(Path(__file__).resolve().parents[2] / "examples" / "signorini_liftoff.toml")
    res = run_setup(setup, tmp_path / "out")
    files = json.loads((tmp_path / "out" / "summary.json").read_text())["files"]
    report = (tmp_path / "out" / "report.md").read_text()
    for name in PICTURE_FILES:
        assert name in files and name in res.files
        assert f"]({name})" in report
        var, ncol = _not_blank(_image(tmp_path / "out" / name))
        assert var > 1e-3 and ncol > 50


def test_3d_pressure_view_looks_at_the_touching_faces_of_a_curved_body(tmp_path):
    """Hemisphere pressed onto the plane y = 0 (finite deformation): the camera looks from below (-y), not along
    the mean normal of the whole curved contact boundary (a diagonal view, as before the fix)."""
    from alcontact.contact import solve_finite
    from alcontact.problems.hemisphere import hemisphere

    fs = solve_finite(hemisphere(n=3), steps=2)
    assert fs.success
    fig = body_figure(fs.solution, "contact_pressure")
    ax = fig.axes[0]
    assert abs(ax.elev) < 20 and abs(ax.azim + 90) < 20, (ax.elev, ax.azim)
    assert "displacement x" not in fig.get_suptitle()  # finite deformation: drawn as it is
    names = save_body_pictures(fs.solution, tmp_path)
    for name in names:
        var, ncol = _not_blank(_image(tmp_path / name))
        assert var > 1e-3 and ncol > 50
