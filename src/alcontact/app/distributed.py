"""``mpirun -n N alcontact run problem.toml``: a problem file solved by the distributed contact path.

Rank 0 reads and checks the file (as ``alcontact check``), refuses what is not distributed
yet with one message (finite deformation, friction), and holds the mesh while it is
partitioned (handed to the solve as a builder, so that rank 0 releases it once distributed);
every rank then solves its part (:func:`alcontact.contact.solve_distributed`, over the file's
load steps) and writes its piece of the VTU. The results folder is staged and moved into
place by rank 0 (:class:`alcontact.io.ResultsFolder`, as the serial run): ``solution.pvtu``
(ParaView opens the pieces ``solution_<rank>.vtu`` as one), ``solution.pvd`` (with load
steps: over ``steps/solution_NNNN.pvtu`` and their pieces ``steps/solution_NNNN_<rank>.vtu``),
``summary.json`` (one entry per step in ``steps``) and ``report.md``.
"""

from __future__ import annotations

import logging
import os
import time
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["headline", "run_distributed", "refusal"]

logger = logging.getLogger(__name__)

#: the fields of the VTU pieces: name -> components (``None``: a scalar)
_FIELDS = {"displacement": 3, "contact_pressure": None, "gap": None, "rank": None}


def refusal(setup) -> str | None:
    """Why the problem file ``setup`` cannot run on the distributed path yet (``None``: it can)."""
    if setup.finite:
        return ("the distributed (MPI) contact path solves small-deformation problems (frictionless or Coulomb, one "
                "or more load steps); this problem has finite deformation (kinematics = \"finite\"): run it as one "
                "process (without mpirun).")
    mus = sorted(set(setup.pair_friction))
    if len(mus) > 1:
        return ("the distributed (MPI) contact path takes one Coulomb coefficient for all contact pairs; this "
                f"problem's pairs have mu = {'/'.join(f'{m:g}' for m in mus)}: give every pair the same friction, or run "
                "it as one process (without mpirun).")
    return None


def run_distributed(problem_file, out=None, force: bool = False, *, algorithm: str | None = None,
                    penalty: str | None = None, overrides: dict | None = None, comm=None) -> dict:
    """Solve ``problem_file`` over the ranks of ``comm`` and write the results folder; the summary on every rank.

    Raises
    ------
    alcontact.distributed.DistributedError
        On every rank, with the message of the rank that failed (bad input, a refused problem).
    """
    from ..contact import available_algorithms, find_algorithm, solve_distributed, solve_distributed_friction
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
            frictional = setup.friction > 0
            alg = algorithm or setup.algorithm
            if alg not in available_algorithms():
                find_algorithm(alg)
            entry = find_algorithm(alg, friction=True) if frictional else find_algorithm(alg)
            pen = penalty if penalty is not None else (setup.penalty if entry.penalty is None else None)
            given = setup.friction_options if frictional else setup.options
            head = (alg, pen, {**given, **(overrides or {})}, dict(setup.petsc_options), str(out), setup.name,
                    frictional)
    alg, pen, options, petsc_options, out, name, frictional = comm.bcast(head, root=0)
    build = problem = history = times = None
    if comm.rank == 0:  # handed over as a builder: rank 0 releases the whole mesh once it is distributed
        build, history, times = [setup.problem].pop, setup.history, list(setup.times)
        problem = setup.problem if frictional else None
        setup = None
    if frictional:
        fsol = solve_distributed_friction(problem, history, alg, pen, options, comm=comm,
                                          petsc_options=petsc_options)
        problem = None
        with collective(comm, "collecting the accepted load steps"):
            sol = _friction_views(fsol)
        summary = _friction_summary(fsol, name, options, petsc_options, problem_file, comm)
    else:
        sol = solve_distributed(build, alg, pen, options, comm=comm, petsc_options=petsc_options, steps=times,
                                history=history)
        summary = _summary(sol, name, alg, options, petsc_options, problem_file, comm)
    staging = folder = None
    with collective(comm, "creating the results folder"):
        if comm.rank == 0:
            folder = ResultsFolder(out, force)
            staging = str(folder.__enter__().path)
    staging = Path(comm.bcast(staging, root=0))
    failed = None
    try:
        _write_results(staging, sol, summary, comm)
    except BaseException as exc:  # noqa: BLE001 - rank 0 discards the staging folder, then re-raises
        failed = exc
    if comm.rank == 0:
        folder.__exit__(type(failed) if failed else None, failed, None)
    if failed is not None:
        raise failed
    summary["wall_s"] = time.perf_counter() - t0
    summary["out"] = out
    return summary


