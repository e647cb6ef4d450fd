r"""Contact systems at finite deformation: one full-space Newton for every algorithm, frictionless and Coulomb.

Kinematics (current configuration). Contact point ``i`` is a DOF location of the
candidate boundary with reference position :math:`X_i` and reference tributary
weight :math:`w_i` (a nodal collocation of the reference-configuration contact
integral, as on the small-deformation path). Its current position is
:math:`x_i = X_i + u_i`, its gap the obstacle's signed distance there,

.. math::

    g_i(u) = \operatorname{gap}(X_i + u_i) \le 0, \qquad
    \frac{\partial g_i}{\partial u_i} = -\nu_i(x_i), \qquad
    \frac{\partial^2 g_i}{\partial u_i^2} = H(x_i),

with :math:`\nu` the obstacle normal at the projection of :math:`x_i` and :math:`H` the
Hessian of the signed distance (the curvature of the obstacle surface, zero for a
plane); the small-deformation gap (6.15) is its linearization at :math:`u = 0`. These are
evaluated by the system's :class:`~alcontact.contact.kinematics.CurrentGap` (``kinematics``). Large
sliding needs nothing more: the projection is recomputed at every evaluation.

Subproblem (S) of Algorithms 6.1 / 6.3 and the pure penalty (same laws
:math:`t_N = p'(g/\eta, \lambda)` as :mod:`alcontact.contact.laws._normal`): with the free
DOFs :math:`x` and :math:`u = u(x)` (prescribed values on the fixed DOFs),

.. math::

    \Pi(x) = \Pi_{int}(u) - f_{ext}\cdot u + \sum_i w_i\,\psi_i(g_i(u)), \\
    R(x) = f_{int}(u) - f_{ext} + B(u)^T (w \circ t_N(g(u))) = 0, \\
    J(x) = K_T(u) + B^T \operatorname{diag}(w \circ dt_N/dg)\, B
           + \sum_i w_i\, t_{N,i}\, H(x_i),

``B(u)`` the rows :math:`-\nu_i^T` on the free DOFs of the points. The last term of
``J`` is the geometric (curvature) part of the consistent linearization; without it
Newton's convergence on a curved obstacle is only linear. Newton's method is
globalized by backtracking on :math:`\Pi` (Armijo), or on :math:`\tfrac12|R|^2` when the
body has no stored energy; a trial step that inverts an element
(:class:`~alcontact.errors.InvertedElementError`) is rejected like one that raises
:math:`\Pi` (the step is halved).

The semi-smooth Newton reference (:func:`~alcontact.contact.algorithms._frictionless.run_ssn`) enforces
:math:`g_A(u) = 0` on its active set by Newton's method on the saddle-point system

.. math::

    \begin{pmatrix} K_T + \sum_{i\in A} r_i H_i & B_A^T \\ B_A & 0 \end{pmatrix}
    \begin{pmatrix} \Delta x \\ \Delta r \end{pmatrix}
    = -\begin{pmatrix} f_{int} - f_{ext} + B_A^T r \\ g_A \end{pmatrix},

:math:`r = w \circ \lambda` the contact forces of the active points (a direct sparse
solve), which converges quadratically.

Cost of a Newton iteration: one assembly of :math:`J` and one factorization by
:class:`NewtonSolver` (MKL PARDISO with the symbolic analysis kept between iterations,
SuperLU without it). The values of :math:`J` are filled into fixed sparse structures
(:mod:`._finite_matrices`), the tangent reuses the deformation gradient of the accepted
trial state, and the body state of the last evaluated displacement is kept. The outer
loop of Algorithm 6.1 solves its subproblems inexactly (``inexact_subproblems``) and updates the multipliers by a Newton step on the dual
(:meth:`FiniteContact.multiplier_step`, a few back-substitutions with the factor of the
last iteration); the tangent predictor of a load step also predicts the pressures.

:class:`FiniteContact` offers the interface of the outer loops of
:mod:`alcontact.contact.algorithms._frictionless` (``cand``, ``h``, ``start``, ``gaps``,
``scale_forces``, ``subproblem``, ``solve_active``, ``extend``, ``all_gaps``,
``final_displacement``, ``timings``, ``extra``), so penalty, Algorithm 6.1, Algorithm
6.3 with every contact penalty and the reference run unchanged; the state is the
free displacement. :meth:`FiniteContact.configure` sets the data of one load step
(prescribed values, loads, obstacle position, starting state): see
:mod:`alcontact.contact.stepping._steps`.

AMG + CG solver of the Newton systems of finite-deformation contact (``linear_solver="amg"``).

:class:`~alcontact.contact.systems._full_space.FiniteContact` solves one symmetric system per Newton
iteration of subproblem (S) (module doc of :mod:`alcontact.contact.systems._full_space`),

.. math::

    J(x_k)\,\Delta x = -R(x_k), \qquad
    J = K_T + B^T \operatorname{diag}(w \circ dt_N/dg)\, B + \sum_i w_i t_{N,i} H_i,

and a few more with the same matrix (the dual Newton step of Algorithm 6.1,
:meth:`~alcontact.contact.systems._full_space.FiniteContact.multiplier_step`). The direct path
factorizes every :math:`J` (:class:`~alcontact.contact.systems._full_space.NewtonSolver`, MKL PARDISO).
:class:`AMGNewtonSolver` offers the same surface (``newton_step``, ``solve``, ``resolve``,
``info``) without a factorization: it is :class:`alcontact.linalg.NewtonKrylovSolver`
(preconditioned CG with the factors of an approximate solver, reused across Newton iterations
and load steps while they stay good, an Eisenstat-Walker forcing term, a symmetric-indefinite
factorization for a system with negative curvature, counted in ``direct_fallbacks``; the
measurements of its constants are those of this path) with the near-null space of the body:
the rigid-body modes at the *current configuration* :math:`x = X + u` of the load step's start
(:meth:`AMGNewtonSolver.near_null`); at finite rotations the modes of the reference
configuration are no longer the kernel of the tangent's elastic part. The curvature term
:math:`w_i t_{N,i} H_i` of a convex obstacle is negative semidefinite, so a buckling or strongly
curved contact state can make :math:`J` indefinite: with ``fallback=False`` that Newton step
fails (:class:`numpy.linalg.LinAlgError`) and the load step is cut back.

The semi-smooth reference ``ssn`` solves saddle-point systems (indefinite by construction)
and stays direct-only (its registry entry lists ``direct`` only).

Coulomb friction at finite deformation: Algorithms 6.2 and 6.4 in the current configuration.

Kinematics (current configuration, nodal collocation as in
:mod:`alcontact.contact.systems._full_space`). Contact point ``i`` has the current position
:math:`x_i = X_i + u_i`, the gap :math:`g_i = \operatorname{gap}(x_i)`, the obstacle
normal :math:`\nu_i` and the projection :math:`\bar x_i = x_i + g_i\nu_i` onto the obstacle.
The obstacle moves rigidly, :math:`x = Q(t)\,y + c(t)` (``obstacle_path``: a translation
:math:`c`, or an :class:`~alcontact.contact.obstacles.RigidMotion` with a rotation :math:`Q`);
the point of the obstacle's *own* surface that contact point ``i`` touches is
:math:`y_i = Q^T(\bar x_i - c)` (its surface coordinate,
:meth:`FiniteFrictionContact.surface_points`). The slip of a load step :math:`n \to n+1` is
measured *on the obstacle's surface*, from the previous surface point :math:`y_{i,n}`
(carried with the obstacle: :math:`Q y_{i,n} + c`) to the current projection, as a vector of
the current tangent plane,

.. math::

    \Delta s_{T,i} = \operatorname{slip}(x_i;\ Q y_{i,n} + c)
    \qquad (:func:`~alcontact.contact.obstacles.surface_slip`):

the geodesic for the analytic obstacles (exact for a plane; great-circle arc
:math:`\frac{\theta}{\sin\theta} P_i (x_i - Q y_{i,n} - c)` on a circle/sphere,
:math:`\theta` the turn of the normal; axial part plus arc on a cylinder) and, for a general
signed-distance obstacle, the chord projected onto the current tangent plane,
:math:`P_i (x_i - Q y_{i,n} - c)`, :math:`P_i = I - \nu_i\nu_i^T`, a first-order consistent
choice (relative error :math:`\theta^2/6`). The tangential traction of the last step,
tangent to the obstacle at the old normal, is transported into the current tangent plane
by the minimal rotation of the normals
(:func:`~alcontact.contact.obstacles.transport_tangent`, the parallel transport for the
analytic obstacles) before it starts the step's multipliers; within the step the
multiplier is projected, :math:`P\lambda_T`, onto the tangent plane of the current iterate.

Local law of one AL subproblem with multipliers :math:`(\lambda_N, \lambda_T)` (the
dissertation's (6.46)-(6.50) with the corrected (6.49), see
:mod:`alcontact.contact.laws._coulomb`; vectors in the ambient space, tangent to the
obstacle):

.. math::

    t_N &= t_N(g; \lambda_N) \quad (\langle\lambda_N + \varepsilon_N g\rangle \text{ (6.52), Algorithm 6.2; }
          p'(g/\eta, \lambda_N) \text{, Algorithm 6.4}),\\
    z &= P\,\lambda_T + \varepsilon_T \Delta s_T
         \quad (\lambda_T \text{ projected onto the current tangent plane}),\\
    t_T &= \operatorname{proj}_{\{|t| \le \rho\}}(z), \qquad \rho = \mu\lambda_N \text{ (radius ``multiplier'')
          or } \mu t_N \text{ (``traction'')},

with the dissertation's sign: :math:`t_T` points along the slip, the friction force on
the body is :math:`-w_i t_{T,i}`. The force of the obstacle on the body at point ``i`` is
:math:`w_i (t_{N,i}\nu_i - t_{T,i})`, and the subproblem is

.. math::

    R(x) = f_{int}(u) - f_{ext} - \sum_i w_i\,(t_{N,i}\nu_i - t_{T,i}) = 0,

solved by Newton's method with the consistent (non-symmetric) point blocks

.. math::

    \frac{\partial}{\partial x_i} w_i(t_T - t_N\nu) = w_i\Big(k_N \nu\nu^T + t_N H + \frac{\partial t_T}{\partial z}
      \Big(\varepsilon_T \frac{\partial\Delta s_T}{\partial x} + (\nu\cdot\lambda_T) H + \nu (H \lambda_T)^T\Big)
      + n\,\frac{\partial\rho}{\partial x}\Big),

:math:`\partial\Delta s_T/\partial x` from :func:`~alcontact.contact.obstacles.surface_slip`
(for the chord :math:`P + (\nu\cdot b) H + \nu (H b)^T`, :math:`b = x - Q y_n - c`; the arc adds
the derivative of :math:`\theta/\sin\theta`), :math:`H` the Hessian of the gap
(:math:`\partial\nu/\partial x = -H`), :math:`\partial t_T/\partial z` the derivative of the
return mapping (identity at stick, :math:`\rho/|z|\,(I - nn^T)` at slip, :math:`n = z/|z|`),
:math:`\partial\rho/\partial x = -\mu k_N \nu^T` for the coupled radius at slip. The
line search backtracks on the residual norm (a frictional step has no potential) and
halves a step that inverts an element.

Outer loop (Algorithm 6.2, resp. 6.4 with a family-P penalty): the one loop of the
small-deformation solvers, :func:`alcontact.contact.algorithms._coulomb._step_al`, on the step's
system :class:`_FiniteALCtx` (first-order updates :math:`\lambda_N \leftarrow t_N`,
:math:`\lambda_T \leftarrow t_T` ((6.2b), (6.2c)) until the penetration, complementarity,
multiplier change and the slip of the sticking points are below their tolerances; what
the finite system declares differently is listed there). A step starts from
:math:`\lambda_T = t_{T,n}` (transported into the current tangent plane).
The reference ``"ssn"`` (:func:`_step_ssn_finite`) solves the Alart-Curnier equations of the same
time-discrete law exactly, in :math:`(u, \lambda_N, \lambda_T)`, by a semi-smooth Newton method.
Every accepted step is verified by :func:`~alcontact.contact._verify.check_state`
(penetration, complementarity, Coulomb bound and slip direction) before it is
reported converged.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ... import linalg as _linalg
from ...errors import InputError, InvertedElementError
from ...fem.elasticity import rigid_body_modes
from ...fem.mixed import MixedHyperelastic
from ...linalg import SequenceSolver
from ...status import Status
from ..algorithms._subproblem import (LineSearch, NewtonOutcome, NewtonResult, NewtonSettings, NewtonSystem,
                                      newton, subproblem_outcome)
from ..kinematics._gap import point_blocks
from ..kinematics._mortar_current import current_kinematics
from ..kinematics._points import ContactPoints
from ..laws._coulomb import OPEN, SLIP, STICK, CoulombLaw, return_mapping
from ..masters.obstacles import frame, surface_slip
from ._krylov import _NEWTON_TOL_FLOOR
from ._layout import NewtonLayout
from ._two_body import body_slide


logger = logging.getLogger(__name__)


#: Armijo constant of the line search
_ARMIJO = 1e-4
_EPS = float(np.finfo(float).eps)
#: halvings of a Newton step before the line search gives up
_MAX_HALVINGS = 40
#: a residual decrease accepts a step of (S) only where the energy rose by at most this fraction of it
#: (its round-off; :class:`~._newton.LineSearch`): with any rise allowed, the energy and the residual tests
#: took turns and the Newton iterates of a sliding step cycled (issue 18: 60 iterations, cut-backs)
_MERIT_SLACK = 1e-10
#: secant predictor: a point enters the starting active set when its extrapolated penetration
#: exceeds this fraction of its predicted approach (:meth:`FiniteContact.initial_active`)
_ENTRY_FRACTION = 0.5
#: secant predictor: largest relative deviation of the step's data change from a multiple of the last one
_SECANT_RTOL = 1e-8
#: relative residual of (S) below which its next correction reuses the factor at hand (a chord step,
#: :meth:`_Subproblem.step`): from there a simplified-Newton step with the same step's factor contracts as well
#: as a new tangent, and at 60k-100k DOFs the residual is near its round-off floor (one ulp of the state moves
#: it by 1-3e-12 of the force unit at 62k DOFs), where a new tangent buys nothing
_CHORD_LEVEL = 1e-9
#: chord steps of one subproblem at most
_MAX_CHORDS = 3
#: a contact spring below this fraction of the largest one counts as absent when a chord step compares the
#: springs of the factor at hand with the current ones (:func:`_springs_on`)
_CHORD_SPRING = 1e-8
#: relative tolerance of iterative back-substitutions in the dual step of Algorithm 6.3's start
#: (:meth:`FiniteContact.start_multiplier_step`)
_START_RESOLVE_RTOL = 1e-8
#: values of the ``predictor`` option (:meth:`FiniteContact.configure`): ``"auto"`` the secant predictor where
#: the loading is proportional, the slide predictor where the obstacle translates along the contact zone, the
#: tangent predictor otherwise; ``"tangent"`` the tangent predictor in every step
PREDICTORS = ("auto", "tangent")


class NewtonSolver(SequenceSolver):
    r"""The solver of the symmetric Newton systems of :class:`FiniteContact` (a registry solver).

    Every Newton matrix of :class:`FiniteContact` is symmetric (the tangent, the contact
    terms, the saddle-point matrix of the reference) and possibly indefinite, and few
    sparsity patterns occur: the Newton matrices of a run share the structure of
    :class:`~._finite_matrices.NewtonLayout` (the free block of the body's fixed tangent
    pattern, :attr:`Hyperelastic.tangent_pattern
    <alcontact.fem.hyperelastic.Hyperelastic.tangent_pattern>`, and one saddle-point pattern
    over all movable contact points, :meth:`FiniteContact._saddle_matrix`), so a run analyses
    each pattern once and refactorizes by a gather. A
    :class:`~alcontact.linalg.SequenceSolver` for ``"symmetric-indefinite"`` matrices: the
    registry's choice (MKL PARDISO when installed, analyses of the ``keep`` most recent
    patterns kept, else SuperLU) or the solver named by the ``linear_solver`` option, with the
    residual check and the SuperLU fallback there.

    Parameters
    ----------
    name : str, optional
        ``"auto"``, ``"direct"`` (the registry's choice) or a registry name (that solver runs;
        :func:`alcontact.linalg.select_solver`). Default: the registry's choice.
    use_pardiso : bool
        False: SuperLU only (no analysis kept).
    keep : int
        Sparsity patterns whose analyses are kept.
    saddle, near_null : optional
        The blocks of a mixed u-p body's saddle-point matrices and the near-null space, for an
        approximate solver (:class:`~alcontact.linalg.SequenceSolver`).
    """

    #: lowest Newton tolerance its solves reach (exact solves: none)
    tol_floor = 0.0

    def __init__(self, name: str | None = None, *, use_pardiso: bool = True, keep: int = 3, saddle=None,
                 near_null=None):
        super().__init__(name if use_pardiso else "superlu", matrix_type="symmetric-indefinite", keep=keep,
                         saddle=saddle, near_null=near_null)

    def newton_step(self, A, rhs: np.ndarray, history) -> np.ndarray:
        """The Newton correction ``A dx = rhs`` (exact; ``history`` serves inexact solvers'
        forcing terms, :class:`~alcontact.contact.systems._full_space.AMGNewtonSolver`)."""
        return self.solve(A, rhs)

    def info(self) -> dict:
        """Counters for ``solution.extra``: ``linear_solver`` (registry name of the solver that ran)."""
        return {"linear_solver": self.backend, "analyses": int(self.analyses),
                "fallback_solves": int(self.fallback_solves)}


_DEFAULT_SOLVER: NewtonSolver | None = None


def linear_solve(A: sp.spmatrix, rhs: np.ndarray, solver: SequenceSolver | None = None) -> np.ndarray:
    """Solve one symmetric Newton system ``A x = rhs`` (:class:`NewtonSolver`).

    ``solver`` keeps its analyses between calls (a :class:`FiniteContact` owns one);
    without it a shared module solver is used. Raises :class:`numpy.linalg.LinAlgError`
    for a singular matrix.
    """
    global _DEFAULT_SOLVER
    if solver is None:
        if _DEFAULT_SOLVER is None:
            _DEFAULT_SOLVER = NewtonSolver()
        solver = _DEFAULT_SOLVER
    return solver.solve(A, rhs)


class FiniteContact(ContactPoints):
    """Frictionless contact of a (nonlinear) body with a rigid obstacle at finite deformation.

    Parameters
    ----------
    problem : ContactProblem
        Body (the :class:`~alcontact.fem._body.Body` protocol), supports, loads,
        obstacle and contact boundary. The supports and loads of ``problem`` give
        the fixed DOFs; their values per load step are set by :meth:`configure`.
    fixed : ndarray of int, optional
        Fixed DOFs (default those of the problem's supports).
    solver : callable, optional
        ``solver(fc)`` returns the solver of the Newton systems (the surface of
        :class:`NewtonSolver`: ``newton_step``, ``solve``, ``resolve``, ``info``), e.g.
        :class:`~alcontact.contact.systems._full_space.AMGNewtonSolver`; default a :class:`NewtonSolver`.
    margin : float
        Candidates of a step are the points whose gap at the step's starting state
        exceeds ``-max(margin * h, 2 * max_penetration)``; points that penetrate
        after a solve are added (:meth:`extend`).
    predictor : {"auto", "tangent"}
        The load-step predictor of :meth:`configure` (:data:`PREDICTORS`; option ``predictor``
        of :class:`~alcontact.contact.ContactOptions`).
    slide_start_reach : float
        After the slide predictor, the penalty start of Algorithm 6.3 shifts only the points open by
        at most this fraction of ``h`` (:meth:`entry_multipliers`; option ``slide_start_reach``).
    kinematics : callable, optional
        ``kinematics(points, dofs, pos, master, n_free)`` returns the
        :class:`~alcontact.contact.kinematics.ContactKinematics` of the contact points (default
        :class:`~alcontact.contact.kinematics.CurrentGap` against a rigid master, the mortar gap at the
        current configuration, :class:`~alcontact.contact.kinematics.CurrentMortarGap`, between two bodies; with
        :class:`~alcontact.contact.kinematics.LinearizedGap` the same Newton solves the
        small-deformation contact problem).

    Attributes
    ----------
    kinematics : ~alcontact.contact.kinematics.CurrentGap
        The gap in the current configuration, its constraint rows and curvature (module doc),
        measured against the step's master :attr:`obstacle`. A kinematics that declares
        ``pointwise = False`` (its gaps couple several points, e.g. mortar) is assembled from
        its sparse gradient and curvature; a pointwise one fills its ``d x d`` blocks into the
        fixed structure of :class:`NewtonLayout`.
    points, dofs, weights : ndarray
        Reference positions, DOFs and reference tributary weights of all contact-boundary points.
    normals : ndarray (m, d)
        Obstacle normals at the current positions (updated by :meth:`all_gaps`).
    cand : ndarray of int
        Current candidates.
    residual_log : list of list of float
        Relative residuals of every Newton solve (subproblem or active-set step), in order.
    linear_solves, newton_iterations : int
        Counters over the life of the object.
    carried_stiffness : float or None
        Stiffness the pure penalty method's last converged load step ended with
        (:attr:`penalty_continuation`); ``None`` before.
    """

    #: how the linear systems are solved (``solution.extra["strategy"]``): Newton on the full displacement space
    strategy = "full-space-newton"

    factorizations = 0
    # ---- ContactSystem (:mod:`alcontact.contact.systems._protocol`): what finite deformation declares
    #: each Newton iteration costs an assembly and a factorization: the subproblems (S) of Algorithms
    #: 6.1 / 6.3 are solved inexactly (:func:`~alcontact.contact.algorithms._frictionless.run_al`; option
    #: ``subproblems = "exact"`` turns it off)
    inexact_subproblems = True
    #: :meth:`multiplier_step` is a second-order update: Algorithm 6.1 stops as soon as penetration and
    #: complementarity hold at a subproblem solved to ``newton_tol`` (the KKT conditions at the returned state)
    physical_stopping = True
    #: the pure-penalty start of Algorithm 6.3 (``initial="penalty"``,
    #: :func:`~alcontact.contact.algorithms._frictionless.run_al`) solves the penalty subproblem of a load step with
    #: the step's predicted pressures as multipliers (:meth:`initial_multipliers`,
    #: :math:`t_N = \langle\lambda_{pred} + \varepsilon_N g\rangle`, the first subproblem of Algorithm 6.1),
    #: its Newton solve started with the entry rule (:meth:`entry_multipliers`), and takes the second-order
    #: update of that start (:meth:`start_multiplier_step`) as its initial multipliers; the MET iterations
    #: themselves stay first order (``docs/benchmarks/finite_met_penalty.md``)
    warm_penalty_start = True
    #: the pure penalty method starts each load step at the stiffness the last converged step ended
    #: with (:attr:`carried_stiffness`; :func:`~alcontact.contact.algorithms._frictionless.run_penalty`), its first
    #: solve started with the entry rule: Algorithm 5.2's increasing sequence continued over the load steps
    penalty_continuation = True

    def __init__(self, problem, *, margin: float = 2.0, fixed=None, solver=None, predictor: str = "auto",
                 slide_start_reach: float = 0.05, kinematics=None):
        t0 = time.perf_counter()
        if predictor not in PREDICTORS:
            raise InputError(f"predictor = {predictor!r:.40}: expected one of {', '.join(PREDICTORS)}.")
        #: the load-step predictor (option ``predictor``, :meth:`configure`)
        self.predictor = predictor
        #: the reach of the consistent shift at Algorithm 6.3's penalty start (option ``slide_start_reach``,
        #: :meth:`entry_multipliers`)
        self.slide_start_reach = float(slide_start_reach)
        self._setup_problem(problem)
        if fixed is not None:  # fixed DOFs of a load history (values set by configure)
            self.fixed = np.asarray(fixed, dtype=np.int64)
            self.fixed_values = np.zeros(self.fixed.size)
        self.body = self.model
        model = self.model
        n = model.ndofs
        mask = np.ones(n, dtype=bool)
        mask[self.fixed] = False
        self.free = np.flatnonzero(mask)
        self.margin = float(margin)
        model.check_restrained(self.fixed)
        pts, dofs = problem.slave_nodes()
        self.points, self.dofs = pts, dofs
        self.weights = np.asarray(problem.slave_weights(), dtype=float)
        free_pos = -np.ones(n, dtype=np.int64)
        free_pos[self.free] = np.arange(self.free.size)
        self.pos = free_pos[dofs]  # (m, d), -1 on fixed DOFs
        self.movable = np.any(self.pos >= 0, axis=1)
        self._movable_pts = np.flatnonzero(self.movable)
        if kinematics is None:  # the current gap against a rigid master, the current mortar gap between two bodies
            kinematics = current_kinematics(problem, self.free)
        #: the gap in the current configuration against the master (:attr:`obstacle`, moved by :meth:`configure`)
        self.kinematics = kinematics(pts, dofs, self.pos, problem.obstacle, self.free.size)
        # a kinematics with its own multiplier weights and contact element size (the mortar gap) gives them
        self.weights = np.asarray(getattr(self.kinematics, "weights", self.weights), dtype=float)
        self.h = getattr(self.kinematics, "h", None) or self._element_size()
        self.linear_solves = 0
        self.newton_iterations = 0
        self.chord_steps = 0
        #: stiffness the pure penalty method's last converged load step ended with (:attr:`penalty_continuation`)
        self.carried_stiffness: float | None = None
        self._factor_stiffness = None
        # the solver of the Newton systems: NewtonSolver (direct) or a factory's (solver(self), e.g. AMG + CG)
        self.solver = NewtonSolver() if solver is None else solver(self)
        self.residual_log: list[list[float]] = []
        self.assembly_seconds = 0.0
        self.solve_seconds = 0.0
        self.fixed_values = np.asarray(self.fixed_values, dtype=float)
        self.load = np.asarray(self.load, dtype=float)
        self.x0 = np.zeros(self.free.size)
        self.normals = np.zeros_like(pts)
        self.gap0 = self.all_gaps(np.zeros(n))
        self.cand = np.empty(0, dtype=np.int64)
        self.last_pressure = np.zeros(pts.shape[0])
        self.start_pressure = self.last_pressure
        self._history: list[list] = []
        self.configure(self.fixed_values, self.load, self.obstacle, self.x0)
        self.accept(self.last_pressure)
        self.setup_seconds = time.perf_counter() - t0

    # ------------------------------------------------------------------ step data
    def configure(self, fixed_values, load, obstacle, x_start, *, predictor_stiffness: float | None = None) -> None:
        """Set the data of one load step and its starting state; choose the candidates.

        Parameters
        ----------
        fixed_values : ndarray
            Values of the fixed DOFs (aligned with ``self.fixed``).
        load : ndarray (ndofs,)
            External (dead) load vector.
        obstacle : Obstacle
            Obstacle at this step (e.g. :func:`~alcontact.contact.obstacles.translate` of the original).
        x_start : ndarray
            Last converged free displacement (for the data set before this call).
        predictor_stiffness : float, optional
            Penalty stiffness :math:`\varepsilon_N` of the tangent predictor. With it the
            step starts from the secant predictor (:meth:`_secant`: the last two converged
            steps extrapolated, no assembly) where the loading is proportional and the obstacle
            does not slide (option ``predictor = "auto"``, :attr:`predictor_used`), else from the
            tangent predictor: the starting state is ``x_start`` plus one linearized step for
            the changes of the prescribed values, loads and obstacle position, with the points
            that carried pressure
            (:meth:`accept`) held by springs :math:`w_i \varepsilon_N`, whose forces predict the
            starting pressures (:meth:`initial_multipliers`); without it (or when the
            predicted state inverts an element) the step starts from ``x_start`` and the last
            accepted pressures.
        """
        fixed_values = np.asarray(fixed_values, dtype=float)
        load = np.asarray(load, dtype=float)
        x_start = np.array(x_start, dtype=float)
        if self._history and self._history[-1][1] is None:
            self._history[-1][1] = x_start.copy()  # the converged state of the last accepted step
        self.start_pressure = self.last_pressure.copy()
        self._factor_stiffness = None  # the factor at hand is no subproblem's of this step
        self.predictor_used = "none"
        self.predicted_approach = None
        if predictor_stiffness is not None and self.predictor == "auto":
            slid = body_slide(self, x_start, fixed_values, load)  # a two-body pair sliding (systems._two_body)
            if slid is not None:  # the step's data change is the carried translation: no tangent predictor
                x_start, self.start_pressure = slid
                self.predictor_used = "slide"
                predictor_stiffness = None
        if predictor_stiffness is not None:
            pred_obstacle = self._predictor_obstacle(obstacle)
            # a sliding obstacle moves the contact zone: no extrapolation of its pressures and gaps
            secant = (self._secant(x_start, fixed_values, load, obstacle)
                      if self.predictor == "auto" and pred_obstacle is obstacle else None)
            if secant is not None:
                x_start, self.start_pressure = secant
                self.predictor_used = "secant"
            else:
                slid = (self._slide(x_start, obstacle) if self.predictor == "auto" and pred_obstacle is not obstacle
                        else None)
                if slid is not None:
                    # the contact state travels with the obstacle; the rest of the data change (supports,
                    # loads) is predicted by the tangent predictor from there
                    x_start, carried = slid
                    base = (self._accepted[0], self._accepted[1], obstacle)
                    self.start_pressure = carried
                    pred_obstacle = obstacle
                    self.predictor_used = "slide"
                else:
                    base = None
                x_pred = self._predict(x_start, fixed_values, load, pred_obstacle, float(predictor_stiffness),
                                       base=base)
                if (x_pred is not x_start and pred_obstacle is obstacle
                        and not np.any(self.last_pressure > 0)):
                    # first contact: the predictor has no springs, every predicted penetration is unbalanced
                    self.predicted_approach = self._approach(x_start, x_pred, fixed_values, obstacle)
                x_start = x_pred
        self.fixed_values = fixed_values
        self.load = load
        self.obstacle = obstacle
        self.x0 = x_start
        self.u_free = self.expand(self.x0)
        self.g_free = self.all_gaps(self.u_free)
        gmax = float(np.max(self.g_free[self.movable], initial=-np.inf))
        self.max_free_penetration = gmax
        thr = -max(self.margin * self.h, 2.0 * max(gmax, 0.0))
        self.cand = np.flatnonzero(self.movable & (self.g_free > thr))

    @staticmethod
    def _data_increment(new, old):
        """Parts of the change of the step data ``(fixed values, load, obstacle)``, or ``None``
        when the obstacle changed otherwise than by a translation of the same base."""
        parts = [np.asarray(new[0]) - np.asarray(old[0]), np.asarray(new[1]) - np.asarray(old[1])]
        ob, ob_old = new[2], old[2]
        if ob is not ob_old:
            base, base_old = getattr(ob, "base", ob), getattr(ob_old, "base", ob_old)
            if base is not base_old:
                return None
            if any(o is not base and not hasattr(o, "offset") for o in (ob, ob_old)):
                return None  # moved otherwise than by a translation (e.g. rotated, obstacles.Moved)
            off = np.asarray(getattr(ob, "offset", 0.0), dtype=float)
            off_old = np.asarray(getattr(ob_old, "offset", 0.0), dtype=float)
            parts.append(np.broadcast_to(off - off_old, (max(off.size, off_old.size),)).astype(float))
        return parts

    def _secant(self, x, fixed_values, load, obstacle):
        r"""Secant predictor of :meth:`configure`: ``(x, pressures)`` extrapolated linearly, or ``None``.

        When the data change of the new step is a multiple :math:`\rho` of the last accepted
        step's (proportional loading, a straight obstacle path; every part, to
        ``_SECANT_RTOL``), the state and the pressures are extrapolated from the last two
        converged steps, :math:`x_{k+1} = x_k + \rho\,(x_k - x_{k-1})`,
        :math:`\lambda_{k+1} = \langle\lambda_k + \rho\,(\lambda_k - \lambda_{k-1})\rangle`:
        no assembly and no solve, and the active set of the new step (points entering contact)
        is predicted to first order. ``None`` (the tangent predictor runs) for the first step,
        after a change of the loading direction, or when the extrapolated state inverts an element.
        """
        if len(self._history) < 2 or self._history[-1][1] is None or self._history[-2][1] is None:
            return None
        (data_k, x_k, p_k), (data_km, x_km, p_km) = self._history[-1], self._history[-2]
        if x_k.shape != x.shape or x_km.shape != x.shape or not np.array_equal(x_k, x):
            return None
        new = self._data_increment((fixed_values, load, obstacle), data_k)
        old = self._data_increment(data_k, data_km)
        if new is None or old is None or len(new) != len(old):
            return None
        den = sum(float(b @ b) for b in old)
        if den == 0.0:
            return None
        rho = sum(float(a @ b) for a, b in zip(new, old)) / den
        if not rho > 0.0:
            return None
        for a, b in zip(new, old):
            if float(np.linalg.norm(a - rho * b)) > _SECANT_RTOL * max(float(np.linalg.norm(a)), 1e-300):
                return None
        trial = x + rho * (x - x_km)
        u = np.zeros(self.model.ndofs)
        u[self.free] = trial
        u[self.fixed] = fixed_values
        try:
            fint = self.body.internal_force(u)
        except InvertedElementError:
            return None
        if not (np.all(np.isfinite(fint)) and np.all(np.isfinite(trial))):
            return None
        self.predicted_approach = self._approach(x, trial, fixed_values, obstacle)
        return trial, np.maximum(p_k + rho * (p_k - p_km), 0.0)

    def _approach(self, x, trial, fixed_values, obstacle) -> np.ndarray:
        """Predicted approach of every contact-boundary point: its gap at the predicted state ``trial``
        (step data ``fixed_values``, ``obstacle``) minus its gap at the last converged state ``x``."""
        fv_old, _, ob_old = self._accepted
        u = np.zeros(self.model.ndofs)
        u[self.free] = trial
        u[self.fixed] = fixed_values
        uk = np.zeros(self.model.ndofs)
        uk[self.free] = x
        uk[self.fixed] = fv_old
        return self.kinematics.against(obstacle).gaps(u) - self.kinematics.against(ob_old).gaps(uk)

    def _predictor_obstacle(self, obstacle):
        """The obstacle the tangent predictor linearizes with: ``obstacle``, or the last accepted one
        when the step's translation is mostly tangential to the contact zone.

        A sliding indenter (ironing) moves the pressed points' gaps in opposite directions on its
        two sides; predicting that with springs on the pressed points sent the frictionless
        ironing example into two cut-backs and up to 140 Newton iterations a step (8-13 when
        Newton takes the sliding from the last state). A pressing motion (Hertz) keeps its
        prediction.
        """
        old = self._accepted[2]
        d = getattr(obstacle, "offset", None)
        d0 = getattr(old, "offset", None)
        pressed = self.last_pressure > 0
        if d is None or d0 is None or not np.any(pressed):
            return obstacle
        d = np.asarray(d, dtype=float) - np.asarray(d0, dtype=float)
        nbar = self.normals[pressed].mean(axis=0)
        nn = float(np.linalg.norm(nbar))
        if nn == 0.0 or abs(float(nbar @ d)) >= 0.5 * nn * float(np.linalg.norm(d)):
            return obstacle
        return old

    def _slide(self, x, obstacle):
        r"""Slide predictor of :meth:`configure`: ``(x, pressures)`` carried along with the obstacle, or ``None``.

        When the obstacle translates by :math:`\Delta c` along the contact zone, steady sliding
        moves the contact state with it: the prediction is the last converged displacement and
        pressures translated by :math:`\Delta c`,

        .. math::

            u_{pred}(X_j) = u_k(X_j - \Delta c), \qquad
            \lambda_{pred}(X_i) = \lambda_k(X_i - \Delta c),

        the finite-element interpolants evaluated at the shifted nodes
        (:meth:`~alcontact.fem.LinearElasticity.probe`); a node whose shifted position lies outside
        the body keeps its value, the fixed DOFs keep theirs. Without it a sliding step started from
        the last state, where the front of the contact zone penetrates and its back pulls: the
        semi-smooth Newton reference switched most of its active set back and forth (9-11 Newton
        per step of half an element on the 2D ironing case, 3-4 with it), the subproblems of
        Algorithms 6.1 / 6.3 cut back. ``None`` for a body without ``probe``, a non-translated
        obstacle, or a prediction that inverts an element.
        """
        probe = getattr(self.body, "probe", None)
        ob_old = self._accepted[2]
        d = getattr(obstacle, "offset", None)
        d0 = getattr(ob_old, "offset", None)
        if probe is None or d is None or d0 is None or getattr(obstacle, "base", obstacle) is not getattr(
                ob_old, "base", ob_old):
            return None
        shift = np.asarray(d, dtype=float) - np.asarray(d0, dtype=float)
        if shift.shape != (self.dim,) or not np.any(shift):
            return None
        X = np.asarray(self.body.scalar_doflocs, dtype=float)  # (d, n_scalar)
        P, inside = probe((X - shift[:, None]).T)
        dof_map = np.asarray(self.body.dof_map)  # (n_scalar, d)
        u = self.expand(x)
        u_new = u.copy()
        for c in range(self.dim):
            comp = u[dof_map[:, c]]
            comp[inside] = P @ comp
            u_new[dof_map[:, c]] = comp
        # the pressures as a scalar field on the contact-boundary DOFs (zero elsewhere), carried the same way
        scalar_of = np.full(self.model.ndofs, -1, dtype=np.int64)
        scalar_of[dof_map[:, 0]] = np.arange(dof_map.shape[0])
        sp_idx = scalar_of[self.dofs[:, 0]]
        field = np.zeros(dof_map.shape[0])
        field[sp_idx] = self.last_pressure
        field[inside] = P @ field
        trial = u_new[self.free]
        try:
            fint = self.body.internal_force(u_new)
        except InvertedElementError:
            return None
        if not (np.all(np.isfinite(fint)) and np.all(np.isfinite(trial))):
            return None
        return trial, np.maximum(field[sp_idx], 0.0)

    def _predict(self, x, fixed_values, load, obstacle, eps, *, base=None) -> np.ndarray:
        """Tangent predictor of :meth:`configure` (linearized at ``x``: the last converged state, or the
        slide prediction with ``base`` its data ``(fixed values, load, obstacle)``)."""
        fv_old, load_old, ob_old = self._accepted if base is None else base
        du_d = fixed_values - fv_old
        df = load - load_old
        p0 = self.last_pressure if base is None else self.start_pressure
        pressed = np.flatnonzero(p0 > 0)
        u = np.zeros(self.model.ndofs)
        u[self.free] = x
        u[self.fixed] = fv_old
        old = self.kinematics.against(ob_old)
        dg = self.kinematics.against(obstacle).gaps(u, pressed) - old.gaps(u, pressed)  # from the obstacle motion alone
        if not (np.any(du_d) or np.any(df) or np.any(dg)):
            return x
        try:
            K = self.body.tangent(u).tocsr()
            Kf = K[self.free]
            Bm = old.evaluate(u, pressed).gradient()
            k = eps * self.weights[pressed]
            J = Kf[:, self.free] + Bm.T @ sp.diags(k) @ Bm
            rhs = df[self.free] - Kf[:, self.fixed] @ du_d - Bm.T @ (k * dg)
            self._factor_stiffness = None
            dx = linear_solve(J, rhs, self.solver)
            self.linear_solves += 1
            trial = x + dx
            u_new = u.copy()
            u_new[self.free] = trial
            u_new[self.fixed] = fixed_values
            fint = self.body.internal_force(u_new)  # raises for inverted elements
            if np.all(np.isfinite(fint)) and np.all(np.isfinite(trial)):
                # predicted pressures: the springs' force change eps_N (dg + B dx) on the pressed points
                p = p0.copy()
                p[pressed] = np.maximum(p[pressed] + eps * (dg + Bm @ dx), 0.0)
                self.start_pressure = p
                return trial
        except (InvertedElementError, np.linalg.LinAlgError):
            pass
        logger.debug("tangent predictor rejected; the step starts from the last converged state")
        return x

    # ------------------------------------------------------------------ kinematics
    @property
    def obstacle(self):
        """The master of the load step (that of :attr:`kinematics`; :meth:`configure` moves it)."""
        return self.kinematics.master

    @obstacle.setter
    def obstacle(self, master) -> None:
        self.kinematics.master = master

    def _current(self, u: np.ndarray, idx: np.ndarray) -> np.ndarray:
        return self.kinematics.current(u, idx)

    def all_gaps(self, u: np.ndarray) -> np.ndarray:
        """Gaps :math:`\\operatorname{gap}(X_i + u_i)` of every contact-boundary point (normals updated)."""
        ev = self.kinematics.evaluate(u)
        self.normals = ev.normals
        return ev.g

    def gaps(self, x: np.ndarray) -> np.ndarray:
        """Gaps of the candidates for the free displacement ``x``."""
        return self.kinematics.gaps(self.expand(x), self.cand)

    def _point_blocks(self, idx: np.ndarray, blocks: np.ndarray) -> sp.csr_matrix:
        """Sparse sum of the ``d x d`` blocks of the points ``idx`` on their free DOFs."""
        return point_blocks(self.pos[idx], blocks, self.free.size)

    # ------------------------------------------------------------------ body
    def _body_state(self, u: np.ndarray, energy: bool):
        """``(f_int - f_ext, Pi_body)``; raises InvertedElementError for J <= 0.

        The internal force and stored energy of the last state are kept: a subproblem starts
        where the last one stopped (new multipliers, same state), and the residual function and
        the Newton systems evaluate the same state more than once.
        """
        kept = getattr(self, "_kept_body", None)
        if kept is not None and np.array_equal(kept[0], u):
            _, fint, e_int = kept
        else:
            fint = np.asarray(self.body.internal_force(u), dtype=float)
            if not np.all(np.isfinite(fint)):
                raise InvertedElementError("non-finite internal force (an element is inverted or degenerate)")
            e_int = None
        if energy and e_int is None:
            e_int = float(self.body.energy(u))
        self._kept_body = (np.array(u, dtype=float), fint, e_int)
        e = e_int - float(self.load @ u) if energy else np.nan
        return fint - self.load, e

    def _free_tangent_data(self, u: np.ndarray):
        """``(layout, values)`` of the free block of :math:`K_T(u)` on its fixed structure
        (:class:`~._finite_matrices.NewtonLayout`), or ``(None, matrix)`` for a body without
        :meth:`tangent_data <alcontact.fem.hyperelastic.Hyperelastic.tangent_data>`."""
        body = self.body
        if not hasattr(body, "tangent_data"):
            K = body.tangent(u).tocsr()
            return None, K[self.free][:, self.free]
        indptr, indices = body.tangent_pattern
        layout = getattr(self, "_layout", None)
        if layout is None or not layout.matches(indptr, indices):
            layout = NewtonLayout(indptr, indices, self.free, self.pos, self._movable_pts)
            self._layout = layout
        kdata = body.tangent_data(u)
        if not layout.complete:
            K = sp.csr_matrix((kdata, indices, indptr), shape=(body.ndofs, body.ndofs))
            return None, K[self.free][:, self.free]
        return layout, layout.free_block(kdata)

    def _tangent_free(self, u: np.ndarray) -> sp.csr_matrix:
        """Free block of :math:`K_T(u)` (CSR; on the fixed structure of :attr:`_layout` where the body has one)."""
        layout, data = self._free_tangent_data(u)
        return data if layout is None else layout.matrix(data)

    def _tangent_blocks(self, u: np.ndarray, idx: np.ndarray, blocks: np.ndarray) -> sp.csr_matrix:
        """Free block of :math:`K_T(u)` plus the ``d x d`` ``blocks`` of the points ``idx``."""
        layout, data = self._free_tangent_data(u)
        if layout is None:
            return data + self._point_blocks(idx, blocks)
        layout.add_blocks(data, idx, blocks)
        return layout.matrix(data)

    # ------------------------------------------- interface of the outer loops
    def start(self) -> np.ndarray:
        return self.x0.copy()

    def initial_multipliers(self) -> np.ndarray:
        """Starting pressures of the step on the current candidates (warm start).

        Those of the last accepted load step, updated by the tangent predictor where it ran
        (:meth:`configure`): the pressed points' spring forces of the linearized step.
        """
        return self.start_pressure[self.cand].copy()

    def accept(self, pressure: np.ndarray) -> None:
        """Record the data and pressures (all points) of an accepted load step (next warm start)."""
        self.last_pressure = np.asarray(pressure, dtype=float).copy()
        self._accepted = (self.fixed_values, self.load, self.obstacle)
        # the last two accepted steps: [data, converged state (set by the next configure), pressures]
        self._history = self._history[-1:] + [[self._accepted, None, self.last_pressure]]

    def scale_forces(self, x: np.ndarray, factor: float) -> np.ndarray:
        r"""Contact forces scaled by ``factor``, to first order (used for barrier starting points).

        At an equilibrium ``x`` the contact forces balance the body, :math:`B^T r = -(f_{int} -
        f_{ext})`, so scaling them changes the state by
        :math:`\Delta x = (\text{factor} - 1)\, K_T^{-1} (f_{int} - f_{ext})` (exact for a linear body).
        """
        try:
            u = self.expand(x)
            rb, _ = self._body_state(u, False)
            rhs = rb[self.free]
            if not np.any(rhs):
                return np.array(x, dtype=float)
            self._factor_stiffness = None
            dx = linear_solve(self._tangent_free(u), (factor - 1.0) * rhs, self.solver)
            self.linear_solves += 1
            return np.asarray(x, dtype=float) + dx
        except (InvertedElementError, np.linalg.LinAlgError):
            return np.array(x, dtype=float)

    def final_displacement(self, x: np.ndarray) -> np.ndarray:
        return self.expand(x)

    def timings(self) -> dict:
        return {"setup_s": self.setup_seconds, "factor_s": 0.0, "assembly_s": self.assembly_seconds,
                "linear_solve_s": self.solve_seconds}

    def extra(self) -> dict:
        return {**self.solver.info(), "strategy": self.strategy, "kinematics": "finite", "newton_total": int(self.newton_iterations),
                "chord_steps": int(self.chord_steps)}

    def force_scale(self, r_body: np.ndarray, contact: np.ndarray) -> float:
        """Force unit of the relative residuals: largest external, internal (reaction) or contact force.

        ``r_body`` is :math:`f_{int} - f_{ext}` on all DOFs, ``contact`` the contact forces.
        """
        fmax = float(np.max(np.abs(self.load), initial=0.0))
        return max(fmax, float(np.max(np.abs(r_body + self.load), initial=0.0)),
                   float(np.max(np.abs(contact), initial=0.0)), 1e-300)

    # ------------------------------------------------------------------ subproblem (S)
    def residual(self, law, lam, x: np.ndarray) -> np.ndarray:
        r""":math:`R(x) = f_{int}(u) - f_{ext} + B(u)^T (w \circ t_N(g(u)))` on the free DOFs (module doc)."""
        u = self.expand(x)
        rb, _ = self._body_state(u, False)
        ev = self.kinematics.evaluate(u, self.cand)
        t = law.traction(ev.g, lam)
        return rb[self.free] + ev.gradient().T @ (self.weights[self.cand] * t)

    def jacobian(self, law, lam, x: np.ndarray) -> sp.csr_matrix:
        r"""Consistent tangent :math:`J(x) = \partial R/\partial x` with the curvature term (module doc)."""
        u = self.expand(x)
        g = self.kinematics.gaps(u, self.cand)
        return self._newton_matrix(u, law.traction(g, lam), law.stiffness(g, lam))

    def _newton_matrix(self, u, t, D, *, curvature: bool = True) -> sp.csr_matrix:
        r""":math:`K_T + B^T \operatorname{diag}(w D) B + \sum_i w_i t_i H_i` at ``u`` (candidates); without the
        last (curvature) term for ``curvature=False`` (a kinematics that is not pointwise only)."""
        cand = self.cand
        w = self.weights[cand]
        ev = self.kinematics.evaluate(u, cand, hessian=True)
        nu, H = ev.normals, ev.hessian
        layout, data = self._free_tangent_data(u)
        if layout is None or not self.kinematics.pointwise:
            # the gap's gradient and curvature as sparse matrices (a kinematics coupling several points)
            Bm = ev.gradient()
            K = data if layout is None else layout.matrix(data)
            J = K + Bm.T @ sp.diags(w * D) @ Bm
            return (J + ev.curvature(w * t) if curvature else J).tocsr()
        # B^T diag(w D) B is the block (-nu_i w_i D_i)(-nu_i)^T of every point (the products of the sparse
        # product, in its order), added before the curvature blocks as the sparse sum did
        layout.add_blocks(data, cand, ((-nu) * (w * D)[:, None])[:, :, None] * (-nu)[:, None, :])
        layout.add_blocks(data, cand, (w * t)[:, None, None] * H)
        return layout.matrix(data)

    def subproblem(self, law, lam, x0, *, tol: float, maxiter: int) -> NewtonOutcome:
        """Newton's method for :math:`R(x) = 0` of subproblem (S) (module doc, :class:`_Subproblem`)."""
        log: list[float] = []
        self.residual_log.append(log)
        system = _Subproblem(self, law, np.asarray(lam, dtype=float))
        system.tol = float(tol)
        try:
            out = newton(system, x0, tol=tol, maxiter=maxiter, settings=_SETTINGS, log=log)
        except InvertedElementError as exc:
            x = np.array(x0, dtype=float)
            return NewtonOutcome(x, self.gaps(x), np.zeros(self.cand.size), 0, Status.NEWTON_FAILED, np.inf,
                                 f"inverted element at the starting state ({exc})")
        return subproblem_outcome(out, out.state.g, out.state.t)

    def multiplier_step(self, law, lam, out, *, rtol: float = 1e-8, maxiter: int = 10) -> np.ndarray | None:
        r"""Second-order multiplier update of Algorithm 6.1 (a Newton step on the dual), or ``None``.

        At the subproblem's solution :math:`x(\lambda)` the points with
        :math:`t_{N,i} > 0` form the active set :math:`A`; with :math:`S = B_A J^{-1} B_A^T`
        (:math:`J` the Newton matrix of (S), whose factor the last Newton iteration left in
        :attr:`solver`) the linearized gaps vanish, :math:`g_A - S\,W_A\Delta\lambda_A = 0`,
        for the update solved here by conjugate gradients preconditioned with the
        first-order step :math:`(\varepsilon_N W_A)^{-1}` (the Macaulay update (6.13) is one
        Richardson step of this system; its contraction :math:`1/(1 + \varepsilon_N \sigma)`
        per outer iteration becomes a few back-substitutions). The step
        is semi-smooth: a point the entry shift (:meth:`entry_multipliers`) kept out that still
        penetrates (:math:`\lambda_i < 0`, :math:`t_{N,i} = 0`, :math:`g_i > 0`: with the clipped
        multiplier :math:`\langle\lambda_i\rangle + g_i/\eta_i > 0`) enters :math:`A` with
        :math:`\lambda_i = 0` and preconditioner :math:`1/\eta_i`, so its gap is closed by the
        dual step and its force enters the primal correction (before, it entered the next
        subproblem with its full penalty force, and that Newton released such points one per
        iteration); an entering point whose multiplier comes out negative leaves :math:`A`
        again and the system is re-solved. Returns the new multipliers
        on the candidates (zero off :math:`A`, clipped at zero) with the next starting state :math:`x - J^{-1} B_A^T W_A
        \Delta\lambda_A` (the primal change of the dual step), or ``None`` when no factor of
        the current candidates is at hand or the subproblem took no Newton iteration (the
        caller keeps the first-order update).
        """
        t = np.asarray(out.t, dtype=float)
        g_all = np.asarray(out.g, dtype=float)
        lam_all = np.asarray(lam, dtype=float)
        if not np.any(t > 0) or out.iterations == 0:
            # no Newton iteration: the state is a start (e.g. a primal correction), not x(lambda),
            # and the factor at hand is another state's; the first-order update is safer
            return None
        eps_all = np.asarray(law.stiffness(g_all, lam_all), dtype=float)
        # points kept out by the entry shift (lambda_i < 0, no traction) that still penetrate: a
        # semi-smooth step takes them into A with the clipped multiplier 0 (lambda + g/eta > 0)
        enter = (t <= 0) & (lam_all < 0) & (g_all > 0)
        eta = getattr(law, "eta", None)
        if np.any(enter) and eta is not None:
            eps_enter = 1.0 / np.broadcast_to(np.asarray(eta, dtype=float), t.shape)
        else:
            enter[:] = False
            eps_enter = eps_all
        base = np.flatnonzero(t > 0)
        if not np.all(eps_all[base] > 0):
            return None
        u_state = self.expand(out.state)
        for _ in range(4):  # the entering points that would pull leave A again (a few re-solves)
            act = np.flatnonzero((t > 0) | enter)
            result = self._dual_newton(act, np.where(enter, eps_enter, eps_all)[act],
                                       np.where(enter, 0.0, lam_all)[act], g_all[act], u_state, rtol, maxiter)
            if result is None:
                return None
            lam_a, y, Bm, w = result
            pulls = enter[act] & (lam_a + y / w < 0)
            if not np.any(pulls):
                break
            enter[act[pulls]] = False
        new = np.zeros_like(t)
        new[act] = np.maximum(lam_a + y / w, 0.0)
        # the primal change the dual step implies at fixed Newton matrix: J dx = -B_A^T W_A dlam_A
        dx = self.solver.resolve(-(Bm.T @ (w * (new[act] - lam_a))))
        if dx is None or not np.all(np.isfinite(dx)):
            return new
        x_new = np.asarray(out.state, dtype=float) + dx
        try:  # a primal change that inverts an element is no start for the next subproblem: the multipliers only
            self._body_state(self.expand(x_new), False)
        except InvertedElementError:
            return new
        return new, x_new

    def start_multiplier_step(self, law, lam, out):
        r"""Initial multipliers of Algorithm 6.3 from its penalty start (:attr:`warm_penalty_start`), or ``None``.

        :meth:`multiplier_step` on the start's subproblem (the Macaulay law of
        :func:`~alcontact.contact.algorithms._frictionless._penalty_start`): the Newton step on the dual with
        its primal correction, the entering points of the semi-smooth step included. Its products
        are solved to ``_START_RESOLVE_RTOL`` where the solver's back-substitutions are iterative
        (``solver.resolve_rtol``, AMG + CG: 1e-2 for the dual steps of Algorithm 6.1, which the
        next subproblem corrects): the first-order MET iterations that follow keep the start's error
        for several outer iterations (half-cylinder P2 ``n = 4``, 4 steps, exp-met1: 11 11 9 10 Newton
        per step with 1e-2, 7 7 6 7 with 1e-8 as on the direct path). ``None`` where
        :meth:`multiplier_step` gives none (the caller keeps the start's tractions).
        """
        rtol = getattr(self.solver, "resolve_rtol", None)
        if rtol is None:
            return self.multiplier_step(law, lam, out)
        self.solver.resolve_rtol = min(float(rtol), _START_RESOLVE_RTOL)
        try:
            return self.multiplier_step(law, lam, out)
        finally:
            self.solver.resolve_rtol = rtol

    def _dual_newton(self, act, eps, lam_a, g, u_state, rtol, maxiter):
        r"""Solve :math:`S\,y = g_A`, :math:`S = B_A J^{-1} B_A^T`, by preconditioned CG (:meth:`multiplier_step`).

        Returns ``(lam_a, y, B_A, w_A)`` (``y = W_A \Delta\lambda_A``, forces) or ``None`` when no
        factor is at hand or the iteration breaks down.
        """
        pts = self.cand[act]
        Bm = self.kinematics.evaluate(u_state, pts).gradient()
        w = self.weights[pts]

        def S(v):
            z = self.solver.resolve(Bm.T @ v)
            if z is None:
                raise np.linalg.LinAlgError("no factor")
            return Bm @ z

        try:  # preconditioned CG on S y = g_A, y = W_A dlam (forces); M^-1 = eps W
            y = np.zeros(act.size)
            r = g.copy()
            z = eps * w * r
            p = z.copy()
            rz = float(r @ z)
            r0 = np.sqrt(abs(rz))
            for _ in range(maxiter):
                Sp = S(p)
                pSp = float(p @ Sp)
                if not pSp > 0:
                    break
                a = rz / pSp
                y += a * p
                r -= a * Sp
                z = eps * w * r
                rz_new = float(r @ z)
                if np.sqrt(abs(rz_new)) <= rtol * r0:
                    break
                p = z + (rz_new / rz) * p
                rz = rz_new
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(y)):
            return None
        return lam_a, y, Bm, w

    # ------------------------------------------------------------------ reference (active set)
    def initial_active(self, lam: np.ndarray, g: np.ndarray, c: float) -> np.ndarray:
        r"""Starting active set of :func:`~alcontact.contact.algorithms._frictionless.run_ssn` on the candidates.

        The semi-smooth rule :math:`\lambda_i + c\,g_i > 0` at the starting state, except after
        the secant predictor (:meth:`configure`) or the tangent predictor of a first contact
        (no point pressed yet): there a point without predicted pressure
        starts active only when its extrapolated gap exceeds ``_ENTRY_FRACTION`` of its predicted
        approach :math:`\Delta g_i` (it crosses the obstacle in the first half of the step).
        Linear extrapolation overestimates the approach of the points beyond the contact edge
        (the contact zone flattens as it grows); the active-set iteration releases wrongly
        active points one per Newton step (the edge point pulls, its neighbour takes over),
        but takes in all penetrating points at once.

        After the slide predictor a point with carried pressure also starts active where it is open by at
        most :attr:`slide_start_reach` :math:`h` at the predicted state (as in :meth:`entry_multipliers`): the
        carried displacement interpolates the deformed surface between nodes, so a pressed point of the
        carried zone can sit slightly off the obstacle, and with :math:`c = \varepsilon_N` (100 E'/h) the
        rule drops it for a gap of 1e-3 h. On a coarse case (cylinder radius 2 elements, slid 0.44 R per
        step; ``tests/regression/test_determinism_finite_sliding.py``) the rule started a step with one of
        three pressed points active: 54 Newton iterations and a cut-back (4-5 with ``predictor = "tangent"``);
        with the carried zone 3-4. Ironing 2d-s (40 sliding steps of 0.05 R): 3.65 / 5 -> 3.00 / 3 Newton
        per step (mean / max). Every carried point (any gap) made the coarse case fail.
        """
        lam = np.asarray(lam, dtype=float)
        g = np.asarray(g, dtype=float)
        rule = (lam + c * g) > 0
        if self.predictor_used == "slide":
            # the carried contact zone: a point with carried pressure open by at most slide_start_reach h
            return rule | ((lam > 0) & (g > -self.slide_start_reach * self.h))
        if self.predicted_approach is None:
            return rule
        dg = np.maximum(self.predicted_approach[self.cand], 0.0)
        return (lam > 0) & rule | (g > _ENTRY_FRACTION * dg) & (dg > 0)

    def entry_multipliers(self, lam: np.ndarray, law, *, penalty_start: bool = False) -> np.ndarray:
        r"""Starting multipliers of Algorithm 6.1 with the entry rule of :meth:`initial_active`.

        After the secant predictor the Macaulay law :math:`t_N = \langle\lambda + g/\eta\rangle`
        of subproblem (S) would load every extrapolated penetration with a penalty force, so the
        primal Newton releases the over-predicted points beyond the contact edge one per
        iteration (they pull; their neighbour takes over). A point without predicted pressure
        that :meth:`initial_active` keeps out of the starting set gets the multiplier
        :math:`\lambda_i = -g_i/\eta_i` instead: its traction is zero at the start and grows only
        if the point penetrates deeper than predicted (applied only where the law's traction
        vanishes at the shifted multiplier: the Macaulay law). The shift acts in the first subproblem
        only: the multiplier update (6.13) or :meth:`multiplier_step` gives it
        :math:`\langle\lambda_i + g_i/\eta_i\rangle \ge 0` at the subproblem's solution, where a point
        that still penetrates enters with its full penalty force (all at once). Unchanged
        (``lam``) without a predicted approach (secant prediction, first contact).

        After the slide predictor the pressed points get
        :math:`\lambda_i = p_i - g_i/\eta_i` instead, so that the starting traction is the carried
        pressure :math:`p_i`. With ``penalty_start`` (the penalty start of Algorithm 6.3,
        :func:`~alcontact.contact.algorithms._frictionless._penalty_start`) a point open by more than
        :attr:`slide_start_reach` :math:`h` at the predicted state (option ``slide_start_reach``) keeps :math:`\lambda_i = p_i`
        (its Macaulay traction is zero there).
        """
        lam = np.asarray(lam, dtype=float)
        if self.predictor_used == "slide":
            # the carried pressures as the starting tractions: lambda_i = p_i - g_i / eta_i on the pressed points
            g = self.gaps(self.x0)
            c = 1.0 / np.asarray(law.eta, dtype=float)
            pressed = lam > 0
            if penalty_start:
                # an open point's carried pressure is interpolated across the contact edge: no start traction
                pressed &= g > -self.slide_start_reach * self.h
            shifted = np.where(pressed, lam - c * g, lam)
            same = np.asarray(law.traction(g, shifted), dtype=float)
            return np.where(pressed & np.isclose(same, lam, rtol=1e-12, atol=0.0), shifted, lam)
        if self.predicted_approach is None:
            return lam
        g = self.gaps(self.x0)
        c = 1.0 / np.asarray(law.eta, dtype=float)
        kept_out = ~np.asarray(self.initial_active(lam, g, c), dtype=bool) & (lam + c * g > 0)
        shifted = np.where(kept_out, -c * g, lam)
        # only where the law's traction vanishes there (the Macaulay law; no other law is shifted)
        free = np.asarray(law.traction(g, shifted), dtype=float) <= 0.0
        return np.where(kept_out & free, shifted, lam)

    def solve_active(self, active, lam, x, c, *, tol: float = 1e-12, maxiter: int = 50):
        r"""Active-set step of :func:`run_ssn`, as a semi-smooth Newton method (Alart-Curnier type).

        Newton's method on the saddle-point system of :math:`g_A(u) = 0` (module doc),
        with the active set re-predicted after every Newton step from
        :math:`\lambda_i + c\,g_i > 0` on all candidates and switched as soon as it changes
        (a Newton step of :math:`\lambda - \max(0, \lambda + c g) = 0`), so the outer
        active-set loop mostly finds its set settled. Returns ``(x, lam_new, g)`` with the
        pressures ``lam_new`` (zero off the final active set) and the gaps of all candidates.
        Whether the last Newton solve converged is left in :attr:`active_converged` (with its
        relative residual in :attr:`active_residual`): a solve that stopped at its budget or
        stalled is a failure of the step (``run_ssn`` returns ``NEWTON_FAILED`` and the load
        step is cut back), never a state to accept because its active set settled. A switch into
        a set entered before (single Newton steps whose predicted sets cycle: a point of the
        contact zone released after one step penetrates, taken back, its neighbour released, ...;
        two-body ironing, 4-cycles until the budget ran out) solves that set to convergence before
        the next switch, from gaps that are no longer a single Newton step's.
        """
        active = np.asarray(active, dtype=bool).copy()
        lam_all = np.where(active, np.maximum(np.asarray(lam, dtype=float), 0.0), 0.0)
        x = np.array(x, dtype=float)
        budget = int(maxiter)
        converged_sets = set()
        entered = {active.tobytes()}
        switch = True
        ok = False
        while budget > 0:
            x, lam_all, ok, used = self._equality_newton(active, lam_all, x, c, tol, budget, switch=switch)
            budget -= used
            new_active = (lam_all + c * self.gaps(x)) > 0
            if ok:
                key = active.tobytes()
                if np.array_equal(new_active, active) or key in converged_sets:
                    break
                converged_sets.add(key)  # converged on a set that changes: the outer loop goes on from here
            elif np.array_equal(new_active, active):
                break  # the equality Newton failed on a settled set (logged there)
            # a set entered before (the switches after single Newton steps cycle): solve it before switching again
            switch = new_active.tobytes() not in entered
            entered.add(new_active.tobytes())
            lam_all = np.where(new_active, lam_all, 0.0)
            active = new_active
        self.active_converged = bool(ok)
        self.active_residual = float(self._last_equality_residual)
        return x, np.where(active, lam_all, 0.0), self.gaps(x)

    def _saddle_rows(self) -> np.ndarray:
        """Row of every candidate among the constraint rows of :meth:`_saddle_matrix`."""
        rows = -np.ones(self.points.shape[0], dtype=np.int64)
        rows[self._movable_pts] = np.arange(self._movable_pts.size)
        return rows[self.cand]

    def _saddle_matrix(self, u, Kt, active) -> sp.spmatrix:
        r"""Saddle-point matrix of :meth:`_equality_newton` over all movable contact points (one pattern).

        One constraint row per movable point of the contact boundary (:meth:`_saddle_rows`
        gives the candidates' rows); the rows of the inactive candidates and of the
        non-candidates read :math:`\Delta r_i = 0` (a unit diagonal, their constraint row
        stored as explicit zeros), so the pattern is that of the whole run and
        :class:`NewtonSolver` keeps one analysis while the active set and the candidates
        of the load steps change (a new analysis per step cost about one factorization).
        """
        pts = self._movable_pts
        on = np.zeros(pts.size, dtype=bool)
        on[self._saddle_rows()] = active
        ev = self.kinematics.evaluate(u, pts)
        layout = getattr(self, "_layout", None)
        if layout is not None and layout.built_here(Kt) and self.kinematics.pointwise:
            return layout.saddle(Kt.data, ev.normals, on)  # the same matrix on its fixed structure
        Bc = ev.gradient(on)
        nc = pts.size
        D = sp.csr_matrix(((~on).astype(float), np.arange(nc), np.arange(nc + 1)), shape=(nc, nc))
        return sp.bmat([[Kt, Bc.T], [Bc, D]], format="csc")

    def _equality_newton(self, active, lam_all, x, c, tol, maxiter, *, switch: bool = True):
        """Newton on :math:`g_A = 0` (saddle point, :class:`_EqualityNewton`); stops early when the
        predicted active set changes (unless ``switch`` is false: then it solves on ``active``).

        Returns ``(x, lam_all, converged, newton_steps)``. An inverted element at the start
        propagates (the load step is cut back).
        """
        log: list[float] = []
        self.residual_log.append(log)
        system = _EqualityNewton(self, active, lam_all, c, tol)
        system.switch = switch
        z0 = np.concatenate([np.asarray(x, dtype=float), system.r0])
        out = newton(system, z0, tol=tol, maxiter=maxiter, settings=_EQUALITY_SETTINGS, log=log)
        x_new, r = system.split(out.x)
        self._last_equality_residual = float(out.residual)
        if not out.converged and not system.switched:
            logger.warning("active-set Newton with %d active points stopped (%s) at relative residual %.2e after "
                           "%d steps", system.A.size, out.message, out.residual, out.iterations)
        return x_new, system.lam_of(r), out.converged, out.iterations


