r"""Coulomb friction with incremental loading, small deformation, 2D and 3D (section 6.2).

Registered algorithms (entries of the registry of :mod:`alcontact.contact._algorithms` with
``friction=True``, :func:`friction_algorithms`):

``simo-laursen``
    Algorithm 6.2: per load step, augmented Lagrangian iterations with the
    normal traction :math:`\langle\lambda_N + \varepsilon_N g\rangle` (6.52), the
    return mapping (6.47)-(6.50) (corrected (6.49)) in AL form, and the updates
    (6.2b) :math:`\lambda_N \leftarrow \langle\lambda_N + \varepsilon_N g\rangle`,
    (6.2c) :math:`\lambda_T \leftarrow \operatorname{proj}_{B(\mu t_N)}
    (\lambda_T + \varepsilon_T \Delta u_T)` (:math:`\lambda_T = t_{T,n} + \Delta\lambda_T`).
``family-p``
    Algorithm 6.4: the same with the normal traction of a family-P penalty,
    :math:`t_N = p'(g/\eta, \lambda_N)`, update :math:`\lambda_N \leftarrow p'(g/\eta, \lambda_N)`
    (scaling :math:`\eta` as in :mod:`alcontact.contact._laws`).
``ssn``
    Reference: Alart-Curnier semi-smooth Newton on the multipliers
    :math:`(\lambda_N, \lambda_T)` of the same discrete problem (no penalty),
    :math:`\lambda_N - \max(0, \lambda_N + c_N g) = 0`,
    :math:`\lambda_T - \operatorname{proj}_{B(\mu\max(0, \lambda_N + c_N g))}
    (\lambda_T + c_T (u_T - u_{T,n})) = 0`.

A converged AL step satisfies the *exact* time-discrete Coulomb law (the fixed
point of (6.2c) has :math:`\Delta u_T = 0` at stick points and
:math:`|\lambda_T| = \mu\lambda_N`, :math:`\Delta u_T \parallel \lambda_T` at slip
points), so all three algorithms solve the same discrete problem and agree to
solver tolerance.

Outer update of Algorithms 6.2 / 6.4 (option ``multiplier_update``): the
first-order updates (6.2b)/(6.2c) contract the multiplier error by a fixed
factor per outer iteration (about 1/60 normal, 1/13 tangential on the 2D
Cattaneo-Mindlin case: 6-8 outer iterations per step); the default second-order
multiplier iteration (Newton on :math:`\lambda = t(\lambda)` with the exact
sensitivity of the subproblem, plus a tangent predictor from the last step) needs
one subproblem and one confirming subproblem per step while the stick/slip sets
do not change, with the same stopping test.

Coulomb radius of the subproblems (option ``radius``): ``"multiplier"`` (default)
takes the coupled radius :math:`\mu t_N(g)` in the first subproblem of a step and
the fixed radius :math:`\mu\lambda_N` of (6.2c) afterwards (hybrid radius,
:func:`_coupled_start`: points entering contact at :math:`\lambda_N = 0` stick from the
first subproblem instead of slipping on a disc of radius 0; 2 outer iterations per
step on Cattaneo-Mindlin with friction from the first step instead of 3-5);
``"traction"`` takes the coupled radius in every subproblem.

Every subproblem is solved by a semi-smooth Newton method in the condensed
variables (see :mod:`alcontact.contact._friction_discrete`) with the consistent
tangent of the return mapping and backtracking on the residual norm (the
frictional problem is non-symmetric: there is no energy to descend).
On the AMG path (:mod:`alcontact.contact._friction_iterative`) the same loop
:func:`_step_al` drives the subproblems in the free displacements instead (the step's
system, :class:`_ALSystem`, is the only difference; that path declares first-order
multiplier updates), and the same load step (:class:`_StepPath`) adds candidates and
checks a held body's equilibrium.

The steps are walked by :func:`~alcontact.contact._stepping.step_through`: a step
that fails is retried from the last converged state with the increment times
``cutback_factor``, down to ``cutback_factor**max_cutbacks`` times the requested
one; the converged steps are kept. A problem with ``kinematics="finite"`` goes to
:func:`~alcontact.contact.solve_finite_friction` (same algorithms in the current
configuration, driven by the same loop :func:`_step_al` through the step's system
:class:`~alcontact.contact._finite_friction._FiniteALCtx`).
"""

from __future__ import annotations

import logging
import time
import warnings
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import numpy as np
import scipy.linalg as sla

from .. import penalties as _pen
from .._options import MAX_STEPS, VALUE_RANGE, is_integer, is_real, show
from ..errors import InputError
from ..linalg import select_solver
from ._algorithms import (DEFAULT_PENALTY, FRICTION_DEFAULTS, ContactOptions, algorithm_docs, algorithm_names,
                          check_solve_args, find_algorithm, options_with, register_family)
from ._friction_discrete import FrictionalContact
from ._friction_laws import OPEN, SLIP, STICK, Macaulay, block_diag, local_law, tangential_energy
from ._friction_solution import FrictionSolution, FrictionStep
from ._laws import eta_for_stiffness, freezes_at_zero, make_law
from ._loading import LoadHistory, problem_at
from ._newton import LineSearch, NewtonResult, NewtonSettings, NewtonSystem, inner_failure, newton
from ._solution import ContactStatus
from ._stiffness import penalty_stiffness
from ._stepping import Attempt, StepRecord, step_through
from ._verify import check_state, equilibrium_tolerance, reach, state_equilibrium

__all__ = ["FrictionOptions", "solve_friction", "friction_algorithms", "friction_algorithm_docs"]

logger = logging.getLogger(__name__)

#: Largest relative equilibrium residual of a step of a body held only by the obstacle.
_EQUILIBRIUM_TOL = 1e-7

@dataclass(frozen=True)
class FrictionOptions(ContactOptions):
    """:class:`~alcontact.contact.ContactOptions` under the name the frictional solvers used before issue 9.

    The same fields, declarations and defaults (one options type: the frictional
    options are the fields of ``ContactOptions`` marked *friction*, and the Newton
    options ``newton_tol`` / ``maxiter_newton`` default to the frictional algorithms'
    values through their registry entries); only its messages say
    ``"friction option ..."``. Kept for code that imports it; pass a ``ContactOptions``
    in new code. Every solver accepts either.
    """

    _KIND: ClassVar[str] = "friction"


# ---------------------------------------------------------------------------
# the condensed Newton systems of a step (driven by _newton.newton)
# ---------------------------------------------------------------------------
def _solve(J, b):
    """``J^{-1} b`` (LinAlgError/ValueError when singular or not finite).

    An ill-conditioned ``J`` (a body held only by the obstacle whose iterate lets
    every touching point slip: the rigid motion is then free) is not an error
    here: the callers check what the step does (line search, residual), so
    SciPy's ``LinAlgWarning`` is logged at debug level instead of raised to the user.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", sla.LinAlgWarning)
        x = sla.solve(J, b, check_finite=True)
    for w in caught:
        if issubclass(w.category, sla.LinAlgWarning):
            logger.debug("friction: %s", w.message)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return x


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
    :class:`~alcontact.contact._friction_iterative._FullSpaceFriction`)."""

    def residual(self, state):
        return state.F

    def merit(self, state):
        return state.energy


