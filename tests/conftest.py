"""Test configuration.

Under CI (``CI`` set in the environment) Hypothesis runs derandomized, so a
submission's result does not depend on the random examples drawn that day; the
random search still runs in every developer's ``make test``.

One BLAS/OpenMP thread per process (set before NumPy is imported, unless the
environment says otherwise): ``make test`` runs one pytest worker per core, and
multi-threaded BLAS in each worker oversubscribes the cores (the suite took
several times longer on 2 cores). The xdist workers inherit these variables.
CHOLMOD (cholespy) links a single-threaded reference BLAS.

``make fuzz`` sets ``ALCONTACT_FUZZ=1``, which selects the ``fuzz`` profile: the
fuzz tests (problem files ``tests/unit/test_config_fuzz.py``, Gmsh files
``tests/unit/test_gmsh_fuzz.py``, Python-API calls ``tests/unit/test_api_fuzz.py``)
then draw 40,000 examples each instead of their 1,000 or fewer.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS",
             "NUMEXPR_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

from hypothesis import HealthCheck, settings  # noqa: E402

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("fuzz", max_examples=40_000, deadline=None, print_blob=True,
                          suppress_health_check=[HealthCheck.too_slow])
if os.environ.get("ALCONTACT_FUZZ"):
    settings.load_profile("fuzz")
elif os.environ.get("CI"):
    settings.load_profile("ci")
