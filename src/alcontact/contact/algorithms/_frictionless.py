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

import dataclasses
import logging
from dataclasses import dataclass, field
from typing import Any, Callable, ClassVar, Mapping

import numpy as np

from ... import penalties as _pen
from ..._options import as_options, check_dataclass, declarations, declared
from ...errors import InputError, UnknownNameError
from ...linalg import registered_solvers, select_solver
from ...optim import StrategyState, available_strategies, make_strategy
from ..laws._normal import eta_for_stiffness, freezes_at_zero, make_law
from ..solution._solution import ContactIteration, ContactStatus
from ..systems._protocol import ContactSystem


logger = logging.getLogger(__name__)

#: Largest number of outer (multiplier) iterations an option accepts.
MAX_ITER = 100_000
#: Largest number of Newton iterations per subproblem an option accepts.
MAX_NEWTON = 10_000


def _solver_names() -> tuple[str, ...]:
    """Allowed ``linear_solver`` values: the rules and every registered solver (at check time).

    Each runs where it is named (:func:`alcontact.linalg.select_solver`): an exact one factorizes,
    an approximate one (``kind="iterative"``) preconditions the Krylov solves.
    """
    return tuple(dict.fromkeys(("auto", "direct", "amg", *registered_solvers())))


#: Largest ``max_cutbacks`` an option accepts (0.5**50 of an increment is below round-off).
MAX_CUTBACKS = 50


