"""Result objects of :func:`alcontact.optim.minimize`: status enum, history, result.

``Status`` is the project's one status table :class:`alcontact.status.Status`
(shared with :class:`alcontact.contact.ContactStatus`); its optimization members
are ``CONVERGED_KKT``, ``UNCONSTRAINED_CONVERGED``, ``MAXITER``, ``INNER_FAILED``,
``NONFINITE``, ``PENALTY_LIMIT`` and ``UNBOUNDED``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ConvergenceError
from ..status import Status

__all__ = ["Status", "IterationRecord", "ALResult"]


def _readonly(a):
    if a is None:
        return None
    a = np.array(a, dtype=float, copy=True)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class IterationRecord:
    """One outer iteration of the augmented Lagrangian loop.

    Attributes
    ----------
    k : int
        Outer iteration number (1-based: the state after the k-th subproblem).
    f : float
        Objective value at the subproblem solution.
    feasibility, stationarity, complementarity : float
        KKT measures (C4), (C1) (scaled), (C2) at that point; see
        :class:`ALResult`.
    eta_min, eta_max : float
        Smallest and largest penalty parameter used for the subproblem
        (a smaller ``eta`` is a stronger penalty for the AL methods).
    inner_iterations : int
        Newton iterations of this subproblem.
    inner_status : str
        Termination reason of the inner solver.
    inner_tol : float
        Tolerance the subproblem was solved to (scaled gradient norm).
    factor : float
        Factor applied to ``eta`` after this iteration (``eta <- eta / factor``;
        1 = unchanged, > 1 = tightened).
    """

    k: int
    f: float
    feasibility: float
    stationarity: float
    complementarity: float
    eta_min: float
    eta_max: float
    inner_iterations: int
    inner_status: str
    inner_tol: float
    factor: float


@dataclass(frozen=True)
class ALResult:
    """Result of :func:`alcontact.optim.minimize` (frozen; arrays are read-only).

    Attributes
    ----------
    x : ndarray, shape (n,)
        Final iterate.
    fun : float
        Objective value at ``x``.
    success : bool
        ``status > 0``.
    status : Status
        Termination reason (positive = converged, negative = failed).
    message : str
        Human-readable reason, including hints for failures.
    nit : int
        Outer iterations (subproblems solved).
    nit_inner : int
        Total inner (Newton) iterations.
    nfev, njev, nhev : int
        Calls of the objective, its gradient and its Hessian (finite
        difference evaluations included).
    ncev : int
        Evaluations of the constraint functions (all constraint objects at one
        point count as one).
    multipliers_ineq : ndarray, shape (m,)
        Multipliers of the internal inequalities ``g(x) <= 0``, estimated as
        :math:`\\bar\\mu_i = p'(g_i/\\eta_i, \\mu_i)` (5.29)-(5.30), clipped at 0.
    multipliers_eq : ndarray, shape (p,)
        Multipliers of the internal equalities ``h(x) = 0``.
    multipliers : tuple of ndarray
        SciPy-like multipliers, one array per user constraint object in the
        order given, of the length of that constraint's ``fun``: the
        derivative of the Lagrangian :math:`f + \\sum v^T c` with respect to
        the constraint value (positive when the upper bound is active,
        negative when the lower bound is active).
    multipliers_bounds : ndarray, shape (n,) or None
        The same for ``bounds`` (None without bounds).
    constr_ineq, constr_eq : ndarray
        Internal constraint values ``g(x)`` and ``h(x)``.
    stationarity : float
        (C1) :math:`\\|\\nabla f + J_g^T\\mu + J_h^T\\lambda\\|_\\infty /
        \\max(1, \\|\\nabla f\\|_\\infty)`.
    feasibility : float
        (C4) :math:`\\max(\\max_i g_i^+, \\max_j |h_j|)`.
    complementarity : float
        (C2) :math:`\\max_i |\\mu_i g_i|`.
    eta : ndarray
        Final penalty parameters (inequalities first, then equalities).
    method, penalty, strategy, inner : str
        Registry names used.
    history : tuple of IterationRecord
        One record per outer iteration.
    """

    x: np.ndarray
    fun: float
    success: bool
    status: Status
    message: str
    nit: int
    nit_inner: int
    nfev: int
    njev: int
    nhev: int
    ncev: int
    multipliers_ineq: np.ndarray
    multipliers_eq: np.ndarray
    multipliers: tuple
    multipliers_bounds: np.ndarray | None
    constr_ineq: np.ndarray
    constr_eq: np.ndarray
    stationarity: float
    feasibility: float
    complementarity: float
    eta: np.ndarray
    method: str
    penalty: str
    strategy: str
    inner: str
    history: tuple = field(default=())

    def __post_init__(self):
        for name in ("x", "multipliers_ineq", "multipliers_eq", "multipliers_bounds",
                     "constr_ineq", "constr_eq", "eta"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "multipliers",
                           tuple(_readonly(v) for v in self.multipliers))
        object.__setattr__(self, "history", tuple(self.history))

    def raise_for_status(self) -> "ALResult":
        """Raise :class:`alcontact.errors.ConvergenceError` unless converged.

        Returns
        -------
        ALResult
            ``self``, so that ``minimize(...).raise_for_status().x`` works.
        """
        if self.status <= 0:
            raise ConvergenceError(
                f"{self.method} ({self.penalty}) did not converge: "
                f"{self.status.name}: {self.message}")
        return self

    def __repr__(self) -> str:  # short, like SciPy's OptimizeResult
        return (f"ALResult(status={self.status.name}, success={self.success}, "
                f"fun={self.fun:.10g}, nit={self.nit}, nit_inner={self.nit_inner}, "
                f"feasibility={self.feasibility:.3g}, "
                f"stationarity={self.stationarity:.3g}, "
                f"complementarity={self.complementarity:.3g}, "
                f"message={self.message!r})")
