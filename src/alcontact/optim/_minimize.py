"""Public entry point :func:`minimize` and its options."""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .. import penalties as _penalties
from .._options import is_integer, is_real, show
from ..errors import InputError, NonFiniteError, UnknownNameError
from ._inner import make_inner
from ._outer import METHODS, initial_eta, run_outer
from ._problem import NLP, NonFiniteValue
from ._result import ALResult, Status
from ._safeguards import safeguard_penalty
from ._strategies import make_strategy

__all__ = ["minimize", "available_methods", "Options"]

log = logging.getLogger("alcontact.optim")


@dataclass(frozen=True)
class Options:
    """Options of :func:`minimize` (pass as a dict; unknown keys are errors).

    Attributes
    ----------
    maxiter : int
        Outer iterations (subproblems), default 100.
    maxiter_inner : int
        Newton iterations per subproblem, default 100 (measured on the
        Hock-Schittkowski set: 100 instead of 50 lets exp-met1 finish HS104 and
        HS106 at about the same total time).
    gtol : float
        Tolerance on the scaled stationarity (C1); alias ``tol``. Default 1e-8.
    feas_tol : float
        Tolerance on the feasibility (C4) ``max(g+, |h|)``; alias ``ftol``. Default 1e-8.
    ctol : float
        Tolerance on the complementarity (C2) ``max |mu_i g_i|``. Default 1e-8.
    eta0 : float or array or None
        Starting penalty parameter(s) (m inequalities then p equalities); None:
        automatic and scale-aware (see :func:`minimize`).
    mu0 : float or array
        Starting inequality multipliers (> 0 for family P), default 1.
    lam0 : float or array
        Starting equality multipliers, default 0.
    strategy : str or None
        Penalty-parameter strategy name (None: the method's default).
    strategy_options : dict or None
        Its parameters (``tau``, ``factor``, ...).
    inner : str
        Inner solver name, default ``"newton"`` (line search, Hessian shifts and a
        negative-curvature step at saddle points of small dense problems);
        ``"trust-region"`` solves the trust-region subproblem exactly for dense
        Hessians (see :func:`available_inner_solvers`).
    inner_options : dict or None
        Its parameters.
    penalty_options : dict or None
        Extra parameters for ``alcontact.penalties.make``.
    inner_tol0 : float
        Tolerance of the first subproblem (scaled gradient norm); later ones use
        ``max(gtol/10, min(inner_tol0, kkt_previous/10))``. Default 1e-2.
    mu_min, mu_max : float
        Multiplier safeguard: ``mu <- clip(p'(g/eta, mu), mu_min, mu_max)``.
        ``mu_min=None`` picks 1e-12 for penalties whose zero multiplier would
        freeze (MET 1/2, quadratic) and 0 otherwise (Rockafellar).
    eta_min, eta_max : float
        Bounds of the penalty parameter, default 1e-12 and 1e12.
    unbounded_below : float
        A subproblem value below this declares the problem unbounded, default -1e20.
    polish : bool
        Method ``"al"``: once the active-set estimate ``{i: mu_i > -g_i}`` repeats
        in two consecutive outer iterations, try a few Newton iterations on the KKT
        system of ``f`` and the active constraints; the polished point is accepted
        only if it meets every KKT tolerance (and second-order necessary conditions
        for dense problems). Default True; False gives the pure AL iteration.
    polish_maxiter : int
        Newton-KKT iterations per polish attempt, default 8.
    extrapolate : bool
        Method ``"al"``: replace a MET penalty's generator beyond ``y = b/2`` (bounded
        domain, e.g. the modified log barrier: Ben-Tal & Zibulevsky's quadratic
        extrapolation) or beyond ``y = exp_cap`` (exponential) by its second-order
        Taylor polynomial, so that the subproblem is defined everywhere and does not
        overflow. Default True; False keeps the pure penalties (domain checks and
        fraction-to-boundary steps apply).
    exp_cap : float
        Extrapolation point of fast-growing unbounded generators, default 20.
    stall_iter : int
        Stop (status ``MAXITER``, message "no progress") when the KKT error
        ``max(stationarity, feasibility, complementarity)`` has not halved in this
        many outer iterations, default 20.
    project_x0 : bool
        Move ``x0`` into the variable bounds first, by ``bound_push`` (the message
        says so; not for method ``"barrier"``). Default True.
    bound_push : float
        With ``project_x0``: 0 clips ``x0`` into the bounds (as SciPy does); a
        positive value moves each entry at least ``min(bound_push max(1, |bound|),
        bound_push (ub - lb))`` inside (IPOPT's ``bound_push``/``bound_frac``
        rule), default 1e-2. Measured on the Hock-Schittkowski set (HS16 starts
        outside its bounds): with the pushed start every AL variant reaches the
        global minimum, with the unprojected start none does.
    scale_eta0 : bool
        Automatic ``eta0`` from ALGENCAN's rule applied to the problem scaled by
        ``1/max(1, |grad f(x0)|)`` and ``1/max(1, |grad c_i(x0)|)`` (one value per
        constraint); False: the unscaled rule with one value. Default True. (With
        ``scale`` the problem is already scaled and both rules agree.)
    eta0_factor : float or None
        Multiplies the automatic ``eta0``; None takes the penalty's declared fact
        ``eta0_factor`` (:func:`alcontact.penalties.facts`; 0.1 for ``"log-met1"``:
        its modified barrier needs a stronger start; 1 otherwise).
    scale : bool
        Method ``"al"``: solve the problem scaled as ALGENCAN does, ``f`` by
        ``1/max(1, |grad f(x0)|_inf)`` and each constraint by
        ``1/max(1, |grad c_i(x0)|_inf)`` (bounds keep scale 1). The KKT tests and
        every reported quantity (``fun``, multipliers, constraint values,
        stationarity, feasibility, complementarity, history) are in the user's
        units; only ``eta`` belongs to the scaled problem. Default True.
    bounds_as : str
        Method ``"al"``: ``"box"`` (default) keeps the variable bounds exactly, as
        ALGENCAN and LANCELOT do: each subproblem is
        :math:`\\min L(x)` s.t. :math:`l \\le x \\le u`, solved by Bertsekas'
        projected Newton method (:meth:`~alcontact.optim._inner.Newton.solve_box`,
        projected-gradient stopping measure), ``x0`` is moved into the box, every
        iterate (and the Newton-KKT polish) stays in it, and the bound multipliers
        are read from the Lagrangian gradient. ``"constraints"`` penalises the
        bounds like any other inequality. The other methods always do the latter.
        Measured on the Hock-Schittkowski set (benchmarks/nlp_hs.py, problems
        solved of 53, box / constraints): rockafellar 48/48, exp-met1 48/47,
        log-met1 49/48, log-met2 48/47, quad-met2 49/44 (penalised bounds let
        iterates leave the box: HS104 reaches ``x2 ~ 1e-14`` where ``x^0.67`` is
        not smooth, HS117 becomes unbounded).
    """

    maxiter: int = 100
    maxiter_inner: int = 100
    gtol: float = 1e-8
    feas_tol: float = 1e-8
    ctol: float = 1e-8
    eta0: object = None
    mu0: object = 1.0
    lam0: object = 0.0
    strategy: str | None = None
    strategy_options: dict | None = None
    inner: str = "newton"
    inner_options: dict | None = None
    penalty_options: dict | None = None
    inner_tol0: float = 1e-2
    mu_min: float | None = None
    mu_max: float = 1e12
    eta_min: float = 1e-12
    eta_max: float = 1e12
    unbounded_below: float = -1e20
    polish: bool = True
    polish_maxiter: int = 8
    extrapolate: bool = True
    exp_cap: float = 20.0
    stall_iter: int = 20
    project_x0: bool = True
    scale_eta0: bool = True
    scale: bool = True
    eta0_factor: float | None = None
    bound_push: float = 1e-2
    bounds_as: str = "box"

    _ALIASES = {"tol": "gtol", "ftol": "feas_tol"}

    @classmethod
    def from_dict(cls, options) -> "Options":
        if options is None:
            return cls()
        if isinstance(options, Options):
            return options
        if not isinstance(options, dict):
            raise InputError(f"options must be a dict, got {type(options).__name__}")
        known = [f.name for f in dataclasses.fields(cls)]
        kw = {}
        for key, value in options.items():
            name = cls._ALIASES.get(key, key)
            if name not in known:
                raise UnknownNameError("option", key, known + list(cls._ALIASES))
            kw[name] = value
        o = cls(**kw)
        for check in _OPTION_CHECKS:
            check(o)
        return o