@dataclass(frozen=True)
class ContactOptions:
    """Options of every contact solver, frictionless and frictional (every field has a default).

    One options type for :func:`~alcontact.contact.solve` in every case (and its deprecated wrappers).
    A solver ignores the fields it has no use for: those marked *frictionless* below are
    read by the frictionless algorithms only, those marked *friction* (declared with
    ``only="friction"``) by the frictional ones only.

    Attributes
    ----------
    eps_n : float or None
        Penalty stiffness :math:`\\varepsilon_N` (pressure per length). ``None``:
        ``penalty_scale * E' / h`` with the contact-zone element size ``h`` and
        ``E' = E/(1-nu^2)`` (plane strain, 3D) or ``E`` (plane stress).
    penalty_scale : float or None
        Multiplier of the automatic :math:`\\varepsilon_N`. ``None``: the algorithm's
        default (:attr:`Algorithm.defaults`): 100, and 10 for Algorithms 6.2 / 6.4 with Coulomb
        friction at finite deformation (:data:`~alcontact.contact.algorithms._coulomb.FINITE_AL_DEFAULTS`:
        the stiff penalty costs Newton iterations in the first subproblem of every sliding
        step; the converged solution does not depend on it).
    tol_penetration : float
        Max penetration over ``h`` (TOL1 of Algorithm 6.2, relative).
    tol_complementarity : float
        Max :math:`|\\lambda g|` over ``p_ref h`` (``p_ref`` = largest pressure).
    tol_multiplier : float
        Max multiplier change over ``p_ref`` (with friction: of :math:`(\\lambda_N, \\lambda_T)`).
    maxiter : int
        Outer iterations (per load step).
    newton_tol : float or None
        Relative residual of each Newton solve (also of the semi-smooth Newton references).
        ``None``: the default of the algorithm's registry entry (:class:`Algorithm`):
        ``1e-12`` frictionless, ``1e-11`` with friction.
    maxiter_newton : int or None
        Newton iterations per subproblem; ``None``: the algorithm's default, ``60``
        frictionless, ``200`` with friction.
    strategy : str
        Frictionless penalty update between the outer iterations of Algorithms 6.1 / 6.3: a
        rule of the registry shared with :mod:`alcontact.optim`
        (:func:`alcontact.optim.available_strategies`); the rule's factor multiplies
        :math:`\\varepsilon_N` (never beyond ``eps_max``). ``"fixed"`` keeps it,
        ``"infeasibility"`` multiplies it by ``alpha`` when the penetration did not drop by the
        factor ``tau``.
    tau, alpha : float
        Parameters offered to the rule (``tau``, ``factor``; ``feas_tol`` is
        ``tol_penetration``); ``alpha`` is also the growth of the pure penalty and of the
        ``log-barrier`` stiffness (its barrier parameter falls by ``alpha``).
    eps_max : float
        Largest :math:`\\varepsilon_N` relative to the initial one.
    eta_scaling : {"adaptive", "fixed"}
        Scale of family-P penalties (see :mod:`alcontact.contact.laws._normal`).
    initial : {"penalty", "uniform"}
        Frictionless: initial multipliers of family-P penalties: from one pure-penalty
        solve (floored at ``multiplier_floor`` times its largest pressure), or the
        uniform value ``eps_n * h``. At finite deformation (load steps) the penalty solve
        of a step starts from the step's predicted pressures with the entry rule, and its
        dual Newton step gives the initial multipliers (``_penalty_start``,
        :attr:`ContactSystem.warm_penalty_start
        <alcontact.contact.systems._protocol.ContactSystem.warm_penalty_start>`).
    multiplier_floor : float
        Relative lower bound keeping MET multipliers positive.
    linear_solver : {"auto", "direct", "amg", "mkl-pardiso", "cholmod", "superlu", ...}
        ``"direct"``: one sparse factorization of the stiffness (the fastest
        installed direct solver), problem condensed on the contact points
        (:mod:`alcontact.contact.systems._condensed`). ``"amg"``: no factorization;
        full-space Newton with conjugate gradients preconditioned by smoothed-aggregation
        AMG (PyAMG; :mod:`alcontact.contact.systems._krylov`, with friction
        :mod:`alcontact.contact.systems._krylov`), for meshes whose factor does not
        fit in memory; at finite deformation (penalty, Algorithm 6.1, Algorithm 6.3) each Newton
        system by CG with an AMG hierarchy kept across iterations and an inexact-Newton forcing term
        (:mod:`alcontact.contact.systems._full_space`). Any registry name (:func:`alcontact.linalg.registered_solvers`)
        runs that solver on every path (:func:`alcontact.linalg.select_solver`): a direct one factorizes,
        an iterative one (``kind="iterative"``) preconditions the Krylov solves (GMRES around its factor of
        each Newton matrix where an algorithm has no AMG path). ``"auto"``: :func:`alcontact.linalg.choose_solver`
        (``"amg"`` for 3D models with more than :data:`~alcontact.linalg.AUTO_AMG_DOFS` = 250k DOFs,
        else ``"direct"``). Only the algorithms
        whose registry entry lists the ``amg`` path (:attr:`Algorithm.linear_solvers`) take
        ``"amg"``; the others run on a direct factorization (``"auto"``: the fastest installed one).
    subproblems : {"inexact", "exact"}
        Frictionless Algorithms 6.1 / 6.3: ``"inexact"``: where the model declares it
        (:attr:`ContactSystem.inexact_subproblems <alcontact.contact.systems._protocol.ContactSystem.inexact_subproblems>`:
        finite deformation, the AMG path above ``INEXACT_DOFS`` free DOFs) the Newton tolerance of each
        subproblem (S) follows the last multiplier change, ``min(1e-3 dlam, dlam**2)`` (the first one
        ``1e-2``), and the loop stops only after a subproblem solved to ``newton_tol``; ``"exact"``:
        every subproblem to ``newton_tol`` (e.g. to observe Newton's quadratic convergence; half-cylinder
        P2 n = 8, 20 steps, Algorithm 6.1: 3.10 Newton per step inexact, more exact).
    predictor : {"auto", "tangent"}
        Finite deformation: the start of a load step. ``"auto"``: the secant predictor (the last two
        converged steps extrapolated, no assembly) where the loading is proportional, the slide predictor
        (state and pressures carried along with an obstacle that translates along the contact zone,
        :math:`u(X) \\leftarrow u(X - \\Delta c)`) where it slides, else the tangent predictor (one assembly
        and solve); ``"tangent"``: the tangent predictor in every step. Same solutions; ``"auto"`` costs
        fewer assembly + solves (``docs/benchmarks/finite.md``, ``docs/benchmarks/ironing.md``).
    slide_start_reach : float
        Finite deformation, Algorithm 6.3 after the slide predictor: the penalty start shifts the
        multipliers of the pressed points so that their starting tractions are the carried pressures,
        but only at points open by at most ``slide_start_reach`` times ``h`` at the predicted state
        (beyond the contact edge the carried pressure is interpolated from a pressed neighbour). A value
        above the candidate margin (2) shifts every pressed point. Measured, Newton per sliding step of
        exp-met1 (mean / max, 40 steps) for every pressed point, 0, 0.02, 0.03, 0.05, 0.07, 0.1: ironing
        3d-s 9.85/14, 6.92/10, 6.33/10, 6.28/10, 5.58/10, 6.25/8, 6.25/8; 2d-s 6.55/10, 5.92/8, 5.25/8,
        5.03/6, 5.00/6, 6.40/8, 6.55/10 (``docs/benchmarks/ironing.md``, issue 18, with the penalty
        start's entry solve to ``newton_tol``, as then). The semi-smooth Newton reference (``ssn``)
        starts with the same points active (those with carried pressure open by at most this times
        ``h``, besides its rule :math:`\\lambda + c\\,g > 0`;
        :meth:`~alcontact.contact.systems._full_space.FiniteContact.initial_active`).
    eps_t : float or None
        Friction: tangential penalty stiffness :math:`\\varepsilon_T`; ``None``: ``tangential_scale * eps_n``.
    tangential_scale : float
        Friction: :math:`\\varepsilon_T / \\varepsilon_N` of the automatic ``eps_t``.
    tol_slip : float
        Friction: max :math:`|u_{T,n+1} - u_{T,n}|/h` at stick points (TOL2 of Algorithm 6.2).
    max_cutbacks : int
        Friction: failed attempts allowed per requested load step before giving up.
    cutback_factor : float
        Friction: fraction of the failed increment tried next.
    eta_floor : float
        Friction, family-P: the scale :math:`\\eta` is computed from
        :math:`\\max(\\lambda_N, \\text{eta\\_floor}\\, p_{ref})`, so points that enter
        contact with a tiny multiplier do not get an exploding law.
    margin : float
        Friction: candidate points: largest free gap over the history above ``-margin`` times
        the largest free penetration (more are added when they penetrate).
    radius : {"multiplier", "traction"}
        Friction: radius of the Coulomb disc inside an AL subproblem: :math:`\\mu\\lambda_N`
        (fixed, as in (6.2c): the subproblem has a convex potential, robust
        Newton) or :math:`\\mu t_N(g)` (coupled, non-symmetric tangent). Both
        converge to the same step solution. With ``"multiplier"`` and the ``"newton"``
        update the small-kinematics direct path takes the coupled radius in the first
        subproblem of a step (points entering contact stick at once; hybrid radius).
    multiplier_update : {"newton", "first-order"}
        Friction: outer update of Algorithms 6.2 / 6.4. ``"first-order"``: (6.2b)/(6.2c),
        :math:`\\lambda \\leftarrow t(\\lambda)`. ``"newton"``: a second-order
        multiplier iteration (Bertsekas) on the fixed point :math:`\\lambda = t(\\lambda)`
        with the exact sensitivity of the subproblem solution; it falls back to the
        first-order update for the rest of the step as soon as the multiplier
        change does not halve. It also starts every step from the tangent
        predictor :math:`\\lambda_n + (d\\lambda^*/dy_f)\\Delta y_f` of the last
        converged step. Same stopping test, same solution. At finite deformation
        Algorithms 6.2 / 6.4 take it with the sensitivity of the full-space subproblem
        (no tangent predictor), with every penalty (a barrier-type one, log MET 1/2, since issue 18).
    """

    #: word naming this class's fields in messages (``"contact option maxiter = ..."``)
    _KIND: ClassVar[str] = "contact"

    eps_n: float | None = declared(
        "float", None, "Normal penalty stiffness (default: `penalty_scale` E'/h).", low=0, low_open=True)
    penalty_scale: float | None = declared(
        "float", None, "Multiplier of the automatic stiffness E'/h (default: the algorithm's, 100; 10 for "
        "simo-laursen and family-p with friction at finite deformation).", low=0, low_open=True)
    tol_penetration: float = declared("float", 1e-8, "Stop: max penetration / h.", low=0, low_open=True)
    tol_complementarity: float = declared("float", 1e-8, "Stop: max |lambda g| / (p_max h).", low=0, low_open=True)
    tol_multiplier: float = declared("float", 1e-8, "Stop: max multiplier change / p_max.", low=0, low_open=True)
    maxiter: int = declared("int", 100, "Outer (multiplier) iterations (per load step).", low=1, high=MAX_ITER)
    newton_tol: float | None = declared(
        "float", None, "Relative residual of each Newton solve (default: the algorithm's, 1e-12 frictionless, "
        "1e-11 with friction).", low=0, low_open=True)
    maxiter_newton: int | None = declared(
        "int", None, "Newton iterations per subproblem (default: the algorithm's, 60 frictionless, 200 with "
        "friction).", low=1, high=MAX_NEWTON)
    strategy: str = declared("str", "fixed", "Frictionless penalty update rule (shared with `alcontact.optim`): "
                             "`fixed`, `infeasibility`, ...", choices=available_strategies)
    tau: float = declared("float", 0.25, "`infeasibility`: required drop of the penetration per iteration.",
                          low=0, high=1, low_open=True, high_open=True)
    alpha: float = declared("float", 10.0, "Penalty growth factor (`infeasibility`, pure penalty, `log-barrier`).",
                            low=1, low_open=True)
    eps_max: float = declared("float", 1e10, "Largest penalty stiffness over the initial one.", low=1)
    eta_scaling: str = declared("str", "adaptive", "Scale of family-P penalties: `adaptive` or `fixed`.",
                                choices=("adaptive", "fixed"))
    initial: str = declared("str", "penalty", "Frictionless family-P initial multipliers: `penalty` or `uniform`.",
                            choices=("penalty", "uniform"))
    multiplier_floor: float = declared("float", 1e-10, "Relative floor keeping MET multipliers positive.",
                                       low=0, high=1, low_open=True, high_open=True)
    linear_solver: str = declared(
        "str", "auto", "Linear solver: `direct` (one factorization by the fastest installed solver), `amg` "
        "(PyAMG + CG/GMRES, no factorization; at finite kinematics penalty, simo-laursen and family-p), `auto` (amg where available for 3D above "
        "250k DOFs, else direct), or any registered solver by name (a direct one factorizes, an iterative one "
        "preconditions the Krylov solves).", choices=_solver_names)
    subproblems: str = declared(
        "str", "inexact", "Algorithms 6.1/6.3: `inexact` (Newton tolerance of a subproblem from the last multiplier "
        "change where the model offers it: finite deformation, large AMG models) or `exact` (every subproblem to "
        "newton_tol).", choices=("inexact", "exact"))
    predictor: str = declared(
        "str", "auto", "Finite deformation: load-step predictor: `auto` (secant where the loading is proportional, "
        "slide where the obstacle slides, else tangent) or `tangent`.", choices=("auto", "tangent"))
    slide_start_reach: float = declared(
        "float", 0.05, "Finite deformation, after the slide predictor: family-p's penalty start shifts, and ssn "
        "starts active, the pressed points open by at most this x h.", low=0)
    # ---- read by the frictional solvers only
    eps_t: float | None = declared("float", None, "Friction: tangential penalty stiffness (default: "
                                   "`tangential_scale` eps_n).", low=0, low_open=True, only="friction")
    tangential_scale: float = declared("float", 1.0, "Friction: eps_t / eps_n.", low=0, low_open=True,
                                       only="friction")
    tol_slip: float = declared("float", 1e-8, "Friction: stop: max slip change at stick points / h.", low=0,
                               low_open=True, only="friction")
    max_cutbacks: int = declared("int", 6, "Friction: failed attempts per load step before giving up.", low=0,
                                 high=MAX_CUTBACKS, only="friction")
    cutback_factor: float = declared("float", 0.5, "Friction: fraction of a failed increment tried next.",
                                     low=0, high=1, low_open=True, high_open=True, only="friction")
    eta_floor: float = declared("float", 1e-2, "Friction, family-P: relative floor of the multiplier in eta.",
                                low=0, high=1, low_open=True, only="friction")
    margin: float = declared("float", 0.25, "Friction: candidate points: free gap above -margin x max "
                             "penetration.", low=0, only="friction")
    radius: str = declared("str", "multiplier", "Friction: Coulomb disc in a subproblem: `multiplier` or "
                           "`traction`.", choices=("multiplier", "traction"), only="friction")
    multiplier_update: str = declared(
        "str", "newton", "Friction: AL multiplier update: `newton` (second-order, falls back to first-order) or "
        "`first-order`.", choices=("newton", "first-order"), only="friction")

    def __post_init__(self) -> None:
        check_dataclass(self, self._KIND)

    def validate(self) -> "ContactOptions":
        """This object: every field was checked against its declaration when it was made.

        Raises
        ------
        InputError
            Naming the field, the value, the allowed range and the default.
        """
        return check_dataclass(self, self._KIND)

    def resolved(self, algorithm: "Algorithm") -> "ContactOptions":
        """These options with every automatic (``None``) field of ``algorithm.defaults`` (over
        :data:`BASE_DEFAULTS`, which an entry without defaults gets) filled in."""
        fill = {k: v for k, v in {**BASE_DEFAULTS, **algorithm.defaults}.items() if getattr(self, k) is None}
        return dataclasses.replace(self, **fill) if fill else self


