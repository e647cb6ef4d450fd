"""What the command line does, one Python call per command.

:func:`run_problem` is ``alcontact run``: build (or take) a contact problem,
solve it, summarize it against its analytical reference and, given a folder,
write the result files. :func:`list_components` is ``alcontact list``. The CLI
(:mod:`alcontact.cli`) only parses options, shows progress and prints.

Results folder written by :func:`write_results`:

``solution.vtu``
    Mesh and point fields (see :mod:`alcontact.io.vtu`).
``history.csv``
    One row per outer iteration (:data:`alcontact.io.HISTORY_COLUMNS`).
``pressure.png``
    Contact pressure along the contact boundary against the analytical profile.
``convergence.png``
    Penetration, complementarity and multiplier change per outer iteration (log scale).
``body_pressure.png``, ``body_von_mises.png``
    Pictures of the deformed body coloured by contact pressure and by von Mises stress
    (:mod:`alcontact.viz.pictures`).
``report.md``
    One page: problem, solver, outcome, key numbers against the reference, the plots.
``summary.json``
    Keys :data:`alcontact.io.SUMMARY_KEYS` (stable) plus extras, see
    :func:`summarize`; its ``files`` list is the manifest of the folder.

The folder is written as a whole (:class:`alcontact.io.ResultsFolder`): into a
staging folder beside it, moved into place when every file is written.

Examples
--------
>>> from alcontact.runner import run_problem
>>> sol, summary = run_problem(level=0)               # doctest: +SKIP
>>> summary["status"], summary["dofs"]                # doctest: +SKIP
('converged', 2232)
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import logging
import math
import os
import re
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from .errors import InputError, UnknownNameError

__all__ = [
    "BuiltinProblem",
    "BUILTIN_PROBLEMS",
    "DEFAULT_PROBLEM",
    "RESULT_FILES",
    "quick_bench_estimate",
    "build_problem",
    "run_problem",
    "summarize",
    "write_results",
    "what_to_try",
    "list_components",
    "run_setup",
    "run_benchmarks",
    "BENCH_SUITES",
    "write_setup_results",
    "RunOutput",
]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class BuiltinProblem:
    """A benchmark problem the CLI can run by name."""

    name: str
    doc: str
    factory: Callable[..., Any]  # factory(level=..., order=...) -> ContactProblem
    default_level: int
    levels: int  # number of refinement levels (0 .. levels-1)
    units: tuple[str, str] | None = None  # (length, stress) units of the plots and the report


def _hertz(kind: str):
    def factory(level: int, order: int):
        from .problems import hertz

        return (hertz.hertz_2d if kind == "2d" else hertz.hertz_3d)(level=level, order=order)

    return factory


#: Built-in problems by name. Default levels: about 10k DOFs, a few seconds.
BUILTIN_PROBLEMS: dict[str, BuiltinProblem] = {
    "hertz-2d": BuiltinProblem(
        "hertz-2d", "rigid cylinder on an elastic block, plane strain, half model (Hertz line contact)",
        _hertz("2d"), default_level=2, levels=6, units=("mm", "MPa"),
    ),
    "hertz-3d": BuiltinProblem(
        "hertz-3d", "rigid sphere on an elastic block, quarter model (Hertz point contact)",
        _hertz("3d"), default_level=0, levels=6, units=("mm", "MPa"),
    ),
}

DEFAULT_PROBLEM = "hertz-2d"

#: Files :func:`write_results` writes (``summary.json`` last).
RESULT_FILES: tuple[str, ...] = ("solution.vtu", "history.csv", "pressure.png", "convergence.png",
                                 "body_pressure.png", "body_von_mises.png", "report.md", "summary.json")


def build_problem(name: str = DEFAULT_PROBLEM, level: int | None = None, order: int = 1):
    """Build the built-in problem ``name`` at refinement ``level`` (default: its default level).

    Raises
    ------
    UnknownNameError
        ``name`` is not a built-in problem.
    InputError
        ``level`` is out of range.
    """
    if name not in BUILTIN_PROBLEMS:
        raise UnknownNameError("problem", name, list(BUILTIN_PROBLEMS))
    spec = BUILTIN_PROBLEMS[name]
    lvl = spec.default_level if level is None else int(level)
    if not 0 <= lvl < spec.levels:
        raise InputError(f"level={level!r} is out of range for {name!r}; use 0 .. {spec.levels - 1}.")
    return spec.factory(level=lvl, order=order)


def _finite_or_none(x) -> float | None:
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def _error_pct(num, exact) -> float | None:
    if num is None or exact is None or exact == 0:
        return None
    return 100.0 * (num - exact) / exact


def _complementarity(gap, pressure, h: float) -> float:
    """The ``complementarity`` measure of :func:`alcontact.contact.check_state` of a returned step (the one its
    verification checked)."""
    from .contact import check_state

    return check_state(gap, pressure, h, tol_penetration=1.0, tol_complementarity=1.0).value("complementarity")


def equilibrium_keys(eq) -> dict[str, Any]:
    """``summary.json`` keys of an :class:`~alcontact.contact._estimators.Equilibrium`."""
    return {
        "equilibrium_residual": float(eq.residual),
        "equilibrium_free_residual": float(eq.free_residual),
        "reaction_force_vector": [float(x) for x in eq.reaction],
        "applied_load_vector": [float(x) for x in eq.applied_load],
        "contact_force_from_nodal_forces": [float(x) for x in eq.contact_force],
    }


def _half_width_measure(solution, axis: int, center) -> str:
    from .viz.plots import contact_center

    return "from the contact centre" if contact_center(solution, center, declared=False) is not None \
        else "half the extent of the loaded zone"


def summarize(problem, solution, *, problem_name: str | None = None, level: int | None = None,
              options: dict | None = None, build_time_s: float | None = None) -> dict[str, Any]:
    r"""The ``summary.json`` dictionary of a solved problem.

    Stable keys (:data:`alcontact.io.SUMMARY_KEYS`):

    ``status``
        ``"converged"`` or the failure label (``"maxiter"``, ``"newton-failed"``,
        ``"no-contact"``, ``"nonfinite"``, ``"penalty-limit"``).
    ``algorithm``, ``penalty``
        Registry names (the penalty actually used, e.g. ``"rockafellar"`` for simo-laursen).
    ``dofs``, ``outer_iterations``, ``newton_iterations``, ``linear_solves``
        Model size and solver counters.
    ``wall_time_s``
        Wall time of :func:`alcontact.contact.solve` (setup, factorization,
        contact iterations; not the mesh generation nor the file output).
    ``linear_solve_time_s``
        One factorization plus one solve of the same stiffness, measured in the
        same run (``solution.timings["linear_solve_s"]``), so
        ``time_ratio_contact_to_linear`` compares the contact solve with a linear one.
        Finite-deformation runs (:func:`run_setup`): the mean of the run's Newton linear
        solves (``linear_solve_time_kind = "mean Newton linear solve"``), with their total
        ``linear_solve_time_total_s`` and number ``linear_solve_count``.
    ``contact_half_width``, ``contact_half_width_exact``
        Computed half-width ``a`` (contact radius in 3D) and the analytical one
        for the load the model carries. Measured from the contact centre
        (``problem.meta["center"]``); a problem file's centre that is only the default
        origin (``meta["center_declared"]`` false) is used while it lies in the
        contact zone, otherwise ``a`` is half the extent of the loaded zone
        (:func:`alcontact.viz.contact_half_width`), never the distance of the zone
        from the origin.
    ``peak_pressure``, ``peak_pressure_exact``
        Estimated peak pressure and the analytical ``p0``.
    ``total_contact_force``
        Total load ``P`` of the full (unsymmetrized) body:
        ``reference.load(normal_force)``, i.e. 2x the half model's contact force
        in 2D (per unit thickness) and 4x the quarter model's in 3D; the
        model's own force is ``model_contact_force``, the sum of the normal nodal
        contact forces the solver applied. Without a reference, the model's force.

    Estimators (``docs/estimators.md``): for a problem whose reference is a Hertz
    profile, ``peak_pressure`` is ``p0`` of the L2 least-squares fit of
    :math:`p_0\sqrt{1-r^2/a^2}` to the recovered pressure and ``contact_half_width``
    is ``a`` of the load-matched fit (the profile carries the model's contact load);
    otherwise the largest recovered pressure and the outermost loaded point
    interpolated along the boundary. ``peak_pressure_nodal_max`` is the raw
    largest nodal pressure, ``contact_half_width_edge`` the interpolated edge.
    ``equilibrium_residual`` is :math:`|F_c + F_{ext} + R|` (contact force, applied loads,
    support reactions; ``contact_force_vector``, ``applied_load_vector``,
    ``reaction_force_vector``) and ``equilibrium_free_residual`` the largest imbalance on a
    free DOF, both over the force scale of :func:`alcontact.contact._estimators.equilibrium`
    (which does not vanish with the contact force); a converged result has both below its
    equilibrium tolerance (``newton_tol``, at least 1e-11; see :mod:`alcontact.contact._verify`),
    as ``penetration`` and ``complementarity``, the measures the verification checked on the
    returned state, are below theirs.

    Exact values and errors are ``None`` when the problem has no analytical reference.
    Extras: ``problem``, ``problem_label``, ``level``, ``dim``, ``order``,
    ``status_code``, ``message``, the errors in percent, ``penetration``,
    ``complementarity``, ``residual``, ``eps_n``, ``time_ratio_contact_to_linear``,
    ``timings``, ``options``, ...
    """
    res = solution.result
    model = problem.model
    meta = getattr(problem, "meta", None) or {}
    ref = getattr(problem, "reference", None)
    center = meta.get("center")
    axis = int(meta.get("symmetry_axis", 0))

    from .viz.plots import edge_search_applies, contact_half_width

    declared = bool(meta.get("center_declared", True))
    if (declared or center is None) and edge_search_applies(solution):
        a_num = float(solution.contact_half_width(axis=axis, center=center))
        a_edge = float(solution.contact_half_width_edge(axis=axis, center=center))
    else:  # a problem file's default centre (the origin) only while it lies in the contact zone; a curved 3D
        # boundary has no line of a flat plane to search the edge on (viz.contact_half_width)
        a_num = a_edge = contact_half_width(solution, axis=axis, center=center, declared=declared)
    p_num = float(solution.peak_pressure)
    p_max = float(solution.peak_pressure_nodal_max)
    f_model = float(solution.normal_force)
    eq = solution.equilibrium()
    a_ex = p_ex = None
    load = f_model
    if ref is not None:
        load = float(ref.load(f_model))
        if load > 0:
            try:  # a load or radius at the edge of double precision: no reference rather than a traceback
                a_ex = float(ref.half_width(load))
                p_ex = float(ref.peak_pressure(load))
            except (ZeroDivisionError, OverflowError):
                a_ex = p_ex = None
            a_ex, p_ex = (None, None) if a_ex is None or not (math.isfinite(a_ex) and a_ex > 0
                                                               and math.isfinite(p_ex)) else (a_ex, p_ex)
    wall = float(solution.timings.get("total_s", float("nan")))
    lin = float(solution.timings.get("linear_solve_s", float("nan")))
    ratio = wall / lin if lin > 0 else None

    summary: dict[str, Any] = {
        # --- stable contract (SUMMARY_KEYS) ---
        "status": res.status.label,
        "algorithm": res.algorithm,
        "penalty": res.penalty,
        "dofs": int(solution.extra.get("dofs", model.ndofs)),
        "outer_iterations": int(res.outer_iterations),
        "newton_iterations": int(res.newton_iterations),
        "linear_solves": int(res.linear_solves),
        "wall_time_s": _finite_or_none(wall),
        "linear_solve_time_s": _finite_or_none(lin),
        "contact_half_width": a_num,
        "contact_half_width_exact": a_ex,
        "peak_pressure": p_num,
        "peak_pressure_exact": p_ex,
        "total_contact_force": load,
        # --- extras ---
        "problem": problem_name or getattr(problem, "name", "contact"),
        "problem_label": getattr(problem, "name", None),
        "level": level,
        "dim": int(model.dim),
        "order": int(getattr(model, "order", 1)),
        "status_code": int(res.status),
        "message": res.message,
        "contact_half_width_error_pct": _error_pct(a_num, a_ex),
        "contact_half_width_measure": "from the contact centre" if declared or center is None or a_ex is not None
        else _half_width_measure(solution, axis, center),
        "peak_pressure_error_pct": _error_pct(p_num, p_ex),
        "model_contact_force": f_model,
        "contact_force_vector": np.asarray(solution.total_contact_force, dtype=float).tolist(),
        **equilibrium_keys(eq),
        "peak_pressure_nodal_max": p_max,
        "peak_pressure_nodal_max_error_pct": _error_pct(p_max, p_ex),
        "contact_half_width_edge": a_edge,
        "contact_half_width_edge_error_pct": _error_pct(a_edge, a_ex),
        "penetration": float(res.penetration),
        "complementarity": float(res.complementarity),
        "residual": float(res.residual),
        "eps_n": float(res.eps_n),
        "factorizations": int(res.factorizations),
        "time_ratio_contact_to_linear": ratio,
        "build_time_s": build_time_s,
        "element_size_h": solution.extra.get("h"),
        "contact_candidates": solution.extra.get("candidates"),
        "active_points": int(np.count_nonzero(solution.active)),
        "timings": dict(solution.timings),
        "options": dict(options or {}),
        "alcontact_version": __version__,
        "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
    }
    return summary


def _tolerances(options: dict) -> dict[str, float]:
    from .contact import ContactOptions

    known = {f.name for f in dataclasses.fields(ContactOptions)}
    opts = ContactOptions(**{k: v for k, v in options.items() if k in known})
    return {
        "penetration": opts.tol_penetration,
        "complementarity": opts.tol_complementarity,
        "multiplier_change": opts.tol_multiplier,
    }


def _per_radian(model, summary: dict) -> dict[str, Any]:
    """A body of revolution (``geometry = "axisymmetric"``): its forces are totals over the revolution
    (2 pi integrated); the summary adds ``geometry`` and every force key again per radian (``<key>_per_radian``)."""
    if not model.axisymmetric:
        return {}
    out: dict[str, Any] = {"geometry": "axisymmetric",
                           "forces": "totals over the revolution (2 pi integrated); *_per_radian: divided by 2 pi"}
    def numbers(v):  # a number or a (nested) list of numbers
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return True
        return isinstance(v, list) and bool(v) and all(numbers(x) for x in v)

    def per_radian(v):
        return [per_radian(x) for x in v] if isinstance(v, list) else float(v) / (2.0 * math.pi)

    for key, v in summary.items():
        if "force" in key and numbers(v):
            out[f"{key}_per_radian"] = per_radian(v)
    return out


def write_results(out: str | os.PathLike, problem, solution, summary: dict, *,
                  tolerances: dict | None = None, units=None, description: str = "") -> dict[str, Path]:
    """Write the result files of :data:`RESULT_FILES` into the existing folder ``out``.

    Each file is written atomically; ``summary.json`` is written last. To get
    the whole set or nothing, write into :class:`alcontact.io.ResultsFolder`
    (as :func:`run_problem` does). ``units`` (:class:`alcontact.viz.Units`)
    label the plots. Returns ``{file name: path}``.
    """
    from .io import write_history_csv, write_json, write_solution_vtu
    from .io.report import write_report
    from .viz import save_convergence_plot, save_pressure_plot
    from .viz.pictures import save_body_pictures

    out = Path(out)
    paths = {name: out / name for name in RESULT_FILES}
    write_solution_vtu(paths["solution.vtu"], solution)
    write_history_csv(paths["history.csv"], solution.result.history)
    save_pressure_plot(solution, paths["pressure.png"], units=units)
    save_convergence_plot(solution.result, paths["convergence.png"], tolerances=tolerances)
    save_body_pictures(solution, out, units=units, title=summary.get("problem_label") or summary.get("problem"))
    write_report(paths["report.md"], summary, list(RESULT_FILES), description=description, units=units)
    write_json(paths["summary.json"], {**summary, **_per_radian(problem.model, summary), "files": list(RESULT_FILES)})
    logger.info("results written to %s", out)
    return paths


_ADVICE = {
    "maxiter": "raise the iteration limit (--maxiter), try another algorithm (--algorithm ssn or "
               "--algorithm family-p), or a different penalty stiffness (--penalty-scale).",
    "newton-failed": "lower the penalty stiffness (--penalty-scale 10), try another penalty "
                     "(--algorithm family-p --penalty NAME, see `alcontact list`) or --algorithm ssn.",
    "nonfinite": "lower the penalty stiffness (--penalty-scale), or use a penalty without a barrier "
                 "(--penalty exp-met1); check the material constants and loads.",
    "penalty-limit": "the penalty stiffness hit its limit: raise --maxiter, or use an augmented "
                     "Lagrangian algorithm (simo-laursen, family-p) instead of the pure penalty.",
    "no-contact": "the body does not reach the obstacle: move the obstacle closer, increase the "
                  "load or check the contact boundary name.",
    "unbounded": "no static equilibrium: the loads exceed what the supports, the obstacle and friction can "
                 "hold (see the message); prescribe that motion as a displacement, or add a support.",
    "not-verified": "the returned state fails a tolerance (see the message): tighten newton_tol, raise "
                    "--maxiter, or try --algorithm ssn; report it if the reference fails too.",
}


def what_to_try(status) -> str:
    """One line of advice for a failed solve (empty when it converged).

    ``status``: a ``ContactResult``, a ``ContactStatus`` or its label
    (``summary["status"]``).
    """
    status = getattr(status, "status", status)
    label = getattr(status, "label", status)
    if label == "converged":
        return ""
    return _ADVICE.get(str(label), "try another algorithm (see `alcontact list`).")


def run_problem(problem=None, out: str | os.PathLike | None = None, algorithm: str | None = None,
                penalty: str | None = None, force: bool = False, *, level: int | None = None,
                order: int = 1, progress: Callable[[str], None] | None = None, **options):
    """Solve a contact problem and (optionally) write its results folder.

    Parameters
    ----------
    problem : None, str or ContactProblem
        ``None``: the built-in 2D Hertz problem; a name from
        :data:`BUILTIN_PROBLEMS`; or a problem object (``level``/``order`` unused).
    out : path-like, optional
        Results folder; ``None`` writes nothing.
    algorithm : str, optional
        Default :data:`alcontact.contact.DEFAULT_ALGORITHM`.
    penalty : str, optional
        Penalty of ``family-p`` (default :data:`alcontact.contact.DEFAULT_PENALTY`).
    force : bool
        Write into a non-empty ``out`` (replacing our files).
    level, order : int
        Refinement level and polynomial order of a built-in problem.
    progress : callable, optional
        Called with a short phase description ("building", "solving", ...).
    **options
        Fields of :class:`alcontact.contact.ContactOptions` (``None`` values are ignored).

    Returns
    -------
    solution : ContactSolution
    summary : dict
        As written to ``summary.json`` (see :func:`summarize`).

    Raises
    ------
    OutputExistsError
        ``out`` is a non-empty folder and ``force`` is false (checked before solving).
    UnknownNameError, InputError
        Unknown problem/algorithm/penalty/option or a value out of range.

    Notes
    -----
    A failed solve raises nothing: ``summary["status"]`` is the failure label
    and the files are still written (they help to see what went wrong).
    """
    from .contact import DEFAULT_ALGORITHM, available_algorithms, solve
    from .io import ResultsFolder, check_output_dir

    def report(msg: str) -> None:
        logger.info(msg)
        if progress is not None:
            progress(msg)

    options = {k: v for k, v in options.items() if v is not None}
    algorithm = algorithm or DEFAULT_ALGORITHM
    if algorithm not in available_algorithms():
        raise UnknownNameError("algorithm", algorithm, available_algorithms())
    if out is not None:
        check_output_dir(out, force)  # fail before the (long) solve

    t0 = time.perf_counter()
    if problem is None or isinstance(problem, str):
        name = problem or DEFAULT_PROBLEM
        spec = BUILTIN_PROBLEMS.get(name)
        lvl = level if level is not None or spec is None else spec.default_level
        report(f"building {name} (level {lvl}, P{order})")
        prob = build_problem(name, lvl, order)
    else:
        name, lvl, prob, spec = getattr(problem, "name", "contact"), None, problem, None
    build_time = time.perf_counter() - t0

    report(f"solving {name} with {prob.model.ndofs} DOFs ({algorithm})")
    solution = solve(prob, algorithm=algorithm, penalty=penalty, **options)
    summary = summarize(prob, solution, problem_name=name, level=lvl, options=options, build_time_s=build_time)
    units = None
    if spec is not None and spec.units:
        from .viz import Units

        units = Units(*spec.units)
        summary["units"] = {"length": units.length, "stress": units.pressure, "force": units.force(prob.model.dim)}
    logger.info("%s: %s after %d outer iterations", name, summary["status"], summary["outer_iterations"])

    if out is not None:
        report(f"writing results to {out}")
        doc = spec.doc if spec is not None else ""
        with ResultsFolder(out, force) as folder:
            write_results(folder.path, prob, solution, summary, tolerances=_tolerances(options), units=units,
                          description=doc[:1].upper() + doc[1:] + "." if doc else "")
    return solution, summary


def list_components() -> dict[str, dict[str, str]]:
    """Registered names with one line each: what ``alcontact list`` prints.

    Returns
    -------
    dict
        ``{"algorithms": ..., "friction-algorithms": ..., "penalties": ..., "obstacles": ...,
        "problems": ..., "examples": ...}`` (``examples``: the problem files of the repository),
        each ``{name: one-line description}``. Penalties usable by the
        ``family-p`` algorithm are marked ``[contact]``.
    """
    from . import penalties
    from .contact import contact_penalties, obstacles
    from .contact._algorithms import describe_algorithms

    usable = set(contact_penalties())
    pens = {name: (f"[contact] {doc}" if name in usable else doc) for name, doc in penalties.describe().items()}
    from .io.schema import _repo_root

    examples = {}
    ex_dir = _repo_root() / "examples"
    if ex_dir.is_dir():
        for f in sorted(ex_dir.glob("*.toml")):
            first = next((ln.lstrip("# ").strip() for ln in f.read_text(encoding="utf-8").splitlines()
                          if ln.startswith("#")), "")
            examples[f"examples/{f.name}"] = first
    return {
        "algorithms": describe_algorithms(friction=False),  # one registry, with what each entry supports
        "friction-algorithms": describe_algorithms(friction=True),
        "penalties": pens,
        "obstacles": dict(obstacles.docs()),
        "problems": {
            name: f"{spec.doc} (--level 0..{spec.levels - 1}, default {spec.default_level})"
            for name, spec in BUILTIN_PROBLEMS.items()
        },
        "examples": examples,
    }


# =========================================================================== problem files
def _friction_frames(fsol) -> list:
    """One :class:`~alcontact.contact.ContactSolution` per converged step of a frictional solve.

    The frames carry the frictional fields in ``extra`` (``slip``, ``slip_increment``,
    ``state``, ``shear``, ``tangential_force``, ``mu``, ``t``) so that the VTU
    writer, the plots and :func:`summarize` treat both kinds of run alike.
    """
    from .contact import ContactResult, ContactSolution, ContactStatus

    problem = fsol.problem
    m, d = fsol.points.shape
    steps = list(fsol.steps)
    frames = []
    timings = {**fsol.timings, "linear_solve_s": fsol.timings.get("factor_s", float("nan"))}
    for k, st in enumerate(steps):
        last = k == len(steps) - 1
        status = fsol.status if last else ContactStatus.CONVERGED
        result = ContactResult(
            status=status, message=fsol.message if last else "converged", algorithm=fsol.algorithm,
            penalty=fsol.penalty, outer_iterations=int(st.outer_iterations), newton_iterations=int(st.newton_iterations),
            linear_solves=int(fsol.linear_solves), factorizations=int(fsol.factorizations),
            penetration=float(st.penetration), complementarity=_complementarity(st.gap, st.pressure, fsol.h),
            residual=float("nan"), eps_n=float(fsol.eps_n), history=())
        frames.append(ContactSolution(
            problem=problem, u=st.u, points=fsol.points, pressure=st.pressure, gap=st.gap, weights=fsol.weights,
            active=st.state != 0, normals=fsol.normals, total_contact_force=st.contact_force, result=result,
            timings=timings,
            extra={"t": float(st.t), "requested": bool(st.requested), "slip": st.slip_total,
                   "slip_increment": st.slip, "state": st.state, "shear": st.shear,
                   "tangential_force": np.asarray(st.tangential_force, dtype=float),
                   "mu": float(fsol.friction) * float(fsol.history.friction_factor(st.t)),
                   "coulomb": float(st.coulomb), "cutbacks": int(st.cutbacks), "h": fsol.h,
                   "candidates": fsol.extra.get("candidates"), "dofs": fsol.extra.get("dofs")}))
    if not frames:  # nothing converged: report the contact-free start
        z = np.zeros(m)
        result = ContactResult(status=fsol.status, message=fsol.message, algorithm=fsol.algorithm,
                               penalty=fsol.penalty, outer_iterations=0, newton_iterations=0,
                               linear_solves=int(fsol.linear_solves), factorizations=1, penetration=0.0,
                               complementarity=float("nan"), residual=float("nan"), eps_n=float(fsol.eps_n))
        frames.append(ContactSolution(
            problem=problem, u=np.zeros(problem.model.ndofs), points=fsol.points, pressure=z, gap=z,
            weights=fsol.weights, active=z.astype(bool), normals=fsol.normals, total_contact_force=np.zeros(d),
            result=result, timings=timings,
            extra={"t": 0.0, "slip": np.zeros((m, d)), "slip_increment": np.zeros((m, d)),
                   "state": np.zeros(m, int), "shear": np.zeros((m, d)), "tangential_force": np.zeros(d),
                   "mu": float(fsol.friction), "h": fsol.h, "dofs": problem.model.ndofs}))
    return frames


def _solve_finite_setup(setup, on_step=None):
    """Finite-deformation run of a problem file: ``(FiniteSolution, frames)``.

    One :class:`~alcontact.contact.ContactSolution` per accepted step (from the
    ``on_step`` hook of :func:`~alcontact.contact.solve_finite`); the last frame is
    the verified solution of the run. Each frame's problem carries the loads of
    its step time (``problem_at``), so ``frame.equilibrium()`` is that step's balance.
    """
    from .contact import ContactSolution, problem_at, solve_finite
    from .contact.obstacles import translate

    prob = setup.problem
    model = prob.model
    _, dofs = model.node_dofs(prob.contact_boundary)
    states: list[tuple[Any, np.ndarray, np.ndarray]] = []
    total = len(setup.times)

    def collect(step, u, pressure):
        states.append((step, u, pressure))
        if on_step is not None:
            done = sum(1 for t in setup.times if t <= step.t + 1e-12 * max(1.0, abs(step.t)))
            on_step(done, total, float(step.t))

    def at(t: float):
        return problem_at(prob, setup.history, t) if setup.history is not None else prob

    path = None
    if setup.obstacle_path is not None:
        path = setup.obstacle_offset
    if on_step is not None:
        on_step(0, total, setup.times[0])
    fs = solve_finite(prob, setup.algorithm, setup.penalty, steps=list(setup.times), history=setup.history,
                      obstacle_path=path, max_cutbacks=setup.max_cutbacks, on_step=collect, **setup.options)
    base = fs.solution
    frames = []
    for k, (step, u, pressure) in enumerate(states[:-1] if fs.steps else []):
        ob = prob.obstacle if path is None else translate(prob.obstacle, path(step.t))
        gap, normals = ob.evaluate(base.points + u[dofs])
        nodal = base.weights * pressure
        res = dataclasses.replace(base.result, status=step.status, message=step.message,
                                  outer_iterations=int(step.outer_iterations),
                                  newton_iterations=int(step.newton_iterations),
                                  linear_solves=int(step.linear_solves), history=(),
                                  penetration=float(max(np.max(gap, initial=0.0), 0.0)) / float(base.extra["h"]))
        frames.append(ContactSolution(
            problem=at(step.t), u=u, points=base.points, pressure=pressure, gap=np.asarray(gap, dtype=float),
            weights=base.weights, active=pressure > 0, normals=np.asarray(normals, dtype=float),
            total_contact_force=np.asarray(step.force, dtype=float), result=res, nodal_forces=nodal,
            timings={"total_s": float(step.seconds)},
            extra={**base.extra, "t": float(step.t), "cutbacks": int(step.cutbacks), "seconds": float(step.seconds),
                   "requested": bool(getattr(step, "requested", True))}))
    if fs.steps:
        last = fs.steps[-1]
        frames.append(dataclasses.replace(base, problem=at(last.t), extra={
            **base.extra, "t": float(last.t), "cutbacks": int(last.cutbacks), "seconds": float(last.seconds),
            "requested": bool(getattr(last, "requested", True)),
            "step_newton_iterations": int(last.newton_iterations), "step_outer_iterations": int(last.outer_iterations)}))
        for fr, st in zip(frames[:-1], fs.steps[:-1]):
            fr.extra.update(step_newton_iterations=int(st.newton_iterations),
                            step_outer_iterations=int(st.outer_iterations))
    else:  # no step was accepted: the undeformed start with the failure status
        frames.append(dataclasses.replace(base, extra={**base.extra, "t": 0.0, "cutbacks": 0}))
    return fs, frames


def _solve_finite_friction_setup(setup, on_step=None):
    """Finite-deformation run with Coulomb friction: ``(FiniteFrictionSolution, frames)``.

    :func:`~alcontact.contact.solve_friction` dispatches the ``kinematics = "finite"``
    problem to :func:`~alcontact.contact.solve_finite_friction`. One
    :class:`~alcontact.contact.ContactSolution` per accepted step, as for frictionless
    finite runs (deformed configuration, the step's loads in ``problem``), with the
    frictional fields in ``extra`` (``slip``, ``slip_increment``, ``state``, ``shear``,
    ``tangential_force``, ``dissipation``) so the VTU writer, the rows and the plots
    treat it like the other stepped runs.
    """
    from .contact import ContactResult, ContactSolution, problem_at, solve_friction

    prob = setup.problem
    total = len(setup.times)
    path = setup.obstacle_offset if setup.obstacle_path is not None else None
    fopts = dict(setup.friction_options)
    fopts.setdefault("max_cutbacks", setup.max_cutbacks)

    def progress(k: int, t: float, n: int) -> None:
        if on_step is not None:
            on_step(k, n, t)

    fs = solve_friction(prob, setup.history, setup.algorithm, setup.penalty, steps=list(setup.times),
                        obstacle_path=path, on_step=progress, **fopts)
    if on_step is not None:
        on_step(total, total, float(fs.steps[-1].t) if fs.steps else 0.0)
    ex = fs.extra
    points, weights, h = ex["points"], ex["weights"], float(ex["h"])
    m, d = points.shape

    def at(t: float):
        return problem_at(prob, setup.history, t) if setup.history is not None else prob

    frames = []
    slip_total = np.zeros((m, d))
    for k, st in enumerate(fs.steps):
        last = k == len(fs.steps) - 1
        slip_total = slip_total + st.slip
        result = ContactResult(
            status=fs.status if last else st.status, message=fs.message if last else st.message,
            algorithm=str(ex["algorithm"]), penalty=str(ex["penalty"]), outer_iterations=int(st.outer_iterations),
            newton_iterations=int(st.newton_iterations), linear_solves=int(st.linear_solves),
            factorizations=int(st.linear_solves), penetration=float(max(np.max(st.gap, initial=0.0), 0.0)) / h,
            complementarity=_complementarity(st.gap, st.pressure, h), residual=float("nan"), eps_n=float(ex["eps_n"]))
        frames.append(ContactSolution(
            problem=at(st.t), u=st.u, points=points, pressure=st.pressure, gap=st.gap, weights=weights,
            active=st.states != 0, normals=st.normals, total_contact_force=np.asarray(st.force, dtype=float),
            result=result, nodal_forces=weights * st.pressure,
            timings={"total_s": float(ex["total_s"]), "linear_solve_s": float(ex.get("linear_solve_s", float("nan")))}
            if last else {"total_s": float(st.seconds)},
            extra={"t": float(st.t), "cutbacks": int(st.cutbacks), "seconds": float(st.seconds),
                   "requested": bool(getattr(st, "requested", True)),
                   "step_newton_iterations": int(st.newton_iterations),
                   "step_outer_iterations": int(st.outer_iterations), "slip": slip_total.copy(),
                   "slip_increment": st.slip, "state": st.states, "shear": -np.asarray(st.traction_t, dtype=float),
                   "tangential_force": np.asarray(st.tangential_force, dtype=float), "mu": float(ex["mu"]),
                   "dissipation": float(st.dissipation), "h": h, "dofs": int(ex["dofs"])}))
    if not frames:  # nothing converged: the undeformed start with the failure status
        z = np.zeros(m)
        result = ContactResult(status=fs.status, message=fs.message, algorithm=str(ex["algorithm"]),
                               penalty=str(ex["penalty"]), outer_iterations=0, newton_iterations=0,
                               linear_solves=int(ex["linear_solves"]), factorizations=int(ex["linear_solves"]),
                               penetration=0.0, complementarity=float("nan"), residual=float("nan"),
                               eps_n=float(ex["eps_n"]))
        frames.append(ContactSolution(
            problem=prob, u=np.asarray(fs.u, dtype=float), points=points, pressure=z, gap=np.asarray(fs.gap),
            weights=weights, active=z.astype(bool), normals=fs.normals, total_contact_force=np.zeros(d),
            result=result, timings={"total_s": float(ex["total_s"])},
            extra={"t": 0.0, "cutbacks": 0, "seconds": 0.0, "slip": np.zeros((m, d)),
                   "slip_increment": np.zeros((m, d)), "state": np.zeros(m, int), "shear": np.zeros((m, d)),
                   "tangential_force": np.zeros(d), "mu": float(ex["mu"]), "dissipation": 0.0, "h": h,
                   "dofs": int(ex["dofs"])}))
    return fs, frames


def _finite_friction_summary(setup, fs, frames) -> dict[str, Any]:
    """``summary.json`` keys of the friction of a finite-deformation run (per accepted step, and the totals)."""
    final = frames[-1]
    steps = fs.steps
    tf = np.asarray(final.extra["tangential_force"], dtype=float)
    st = np.asarray(final.extra["state"])
    return {
        "step_dissipation": [float(s.dissipation) for s in steps],
        "dissipation": float(sum(s.dissipation for s in steps)),
        "step_normal_force": [float(s.normal_force) for s in steps],
        "step_tangential_force": [[float(x) for x in s.tangential_force] for s in steps],
        "step_stored_energy": [float(s.stored_energy) for s in steps],
        "step_obstacle_offset": [[float(x) for x in s.offset] for s in steps],
        "tangential_force": float(np.linalg.norm(tf)), "tangential_force_vector": tf.tolist(),
        "coulomb_limit": float(setup.friction * final.normal_force),
        "stick_points": int(np.sum(st == 1)), "slip_points": int(np.sum(st == 2)), "open_points": int(np.sum(st == 0)),
        "eps_t": float(fs.extra["eps_t"]),
    }


#: keys of ``solution.extra`` of a finite-deformation run copied to ``summary.json``
_FINITE_SOLVER_KEYS = ("linear_solver", "direct_solver", "amg_setups", "cg_iterations", "cg_per_newton",
                       "direct_fallbacks")


def _finite_summary(setup, fs, frames, wall: float) -> dict[str, Any]:
    """``summary.json`` keys of a finite-deformation run (the per-step lists have one entry per accepted step)."""
    final = frames[-1]
    steps = fs.steps
    res = final.result
    out: dict[str, Any] = {
        "kinematics": "finite",
        "material_model": getattr(setup.problem.model.law, "name", None),
        "status": res.status.label, "status_code": int(res.status), "message": res.message,
        "converged_steps": sum(1 for t in setup.times if steps and t <= steps[-1].t + 1e-12 * max(1.0, abs(t))),
        "accepted_steps": len(steps),
        "outer_iterations": int(sum(s.outer_iterations for s in steps)),
        "newton_iterations": int(sum(s.newton_iterations for s in steps)),
        "linear_solves": int(sum(s.linear_solves for s in steps)),
        "wall_time_s": float(final.timings.get("total_s", wall)),
        "step_times": [float(s.t) for s in steps],
        # False: a sub-step a cut-back inserted (halved increment); step_times holds both kinds
        "step_requested": [bool(getattr(s, "requested", True)) for s in steps],
        "step_newton_iterations": [int(s.newton_iterations) for s in steps],
        "step_outer_iterations": [int(s.outer_iterations) for s in steps],
        "step_cutbacks": [int(s.cutbacks) for s in steps],
        "step_seconds": [float(s.seconds) for s in steps],
        "step_contact_force": [[float(x) for x in s.force] for s in steps],
        "cutbacks": int(sum(s.cutbacks for s in steps)),
        "final_contact_force": [float(x) for x in final.total_contact_force],
        "max_cutbacks": int(setup.max_cutbacks),
        "obstacle_path": list(setup.obstacle_path) if setup.obstacle_path is not None else None,
        # the linear-solver path of the Newton systems (direct factorization or AMG + CG) and its counters
        **{k: final.extra[k] for k in _FINITE_SOLVER_KEYS if k in final.extra},
    }
    if steps:
        out.update(equilibrium_keys(final.equilibrium()))
    # the solver times all its Newton linear solves together: one solve is their mean
    total = final.timings.get("linear_solve_s")
    total = total if total is not None and math.isfinite(total) else None
    count = int(fs.extra.get("linear_solves", final.result.linear_solves))  # the run's (friction: its extra)
    lin = total / count if total and count > 0 else None
    out["linear_solve_time_s"] = lin
    out["linear_solve_time_total_s"] = total
    out["linear_solve_count"] = count
    out["linear_solve_time_kind"] = "mean Newton linear solve" if lin else None
    out["time_ratio_contact_to_linear"] = out["wall_time_s"] / lin if lin else None
    if not fs.success:
        reached = float(steps[-1].t) if steps else 0.0
        out["message"] = (f"stopped at t={reached:g} of t={setup.times[-1]:g} ({len(steps)} accepted steps, "
                          f"{out['cutbacks']} cut-backs): {fs.message}")
    return out


def _controls(setup) -> list[tuple[str, str, str, int]]:
    """Boundaries whose mean displacement is the abscissa of the load-displacement curve.

    The first ramped normal action and the first ramped tangential one:
    ``(label, kind, boundary, component)``.
    """
    from .contact import Support

    out = []
    hist = setup.history
    if hist is None:
        return out
    for want in ("normal", "tangential"):
        for case in hist.cases:
            if case.tangential != (want == "tangential") or not hasattr(case.item, "boundary"):
                continue
            item = case.item
            dim = setup.problem.model.dim
            if isinstance(item, Support) and item.components is not None:
                comp = int(item.components[0])
            elif isinstance(item, Support):
                comp = int(np.argmax(np.abs(np.broadcast_to(np.asarray(item.value, float), (dim,)))))
            else:
                comp = dim - 1 if want == "normal" else 0
            out.append((f"{item.boundary}_{'xyz'[comp]}", want, item.boundary, comp))
            break
    return out


def _prescribed(setup, t: float) -> dict[str, float]:
    """What the problem file prescribes at pseudo-time ``t``: ``reaction_force.csv``'s leading columns.

    ``prescribed_u_<boundary>_<x|y|z>``: the value of each ramped support component (value x
    amplitude; zero throughout: left out by :func:`_prescribed_quantities`),
    ``load_factor_<load>``: the amplitude of each ramped load, ``obstacle_<x|y|z>`` and
    ``obstacle_travel``: the obstacle's translation ``t * path`` and the distance it has
    travelled along its (straight) path.
    """
    from .contact import Support

    out: dict[str, float] = {}
    dim = int(setup.problem.model.dim)
    for case in (setup.history.cases if setup.history is not None else ()):
        a = float(case.value(t))
        item = case.item
        if isinstance(item, Support):
            if callable(item.value):  # a field of values (Python API): no single prescribed number
                continue
            comps = range(dim) if item.components is None else item.components
            for c in comps:
                v = item.value if np.ndim(item.value) == 0 else item.value[c]
                key = f"prescribed_u_{item.boundary}_{'xyz'[c]}"
                out[key] = out.get(key, 0.0) + float(v) * a
        else:
            out["load_factor_" + re.sub(r"\W+", "_", str(case.name or case.label)).strip("_")] = a
    if setup.obstacle_path is not None:
        off = setup.obstacle_offset(t)
        for c, v in zip("xyz", off):
            out[f"obstacle_{c}"] = float(v)
        out["obstacle_travel"] = float(np.linalg.norm(off))
    return out


def _prescribed_quantities(setup, rows, final) -> list[tuple[str, str, bool]]:
    """The prescribed quantities that change over the steps: ``(column, label, normal)``.

    ``normal``: a pressing action (a support not marked ``tangential``, an obstacle moving
    along the contact normal), preferred as the abscissa of a phase that has one.
    """
    from .contact import Support

    if not rows:
        return []
    start = _prescribed(setup, 0.0)
    moving = [k for k in rows[0] if k.startswith(("prescribed_u_", "load_factor_", "obstacle_travel"))
              and any(abs(float(r[k]) - start.get(k, 0.0)) > 0 for r in rows)]
    tangential = set()
    for case in (setup.history.cases if setup.history is not None else ()):
        if case.tangential and isinstance(case.item, Support):
            tangential |= {k for k in moving if k.startswith(f"prescribed_u_{case.item.boundary}_")}
    out = []
    for k in moving:
        if k == "obstacle_travel":
            path = np.asarray(setup.obstacle_path, dtype=float)
            w = np.asarray(final.pressure, dtype=float)
            n = np.asarray(final.normals, dtype=float).T @ (w if w.sum() > 0 else np.ones_like(w))
            along = abs(float(path @ n)) / max(float(np.linalg.norm(path) * np.linalg.norm(n)), 1e-300)
            out.append((k, "obstacle travel along its path", along > 0.5))
        elif k.startswith("prescribed_u_"):
            boundary, comp = k[len("prescribed_u_"):].rsplit("_", 1)
            out.append((k, f"prescribed u_{comp} of {boundary}", k not in tangential))
        else:
            out.append((k, f"load factor of {k[len('load_factor_'):]}", True))
    return out


def _step_rows(setup, frames, controls) -> list[dict[str, Any]]:
    from .viz.plots import contact_half_width

    model = setup.problem.model
    meta = setup.problem.meta
    axis = int(meta.get("symmetry_axis", 0))
    rows = []
    for k, fr in enumerate(frames):
        ex = fr.extra
        tf = np.asarray(ex.get("tangential_force", np.zeros(model.dim)), dtype=float)
        row: dict[str, Any] = {
            "step": k + 1, "t": float(ex.get("t", setup.times[min(k, len(setup.times) - 1)])),
            "requested": int(bool(ex.get("requested", True))),  # 0: a sub-step inserted by a cut-back
            "status": fr.result.status.label,
            "outer_iterations": ex.get("step_outer_iterations", fr.result.outer_iterations),
            "newton_iterations": ex.get("step_newton_iterations", fr.result.newton_iterations),
            "normal_force": fr.normal_force,
            "tangential_force": float(np.linalg.norm(tf)),
            "peak_pressure": fr.peak_pressure,
            "contact_half_width": contact_half_width(fr, axis=axis, center=meta.get("center"),
                                                     declared=bool(meta.get("center_declared", True))),
            "active_points": int(np.count_nonzero(fr.active)),
            "penetration": fr.result.penetration,
        }
        for c, v in zip("xyz", np.asarray(fr.total_contact_force, dtype=float)):
            row[f"force_{c}"] = float(v)
        if "state" in ex:
            st = np.asarray(ex["state"])
            row.update(stick_points=int(np.sum(st == 1)), slip_points=int(np.sum(st == 2)),
                       coulomb=ex.get("coulomb"), cutbacks=ex.get("cutbacks", 0))
            if "dissipation" in ex:  # finite deformation: the frictional dissipation of the step
                row["dissipation"] = float(ex["dissipation"])
        if "seconds" in ex:  # finite deformation: the support reactions of the step (f_int - f_ext - f_c)
            row.update(cutbacks=int(ex.get("cutbacks", 0)), seconds=float(ex["seconds"]))
            for c, v in zip("xyz", fr.equilibrium().reaction):
                row[f"reaction_{c}"] = float(v)
        for label, _kind, boundary, comp in controls:
            _, dofs = model.node_dofs(boundary)
            row[f"u_{label}"] = float(np.mean(np.asarray(fr.u)[dofs[:, comp]]))
        row.update(_prescribed(setup, row["t"]))
        rows.append(row)
    return rows


def _add_tangential_curves(fig, rows, control: str | None, dim: int) -> None:
    """Add the components of the reaction and contact force that :func:`reaction_force_figure` does not
    plot (with friction: the tangential ones) to its axes, against the same abscissa."""
    if not rows or not fig.axes:
        return
    ax = fig.axes[0]
    axes = "xyz"[:dim]
    if control is not None and control[-1:] in axes:
        shown = control[-1]
        x = np.array([float(r[f"u_{control}"]) for r in rows])
    else:  # the component reaction_force_figure picks
        shown = max(axes, key=lambda c: max(abs(float(r.get(f"reaction_{c}", r.get(f"force_{c}", 0.0))))
                                            for r in rows))
        x = np.array([float(r["t"]) for r in rows])
    x = np.concatenate([[0.0], x])
    for c in axes:
        if c == shown:
            continue
        for key, style, label in ((f"reaction_{c}", "^-", f"support reaction R_{c} (tangential)"),
                                  (f"force_{c}", "v--", f"contact force F_{c} on the body (friction)")):
            y = np.concatenate([[0.0], [float(r.get(key, np.nan)) for r in rows]])
            ax.plot(x, y, style, ms=4, label=label)
    ax.legend(fontsize="small")


def _reaction_rows(rows, controls) -> list[dict[str, Any]]:
    """Columns of ``reaction_force.csv``: step, t, the driving displacements, reactions and contact forces."""
    keep = ("step", "t", "requested") + tuple(f"u_{c[0]}" for c in controls)
    lead = ("prescribed_u_", "load_factor_", "obstacle_")
    return [{**{k: v for k, v in r.items() if k in keep or k.startswith(lead)},
             **{k: v for k, v in r.items() if k.startswith(("reaction_", "force_"))}} for r in rows]


def _write_rows_csv(path, rows) -> Path:
    import csv
    import io as _io

    from .io import write_text_atomic

    cols: list[str] = []
    for r in rows:
        cols += [c for c in r if c not in cols]
    buf = _io.StringIO()
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (repr(float(v)) if isinstance(v, (float, np.floating)) else v) for k, v in r.items()})
    return write_text_atomic(path, buf.getvalue())


def _stick_half_width(frame, axis: int, center) -> float | None:
    st = np.asarray(frame.extra.get("state", []))
    if st.size == 0 or not np.any(st == 1):
        return None
    r = np.abs(frame.points[:, axis] - (0.0 if center is None else center[axis]))
    last = float(np.max(r[st == 1]))
    beyond = r[(r > last) & (st != 1)]
    return 0.5 * (last + float(beyond.min())) if beyond.size else last


@dataclass
class RunOutput:
    """What :func:`run_setup` returns.

    Attributes
    ----------
    frames : list of ContactSolution
        One per load step (frictional steps are converted, see ``extra``).
    raw : ContactSolution, list of them, or FrictionSolution
        The solver's own result(s).
    summary : dict
        As written to ``summary.json``.
    files : list of str
        Files written into the results folder (empty without a folder).
    """

    frames: list
    raw: Any
    summary: dict
    files: list


def _override(setup, algorithm, penalty, options):
    """``setup`` with command-line overrides of algorithm, penalty and solver options."""
    from .contact._algorithms import find_algorithm

    if not (algorithm or penalty or options):
        return setup
    opts = {**setup.options, **options}
    fopts = {**setup.friction_options, **options}  # one options type (ContactOptions) for both runs
    alg = algorithm or setup.algorithm
    takes_penalty = find_algorithm(alg).penalty is None  # the registry entry has no fixed penalty (family-P)
    pen = penalty if penalty is not None else (setup.penalty if takes_penalty else None)
    return dataclasses.replace(setup, algorithm=alg, penalty=pen, options=opts, friction_options=fopts)


def run_setup(setup, out: str | os.PathLike | None = None, force: bool = False, *,
              algorithm: str | None = None, penalty: str | None = None,
              progress: Callable[[str], None] | None = None,
              on_step: Callable[[int, int, float], None] | None = None, **options) -> RunOutput:
    """Solve a problem file (:class:`alcontact.io.ProblemSetup`) and write its results folder.

    Frictionless problems are solved at every step time (independently: the
    problem is path independent); with friction, :func:`solve_friction` follows
    the load history; finite-deformation problems (``kinematics = "finite"``) are
    solved by :func:`~alcontact.contact.solve_finite` over the step times, each step
    from the last, with cut-backs (frames: one per accepted step). ``algorithm``, ``penalty`` and ``**options`` (fields of
    ``ContactOptions``) override the file.

    Parameters
    ----------
    out : path-like, optional
        Results folder; ``None`` writes nothing.
    progress : callable, optional
        Called with a short phase description.
    on_step : callable, optional
        ``on_step(done, total, t)`` when load step ``done`` (1-based) starts
        (``done = 0``) or ends.

    Returns
    -------
    RunOutput
    """
    from .contact import available_algorithms, solve
    from .io import ResultsFolder, check_output_dir

    options = {k: v for k, v in options.items() if v is not None}
    if algorithm is not None and algorithm not in available_algorithms():
        raise UnknownNameError("algorithm", algorithm, available_algorithms())
    setup = _override(setup, algorithm, penalty, options)
    if out is not None:
        check_output_dir(out, force)

    def report(msg: str) -> None:
        logger.info(msg)
        if progress is not None:
            progress(msg)

    prob = setup.problem
    times = setup.times
    n = len(times)
    name = setup.name
    t0 = time.perf_counter()
    if setup.finite:
        law = f", Coulomb mu={setup.friction:g}" if setup.friction > 0 else ""
        report(f"solving {name}: {prob.model.ndofs} DOFs, {n} load steps, finite deformation{law} "
               f"({setup.algorithm})")
        if setup.friction > 0:
            raw, frames = _solve_finite_friction_setup(setup, on_step)
        else:
            raw, frames = _solve_finite_setup(setup, on_step)
    elif setup.friction > 0:
        from .contact import solve_friction

        report(f"solving {name}: {prob.model.ndofs} DOFs, {n} load steps, friction ({setup.algorithm})")
        step_cb = None if on_step is None else (lambda k, t, n_steps: on_step(k, n_steps, t))
        raw = solve_friction(prob, setup.history, algorithm=setup.algorithm, penalty=setup.penalty,
                             on_step=step_cb, **setup.friction_options)
        frames = _friction_frames(raw)
        if on_step is not None:
            on_step(n, n, times[-1])
    else:
        from .contact import problem_at

        raw = []
        for k, t in enumerate(times):
            report(f"solving {name}: {prob.model.ndofs} DOFs, step {k + 1}/{n} (t = {t:g}, {setup.algorithm})")
            if on_step is not None:
                on_step(k, n, t)
            p_t = problem_at(prob, setup.history, t) if setup.history is not None else prob
            sol = solve(p_t, algorithm=setup.algorithm, penalty=setup.penalty, **setup.options)
            sol.extra["t"] = float(t)
            raw.append(sol)
            if on_step is not None:
                on_step(k + 1, n, t)
            if not sol.result.success:
                break
        frames = raw
    wall = time.perf_counter() - t0

    final = frames[-1]
    summary = summarize(prob, final, problem_name=name, options=options)
    summary["problem_label"] = name
    summary["source"] = str(setup.source) if setup.source is not None else None
    summary["load_steps"] = n
    summary["converged_steps"] = sum(1 for f in frames if f.result.success)
    summary["wall_time_total_s"] = wall
    summary["friction"] = setup.friction
    if setup.finite:
        summary.update(_finite_summary(setup, raw, frames, wall))
        if setup.friction > 0:
            summary.update(_finite_friction_summary(setup, raw, frames))
    elif setup.friction > 0:
        summary.update(outer_iterations=int(raw.outer_iterations), newton_iterations=int(raw.newton_iterations),
                       status=raw.status.label, status_code=int(raw.status), message=raw.message,
                       cutbacks=int(raw.cutbacks), wall_time_s=float(raw.timings.get("total_s", wall)))
        if raw.steps:  # loads and supports of the history at the final step's time
            summary.update(equilibrium_keys(raw.equilibrium()))
        tf = np.asarray(final.extra["tangential_force"], dtype=float)
        st = np.asarray(final.extra["state"])
        summary.update(tangential_force=float(np.linalg.norm(tf)), tangential_force_vector=tf.tolist(),
                       coulomb_limit=float(setup.friction * final.normal_force),
                       stick_points=int(np.sum(st == 1)), slip_points=int(np.sum(st == 2)),
                       open_points=int(np.sum(st == 0)), eps_t=float(raw.eps_t))
        meta = prob.meta
        axis = int(meta.get("symmetry_axis", 0))
        c_num = _stick_half_width(final, axis, meta.get("center"))
        summary["stick_half_width"] = c_num
        if setup.mindlin is not None and final.normal_force > 0:
            sym = setup.mindlin.hertz.symmetry
            c_ex = setup.mindlin.stick_half_width(sym * final.normal_force, sym * abs(float(tf[axis])))
            summary["stick_half_width_exact"] = c_ex
            summary["stick_half_width_error_pct"] = _error_pct(c_num, c_ex)
    elif n > 1:
        summary.update(outer_iterations=sum(f.result.outer_iterations for f in frames),
                       newton_iterations=sum(f.result.newton_iterations for f in frames),
                       linear_solves=sum(f.result.linear_solves for f in frames),
                       wall_time_s=sum(float(f.timings.get("total_s", 0.0)) for f in frames))
        # the total time of all steps against one linear solve (summarize() took the last step's time)
        lin = summary.get("linear_solve_time_s")
        summary["time_ratio_contact_to_linear"] = summary["wall_time_s"] / lin if lin else None
        if len(frames) < n:
            summary["message"] = f"step {len(frames)} of {n} failed: {final.result.message}"
    if setup.friction > 0 and "shear" in final.extra:
        # |Q| = |sum of q_i| <= sum of |q_i| <= mu N: the two differ where the tangents turn over the zone
        q = np.linalg.norm(np.asarray(final.extra["shear"], dtype=float), axis=1)
        summary["tangential_force_magnitude_sum"] = float(np.sum(np.asarray(final.weights, dtype=float) * q))
    summary["units"] = setup.plot_units().as_dict(int(prob.model.dim))
    logger.info("%s: %s", name, summary["status"])

    files: list[str] = []
    if out is not None:
        report(f"writing results to {out}")
        with ResultsFolder(out, force) as folder:
            files = write_setup_results(folder.path, setup, frames, summary)
    return RunOutput(frames=frames, raw=raw, summary=summary, files=files)


def write_setup_results(folder: Path, setup, frames, summary: dict) -> list[str]:
    """Write the results folder of a problem-file run; return the file names (``summary.json`` last).

    Files (switched by ``[output]``): ``solution.vtu`` (final state), ``steps/solution_NNNN.vtu``
    and ``solution.pvd`` (stepped runs), ``history.csv`` (outer iterations of
    the last frictionless solve), ``steps.csv``, ``pressure.png``,
    ``convergence.png``, ``load_displacement.png``, ``body_pressure.png`` and
    ``body_von_mises.png`` (pictures of the deformed body), ``report.md``, ``summary.json``.
    Finite-deformation runs write the VTU files in the deformed configuration and
    add ``reaction_force.csv`` and ``reaction_force.png`` (support reaction and
    contact force against the prescribed displacement, per step).
    """
    from .io import write_history_csv, write_json, write_pvd, write_solution_vtu
    from .io.report import write_report

    o = setup.output
    units = setup.plot_units()
    final = frames[-1]
    friction = setup.friction > 0
    stepped = len(frames) > 1 or setup.stepped
    files: list[str] = []
    if o["vtu"]:
        write_solution_vtu(folder / "solution.vtu", final)
        files.append("solution.vtu")
        if o["series"] and stepped:
            (folder / "steps").mkdir(exist_ok=True)
            entries = []
            for k, fr in enumerate(frames):
                rel = f"steps/solution_{k + 1:04d}.vtu"
                write_solution_vtu(folder / rel, fr)
                entries.append((fr.extra.get("t", k + 1), rel))
            write_pvd(folder / "solution.pvd", entries)
            files += ["solution.pvd", "steps/"]
    controls = _controls(setup)
    rows = _step_rows(setup, frames, controls)
    if o["csv"]:
        if not friction:
            write_history_csv(folder / "history.csv", final.result.history)
            files.append("history.csv")
        _write_rows_csv(folder / "steps.csv", rows)
        files.append("steps.csv")
        if setup.finite:
            _write_rows_csv(folder / "reaction_force.csv", _reaction_rows(rows, controls))
            files.append("reaction_force.csv")
    if o["plots"]:
        from .viz import save_convergence_plot, save_figure, save_pressure_plot
        from .viz.plots import load_displacement_figure, steps_figure

        meta = setup.problem.meta
        save_pressure_plot(final, folder / "pressure.png", mindlin=setup.mindlin,
                           axis=int(meta.get("symmetry_axis", 0)), units=units)
        files.append("pressure.png")
        if friction:
            save_figure(steps_figure(rows, title=f"{setup.name}: {summary['status']}"), folder / "convergence.png")
        else:
            save_convergence_plot(final.result, folder / "convergence.png", tolerances=_tolerances(setup.options))
        files.append("convergence.png")
        from .viz.plots import force_path_figure

        dim = int(setup.problem.model.dim)
        quantities = _prescribed_quantities(setup, rows, final)  # what the file prescribes and the run moved
        start = _prescribed(setup, 0.0)
        if stepped:
            if quantities and not any(q[0].startswith("load_factor_") for q in quantities):
                # displacement-driven (supports, the obstacle's path): forces against what was prescribed,
                # one panel per phase (press, then slide)
                fig = force_path_figure(rows, quantities, start=start, title=setup.name, units=units, dim=dim)
            else:  # load-driven: the loads' effect, the mean displacement of the loaded boundary
                fig = load_displacement_figure(rows, [(c[0], c[1]) for c in controls], title=setup.name, dim=dim,
                                               units=units)
            save_figure(fig, folder / "load_displacement.png")
            files.append("load_displacement.png")
        if setup.finite:
            from .viz.plots import reaction_force_figure

            title = f"{setup.name}: reaction-force curve"
            if quantities:  # one panel per phase of the prescribed path, against what was prescribed
                fig = force_path_figure(rows, quantities, start=start, title=title, units=units, dim=dim)
            else:
                control = next((c[0] for c in controls if c[1] == "normal"), None)
                fig = reaction_force_figure(rows, control, title=title, dim=dim, units=units)
                if friction:
                    _add_tangential_curves(fig, rows, control, dim)
            save_figure(fig, folder / "reaction_force.png")
            files.append("reaction_force.png")
        from .viz.pictures import save_body_pictures

        files += save_body_pictures(final, folder, units=units, title=setup.name)
    if o["report"]:
        files.append("report.md")
        write_report(folder / "report.md", summary, files + ["summary.json"],
                     description=setup.data["problem"]["description"],
                     source=str(setup.source) if setup.source else None, units=units)
    files.append("summary.json")
    write_json(folder / "summary.json", {**summary, **_per_radian(setup.problem.model, summary), "files": files})
    logger.info("results written to %s", folder)
    return files


# =========================================================================== benchmarks
@dataclass(frozen=True)
class BenchSuite:
    """A benchmark script of ``benchmarks/`` with ``run(out_dir, [cases,] variants)``."""

    script: str
    report: str
    takes_cases: bool
    quick: dict


#: Benchmark suites of ``alcontact bench``.
BENCH_SUITES: dict[str, BenchSuite] = {
    "hertz": BenchSuite("hertz.py", "hertz.md", True,
                        {"cases": ["2d-10k"], "variants": ["ssn", "simo-laursen", "exp-met1", "log-met2"]}),
    "friction": BenchSuite("friction.py", "friction.md", True,
                           {"cases": ["mindlin-2d"], "variants": ["ssn", "simo-laursen", "exp-met1"]}),
    "nlp": BenchSuite("nlp_hs.py", "nlp_hs.md", False, {"variants": ["rockafellar", "exp-met1", "SLSQP"]}),
    "finite": BenchSuite("finite.py", "finite.md", True,
                         {"cases": ["2d-5k"], "variants": ["ssn", "simo-laursen", "quad-met1"]}),
    "ironing": BenchSuite("ironing.py", "ironing.md", True,
                          {"cases": ["2d-s"], "variants": ["ssn", "simo-laursen", "exp-met1"]}),
}


def quick_bench_estimate(suites=None) -> tuple[float, str] | None:
    """Seconds ``alcontact bench --quick`` takes for ``suites`` (default all), and where that was measured.

    From the committed calibration (``benchmarks/time_estimates.py --bench`` writes
    ``alcontact/io/time_calibration.json``); ``None`` without one.
    """
    from .io.preflight import machine_kind, time_calibration

    cal = time_calibration()
    per = ((cal.get("bench_quick") or {}).get("suites_s")) or {}
    names = list(suites or BENCH_SUITES)
    if not per or any(n not in per for n in names if n in BENCH_SUITES):
        return None
    overhead = max(float(cal["bench_quick"].get("total_s", 0.0)) - sum(per.values()), 0.0)  # start, imports
    return overhead + float(sum(per[n] for n in names if n in per)), machine_kind(cal)


def run_benchmarks(out: str | os.PathLike, *, suites=None, quick: bool = False, cases=None, variants=None,
                   benchmarks_dir: str | os.PathLike | None = None, log: Callable[[str], None] | None = None) -> Path:
    """``alcontact bench``: run benchmark scripts of ``benchmarks/`` and write ``bench.md``.

    Each suite's script is loaded with :func:`runpy.run_path` and its ``run``
    function called (``hertz.py``, ``friction.py``, ``finite.py``, ``ironing.py``: ``run(out_dir, cases, variants)``,
    ``nlp_hs.py``: ``run(out_dir, variants)``); each writes its CSV and
    markdown into ``out``; ``bench.md`` joins the markdown reports.

    Raises
    ------
    InputError
        Unknown suite, or the benchmarks folder is missing (pass ``benchmarks_dir``).
    """
    import runpy

    from .io import write_text_atomic
    from .io.schema import _repo_root

    names = list(suites or BENCH_SUITES)
    for s in names:
        if s not in BENCH_SUITES:
            raise UnknownNameError("benchmark suite", s, list(BENCH_SUITES))
    folder = Path(benchmarks_dir) if benchmarks_dir is not None else _repo_root() / "benchmarks"
    if not folder.is_dir():
        raise InputError(f"benchmarks folder {str(folder)!r} not found; run from a checkout of the repository "
                         "or pass --benchmarks-dir.")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    parts = ["# alcontact benchmarks", "",
             f"alcontact {__version__}, {_dt.datetime.now(_dt.timezone.utc).isoformat(timespec='seconds')}"
             + (" (quick)" if quick else ""), ""]
    for s in names:
        suite = BENCH_SUITES[s]
        path = folder / suite.script
        if not path.is_file():
            raise InputError(f"benchmark script {str(path)!r} not found; pass --benchmarks-dir.")
        ns = runpy.run_path(str(path), run_name=f"alcontact_bench_{s}")
        kw: dict[str, Any] = dict(suite.quick) if quick else {}
        if variants:
            kw["variants"] = list(variants)
        if cases and suite.takes_cases:
            kw["cases"] = list(cases)
        if log is not None:
            log(f"benchmark {s}: {', '.join(f'{k}={v}' for k, v in kw.items()) or 'full'}")
        t0 = time.perf_counter()
        if suite.takes_cases:
            ns["run"](out, kw.get("cases"), kw.get("variants"), **({"log": log} if log is not None else {}))
        else:
            ns["run"](out, kw.get("variants"))
        md = out / suite.report
        parts += [f"<!-- {s}: {time.perf_counter() - t0:.1f} s -->", ""]
        if md.is_file():
            text = md.read_text(encoding="utf-8")
            parts += ["#" + text if text.startswith("# ") else text, ""]
    report = out / "bench.md"
    write_text_atomic(report, "\n".join(parts))
    return report