class _CondensedSystem(_PointSystem):
    """``F(x) = 0`` on the condensed forces of a step, for :func:`~._newton.newton`.

    ``fun(x) -> (F, aux)``, ``jac(x, aux) -> J`` (dense, possibly unsymmetric), ``scale(x, aux) > 0``
    the force unit of the relative residual. Globalization: Armijo on ``energy(x)`` (with
    ``grad(x, F)`` its gradient) when the problem has a potential, else a decrease of the
    residual norm (:data:`_POTENTIAL`, :data:`_NO_POTENTIAL`).
    """

    def __init__(self, fun, jac, scale, energy=None, grad=None):
        self.fun, self.jac, self.scale, self.energy, self.grad = fun, jac, scale, energy, grad
        self.fs = 1e-300

    def evaluate(self, x):
        F, aux = self.fun(x)
        return _Point(x, F, aux, self.energy(x) if self.energy is not None else 0.0)

    def slope(self, x, state, dx):
        return float(self.grad(x, state.F) @ dx)

    def measure(self, state):
        self.fs = max(self.scale(state.x, state.aux), 1e-300)
        return float(np.max(np.abs(state.F), initial=0.0)) / self.fs

    def step(self, x, state, history):
        return _solve(self.jac(x, state.aux), -state.F)

    def negligible(self, x, state, dx):
        return float(np.max(np.abs(dx), initial=0.0)) <= 1e-14 * max(float(np.max(np.abs(x), initial=0.0)), self.fs)


#: with a potential: Armijo on it (full step when it is flat to round-off); no stall test; a
#: correction at round-off level converges within 1e3 times the tolerance
_POTENTIAL = NewtonSettings(LineSearch(halvings=50), stall=0.0, negligible_tol=1e3)
#: without one: a decrease of the residual norm
_NO_POTENTIAL = NewtonSettings(LineSearch(halvings=50, merit=False, residual_decrease=True, full_step=False),
                               stall=0.0, negligible_tol=1e3)


def _newton(fun, jac, x0, scale, *, tol, maxiter, energy=None, grad=None) -> NewtonResult:
    """Solve ``F(x) = 0`` by :func:`~._newton.newton` on a :class:`_CondensedSystem`."""
    system = _CondensedSystem(fun, jac, scale, energy, grad)
    return newton(system, x0, tol=tol, maxiter=maxiter, settings=_POTENTIAL if energy is not None else _NO_POTENTIAL)


# ---------------------------------------------------------------------------
# one load step
# ---------------------------------------------------------------------------
@dataclass
class _StepOut:
    ok: bool
    message: str
    R: np.ndarray  # (c, d) local nodal forces on the candidates
    t: np.ndarray  # (c, d) tractions
    outer: int
    newton: int
    status: ContactStatus = ContactStatus.CONVERGED
    predictor: np.ndarray | None = None  # (c d, c d) d lambda* / d y_free at the converged state
    z: np.ndarray | None = None  # last iterate in the unknowns of the step's system (_ALSystem.start)
    last_state: Any = None  # the system's state of the last subproblem (NewtonResult.state; None: none solved)


class _ALSystem(Protocol):
    """The system of a load step that the one AL loop :func:`_step_al` drives (Algorithms 6.2 / 6.4).

    Its unknowns ``z`` are the condensed contact forces ``R`` ``(c, d)`` on the direct path
    (:class:`_Ctx`), the free displacements ``x`` on the AMG path
    (:class:`~alcontact.contact._friction_iterative._FullCtx`) or the free displacements at
    finite deformation (:class:`~alcontact.contact._finite_friction._FiniteALCtx`); the
    multipliers, the stopping test (:func:`_measures`) and the updates (6.2b)/(6.2c) are the same.

    A subproblem's state carries ``aux = (y, t, Dy, state)``: ``y`` ``(c, 1 + k)`` the gaps and
    the ``k`` tangential kinematic components whose change from ``uTn`` is the step's slip, ``t``
    ``(c, 1 + k)`` the normal and tangential tractions, ``Dy`` the tangent of ``t`` (read only by
    the second-order update) and ``state`` the OPEN / STICK / SLIP flags.
    """

    #: prefix of the loop's debug lines
    label: ClassVar[str]
    fc: FrictionalContact
    lamN: np.ndarray
    lamT: np.ndarray
    uTn: np.ndarray
    eps_n: float
    mu: float
    opts: ContactOptions
    tfree: np.ndarray | None

    @property
    def c(self) -> int:
        """The number of candidates."""

    @property
    def d(self) -> int:
        """The columns ``1 + k`` of the tractions ``t`` (``aux[1]``)."""

    @property
    def second_order(self) -> bool:
        """Whether the loop takes the second-order multiplier update (:func:`_second_order_update`,
        :func:`_tangent_predictor`, :func:`_coupled_start`); only a system with the dense
        condensed sensitivity can."""

    @property
    def full_predictor(self) -> bool:
        """Whether the family-P predictor of a first-order step is a full outer iteration of
        Algorithm 6.2: both multipliers are taken from it (else only :math:`\\lambda_N`) and it
        is counted as an outer iteration (else not; see :func:`_step_al`)."""

    @property
    def start(self) -> np.ndarray:
        """The first iterate ``z`` of the step."""

    def subproblem(self, law, lamN, lamT, z, coupled: bool = False) -> NewtonResult:
        """Subproblem (6.2a) from ``z`` for fixed multipliers; ``state.aux = (y, t, Dy, state)``."""

    def iterate(self, out: NewtonResult) -> np.ndarray:
        """The unknowns ``z`` of a subproblem's result."""

    def inside_domain(self, law, lamN, z) -> np.ndarray:
        """A start ``z`` with every gap inside the domain of a barrier-type penalty."""

    def forces(self, z, t) -> np.ndarray:
        """The local contact forces ``R`` ``(c, d)`` of the iterate ``z`` with tractions ``t``."""


@dataclass
class _Ctx:
    """Everything one step needs about the candidates and the previous state."""

    fc: FrictionalContact
    yf: np.ndarray  # (c, d)
    w: np.ndarray  # (c,)
    A4: np.ndarray  # (c, d, c, d)
    lamN: np.ndarray
    lamT: np.ndarray
    uTn: np.ndarray
    R0: np.ndarray
    eps_n: float
    eps_t: float
    mu: float
    opts: FrictionOptions
    tfree: np.ndarray | None = None  # (c, d-1) tangent directions not held by a support

    label: ClassVar[str] = "friction AL"
    #: the family-P predictor of a first-order step gives lambda_N only and is not counted (_step_al)
    full_predictor: ClassVar[bool] = False

    @property
    def c(self):
        return self.yf.shape[0]

    @property
    def d(self):
        return self.yf.shape[1]

    def y(self, R):
        return self.yf - (self.fc.A @ R.ravel()).reshape(self.yf.shape)

    def shifted(self, y, t, Dy):
        r"""Law shifted by the contact springs of a body held by the obstacle (exact rewriting,
        :meth:`FrictionalContact._stabilize`): :math:`t - \kappa(y - y^0)` and its tangent
        (``t``, ``Dy`` unchanged without springs)."""
        if self.fc.spring is None:
            return t, Dy
        return t - self.fc.spring_traction(y), Dy - self.fc.spring_tangent()

    # the _ALSystem of the condensed forces R
    @property
    def second_order(self) -> bool:
        """The option ``multiplier_update``: ``"newton"`` takes the second-order update."""
        return self.opts.multiplier_update == "newton"

    @property
    def start(self):
        return self.R0.copy()

    def subproblem(self, law, lamN, lamT, R, coupled: bool = False) -> NewtonResult:
        return _al_subproblem(self, law, lamN, lamT, R, coupled)

    def iterate(self, out):
        return out.x.reshape(self.c, self.d)

    def inside_domain(self, law, lamN, R):
        return _inside_domain(self, law, lamN, R)

    def forces(self, R, t):
        return R


def _fixed_radius(ctx: _Ctx, coupled: bool) -> bool:
    """Whether a subproblem uses the fixed Coulomb radius :math:`\\mu\\lambda_N` of (6.2c).

    ``coupled=True`` asks for the coupled radius :math:`\\mu t_N(g)` whatever
    ``radius`` says (the first subproblem of a step, :func:`_step_al`).
    """
    return ctx.opts.radius == "multiplier" and not coupled


