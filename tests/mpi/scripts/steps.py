"""Distributed load steps (run under mpirun by tests/mpi/test_distributed_steps.py).

Usage: python steps.py OUT.json PROBLEM_FILE CASE [CASE ...]; CASE "ALGORITHM:SOLVER" (SOLVER "petsc" or
"petsc-direct"). The problem file's load history and step times are solved by
``contact.solve_distributed``; rank 0 writes, per case and step, the time, status, contact force, largest
nodal pressure, equilibrium measures and the displacement gathered in the mesh's node order to OUT.json.
"""

import json
import sys

import numpy as np

from alcontact.contact import solve_distributed
from alcontact.distributed import run_ranks, world
from alcontact.io import load_problem


def main(out, problem_file, *cases):
    comm = world()
    results = {}
    for case in cases:
        algorithm, solver = case.split(":")
        setup = load_problem(problem_file) if comm.rank == 0 else None
        sol = solve_distributed(setup.problem if setup else None, algorithm, None, {"linear_solver": solver},
                                comm=comm, steps=list(setup.times) if setup else None,
                                history=setup.history if setup else None)
        steps = []
        for s in sol.steps:
            us = comm.gather(s.u.reshape(-1, s.nodes.shape[1]), root=0)
            nodes = comm.gather(s.global_nodes, root=0)
            if comm.rank == 0:
                u = np.empty((setup.problem.model.mesh.p.shape[1], s.nodes.shape[1]))
                u[np.concatenate(nodes)] = np.concatenate(us)
                steps.append({"t": s.extra["t"], "status": int(s.result.status), "message": s.result.message,
                              "force": s.total_contact_force.tolist(), "peak": s.peak_pressure,
                              "residual": s.equilibrium["residual"], "balance": s.equilibrium["balance"],
                              "u": u.tolist(), "extra": s.extra})
        if comm.rank == 0:
            results[case] = {"ranks": comm.size, "steps": steps}
    if comm.rank == 0:
        with open(out, "w") as fh:
            json.dump(results, fh)


if __name__ == "__main__":
    run_ranks(main, *sys.argv[1:])
