"""General augmented Lagrangian engine (chapter 5 of Sant'Ana, 2005).

:func:`minimize` is shaped like :func:`scipy.optimize.minimize`: SciPy's
``NonlinearConstraint`` / ``LinearConstraint`` / ``Bounds`` in, a frozen
:class:`ALResult` out. Registered outer methods (:func:`available_methods`):

- ``"barrier"`` -- Algorithm 5.1, logarithmic (5.2) or inverse (5.3) barrier;
- ``"exterior-penalty"`` -- Algorithm 5.2, quadratic penalty (5.8)/(5.9);
- ``"hestenes-powell"`` -- Algorithm 5.3, equality constraints (5.13)-(5.15);
- ``"al"`` -- Algorithm 5.4 (corrected update ``mu <- p'(g/eta, mu)``) with any
  AL penalty of :mod:`alcontact.penalties` for inequalities and Hestenes-Powell
  for equalities in the same loop.

Variable bounds of ``"al"`` stay an exact box of every subproblem (ALGENCAN /
LANCELOT style, option ``bounds_as``): the inner solver is then Bertsekas'
projected Newton method, iterates never leave the box and the bound multipliers
are read from the Lagrangian gradient.

Penalty-parameter update rules (:func:`available_strategies`, :func:`register_strategy`;
shared with the contact algorithms) and inner solvers
(:func:`available_inner_solvers`) are registries too. :func:`newton` is the one globalized Newton method of the package (contact
subproblems and the hyperelastic body's solves). Throughout, ``eta -> 0``
is the constrained limit: a smaller ``eta`` is a stronger AL penalty.
"""

from __future__ import annotations

from ._inner import available_inner_solvers
from ._minimize import Options, available_methods, minimize
from ._newton import LineSearch, NewtonRecord, NewtonResult, NewtonSettings, NewtonSystem, inner_failure, newton
from ._result import ALResult, IterationRecord, Status
from ._strategies import (PenaltyUpdate, StrategyState, available_strategies, describe_strategies, make_strategy,
                          register_strategy, unregister_strategy)

__all__ = [
    "minimize",
    "ALResult",
    "IterationRecord",
    "Status",
    "Options",
    "available_methods",
    "available_strategies",
    "describe_strategies",
    "make_strategy",
    "register_strategy",
    "unregister_strategy",
    "PenaltyUpdate",
    "StrategyState",
    "newton",
    "NewtonSystem",
    "NewtonSettings",
    "LineSearch",
    "NewtonRecord",
    "NewtonResult",
    "inner_failure",
    "available_inner_solvers",
]
