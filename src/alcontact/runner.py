"""Former home of the application layer, kept importable for one release: use :mod:`alcontact.app`.

Every public name of :mod:`alcontact.app` is re-exported here unchanged (``run_problem``,
``run_setup``, ``summarize``, ``write_results``, ...), and the private helpers that user
scripts reached into (``_ADVICE``) stay reachable.
"""

from __future__ import annotations

from .app import (BENCH_SUITES, BUILTIN_PROBLEMS, DEFAULT_PROBLEM, RESULT_FILES, BenchSuite, BuiltinProblem,
                  RunOutput, build_problem, equilibrium_keys, list_components, quick_bench_estimate, run_benchmarks,
                  run_problem, run_setup, setup_summary, summarize, what_to_try, write_results, write_setup_results)
from .app.summary import ADVICE

_ADVICE = ADVICE  # the name of the former module

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
    "_ADVICE",
]