def friction_only_options() -> tuple[str, ...]:
    """Names of the :class:`ContactOptions` fields that only the frictional solvers read."""
    return tuple(o.name for o in declarations(ContactOptions) if o.only == "friction")


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


def options_with(options, cls, overrides: dict, kind: str, algorithm: "Algorithm | None" = None):
    """``options`` (``None``, a ``cls`` or a dict of its fields) with ``overrides`` applied, validated.

    Unknown field names are an :class:`~alcontact.errors.UnknownNameError` with the
    closest match and the known ones; bad values an :class:`~alcontact.errors.InputError`
    naming the key, the value, the allowed range and the default. With ``algorithm``
    (a registry entry, :class:`Algorithm`) the automatic (``None``) options get the
    entry's defaults (:meth:`ContactOptions.resolved`) and the options are checked
    against what the entry supports (:meth:`Algorithm.check_options`).
    """
    opts = as_options(cls, options, overrides, kind)
    if algorithm is not None:
        algorithm.check_options(opts)
        opts = opts.resolved(algorithm)
    return opts


def check_solve_args(problem, algorithm, penalty, known, kind: str) -> None:
    """Entry checks of :func:`~alcontact.contact.solve`, frictionless and Coulomb.

    Raises
    ------
    InputError
        ``problem`` is not a :class:`~alcontact.contact.ContactProblem`, or
        ``algorithm`` / ``penalty`` are not names.
    UnknownNameError
        ``algorithm`` is not one of ``known`` (with the closest match).
    """
    from ..._options import show
    from ..problem._problem import ContactProblem

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


def resolve_penalty(algorithm, penalty: str | None, default: str | None = None) -> str:
    """Penalty name an algorithm runs with: its fixed one, or ``penalty`` (its default) for family-p.

    ``algorithm`` is a registry entry (:class:`Algorithm`) or the name of a frictionless
    one. A penalty given to an algorithm with a fixed one, or one not usable by
    Algorithm 6.3 / 6.4, is an error naming the way out.
    """
    entry = algorithm if isinstance(algorithm, Algorithm) else find_algorithm(algorithm)
    return entry.penalty_for(penalty, default)


def contact_penalties() -> list[str]:
    """Registered penalties usable by Algorithm 6.3: those declaring ``usable_for_contact``.

    That fact defaults to (P1), (P3), (P4) and not ``equality_only``
    (:func:`alcontact.penalties.facts`).
    """
    return [name for name in _pen.available() if _pen.facts(_pen.make(name)).usable_for_contact]


def _usable_for_contact(name: str) -> bool:
    """Whether ``name`` is one of :func:`contact_penalties` (makes only that penalty)."""
    return name in _pen.available() and bool(_pen.facts(_pen.make(name)).usable_for_contact)


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


def _initial_multipliers(dc: ContactSystem) -> np.ndarray:
    """Starting multipliers: zero, or the warm start of a load-stepped model (``dc.initial_multipliers``)."""
    return np.asarray(dc.initial_multipliers(), dtype=float)


def _penalty_solve(dc, opts, eps, r0, lam0=None, *, entry: bool = False, maxiter: int | None = None):
    r"""The penalty subproblem :math:`t_N = \langle\lambda_0 + \varepsilon_N g\rangle` (``lam0`` zero: (6.10)).

    With ``entry`` its Newton solve starts with the model's entry rule (:func:`_entry_subproblem`);
    ``maxiter`` (default ``opts.maxiter_newton``) bounds its Newton iterations.
    """
    pen = _pen.make("rockafellar")
    law = make_law(pen, np.full(dc.cand.size, 1.0 / eps))
    lam0 = np.zeros(dc.cand.size) if lam0 is None else np.asarray(lam0, dtype=float)
    maxiter = opts.maxiter_newton if maxiter is None else min(int(maxiter), opts.maxiter_newton)
    if entry:
        return _entry_subproblem(dc, law, lam0, r0, tol=opts.newton_tol, maxiter=maxiter)[0]
    return dc.subproblem(law, lam0, r0, tol=opts.newton_tol, maxiter=maxiter)


#: Newton iterations the first penalty solve of a load step at the carried stiffness may take before the
#: step's sequence restarts from ``eps0`` (:func:`run_penalty`): 3-5 where it works (half-cylinder pressed
#: at finite deformation); on the sliding strip of ``examples/finite_ironing.toml`` it stalls on the
#: round-off of its stiff contact forces and used the whole budget (60) in every step
_CARRIED_BUDGET = 10


