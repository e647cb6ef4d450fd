"""Contact of elastic bodies with rigid obstacles (chapter 6): one entry point, :func:`solve`.

:func:`solve` runs every case and returns one :class:`ContactSolution` with per-step
:class:`ContactFrame` frames; the problem decides what runs:

- frictionless contact at small deformation (linearized gap (6.15)) with the pure penalty
  method (6.10), Algorithm 6.1 (Simo & Laursen, Macaulay update (6.13)), Algorithm 6.3
  (family-P penalties, the dissertation's proposal) or a semi-smooth Newton / primal-dual
  active-set reference; one static solve, or one per step time of a ``history``;
- finite deformation (``ContactProblem(..., kinematics="finite")``: gap at the current
  configuration, load steps with cut-backs, one full-space Newton for every algorithm);
- Coulomb friction (``problem.friction > 0`` or ``friction=``) with load stepping:
  Algorithm 6.2 (Macaulay normal part), Algorithm 6.4 (family-P normal part) and an
  Alart-Curnier semi-smooth Newton reference, at small or finite deformation.

:func:`solve_friction`, :func:`solve_finite` and :func:`solve_finite_friction` are kept for
one release as thin wrappers over :func:`solve` returning the stepping engines' own records.

Examples
--------
>>> from alcontact.problems import hertz
>>> sol = solve(hertz.hertz_2d(level=0), algorithm="simo-laursen")  # doctest: +SKIP
"""

from __future__ import annotations

from . import obstacles
from ._master import Master
from ._problem import Boundary, ContactPair
from ._algorithms import ContactOptions, algorithm_docs, available_algorithms, contact_penalties
from ._problem import BodyForce, ContactProblem, Pressure, Support, Traction
from ._solution import ContactFrame, ContactIteration, ContactResult, ContactSolution, ContactStatus
from ._solve import DEFAULT_ALGORITHM, DEFAULT_PENALTY, solve, solve_finite, solve_finite_friction, solve_friction
from ._friction import FrictionOptions, friction_algorithm_docs, friction_algorithms
from ._friction_solution import FrictionSolution, FrictionStep
from ._loading import LoadCase, LoadHistory, Ramp, problem_at
from ._problem import KINEMATICS
from ._stepping import FiniteSolution, FiniteStep
from ._finite_friction import FiniteFrictionSolution, FiniteFrictionStep, finite_friction_algorithms
from . import _friction_iterative  # noqa: F401  (registers the Krylov strategy of solve_friction)
from ._verify import check_state

# the algorithm registry, the merged supports and the element size, for the problem-file loader and the
# application layer (alcontact.io, alcontact.runner): public names, so no caller reaches into a private module
from ._algorithms import describe_algorithms, find_algorithm, friction_only_options
from ._discrete import _element_size as contact_element_size
from ._problem import merge_supports

__all__ = [
    "obstacles",
    "ContactProblem",
    "ContactPair",
    "Boundary",
    "Master",
    "Support",
    "Traction",
    "Pressure",
    "BodyForce",
    "ContactOptions",
    "ContactStatus",
    "ContactIteration",
    "ContactResult",
    "ContactSolution",
    "ContactFrame",
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
    "describe_algorithms",
    "find_algorithm",
    "friction_only_options",
    "contact_element_size",
    "merge_supports",
]
