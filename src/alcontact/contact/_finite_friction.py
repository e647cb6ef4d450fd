r"""Coulomb friction at finite deformation: Algorithms 6.2 and 6.4 in the current configuration.

Kinematics (current configuration, nodal collocation as in
:mod:`alcontact.contact._finite`). Contact point ``i`` has the current position
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
:mod:`alcontact.contact._friction_laws`; vectors in the ambient space, tangent to the
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
small-deformation solvers, :func:`alcontact.contact._friction._step_al`, on the step's
system :class:`_FiniteALCtx` (first-order updates :math:`\lambda_N \leftarrow t_N`,
:math:`\lambda_T \leftarrow t_T` ((6.2b), (6.2c)) until the penetration, complementarity,
multiplier change and the slip of the sticking points are below their tolerances; what
the finite system declares differently is listed there). A step starts from
:math:`\lambda_T = t_{T,n}` (transported into the current tangent plane).
The reference ``"ssn"`` (:func:`_step_ssn`) solves the Alart-Curnier equations of the same
time-discrete law exactly, in :math:`(u, \lambda_N, \lambda_T)`, by a semi-smooth Newton method.
Every accepted step is verified by :func:`~alcontact.contact._verify.check_state`
(penetration, complementarity, Coulomb bound and slip direction) before it is
reported converged.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass, field
from typing import Any, Callable, ClassVar, Sequence

import numpy as np
import scipy.sparse as sp

from .. import penalties as _pen
from .._options import is_real, show
from ..errors import InputError, InvertedElementError
from ..linalg import SequenceSolver
from ..status import Status
from ._algorithms import (FRICTION_DEFAULTS, _first_push, algorithm_names, find_algorithm, options_with,
                          register_family)
from ._finite import FiniteContact
from ._finite_iterative import finite_solver
from ._friction import FrictionOptions, _step_al, _StepOut, register_friction_kinematics
from ._friction_laws import OPEN, SLIP, STICK, return_mapping
from ._laws import make_law
from ._loading import LoadHistory
from ._newton import LineSearch, NewtonResult, NewtonSettings, NewtonSystem, inner_failure, newton
from ._solution import ContactStatus
from ._stiffness import penalty_stiffness
from ._stepping import Attempt, StepRecord, StepRecords, _StepData, _step_times, step_through
from ._verify import check_state, equilibrium_tolerance, reach, state_equilibrium, verified_status
from .obstacles import frame, surface_slip, transport_tangent

__all__ = ["FiniteFrictionContact", "FiniteFrictionStep", "FiniteFrictionSolution", "solve_finite_friction",
           "finite_friction_algorithms"]

logger = logging.getLogger(__name__)

_ARMIJO = 1e-4
_MAX_HALVINGS = 40


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

    @property
    def aux(self) -> tuple:
        """``(y, t, Dy, state)`` of the AL loop (:class:`_FiniteALCtx`): ``y = [g, slip]``,
        ``t = [t_N, t_T]`` (``(c, 1 + d)`` each), no tangent ``Dy`` (first-order updates only)."""
        return np.column_stack([self.g, self.slip]), np.column_stack([self.tN, self.tT]), None, self.state


class FiniteFrictionContact(FiniteContact):
    """:class:`~alcontact.contact._finite.FiniteContact` with Coulomb friction (module doc).

    The frictional history of a step is set by :meth:`set_history`: the surface coordinates
    of all contact points at the last converged step (:meth:`surface_points`), the obstacle
    translation of the current step, :math:`\\mu` and :math:`\\varepsilon_T`.
    """

    @property
    def friction_solver(self) -> SequenceSolver:
        """Solver of the non-symmetric Newton matrices of friction: the one of the symmetric systems
        (:attr:`solver`, the ``linear_solver`` option), analyses kept by pattern."""
        solver = getattr(self, "_friction_solver", None)
        if solver is None:
            solver = self._friction_solver = SequenceSolver(self.solver.backend, matrix_type="unsymmetric")
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
        self.mu = float(mu)
        self.eps_t = float(eps_t)
        self.coupled = radius == "traction"

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
        z = lamT - nl[:, None] * nu + self.eps_t * slip
        if not blocks:
            return z, slip, None, None
        H = self.obstacle.gap_hessian(xc)
        Hl = np.einsum("ijk,ik->ij", H, lamT)
        dz = nl[:, None, None] * H + nu[:, :, None] * Hl[:, None, :] + self.eps_t * dslip
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
        rho = self.mu * (tN if self.coupled else np.maximum(lamN, 0.0))
        tT, opened, stick, slipping, n, dproj = return_mapping(z, rho)
        state = np.where(opened, OPEN, np.where(stick, STICK, SLIP))
        if not blocks:
            return g, nu, tN, tT, slip, state, None
        dT = dproj @ dz
        if self.coupled:
            dT = dT - np.where(slipping[:, None, None], self.mu * kN[:, None, None] * n[:, :, None] * nu[:, None, :],
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

        Returns the :class:`~alcontact.contact._newton.NewtonResult`; its ``state`` is the
        :class:`_Local` state of the last iterate (``None`` when the start inverts an element).
        """
        log: list[float] = []
        self.residual_log.append(log)
        system = _FrictionSubproblem(self, law, lamN, lamT)
        try:
            return newton(system, x0, tol=tol, maxiter=maxiter, settings=_SETTINGS, log=log)
        except InvertedElementError as exc:
            return NewtonResult(np.array(x0, dtype=float), None, Status.NEWTON_FAILED,
                                f"inverted element at the starting state ({exc})", 0, np.inf)


