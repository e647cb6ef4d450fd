"""How the process was started: one process, or one rank of an MPI launcher (``mpirun -n N``).

Read from the environment the launchers set (OpenMPI: ``OMPI_COMM_WORLD_SIZE`` /
``OMPI_COMM_WORLD_RANK``; MPICH and Intel MPI: ``PMI_SIZE`` / ``PMI_RANK``), so the check
imports no MPI library: a serial environment started under ``mpirun`` gets a clear
message instead of N copies of a serial run writing one results folder.
"""

from __future__ import annotations

import importlib.util
import os

from ..errors import InputError

__all__ = ["check_launch", "launch_rank", "launch_size", "mpi_extras_missing"]

#: (size, rank) environment variables of the MPI launchers, first match wins
_LAUNCHER_VARS = (("OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"), ("PMI_SIZE", "PMI_RANK"))


def _read(var: str) -> int | None:
    value = os.environ.get(var, "").strip()
    return int(value) if value.isdigit() else None


def launch_size() -> int:
    """Number of processes the MPI launcher started (1 when not started by one)."""
    for size_var, _ in _LAUNCHER_VARS:
        size = _read(size_var)
        if size is not None:
            return max(size, 1)
    return 1


def launch_rank() -> int:
    """Rank of this process in the MPI launch (0 when not started by a launcher)."""
    for size_var, rank_var in _LAUNCHER_VARS:
        if _read(size_var) is not None:
            return _read(rank_var) or 0
    return 0


def _installed(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):  # ValueError: a module blocked in sys.modules
        return False


def mpi_extras_missing() -> list[str]:
    """The MPI extras (mpi4py, petsc4py) this environment lacks (empty: the distributed path can run)."""
    return [m for m in ("mpi4py", "petsc4py") if not _installed(m)]


def check_launch(what: str) -> None:
    """Refuse to run ``what`` (e.g. ``"alcontact run"``) as several MPI ranks, with the way out.

    Started by ``mpirun -n N`` with N > 1, every rank would run the same serial solve and
    write the same results folder. Without the MPI extras (mpi4py, petsc4py) the message
    gives the ``make mpi`` command; with them (the CLI calls it only for a run without a
    problem file: ``mpirun -n N alcontact run problem.toml`` runs the distributed path,
    :func:`alcontact.contact.solve_distributed`), it says that a built-in problem runs as one
    process and the distributed path takes problem files.

    Raises
    ------
    InputError
        Started as more than one MPI rank.
    """
    from ..linalg import MPI_SETUP_HINT

    size = launch_size()
    if size <= 1:
        return
    missing = mpi_extras_missing()
    if missing:
        raise InputError(f"{what} was started by an MPI launcher as {size} processes, but this environment has no "
                         f"MPI extras ({' and '.join(missing)} not installed): {MPI_SETUP_HINT}; or run it "
                         "without mpirun, as one process.")
    raise InputError(f"{what} was started by an MPI launcher as {size} processes without a problem file: the "
                     "distributed path runs problem files (mpirun -n N alcontact run problem.toml; frictionless "
                     "small-deformation contact in one load step); a built-in problem runs as one process: give a "
                     "problem file or run it without mpirun.")