def _write_results(staging: Path, sol, summary: dict, comm) -> None:
    """Every rank's VTU pieces (of every load step when there are several) and rank 0's files, into ``staging``."""
    from ..distributed import collective

    entries = []
    stepped = _stepped(sol)
    if stepped:
        with collective(comm, "creating the steps folder"):
            if comm.rank == 0:
                (staging / "steps").mkdir()
    for k, step in enumerate(sol.steps if stepped else []):
        values = _piece_values(step, comm)  # collective: the ghost nodes' values from their owners
        stem = f"steps/solution_{k + 1:04d}"
        with collective(comm, "writing the VTU pieces of the steps"):
            _write_piece(staging, step, values, f"{stem}_{comm.rank}.vtu")
            if comm.rank == 0:
                _write_pvtu(staging / f"{stem}.pvtu", [f"solution_{k + 1:04d}_{r}.vtu" for r in range(comm.size)])
        entries.append((step.extra["t"], f"{stem}.pvtu"))
    values = _piece_values(sol, comm)
    with collective(comm, "writing the VTU pieces"):
        _write_piece(staging, sol, values, f"solution_{comm.rank}.vtu")
    with collective(comm, "writing summary.json and report.md"):
        if comm.rank == 0:
            _write_master(staging, [f"solution_{k}.vtu" for k in range(comm.size)], summary,
                          entries or [(1.0, "solution.pvtu")])


def headline(summary: dict) -> str:
    """The one line the command line prints for a distributed run (rank 0)."""
    s = summary
    head = f"{s['problem']}: {s['status']} on {s['ranks']} MPI ranks ({s['dofs']} DOFs); "
    if "friction" in s:
        return (head + f"{len(s['steps'])} load steps, normal force {s['normal_force']:.10g}, tangential force "
                f"{s['tangential_force']}; results in {s['out']}")
    return (head + f"contact force {s['model_contact_force']:.10g}, largest nodal pressure "
            f"{s['peak_pressure_nodal_max']:.10g}; results in {s['out']}")


def _friction_views(fsol):
    """The steps of a frictional solve as the views the VTU writer reads (``u``, ``pressure``, ``gap``, ``piece``,
    ``point_nodes``, ``extra["t"]``); the last one carries ``steps`` (all of them)."""
    from types import SimpleNamespace

    views = [SimpleNamespace(u=st.u, pressure=st.pressure, gap=st.gap, piece=fsol.piece,
                             point_nodes=fsol.point_nodes, extra={"t": st.t}) for st in fsol.steps]
    if not views:  # no accepted step: the contact-free start is not written; an empty final view for the writer
        raise InputError(f"distributed frictional solve: no load step was accepted ({fsol.message}).")
    last = views[-1]
    last.steps = views
    return last


def _friction_summary(fsol, name, options, petsc_options, problem_file, comm) -> dict:
    last = fsol.steps[-1] if fsol.steps else None
    files = ["summary.json", "report.md", "solution.pvtu", "solution.pvd", "steps/"] + \
        [f"solution_{k}.vtu" for k in range(comm.size)]
    return {
        "problem": name, "source": str(problem_file), "status": fsol.status.label, "status_code": int(fsol.status),
        "message": fsol.message, "algorithm": fsol.algorithm, "penalty": fsol.penalty, "friction": fsol.friction,
        "ranks": int(comm.size), "dofs": fsol.extra["dofs"], "candidates": fsol.extra["candidates"],
        "linear_solver": fsol.extra["linear_solver"], "strategy": fsol.extra["strategy"],
        "outer_iterations": fsol.outer_iterations, "newton_iterations": fsol.newton_iterations,
        "cutbacks": fsol.cutbacks, "linear_solves": fsol.linear_solves,
        "ksp_iterations": fsol.extra.get("ksp_iterations"),
        "contact_force_vector": last.contact_force.tolist() if last else None,
        "normal_force": last.normal_force if last else None,
        "tangential_force": last.tangential_force.tolist() if last else None,
        "options": options, "petsc_options": petsc_options, "timings": fsol.timings, "files": files,
        "steps": [{"t": st.t, "normal_force": st.normal_force, "tangential_force": st.tangential_force.tolist(),
                   "contact_force_vector": st.contact_force.tolist(), "outer_iterations": st.outer_iterations,
                   "newton_iterations": st.newton_iterations, "cutbacks": st.cutbacks,
                   "equilibrium": st.equilibrium} for st in fsol.steps],
    }


