"""Contact of linear elastic bodies with rigid obstacles (chapter 6).

Frictionless contact (small deformation, linearized gap (6.15)) with

- the pure penalty method (6.10),
- Algorithm 6.1 (Simo & Laursen, Macaulay update (6.13)),
- Algorithm 6.3 (family-P penalties, the dissertation's proposal),
- a semi-smooth Newton / primal-dual active-set reference;

finite-deformation frictionless contact (gap at the current configuration, load
steps, one full-space Newton for every algorithm: :func:`solve_finite`, or
``ContactProblem(..., kinematics="finite")``);
and Coulomb friction with load stepping (:func:`solve_friction`): Algorithm 6.2
(Macaulay normal part), Algorithm 6.4 (family-P normal part) and an Alart-Curnier
semi-smooth Newton reference.

All work on the problem condensed on the contact points (one factorization of
the stiffness, see :mod:`alcontact.contact._discrete`).

Examples
--------
>>> from alcontact.problems import hertz
>>> sol = solve(hertz.hertz_2d(level=0), algorithm="simo-laursen")  # doctest: +SKIP
"""

from __future__ import annotations

from . import obstacles
from ._algorithms import ContactOptions, algorithm_docs, available_algorithms, contact_penalties
from ._problem import BodyForce, ContactProblem, Pressure, Support, Traction
from ._solution import ContactIteration, ContactResult, ContactSolution, ContactStatus
from ._solve import DEFAULT_ALGORITHM, DEFAULT_PENALTY, solve
from ._friction import FrictionOptions, friction_algorithm_docs, friction_algorithms, solve_friction
from ._friction_solution import FrictionSolution, FrictionStep
from ._loading import LoadCase, LoadHistory, Ramp, problem_at
from ._problem import KINEMATICS
from ._stepping import FiniteSolution, FiniteStep, solve_finite
from . import _friction_iterative  # noqa: F401  (registers the Krylov strategy of solve_friction)
from ._finite_friction import (FiniteFrictionSolution, FiniteFrictionStep, finite_friction_algorithms,
                               solve_finite_friction)
from ._verify import check_state

__all__ = [
    "obstacles",
    "ContactProblem",
    "Support",
    "Traction",
    "Pressure",
    "BodyForce",
    "ContactOptions",
    "ContactStatus",
    "ContactIteration",
    "ContactResult",
    "ContactSolution",
    "solve",
    "available_algorithms",
    "algorithm_docs",
    "contact_penalties",
    "DEFAULT_ALGORITHM",
    "DEFAULT_PENALTY",
    "solve_friction",
    "FrictionOptions",
    "FrictionSolution",
    "FrictionStep",
    "friction_algorithms",
    "friction_algorithm_docs",
    "LoadHistory",
    "LoadCase",
    "Ramp",
    "problem_at",
    "KINEMATICS",
    "solve_finite",
    "FiniteSolution",
    "FiniteStep",
    "solve_finite_friction",
    "FiniteFrictionSolution",
    "FiniteFrictionStep",
    "finite_friction_algorithms",
    "check_state",
]
