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

:func:`solve_friction`, :func:`solve_finite` and :func:`solve_finite_friction` are deprecated
(a :class:`DeprecationWarning` names the :func:`solve` call to use) and kept for one release as
thin wrappers over :func:`solve` returning the stepping engines' own records.

The package is organized by concept, one subpackage each: :mod:`~alcontact.contact.problem`
(problem, pairs, supports, loads, load histories), :mod:`~alcontact.contact.masters` (the master
protocol and the rigid obstacles, also :mod:`alcontact.contact.obstacles`),
:mod:`~alcontact.contact.kinematics` (linearized gap (6.15)), :mod:`~alcontact.contact.laws`
(normal and family-P laws, Coulomb return mapping), :mod:`~alcontact.contact.algorithms`
(penalty, Algorithms 6.1-6.4, semi-smooth Newton references, the registry),
:mod:`~alcontact.contact.systems` (the :class:`~alcontact.contact.systems.ContactSystem`
protocol and its condensed, Krylov and full-space strategies), :mod:`~alcontact.contact.stepping`
(load steps and cut-backs) and :mod:`~alcontact.contact.solution` (solutions, frames, estimators).

Examples
--------
>>> from alcontact.problems import hertz
>>> sol = solve(hertz.hertz_2d(level=0), algorithm="simo-laursen")  # doctest: +SKIP
"""

from __future__ import annotations

from .algorithms import (DEFAULT_PENALTY, ContactOptions, FrictionOptions, algorithm_docs, available_algorithms,
                         contact_penalties, describe_algorithms, find_algorithm, finite_friction_algorithms,
                         friction_algorithm_docs, friction_algorithms, friction_only_options)
from .kinematics._points import _element_size as contact_element_size
from .kinematics._start import PairStart, pair_start
from .masters import BodySurface, Master, RigidBody, obstacles
from .problem import (KINEMATICS, BodyForce, Boundary, ContactPair, ContactProblem, LoadCase, LoadHistory, Pressure,
                      Ramp, RigidLoad, Support, Traction, merge_supports, problem_at)
from .solution import (ContactFrame, ContactIteration, ContactResult, ContactSolution, ContactStatus,
                       FiniteFrictionSolution, FiniteFrictionStep, FiniteSolution, FiniteStep, FrictionSolution,
                       FrictionStep)
from ._distributed import DistributedContactSolution, solve_distributed
from ._solve import DEFAULT_ALGORITHM, solve, solve_finite, solve_finite_friction, solve_friction
from ._verify import check_state

__all__ = [
    "obstacles",
    "ContactProblem",
    "ContactPair",
    "Boundary",
    "Master",
    "BodySurface",
    "RigidBody",
    "RigidLoad",
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
    "solve_distributed",
    "DistributedContactSolution",
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
    "pair_start",
    "PairStart",
    "merge_supports",
]
