"""Tests of the PETSc/MPI backend: run by ``make test`` in ``.venv-mpi`` (``make mpi``).

They are never skipped: without petsc4py, mpi4py or ``mpirun`` the session stops with an
error that says how to install them.
"""

import os
import shutil

import pytest

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
    os.environ.setdefault(_var, "1")


def pytest_configure(config):
    missing = []
    try:
        from alcontact.linalg import petsc

        petsc()
    except Exception as exc:  # the InputError that names `make mpi`
        missing.append(str(exc))
    try:
        import mpi4py  # noqa: F401
    except ImportError as exc:
        missing.append(f"mpi4py: {exc}")
    if shutil.which("mpirun") is None:
        missing.append("mpirun is not on PATH (OpenMPI: apt-get install openmpi-bin)")
    if missing:
        raise pytest.UsageError("tests/mpi need the MPI environment; run `make mpi` and use .venv-mpi/bin/python "
                                "(make test does), or leave them out explicitly (make test-serial, pytest "
                                "--ignore=tests/mpi): " + "; ".join(missing))