def _summary(sol, name, algorithm, options, petsc_options, problem_file, comm) -> dict:
    r = sol.result
    files = ["summary.json", "report.md", "solution.pvtu", "solution.pvd"] + \
        [f"solution_{k}.vtu" for k in range(comm.size)] + (["steps/"] if _stepped(sol) else [])
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
        "steps": [{"t": st.extra["t"], "status": st.result.status.label, "model_contact_force": st.model_contact_force,
                   "contact_force_vector": st.total_contact_force.tolist(), "peak_pressure_nodal_max": st.peak_pressure,
                   "outer_iterations": st.result.outer_iterations, "newton_iterations": st.result.newton_iterations}
                  for st in sol.steps],
    }


def _stepped(sol) -> bool:
    """Whether the run had load steps (more than one, or one at a time other than 1): then ``steps/`` is written."""
    return len(sol.steps) > 1 or sol.steps[0].extra["t"] != 1.0


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


def _write_piece(staging: Path, sol, got: np.ndarray, name: str) -> None:
    """This rank's piece ``name`` (``solution_<rank>.vtu``): its elements and their nodes."""
    import meshio

    piece = sol.piece
    dim = piece.points.shape[0]
    nv = piece.points.shape[1]  # the vertices (a P2 piece's nodes are its vertices, then its edge nodes)
    got = got[:nv]
    pts = np.zeros((nv, 3))
    pts[:, :dim] = piece.points.T
    disp = np.zeros((pts.shape[0], 3))
    disp[:, :dim] = got[:, :dim]
    cell = "triangle" if dim == 2 else "tetra"
    data = {"displacement": disp, "contact_pressure": got[:, dim].copy(), "gap": got[:, dim + 1].copy(),
            "rank": got[:, dim + 2].copy()}
    meshio.write(os.fspath(staging / name),
                 meshio.Mesh(pts, [(cell, piece.elements.T.astype(np.int64))], point_data=data))


def _write_pvtu(path: Path, pieces: list[str]) -> None:
    """A ``.pvtu`` over the VTU ``pieces`` (names relative to its folder)."""
    from ..io.results import write_text_atomic

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
    write_text_atomic(path, "\n".join(lines))


def _write_master(staging: Path, pieces: list[str], summary: dict, entries: list) -> None:
    """``solution.pvtu`` over the pieces, ``solution.pvd`` over the steps' ``entries`` (time, file), ``summary.json``
    and ``report.md`` (rank 0)."""
    from ..io import write_json
    from ..io.results import write_text_atomic
    from ..io.vtu import write_pvd

    _write_pvtu(staging / "solution.pvtu", pieces)
    write_pvd(staging / "solution.pvd", entries)
    write_json(staging / "summary.json", summary)
    s = summary
    if "friction" in s:
        report = [f"# {s['problem']}: distributed frictional contact solve", "",
                  f"- status: **{s['status']}** ({s['message']})",
                  f"- {s['ranks']} MPI ranks, {s['dofs']} DOFs, {s['candidates']} contact candidates, friction "
                  f"{s['friction']:g}",
                  f"- algorithm {s['algorithm']} (penalty {s['penalty']}), linear solver {s['linear_solver']}",
                  f"- {len(s['steps'])} load steps ({s['cutbacks']} cut-backs), outer iterations "
                  f"{s['outer_iterations']}, Newton iterations {s['newton_iterations']}, KSP solves "
                  f"{s['linear_solves']}", "", "| t | normal force | tangential force | equilibrium |",
                  "|---|---|---|---|"]
        report += [f"| {st['t']:g} | {st['normal_force']:.10g} | {st['tangential_force']} | {st['equilibrium']:.1e} |"
                   for st in s["steps"]]
        report += ["", "Open `solution.pvd` in ParaView: one piece per rank and step.", ""]
        write_text_atomic(staging / "report.md", "\n".join(report))
        return
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
