r"""Frictionless contact at small deformation distributed over MPI ranks on PETSc.

The same discrete problem as :mod:`alcontact.contact.systems._krylov` (linearized gap
(6.15), nodal weights, the laws :math:`t_N = p'(g/\eta, \lambda)` of the outer loops),
with the displacement a distributed vector and every linear solve a PETSc KSP on an
``MPIAIJ`` matrix:

.. math::

    R(u) = K u - f + B^T (w \circ t_N(g(u))) \;(\text{free rows}), \qquad
    J = K + B^T \operatorname{diag}(w \circ dt_N/dg)\, B ,

with Dirichlet rows and columns of ``K`` and ``J`` eliminated (``MatZeroRowsColumns``,
the prescribed values held in ``u``; every Newton step is set to 0 on those rows, where a
preconditioned Krylov iterate is not exactly 0). The contact term of ``J`` is one ``d x d`` block
per contact point at its own node, so every rank adds the blocks of the points it owns
to rows it owns: no communication.

The Newton matrices, as on the serial Krylov path (:mod:`~alcontact.contact.systems._krylov`): one
``MPIAIJ`` matrix ``J`` with the pattern of ``K`` and of every contact block, whose values are
rewritten for each Newton step, and one KSP on it, so that PCGAMG keeps the prolongators of
its first hierarchy and recomputes only the Galerkin coarse operators
(``pc_gamg_reuse_interpolation``, :data:`GAMG_DEFAULTS`; ``extra["gamg_setups"]`` counts the
hierarchies built, ``"gamg_updates"`` the Galerkin updates). A Newton matrix equal to the last
one (no contact stiffness changed: the same active set under Algorithm 6.1's piecewise-linear law)
is not assembled again and keeps its preconditioner (``"pc_reused"``): the Galerkin update of an
identical matrix would rebuild the same preconditioner (``docs/benchmarks/distributed.md`` measures
what it saves). A matrix that did change is first solved with the preconditioner of the last update
(*lagged*, ``"pc_lagged"``: CG on the new matrix, no Galerkin products) while CG's iterations per decade
stay within :data:`LAG_GROWTH` times those of the first solve after that update; past it, or when CG fails
with it (``"lag_failures"``; a lagged solve is capped at twice the allowed iterations), the next solve
updates it. The contact term changes a few rows of the matrix; at 1M DOFs (3D Hertz, 1 rank) the nine
updates took about three quarters of the Newton phase; lagged, it takes two. The Chebyshev smoothers
estimate the spectrum of their own operator at each update (``pc_gamg_use_sa_esteig
false``: GAMG's estimates are those of the first matrix, with which CG met an indefinite
preconditioner once the springs were stiff), and the finest level's smoother is point-block
Jacobi (:data:`FINE_SMOOTHER`): each contact spring :math:`k_i \nu_i \nu_i^T` lies in its
node's ``d x d`` diagonal block, which point-block Jacobi inverts exactly, the role the
Householder reflections of stiff springs play on the serial path. The Newton steps are
inexact with the serial path's forcing terms (1e-3 down to 1e-6, tightened in the last step
to reach the Newton tolerance); the direct KSP (MUMPS) refactorizes the same pattern
numerically.

Ownership: the mesh is read and partitioned on rank 0
(:class:`alcontact.distributed.DistributedElasticity`: METIS, each rank assembles its
elements with scikit-fem into the ``MPIAIJ`` stiffness); a contact point belongs to the
rank that owns its node, which evaluates its gap and normal (the obstacle is sent to
every rank) and holds its weight. The state the outer loops iterate on is the owned
part of ``u`` (a NumPy array of ``dim * n_owned`` entries): opaque to them.

What the :class:`~alcontact.contact.systems._protocol.ContactSystem` protocol assumes, and
how it is met here: the outer loops (:func:`~alcontact.contact.algorithms._frictionless.run_al`,
``run_penalty``, ``run_ssn``) handle the candidates' multipliers, gaps and tractions as
NumPy arrays over *all* candidates (``cand``, :meth:`gaps`, ``out.g``, ``out.t``,
:meth:`initial_multipliers`) and take their maxima, sums and "any" tests with NumPy. These
arrays are therefore replicated on every rank: each rank computes its own candidates'
gaps and an ``Allgatherv`` assembles the candidate vector (a surface array, ``O(n^{(d-1)/d})``
entries, never one of the volume's ``n``). Every rank then takes the same decisions from
the same numbers, which is what the MPI reductions of a distributed loop would give, and
the serial loops run unchanged. The Newton solve of each subproblem
(:func:`alcontact.optim.newton`) sees the owned part of ``u``; every number it decides on
(:meth:`_Subproblem.measure`, ``merit``, ``slope``, the finiteness tests, the
"negligible step" test) is reduced over the ranks first, and the step that would compare
local maxima (the full step on a flat merit) is switched off.
"""

from __future__ import annotations

import logging
import pickle
import time

import numpy as np

from ...errors import InputError
from ...optim import LineSearch, NewtonSettings, NewtonSystem, newton
from ..algorithms._subproblem import NewtonOutcome, subproblem_outcome
from ..kinematics._points import _element_size
from ..problem._loading import component_fields
from ._krylov import _FORCING_MAX, _FORCING_MIN, _FORCING_SLOW, _FORCING_START, INEXACT_DOFS, INEXACT_FIRST_TOL

__all__ = ["DistributedContact", "DistributedFrictionalContact"]

logger = logging.getLogger(__name__)

#: Newton tolerance floor of the distributed subproblems (KSP solves and round-off of :math:`Ku`, as on
#: the serial Krylov path)
_NEWTON_TOL_FLOOR = 1e-11
#: the Newton settings: a trial whose relative residual (``measure``, reduced over the ranks) decreases is
#: accepted, the rank-independent form of the serial "full step on a flat merit" (which compares local maxima of
#: the residual and is off here); without it the merit, flat to round-off near the solution of a
#: displacement-driven problem, accepted steps of 1e-5 and the Newton stalled (flat punch, semi-smooth Newton:
#: relative residual 1.2e-7 after 20 iterations)
_SETTINGS = NewtonSettings(line_search=LineSearch(full_step=False, measure_decrease=True))
#: the inner augmented Lagrangian of the semi-smooth Newton reference: relative update and budget
_UZAWA_TOL = 1e-10
#: relative (true) residual of the CG + GAMG solves of the Newton systems
_KSP_RTOL = 1e-10
#: GAMG options of the Newton solves (the problem file's ``petsc_options`` override them; module doc): keep the
#: prolongators of the first hierarchy and recompute only the Galerkin coarse operators when the values of the
#: Newton matrix change, and let every Chebyshev smoother estimate the spectrum of its own operator (the estimates
#: GAMG hands over from its prolongator smoothing are those of the first matrix: with them CG met an indefinite
#: preconditioner as soon as the contact springs were stiff)
GAMG_DEFAULTS = {"pc_gamg_reuse_interpolation": "true", "pc_gamg_use_sa_esteig": "false"}
#: PC of the finest level's Chebyshev smoother, unless ``petsc_options`` name ``mg_levels_pc_type``: point-block
#: Jacobi inverts each node's ``d x d`` block, where each contact spring lives (module doc)
FINE_SMOOTHER = "pbjacobi"
_UZAWA_MAXITER = 200
#: a Newton matrix whose values changed is solved with the preconditioner of the last GAMG update (lagged:
#: CG on the new matrix, no Galerkin products) while the lagged solves take at most this many times the CG
#: iterations per decade of the first solve after that update; then the next solve updates it (``lag``)
LAG_GROWTH = 1.5


