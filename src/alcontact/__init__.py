"""alcontact: augmented Lagrangian methods for elastic contact with rigid obstacles.

Sub-packages mirror the mathematics of Sant'Ana (2005):

- :mod:`alcontact.penalties` -- theta generators, MET 1 / MET 2, classical penalties (ch. 5)
- :mod:`alcontact.optim` -- general augmented Lagrangian engine, Algorithms 5.1-5.4
- :mod:`alcontact.fem` -- linear elasticity on scikit-fem, chapter 4 model problems
- :mod:`alcontact.contact` -- rigid obstacles, Algorithms 6.1-6.4, semi-smooth Newton reference
"""

from __future__ import annotations

import logging

__version__ = "0.1.0"
__all__ = ["__version__"]

logging.getLogger(__name__).addHandler(logging.NullHandler())
