"""``mpirun -n N alcontact run problem.toml``: a problem file solved by the distributed contact path.

Rank 0 reads and checks the file (as ``alcontact check``), refuses what is not distributed
yet with one message (finite deformation, friction, load steps, bodies other than linear
elastic P1), and holds the mesh while it is partitioned; every rank then solves its part
(:func:`alcontact.contact.solve_distributed`) and writes its piece of the VTU. The results
folder is staged and moved into place by rank 0 (:class:`alcontact.io.ResultsFolder`, as
the serial run): ``solution.pvtu`` (ParaView opens the pieces ``solution_<rank>.vtu`` as
one), ``solution.pvd``, ``summary.json`` and ``report.md``. No rank builds an array of the
mesh's size except rank 0 while it reads and partitions the mesh.
"""

from __future__ import annotations

import logging
import os
import time
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["run_distributed", "refusal"]

logger = logging.getLogger(__name__)

#: the fields of the VTU pieces: name -> components (``None``: a scalar)
_FIELDS = {"displacement": 3, "contact_pressure": None, "gap": None, "rank": None}


def refusal(setup) -> str | None:
    """Why the problem file ``setup`` cannot run on the distributed path yet (``None``: it can)."""
    what = []
    if setup.finite:
        what.append("finite deformation (kinematics = \"finite\")")
    if setup.friction > 0:  # the largest coefficient of the pairs
        what.append("friction")
    if len(setup.times) > 1:
        what.append(f"load steps ({len(setup.times)} step times)")
    if not what:
        return None
    return ("the distributed (MPI) contact path solves frictionless small-deformation problems in one load step; "
            f"this problem has {' and '.join(what)}: run it as one process (without mpirun).")


def run_distributed(problem_file, out=None, force: bool = False, *, algorithm: str | None = None,
                    penalty: str | None = None, overrides: dict | None = None, comm=None) -> dict:
    """Solve ``problem_file`` over the ranks of ``comm`` and write the results folder; the summary on every rank.

    Raises
    ------
    alcontact.distributed.DistributedError
        On every rank, with the message of the rank that failed (bad input, a refused problem).
    """
    from ..contact import available_algorithms, find_algorithm, solve_distributed
    from ..distributed import collective, world
    from ..io import ResultsFolder, check_output_dir
    from ..io.preflight import check_problem

    comm = comm if comm is not None else world()
    t0 = time.perf_counter()
    setup = head = None
    with collective(comm, "reading the problem file"):
        if comm.rank == 0:
            setup = check_problem(problem_file).setup
            why = refusal(setup)
            if why:
                raise InputError(why)
            out = Path(out if out is not None else setup.output["folder"])
            check_output_dir(out, force)
            alg = algorithm or setup.algorithm
            if alg not in available_algorithms():
                find_algorithm(alg)
            pen = penalty if penalty is not None else (setup.penalty if find_algorithm(alg).penalty is None else None)
            head = (alg, pen, {**setup.options, **(overrides or {})}, dict(setup.petsc_options), str(out), setup.name)
    alg, pen, options, petsc_options, out, name = comm.bcast(head, root=0)
    sol = solve_distributed(setup.problem if comm.rank == 0 else None, alg, pen, options, comm=comm,
                            petsc_options=petsc_options)
    summary = _summary(sol, name, alg, options, petsc_options, problem_file, comm)
    staging = folder = None
    with collective(comm, "creating the results folder"):
        if comm.rank == 0:
            folder = ResultsFolder(out, force)
            staging = str(folder.__enter__().path)
    staging = Path(comm.bcast(staging, root=0))
    failed = None
    try:
        values = _piece_values(sol, comm)  # collective: the ghost nodes' values from their owners
        with collective(comm, "writing the VTU pieces"):
            _write_piece(staging, sol, values, comm.rank)
        with collective(comm, "writing summary.json and report.md"):
            if comm.rank == 0:
                _write_master(staging, [f"solution_{k}.vtu" for k in range(comm.size)], summary)
    except BaseException as exc:  # noqa: BLE001 - rank 0 discards the staging folder, then re-raises
        failed = exc
    if comm.rank == 0:
        folder.__exit__(type(failed) if failed else None, failed, None)
    if failed is not None:
        raise failed
    summary["wall_s"] = time.perf_counter() - t0
    summary["out"] = out
    return summary


def _summary(sol, name, algorithm, options, petsc_options, problem_file, comm) -> dict:
    r = sol.result
    files = ["summary.json", "report.md", "solution.pvtu", "solution.pvd"] + \
        [f"solution_{k}.vtu" for k in range(comm.size)]
    return {
        "problem": name, "source": str(problem_file), "status": r.status.label, "status_code": int(r.status),
        "message": r.message, "algorithm": r.algorithm, "penalty": r.penalty, "ranks": int(comm.size),
        "dofs": sol.extra["dofs"], "candidates": sol.extra["candidates"],
        "linear_solver": sol.extra["linear_solver"], "strategy": sol.extra["strategy"],
        "outer_iterations": r.outer_iterations, "newton_iterations": r.newton_iterations,
        "linear_solves": r.linear_solves, "ksp_iterations": sol.extra["ksp_iterations"],
        "penetration": r.penetration, "complementarity": r.complementarity,
        "contact_force_vector": sol.total_contact_force.tolist(), "model_contact_force": sol.model_contact_force,
        "peak_pressure_nodal_max": sol.peak_pressure,
        "contact_extent": sol.contact_extent.tolist(),
        "equilibrium": {"residual": sol.equilibrium["residual"], "balance": sol.equilibrium["balance"]},
        "options": options, "petsc_options": petsc_options, "timings": sol.timings, "files": files,
    }