#: a frictional step has no potential: backtracking on the residual norm, inverted elements halve the step
_SETTINGS = NewtonSettings(LineSearch(halvings=_MAX_HALVINGS, armijo=_ARMIJO, merit=False, residual_decrease=True,
                                      full_step=False), stall=1e-9)
#: the semi-smooth reference: the same, the stall test from the third iterate on
_SSN_SETTINGS = dataclasses.replace(_SETTINGS, stall_from=3)


class _FrictionSubproblem(NewtonSystem):
    """The frictional subproblem of :class:`FiniteFrictionContact` for :func:`~._newton.newton`.

    State: :class:`_Local`. Relative residual :math:`\\max|R|` over the running force unit
    (:meth:`~alcontact.contact._finite.FiniteContact.force_scale` with the contact tractions).
    """

    domain_errors = (InvertedElementError,)

    def __init__(self, dc, law, lamN, lamT):
        self.dc, self.law, self.lamN, self.lamT = dc, law, lamN, lamT
        self.w = dc.weights[dc.cand]
        self.scale = 0.0

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
        ta = time.perf_counter()
        J = dc.friction_jacobian(self.law, self.lamN, self.lamT, state.u)
        tb = time.perf_counter()
        dc.assembly_seconds += tb - ta
        dx = dc.friction_solver.solve(J, -state.R)
        dc.solve_seconds += time.perf_counter() - tb
        dc.linear_solves += 1
        dc.newton_iterations += 1
        return dx


# ---------------------------------------------------------------------------
# results
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class FiniteFrictionStep:
    """One accepted load step of :func:`solve_finite_friction`.

    Attributes
    ----------
    t : float
    status : ContactStatus
    newton_iterations, outer_iterations, cutbacks : int
    force : ndarray (d,)
        Resultant contact force on the body :math:`\\sum_i w_i (t_{N,i}\\nu_i - t_{T,i})`.
    normal_force : float
        :math:`\\sum_i w_i t_{N,i}`.
    tangential_force : ndarray (d,)
        Resultant friction force on the body :math:`-\\sum_i w_i t_{T,i}`.
    states : ndarray (m,) of int
        OPEN / STICK / SLIP (:mod:`alcontact.contact._friction_laws`) of every contact point.
    dissipation : float
        Frictional dissipation of the step :math:`\\sum_i w_i\\, t_{T,i}\\cdot\\Delta s_{T,i}` (>= 0).
    stored_energy : float
        :math:`\\Pi_{int}(u)` of the body at the end of the step.
    offset : ndarray (d,)
        Obstacle translation :math:`c(t)` (the translation part :math:`b` of the placement
        :math:`x = Qy + b` when ``obstacle_path`` returns a
        :class:`~alcontact.contact.obstacles.RigidMotion`).
    seconds : float
    message : str
    u : ndarray (ndofs,)
        Displacement at the end of the step.
    pressure, gap : ndarray (m,)
        Normal traction :math:`t_N` and gap (current configuration) of every contact point.
    traction_t : ndarray (m, d)
        Tangential traction (dissertation sign: along the slip; the force on the body is :math:`-w\\,t_T`).
    slip : ndarray (m, d)
        Slip increment :math:`\\Delta s_T` of the step (zero at open points).
    normals : ndarray (m, d)
        Obstacle normals at the projections of the contact points.
    linear_solves : int
        Newton systems solved in this step (failed tries included).
    requested : bool
        ``t`` is a requested step time; ``False`` for a sub-step a cut-back inserted.
    state_reversals : int or None
        Contact points whose OPEN / STICK / SLIP state went back to a state it had left, between
        the Newton iterates (start included) of the step's accepted solve: ``A -> B -> A``
        (:func:`state_reversals`); ``None`` where not tracked (only ``ssn`` tracks it).
    """

    t: float
    status: ContactStatus
    newton_iterations: int
    outer_iterations: int
    cutbacks: int
    force: np.ndarray
    normal_force: float
    tangential_force: np.ndarray
    states: np.ndarray
    dissipation: float
    stored_energy: float
    offset: np.ndarray
    seconds: float
    message: str
    u: np.ndarray | None = None
    pressure: np.ndarray | None = None
    gap: np.ndarray | None = None
    traction_t: np.ndarray | None = None
    slip: np.ndarray | None = None
    normals: np.ndarray | None = None
    linear_solves: int = 0
    requested: bool = True
    state_reversals: int | None = None

    @property
    def state(self) -> np.ndarray:
        """``states`` (the name of :class:`~alcontact.contact._stepping.Frame`)."""
        return self.states