def _al_subproblem(ctx: _Ctx, law, lamN, lamT, R0, coupled: bool = False) -> NewtonResult:
    """Subproblem (6.2a): ``R = w t(y_free - A R)`` for fixed multipliers.

    ``radius="multiplier"``: the Coulomb disc has the fixed radius
    :math:`\\mu\\lambda_N` (as in (6.2c)); the subproblem is then the stationarity of
    the convex potential :math:`\\tfrac12 R^TAR + \\sum_i w_i(\\psi_N(g_i) + \\phi_T(u_{T,i}))`
    (symmetric tangent, Armijo on the potential: globally convergent). ``"traction"``
    (or ``coupled=True``): radius :math:`\\mu t_N(g)`, coupled and non-symmetric,
    residual backtracking.
    """
    c, d, w = ctx.c, ctx.d, ctx.w
    n = c * d
    rho = ctx.mu * np.maximum(lamN, 0.0) if _fixed_radius(ctx, coupled) else None

    def fun(x):
        R = x.reshape(c, d)
        y = ctx.y(R)
        t, Dy, _, st = local_law(law, lamN, lamT, y, ctx.uTn, ctx.eps_t, ctx.mu, rho=rho, tfree=ctx.tfree)
        ts, Dys = ctx.shifted(y, t, Dy)
        return (R - w[:, None] * ts).ravel(), (y, t, Dys, st)

    energy = grad = None
    # held by the obstacle: the spring-shifted potential cancels large terms along the rigid motions
    # (round-off defeats Armijo there); backtrack on the residual instead
    if rho is not None and ctx.fc.spring is None:
        def energy(x):
            y = ctx.y(x.reshape(c, d))
            e = law.energy(y[:, 0], lamN) + tangential_energy(lamT, y[:, 1:], ctx.uTn, ctx.eps_t, rho, ctx.tfree)
            e = e - ctx.fc.spring_energy(y)
            return 0.5 * float(x @ (ctx.fc.A @ x)) + float(np.sum(w * e))

        def grad(x, F):
            return ctx.fc.A @ F

    def jac(x, aux):
        Dy = aux[2]
        J = np.einsum("ikm,imjl->ikjl", w[:, None, None] * Dy, ctx.A4).reshape(n, n)
        J[np.diag_indices(n)] += 1.0
        return J

    def scale(x, aux):
        # held by the obstacle: x holds the spring forces kappa w (y - y0) of the rigid motion, which are no
        # measure of the physical forces w t (a far-away iterate would pass relative to itself)
        xs = 0.0 if ctx.fc.spring is not None else float(np.max(np.abs(x), initial=0.0))
        return max(xs, float(np.max(np.abs(w[:, None] * aux[1]), initial=0.0)))

    return _newton(fun, jac, R0.ravel(), scale, tol=ctx.opts.newton_tol, maxiter=ctx.opts.maxiter_newton,
                   energy=energy, grad=grad)


def _measures(ctx: _ALSystem, t, y, st, lamN_old, lamT_old):
    """Relative penetration, complementarity, multiplier change and stick slip of an outer iterate."""
    h = ctx.fc.h
    tN, tT = t[:, 0], t[:, 1:]
    pref = max(float(np.max(tN, initial=0.0)), 1e-300)
    pen = float(np.max(y[:, 0], initial=0.0)) / h
    compl = float(np.max(np.abs(tN * np.minimum(y[:, 0], 0.0)), initial=0.0)) / (pref * h)
    dlam = max(float(np.max(np.abs(tN - lamN_old), initial=0.0)),
               float(np.max(np.abs(tT - lamT_old), initial=0.0))) / pref
    duT = y[:, 1:] - ctx.uTn
    dslip = np.linalg.norm(duT if ctx.tfree is None else np.where(ctx.tfree, duT, 0.0), axis=1)
    stick_slip = float(np.max(dslip[st == STICK], initial=0.0)) / h
    return pen, compl, dlam, stick_slip


def _inside_domain(ctx: _Ctx, law, lamN, R):
    """Start for barrier-type penalties (log): push harder until every gap is inside ``g < eta b``.

    The predictor leaves the contact points penetrating by about ``lambda/eps_N``,
    which is the domain bound of the modified log barriers; scaling the normal
    contact forces up closes those penetrations (as in the frictionless solver).
    """
    bound = law.gap_bound(lamN)
    scale = 0.5
    while np.any(ctx.y(R)[:, 0] >= 0.99 * bound) and np.any(R[:, 0]) and scale < 1e6:
        trial = R.copy()
        trial[:, 0] *= 1.0 + scale
        if not np.any(ctx.y(trial)[:, 0] >= 0.99 * bound):
            return trial
        scale *= 2
    return R


class _WithDlam:
    """A normal law plus :math:`\\partial t_N/\\partial\\lambda_N` by central differences.

    The laws of :mod:`alcontact.contact._laws` give :math:`t_N` and
    :math:`\\partial t_N/\\partial g` only; the second-order multiplier update needs the
    multiplier derivative too (an approximation only changes its convergence rate,
    never the fixed point it converges to).
    """

    def __init__(self, law, pref: float):
        self.law = law
        self.pref = pref

    def traction(self, g, lam):
        return self.law.traction(g, lam)

    def stiffness(self, g, lam):
        return self.law.stiffness(g, lam)

    def dlam(self, g, lam):
        lam = np.asarray(lam, dtype=float)
        h = 1e-6 * np.maximum(np.abs(lam), 1e-3 * self.pref)
        lo = np.where(lam > 0, np.maximum(lam - h, 0.5 * lam), lam - h)
        hi = lam + h
        with np.errstate(all="ignore"):
            d = (np.asarray(self.law.traction(g, hi), dtype=float)
                 - np.asarray(self.law.traction(g, lo), dtype=float)) / (hi - lo)
        return np.where(np.isfinite(d), d, 0.0)


def _sensitivity(ctx: _Ctx, law, lamN, lamT, y, t, coupled: bool = False):
    r"""Derivatives of the multiplier map :math:`\lambda \mapsto t(\lambda)` of the subproblem (6.2a).

    At the subproblem solution :math:`R(\lambda, y_f)`,
    :math:`F = R - W t(\lambda, y_f - A R) = 0`, so
    :math:`J_R\, dR = W (D_\lambda t\, d\lambda + D_y t\, dy_f)` with the subproblem matrix
    :math:`J_R = I + W D_y t\, A`, and
    :math:`dt = D_\lambda t\, d\lambda + D_y t\,(dy_f - A\, dR)` (the radius
    :math:`\mu\lambda_N` of (6.2c) is differentiated too).

    Returns
    -------
    (M, T_y) or None
        :math:`M = I - \partial t/\partial\lambda` and :math:`T_y = \partial t/\partial y_f`
        (``(c d, c d)`` each); ``None`` when :math:`J_R` is singular.
    """
    c, d, w = ctx.c, ctx.d, ctx.w
    n = c * d
    pref = max(float(np.max(t[:, 0], initial=0.0)), 1e-300)
    fixed = _fixed_radius(ctx, coupled)
    rho = ctx.mu * np.maximum(lamN, 0.0) if fixed else None
    drho = ctx.mu * (lamN > 0) if fixed else None
    _, Dy, Dl, _ = local_law(_WithDlam(law, pref), lamN, lamT, y, ctx.uTn, ctx.eps_t, ctx.mu, with_lam=True,
                             rho=rho, drho=drho, tfree=ctx.tfree)
    W = w.repeat(d)[:, None]
    Dys = ctx.shifted(y, t, Dy)[1]  # the subproblem is solved for the spring-shifted law
    JR = W * np.einsum("ikm,imjl->ikjl", Dys, ctx.A4).reshape(n, n)
    JR[np.diag_indices(n)] += 1.0
    Dlf, Dyf = block_diag(Dl), block_diag(Dy)
    try:
        dR = _solve(JR, W * np.hstack([Dlf, block_diag(Dys)]))
    except (sla.LinAlgError, ValueError):
        return None
    DyAdR = _dy_times(Dy, ctx.fc.A @ dR, c, d)
    M = np.eye(n) - Dlf + DyAdR[:, :n]
    return M, Dyf - DyAdR[:, n:]