# ---------------------------------------------------------------------- the Newton systems of FiniteContact
#: subproblem (S): Armijo on the energy (or |R|^2/2) or a residual decrease, inverted elements halve the step
_SETTINGS = NewtonSettings(LineSearch(halvings=_MAX_HALVINGS, armijo=_ARMIJO, residual_decrease=True,
                                      residual_merit_slack=_MERIT_SLACK))
#: active-set reference: backtracking on the relative residual, any step below 2**-20 accepted
_EQUALITY_SETTINGS = NewtonSettings(LineSearch(halvings=_MAX_HALVINGS, armijo=_ARMIJO, merit=False,
                                               measure_decrease=True, accept_below=2.0**-20, full_step=False),
                                    stall_from=3)


def _springs_on(D: np.ndarray) -> np.ndarray:
    r"""The candidates whose contact spring :math:`\partial t_N/\partial g` counts in a chord step's comparison
    (:meth:`_Subproblem._chord`): above :data:`_CHORD_SPRING` of the largest.

    A barrier-type law (log MET 1/2) keeps a spring at every open candidate (its floored multiplier,
    ``multiplier_floor``): on the 3D ironing case at most 3e-22 of the largest spring; the factor of the
    Macaulay law that Algorithm 6.3's penalty start leaves has none there. A chord step with that factor
    misses springs that change the Newton matrix by less than 1e-8 of its contact part: it contracts as a
    new tangent would. Compared by sign (``D > 0``),
    as before issue 18, the last MET subproblem of every sliding step of the 3D ironing case took a new
    tangent for a residual of 3e-12 (log-met1 3d-s 6.55 Newton per step, 5.58 with this comparison, as
    exp-met1 and quad-met1, whose springs underflow to zero there).
    """
    D = np.asarray(D, dtype=float)
    return D > _CHORD_SPRING * float(np.max(D, initial=0.0))