def _entry_subproblem(dc, law, lam, r0, *, tol, maxiter, finish: bool = True, penalty_start: bool = False):
    r"""Subproblem (S) with the multipliers ``lam``, its Newton solve started with the model's entry rule.

    A model that predicts which points enter contact in a load step
    (``dc.entry_multipliers``, :meth:`FiniteContact.entry_multipliers
    <alcontact.contact.systems._full_space.FiniteContact.entry_multipliers>`) first solves (S) with the
    points it keeps out shifted to zero traction at the start (over-predicted edge points start
    without penalty force, so the primal Newton does not release them one per iteration). Where
    no shifted point penetrates at that solution its traction is zero under both multipliers
    (the Macaulay law), and the solution is the one of (S) with ``lam``; otherwise (S) with
    ``lam`` is solved on from there (with ``finish``; all the Newton iterations counted), so
    the shift only picks where Newton's method starts. Returns ``(outcome, multipliers)``: the
    multipliers of the returned solution (``lam``, or the shifted ones where ``finish`` is off
    and a shifted point still penetrates: the caller's dual step takes those points in).
    ``penalty_start`` tells the model that this is the penalty start of Algorithm 6.3
    (option ``slide_start_reach``).
    """
    shifted = np.asarray(dc.entry_multipliers(lam, law, penalty_start=penalty_start), dtype=float)
    if not np.any(shifted != lam):
        return dc.subproblem(law, lam, r0, tol=tol, maxiter=maxiter), lam
    first = dc.subproblem(law, shifted, r0, tol=tol, maxiter=maxiter)
    if first.converged and np.array_equal(first.t, np.asarray(law.traction(first.g, lam), dtype=float)):
        return first, lam
    if first.converged and not finish:
        return first, shifted
    return _solve_on(dc, law, lam, first, r0, tol=tol, maxiter=maxiter), lam


def _solve_on(dc, law, lam, first, r0, *, tol, maxiter):
    """(S) with ``lam`` from where the entry-shifted solve ``first`` stopped (from ``r0`` where it failed),
    the Newton iterations of both counted."""
    out = dc.subproblem(law, lam, first.state if first.converged else r0, tol=tol, maxiter=maxiter)
    return dataclasses.replace(out, iterations=out.iterations + first.iterations)


def run_penalty(dc: ContactSystem, opts, eps0, penalty_name=None) -> _Run:
    """Pure penalty (6.10), stiffness raised by ``alpha`` until the penetration tolerance is met.

    A load-stepped model with ``dc.penalty_continuation`` (finite deformation,
    :attr:`ContactSystem.penalty_continuation <alcontact.contact.systems._protocol.ContactSystem.penalty_continuation>`)
    starts each step at the stiffness its last converged step ended with (``dc.carried_stiffness``,
    at least ``eps0``, at most ``eps_max * eps0``) instead of ``eps0``: the sequence of (6.10) of
    Algorithm 5.2 continued over the load steps, the same stopping test (penetration at most
    ``tol_penetration``). It starts one growth factor below that stiffness (``/ alpha``): the
    last solve then starts from the solution one stiffness below, as within a step (a solve at
    :math:`10^6\varepsilon_N` from the predicted state stalls at the round-off floor of its contact
    forces: on the AMG path 1.4e-6 off in force). The first solve of a step starts Newton with the
    model's entry rule (:func:`_entry_subproblem`); Newton per step with / without it (20 steps,
    half-cylinder P2): n = 8 4.80 / 4.45, n = 24 5.00 / 4.95, n = 56 5.10 / 5.90, n = 88 6.20 / 6.85;
    3D hemisphere n = 12 (10 steps) 5.30 / 4.80: it pays on the finer 2D meshes, where the contact
    edge has more points to release. Taking the
    entry-shifted solution as the start of the full-stiffness solve instead (no re-solve where a
    kept-out point still penetrates) saved 0.6-1.3 Newton per step but left that solve 1e-7 to
    3e-7 apart in force on the AMG and direct paths (the round-off floor again), so it is not done.
    A first solve at the carried stiffness that fails, or takes more than :data:`_CARRIED_BUDGET`
    Newton iterations, restarts the step's sequence from ``eps0``.
    """
    carry = bool(dc.penalty_continuation)
    carried = dc.carried_stiffness if carry else None
    eps = eps0 if carried is None else min(max(eps0, float(carried) / opts.alpha), opts.eps_max * eps0)
    r = dc.start()
    hist, newton = [], 0
    lam_old = np.zeros(dc.cand.size)
    for k in range(1, opts.maxiter + 1):
        out = _penalty_solve(dc, opts, eps, r, entry=carry and k == 1,
                             maxiter=_CARRIED_BUDGET if (carried is not None and k == 1) else None)
        newton += out.iterations
        r = out.state
        lam = out.t
        pen, compl, dlam = _measures(dc, lam, out.g, lam_old)
        hist.append(ContactIteration(k, pen, compl, dlam, out.residual, out.iterations, eps, int(np.sum(lam > 0))))
        logger.info("penalty iteration %d: eps_N %.3e, penetration %.2e h", k, eps, pen)
        if not out.converged and carried is not None and k == 1:
            # the carried stiffness failed from this start: the step's sequence from eps0, as without it
            logger.info("penalty iteration 1 at the carried eps_N %.3e failed (%s); restarting from %.3e", eps,
                        out.message, eps0)
            eps, r, carried = eps0, dc.start(), None
            continue
        if not out.converged:
            return _Run(r, lam, out.g, ContactStatus.NEWTON_FAILED,
                        f"Newton failed in penalty iteration {k}: {out.message}", k, newton, eps, out.residual, hist)
        if pen <= opts.tol_penetration:
            if carry:
                dc.carried_stiffness = eps
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


def _after_dual_step(better, lam, state):
    """Multipliers and next start after a model's Newton step on the dual (``dc.multiplier_step``).

    ``better`` is its result: ``None`` (no step: ``(lam, state)`` stay), the new multipliers
    (``state`` stays), or the multipliers with the primal correction of the dual step as the
    next start.
    """
    if isinstance(better, tuple):
        return better
    return (lam, state) if better is None else (better, state)


