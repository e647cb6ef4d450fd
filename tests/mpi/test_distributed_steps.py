"""Load steps on the distributed path: the flat punch of ``examples/flat_punch.toml`` (the bottom pushed up in
four steps by a ramped support) on 1, 2 and 3 ranks.

Reference: the serial path, ``contact.solve`` with the same problem, history and step times (default linear
solver, condensed). Every step is compared to 1e-8 relative in the contact force (its norm), the largest nodal
pressure and the displacement field (max norm over the mesh); equilibrium (free-DOF residual and the balance
contact force = reactions + loads) below 1e-8 at every step. The KSP is CG + GAMG (``petsc``, to a relative
residual of 1e-10 in the last Newton step) or MUMPS (``petsc-direct``).
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

import numpy as np
import pytest

from ._mpi import mpirun

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = str(Path(__file__).parent / "scripts" / "steps.py")
PUNCH = str(ROOT / "examples" / "flat_punch.toml")
TOL = 1e-8
CASES = {1: ["ssn:petsc-direct", "simo-laursen:petsc"], 2: ["simo-laursen:petsc-direct"], 3: ["ssn:petsc"]}


@functools.cache
def serial(algorithm: str):
    from alcontact.contact import solve
    from alcontact.io import load_problem

    setup = load_problem(PUNCH)
    sol = solve(setup.problem, algorithm, steps=list(setup.times), history=setup.history)
    assert sol.result.status > 0, sol.result.message
    _, dmap = setup.problem.model.all_node_dofs()
    return [(f.t, f.contact_force, float(np.max(f.pressure)), f.u[dmap]) for f in sol.frames]


def _rel(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(float(np.max(np.abs(b))), 1e-300))


@pytest.mark.parametrize("ranks", [1, 2, pytest.param(3, marks=pytest.mark.slow)])
def test_load_steps_same_on_every_rank_count_as_serial(tmp_path, ranks):
    out = tmp_path / "steps.json"
    proc = mpirun(ranks, SCRIPT, str(out), PUNCH, *CASES[ranks], timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    results = json.loads(out.read_text())
    for case in CASES[ranks]:
        algorithm, solver = case.split(":")
        got, ref = results[case]["steps"], serial(algorithm)
        assert len(got) == len(ref) == 4, case
        for g, (t, force, peak, u) in zip(got, ref):
            assert g["status"] > 0, g["message"]
            assert g["t"] == pytest.approx(t, rel=1e-15)
            assert np.linalg.norm(np.subtract(g["force"], force)) <= TOL * np.linalg.norm(force), (case, t)
            assert g["peak"] == pytest.approx(peak, rel=TOL), (case, t)
            assert _rel(g["u"], u) <= TOL, (case, t)
            assert g["residual"] <= TOL and g["balance"] <= TOL, (case, t)
            assert g["extra"]["linear_solver"] == solver and g["extra"]["ranks"] == ranks
