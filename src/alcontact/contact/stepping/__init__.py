"""Load stepping: incremental solves over step times, with cut-backs (section 6.2).

:func:`step_through` walks the step times of every stepped solve: an *attempt* (one try of
the step from the last accepted state) and a *commit*; a failed try is cut back, a failure
at the smallest increment ends the run with a negative status. The engines built on it:
frictionless contact at finite deformation (:mod:`~alcontact.contact.stepping._frictionless`)
and Coulomb friction at small and finite deformation
(:mod:`~alcontact.contact.stepping._coulomb`); :func:`alcontact.contact.solve` calls them.

Public names
------------
step_through, Attempt, StepRecord, SteppingResult, register_friction_strategy,
register_friction_kinematics
"""

from ._coulomb import register_friction_kinematics, register_friction_strategy
from ._steps import Attempt, StepRecord, SteppingResult, step_through

__all__ = ["step_through", "Attempt", "StepRecord", "SteppingResult", "register_friction_strategy",
           "register_friction_kinematics"]