def _check_counts(o: Options) -> None:
    """Iteration limits: positive integers."""
    for name in ("maxiter", "maxiter_inner", "polish_maxiter", "stall_iter"):
        v = getattr(o, name)
        if not is_integer(v) or v < 1:
            raise InputError(f"options[{name!r}] = {show(v)} must be a positive integer (got "
                             f"{type(v).__name__}); e.g. {{{name!r}: {getattr(Options, name)}}}")


def _check_positive(o: Options) -> None:
    """Tolerances, bounds of ``eta`` and ``mu``, caps: positive finite numbers."""
    for name in ("gtol", "feas_tol", "ctol", "inner_tol0", "mu_max", "eta_min", "eta_max",
                 "exp_cap") + (("eta0_factor",) if o.eta0_factor is not None else ()):
        v = getattr(o, name)
        if not (is_real(v) and v > 0 and math.isfinite(v)):
            raise InputError(f"options[{name!r}] = {show(v)} must be a positive finite number (got "
                             f"{type(v).__name__}); e.g. {{{name!r}: {getattr(Options, name) or 1.0}}}")


def _check_ranges(o: Options) -> None:
    """``mu_min``, ``unbounded_below`` and ``bound_push`` in their ranges."""
    if o.mu_min is not None and not (is_real(o.mu_min) and math.isfinite(o.mu_min) and o.mu_min >= 0):
        raise InputError(f"options['mu_min'] = {show(o.mu_min)} must be a finite number >= 0 or None "
                         "(automatic)")
    if not (is_real(o.unbounded_below) and not math.isnan(o.unbounded_below)):
        raise InputError(f"options['unbounded_below'] = {show(o.unbounded_below)} must be a number, e.g. -1e20")
    if not (is_real(o.bound_push) and 0 <= o.bound_push < 0.5):
        raise InputError(f"options['bound_push'] = {show(o.bound_push)} must lie in [0, 0.5)")


