"""Issue 20, item 2: force curves against what the user prescribed, one panel per phase of the path.

``reaction_force.csv`` carries the prescribed quantities (support displacements, the obstacle's position
and travel along its path, load factors), computed from the problem file's data (reference: ``value x
ramp(t)`` and ``t * path``); ``reaction_force.png`` plots the forces against them, with a panel per
phase when the path turns (press, then slide).
"""

from __future__ import annotations

import csv
import shutil
from pathlib import Path

import numpy as np
import pytest

import alcontact.viz
import alcontact.viz.plots
from alcontact.io import load_problem
from alcontact.runner import run_setup
from alcontact.viz import load_path_phases

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture
def captured(monkeypatch):
    figs = {}
    original = alcontact.viz.plots.save_figure

    def keep(fig, path, **kw):
        figs[Path(path).name] = fig
        return original(fig, path, **kw)

    monkeypatch.setattr(alcontact.viz.plots, "save_figure", keep)
    monkeypatch.setattr(alcontact.viz, "save_figure", keep)
    return figs


def _csv(path: Path) -> list[dict[str, float]]:
    with open(path, newline="", encoding="utf-8") as fh:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(fh)]


def test_press_then_slide_has_two_phases_against_what_was_prescribed(tmp_path, captured):
    run_setup(load_problem(EXAMPLES / "finite_ironing_friction.toml"), tmp_path / "o")
    rows = _csv(tmp_path / "o" / "reaction_force.csv")
    t = np.array([r["t"] for r in rows])
    # the file: bottom pushed up by 0.15 until t = 0.25 (ramp), obstacle at t * [2.0, 0.0]
    np.testing.assert_allclose([r["prescribed_u_bottom_y"] for r in rows], 0.15 * np.minimum(t / 0.25, 1.0),
                               rtol=1e-12)
    np.testing.assert_allclose([r["obstacle_x"] for r in rows], 2.0 * t, rtol=1e-12)
    np.testing.assert_allclose([r["obstacle_y"] for r in rows], 0.0, atol=0)
    np.testing.assert_allclose([r["obstacle_travel"] for r in rows], 2.0 * t, rtol=1e-12)
    fig = captured["reaction_force.png"]
    assert len(fig.axes) == 2
    press, slide = fig.axes
    assert press.get_xlabel() == "prescribed u_y of bottom (L)"
    assert slide.get_xlabel() == "obstacle travel along its path (L)"
    x_press = press.get_lines()[0].get_xdata()
    np.testing.assert_allclose(x_press, [0.0, 0.0375, 0.075, 0.1125, 0.15], rtol=1e-12)
    x_slide = slide.get_lines()[0].get_xdata()
    np.testing.assert_allclose(x_slide, 2.0 * t[3:], rtol=1e-12)  # from the end of the press on
    # the plotted contact force is the CSV's
    fy = slide.get_lines()[2].get_ydata()
    assert slide.get_lines()[2].get_label() == "contact force F_y on the body"
    np.testing.assert_allclose(fy, [r["force_y"] for r in rows[3:]], rtol=1e-15)


def test_a_single_press_is_one_panel(tmp_path, captured):
    shutil.copy(EXAMPLES / "half_cylinder.msh", tmp_path / "half_cylinder.msh")
    shutil.copy(EXAMPLES / "finite_half_cylinder.toml", tmp_path / "p.toml")
    run_setup(load_problem(tmp_path / "p.toml"), tmp_path / "o")
    rows = _csv(tmp_path / "o" / "reaction_force.csv")
    np.testing.assert_allclose([r["prescribed_u_top_y"] for r in rows], [-0.2 * r["t"] for r in rows], rtol=1e-12)
    fig = captured["reaction_force.png"]
    assert len(fig.axes) == 1
    assert fig.axes[0].get_xlabel() == "prescribed u_y of top (L)"


def _rows(values, col="q"):
    return [{"t": float(k + 1), col: v} for k, v in enumerate(values)]


def test_phases_split_where_the_motion_turns():
    q = [("a", "a", True), ("b", "b", False)]
    rows = [{"t": 1, "a": 1, "b": 0}, {"t": 2, "a": 2, "b": 0}, {"t": 3, "a": 2, "b": 1}, {"t": 4, "a": 2, "b": 2}]
    assert load_path_phases(rows, q) == [(0, 1, "a"), (2, 3, "b")]
    # load, hold, unload: the hold stays in the loading phase, the unloading is a phase of its own
    up_down = _rows([1.0, 2.0, 2.0, 1.0, 0.0])
    assert load_path_phases(up_down, [("q", "q", True)]) == [(0, 2, "q"), (3, 4, "q")]
    # both move: the pressing one is the abscissa even when the other moves more
    both = [{"t": 1, "a": 0.1, "b": 1.0}, {"t": 2, "a": 0.2, "b": 2.0}]
    assert load_path_phases(both, q) == [(0, 1, "a")]
    assert load_path_phases(_rows([1.0, 2.0, 3.0]), [("q", "q", True)]) == [(0, 2, "q")]


def test_small_deformation_press_then_slide(tmp_path, captured):
    """examples/sliding_block.toml (small deformation, friction): the top pressed down by 0.005 until t = 0.5,
    then moved by 0.009 along x: two panels, the slide ending at the Coulomb limit |F_x| = mu F_y."""
    run_setup(load_problem(EXAMPLES / "sliding_block.toml"), tmp_path / "o")
    rows = _csv_steps(tmp_path / "o" / "steps.csv")
    t = np.array([r["t"] for r in rows])
    np.testing.assert_allclose([r["prescribed_u_top_y"] for r in rows], -0.005 * np.minimum(t / 0.5, 1.0), rtol=1e-12)
    np.testing.assert_allclose([r["prescribed_u_top_x"] for r in rows], 0.009 * np.clip(2 * t - 1, 0, 1), rtol=1e-12,
                               atol=1e-15)
    fig = captured["load_displacement.png"]
    press, slide = fig.axes
    assert press.get_xlabel() == "prescribed u_y of top (L)" and slide.get_xlabel() == "prescribed u_x of top (L)"
    fx = slide.get_lines()[0].get_ydata()
    fy = slide.get_lines()[1].get_ydata()
    assert abs(fx[-1]) == pytest.approx(0.3 * fy[-1], rel=1e-6)


def _csv_steps(path: Path) -> list[dict[str, float]]:
    with open(path, newline="", encoding="utf-8") as fh:
        return [{k: float(v) for k, v in r.items() if k.startswith(("prescribed_", "t"))} for r in csv.DictReader(fh)]


def test_a_cyclic_path_is_drawn_over_the_pseudo_time():
    from alcontact.viz import force_path_figure

    q = [(0.1 * (-1) ** (k // 2)) for k in range(12)]  # up, down, up, ...: six phases
    rows = [{"t": k + 1.0, "prescribed_u_top_y": v, "force_y": 10 * v} for k, v in enumerate(np.cumsum(q))]
    assert len(load_path_phases(rows, [("prescribed_u_top_y", "u", True)])) == 6
    fig = force_path_figure(rows, [("prescribed_u_top_y", "prescribed u_y of top", True)])
    assert len(fig.axes) == 1 and fig.axes[0].get_xlabel().startswith("pseudo-time")
    assert [ln.get_label() for ln in fig.axes[0].get_lines() if not ln.get_label().startswith("_")] == \
        ["contact force F_y on the body"]
