"""Distributed Hertz contact (run under mpirun by tests/mpi/test_distributed_contact.py).

Usage: python contact.py OUT.json DIM PARTITION CASE [CASE ...]
  DIM 2 or 3 (the Hertz problems of alcontact.problems.hertz at a coarse mesh, see ``problem``), or "2p2", "3p2"
  (the same with P2 elements);
  PARTITION "metis", or "zone" (element slabs along x - y by centroid, cutting the contact zone:
  a partition forced through it, :func:`zone_parts`); CASE "ALGORITHM:SOLVER[:PENALTY]"
  (SOLVER "petsc" or "petsc-direct"), or a failure: "fail:rank1" (the obstacle raises on rank 1
  only), "fail:tiny" (fewer elements than ranks), "fail:solver" (an unknown linear solver on rank 0).
Rank 0 writes, per case, the status, counters, contact force, peak pressure, contact extent,
equilibrium measures and the displacement gathered in the mesh's node order to OUT.json.
"""

import json
import sys

import numpy as np

from alcontact.contact import solve_distributed
from alcontact.contact.obstacles import Circle
from alcontact.distributed import run_ranks, world
from alcontact.problems import hertz


def problem(dim, order: int = 1):
    """The coarse Hertz problems of the tests (also built by the test for the serial reference)."""
    return hertz.hertz_2d(n_per_a=4, order=order) if dim == 2 else hertz.hertz_3d(n_per_a=1, order=order)


class FailingCircle(Circle):
    """A circle whose evaluation fails on rank 1 (bad input seen by one rank only)."""

    def evaluate(self, x):
        if world().rank == 1:
            raise ValueError("bad obstacle input on rank 1 (test)")
        return super().evaluate(x)


def zone_parts(mesh, size):
    """Element slabs by centroid through the contact zone (``x`` and, in 3D, ``y`` in ``[0, 0.9]`` on the
    surface): along ``x`` of width ``0.9 / size`` in 2D (the last slab takes the rest), along ``x - y`` of width
    ``2.4 / size`` from ``x - y = -1.2`` in 3D (a diagonal cut; the 3D mesh is coarser there)."""
    xc = mesh.p[:, mesh.t].mean(axis=1)
    s = xc[0] / (0.9 / size) if mesh.p.shape[0] == 2 else (xc[0] - xc[1] + 1.2) / (2.4 / size)
    return np.minimum(np.maximum(s, 0).astype(int), size - 1)


def main(out, dim, partition, *cases):
    comm = world()
    dim, order = (int(dim[0]), 2) if str(dim).endswith("p2") else (int(dim), 1)  # "2p2", "3p2": P2 elements
    results = {}
    for case in cases:
        algorithm, solver, *rest = case.split(":")
        prob = parts = None
        if comm.rank == 0:
            prob = problem(dim, order)
            if case == "fail:rank1":
                from alcontact.contact import ContactProblem

                prob = hertz.hertz_2d(n_per_a=4)
                ob = prob.obstacle
                prob = ContactProblem(prob.model, FailingCircle(center=tuple(ob.center), radius=ob.radius), "top",
                                      supports=prob.supports, loads=prob.loads)
            if case == "fail:tiny":
                from alcontact.contact import ContactProblem, Support
                from alcontact.fem import LinearElasticity, Material, meshes

                body = LinearElasticity(meshes.rectangle(0, 1, 0, 1, 1, 1), Material(E=1.0, nu=0.3))
                prob = ContactProblem(body, Circle(center=(0.5, 2.0), radius=1.0), "top",
                                      supports=[Support("bottom")])
            if partition == "zone" and case != "fail:tiny":
                parts = zone_parts(prob.model.mesh, comm.size)
        if algorithm == "fail":
            solver = "no-such-solver" if solver == "solver" else "petsc-direct"
            algorithm = "simo-laursen"
        sol = solve_distributed(prob, algorithm, rest[0] if rest else None, {"linear_solver": solver}, comm=comm,
                                parts=parts)
        us = comm.gather(sol.u.reshape(-1, dim), root=0)
        nodes = comm.gather(sol.global_nodes, root=0)
        if comm.rank == 0:
            u = np.empty((prob.model.all_node_dofs()[0].shape[0], dim))
            u[np.concatenate(nodes)] = np.concatenate(us)
            r = sol.result
            results[case] = {
                "ranks": comm.size, "status": int(r.status), "message": r.message,
                "outer": r.outer_iterations, "newton": r.newton_iterations, "linear_solves": r.linear_solves,
                "force": sol.total_contact_force.tolist(), "peak": sol.peak_pressure,
                "extent": sol.contact_extent.tolist(), "residual": sol.equilibrium["residual"],
                "balance": sol.equilibrium["balance"], "u": u.tolist(), "extra": sol.extra,
                "ranks_with_contact": None,
            }
        # how many ranks own active contact points (the zone partition must cut the contact zone)
        n_active = comm.gather(int(np.sum(sol.active)), root=0)
        if comm.rank == 0:
            results[case]["ranks_with_contact"] = int(np.sum(np.asarray(n_active) > 0))
    if comm.rank == 0:
        with open(out, "w") as fh:
            json.dump(results, fh)


if __name__ == "__main__":
    run_ranks(main, *sys.argv[1:])
