"""Result files: atomic writes, the results folder, ``summary.json`` and ``history.csv``.

Every file is written to a temporary file in its destination folder and moved
into place with :func:`os.replace` (atomic on POSIX and Windows within one
file system), so a reader sees either the previous file or the complete new
one, never a partial file; the temporary file is removed if writing fails.

A results folder is whole or absent (:class:`ResultsFolder`): its files are
written into a hidden staging folder (beside a new target, inside an existing
one) and moved into place at the end, with SIGINT/SIGTERM deferred for the few
renames that takes. An exception or a
signal during the writing removes the staging folder and leaves the target
as it was.

Which files a results folder owns: the names listed under ``"files"`` in its
``summary.json`` (the manifest every run writes), ``summary.json`` itself and
temporary files of interrupted writes of older versions (``.<stem>.<random>.tmp<suffix>``).
``--force`` replaces exactly the owned set: stale files of an earlier run (e.g.
``steps/`` of a load-stepped run followed by a single solve) disappear, every
other file is kept. A file alcontact would write but does not own (e.g. a
``report.md`` of your own in a folder without ``summary.json``) is never
overwritten: the run is refused with :class:`~alcontact.errors.OutputExistsError`
before solving.

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
import re
import shutil
import signal
import tempfile
import threading
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .._options import is_path, require
from ..errors import AlcontactError, OutputExistsError, OutputInUseError, OutputPathError

__all__ = [
    "SUMMARY_KEYS",
    "HISTORY_COLUMNS",
    "atomic_path",
    "write_text_atomic",
    "write_json",
    "write_history_csv",
    "prepare_output_dir",
    "check_output_dir",
    "owned_entries",
    "ResultsFolder",
    "output_lock",
    "output_path_issue",
    "RESULT_NAMES",
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

#: Every entry alcontact may write into a results folder (``steps/`` is a folder).
RESULT_NAMES: frozenset[str] = frozenset({
    "solution.vtu", "solution.pvd", "steps/", "history.csv", "steps.csv", "pressure.png",
    "convergence.png", "load_displacement.png", "report.md", "summary.json",
    "reaction_force.csv", "reaction_force.png",  # finite-deformation runs (reaction_force.csv: rigid bodies too)
    "interface_pressure.png",  # a pair between two bodies: the pressure on both sides
    "body_pressure.png", "body_von_mises.png",  # pictures of the body (alcontact.viz.pictures)
})

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
    require("atomic_path", "path", path, is_path(path), "a file path (str or pathlib.Path)", OutputPathError)
    path = Path(path)
    if path.is_dir():
        raise OutputPathError(f"cannot write the file '{path}': a folder of that name exists. Give a file name "
                              "(e.g. add the file's name to the folder's path) or move the folder away.")
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
    require("write_text_atomic", "path", path, is_path(path), "a file path (str or pathlib.Path)", OutputPathError)
    require("write_text_atomic", "text", text, isinstance(text, str), "a str")
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
    require("write_json", "data", data, isinstance(data, Mapping), "a dict")
    text = json.dumps(jsonable(data), indent=2, allow_nan=False) + "\n"
    return write_text_atomic(path, text)


def write_history_csv(path: str | os.PathLike, history) -> Path:
    """Write the outer-iteration history (a sequence of ``ContactIteration``) as CSV.

    One row per outer iteration, columns :data:`HISTORY_COLUMNS`; floats with
    17 significant digits (round trip). An empty history gives the header only.
    """
    ok = not isinstance(history, (str, bytes, Mapping)) and np.iterable(history)
    require("write_history_csv", "history", history, ok, "a list of ContactIteration records")
    history = list(history)
    for i, it in enumerate(history):
        require("write_history_csv", f"history[{i}]", it, all(hasattr(it, c) for c in HISTORY_COLUMNS),
                f"a record with the fields {', '.join(HISTORY_COLUMNS)} (a ContactIteration)")
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


# --------------------------------------------------------------------------- results folder
_TEMP_FILE = re.compile(r"^\..+\.tmp(\.[A-Za-z0-9]+)?$")  # atomic_path's temporary files
_STAGING_TAG = ".partial-"  # staging folder beside a new results folder: .<name>.partial-<random>
_STAGING_INSIDE = ".alcontact-partial-"  # staging folder inside an existing one
_LOCK_TAG = ".alcontact-lock"  # lock file beside the folder (.<name>.alcontact-lock) or inside it
#: bytes a staging folder adds to the folder's name: "." + name + ".partial-" + 8 random characters
_STAGING_EXTRA = 1 + len(_STAGING_TAG) + 8


def _entry_name(p: Path) -> str:
    return p.name + "/" if p.is_dir() and not p.is_symlink() else p.name


def owned_entries(folder: str | os.PathLike) -> tuple[list[str], list[str]]:
    """Split the entries of an existing results folder into (owned, foreign).

    Owned: ``summary.json``, the names its ``"files"`` list holds (plain names
    of :data:`RESULT_NAMES` only, so a damaged manifest cannot point outside
    the folder) and leftovers of killed writes: temporary files of atomic
    writes (``.<stem>.<random>.tmp<suffix>``) and staging folders
    (``.alcontact-partial-*``).
    Folder names end with ``/`` (``"steps/"``).

    Returns
    -------
    owned, foreign : list of str
        Sorted names of the entries present in ``folder``.
    """
    require("owned_entries", "folder", folder, is_path(folder), "a folder path (str or pathlib.Path)", OutputPathError)
    folder = Path(folder)
    require("owned_entries", "folder", folder, folder.is_dir(), "an existing folder", OutputPathError)
    listed: set[str] = set()
    summary = folder / "summary.json"
    if summary.is_file():
        listed.add("summary.json")
        try:
            files = json.loads(summary.read_text(encoding="utf-8")).get("files", [])
        except (OSError, ValueError, AttributeError):
            files = []
        listed |= {f for f in files if isinstance(f, str) and f in RESULT_NAMES}
    owned, foreign = [], []
    for p in sorted(folder.iterdir()):
        name = _entry_name(p)
        ours = name in listed or (p.is_file() and (_TEMP_FILE.match(p.name) or p.name == _LOCK_TAG)) or \
            (p.is_dir() and p.name.startswith(_STAGING_INSIDE))
        (owned if ours else foreign).append(name)
    return owned, foreign


def _leftover(name: str) -> bool:
    """A temporary file or staging folder of an interrupted (killed) write."""
    return bool(_TEMP_FILE.match(name)) or name.startswith(_STAGING_INSIDE) or name == _LOCK_TAG


def _short(path: Path) -> str:
    text = str(path)
    return text if len(text) <= 80 else text[:40] + "..." + text[-20:]


def _first_existing(path: Path) -> Path:
    p = path
    while not os.path.lexists(p) and p != p.parent:  # lexists: False (no OSError) for over-long names
        p = p.parent
    return p


def _name_max(where: Path) -> int:
    try:
        return int(os.pathconf(where, "PC_NAME_MAX"))
    except (OSError, ValueError, AttributeError):
        return 255


def output_path_issue(path: str | os.PathLike) -> str | None:
    """Why no results folder can be made at ``path`` by its name alone, or ``None``; touches nothing.

    A name longer than the file system allows (255 bytes on most), counting the
    staging folder's longer name (``.<name>.partial-<random>``, :class:`ResultsFolder`);
    a path longer than ``PATH_MAX``; a NUL character.
    """
    text = os.fspath(path)
    if "\0" in text:
        return "the name holds a NUL character, which no file name may hold; choose another name"
    raw = os.fsencode(text)
    limit = _name_max(_first_existing(Path(text).absolute()))
    parts = [q for q in Path(text).parts if q not in ("/", "")]
    for i, part in enumerate(parts):
        n = len(os.fsencode(part))
        last = i == len(parts) - 1
        room = limit - (_STAGING_EXTRA if last else 0)
        if n > room:
            what = "the folder name" if last else f"the path component {part[:20]!r}..."
            extra = f" ({limit} less {_STAGING_EXTRA} for the staging folder written beside it)" if last else ""
            return (f"{what} is {n} bytes long, more than the {room} bytes the file system allows{extra}; "
                    "choose a shorter name")
    if len(raw) > 4000:
        return f"the path is {len(raw)} bytes long (most systems allow 4096); choose a shorter path"
    return None


def check_output_dir(path: str | os.PathLike, force: bool = False) -> Path:
    """Check that a results folder can be written at ``path``; create nothing.

    Called before a (long) solve, so that a bad ``--out`` fails at once.

    Raises
    ------
    OutputExistsError
        ``path`` is a file, or a folder with entries and ``force`` is false,
        or (with ``force``) a folder holding a file alcontact would write but
        does not own (see :func:`owned_entries`).
    OutputPathError
        A parent of ``path`` is a file, or the place is not writable.
    """
    require("check_output_dir", "path", path, is_path(path), "a folder path (str or pathlib.Path)", OutputPathError)
    require("check_output_dir", "force", force, isinstance(force, (bool, np.bool_)), "True or False")
    path = Path(path)
    why = output_path_issue(path)
    if why is not None:
        raise OutputPathError(f"--out '{_short(path)}': {why}.")
    if path.is_symlink() and not path.exists():
        raise OutputPathError(f"--out '{path}' is a symbolic link to a place that does not exist (or a loop of "
                              f"links, -> '{os.readlink(path)}'); remove the link, or choose another --out.")
    base = _first_existing(path.parent)
    if base.is_symlink() and not base.exists():
        raise OutputPathError(f"--out '{path}': '{base}' is a symbolic link to a place that does not exist (or "
                              "a loop of links); remove or fix the link, or choose another --out.")
    if path.exists() and not path.is_dir():
        raise OutputExistsError(f"results path '{path}' exists and is not a folder; choose another --out.")
    if base.exists() and not base.is_dir():
        raise OutputPathError(
            f"--out '{path}': '{base}' is a file, not a folder, so no results folder can be created "
            f"under it; choose an --out outside it (e.g. '{base.parent / 'results'}').")
    if not path.is_dir() and not os.access(base, os.W_OK | os.X_OK):
        raise OutputPathError(
            f"--out '{path}': cannot write in '{base}' (permission denied or read-only); choose an --out "
            "in a writable folder, or make that folder writable.")
    if path.is_dir():
        owned, foreign = owned_entries(path)
        if not force and any(not _leftover(n) for n in owned + foreign):
            raise OutputExistsError(
                f"results folder '{path}' exists and is not empty; pass --force to replace the results of "
                "the earlier run in it (other files are kept), or choose another --out.")
        clash = [n for n in foreign if n in RESULT_NAMES]
        if clash:
            raise OutputExistsError(
                f"results folder '{path}' holds {', '.join(repr(n) for n in clash)}, which alcontact would "
                "write but did not (no summary.json lists it), so --force does not overwrite it; move it "
                "away or choose another --out.")
        if not os.access(path, os.W_OK | os.X_OK):
            raise OutputPathError(
                f"--out '{path}': cannot write in '{path}' (permission denied or read-only); choose another "
                "--out, or make the folder writable.")
    return path


def prepare_output_dir(path: str | os.PathLike, force: bool = False, *, create: bool = True) -> Path:
    """Check the results folder ``path`` (see :func:`check_output_dir`) and create it.

    Prefer :class:`ResultsFolder`, which writes the whole set of files at once.

    Parameters
    ----------
    path : path-like
    force : bool
        Reuse a non-empty folder (see :func:`owned_entries`).
    create : bool
        ``False``: only check (e.g. before a long computation), create nothing.

    Returns
    -------
    Path
        The folder (created with its parents if missing).

    Raises
    ------
    OutputExistsError, OutputPathError
        As :func:`check_output_dir`.
    """
    require("prepare_output_dir", "force", force, isinstance(force, (bool, np.bool_)), "True or False")
    require("prepare_output_dir", "create", create, isinstance(create, (bool, np.bool_)), "True or False")
    path = check_output_dir(path, force)
    if create:
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputPathError(f"--out '{path}': cannot create the folder ({exc.strerror}); choose another "
                                  "--out.") from exc
    return path


# --------------------------------------------------------------------------- lock
_HELD: dict[str, int] = {}  # lock files this process holds -> depth (the CLI holds it over the solve)
_HELD_GUARD = threading.Lock()


def _lock_file(target: Path) -> Path | None:
    """The lock file of results folder ``target``: ``.<name>.alcontact-lock`` beside it.

    Beside, so that one name serves a folder that exists and one still to be made
    (staged beside it). Inside the folder (``.alcontact-lock``) when its parent
    cannot be written (``.``, a mount point). ``None`` when neither place exists yet:
    nothing can be staged there either.
    """
    real = Path(os.path.realpath(target))
    parent = real.parent
    if real.name and parent.is_dir() and os.access(parent, os.W_OK | os.X_OK):
        return parent / f".{real.name}{_LOCK_TAG}"
    if real.is_dir():
        return real / _LOCK_TAG
    return None


def _take(lock: Path, target: Path) -> int:
    """Open and lock ``lock`` (non-blocking); return its descriptor.

    The file is removed when released; a taker that locked a file removed meanwhile
    (its inode no longer at ``lock``) tries again, so two runs never both hold one.
    """
    import fcntl

    for _ in range(50):
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            try:
                owner = os.pread(fd, 64, 0).decode("ascii", "replace").strip()
            except OSError:
                owner = ""
            os.close(fd)
            by = f" (process {owner})" if owner.isdigit() else ""
            raise OutputInUseError(
                f"results folder '{target}' is in use: another alcontact run{by} is writing it (lock file "
                f"'{lock}'); wait until it ends, or choose another --out.") from None
        try:
            same = os.stat(lock).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
            return fd
        os.close(fd)
    raise OutputInUseError(f"cannot take the lock file '{lock}' (it keeps being replaced); choose another --out.")


@contextlib.contextmanager
def output_lock(target: str | os.PathLike) -> Iterator[Path | None]:
    """Hold the lock of the results folder ``target`` during the block (re-entrant within a process).

    Two runs writing one folder at once would delete each other's staging folders;
    with the lock, the second one is refused at once with
    :class:`~alcontact.errors.OutputInUseError` ("in use"). The lock is an advisory
    ``flock`` on ``.<name>.alcontact-lock`` beside the folder: the kernel releases it
    when the process dies, even by SIGKILL, so a stale lock file never blocks a run.
    The file is removed on release. Without ``fcntl`` (Windows), or when no place for
    the lock exists yet, the block runs unlocked.

    Yields
    ------
    Path or None
        The lock file, or ``None`` when unlocked.
    """
    lock = _lock_file(Path(target))
    try:
        import fcntl  # noqa: F401
    except ImportError:  # pragma: no cover - not POSIX
        lock = None
    if lock is None:
        yield None
        return
    key = str(lock)
    with _HELD_GUARD:
        depth = _HELD.get(key, 0)
        _HELD[key] = depth + 1
    fd = None
    try:
        if depth == 0:
            try:
                fd = _take(lock, Path(target))
            except OSError as exc:
                if isinstance(exc, AlcontactError):
                    raise
                logger.debug("no lock for %s (%s): writing unlocked", target, exc)
        yield lock
    finally:
        with _HELD_GUARD:
            _HELD[key] -= 1
            if not _HELD[key]:
                del _HELD[key]
        if fd is not None:
            with contextlib.suppress(OSError):
                os.unlink(lock)
            os.close(fd)


def _remove_stale_staging(where: Path, prefix: str) -> None:
    """Delete staging folders ``where/<prefix>*`` of runs that died (we hold the lock: no live run owns one)."""
    try:
        stale = [p for p in where.iterdir() if p.name.startswith(prefix) and p.is_dir() and not p.is_symlink()]
    except OSError:
        return
    for p in stale:
        shutil.rmtree(p, ignore_errors=True)
    if stale:
        logger.info("removed %d staging folder(s) of interrupted runs: %s", len(stale),
                    ", ".join(p.name for p in stale))


_DEFERRED_SIGNALS = tuple(getattr(signal, n) for n in ("SIGINT", "SIGTERM") if hasattr(signal, n))


@contextlib.contextmanager
def _signals_deferred() -> Iterator[None]:
    """Hold SIGINT/SIGTERM back during the block, then deliver them to the previous handlers.

    Used for the renames that put a results folder in place, so that an
    interrupt never leaves half of the old and half of the new files. Only
    in the main thread (the only one Python delivers signals to).
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []
    old = {s: signal.signal(s, lambda signum, frame: pending.append(signum)) for s in _DEFERRED_SIGNALS}
    try:
        yield
    finally:
        for s, handler in old.items():
            signal.signal(s, handler if handler is not None else signal.SIG_DFL)
        for s in dict.fromkeys(pending):
            signal.raise_signal(s)