@dataclass
class _SubState:
    """State of :class:`_Subproblem` at one iterate."""

    u: np.ndarray
    g: np.ndarray
    t: np.ndarray
    R: np.ndarray
    pi: float
    r_body: np.ndarray
    inside: bool


def _contact_roundoff_floor(coord: float, w: np.ndarray, stiffness: np.ndarray, scale: float) -> float:
    """Round-off floor of a subproblem's relative residual: gaps (and slips) computed from absolute
    coordinates of size ``coord`` carry an error of a few ulps, times the contact ``stiffness`` and the
    weights ``w`` of the points, over the force ``scale`` (1e3 ulps: the sums of the assembly)."""
    return 1e3 * _EPS * coord * float(np.max(w * stiffness, initial=0.0)) / max(scale, 1e-300)


class _Subproblem(NewtonSystem):
    """Subproblem (S) of :class:`FiniteContact` (module doc) for :func:`~._newton.newton`.

    Merit: the total energy where the body has one (decided at the start), else
    :math:`\\tfrac12|R|^2`. The relative residual is :math:`\\max|R|` over the force unit
    (:meth:`FiniteContact.force_scale` at the start, raised by the contact forces of every
    iterate); a stall counts as converged below ``max(1e-8, floor)``, ``floor`` the round-off
    of the contact forces (gaps from absolute coordinates times the contact stiffness).
    """

    domain_errors = (InvertedElementError,)

    def __init__(self, fc, law, lam):
        self.fc, self.law, self.lam = fc, law, lam
        self.w = fc.weights[fc.cand]
        self.use_energy = None
        self.scale = None
        self.coord = 1.0
        self.floor = 0.0
        self.tol = 0.0
        self.chords = 0
        #: Newton steps taken without the gap curvature (an indefinite Newton matrix, :meth:`step`)
        self.descent_steps = 0

    def evaluate(self, x):
        fc, cand, w = self.fc, self.fc.cand, self.w
        need_energy = self.use_energy is not False
        u = fc.expand(x)
        r_body, e_body = fc._body_state(u, need_energy)
        ev = fc.kinematics.evaluate(u, cand)
        g = ev.g
        t = self.law.traction(g, self.lam)
        R = r_body[fc.free] + ev.gradient().T @ (w * t)
        inside = True
        pi = np.nan
        if need_energy:
            e_pen = self.law.energy(g, self.lam)
            inside = bool(np.all(np.isfinite(e_pen)))
            pi = e_body + float(np.sum(w * e_pen))
        if self.use_energy is None:  # the start: globalize on the energy where the body has one
            # (a NaN penalty energy keeps the NaN merit: the driver reports NONFINITE)
            self.use_energy = bool(np.isfinite(pi)) or bool(np.any(np.isnan(e_pen)))
            self.coord = float(np.max(np.abs(fc._current(u, cand)), initial=1.0))
        return _SubState(u, g, t, R, pi, r_body, inside)

    def residual(self, state):
        return state.R

    def merit(self, state):
        return state.pi if self.use_energy else 0.5 * float(state.R @ state.R)

    def slope(self, x, state, dx):
        return float(state.R @ dx) if self.use_energy else -float(state.R @ state.R)

    def inside(self, state):
        return state.inside

    def measure(self, state):
        if self.scale is None:
            self.scale = self.fc.force_scale(state.r_body, self.w * state.t)
        else:
            self.scale = max(self.scale, float(np.max(np.abs(self.w * state.t), initial=0.0)))
        return float(np.max(np.abs(state.R), initial=0.0)) / self.scale

    def stall_level(self, state, level):
        return max(level, self.floor)

    def _chord(self, state, history, D) -> bool:
        """Whether the next correction may reuse the factor at hand (a chord step, :meth:`step`)."""
        fc = self.fc
        rec = getattr(fc, "_factor_stiffness", None)
        res = history[-1].residual if history else np.inf
        if rec is None or self.chords >= _MAX_CHORDS:
            return False
        if not (self.tol < res <= _CHORD_LEVEL):
            return False
        cand, d = rec
        return (cand.shape == fc.cand.shape and np.array_equal(cand, fc.cand)
                and np.array_equal(_springs_on(d), _springs_on(D)))

    def step(self, x, state, history):
        fc = self.fc
        ta = time.perf_counter()
        D = self.law.stiffness(state.g, self.lam)
        if self._chord(state, history, D):
            # near convergence (and near the round-off floor ||K|| ulp(u) of large meshes) the
            # factor at hand does as well as a new tangent: a chord step, no assembly
            dx = fc.solver.resolve(-state.R)
            if dx is not None and np.all(np.isfinite(dx)):
                fc.solve_seconds += time.perf_counter() - ta
                fc.chord_steps += 1
                self.chords += 1
                return dx
        self.floor = _contact_roundoff_floor(self.coord, self.w, np.abs(D), self.scale)
        J = fc._newton_matrix(state.u, state.t, D)
        tb = time.perf_counter()
        fc.assembly_seconds += tb - ta
        fc._factor_stiffness = (fc.cand, D)  # the contact springs in the factor (chord steps, _Subproblem._chord)
        dx = fc.solver.newton_step(J, -state.R, history)
        fc.linear_solves += 1
        if self.use_energy and not fc.kinematics.pointwise and float(state.R @ dx) >= 0.0:
            # an ascent direction: the curvature of a mortar gap (of order w t / h under the large tractions
            # of a subproblem's start) made the Newton matrix indefinite; the step without it descends
            J = fc._newton_matrix(state.u, state.t, D, curvature=False)
            dx = fc.solver.newton_step(J, -state.R, history)
            fc.linear_solves += 1
            self.descent_steps += 1
        fc.solve_seconds += time.perf_counter() - tb
        fc.newton_iterations += 1
        return dx


