"""Test configuration.

Under CI (``CI`` set in the environment) Hypothesis runs derandomized, so a
submission's result does not depend on the random examples drawn that day; the
random search still runs in every developer's ``make test``.

``make fuzz`` sets ``ALCONTACT_FUZZ=1``, which selects the ``fuzz`` profile: the
problem-file fuzz tests (``tests/unit/test_config_fuzz.py``) then draw 40,000
examples each (120,000 in all) instead of their few hundred.
"""

import os

from hypothesis import HealthCheck, settings

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("fuzz", max_examples=40_000, deadline=None, print_blob=True,
                          suppress_health_check=[HealthCheck.too_slow])
if os.environ.get("ALCONTACT_FUZZ"):
    settings.load_profile("fuzz")
elif os.environ.get("CI"):
    settings.load_profile("ci")
