"""Records of stepped solves: one state per accepted load step.

:class:`StepRecords` is the shape shared by every stepped solution; :class:`FiniteStep` /
:class:`FiniteSolution` (frictionless, finite deformation), :class:`FrictionStep` /
:class:`FrictionSolution` (Coulomb, small deformation) and :class:`FiniteFrictionStep` /
:class:`FiniteFrictionSolution` (Coulomb, finite deformation) are its three kinds;
:class:`Frame` / :func:`frame_of` give one step the fields of a
:class:`~alcontact.contact.ContactFrame`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import ConvergenceError
from ..laws._coulomb import OPEN, SLIP, STICK
from ._solution import ContactSolution, ContactStatus


@dataclass(frozen=True)
class FiniteStep:
    """One accepted load step.

    Attributes
    ----------
    t : float
        Pseudo-time of the step.
    status : ContactStatus
    newton_iterations : int
        Newton iterations of this step (all subproblems and active-set steps, the
        failed attempts of cut-backs included).
    outer_iterations : int
        Outer (multiplier / active-set) iterations of the accepted attempt.
    linear_solves : int
        Newton systems solved in this step.
    force : ndarray (d,)
        Resultant contact force on the body :math:`\\sum_i w_i t_{N,i}\\,\\nu_i`.
    cutbacks : int
        Halvings of the increment needed before this step was accepted.
    seconds : float
        Wall time of the step (failed attempts included).
    message : str
    u : ndarray (ndofs,)
        Displacement at the end of the step.
    pressure, gap : ndarray (m,)
        Contact pressure and gap (current configuration) of every contact-boundary point.
    normal_force : float
        :math:`\\sum_i w_i t_{N,i}`.
    requested : bool
        ``t`` is a requested step time; ``False`` for a sub-step a cut-back inserted
        (the increment halved after a failed try).
    normals : ndarray (m, d) or None
        Master normals at the contact points at the end of the step, kept where the master
        deforms (two-body pairs); ``None`` against a rigid master (its normals follow from its
        placement at ``t``).
    """

    t: float
    status: ContactStatus
    newton_iterations: int
    outer_iterations: int
    linear_solves: int
    force: np.ndarray
    cutbacks: int
    seconds: float
    message: str
    u: np.ndarray | None = None
    pressure: np.ndarray | None = None
    gap: np.ndarray | None = None
    normal_force: float = float("nan")
    requested: bool = True
    normals: np.ndarray | None = None


@dataclass(frozen=True)
class Frame:
    r"""State of one accepted load step, the same shape for every stepped solve.

    Attributes
    ----------
    t : float
        Pseudo-time.
    u : ndarray (ndofs,)
        Displacement.
    pressure, gap : ndarray (m,)
        Normal traction :math:`t_N \ge 0` and gap (:math:`g \le 0`: no penetration) of every
        contact-boundary point.
    force : ndarray (d,)
        Resultant contact force on the body (normal and tangential parts).
    normal_force : float
        :math:`\sum_i w_i t_{N,i}`.
    tangential_force : ndarray (d,)
        Resultant friction force on the body (zeros without friction).
    newton_iterations, outer_iterations, cutbacks : int
        Counters of the step as its solver records them.
    seconds : float
        Wall time of the step (NaN where the solver does not time steps).
    slip : ndarray (m, d) or None
        Slip increment of the step (frictional solves).
    state : ndarray of int (m,) or None
        ``OPEN`` / ``STICK`` / ``SLIP`` (frictional solves, :mod:`alcontact.contact.laws._coulomb`).
    """

    t: float
    u: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    force: np.ndarray
    normal_force: float
    tangential_force: np.ndarray
    newton_iterations: int
    outer_iterations: int
    cutbacks: int
    seconds: float
    slip: np.ndarray | None = None
    state: np.ndarray | None = None


def frame_of(step) -> Frame:
    """The :class:`Frame` of a step record (:class:`FiniteStep`, ``FrictionStep``, ``FiniteFrictionStep``)."""
    force = np.asarray(step.force, dtype=float)
    tang = getattr(step, "tangential_force", None)
    return Frame(t=float(step.t), u=step.u, pressure=step.pressure, gap=step.gap, force=force,
                 normal_force=float(step.normal_force),
                 tangential_force=np.zeros_like(force) if tang is None else np.asarray(tang, dtype=float),
                 newton_iterations=int(step.newton_iterations), outer_iterations=int(step.outer_iterations),
                 cutbacks=int(step.cutbacks), seconds=float(getattr(step, "seconds", float("nan"))),
                 slip=getattr(step, "slip", None), state=getattr(step, "state", None))


class StepRecords:
    """Views on the per-step records ``steps`` and ``status`` of a load-stepped solution.

    Shared by :class:`FiniteSolution`, ``FiniteFrictionSolution`` and ``FrictionSolution``:
    every step record has ``t``, ``u``, ``pressure``, ``gap``, ``force``, ``normal_force``
    and the counters, so :attr:`frames` gives one :class:`Frame` per accepted step.
    """

    @property
    def success(self) -> bool:
        return self.status > 0

    def raise_for_status(self) -> None:
        """Raise :class:`~alcontact.errors.ConvergenceError` unless every step converged."""
        if not self.success:
            raise ConvergenceError(f"load-stepped contact solve failed ({self.status.label}): {self.message}")

    @property
    def times(self) -> np.ndarray:
        """Pseudo-time of every accepted step, in order: the requested step times *and* the sub-steps
        that cut-backs inserted (a failed step's increment halved, ``max_cutbacks`` times at most).

        :attr:`requested` marks which is which; :attr:`requested_times` keeps the requested ones.
        """
        return np.array([s.t for s in self.steps])

    @property
    def requested(self) -> np.ndarray:
        """Per accepted step: ``True`` at a requested step time, ``False`` at a cut-back sub-step."""
        return np.array([bool(getattr(s, "requested", True)) for s in self.steps], dtype=bool)

    @property
    def requested_times(self) -> np.ndarray:
        """The requested step times that were reached (:attr:`times` without the cut-back sub-steps)."""
        return self.times[self.requested] if self.steps else np.array([])

    @property
    def forces(self) -> np.ndarray:
        """Resultant contact force on the body per step, shape ``(steps, d)``."""
        return np.array([s.force for s in self.steps])

    @property
    def normal_forces(self) -> np.ndarray:
        """:math:`\\sum_i w_i t_{N,i}` per step."""
        return np.array([s.normal_force for s in self.steps])

    @property
    def tangential_forces(self) -> np.ndarray:
        """``(steps, d)`` resultants of the friction forces on the body (zeros without friction)."""
        out = [getattr(s, "tangential_force", None) for s in self.steps]
        out = [np.zeros_like(np.asarray(s.force, dtype=float)) if f is None else f for s, f in zip(self.steps, out)]
        return np.array(out, dtype=float).reshape(len(self.steps), -1)

    @property
    def step_newton_iterations(self) -> list[int]:
        """Newton iterations of every accepted step."""
        return [int(s.newton_iterations) for s in self.steps]

    @property
    def frames(self) -> tuple[Frame, ...]:
        """One :class:`Frame` per accepted step."""
        return tuple(frame_of(s) for s in self.steps)


@dataclass(frozen=True)
class FiniteSolution(StepRecords):
    """Outcome of a load-stepped finite-deformation contact solve.

    Attributes
    ----------
    solution : ContactSolution
        State of the last accepted step (displacement, pressures, gaps at the
        current configuration, normals at the current projections).
    steps : tuple of FiniteStep
    status : ContactStatus
        ``CONVERGED`` when every step was reached, else the status of the failed step.
    message : str
    extra : dict
        ``h``, ``dofs`` and ``residual_log`` (relative residuals of every Newton solve,
        :attr:`FiniteContact.residual_log <alcontact.contact.systems._full_space.FiniteContact>`).
    """

    solution: ContactSolution
    steps: tuple[FiniteStep, ...]
    status: ContactStatus
    message: str
    extra: dict = field(default_factory=dict)

    @property
    def u(self) -> np.ndarray:
        return self.solution.u

    def raise_for_status(self) -> None:
        self.solution.result.raise_for_status()


@dataclass(frozen=True)
class FrictionStep:
    """Converged state at the end of one load step (arrays over the ``m`` contact-boundary points).

    Attributes
    ----------
    t : float
        Pseudo-time.
    requested : bool
        False for an intermediate step inserted by a cut-back.
    u : ndarray (ndofs,)
        Displacement.
    pressure : ndarray (m,)
        Normal traction :math:`t_N \\ge 0`.
    traction_t : ndarray (m, d-1)
        Tangential traction :math:`t_T` in the tangent bases, dissertation sign
        (the force on the body is :math:`-w\\,T t_T`).
    shear : ndarray (m, d)
        Tangential traction on the body, global components (:math:`-T t_T`).
    slip : ndarray (m, d)
        Slip increment of the step :math:`T(u_{T,n+1} - u_{T,n})` at closed points (0 when open).
    slip_total : ndarray (m, d)
        Slip accumulated over the steps so far.
    gap : ndarray (m,)
        Linearized gap (6.15).
    state : ndarray of int (m,)
        ``OPEN`` (0), ``STICK`` (1), ``SLIP`` (2).
    normal_force : float
        :math:`\\sum_i w_i t_{N,i}`.
    tangential_force : ndarray (d,)
        Resultant of the tangential tractions on the body.
    contact_force : ndarray (d,)
        Resultant of all contact tractions on the body.
    outer_iterations, newton_iterations, cutbacks : int
        Counters of this step (``cutbacks``: failed attempts before it converged).
    penetration : float
        Max gap over ``h``.
    coulomb : float
        Max violation :math:`(|t_T| - \\mu t_N)^+` over the largest pressure.
    seconds : float
        Wall time of the tries since the last accepted step (failed ones included).
    linear_solves : int
        Linear solves of the tries since the last accepted step (failed ones included).
    two_body : dict
        Between two bodies (a mortar pair): ``slave_contact_force`` and ``master_contact_force`` (the
        resultants of the normal and tangential contact forces on each side), ``contact_force_balance``
        :math:`|F_s + F_m| / |F_s|` and ``contact_force_points`` (``(dofs, forces)`` of every node the
        contact forces act on); empty against a rigid master.
    """

    t: float
    requested: bool
    u: np.ndarray
    pressure: np.ndarray
    traction_t: np.ndarray
    shear: np.ndarray
    slip: np.ndarray
    slip_total: np.ndarray
    gap: np.ndarray
    state: np.ndarray
    normal_force: float
    tangential_force: np.ndarray
    contact_force: np.ndarray
    outer_iterations: int
    newton_iterations: int
    cutbacks: int
    penetration: float
    coulomb: float
    seconds: float = float("nan")
    linear_solves: int = 0
    two_body: dict = field(default_factory=dict)

    @property
    def force(self) -> np.ndarray:
        """``contact_force`` (the name of :class:`~alcontact.contact.solution._records.Frame`)."""
        return self.contact_force

    @property
    def n_stick(self) -> int:
        return int(np.sum(self.state == STICK))

    @property
    def n_slip(self) -> int:
        return int(np.sum(self.state == SLIP))

    @property
    def n_open(self) -> int:
        return int(np.sum(self.state == OPEN))


@dataclass(frozen=True)
class FrictionSolution(StepRecords):
    """Outcome of :func:`alcontact.contact.solve_friction`.

    ``steps`` holds every converged step (requested ones and those inserted by
    cut-backs); after a failure it holds the steps converged before it and
    ``status`` is negative. ``final`` is the last converged step. The per-step views
    (``times``, ``forces``, ``normal_forces``, ``tangential_forces``, ``frames``) are
    those of every stepped solution (:class:`~alcontact.contact.solution._records.StepRecords`).
    """

    problem: Any
    history: Any
    algorithm: str
    penalty: str
    friction: float
    points: np.ndarray
    normals: np.ndarray
    tangents: np.ndarray
    weights: np.ndarray
    steps: tuple[FrictionStep, ...]
    status: ContactStatus
    message: str
    outer_iterations: int
    newton_iterations: int
    cutbacks: int
    linear_solves: int
    eps_n: float
    eps_t: float
    h: float
    factorizations: int = 1
    timings: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)

    def raise_for_status(self) -> None:
        """Raise :class:`~alcontact.errors.ConvergenceError` unless converged."""
        if not self.success:
            raise ConvergenceError(f"frictional contact solve failed ({self.status.label}): {self.message}")

    @property
    def final(self) -> FrictionStep:
        if not self.steps:
            raise ConvergenceError(f"no load step converged: {self.message}")
        return self.steps[-1]

    @property
    def requested_steps(self) -> tuple[FrictionStep, ...]:
        return tuple(s for s in self.steps if s.requested)

    def equilibrium(self, step: FrictionStep | None = None):
        r"""Global equilibrium :math:`F_c + F_{ext} + R = 0` of a converged step (default: the final one).

        The contact forces are :math:`w_i (t_{N,i}\nu_i + s_i)` with ``s`` the step's
        ``shear``; loads and supports are those of the history at the step's time
        (:func:`~alcontact.contact.problem._loading.problem_at`). Returns an
        :class:`~alcontact.contact.solution._estimators.Equilibrium`.
        """
        from ._estimators import equilibrium, nodal_force_vector
        from ..problem._loading import problem_at

        st = self.final if step is None else step
        prob = self.problem if self.history is None else problem_at(self.problem, self.history, st.t)
        model = prob.model
        _, dofs = prob.slave_nodes()
        w = np.asarray(self.weights, dtype=float)[:, None]
        forces = w * (np.asarray(st.pressure, dtype=float)[:, None] * self.normals + np.asarray(st.shear, dtype=float))
        if "contact_force_points" in st.two_body:  # two bodies: the forces on the slave and the master nodes
            dofs, forces = st.two_body["contact_force_points"]
        fixed, _ = prob.dirichlet()
        return equilibrium(model, st.u, fixed, prob.load_vector(), nodal_force_vector(model.ndofs, dofs, forces),
                           length=self.h)


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
        OPEN / STICK / SLIP (:mod:`alcontact.contact.laws._coulomb`) of every contact point.
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
        (:func:`state_reversals`; the AL algorithms: over the Newton iterates of all the subproblems of
        the accepted try, whose multipliers change between them); ``None`` where not tracked.
    stick_slip_reversals : int or None
        The same between STICK and SLIP only (the iterates where a point is open are skipped:
        a point at the edge of the contact zone that opens for one iterate is no stick/slip reversal).
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
    stick_slip_reversals: int | None = None

    @property
    def state(self) -> np.ndarray:
        """``states`` (the name of :class:`~alcontact.contact.solution._records.Frame`)."""
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