class _EqualityNewton(NewtonSystem):
    """Newton on :math:`g_A(u) = 0` with the saddle-point matrix (:meth:`FiniteContact._equality_newton`).

    Unknowns ``z = (x, r_A)`` (free displacement, contact forces of the active points). The
    relative residual is the larger of :math:`\\max|R|` over the running force unit and
    :math:`\\max|g_A|/h`; after a full step the predicted active set
    :math:`\\lambda + c\\,g > 0` is compared with ``active`` and a change stops the iteration
    (semi-smooth Newton switches at once).
    """

    domain_errors = (InvertedElementError,)

    def __init__(self, fc, active, lam_all, c, tol):
        self.fc, self.active, self.c, self.tol = fc, active, c, tol
        self.idx = np.flatnonzero(active)
        self.A = fc.cand[self.idx]
        self.wA = fc.weights[self.A]
        self.r0 = np.maximum(lam_all[self.idx], 0.0) * self.wA
        self.nf = fc.free.size
        self.rows = fc._saddle_rows()[self.idx]  # constraint rows of the active points in the saddle-point matrix
        self.scale_run = 0.0  # running force unit: a free rigid motion has no forces left to scale by
        self.last = np.inf
        self.switched = False
        #: stop at a change of the predicted active set (off: solve this set first, :meth:`FiniteContact.solve_active`)
        self.switch = True

    def split(self, z):
        return z[:self.nf], z[self.nf:]

    def lam_of(self, r):
        out = np.zeros(self.fc.cand.size)
        out[self.idx] = r / self.wA
        return out

    def evaluate(self, z):
        fc = self.fc
        x, r = self.split(z)
        u = fc.expand(x)
        rb, _ = fc._body_state(u, False)
        ev = fc.kinematics.evaluate(u, self.A)
        gA = ev.g
        R = rb[fc.free] + ev.gradient().T @ r
        return u, gA, R, r, rb, np.concatenate([R, gA])

    def residual(self, state):
        return state[5]

    def measure(self, state):
        _, gA, R, r, rb, _ = state
        self.scale_run = max(self.scale_run, self.fc.force_scale(rb, r))
        self.last = max(float(np.max(np.abs(R), initial=0.0)) / self.scale_run,
                        float(np.max(np.abs(gA), initial=0.0)) / self.fc.h)
        return self.last

    def step(self, z, state, history):
        fc, A = self.fc, self.A
        u, gA, R, r, _, _ = state
        ta = time.perf_counter()
        ev = fc.kinematics.evaluate(u, A, hessian=True)
        Kt = (fc._tangent_blocks(u, A, r[:, None, None] * ev.hessian) if fc.kinematics.pointwise
              else (fc._tangent_free(u) + ev.curvature(r)).tocsr())
        J = fc._saddle_matrix(u, Kt, self.active)
        tb = time.perf_counter()
        fc.assembly_seconds += tb - ta
        rhs_g = np.zeros(J.shape[0] - self.nf)
        rhs_g[self.rows] = gA
        fc._factor_stiffness = None
        step = linear_solve(J, -np.concatenate([R, rhs_g]), fc.solver)
        fc.solve_seconds += time.perf_counter() - tb
        fc.linear_solves += 1
        fc.newton_iterations += 1
        return np.concatenate([step[:self.nf], step[self.nf:][self.rows]])

    def interrupt(self, z, state, alpha):
        if self.switch and alpha == 1.0 and self.last > self.tol:
            # semi-smooth Newton: switch as soon as the predicted active set changes
            x, r = self.split(z)
            predicted = (self.lam_of(r) + self.c * self.fc.gaps(x)) > 0
            if not np.array_equal(predicted, self.active):
                self.switched = True
                return "the predicted active set changed"
        return None