@dataclass(frozen=True)
class FiniteFrictionSolution(StepRecords):
    """Outcome of :func:`solve_finite_friction`.

    Attributes
    ----------
    u : ndarray
        Displacement of the last accepted step.
    steps : tuple of FiniteFrictionStep
    status : ContactStatus
        ``CONVERGED`` when every step was reached and verified, else the status of the failed step.
    message : str
    pressure, gap : ndarray (m,)
        Normal tractions and gaps of all contact points at the last step.
    traction_t : ndarray (m, d)
        Tangential tractions (dissertation sign, tangent to the obstacle).
    normals : ndarray (m, d)
    extra : dict
        ``h``, ``weights`` (reference tributary weights of the contact points), ``points`` (their
        reference positions), ``eps_n``, ``eps_t``,
        ``mu``, ``algorithm``, ``penalty``, ``residual_log``.
    """

    u: np.ndarray
    steps: tuple[FiniteFrictionStep, ...]
    status: ContactStatus
    message: str
    pressure: np.ndarray
    gap: np.ndarray
    traction_t: np.ndarray
    normals: np.ndarray
    extra: dict = field(default_factory=dict)

    @property
    def dissipation(self) -> np.ndarray:
        """Cumulative frictional dissipation after each step."""
        return np.cumsum([s.dissipation for s in self.steps])


# ---------------------------------------------------------------------------
# one load step: Algorithms 6.2 / 6.4
# ---------------------------------------------------------------------------
@dataclass
class _FiniteALCtx:
    r"""The :class:`~alcontact.contact._friction._ALSystem` of a finite-deformation load step.

    The one AL loop :func:`~alcontact.contact._friction._step_al` (Algorithms 6.2 / 6.4)
    drives it; its unknowns are the free displacements ``x``, a subproblem is
    :meth:`FiniteFrictionContact.friction_subproblem` and its state the :class:`_Local` of the
    last iterate (``aux``: gaps and slips, tractions). The reference ``ssn``
    (:func:`_step_ssn`) takes the same system. What differs from the small-deformation
    paths, each by a declaration here:

    - the multipliers ``lamT`` are ambient vectors ``(c, d)`` tangent to the obstacle, the
      tractions ``t = [t_N, t_T]`` have ``d + 1`` columns (:attr:`d`);
    - the slip of the stopping test is the step's slip on the obstacle's surface
      (``aux[0][:, 1:]``, :func:`~alcontact.contact.obstacles.surface_slip`), measured
      from the previous surface point: the reference :attr:`uTn` is zero, and no tangent
      direction is held by a support (:attr:`tfree` is ``None``);
    - first-order multiplier updates only (:attr:`second_order` false: the second-order
      update needs the dense sensitivity of the condensed small-deformation subproblem),
      so the hybrid Coulomb radius of the first subproblem is not taken either; the radius
      is the one :meth:`FiniteFrictionContact.set_history` set from ``radius``;
    - the family-P predictor is a full Simo-Laursen outer iteration (:attr:`full_predictor`):
      both multipliers are taken from it and it is counted (its tangential traction, in the
      tangent planes of the predicted state, starts the family-P iterations);
    - the inside-domain move of a barrier-type penalty (:meth:`inside_domain`) is that of the
      frictionless finite solver (first-order scaling of the contact forces); before it the
      finite path had none and ``family-p`` with ``log-met1`` failed at its first load step.
    """

    fc: FiniteFrictionContact
    lamN: np.ndarray  # (c,)
    lamT: np.ndarray  # (c, d), tangent to the obstacle
    x0: np.ndarray  # free displacements the step starts from
    eps_n: float
    opts: Any

    label: ClassVar[str] = "finite friction AL"
    second_order: ClassVar[bool] = False
    full_predictor: ClassVar[bool] = True
    tfree: ClassVar[None] = None

    @property
    def c(self) -> int:
        return int(self.fc.cand.size)

    @property
    def d(self) -> int:
        """Columns of the tractions ``[t_N, t_T]`` (``t_T`` ambient, ``dim`` components)."""
        return self.fc.dim + 1

    @property
    def mu(self) -> float:
        return self.fc.mu

    @property
    def uTn(self) -> np.ndarray:
        """Zero: the slip ``aux[0][:, 1:]`` is already measured from the previous surface point."""
        return np.zeros((self.c, self.fc.dim))

    @property
    def start(self) -> np.ndarray:
        return self.x0.copy()

    def subproblem(self, law, lamN, lamT, x, coupled: bool = False) -> NewtonResult:
        """:meth:`FiniteFrictionContact.friction_subproblem` (``coupled`` is never asked: first-order updates)."""
        return self.fc.friction_subproblem(law, lamN, lamT, x, tol=self.opts.newton_tol,
                                           maxiter=self.opts.maxiter_newton)

    def iterate(self, out: NewtonResult) -> np.ndarray:
        return out.x

    def inside_domain(self, law, lamN, x) -> np.ndarray:
        """Start for barrier-type penalties: contact forces scaled up until every gap is inside ``g < eta b``.

        The barrier start of the frictionless finite-deformation solver
        (:func:`~alcontact.contact._algorithms.run_al`): the forces are scaled to first order
        (:meth:`~alcontact.contact._finite.FiniteContact.scale_forces`), first by the scale that
        just closes the penetrations (:func:`~alcontact.contact._algorithms._first_push`), doubled
        while the start is still outside; ``x`` unchanged when it is inside or no force can be scaled.
        """
        dc = self.fc
        bound = law.gap_bound(lamN)
        g = dc.gaps(x)
        if not np.any(g >= 0.99 * bound):
            return x
        doubled = dc.scale_forces(x, 2.0)
        if np.array_equal(doubled, x):  # no contact force to scale up
            return x
        scale = _first_push(g, dc.gaps(doubled), bound)
        while scale < 1e6:
            trial = dc.scale_forces(x, 1.0 + scale)
            if not np.any(dc.gaps(trial) >= 0.99 * bound):
                return trial
            scale *= 2
        return x

    def forces(self, x, t) -> np.ndarray:
        r"""Force of the obstacle on the body at each candidate, :math:`w_i (t_{N,i}\nu_i - t_{T,i})` ``(c, d)``."""
        dc = self.fc
        nu = dc.obstacle.normal(dc._current(dc.expand(x), dc.cand))
        with np.errstate(invalid="ignore", over="ignore"):  # the non-finite tractions of a failed step as they are
            return dc.weights[dc.cand][:, None] * (t[:, :1] * nu - t[:, 1:])


