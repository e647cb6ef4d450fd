r"""The contact systems of the one globalized Newton method, and the condensed subproblem (S).

Every inner solve of the contact algorithms is Newton's method on a system
:math:`F(x) = 0`: the condensed subproblem (S) of Algorithms 6.1 / 6.3
(:class:`CondensedSubproblem`), its full-space form with AMG-preconditioned CG
(:mod:`alcontact.contact.systems._krylov`), the finite-deformation subproblem and its
active-set reference (:mod:`alcontact.contact.systems._full_space`), and the frictional
subproblems (6.2a) and Alart-Curnier systems (:mod:`alcontact.contact.algorithms._coulomb`,
:mod:`alcontact.contact.systems._full_space`). The loop is :func:`alcontact.optim.newton`
(shared with the hyperelastic body's own solves); its names are re-exported here for
the contact modules. A problem is a :class:`~alcontact.optim.NewtonSystem`.

The systems and their settings:

==========================================  ===========================================================
system                                      line search / stall test
==========================================  ===========================================================
:class:`CondensedSubproblem` (direct path)  Armijo on :math:`\Pi`, full step on a flat merit; stall at
                                            ``max(1e-8, floor)``, ``floor`` the round-off of :math:`F`
``_iterative._FullSpaceSubproblem`` (AMG)   the same; tolerance raised to the round-off bound of
                                            :math:`R`; CG forcing tightened after a damped step
``_finite._Subproblem``                     Armijo on :math:`\Pi` (or :math:`|R|^2/2`) or a residual
                                            decrease; inverted elements halve; stall at
                                            ``max(1e-8, floor)``
``_finite._EqualityNewton`` (reference)     decrease of the relative residual, any step below
                                            :math:`2^{-20}`; stops when the active set changes
``_friction._CondensedSystem``              Armijo on the potential (radius :math:`\mu\lambda_N`) or a
                                            residual decrease (coupled radius, Alart-Curnier)
``_friction_iterative._FullSpaceFriction``  as ``_FullSpaceSubproblem`` (AMG); Armijo on the potential or
                                            a residual decrease (coupled radius, GMRES); stall 1e-8
``_finite_friction._FrictionSubproblem``    residual decrease, inverted elements halve; stall 1e-9
(and the Alart-Curnier reference)           (the reference: from the third iterate on)
==========================================  ===========================================================

Every outcome carries a :class:`~alcontact.status.Status` (``CONVERGED``,
``MAXITER``, ``LINE_SEARCH_FAILED``, ``NONFINITE``, ``NEWTON_FAILED``) and a message
for people; callers test the status. The history records the relative residual of
every iterate and the step length taken from it (the quadratic-rate tests read it).

For fixed multipliers :math:`\lambda` the subproblem (S) of Algorithms 6.1 / 6.3
on the condensed variables (:class:`CondensedSubproblem`) is the minimization of
the potential energy plus the penalty energy. On the manifold of equilibrium
states :math:`u = u_{free} - K^{-1}B^T r` it reads

.. math::

    \Pi(r) = \tfrac12 r^T S r + \sum_i w_i\, \psi_i(g_i), \qquad g = g_{free} - S r,

whose stationarity :math:`r = w \circ t_N(g)` is the equilibrium of the body with
the penalized contact traction. Newton's step solves
:math:`(I + W D S)\,\Delta r = -(r - w\circ t_N)` with :math:`D = \mathrm{diag}(dt_N/dg)`;
it is exactly the full-space Newton step, restricted to the contact points.
Globalized by backtracking (Armijo) on :math:`\Pi`, which is ``+inf`` outside the
domain of barrier-type penalties, so iterates stay inside it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ...optim import LineSearch, NewtonResult, NewtonSettings, NewtonSystem, inner_failure, newton
from ...status import Status


# ---------------------------------------------------------------------- subproblem (S) of the outer loops
@dataclass(frozen=True)
class NewtonOutcome:
    """Outcome of one subproblem (S) for the outer loops of :mod:`alcontact.contact.algorithms._frictionless`.

    ``state`` is the iterate of the outer loops: the contact forces ``r`` of the
    condensed path, the free displacement ``x`` of the AMG and finite-deformation paths;
    ``g`` and ``t`` the gaps and normal tractions of the candidates there.
    """

    state: np.ndarray
    g: np.ndarray
    t: np.ndarray
    iterations: int
    status: Status
    residual: float
    message: str

    @property
    def converged(self) -> bool:
        return self.status.success


def subproblem_outcome(out: NewtonResult, g, t) -> NewtonOutcome:
    """The :class:`NewtonOutcome` of a :func:`newton` result with the gaps ``g`` and tractions ``t`` of its state."""
    return NewtonOutcome(out.x, g, t, out.iterations, out.status, out.residual, out.message)


class CondensedSubproblem(NewtonSystem):
    r"""Subproblem (S) on the condensed contact forces ``r`` (module doc): :math:`F = r - w\circ t_N(g)`.

    State: ``(r, g, t, F, Pi)``. Relative residual :math:`\max|F|` over the largest contact
    force (of the start, or the current iterate where larger).

    A residual that stalls (drops by less than half) counts as converged below the
    round-off floor of that residual (:meth:`roundoff_floor`, the stall level of
    :func:`newton` where it exceeds the fixed 1e-8 of :class:`NewtonSettings`): at a large
    penalty stiffness the gaps :math:`g = g^{free} - S r` lose digits to cancellation and
    :math:`F` carries their error times :math:`w D`, so no Newton step can bring it lower.
    The pure penalty stalled at 1.4e-8 to 2.0e-8 relative on the 2D Hertz model at 983,616
    DOFs (847 candidates, :math:`\varepsilon_N = 1.1\cdot 10^{13}`) and failed after 60
    Newton steps with the fixed level alone. The tolerance itself is not raised: a
    residual still decreasing, or an iteration limit reached, keeps its status.
    """

    #: safety factor of :meth:`roundoff_floor`: the stalled residuals measured on 2D Hertz
    #: models (30, 111 and 847 candidates) lie at 0.05-0.1 times ``sqrt(m) u`` times the bound
    FLOOR_FACTOR = 1.0

    def __init__(self, dc, law, lam):
        self.S = dc.S
        self.w = dc.weights[dc.cand]
        self.gfree = dc.g_free[dc.cand]
        self.law, self.lam = law, lam
        self.scale = None
        self.fscale = 1e-300
        self._Sabs = None  # |S|, built the first time the round-off floor may matter
        self._Smax = float(max(np.max(self.S, initial=0.0), -np.min(self.S, initial=0.0)))  # max|S|, no copy

    def evaluate(self, r):
        g = self.gfree - self.S @ r
        t = self.law.traction(g, self.lam)
        pi = 0.5 * r @ (self.S @ r) + float(np.sum(self.w * self.law.energy(g, self.lam)))
        return r, g, t, r - self.w * t, pi

    def residual(self, state):
        return state[3]

    def merit(self, state):
        return state[4]

    def measure(self, state):
        r, _, t, F, _ = state
        if self.scale is None:
            self.scale = max(float(np.max(np.abs(self.w * t), initial=0.0)),
                             float(np.max(np.abs(r), initial=0.0)))
        self.fscale = max(self.scale, float(np.max(np.abs(r), initial=0.0)), 1e-300)
        return float(np.max(np.abs(F), initial=0.0)) / self.fscale

    def step(self, r, state, history):
        with warnings.catch_warnings():  # ill-conditioning shows in the residual test, not as a warning
            warnings.simplefilter("ignore", sla.LinAlgWarning)
            return newton_step(self.S, self.w * self.law.stiffness(state[1], self.lam), state[3])

    def slope(self, r, state, dr):
        return float((self.S @ state[3]) @ dr)  # grad Pi = S F

    def negligible(self, r, state, dr):
        return float(np.max(np.abs(dr), initial=0.0)) <= 1e-13 * self.fscale

    def stall_level(self, state, level):
        return max(level, self.roundoff_floor(state, level))

    def roundoff_floor(self, state, tol: float = 0.0) -> float:
        r"""Round-off floor of the relative residual :meth:`measure` at ``state``.

        In floating point (unit round-off :math:`u`) the gaps carry the error
        :math:`|\delta g_i| \lesssim u\,(|g^{free}_i| + (|S|\,|r|)_i)` (the rounding of
        :math:`S r`, whose terms cancel against :math:`g^{free}` where the body is in
        contact), the traction :math:`t_N(g)` passes it on times :math:`D_i = dt_N/dg`
        and adds :math:`u|t_i|`, and the difference :math:`r - w\circ t` adds
        :math:`u|r_i|`. To first order

        .. math::

            |\delta F_i| \lesssim u\,\bigl(|r_i| + w_i|t_i|
                + w_i D_i\,(|g^{free}_i| + (|S|\,|r|)_i)\bigr),

        and the residual an exact Newton step :math:`(I + W D S)\Delta r = -F`
        leaves is this evaluation error of the next iterate. The rounding errors of the
        :math:`m` products of :math:`(S r)_i` add up like a random walk, so the floor is
        :attr:`FLOOR_FACTOR` times :math:`\sqrt{m}` times the maximum of the bound over the
        force scale of :meth:`measure` (:math:`m` the candidates).
        It grows with :math:`\max(w D)\,\max|S|`, the conditioning of the Newton
        matrix: about :math:`u` at the default penalty, 1e-8 and more for the pure penalty
        at :math:`\varepsilon_N h / E'` of 1e5 and beyond. A residual far above it is
        not round-off and still fails.

        A non-finite bound (a barrier's infinite stiffness) gives 0: no round-off is claimed.
        ``tol``: where the cheap bound with :math:`\max|S|\sum|r|` in place of :math:`|S||r|`
        already stays below it, that bound is returned (no :math:`|S|` is built).
        """
        r, g, t, _, _ = state
        if r.size == 0:
            return 0.0
        unit = self.FLOOR_FACTOR * np.sqrt(r.size) * np.finfo(float).eps
        wd = self.w * np.abs(self.law.stiffness(g, self.lam))
        base = np.abs(r) + self.w * np.abs(t)
        fscale = max(self.fscale, 1e-300)
        cheap = unit * float(np.max(
            base + wd * (np.abs(self.gfree) + self._Smax * float(np.sum(np.abs(r)))))) / fscale
        if not np.isfinite(cheap):  # an infinite stiffness (barrier at its pole): no floor is claimed
            return 0.0
        if cheap <= tol:
            return cheap
        if self._Sabs is None:
            self._Sabs = np.abs(self.S)
        bound = base + wd * (np.abs(self.gfree) + self._Sabs @ np.abs(r))
        return unit * float(np.max(bound)) / fscale


#: rows whose coupling ``wd_i * max|S|`` is below this are decoupled (``dr_i = -F_i``): far below round-off
_DECOUPLED = 1e-200


def newton_step(S, wd, F) -> np.ndarray:
    r"""Newton correction: solve :math:`(I + \mathrm{diag}(wd)\,S)\,\Delta r = -F`.

    With :math:`wd \ge 0` (every law of family P and the Macaulay law) the system is
    solved in its symmetric form. Rows with :math:`wd_i = 0` (points off contact under a
    Macaulay law, or whose coupling is below round-off) give :math:`\Delta r_i = -F_i`;
    on the others, ``P``,

    .. math::

        (\mathrm{diag}(1/wd_P) + S_{PP})\,\Delta r_P = -F_P / wd_P - S_{PZ}\,\Delta r_Z,

    a symmetric positive definite system (``S`` is) solved by Cholesky on the ``|P|``
    rows only: a third of the LU of the whole matrix when every row is coupled, less when
    part of the candidates is off contact. A negative ``wd_i`` (contact springs of a body
    held only by the obstacle) or a Cholesky that fails falls back to the LU of the whole
    matrix.
    """
    n = F.size
    smax = float(np.max(np.abs(np.diagonal(S)), initial=0.0))
    if n and np.all(wd >= 0):
        P = wd * smax > _DECOUPLED
        dr = -np.asarray(F, dtype=float).copy()
        if not np.any(P):
            return dr
        Z = ~P
        A = S[np.ix_(P, P)]
        A[np.diag_indices_from(A)] += 1.0 / wd[P]
        rhs = dr[P] / wd[P]
        if np.any(Z):
            rhs -= S[np.ix_(P, Z)] @ dr[Z]
        try:
            c = sla.cho_factor(A, lower=True, check_finite=True)
        except np.linalg.LinAlgError:
            pass  # not positive definite to round-off: the LU below
        else:
            dr[P] = sla.cho_solve(c, rhs, check_finite=False)
            return dr
    J = S * wd[:, None]
    J[np.diag_indices_from(J)] += 1.0
    return sla.solve(J, -F, check_finite=True)


def solve_subproblem(dc, law, lam, r0, *, tol=1e-12, maxiter=60) -> NewtonOutcome:
    """Solve ``r = w t_N(g_free - S r; lam)`` by :func:`newton` (:class:`CondensedSubproblem`)."""
    out = newton(CondensedSubproblem(dc, law, lam), r0, tol=tol, maxiter=maxiter)
    return subproblem_outcome(out, out.state[1], out.state[2])


@dataclass(frozen=True)
class _Point:
    """State of :class:`_CondensedSystem` at one iterate: residual, the caller's ``aux``, energy."""

    x: np.ndarray
    F: np.ndarray
    aux: tuple
    energy: float


class _PointSystem(NewtonSystem):
    """A Newton system whose states are :class:`_Point`: the residual ``F``, the merit its ``energy``
    (the subproblems of both paths: :class:`_CondensedSystem`,
    :class:`~alcontact.contact.systems._krylov._FullSpaceFriction`)."""

    def residual(self, state):
        return state.F

    def merit(self, state):
        return state.energy
