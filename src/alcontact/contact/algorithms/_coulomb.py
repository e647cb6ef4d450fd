r"""Coulomb friction algorithms (section 6.2): Algorithms 6.2 and 6.4 and the Alart-Curnier reference.

Registered algorithms (entries of the registry of :mod:`alcontact.contact.algorithms._frictionless` with
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
    (scaling :math:`\eta` as in :mod:`alcontact.contact.laws._normal`).
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
variables (see :mod:`alcontact.contact.systems._condensed`) with the consistent
tangent of the return mapping and backtracking on the residual norm (the
frictional problem is non-symmetric: there is no energy to descend).
On the AMG path (:mod:`alcontact.contact.systems._krylov`) the same loop
:func:`_step_al` drives the subproblems in the free displacements instead (the step's
system, :class:`_ALSystem`, is the only difference; that path declares first-order
multiplier updates; the finite-deformation path takes the second-order update of
Algorithm 6.2 with its own sensitivity), and the same load step (:class:`_StepPath`) adds candidates and
checks a held body's equilibrium.

The steps are walked by :func:`~alcontact.contact.stepping._steps.step_through`: a step
that fails is retried from the last converged state with the increment times
``cutback_factor``, down to ``cutback_factor**max_cutbacks`` times the requested
one; the converged steps are kept. A problem with ``kinematics="finite"`` goes to
:func:`~alcontact.contact.solve_finite_friction` (same algorithms in the current
configuration, driven by the same loop :func:`_step_al` through the step's system
:class:`~alcontact.contact.algorithms._coulomb._FiniteALCtx`).
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, Sequence

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ... import penalties as _pen
from ...errors import InvertedElementError
from ..laws._coulomb import OPEN, SLIP, STICK, Macaulay, block_diag, local_law, return_mapping, tangential_energy
from ..laws._normal import eta_for_stiffness, freezes_at_zero, make_law
from ..laws._stiffness import penalty_stiffness
from ..solution._solution import ContactStatus
from ..systems._condensed import FrictionalContact
from ..systems._full_space import _FRICTION_SSN_SETTINGS, FiniteFrictionContact, _Local
from ._frictionless import (DEFAULT_PENALTY, FRICTION_DEFAULTS, ContactOptions, algorithm_docs, algorithm_names,
                            register_family)
from ._frictionless import _inside_domain as _frictionless_start
from ._subproblem import (LineSearch, NewtonResult, NewtonSettings, NewtonSystem, _Point, _PointSystem,
                          inner_failure, newton)


logger = logging.getLogger(__name__)

#: Largest relative equilibrium residual of a step of a body held only by the obstacle.
_EQUILIBRIUM_TOL = 1e-7
#: Right-hand sides per back-substitution of the finite-deformation sensitivity (:meth:`_FiniteALCtx.sensitivity`).
_SENSITIVITY_BLOCK = 512

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


class _CondensedSystem(_PointSystem):
    """``F(x) = 0`` on the condensed forces of a step, for :func:`~._newton.newton`.

    ``fun(x) -> (F, aux)``, ``jac(x, aux) -> J`` (dense, possibly unsymmetric), ``scale(x, aux) > 0``
    the force unit of the relative residual. Globalization: Armijo on ``energy(x)`` (with
    ``grad(x, F)`` its gradient) when the problem has a potential, else a decrease of the
    residual norm (:data:`_POTENTIAL`, :data:`_NO_POTENTIAL`). ``floor(x, aux)``, when given, bounds
    the round-off of ``F`` (in force units): the tolerance is raised to it (:meth:`tolerance`), as the
    AMG path's does (:class:`~alcontact.contact.systems._krylov._FullSpaceFriction`).
    """

    def __init__(self, fun, jac, scale, energy=None, grad=None, floor=None):
        self.fun, self.jac, self.scale, self.energy, self.grad, self.floor = fun, jac, scale, energy, grad, floor
        self.fs = 1e-300

    def tolerance(self, state, tol):
        """``tol``, or the round-off floor of the residual where it is higher (a large contact zone with a stiff
        penalty: :math:`F = R - W t(y_f - A R)` cancels terms of size :math:`\\varepsilon_N |y_f|`)."""
        if self.floor is None:
            return tol
        return max(tol, float(self.floor(state.x, state.aux)) / self.fs)

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


def _newton(fun, jac, x0, scale, *, tol, maxiter, energy=None, grad=None, floor=None) -> NewtonResult:
    """Solve ``F(x) = 0`` by :func:`~._newton.newton` on a :class:`_CondensedSystem`."""
    system = _CondensedSystem(fun, jac, scale, energy, grad, floor)
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
    (:class:`~alcontact.contact.systems._krylov._FullCtx`) or the free displacements at
    finite deformation (:class:`~alcontact.contact.algorithms._coulomb._FiniteALCtx`); the
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
        :func:`_tangent_predictor`, :func:`_coupled_start`); only a system with the sensitivity
        :meth:`sensitivity` can (the condensed path's dense one, the finite-deformation path's
        from one factorization of its Newton matrix; not the AMG path)."""

    @property
    def tangent_predictor(self) -> bool:
        """Whether a converged step computes the tangent predictor :func:`_tangent_predictor` of the next
        one (with :attr:`second_order`; a system whose :meth:`sensitivity` has no ``T_y`` declares false)."""

    @property
    def full_predictor(self) -> bool:
        """Whether the family-P predictor of a first-order step is a full outer iteration of
        Algorithm 6.2: both multipliers are taken from it (else only :math:`\\lambda_N`) and it
        is counted as an outer iteration (else not; see :func:`_step_al`)."""

    @property
    def final_coupled(self) -> bool:
        """Whether the subproblem expected to be the last of a step takes the coupled Coulomb radius
        (:func:`_final_coupled`; finite deformation)."""

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

    def sensitivity(self, law, lamN, lamT, state, coupled: bool = False):
        r"""``(M, T_y, Z)`` at the solution ``state`` of a subproblem: :math:`M = I - \partial t/\partial\lambda`
        ``(c d, c d)`` of the multiplier map :math:`\lambda \mapsto t(\lambda)`, the sensitivity
        :math:`T_y` of the tractions to the free kinematics of the tangent predictor (``None``: no
        predictor) and the derivative :math:`Z = dz/d\lambda` of the subproblem's solution (``None``:
        the next subproblem starts from ``z``), or ``None`` when singular. Asked only of a system
        with :attr:`second_order`."""


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
    mu: float | np.ndarray  # one coefficient, or one per candidate (pairs with their own)
    opts: FrictionOptions
    tfree: np.ndarray | None = None  # (c, d-1) tangent directions not held by a support

    label: ClassVar[str] = "friction AL"
    #: the converged step gives the tangent predictor of the next one (second-order update)
    tangent_predictor: ClassVar[bool] = True
    #: the family-P predictor of a first-order step gives lambda_N only and is not counted (_step_al)
    full_predictor: ClassVar[bool] = False
    #: the last subproblem keeps the fixed radius (_final_coupled: measured at finite deformation only)
    final_coupled: ClassVar[bool] = False

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

    def sensitivity(self, law, lamN, lamT, state, coupled: bool = False):
        """:func:`_sensitivity` at the subproblem's solution ``state`` (its ``aux`` gives ``y`` and ``t``)."""
        sens = _sensitivity(self, law, lamN, lamT, state.aux[0], state.aux[1], coupled)
        return None if sens is None else (*sens, None)

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
                   energy=energy, grad=grad, floor=_roundoff_floor(ctx))