def _check_flags(o: Options) -> None:
    """Switches: ``True`` or ``False``."""
    for name in ("polish", "extrapolate", "project_x0", "scale_eta0", "scale"):
        v = getattr(o, name)
        if not isinstance(v, (bool, np.bool_)):
            raise InputError(f"options[{name!r}] = {show(v)} must be True or False (got {type(v).__name__})")


def _check_names(o: Options) -> None:
    """Registry names are strings (looked up when used); ``bounds_as`` one of its two values."""
    for name, allowed in (("strategy", None), ("inner", None), ("bounds_as", ("box", "constraints"))):
        v = getattr(o, name)
        if v is None and name == "strategy":
            continue
        if not isinstance(v, str) or (allowed and v not in allowed):
            what = f"one of {', '.join(map(repr, allowed))}" if allowed else "a name (str)"
            raise InputError(f"options[{name!r}] = {show(v)} must be {what}")


def _check_starts(o: Options) -> None:
    """Starting ``eta0`` (positive, or None), ``mu0`` and ``lam0``: finite numbers or 1-D arrays."""
    for name in ("eta0", "mu0", "lam0"):
        v = getattr(o, name)
        if v is None and name == "eta0":
            continue
        a = _numbers(v, name)
        if name == "eta0" and not np.all(a > 0):
            raise InputError(f"options['eta0'] = {show(v)} must be positive (a smaller eta0 is a stronger "
                             "penalty), or None for the automatic value")


def _check_parameter_dicts(o: Options) -> None:
    """Parameters of the strategy, the inner solver and the penalty: dicts or None; ``eta_min < eta_max``."""
    for name in ("strategy_options", "inner_options", "penalty_options"):
        v = getattr(o, name)
        if v is not None and not isinstance(v, dict):
            raise InputError(f"options[{name!r}] = {show(v)} must be a dict of parameters or None "
                             f"(got {type(v).__name__})")
    if not o.eta_min < o.eta_max:
        raise InputError("options: eta_min must be smaller than eta_max")


#: The checks of :meth:`Options.from_dict`, in the order they run (the first failing one raises).
_OPTION_CHECKS = (_check_counts, _check_positive, _check_ranges, _check_flags, _check_names, _check_starts,
                  _check_parameter_dicts)


def _accepted(spec) -> list[str]:
    """Registered penalties whose declared facts the method ``spec`` accepts."""
    out = []
    for name in _penalties.available():
        try:
            ok = spec.accepts(_penalties.facts(_penalties.make(name)))
        except (InputError, TypeError):  # a user factory that needs parameters
            continue
        if ok:
            out.append(name)
    return out


