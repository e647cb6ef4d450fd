"""The one entry point :func:`solve` of every contact problem, and the deprecated wrappers.

:func:`solve` decides in one place what runs: the kinematics of the problem
(``problem.kinematics``: ``"small"`` or ``"finite"``) and its friction (``problem.friction``
or ``friction=``: Coulomb when positive) pick the stepping engine; ``steps`` / ``history``
make it a load-stepped run. Every case returns one :class:`ContactSolution` whose
``frames`` hold the accepted load steps (one frame for a static solve), built by
:mod:`alcontact.contact.solution._frames`.
"""

from __future__ import annotations

import dataclasses
import logging
import time
import warnings

import numpy as np

from ..errors import InputError
from ..linalg import select_solver
from ._verify import check_state, equilibrium_tolerance, reach, state_equilibrium, verified_status
from .algorithms._frictionless import (ContactOptions, _Run, available_algorithms, check_solve_args,
                                       find_algorithm, options_with)
from .laws._stiffness import penalty_stiffness
from .problem._loading import LoadHistory, problem_at
from .solution._frames import finite_friction_solution, finite_solution, friction_solution, stepped_solution
from .solution._rigid import rigid_body_results
from .solution._sides import two_body_sides
from .solution._solution import ContactResult, ContactSolution, ContactStatus
from .stepping._coulomb import finite_friction_steps, solve_finite_friction as _finite_friction_engine, \
    solve_friction as _friction_engine
from .stepping._frictionless import solve_finite as _finite_engine
from .systems._condensed import DiscreteContact


logger = logging.getLogger(__name__)

DEFAULT_ALGORITHM = "simo-laursen"


