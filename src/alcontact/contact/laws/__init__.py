"""Contact laws: the normal law (6.10)/(6.13) or a family-P penalty, and Coulomb's law.

- Normal: the contact pressure as a function of the gap and the multiplier,
  :math:`t_N = \\langle \\lambda + \\varepsilon g \\rangle` (Macaulay, (6.13): pure penalty and
  Algorithm 6.1) or :math:`t_N = p'(g/\\eta, \\lambda)` with a family-P penalty :math:`p`
  (Algorithm 6.3, the dissertation's proposal), scaled by :math:`\\eta`
  (:func:`eta_for_stiffness`); :func:`make_law` builds the :class:`NormalLaw` of a registered
  penalty.
- Coulomb: the return mapping (6.47)-(6.50) of the tangential traction onto the disc
  :math:`|t_T| \\le \\mu t_N` (:func:`return_mapping`, :func:`local_law`; states
  ``OPEN`` / ``STICK`` / ``SLIP``); :class:`CoulombLaw` holds its data (:math:`\\mu`,
  :math:`\\varepsilon_T`, the disc radius): the tangential part of a contact law, held by the
  frictional system at finite deformation.
- :func:`penalty_stiffness`: the automatic penalty :math:`E'/h` shared by every solve.

Public names
------------
NormalLaw, make_law, eta_for_stiffness, freezes_at_zero, Macaulay, CoulombLaw, return_mapping, local_law,
tangential_energy, OPEN, STICK, SLIP, penalty_stiffness
"""

from ._coulomb import OPEN, SLIP, STICK, CoulombLaw, Macaulay, local_law, return_mapping, tangential_energy
from ._normal import NormalLaw, eta_for_stiffness, freezes_at_zero, make_law
from ._stiffness import penalty_stiffness

__all__ = ["NormalLaw", "make_law", "eta_for_stiffness", "freezes_at_zero", "Macaulay", "CoulombLaw", "return_mapping",
           "local_law", "tangential_energy", "OPEN", "STICK", "SLIP", "penalty_stiffness"]
