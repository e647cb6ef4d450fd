"""Input and output: result files (atomic writes, ``summary.json``, ``history.csv``) and VTU.

- :mod:`alcontact.io.results` -- atomic file writes, the results folder, summary and history files
- :mod:`alcontact.io.vtu` -- VTU output of a contact solution (meshio, imported on use), .pvd series
- :mod:`alcontact.io.schema` -- every option of a problem file (type, default, doc); docs/problem-file.md
- :mod:`alcontact.io.config` -- read, validate and build a TOML problem file (:func:`load_problem`)
- :mod:`alcontact.io.report` -- report.md of a results folder
"""

from __future__ import annotations

from .results import (
    HISTORY_COLUMNS,
    RESULT_NAMES,
    SUMMARY_KEYS,
    ResultsFolder,
    atomic_path,
    check_output_dir,
    jsonable,
    owned_entries,
    prepare_output_dir,
    write_history_csv,
    write_json,
    write_text_atomic,
)
from .vtu import FRICTION_FIELDS, POINT_FIELDS, solution_point_data, write_pvd, write_solution_vtu

__all__ = [
    "load_problem",
    "ProblemSetup",
    "SUMMARY_KEYS",
    "HISTORY_COLUMNS",
    "POINT_FIELDS",
    "FRICTION_FIELDS",
    "write_pvd",
    "atomic_path",
    "write_text_atomic",
    "write_json",
    "write_history_csv",
    "prepare_output_dir",
    "check_output_dir",
    "owned_entries",
    "ResultsFolder",
    "RESULT_NAMES",
    "jsonable",
    "solution_point_data",
    "write_solution_vtu",
]


def __getattr__(name: str):
    # lazy: keeps `python -m alcontact.io.schema` free of a double import of schema
    if name in ("load_problem", "ProblemSetup"):
        from . import config

        return getattr(config, name)
    raise AttributeError(f"module 'alcontact.io' has no attribute {name!r}")