def state_reversals(history: Sequence[np.ndarray]) -> int:
    """Points whose state returned to one it had left along ``history`` (a state per iterate).

    Consecutive repeats count once: a point with states ``STICK, SLIP, SLIP, STICK`` has one
    reversal, ``STICK, SLIP, OPEN`` none.
    """
    if len(history) < 3:
        return 0
    H = np.asarray(history)  # (iterates, points)
    count = 0
    for col in H.T:
        seq = col[np.concatenate([[True], col[1:] != col[:-1]])]
        if seq.size >= 3 and np.any(seq[2:] == seq[:-2]):
            count += 1
    return count


def _ssn_parameter(dc) -> float:
    r"""The Alart-Curnier parameter :math:`c` of :func:`_step_ssn`: :math:`E'/h`, the stiffness of the
    first element row under the contact surface (:func:`~._solve.penalty_stiffness` with scale 1).

    The solution does not depend on :math:`c` (the complementarity functions vanish at the same
    points for every :math:`c > 0`), its Newton path does. With the AL penalty
    :math:`\varepsilon_N` (``penalty_scale`` = 100 times :math:`E'/h`) a sliding step at the
    stick-to-slip transition of the 2D ironing problem (h = 0.1, :math:`\mu` = 0.3) took 41-65
    Newton iterations and a cut-back: the first full Newton step opened every contact point
    (:math:`\lambda_N + c\,g < 0` for a small penetration error times a large :math:`c`) and the
    backtracking on the residual norm rebuilt the contact zone point by point. With
    :math:`c = E'/h` the same steps take 4-5 (issue 18; ``docs/benchmarks/ironing.md``).
    """
    return penalty_stiffness(dc.problem.model, dc.h, 1.0)


