"""Distributed Coulomb friction (run under mpirun by tests/mpi/test_distributed_friction.py).

Usage: python friction.py OUT.json PROBLEM_FILE CELLS CASE [CASE ...]; CELLS "nx,ny" replaces the file's
``[mesh] cells``; CASE "ALGORITHM:SOLVER". Rank 0 writes, per case and accepted step, the time, the normal and
tangential forces, the equilibrium measure and the displacement gathered in the mesh's node order.
"""

import json
import sys

import numpy as np

from alcontact.contact import solve_distributed_friction
from alcontact.distributed import run_ranks, world


def setup_of(problem_file, cells):
    import tempfile
    from pathlib import Path

    from alcontact.io import load_problem

    text = Path(problem_file).read_text()
    nx, ny = cells.split(",")
    text = text.replace("cells = [8, 2]", f"cells = [{nx}, {ny}]", 1)
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as fh:
        fh.write(text)
    return load_problem(fh.name)


def main(out, problem_file, cells, *cases):
    comm = world()
    results = {}
    for case in cases:
        algorithm, solver = case.split(":")
        setup = setup_of(problem_file, cells) if comm.rank == 0 else None
        sol = solve_distributed_friction(setup.problem if setup else None, setup.history if setup else None,
                                         algorithm, None, {"linear_solver": solver}, comm=comm)
        steps = []
        for s in sol.steps:
            us = comm.gather(s.u.reshape(-1, sol.nodes.shape[1]), root=0)
            nodes = comm.gather(sol.global_nodes, root=0)
            if comm.rank == 0:
                u = np.empty((setup.problem.model.mesh.p.shape[1], sol.nodes.shape[1]))
                u[np.concatenate(nodes)] = np.concatenate(us)
                steps.append({"t": s.t, "normal": s.normal_force, "tangential": s.tangential_force.tolist(),
                              "equilibrium": s.equilibrium, "u": u.tolist()})
        if comm.rank == 0:
            results[case] = {"ranks": comm.size, "status": int(sol.status), "message": sol.message,
                             "steps": steps, "extra": sol.extra}
    if comm.rank == 0:
        with open(out, "w") as fh:
            json.dump(results, fh)


if __name__ == "__main__":
    run_ranks(main, *sys.argv[1:])
