"""Contact algorithms and their registry (chapter 6).

Frictionless (:mod:`~alcontact.contact.algorithms._frictionless`): the pure penalty method
(6.10), Algorithm 6.1 (Simo & Laursen, Macaulay update (6.13)), Algorithm 6.3 (family-P
penalties), a semi-smooth Newton / primal-dual active-set reference and the barrier anchor
(:mod:`~alcontact.contact.algorithms._barrier`: Polyak's modified log barrier with fixed
multipliers, the barrier parameter driven to zero). Coulomb friction
(:mod:`~alcontact.contact.algorithms._coulomb`, section 6.2): Algorithm 6.2 (Macaulay
normal part), Algorithm 6.4 (family-P normal part), the Alart-Curnier semi-smooth Newton
reference and the barrier anchor per load step (:func:`step_barrier`: held normal
multipliers, the tangential part of Algorithm 6.2). Each algorithm is written once against the
:class:`~alcontact.contact.systems.ContactSystem` protocol and registered
(:class:`Algorithm`, :func:`register_family`) for the kinematics and linear solvers it
runs with; the subproblem (S) of a multiplier step is solved by the Newton method of
:mod:`~alcontact.contact.algorithms._subproblem`.

Public names
------------
ContactOptions, FrictionOptions, Algorithm, register, register_family, find_algorithm,
algorithms, algorithm_names, available_algorithms, algorithm_docs, describe_algorithms,
friction_algorithms, friction_algorithm_docs, finite_friction_algorithms, friction_only_options,
contact_penalties, DEFAULT_PENALTY, run_penalty, run_al, run_ssn, solve_subproblem,
BARRIER_PENALTY, run_barrier, step_barrier
"""

from ._coulomb import FrictionOptions, finite_friction_algorithms, friction_algorithm_docs, friction_algorithms
from ._frictionless import (DEFAULT_PENALTY, Algorithm, ContactOptions, algorithm_docs, algorithm_names, algorithms,
                            available_algorithms, contact_penalties, describe_algorithms, find_algorithm,
                            friction_only_options, register, register_family, run_al, run_penalty, run_ssn)
from ._subproblem import solve_subproblem
from ._barrier import BARRIER_PENALTY, run_barrier, step_barrier  # registers "log-barrier"

__all__ = ["ContactOptions", "FrictionOptions", "Algorithm", "register", "register_family", "find_algorithm",
           "algorithms", "algorithm_names", "available_algorithms", "algorithm_docs", "describe_algorithms",
           "friction_algorithms", "friction_algorithm_docs", "finite_friction_algorithms", "friction_only_options",
           "contact_penalties", "DEFAULT_PENALTY", "run_penalty", "run_al", "run_ssn", "solve_subproblem",
           "BARRIER_PENALTY", "run_barrier", "step_barrier"]