def _step_ssn(ctx: _FiniteALCtx, penalty_name: str = "none") -> _StepOut:
    r"""Alart-Curnier semi-smooth Newton reference for one load step (no penalty, exact).

    Unknowns :math:`(x, \lambda_N, \lambda_T)`, equations (with :math:`c = E'/h`, :func:`_ssn_parameter`,
    :math:`\hat t_N = \langle\lambda_N + c g\rangle`,
    :math:`\hat t_T = \operatorname{proj}_{|t| \le \mu\hat t_N} (P\lambda_T + c\,\Delta s_T)`)

    .. math::

        f_{int} - f_{ext} - \sum_i w_i(\lambda_{N,i}\nu_i - \lambda_{T,i}) = 0, \qquad
        w_i(\lambda_{N,i} - \hat t_{N,i}) = 0, \qquad w_i(\lambda_{T,i} - \hat t_{T,i}) = 0,

    solved by Newton's method with the generalized Jacobian (the return-mapping
    derivatives of the module doc with the coupled radius) and backtracking on the residual norm.
    ``ctx`` is the step's system of the AL algorithms (:class:`_FiniteALCtx`: candidates,
    starting multipliers and displacements); one outer iteration.
    """
    dc, lamN, lamT, x, opts = ctx.fc, ctx.lamN, ctx.lamT, ctx.start, ctx.opts
    cand = dc.cand
    k, d = cand.size, dc.dim
    w = dc.weights[cand]
    c = _ssn_parameter(dc)
    mu = dc.mu
    nf = dc.free.size
    macaulay = make_law(_pen.make("rockafellar"), np.full(k, 1.0 / c))
    saved = dc.eps_t, dc.coupled
    dc.eps_t, dc.coupled = c, True
    L = np.concatenate([np.maximum(lamN, 0.0)[:, None], lamT], axis=1)
    log: list[float] = []
    dc.residual_log.append(log)
    states: list[np.ndarray] = []  # the OPEN / STICK / SLIP flags of every iterate

    def evaluate(x_, L_):
        u_ = dc.expand(x_)
        rb, _ = dc._body_state(u_, False)
        g, nu, tN, tT, slip, state, _ = dc._local(macaulay, L_[:, 0], L_[:, 1:], u_, cand, blocks=False)
        Rx = rb[dc.free] + dc._assemble_points(cand, w[:, None] * (L_[:, 1:] - L_[:, :1] * nu))
        RL = w[:, None] * (L_ - np.concatenate([tN[:, None], tT], axis=1))
        return u_, g, nu, tN, tT, slip, state, rb, Rx, RL, L_

    def jacobian(u_, L_, nu):
        lN, lT = L_[:, 0], L_[:, 1:]
        xc = dc._current(u_, cand)
        g = dc.obstacle.gap(xc)
        P = np.eye(d)[None] - nu[:, :, None] * nu[:, None, :]
        z, _, dz_dx, H = dc._trial(lT, xc, nu, cand, blocks=True)
        act = (lN + c * g) > 0
        tN = np.where(act, lN + c * g, 0.0)
        rho = mu * tN
        _, _, _, slipping, n, M = return_mapping(z, rho)
        dtN_dx = -np.where(act, c, 0.0)[:, None] * nu  # (k, d)
        dtN_dl = act.astype(float)
        dtT_dx = M @ dz_dx + np.where(slipping[:, None, None], mu * n[:, :, None] * dtN_dx[:, None, :], 0.0)
        dtT_dlT = M @ P
        dtT_dlN = np.where(slipping[:, None], mu * dtN_dl[:, None] * n, 0.0)
        # x-x block, x-L block, L-x block, L-L block
        Kxx = dc._tangent_free(u_) + dc._point_blocks(cand, (w * lN)[:, None, None] * H)
        nl = d + 1
        pos = dc.pos[cand]  # (k, d)
        rows, cols, vals = [], [], []
        lrow = nf + np.arange(k)[:, None] * nl  # first L index of each point
        for j in range(d):  # dRx/dL: -w nu (lambda_N), +w I (lambda_T)
            keep = pos[:, j] >= 0
            rows += [pos[keep, j], pos[keep, j]]
            cols += [lrow[keep, 0], lrow[keep, 0] + 1 + j]
            vals += [-w[keep] * nu[keep, j], w[keep]]
        Dx = np.concatenate([dtN_dx[:, None, :], dtT_dx], axis=1)  # (k, nl, d)
        for r in range(nl):  # dRL/dx = -w dt/dx
            for j in range(d):
                keep = pos[:, j] >= 0
                rows.append(lrow[keep, 0] + r)
                cols.append(pos[keep, j])
                vals.append(-w[keep] * Dx[keep, r, j])
        DL = np.zeros((k, nl, nl))
        DL[:, 0, 0] = dtN_dl
        DL[:, 1:, 0] = dtT_dlN
        DL[:, 1:, 1:] = dtT_dlT
        DL = w[:, None, None] * (np.eye(nl)[None] - DL)
        for r in range(nl):
            for q in range(nl):
                rows.append(lrow[:, 0] + r)
                cols.append(lrow[:, 0] + q)
                vals.append(DL[:, r, q])
        ntot = nf + k * nl
        rest = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(ntot, ntot))
        return (sp.block_diag([Kxx, sp.csr_matrix((k * nl, k * nl))]) + rest).tocsc()

    class AlartCurnier(NewtonSystem):
        """Unknowns ``z = (x, L)``; relative residual: the larger of the force and multiplier parts."""

        domain_errors = (InvertedElementError,)

        def evaluate(self, z):
            return evaluate(z[:nf], z[nf:].reshape(k, d + 1))

        def residual(self, ev):
            return np.concatenate([ev[8], ev[9].ravel()])

        def measure(self, ev):
            L_ = ev[10]
            pref = max(float(np.max(L_[:, 0], initial=0.0)), 1e-300)
            scale = dc.force_scale(ev[7], w * L_[:, 0])
            return max(float(np.max(np.abs(ev[8]), initial=0.0)) / scale,
                       float(np.max(np.abs(ev[9]) / w[:, None], initial=0.0)) / pref)

        def step(self, z, ev, history):
            states.append(np.where(ev[10][:, 0] > 0, ev[6], OPEN))
            J = jacobian(ev[0], ev[10], ev[2])
            step = dc.friction_solver.solve(J, -self.residual(ev))
            dc.linear_solves += 1
            dc.newton_iterations += 1
            return step

    try:
        try:
            out = newton(AlartCurnier(), np.concatenate([x, L.ravel()]), tol=opts.newton_tol,
                         maxiter=max(opts.maxiter_newton, 100), settings=_SSN_SETTINGS, log=log)
        except InvertedElementError as exc:
            return _StepOut(False, f"inverted element at the start ({exc})", ctx.forces(x, L), L, 1, 0,
                            ContactStatus.NEWTON_FAILED, z=x)
        x, L = out.x[:nf], out.x[nf:].reshape(k, d + 1)
        if not out.converged:
            return _StepOut(False, f"semi-smooth Newton: {out.message}", ctx.forces(x, L), L, 1, out.iterations,
                            inner_failure(out), z=x)
        u, g, nu, tN, tT, slip, state, rb, Rx, RL, _ = out.state
        final = np.where(L[:, 0] > 0, state, OPEN)
        loc = _Local(u, g, nu, L[:, 0].copy(), L[:, 1:].copy(), slip, final, Rx, rb,
                     reversals=state_reversals(states + [final]))
        return _StepOut(True, "converged", ctx.forces(x, L), L.copy(), 1, out.iterations, z=x, last_state=loc)
    finally:
        dc.eps_t, dc.coupled = saved


