r"""Frictionless contact algorithms on the condensed problem.

Registered by name (:func:`available_algorithms`):

``penalty``
    Pure penalty (6.10), :math:`t_N = \varepsilon_N\langle g\rangle`, with the
    penalty stiffness multiplied by ``alpha`` until the penetration tolerance is
    met (Algorithm 5.2 applied to contact).
``simo-laursen``
    Algorithm 6.1: :math:`t_N = \langle\lambda_N + \varepsilon_N g\rangle` (6.12),
    update :math:`\lambda_N \leftarrow \langle\lambda_N + \varepsilon_N g\rangle` (6.13).
``family-p``
    Algorithm 6.3 with any registered penalty satisfying (P1), (P3), (P4):
    :math:`t_N = p'(g/\eta, \lambda_N)`, update :math:`\lambda_N \leftarrow p'(g/\eta, \lambda_N)`
    (corrected 6.66). ``rockafellar`` reproduces Algorithm 6.1.
``ssn``
    Reference: semi-smooth Newton for :math:`\lambda - \max(0, \lambda + c\,g) = 0`, i.e. the
    primal-dual active set method, which solves the discrete contact problem
    exactly (no penalty) in finitely many steps.

Stopping on physical measures (all must hold): max penetration
:math:`\max g^+ / h \le` ``tol_penetration``; complementarity
:math:`\max|\lambda g|/(p_{ref} h) \le` ``tol_complementarity``; multiplier change
:math:`\|\Delta\lambda\|_\infty/p_{ref} \le` ``tol_multiplier``; the equilibrium residual
of each subproblem is driven below ``newton_tol`` by Newton's method.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .. import penalties as _pen
from .._options import as_options, check_dataclass, declared
from ..errors import InputError, UnknownNameError
from ..linalg import registered_solvers
from ._laws import eta_for_stiffness, freezes_at_zero, make_law
from ._solution import ContactIteration, ContactStatus

__all__ = ["ContactOptions", "available_algorithms", "algorithm_docs", "contact_penalties"]

logger = logging.getLogger(__name__)

#: Largest number of outer (multiplier) iterations an option accepts.
MAX_ITER = 100_000
#: Largest number of Newton iterations per subproblem an option accepts.
MAX_NEWTON = 10_000


def _solver_names() -> tuple[str, ...]:
    """Allowed ``linear_solver`` values: the rules plus every registered solver (at check time)."""
    return tuple(dict.fromkeys(("auto", "direct", "amg", *registered_solvers())))


@dataclass(frozen=True)
class ContactOptions:
    """Options of the contact algorithms (every field has a default).

    Attributes
    ----------
    eps_n : float or None
        Penalty stiffness :math:`\\varepsilon_N` (pressure per length). ``None``:
        ``penalty_scale * E' / h`` with the contact-zone element size ``h`` and
        ``E' = E/(1-nu^2)`` (plane strain, 3D) or ``E`` (plane stress).
    penalty_scale : float
        Multiplier of the automatic :math:`\\varepsilon_N`.
    tol_penetration : float
        Max penetration over ``h``.
    tol_complementarity : float
        Max :math:`|\\lambda g|` over ``p_ref h`` (``p_ref`` = largest pressure).
    tol_multiplier : float
        Max multiplier change over ``p_ref``.
    maxiter : int
        Outer iterations.
    newton_tol : float
        Relative equilibrium residual of each subproblem.
    maxiter_newton : int
        Newton iterations per subproblem.
    strategy : {"fixed", "infeasibility"}
        Penalty update: keep :math:`\\varepsilon_N`, or multiply it by ``alpha`` when the
        penetration did not drop by the factor ``tau``.
    tau, alpha : float
        Parameters of ``"infeasibility"`` (and ``alpha`` of the pure penalty).
    eps_max : float
        Largest :math:`\\varepsilon_N` relative to the initial one.
    eta_scaling : {"adaptive", "fixed"}
        Scale of family-P penalties (see :mod:`alcontact.contact._laws`).
    initial : {"penalty", "uniform"}
        Initial multipliers of family-P penalties: from one pure-penalty solve
        (floored at ``multiplier_floor`` times its largest pressure), or the
        uniform value ``eps_n * h``.
    multiplier_floor : float
        Relative lower bound keeping MET multipliers positive.
    linear_solver : {"auto", "direct", "amg", "mkl-pardiso", "cholmod", "superlu", ...}
        ``"direct"``: one sparse factorization of the stiffness (the fastest installed
        direct solver), problem condensed on the contact points
        (:mod:`alcontact.contact._discrete`). ``"amg"``: no factorization;
        full-space Newton with conjugate gradients preconditioned by smoothed-aggregation
        AMG (PyAMG; :mod:`alcontact.contact._iterative`), for meshes whose factor does not
        fit in memory. A direct solver's registry name (:func:`alcontact.linalg.registered_solvers`)
        picks that solver for the factorization. ``"auto"``: :func:`alcontact.linalg.choose_solver`
        (``"amg"`` for 3D models with more than :data:`~alcontact.linalg.AUTO_AMG_DOFS` = 250k DOFs,
        else ``"direct"``).
    """

    eps_n: float | None = declared(
        "float", None, "Normal penalty stiffness (default: `penalty_scale` E'/h).", low=0, low_open=True)
    penalty_scale: float = declared("float", 100.0, "Multiplier of the automatic stiffness E'/h.",
                                    low=0, low_open=True)
    tol_penetration: float = declared("float", 1e-8, "Stop: max penetration / h.", low=0, low_open=True)
    tol_complementarity: float = declared("float", 1e-8, "Stop: max |lambda g| / (p_max h).", low=0, low_open=True)
    tol_multiplier: float = declared("float", 1e-8, "Stop: max multiplier change / p_max.", low=0, low_open=True)
    maxiter: int = declared("int", 100, "Outer (multiplier) iterations (per load step).", low=1, high=MAX_ITER)
    newton_tol: float = declared("float", 1e-12, "Frictionless: relative residual of each Newton solve.",
                                 low=0, low_open=True)
    maxiter_newton: int = declared("int", 60, "Frictionless: Newton iterations per subproblem.",
                                   low=1, high=MAX_NEWTON)
    strategy: str = declared("str", "fixed", "Frictionless penalty update: `fixed` or `infeasibility`.",
                             choices=("fixed", "infeasibility"))
    tau: float = declared("float", 0.25, "`infeasibility`: required drop of the penetration per iteration.",
                          low=0, high=1, low_open=True, high_open=True)
    alpha: float = declared("float", 10.0, "Penalty growth factor (`infeasibility`, pure penalty).",
                            low=1, low_open=True)
    eps_max: float = declared("float", 1e10, "Largest penalty stiffness over the initial one.", low=1)
    eta_scaling: str = declared("str", "adaptive", "Scale of family-P penalties: `adaptive` or `fixed`.",
                                choices=("adaptive", "fixed"))
    initial: str = declared("str", "penalty", "Frictionless family-P initial multipliers: `penalty` or `uniform`.",
                            choices=("penalty", "uniform"))
    multiplier_floor: float = declared("float", 1e-10, "Relative floor keeping MET multipliers positive.",
                                       low=0, high=1, low_open=True, high_open=True)
    linear_solver: str = declared(
        "str", "auto", "Frictionless linear solver: `direct` (one factorization by the fastest installed "
        "solver), `amg` (PyAMG + CG, no factorization), `auto` (amg for 3D above 250k DOFs), or a registered "
        "direct solver by name.", choices=_solver_names)

    def __post_init__(self) -> None:
        check_dataclass(self, "contact")

    def validate(self) -> "ContactOptions":
        """This object: every field was checked against its declaration when it was made.

        Raises
        ------
        InputError
            Naming the field, the value, the allowed range and the default.
        """
        return check_dataclass(self, "contact")


@dataclass
class _Run:
    """Mutable outcome of one algorithm run on the current candidates."""

    r: np.ndarray
    lam: np.ndarray
    g: np.ndarray
    status: ContactStatus
    message: str
    outer: int
    newton: int
    eps: float
    residual: float
    history: list


def options_with(options, cls, overrides: dict, kind: str):
    """``options`` (``None``, a ``cls`` or a dict of its fields) with ``overrides`` applied, validated.

    Unknown field names are an :class:`~alcontact.errors.UnknownNameError` with the
    closest match and the known ones; bad values an :class:`~alcontact.errors.InputError`
    naming the key, the value, the allowed range and the default.
    """
    return as_options(cls, options, overrides, kind)


def check_solve_args(problem, algorithm, penalty, known, kind: str) -> None:
    """Entry checks of :func:`~alcontact.contact.solve` and ``solve_friction``.

    Raises
    ------
    InputError
        ``problem`` is not a :class:`~alcontact.contact.ContactProblem`, or
        ``algorithm`` / ``penalty`` are not names.
    UnknownNameError
        ``algorithm`` is not one of ``known`` (with the closest match).
    """
    from .._options import show
    from ._problem import ContactProblem

    if not isinstance(problem, ContactProblem):
        raise InputError(f"problem = {show(problem)}: expected a ContactProblem, got {type(problem).__name__}; build "
                         "one with alcontact.contact.ContactProblem(model, obstacle, contact_boundary, ...) or load "
                         "a problem file with alcontact.io.load_problem(path).problem.")
    if not isinstance(algorithm, str):
        raise InputError(f"algorithm = {show(algorithm)}: expected a name, got {type(algorithm).__name__}; one of "
                         f"{', '.join(sorted(known))}.")
    if algorithm not in known:
        raise UnknownNameError(f"{kind}algorithm", algorithm, list(known))
    if penalty is not None and not isinstance(penalty, str):
        raise InputError(f"penalty = {show(penalty)}: expected a name or None, got {type(penalty).__name__}; one of "
                         f"{', '.join(contact_penalties())}.")


#: The penalty of each algorithm that does not take one (frictionless and frictional).
FIXED_PENALTIES = {"simo-laursen": "rockafellar", "penalty": "exterior-quadratic", "ssn": "none"}


def resolve_penalty(algorithm: str, penalty: str | None, default: str) -> str:
    """Penalty name an algorithm runs with: its fixed one, or ``penalty`` (``default``) for family-p.

    A penalty given to an algorithm with a fixed one, or one not usable by Algorithm
    6.3 / 6.4, is an error naming the way out.
    """
    if algorithm in FIXED_PENALTIES:
        fixed = FIXED_PENALTIES[algorithm]
        if penalty not in (None, fixed):
            raise InputError(
                f"algorithm {algorithm!r} uses the {fixed!r} penalty; got penalty={penalty!r}. "
                "Use algorithm='family-p' to choose a penalty."
            )
        return fixed
    name = penalty or default
    # only the named penalty's facts (the list of all of them costs about a millisecond per solve)
    if name not in _pen.available() or not _pen.facts(_pen.make(name)).usable_for_contact:
        raise UnknownNameError("contact penalty", name, contact_penalties())
    return name


def contact_penalties() -> list[str]:
    """Registered penalties usable by Algorithm 6.3: those declaring ``usable_for_contact``.

    That fact defaults to (P1), (P3), (P4) and not ``equality_only``
    (:func:`alcontact.penalties.facts`).
    """
    return [name for name in _pen.available() if _pen.facts(_pen.make(name)).usable_for_contact]


def _measures(dc, lam, g, lam_old):
    h = dc.h
    pref = max(float(np.max(lam, initial=0.0)), 1e-300)
    pen = float(np.max(g, initial=0.0)) / h
    with np.errstate(over="ignore"):  # huge loads: an infinite measure is "not complementary"
        compl = float(np.max(np.abs(lam * g), initial=0.0)) / (pref * h)
    dlam = float(np.max(np.abs(lam - lam_old), initial=0.0)) / pref
    return pen, compl, dlam


def _converged(opts, pen, compl, dlam):
    return pen <= opts.tol_penetration and compl <= opts.tol_complementarity and dlam <= opts.tol_multiplier


def _initial_multipliers(dc) -> np.ndarray:
    """Starting multipliers: zero, or the warm start a load-stepped problem offers (``dc.initial_multipliers``)."""
    warm = getattr(dc, "initial_multipliers", None)
    return np.zeros(dc.cand.size) if warm is None else np.asarray(warm(), dtype=float)


def _penalty_solve(dc, opts, eps, r0):
    pen = _pen.make("rockafellar")
    law = make_law(pen, np.full(dc.cand.size, 1.0 / eps))
    lam0 = np.zeros(dc.cand.size)
    return dc.subproblem(law, lam0, r0, tol=opts.newton_tol, maxiter=opts.maxiter_newton)


def run_penalty(dc, opts, eps0, penalty_name=None) -> _Run:
    """Pure penalty (6.10), stiffness raised by ``alpha`` until the penetration tolerance is met."""
    eps = eps0
    r = dc.start()
    hist, newton = [], 0
    lam_old = np.zeros(dc.cand.size)
    for k in range(1, opts.maxiter + 1):
        out = _penalty_solve(dc, opts, eps, r)
        newton += out.iterations
        r = out.state
        lam = out.t
        pen, compl, dlam = _measures(dc, lam, out.g, lam_old)
        hist.append(ContactIteration(k, pen, compl, dlam, out.residual, out.iterations, eps, int(np.sum(lam > 0))))
        logger.info("penalty iteration %d: eps_N %.3e, penetration %.2e h", k, eps, pen)
        if not out.converged:
            return _Run(r, lam, out.g, ContactStatus.NEWTON_FAILED,
                        f"Newton failed in penalty iteration {k}: {out.reason}", k, newton, eps, out.residual, hist)
        if pen <= opts.tol_penetration:
            return _Run(r, lam, out.g, ContactStatus.CONVERGED, "penetration tolerance met", k, newton, eps,
                        out.residual, hist)
        if eps * opts.alpha > opts.eps_max * eps0:
            return _Run(r, lam, out.g, ContactStatus.PENALTY_LIMIT,
                        f"penetration {pen:.2e} h still above tol_penetration={opts.tol_penetration:.1e} at the "
                        f"largest penalty {eps:.3e}; use an augmented Lagrangian algorithm or loosen the tolerance",
                        k, newton, eps, out.residual, hist)
        eps *= opts.alpha
        lam_old = lam
    return _Run(r, lam, out.g, ContactStatus.MAXITER, "maximum iterations", opts.maxiter, newton, eps,
                out.residual, hist)


#: inexact subproblems: Newton tolerance of (S) = min(forcing * dlam, dlam**2), dlam the last
#: relative multiplier change (the quadratic term tightens the solves where Newton is quadratic)
_INEXACT_FORCING = 1e-3
#: inexact subproblems: Newton tolerance of the first subproblem of a solve
_INEXACT_FIRST = 1e-2


#: barrier starts: the first force scale closes the penetrations with this safety factor
_PUSH_MARGIN = 1.5


def _first_push(g, g_doubled, bound) -> float:
    r"""First force scale :math:`s` of the barrier start (contact forces times :math:`1 + s`).

    The gaps are affine in the scale (exactly on the condensed and AMG paths, to first order
    in finite deformation): :math:`g(s) = g - s\,d` with :math:`d = g - g(1)` from the
    doubled forces. The smallest scale that closes every penetration outside the domain,
    :math:`\max_i g_i / d_i`, times :data:`_PUSH_MARGIN`, keeps the start next to the
    penalty solution: the former fixed first scale 0.5 (50 % more contact force) cost the
    first MET 2 subproblem about 15 Newton steps instead of a few. Capped at 0.5; the
    caller doubles it while the start is still outside the domain.
    """
    d = g - g_doubled
    viol = (g >= 0.99 * bound) & (d > 0) & (g > 0)
    if not np.any(viol):
        return 0.5
    need = float(np.max(g[viol] / d[viol]))
    return float(min(0.5, max(_PUSH_MARGIN * need, 1e-12)))


def run_al(dc, opts, eps0, penalty_name="rockafellar") -> _Run:
    """Algorithms 6.1 / 6.3 (outer loop; see module doc).

    A model may ask for inexact subproblems (``dc.inexact_subproblems``: the Newton
    tolerance of (S) follows the last multiplier change, and the loop stops only after a
    subproblem solved to ``newton_tol``) and offer a second-order multiplier update for
    penalties that do not freeze at zero (``dc.multiplier_step(law, lam, out)``, a Newton
    step on the dual with the same fixed point; ``None`` keeps the first-order update).
    The stopping tests are unchanged: they measure the first-order update's change.
    """
    pen = _pen.make(penalty_name)
    n = dc.cand.size
    eps = eps0
    hist, newton, outer0 = [], 0, 0
    needs_positive = freezes_at_zero(pen)  # MET 1/2: a zero multiplier would never revive
    # ---- initial multipliers and starting point
    if not needs_positive:  # Algorithm 6.1: start from lambda = 0 (or the last load step's pressures)
        lam = _initial_multipliers(dc)
        r = dc.start()
    elif opts.initial == "penalty":
        out = _penalty_solve(dc, opts, eps, dc.start())
        newton += out.iterations
        outer0 = 1
        lam = out.t.copy()
        r = out.state.copy()
        hist.append(ContactIteration(0, float(np.max(out.g, initial=0)) / dc.h, np.nan, np.nan, out.residual,
                                     out.iterations, eps, int(np.sum(lam > 0))))
    else:
        lam = np.full(n, eps * dc.h)
        r = dc.start()
    pref = max(float(np.max(lam, initial=0.0)), eps * dc.h * 1e-6)
    floor = opts.multiplier_floor * pref
    if needs_positive:
        lam = np.maximum(lam, floor)
    eta = eta_for_stiffness(pen, lam, eps)
    law = make_law(pen, eta)
    # barrier-type penalties: the start must lie inside the domain g < eta b; pushing
    # harder (scaling the contact forces up) closes the penetrations
    bound = law.gap_bound(lam)
    scale = 0.5
    g_start = dc.gaps(r)
    outside = np.any(g_start >= 0.99 * bound)  # a Macaulay law (Algorithm 6.1) has no bound: no solve
    pushed = False
    if outside:
        doubled = dc.scale_forces(r, 2.0)
        pushed = not np.array_equal(doubled, r)  # any contact force to scale up?
        scale = _first_push(g_start, dc.gaps(doubled), bound)
    while outside and np.any(dc.gaps(r) >= 0.99 * bound) and pushed and scale < 1e6:
        trial = dc.scale_forces(r, 1 + scale)
        if not np.any(dc.gaps(trial) >= 0.99 * bound):
            r = trial
            break
        scale *= 2
    if np.any(dc.gaps(r) >= bound):
        return _Run(r, lam, dc.gaps(r), ContactStatus.NEWTON_FAILED,
                    f"no starting point inside the domain of penalty {penalty_name!r}; use eta_scaling='adaptive' "
                    "or a penalty with unbounded domain (exp-met1)", 0, newton, eps, np.inf, hist)
    pen_prev = np.inf
    out = None
    # inexact subproblems (a model that asks for them, e.g. finite deformation): the Newton
    # tolerance of (S) follows the last multiplier change (forcing term _INEXACT_FORCING); the
    # loop stops only after a subproblem solved to newton_tol
    inexact = bool(getattr(dc, "inexact_subproblems", False))
    second_order = getattr(dc, "multiplier_step", None)
    inner_tol = max(opts.newton_tol, _INEXACT_FIRST) if inexact else opts.newton_tol
    for k in range(1, opts.maxiter + 1):
        out = dc.subproblem(law, lam, r, tol=inner_tol, maxiter=opts.maxiter_newton)
        newton += out.iterations
        if out.reason == "the penalty returned NaN" or not np.all(np.isfinite(out.t)):
            return _Run(r, lam, out.g, ContactStatus.NONFINITE,
                        f"penalty {penalty_name!r} produced non-finite (NaN/inf) tractions in iteration {k}; "
                        "check the penalty's formulas, lower penalty_scale or use another penalty",
                        outer0 + k, newton, eps, out.residual, hist)
        if not out.converged:
            return _Run(out.state, lam, out.g, ContactStatus.NEWTON_FAILED,
                        f"Newton failed in outer iteration {k}: {out.reason}; try penalty_scale < 1 or "
                        "algorithm='ssn'", outer0 + k, newton, eps, out.residual, hist)
        r = out.state
        lam_new = out.t.copy()  # multiplier update: lambda <- p'(g/eta, lambda)
        if needs_positive:
            lam_new = np.maximum(lam_new, floor)
        elif second_order is not None:  # a model may offer a Newton step on the dual (same fixed point)
            better = second_order(law, lam, out)
            if better is not None:
                lam_new = better
        pen_k, compl, dlam = _measures(dc, out.t, out.g, lam)
        hist.append(ContactIteration(outer0 + k, pen_k, compl, dlam, out.residual, out.iterations, eps,
                                     int(np.sum(out.g > -opts.tol_penetration * dc.h))))
        lam = lam_new
        logger.info("outer %d: penetration %.2e h, complementarity %.2e, multiplier change %.2e, %d Newton",
                    outer0 + k, pen_k, compl, dlam, out.iterations)
        if _converged(opts, pen_k, compl, dlam) and inner_tol <= opts.newton_tol:
            return _Run(r, out.t, out.g, ContactStatus.CONVERGED, "converged", outer0 + k, newton, eps,
                        out.residual, hist)
        if inexact:
            inner_tol = max(opts.newton_tol, min(_INEXACT_FORCING * dlam, dlam**2))
            if _converged(opts, pen_k, compl, dlam):
                inner_tol = opts.newton_tol
        if (opts.strategy == "infeasibility" and pen_k > opts.tau * pen_prev and pen_k > opts.tol_penetration
                and eps * opts.alpha <= opts.eps_max * eps0):
            eps *= opts.alpha
            if opts.eta_scaling == "fixed":
                eta = eta / opts.alpha
        pen_prev = pen_k
        if opts.eta_scaling == "adaptive":
            eta_new = eta_for_stiffness(pen, lam, eps)
            # stay inside the domain of barrier-type penalties at the warm start
            bnd = eta_new * np.asarray(pen.domain_upper(lam), dtype=float)
            eta = np.where(out.g < 0.99 * bnd, eta_new, eta)
        law = make_law(pen, eta)
    return _Run(r, out.t, out.g, ContactStatus.MAXITER,
                f"maximum outer iterations ({opts.maxiter}) reached; raise maxiter, use strategy='infeasibility' "
                "or a larger penalty_scale", outer0 + opts.maxiter, newton, eps, out.residual, hist)


def run_ssn(dc, opts, eps0, penalty_name=None) -> _Run:
    r"""Primal-dual active set / semi-smooth Newton on :math:`\lambda = \max(0, \lambda + c g)`.

    Each step enforces :math:`g_A = 0` on the active set and zero pressure elsewhere
    (``dc.solve_active``: a dense solve on the Delassus operator, or an inner
    augmented Lagrangian with AMG-CG on the factorization-free path).
    """
    n = dc.cand.size
    c = eps0
    state = dc.start()
    lam = _initial_multipliers(dc)
    g = dc.gaps(state)
    active = (lam + c * g) > 0
    hist = []
    seen = set()
    for k in range(1, opts.maxiter + 1):
        try:
            state, lam_new, g = dc.solve_active(active, lam, state, c)
        except np.linalg.LinAlgError:  # the active set's rows of the Delassus operator are dependent
            return _Run(state, lam, g, ContactStatus.NEWTON_FAILED,
                        f"singular active-set system at iteration {k} ({int(active.sum())} active points); use "
                        "algorithm='simo-laursen'", k, k, c, 0.0, hist)
        new_active = (lam_new + c * g) > 0
        pen, compl, dlam = _measures(dc, lam_new, g, lam)
        hist.append(ContactIteration(k, pen, compl, dlam, 0.0, 1, c, int(active.sum())))
        logger.info("active-set iteration %d: %d active, penetration %.2e h", k, active.sum(), pen)
        lam = lam_new
        kkt = np.all(lam >= -1e-10 * max(lam.max(initial=0), 1e-300)) and pen <= max(opts.tol_penetration, 1e-12)
        if kkt and (np.array_equal(new_active, active) or compl <= opts.tol_complementarity):
            # converged: the active set repeats, or it changes only at degenerate points (lambda = g = 0)
            return _Run(state, np.maximum(lam, 0), g, ContactStatus.CONVERGED, "active set settled", k, k, c, 0.0,
                        hist)
        key = new_active.tobytes()
        if key in seen:
            return _Run(state, lam, g, ContactStatus.NEWTON_FAILED,
                        "the active-set iteration cycles; use algorithm='simo-laursen'", k, k, c, 0.0, hist)
        seen.add(key)
        active = new_active
    return _Run(state, lam, g, ContactStatus.MAXITER, "maximum active-set iterations", opts.maxiter, opts.maxiter,
                c, 0.0, hist)


_ALGORITHMS: dict[str, tuple[Callable, str]] = {
    "penalty": (run_penalty, "pure penalty (6.10), stiffness raised until the penetration tolerance is met"),
    "simo-laursen": (run_al, "Algorithm 6.1: augmented Lagrangian with the Macaulay update (6.13)"),
    "family-p": (run_al, "Algorithm 6.3: augmented Lagrangian with a family-P penalty (corrected 6.66)"),
    "ssn": (run_ssn, "reference: semi-smooth Newton / primal-dual active set, exact (no penalty)"),
}


def available_algorithms() -> list[str]:
    """Names of the frictionless contact algorithms."""
    return sorted(_ALGORITHMS)


def algorithm_docs() -> dict[str, str]:
    """One line of documentation per algorithm."""
    return {k: v[1] for k, v in sorted(_ALGORITHMS.items())}


def get_algorithm(name: str):
    if name not in _ALGORITHMS:
        raise UnknownNameError("algorithm", name, list(_ALGORITHMS))
    return _ALGORITHMS[name][0]