class _EqualityLaw:
    r"""The law of the active-set step: :math:`t = \mu + c\,g` on the active candidates, 0 elsewhere."""

    def __init__(self, active: np.ndarray, c: float):
        self.active, self.c = np.asarray(active, dtype=bool), float(c)

    def traction(self, g, mu):
        return np.where(self.active, mu + self.c * g, 0.0)

    def energy(self, g, mu):
        return np.where(self.active, mu * g + 0.5 * self.c * g * g, 0.0)

    def stiffness(self, g, mu):
        return np.where(self.active, self.c, 0.0)


class DistributedContact:
    """Frictionless small-deformation contact of a linear elastic P1 body against a rigid master, on N ranks.

    Implements :class:`~alcontact.contact.systems._protocol.ContactSystem` (module doc for the
    arrays that are replicated).

    Parameters
    ----------
    problem : ContactProblem, callable or None
        The problem on rank 0 (one linear elastic body with a P1 triangle or tetrahedron
        mesh, one rigid master, small kinematics), or a function without arguments that builds
        it there (then released once its loads, supports and contact points are distributed,
        before the assembly); ``None`` on the other ranks.
    comm : mpi4py communicator
    parts : ndarray of int, optional
        Rank of each element (on rank 0) instead of METIS (e.g. to force a cut through the contact zone).
    ksp : {"gamg", "direct"}
        CG + GAMG with the rigid-body near-null space, or PETSc's direct solver (MUMPS, else SuperLU_dist).
    options : dict, optional
        PETSc options passed through (names without the dash).
    margin : float
        Candidate rule of :class:`~alcontact.contact.kinematics._points.ContactPoints`.
    forcing : bool
        Inexact Newton steps (forcing terms) with the iterative KSP.
    lag : bool
        With the iterative KSP: solve a changed Newton matrix with the last GAMG update's
        preconditioner while CG's rate holds (:data:`LAG_GROWTH`; ``extra()["pc_lagged"]``),
        instead of a Galerkin update for every changed matrix.
    history : LoadHistory, optional
        On rank 0: ramped supports and loads (sent to every rank); each rank keeps its part of
        every load component (:func:`~alcontact.contact.problem._loading.component_fields`) and
        :meth:`at_time` sets a step's loads and prescribed values.
    t : float
        Step time of the first state (1: the problem as given).

    Attributes
    ----------
    h : float
    cand : ndarray of int
        Candidates, global contact-point numbers (replicated on every rank).
    linear_solves, ksp_iterations : int
        KSP solves on this system and their iterations.
    """

    # ---- ContactSystem: declared capabilities ("not available" values, as ContactPoints declares them)
    physical_stopping = False
    warm_penalty_start = False
    penalty_continuation = False
    factorizations = 0
    gamg_setups = 0

    def __init__(self, problem, *, comm, parts=None, ksp: str = "gamg", options: dict | None = None,
                 margin: float = 0.25, forcing: bool = True, history=None, t: float = 1.0, frictional: bool = False,
                 lag: bool = True):
        from mpi4py import MPI

        from ...distributed import DistributedElasticity, collective, release_memory
        from ...linalg import petsc

        PETSc = petsc()
        t0 = time.perf_counter()
        self.comm, self.MPI, self.PETSc = comm, MPI, PETSc
        if ksp not in ("gamg", "direct"):
            raise InputError(f"ksp={ksp!r}; allowed: 'gamg', 'direct'.")
        self.ksp_kind, self.options = ksp, dict(options or {})
        #: inexact Newton (forcing terms) on the iterative KSP; the direct one solves exactly
        self.forcing = ksp == "gamg" and forcing
        self.carried_stiffness = None
        self.active_converged = True
        self.active_residual = float("nan")
        self.linear_solves = 0
        self.ksp_iterations = 0
        self.ksp_setups = 0
        self.pc_reused = 0  # Newton solves whose J was the matrix of the last preconditioner set-up
        self.lag = lag
        self.pc_lagged = 0  # Newton solves of a changed J preconditioned by an earlier update (solve_newton)
        self.lag_failures = 0  # of them, those where CG failed and the preconditioner was updated after all
        # every collective call (bcast, scatter) sits between guarded blocks: a rank that fails inside a block
        # reaches the block's agreement, never leaves the others waiting in a call it skipped
        head = None
        with collective(comm, "checking the problem for the distributed path"):
            if comm.rank == 0:
                if callable(problem) and not hasattr(problem, "model"):
                    problem = problem()
                # an obstacle or a load history that cannot be sent fails here
                head = pickle.dumps((*self._check(problem, frictional), self._check_history(history)))
        head = comm.bcast(head, root=0)
        with collective(comm, "receiving the material and the obstacle"):
            material, obstacle, history = pickle.loads(head)
        self.history = history
        order = comm.bcast(int(getattr(problem.model, "order", 1)) if comm.rank == 0 else None, root=0)
        self.body = DistributedElasticity(problem.model.mesh if comm.rank == 0 else None, material, comm=comm,
                                          parts=parts, order=order, checked_mesh=True,  # by problem.model
                                          element_nodes=problem.model.scalar_dofs.element_dofs
                                          if comm.rank == 0 and order == 2 else None)
        self.dim = dim = self.body.dim
        piece = self.body.piece
        self.n_own = piece.node_range[1] - piece.node_range[0]
        self.dof_start = dim * piece.node_range[0]
        self.n_global = dim * piece.n_nodes
        ranges = comm.allgather(piece.node_range)
        pieces = h = None
        with collective(comm, "distributing loads, supports and contact points"):
            if comm.rank == 0:
                pieces = self._pieces(problem, history, ranges)
                h = _element_size(problem.model, problem.contact_boundary, problem.obstacle)
        mine = comm.scatter(pieces, root=0)
        del pieces
        problem = None  # rank 0 holds nothing of the whole mesh from here on (when the caller holds no reference)
        self.body.forget_numbering()
        if comm.rank == 0:
            release_memory()
        self.h = float(comm.bcast(h, root=0))
        self.f_parts = mine["f"]  # (ncomp, dim * n_own): the load of each component at amplitude 1
        self.fixed = mine["fixed"]  # local DOF numbers
        self.value_parts = mine["values"]  # (ncomp, nfixed): the prescribed values of each component
        self.f = self.f_parts[0].copy()
        self.fixed_values = self.value_parts[0].copy()
        self.point_node = mine["node"]  # local node of each owned contact point
        self.points = mine["points"]  # (m_r, dim) coordinates
        self.weights = mine["weights"]
        free = np.ones(dim * self.n_own, dtype=bool)
        free[self.fixed] = False
        self.free = free
        self.n_free_global = int(comm.allreduce(int(free.sum()), op=MPI.SUM))
        with collective(comm, "evaluating the obstacle at the contact points"):
            gap0, nu = obstacle.evaluate(self.points) if self.points.shape[0] else (np.zeros(0), np.zeros((0, dim)))
            self.gap0 = np.asarray(gap0, dtype=float).reshape(-1)
            self.normals = np.asarray(nu, dtype=float).reshape(-1, dim)
        self.point_dofs = dim * self.point_node[:, None] + np.arange(dim)  # (m_r, dim) local DOFs
        self.coef = np.where(free[self.point_dofs], -self.normals, 0.0)  # the rows -nu_i^T on the free DOFs
        self.movable = np.linalg.norm(self.coef, axis=1) > 1e-12
        counts = np.array(comm.allgather(self.points.shape[0]), dtype=np.int64)
        self.point_offset = int(np.sum(counts[:comm.rank]))
        self.n_points = int(counts.sum())
        self._setup_matrices()
        self.margin = margin
        self.cand = np.empty(0, dtype=np.int64)
        self._my_pos = self._my_pt = np.empty(0, dtype=np.int64)
        self.at_time(t)
        self.setup_seconds = time.perf_counter() - t0

    # ------------------------------------------------------------ set-up (rank 0 reads, all ranks own)
    @staticmethod
    def _check(problem, frictional: bool = False):
        from ...fem import LinearElasticity
        from ..problem import ContactProblem

        if not isinstance(problem, ContactProblem):
            raise InputError(f"the distributed contact solve needs a ContactProblem on rank 0; got "
                             f"{type(problem).__name__}.")
        model = problem.model
        what = []
        if not isinstance(model, LinearElasticity) or getattr(model, "order", 1) not in (1, 2) or \
                getattr(model, "axisymmetric", False) or getattr(model, "volumetric", "full") != "full":
            what.append("a linear elastic body with P1 or P2 elements (no mixed, axisymmetric or hyperelastic "
                        "body)")
        if getattr(problem, "kinematics", "small") != "small":
            what.append("small deformation (kinematics = 'small')")
        if float(problem.friction or 0.0) > 0 and not frictional:
            what.append("frictionless contact (friction = 0; Coulomb friction: solve_distributed_friction)")
        if len(problem.pairs) != 1 or not problem.pairs[0].master.rigid:
            what.append("one contact pair against a rigid obstacle")
        if what:
            raise InputError("the distributed (MPI) contact path solves " + "; ".join(what) + " so far; run this "
                             "problem as one process (without mpirun).")
        return model.material, problem.obstacle

    @staticmethod
    def _check_history(history):
        from ..problem import LoadHistory

        if history is not None and not isinstance(history, LoadHistory):
            raise InputError(f"history must be a LoadHistory or None; got {type(history).__name__}.")
        return history

    def _pieces(self, problem, history, ranges):
        """On rank 0: the loads and prescribed values (per component of the history, rows ``(ncomp, ...)``), the
        supports and the contact points of every rank, in its local numbering."""
        model, dim = problem.model, self.body.dim
        new = self.body.numbering
        _, dmap = model.all_node_dofs()  # (n_nodes, dim) model DOFs of the mesh's nodes
        dist = np.empty(model.ndofs, dtype=np.int64)
        for c in range(dim):
            dist[dmap[:, c]] = dim * new + c
        if history is None:  # the problem's own supports and loads (one component, amplitude 1)
            fixed, values = problem.dirichlet()
            fixed = np.asarray(fixed, dtype=np.int64)
            values = np.zeros(fixed.size) if values is None else \
                np.broadcast_to(np.asarray(values, float), fixed.shape)
            parts = [(values, problem.load_vector())]
        else:  # the base and every case of the history at amplitude 1 (component_fields, as the serial steps)
            fixed, parts = component_fields(problem, history)
            fixed = np.asarray(fixed, dtype=np.int64)
        f = np.zeros((len(parts), model.ndofs))
        for k, (_, load) in enumerate(parts):
            f[k, dist] = load
        values = np.stack([np.broadcast_to(np.asarray(fv, float), fixed.shape) for fv, _ in parts])
        del parts
        fixed_d = dist[fixed]
        pts, cdofs = model.node_dofs(problem.contact_boundary)
        w = model.boundary_weights(problem.contact_boundary)
        cnode = dist[cdofs[:, 0]] // dim  # distributed node of each contact point
        order = np.argsort(cnode, kind="stable")
        pieces = []
        for (a, b) in ranges:
            sel = (fixed_d >= dim * a) & (fixed_d < dim * b)
            on = order[(cnode[order] >= a) & (cnode[order] < b)]
            pieces.append({"f": f[:, dim * a:dim * b].copy(), "fixed": fixed_d[sel] - dim * a,
                           "values": np.array(values[:, sel], dtype=float), "node": cnode[on] - a,
                           "points": np.ascontiguousarray(pts[on], dtype=float), "weights": np.asarray(w[on], float)})
        return pieces

    def _rows(self, local: np.ndarray) -> np.ndarray:
        return (self.dof_start + np.asarray(local, dtype=np.int64)).astype(self.PETSc.IntType)

    def _setup_matrices(self) -> None:
        r"""The one matrix ``J`` (``MPIAIJ``: ``K`` with the supported rows and columns eliminated, then the contact
        blocks of each Newton step), the supported rows of ``K`` (:meth:`matvec`), the KSP and the near-null space.

        ``J`` differs from the eliminated stiffness :math:`K_c` only in the ``d x d`` blocks of the
        contact points, whose :math:`K_c` values are kept (``blocks0``): no second copy of the
        stiffness is held. ``Kfix``: the rows of ``K`` of the supported DOFs (a surface of rows), so
        that :math:`Kx` is :math:`K_c x` plus the coupling of the supported DOFs (:meth:`matvec`).
        """
        from ...linalg import configure_ksp, direct_package, near_null_space

        PETSc = self.PETSc
        t0 = time.perf_counter()
        # the d x d block of every contact point in the pattern (an entry of K that cancels exactly, e.g. the
        # x-y coupling of a node of a structured tetrahedral mesh, is not stored by the assembly)
        K, _ = self.body.assemble(np.zeros(self.dim), node_blocks=self.point_node)
        K.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, True)
        comm = K.getComm()
        fixed_rows = self._rows(self.fixed)
        iscol = PETSc.IS().createStride(self.dim * self.n_own, first=self.dof_start, step=1, comm=comm)
        isrow = PETSc.IS().createGeneral(fixed_rows, comm=comm)
        self.Kfix = K.createSubMatrix(isrow, iscol)  # rows of the supported DOFs, in the order of self.fixed
        for obj in (isrow, iscol):
            obj.destroy()
        self._fx, self._fy = self.Kfix.createVecs()  # (columns: the DOF layout, rows: the supported DOFs)
        K.zeroRowsColumns(fixed_rows, diag=1.0)
        K.setOption(PETSc.Mat.Option.SPD, True)
        # the rows of the contact points' DOFs of K_c: J x on those rows would hold the contact springs, whose
        # subtraction cancels digits (k |c x| is 1e3 times the forces at the default penalty)
        iscol = PETSc.IS().createStride(self.dim * self.n_own, first=self.dof_start, step=1, comm=comm)
        isrow = PETSc.IS().createGeneral(self._rows(self.point_dofs.ravel()), comm=comm)
        self.Kpts = K.createSubMatrix(isrow, iscol)
        for obj in (isrow, iscol):
            obj.destroy()
        self._py = self.Kpts.createVecLeft()
        # the one Newton matrix: the values of every J are written into it (same nonzero pattern), so the KSP's
        # preconditioner sees one operator whose values change and GAMG keeps its prolongators (module doc)
        self.J = K
        d = self.dim
        self.blocks0 = np.empty((self.points.shape[0], d, d))
        for i, dofs in enumerate(self.point_dofs):
            rows = self._rows(dofs)
            self.blocks0[i] = K.getValues(rows, rows).reshape(d, d)
        self._k_in_J = np.zeros(self.points.shape[0])  # the contact stiffness of each owned point now in J
        self._pc_stale = False  # J changed since the KSP's preconditioner was set up (newton_matrix, solve_newton)
        # CG iterations per decade of the first solve after the last preconditioner update, and of the last
        # solve with a lagged one (solve_newton)
        self._fresh_rate: float | None = None
        self._lag_rate: float | None = None
        self.assembly_seconds = time.perf_counter() - t0
        n = self.comm.allreduce(int(self.fixed.size), op=self.MPI.SUM)
        if n == 0:
            raise InputError("no support holds the body: the distributed path needs supports that stop every "
                             "rigid motion (a body held by the obstacle alone runs as one process).")
        t1 = time.perf_counter()
        self.null = near_null_space(self.body.rigid_modes(), comm=K.getComm()) if self.ksp_kind == "gamg" else None
        if self.ksp_kind == "gamg":
            self.J.setNearNullSpace(self.null)
            self.ksp = configure_ksp(self.J, ksp_type="cg", pc_type="gamg", rtol=1e-10,
                                     options={**GAMG_DEFAULTS, **self.options}, near_null=self.null, defer_check=True)
            pc = self.ksp.getPC()
            levels = pc.getMGLevels()
            if levels > 1 and "mg_levels_pc_type" not in self.options:
                pc.getMGSmoother(levels - 1).getPC().setType(FINE_SMOOTHER)
            self._hierarchy = self.hierarchy()
            self.gamg_setups = 1
        else:
            pkg = direct_package()
            self.ksp = configure_ksp(self.J, ksp_type="preonly", pc_type="cholesky" if pkg == "mumps" else "lu",
                                     rtol=1e-12, options=self.options, factor_solver=pkg, defer_check=True)
        self.ksp_setups += 1
        self.factor_seconds = time.perf_counter() - t1
        self._vx, self._vy = K.createVecRight(), K.createVecRight()
        if np.unique(self.point_node).size != self.point_node.size:
            raise InputError("two contact points of one rank share a node: the distributed path takes one contact "
                             "boundary (one point per node); run this problem as one process.")

    def amplitudes(self, t: float) -> np.ndarray:
        """Amplitude of each load component at ``t``: 1 for the problem's own, then the history's cases."""
        return np.concatenate([[1.0], self.history.amplitudes(t)]) if self.history is not None else np.ones(1)

    def at_time(self, t: float) -> None:
        """Loads and prescribed values at the step time ``t``, its contact-free solution and candidates (as a
        serial step: each frictionless small-deformation step is an independent solve)."""
        a = self.amplitudes(t)
        self.t = float(t)
        self.f = a @ self.f_parts
        self.fixed_values = a @ self.value_parts
        self.newton_matrix(np.zeros(self.cand.size))  # J = K_c again: no contact springs
        self.u_free = self._solve_free()
        self.x_free = self.u_free
        self._select_candidates(self.local_gaps(self.u_free), self.margin)

    #: the first inexact subproblem's Newton tolerance, the serial Krylov path's
    inexact_first_tol = INEXACT_FIRST_TOL

    @property
    def inexact_subproblems(self) -> bool:
        """Solve (S) of Algorithms 6.1 / 6.3 inexactly above the serial Krylov path's size
        (:data:`~alcontact.contact.systems._krylov.INEXACT_DOFS`, the same rule and the same outer loop:
        the Newton tolerance of a subproblem follows the last multiplier change, the last one is solved to
        ``newton_tol``); with the iterative KSP only (MUMPS solves each Newton step exactly)."""
        return self.ksp_kind == "gamg" and self.n_free_global > INEXACT_DOFS

    def _ksp_solve(self, rhs: np.ndarray, rtol: float, *, lagged: bool = False) -> np.ndarray:
        """Solve with the current operator of the KSP; counted; a failed solve raises (collectively).
        ``lagged``: preconditioned by an earlier update (its rate is recorded for :meth:`_lag_holds`)."""
        ksp = self.ksp
        decades = max(-np.log10(rtol), 1.0)
        if self.ksp_kind == "gamg":
            # a lagged preconditioner gets twice the iterations its rate test allows, then it is updated
            cap = int(np.ceil(2.0 * LAG_GROWTH * self._fresh_rate * decades)) + 5 if lagged else 10_000
            ksp.setTolerances(rtol=float(rtol), atol=0.0, max_it=cap)
        self._vy.array[:] = rhs
        self._vx.set(0.0)
        ksp.solve(self._vy, self._vx)
        its, reason = int(ksp.getIterationNumber()), int(ksp.getConvergedReason())
        self.linear_solves += 1
        self.ksp_iterations += its
        if self.ksp_kind == "gamg":  # a hierarchy with other prolongators: GAMG built it from scratch
            now = self.hierarchy()
            if now != self._hierarchy:
                self.gamg_setups += 1
                self._hierarchy = now
        if self.linear_solves == 1:
            from ...linalg import report_unused_options

            given = {**GAMG_DEFAULTS, **self.options} if self.ksp_kind == "gamg" else self.options
            report_unused_options(ksp.getOptionsPrefix() or "", given,
                                  reported=None if self.comm.rank == 0 else set(given))
        if reason < 0:
            raise np.linalg.LinAlgError(f"PETSc KSP {ksp.getType()} / PC {ksp.getPC().getType()} did not converge "
                                        f"(reason {reason}, {its} iterations)")
        if self.ksp_kind == "gamg":
            rate = its / decades  # CG iterations per decade
            if lagged:
                self._lag_rate = rate
            elif self._fresh_rate is None and its > 0:  # (a zero right-hand side takes no iteration: no rate)
                self._fresh_rate, self._lag_rate = rate, None
        return self._vx.array.copy()

    def hierarchy(self) -> tuple:
        """Ids of the GAMG prolongators (:func:`alcontact.linalg.mg_hierarchy`; ``()`` without GAMG)."""
        from ...linalg import mg_hierarchy

        return mg_hierarchy(self.ksp) if self.ksp_kind == "gamg" else ()

    def smoothers(self) -> list[str]:
        """PC type of the smoother of each GAMG level, coarsest first (``[]`` without GAMG)."""
        from ...linalg import mg_smoothers

        return mg_smoothers(self.ksp) if self.ksp_kind == "gamg" else []

    def matvec(self, x: np.ndarray) -> np.ndarray:
        r""":math:`K x` (owned rows) for the owned part ``x`` of a distributed vector.

        From ``J``: :math:`K_c x` is :math:`J x` on the rows without contact points and ``Kpts x`` on theirs
        (the rows of :math:`K_c` at the contact points, a surface of rows); on the free rows
        :math:`K x = K_c x + K_{fd} x_d` (:math:`K_{fd} = K_{df}^T`, the transpose of the supported rows),
        on the supported rows :math:`K x` is those rows times ``x``.
        """
        self._vx.array[:] = x
        self.J.mult(self._vx, self._vy)
        y = self._vy.array.copy()
        self.Kpts.mult(self._vx, self._py)  # the contact points' rows of K_c x, without the springs in J
        y[self.point_dofs.ravel()] = self._py.array
        self._fx.array[:] = x
        self.Kfix.mult(self._fx, self._fy)  # the supported rows of K x
        fixed_rows = self._fy.array.copy()
        self._fy.array[:] = x[self.fixed]
        self.Kfix.multTranspose(self._fy, self._fx)  # K_fd x_d on the free rows
        y[self.free] += self._fx.array[self.free]
        y[self.fixed] = fixed_rows
        return y

    def _solve_free(self) -> np.ndarray:
        """The contact-free displacement (owned part), prescribed values included."""
        ud = np.zeros(self.dim * self.n_own)
        ud[self.fixed] = self.fixed_values
        b = self.f - self.matvec(ud)
        b[self.fixed] = self.fixed_values
        t0 = time.perf_counter()
        x = self._ksp_solve(b, 1e-12)  # the KSP's operator holds the values of Kc
        x[self.fixed] = self.fixed_values
        self.reference_seconds = time.perf_counter() - t0 + self.factor_seconds
        self.b_lifted = self.allmax(np.abs(b[self.free]))
        self.load_scale = self.allmax(np.abs(self.f[self.free]))
        if not self.allbool(np.all(np.isfinite(x))):
            raise InputError("the contact-free solution is not finite; check loads and supports.")
        return x

    # ------------------------------------------------------------ reductions and replicated arrays
    def allmax(self, a) -> float:
        return float(self.comm.allreduce(float(np.max(a, initial=0.0)), op=self.MPI.MAX))

    def allsum(self, value: float) -> float:
        return float(self.comm.allreduce(float(value), op=self.MPI.SUM))

    def allbool(self, ok: bool) -> bool:
        """``ok`` on every rank."""
        return bool(self.comm.allreduce(bool(ok), op=self.MPI.LAND))

    def allgather_points(self, local: np.ndarray) -> np.ndarray:
        """The values of every contact point (rank-major global numbering) from the owned ones."""
        parts = self.comm.allgather(np.asarray(local))
        return np.concatenate(parts) if parts else np.zeros(0)

    def local_gaps(self, x: np.ndarray) -> np.ndarray:
        """Linearized gaps (6.15) of the owned contact points for the owned displacement ``x``."""
        return self.gap0 - np.einsum("ij,ij->i", self.normals, x[self.point_dofs])

    def _select_candidates(self, g: np.ndarray, margin: float) -> None:
        """The candidate rule of :meth:`ContactPoints._select_candidates` with global maxima."""
        pinned = ~self.movable & (g > 0.0)
        bad = self.comm.allgather(self.points[np.flatnonzero(pinned)[0]].tolist() if np.any(pinned) else None)
        bad = [b for b in bad if b is not None]
        if bad:
            raise InputError(f"contact point {bad[0]} is held by a Dirichlet condition in the normal direction but "
                             "penetrates the obstacle; move the obstacle or release that support.")
        gmax = float(self.comm.allreduce(float(np.max(g[self.movable], initial=-np.inf)), op=self.MPI.MAX))
        self.max_free_penetration = gmax
        self.g_free = g
        if gmax > 0:
            thr = -max(margin * gmax, 1e-12 * self.h)
            local = np.flatnonzero(self.movable & (g > thr))
        else:
            local = np.empty(0, dtype=np.int64)
        self.cand = np.empty(0, dtype=np.int64)
        self._add_candidates(local)

    def _add_candidates(self, local_new: np.ndarray) -> None:
        """Append the owned points ``local_new`` of every rank (rank-major) to the replicated ``cand``."""
        new = self.allgather_points(self.point_offset + np.asarray(local_new, dtype=np.int64)).astype(np.int64)
        self.cand = np.concatenate([self.cand, new]).astype(np.int64)
        mine = (self.cand >= self.point_offset) & (self.cand < self.point_offset + self.points.shape[0])
        self._my_pos = np.flatnonzero(mine)  # where this rank's candidates sit in cand
        self._my_pt = self.cand[mine] - self.point_offset  # their owned point numbers
        # the order in which Allgatherv returns the candidates' values: rank-major, by position in cand
        self._perm = self.allgather_points(self._my_pos).astype(np.int64)

    def extend(self, x: np.ndarray, tol: float) -> int:
        """Add the non-candidate points whose gap at ``x`` exceeds ``tol`` (as the serial driver); their number."""
        outside = np.ones(self.points.shape[0], dtype=bool)
        outside[self._my_pt] = False
        add = np.flatnonzero(outside & self.movable & (self.local_gaps(x) > tol))
        total = int(self.comm.allreduce(int(add.size), op=self.MPI.SUM))
        if total:
            logger.info("adding %d contact candidates that penetrate", total)
            self._add_candidates(add)
        return total

    def replicate(self, mine: np.ndarray) -> np.ndarray:
        """The candidate vector (replicated) from this rank's candidates' values."""
        out = np.empty(self.cand.size)
        out[self._perm] = self.allgather_points(mine)
        return out

    def contact_force(self, x_shape: int, wt_cand: np.ndarray) -> np.ndarray:
        r"""``B^T (w t)``, owned part: the forces :math:`-\nu_i w_i t_i` on the free DOFs of the candidates."""
        out = np.zeros(x_shape)
        np.add.at(out, self.point_dofs[self._my_pt].ravel(),
                  (self.coef[self._my_pt] * wt_cand[self._my_pos][:, None]).ravel())
        return out

    def newton_matrix(self, k_cand: np.ndarray):
        r""":math:`J = K + B^T \operatorname{diag}(k) B`, supported rows and columns eliminated, written into the
        one Newton matrix ``self.J``: the block of each owned contact point whose stiffness changed is set to its
        :math:`K_c` block plus :math:`k_i c_i c_i^T` (``c_i`` the row :math:`-\nu_i^T` on the free DOFs)."""
        PETSc = self.PETSc
        J = self.J
        k = np.zeros(self.points.shape[0])
        k[self._my_pt] = np.asarray(k_cand, dtype=float)[self._my_pos]
        c = self.coef
        changed = np.flatnonzero(k != self._k_in_J)
        for i in changed:
            rows = self._rows(self.point_dofs[i])
            J.setValues(rows, rows, (self.blocks0[i] + k[i] * np.outer(c[i], c[i])).ravel(),
                        addv=PETSc.InsertMode.INSERT_VALUES)
        # an unchanged J (the same active set under a piecewise-linear law: most Newton steps) keeps its
        # preconditioner; assembling it would mark it changed and GAMG would redo its Galerkin products
        if not self.allbool(changed.size == 0):
            J.assemble()
            self._pc_stale = True
        self._k_in_J = k
        return J

    def solve_newton(self, J, rhs: np.ndarray, rtol: float) -> np.ndarray:
        """``J dx = rhs`` with the KSP: CG on the new values of ``J``, preconditioned by the last GAMG update
        while its rate holds (:data:`LAG_GROWTH`), else by a new Galerkin update for ``J``."""
        t0 = time.perf_counter()
        try:
            if self._pc_stale and self.ksp_kind == "gamg" and self.lag and self._lag_holds():
                self.ksp.getPC().setReusePreconditioner(True)  # PCSetUp leaves the preconditioner as it is
                self.pc_lagged += 1
                try:
                    return self._ksp_solve(rhs, rtol, lagged=True)
                except np.linalg.LinAlgError:  # CG broke down or diverged with the old preconditioner: update it
                    self.lag_failures += 1
            if self._pc_stale:
                # the same operator again: KSPSolve updates its preconditioner only after KSPSetOperators, and with
                # the same matrix object PCGAMG sees SAME_NONZERO_PATTERN (it keeps the prolongators with
                # reuse_interpolation); not when J has not changed since the last set-up (newton_matrix)
                self.ksp.getPC().setReusePreconditioner(False)
                self.ksp.setOperators(J)
                self.ksp_setups += 1
                self._pc_stale = False
                self._fresh_rate = None
            else:
                self.pc_reused += 1
            return self._ksp_solve(rhs, rtol)
        finally:
            self.solve_seconds_total = getattr(self, "solve_seconds_total", 0.0) + time.perf_counter() - t0

    def _lag_holds(self) -> bool:
        """Whether the last lagged solve's CG iterations per decade of residual reduction stayed within
        :data:`LAG_GROWTH` times those of the first solve after the last update (same on every rank: the
        iteration counts are the KSP's, collective)."""
        if self._fresh_rate is None:
            return False
        return self._lag_rate is None or self._lag_rate <= LAG_GROWTH * self._fresh_rate

    # ------------------------------------------------------------ the ContactSystem protocol
    def start(self) -> np.ndarray:
        return self.x_free.copy()

    def gaps(self, x: np.ndarray) -> np.ndarray:
        return self.replicate(self.local_gaps(x)[self._my_pt])

    def subproblem(self, law, lam, x0, *, tol: float, maxiter: int) -> NewtonOutcome:
        tol = max(tol, _NEWTON_TOL_FLOOR)
        out = newton(_Subproblem(self, law, np.asarray(lam, dtype=float)), x0, tol=tol, maxiter=maxiter,
                     settings=_SETTINGS)
        return subproblem_outcome(out, out.state[0], out.state[1])

    def scale_forces(self, x: np.ndarray, factor: float) -> np.ndarray:
        """Contact forces scaled by ``factor``: ``x_free + factor (x - x_free)`` (linearity)."""
        return self.x_free + factor * (x - self.x_free)

    def solve_active(self, active, lam, x, c):
        r"""Active-set step of the semi-smooth Newton reference: :math:`g_A = 0` by an inner augmented
        Lagrangian (Uzawa) iteration with penalty ``c`` (as the serial Krylov path), each step a Newton
        solve of the equality-constrained subproblem."""
        active = np.asarray(active, dtype=bool)
        lam_new = np.zeros(self.cand.size)
        if not np.any(active):
            self.active_converged = True
            x = self.x_free.copy()
            return x, lam_new, self.gaps(x)
        law = _EqualityLaw(active, c)
        mu = np.where(active, np.maximum(lam, 0.0), 0.0)
        change = np.inf
        for _ in range(_UZAWA_MAXITER):
            out = self.subproblem(law, mu, x, tol=1e-12, maxiter=20)
            if not out.converged:
                break
            x = out.state
            mu_next = np.where(active, mu + c * out.g, 0.0)
            change = float(np.max(np.abs(mu_next - mu), initial=0.0)) / max(float(np.max(np.abs(mu_next),
                                                                                      initial=0.0)), 1e-300)
            mu = mu_next
            if change <= _UZAWA_TOL:
                break
        self.active_converged = bool(change <= _UZAWA_TOL)
        self.active_residual = change
        return x, mu, self.gaps(x)

    def initial_multipliers(self) -> np.ndarray:
        return np.zeros(self.cand.size)

    def initial_active(self, lam, g, c) -> np.ndarray:
        return (np.asarray(lam, dtype=float) + c * np.asarray(g, dtype=float)) > 0

    def entry_multipliers(self, lam, law, *, penalty_start: bool = False):
        return lam

    def multiplier_step(self, law, lam, out):
        return None

    def start_multiplier_step(self, law, lam, out):
        return None

    # ------------------------------------------------------------ reporting
    def timings(self) -> dict:
        """Wall seconds of the set-up (``setup_s``: all of it; ``distribute_s``: partitioning and sending the mesh,
        rank 0's serial part; ``assembly_s``, ``factor_s``: the KSP set-up; ``linear_solve_s``: the reference
        solve)."""
        return {"setup_s": self.setup_seconds, "factor_s": self.factor_seconds, "assembly_s": self.assembly_seconds,
                "linear_solve_s": self.reference_seconds, "distribute_s": self.body.seconds.get("distribute", 0.0)}

    def extra(self) -> dict:
        return {"linear_solver": "petsc" if self.ksp_kind == "gamg" else "petsc-direct", "strategy": "distributed",
                "ranks": int(self.comm.size), "ksp_iterations": int(self.ksp_iterations),
                "ksp_setups": int(self.ksp_setups), "gamg_setups": int(self.gamg_setups),
                "gamg_updates": int(self.ksp_setups - self.gamg_setups) if self.ksp_kind == "gamg" else 0,
                "pc_reused": int(self.pc_reused), "pc_lagged": int(self.pc_lagged),
                "lag_failures": int(self.lag_failures), "fine_smoother": (self.smoothers() or [""])[-1]}


