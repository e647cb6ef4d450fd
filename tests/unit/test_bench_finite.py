"""``benchmarks/finite.py`` as the ``finite`` suite of ``alcontact bench``: presets, errors, a tiny run."""

from __future__ import annotations

import csv
import runpy
from pathlib import Path

import pytest

from alcontact.errors import UnknownNameError
from alcontact.problems.half_cylinder import half_cylinder
from alcontact.runner import BENCH_SUITES

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "finite.py"


@pytest.fixture(scope="module")
def finite():
    return runpy.run_path(str(SCRIPT), run_name="alcontact_bench_finite")


def test_suite_registered_with_existing_quick_presets(finite):
    suite = BENCH_SUITES["finite"]
    assert suite.script == "finite.py" and suite.takes_cases
    assert set(suite.quick["cases"]) <= set(finite["CASES"])
    assert set(suite.quick["variants"]) <= set(finite["VARIANTS"])
    assert set(finite["DEFAULT_CASES"]) == {"2d-100k", "3d-100k"}


def test_100k_presets_have_about_100k_dofs(finite):
    """Issue 10 asks for about 100k DOFs: the 2D mesh is built (101 250 DOFs); the 3D P1
    hemisphere has ``3 (n + 1)^3`` DOFs (its docstring): 98 304 at n = 31. Both within 5 %."""
    problem, n, order, steps = finite["CASES"]["2d-100k"]
    assert (problem, order, steps) == ("half-cylinder", 2, 20)
    assert abs(half_cylinder(n, order=order).model.ndofs - 100_000) <= 5_000
    problem, n, order, steps = finite["CASES"]["3d-100k"]
    assert (problem, order, steps) == ("hemisphere", 1, 10)
    assert abs(3 * (n + 1) ** 3 - 100_000) <= 5_000


def test_unknown_case_or_variant_names_the_known_ones(finite, tmp_path):
    with pytest.raises(UnknownNameError, match="Did you mean '3d-100k'"):
        finite["run"](tmp_path, ["3d-100"], ["ssn"], log=lambda _: None)
    with pytest.raises(UnknownNameError, match="Did you mean 'simo-laursen'"):
        finite["run"](tmp_path, ["2d-5k"], ["simo-laurson"], log=lambda _: None)


def test_run_writes_case_csv_and_joined_report(finite, tmp_path):
    """A tiny preset (half-cylinder n = 4, P2, 2 load steps) through ``run``: one CSV row per
    step and variant, the joined ``finite.md`` quotes the ``alcontact bench`` command."""
    finite["CASES"]["tiny"] = ("half-cylinder", 4, 2, 2)
    try:
        messages = []
        finite["run"](tmp_path, ["tiny"], ["ssn", "quad-met1"], log=messages.append, repeat=1)
    finally:
        del finite["CASES"]["tiny"]
    with open(tmp_path / "finite_tiny.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["variant"], r["step"]) for r in rows] == [("ssn", "1"), ("ssn", "2"), ("quad-met1", "1"),
                                                        ("quad-met1", "2")]
    assert all(int(r["newton_iterations"]) >= 1 and float(r["ratio"]) > 0 for r in rows)
    report = (tmp_path / "finite.md").read_text()
    assert "alcontact bench --suite finite --case tiny --variant ssn --variant quad-met1" in report
    assert "| ssn | converged | 2 |" in report and "| quad-met1 | converged | 2 |" in report
    assert any(m.startswith("ssn: converged") for m in messages)