def _penalty_start(dc, opts, eps):
    r"""The pure-penalty start of Algorithm 6.3 (``initial="penalty"``): ``(outcome, multipliers, state)``.

    One penalty solve (6.10), its tractions the initial multipliers. A load-stepped model with
    ``dc.warm_penalty_start`` (:attr:`ContactSystem.warm_penalty_start
    <alcontact.contact.systems._protocol.ContactSystem.warm_penalty_start>`) gives it what Algorithm 6.1
    starts a step with: the step's predicted pressures as multipliers
    (:math:`t_N = \langle\lambda_{pred} + \varepsilon_N g\rangle`, the first subproblem of Algorithm
    6.1) and its entry rule (:func:`_entry_subproblem`); the initial multipliers are then the
    second-order update of that subproblem
    (:meth:`FiniteContact.start_multiplier_step
    <alcontact.contact.systems._full_space.FiniteContact.start_multiplier_step>`, a Newton step on the dual
    with its primal correction, which takes in the points the entry rule kept out that still
    penetrate; ``None``: its tractions, as without it) instead of its tractions. Where such
    points entered, one more subproblem with those multipliers and a second dual step follow
    (the next iteration of Algorithm 6.1). Algorithm
    6.3 leaves :math:`\lambda^0 > 0` free; its iterations (the first-order update (6.66)) are
    unchanged.

    Where the model solves its subproblems inexactly (:attr:`ContactSystem.inexact_subproblems
    <alcontact.contact.systems._protocol.ContactSystem.inexact_subproblems>`, option ``subproblems``)
    the entry-shifted first solve stops at :data:`_START_ENTRY_TOL`: a second subproblem, solved to
    ``newton_tol``, and a second dual step follow it, and the dual step is a Newton step whose error
    is the larger of the square of the start's and the subproblem's residual, so the first one only
    has to be as accurate as the second dual step corrects (the second subproblem of the 3D ironing
    case starts at relative residual 3e-3 to 1.5e-2 whether the first is solved to 1e-4 or 1e-12).
    Where no point is shifted it is solved to ``newton_tol`` (no second subproblem follows), and where
    the shift changed no traction it is solved on to ``newton_tol``.
    """
    if not dc.warm_penalty_start:
        out = _penalty_solve(dc, opts, eps, dc.start())
        return out, out.t.copy(), out.state.copy()
    law = make_law(_pen.make("rockafellar"), np.full(dc.cand.size, 1.0 / eps))
    lam0 = _initial_multipliers(dc)
    # pressures at or below the multiplier floor are MET's positive floor (barrier penalties keep a tiny traction
    # at every open point), not contact: zero, so that the entry rule sees those points as not pressed
    lam0 = np.where(lam0 > opts.multiplier_floor * float(np.max(lam0, initial=0.0)), lam0, 0.0)
    dual = dc.start_multiplier_step
    # the entry solve is inexact where a second subproblem follows it (the entry rule shifts a point)
    loose = (bool(dc.inexact_subproblems) and opts.subproblems == "inexact"
             and bool(np.any(np.asarray(dc.entry_multipliers(lam0, law, penalty_start=True)) != lam0)))
    out, lam_used = _entry_subproblem(dc, law, lam0, dc.start(),
                                      tol=max(opts.newton_tol, _START_ENTRY_TOL) if loose else opts.newton_tol,
                                      maxiter=opts.maxiter_newton, finish=False, penalty_start=True)
    if loose and out.converged and lam_used is lam0 and out.residual > opts.newton_tol:
        # the shift changed no traction: no second subproblem follows, and the dual step needs (S) to newton_tol
        out = _solve_on(dc, law, lam0, out, dc.start(), tol=opts.newton_tol, maxiter=opts.maxiter_newton)
    better = dual(law, lam_used, out) if out.converged else None
    if isinstance(better, tuple) and lam_used is not lam0:
        # points the entry rule kept out still penetrate: the dual step took them in from its linearization;
        # the next subproblem of Algorithm 6.1 (its multipliers, from its primal correction) and a second
        # dual step bring them to their pressures (without: 2-3 more first-order MET iterations per such step)
        again = dc.subproblem(law, better[0], better[1], tol=opts.newton_tol, maxiter=opts.maxiter_newton)
        if again.converged:
            both = dataclasses.replace(again, iterations=again.iterations + out.iterations)
            return (both, *_after_dual_step(dual(law, better[0], again), again.t.copy(), again.state.copy()))
        out = dataclasses.replace(out, iterations=out.iterations + again.iterations)
    if better is not None:
        return (out, *_after_dual_step(better, None, out.state.copy()))
    if lam_used is not lam0:  # no dual step: the shifted solution is not (S) with lam0's; solve on
        out = _solve_on(dc, law, lam0, out, dc.start(), tol=opts.newton_tol, maxiter=opts.maxiter_newton)
    return out, out.t.copy(), out.state.copy()


#: inexact subproblems: Newton tolerance of (S) = min(forcing * dlam, dlam**2), dlam the last
#: relative multiplier change (the quadratic term tightens the solves where Newton is quadratic)
_INEXACT_FORCING = 1e-3
#: inexact subproblems: Newton tolerance of the entry-shifted first solve of Algorithm 6.3's warm penalty start
#: (:func:`_penalty_start`), which a second subproblem and a second dual step correct. Issue 18, ironing
#: (sliding steps of 0.05 R), Newton per sliding step exp-met1 / log-met1, 1e-12 (newton_tol) -> 1e-8, 1e-6,
#: 1e-4, 1e-3, 1e-2: 3d-s 5.58 / 6.55 -> 5.55 / 6.53, 5.00 / 5.97, 4.55 / 5.53, 4.60 / 5.55, 6.17 / 6.22 (one
#: cut-back: the dual step of a state 1e-2 off mispredicts the zone); 2d-s 5.00 / 5.97 -> 4.03 / 4.97 at 1e-4
_START_ENTRY_TOL = 1e-4


#: barrier starts: the first force scale closes the penetrations with this safety factor
_PUSH_MARGIN = 1.5


def _first_push(g, g_doubled, bound) -> float:
    r"""First force scale :math:`s` of the barrier start (contact forces times :math:`1 + s`).

    The gaps are affine in the scale (exactly on the condensed and AMG paths, to first order
    in finite deformation): :math:`g(s) = g - s\,d` with :math:`d = g - g(1)` from the
    doubled forces. The smallest scale that closes every penetration outside the domain,
    :math:`\max_i g_i / d_i`, times :data:`_PUSH_MARGIN`, keeps the start next to the
    penalty solution: the former fixed first scale 0.5 (50 % more contact force) cost the
    first MET 2 subproblem about 15 Newton steps instead of a few, and at finite deformation
    (neo-Hookean half-cylinder, P2, 20 steps) failed log-met1/2 (n = 24 at delta/R = 0.28): the
    edge points with floored multipliers were left at their barrier bound and Newton stalled
    (``tests/verification/test_finite_log_barrier.py``). Capped at 0.5; the
    caller doubles it while the start is still outside the domain.
    """
    d = g - g_doubled
    viol = (g >= 0.99 * bound) & (d > 0) & (g > 0)
    if not np.any(viol):
        return 0.5
    need = float(np.max(g[viol] / d[viol]))
    return float(min(0.5, max(_PUSH_MARGIN * need, 1e-12)))


@dataclass
class _ALStart:
    """Where the outer loop of Algorithms 6.1 / 6.3 starts (:func:`_al_start`)."""

    lam: np.ndarray
    r: Any
    floor: float
    newton: int = 0
    outer0: int = 0
    history: list = field(default_factory=list)


def _al_start(dc: ContactSystem, opts, eps: float, needs_positive: bool) -> _ALStart:
    r"""Initial multipliers and starting state of :func:`run_al`.

    Algorithm 6.1 starts from :math:`\lambda = 0` (or the load step's warm start); Algorithm 6.3
    from one penalty solve (``initial="penalty"``, :func:`_penalty_start`) or the uniform value
    ``eps * h``, floored at ``multiplier_floor`` times the largest one (MET 1/2 freeze at zero).
    """
    if not needs_positive:
        start = _ALStart(_initial_multipliers(dc), dc.start(), 0.0)
    elif opts.initial == "penalty":
        out, lam, r = _penalty_start(dc, opts, eps)
        start = _ALStart(lam, r, 0.0, out.iterations, 1)
        start.history.append(ContactIteration(0, float(np.max(out.g, initial=0)) / dc.h, np.nan, np.nan, out.residual,
                                              out.iterations, eps, int(np.sum(lam > 0))))
    else:
        start = _ALStart(np.full(dc.cand.size, eps * dc.h), dc.start(), 0.0)
    pref = max(float(np.max(start.lam, initial=0.0)), eps * dc.h * 1e-6)
    start.floor = opts.multiplier_floor * pref
    if needs_positive:
        start.lam = np.maximum(start.lam, start.floor)
    return start