class _Subproblem(NewtonSystem):
    r"""Subproblem (S) on the owned displacement: :math:`R(u) = Ku - f + B^T(w \circ t_N(g(u)))` (module doc).

    State ``(g, t, R, Pi)`` with ``g``, ``t`` replicated over the candidates. Relative residual
    :math:`\max|R|` (over every rank) over the largest applied load or contact force, as
    :class:`~alcontact.contact.systems._krylov._FullSpaceSubproblem`.
    """

    def __init__(self, dc: DistributedContact, law, lam):
        self.dc, self.law, self.lam = dc, law, lam
        self.w = dc.replicate(dc.weights[dc._my_pt])
        self.scale = None
        self.fscale = 1e-300
        self.forcing = _FORCING_START
        self.tol_k = _NEWTON_TOL_FLOOR

    def evaluate(self, x):
        dc = self.dc
        Kx = dc.matvec(x)
        g = dc.gaps(x)
        t = np.asarray(self.law.traction(g, self.lam), dtype=float)
        R = Kx - dc.f + dc.contact_force(x.size, self.w * t)
        R[dc.fixed] = 0.0
        energy = float(np.sum(self.w * self.law.energy(g, self.lam)))  # replicated: the same on every rank
        local = 0.5 * float(x @ Kx) - float(dc.f @ x)
        pi = dc.allsum(local) + energy
        if not dc.allbool(bool(np.all(np.isfinite(R)))):
            R = np.full_like(R, np.nan)  # every rank sees the non-finite residual of one
        return g, t, R, pi

    def residual(self, state):
        return state[2]

    def merit(self, state):
        return state[3]

    def slope(self, x, state, dx):
        return self.dc.allsum(float(state[2] @ dx))

    def measure(self, state):
        dc = self.dc
        wt = float(np.max(np.abs(self.w * state[1]), initial=0.0))
        if self.scale is None:  # neither contact forces nor loads: the right-hand side with the supports
            self.scale = max(wt, dc.load_scale) or dc.b_lifted
        self.fscale = max(self.scale, wt, 1e-300)
        return dc.allmax(np.abs(state[2])) / self.fscale

    def tolerance(self, state, tol):
        self.tol_k = tol
        return tol

    def step(self, x, state, history):
        dc = self.dc
        rtol = _KSP_RTOL
        if dc.forcing:  # inexact Newton with the serial Krylov path's forcing terms (its module doc)
            res = history[-1].residual
            if len(history) > 1:
                last = history[-2]
                if last.step < 1.0 or last.full_step or res > 0.5 * last.residual:
                    self.forcing = max(_FORCING_SLOW * self.forcing, _FORCING_MIN)
            rtol = float(np.clip(max(min(self.forcing, res), 0.1 * self.tol_k / max(res, 1e-300)), 1e-14,
                                 _FORCING_MAX))
        k = self.w * np.asarray(self.law.stiffness(state[0], self.lam), dtype=float)
        J = dc.newton_matrix(k)
        dx = dc.solve_newton(J, -state[2], rtol)
        # the supported rows of J are the identity and their right-hand side is 0, but a Krylov iterate preconditioned
        # by GAMG is not exactly 0 there: the prescribed values would drift by the solve's error (an inexact step
        # moved them by 1e-3 relative and converged to another problem's solution)
        dx[dc.fixed] = 0.0
        if not dc.allbool(bool(np.all(np.isfinite(dx)))):
            dx = np.full_like(dx, np.nan)
        return dx

    def negligible(self, x, state, dx):
        dc = self.dc
        return dc.allmax(np.abs(dx)) <= 1e-14 * max(dc.allmax(np.abs(x)), 1e-300)