def _roundoff_floor(ctx: _Ctx):
    r"""``floor(x, aux)`` of :class:`_CondensedSystem`: a bound of the round-off of :math:`R - W t(y)`,
    :math:`y = y_f - A R`: :math:`10\,\epsilon\,\max(|R| + W(|t| + |D_y t|(|y_f| + |A||R|)))`."""
    absA = np.abs(ctx.fc.A)
    c, d, w = ctx.c, ctx.d, ctx.w

    def floor(x, aux):
        t, Dy = aux[1], aux[2]
        yerr = np.abs(ctx.yf) + (absA @ np.abs(x)).reshape(c, d)
        terr = np.abs(t) + np.einsum("cij,cj->ci", np.abs(Dy), yerr)
        return 10.0 * np.finfo(float).eps * float(np.max(np.abs(x) + (w[:, None] * terr).ravel(), initial=0.0))

    return floor


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

    The laws of :mod:`alcontact.contact.laws._normal` give :math:`t_N` and
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


def _second_order_update(ctx: _ALSystem, law, lamN, lamT, state, z, coupled: bool = False):
    r"""Newton step on the multiplier fixed point :math:`G(\lambda) = \lambda - t(\lambda) = 0`.

    Solves :math:`(I - dt/d\lambda)\,\Delta = t - \lambda` with the derivatives of
    ``ctx.sensitivity`` at the subproblem's solution ``state`` (:func:`_sensitivity` on the
    condensed path, :meth:`_FiniteALCtx.sensitivity` at finite deformation; the second-order
    multiplier iteration of Bertsekas); the new multipliers are made admissible (:func:`_admissible`).
    Where the system gives the derivative :math:`dz/d\lambda` of the subproblem's solution
    (the third member of ``ctx.sensitivity``; finite deformation), the next subproblem starts
    from its first-order change :math:`z + (dz/d\lambda)\,\Delta\lambda` instead of ``z``.

    Returns
    -------
    (lamN, lamT, z) or None
        The new multipliers and the start of the next subproblem; ``None`` when a Newton matrix
        is singular or the step is not finite.
    """
    sens = ctx.sensitivity(law, lamN, lamT, state, coupled)
    if sens is None:
        return None
    t = state.aux[1]
    lam = np.concatenate([lamN[:, None], lamT], axis=1)
    try:
        step = _solve(sens[0], (t - lam).ravel()).reshape(lam.shape)
    except (sla.LinAlgError, ValueError):
        return None
    new = lam + step
    if not np.all(np.isfinite(new)):
        return None
    newN, newT = _admissible(ctx, new)
    if sens[2] is not None:
        moved = z + sens[2] @ (np.concatenate([newN[:, None], newT], axis=1) - lam).ravel()
        z = moved if np.all(np.isfinite(moved)) else z
    return newN, newT, z