class ResultsFolder:
    """A results folder written as a whole: files go into a staging folder, moved into place at the end.

    Parameters
    ----------
    path : path-like
        The results folder (``--out``); its parents are created.
    force : bool
        Replace the files of an earlier run in ``path`` (see :func:`owned_entries`).

    Attributes
    ----------
    target : Path
        ``path``.
    path : Path
        The staging folder to write into (inside the ``with`` block).
    committed : bool
        True once the files are in place.

    Notes
    -----
    A missing ``target`` is staged beside it (``.<name>.partial-<random>``)
    and appears with one rename. An existing folder (``--force``, an empty
    folder, ``.``, a mount point) is staged inside it
    (``.alcontact-partial-<random>``), so that neither its parent nor the
    folder itself changes: at the end the owned entries are deleted
    (``summary.json`` first) and the new entries moved in (``summary.json``
    last). SIGINT/SIGTERM are deferred meanwhile, so only a hard kill during
    those milliseconds can leave a folder without ``summary.json``, whose
    files the next run then treats as foreign (it refuses and says so). On an
    exception (including ``KeyboardInterrupt``) the staging folder is deleted
    and ``target`` is not touched; the exception gets the attribute
    ``results_state = "unchanged"`` (``"written"`` when a deferred signal
    arrives after the files were put in place). An ``OSError`` of the writing
    (a full disk) becomes an :class:`~alcontact.errors.OutputPathError`.

    One run at a time: the block holds :func:`output_lock` (a second run into
    the same folder gets :class:`~alcontact.errors.OutputInUseError`), and
    under it staging folders left by killed runs (``.<name>.partial-*``
    beside, ``.alcontact-partial-*`` inside) are removed. ``a/b/../c`` is
    staged in the real parent ``a``, so no folder ``a/b`` is left behind.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "res"
    >>> with ResultsFolder(out) as rf:
    ...     _ = write_json(rf.path / "summary.json", {"files": ["summary.json"]})
    >>> sorted(p.name for p in out.iterdir())
    ['summary.json']
    """

    def __init__(self, path: str | os.PathLike, force: bool = False):
        require("ResultsFolder", "path", path, is_path(path), "a folder path (str or pathlib.Path)", OutputPathError)
        require("ResultsFolder", "force", force, isinstance(force, (bool, np.bool_)), "True or False")
        self.target = Path(path)
        self.force = force
        self.path: Path | None = None
        self.committed = False

    def __enter__(self) -> ResultsFolder:
        check_output_dir(self.target, self.force)
        inside = self.target.is_dir()
        # the real parent: '--out a/b/../c' makes 'a/c', not a stray 'a/b'
        where = self.target if inside else Path(os.path.realpath(self.target.parent))
        self._lock = contextlib.ExitStack()
        try:
            where.mkdir(parents=True, exist_ok=True)
            self._lock.enter_context(output_lock(self.target))
            check_output_dir(self.target, self.force)  # again, under the lock: another run may have written it
            inside = self.target.is_dir()
            where = self.target if inside else where
            self._final = where / self.target.name if not inside else self.target
            prefix = _STAGING_INSIDE if inside else f".{self.target.name}{_STAGING_TAG}"
            if self.target.name not in ("", ".", ".."):
                _remove_stale_staging(Path(os.path.realpath(self.target.parent)),
                                      f".{self.target.name}{_STAGING_TAG}")
            if inside:
                _remove_stale_staging(where, _STAGING_INSIDE)
            self.path = Path(tempfile.mkdtemp(dir=where, prefix=prefix))
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(self.path, 0o777 & ~umask)
        except BaseException as exc:
            if self.path is not None:
                shutil.rmtree(self.path, ignore_errors=True)
            self._lock.close()
            if not isinstance(exc, OSError) or isinstance(exc, AlcontactError):
                raise
            raise OutputPathError(
                f"--out '{self.target}': cannot create a folder in '{where}' ({exc.strerror or exc}); choose "
                "an --out in a writable folder.") from exc
        logger.debug("staging results in %s", self.path)
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        with self._lock:
            self._exit(exc)

    def _exit(self, exc) -> None:
        if exc is not None:
            with _signals_deferred():
                shutil.rmtree(self.path, ignore_errors=True)
            with contextlib.suppress(AttributeError, TypeError):
                exc.results_state = "unchanged"
            logger.debug("discarded the partial results in %s", self.path)
            if isinstance(exc, OSError) and not isinstance(exc, AlcontactError):  # e.g. a full disk (ENOSPC)
                err = OutputPathError(
                    f"--out '{self.target}': writing the result files failed ({exc.strerror or exc}); the folder "
                    "was left as it was (no partial files). Free space or fix the permissions, or choose another "
                    "--out.")
                err.results_state = "unchanged"
                raise err from exc
            return
        try:
            with _signals_deferred():
                try:
                    self._commit()
                except BaseException:
                    shutil.rmtree(self.path, ignore_errors=True)
                    raise
        except BaseException as err:
            state = "written" if self.committed else "unchanged"
            with contextlib.suppress(AttributeError, TypeError):
                err.results_state = state
            if isinstance(err, OSError) and not isinstance(err, AlcontactError):
                new = OutputPathError(f"--out '{self.target}': putting the result files in place failed "
                                      f"({err.strerror or err}); check the folder and choose another --out if it "
                                      "is not writable.")
                new.results_state = state
                raise new from err
            raise
        logger.info("results written to %s", self.target)

    def _commit(self) -> None:
        staging, target = self.path, self.target
        if staging.parent != target:  # the target did not exist: one rename
            try:
                os.rename(staging, self._final)
            except OSError as exc:
                raise OutputExistsError(f"results folder '{target}' appeared during the run ({exc.strerror}); "
                                        "choose another --out.") from exc
            self.committed = True
            return
        new = sorted(staging.iterdir(), key=lambda p: (p.name == "summary.json", p.name))
        owned, foreign = owned_entries(target)
        clash = set(foreign) & {_entry_name(p) for p in new}
        if clash:
            raise OutputExistsError(f"results folder '{target}' holds {', '.join(sorted(clash))} of someone "
                                    "else; move it away or choose another --out.")
        # summary.json (the manifest) goes first and comes back last: a folder is never
        # described by a manifest of another set of files
        for name in sorted(owned, key=lambda n: n != "summary.json"):
            p = target / name.rstrip("/")
            if p == staging or name == _LOCK_TAG:
                continue
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p)
            else:
                p.unlink()
        for p in new:
            os.rename(p, target / p.name)
        self.committed = True
        staging.rmdir()
