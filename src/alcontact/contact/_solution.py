"""Contact solver result and contact solution objects."""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ConvergenceError
from ..status import Status

__all__ = ["ContactStatus", "ContactIteration", "ContactResult", "ContactSolution"]

logger = logging.getLogger(__name__)


#: Termination reason of a contact solve: the project's one status table
#: :class:`alcontact.status.Status` (positive = converged, negative = failed, as PETSc),
#: shared with :func:`alcontact.optim.minimize`.  Contact members: ``CONVERGED``,
#: ``NO_CONTACT``, ``MAXITER``, ``NEWTON_FAILED``, ``NONFINITE``, ``PENALTY_LIMIT``,
#: ``NOT_VERIFIED``.
ContactStatus = Status


@dataclass(frozen=True)
class ContactIteration:
    """One outer iteration (one subproblem (S) and one multiplier update)."""

    k: int
    penetration: float  # max positive gap / h
    complementarity: float  # max |lambda g| / (p_ref h)
    multiplier_change: float  # max |lambda_new - lambda| / p_ref
    residual: float  # Newton residual of the subproblem (relative)
    newton_iterations: int
    eps_n: float
    active: int


@dataclass(frozen=True)
class ContactResult:
    """Solver outcome: status, counters and per-iteration history."""

    status: ContactStatus
    message: str
    algorithm: str
    penalty: str
    outer_iterations: int
    newton_iterations: int
    linear_solves: int
    factorizations: int
    penetration: float
    complementarity: float
    residual: float
    eps_n: float
    history: tuple[ContactIteration, ...] = ()

    @property
    def success(self) -> bool:
        return self.status > 0

    def raise_for_status(self) -> None:
        """Raise :class:`~alcontact.errors.ConvergenceError` unless converged."""
        if not self.success:
            raise ConvergenceError(f"contact solve failed ({self.status.label}): {self.message}")


@dataclass(frozen=True)
class ContactSolution:
    """Displacements and contact quantities of a solved contact problem.

    Attributes
    ----------
    u : ndarray (ndofs,)
        Displacement.
    points : ndarray (m, d)
        Contact-boundary points (reference positions).
    pressure : ndarray (m,)
        Contact pressure :math:`\\lambda_N` per point (stress units; 0 off the candidates).
    gap : ndarray (m,)
        Linearized gap (6.15) per point (<= 0 feasible).
    weights : ndarray (m,)
        Tributary lengths / areas.
    active : ndarray of bool (m,)
        Points in contact (positive pressure and closed gap).
    normals : ndarray (m, d)
        Obstacle normals at the points.
    total_contact_force : ndarray (d,)
        Resultant of the contact forces on the body :math:`\\sum_i w_i \\lambda_i \\nu_i`.
    result : ContactResult
    timings : dict
        ``setup_s``, ``factor_s``, ``linear_solve_s`` (one factor + solve), ``solve_s``, ``total_s``.
    """

    problem: Any
    u: np.ndarray
    points: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    weights: np.ndarray
    active: np.ndarray
    normals: np.ndarray
    total_contact_force: np.ndarray
    result: ContactResult
    timings: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)

    @property
    def status(self) -> ContactStatus:
        return self.result.status

    @property
    def normal_force(self) -> float:
        """Total normal contact force :math:`\\sum_i w_i\\lambda_i`."""
        return float(np.sum(self.weights * self.pressure))

    def contact_half_width(self, axis: int = 0, center=None) -> float:
        """Half-width of the contact zone along coordinate ``axis``.

        2D: along the contact boundary; 3D: along the line through ``center``
        parallel to ``axis`` in the contact plane (e.g. a symmetry line), which
        for a circular contact is the contact radius. The edge is located
        between the last loaded point and the next one from the square-root
        behaviour of the pressure at a smooth contact edge,
        :math:`p \\propto \\sqrt{a - r}`: with the last two loaded points
        :math:`r_1 < r_2`, :math:`a = (r_2 - \\rho r_1)/(1-\\rho)`,
        :math:`\\rho = (p_2/p_1)^2`, kept between :math:`r_2` and the first
        unloaded point.
        """
        pts = self.points
        d = pts.shape[1]
        c = np.zeros(d) if center is None else np.asarray(center, dtype=float)
        if c.size < d:
            c = np.concatenate([c, np.zeros(d - c.size)])
        on_line = np.ones(pts.shape[0], bool)
        if d == 3:
            # points on the line through c along `axis`, within the contact plane
            other = [k for k in range(d) if k != axis]
            spread = np.ptp(pts, axis=0)
            flat = int(np.argmin(spread))  # normal direction of the (flat) contact boundary
            lateral = [k for k in other if k != flat][0]
            on_line = np.abs(pts[:, lateral] - c[lateral]) <= 1e-9 * max(spread.max(), 1e-300)
        r = np.abs(pts[on_line, axis] - c[axis])
        p = self.pressure[on_line]
        loaded = self.active[on_line] & (p > 0)
        if not np.any(loaded):
            return 0.0
        order = np.argsort(r, kind="stable")
        r, p, loaded = r[order], p[order], loaded[order]
        last = int(np.flatnonzero(loaded).max())
        r2, p2 = r[last], p[last]
        cap = r[last + 1] if last + 1 < r.size else r2
        if last == 0:
            return float(0.5 * (r2 + cap))
        r1, p1 = r[last - 1], p[last - 1]
        if p1 <= p2 or p1 <= 0 or r1 >= r2:
            return float(0.5 * (r2 + cap))
        rho = (p2 / p1) ** 2
        a = (r2 - rho * r1) / (1.0 - rho)
        return float(min(max(a, r2), cap))

    @property
    def peak_pressure(self) -> float:
        return float(np.max(self.pressure, initial=0.0))
