"""Test configuration.

Under CI (``CI`` set in the environment) Hypothesis runs derandomized, so a
submission's result does not depend on the random examples drawn that day; the
random search still runs in every developer's ``make test``.
"""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
