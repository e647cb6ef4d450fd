"""Run a script under ``mpirun -n N`` with a timeout (so a hang fails the test instead of stalling CI)."""

from __future__ import annotations

import os
import subprocess
import sys

MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMPI_MCA_rmaps_base_oversubscribe": "1",
           "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}


def mpirun(n: int, script: str, *args: str, timeout: float = 120.0) -> subprocess.CompletedProcess:
    """``mpirun -n n --oversubscribe python script args`` with this interpreter; output captured."""
    env = dict(os.environ, **MPI_ENV)
    cmd = ["mpirun", "-n", str(n), "--oversubscribe", sys.executable, script, *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
