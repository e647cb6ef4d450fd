"""One pipeline from a problem (built-in name, problem object or problem file) to a results folder.

:func:`run_problem` is ``alcontact run`` without a file, :func:`run_setup` with one: build or
take the problem, solve it with :func:`alcontact.contact.solve` (which decides what runs),
summarize it (:mod:`alcontact.app.summary`) and write the folder (:mod:`alcontact.app.writer`).
:func:`list_components` is ``alcontact list``.
"""

from __future__ import annotations

import dataclasses
import logging
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..errors import UnknownNameError
from .builtin import BUILTIN_PROBLEMS, DEFAULT_PROBLEM, build_problem
from .summary import _tolerances, setup_summary, summarize
from .writer import write_results, write_setup_results
from ._paths import repo_root

__all__ = ["run_problem", "run_setup", "list_components", "RunOutput"]

logger = logging.getLogger(__name__)


def run_problem(problem=None, out: str | os.PathLike | None = None, algorithm: str | None = None,
                penalty: str | None = None, force: bool = False, *, level: int | None = None,
                order: int = 1, progress: Callable[[str], None] | None = None, petsc_options: dict | None = None,
                **options):
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
    petsc_options : dict, optional
        PETSc options of ``linear_solver="petsc"`` / ``"petsc-direct"``
        (:func:`alcontact.linalg.backend_options`), e.g. ``{"ksp_rtol": 1e-10}``.
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
    from ..contact import DEFAULT_ALGORITHM, available_algorithms, solve
    from ..io import ResultsFolder, check_output_dir
    from ..linalg import backend_options

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
    with backend_options(petsc_options):
        solution = solve(prob, algorithm=algorithm, penalty=penalty, **options)
    summary = summarize(prob, solution, problem_name=name, level=lvl, options=options, build_time_s=build_time)
    units = None
    if spec is not None and spec.units:
        from ..viz import Units

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
    from .. import penalties
    from ..contact import contact_penalties, obstacles
    from ..contact import describe_algorithms

    usable = set(contact_penalties())
    pens = {name: (f"[contact] {doc}" if name in usable else doc) for name, doc in penalties.describe().items()}

    examples = {}
    ex_dir = repo_root() / "examples"
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
    from ..contact import find_algorithm

    if not (algorithm or penalty or options):
        return setup
    opts = {**setup.options, **options}
    fopts = {**setup.friction_options, **options}  # one options type (ContactOptions) for both runs
    alg = algorithm or setup.algorithm
    takes_penalty = find_algorithm(alg).penalty is None  # the registry entry has no fixed penalty (family-P)
    pen = penalty if penalty is not None else (setup.penalty if takes_penalty else None)
    return dataclasses.replace(setup, algorithm=alg, penalty=pen, options=opts, friction_options=fopts)


def _solving_line(setup) -> str:
    """The progress line of a problem-file solve."""
    n = len(setup.times)
    head = f"solving {setup.name}: {setup.problem.model.ndofs} DOFs, {n} load steps"
    if setup.finite:
        law = f", Coulomb mu={setup.friction:g}" if setup.friction > 0 else ""
        return f"{head}, finite deformation{law} ({setup.algorithm})"
    if setup.friction > 0:
        return f"{head}, friction ({setup.algorithm})"
    return f"{head} ({setup.algorithm})"


def _solve_arguments(setup) -> dict[str, Any]:
    """Keyword arguments of :func:`alcontact.contact.solve` for a problem file: the step times, the
    history, the obstacle's path, the cut-backs and the options of its kind of run (the friction-only
    keys only with friction; :func:`~alcontact.contact.solve` decides the engine from the problem)."""
    frictional = setup.friction > 0
    options = dict(setup.friction_options if frictional else setup.options)
    kw: dict[str, Any] = {"history": setup.history}
    if setup.finite:
        kw["steps"] = list(setup.times)
        kw["obstacle_path"] = setup.obstacle_offset if setup.obstacle_path is not None else None
        kw["max_cutbacks"] = options.pop("max_cutbacks", setup.max_cutbacks)
    elif not frictional:
        kw["steps"] = list(setup.times)
    return {**kw, **options}


def run_setup(setup, out: str | os.PathLike | None = None, force: bool = False, *,
              algorithm: str | None = None, penalty: str | None = None,
              progress: Callable[[str], None] | None = None,
              on_step: Callable[[int, int, float], None] | None = None, petsc_options: dict | None = None,
              **options) -> RunOutput:
    """Solve a problem file (:class:`alcontact.io.ProblemSetup`) and write its results folder.

    Frictionless problems are solved at every step time (independently: the
    problem is path independent); with friction, :func:`~alcontact.contact.solve` follows
    the load history; finite-deformation problems (``kinematics = "finite"``) are
    solved by :func:`~alcontact.contact.solve` over the step times, each step
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
    petsc_options : dict, optional
        PETSc options (:func:`alcontact.linalg.backend_options`); given, they replace the
        file's ``[solver.petsc_options]``.

    Returns
    -------
    RunOutput
    """
    from ..contact import available_algorithms, solve
    from ..io import ResultsFolder, check_output_dir
    from ..linalg import backend_options

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

    t0 = time.perf_counter()
    report(_solving_line(setup))
    petsc = dict(setup.petsc_options if petsc_options is None else petsc_options or {})
    with backend_options(petsc):
        solution = solve(setup.problem, setup.algorithm, setup.penalty, on_step=on_step, **_solve_arguments(setup))
    frames = list(solution.frame_solutions())
    raw = solution.record if solution.record is not None else frames
    wall = time.perf_counter() - t0
    summary = setup_summary(setup, solution, raw, options, wall)
    summary["petsc_options"] = petsc  # the backend options the solve ran with (empty: none)
    logger.info("%s: %s", setup.name, summary["status"])

    files: list[str] = []
    if out is not None:
        report(f"writing results to {out}")
        with ResultsFolder(out, force) as folder:
            files = write_setup_results(folder.path, setup, frames, summary)
    return RunOutput(frames=frames, raw=raw, summary=summary, files=files)
