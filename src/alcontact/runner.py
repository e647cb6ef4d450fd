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
``summary.json``
    Written last; keys :data:`alcontact.io.SUMMARY_KEYS` (stable) plus extras, see
    :func:`summarize`.

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
    "build_problem",
    "run_problem",
    "summarize",
    "write_results",
    "what_to_try",
    "list_components",
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


def _hertz(kind: str):
    def factory(level: int, order: int):
        from .problems import hertz

        return (hertz.hertz_2d if kind == "2d" else hertz.hertz_3d)(level=level, order=order)

    return factory


#: Built-in problems by name. Default levels: about 10k DOFs, a few seconds.
BUILTIN_PROBLEMS: dict[str, BuiltinProblem] = {
    "hertz-2d": BuiltinProblem(
        "hertz-2d", "rigid cylinder on an elastic block, plane strain, half model (Hertz line contact)",
        _hertz("2d"), default_level=2, levels=6,
    ),
    "hertz-3d": BuiltinProblem(
        "hertz-3d", "rigid sphere on an elastic block, quarter model (Hertz point contact)",
        _hertz("3d"), default_level=0, levels=6,
    ),
}

DEFAULT_PROBLEM = "hertz-2d"

#: Files :func:`write_results` writes (``summary.json`` last).
RESULT_FILES: tuple[str, ...] = ("solution.vtu", "history.csv", "pressure.png", "convergence.png", "summary.json")


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


def summarize(problem, solution, *, problem_name: str | None = None, level: int | None = None,
              options: dict | None = None, build_time_s: float | None = None) -> dict[str, Any]:
    """The ``summary.json`` dictionary of a solved problem.

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
    ``contact_half_width``, ``contact_half_width_exact``
        Computed half-width ``a`` (contact radius in 3D) and the analytical one
        for the load the model carries.
    ``peak_pressure``, ``peak_pressure_exact``
        Largest computed pressure and the analytical ``p0``.
    ``total_contact_force``
        Total load ``P`` of the full (unsymmetrized) body:
        ``reference.load(normal_force)``, i.e. 2x the half model's contact force
        in 2D (per unit thickness) and 4x the quarter model's in 3D; the
        model's own force is ``model_contact_force``. Without a reference, the
        model's force.

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

    a_num = float(solution.contact_half_width(axis=axis, center=center))
    p_num = float(solution.peak_pressure)
    f_model = float(solution.normal_force)
    a_ex = p_ex = None
    load = f_model
    if ref is not None:
        load = float(ref.load(f_model))
        if load > 0:
            a_ex = float(ref.half_width(load))
            p_ex = float(ref.peak_pressure(load))
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
        "peak_pressure_error_pct": _error_pct(p_num, p_ex),
        "model_contact_force": f_model,
        "contact_force_vector": np.asarray(solution.total_contact_force, dtype=float).tolist(),
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


def write_results(out: str | os.PathLike, problem, solution, summary: dict, *,
                  tolerances: dict | None = None) -> dict[str, Path]:
    """Write the result files of :data:`RESULT_FILES` into the existing folder ``out``.

    Each file is written atomically; ``summary.json`` is written last, so its
    presence means the set is complete. Returns ``{file name: path}``.
    """
    from .io import write_history_csv, write_json, write_solution_vtu
    from .viz import save_convergence_plot, save_pressure_plot

    out = Path(out)
    paths = {name: out / name for name in RESULT_FILES}
    write_solution_vtu(paths["solution.vtu"], solution)
    write_history_csv(paths["history.csv"], solution.result.history)
    save_pressure_plot(solution, paths["pressure.png"])
    save_convergence_plot(solution.result, paths["convergence.png"], tolerances=tolerances)
    write_json(paths["summary.json"], {**summary, "files": list(RESULT_FILES)})
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
    from .io import prepare_output_dir

    def report(msg: str) -> None:
        logger.info(msg)
        if progress is not None:
            progress(msg)

    options = {k: v for k, v in options.items() if v is not None}
    algorithm = algorithm or DEFAULT_ALGORITHM
    if algorithm not in available_algorithms():
        raise UnknownNameError("algorithm", algorithm, available_algorithms())
    if out is not None:
        prepare_output_dir(out, force, create=False)  # fail before the (long) solve

    t0 = time.perf_counter()
    if problem is None or isinstance(problem, str):
        name = problem or DEFAULT_PROBLEM
        spec = BUILTIN_PROBLEMS.get(name)
        lvl = level if level is not None or spec is None else spec.default_level
        report(f"building {name} (level {lvl}, P{order})")
        prob = build_problem(name, lvl, order)
    else:
        name, lvl, prob = getattr(problem, "name", "contact"), None, problem
    build_time = time.perf_counter() - t0

    report(f"solving {name} with {prob.model.ndofs} DOFs ({algorithm})")
    solution = solve(prob, algorithm=algorithm, penalty=penalty, **options)
    summary = summarize(prob, solution, problem_name=name, level=lvl, options=options, build_time_s=build_time)
    logger.info("%s: %s after %d outer iterations", name, summary["status"], summary["outer_iterations"])

    if out is not None:
        report(f"writing results to {out}")
        folder = prepare_output_dir(out, force)
        write_results(folder, prob, solution, summary, tolerances=_tolerances(options))
    return solution, summary


def list_components() -> dict[str, dict[str, str]]:
    """Registered names with one line each: what ``alcontact list`` prints.

    Returns
    -------
    dict
        ``{"algorithms": ..., "penalties": ..., "obstacles": ..., "problems": ...}``,
        each ``{name: one-line description}``. Penalties usable by the
        ``family-p`` algorithm are marked ``[contact]``.
    """
    from . import penalties
    from .contact import algorithm_docs, contact_penalties, obstacles

    usable = set(contact_penalties())
    pens = {name: (f"[contact] {doc}" if name in usable else doc) for name, doc in penalties.describe().items()}
    return {
        "algorithms": dict(algorithm_docs()),
        "penalties": pens,
        "obstacles": dict(obstacles.docs()),
        "problems": {
            name: f"{spec.doc} (--level 0..{spec.levels - 1}, default {spec.default_level})"
            for name, spec in BUILTIN_PROBLEMS.items()
        },
    }