class DistributedFrictionalContact:
    r"""The condensed frictional problem of section 6.2 at small deformation, distributed over the ranks.

    What :class:`~alcontact.contact.systems._condensed.FrictionalContact` offers the steps of the
    frictional algorithms (Algorithms 6.2 / 6.4 and the Alart-Curnier reference, driven by
    :class:`~alcontact.contact.stepping._coulomb._CondensedPath`), on a :class:`DistributedContact`
    (``dc``: the body, the one KSP, the owned contact points) instead of a factorization:

    * the arrays over the ``m`` contact-boundary points (``points``, ``weights``, ``normals``,
      ``tangents``, ``tfree``, ``movable``, the local kinematics ``y = (g, u_T)``) are replicated
      on every rank (one ``Allgatherv`` each: a surface), in the rank-major order of the owned
      points;
    * the condensed compliance on the candidates, :math:`A = E^T P K^{-1} P^T E` (``(c d, c d)``,
      replicated), is built column by column: one KSP solve per candidate and component, the
      force :math:`E_j e_l` on candidate ``j``'s free DOFs, each column read at every
      candidate's DOFs by its owner and gathered (symmetrized as on the serial path);
    * the contact-free solution of every load component (base and cases, amplitude 1) is one
      solve each; :meth:`u_free` and :meth:`y_free` combine them with the history's
      amplitudes; :meth:`displacement` is one solve for the candidates' forces.

    A body held by the obstacle alone (springs, ``spring`` of the serial path) is refused by
    :class:`DistributedContact`; ``spring`` is ``None``.
    """

    spring = None
    strategy = "distributed"

    def __init__(self, problem, history, *, comm, parts=None, ksp: str = "gamg", options: dict | None = None,
                 margin: float = 0.25):
        from ..kinematics._points import tangent_bases

        t0 = time.perf_counter()
        dc = DistributedContact(problem, comm=comm, parts=parts, ksp=ksp, options=options, margin=margin,
                                history=history, t=0.0, forcing=False, frictional=True)
        self.dc, self.comm, self.dim, self.h = dc, comm, dc.dim, dc.h
        self.history = dc.history
        d = self.dim
        off, mr = dc.point_offset, dc.points.shape[0]
        self._own = slice(off, off + mr)
        gather = dc.allgather_points
        self.points = gather(dc.points).reshape(-1, d)
        self.weights = gather(dc.weights)
        self.normals = gather(dc.normals).reshape(-1, d)
        self.gap0 = gather(dc.gap0)
        self.movable = gather(dc.movable).astype(bool)
        held_own = ~dc.free[dc.point_dofs]  # (m_r, d) supported axes of each owned point
        held = gather(held_own.astype(np.int8)).reshape(-1, d).astype(bool)
        self.tangents = tangent_bases(self.normals, held)  # one basis rule over all points, as the serial path
        self.E = np.concatenate([self.normals[:, :, None], -self.tangents], axis=2)  # (m, d, d)
        free_part = np.linalg.norm(np.where(held[:, :, None], 0.0, self.E), axis=1)
        self.tfree = free_part[:, 1:] > 1e-12
        self._E_own = self.E[self._own]
        self._held_own = held_own
        # the contact-free solution of every load component (amplitude 1), and its local kinematics
        t1 = time.perf_counter()
        dc.newton_matrix(np.zeros(dc.cand.size))
        self.u_parts = []
        for k in range(dc.f_parts.shape[0]):
            dc.f, dc.fixed_values = dc.f_parts[k].copy(), dc.value_parts[k].copy()
            self.u_parts.append(dc._solve_free())
        self.u_parts = np.stack(self.u_parts)
        self.solve_seconds = (time.perf_counter() - t1) / len(self.u_parts)
        self.y_parts = np.stack([self._local_all(u) for u in self.u_parts])  # (ncomp, m, d), without the gap0
        times = self.history.times if self.history is not None else (1.0,)
        self.gmax_t = np.max(np.stack([self.y_free(t)[:, 0] for t in times]), axis=0)
        # candidates: the serial rule on the largest contact-free gap over the steps (owned points, then gathered)
        dc.cand = np.empty(0, dtype=np.int64)
        dc._add_candidates(np.empty(0, dtype=np.int64))
        dc.margin = margin
        dc._select_candidates(self.gmax_t[self._own], margin)
        chosen = dc.cand.copy()
        dc.cand = np.empty(0, dtype=np.int64)
        dc._add_candidates(np.empty(0, dtype=np.int64))
        self.A = np.zeros((0, 0))
        self.add(chosen)
        self.setup_seconds = time.perf_counter() - t0
        self.factor_seconds = dc.factor_seconds

    # ------------------------------------------------------------------ replicated kinematics
    def _local_own(self, u: np.ndarray) -> np.ndarray:
        """``(m_r, d)``: :math:`(-\\nu\\cdot u_i, T_i^T u_i)` of the owned points (no gap offset)."""
        dc = self.dc
        ui = u[dc.point_dofs]
        yn = -np.einsum("ij,ij->i", dc.normals, ui)
        yt = np.einsum("ijk,ij->ik", self.tangents[self._own], ui)
        return np.concatenate([yn[:, None], yt], axis=1)

    def _local_all(self, u: np.ndarray) -> np.ndarray:
        return self.dc.allgather_points(self._local_own(u)).reshape(-1, self.dim)

    def all_local(self, u: np.ndarray) -> np.ndarray:
        """Local kinematics ``(m, d)`` (gap, u_T) of every contact-boundary point (replicated)."""
        y = self._local_all(u)
        y[:, 0] += self.gap0
        return y

    def amplitudes(self, t: float) -> np.ndarray:
        return self.dc.amplitudes(t)

    def u_free(self, t: float) -> np.ndarray:
        return self.amplitudes(t) @ self.u_parts

    def y_free(self, t: float) -> np.ndarray:
        """Contact-free local kinematics ``(m, d)`` (replicated): column 0 the gap, then ``u_T``."""
        y = np.tensordot(self.amplitudes(t), self.y_parts, axes=1)
        y[:, 0] += self.gap0
        return y

    def load(self, t: float) -> np.ndarray:
        """The load vector at ``t`` (owned rows)."""
        return self.amplitudes(t) @ self.dc.f_parts

    def prescribed(self, t: float) -> np.ndarray:
        """The prescribed values at ``t`` (this rank's supported DOFs)."""
        return self.amplitudes(t) @ self.dc.value_parts

    # ------------------------------------------------------------------ candidates and compliance
    @property
    def cand(self) -> np.ndarray:
        return self.dc.cand

    @property
    def ncand(self) -> int:
        return int(self.dc.cand.size)

    @property
    def linear_solves(self) -> int:
        return self.dc.linear_solves

    def _solve_forces(self, F_own: np.ndarray) -> np.ndarray:
        """:math:`K_c^{-1} P^T F` for the forces ``F_own`` ``(m_r, d)`` at the owned points (free DOFs only)."""
        dc = self.dc
        rhs = np.zeros(dc.dim * dc.n_own)
        np.add.at(rhs, dc.point_dofs.ravel(), np.where(self._held_own, 0.0, F_own).ravel())
        x = dc._ksp_solve(rhs, 1e-13)
        x[dc.fixed] = 0.0
        return x

    def add(self, new: np.ndarray) -> np.ndarray:
        """Add the movable points ``new`` (global numbers, the same on every rank) that are not candidates yet;
        returns them. One KSP solve per added point and component gives the compliance columns."""
        dc, d = self.dc, self.dim
        new = np.setdiff1d(np.asarray(new, dtype=np.int64), dc.cand)
        new = new[self.movable[new]]
        if new.size == 0:
            return new
        c_old = dc.cand.size
        off, mr = dc.point_offset, dc.points.shape[0]
        mine = new[(new >= off) & (new < off + mr)] - off
        dc._add_candidates(mine)
        added = dc.cand[c_old:]
        c = dc.cand.size
        dc.newton_matrix(np.zeros(c))  # J = K_c
        A = np.zeros((c * d, c * d))
        A[:c_old * d, :c_old * d] = self.A
        E_own = self._E_own
        for jj, j in enumerate(added):
            for l in range(d):
                F = np.zeros((mr, d))
                if off <= j < off + mr:
                    F[j - off] = E_own[j - off][:, l]
                x = self._solve_forces(F)
                col = np.einsum("iak,ia->ik", E_own[dc._my_pt], x[dc.point_dofs[dc._my_pt]])  # (c_r, d)
                full = np.empty((c, d))
                full[dc._perm] = dc.allgather_points(col).reshape(-1, d)
                A[:, (c_old + jj) * d + l] = full.ravel()
        A[c_old * d:, :c_old * d] = A[:c_old * d, c_old * d:].T  # the new rows by symmetry
        self.A = 0.5 * (A + A.T)
        return np.asarray(added, dtype=np.int64)

    def displacement(self, t: float, R: np.ndarray) -> np.ndarray:
        """Owned displacement for local forces ``R`` ``(c, d)`` on the candidates (one KSP solve)."""
        dc = self.dc
        u = self.u_free(t)
        if dc.cand.size == 0:
            return u
        F = np.zeros((dc.points.shape[0], self.dim))
        F[dc._my_pt] = np.einsum("ijk,ik->ij", self._E_own[dc._my_pt], np.asarray(R)[dc._my_pos])
        return u + self._solve_forces(F)

    # no contact springs (``spring`` is None): the spring terms of the serial condensed problem are zero
    def spring_traction(self, y: np.ndarray) -> np.ndarray:
        return np.zeros_like(y)

    def spring_tangent(self) -> np.ndarray:
        return np.zeros((self.ncand, self.dim, self.dim))

    def spring_energy(self, y: np.ndarray) -> np.ndarray:
        return np.zeros(y.shape[0])

    def slides_away(self, t: float, mu: float) -> None:
        """Only a body held by the obstacle can slide away (none here: ``spring`` is ``None``)."""
        return None

    def stats(self) -> dict:
        return {"ksp_iterations": int(self.dc.ksp_iterations), "ranks": int(self.comm.size),
                **{k: v for k, v in self.dc.extra().items() if k in ("gamg_setups", "gamg_updates", "pc_reused",
                                                                      "fine_smoother")}}
