"""Former home of the application layer, kept importable for one release: use :mod:`alcontact.app`.

Every public name of :mod:`alcontact.app` is re-exported here unchanged (``run_problem``,
``run_setup``, ``summarize``, ``write_results``, ...), and the private helpers that user
scripts reached into (``_ADVICE``) stay reachable.
"""

from __future__ import annotations

from . import app as _app
from .app import *  # noqa: F401,F403  (every public name of alcontact.app, listed once in its __all__)
from .app.summary import ADVICE

_ADVICE = ADVICE  # the name of the former module

__all__ = [*_app.__all__, "_ADVICE"]