def _piece_values(sol, comm) -> np.ndarray:
    """Displacement, pressure, gap and owner rank at every node of this rank's piece, ``(n_local, dim + 3)``:
    owned values and the ghost nodes' from their owners (one PETSc scatter)."""
    from ..linalg import petsc

    PETSc = petsc()
    piece = sol.piece
    dim = piece.points.shape[0]
    k = dim + 3
    n_own = piece.node_range[1] - piece.node_range[0]
    vals = np.zeros((n_own, k))
    vals[:, :dim] = sol.u.reshape(-1, dim)
    vals[sol.point_nodes, dim] = sol.pressure
    vals[sol.point_nodes, dim + 1] = sol.gap
    vals[:, dim + 2] = comm.rank
    v = PETSc.Vec().createMPI((n_own * k, piece.n_nodes * k), comm=comm)
    v.array[:] = vals.ravel()
    idx = (k * piece.global_nodes[:, None] + np.arange(k)).ravel().astype(PETSc.IntType)
    iset = PETSc.IS().createGeneral(idx, comm=PETSc.COMM_SELF)
    local = PETSc.Vec().createSeq(idx.size, comm=PETSc.COMM_SELF)
    scatter = PETSc.Scatter().create(v, iset, local, None)
    scatter.scatter(v, local, addv=PETSc.InsertMode.INSERT_VALUES, mode=PETSc.ScatterMode.FORWARD)
    out = local.getArray().reshape(-1, k).copy()
    for obj in (scatter, local, iset, v):
        obj.destroy()
    return out


def _write_piece(staging: Path, sol, got: np.ndarray, rank: int) -> None:
    """This rank's ``solution_<rank>.vtu``: its elements and their nodes."""
    import meshio

    piece = sol.piece
    dim = piece.points.shape[0]
    pts = np.zeros((piece.points.shape[1], 3))
    pts[:, :dim] = piece.points.T
    disp = np.zeros((pts.shape[0], 3))
    disp[:, :dim] = got[:, :dim]
    cell = "triangle" if dim == 2 else "tetra"
    data = {"displacement": disp, "contact_pressure": got[:, dim].copy(), "gap": got[:, dim + 1].copy(),
            "rank": got[:, dim + 2].copy()}
    meshio.write(os.fspath(staging / f"solution_{rank}.vtu"),
                 meshio.Mesh(pts, [(cell, piece.elements.T.astype(np.int64))], point_data=data))


def _write_master(staging: Path, pieces: list[str], summary: dict) -> None:
    """``solution.pvtu`` over the pieces, ``solution.pvd``, ``summary.json`` and ``report.md`` (rank 0)."""
    from ..io import write_json
    from ..io.results import write_text_atomic
    from ..io.vtu import write_pvd

    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian">',
             '  <PUnstructuredGrid GhostLevel="0">', '    <PPoints>',
             '      <PDataArray type="Float64" NumberOfComponents="3"/>', '    </PPoints>', '    <PPointData>']
    for fname, comps in _FIELDS.items():
        extra = f' NumberOfComponents="{comps}"' if comps else ""
        lines.append(f'      <PDataArray type="Float64" Name="{fname}"{extra}/>')
    lines.append('    </PPointData>')
    lines += [f'    <Piece Source="{p}"/>' for p in pieces]
    lines += ['  </PUnstructuredGrid>', '</VTKFile>', '']
    write_text_atomic(staging / "solution.pvtu", "\n".join(lines))
    write_pvd(staging / "solution.pvd", [(1.0, "solution.pvtu")])
    write_json(staging / "summary.json", summary)
    s = summary
    report = [f"# {s['problem']}: distributed contact solve", "",
              f"- status: **{s['status']}** ({s['message']})",
              f"- {s['ranks']} MPI ranks, {s['dofs']} DOFs, {s['candidates']} contact candidates",
              f"- algorithm {s['algorithm']} (penalty {s['penalty']}), linear solver {s['linear_solver']}",
              f"- outer iterations {s['outer_iterations']}, Newton iterations {s['newton_iterations']}, "
              f"KSP solves {s['linear_solves']} ({s['ksp_iterations']} iterations)",
              f"- contact force {s['contact_force_vector']} (sum of w lambda {s['model_contact_force']:.10g}), "
              f"largest nodal pressure {s['peak_pressure_nodal_max']:.10g}",
              f"- penetration {s['penetration']:.2e} h, complementarity {s['complementarity']:.2e}, equilibrium "
              f"residual {s['equilibrium']['residual']:.2e}, balance {s['equilibrium']['balance']:.2e}", "",
              "Open `solution.pvd` (or `solution.pvtu`) in ParaView: one piece per rank.", ""]
    write_text_atomic(staging / "report.md", "\n".join(report))
