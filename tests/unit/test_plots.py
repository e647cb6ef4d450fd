"""Figures: every axis names a quantity with its unit, every drawn line is in the legend."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from alcontact.viz import Units, convergence_figure, load_displacement_figure, pressure_figure, steps_figure

MM_MPA = Units("mm", "MPa")


@pytest.fixture(scope="module")
def hertz2d():
    from alcontact.contact import solve
    from alcontact.problems import hertz

    return solve(hertz.hertz_2d(level=0))


def _hertz3d_like():
    """A 3D contact solution with Hertz's pressure on a grid of the plane z = 0 (no solve needed)."""
    from alcontact.problems.hertz import HertzReference

    ref = HertzReference("sphere", radius=10.0, e_star=200e3 / (1 - 0.3**2), symmetry=4.0)
    x, y = np.meshgrid(np.linspace(0, 2, 21), np.linspace(0, 2, 21))
    pts = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    P = 4000.0
    p = ref.pressure(np.hypot(pts[:, 0], pts[:, 1]), P)
    a = ref.half_width(P)
    problem = SimpleNamespace(reference=ref, meta={"center": (0.0, 0.0, 0.0)}, name="hertz-3d like")
    return SimpleNamespace(problem=problem, points=pts, pressure=p, normal_force=P / 4, extra={},
                           contact_half_width=lambda axis=0, center=None: a)


def _labels(ax) -> list[str]:
    leg = ax.get_legend()
    return [t.get_text() for t in leg.get_texts()] if leg is not None else []


def _assert_every_line_in_legend(ax, unlabeled_ok=0):
    """Each line drawn on ``ax`` has a legend entry, except ``unlabeled_ok`` documented duplicates/axes."""
    labels = _labels(ax)
    drawn = [ln.get_label() for ln in ax.get_lines()]
    missing = [lbl for lbl in drawn if lbl.startswith("_")]
    assert len(missing) == unlabeled_ok, drawn
    assert [lbl for lbl in drawn if not lbl.startswith("_")] == labels


def test_pressure_figure_2d_units_and_reference_lines_in_legend(hertz2d):
    fig = pressure_figure(hertz2d, units=MM_MPA)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "x (along the contact boundary) (mm)"
    assert ax.get_ylabel() == "contact pressure p (MPa)"
    _assert_every_line_in_legend(ax)
    labels = _labels(ax)
    dashed = {ln.get_label() for ln in ax.get_lines() if ln.get_linestyle() in ("--", ":")}
    assert len(dashed) == 2 and dashed <= set(labels)  # both half-width lines are explained
    assert any(lbl.startswith("analytical $a$") and lbl.endswith(" mm") for lbl in labels)
    assert any("MPa" in lbl for lbl in labels)


def test_pressure_figure_3d_says_r(hertz2d):
    sol = _hertz3d_like()
    fig = pressure_figure(sol, units=MM_MPA)
    ax = fig.axes[0]
    assert ax.get_xlabel().startswith("r (") and ax.get_xlabel().endswith("(mm)")
    labels = _labels(ax)
    assert any("r^2/a^2" in lbl for lbl in labels) and not any("x^2" in lbl for lbl in labels)
    _assert_every_line_in_legend(ax)


def test_generic_units_are_explained_in_the_figure(hertz2d):
    fig = pressure_figure(hertz2d)  # a problem file: units not named
    ax = fig.axes[0]
    assert ax.get_xlabel().endswith("(L)") and ax.get_ylabel().endswith("([E])")
    assert "L = length unit of the mesh" in fig.get_supxlabel()
    assert "[E] = stress unit" in fig.get_supxlabel()


def test_convergence_figure_has_the_tolerance_in_its_legend(hertz2d):
    tol = {"penetration": 1e-8, "complementarity": 1e-8, "multiplier_change": 1e-8}
    ax = convergence_figure(hertz2d.result, tolerances=tol).axes[0]
    _assert_every_line_in_legend(ax)
    assert "tolerance 1e-08" in _labels(ax)
    assert "(dimensionless)" in ax.get_ylabel() and "(count)" in ax.get_xlabel()
    ax = convergence_figure(hertz2d.result, tolerances={**tol, "penetration": 1e-6}).axes[0]
    _assert_every_line_in_legend(ax)
    assert sum(lbl.startswith("tolerance of") for lbl in _labels(ax)) == 3


def test_load_displacement_and_steps_figures_have_units():
    rows = [{"t": t, "normal_force": 10 * t, "tangential_force": 0.0, "u_top_y": -0.01 * t, "outer_iterations": 3,
             "newton_iterations": 5, "penetration": 1e-9} for t in (0.5, 1.0)]
    ax = load_displacement_figure(rows, [("top_y", "normal")], units=MM_MPA, dim=2).axes[0]
    assert ax.get_xlabel().endswith("(mm)") and ax.get_ylabel().endswith("(N/mm)")
    _assert_every_line_in_legend(ax)
    ax = load_displacement_figure(rows, [("top_y", "normal")], units=MM_MPA, dim=3).axes[0]
    assert ax.get_ylabel().endswith("(N)")
    fig = steps_figure(rows)
    for ax in fig.axes:
        assert ax.get_ylabel().endswith(")")
        _assert_every_line_in_legend(ax)
    assert "dimensionless" in fig.axes[1].get_xlabel()


def test_units_force():
    assert Units("mm", "MPa").force(2) == "N/mm" and Units("m", "Pa").force(3) == "N"
    assert Units("in", "psi").force(3) == "lbf" and Units("cm", "psi").force(3) == "psi·cm²"
    assert Units().force(2) == "[E]·L" and Units().note and not MM_MPA.note
