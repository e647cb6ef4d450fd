"""The rigid obstacles under their historical import path, ``alcontact.contact.obstacles``.

The code lives in :mod:`alcontact.contact.masters.obstacles` (the rigid masters of a
contact pair); this module *is* that module (one module object, so names, registrations
and monkeypatching are shared), kept so that ``from alcontact.contact.obstacles import
Sphere`` and ``from alcontact.contact import obstacles`` keep working.
"""

import sys

from .masters import obstacles as _obstacles

sys.modules[__name__] = _obstacles