#: configuration of the rigid-body near-null modes (:meth:`AMGNewtonSolver.near_null`). The reference
#: configuration's gave the same CG and Newton counts on both cases of the rebuild factor of
#: :class:`alcontact.linalg.NewtonKrylovSolver` (half-cylinder to delta/R = 0.4: 26.4 CG per Newton step
#: either way); the current one costs nothing more
_MODES = "current"


class AMGNewtonSolver(_linalg.NewtonKrylovSolver):
    r"""Solver of the Newton systems of :class:`~alcontact.contact.systems._full_space.FiniteContact` by AMG + CG.

    :class:`alcontact.linalg.NewtonKrylovSolver` (module doc) with the near-null space of the body:
    its rigid-body modes on the free DOFs at the configuration of :attr:`modes`.

    Parameters
    ----------
    fc : FiniteContact
        The model whose systems are solved (its free DOFs and current configuration give the
        rigid-body near-null space).
    solver : alcontact.linalg.SolverChoice, optional
        The approximate solver whose factors precondition CG (:func:`alcontact.linalg.select_solver`;
        default ``"amg"``, PyAMG smoothed aggregation with sparse LU on a coarsest level of at most
        500 rows).
    modes : {"current", "reference"}, optional
        Configuration of the rigid-body near-null modes; default ``_MODES`` (``"current"``).
    **options
        ``rtol``, ``forcing_max``, ``rebuild_factor``, ``fallback`` of :class:`~alcontact.linalg.NewtonKrylovSolver`.
    """

    #: lowest Newton tolerance its inexact solves reach (:data:`~alcontact.contact.systems._krylov._NEWTON_TOL_FLOOR`)
    tol_floor = _NEWTON_TOL_FLOOR

    def __init__(self, fc, *, solver: _linalg.SolverChoice | None = None, modes: str | None = None, **options):
        modes = _MODES if modes is None else modes
        if modes not in ("current", "reference"):
            raise InputError(f"modes={modes!r}; allowed: current, reference.")
        model = fc.model
        solver = _linalg.select_solver("amg", dim=model.dim, ndofs=model.ndofs) if solver is None else solver
        self.fc = fc
        self.modes = modes
        pts, dofs = model.all_node_dofs()
        self._pts = np.asarray(pts, dtype=float)
        self._dofs = np.asarray(dofs, dtype=np.int64)
        super().__init__(solver, near_null=self.near_null, dim=model.dim, **options)

    def near_null(self) -> np.ndarray:
        """Rigid-body modes ``(n_free, k)`` of the body at the configuration of :attr:`modes`.

        ``"current"``: at :math:`X + u` with ``u`` the displacement of the load step's start
        (:attr:`FiniteContact.u_free <alcontact.contact.systems._full_space.FiniteContact>`).
        """
        pts = self._pts
        if self.modes == "current":
            u = getattr(self.fc, "u_free", None)
            if u is not None:
                pts = pts + np.asarray(u, dtype=float)[self._dofs]
        model = self.fc.model
        # several bodies (a MultiBody): each body's own rigid modes, zero on the others (the kernel of the
        # block-diagonal tangent; the modes of all nodes together are only its common part)
        owner = model.body_of_dofs()[self._dofs[:, 0]] if hasattr(model, "body_of_dofs") else \
            np.zeros(pts.shape[0], dtype=np.int64)
        blocks = []
        for b in np.unique(owner):
            rows = owner == b
            modes, _ = rigid_body_modes(pts[rows])
            R = np.zeros((model.ndofs, modes.shape[-1]))
            R[self._dofs[rows].ravel()] = modes.reshape(-1, modes.shape[-1])
            blocks.append(R)
        return np.ascontiguousarray(np.hstack(blocks)[self.fc.free])

    def info(self) -> dict:
        """:meth:`alcontact.linalg.NewtonKrylovSolver.info` and the near-null configuration."""
        return {**super().info(), "near_null": self.modes}


