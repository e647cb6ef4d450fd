"""Contact systems: the :class:`ContactSystem` protocol the algorithms call, one module per strategy.

An algorithm (:mod:`alcontact.contact.algorithms`) sees a contact problem only through the
declared members of :class:`ContactSystem` (gaps (6.15) of the candidates, the subproblem (S)
of a multiplier step, the displacement, declared capabilities). The strategies that
implement it, each for frictionless contact and Coulomb friction:

- condensed (:mod:`~alcontact.contact.systems._condensed`): small deformation, the stiffness
  factorized once, the problem condensed on the contact points by the Delassus operator
  :math:`S = B K^{-1} B^T` (:class:`DiscreteContact`, :class:`FrictionalContact`);
- Krylov (:mod:`~alcontact.contact.systems._krylov`): small deformation without a
  factorization, full-space Newton with AMG-preconditioned CG/GMRES
  (:class:`IterativeContact`, :class:`IterativeFrictionalContact`);
- full space (:mod:`~alcontact.contact.systems._full_space`): finite deformation, one
  full-space Newton per subproblem with a direct (:class:`NewtonSolver`) or AMG
  (:class:`AMGNewtonSolver`) linear solver (:class:`FiniteContact`,
  :class:`FiniteFrictionContact`), on the fixed sparse structure of :class:`NewtonLayout`;
- distributed (:mod:`~alcontact.contact.systems._distributed`): small deformation, frictionless,
  over MPI ranks on PETSc ``MPIAIJ`` matrices and KSP solves (:class:`DistributedContact`).

Public names
------------
ContactSystem, CondensedContact, DiscreteContact, FrictionalContact, IterativeContact,
IterativeFrictionalContact, FiniteContact, FiniteFrictionContact, NewtonSolver, AMGNewtonSolver,
finite_solver, NewtonLayout, DistributedContact
"""

from ._condensed import CondensedContact, DiscreteContact, FrictionalContact
from ._distributed import DistributedContact
from ._full_space import AMGNewtonSolver, FiniteContact, FiniteFrictionContact, NewtonSolver, finite_solver
from ._krylov import IterativeContact, IterativeFrictionalContact
from ._layout import NewtonLayout
from ._protocol import ContactSystem

__all__ = ["ContactSystem", "CondensedContact", "DiscreteContact", "FrictionalContact", "IterativeContact",
           "IterativeFrictionalContact", "FiniteContact", "FiniteFrictionContact", "NewtonSolver", "AMGNewtonSolver",
           "finite_solver", "NewtonLayout", "DistributedContact"]
