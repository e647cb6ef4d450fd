"""Distributed linear elasticity against the serial solve (run under mpirun by tests/mpi).

Usage: python elasticity.py OUT.json DIM SOLVER PARTITION [FAIL]
  DIM 2 or 3; SOLVER gamg or direct; PARTITION metis or slabs (elements cut into slabs
  along x by their centroid: a forced cut); FAIL: "clamped-rank1" makes clamped() raise on
  rank 1 only, "tiny" distributes a mesh with fewer elements than ranks.
Rank 0 writes {"ranks", "rel_error", "iterations", "reason", "n_dofs"} to OUT.json.
"""

import json
import sys

import numpy as np
import scipy.sparse.linalg as spla

from alcontact.distributed import DistributedElasticity, run_ranks, world
from alcontact.fem import LinearElasticity, Material, meshes


def serial(mesh, material, force, clamped):
    """Reference: the serial model, clamped DOFs eliminated, SuperLU."""
    model = LinearElasticity(mesh, material)
    K = model.stiffness()
    f = model.body_load(force)
    pts, dmap = model.all_node_dofs()
    fixed = dmap[clamped(pts.T)].ravel()
    free = np.setdiff1d(np.arange(model.ndofs), fixed)
    u = np.zeros(model.ndofs)
    u[free] = spla.spsolve(K[free][:, free].tocsc(), f[free])
    return u[dmap]  # (n_nodes, dim)


def main(out, dim, solver, partition, fail=""):
    comm = world()
    dim = int(dim)
    material = Material(E=200.0, nu=0.3)
    force = [0.0, -1.0] if dim == 2 else [0.0, 0.3, -1.0]
    mesh = None
    if comm.rank == 0:
        if fail == "tiny":
            mesh = meshes.rectangle(0, 1, 0, 1, 1, 1)  # 2 triangles
        else:
            mesh = meshes.rectangle(0, 3, 0, 1, 24, 8) if dim == 2 else meshes.box(0, 3, 0, 1, 0, 1, 9, 3, 3)
    parts = None
    if comm.rank == 0 and partition == "slabs" and fail != "tiny":
        xc = mesh.p[0, mesh.t].mean(axis=0)
        parts = np.minimum((xc / 3.0 * comm.size).astype(int), comm.size - 1)

    def clamped(x):
        if fail == "clamped-rank1" and comm.rank == 1:
            raise ValueError("bad input on rank 1 (test)")
        return x[0] < 1e-12

    model = DistributedElasticity(mesh, material, comm=comm, parts=parts)
    sol = model.solve(force, clamped, solver=solver, rtol=1e-13)
    u, _ = model.gather(sol)
    if comm.rank == 0:
        ref = serial(mesh, material, force, clamped)
        mine = u[model.numbering]  # back to the mesh's node order
        err = float(np.max(np.abs(mine - ref)) / np.max(np.abs(ref)))
        with open(out, "w") as fh:
            json.dump({"ranks": comm.size, "rel_error": err, "iterations": sol.iterations, "reason": sol.reason,
                       "n_dofs": int(ref.size), "local_nodes": int(sol.points.shape[0])}, fh)


if __name__ == "__main__":
    run_ranks(main, *sys.argv[1:])