def finite_solver(linear_solver: str, entry, model, **options):
    """Factory ``fc -> solver`` of the Newton systems of :class:`~alcontact.contact.systems._full_space.FiniteContact`.

    The solver of the ``linear_solver`` option is :func:`alcontact.linalg.select_solver`'s (its
    ``"auto"`` size rule where the algorithm ``entry`` has a Krylov path, :attr:`Algorithm.linear_solvers
    <alcontact.contact.algorithms._frictionless.Algorithm>` listing ``amg``; an exact solver registered for
    symmetric indefinite matrices otherwise). An exact solver factorizes every Newton matrix
    (:class:`~alcontact.contact.systems._full_space.NewtonSolver`); an approximate one preconditions CG with an
    inexact-Newton forcing term (:class:`AMGNewtonSolver`) where the entry has a Krylov path, else
    GMRES around its factor of each matrix (:class:`~alcontact.linalg.SequenceSolver`).

    A mixed u-p body (:class:`~alcontact.fem.MixedHyperelastic`) has saddle-point Newton matrices
    (symmetric indefinite by construction, its pressure block ``-M_p / kappa <= 0``), on which CG
    fails. An approximate solver then runs MINRES with the block-diagonal preconditioner of
    :mod:`alcontact.linalg._saddle` (its hierarchy on the displacement block, the scaled lumped pressure
    mass on the pressure rows: :meth:`MixedHyperelastic.saddle_point
    <alcontact.fem.MixedHyperelastic.saddle_point>`) where the entry has a Krylov path, and GMRES with the
    same preconditioner around each matrix otherwise (``factor-gmres``). ``"auto"`` chooses a direct
    solver for it (measured faster up to 100k DOFs: ``docs/benchmarks/mixed_amg.md``).
    """
    saddle = isinstance(model, MixedHyperelastic)
    solver = _linalg.select_solver(linear_solver, dim=model.dim, ndofs=model.ndofs, matrix_type="symmetric-indefinite",
                                   allow_iterative="amg" in entry.linear_solvers and not saddle)
    if solver.exact:
        return lambda fc: NewtonSolver(solver.name)
    if saddle and "amg" in entry.linear_solvers:
        return lambda fc: AMGNewtonSolver(fc, solver=solver, saddle=model.saddle_point(fc.free), **options)
    if saddle:
        return lambda fc: NewtonSolver(solver.name, saddle=model.saddle_point(fc.free),
                                       near_null=lambda: model.near_null()[fc.free])
    if "amg" not in entry.linear_solvers:
        return lambda fc: NewtonSolver(solver.name)
    return lambda fc: AMGNewtonSolver(fc, solver=solver, **options)


