"""Issue 20, item 3: the numbers of ``report.md`` equal those of ``summary.json``, which equal the solver's.

Finite-deformation and moving-obstacle runs (examples/finite_ironing*.toml) used to show the total
of all linear solves as "one linear solve", the distance of the contact zone from the origin as its
"half-width", |Q| against mu N without a word, and told users to warp VTUs that are already in the
deformed configuration. References: the solver's own timings and counters (``RunOutput.raw``), the
contact points and pressures of the final frame (half-width: half the extent of the loaded points,
computed here from them), Coulomb's law (sum |q_i| <= mu N, equality when every loaded point slips).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from alcontact.io import load_problem
from alcontact.runner import run_setup

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _table(report: str) -> dict[str, str]:
    """``{quantity: computed}`` of the report's table."""
    rows = {}
    for line in report.splitlines():
        if line.startswith("| ") and not line.startswith("| quantity") and not line.startswith("|---"):
            cells = [c.strip() for c in line.strip("|").split(" | ")]
            rows[cells[0]] = cells[1]
    return rows


def _run(tmp_path, name):
    out = tmp_path / name
    res = run_setup(load_problem(EXAMPLES / f"{name}.toml"), out)
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    return res, summary, _table((out / "report.md").read_text(encoding="utf-8")), out


@pytest.fixture(scope="module")
def ironing(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("iron"), "finite_ironing")


@pytest.fixture(scope="module")
def ironing_friction(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("ironf"), "finite_ironing_friction")


def test_one_linear_solve_is_one_solve(ironing):
    res, s, table, _ = ironing
    sol = res.raw.solution  # the solver's result: all its Newton linear solves timed together
    total, count = sol.timings["linear_solve_s"], sol.result.linear_solves
    assert count > 10
    assert s["linear_solve_time_total_s"] == total
    assert s["linear_solve_count"] == count
    assert s["linear_solve_time_s"] == pytest.approx(total / count, rel=1e-15)
    assert s["linear_solve_time_s"] < s["wall_time_s"] / 10  # one solve, not the run
    assert s["time_ratio_contact_to_linear"] == pytest.approx(s["wall_time_s"] / s["linear_solve_time_s"])
    assert table[f"one Newton linear solve, mean of {count} (s)"] == format(s["linear_solve_time_s"], ".3g")
    assert table["all linear solves together (s)"] == format(total, ".3f")
    assert table["wall time / one Newton linear solve"] == format(s["time_ratio_contact_to_linear"], ".2f")
    assert not any(k.startswith("one linear elastic solve") for k in table)


def test_half_width_of_a_moving_obstacle_is_a_width(ironing):
    res, s, table, _ = ironing
    final = res.frames[-1]
    loaded = final.pressure > 0
    assert loaded.sum() >= 2
    x = final.points[loaded, 0]  # the strip's top face y = 1: the contact boundary is a line along x
    expected = 0.5 * (x.max() - x.min())
    assert s["contact_half_width"] == pytest.approx(expected, rel=1e-12)
    assert s["contact_half_width"] < 0.5  # the cylinder's radius; the old value, 3.09, was its distance from x = 0
    assert s["contact_half_width_measure"] == "half the extent of the loaded zone"
    assert table["contact half-width a: half the extent of the loaded zone (L)"] == format(expected, ".5g")
    assert table["peak pressure p0 ([E])"] == format(s["peak_pressure"], ".5g")
    assert s["peak_pressure"] == pytest.approx(float(final.pressure.max()), rel=1e-15)


def test_friction_resultant_and_coulomb_bound(ironing_friction):
    res, s, table, out = ironing_friction
    final = res.frames[-1]
    q = np.linalg.norm(final.extra["shear"], axis=1)
    mu_n = 0.3 * final.normal_force
    assert s["coulomb_limit"] == pytest.approx(mu_n, rel=1e-15)
    assert s["tangential_force_magnitude_sum"] == pytest.approx(float(np.sum(final.weights * q)), rel=1e-12)
    assert s["tangential_force"] == pytest.approx(float(np.linalg.norm(final.extra["tangential_force"])), rel=1e-15)
    assert s["tangential_force"] <= s["tangential_force_magnitude_sum"] <= mu_n * (1 + 1e-9)
    if s["stick_points"] == 0:  # every loaded point slips: sum |q_i| = mu N (Coulomb's law, equality)
        assert s["tangential_force_magnitude_sum"] == pytest.approx(mu_n, rel=1e-6)
    assert table["tangential force of the model, resultant \\|Q\\| = \\|sum q_i\\| ([E]·L)"] == \
        format(s["tangential_force"], ".5g")
    assert table["sum of the nodal tangential force magnitudes, sum \\|q_i\\| ([E]·L)"] == \
        format(s["tangential_force_magnitude_sum"], ".5g")
    report = (out / "report.md").read_text(encoding="utf-8")
    assert "no sign of sticking" in report


def test_deformed_vtus_are_not_to_be_warped(ironing, tmp_path):
    *_, out = ironing
    report = (out / "report.md").read_text(encoding="utf-8")
    assert "Warp By Vector" not in report.replace("no Warp By Vector needed", "")
    assert "already moved" in report
    small = tmp_path / "small"
    run_setup(load_problem(EXAMPLES / "signorini_liftoff.toml"), small)
    assert "Warp By Vector" in (small / "report.md").read_text(encoding="utf-8")


def test_printed_table_says_the_same(tmp_path):
    from _helpers import flat, runner
    from alcontact.cli import app

    res = runner.invoke(app, ["run", str(EXAMPLES / "finite_ironing.toml"), "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "o" / "summary.json").read_text(encoding="utf-8"))
    text = flat(res.stdout)
    assert f"one Newton linear solve, mean of {s['linear_solve_count']} (s) │ {s['linear_solve_time_s']:.3g}" in text
    assert f"contact half-width a (half the loaded zone) │ {s['contact_half_width']:.5g}" in text


def test_one_linear_solve_of_a_frictional_finite_run(ironing_friction):
    res, s, table, _ = ironing_friction
    total, count = res.raw.extra["linear_solve_s"], res.raw.extra["linear_solves"]
    assert count == s["linear_solve_count"] == s["linear_solves"]
    assert s["linear_solve_time_s"] == pytest.approx(total / count, rel=1e-15)
    assert table[f"one Newton linear solve, mean of {count} (s)"] == format(s["linear_solve_time_s"], ".3g")


def test_half_width_of_a_curved_3d_body_is_its_contact_radius():
    """A quarter hemisphere pressed on the plane y = 0 (no Hertz reference): the edge search along a line of
    the 'flat' coordinate plane found nothing (a = 0); the contact radius is the largest distance of a loaded
    point from the y axis through the pole (exact geometry of the reference configuration)."""
    from alcontact.contact import solve_finite
    from alcontact.problems.hemisphere import hemisphere
    from alcontact.runner import summarize

    prob = hemisphere(n=4, delta=0.1)
    sol = solve_finite(prob, steps=2).solution
    s = summarize(prob, sol)
    loaded = sol.pressure > 0
    assert loaded.sum() >= 3
    expected = float(np.max(np.hypot(sol.points[loaded, 0], sol.points[loaded, 2])))
    assert s["contact_half_width"] == pytest.approx(expected, rel=1e-12)
    assert 0.2 < s["contact_half_width"] < 0.5  # about sqrt(R delta) = 0.32 for R = 1, delta = 0.1