register_family((
    ("simo-laursen", _step_al, "rockafellar", "Algorithm 6.2 at finite deformation: AL, Macaulay normal law (6.52), "
                                              "return mapping onto the Coulomb cone in the current configuration"),
    ("family-p", _step_al, None, "Algorithm 6.4 at finite deformation: Algorithm 6.2 with a family-P normal penalty"),
    ("ssn", _step_ssn, "none",
     "reference: Alart-Curnier semi-smooth Newton on (u, lambda_N, lambda_T), exact (no penalty)"),
), friction=True, kinematics="finite", linear_solvers=("direct",), defaults=FRICTION_DEFAULTS)


def finite_friction_algorithms() -> list[str]:
    """Names of the finite-deformation frictional algorithms."""
    return algorithm_names(friction=True, kinematics="finite")


# ---------------------------------------------------------------------------
# load stepping
# ---------------------------------------------------------------------------
def solve_finite_friction(problem, mu: float, algorithm: str = "simo-laursen", penalty: str | None = None,
                          options: FrictionOptions | dict | None = None, *, steps: int | Sequence[float] = 10,
                          history: LoadHistory | None = None,
                          obstacle_path: Callable[[float], Any] | None = None,
                          on_step: Callable[[FiniteFrictionStep], None] | None = None,
                          progress: Callable[[int, float, int], None] | None = None,
                          **option_overrides) -> FiniteFrictionSolution:
    """Coulomb friction at finite deformation, in load steps (module doc).

    Parameters
    ----------
    problem : ContactProblem
        Body (e.g. :class:`~alcontact.fem.hyperelastic.Hyperelastic`), supports, loads,
        obstacle and contact boundary.
    mu : float
        Coulomb coefficient (>= 0).
    algorithm : {"simo-laursen", "family-p"}
        Algorithm 6.2 (Macaulay normal law) or 6.4 (family-P normal law ``penalty``).
    penalty : str, optional
        Family-P penalty of Algorithm 6.4 (default ``exp-met1``).
    options : FrictionOptions or dict, optional
        Tolerances and penalties (``eps_n``, ``eps_t``, ``penalty_scale``, ``tangential_scale``,
        ``tol_*``, ``maxiter``, ``newton_tol``, ``max_cutbacks``, ``cutback_factor``, ``radius``).
    steps : int or sequence of float
        Number of uniform load steps or the increasing step times in (0, 1].
    history : LoadHistory, optional
        Amplitudes of the load cases (as :func:`~alcontact.contact.solve_finite`); without it
        every support value and load is scaled by the pseudo-time.
    obstacle_path : callable ``t -> (d,)`` or ``t -> RigidMotion``, optional
        Translation of the obstacle at pseudo-time ``t`` (default none), or its rigid
        placement (rotation and translation, :class:`~alcontact.contact.obstacles.RigidMotion`);
        the slip is measured on the moving obstacle's surface in its own frame.
    on_step : callable ``step -> None``, optional
        Called with every accepted :class:`FiniteFrictionStep` (it carries the step's
        displacement, pressures, gaps, tangential tractions, slip and stick/slip states).
    progress : callable ``(k, t, n) -> None``, optional
        Called before requested step ``k`` (0-based) of ``n`` at pseudo-time ``t``
        (the ``on_step`` of :func:`~alcontact.contact.solve_friction`).

    Returns
    -------
    FiniteFrictionSolution
        A negative status (with a logged warning) when a step fails at the smallest increment
        (``max_cutbacks`` reductions by ``cutback_factor``, :func:`~alcontact.contact._stepping.step_through`)
        or its state fails the verification.
    """
    t_start = time.perf_counter()
    if not (is_real(mu) and 0 <= mu <= 1e100):  # comparisons, not isfinite: a huge int is no float
        raise InputError(f"mu = {show(mu)}: the Coulomb coefficient must be a finite number >= 0 (at most 1e100).")
    entry = find_algorithm(algorithm, friction=True, kinematics="finite")
    pen_name = entry.penalty_for(penalty)
    opts = options_with(options, FrictionOptions, option_overrides, "friction options", entry)
    times = _step_times(steps)
    step_fn = entry.run
    data = _StepData(problem, history, obstacle_path)
    dc = FiniteFrictionContact(problem, fixed=data.fixed, predictor=opts.predictor,
                               slide_start_reach=opts.slide_start_reach,
                               solver=finite_solver(opts.linear_solver, entry, problem.model))
    d = dc.dim
    m = dc.points.shape[0]
    eps_n = opts.eps_n if opts.eps_n is not None else penalty_stiffness(problem.model, dc.h, opts.penalty_scale)
    eps_t = opts.eps_t if opts.eps_t is not None else opts.tangential_scale * eps_n

    x0 = np.zeros(dc.free.size)
    dc.configure(*data(0.0), x0)
    dc.accept(np.zeros(m))
    dc.place()
    # the committed state every try starts from
    u0 = dc.expand(x0)
    state = {"x": x0, "y_prev": dc.surface_points(u0), "nu_prev": dc.obstacle.normal(dc.points + u0[dc.dofs]),
             "lamN": np.zeros(m), "lamT": np.zeros((m, d)), "last": None}
    records: list[FiniteFrictionStep] = []

    def attempt(t: float) -> Attempt:
        newton0, solves0 = dc.newton_iterations, dc.linear_solves
        res, exc = _attempt(dc, data, step_fn, state["x"], t, state["y_prev"], state["nu_prev"],
                            state["lamN"], state["lamT"], mu, eps_n, eps_t, pen_name, opts)
        counts = dict(newton=dc.newton_iterations - newton0, linear_solves=dc.linear_solves - solves0)
        if exc is not None:
            return Attempt(False, ContactStatus.NEWTON_FAILED, str(exc), **counts)
        return Attempt(bool(res.ok), res.status, res.message, outer=int(res.outer), value=res, **counts)

    def commit(t: float, att: Attempt, rec: StepRecord) -> FiniteFrictionStep:
        res = att.value
        step, full = _record(dc, res, t, mu, opts, rec.cutbacks, rec.newton_iterations, rec.seconds,
                             rec.linear_solves, fixed=data.fixed, load=data(t)[1])
        step = dataclasses.replace(step, requested=rec.requested)  # False: a sub-step of a cut-back
        records.append(step)
        state["last"] = full
        if step.status > 0:
            state["x"] = res.z
            state["y_prev"] = dc.surface_points(dc.expand(res.z))
            state["nu_prev"] = full["normals"].copy()
            state["lamN"], state["lamT"] = full["pressure"].copy(), full["traction_t"].copy()
            dc.accept(state["lamN"])
        return step

    run = step_through(times, attempt, commit, max_cutbacks=opts.max_cutbacks, factor=opts.cutback_factor,
                       on_step=on_step, before_step=progress, what="finite-deformation friction",
                       advice="use more load steps, a smaller penalty_scale or a smaller tangential_scale",
                       done_message="all load steps converged and verified")
    status, message, last, x = run.status, run.message, state["last"], state["x"]
    if last is None:
        u = dc.expand(x)
        g_all = dc.all_gaps(u)
        last = {"u": u, "pressure": np.zeros(m), "gap": g_all, "traction_t": np.zeros((m, d)),
                "normals": dc.normals.copy()}
    return FiniteFrictionSolution(
        u=last["u"], steps=tuple(records), status=status, message=message, pressure=last["pressure"],
        gap=last["gap"], traction_t=last["traction_t"], normals=last["normals"],
        extra={"h": dc.h, "weights": dc.weights.copy(), "points": dc.points.copy(), "eps_n": float(eps_n),
               "eps_t": float(eps_t), "mu": float(mu), "algorithm": algorithm, "penalty": pen_name,
               "dofs": int(problem.model.ndofs), "residual_log": dc.residual_log,
               "newton_total": int(dc.newton_iterations), "linear_solves": int(dc.linear_solves),
               "cutbacks": int(run.cutbacks), "total_s": time.perf_counter() - t_start,
               "linear_solver": "direct" if dc.friction_solver.exact else "amg",
               "direct_solver": dc.friction_solver.backend,
               "fallback_solves": int(dc.friction_solver.fallback_solves + dc.solver.fallback_solves),
               "krylov_iterations": int(dc.friction_solver.krylov_iterations + dc.solver.krylov_iterations),
               "linear_solve_s": float(dc.solve_seconds)})  # all Newton linear solves together


