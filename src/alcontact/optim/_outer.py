"""Outer loops of Algorithms 5.1-5.4 in one parametrised form (method registry).

All methods minimise, for fixed ``(eta, mu, lam)``, the subproblem (SL)

.. math::

    L(x) = f(x) + \\sum_i \\eta_i\\, p\\!\\left(\\frac{g_i(x)}{s_i}, \\mu_i\\right)
               + \\sum_j \\eta_j\\, q\\!\\left(\\frac{h_j(x)}{\\eta_j}, \\lambda_j\\right)

with ``s = eta`` for the augmented Lagrangian (5.28) and the exterior penalty
(5.10, ``t = 1/eta``), and ``s = 1`` for the barrier (5.1, ``rho = eta``);
``q`` is Hestenes-Powell's ``lam y + y^2/2`` (5.13, ``rho = 1/eta``).
The multiplier estimates are the weights of the constraint gradients in
:math:`\\nabla L` (5.29)-(5.30), :math:`\\bar\\mu_i = (\\eta_i/s_i) p'(g_i/s_i, \\mu_i)`,
and the AL update is :math:`\\mu \\leftarrow p'(g/\\eta, \\mu)` (Algorithm 5.4 as
corrected). ``eta -> 0`` is always the constrained limit; strategies return
the factor of ``eta <- eta / factor``.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..errors import DomainError, InputError
from ..penalties import PenaltyFacts, facts
from ._inner import InnerResult
from ._polish import kkt_polish
from ._problem import NLP, NonFiniteValue
from ._result import IterationRecord, Status
from ._strategies import StrategyState

__all__ = ["MethodSpec", "METHODS", "run_outer", "kkt_measures", "box_multipliers"]

log = logging.getLogger("alcontact.optim")


@dataclass(frozen=True)
class MethodSpec:
    """Declared facts of an outer method.

    Attributes
    ----------
    name : str
        Registry name.
    default_penalty : str
        Inequality penalty used when the caller gives none.
    accepts : callable
        Predicate on the declared facts of a penalty
        (:class:`alcontact.penalties.PenaltyFacts`): whether the method takes it.
    scaled : bool
        Whether the penalty argument is ``g/eta`` (5.28) or ``g`` (5.1).
    update_multipliers : bool
        Whether multipliers are updated (AL methods) or fixed (pure penalties).
    inequalities, equalities : bool
        Which constraint kinds the method accepts.
    strategy : str
        Default penalty-parameter strategy.
    strategy_options : tuple of (str, float)
        Its default parameters.
    summary : str
        One line for :func:`available_methods` users.
    polish : bool
        Whether the Newton-KKT polish (option ``polish``) applies; the classical
        methods of Algorithms 5.1-5.3 stay pure.
    safeguards : bool
        Whether the subproblem uses the safeguarded MET penalties (option
        ``extrapolate``, Matioli's safeguard) of :mod:`._safeguards`.
    autoscale : bool
        Whether option ``scale`` (automatic scaling of ``f`` and the constraints,
        :meth:`NLP.set_scaling`) applies.
    box : bool
        Whether option ``bounds_as="box"`` applies: variable bounds stay an exact
        box of the subproblems (projected Newton inner solver) instead of penalised
        inequalities.
    """

    name: str
    default_penalty: str
    accepts: Callable[[PenaltyFacts], bool]
    scaled: bool
    update_multipliers: bool
    inequalities: bool
    equalities: bool
    strategy: str
    strategy_options: tuple
    summary: str
    polish: bool = False
    safeguards: bool = False
    autoscale: bool = False
    box: bool = False


def _al_penalty(f: PenaltyFacts) -> bool:
    """Algorithm 5.4: a penalty of the multipliers (not a pure barrier / exterior penalty)
    for inequalities (not equality-only)."""
    return f.uses_multiplier and not f.equality_only


def _barrier(f: PenaltyFacts) -> bool:
    """Algorithm 5.1: no multiplier, bounded domain (``p -> inf`` at ``b``)."""
    return not f.uses_multiplier and f.bounded_domain


def _exterior(f: PenaltyFacts) -> bool:
    """Algorithm 5.2: no multiplier, defined on the whole line."""
    return not f.uses_multiplier and not f.bounded_domain


def _equality(f: PenaltyFacts) -> bool:
    """Algorithm 5.3: a penalty of equality constraints."""
    return f.equality_only


METHODS = {
    "al": MethodSpec(
        "al", "exp-met1", _al_penalty, True, True, True, True,
        "per-constraint", (("tau", 0.5), ("factor", 10.0)),
        "Algorithm 5.4 (corrected): inequalities with any AL penalty (family P, "
        "Rockafellar, quadratic with safeguard), equalities by Hestenes-Powell",
        polish=True, safeguards=True, autoscale=True, box=True),
    "hestenes-powell": MethodSpec(
        "hestenes-powell", "hestenes-powell", _equality, True, True,
        False, True, "infeasibility", (("tau", 0.25), ("factor", 10.0)),
        "Algorithm 5.3: method of multipliers for equality constraints (5.13)-(5.15)"),
    "barrier": MethodSpec(
        "barrier", "log-barrier", _barrier, False, False,
        True, False, "always", (("factor", 2.0),),
        "Algorithm 5.1: logarithmic (5.2) or inverse (5.3) barrier, rho -> 0"),
    "exterior-penalty": MethodSpec(
        "exterior-penalty", "exterior-quadratic", _exterior, True, False,
        True, True, "always", (("factor", 2.0),),
        "Algorithm 5.2: exterior quadratic penalty (5.8)/(5.9), t = 1/eta -> inf"),
}


class Subproblem:
    """The function (SL) for fixed parameters; see the module docstring."""

    def __init__(self, nlp: NLP, pen, hp, scaled, eta, mu, lam, unbounded_below):
        self.nlp, self.pen, self.hp, self.scaled = nlp, pen, hp, scaled
        self.m, self.p = nlp.m, nlp.p
        # the box l <= x <= u of method "al" (None: bounds, if any, are rows of g)
        self.lower, self.upper = nlp.lower, nlp.upper
        self.unbounded_below = unbounded_below
        self.last_nonfinite = None
        self.set(eta, mu, lam)

    def set(self, eta, mu, lam):
        self.eta = np.asarray(eta, dtype=float)
        self.eta_g, self.eta_h = self.eta[:self.m], self.eta[self.m:]
        self.s = self.eta_g if self.scaled else np.ones(self.m)
        self.mu, self.lam = np.asarray(mu, float), np.asarray(lam, float)
        self.b = (_domain(self.pen, self.mu) if self.m else np.zeros(0))
        self.bounded = bool(self.m) and bool(np.any(np.isfinite(self.b)))

    # weights = multiplier estimates; curvature = second-derivative weights
    def weights(self, g, h):
        with np.errstate(all="ignore"):
            y = g / self.s
            wg = (self.eta_g / self.s) * self.pen.derivative(y, self.mu) if self.m \
                else np.zeros(0)
            wh = self.hp.derivative(h / self.eta_h, self.lam) if self.p else np.zeros(0)
        return np.asarray(wg, float), np.asarray(wh, float)

    def value(self, x):
        try:
            f = self.nlp.f(x)
            g, h = self.nlp.constraints(x)
        except NonFiniteValue as exc:
            self.last_nonfinite = exc.callback
            return math.inf
        total = f
        with np.errstate(all="ignore"):
            if self.m:
                y = g / self.s
                if self.bounded and np.any(y >= self.b):
                    return math.inf
                total += float(np.sum(self.eta_g * self.pen.value(y, self.mu)))
            if self.p:
                total += float(np.sum(self.eta_h * self.hp.value(h / self.eta_h, self.lam)))
        return total if math.isfinite(total) else math.inf

    def gradient(self, x):
        gf = self.nlp.grad(x)
        g, h = self.nlp.constraints(x)
        Jg, Jh = self.nlp.jacobians(x)
        wg, wh = self.weights(g, h)
        gl = gf.copy()
        if self.m:
            gl += np.asarray(Jg.T @ wg).ravel()
        if self.p:
            gl += np.asarray(Jh.T @ wh).ravel()
        # the same normalisation as the stationarity of kkt_measures (user's units)
        scale = max(self.nlp.f_scale, float(np.max(np.abs(gf))))
        return gl, scale

    def hessian(self, x):
        nlp = self.nlp
        H = nlp.hess_f(x, sparse=nlp.sparse)
        g, h = nlp.constraints(x)
        Jg, Jh = nlp.jacobians(x)
        wg, wh = self.weights(g, h)
        Hc = nlp.constraint_hessian(x, wg, wh)
        if Hc is not None:
            if nlp.sparse:
                Hc = sp.csr_matrix(Hc) if not sp.issparse(Hc) else Hc
            elif sp.issparse(Hc):
                Hc = Hc.toarray()
            H = H + Hc
        with np.errstate(all="ignore"):
            parts = []
            if self.m:
                cg = (self.eta_g / self.s ** 2) * self.pen.second_derivative(g / self.s, self.mu)
                parts.append((Jg, np.asarray(cg, float)))
            if self.p:
                ch = self.hp.second_derivative(h / self.eta_h, self.lam) / self.eta_h
                parts.append((Jh, np.asarray(ch, float)))
        for J, c in parts:
            if nlp.sparse:
                H = H + J.T @ sp.diags(c) @ J
            else:
                H = H + J.T @ (c[:, None] * J)
        return H.tocsr() if sp.issparse(H) else H

    def max_step(self, x, d):
        """Largest step keeping the linearised ``g/s`` below 99.5 % of the way to ``b``."""
        if not self.bounded:
            return math.inf
        g, _ = self.nlp.constraints(x)
        Jg, _ = self.nlp.jacobians(x)
        y = g / self.s
        dy = np.asarray(Jg @ d).ravel() / self.s
        mask = (dy > 0) & np.isfinite(self.b)
        if not np.any(mask):
            return math.inf
        return float(np.min(0.995 * (self.b[mask] - y[mask]) / dy[mask]))


def _domain(pen, mu):
    """Vector of domain bounds ``b(mu_i)`` (per-entry fallback if not vectorised)."""
    try:
        b = np.broadcast_to(np.asarray(pen.domain_upper(mu), dtype=float), mu.shape)
    except (TypeError, ValueError):
        b = np.array([float(pen.domain_upper(float(v))) for v in mu])
    return np.array(b, dtype=float)


@dataclass
class OuterOutcome:
    """Mutable state handed back to :func:`minimize` to build the result."""

    x: np.ndarray
    status: Status
    message: str
    nit: int
    nit_inner: int
    mu: np.ndarray
    lam: np.ndarray
    g: np.ndarray
    h: np.ndarray
    stationarity: float
    feasibility: float
    complementarity: float
    eta: np.ndarray
    history: list
    box_multipliers: np.ndarray | None = None  # v of box_multipliers (scaled units)


def _lagrangian_gradient(nlp, x, mu, lam):
    gf = nlp.grad(x)
    Jg, Jh = nlp.jacobians(x)
    r = gf.copy()
    if nlp.m:
        r += np.asarray(Jg.T @ mu).ravel()
    if nlp.p:
        r += np.asarray(Jh.T @ lam).ravel()
    return gf, r


def box_multipliers(nlp, x, r, gf):
    """Bound multipliers of the box from the Lagrangian gradient ``r`` (scaled units).

    Returns ``v`` with ``r - v`` the stationarity residual: ``v_i = max(r_i, 0)``
    for a lower bound, ``min(r_i, 0)`` for an upper bound (the sign restriction
    (C3)), assigned to the bound only where that lowers the KKT error, i.e. where the
    complementarity :math:`|v_i| d_i / s_f` (``d_i`` the distance to the bound) does
    not exceed the stationarity :math:`|v_i| / \\max(s_f, \\|\\nabla f\\|_\\infty)`
    it removes; always for a variable on its bound. The multipliers of the user's
    ``Bounds`` (weights on ``x``, :attr:`ALResult.multipliers_bounds`) are
    ``-v / s_f``. Zero without a box.
    """
    v = np.zeros(nlp.n)
    if not nlp.has_box:
        return v
    sf = nlp.f_scale
    reach = sf / max(sf, float(np.max(np.abs(gf))))
    with np.errstate(invalid="ignore"):
        dl, du = x - nlp.lower, nlp.upper - x
    lo = (r > 0) & np.isfinite(nlp.lower) & (dl <= reach)
    up = (r < 0) & np.isfinite(nlp.upper) & (du <= reach)
    v[lo] = r[lo]
    v[up] = r[up]
    return v


def kkt_measures(nlp, x, mu, lam):
    """(C1)-(C4) measures at ``x`` with multipliers ``mu >= 0`` and ``lam``.

    Returns ``(stationarity, feasibility, complementarity, g, h)``; stationarity is
    :math:`\\|\\nabla f + J_g^T\\mu + J_h^T\\lambda - v\\|_\\infty / \\max(1, \\|\\nabla f\\|_\\infty)`
    with the box multipliers ``v`` of :func:`box_multipliers` (zero when the bounds
    are rows of ``g``). ``mu``, ``lam``, ``g`` and ``h`` belong to the (possibly
    scaled, see :meth:`NLP.set_scaling`) internal problem; the three measures are
    those of the user's problem in its own units (multipliers ``mu s_g / s_f``), so
    the tolerances always mean the same thing.
    """
    gf, r = _lagrangian_gradient(nlp, x, mu, lam)
    g, h = nlp.constraints(x)
    sf = nlp.f_scale
    comp = float(np.max(np.abs(mu * g), initial=0.0)) / sf
    feas_box = 0.0
    if nlp.has_box:
        v = box_multipliers(nlp, x, r, gf)
        with np.errstate(invalid="ignore"):
            dist = np.where(v > 0, x - nlp.lower, np.where(v < 0, nlp.upper - x, 0.0))
        comp = max(comp, float(np.max(np.abs(v * dist), initial=0.0)) / sf)
        r = r - v
        feas_box = float(np.max(np.maximum(nlp.lower - x, x - nlp.upper), initial=0.0))
    stat = float(np.max(np.abs(r))) / max(sf, float(np.max(np.abs(gf))))
    gu, hu = g / nlp.g_scale, h / nlp.h_scale
    feas = max(float(np.max(gu, initial=0.0)), float(np.max(np.abs(hu), initial=0.0)),
               feas_box)
    return stat, feas, comp, g, h


def box_active(nlp, x, mu, lam):
    """Active-bound estimate of the box: the analogue of ``mu_i > -g_i``.

    Lower bound ``i`` is active when ``x_i - l_i < r_i`` (``r`` the Lagrangian
    gradient), upper bound ``i`` when ``u_i - x_i < -r_i``; fixed variables
    (``l_i = u_i``) always. Returns ``(at_lower, at_upper)`` boolean arrays.
    """
    _, r = _lagrangian_gradient(nlp, x, mu, lam)
    with np.errstate(invalid="ignore"):
        at_lo = (x - nlp.lower < r) | (nlp.lower == nlp.upper)
        at_up = (nlp.upper - x < -r) & ~at_lo
    return at_lo, at_up


def _merit(stat, feas, comp):
    return max(stat, feas, comp)


@dataclass
class _Loop:
    """State of :func:`run_outer` between its steps (one outer iteration is split over small functions)."""

    nlp: NLP
    spec: MethodSpec
    pen: Any
    sub: Subproblem
    opts: Any
    mu_min: float
    restart: bool
    mu_start: np.ndarray
    x: np.ndarray
    eta: np.ndarray
    mu: np.ndarray
    lam: np.ndarray
    g: np.ndarray
    h: np.ndarray
    prev_feas: float
    history: list = field(default_factory=list)
    k: int = 0
    nit_inner: int = 0
    status: Status = Status.MAXITER
    message: str = ""
    stat: float = math.inf
    feas: float = math.inf
    comp: float = math.inf
    prev_comp: float = math.inf
    prev_kkt: float = math.inf
    prev_v: np.ndarray | None = None
    prev_active: np.ndarray | None = None
    best_merit: float = math.inf
    stalled: int = 0
    inner_failures: int = 0
    unbounded_retries: int = 0
    at_limit: int = 0
    mu_rep: np.ndarray | None = None
    lam_rep: np.ndarray | None = None
    wg: np.ndarray | None = None
    wh: np.ndarray | None = None

    def record(self, res, tol, factor, **kw):
        _record(self.history, self.k, self.nlp, self.x, self.stat, self.feas, self.comp, self.eta, res, tol,
                factor, **kw)

    def stop(self, status, message, res=None, tol=None) -> bool:
        """End the loop with ``status``; with ``res`` the iteration is recorded first. Returns True."""
        if res is not None:
            self.record(res, tol, 1.0)
        self.status, self.message = status, message
        return True


def run_outer(nlp: NLP, spec: MethodSpec, pen, hp, strategy, inner, opts, eta, mu, lam):
    """Outer loop shared by all methods; returns an :class:`OuterOutcome`.

    For the AL methods the subproblem uses the *safeguarded* multipliers
    ``clip(mu_est, mu_min, mu_max)`` (Birgin & Martinez), the KKT tests the
    unsafeguarded estimates ``mu_est = p'(g/eta, mu)``. With ``spec.polish`` and
    ``opts.polish`` a Newton-KKT polish (:mod:`._polish`) is tried whenever the
    active-set estimate repeats. One iteration: the subproblem (:func:`_measure`), an
    unbounded retry (:func:`_unbounded`), the bounds-only case (:func:`_box_only`), the KKT
    test, the polish (:func:`_polish_step`), the inner-failure count, the multiplier update
    (:func:`_update_multipliers`) and the penalty update by ``strategy`` (:func:`_update_eta`).
    """
    m, p = nlp.m, nlp.p
    known = facts(pen)
    freezes = m > 0 and spec.update_multipliers and known.freezes_at_zero
    x = nlp.project(nlp.x0.copy())
    g0, h0 = nlp.constraints(x)
    st = _Loop(nlp, spec, pen, Subproblem(nlp, pen, hp, spec.scaled, eta, mu, lam, opts.unbounded_below), opts,
               mu_min=opts.mu_min if opts.mu_min is not None else (1e-12 if freezes else 0.0),
               restart=freezes and not known.family_p, mu_start=np.array(mu, dtype=float), x=x, eta=eta, mu=mu,
               lam=lam, g=g0, h=h0,
               prev_feas=max(float(np.max(g0 / nlp.g_scale, initial=0.0)),
                             float(np.max(np.abs(h0 / nlp.h_scale), initial=0.0))),
               message=f"outer iteration limit maxiter={opts.maxiter} reached", mu_rep=np.zeros(m),
               lam_rep=np.zeros(p))
    polish = bool(spec.polish and opts.polish and m + p > 0)
    for k in range(1, opts.maxiter + 1):
        st.k = k
        if spec.scaled and m:
            st.eta = _keep_in_domain(nlp, st.sub, pen, st.x, st.eta, st.mu)
        st.sub.set(st.eta, st.mu, st.lam)
        tol = max(0.1 * opts.gtol, min(opts.inner_tol0, 0.1 * st.prev_kkt))
        if m + p == 0:
            # only a box (or nothing): one subproblem, refined if the KKT test fails
            tol = opts.gtol * 0.01 ** (k - 1)
        x_prev = st.x.copy()
        res: InnerResult = inner.solve(st.sub, st.x, tol, opts.maxiter_inner)
        st.nit_inner += res.nit
        if _measure(st, res, tol):
            break
        action = _unbounded(st, res, tol, x_prev)
        if action is None and m + p == 0:
            action = _box_only(st, res, tol)
        if action == "continue":
            continue
        if action == "break":
            break
        if st.stat <= opts.gtol and st.feas <= opts.feas_tol and st.comp <= opts.ctol:
            st.stop(Status.CONVERGED_KKT, "KKT tolerances met", res, tol)
            break
        if polish:
            res = _polish_step(st, res, tol)
            if res is None:
                break
        st.inner_failures = 0 if res.ok or res.code == Status.MAXITER else st.inner_failures + 1
        if st.inner_failures >= 3:
            st.stop(Status.INNER_FAILED, f"inner solver failed {st.inner_failures} times in a row "
                    f"({res.status}; scaled gradient {res.measure:.3g})", res, tol)
            break
        _update_multipliers(st)
        if _update_eta(st, strategy, res, tol):
            break
    zb = np.zeros(nlp.n)
    if nlp.has_box:
        try:
            gf, r = _lagrangian_gradient(nlp, st.x, st.mu_rep, st.lam_rep)
            zb = box_multipliers(nlp, st.x, r, gf)
        except NonFiniteValue:
            zb = np.full(nlp.n, math.nan)
    return OuterOutcome(st.x, st.status, st.message, st.k, st.nit_inner, st.mu_rep, st.lam_rep, st.g, st.h, st.stat,
                        st.feas, st.comp, np.asarray(st.eta, float), st.history, zb)


def _measure(st: _Loop, res: InnerResult, tol) -> bool:
    """Take the subproblem's solution; the multiplier estimates and the KKT measures there. True: stop."""
    if res.code == Status.NONFINITE:
        st.x = res.x
        return st.stop(Status.NONFINITE, f"non-finite value from {res.nonfinite or 'a callback'}", res, tol)
    st.x = res.x
    try:
        st.g, st.h = st.nlp.constraints(st.x)
        st.wg, st.wh = st.sub.weights(st.g, st.h)
        st.mu_rep = np.maximum(np.nan_to_num(st.wg, nan=0.0, posinf=st.opts.mu_max), 0.0)
        st.lam_rep = st.wh
        st.stat, st.feas, st.comp, st.g, st.h = kkt_measures(st.nlp, st.x, st.mu_rep, st.lam_rep)
    except NonFiniteValue as exc:
        return st.stop(Status.NONFINITE, f"non-finite value from {exc.callback}")
    return False


def _unbounded(st: _Loop, res: InnerResult, tol, x_prev) -> str | None:
    """A subproblem unbounded below: retry with a 100x stronger penalty (8 times), then stop."""
    if res.code != Status.UNBOUNDED:
        return None
    opts = st.opts
    if st.unbounded_retries < 8 and np.all(st.eta > opts.eta_min):
        # too weak a penalty for the scale of f: restart the subproblem stronger
        st.unbounded_retries += 1
        st.x = x_prev
        st.eta = np.clip(st.eta / 100.0, opts.eta_min, opts.eta_max)
        log.debug("subproblem unbounded below: eta decreased 100x and retried")
        return "continue"
    st.stop(Status.UNBOUNDED, f"subproblem unbounded below (L < {opts.unbounded_below:g}) at outer iteration "
            f"{st.k}", res, tol)
    return "break"


def _box_only(st: _Loop, res: InnerResult, tol) -> str:
    """No constraints but (maybe) a box: one subproblem, refined (up to 4) while the KKT test fails."""
    opts, nlp = st.opts, st.nlp
    st.record(res, tol, 1.0)
    if nlp.has_box and st.stat <= opts.gtol and st.comp <= opts.ctol:
        st.stop(Status.CONVERGED_KKT, "KKT tolerances met (bounds only)")
    elif nlp.has_box and res.ok and st.k < min(opts.maxiter, 4):
        return "continue"
    elif st.stat <= opts.gtol and not nlp.has_box:
        st.stop(Status.UNCONSTRAINED_CONVERGED, "gradient norm below gtol")
    else:
        st.stop(Status.INNER_FAILED, f"unconstrained Newton solve stopped: {res.status}")
    return "break"


def _polish_step(st: _Loop, res: InnerResult, tol) -> InnerResult | None:
    """Newton-KKT polish when the active-set estimate repeats (:mod:`._polish`).

    Returns None when the polished point meets every tolerance (the loop stops converged),
    else ``res`` with the polish iterations added.
    """
    nlp, m = st.nlp, st.nlp.m
    active = st.mu_rep > -st.g
    fix = None
    if nlp.has_box:
        at_lo, at_up = box_active(nlp, st.x, st.mu_rep, st.lam_rep)
        active = np.concatenate([active, at_lo, at_up])
        fix = (at_lo, at_up)
    if st.prev_active is not None and np.array_equal(active, st.prev_active):
        ok, xp, mup, lamp, meas, pit = kkt_polish(
            nlp, st.x, st.g, st.mu_rep, st.lam_rep, st.opts, kkt_measures, st.opts.polish_maxiter, box_fixed=fix)
        st.nit_inner += pit
        if ok:
            st.x, st.mu_rep, st.lam_rep = xp, mup, lamp
            st.stat, st.feas, st.comp, st.g, st.h = meas
            st.record(res, tol, 1.0, extra_inner=pit, tag="+kkt-polish")
            nact = int(np.sum(active[:m]))
            st.stop(Status.CONVERGED_KKT, f"KKT tolerances met after {pit} Newton-KKT polish step(s) "
                    f"on the active set ({nact} of {m} inequalities active"
                    + (f", {int(np.sum(active[m:]))} bounds" if fix else "") + ")")
            return None
        res = InnerResult(res.x, res.value, res.nit + pit, res.status, res.measure, res.nonfinite)
    st.prev_active = active
    return res


def _update_multipliers(st: _Loop) -> None:
    """``mu <- p'(g/eta, mu)`` (Algorithm 5.4 corrected) into ``[mu_min, mu_max]``; ``lam <- lam + h/eta``."""
    if not st.spec.update_multipliers:
        return
    opts, g = st.opts, st.g
    # the next subproblem's multipliers are safeguarded (the KKT test used mu_rep)
    if st.nlp.m:
        mu = np.clip(np.nan_to_num(st.wg, nan=st.mu_min, posinf=opts.mu_max), st.mu_min, opts.mu_max)
        if st.restart:
            # quadratic theta (5.27) with Matioli's safeguard is PHR with the
            # penalty rho_i = mu_i^2/eta_i: a multiplier at the floor kills the
            # penalty of its constraint. Keep every multiplier above a floor
            # relative to the largest one, and restart violated constraints
            # whose multiplier is frozen anyway (all multipliers tiny)
            mu = np.maximum(mu, QUAD_MU_FLOOR * float(np.max(mu)))
            frozen = (g > opts.feas_tol) & (mu < 1e-6 * max(1.0, float(np.max(mu))))
            mu[frozen] = np.maximum(mu[frozen], st.mu_start[frozen])
        st.mu = mu
    if st.nlp.p:
        st.lam = np.clip(st.wh, -opts.mu_max, opts.mu_max)


def _update_eta(st: _Loop, strategy, res: InnerResult, tol) -> bool:
    """The penalty update ``eta <- eta / factor`` of the strategy; records the iteration. True: stop.

    Stops at the penalty limit (``eta_min`` reached three times with the constraints still
    violated) or when the KKT error did not halve in ``stall_iter`` iterations.
    """
    opts, eta, m = st.opts, st.eta, st.nlp.m
    with np.errstate(all="ignore"):
        v = np.concatenate([np.abs(np.maximum(st.g, -eta[:m] * st.mu_rep)), np.abs(st.h)])
    factor = strategy(StrategyState(st.k, st.feas, st.prev_feas, st.comp, st.prev_comp, v, st.prev_v))
    factor = np.broadcast_to(np.asarray(factor, dtype=float), np.shape(eta))
    new_eta = np.clip(eta / factor, opts.eta_min, opts.eta_max)
    st.record(res, tol, float(np.max(eta / new_eta)))
    tight = factor > 1
    if np.any(tight) and np.all(new_eta[tight] == eta[tight]) and st.feas > opts.feas_tol:
        st.at_limit += 1
        if st.at_limit >= 3:
            return st.stop(Status.PENALTY_LIMIT, f"penalty parameter at its limit eta_min={opts.eta_min:g} and "
                           f"constraints still violated by {st.feas:.3g}")
    else:
        st.at_limit = 0
    merit = _merit(st.stat, st.feas, st.comp)
    if merit < 0.5 * st.best_merit:
        st.best_merit, st.stalled = merit, 0
    else:
        st.stalled += 1
        if st.stalled >= opts.stall_iter:
            st.message = (f"no progress: the KKT error max(stationarity, feasibility, "
                          f"complementarity) = {merit:.3g} did not halve in "
                          f"{opts.stall_iter} outer iterations (stopped at {st.k})")
            return True
    st.eta = new_eta
    st.prev_feas, st.prev_comp, st.prev_v = st.feas, st.comp, v
    st.prev_kkt = max(st.feas, st.comp, st.stat)
    return False


def _keep_in_domain(nlp, sub, pen, x, eta, mu):
    """Weaken ``eta_i`` where ``g_i(x)/eta_i`` left the domain of a modified barrier.

    After ``mu <- p'(g/eta, mu)`` the bound ``b(mu)`` of log-met2 moves, and a
    tightened ``eta`` may push a violated constraint out; the subproblem must start
    inside, so those entries of ``eta`` grow to ``g_i / (b_i / 2)``. For unbounded
    domains (exponential) ``g_i/eta_i`` is kept below 10 (reset to 5) against overflow.
    """
    m = nlp.m
    g, _ = nlp.constraints(x)
    b = _domain(pen, np.asarray(mu, float))
    eta = np.array(eta, dtype=float)
    eg = eta[:m]
    # unbounded domains (exponential): keep g/eta <= 10 so that exp does not overflow
    with np.errstate(all="ignore"):
        fast = float(np.max(pen.value(np.array([50.0]), np.ones(1)))) > 1e15
    limit = np.where(np.isfinite(b), 0.9 * b, 10.0 if fast else np.inf)
    target = np.where(np.isfinite(b), 0.5 * b, 5.0)
    bad = g / eg >= limit
    if np.any(bad):
        eg[bad] = g[bad] / target[bad]
        log.debug("eta weakened for %d constraint(s) to keep x inside the penalty "
                  "domain", int(np.sum(bad)))
    return eta


def _record(history, k, nlp, x, stat, feas, comp, eta, res, tol, factor, extra_inner=0,
            tag=""):
    try:
        f = nlp.f_unscaled(x)
    except NonFiniteValue:
        f = math.nan
    eta = np.asarray(eta, float)
    history.append(IterationRecord(
        k=k, f=f, feasibility=feas, stationarity=stat, complementarity=comp,
        eta_min=float(np.min(eta)) if eta.size else math.nan,
        eta_max=float(np.max(eta)) if eta.size else math.nan,
        inner_iterations=res.nit + extra_inner, inner_status=res.status + tag,
        inner_tol=tol, factor=factor))
    log.debug("outer %3d: f=%.10g feas=%.2e stat=%.2e comp=%.2e eta=[%.2e, %.2e] "
              "inner=%d (%s)", k, f, feas, stat, comp, history[-1].eta_min,
              history[-1].eta_max, res.nit, res.status)


#: Relative multiplier floor of the penalties without property (d) (quad-met1/2 with
#: Matioli's safeguard): ``mu_i >= QUAD_MU_FLOOR * max_j mu_j`` for the next
#: subproblem. Measured on the Hock-Schittkowski set with the box inner solver
#: (quad-met2 solved of 53): no floor 47, 1e-2 48, 1e-3 48, 3e-4 49, 1e-4 49,
#: 3e-5 48, 1e-5 49, 1e-6 48; reviving violated constraints to a penalty
#: rho_i = mu_i^2/eta_i of the first subproblem instead: 47.
QUAD_MU_FLOOR = 1e-4



def initial_eta(nlp, spec, pen, opts, f0, g0, h0, mu0):
    """Starting penalty parameters (length m + p), scale-aware; see :func:`minimize`."""
    m, p = nlp.m, nlp.p
    if opts.eta0 is not None:
        eta = np.asarray(opts.eta0, dtype=float)
        if eta.ndim == 0:
            eta = np.full(m + p, float(eta))
        elif eta.shape != (m + p,):
            raise InputError(f"options['eta0'] has {eta.size} entries; expected a scalar "
                             f"or m + p = {m} + {p} = {m + p} (inequalities first)")
        if np.any(~(eta > 0)):
            raise InputError("options['eta0'] must be positive")
        user = True
    else:
        viol = np.concatenate([np.maximum(g0, 0.0), np.abs(h0)])
        if spec.scaled and opts.scale_eta0 and m + p:
            # ALGENCAN's rho0 = 10 max(1,|sf f|) / max(1, |sc c+|^2 / 2) for the problem
            # scaled by sf = 1/max(1,|grad f(x0)|), sc_i = 1/max(1,|grad c_i(x0)|)
            # (Birgin & Martinez 2014, sec. 12.5); the equivalent unscaled quadratic
            # penalty g_i^2 sc_i^2 / (2 eta sf) gives eta_i = sf / (rho sc_i^2)
            sf = 1.0 / max(1.0, float(np.max(np.abs(nlp.grad(nlp.x0)))))
            Jg, Jh = nlp.jacobians(nlp.x0)
            rows = [Jg, Jh]
            jn = np.concatenate([
                np.asarray(abs(J).max(axis=1).toarray() if sp.issparse(J)
                           else np.max(np.abs(J), axis=1, initial=0.0)).ravel()
                for J in rows])
            sc = 1.0 / np.maximum(1.0, jn)
            sv = viol * sc
            rho = 10.0 * max(1.0, abs(f0) * sf) / max(1.0, 0.5 * float(sv @ sv))
            eta = np.clip(sf / (rho * sc ** 2), 1e-8, 1e8)
        elif spec.scaled:
            # ALGENCAN-like rho0 = 10 max(1,|f|) / max(1, |c|^2 / 2), eta = 1/rho
            rho = 10.0 * max(1.0, abs(f0)) / max(1.0, 0.5 * float(viol @ viol))
            eta = np.full(m + p, float(np.clip(1.0 / rho, 1e-8, 1e8)))
        else:  # barrier weight rho0 of Algorithm 5.1
            eta = np.full(m + p, 0.1 * max(1.0, abs(f0)) / max(1, m))
        user = False
        if spec.scaled:
            factor = opts.eta0_factor
            if factor is None:
                factor = facts(pen).eta0_factor
            eta = eta * factor
    if m:
        b = _domain(pen, np.asarray(mu0, float))
        y = g0 / (eta[:m] if spec.scaled else 1.0)
        out = np.flatnonzero(~(y < b))
        if out.size:
            i = int(out[0])
            where = nlp.describe(i)
            if not spec.scaled:
                raise DomainError(
                    f"x0 is outside the domain of the {pen.name} penalty: inequality {i} "
                    f"({where}) has g = {g0[i]:.6g} but the barrier needs g < {b[i]:g}. "
                    "Start from a strictly feasible x0 or use method='al'.")
            if user:
                need = g0[i] / b[i]
                raise DomainError(
                    f"x0 is outside the domain of the {pen.name} penalty for the given "
                    f"eta0: inequality {i} ({where}) has g/eta = {y[i]:.6g} >= "
                    f"b = {b[i]:g}. Use eta0 > {need:.6g} or leave eta0 unset.")
        if spec.scaled and not user:
            # keep g/eta inside (half) the domain, and O(1) for fast-growing unbounded
            # ones (a pure exponential would overflow; the extrapolated one does not)
            with np.errstate(all="ignore"):
                fast = float(np.max(pen.value(np.array([50.0]), np.ones(1)))) > 1e15
            cap = np.where(np.isfinite(b), 0.5 * b, 1.0 if fast else np.inf)
            need = np.where(g0 > 0, g0 / cap, 0.0)
            eta[:m] = np.maximum(eta[:m], need)
    return eta
