"""Result files: atomic writes, the results folder, ``summary.json`` and ``history.csv``.

Every file is written to a temporary file in its destination folder and moved
into place with :func:`os.replace` (atomic on POSIX and Windows within one
file system), so a reader sees either the previous file or the complete new
one, never a partial file; the temporary file is removed if writing fails.

The keys of ``summary.json`` listed in :data:`SUMMARY_KEYS` are a stable public
contract (scripts and the benchmark report read them); new keys may be added,
these are never renamed or removed.

Examples
--------
>>> import tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> write_text_atomic(d / "note.txt", "hello\\n").name
'note.txt'
>>> sorted(p.name for p in d.iterdir())
['note.txt']
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import io
import json
import logging
import math
import os
import tempfile
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import OutputExistsError

__all__ = [
    "SUMMARY_KEYS",
    "HISTORY_COLUMNS",
    "atomic_path",
    "write_text_atomic",
    "write_json",
    "write_history_csv",
    "prepare_output_dir",
    "jsonable",
]

logger = logging.getLogger(__name__)

#: Keys every ``summary.json`` holds (stable public contract; values may be ``null``
#: where a problem has no analytical reference).
SUMMARY_KEYS: tuple[str, ...] = (
    "status",
    "algorithm",
    "penalty",
    "dofs",
    "outer_iterations",
    "newton_iterations",
    "linear_solves",
    "wall_time_s",
    "linear_solve_time_s",
    "contact_half_width",
    "contact_half_width_exact",
    "peak_pressure",
    "peak_pressure_exact",
    "total_contact_force",
)

#: Columns of ``history.csv``: the fields of :class:`alcontact.contact.ContactIteration`.
HISTORY_COLUMNS: tuple[str, ...] = (
    "k",
    "penetration",
    "complementarity",
    "multiplier_change",
    "residual",
    "newton_iterations",
    "eps_n",
    "active",
)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; move it onto ``path`` on success.

    For writers that take a file name (meshio, matplotlib). The temporary name
    keeps the suffix of ``path`` (some writers infer the format from it) and
    starts with a dot. If the block raises, the temporary file is removed and
    ``path`` is left as it was.

    Parameters
    ----------
    path : path-like
        Destination; its folder must exist.
    """
    path = Path(path)
    fd, tmp_name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}")
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        # mkstemp creates 0600 files; give the result the usual permissions
        mode = path.stat().st_mode & 0o777 if path.exists() else 0o644
        os.chmod(tmp, mode)
        with open(tmp, "rb") as fh:  # flush the data to disk before the rename
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    logger.debug("wrote %s", path)


def write_text_atomic(path: str | os.PathLike, text: str, *, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically; return ``path``."""
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "w", encoding=encoding, newline="") as fh:
        fh.write(text)
    return path


def jsonable(value: Any) -> Any:
    """Convert NumPy scalars/arrays, tuples and dataclasses to JSON types.

    Non-finite floats become ``None`` (JSON has no NaN/Infinity).
    """
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return jsonable(dataclasses.asdict(value))
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        f = float(value)
        return f if math.isfinite(f) else None
    if value is None or isinstance(value, str):
        return value
    return str(value)


def write_json(path: str | os.PathLike, data: Mapping[str, Any]) -> Path:
    """Write ``data`` as indented JSON (keys in insertion order), atomically."""
    text = json.dumps(jsonable(data), indent=2, allow_nan=False) + "\n"
    return write_text_atomic(path, text)


def write_history_csv(path: str | os.PathLike, history) -> Path:
    """Write the outer-iteration history (a sequence of ``ContactIteration``) as CSV.

    One row per outer iteration, columns :data:`HISTORY_COLUMNS`; floats with
    17 significant digits (round trip). An empty history gives the header only.
    """
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(HISTORY_COLUMNS)
    for it in history:
        row = []
        for col in HISTORY_COLUMNS:
            v = getattr(it, col)
            row.append(repr(float(v)) if isinstance(v, (float, np.floating)) else str(int(v)))
        writer.writerow(row)
    return write_text_atomic(path, buf.getvalue())


def prepare_output_dir(path: str | os.PathLike, force: bool = False, *, create: bool = True) -> Path:
    """Create the results folder ``path``, refusing to reuse a non-empty one.

    Parameters
    ----------
    path : path-like
    force : bool
        Reuse a non-empty folder (our files in it are replaced, others kept).
    create : bool
        ``False``: only check (e.g. before a long computation), create nothing.

    Returns
    -------
    Path
        The folder (created with its parents if missing).

    Raises
    ------
    OutputExistsError
        ``path`` is a non-empty folder and ``force`` is false, or ``path`` is a file.
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputExistsError(f"results path '{path}' exists and is not a folder; choose another --out.")
    if path.is_dir() and not force and any(path.iterdir()):
        raise OutputExistsError(
            f"results folder '{path}' exists and is not empty; pass --force to overwrite the result "
            "files in it, or choose another --out."
        )
    if create:
        path.mkdir(parents=True, exist_ok=True)
    return path
