"""``benchmarks/two_body_ironing.py`` as the ``two-body-ironing`` suite of ``alcontact bench``: presets, errors, a
tiny run."""

from __future__ import annotations

import csv
import json
import runpy
from pathlib import Path

import pytest

from alcontact.errors import UnknownNameError
from alcontact.runner import BENCH_SUITES

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "two_body_ironing.py"


@pytest.fixture(scope="module")
def bench():
    return runpy.run_path(str(SCRIPT), run_name="alcontact_bench_two_body_ironing")


def test_suite_registered_with_existing_quick_presets(bench):
    suite = BENCH_SUITES["two-body-ironing"]
    assert suite.script == "two_body_ironing.py" and suite.takes_cases
    assert set(suite.quick["cases"]) <= set(bench["CASES"])
    assert set(suite.quick["variants"]) <= set(bench["VARIANTS"])


def test_unknown_case_or_variant_names_the_known_ones(bench, tmp_path):
    with pytest.raises(UnknownNameError, match="Did you mean '2d-s'"):
        bench["run"](tmp_path, ["2d-ss"], ["ssn"], log=lambda _: None)
    with pytest.raises(UnknownNameError, match="Did you mean 'simo-laursen'"):
        bench["run"](tmp_path, ["2d-s"], ["simo-laurson"], log=lambda _: None)


def test_run_writes_csv_json_and_report(bench, tmp_path):
    """The tiny preset (block h = 1/6, slid 0.3 R: 4 pressing and 6 sliding steps) through ``run``: one CSV row
    per accepted load step, the summary in JSON, the markdown quoting the command."""
    messages = []
    bench["run"](tmp_path, ["tiny"], ["ssn"], log=messages.append)
    with open(tmp_path / "two_body_ironing.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["phase"] for r in rows].count("slide") >= 6 and all(int(r["newton_iterations"]) >= 1 for r in rows)
    (summary,) = json.loads((tmp_path / "two_body_ironing.json").read_text())
    assert summary["status"] == "converged" and summary["load_steps"] == 10
    assert summary["contact_force_balance"] < 1e-10 and summary["gap_evaluation_per_newton"] > 0
    report = (tmp_path / "two_body_ironing.md").read_text()
    assert "alcontact bench --suite two-body-ironing --case tiny --variant ssn" in report
    assert any(m.startswith("two_body_ironing tiny ssn: converged") for m in messages)