def _admissible(ctx: _Ctx, lam):
    r"""Multipliers ``(c, d)`` made admissible: :math:`\lambda_N \ge 0`, :math:`|\lambda_T| \le \mu\lambda_N`."""
    newN = np.maximum(lam[:, 0], 0.0)
    newT = lam[:, 1:]
    if ctx.tfree is not None:
        newT = np.where(ctx.tfree, newT, 0.0)
    nT = np.linalg.norm(newT, axis=1)
    radius = ctx.mu * newN
    over = nT > radius
    newT = np.where(over[:, None], newT * (radius / np.where(over, nT, 1.0))[:, None], newT)
    return newN, newT


def _second_order_update(ctx: _Ctx, law, lamN, lamT, y, t, coupled: bool = False):
    r"""Newton step on the multiplier fixed point :math:`G(\lambda) = \lambda - t(\lambda) = 0`.

    Solves :math:`(I - dt/d\lambda)\,\Delta = t - \lambda` with the derivatives of
    :func:`_sensitivity` (the second-order multiplier iteration of Bertsekas); the
    new multipliers are made admissible (:func:`_admissible`).

    Returns
    -------
    (lamN, lamT) or None
        ``None`` when a Newton matrix is singular or the step is not finite.
    """
    sens = _sensitivity(ctx, law, lamN, lamT, y, t, coupled)
    if sens is None:
        return None
    lam = np.concatenate([lamN[:, None], lamT], axis=1)
    try:
        step = _solve(sens[0], (t - lam).ravel()).reshape(lam.shape)
    except (sla.LinAlgError, ValueError):
        return None
    new = lam + step
    return _admissible(ctx, new) if np.all(np.isfinite(new)) else None


def _tangent_predictor(ctx: _Ctx, law, lamN, lamT, y, t):
    r"""Sensitivity :math:`d\lambda^*/dy_f = (I - \partial t/\partial\lambda)^{-1}\,\partial t/\partial y_f`
    of the converged multipliers to the free kinematics (implicit function theorem at
    the fixed point): the next load step starts from
    :math:`\lambda_n + (d\lambda^*/dy_f)\,\Delta y_f` (``None`` when singular).
    """
    sens = _sensitivity(ctx, law, lamN, lamT, y, t)
    if sens is None:
        return None
    try:
        P = _solve(sens[0], sens[1])
    except (sla.LinAlgError, ValueError):
        return None
    return P if np.all(np.isfinite(P)) else None


def _dy_times(Dy, B, c, d):
    """Block-diagonal ``Dy`` (c, d, d) times a dense ``(c d, m)`` matrix ``B``."""
    return np.einsum("ikm,imj->ikj", Dy, B.reshape(c, d, -1)).reshape(c * d, -1)


def _coupled_start(ctx: _ALSystem) -> bool:
    r"""Whether the first subproblem of a step takes the coupled Coulomb radius (hybrid radius).

    With the fixed radius :math:`\mu\lambda_N` of (6.2c) a point that enters contact
    in the step starts with :math:`\lambda_N = 0`, a Coulomb disc of radius 0: it slips
    freely in the first subproblem, and the second-order update cannot foresee that it
    sticks (the radius has no sensitivity to a multiplier at 0). The first subproblem
    therefore takes the radius :math:`\mu t_N(g)` of the current iterate (and the
    second-order update its exact sensitivity); every later one the fixed radius (the
    convex subproblem). The fixed point and the stopping test are those of (6.2c).
    Only with ``radius="multiplier"``, the second-order update (``ctx.second_order``), and
    a body held by its supports (a body held by the obstacle starts sticking, :func:`_advance`).
    """
    return ctx.opts.radius == "multiplier" and ctx.second_order and ctx.fc.spring is None and ctx.mu > 0


def _first_subproblem(ctx: _ALSystem, law, lamN, lamT, z, coupled: bool):
    """The first subproblem of a step: coupled radius when ``coupled``, the fixed radius when that fails.

    Returns the Newton result and whether it used the coupled radius.
    """
    if coupled:
        out = ctx.subproblem(law, lamN, lamT, z, coupled=True)
        if out.converged and np.all(np.isfinite(out.state.aux[1])):
            return out, True
        logger.debug("%s: first subproblem with the coupled radius failed (%s); fixed radius", ctx.label,
                     out.message)
    return ctx.subproblem(law, lamN, lamT, z), False