def _solve_static(problem, algorithm: str = DEFAULT_ALGORITHM, penalty: str | None = None,
                  options: ContactOptions | None = None, **option_overrides) -> ContactSolution:
    """One frictionless small-deformation contact solve (the one-step case of :func:`solve`).

    Parameters
    ----------
    problem : ContactProblem
    algorithm : str
        One of :func:`available_algorithms`: ``"penalty"``, ``"simo-laursen"``
        (Algorithm 6.1), ``"family-p"`` (Algorithm 6.3), ``"ssn"``.
    penalty : str, optional
        Penalty of ``"family-p"`` (one of :func:`contact_penalties`; default
        ``"exp-met1"``).
    options : ContactOptions or dict, optional
        Options; a dict holds :class:`ContactOptions` fields (as ``optim.minimize`` takes them).
    **option_overrides
        Fields of :class:`ContactOptions` (e.g. ``penalty_scale=10``).

    Returns
    -------
    ContactSolution
        ``solution.result.status`` is negative when the solve failed; a warning
        is logged saying what to try.

    Raises
    ------
    InputError
        ``problem`` not a :class:`ContactProblem`, unknown algorithm, penalty or
        option (with the closest match), or an option value of the wrong type or
        out of range (naming the key, the value, the allowed range and the default).
    """
    check_solve_args(problem, algorithm, penalty, available_algorithms(), "")
    t_start = time.perf_counter()
    entry = find_algorithm(algorithm)
    run = entry.run
    pen_name = entry.penalty_for(penalty)
    opts = options_with(options, ContactOptions, option_overrides, "contact", entry)

    from .systems._krylov import IterativeContact

    # both strategies offer the interface the outer loops use (start, gaps, subproblem, solve_active, ...):
    # the condensed (Delassus) one needs an exact factorization, an approximate solver preconditions CG
    solver = select_solver(opts.linear_solver, dim=problem.model.dim, ndofs=problem.model.ndofs)
    if solver.exact:
        dc = DiscreteContact(problem, linear_solver=solver.name)
    else:
        dc = IterativeContact(problem, solver=solver)
    eps0 = opts.eps_n if opts.eps_n is not None else penalty_stiffness(problem.model, dc.h, opts.penalty_scale)
    t_solve = time.perf_counter()

    if dc.cand.size == 0:
        i = int(np.argmax(np.where(dc.movable, dc.g_free, -np.inf)))
        msg = (
            f"the body never reaches the obstacle: smallest clearance {-dc.g_free[i]:.4g} at point "
            f"{np.round(dc.points[i], 6).tolist()}; move the obstacle closer, increase the load, or check "
            "the contact boundary name"
        )
        out = _Run(dc.start(), np.zeros(0), np.zeros(0), ContactStatus.NO_CONTACT, msg, 0, 0, eps0, 0.0, [])
        u = dc.u_free
    else:
        for _attempt in range(8):
            out = run(dc, opts, eps0, pen_name)
            u = dc.final_displacement(out.r)
            if out.status < 0:  # a failed run: its multipliers belong to the candidates it had
                break
            added = dc.extend(dc.all_gaps(u), opts.tol_penetration * dc.h)
            if added.size == 0:
                break
    g_all = dc.all_gaps(u)
    m = dc.points.shape[0]
    pressure = np.zeros(m)
    if out.lam.size:
        pressure[dc.cand[: out.lam.size]] = dc.applied_pressure(out)  # candidates added later carry none
    if out.status > 0 and not np.all(np.isfinite(u)):
        out.status, out.message = ContactStatus.NONFINITE, "non-finite displacement"
    nodal = dc.weights * np.maximum(pressure, 0.0)  # the normal nodal forces r = w lambda the solver applied
    # the one place a small-deformation frictionless result is built: every measure of the returned state
    # (gaps of u, the applied pressures, equilibrium of u with those forces) against its tolerance. The
    # condensed direct path reports the forces u carries (r / w); the AMG path its multipliers, which differ
    # from the tractions u balances by the last multiplier change (the ssn reference's inner Uzawa iteration
    # stops at a relative update of 1e-8): its equilibrium tolerance has tol_multiplier in it
    fixed, _ = problem.dirichlet()
    eq = state_equilibrium(problem.model, u, fixed, problem.load_vector(), *dc.force_points(nodal), dc.h,
                           pressure=pressure, weights=dc.weights)
    check = check_state(g_all, pressure, dc.h, tol_penetration=opts.tol_penetration,
                        tol_complementarity=opts.tol_complementarity, equilibrium=eq.largest,
                        tol_equilibrium=equilibrium_tolerance(opts, multipliers=not isinstance(dc, DiscreteContact)),
                        reach=reach(dc.points, u))
    out.status, out.message = verified_status(out.status, out.message, check, what=f"contact solve {algorithm}")
    pressure = np.maximum(pressure, 0.0)
    force = np.sum(nodal[:, None] * dc.normals, axis=0)
    if np.any(pressure > 0):  # pressure field of the nodal forces (differs from lambda for 3D P2)
        pressure = problem.slave_pressure(nodal)
    closed = g_all > -max(1e-6, 10 * opts.tol_penetration) * dc.h
    active = closed & (pressure > 1e-12 * max(float(pressure.max(initial=0.0)), 1e-300))
    # the printed invariants are the checked ones (of the applied pressures, not of the recovered field)
    pen_final = check.value("penetration")
    compl = check.value("complementarity")
    result = ContactResult(
        status=out.status,
        message=out.message,
        algorithm=algorithm,
        penalty=pen_name,
        outer_iterations=int(out.outer),
        newton_iterations=int(out.newton),
        linear_solves=int(dc.linear_solves),
        factorizations=dc.factorizations,
        penetration=pen_final,
        complementarity=compl,
        residual=float(out.residual),
        eps_n=float(out.eps),
        history=tuple(out.history),
    )
    if out.status < 0:
        logger.warning("contact solve %s/%s failed (%s): %s", algorithm, pen_name, out.status.label, out.message)
    t_end = time.perf_counter()
    timings = dict(dc.timings(), solve_s=t_end - t_solve, total_s=t_end - t_start)
    two_body = {} if dc.mortar is None else {
        **_force_balance(dc, nodal),
        **two_body_sides(problem, dc.mortar, nodal, g_all),
        **rigid_body_results(problem.model, u, dc.mortar.contact_force(nodal), problem.load_vector(), fixed)}
    return ContactSolution(
        problem=problem,
        u=u,
        points=dc.points,
        pressure=pressure,
        gap=g_all,
        weights=dc.weights,
        active=active,
        normals=dc.normals,
        total_contact_force=force,
        result=result,
        timings=timings,
        nodal_forces=nodal,
        extra={"h": dc.h, "candidates": int(dc.cand.size), "dofs": int(problem.model.ndofs), **dc.extra(),
               **two_body},
    )


