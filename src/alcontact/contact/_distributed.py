r"""The distributed contact solve: :func:`solve_distributed`, the MPI counterpart of :func:`~alcontact.contact.solve`.

Frictionless contact at small deformation of one linear elastic P1 body against a rigid
master, over the ranks of an MPI communicator, by the serial outer loops (the pure
penalty (6.10), Algorithm 6.1, Algorithm 6.3 with any registered family-P penalty, the
semi-smooth Newton reference) on :class:`~alcontact.contact.systems._distributed.DistributedContact`
(PETSc ``MPIAIJ`` matrices and KSP solves). The candidate extension, the verification of
the returned state (:func:`~alcontact.contact._verify.check_state`: penetration,
complementarity, equilibrium) and the status are those of the serial small-deformation
solve, with every measure reduced over the ranks.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ._solve import _times
from ._verify import check_state, equilibrium_tolerance, verified_status
from .algorithms._frictionless import ContactOptions, _Run, available_algorithms, find_algorithm, options_with
from .laws._stiffness import penalty_stiffness
from .solution._solution import ContactResult, ContactStatus

__all__ = ["DistributedContactSolution", "solve_distributed"]

logger = logging.getLogger(__name__)

#: the ``linear_solver`` names of the distributed path and the KSP each runs
_KSP_OF = {"petsc": "gamg", "auto": "gamg", "petsc-direct": "direct"}


@dataclass
class DistributedContactSolution:
    """What one rank holds of a distributed contact solution, and the global measures (equal on every rank).

    Attributes
    ----------
    result : ContactResult
        Status, message, counters, checked invariants (the same on every rank).
    u : ndarray (n_owned_nodes * dim,)
        Displacement of the nodes this rank owns, node-major.
    nodes : ndarray (n_owned_nodes, dim)
        Their coordinates.
    global_nodes : ndarray of int (n_owned_nodes,)
        Their numbers in the mesh rank 0 read (``mesh.p`` columns).
    points, gap, pressure, weights, normals : ndarray
        The contact points this rank owns: coordinates ``(m_r, dim)``, gaps (6.15), pressures
        (the multipliers applied, 0 off the candidates), tributary weights, obstacle normals.
    active : ndarray of bool (m_r,)
        Closed points with a positive pressure.
    total_contact_force : ndarray (dim,)
        :math:`\\sum_i w_i \\lambda_i \\nu_i` over all ranks.
    model_contact_force : float
        :math:`\\sum_i w_i \\lambda_i` over all ranks (``model_contact_force`` of the serial summary).
    peak_pressure : float
        The largest nodal pressure (``peak_pressure_nodal_max`` of the serial summary).
    contact_extent : ndarray (dim, 2)
        Smallest and largest coordinate of the active points along each axis (all ranks).
    equilibrium : dict
        ``residual``: largest free-DOF residual of :math:`Ku - f - f_c` over the force scale;
        ``balance``: :math:`|\\sum (f + f_c + r)|` per component over :math:`|\\sum f_c|`, with
        :math:`r` the support reactions (contact force = reactions + loads).
    timings, extra : dict
    piece : alcontact.distributed.LocalPiece
        This rank's elements and their nodes (for output).
    point_nodes : ndarray of int (m_r,)
        Owned node (index into ``u.reshape(-1, dim)``) of each contact point of this rank.
    steps : list of DistributedContactSolution
        Every load step solved, in order (the last is this solution; ``extra["t"]`` the step time).
    """

    result: ContactResult
    u: np.ndarray
    nodes: np.ndarray
    global_nodes: np.ndarray
    points: np.ndarray
    gap: np.ndarray
    pressure: np.ndarray
    weights: np.ndarray
    normals: np.ndarray
    active: np.ndarray
    total_contact_force: np.ndarray
    model_contact_force: float
    peak_pressure: float
    contact_extent: np.ndarray
    equilibrium: dict
    timings: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)
    piece: object = None
    point_nodes: np.ndarray | None = None
    steps: list = field(default_factory=list)


def _ksp_kind(linear_solver: str) -> str:
    if linear_solver not in _KSP_OF:
        raise InputError(f"linear_solver = {linear_solver!r} does not run on the distributed path; use "
                         f"{' or '.join(repr(k) for k in _KSP_OF if k != 'auto')} (or 'auto': 'petsc').")
    return _KSP_OF[linear_solver]


def solve_distributed(problem, algorithm: str = "simo-laursen", penalty: str | None = None, options=None, *,
                      comm=None, parts=None, petsc_options: dict | None = None, steps=None, history=None,
                      on_step=None) -> DistributedContactSolution:
    """Solve a frictionless small-deformation contact problem over the ranks of ``comm`` (module doc).

    Call it on every rank (``mpirun -n N``): the problem and the arguments are read on rank 0
    (pass ``problem=None`` elsewhere) and sent to the others.

    Parameters
    ----------
    problem : ContactProblem, callable or None
        On rank 0: the problem, or a function without arguments that builds it; a problem built
        so is released on rank 0 once it is distributed (rank 0 then holds no array over the whole
        mesh while the ranks solve).
    algorithm, penalty, options
        As :func:`alcontact.contact.solve` (rank 0's are used); ``options["linear_solver"]`` picks
        the KSP: ``"petsc"`` (CG + GAMG with the rigid-body near-null space, the default) or
        ``"petsc-direct"`` (MUMPS, else SuperLU_dist).
    comm : mpi4py communicator, optional
        Default ``MPI.COMM_WORLD``.
    parts : ndarray of int, optional
        Rank of each element (on rank 0) instead of METIS.
    petsc_options : dict, optional
        PETSc options passed through (names without the dash; unused ones are reported).
    steps, history
        Load steps, as :func:`alcontact.contact.solve` takes them at small deformation without
        friction (on rank 0): ``history`` a :class:`~alcontact.contact.LoadHistory` (ramped
        supports and loads), ``steps`` a number of equal steps or the step times (default: the
        history's times, else one step). Every step is an independent solve (the problem is path
        independent); the run stops at the first step that fails.
    on_step : callable, optional
        ``on_step(k, n, t)`` on every rank before step ``k`` of ``n`` and ``on_step(k + 1, n, t)`` after it.

    Returns
    -------
    DistributedContactSolution
        On every rank: its own part of the fields, the global measures and the one status, of
        the last step solved; ``steps`` holds the solution of every step (``extra["t"]`` its time).

    Raises
    ------
    alcontact.distributed.DistributedError
        On every rank, when the set-up failed on one (bad input: the message of the rank that failed).

    Examples
    --------
    ``mpirun -n 2 .venv-mpi/bin/python script.py`` with::

        from alcontact.distributed import world
        comm = world()
        problem = hertz.hertz_2d(1) if comm.rank == 0 else None
        sol = solve_distributed(problem, "simo-laursen", comm=comm)
    """
    from ..distributed import collective, world
    from .systems._distributed import DistributedContact

    comm = comm if comm is not None else world()
    t_start = time.perf_counter()
    head = None
    with collective(comm, "reading the solve's arguments"):
        if comm.rank == 0:
            if algorithm not in available_algorithms():
                find_algorithm(algorithm)  # the UnknownNameError with the closest match
            entry = find_algorithm(algorithm)
            pen_name = entry.penalty_for(penalty)
            opts = options_with(options, ContactOptions, {}, "contact", entry)
            _ksp_kind(opts.linear_solver)
            times = (1.0,) if steps is None and history is None else _times(steps, history)
            head = (algorithm, pen_name, opts, dict(petsc_options or {}), tuple(times))
    algorithm, pen_name, opts, petsc_options, times = comm.bcast(head, root=0)
    entry = find_algorithm(algorithm)
    dc = DistributedContact(problem, comm=comm, parts=parts, ksp=_ksp_kind(opts.linear_solver),
                            options=petsc_options, margin=opts.margin, history=history if comm.rank == 0 else None,
                            t=times[0])
    # the body's material and dimension are all the automatic stiffness reads: the same on every rank
    eps0 = float(opts.eps_n if opts.eps_n is not None else penalty_stiffness(dc.body, dc.h, opts.penalty_scale))
    solved = []
    for k, t in enumerate(times):
        if on_step is not None:
            on_step(k, len(times), t)
        t_solve = time.perf_counter()
        if k > 0:
            dc.at_time(t)
        solution = _solve_step(dc, entry, opts, eps0, pen_name, algorithm)
        t_end = time.perf_counter()
        solution.timings = dict(dc.timings(), solve_s=t_end - t_solve, total_s=t_end - t_start)
        solution.extra["t"] = float(t)
        solved.append(solution)
        if on_step is not None:
            on_step(k + 1, len(times), t)
        if solution.result.status < 0:
            break
    solution.steps = solved
    return solution


def _solve_step(dc, entry, opts, eps0, pen_name, algorithm) -> DistributedContactSolution:
    """One step from the contact-free state of ``dc``: the outer loop, the candidates added while any penetrate."""
    if dc.cand.size == 0:
        out = _Run(dc.start(), np.zeros(0), np.zeros(0), ContactStatus.NO_CONTACT,
                   f"the body never reaches the obstacle (smallest clearance {-dc.max_free_penetration:.4g}); move "
                   "the obstacle closer, increase the load, or check the contact boundary name", 0, 0, eps0, 0.0, [])
    else:
        for _attempt in range(8):
            out = entry.run(dc, opts, eps0, pen_name)
            if out.status < 0 or dc.extend(out.r, opts.tol_penetration * dc.h) == 0:
                break
    return _build(dc, out, opts, algorithm, pen_name)


def _build(dc, out, opts, algorithm, pen_name) -> DistributedContactSolution:
    """The one place a distributed result is built: every printed measure checked at the returned state."""
    MPI, comm, dim = dc.MPI, dc.comm, dc.dim
    u = np.asarray(out.r, dtype=float)
    m = dc.points.shape[0]
    pressure = np.zeros(m)
    lam = np.asarray(out.lam, dtype=float)
    if lam.size:
        pos = dc._my_pos[dc._my_pos < lam.size]  # candidates added after the last run carry none
        pressure[dc.cand[pos] - dc.point_offset] = lam[pos]
    g = dc.local_gaps(u)
    if out.status > 0 and not dc.allbool(bool(np.all(np.isfinite(u)))):
        out.status, out.message = ContactStatus.NONFINITE, "non-finite displacement"
    nodal = dc.weights * np.maximum(pressure, 0.0)
    fc = np.zeros(u.size)  # the contact forces on the body, owned DOFs
    np.add.at(fc, dc.point_dofs.ravel(), (nodal[:, None] * dc.normals).ravel())
    r = dc.matvec(u) - dc.f - fc
    react = np.zeros(u.size)
    react[dc.fixed] = r[dc.fixed]  # support reactions: K u = f + f_c + reactions
    r[dc.fixed] = 0.0
    force = _reduce(comm, np.sum(nodal[:, None] * dc.normals, axis=0), MPI.SUM)
    loads = _reduce(comm, dc.f.reshape(-1, dim).sum(axis=0), MPI.SUM)
    reactions = _reduce(comm, react.reshape(-1, dim).sum(axis=0), MPI.SUM)
    scale = max(dc.allmax(np.abs(dc.f)), dc.allmax(np.abs(fc)), dc.allmax(np.abs(react)),
                dc.allmax(np.abs(pressure)) * dc.allmax(np.abs(dc.weights)), 1e-300)
    residual = dc.allmax(np.abs(r)) / scale
    fnorm = max(float(np.linalg.norm(force)), 1e-300)
    balance = float(np.max(np.abs(force + loads + reactions))) / fnorm
    # the contact-point arrays (a surface, not the volume) gathered for the one check of the serial path
    g_all = dc.allgather_points(g)
    p_all = dc.allgather_points(pressure)
    reach = dc.allmax(np.abs(dc.points)) + dc.allmax(np.abs(u))
    check = check_state(g_all, p_all, dc.h, tol_penetration=opts.tol_penetration,
                        tol_complementarity=opts.tol_complementarity, equilibrium=residual,
                        tol_equilibrium=equilibrium_tolerance(opts, multipliers=True, floor=1e-11), reach=reach)
    out.status, out.message = verified_status(out.status, out.message, check,
                                              what=f"distributed contact solve {algorithm}")
    pressure = np.maximum(pressure, 0.0)
    pmax = dc.allmax(pressure)
    closed = g > -max(1e-6, 10 * opts.tol_penetration) * dc.h
    active = closed & (pressure > 1e-12 * max(pmax, 1e-300))
    lo = np.where(active[:, None], dc.points, np.inf).min(axis=0, initial=np.inf)
    hi = np.where(active[:, None], dc.points, -np.inf).max(axis=0, initial=-np.inf)
    extent = np.column_stack([_reduce(comm, lo, MPI.MIN), _reduce(comm, hi, MPI.MAX)])
    result = ContactResult(status=out.status, message=out.message, algorithm=algorithm, penalty=pen_name,
                           outer_iterations=int(out.outer), newton_iterations=int(out.newton),
                           linear_solves=int(dc.linear_solves), factorizations=0,
                           penetration=check.value("penetration"), complementarity=check.value("complementarity"),
                           residual=float(out.residual), eps_n=float(out.eps), history=tuple(out.history))
    if out.status < 0 and comm.rank == 0:
        logger.warning("distributed contact solve %s/%s failed (%s): %s", algorithm, pen_name, out.status.label,
                       out.message)
    body = dc.body
    return DistributedContactSolution(
        result=result, u=u, nodes=body.owned_points(), global_nodes=body.owned_mesh_nodes(),
        points=dc.points, gap=g, pressure=pressure, weights=dc.weights, normals=dc.normals, active=active,
        total_contact_force=force, model_contact_force=dc.allsum(float(np.sum(nodal))), peak_pressure=pmax,
        contact_extent=extent,
        equilibrium={"residual": residual, "balance": balance, "loads": loads, "reactions": reactions},
        extra={"h": dc.h, "candidates": int(dc.cand.size), "dofs": int(dc.n_global), **dc.extra()},
        piece=body.piece, point_nodes=dc.point_node)


def _reduce(comm, a, op) -> np.ndarray:
    """Element-wise reduction of a small float array over the ranks."""
    a = np.ascontiguousarray(a, dtype=float)
    out = np.empty_like(a)
    comm.Allreduce(a, out, op=op)
    return out