def available_methods() -> list[str]:
    """Names of the registered outer methods (``"al"``, ``"barrier"``, ...)."""
    return sorted(METHODS)


_HINTS = {
    Status.MAXITER: "raise options['maxiter'], try strategy='kkt' or a smaller eta0 "
                    "(stronger penalty), or loosen gtol/feas_tol/ctol",
    Status.INNER_FAILED: "check jac/hess against finite differences, rescale the "
                         "problem, or try another penalty or eta0",
    Status.NONFINITE: "guard the callback against NaN/inf (e.g. add bounds that keep x "
                      "inside its domain)",
    Status.PENALTY_LIMIT: "the constraints may be inconsistent (infeasible problem); "
                          "check them or lower eta_min",
    Status.UNBOUNDED: "the objective may be unbounded below on the feasible set, or the "
                      "penalty too weak: decrease eta0",
}


def _numbers(value, name):
    """``value`` (a number or an array of numbers) as a float array; InputError naming the option otherwise."""
    try:
        if isinstance(value, (str, bytes, bool, np.bool_, dict)):
            raise TypeError
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"options[{name!r}] = {show(value)} must be a number or an array of numbers "
                         f"(got {type(value).__name__})") from None
    if a.ndim > 1 or not np.all(np.isfinite(a)):
        raise InputError(f"options[{name!r}] = {show(value)} must be a finite number or a 1-D array of them")
    return a


def _vector(value, size, name):
    a = _numbers(value, name)
    if a.ndim == 0:
        return np.full(size, float(a))
    if a.shape != (size,):
        raise InputError(f"options[{name!r}] has {a.size} entries; expected a scalar or "
                         f"{size}")
    return a.copy()


