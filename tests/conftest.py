"""Test configuration.

Under CI (``CI`` set in the environment) Hypothesis runs derandomized, so a
submission's result does not depend on the random examples drawn that day; the
random search still runs in every developer's ``make test``.

One BLAS/OpenMP thread per process (set before NumPy is imported, unless the
environment says otherwise): ``make test`` runs one pytest worker per core, and
multi-threaded BLAS in each worker oversubscribes the cores (the suite took
several times longer on 2 cores). The xdist workers inherit these variables.
CHOLMOD (cholespy) links a single-threaded reference BLAS.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS",
             "NUMEXPR_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

from hypothesis import settings  # noqa: E402

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
