r"""The distributed contact solves: :func:`solve_distributed` and :func:`solve_distributed_friction`, the MPI
counterparts of :func:`~alcontact.contact.solve` at small deformation.

Contact of one linear elastic P1 body against a rigid master, over the ranks of an MPI
communicator. Frictionless (:func:`solve_distributed`): the serial outer loops (the pure
penalty (6.10), Algorithm 6.1, Algorithm 6.3 with any registered family-P penalty, the
semi-smooth Newton reference) on :class:`~alcontact.contact.systems._distributed.DistributedContact`
(PETSc ``MPIAIJ`` matrices and KSP solves), one independent solve per load step (the
problem is path independent). The candidate extension, the verification of the returned
state (:func:`~alcontact.contact._verify.check_state`: penetration, complementarity,
equilibrium) and the status are those of the serial small-deformation solve, with every
measure reduced over the ranks. Coulomb friction (:func:`solve_distributed_friction`):
Algorithms 6.2 / 6.4 and the Alart-Curnier reference, the serial direct path's load steps
(with cut-backs) on :class:`~alcontact.contact.systems._distributed.DistributedFrictionalContact`.
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

__all__ = ["DistributedContactSolution", "DistributedFrictionSolution", "DistributedFrictionStep", "solve_distributed",
           "solve_distributed_friction"]

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
        The largest multiplier :math:`\\lambda_i` (nodal pressure). It is ``peak_pressure_nodal_max`` of the
        serial summary except for 3D P2 bodies, whose serial pressure is recovered from the nodal forces by
        the boundary mass matrix (the vertex weights of a P2 triangle vanish); that recovery is not
        distributed yet, so there the two differ while the forces and displacements agree.
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
                      on_step=None, lag_preconditioner: bool = True) -> DistributedContactSolution:
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
    lag_preconditioner : bool
        With ``"petsc"``: a Newton matrix whose values changed is solved by CG with the preconditioner
        of the last GAMG update while CG's iterations per decade stay within
        :data:`~alcontact.contact.systems._distributed.LAG_GROWTH` times those after that update
        (``extra["pc_lagged"]`` counts those solves, ``extra["gamg_updates"]`` the Galerkin updates); ``False``
        updates it for every changed matrix. At 1M DOFs (3D Hertz, 1 rank) the updates took about
        three quarters of the Newton phase (``docs/benchmarks/distributed.md``).

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
            head = (algorithm, pen_name, opts, dict(petsc_options or {}), tuple(times), bool(lag_preconditioner))
    algorithm, pen_name, opts, petsc_options, times, lag = comm.bcast(head, root=0)
    entry = find_algorithm(algorithm)
    dc = DistributedContact(problem, comm=comm, parts=parts, ksp=_ksp_kind(opts.linear_solver),
                            options=petsc_options, margin=opts.margin, history=history if comm.rank == 0 else None,
                            t=times[0], lag=lag)
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


@dataclass
class DistributedFrictionStep:
    """One accepted load step of a distributed frictional solve: this rank's fields and the global measures.

    Attributes
    ----------
    t : float
    u : ndarray (n_owned_nodes * dim,)
        Displacement of the owned nodes.
    pressure, gap : ndarray (m_r,)
        Normal traction and gap of the contact points this rank owns.
    traction_t, slip : ndarray
        Tangential traction ``(m_r, d-1)`` in the tangent bases and the step's slip ``(m_r, d)`` (global axes).
    state : ndarray of int (m_r,)
        Open, stick or slip (:mod:`alcontact.contact.laws._coulomb`).
    normal_force, tangential_force, contact_force
        :math:`\\sum w t_N`, :math:`\\sum w (-T t_T)` and their sum with the normals (all ranks).
    outer_iterations, newton_iterations, cutbacks : int
    equilibrium : float
        Largest free-DOF residual of :math:`Ku - f - f_c` over the force scale (all ranks).
    """

    t: float
    u: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    traction_t: np.ndarray
    slip: np.ndarray
    state: np.ndarray
    normal_force: float
    tangential_force: np.ndarray
    contact_force: np.ndarray
    outer_iterations: int
    newton_iterations: int
    cutbacks: int
    equilibrium: float


@dataclass
class DistributedFrictionSolution:
    """What one rank holds of a distributed frictional solve (status and global measures equal on every rank).

    Attributes
    ----------
    status : ContactStatus
    message : str
    steps : list of DistributedFrictionStep
    algorithm, penalty : str
    friction : float
    outer_iterations, newton_iterations, cutbacks, linear_solves : int
    eps_n, eps_t, h : float
    nodes, global_nodes : ndarray
        Coordinates and mesh node numbers of the owned nodes (as :class:`DistributedContactSolution`).
    points, normals, weights : ndarray
        The contact points this rank owns.
    piece, point_nodes
        This rank's elements and the owned node of each owned contact point (for output).
    timings, extra : dict
    """

    status: ContactStatus
    message: str
    steps: list
    algorithm: str
    penalty: str
    friction: float
    outer_iterations: int
    newton_iterations: int
    cutbacks: int
    linear_solves: int
    eps_n: float
    eps_t: float
    h: float
    nodes: np.ndarray
    global_nodes: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    weights: np.ndarray
    piece: object = None
    point_nodes: np.ndarray | None = None
    timings: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)


def solve_distributed_friction(problem, history=None, algorithm: str = "simo-laursen", penalty: str | None = None,
                               options=None, *, comm=None, parts=None, petsc_options: dict | None = None,
                               steps=None, friction: float | None = None) -> DistributedFrictionSolution:
    r"""Coulomb friction at small deformation over the ranks of ``comm``: Algorithms 6.2 / 6.4 or the
    Alart-Curnier reference, each load step on the condensed problem of
    :class:`~alcontact.contact.systems._distributed.DistributedFrictionalContact`.

    The steps, candidate updates, cut-backs and stopping tests are those of the serial
    :func:`~alcontact.contact.stepping._coulomb.solve_friction` on its direct path
    (:class:`~alcontact.contact.stepping._coulomb._CondensedPath`, the same step function of the
    algorithm's registry entry), on the replicated candidate arrays; the returned state of every step
    is verified (:func:`~alcontact.contact._verify.check_state`: penetration, complementarity, the
    Coulomb law, equilibrium with every measure reduced over the ranks) before it is accepted.

    Parameters
    ----------
    problem : ContactProblem or None
        On rank 0 (``problem.friction`` the coefficient); ``None`` elsewhere.
    history : LoadHistory
        On rank 0: ramped supports and loads and the step times.
    algorithm, penalty, options, steps, friction
        As :func:`alcontact.contact.solve_friction` (rank 0's are used); ``options["linear_solver"]``
        ``"petsc"`` (CG + GAMG) or ``"petsc-direct"`` (MUMPS).
    comm, parts, petsc_options
        As :func:`solve_distributed`.

    Returns
    -------
    DistributedFrictionSolution
    """
    from ..distributed import collective, world
    from .algorithms._coulomb import FrictionOptions, friction_algorithms
    from .algorithms._frictionless import check_solve_args
    from .problem._loading import LoadHistory
    from .stepping._coulomb import _check_tangential_start, _checked_steps, _closed, _CondensedPath, _resolve, _State
    from .stepping._steps import Attempt, step_through
    from .systems._distributed import DistributedFrictionalContact

    comm = comm if comm is not None else world()
    t_start = time.perf_counter()
    head = None
    with collective(comm, "reading the frictional solve's arguments"):
        if comm.rank == 0:
            check_solve_args(problem, algorithm, penalty, friction_algorithms(), "friction ")
            _, pen_name = _resolve(algorithm, penalty)
            opts = options_with(options, FrictionOptions, {}, "friction", find_algorithm(algorithm, friction=True))
            _ksp_kind(opts.linear_solver)
            if not isinstance(history, LoadHistory):
                raise InputError(f"history must be a LoadHistory; got {type(history).__name__}.")
            if steps is not None:
                history = history.with_times(_checked_steps(steps))
            mu = float(problem.friction if friction is None else friction)
            if not (np.isfinite(mu) and mu >= 0):
                raise InputError(f"friction = {mu!r}: the friction coefficient must be a finite number >= 0.")
            head = (algorithm, pen_name, opts, dict(petsc_options or {}), mu)
    algorithm, pen_name, opts, petsc_options, mu = comm.bcast(head, root=0)
    step_fn = find_algorithm(algorithm, friction=True).run
    fc = DistributedFrictionalContact(problem if comm.rank == 0 else None, history if comm.rank == 0 else None,
                                      comm=comm, parts=parts, ksp=_ksp_kind(opts.linear_solver), options=petsc_options,
                                      margin=opts.margin)
    dc = fc.dc
    history = fc.history
    eps_n = float(opts.eps_n if opts.eps_n is not None else penalty_stiffness(dc.body, fc.h, opts.penalty_scale))
    eps_t = float(opts.eps_t if opts.eps_t is not None else opts.tangential_scale * eps_n)
    m, d = fc.points.shape
    u0 = fc.u_free(0.0)
    cur = {"state": _State(0.0, u0, fc.all_local(u0), np.zeros(m), np.zeros((m, d - 1)), np.zeros((m, d)),
                           np.zeros((m, d)))}
    tangential = [c for c in history.cases if c.tangential]
    advance = _CondensedPath().advance
    records: list[DistributedFrictionStep] = []
    own = fc._own

    def forces(tN, tT):
        shear = -np.einsum("ijk,ik->ij", fc.tangents, tT)
        return shear, fc.weights[:, None] * (tN[:, None] * fc.normals + shear)

    def equilibrium(t, u, tN, tT):
        """Largest free-DOF residual of K u - f(t) - f_c over the force scale (reduced), as :func:`_build`."""
        _, point_force = forces(tN, tT)
        fcv = np.zeros(u.size)
        np.add.at(fcv, dc.point_dofs.ravel(), point_force[own].ravel())
        f = fc.load(t)
        r = dc.matvec(u) - f - fcv
        react = np.zeros(u.size)
        react[dc.fixed] = r[dc.fixed]
        r[dc.fixed] = 0.0
        scale = max(dc.allmax(np.abs(f)), dc.allmax(np.abs(fcv)), dc.allmax(np.abs(react)),
                    float(np.max(np.abs(tN), initial=0.0)) * float(np.max(fc.weights, initial=0.0)), 1e-300)
        return dc.allmax(np.abs(r)) / scale

    def attempt(t: float) -> Attempt:
        prev = cur["state"]
        _check_tangential_start(fc, prev, t, tangential, opts)
        solves0 = fc.linear_solves
        mu_t = mu * history.friction_factor(t)
        res, out, o, nw = advance(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu_t, opts)
        counts = dict(newton=nw, outer=o, linear_solves=fc.linear_solves - solves0)
        if res is not None:
            u, y_all, tN, tT = res[:4]
            closed = _closed(fc, tN, y_all[:, 0], opts)
            duT = y_all[:, 1:] - prev.y[:, 1:]
            eq = equilibrium(t, u, tN, tT)
            check = check_state(y_all[:, 0], tN, fc.h, tol_penetration=opts.tol_penetration,
                                tol_complementarity=opts.tol_complementarity, traction_t=tT,
                                slip=np.where(closed[:, None] & fc.tfree, duT, 0.0), mu=mu_t,
                                tol_friction=max(opts.tol_multiplier, opts.tol_slip), equilibrium=eq,
                                tol_equilibrium=equilibrium_tolerance(opts, multipliers=True),
                                reach=dc.allmax(np.abs(dc.points)) + dc.allmax(np.abs(u)))
            if not check.ok:
                return Attempt(False, ContactStatus.NOT_VERIFIED, f"{algorithm} reported {out.message!r} but the "
                               f"state fails verification: {check.describe()}", **counts)
            counts["value"] = (res, out, eq)
        return Attempt(res is not None, out.status, out.message, **counts)

    def commit(t: float, att, rec):
        from .laws._coulomb import OPEN, SLIP, STICK

        prev = cur["state"]
        (u, y_all, tN, tT, R, pred), out, eq = att.value
        closed = _closed(fc, tN, y_all[:, 0], opts)
        duT = y_all[:, 1:] - prev.y[:, 1:]
        slip = np.where(closed[:, None], np.einsum("ijk,ik->ij", fc.tangents, duT), 0.0)
        nT = np.linalg.norm(tT, axis=1)
        pref = max(float(np.max(tN, initial=0.0)), 1e-300)
        mu_t = mu * history.friction_factor(t)
        saturated = nT >= mu_t * tN - 1e-6 * max(mu_t, 1e-300) * pref
        st = np.where(~closed, OPEN, np.where(saturated, SLIP, STICK))
        shear, _ = forces(tN, tT)
        w = fc.weights
        tang = np.sum(w[:, None] * shear, axis=0)
        step = DistributedFrictionStep(
            t=float(t), u=u, pressure=tN[own].copy(), gap=y_all[own, 0].copy(), traction_t=tT[own].copy(),
            slip=slip[own].copy(), state=st[own].copy(), normal_force=float(np.sum(w * tN)), tangential_force=tang,
            contact_force=tang + np.sum((w * tN)[:, None] * fc.normals, axis=0), outer_iterations=int(out.outer),
            newton_iterations=int(out.newton), cutbacks=rec.step_cutbacks, equilibrium=float(eq))
        records.append(step)
        cur["state"] = _State(float(t), u, y_all, tN, tT, R, prev.slip_total + slip, pred)
        return step

    run = step_through(history.times, attempt, commit, max_cutbacks=opts.max_cutbacks, factor=opts.cutback_factor,
                       recoverable=(), what=f"distributed frictional contact {algorithm}",
                       advice="use more load steps, a smaller penalty_scale or algorithm='ssn'",
                       done_message="converged")
    status, message = run.status, run.message
    if fc.ncand == 0 and status > 0:
        status = ContactStatus.NO_CONTACT
        message = ("the body never reaches the obstacle; check the loads, the obstacle or the contact boundary "
                   f"(smallest clearance {-float(np.max(np.where(fc.movable, fc.gmax_t, -np.inf))):.4g})")
    t_end = time.perf_counter()
    body = dc.body
    return DistributedFrictionSolution(
        status=status, message=message, steps=records, algorithm=algorithm, penalty=pen_name, friction=mu,
        outer_iterations=run.outer_iterations, newton_iterations=run.newton_iterations, cutbacks=run.cutbacks,
        linear_solves=fc.linear_solves, eps_n=eps_n, eps_t=eps_t, h=fc.h, nodes=body.owned_points(),
        global_nodes=body.owned_mesh_nodes(), points=dc.points, normals=dc.normals, weights=dc.weights,
        piece=body.piece, point_nodes=dc.point_node,
        timings={"setup_s": fc.setup_seconds, "factor_s": fc.factor_seconds, "total_s": t_end - t_start},
        extra={"candidates": fc.ncand, "dofs": int(dc.n_global), "linear_solver": dc.extra()["linear_solver"],
               "strategy": "distributed", **fc.stats()})
