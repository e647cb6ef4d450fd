"""The run-time estimate of a finite-deformation run counts what its steps cost (issue 18).

A 13k-DOF 2D ironing with friction (mu = 0.3, 40 steps) ran 12.9 min where ``alcontact check`` said 1.3:
the estimate counted 10 Newton iterations of the linear-algebra model per step, and the step took 39
(plus sensitivities, line searches, return mappings). The solver model of a finite-deformation run is now
load steps x tangent assembly + solve *units* per step x one unit, both measured by the ironing benchmark
(``time_calibration.json``'s ``finite`` section, written by ``benchmarks/time_estimates.py`` from
``docs/benchmarks/ironing*.json``). Checked here: the model is that product, it distinguishes friction and
the algorithm, falls back where the calibration has no entry, and the committed section is the one the
committed benchmark summaries give.
"""

import importlib.util
from pathlib import Path

import pytest

from alcontact.io import preflight

ROOT = Path(__file__).resolve().parents[2]
PROBLEM = ROOT / "benchmarks" / "problems" / "ironing_friction_13k.toml"

FINITE = {"unit_s": {"2": [1e-6, 1.0], "3": [2e-7, 1.5]},
          "step_units": {"frictionless": {"ssn": 8.0, "default": 11.0},
                         "friction": {"simo-laursen": 25.0, "default": 18.0}}}


def _est(dim=2, ndofs=10_000):
    return preflight.SizeEstimate(dim, 1, ndofs // dim, ndofs, ndofs, "direct", 1e8, 3.0, exact=True)


def _data(friction=0.0, algorithm=None, steps=40):
    data = {"contact": {"kinematics": "finite", "friction": friction}, "loading": {"steps": steps}}
    if algorithm:
        data["solver"] = {"algorithm": algorithm}
    return data


@pytest.fixture
def calibrated(monkeypatch):
    monkeypatch.setattr(preflight, "time_calibration", lambda: {"finite": FINITE})


def test_steps_times_units_times_measured_unit(calibrated):
    est = preflight._finite_cost(_est(), _data(0.3, "simo-laursen"))
    assert est.seconds == pytest.approx(40 * 25.0 * 1e-6 * 10_000, rel=1e-12)
    assert "25 tangent assembly + solve units per frictional simo-laursen step (measured)" in est.note
    # the schema's default algorithm (simo-laursen) when [solver] names none
    assert preflight._finite_cost(_est(), _data(0.3)).seconds == est.seconds


def test_friction_algorithm_and_dimension_select_their_entry(calibrated):
    ssn = preflight._finite_cost(_est(), _data(0.0, "ssn")).seconds
    assert ssn == pytest.approx(40 * 8.0 * 1e-2, rel=1e-12)
    # an algorithm the benchmark did not measure: the mean over the measured ones
    penalty = preflight._finite_cost(_est(), _data(0.0, "penalty")).seconds
    assert penalty == pytest.approx(40 * 11.0 * 1e-2, rel=1e-12)
    three = preflight._finite_cost(_est(3, 12_000), _data(0.3, "ssn")).seconds
    assert three == pytest.approx(40 * 18.0 * 2e-7 * 12_000 ** 1.5, rel=1e-12)


def test_without_a_measured_model_the_newton_count_model(monkeypatch):
    monkeypatch.setattr(preflight, "time_calibration", lambda: {})
    est = preflight._finite_cost(_est(), _data(0.3))
    per_newton = 3.0 / 3.0 + preflight._T_TANGENT * 10_000 * 3
    assert est.seconds == pytest.approx(40 * preflight.NEWTON_PER_STEP * per_newton, rel=1e-12)
    small = {"contact": {"kinematics": "small"}}
    assert preflight._finite_cost(_est(), small) == _est()


def test_committed_finite_section_is_the_benchmarks():
    """``time_calibration.json`` holds what ``benchmarks/time_estimates.py`` computes from the committed ironing
    summaries (``finite_model``): the estimate learns from those runs, not from a hand-written number."""
    spec = importlib.util.spec_from_file_location("time_estimates", ROOT / "benchmarks" / "time_estimates.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    got, want = preflight.time_calibration()["finite"], mod.finite_model(ROOT / "docs" / "benchmarks")
    assert got.keys() == want.keys()
    for key in want:
        if key == "unit_s":  # a least-squares fit (np.polyfit, LAPACK): the same to round-off on every machine
            assert got[key].keys() == want[key].keys()
            for dim in want[key]:
                assert got[key][dim] == pytest.approx(want[key][dim], rel=1e-12, abs=0.0)
        else:
            assert got[key] == want[key]


def test_the_13k_frictional_ironing_is_estimated_from_its_steps():
    """The case of the issue: the estimate is the measured model's (its note says so), not 10 Newton per step."""
    pre = preflight.check_problem(PROBLEM)
    assert pre.size.ndofs == 13_158 and len(pre.setup.times) == 40
    assert "frictional simo-laursen step (measured)" in pre.size.note
