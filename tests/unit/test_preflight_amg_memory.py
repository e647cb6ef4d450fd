"""The preflight memory model of the AMG path against the measured benchmark runs.

Reference: the resident-set peaks of the first contact solve measured by
``benchmarks/hertz_3d_large.py`` on 3D P1 Hertz (the records with a ``first_solve_gb`` in
``docs/benchmarks/hertz_3d_large.json``: branch ``h-big3d3``, 128k to 1M DOFs, and the 5.06M-DOF
run on ``main``). Tolerance: the estimate
(:func:`alcontact.io.preflight._cost` with the exact node, element and DOF counts of each
run) lies within 20 % of every measured peak, so ``alcontact check`` refuses or admits a
size on a number that was measured, and a change of the model constants without a new
measurement fails here.

Reaches inside the package: unit test of the preflight cost model ``io.preflight._cost`` against
measured memory.
"""

from __future__ import annotations

import json
from pathlib import Path

from alcontact.io.preflight import _cost

RECORDS = Path(__file__).resolve().parents[2] / "docs" / "benchmarks" / "hertz_3d_large.json"


def _measured():
    recs = [r for r in json.loads(RECORDS.read_text()) if r.get("first_solve_gb")]
    return recs


def test_amg_memory_model_matches_the_measured_peaks():
    recs = _measured()
    assert len(recs) >= 4  # 128k, 311k, 1M and 5M measured
    for r in recs:
        nodes = r["dofs"] // 3
        est = _cost(3, 1, nodes, r["elements"], "amg", True)
        measured = r["first_solve_gb"] * 1e9
        assert est.ndofs == r["dofs"]
        assert abs(est.memory_bytes / measured - 1.0) <= 0.20, (r["dofs"], est.memory_bytes, measured)

