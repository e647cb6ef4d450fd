"""The application layer: what the command line does, one Python call per command.

Modules: :mod:`~alcontact.app.builtin` (built-in problems), :mod:`~alcontact.app.pipeline`
(:func:`run_problem`, :func:`run_setup`: problem -> :func:`alcontact.contact.solve` -> summary
-> results folder), :mod:`~alcontact.app.summary` (``summary.json``), :mod:`~alcontact.app.writer`
(the results folder), :mod:`~alcontact.app.bench` (``alcontact bench``), :mod:`~alcontact.app.study`
and :mod:`~alcontact.app.study_report` (``alcontact study``: the method x penalty-parameter matrix).

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
>>> from alcontact.app import run_problem
>>> sol, summary = run_problem(level=0)               # doctest: +SKIP
>>> summary["status"], summary["dofs"]                # doctest: +SKIP
('converged', 2232)
"""

from .bench import BENCH_SUITES, BenchSuite, quick_bench_estimate, run_benchmarks
from .builtin import BUILTIN_PROBLEMS, DEFAULT_PROBLEM, BuiltinProblem, build_problem
from .pipeline import RunOutput, list_components, run_problem, run_setup
from .summary import equilibrium_keys, setup_summary, summarize, what_to_try
from .writer import RESULT_FILES, write_results, write_setup_results

__all__ = [
    "BuiltinProblem",
    "BUILTIN_PROBLEMS",
    "DEFAULT_PROBLEM",
    "RESULT_FILES",
    "quick_bench_estimate",
    "build_problem",
    "run_problem",
    "summarize",
    "setup_summary",
    "equilibrium_keys",
    "write_results",
    "what_to_try",
    "list_components",
    "run_setup",
    "run_benchmarks",
    "BENCH_SUITES",
    "BenchSuite",
    "write_setup_results",
    "RunOutput",
]
