"""``benchmarks/ironing.py`` as the ``ironing`` suite of ``alcontact bench``: presets, errors, a tiny run."""

from __future__ import annotations

import csv
import json
import runpy
from pathlib import Path

import pytest

from alcontact.errors import UnknownNameError
from alcontact.runner import BENCH_SUITES

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "ironing.py"


@pytest.fixture(scope="module")
def ironing():
    return runpy.run_path(str(SCRIPT), run_name="alcontact_bench_ironing")


def test_suite_registered_with_existing_quick_presets(ironing):
    suite = BENCH_SUITES["ironing"]
    assert suite.script == "ironing.py" and suite.takes_cases
    assert set(suite.quick["cases"]) <= set(ironing["CASES"])
    assert set(suite.quick["variants"]) <= set(ironing["VARIANTS"])


def test_unknown_case_or_variant_names_the_known_ones(ironing, tmp_path):
    with pytest.raises(UnknownNameError, match="Did you mean '2d-s'"):
        ironing["run"](tmp_path, ["2d-ss"], ["ssn"], log=lambda _: None)
    with pytest.raises(UnknownNameError, match="Did you mean 'simo-laursen'"):
        ironing["run"](tmp_path, ["2d-s"], ["simo-laurson"], log=lambda _: None)


def test_run_writes_csv_json_and_report(ironing, tmp_path):
    """A tiny preset (2D, h = 1/4, slid 0.25 R: 5 sliding steps) through ``run``: one CSV row per sliding
    step, the summary in JSON with the independent equilibrium check, the markdown quoting the command."""
    ironing["CASES"]["tiny"] = (2, 4)
    try:
        messages = []
        ironing["run"](tmp_path, ["tiny"], ["ssn"], log=messages.append, repeat=1, slide=0.25)
    finally:
        del ironing["CASES"]["tiny"]
    with open(tmp_path / "ironing.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["step"] for r in rows] == ["5", "6", "7", "8", "9"]
    assert all(int(r["newton_iterations"]) >= 1 and float(r["ratio"]) > 0 for r in rows)
    (summary,) = json.loads((tmp_path / "ironing.json").read_text())
    assert summary["status"] == "converged" and summary["sliding_steps"] == 5
    assert summary["equilibrium_max"] < 1e-9
    report = (tmp_path / "ironing.md").read_text()
    assert "alcontact bench --suite ironing --case tiny --variant ssn" in report
    assert any(m.startswith("ironing tiny ssn: converged") for m in messages)


def test_friction_variant_records_coulomb_law_and_reversals(ironing, tmp_path):
    """The ``ssn-coulomb`` variant (mu = 0.3) on the tiny preset: the friction columns are filled from
    the returned steps (slip-law error, stick ratio, reversals) and the friction table is in the report."""
    ironing["CASES"]["tiny"] = (2, 4)
    try:
        ironing["run"](tmp_path, ["tiny"], ["ssn-coulomb"], log=lambda _: None, repeat=1, slide=0.25)
    finally:
        del ironing["CASES"]["tiny"]
    with open(tmp_path / "ironing.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 5 and all(r["slip_law_error"] and r["state_reversals"] != "" for r in rows)
    (summary,) = json.loads((tmp_path / "ironing.json").read_text())
    assert summary["status"] == "converged" and summary["mu"] == 0.3
    assert summary["slip_law_error_max"] < 1e-8 and summary["stick_ratio_max"] <= 1.0 + 1e-8
    assert summary["equilibrium_max"] < 1e-9 and isinstance(summary["state_reversals"], int)
    assert "Coulomb friction, mu = 0.3" in (tmp_path / "ironing.md").read_text()
