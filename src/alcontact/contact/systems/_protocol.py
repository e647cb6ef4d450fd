r"""The contact system: everything the frictionless contact algorithms may call.

:func:`~alcontact.contact.algorithms._frictionless.run_penalty` (pure penalty (6.10), Algorithm 5.2),
:func:`~alcontact.contact.algorithms._frictionless.run_al` (Algorithms 6.1 and 6.3) and
:func:`~alcontact.contact.algorithms._frictionless.run_ssn` (the semi-smooth Newton reference) see a model
only through :class:`ContactSystem`. Every model class implements all of it:

- :class:`~alcontact.contact.systems._condensed.DiscreteContact` (small deformation, the problem
  condensed on the contact points of one sparse factorization),
- :class:`~alcontact.contact.systems._krylov.IterativeContact` (small deformation, full space,
  AMG + CG),
- :class:`~alcontact.contact.systems._full_space.FiniteContact` (finite deformation, gap at the deformed
  position) and, through it, the frictional finite-deformation model.

A capability a model does not have is a member with a declared *not available* value (a
warm start of zeros, the plain semi-smooth rule, no multiplier shift, no second-order update
(``None``), ``False``), defined once on :class:`~alcontact.contact.kinematics._points.ContactPoints`,
the base of every model; the algorithms never ask whether a member exists. What differs between
small and finite deformation is therefore visible here, as declared members, and the user's
choices are options (:class:`~alcontact.contact.ContactOptions`).

What the kinematics declares and what the strategy declares. Every model holds its gap as a
:class:`~alcontact.contact.kinematics.ContactKinematics` object (``kinematics``: the linearized
gap (6.15) at small deformation, the gap in the current configuration at finite deformation)
and takes every gap, constraint row and curvature term from it; Algorithms 6.1 / 6.3 are the
same code on both. The capabilities below are not facts of the gap but of the strategy that
solves the subproblems, and stay declared by the model: :attr:`ContactSystem.physical_stopping`
holds where :meth:`ContactSystem.multiplier_step` is a second-order update (it needs the factor
of the full Newton matrix of (S), which the full-space Newton keeps);
:attr:`ContactSystem.warm_penalty_start` and :attr:`ContactSystem.penalty_continuation` need a
load-step predictor and the state of the last accepted step (the load-stepped full-space model);
:attr:`ContactSystem.inexact_subproblems` holds where a Newton iteration costs an assembly or a
V-cycle (the full-space Newton, and the large AMG model at small deformation as well).

Sign convention: :math:`g \le 0` is feasible (no penetration); multipliers and tractions are
pressures :math:`\lambda_N, t_N \ge 0`. Arrays over "the candidates" have one entry per
point of :attr:`ContactSystem.cand`; a *state* is whatever the model iterates on (condensed
contact forces, or free displacements), opaque to the algorithms.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class ContactSystem(Protocol):
    r"""What the frictionless contact algorithms call on a contact model (module doc).

    Attributes
    ----------
    h : float
        Contact-zone element size: the unit of the penetration measures of the stopping
        tests (max :math:`g^+ / h`) and of the automatic stiffness :math:`E'/h`.
    cand : ndarray of int
        The candidate contact points of the current solve; every multiplier, gap and
        traction array the algorithms handle is aligned with it.
    inexact_subproblems : bool
        Whether the subproblems (S) of Algorithms 6.1 / 6.3 may be solved inexactly (Newton
        tolerance from the last multiplier change, the last one to ``newton_tol``): each of
        the model's Newton iterations costs an assembly or a V-cycle. ``True`` at finite
        deformation and on large AMG models; the option ``subproblems = "exact"`` overrides it.
    inexact_first_tol : float
        Where :attr:`inexact_subproblems` holds, the Newton tolerance of the first subproblem of a
        solve (later ones follow the multiplier change): 1e-2 at finite deformation (tuned on the
        ironing steps of issue 18), 1e-4 on the AMG paths (a looser first solve cost Algorithm 6.1 three
        more outer iterations at 1M DOFs, issue 21).
    physical_stopping : bool
        Whether Algorithm 6.1 may stop as soon as penetration and complementarity hold at a
        subproblem solved to ``newton_tol`` (the model's :meth:`multiplier_step` is a
        second-order update, so the multiplier change is not needed as a test). ``False``:
        the three tests of (6.13) must hold.
    warm_penalty_start : bool
        Whether the pure-penalty start of Algorithm 6.3 (``initial = "penalty"``) is the first
        subproblem of Algorithm 6.1 of a load step: multipliers :meth:`initial_multipliers`,
        :meth:`entry_multipliers` and :meth:`start_multiplier_step`. ``False``: one penalty
        solve (6.10) from :meth:`start`.
    penalty_continuation : bool
        Whether the pure penalty method (6.10) continues its increasing stiffness sequence
        (Algorithm 5.2) over load steps from :attr:`carried_stiffness`, its first solve of a
        step started with :meth:`entry_multipliers`.
    carried_stiffness : float or None
        The stiffness the last converged penalty step ended with (written by
        :func:`~alcontact.contact.algorithms._frictionless.run_penalty` where
        :attr:`penalty_continuation`); ``None`` before, and always on models without it.
    active_converged : bool
        Whether the inner solve of the last :meth:`solve_active` met its tolerance
        (``True`` on models whose active-set step is a direct solve).
    active_residual : float
        Relative residual of that inner solve (``nan`` where there is none).
    """

    h: float
    cand: np.ndarray
    carried_stiffness: float | None
    active_converged: bool
    active_residual: float

    @property
    def inexact_subproblems(self) -> bool: ...

    @property
    def inexact_first_tol(self) -> float: ...

    @property
    def physical_stopping(self) -> bool: ...

    @property
    def warm_penalty_start(self) -> bool: ...

    @property
    def penalty_continuation(self) -> bool: ...

    def start(self) -> Any:
        """The starting state of the solve (the step's prediction at finite deformation)."""

    def gaps(self, state: Any) -> np.ndarray:
        r"""Gaps :math:`g` (6.15) of the candidates at ``state`` (finite: at the deformed position)."""

    def subproblem(self, law: Any, lam: np.ndarray, state: Any, *, tol: float, maxiter: int) -> Any:
        r"""Solve subproblem (S) of Algorithms 6.1 / 6.3 by Newton's method from ``state``.

        Equilibrium with the traction :math:`t_N = \texttt{law.traction}(g, \lambda)`:
        :math:`\langle\lambda_N + \varepsilon_N g\rangle` (6.12) for Algorithm 6.1 and the
        pure penalty (6.10) (:math:`\lambda = 0`), :math:`p'(g/\eta, \lambda_N)` (6.66) for
        Algorithm 6.3. ``tol`` is the relative residual, ``maxiter`` the Newton budget.
        Returns a :class:`~alcontact.contact.algorithms._subproblem.NewtonOutcome` (``state``, ``g``, ``t``,
        ``iterations``, ``status``, ``converged``, ``residual``, ``message``).
        """

    def scale_forces(self, state: Any, factor: float) -> Any:
        """``state`` with its contact forces scaled by ``factor`` (exact for a linear body, first order
        otherwise): barrier-type penalties of Algorithm 6.3 need a start inside their domain."""

    def solve_active(self, active: np.ndarray, lam: np.ndarray, state: Any, c: float) -> tuple:
        r"""One step of the semi-smooth Newton reference on :math:`\lambda = \max(0, \lambda + c\,g)`.

        Enforces :math:`g_A = 0` on the ``active`` candidates and zero pressure elsewhere;
        returns ``(state, multipliers, gaps)``. Raises :class:`numpy.linalg.LinAlgError` for
        dependent active rows; records :attr:`active_converged` and :attr:`active_residual`.
        """

    def initial_multipliers(self) -> np.ndarray:
        r"""Starting multipliers on the candidates: the warm start of a load step (finite deformation:
        the predicted pressures), zeros on models without one (Algorithm 6.1 starts from
        :math:`\lambda_N = 0`)."""

    def initial_active(self, lam: np.ndarray, g: np.ndarray, c: float) -> np.ndarray:
        r"""Starting active set of the reference: the rule :math:`\lambda + c\,g > 0`, or a model's
        prediction of which points enter contact in a load step (finite deformation)."""

    def entry_multipliers(self, lam: np.ndarray, law: Any, *, penalty_start: bool = False) -> np.ndarray:
        r"""Multipliers of the first subproblem (S) of a step: ``lam`` itself (no prediction), or
        ``lam`` shifted so that points predicted to stay open start without traction and carried
        pressures start as tractions (finite deformation). ``penalty_start``: the start of
        Algorithm 6.3 asks (option ``slide_start_reach``)."""

    def multiplier_step(self, law: Any, lam: np.ndarray, out: Any) -> Any:
        r"""Second-order update of the multipliers after subproblem ``out`` solved with ``lam``.

        A Newton step on the dual of Algorithm 6.1 with the same fixed point as (6.13):
        ``None`` (keep the first-order update (6.13) / (6.66); the only value on models
        without one), the new multipliers, or ``(multipliers, next starting state)``.
        """

    def start_multiplier_step(self, law: Any, lam: np.ndarray, out: Any) -> Any:
        """:meth:`multiplier_step` of the warm penalty start of Algorithm 6.3
        (:attr:`warm_penalty_start`): ``None`` where there is none (keep the start's tractions)."""


#: Names of the members of :class:`ContactSystem` (the whole interface the algorithms call).
SYSTEM_MEMBERS: tuple[str, ...] = (
    "h", "cand", "carried_stiffness", "active_converged", "active_residual", "inexact_subproblems",
    "inexact_first_tol", "physical_stopping", "warm_penalty_start", "penalty_continuation", "start", "gaps", "subproblem",
    "scale_forces", "solve_active", "initial_multipliers", "initial_active", "entry_multipliers",
    "multiplier_step", "start_multiplier_step")
