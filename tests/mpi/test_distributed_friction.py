"""Coulomb friction on the distributed path: the sliding block of ``examples/sliding_block.toml`` (pressed by its
top, then sheared three times as far as it can stick; mu = 0.3), on a refined mesh (24 x 6 cells), on 1, 2 and 3
ranks.

References: (1) the serial path, ``contact.solve`` with the same problem and history (default linear solver:
the condensed direct path, the same step algorithm); every accepted step is compared to 1e-8 relative in the
normal force, the tangential force vector and the displacement field (max norm). (2) Coulomb's law, closed form:
once the block slides (the last two steps) the tangential force equals mu times the normal force (to 1e-8).
Equilibrium of every step's returned state below 1e-8. The KSP is CG + GAMG (``petsc``) or MUMPS
(``petsc-direct``).
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

import numpy as np
import pytest

from ._mpi import mpirun

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = str(Path(__file__).parent / "scripts" / "friction.py")
BLOCK = str(ROOT / "examples" / "sliding_block.toml")
CELLS = "24,6"
TOL = 1e-8
MU = 0.3
CASES = {1: ["simo-laursen:petsc-direct", "ssn:petsc"], 2: ["simo-laursen:petsc", "family-p:petsc-direct"],
         3: ["ssn:petsc-direct"]}


@functools.cache
def serial(algorithm: str):
    import importlib.util

    from alcontact.contact import solve

    spec = importlib.util.spec_from_file_location("friction_script", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    setup = mod.setup_of(BLOCK, CELLS)
    sol = solve(setup.problem, algorithm, history=setup.history)
    assert sol.result.status > 0, sol.result.message
    _, dmap = setup.problem.model.all_node_dofs()
    return [(f.t, f.normal_force, f.tangential_force, f.u[dmap]) for f in sol.frames]


def _rel(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(float(np.max(np.abs(b))), 1e-300))


@pytest.mark.parametrize("ranks", [1, 2, pytest.param(3, marks=pytest.mark.slow)])
def test_sliding_block_same_on_every_rank_count_as_serial(tmp_path, ranks):
    out = tmp_path / "friction.json"
    proc = mpirun(ranks, SCRIPT, str(out), BLOCK, CELLS, *CASES[ranks], timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    results = json.loads(out.read_text())
    for case in CASES[ranks]:
        algorithm, solver = case.split(":")
        got = results[case]
        assert got["status"] > 0, got["message"]
        assert got["extra"]["linear_solver"] == solver and got["extra"]["ranks"] == ranks
        ref = serial(algorithm)
        assert len(got["steps"]) == len(ref) == 8, case
        for g, (t, normal, tangential, u) in zip(got["steps"], ref):
            assert g["t"] == pytest.approx(t, rel=1e-15)
            assert g["normal"] == pytest.approx(normal, rel=TOL), (case, t)
            assert np.linalg.norm(np.subtract(g["tangential"], tangential)) <= TOL * abs(normal), (case, t)
            assert _rel(g["u"], u) <= TOL, (case, t)
            assert g["equilibrium"] <= TOL, (case, t)
        for g in got["steps"][-2:]:  # sliding: |T| = mu N (Coulomb)
            assert np.linalg.norm(g["tangential"]) == pytest.approx(MU * g["normal"], rel=TOL), case


def test_bad_frictional_input_is_refused_with_the_way_out():
    """On one rank of this process: a linear solver the distributed path does not have and a history that is not
    a LoadHistory are each one DistributedError naming the value and the choices."""
    from alcontact.contact import solve_distributed_friction
    from alcontact.distributed import DistributedError, world
    from alcontact.io import load_problem

    setup = load_problem(BLOCK)
    with pytest.raises(DistributedError, match="'amg' does not run on the distributed path; use 'petsc' or "
                                               "'petsc-direct'"):
        solve_distributed_friction(setup.problem, setup.history, options={"linear_solver": "amg"}, comm=world())
    with pytest.raises(DistributedError, match="history must be a LoadHistory"):
        solve_distributed_friction(setup.problem, [0.5, 1.0], comm=world())