def _step_al(ctx: _ALSystem, penalty_name: str) -> _StepOut:
    """Algorithms 6.2 (``rockafellar``) / 6.4 (family-P) for one load step of either path.

    ``ctx`` is the step's system (:class:`_ALSystem`: the condensed forces of the direct
    path, :class:`_Ctx`, the free displacements of the AMG path,
    :class:`~alcontact.contact._friction_iterative._FullCtx`, or those of a finite-deformation
    step, :class:`~alcontact.contact._finite_friction._FiniteALCtx`); the loop, the multiplier
    updates and the stopping test are the same on all three. The outer update is
    (6.2b)/(6.2c) (``multiplier_update="first-order"``, or a system without the
    second-order update, ``ctx.second_order`` false) or, by default, the second-order
    multiplier iteration :func:`_second_order_update`, which falls back to the
    first-order update for the rest of the step as soon as the multiplier change does
    not decrease by half (or a subproblem fails after a second-order update). The
    stopping test is the same for both. The result's ``z`` is the last iterate, its
    ``last_state`` the state of the last subproblem.

    Family-P (Algorithm 6.4) starts with a predictor, one Simo-Laursen subproblem at the
    step's multipliers. With the second-order update it is a full outer iteration (counted);
    with first-order updates it gives :math:`\\lambda_N` for the points entering contact and
    is not counted, unless the system declares ``full_predictor``: then it is the first
    outer iteration (6.2b)/(6.2c) of Algorithm 6.2 (both multipliers taken, counted).
    A barrier-type penalty then moves the iterate inside its domain (``ctx.inside_domain``).
    """
    opts = ctx.opts
    lamN, lamT = ctx.lamN.copy(), ctx.lamT.copy()
    z = ctx.start
    newton = 0
    macaulay = make_law(_pen.make("rockafellar"), np.full(ctx.c, 1.0 / ctx.eps_n))
    pen = _pen.make(penalty_name)
    family_p = freezes_at_zero(pen)  # MET 1/2: positive multipliers, predictor, scaled eta
    second_order = ctx.second_order
    outer0 = 0
    coupled = _coupled_start(ctx)
    if family_p:
        # predictor: one Simo-Laursen subproblem gives multipliers for points entering contact
        # (with the second-order update it is a full Simo-Laursen outer iteration, counted as one)
        # (ctx.full_predictor: a first-order outer iteration, both multipliers, counted whether it converges or not)
        out, coupled = _first_subproblem(ctx, macaulay, lamN, lamT, z, coupled)
        newton += out.iterations
        outer0 = 1 if ctx.full_predictor else 0
        if out.converged:
            z = ctx.iterate(out)
            upd = (_second_order_update(ctx, macaulay, lamN, lamT, out.state.aux[0], out.state.aux[1], coupled)
                   if second_order else None)
            if upd is not None:
                lamN, lamT = upd
                outer0 = 1
            elif ctx.full_predictor:
                lamN, lamT = out.state.aux[1][:, 0].copy(), out.state.aux[1][:, 1:].copy()
            else:
                lamN = out.state.aux[1][:, 0].copy()
        pref = max(float(np.max(lamN, initial=0.0)), ctx.eps_n * ctx.fc.h * 1e-6)
        floor = opts.multiplier_floor * pref
        lamN = np.maximum(lamN, floor)
        eta = eta_for_stiffness(pen, np.maximum(lamN, opts.eta_floor * pref), ctx.eps_n)
        law = make_law(pen, eta)
        z = ctx.inside_domain(law, lamN, z)
    else:
        law = macaulay
    fallback = None  # first-order multipliers (and z) of the last second-order update
    dlam_prev = np.inf
    coupled = coupled and not family_p  # the hybrid radius serves the first subproblem only
    t = np.zeros((ctx.c, ctx.d))
    for k in range(1, opts.maxiter + 1):
        if coupled:
            out, coupled = _first_subproblem(ctx, law, lamN, lamT, z, coupled)
        else:
            out = ctx.subproblem(law, lamN, lamT, z)
        newton += out.iterations
        if not out.converged and fallback is not None:
            logger.debug("%s outer %d: subproblem failed after a second-order update (%s); first-order "
                         "update from here", ctx.label, k, out.message)
            lamN, lamT, z = fallback
            second_order, fallback = False, None
            continue
        if not out.converged:
            # no state when the start is outside the body's domain (finite deformation: an inverted element)
            t = out.state.aux[1] if out.state is not None else np.zeros((ctx.c, ctx.d))
            return _StepOut(False, f"Newton failed in outer iteration {k}: {out.message}", ctx.forces(z, t), t,
                            k + outer0, newton, inner_failure(out), z=z, last_state=out.state)
        z = ctx.iterate(out)
        y, t, _, st = out.state.aux
        if not np.all(np.isfinite(t)):
            return _StepOut(False, f"non-finite tractions in outer iteration {k}", ctx.forces(z, t), t, k + outer0,
                            newton, ContactStatus.NONFINITE, z=z, last_state=out.state)
        pen_k, compl, dlam, stick_slip = _measures(ctx, t, y, st, lamN, lamT)
        logger.debug("%s outer %d: pen=%.2e compl=%.2e dlam=%.2e stick-slip=%.2e newton=%d%s", ctx.label,
                     k, pen_k, compl, dlam, stick_slip, out.iterations, " (second-order)" if fallback else "")
        if (pen_k <= opts.tol_penetration and compl <= opts.tol_complementarity and dlam <= opts.tol_multiplier
                and stick_slip <= opts.tol_slip):
            pred = _tangent_predictor(ctx, law, lamN, lamT, y, t) if ctx.second_order else None
            return _StepOut(True, "converged", ctx.forces(z, t), t, k + outer0, newton, predictor=pred, z=z,
                            last_state=out.state)
        if fallback is not None and not dlam <= 0.5 * dlam_prev:
            logger.debug("%s outer %d: second-order update did not halve the multiplier change; "
                         "first-order update from here", ctx.label, k)
            second_order = False
        dlam_prev = dlam
        # multiplier updates (6.2b)/(6.2c), resp. lambda_N <- p'(g/eta, lambda_N)
        upd = _second_order_update(ctx, law, lamN, lamT, y, t, coupled) if second_order else None
        coupled = False
        fallback = (t[:, 0].copy(), t[:, 1:].copy(), z.copy()) if upd is not None else None
        lamN, lamT = upd if upd is not None else (t[:, 0].copy(), t[:, 1:].copy())
        if family_p:
            pref = max(float(np.max(lamN, initial=0.0)), 1e-300)
            lamN = np.maximum(lamN, opts.multiplier_floor * pref)
            if opts.eta_scaling == "adaptive":
                eta_new = eta_for_stiffness(pen, np.maximum(lamN, opts.eta_floor * pref), ctx.eps_n)
                bnd = eta_new * np.asarray(pen.domain_upper(lamN), dtype=float)
                eta = np.where(y[:, 0] < 0.99 * bnd, eta_new, eta)
                law = make_law(pen, eta)
            if upd is not None:
                z = ctx.inside_domain(law, lamN, z)
    return _StepOut(False, f"maximum outer iterations ({opts.maxiter}) reached", ctx.forces(z, t), t,
                    opts.maxiter + outer0, newton, ContactStatus.MAXITER, z=z, last_state=out.state)


def _step_ssn(ctx: _Ctx, penalty_name: str = "none") -> _StepOut:
    """Alart-Curnier semi-smooth Newton for one load step (reference, no penalty)."""
    c, d, w = ctx.c, ctx.d, ctx.w
    n = c * d
    law = Macaulay(ctx.eps_n)

    # unknowns: the condensed forces R = w (L - kappa (y - y0)) (R = w L without contact springs), so that
    # y = y_free - A R is explicit and L = R / w + kappa (y - y0)
    S = block_diag(ctx.fc.spring_tangent())
    A = ctx.fc.A

    def fun(x):
        R = x.reshape(c, d)
        y = ctx.y(R)
        L = R / w[:, None] + ctx.fc.spring_traction(y)
        t, Dy, Dl, st = local_law(law, L[:, 0], L[:, 1:], y, ctx.uTn, ctx.eps_t, ctx.mu, with_lam=True,
                                   tfree=ctx.tfree)
        return (L - t).ravel(), (y, t, Dy, st, Dl, L)

    def jac(x, aux):
        # dF/dR = (I - Dl) dL/dR + Dy A,  dL/dR = W^-1 - S A
        Dy, Dl = aux[2], aux[4]
        dL = np.diag(1.0 / w.repeat(d)) - S @ A
        return (np.eye(n) - block_diag(Dl)) @ dL + _dy_times(Dy, A, c, d)

    def scale(x, aux):
        return max(float(np.max(np.abs(aux[5]), initial=0.0)), float(np.max(np.abs(aux[1]), initial=0.0)))

    out = _newton(fun, jac, ctx.R0.ravel(), scale, tol=ctx.opts.newton_tol,
                  maxiter=max(ctx.opts.maxiter_newton, 100))
    R = out.x.reshape(c, d)
    if not out.converged:
        return _StepOut(False, f"semi-smooth Newton failed: {out.message}", R, out.state.aux[1], 1,
                        out.iterations, inner_failure(out))
    return _StepOut(True, "converged", R, out.state.aux[5].copy(), 1, out.iterations)


register_family((
    ("simo-laursen", _step_al, "rockafellar",
     "Algorithm 6.2: AL with the Macaulay normal law (6.52) and return mapping (6.47)-(6.50)"),
    ("family-p", _step_al, None, "Algorithm 6.4: Algorithm 6.2 with a family-P normal penalty"),
    ("ssn", _step_ssn, "none",
     "reference: Alart-Curnier semi-smooth Newton on (lambda_N, lambda_T), exact (no penalty)"),
), friction=True, kinematics="small", linear_solvers=("direct", "amg"), defaults=FRICTION_DEFAULTS)
#: Family-P penalty of the frictional algorithms when none is given.
DEFAULT_FRICTION_PENALTY = DEFAULT_PENALTY


def friction_algorithms() -> list[str]:
    """Names of the frictional algorithms (small deformation)."""
    return algorithm_names(friction=True, kinematics="small")


def friction_algorithm_docs() -> dict[str, str]:
    """One line of documentation per frictional algorithm (small deformation)."""
    return algorithm_docs(friction=True)