@dataclass
class _Local:
    """Local kinematics and tractions of the candidates at one state."""

    u: np.ndarray
    g: np.ndarray
    nu: np.ndarray
    tN: np.ndarray
    tT: np.ndarray  # (c, d), tangent to the obstacle
    slip: np.ndarray  # (c, d), slip on the obstacle surface (obstacles.surface_slip)
    state: np.ndarray
    R: np.ndarray
    r_body: np.ndarray
    reversals: int | None = None  # see FiniteFrictionStep.state_reversals
    stick_slip_reversals: int | None = None  # see FiniteFrictionStep.stick_slip_reversals

    @property
    def aux(self) -> tuple:
        """``(y, t, Dy, state)`` of the AL loop (:class:`_FiniteALCtx`): ``y = [g, slip]``,
        ``t = [t_N, t_T]`` (``(c, 1 + d)`` each), no tangent ``Dy`` (first-order updates only)."""
        return np.column_stack([self.g, self.slip]), np.column_stack([self.tN, self.tT]), None, self.state


#: a point whose normal traction is at most this fraction of the largest counts as open in the state trace
#: (:func:`contact_states`)
_TRACE_FLOOR = 1e-14


def contact_states(loc: "_Local") -> np.ndarray:
    """The OPEN / STICK / SLIP flags of a state for the state trace (:attr:`FiniteFrictionContact.state_trace`):
    its flags, OPEN where :math:`t_N` is at most :data:`_TRACE_FLOOR` of the largest.

    A family-P law keeps a positive traction at every candidate (``exp-met1``: down to 1e-280 of the largest
    at the open points of the 2D ironing case), whose return mapping flags stick or slip; such a point is
    open to round-off, and its flags flip with the underflow, not with the contact.
    """
    tN = np.asarray(loc.tN, dtype=float)
    return np.where(tN > _TRACE_FLOOR * float(np.max(tN, initial=0.0)), loc.state, OPEN)