def _force_balance(dc, nodal: np.ndarray) -> dict:
    r"""Contact forces on the slave and master sides of a two-body (mortar) pair and their balance.

    ``slave_contact_force`` / ``master_contact_force``: the resultant of :math:`-B^T r` on the DOFs of each
    side; ``contact_force_points``: ``(dofs, forces)`` of every node it acts on (what
    :meth:`ContactSolution.equilibrium` balances); ``contact_force_balance`` :math:`|F_s + F_m| / |F_s|` (action = reaction: zero to round-off, since
    the master weights of every slave node sum to its own, :mod:`alcontact.contact.kinematics._mortar`).
    """
    fc = dc.mortar.contact_force(nodal)
    d = dc.dim
    slave = fc[dc.dofs].sum(axis=0)
    master = fc[dc.mortar.master_dofs].sum(axis=0) if not np.array_equal(dc.dofs, dc.mortar.master_dofs) else \
        np.zeros(d)
    norm = float(np.linalg.norm(slave))
    balance = float(np.linalg.norm(slave + master)) / norm if norm > 0 else 0.0
    return {"slave_contact_force": slave.tolist(), "master_contact_force": master.tolist(),
            "contact_force_balance": balance, "contact_force_points": dc.force_points(nodal)}


def solve(problem, algorithm: str = DEFAULT_ALGORITHM, penalty: str | None = None,
          options: ContactOptions | dict | None = None, *, steps=None, history: LoadHistory | None = None,
          obstacle_path=None, friction: float | None = None, on_step=None,
          **option_overrides) -> ContactSolution:
    r"""Solve a contact problem: small or finite deformation, frictionless or Coulomb, one step or load-stepped.

    What runs is decided here, from the problem (module doc):

    ========================  ==================  ==================================================
    ``problem.kinematics``    friction :math:`\mu`  engine
    ========================  ==================  ==================================================
    ``"small"``               0                   one static solve (Algorithm 6.1 / 6.3, penalty,
                                                  ssn); with ``history``/``steps`` one per step time
                                                  (frictionless contact is path independent)
    ``"small"``               > 0                 incremental Coulomb friction (Algorithms 6.2 /
                                                  6.4, ssn) over the history
    ``"finite"``              0                   load steps from the last state, with cut-backs
    ``"finite"``              > 0                 load steps with Coulomb friction at the current
                                                  configuration
    ========================  ==================  ==================================================

    Parameters
    ----------
    problem : ContactProblem
    algorithm : str
        ``"penalty"``, ``"simo-laursen"`` (Algorithm 6.1; 6.2 with friction), ``"family-p"``
        (Algorithm 6.3; 6.4 with friction) or ``"ssn"`` (see :func:`available_algorithms`,
        :func:`friction_algorithms`).
    penalty : str, optional
        Penalty of ``"family-p"`` (one of :func:`contact_penalties`; default ``"exp-met1"``).
    options : ContactOptions or dict, optional
        Options; a dict holds :class:`ContactOptions` fields (as ``optim.minimize`` takes them).
    steps : int or sequence of float, optional
        Number of uniform load steps on ``(0, 1]`` or the step times. Default: the history's
        times; without a history one static step at small deformation, 10 uniform steps at
        finite deformation. Without a history, finite deformation scales every support value
        and load by the pseudo-time; small deformation applies the problem's own loads at
        every step time (a history ramps them).
    history : LoadHistory, optional
        Ramped supports and loads (and a friction amplitude) over pseudo-time.
    obstacle_path : callable ``t -> (d,)`` or ``t -> RigidMotion``, optional
        Finite deformation: the obstacle's translation (or rigid placement) at pseudo-time ``t``.
    friction : float, optional
        Coulomb coefficient; overrides ``problem.friction``.
    on_step : callable ``(done, total, t) -> None``, optional
        Progress of a stepped run: ``done`` requested steps of ``total`` reached at pseudo-time
        ``t`` (``done = 0`` before the first).
    **option_overrides
        Fields of :class:`ContactOptions` (e.g. ``penalty_scale=10``; ``max_cutbacks``: cut-backs
        allowed per load step, default 6).

    Returns
    -------
    ContactSolution
        The state of the last accepted step (``u``, ``pressure``, ``gap``, ``result``, ...), with
        every accepted step in ``frames`` (:class:`ContactFrame`: displacement, pressure, gap,
        global tangential traction, slip, stick/slip/open state, contact and reaction forces,
        counters, timing, status). ``solution.result.status`` is negative when the solve failed;
        a warning is logged saying what to try.

    Raises
    ------
    InputError
        ``problem`` not a :class:`ContactProblem`, unknown algorithm, penalty or option (with
        the closest match), an option value of the wrong type or out of range (naming the key,
        the value, the allowed range and the default), or an argument the case does not take
        (``obstacle_path`` at small deformation).

    Examples
    --------
    >>> from alcontact.problems import hertz
    >>> sol = solve(hertz.hertz_2d(level=0), algorithm="simo-laursen")  # doctest: +SKIP
    >>> len(sol.frames), sol.final.normal_force                           # doctest: +SKIP
    """
    if on_step is not None and not callable(on_step):
        raise InputError(f"on_step = {on_step!r:.40}: expected None or a callable (done, total, t).")
    return _solve_any(problem, algorithm, penalty, options, steps=steps, history=history,
                      obstacle_path=obstacle_path, friction=friction, progress=on_step,
                      overrides=option_overrides)