def _attempt(dc, data, step_fn, x, t, y_prev, nu_prev, lamN_all, lamT_all, mu, eps_n, eps_t, pen_name,
             opts):
    """One try of the step to ``t`` from ``x``: ``(step result, exception or None)``.

    The last tangential tractions (tangent to the obstacle at the normals ``nu_prev``) are
    transported into the tangent planes at the step's predictor
    (:func:`~alcontact.contact.obstacles.transport_tangent`) and start the step's multipliers.
    """
    try:
        fv, load, ob = data(t)
        dc.configure(fv, load, ob, x, predictor_stiffness=eps_n)
        dc.set_history(y_prev, mu, eps_t, opts.radius)
        nu_start = dc.obstacle.normal(dc.points + dc.expand(dc.x0)[dc.dofs])
        lamT_all = transport_tangent(lamT_all, nu_prev, nu_start)
        res = None
        for _ in range(8):
            cand = dc.cand
            res = step_fn(_FiniteALCtx(dc, lamN_all[cand].copy(), lamT_all[cand].copy(), dc.x0, eps_n, opts),
                          pen_name)
            if not res.ok:
                break
            added = dc.extend(dc.all_gaps(dc.expand(res.z)), opts.tol_penetration * dc.h)
            if added.size == 0:
                break
            dc.x0 = res.z
        return res, None
    except InvertedElementError as exc:
        return None, exc