def minimize(fun, x0, *, jac=None, hess=None, constraints=(), bounds=None, method="al",
             penalty=None, options=None) -> ALResult:
    """Minimize ``f(x)`` subject to constraints by penalty or augmented Lagrangian methods.

    The constrained problem is converted to the dissertation's form
    :math:`\\min f(x)` s.t. :math:`g(x) \\le 0`, :math:`h(x) = 0` (problems (P) and
    (P1), chapter 5). Each outer iteration minimises the subproblem (SL)

    .. math::

        L(x, \\mu, \\eta) = f(x) + \\sum_i \\eta_i\\, p(g_i(x)/\\eta_i, \\mu_i)
            + \\sum_j \\left(\\lambda_j h_j + \\frac{h_j^2}{2\\eta_j}\\right)
        \\qquad (5.28), (5.13)

    with a Newton method, then updates :math:`\\mu_i \\leftarrow p'(g_i/\\eta_i, \\mu_i)`
    (Algorithm 5.4, corrected: the printed update uses ``p``),
    :math:`\\lambda \\leftarrow \\lambda + h/\\eta` (5.15) and ``eta`` by a strategy.

    Parameters
    ----------
    fun : callable
        ``fun(x) -> float``; with ``jac=True`` it returns ``(f, grad)``.
    x0 : array_like, shape (n,)
        Starting point.
    jac : callable, True or None
        Gradient ``jac(x) -> (n,)``; None (or a string) uses central differences.
    hess : callable or None
        Hessian ``hess(x) -> (n, n)`` dense or ``scipy.sparse``; None (or a string
        or a ``HessianUpdateStrategy``) uses finite differences of the gradient.
    constraints : NonlinearConstraint, LinearConstraint, dict or a sequence of them
        SciPy's constraint objects; ``lb == ub`` becomes an equality, a finite
        ``ub`` gives ``c - ub <= 0``, a finite ``lb`` gives ``lb - c <= 0``.
        Jacobians may be sparse; a constraint ``hess(x, v)`` returns
        :math:`\\sum_i v_i \\nabla^2 c_i` (finite differences when not callable).
    bounds : scipy.optimize.Bounds or sequence of (lb, ub) or None
        Variable bounds: for method ``"al"`` an exact box of the subproblems
        (option ``bounds_as``), for the other methods linear inequalities.
    method : str
        ``"al"`` (Algorithm 5.4, default), ``"hestenes-powell"`` (5.3),
        ``"barrier"`` (5.1), ``"exterior-penalty"`` (5.2); see
        :func:`available_methods`.
    penalty : str or None
        Inequality penalty name from :func:`alcontact.penalties.available`; None
        picks the method's default (``"exp-met1"`` for ``"al"``,
        ``"log-barrier"`` for ``"barrier"``). For ``"al"``, ``"rockafellar"``,
        ``"exp-met1"``, ``"exp-met2"``, ``"log-met1"``, ``"log-met2"``,
        ``"quad-met1"`` and ``"quad-met2"`` (the last two with the multiplier
        safeguard) are accepted.
    options : dict or None
        See :class:`Options` (``maxiter``, ``gtol``/``tol``, ``feas_tol``/``ftol``,
        ``ctol``, ``eta0``, ``mu0``, ``strategy``, ...).

    Returns
    -------
    ALResult
        Frozen result; ``status > 0`` means converged. A failure logs a warning;
        ``result.raise_for_status()`` raises :class:`~alcontact.errors.ConvergenceError`.

    Raises
    ------
    InputError
        Inconsistent sizes, bad options, constraints the method cannot handle.
    UnknownNameError
        Unknown method, penalty, strategy, inner solver or option.
    DomainError
        ``x0`` outside the domain of a barrier (method ``"barrier"`` needs
        ``g(x0) < 0``) or of a modified barrier for a user-given ``eta0``.
    NonFiniteError
        A callback returns NaN/inf at ``x0`` (later NaNs give ``Status.NONFINITE``).

    Notes
    -----
    ``eta`` divides ``g`` in (5.28), so a *smaller* ``eta`` is a *stronger*
    penalty (Algorithm 5.4 prints ``eta <- 2 eta``; section 6.3.1 says the
    opposite; measurements favour decreasing it, see the module docs). The
    default ``eta0`` is ALGENCAN-like, ``1 / (10 max(1,|f(x0)|) / max(1, |c+(x0)|^2/2))``,
    raised where needed so that ``g_i(x0)/eta_i`` lies inside half the domain of a
    modified barrier (and is at most 1 for the exponential).

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.optimize import NonlinearConstraint
    >>> from alcontact.optim import minimize
    >>> con = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, -1.0)
    >>> res = minimize(lambda x: x @ x, [1.0, 2.0], jac=lambda x: 2 * x,
    ...                hess=lambda x: 2 * np.eye(2), constraints=con)
    >>> bool(res.success), np.round(res.x, 6).tolist()
    (True, [-0.5, -0.5])
    """
    try:
        spec = METHODS[method]
    except (KeyError, TypeError):
        raise UnknownNameError("method", method, list(METHODS)) from None
    opts = Options.from_dict(options)
    pen_name, pen, known = _penalty(spec, method, penalty, opts)
    strat_name = opts.strategy or spec.strategy
    sopts = dict(spec.strategy_options) if opts.strategy is None else {}
    sopts.update(opts.strategy_options or {})
    strategy = make_strategy(strat_name, {"feas_tol": opts.feas_tol}, **sopts)
    inner = make_inner(opts.inner, **(opts.inner_options or {}))
    nlp, projected, f0, g0, h0 = _problem(fun, x0, jac, hess, constraints, bounds, spec, opts)
    _check_constraint_kinds(nlp, spec, method)
    explicit = ("eta_min" in options) if isinstance(options, Mapping) else \
        (options is not None and opts.eta_min != Options.eta_min)
    if known.eta_min is not None and not explicit:
        # a declared floor, e.g. the inverse barrier (5.3): its complementarity mu g
        # behaves like sqrt(rho), reaching ctol needs eta far below the default 1e-12
        opts = dataclasses.replace(opts, eta_min=known.eta_min)
    if spec.safeguards and spec.update_multipliers:
        pen = safeguard_penalty(pen, extrapolate=opts.extrapolate, cap=opts.exp_cap)
    hp = _penalties.make("hestenes-powell")
    mu = _vector(opts.mu0, nlp.m, "mu0")
    lam = _vector(opts.lam0, nlp.p, "lam0")
    if spec.update_multipliers and nlp.m and known.family_p and np.any(mu <= 0):
        raise InputError(f"options['mu0'] must be > 0 for the family-P penalty {pen_name!r}")
    if not spec.update_multipliers:
        lam = np.zeros(nlp.p)
    eta = initial_eta(nlp, spec, pen, opts, f0, g0, h0, mu)

    out = run_outer(nlp, spec, pen, hp, strategy, inner, opts, eta, mu, lam)
    message = _message(out, projected, nlp.has_fd)
    if out.status <= 0:
        log.warning("minimize(method=%r, penalty=%r) failed: %s", method, pen_name, message)
    try:
        fx = nlp.f_unscaled(out.x)
    except NonFiniteValue:
        fx = math.nan
    g_out, h_out, mu_out, lam_out = nlp.unscale(out.g, out.h, out.mu, out.lam)
    user_blocks, mb = _block_multipliers(nlp, out, mu_out, lam_out, bounds)
    return ALResult(
        x=out.x, fun=fx, success=bool(out.status > 0), status=Status(out.status),
        message=message, nit=out.nit, nit_inner=out.nit_inner, nfev=nlp.nfev,
        njev=nlp.njev, nhev=nlp.nhev, ncev=nlp.ncev, multipliers_ineq=mu_out,
        multipliers_eq=lam_out, multipliers=tuple(user_blocks), multipliers_bounds=mb,
        constr_ineq=g_out, constr_eq=h_out, stationarity=out.stationarity,
        feasibility=out.feasibility, complementarity=out.complementarity, eta=out.eta,
        method=method, penalty=pen_name, strategy=strat_name, inner=opts.inner,
        history=tuple(out.history))