def _case(problem, friction) -> tuple[str, float]:
    """``(kinematics, mu)`` of a problem: the one decision of what runs."""
    kinematics = getattr(problem, "kinematics", "small")
    mu = getattr(problem, "friction", 0.0) if friction is None else friction
    try:
        frictional = float(mu) > 0
    except (TypeError, ValueError):
        frictional = True  # the frictional engine names the bad value
    return kinematics, (mu if frictional else 0.0)


def _solve_any(problem, algorithm, penalty, options, *, steps, history, obstacle_path, friction, progress,
               overrides, hooks=None) -> ContactSolution:
    """:func:`solve` with the engine's own callbacks (``hooks``) for the deprecated wrappers."""
    hooks = hooks or {}
    kinematics, mu = _case(problem, friction)
    if mu != 0 and not all(getattr(p, "rigid", True) for p in getattr(problem, "pairs", ())):
        raise InputError(f"friction = {mu!r}: friction between two deformable bodies is not supported yet; solve "
                         "the two-body problem frictionless (friction=0).")
    if kinematics == "finite" and len(problem.pairs) > 1 and (mu != 0 or obstacle_path is not None):
        raise InputError(f"{len(problem.pairs)} contact pairs at kinematics='finite' run frictionless with fixed "
                         "masters so far; give friction 0 and no obstacle_path, or kinematics='small' (friction), "
                         "or one pair.")
    max_cutbacks = None  # an option of the frictional engines (in overrides), an argument of the frictionless one
    if kinematics == "finite" and mu == 0:
        if "max_cutbacks" in overrides:
            overrides = dict(overrides)
            max_cutbacks = overrides.pop("max_cutbacks")
        return _finite(problem, algorithm, penalty, options, steps, history, obstacle_path, max_cutbacks,
                       progress, overrides, hooks)
    if kinematics == "finite":
        return _finite_friction(problem, mu, algorithm, penalty, options, steps, history, obstacle_path,
                                max_cutbacks, progress, overrides, hooks)
    if obstacle_path is not None:
        raise InputError("obstacle_path: a moving obstacle needs kinematics='finite' (ContactProblem(..., "
                         "kinematics='finite') with a hyperelastic body); at small kinematics move the body with "
                         "a ramped support instead.")
    if mu != 0:
        return _small_friction(problem, mu, algorithm, penalty, options, steps, history, max_cutbacks, progress,
                               overrides, hooks)
    if steps is None and history is None:
        return _solve_static(problem, algorithm, penalty, options, **overrides)
    return _small_stepped(problem, algorithm, penalty, options, steps, history, progress, overrides)


def _times(steps, history):
    if steps is None:
        return tuple(history.times)
    if isinstance(steps, (int, np.integer)) and not isinstance(steps, bool):
        return LoadHistory.uniform(int(steps))
    return LoadHistory.check_times(steps)


def _small_stepped(problem, algorithm, penalty, options, steps, history, progress, overrides):
    """Frictionless small deformation over step times: one independent static solve per step (the problem is
    path independent); the run stops at the first failed step."""
    if history is not None and not isinstance(history, LoadHistory):
        raise InputError(f"history must be a LoadHistory or None; got {type(history).__name__}.")
    times = _times(steps, history)
    n = len(times)
    views = []
    for k, t in enumerate(times):
        if progress is not None:
            progress(k, n, t)
        p_t = problem_at(problem, history, t) if history is not None else problem
        sol = _solve_static(p_t, algorithm, penalty, options, **overrides)
        views.append(dataclasses.replace(sol, extra={**sol.extra, "t": float(t)}))
        if progress is not None:
            progress(k + 1, n, t)
        if not sol.result.success:
            break
    return stepped_solution(views)