def _checked_steps(steps):
    """``steps`` of :func:`solve_friction`: a count in [1, MAX_STEPS] or increasing positive times."""
    if is_integer(steps):
        if not 1 <= steps <= MAX_STEPS:
            raise InputError(f"steps = {show(steps)}: out of range, must be in [1, {MAX_STEPS}] (or a sequence of "
                             "step times).")
        return int(steps)
    ok = isinstance(steps, (list, tuple, np.ndarray)) and 0 < len(steps) <= MAX_STEPS and all(
        is_real(t) and np.isfinite(t) and t > 0 for t in steps)
    if not ok or any(b <= a for a, b in zip(steps, steps[1:])):
        raise InputError(f"steps = {show(steps)}: expected a number of steps or positive, strictly increasing step "
                         "times, e.g. steps=[0.25, 0.5, 1.0].")
    return tuple(float(t) for t in steps)


def _resolve(algorithm: str, penalty: str | None):
    """Step function and penalty of the frictional ``algorithm`` (registry entry)."""
    entry = find_algorithm(algorithm, friction=True)
    return entry.run, entry.penalty_for(penalty)


# ---------------------------------------------------------------------------
# load stepping
# ---------------------------------------------------------------------------
@dataclass
class _State:
    """Converged state over all m contact-boundary points."""

    t: float
    u: np.ndarray
    y: np.ndarray  # (m, d) gap and u_T
    tN: np.ndarray  # (m,)
    tT: np.ndarray  # (m, d-1)
    R: np.ndarray  # (m, d)
    slip_total: np.ndarray  # (m, d)
    predictor: tuple | None = None  # (candidates, d lambda*/d y_free) of the last step, for the next start


def _closed(fc, tN, g, opts):
    return (tN > 0) & (g >= -max(1e-6, 10 * opts.tol_penetration) * fc.h)


class _StepPath(ABC):
    """How a solution path sets up one load step; the step itself (:meth:`advance`) is shared.

    A path gives the system of a step (:meth:`context`, an :class:`_ALSystem` for the AL
    algorithms), the step without candidates (:meth:`without_candidates`) and the
    displacement of a solved step (:meth:`displacement`); :meth:`advance` adds the
    candidates that penetrate, assembles the state over all points and accepts a step of a
    body held by the obstacle only in equilibrium.
    """

    @abstractmethod
    def context(self, fc, prev: _State, t: float, last: _StepOut | None, step_fn, eps_n, eps_t, mu, opts):
        """The step's system on the candidates ``fc.cand`` and the Newton iterations spent to set it up.

        ``last`` is the previous attempt of the same step (before candidates were added), or ``None``.
        """

    @abstractmethod
    def without_candidates(self, fc, t: float) -> tuple[_StepOut, np.ndarray]:
        """The step without contact candidates and its displacement."""

    @abstractmethod
    def displacement(self, fc, t: float, out: _StepOut) -> np.ndarray:
        """The displacement of the solved step ``out``."""

    def advance(self, fc, prev: _State, t: float, step_fn, pen_name, eps_n, eps_t, mu, opts):
        """Solve one step from ``prev`` to time ``t`` (adding candidates that penetrate).

        Returns ``(result, out, outer, newton)`` with ``result = (u, y_all, tN, tT, R, predictor)``
        over all points (``None`` when the step failed; ``out`` says why).
        """
        outer = newton = 0
        last = None
        for _attempt in range(8):
            cand = fc.cand
            d = fc.dim
            if cand.size == 0:
                out, u = self.without_candidates(fc, t)
            else:
                ctx, pre = self.context(fc, prev, t, last, step_fn, eps_n, eps_t, mu, opts)
                newton += pre
                out = step_fn(ctx, pen_name)
                outer += out.outer
                newton += out.newton
                if not out.ok:
                    return None, out, outer, newton
                u = self.displacement(fc, t, out)
            y_all = fc.all_local(u)
            outside = np.ones(fc.points.shape[0], bool)
            outside[cand] = False
            add = fc.add(np.flatnonzero(outside & (y_all[:, 0] > opts.tol_penetration * fc.h)))
            if add.size:
                logger.info("t=%g: adding %d contact candidates that penetrate", t, add.size)
                last = out
                continue
            m = fc.points.shape[0]
            tN = np.zeros(m)
            tT = np.zeros((m, d - 1))
            R = np.zeros((m, d))
            tN[cand], tT[cand], R[cand] = out.t[:, 0], out.t[:, 1:], out.R
            if fc.spring is not None:  # held by the obstacle: accept only a step in equilibrium
                R_phys = np.zeros((m, d))
                R_phys[cand] = fc.weights[cand, None] * out.t
                defect = fc.equilibrium_defect(t, u, R_phys)
                if not defect <= _EQUILIBRIUM_TOL:
                    return None, _StepOut(False, f"no equilibrium found (relative residual {defect:.2e}): the "
                                                 "obstacle and friction do not hold the body there", prev.R, prev.R,
                                          outer, newton, ContactStatus.NEWTON_FAILED), outer, newton
            pred = (cand.copy(), out.predictor) if out.predictor is not None else None
            return (u, y_all, tN, tT, R, pred), out, outer, newton
        return None, _StepOut(False, "candidate set did not settle", prev.R, prev.R, 0, 0, ContactStatus.MAXITER), \
            outer, newton


class _CondensedPath(_StepPath):
    """The direct path: steps on the condensed forces of :class:`FrictionalContact` (:class:`_Ctx`).

    A body held by the obstacle starts each step sticking (:meth:`FrictionalContact.frozen_start`),
    at first contact from the semi-smooth Newton solution; the multipliers start from the tangent
    predictor of the last step where it has the same candidates.
    """

    def context(self, fc, prev, t, last, step_fn, eps_n, eps_t, mu, opts):
        cand = fc.cand
        c, d = cand.size, fc.dim
        newton = 0
        ctx = _Ctx(fc, fc.y_free(t)[cand], fc.weights[cand], fc.A.reshape(c, d, c, d), prev.tN[cand].copy(),
                   prev.tT[cand].copy(), prev.y[cand, 1:].copy(), prev.R[cand].copy(), eps_n, eps_t, mu, opts,
                   fc.tfree[cand])
        if fc.spring is not None:  # held by the obstacle only
            closed = prev.tN[cand] > 0
            if np.any(closed):  # start sticking (FrictionalContact.frozen_start)
                R0 = fc.frozen_start(prev.t, t, ctx.R0, closed)
                ctx.R0 = ctx.R0 if R0 is None else R0
            elif step_fn is not _step_ssn:
                # first contact: with zero multipliers the Coulomb discs of the AL subproblem have radius 0
                # and nothing holds the tangential rigid motion; start from the semi-smooth Newton solution
                # of the same discrete problem (a predictor: the AL stopping test decides)
                pre = _step_ssn(ctx)
                newton += pre.newton
                if pre.ok:
                    ctx.R0, ctx.lamN, ctx.lamT = pre.R, pre.t[:, 0].copy(), pre.t[:, 1:].copy()
        if prev.predictor is not None and np.array_equal(prev.predictor[0], cand):
            # tangent predictor: lambda_n + (d lambda*/d y_free) (y_free(t) - y_free(t_n))
            dyf = (ctx.yf - fc.y_free(prev.t)[cand]).ravel()
            lam0 = np.concatenate([ctx.lamN[:, None], ctx.lamT], axis=1) + (prev.predictor[1] @ dyf).reshape(c, d)
            if np.all(np.isfinite(lam0)):
                ctx.lamN, ctx.lamT = _admissible(ctx, lam0)
        return ctx, newton

    def without_candidates(self, fc, t):
        d = fc.dim
        return _StepOut(True, "no candidate points", np.zeros((0, d)), np.zeros((0, d)), 0, 0), fc.u_free(t)

    def displacement(self, fc, t, out):
        return fc.displacement(t, out.R)