def _penalty(spec, method, penalty, opts):
    """``(name, penalty, facts)`` of the inequality penalty: the method's default or ``penalty``, accepted by it."""
    pen_name = spec.default_penalty if penalty is None else penalty
    known_pen = list(_penalties.available())
    if not isinstance(pen_name, str) or pen_name not in known_pen:
        raise UnknownNameError("penalty", pen_name, known_pen)
    pen = _penalties.make(pen_name, **(opts.penalty_options or {}))
    known = _penalties.facts(pen)
    if not spec.accepts(known):
        raise InputError(f"method {method!r} does not take penalty {pen_name!r}; "
                         f"allowed: {', '.join(_accepted(spec))}")
    return pen_name, pen, known


def _problem(fun, x0, jac, hess, constraints, bounds, spec, opts):
    """``(nlp, projected, f0, g0, h0)``: the NLP, whether ``x0`` was moved into the bounds, values at ``x0``."""
    try:
        box = spec.box and opts.bounds_as == "box"
        nlp = NLP(fun, x0, jac=jac, hess=hess, constraints=constraints, bounds=bounds,
                  box=box)
        projected = opts.project_x0 and spec.scaled and \
            nlp.project_into_bounds(opts.bound_push)
        projected = projected or nlp.x0_clipped  # box: x0 is clipped in any case
        if opts.scale and spec.autoscale:
            nlp.set_scaling()
        f0 = nlp.f(nlp.x0)
        g0, h0 = nlp.constraints(nlp.x0)
    except NonFiniteValue as exc:
        raise NonFiniteError(f"{exc} at x0; the starting point must give finite values"
                             ) from None
    return nlp, projected, f0, g0, h0


def _check_constraint_kinds(nlp, spec, method) -> None:
    """The method handles the problem's kinds of constraints (inequalities, equalities)."""
    if nlp.m and not spec.inequalities:
        raise InputError(f"method {method!r} handles equality constraints only but the "
                         f"problem has {nlp.m} inequalities; use method='al'")
    if nlp.p and not spec.equalities:
        raise InputError(f"method {method!r} handles inequality constraints only but the "
                         f"problem has {nlp.p} equalities; use method='al'")


def _message(out, projected, has_fd) -> str:
    """The outer loop's message with what was changed or approximated, and a hint on failure."""
    message = out.message
    if projected:
        message += " (x0 was moved into the bounds)"
    if has_fd:
        message += " (some derivatives by finite differences)"
    if out.status <= 0:
        message += f"; try: {_HINTS[out.status]}"
    return message


def _block_multipliers(nlp, out, mu_out, lam_out, bounds):
    """Multipliers of the user's constraint blocks, and of the variable bounds (None without bounds)."""
    per_block = nlp.block_weights(mu_out, lam_out)
    user_blocks = [v for b, v in zip(nlp.blocks, per_block) if not b.is_bounds]
    mb = next((v for b, v in zip(nlp.blocks, per_block) if b.is_bounds), None)
    if nlp.has_box:
        # weights on x: grad f + sum mu grad g + sum lam grad h + mb = 0 (user's units)
        mb = -np.asarray(out.box_multipliers, float) / nlp.f_scale
    if mb is None and bounds is not None:
        mb = np.zeros(nlp.n)
    return user_blocks, mb