def _engine_progress(given, progress):
    """The Coulomb engines' step callback ``(k, t, n)``: ``given`` as it is, else ``progress(k, n, t)`` of
    :func:`solve` (``None`` without either)."""
    if given is not None or progress is None:
        return given
    return lambda k, t, n: progress(k, n, t)


def _small_friction(problem, mu, algorithm, penalty, options, steps, history, max_cutbacks, progress, overrides,
                    hooks):
    if history is None:  # the problem's own loads at every step time
        history = LoadHistory((), _times(steps, None) if steps is not None else (1.0,))
        steps = None
    if max_cutbacks is not None:
        overrides = dict(overrides, max_cutbacks=max_cutbacks)
    cb = _engine_progress(hooks.get("on_step"), progress)
    fsol = _friction_engine(problem, history, algorithm, penalty, options, steps=steps, friction=mu, on_step=cb,
                            **overrides)
    if progress is not None:
        times = fsol.history.times
        progress(len(times), len(times), times[-1])
    return friction_solution(fsol)


def _finite(problem, algorithm, penalty, options, steps, history, obstacle_path, max_cutbacks, progress,
            overrides, hooks):
    if steps is None:
        steps = tuple(history.times) if isinstance(history, LoadHistory) else 10
    times = _times(steps, None)
    total = len(times)
    user = hooks.get("on_step")

    def collect(step, u, pressure):
        if user is not None:
            user(step, u, pressure)
        if progress is not None:
            done = sum(1 for t in times if t <= step.t + 1e-12 * max(1.0, abs(step.t)))
            progress(done, total, float(step.t))

    if progress is not None:
        progress(0, total, times[0])
    kw = {"max_cutbacks": hooks["max_cutbacks"]} if "max_cutbacks" in hooks else \
        ({} if max_cutbacks is None else {"max_cutbacks": max_cutbacks})
    fs = _finite_engine(problem, algorithm, penalty, options, steps=steps, history=history,
                        obstacle_path=obstacle_path, on_step=user if progress is None else collect, **kw,
                        **overrides)
    return finite_solution(fs, problem, history, obstacle_path)


def _finite_friction(problem, mu, algorithm, penalty, options, steps, history, obstacle_path, max_cutbacks,
                     progress, overrides, hooks):
    steps = finite_friction_steps(history, steps)
    if max_cutbacks is not None:
        overrides = dict(overrides, max_cutbacks=max_cutbacks)
    cb = _engine_progress(hooks.get("progress"), progress)
    fs = _finite_friction_engine(problem, mu, algorithm, penalty, options, steps=steps, history=history,
                                 obstacle_path=obstacle_path, on_step=hooks.get("on_step"), progress=cb,
                                 **overrides)
    if progress is not None:
        total = len(_times(steps, None))
        progress(total, total, float(fs.steps[-1].t) if fs.steps else 0.0)
    return finite_friction_solution(fs, problem, history)


# ---------------------------------------------------------------------------------------------------------------
# the former entry points: deprecated thin wrappers over :func:`solve`, kept for one release so that user code keeps
# running. They keep returning the engines' records (what their callers read); new code calls solve() and reads the
# ContactSolution and its frames, which have one convention for every case.
# ---------------------------------------------------------------------------------------------------------------
def _deprecated(name: str, instead: str) -> None:
    """Warn once per call site that ``name`` is deprecated, naming the :func:`solve` call that replaces it."""
    warnings.warn(f"alcontact.contact.{name} is deprecated and will be removed in the next release; call "
                  f"alcontact.contact.solve({instead}) instead: it returns a ContactSolution with one ContactFrame "
                  f"per step (solution.frames; the engine record this function returned is solution.record).",
                  DeprecationWarning, stacklevel=3)


