"""Distributed linear elasticity (alcontact.distributed) on 1, 2 and 3 ranks against the serial solve.

Reference: the serial model (alcontact.fem.LinearElasticity, clamped DOFs eliminated,
SuperLU) on the same mesh; the distributed displacement must equal it to 1e-8 relative
(max-norm over all nodes, relative to max|u|). CG runs to a relative residual of 1e-13,
so the Krylov error (condition number ~1e4 here) stays far below 1e-8.
Every mpirun has a timeout: a hang fails the test.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from ._mpi import mpirun

SCRIPT = str(Path(__file__).parent / "scripts" / "elasticity.py")


def _run(tmp_path, n, *args):
    out = tmp_path / "out.json"
    proc = mpirun(n, SCRIPT, str(out), *args, timeout=180)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return json.loads(out.read_text())


@pytest.mark.parametrize("n,dim,solver", [(1, 3, "gamg"), (2, 3, "gamg"), (3, 3, "gamg"), (2, 2, "gamg"),
                                          (3, 2, "direct"), (2, 3, "direct")])
def test_distributed_solution_equals_the_serial_one(tmp_path, n, dim, solver):
    res = _run(tmp_path, n, str(dim), solver, "metis")
    assert res["ranks"] == n
    assert res["reason"] > 0
    assert res["rel_error"] <= 1e-8
    if n > 1:  # the mesh was really split: rank 0 owns only part of the nodes
        assert res["local_nodes"] < res["n_dofs"] // dim


def test_forced_slab_partition_gives_the_same_answer(tmp_path):
    """Elements cut into x-slabs (``parts`` given, not METIS): same answer to 1e-8."""
    res = _run(tmp_path, 3, "3", "gamg", "slabs")
    assert res["rel_error"] <= 1e-8


def test_a_rank_that_fails_stops_every_rank_with_one_error(tmp_path):
    """clamped() raises on rank 1 only: exit status non-zero, one message naming rank 1, no hang."""
    proc = mpirun(3, SCRIPT, str(tmp_path / "o.json"), "3", "gamg", "metis", "clamped-rank1", timeout=120)
    assert proc.returncode != 0
    assert proc.stderr.count("error: finding the clamped nodes failed on rank(s) 1") == 1
    assert "bad input on rank 1" in proc.stderr
    assert not (tmp_path / "o.json").exists()


def test_fewer_elements_than_ranks_is_a_clear_error(tmp_path):
    proc = mpirun(3, SCRIPT, str(tmp_path / "o.json"), "2", "gamg", "metis", "tiny", timeout=120)
    assert proc.returncode != 0
    assert "2 elements, fewer than the 3 MPI ranks" in proc.stderr
    assert "Traceback" not in proc.stderr