#: The direct path's step (:meth:`_StepPath.advance` of :class:`_CondensedPath`).
_advance = _CondensedPath().advance


def solve_friction(problem, history: LoadHistory | None, algorithm: str = "simo-laursen", penalty: str | None = None,
                   options: FrictionOptions | None = None, *, steps=None, friction: float | None = None,
                   on_step=None, obstacle_path=None, **option_overrides) -> FrictionSolution:
    r"""Quasi-static frictional contact over a load history.

    Parameters
    ----------
    problem : ContactProblem
        Body, obstacle, contact boundary; its own supports and loads act at full
        value at every step; ``problem.friction`` is the Coulomb coefficient :math:`\mu`.
    history : LoadHistory
        Scaled supports/loads and the step times.
    algorithm : {"simo-laursen", "family-p", "ssn"}
        Algorithm 6.2, Algorithm 6.4, or the semi-smooth Newton reference.
    penalty : str, optional
        Family-P penalty of ``"family-p"`` (default ``"exp-met1"``).
    options : FrictionOptions or dict, optional
        Options; a dict holds :class:`FrictionOptions` fields.
    steps : int or sequence of float, optional
        Overrides ``history.times`` (an int: that many equal steps).
    friction : float, optional
        Overrides ``problem.friction``.
    on_step : callable, optional
        ``on_step(k, t, n)`` is called before requested step ``k`` (0-based) of ``n``,
        at pseudo-time ``t`` (for progress bars).
    obstacle_path : callable ``t -> (d,)``, optional
        Finite kinematics only: translation of the obstacle at pseudo-time ``t``.
    **option_overrides
        Fields of :class:`FrictionOptions`.

    Returns
    -------
    FrictionSolution or FiniteFrictionSolution
        A problem with ``kinematics="finite"`` is solved by
        :func:`~alcontact.contact.solve_finite_friction` (Algorithms 6.2 / 6.4 in the
        current configuration) over ``steps`` (default: the history's times, or 10
        uniform steps without a history, every support and load then scaled by the
        pseudo-time); both solutions share the per-step views
        (:class:`~alcontact.contact._stepping.StepRecords`: ``times``, ``forces``,
        ``frames``, ...).

        Small kinematics: per-step states; ``status`` negative (and a logged warning) when a step
        failed after ``max_cutbacks`` cut-backs, or ``NOT_VERIFIED`` when a recorded
        step fails the penetration, complementarity or Coulomb check of
        :mod:`alcontact.contact._verify`. ``UNBOUNDED`` when a body held only by
        the obstacle has no static equilibrium at a step (the free tangential load
        exceeds :math:`\mu N`, or the loads pull it off a flat obstacle,
        :meth:`FrictionalContact.slides_away`); the steps before it are kept.

    Raises
    ------
    InputError
        Bad options, a negative friction coefficient, a load history not
        defined at some step, or a tangential load case that is non-zero at a
        step that starts without contact.

    Notes
    -----
    Supports may leave rigid motions free when the obstacle holds the body:
    springs on all components of the touching points make the stiffness regular
    and the frictional law is shifted by the same springs, an exact rewriting
    (:meth:`FrictionalContact._stabilize`). Each step of such a body starts from
    sticking (:meth:`FrictionalContact.frozen_start`; at first contact the AL
    algorithms start from the semi-smooth Newton solution, since zero
    multipliers give Coulomb discs of radius 0) and is accepted only in global
    equilibrium (relative residual ``1e-7``).

    Examples
    --------
    >>> from alcontact.problems import friction as fp
    >>> prob, hist = fp.block_on_plane(dim=2, n=4)
    >>> sol = solve_friction(prob, hist)  # doctest: +SKIP
    """
    t_start = time.perf_counter()
    check_solve_args(problem, algorithm, penalty, friction_algorithms(), "friction ")
    step_fn, pen_name = _resolve(algorithm, penalty)
    if getattr(problem, "kinematics", "small") == "finite":
        return _solve_finite(problem, history, algorithm, penalty, options, steps=steps, friction=friction,
                             on_step=on_step, obstacle_path=obstacle_path, **option_overrides)
    opts = options_with(options, FrictionOptions, option_overrides, "friction",
                        find_algorithm(algorithm, friction=True))
    if not isinstance(history, LoadHistory):
        raise InputError(f"history must be a LoadHistory; got {type(history).__name__}.")
    if obstacle_path is not None:
        raise InputError("obstacle_path: a moving obstacle needs kinematics='finite' (ContactProblem(..., "
                         "kinematics='finite') with a hyperelastic body); at small kinematics move the body with "
                         "a ramped support instead.")
    if steps is not None:
        history = history.with_times(_checked_steps(steps))
    mu = problem.friction if friction is None else friction
    if not (is_real(mu) and 0 <= mu <= VALUE_RANGE[1]):  # comparisons, not isfinite: a huge int is no float
        raise InputError(f"friction = {show(mu)}: the friction coefficient must be a finite number >= 0 (at most "
                         f"{VALUE_RANGE[1]:g}). Use 0 for frictionless contact.")
    mu = float(mu)

    solver = select_solver(opts.linear_solver, dim=problem.model.dim, ndofs=problem.model.ndofs)
    path = "direct" if solver.exact else "amg"  # the label of the strategy in solution.extra
    fc, advance = _FRICTION_PATHS[solver.exact](problem, history, opts, solver)
    eps_n = opts.eps_n if opts.eps_n is not None else penalty_stiffness(problem.model, fc.h, opts.penalty_scale)
    eps_t = opts.eps_t if opts.eps_t is not None else opts.tangential_scale * eps_n
    m, d = fc.points.shape
    u0 = fc.u_free(0.0)
    y0 = fc.all_local(u0)
    state = _State(0.0, u0, y0, np.zeros(m), np.zeros((m, d - 1)), np.zeros((m, d)), np.zeros((m, d)))
    tangential = [c for c in history.cases if c.tangential]
    contact_dofs = problem.model.node_dofs(problem.contact_boundary)[1]
    records: list[FrictionStep] = []
    cur = {"state": state}
    t_solve = time.perf_counter()

    def attempt(t: float) -> Attempt:
        prev = cur["state"]
        if tangential and not np.any(_closed(fc, prev.tN, prev.y[:, 0], opts)):
            active = [c.label for c in tangential if c.value(t) != 0.0]
            if active:
                raise InputError(
                    f"tangential load {', '.join(active)} is applied at t={t:g} but no point is in contact at "
                    f"the start of that step (t={prev.t:g}); apply the normal load first (start the tangential "
                    "amplitude at 0 until contact exists).")
        away = fc.slides_away(t, mu * history.friction_factor(t))  # body held by the obstacle only
        if away is not None:
            return Attempt(False, ContactStatus.UNBOUNDED, away, final=True)
        solves0 = fc.linear_solves
        res, out, o, nw = advance(fc, prev, t, step_fn, pen_name, eps_n, eps_t, mu * history.friction_factor(t),
                                   opts)
        counts = dict(newton=nw, outer=o, linear_solves=fc.linear_solves - solves0)
        if res is not None:  # a step is accepted only when its returned state passes every measure (cut back if not)
            check = verify(t, prev, res)
            if not check.ok:
                return Attempt(False, ContactStatus.NOT_VERIFIED, f"{algorithm} reported {out.message!r} but the "
                               f"state fails verification: {check.describe()}", **counts)
        return Attempt(res is not None, out.status, out.message, value=(res, out), **counts)

    def verify(t: float, prev: _State, res):
        """Every measure of the step's returned state (:mod:`alcontact.contact._verify`)."""
        u, y_all, tN, tT = res[:4]
        closed = _closed(fc, tN, y_all[:, 0], opts)
        duT = y_all[:, 1:] - prev.y[:, 1:]
        w = fc.weights
        shear = -np.einsum("ijk,ik->ij", fc.tangents, tT)
        # equilibrium of the step's displacement with the forces it reports (loads and supports at t)
        p_t = problem_at(problem, history, t)
        eq = state_equilibrium(problem.model, u, p_t.dirichlet()[0], p_t.load_vector(), contact_dofs,
                               w[:, None] * (tN[:, None] * fc.normals + shear), fc.h, pressure=tN, weights=w)
        return check_state(y_all[:, 0], tN, fc.h, tol_penetration=opts.tol_penetration,
                           tol_complementarity=opts.tol_complementarity, traction_t=tT,
                           slip=np.where(closed[:, None] & fc.tfree, duT, 0.0), mu=mu * history.friction_factor(t),
                           tol_friction=max(opts.tol_multiplier, opts.tol_slip), equilibrium=eq.largest,
                           tol_equilibrium=equilibrium_tolerance(opts, multipliers=True), reach=reach(fc.points, u))

    def commit(t: float, att: Attempt, rec: StepRecord) -> FrictionStep:
        prev = cur["state"]
        (u, y_all, tN, tT, R, pred), out = att.value
        closed = _closed(fc, tN, y_all[:, 0], opts)
        duT = y_all[:, 1:] - prev.y[:, 1:]
        slip = np.where(closed[:, None], np.einsum("ijk,ik->ij", fc.tangents, duT), 0.0)
        nT = np.linalg.norm(tT, axis=1)
        pref = max(float(np.max(tN, initial=0.0)), 1e-300)
        mu_t = mu * history.friction_factor(t)
        saturated = nT >= mu_t * tN - 1e-6 * max(mu_t, 1e-300) * pref
        st = np.where(~closed, OPEN, np.where(saturated, SLIP, STICK))
        shear = -np.einsum("ijk,ik->ij", fc.tangents, tT)
        w = fc.weights
        tang_force = np.sum(w[:, None] * shear, axis=0)
        normal_force = float(np.sum(w * tN))
        slip_total = prev.slip_total + slip
        step = FrictionStep(
            t=float(t), requested=rec.requested, u=u, pressure=tN, traction_t=tT, shear=shear, slip=slip,
            slip_total=slip_total, gap=y_all[:, 0], state=st, normal_force=normal_force,
            tangential_force=tang_force, contact_force=tang_force + np.sum((w * tN)[:, None] * fc.normals, axis=0),
            outer_iterations=int(out.outer), newton_iterations=int(out.newton), cutbacks=rec.step_cutbacks,
            penetration=float(np.max(y_all[:, 0], initial=0.0)) / fc.h,
            coulomb=float(np.max(np.maximum(nT - mu_t * tN, 0.0), initial=0.0)) / pref, seconds=rec.seconds,
            linear_solves=int(rec.linear_solves),
        )
        records.append(step)
        cur["state"] = _State(float(t), u, y_all, tN, tT, R, slip_total, pred)
        return step

    def advice() -> str:
        tip = "use more load steps, a smaller penalty_scale or algorithm='ssn'"
        if fc.spring is not None:
            tip += ("; the body is held by the obstacle only: if contact and friction cannot balance the loads it "
                    "slides or turns away (no static equilibrium), so prescribe that motion as a displacement or "
                    "add a support")
        return tip

    run = step_through(history.times, attempt, commit, max_cutbacks=opts.max_cutbacks, factor=opts.cutback_factor,
                       before_step=on_step, recoverable=(), what=f"frictional contact {algorithm}", advice=advice,
                       done_message="converged")
    status, message = run.status, run.message
    n_outer, n_newton, n_cut = run.outer_iterations, run.newton_iterations, run.cutbacks
    if fc.ncand == 0 and status > 0:
        i = int(np.argmax(np.where(fc.movable, fc.gmax_t, -np.inf)))
        status = ContactStatus.NO_CONTACT
        message = (f"the body never reaches the obstacle: smallest clearance {-fc.gmax_t[i]:.4g} at point "
                   f"{np.round(fc.points[i], 6).tolist()}; check the loads, the obstacle or the contact boundary")
    if status < 0 and status != run.status:  # a step failure was logged by step_through
        logger.warning("frictional contact %s failed (%s): %s", algorithm, status.label, message)
    t_end = time.perf_counter()
    return FrictionSolution(
        problem=problem, history=history, algorithm=algorithm, penalty=pen_name, friction=mu, points=fc.points,
        normals=fc.normals, tangents=fc.tangents, weights=fc.weights, steps=tuple(records), status=status,
        message=message, outer_iterations=n_outer, newton_iterations=n_newton, cutbacks=n_cut,
        linear_solves=fc.linear_solves, eps_n=float(eps_n), eps_t=float(eps_t), h=fc.h,
        timings={"setup_s": fc.setup_seconds, "factor_s": fc.factor_seconds, "solve_s": t_end - t_solve,
                 "total_s": t_end - t_start},
        extra={"candidates": fc.ncand, "dofs": int(problem.model.ndofs), "linear_solver": path,
               "backend": solver.name, **fc.stats()},
    )