def solve_friction(problem, history: LoadHistory | None, algorithm: str = "simo-laursen", penalty: str | None = None,
                   options=None, *, steps=None, friction: float | None = None, on_step=None, obstacle_path=None,
                   **option_overrides):
    """Coulomb friction over a load history: deprecated, a wrapper over :func:`solve` kept for one release.

    Prefer ``solve(problem, history=history, ...)``, which returns a :class:`ContactSolution`
    with one frame per step. This wrapper returns the stepping engine's own record
    (``solution.record``): a :class:`FrictionSolution` at small deformation (tangential
    tractions ``FrictionStep.traction_t`` in the local tangent bases, ``(m, d-1)``), a
    :class:`FiniteFrictionSolution` at finite deformation. Parameters as
    :func:`alcontact.contact.stepping._coulomb.solve_friction` (``on_step(k, t, n)`` before requested step ``k``).
    A zero coefficient still runs the frictional engine (as before).

    .. deprecated::
        Emits a :class:`DeprecationWarning`; use ``solve(problem, history=history,
        friction=mu, ...)``.
    """
    _deprecated("solve_friction", "problem, history=history, friction=mu, algorithm=..., penalty=..., **options")
    kinematics = getattr(problem, "kinematics", "small")
    mu = getattr(problem, "friction", 0.0) if friction is None else friction
    if kinematics != "finite":
        if not isinstance(history, LoadHistory):  # the engine names the error
            return _friction_engine(problem, history, algorithm, penalty, options, steps=steps, friction=friction,
                                    on_step=on_step, obstacle_path=obstacle_path, **option_overrides)
        if obstacle_path is not None:
            raise InputError("obstacle_path: a moving obstacle needs kinematics='finite' (ContactProblem(..., "
                             "kinematics='finite') with a hyperelastic body); at small kinematics move the body "
                             "with a ramped support instead.")
        return _small_friction(problem, mu, algorithm, penalty, options, steps, history, None, None,
                               option_overrides, {"on_step": on_step}).record
    return _finite_friction(problem, mu, algorithm, penalty, options, steps, history, obstacle_path, None, None,
                            option_overrides, {"progress": on_step}).record


def solve_finite(problem, algorithm: str = "simo-laursen", penalty: str | None = None, options=None, *,
                 steps=10, history: LoadHistory | None = None, obstacle_path=None, max_cutbacks: int = 6,
                 on_step=None, **option_overrides):
    """Frictionless finite-deformation load stepping: deprecated, a wrapper over :func:`solve` kept for one release.

    Prefer ``solve(problem, steps=..., ...)`` with ``problem.kinematics == "finite"``. Returns
    the engine's record (``solution.record``, a :class:`FiniteSolution`); parameters as
    :func:`alcontact.contact.stepping._frictionless.solve_finite` (``on_step(step, u, pressure)`` after every
    accepted step). ``problem.kinematics`` is not consulted (a linear body runs too).

    .. deprecated::
        Emits a :class:`DeprecationWarning`; use ``solve(problem, steps=..., history=...,
        obstacle_path=..., max_cutbacks=...)`` on a ``kinematics="finite"`` problem.
    """
    _deprecated("solve_finite", "problem, steps=..., history=..., obstacle_path=..., max_cutbacks=... (a problem with "
                "kinematics='finite')")
    return _finite(problem, algorithm, penalty, options, steps, history, obstacle_path, None, None,
                   option_overrides, {"on_step": on_step, "max_cutbacks": max_cutbacks}).record


def solve_finite_friction(problem, mu: float, algorithm: str = "simo-laursen", penalty: str | None = None,
                          options=None, *, steps=10, history: LoadHistory | None = None, obstacle_path=None,
                          on_step=None, progress=None, **option_overrides):
    """Coulomb friction at finite deformation: deprecated, a wrapper over :func:`solve` kept for one release.

    Prefer ``solve(problem, friction=mu, steps=..., ...)`` with ``problem.kinematics == "finite"``.
    Returns the engine's record (``solution.record``, a :class:`FiniteFrictionSolution`, its
    ``traction_t`` global ``(m, d)``); parameters as
    :func:`alcontact.contact.stepping._coulomb.solve_finite_friction`.

    .. deprecated::
        Emits a :class:`DeprecationWarning`; use ``solve(problem, friction=mu, steps=...,
        history=..., obstacle_path=..., on_step=...)`` on a ``kinematics="finite"`` problem.
    """
    _deprecated("solve_finite_friction", "problem, friction=mu, steps=..., history=..., obstacle_path=... (a problem "
                "with kinematics='finite')")
    return _finite_friction(problem, mu, algorithm, penalty, options, steps, history, obstacle_path, None, None,
                            option_overrides, {"on_step": on_step, "progress": progress}).record