def _inside_domain(dc: ContactSystem, r, bound):
    r"""A starting state inside the domain :math:`g < 0.99\,\eta b` of a barrier-type penalty (Algorithm 6.3).

    Pushing harder (contact forces times :math:`1 + s`, :func:`_first_push`, ``s`` doubled while
    still outside) closes the penetrations; a Macaulay law (Algorithm 6.1) has no bound: no solve.
    """
    g_start = dc.gaps(r)
    if not np.any(g_start >= 0.99 * bound):
        return r
    doubled = dc.scale_forces(r, 2.0)
    if np.array_equal(doubled, r):  # no contact force to scale up
        return r
    scale = _first_push(g_start, dc.gaps(doubled), bound)
    while np.any(dc.gaps(r) >= 0.99 * bound) and scale < 1e6:
        trial = dc.scale_forces(r, 1 + scale)
        if not np.any(dc.gaps(trial) >= 0.99 * bound):
            return trial
        scale *= 2
    return r


def _next_eta(pen, lam, eps, eta, g):
    r"""Scale :math:`\eta` of the next subproblem (``eta_scaling``), inside a barrier's domain at the warm start."""
    eta_new = eta_for_stiffness(pen, lam, eps)
    bnd = eta_new * np.asarray(pen.domain_upper(lam), dtype=float)
    return np.where(g < 0.99 * bnd, eta_new, eta)


def _subproblem_failure(out, lam, r, k, outer, newton, eps, hist, penalty_name) -> _Run | None:
    """The failed run of outer iteration ``k`` (non-finite tractions, Newton failure), or ``None``."""
    if out.status == ContactStatus.NONFINITE or not np.all(np.isfinite(out.t)):
        return _Run(r, lam, out.g, ContactStatus.NONFINITE,
                    f"penalty {penalty_name!r} produced non-finite (NaN/inf) tractions in iteration {k}; "
                    "check the penalty's formulas, lower penalty_scale or use another penalty",
                    outer, newton, eps, out.residual, hist)
    if not out.converged:
        return _Run(out.state, lam, out.g, ContactStatus.NEWTON_FAILED,
                    f"Newton failed in outer iteration {k}: {out.message}; try penalty_scale < 1 or "
                    "algorithm='ssn'", outer, newton, eps, out.residual, hist)
    return None


def run_al(dc: ContactSystem, opts, eps0, penalty_name="rockafellar") -> _Run:
    """Algorithms 6.1 / 6.3 (outer loop; see module doc) on a :class:`~alcontact.contact.systems._protocol.ContactSystem`.

    With ``opts.subproblems == "inexact"`` a model that declares ``dc.inexact_subproblems`` has
    its subproblems solved inexactly (the Newton tolerance of (S) follows the last multiplier
    change, and the loop stops only after a subproblem solved to ``newton_tol``). After each
    subproblem of a penalty that does not freeze at zero, ``dc.multiplier_step(law, lam, out)``
    may give a second-order multiplier update (a Newton step on the dual with the same fixed
    point, optionally with the primal correction it implies as ``(multipliers, next starting
    state)``; ``None`` keeps the first-order update). The stopping tests measure the first-order
    update's change; a model with ``dc.physical_stopping`` (Algorithm 6.1 at finite deformation)
    also stops as soon as the penetration and complementarity tolerances hold at a subproblem
    solved to ``newton_tol`` (the KKT conditions at the returned state, the measures of
    :mod:`alcontact.contact._verify`).
    """
    pen = _pen.make(penalty_name)
    eps = eps0
    needs_positive = freezes_at_zero(pen)  # MET 1/2: a zero multiplier would never revive
    start = _al_start(dc, opts, eps, needs_positive)
    lam, r, floor, newton, outer0, hist = start.lam, start.r, start.floor, start.newton, start.outer0, start.history
    eta = eta_for_stiffness(pen, lam, eps)
    law = make_law(pen, eta)
    if not needs_positive:  # a model may keep predicted points out of the first (S)
        lam = np.asarray(dc.entry_multipliers(lam, law), dtype=float)
    bound = law.gap_bound(lam)
    r = _inside_domain(dc, r, bound)
    if np.any(dc.gaps(r) >= bound):
        return _Run(r, lam, dc.gaps(r), ContactStatus.NEWTON_FAILED,
                    f"no starting point inside the domain of penalty {penalty_name!r}; use eta_scaling='adaptive' "
                    "or a penalty with unbounded domain (exp-met1)", 0, newton, eps, np.inf, hist)
    update = make_strategy(opts.strategy, {"tau": opts.tau, "factor": opts.alpha, "feas_tol": opts.tol_penetration})
    pen_prev = compl_prev = np.inf
    out = None
    inexact = bool(dc.inexact_subproblems) and opts.subproblems == "inexact"
    # a model with the second-order update may stop on the physical tolerances alone: the returned
    # tractions t = p'(g/eta, lambda) balance the state to newton_tol, so penetration and
    # complementarity are the KKT conditions
    physical = bool(dc.physical_stopping) and not needs_positive
    inner_tol = max(opts.newton_tol, float(dc.inexact_first_tol)) if inexact else opts.newton_tol
    for k in range(1, opts.maxiter + 1):
        out = dc.subproblem(law, lam, r, tol=inner_tol, maxiter=opts.maxiter_newton)
        newton += out.iterations
        failed = _subproblem_failure(out, lam, r, k, outer0 + k, newton, eps, hist, penalty_name)
        if failed is not None:
            return failed
        r = r_next = out.state
        lam_new = out.t.copy()  # multiplier update: lambda <- p'(g/eta, lambda)
        if needs_positive:
            lam_new = np.maximum(lam_new, floor)
        else:  # a model may offer a Newton step on the dual (same fixed point)
            lam_new, r_next = _after_dual_step(dc.multiplier_step(law, lam, out), lam_new, r_next)
        # the change from the clipped multipliers (an entry shift lambda_i < 0 is no multiplier change)
        pen_k, compl, dlam = _measures(dc, out.t, out.g, np.maximum(lam, 0.0))
        hist.append(ContactIteration(outer0 + k, pen_k, compl, dlam, out.residual, out.iterations, eps,
                                     int(np.sum(out.g > -opts.tol_penetration * dc.h))))
        lam = lam_new
        logger.info("outer %d: penetration %.2e h, complementarity %.2e, multiplier change %.2e, %d Newton",
                    outer0 + k, pen_k, compl, dlam, out.iterations)
        if (_converged(opts, pen_k, compl, dlam) and inner_tol <= opts.newton_tol) or (
                physical and pen_k <= opts.tol_penetration and compl <= opts.tol_complementarity
                and out.residual <= opts.newton_tol):
            return _Run(r, out.t, out.g, ContactStatus.CONVERGED, "converged", outer0 + k, newton, eps,
                        out.residual, hist)
        if inexact:
            # dlam * dlam, not dlam**2: a huge change (multipliers from ~0) gives inf, not an OverflowError
            inner_tol = max(opts.newton_tol, min(_INEXACT_FORCING * dlam, dlam * dlam))
            if _converged(opts, pen_k, compl, dlam):
                inner_tol = opts.newton_tol
        # one stiffness: the largest factor of a per-constraint rule
        factor = float(np.max(update(StrategyState(outer0 + k, pen_k, pen_prev, compl, compl_prev))))
        if factor != 1.0 and eps * factor <= opts.eps_max * eps0:
            eps *= factor
            if opts.eta_scaling == "fixed":
                eta = eta / factor
        pen_prev, compl_prev = pen_k, compl
        if opts.eta_scaling == "adaptive":
            eta = _next_eta(pen, lam, eps, eta, out.g)
        law = make_law(pen, eta)
        r = r_next
    return _Run(out.state, out.t, out.g, ContactStatus.MAXITER,
                f"maximum outer iterations ({opts.maxiter}) reached; raise maxiter, use strategy='infeasibility' "
                "or a larger penalty_scale", outer0 + opts.maxiter, newton, eps, out.residual, hist)