def _solve_finite(problem, history, algorithm, penalty, options, *, steps, friction, on_step, obstacle_path,
                  **option_overrides):
    """:func:`solve_friction` of a ``kinematics="finite"`` problem: :func:`solve_finite_friction`
    (registered by :mod:`._finite_friction`, :func:`register_friction_kinematics`)."""
    solve_finite_friction = _KINEMATICS_SOLVERS["finite"]
    if history is not None and not isinstance(history, LoadHistory):
        raise InputError(f"history must be a LoadHistory or None; got {type(history).__name__}.")
    if history is not None and history.friction is not None:
        raise InputError("history: a friction amplitude (friction_ramp) is not available at finite kinematics; "
                         "remove it (the coefficient is constant) or use kinematics='small'.")
    if steps is None:
        steps = history.times if history is not None else 10
    mu = problem.friction if friction is None else friction
    return solve_finite_friction(problem, mu, algorithm, penalty, options, steps=steps, history=history,
                                 obstacle_path=obstacle_path, progress=on_step, **option_overrides)


def _direct_path(problem, history, opts, solver):
    """The condensed problem (:class:`FrictionalContact`) on the exact factorization of ``solver``, and its step."""
    return FrictionalContact(problem, history, margin=opts.margin, linear_solver=solver.name), _advance


#: :attr:`SolverChoice.exact <alcontact.linalg.SolverChoice>` -> ``(problem, history, opts, solver) ->
#: (contact problem, step)``: the condensed problem needs an exact factorization; the full-space problem whose
#: Krylov solves an approximate solver preconditions is registered by :mod:`._friction_iterative`
_FRICTION_PATHS = {True: _direct_path}
#: :func:`solve_friction` of the kinematics other than ``"small"``, registered by their modules
_KINEMATICS_SOLVERS: dict = {}


def register_friction_strategy(exact: bool, make) -> None:
    """Register how :func:`solve_friction` builds its problem for solvers that factorize exactly (``exact``) or not.

    The modules that build on this one (:mod:`._friction_iterative`) register themselves, so that the
    imports run one way (the package imports them).
    """
    _FRICTION_PATHS[bool(exact)] = make


def register_friction_kinematics(kinematics: str, solver) -> None:
    """Register the frictional solver of ``kinematics`` (``"finite"``: :mod:`._finite_friction`)."""
    _KINEMATICS_SOLVERS[kinematics] = solver