class FiniteFrictionContact(FiniteContact):
    """:class:`~alcontact.contact.systems._full_space.FiniteContact` with Coulomb friction (module doc).

    The frictional history of a step is set by :meth:`set_history`: the surface coordinates
    of all contact points at the last converged step (:meth:`surface_points`), the obstacle
    translation of the current step, :math:`\\mu` and :math:`\\varepsilon_T`.
    """

    #: no contact springs: a finite-deformation body is held by its supports (the condensed path's
    #: ``FrictionalContact.spring`` of a body held by the obstacle)
    spring = None
    #: the OPEN / STICK / SLIP flags of the candidates at every Newton iterate of the frictional subproblems
    #: since the caller set it to a list (``None``: not recorded); the stepping engine counts the state
    #: reversals of an accepted AL step from it (:func:`~alcontact.contact.algorithms._coulomb.state_reversals`)
    state_trace: list | None = None

    @property
    def friction_solver(self) -> SequenceSolver:
        """Solver of the non-symmetric Newton matrices of friction: the one of the symmetric systems
        (:attr:`solver`, the ``linear_solver`` option), analyses kept by pattern."""
        solver = getattr(self, "_friction_solver", None)
        if solver is None:
            hints = getattr(self.solver, "hints", None)  # the saddle blocks of a mixed body's matrices
            solver = self._friction_solver = SequenceSolver(
                self.solver.backend, matrix_type="unsymmetric", saddle=None if hints is None else hints.saddle,
                near_null=None if hints is None else hints.near_null)
        return solver

    def set_history(self, y_prev: np.ndarray, mu: float, eps_t: float, radius: str) -> None:
        """Frictional history of the step (call after :meth:`configure` placed the obstacle).

        Parameters
        ----------
        y_prev : ndarray (m, d)
            Surface coordinates of all contact points at the last converged step: their
            projections onto the obstacle in the obstacle's own frame (:meth:`surface_points`).
        mu, eps_t : float
            Coulomb coefficient and tangential penalty.
        radius : {"multiplier", "traction"}
            Radius of the Coulomb disc (module doc).
        """
        self.y_prev = np.asarray(y_prev, dtype=float)
        self.place()
        #: the tangential part of the contact law (Coulomb, the return mapping (6.47)-(6.50))
        self.coulomb = CoulombLaw(mu, eps_t, radius)

    def place(self) -> None:
        """Read the placement :math:`x = Qy + b` of the current obstacle (:func:`~.obstacles.frame`)."""
        self.rotation, self.offset = frame(self.obstacle, self.dim)

    def surface_points(self, u: np.ndarray) -> np.ndarray:
        """Obstacle-fixed surface coordinates :math:`y_i = Q^T(\\bar x_i - b)` of all contact points.

        The projection :math:`\\bar x_i` of :math:`x_i = X_i + u_i` onto the current obstacle,
        taken back to the obstacle's own frame (placement :math:`(Q, b)`, a translation
        :math:`b = c` for ``obstacle_path`` vectors): the point of the obstacle's own
        surface the contact point touches (or faces).
        """
        return (self.obstacle.project(self.points + u[self.dofs]) - self.offset) @ self.rotation

    def _trial(self, lamT, xc, nu, idx, *, blocks: bool):
        r"""Trial tangential traction :math:`z = P\lambda_T + \varepsilon_T\Delta s_T` and the slip.

        :math:`\Delta s_T` is the slip on the obstacle's surface from the previous surface
        point to the projection of :math:`x` (:func:`~alcontact.contact.obstacles.surface_slip`).
        With ``blocks``, also :math:`\partial z/\partial x = (\nu\cdot\lambda_T) H +
        \nu (H\lambda_T)^T + \varepsilon_T\,\partial\Delta s_T/\partial x`.
        """
        y_prev = self.y_prev[idx] @ self.rotation.T + self.offset
        slip, dslip = surface_slip(self.obstacle, xc, y_prev, jacobian=blocks)
        nl = np.einsum("ij,ij->i", nu, lamT)
        z = lamT - nl[:, None] * nu + self.coulomb.eps_t * slip
        if not blocks:
            return z, slip, None, None
        H = self.obstacle.gap_hessian(xc)
        Hl = np.einsum("ijk,ik->ij", H, lamT)
        dz = nl[:, None, None] * H + nu[:, :, None] * Hl[:, None, :] + self.coulomb.eps_t * dslip
        return z, slip, dz, H

    # ------------------------------------------------------------------ local law
    def _local(self, law, lamN, lamT, u, idx, *, blocks: bool):
        xc = self._current(u, idx)
        g, nu = self.obstacle.evaluate(xc)
        tN = np.asarray(law.traction(g, lamN), dtype=float)
        kN = np.asarray(law.stiffness(g, lamN), dtype=float)
        z, slip, dz, H = self._trial(lamT, xc, nu, idx, blocks=blocks)
        if not blocks and not np.all(np.isfinite(tN)):
            # outside the domain of a barrier-type penalty (a line-search trial that its non-finite
            # residual rejects, or a start the AL loop reports): no tangential traction
            return g, nu, tN, np.full_like(z, np.nan), slip, np.full(idx.size, OPEN), None
        rho = self.coulomb.disc_radius(tN, lamN)
        tT, opened, stick, slipping, n, dproj = return_mapping(z, rho)
        state = np.where(opened, OPEN, np.where(stick, STICK, SLIP))
        if not blocks:
            return g, nu, tN, tT, slip, state, None
        dT = dproj @ dz
        if self.coulomb.coupled:
            dT = dT - np.where(slipping[:, None, None], self.coulomb.mu * kN[:, None, None] * n[:, :, None] * nu[:, None, :],
                               0.0)
        K = kN[:, None, None] * nu[:, :, None] * nu[:, None, :] + tN[:, None, None] * H + dT
        return g, nu, tN, tT, slip, state, K

    def _assemble_points(self, idx, vec: np.ndarray) -> np.ndarray:
        """Sum of the point vectors ``vec`` (k, d) onto the free DOFs."""
        out = np.zeros(self.free.size)
        pos = self.pos[idx].ravel()
        keep = pos >= 0
        np.add.at(out, pos[keep], vec.ravel()[keep])
        return out

    def evaluate(self, law, lamN, lamT, x) -> _Local:
        """Residual (module doc) and local state of the candidates at the free displacement ``x``."""
        cand = self.cand
        w = self.weights[cand]
        u = self.expand(x)
        rb, _ = self._body_state(u, False)
        g, nu, tN, tT, slip, state, _ = self._local(law, lamN, lamT, u, cand, blocks=False)
        if np.all(np.isfinite(tN)):
            R = rb[self.free] + self._assemble_points(cand, w[:, None] * (tT - tN[:, None] * nu))
        else:  # outside a barrier's domain (see _local)
            R = np.full(self.free.size, np.nan)
        return _Local(u, g, nu, tN, tT, slip, state, R, rb)

    def friction_jacobian(self, law, lamN, lamT, u) -> sp.csr_matrix:
        """Consistent, non-symmetric Newton matrix of the frictional subproblem (module doc)."""
        cand = self.cand
        w = self.weights[cand]
        *_, K = self._local(law, lamN, lamT, u, cand, blocks=True)
        return (self._tangent_free(u) + self._point_blocks(cand, w[:, None, None] * K)).tocsr()

    def friction_subproblem(self, law, lamN, lamT, x0, *, tol: float, maxiter: int) -> NewtonResult:
        """Newton's method for :math:`R(x) = 0` (module doc, :class:`_FrictionSubproblem`).

        Returns the :class:`~alcontact.contact.algorithms._subproblem.NewtonResult`; its ``state`` is the
        :class:`_Local` state of the last iterate (``None`` when the start inverts an element).
        """
        log: list[float] = []
        self.residual_log.append(log)
        system = _FrictionSubproblem(self, law, lamN, lamT)
        try:
            return newton(system, x0, tol=tol, maxiter=maxiter, settings=_FRICTION_SETTINGS, log=log)
        except InvertedElementError as exc:
            return NewtonResult(np.array(x0, dtype=float), None, Status.NEWTON_FAILED,
                                f"inverted element at the starting state ({exc})", 0, np.inf)


#: a frictional step has no potential: backtracking on the residual norm, inverted elements halve the step;
#: below the stall level (1e-9, or the subproblem's round-off floor where larger: _FrictionSubproblem.stall_level)
#: a failed line search is round-off (the barrier anchor's stiff subproblems, eps_N 4.4e7 on
#: examples/finite_ironing_friction.toml, start at 2.6e-10 after a tangential update that no step lowers: every
#: load step cut back to the smallest increment before)
_FRICTION_SETTINGS = NewtonSettings(LineSearch(halvings=_MAX_HALVINGS, armijo=_ARMIJO, merit=False, residual_decrease=True,
                                      full_step=False), stall=1e-9, stall_on_failed_search=True)
#: the semi-smooth reference: the same, the stall test from the third iterate on
_FRICTION_SSN_SETTINGS = dataclasses.replace(_FRICTION_SETTINGS, stall_from=3)


class _FrictionSubproblem(NewtonSystem):
    """The frictional subproblem of :class:`FiniteFrictionContact` for :func:`~._newton.newton`.

    State: :class:`_Local`. Relative residual :math:`\\max|R|` over the running force unit
    (:meth:`~alcontact.contact.systems._full_space.FiniteContact.force_scale` with the contact tractions).
    A stall (or a failed line search) counts as converged below ``max(1e-9, floor)``, ``floor`` the
    round-off of the contact forces as in :class:`_Subproblem`: gaps and slips from absolute coordinates
    times the largest contact stiffness, the normal one :math:`\\partial t_N/\\partial g` or :math:`\\varepsilon_T`.
    """

    domain_errors = (InvertedElementError,)

    def __init__(self, dc, law, lamN, lamT):
        self.dc, self.law, self.lamN, self.lamT = dc, law, lamN, lamT
        self.w = dc.weights[dc.cand]
        self.scale = 0.0
        self.coord = float(np.max(np.abs(dc._current(dc.expand(dc.x0), dc.cand)), initial=1.0))
        self.floor = 0.0

    def stall_level(self, state, level):
        return max(level, self.floor)

    def evaluate(self, x):
        return self.dc.evaluate(self.law, self.lamN, self.lamT, x)

    def residual(self, state):
        return state.R

    def measure(self, state):
        tabs = np.hypot(state.tN, np.linalg.norm(state.tT, axis=1))
        self.scale = max(self.scale, self.dc.force_scale(state.r_body, self.w * tabs))
        return float(np.max(np.abs(state.R), initial=0.0)) / self.scale

    def step(self, x, state, history):
        dc = self.dc
        if dc.state_trace is not None:  # the OPEN / STICK / SLIP flags of every iterate (state reversals)
            dc.state_trace.append(contact_states(state))
        ta = time.perf_counter()
        stiff = np.maximum(np.abs(self.law.stiffness(state.g, self.lamN)), dc.coulomb.eps_t)
        self.floor = _contact_roundoff_floor(self.coord, self.w, stiff, self.scale)
        J = dc.friction_jacobian(self.law, self.lamN, self.lamT, state.u)
        tb = time.perf_counter()
        dc.assembly_seconds += tb - ta
        dx = dc.friction_solver.solve(J, -state.R)
        dc.solve_seconds += time.perf_counter() - tb
        dc.linear_solves += 1
        dc.newton_iterations += 1
        return dx
