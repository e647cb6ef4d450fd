"""Input and output: result files (atomic writes, ``summary.json``, ``history.csv``) and VTU.

- :mod:`alcontact.io.results` -- atomic file writes, the results folder, summary and history files
- :mod:`alcontact.io.vtu` -- VTU output of a contact solution (meshio, imported on use)
"""

from __future__ import annotations

from .results import (
    HISTORY_COLUMNS,
    SUMMARY_KEYS,
    atomic_path,
    jsonable,
    prepare_output_dir,
    write_history_csv,
    write_json,
    write_text_atomic,
)
from .vtu import POINT_FIELDS, solution_point_data, write_solution_vtu

__all__ = [
    "SUMMARY_KEYS",
    "HISTORY_COLUMNS",
    "POINT_FIELDS",
    "atomic_path",
    "write_text_atomic",
    "write_json",
    "write_history_csv",
    "prepare_output_dir",
    "jsonable",
    "solution_point_data",
    "write_solution_vtu",
]