def run_ssn(dc: ContactSystem, opts, eps0, penalty_name=None) -> _Run:
    r"""Primal-dual active set / semi-smooth Newton on :math:`\lambda = \max(0, \lambda + c g)`.

    Each step enforces :math:`g_A = 0` on the active set and zero pressure elsewhere
    (``dc.solve_active``: a dense solve on the Delassus operator, or an inner
    augmented Lagrangian with AMG-CG on the factorization-free path).
    """
    c = eps0
    state = dc.start()
    lam = _initial_multipliers(dc)
    g = dc.gaps(state)
    # the rule lam + c g > 0, or the model's prediction of the starting set (finite deformation)
    active = np.asarray(dc.initial_active(lam, g, c), dtype=bool)
    hist = []
    seen = set()
    for k in range(1, opts.maxiter + 1):
        try:
            state, lam_new, g = dc.solve_active(active, lam, state, c)
        except np.linalg.LinAlgError:  # the active set's rows of the Delassus operator are dependent
            return _Run(state, lam, g, ContactStatus.NEWTON_FAILED,
                        f"singular active-set system at iteration {k} ({int(active.sum())} active points); use "
                        "algorithm='simo-laursen'", k, k, c, 0.0, hist)
        if not dc.active_converged:
            # an inner Newton that stopped at its budget (or stalled) is a failure, whatever its active set:
            # the load step is cut back, its state is never accepted
            return _Run(state, lam, g, ContactStatus.NEWTON_FAILED,
                        f"the Newton solve of active-set iteration {k} stopped at relative residual "
                        f"{dc.active_residual:.2e} (newton_tol {opts.newton_tol:.1e}); use "
                        "more load steps or algorithm='simo-laursen'", k, k, c,
                        float(dc.active_residual), hist)
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


# --------------------------------------------------------------------------- the algorithm registry
#: Defaults of the automatic Newton options of the frictionless algorithms (:meth:`ContactOptions.resolved`).
FRICTIONLESS_DEFAULTS = {"newton_tol": 1e-12, "maxiter_newton": 60}
#: Defaults of the automatic Newton options of the frictional algorithms.
FRICTION_DEFAULTS = {"newton_tol": 1e-11, "maxiter_newton": 200}
#: Defaults of every entry, under its own ``defaults`` (:meth:`ContactOptions.resolved`): the automatic
#: penalty stiffness is 100 E'/h unless the entry says otherwise (a registered entry without defaults included).
BASE_DEFAULTS = {"penalty_scale": 100.0}
#: Linear-solver paths an entry may declare: ``direct`` (sparse factorization; at small deformation the
#: problem is condensed on the contact points), ``amg`` (factorization-free, PyAMG + CG), ``factor-gmres`` (the
#: factors of an approximate solver precondition GMRES on each Newton system, :class:`~alcontact.linalg.SequenceSolver`).
#: An approximate solver (:attr:`alcontact.linalg.SolverChoice.exact` False) runs only on an entry with ``amg``
#: or ``factor-gmres``.
LINEAR_SOLVER_PATHS = ("direct", "amg", "factor-gmres")
#: the paths on which an approximate solver runs
_APPROXIMATE_PATHS = ("amg", "factor-gmres")


@dataclass(frozen=True)
class Algorithm:
    """A registered contact algorithm and what it supports.

    One registry holds the frictionless, frictional and finite-deformation algorithms
    (:func:`register`, :func:`find_algorithm`, :func:`algorithms`); the solvers, the
    problem-file checks and ``alcontact list`` read it. A name may have one entry per
    combination of ``friction`` and ``kinematics``.

    Parameters
    ----------
    name : str
        Registry name (``"simo-laursen"``).
    run : callable
        The algorithm: ``run(dc, opts, eps0, penalty)`` (frictionless, outer loop of
        :mod:`alcontact.contact.algorithms._frictionless`) or the step function of the frictional
        solvers (:mod:`alcontact.contact.algorithms._coulomb`, :mod:`alcontact.contact.systems._full_space`).
    doc : str
        One line, with the dissertation's algorithm or equation number.
    friction : bool
        Coulomb friction (:func:`~alcontact.contact.solve` with a friction coefficient) or frictionless.
    kinematics : {"small", "finite"}
        Linearized gap (6.15) or gap at the deformed position.
    linear_solvers : tuple of str
        Linear-solver paths it runs on (:data:`LINEAR_SOLVER_PATHS`); an approximate ``linear_solver``
        (e.g. ``"amg"``) is refused by an entry without ``"amg"`` or ``"factor-gmres"``.
    penalty : str or None
        Its fixed penalty, or ``None`` when it takes one (family-P, ``default_penalty``).
    default_penalty : str or None
        Penalty of an entry that takes one, when none is given.
    defaults : mapping
        Values of the automatic (``None``) options, e.g. :data:`FRICTION_DEFAULTS`.
    """

    name: str
    run: Callable
    doc: str
    friction: bool = False
    kinematics: str = "small"
    linear_solvers: tuple[str, ...] = ("direct",)
    penalty: str | None = None
    default_penalty: str | None = None
    defaults: Mapping[str, Any] = field(default_factory=dict)

    @property
    def key(self) -> tuple[str, bool, str]:
        """Its registry key ``(name, friction, kinematics)``."""
        return (self.name, self.friction, self.kinematics)

    @property
    def family(self) -> str:
        """``"algorithm"``, ``"friction algorithm"`` or ``"finite-deformation friction algorithm"`` (messages)."""
        return _FAMILY[(self.friction, self.kinematics)]

    def penalty_for(self, penalty: str | None, default: str | None = None) -> str:
        """The penalty this entry runs with when ``penalty`` is asked for (see :func:`resolve_penalty`)."""
        if self.penalty is not None:
            if penalty not in (None, self.penalty):
                raise InputError(
                    f"algorithm {self.name!r} uses the {self.penalty!r} penalty; got penalty={penalty!r}. "
                    "Use algorithm='family-p' to choose a penalty."
                )
            return self.penalty
        name = penalty or default or self.default_penalty or DEFAULT_PENALTY
        if not _usable_for_contact(name):  # the named one only: making every penalty costs ~1 ms per solve
            raise UnknownNameError("contact penalty", name, contact_penalties())
        return name

    def check_options(self, opts: ContactOptions) -> None:
        """Refuse options this entry cannot honour (an approximate ``linear_solver``, e.g. ``"amg"``, without
        an AMG path: the solver choice says whether the named solver is exact,
        :func:`alcontact.linalg.select_solver`)."""
        name = opts.linear_solver
        if set(_APPROXIMATE_PATHS) & set(self.linear_solvers) or name in ("auto", "direct"):
            return
        if not select_solver(name, dim=3, ndofs=0, allow_iterative=False).exact:
            kin = "" if self.kinematics == "small" else f"{self.kinematics}-deformation "
            raise InputError(
                f"{type(opts)._KIND} option linear_solver = {name!r} (an approximate solver): the {kin}"
                f"{'frictional' if self.friction else ''}{' ' if self.friction else ''}algorithm {self.name!r} has "
                f"no AMG path (it runs on: {', '.join(self.linear_solvers)}); use linear_solver='auto', 'direct' "
                "or a direct solver.")

    def supports(self) -> str:
        """``"small: direct, amg"``: its kinematics and linear-solver paths (for ``alcontact list``)."""
        return f"{self.kinematics}: {', '.join(self.linear_solvers)}"


