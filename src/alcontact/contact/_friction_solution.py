"""Result objects of incremental frictional contact: one state per load step."""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ConvergenceError
from ._friction_laws import OPEN, SLIP, STICK
from ._solution import ContactStatus
from ._stepping import StepRecords

__all__ = ["FrictionStep", "FrictionSolution", "OPEN", "STICK", "SLIP"]

logger = logging.getLogger(__name__)


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

    @property
    def force(self) -> np.ndarray:
        """``contact_force`` (the name of :class:`~alcontact.contact._stepping.Frame`)."""
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
    those of every stepped solution (:class:`~alcontact.contact._stepping.StepRecords`).
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
        (:func:`~alcontact.contact._loading.problem_at`). Returns an
        :class:`~alcontact.contact._estimators.Equilibrium`.
        """
        from ._estimators import equilibrium, nodal_force_vector
        from ._loading import problem_at

        st = self.final if step is None else step
        prob = self.problem if self.history is None else problem_at(self.problem, self.history, st.t)
        model = prob.model
        _, dofs = model.node_dofs(prob.contact_boundary)
        w = np.asarray(self.weights, dtype=float)[:, None]
        forces = w * (np.asarray(st.pressure, dtype=float)[:, None] * self.normals + np.asarray(st.shear, dtype=float))
        fixed, _ = prob.dirichlet()
        return equilibrium(model, st.u, fixed, prob.load_vector(), nodal_force_vector(model.ndofs, dofs, forces),
                           length=self.h)