def _tangent_predictor(ctx: _ALSystem, law, lamN, lamT, state):
    r"""Sensitivity :math:`d\lambda^*/dy_f = (I - \partial t/\partial\lambda)^{-1}\,\partial t/\partial y_f`
    of the converged multipliers to the free kinematics (implicit function theorem at
    the fixed point): the next load step starts from
    :math:`\lambda_n + (d\lambda^*/dy_f)\,\Delta y_f` (``None`` when singular).
    """
    sens = ctx.sensitivity(law, lamN, lamT, state)
    if sens is None or sens[1] is None:
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
    return ctx.opts.radius == "multiplier" and ctx.second_order and ctx.fc.spring is None and bool(np.any(np.asarray(ctx.mu) > 0))


def _final_coupled(ctx: _ALSystem, dlam: float) -> bool:
    r"""Whether the next subproblem takes the coupled Coulomb radius :math:`\mu t_N` because it is expected to be
    the last: the multiplier change ``dlam`` of the one just solved is below :math:`\sqrt{tol_{multiplier}}`.

    With the fixed radius :math:`\mu\lambda_N` of (6.2c) the converged tractions satisfy the slip law
    :math:`|t_T| = \mu t_N` only up to the multiplier change, :math:`|\lambda_N - t_N| \le tol_{multiplier}\,p_{ref}`:
    relative to :math:`t_N` that is large at the weakly pressed points of the contact edge (issue 18, 3D
    ironing with Algorithm 6.2: 3.0e-8). In the last subproblem the coupled radius makes the returned
    tractions satisfy it exactly (to round-off); there the iterate is at the fixed point to
    :math:`\sqrt{tol_{multiplier}}`, where both radii differ by that much and Newton converges alike.
    The fixed point, the update and the stopping test are unchanged; only with ``radius="multiplier"``
    (``"traction"`` takes the coupled radius in every subproblem) and where :func:`_coupled_start`
    applies (the hybrid start: the second-order update, a body held by its supports), on a system that
    declares :attr:`_ALSystem.final_coupled` (finite deformation, :class:`_FiniteALCtx`).
    """
    return ctx.final_coupled and _coupled_start(ctx) and dlam <= float(np.sqrt(ctx.opts.tol_multiplier))


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
    :class:`~alcontact.contact.systems._krylov._FullCtx`, or those of a finite-deformation
    step, :class:`~alcontact.contact.algorithms._coulomb._FiniteALCtx`); the loop, the multiplier
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
            upd = _second_order_update(ctx, macaulay, lamN, lamT, out.state, z, coupled) if second_order else None
            if upd is not None:
                lamN, lamT, z = upd
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
            pred = (_tangent_predictor(ctx, law, lamN, lamT, out.state)
                    if ctx.second_order and ctx.tangent_predictor else None)
            return _StepOut(True, "converged", ctx.forces(z, t), t, k + outer0, newton, predictor=pred, z=z,
                            last_state=out.state)
        if fallback is not None and not dlam <= 0.5 * dlam_prev:
            logger.debug("%s outer %d: second-order update did not halve the multiplier change; "
                         "first-order update from here", ctx.label, k)
            second_order = False
        dlam_prev = dlam
        # multiplier updates (6.2b)/(6.2c), resp. lambda_N <- p'(g/eta, lambda_N)
        upd = _second_order_update(ctx, law, lamN, lamT, out.state, z, coupled) if second_order else None
        # the subproblem expected to be the last (a multiplier change below sqrt(tol_multiplier)) takes the
        # coupled radius mu t_N (_final_coupled)
        coupled = _final_coupled(ctx, dlam)
        fallback = (t[:, 0].copy(), t[:, 1:].copy(), z.copy()) if upd is not None else None
        lamN, lamT, z = upd if upd is not None else (t[:, 0].copy(), t[:, 1:].copy(), z)
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