_FAMILY = {(False, "small"): "algorithm", (False, "finite"): "algorithm",
           (True, "small"): "friction algorithm", (True, "finite"): "finite-deformation friction algorithm"}

#: Every registered algorithm, keyed by ``(name, friction, kinematics)``.
_REGISTRY: dict[tuple[str, bool, str], Algorithm] = {}


def register(entry: Algorithm) -> Algorithm:
    """Add (or replace) a registry entry; returns it.

    Raises
    ------
    ValueError
        Unknown kinematics or linear-solver path.
    """
    from ..problem._problem import KINEMATICS

    if entry.kinematics not in KINEMATICS:
        raise ValueError(f"algorithm {entry.name!r}: unknown kinematics {entry.kinematics!r}")
    bad = set(entry.linear_solvers) - set(LINEAR_SOLVER_PATHS)
    if bad or not entry.linear_solvers:
        raise ValueError(f"algorithm {entry.name!r}: linear-solver paths must be some of {LINEAR_SOLVER_PATHS}")
    _REGISTRY[entry.key] = entry
    return entry


def algorithms(*, friction: bool | None = None, kinematics: str | None = None) -> tuple[Algorithm, ...]:
    """Registry entries, by name; ``friction`` / ``kinematics`` select (``None``: all)."""
    return tuple(e for _, e in sorted(_REGISTRY.items()) if (friction is None or e.friction == friction)
                 and (kinematics is None or e.kinematics == kinematics))


def algorithm_names(*, friction: bool = False, kinematics: str = "small") -> list[str]:
    """Names of the algorithms for ``friction`` and ``kinematics``."""
    return [e.name for e in algorithms(friction=friction, kinematics=kinematics)]


def _check_family(where: str, friction: Any, kinematics: Any = "small") -> None:
    """``friction`` is a bool and ``kinematics`` one of ``small``/``finite`` (else an InputError naming them)."""
    if not isinstance(friction, bool):
        raise InputError(f"{where}: friction = {friction!r:.60}: expected True or False.")
    if not isinstance(kinematics, str) or (friction, kinematics) not in _FAMILY:
        raise InputError(f"{where}: kinematics = {kinematics!r:.60}: expected 'small' or 'finite'.")


def find_algorithm(name: str, *, friction: bool = False, kinematics: str = "small") -> Algorithm:
    """The entry of ``name`` for ``friction`` and ``kinematics``.

    Raises
    ------
    UnknownNameError
        With the closest match and the names registered for that combination.
    InputError
        ``friction`` is not a bool or ``kinematics`` not ``"small"``/``"finite"``.
    """
    _check_family("find_algorithm", friction, kinematics)
    entry = _REGISTRY.get((name, friction, kinematics)) if isinstance(name, str) else None
    if entry is None:
        raise UnknownNameError(_FAMILY[(friction, kinematics)], str(name),
                               algorithm_names(friction=friction, kinematics=kinematics))
    return entry


def describe_algorithms(*, friction: bool) -> dict[str, str]:
    """``{name: "doc [kinematics: linear solvers; ...]"}``, e.g. ``"... [small: direct, amg; finite: direct]"``."""
    _check_family("describe_algorithms", friction)
    out: dict[str, list[Algorithm]] = {}
    for e in sorted(algorithms(friction=friction), key=lambda e: (e.name, e.kinematics != "small")):
        out.setdefault(e.name, []).append(e)
    return {name: f"{es[0].doc} [{'; '.join(e.supports() for e in es)}]" for name, es in out.items()}


def available_algorithms() -> list[str]:
    """Names of the frictionless contact algorithms."""
    return algorithm_names(friction=False, kinematics="small")


def algorithm_docs(*, friction: bool = False, kinematics: str = "small") -> dict[str, str]:
    """One line of documentation per algorithm (default: the frictionless ones at small deformation)."""
    if not isinstance(friction, (bool, np.bool_)):
        raise InputError(f"algorithm_docs: friction = {friction!r:.60}: expected True or False.")
    if not isinstance(kinematics, str):
        raise InputError(f"algorithm_docs: kinematics = {kinematics!r:.60}: expected 'small' or 'finite'.")
    return {e.name: e.doc for e in algorithms(friction=friction, kinematics=kinematics)}


def register_family(rows, *, friction: bool, kinematics: str, linear_solvers: tuple[str, ...],
                    defaults: Mapping[str, Any]) -> None:
    """Register ``(name, run, fixed penalty or None, doc)`` rows of one family (:class:`Algorithm`)."""
    for name, run, penalty, doc in rows:
        register(Algorithm(name, run, doc, friction=friction, kinematics=kinematics, linear_solvers=linear_solvers,
                           penalty=penalty, default_penalty=None if penalty else DEFAULT_PENALTY, defaults=defaults))


def get_algorithm(name: str):
    """The outer loop of the frictionless algorithm ``name``."""
    return find_algorithm(name).run


#: Penalty of family-P algorithms when none is given (frictionless and frictional).
DEFAULT_PENALTY = "exp-met1"

_FRICTIONLESS = (
    ("penalty", run_penalty, "exterior-quadratic",
     "pure penalty (6.10), stiffness raised until the penetration tolerance is met"),
    ("simo-laursen", run_al, "rockafellar", "Algorithm 6.1: augmented Lagrangian with the Macaulay update (6.13)"),
    ("family-p", run_al, None, "Algorithm 6.3: augmented Lagrangian with a family-P penalty (corrected 6.66)"),
    ("ssn", run_ssn, "none", "reference: semi-smooth Newton / primal-dual active set, exact (no penalty)"),
)
register_family(_FRICTIONLESS, friction=False, kinematics="small", linear_solvers=("direct", "amg"),
                defaults=FRICTIONLESS_DEFAULTS)
# finite deformation: the augmented-Lagrangian algorithms (symmetric Newton matrices) also run on AMG + CG
# (:mod:`alcontact.contact.systems._full_space`); the reference solves saddle-point systems, direct only
register_family(_FRICTIONLESS[:3], friction=False, kinematics="finite", linear_solvers=("direct", "amg"),
                defaults=FRICTIONLESS_DEFAULTS)
register_family(_FRICTIONLESS[3:], friction=False, kinematics="finite", linear_solvers=("direct",),
                defaults=FRICTIONLESS_DEFAULTS)