def _record(dc, res, t, mu, opts, cut, newton, seconds, solves=0, *, fixed, load):
    """Verified step record and the full-size fields of an accepted step."""
    m, d = dc.points.shape
    cand = dc.cand
    loc = res.last_state
    u = dc.expand(res.z)
    g_all = dc.all_gaps(u)
    pressure = np.zeros(m)
    traction_t = np.zeros((m, d))
    slip = np.zeros((m, d))
    states = np.full(m, OPEN)
    pressure[cand] = loc.tN
    traction_t[cand] = loc.tT
    slip[cand] = loc.slip
    states[cand] = loc.state
    w = dc.weights
    closed = pressure > 0
    # equilibrium of the step's displacement with the forces it reports (normal and tangential)
    problem = dc.problem
    forces = (w * pressure)[:, None] * dc.normals - w[:, None] * traction_t
    eq = state_equilibrium(problem.model, u, fixed, load, problem.model.node_dofs(problem.contact_boundary)[1],
                           forces, dc.h, pressure=pressure, weights=w)
    check = check_state(g_all, pressure, dc.h, tol_penetration=opts.tol_penetration,
                        tol_complementarity=opts.tol_complementarity, traction_t=traction_t,
                        slip=np.where(closed[:, None], slip, 0.0), mu=mu,
                        tol_friction=max(opts.tol_multiplier, opts.tol_slip), equilibrium=eq.largest,
                        tol_equilibrium=equilibrium_tolerance(opts, multipliers=True), reach=reach(dc.points, u))
    status, message = verified_status(res.status, res.message, check,
                                      what=f"finite-deformation friction step to t={t:.6g}")
    tang = -np.sum(w[:, None] * traction_t, axis=0)
    force = np.sum((w * pressure)[:, None] * dc.normals, axis=0) + tang
    dissipation = float(np.sum(w * np.einsum("ij,ij->i", traction_t, slip)))
    rec = FiniteFrictionStep(
        t=float(t), status=status, newton_iterations=int(newton), outer_iterations=int(res.outer), cutbacks=cut,
        force=force, normal_force=float(np.sum(w * pressure)), tangential_force=tang, states=states,
        dissipation=dissipation, stored_energy=float(dc.body.energy(u)), offset=dc.offset.copy(), seconds=seconds,
        message=message, u=u, pressure=pressure, gap=g_all, traction_t=traction_t,
        slip=np.where(closed[:, None], slip, 0.0), normals=dc.normals.copy(), linear_solves=int(solves),
        state_reversals=loc.reversals)
    full = {"u": u, "pressure": pressure, "gap": g_all, "traction_t": traction_t, "normals": dc.normals.copy()}
    return rec, full


register_friction_kinematics("finite", solve_finite_friction)
