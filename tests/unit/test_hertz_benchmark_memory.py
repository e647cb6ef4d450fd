"""The memory and fit helpers of ``benchmarks/hertz.py`` (issue 11: time, memory and ratio against DOFs)."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

_PATH = Path(__file__).resolve().parents[2] / "benchmarks" / "hertz.py"


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("_hertz_benchmark", _PATH)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    yield mod
    sys.modules.pop(spec.name, None)


@pytest.mark.skipif(not Path("/proc/self/clear_refs").exists(), reason="Linux /proc needed")
def test_peak_rss_sees_a_freed_allocation_and_resets(bench):
    """A 200 MiB array, touched then freed, raises the peak by at least 190 MiB; a reset drops it again.

    Reference: the array's size (200 MiB of float64 ones, every page written); tolerance 10 MiB
    for pages the kernel counts differently. After the reset the peak is the current RSS,
    within 20 MiB of it (it can only grow by what the interpreter allocates in between).
    """
    if not bench.reset_peak_rss():
        pytest.skip("/proc/self/clear_refs is not writable here")
    before = bench.rss_mb()
    a = np.ones(200 * 2**20 // 8)
    del a
    peak = bench.peak_rss_mb()
    assert peak - before >= 190.0
    assert bench.reset_peak_rss()
    assert bench.peak_rss_mb() <= bench.rss_mb() + 20.0
    assert bench.peak_rss_mb() < peak - 150.0


def test_fit_recovers_the_exponent(bench):
    """``_fit`` of y = 3 x^1.23 over 10^4..10^6 returns 1.23 to 1e-12; fewer than 3 points: None."""
    x = np.logspace(4, 6, 7)
    assert math.isclose(bench._fit(x, 3.0 * x ** 1.23), 1.23, abs_tol=1e-12)
    assert bench._fit(x[:2], x[:2]) is None


def test_memory_table_reports_solve_memory_above_the_start(bench):
    """Memory table: linear solve from 100 to 300 MiB, contact solves from 110 to 320 and from 120 to 360:
    solve memory +200, +210..+240, contact/linear solve memory 240/200 = 1.20 (exact arithmetic)."""
    base = dict(case="c", dofs="1000", candidates="5", status="converged", model_rss_mb="90",
                plain_linear_peak_rss_mb="300", plain_linear_base_rss_mb="100")
    rows = [dict(base, variant="a", peak_rss_mb="320", base_rss_mb="110"),
            dict(base, variant="b", peak_rss_mb="360", base_rss_mb="120")]
    line = bench._memory_table(rows, ["c"])[-1]
    assert line == "| c | 1000 | 90 | 300 (+200) | 320-360 (+210-240) | 1.20 |"
