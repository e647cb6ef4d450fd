"""Contact solutions: the one :class:`ContactSolution` with per-step :class:`ContactFrame` s.

Every solve returns a :class:`ContactSolution` (status, displacement, pressure, gaps,
multipliers, the optimization counters and KKT measures, one :class:`ContactFrame` per
step); the stepping engines record their accepted steps (:class:`StepRecords`:
:class:`FiniteStep`, :class:`FrictionStep`, :class:`FiniteFrictionStep`) and
:mod:`~alcontact.contact.solution._frames` turns them into frames. The estimators
(:func:`equilibrium`: global equilibrium of a state; :func:`fit_hertz_field`: the
:math:`L^2` Hertz fit of a pressure field, a :class:`HertzFit`) read a solution.

Public names
------------
ContactSolution, ContactFrame, ContactIteration, ContactResult, ContactStatus, StepRecords,
Frame, FiniteStep, FiniteSolution, FrictionStep, FrictionSolution,
FiniteFrictionStep, FiniteFrictionSolution, Equilibrium, equilibrium, HertzFit, fit_hertz_field
"""

from ._estimators import Equilibrium, HertzFit, equilibrium, fit_hertz_field
from ._records import (FiniteFrictionSolution, FiniteFrictionStep, FiniteSolution, FiniteStep, Frame,
                       FrictionSolution, FrictionStep, StepRecords)
from ._solution import ContactFrame, ContactIteration, ContactResult, ContactSolution, ContactStatus

__all__ = ["ContactSolution", "ContactFrame", "ContactIteration", "ContactResult", "ContactStatus", "StepRecords",
           "Frame", "FiniteStep", "FiniteSolution", "FrictionStep", "FrictionSolution",
           "FiniteFrictionStep", "FiniteFrictionSolution", "Equilibrium", "equilibrium", "HertzFit",
           "fit_hertz_field"]
