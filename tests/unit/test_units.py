"""Issue 20, item 4: ``[units]`` in problem files label every axis, table and summary; bad units are refused.

The numbers of a file are not converted, so the units must be consistent: force = stress x length^2
(N with mm and MPa, kN with GPa and mm). Without ``[units]`` the labels stay ``L`` / ``[E]``.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import alcontact.viz
import alcontact.viz.plots
from _helpers import assert_check_rejects, runner
from alcontact.cli import app
from alcontact.io import load_problem
from alcontact.io.config import load_problem_text
from alcontact.errors import ConfigError
from alcontact.runner import run_setup
from alcontact.viz import Units

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
IRONING = (EXAMPLES / "finite_ironing.toml").read_text(encoding="utf-8")


def _file(tmp_path: Path, units: str, text: str = IRONING) -> Path:
    p = tmp_path / "p.toml"
    p.write_text(text + "\n[units]\n" + units + "\n", encoding="utf-8")
    return p


def _labels(fig) -> list[str]:
    return [t for ax in fig.axes for t in (ax.get_xlabel(), ax.get_ylabel()) if t]


@pytest.fixture
def captured(monkeypatch):
    """The figures a run saves (every PNG goes through save_figure)."""
    figs = []
    original = alcontact.viz.plots.save_figure

    def keep(fig, path, **kw):
        figs.append((Path(path).name, fig))
        return original(fig, path, **kw)

    monkeypatch.setattr(alcontact.viz.plots, "save_figure", keep)
    monkeypatch.setattr(alcontact.viz, "save_figure", keep)
    return figs


def test_units_label_every_plot_table_and_summary(tmp_path, captured):
    setup = load_problem(_file(tmp_path, 'length = "mm"\nstress = "MPa"\nforce = "N"'))
    assert setup.units == ("mm", "MPa", "N")
    run_setup(setup, tmp_path / "out")
    s = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    assert s["units"] == {"length": "mm", "stress": "MPa", "force": "N/mm"}  # 2D: per mm of thickness
    report = (tmp_path / "out" / "report.md").read_text(encoding="utf-8")
    assert "(mm) |" in report and "p0 (MPa)" in report and "P (N/mm)" in report
    assert "[E]" not in report and "(L)" not in report
    names = {name for name, _ in captured}
    assert {"pressure.png", "load_displacement.png", "reaction_force.png"} <= names
    for name, fig in captured:
        labels = _labels(fig)
        assert not any("(L)" in t or "[E]" in t for t in labels), (name, labels)
        assert not fig.get_supxlabel(), name  # no "L = length unit" note when the units are named
        if name != "convergence.png":  # the convergence plot is dimensionless
            assert any(t.endswith(("(mm)", "(MPa)", "(N/mm)")) for t in labels), (name, labels)


def test_without_units_the_labels_stay_generic(tmp_path, captured):
    p = tmp_path / "p.toml"
    p.write_text(IRONING, encoding="utf-8")
    run_setup(load_problem(p), tmp_path / "out")
    s = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    assert s["units"] == {"length": None, "stress": None, "force": None}
    pressure = dict(captured)["pressure.png"]
    assert pressure.axes[0].get_xlabel().endswith("(L)") and pressure.axes[0].get_ylabel().endswith("([E])")


@pytest.mark.parametrize("units, expected", [
    ('length = "mm"\nstress = "GPa"\nforce = "N"', ["units.force", "inconsistent", "set force = 'kN'"]),
    ('length = "mmm"\nstress = "MPa"', ["units.length", "Did you mean 'mm'?"]),
    ('stress = "MPa"\nforce = "N"', ["units.force", "give [units] length and stress too"]),
    ('length = "mm"\nstress = "MPa"\ntemperature = "K"', ["units.temperature"]),
])
def test_bad_units_are_refused_by_check_and_load(tmp_path, units, expected):
    p = _file(tmp_path, units)
    assert_check_rejects(runner.invoke(app, ["check", str(p)]), expected)
    with pytest.raises(ConfigError):
        load_problem(p)


def test_force_unit_is_derived_from_stress_and_length():
    assert Units("mm", "GPa").force(3) == "kN" and Units("m", "Pa").force(2) == "N/m"
    assert Units("cm", "MPa").force(3) == "MPa·cm²"  # 100 N: no named unit
    assert load_problem_text(IRONING + '\n[units]\nlength = "m"\nstress = "kPa"\n').plot_units().force(3) == "kN"