# ---------------------------------------------------------------------------
# one load step: Algorithms 6.2 / 6.4
# ---------------------------------------------------------------------------
@dataclass
class _FiniteALCtx:
    r"""The :class:`~alcontact.contact.algorithms._coulomb._ALSystem` of a finite-deformation load step.

    The one AL loop :func:`~alcontact.contact.algorithms._coulomb._step_al` (Algorithms 6.2 / 6.4)
    drives it; its unknowns are the free displacements ``x``, a subproblem is
    :meth:`FiniteFrictionContact.friction_subproblem` and its state the :class:`_Local` of the
    last iterate (``aux``: gaps and slips, tractions). The reference ``ssn``
    (:func:`_step_ssn_finite`) takes the same system. What differs from the small-deformation
    paths, each by a declaration here:

    - the multipliers ``lamT`` are ambient vectors ``(c, d)`` tangent to the obstacle, the
      tractions ``t = [t_N, t_T]`` have ``d + 1`` columns (:attr:`d`);
    - the slip of the stopping test is the step's slip on the obstacle's surface
      (``aux[0][:, 1:]``, :func:`~alcontact.contact.obstacles.surface_slip`), measured
      from the previous surface point: the reference :attr:`uTn` is zero, and no tangent
      direction is held by a support (:attr:`tfree` is ``None``);
    - the second-order multiplier update of Algorithm 6.2 (:attr:`second_order`, option
      ``multiplier_update``) with the sensitivity of the full-space subproblem
      (:meth:`sensitivity`: one factorization of its Newton matrix, ``c (d + 1)``
      back-substitutions), the next subproblem started from the first-order change of its
      solution, and the hybrid Coulomb radius of the first subproblem (:func:`_coupled_start`;
      the radius of the others is the one :meth:`FiniteFrictionContact.set_history` set from
      ``radius``); no tangent predictor. Before issue 18 this path took first-order updates
      only: on the 2D ironing case (h = 0.1, mu = 0.3, 40 sliding steps of 0.05 R) 11-13 outer
      iterations and 33.4 Newton per sliding step; with it 3 outer iterations and 12.1 Newton
      with ``penalty_scale`` 100, 6.25 with 10, the default here since (:data:`FINITE_AL_DEFAULTS`,
      ``docs/benchmarks/ironing.md``). Algorithm 6.4 takes it with every penalty, a barrier-type one
      (log MET 1/2) included (:attr:`second_order`);
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
    #: no tangent predictor of the multipliers (the sensitivity has no T_y: not factorized for it)
    tangent_predictor: ClassVar[bool] = False
    full_predictor: ClassVar[bool] = True
    #: the last subproblem of a step takes the coupled radius mu t_N (_final_coupled; issue 18)
    final_coupled: ClassVar[bool] = True
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
        return self.fc.coulomb.mu

    @property
    def second_order(self) -> bool:
        """The option ``multiplier_update``: ``"newton"`` takes the second-order update (:meth:`sensitivity`).

        With every penalty. A barrier-type one (``log-met1``, ``log-met2``) kept the first-order updates
        until issue 18: with the second-order update the block of
        ``tests/verification/test_finite_friction_log_barrier.py`` (4 x 4 elements, 9 steps) had needed
        3-4 cut-backs at its stick-to-slip transition (none with first-order updates, 331 Newton). With the
        barrier start of the frictionless solver (:meth:`inside_domain`) it takes 115 Newton and no cut-back
        (112 with the coupled radius of the last subproblem, :func:`_final_coupled`); the 2D ironing case
        (h = 0.1, 20 sliding steps, ``penalty_scale`` 10) 7.35 Newton per sliding step instead of 32.4, and
        the slip law holds to round-off instead of to the floored multiplier (1e-10 of the largest pressure
        as the radius at open points). On the same block ``exp-met1`` takes 124 Newton instead of 320 with
        it, ``quad-met1`` 114 instead of 268, no cut-back.
        """
        return self.opts.multiplier_update == "newton"

    @property
    def uTn(self) -> np.ndarray:
        """Zero: the slip ``aux[0][:, 1:]`` is already measured from the previous surface point."""
        return np.zeros((self.c, self.fc.dim))

    @property
    def start(self) -> np.ndarray:
        return self.x0.copy()

    def subproblem(self, law, lamN, lamT, x, coupled: bool = False) -> NewtonResult:
        """:meth:`FiniteFrictionContact.friction_subproblem` (``coupled``: with the coupled radius :math:`\\mu t_N`)."""
        dc = self.fc
        saved = dc.coulomb
        if coupled:  # the same law with the coupled radius mu t_N for this subproblem
            dc.coulomb = saved.with_radius("traction")
        try:
            return dc.friction_subproblem(law, lamN, lamT, x, tol=self.opts.newton_tol,
                                          maxiter=self.opts.maxiter_newton)
        finally:
            dc.coulomb = saved

    def iterate(self, out: NewtonResult) -> np.ndarray:
        return out.x

    def inside_domain(self, law, lamN, x) -> np.ndarray:
        """Start for barrier-type penalties: contact forces scaled up until every gap is inside ``g < eta b``.

        The barrier start of the frictionless finite-deformation solver, the same function
        (:func:`~alcontact.contact.algorithms._frictionless._inside_domain`): the forces are scaled to first
        order (:meth:`~alcontact.contact.systems._full_space.FiniteContact.scale_forces`), first by the scale
        that just closes the penetrations, doubled while the start is still outside; ``x`` unchanged when it
        is inside or no force can be scaled.
        """
        return _frictionless_start(self.fc, x, law.gap_bound(lamN))

    def sensitivity(self, law, lamN, lamT, state, coupled: bool = False):
        r"""``(M, None, Z)``: :math:`M = I - dt/d\lambda` of the multiplier map at the subproblem's solution ``state``
        and :math:`Z = dx/d\lambda` ``(free DOFs, c (d + 1))``.

        At the solution :math:`x(\lambda)` of the subproblem, :math:`R(x, \lambda) = 0` with
        :math:`R = f_{int} - f_{ext} + \sum_i A_i^T w_i (t_{T,i} - t_{N,i}\nu_i)`, so
        :math:`J\,dx = -A^T F_\lambda\,d\lambda` (:math:`J` the consistent Newton matrix
        :meth:`~alcontact.contact.systems._full_space.FiniteFrictionContact.friction_jacobian`,
        :math:`F_\lambda` the block-diagonal :math:`w_i(\partial t_T/\partial\lambda -
        \nu\,\partial t_N/\partial\lambda)`) and

        .. math::

            \frac{dt}{d\lambda} = \frac{\partial t}{\partial\lambda}
            - \frac{\partial t}{\partial x} A J^{-1} A^T F_\lambda,

        with the local derivatives of the return mapping (6.47)-(6.50) in the current
        configuration (those of the Jacobian, :meth:`FiniteFrictionContact._local`, plus the
        radius :math:`\mu\lambda_N` (or :math:`\mu t_N` with ``coupled``) differentiated in
        :math:`\lambda_N`). One assembly and factorization of :math:`J` and ``c (d + 1)``
        back-substitutions in blocks of :data:`_SENSITIVITY_BLOCK` columns, of which only the rows
        of the contact points are kept (counted as one linear solve); the multipliers are
        :math:`(\lambda_N, \lambda_T)` with ambient :math:`\lambda_T`, ``c (d + 1)`` unknowns.
        ``Z`` is the dense ``(free DOFs, c (d + 1))`` matrix when it fits one block, else an operator:
        one more back-substitution with the same factor when applied (right after this call, by
        :func:`_second_order_update`). No tangent predictor (``T_y`` is ``None``:
        a step starts from the last step's multipliers).
        """
        dc = self.fc
        cand = dc.cand
        k, d = cand.size, dc.dim
        nl = d + 1
        w = dc.weights[cand]
        u = state.u
        lamN = np.asarray(lamN, dtype=float)
        saved = dc.coulomb
        if coupled:
            dc.coulomb = saved.with_radius("traction")
        try:
            mu = dc.coulomb.mu
            xc = dc._current(u, cand)
            g, nu = dc.obstacle.evaluate(xc)
            tN = np.asarray(law.traction(g, lamN), dtype=float)
            kN = np.asarray(law.stiffness(g, lamN), dtype=float)
            pref = max(float(np.max(tN, initial=0.0)), 1e-300)
            dN = _WithDlam(law, pref).dlam(g, lamN)  # dt_N / d lambda_N
            z, _, dz_dx, _ = dc._trial(lamT, xc, nu, cand, blocks=True)
            if dc.coulomb.coupled:
                rho, drho, drho_dx = mu * tN, mu * dN, mu * kN
            else:
                rho, drho, drho_dx = mu * np.maximum(lamN, 0.0), mu * (lamN > 0), np.zeros(k)
            _, _, _, slipping, n, Mp = return_mapping(z, rho)
            P = np.eye(d)[None] - nu[:, :, None] * nu[:, None, :]
            Dl = np.zeros((k, nl, nl))
            Dl[:, 0, 0] = dN
            Dl[:, 1:, 0] = np.where(slipping[:, None], drho[:, None] * n, 0.0)
            Dl[:, 1:, 1:] = Mp @ P
            Dx = np.zeros((k, nl, d))
            Dx[:, 0, :] = -kN[:, None] * nu
            Dx[:, 1:, :] = Mp @ dz_dx - np.where(slipping[:, None, None],
                                                 drho_dx[:, None, None] * n[:, :, None] * nu[:, None, :], 0.0)
            Fl = w[:, None, None] * (Dl[:, 1:, :] - nu[:, :, None] * Dl[:, :1, :])  # (k, d, nl)
            J = dc.friction_jacobian(law, lamN, lamT, u)
        finally:
            dc.coulomb = saved
        pos = dc.pos[cand]  # (k, d), -1 at fixed DOFs
        nf = dc.free.size
        rows, cols, vals = [], [], []
        for j in range(d):
            keep = pos[:, j] >= 0
            for q in range(nl):
                rows.append(pos[keep, j])
                cols.append(np.flatnonzero(keep) * nl + q)
                vals.append(Fl[keep, j, q])
        n = k * nl
        rhs = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(nf, n))
        solver = dc.friction_solver
        dxi = np.zeros((k, d, n))  # d x_i / d lambda at the points
        X = None
        try:
            # J^{-1} A^T F_lambda in column blocks, keeping only the rows of the points (memory: nf x block)
            for c0 in range(0, n, _SENSITIVITY_BLOCK):
                block = rhs[:, c0:c0 + _SENSITIVITY_BLOCK].toarray()
                X = solver.solve(J, block) if c0 == 0 else solver.resolve(block)
                if X is None:
                    return None
                for j in range(d):
                    keep = pos[:, j] >= 0
                    dxi[keep, j, c0:c0 + block.shape[1]] = -X[pos[keep, j]]
        except (np.linalg.LinAlgError, ValueError):
            return None
        dc.linear_solves += 1
        dt = np.einsum("ikj,ijm->ikm", Dx, dxi).reshape(n, n)
        dt += block_diag(Dl)
        M = np.eye(n) - dt
        if not np.all(np.isfinite(M)):
            return None
        _first_order_where_held(M)
        if n <= _SENSITIVITY_BLOCK:  # one block: dx/dlambda at hand
            return M, None, -X

        def dx_dlam(v):  # dx/dlambda v = -J^{-1} A^T F_lambda v, one back-substitution with J's factor
            out = solver.resolve(rhs @ np.ravel(v))
            return np.zeros(nf) if out is None else -out

        return M, None, spla.LinearOperator((nf, n), matvec=dx_dlam, dtype=float)

    def forces(self, x, t) -> np.ndarray:
        r"""Force of the obstacle on the body at each candidate, :math:`w_i (t_{N,i}\nu_i - t_{T,i})` ``(c, d)``."""
        dc = self.fc
        nu = dc.obstacle.normal(dc._current(dc.expand(x), dc.cand))
        with np.errstate(invalid="ignore", over="ignore"):  # the non-finite tractions of a failed step as they are
            return dc.weights[dc.cand][:, None] * (t[:, :1] * nu - t[:, 1:])


def _first_order_where_held(M: np.ndarray) -> None:
    r"""Make :math:`M = I - dt/d\lambda` of :meth:`_FiniteALCtx.sensitivity` regular where a multiplier component
    is held (in place): the first-order update there.

    A sticking point with a DOF held by a support along a tangent direction (the symmetry plane
    :math:`y = 0` of the 3D ironing half model, where the sphere's normal has no :math:`y` part) has a
    tangential multiplier component that moves nothing (its force acts on the held DOF) and that nothing
    moves (:math:`\Delta s_{T,y} = 0`): :math:`dt_k/d\lambda_k = 1` with no coupling, so row and column
    :math:`k` of :math:`M` vanish. Every :math:`\lambda_k` is a fixed point there (:math:`t_k - \lambda_k = 0`);
    the Newton step takes :math:`M_{kk} = 1`, i.e. the first-order update, which keeps it. Before (issue 18),
    the singular :math:`M` turned the second-order update off in every step with such a point in stick: the
    pressing and stick-to-slip steps of the 3D ironing case took 10-12 first-order outer iterations
    (20-29 Newton) instead of 3.
    """
    held = np.flatnonzero(~np.any(M != 0.0, axis=1) & ~np.any(M != 0.0, axis=0))
    M[held, held] = 1.0


def state_reversals(history: Sequence[np.ndarray], among: tuple[int, ...] | None = None) -> int:
    """Points whose state returned to one it had left along ``history`` (a state per iterate).

    Consecutive repeats count once: a point with states ``STICK, SLIP, SLIP, STICK`` has one
    reversal, ``STICK, SLIP, OPEN`` none. ``among``: only the iterates where a point is in one
    of these states count, e.g. ``(STICK, SLIP)``: the stick/slip reversals of the points in contact
    (``SLIP, OPEN, SLIP`` at the edge of the contact zone is none, ``STICK, OPEN, SLIP, STICK`` one).
    """
    if len(history) < 3:
        return 0
    H = np.asarray(history)  # (iterates, points)
    count = 0
    for col in H.T:
        if among is not None:
            col = col[np.isin(col, among)]
            if col.size < 3:
                continue
        seq = col[np.concatenate([[True], col[1:] != col[:-1]])]
        if seq.size >= 3 and np.any(seq[2:] == seq[:-2]):
            count += 1
    return count


def _ssn_parameter(dc) -> float:
    r"""The Alart-Curnier parameter :math:`c` of :func:`_step_ssn_finite`: :math:`E'/h`, the stiffness of the
    first element row under the contact surface (:func:`~._solve.penalty_stiffness` with scale 1).

    The solution does not depend on :math:`c` (the complementarity functions vanish at the same
    points for every :math:`c > 0`), its Newton path does. With the AL penalty
    :math:`\varepsilon_N` (``penalty_scale`` = 100 times :math:`E'/h`, the algorithms' default) a sliding step at the
    stick-to-slip transition of the 2D ironing problem (h = 0.1, :math:`\mu` = 0.3) took 41-65
    Newton iterations and a cut-back: the first full Newton step opened every contact point
    (:math:`\lambda_N + c\,g < 0` for a small penetration error times a large :math:`c`) and the
    backtracking on the residual norm rebuilt the contact zone point by point. With
    :math:`c = E'/h` the same steps take 4-5 (issue 18; ``docs/benchmarks/ironing.md``).
    """
    return penalty_stiffness(dc.problem.model, dc.h, 1.0)


def _step_ssn_finite(ctx: _FiniteALCtx, penalty_name: str = "none") -> _StepOut:
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
    mu = dc.coulomb.mu
    nf = dc.free.size
    macaulay = make_law(_pen.make("rockafellar"), np.full(k, 1.0 / c))
    saved = dc.coulomb
    dc.coulomb = saved.with_radius("traction", eps_t=c)  # the semi-smooth law: eps_T = c, radius mu t_N
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
                         maxiter=max(opts.maxiter_newton, 100), settings=_FRICTION_SSN_SETTINGS, log=log)
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
                     reversals=state_reversals(states + [final]),
                     stick_slip_reversals=state_reversals(states + [final], among=(STICK, SLIP)))
        return _StepOut(True, "converged", ctx.forces(x, L), L.copy(), 1, out.iterations, z=x, last_state=loc)
    finally:
        dc.coulomb = saved


#: Defaults of Algorithms 6.2 and 6.4 at finite deformation: a ten times softer automatic penalty
#: (``penalty_scale`` 10). With the default 100 the first subproblem of each sliding step takes
#: most of the step's Newton iterations (Algorithm 6.2: 12.1 per sliding step on the 2D ironing case,
#: 8.9 in 3D; 6.3 and 7.3 with 10, ``docs/benchmarks/ironing_friction_2d.md``; Algorithm 6.4, issue 18,
#: 40 sliding steps: exp-met1 13.95 -> 7.30 (2D), 10.65 -> 6.97 (3D), quad-met1 12.12 -> 7.17 (2D)); the
#: converged step does not depend on the penalty (the fixed point of (6.2b)/(6.2c) is the discrete
#: Coulomb problem).
FINITE_AL_DEFAULTS = {**FRICTION_DEFAULTS, "penalty_scale": 10.0}

register_family((
    ("simo-laursen", _step_al, "rockafellar", "Algorithm 6.2 at finite deformation: AL, Macaulay normal law (6.52), "
                                              "return mapping onto the Coulomb cone in the current configuration"),
    ("family-p", _step_al, None, "Algorithm 6.4 at finite deformation: Algorithm 6.2 with a family-P normal penalty"),
), friction=True, kinematics="finite", linear_solvers=("direct", "factor-gmres"), defaults=FINITE_AL_DEFAULTS)
register_family((
    ("ssn", _step_ssn_finite, "none",
     "reference: Alart-Curnier semi-smooth Newton on (u, lambda_N, lambda_T), exact (no penalty)"),
), friction=True, kinematics="finite", linear_solvers=("direct", "factor-gmres"), defaults=FRICTION_DEFAULTS)


def finite_friction_algorithms() -> list[str]:
    """Names of the finite-deformation frictional algorithms."""
    return algorithm_names(friction=True, kinematics="finite")
