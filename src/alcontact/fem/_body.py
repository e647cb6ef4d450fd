r"""The body abstraction every contact algorithm works with.

A body is a discretized solid with a displacement vector ``u`` of ``ndofs``
entries (the DOF numbering of its scikit-fem basis). It offers its internal
force, its tangent and, where one exists, its stored energy; the external
loads, Dirichlet data and boundary geometry come from the same object
(named boundaries, tributary weights, load vectors), so that the contact layer
never needs to know which constitutive law is inside.

.. math::

    R(u) = f_{int}(u) - f_{ext} = 0, \qquad K_T(u) = \frac{\partial f_{int}}{\partial u},
    \qquad f_{int} = \frac{\partial \Pi_{int}}{\partial u}.

For the linear elastic body (small deformation) :math:`f_{int} = K u` and
:math:`K_T = K`; for hyperelastic bodies (total Lagrangian, chapter 3)
:math:`f_{int}(u) = \int_\Omega P(F) : \nabla_X \delta u \, dV` with the first
Piola-Kirchhoff stress :math:`P = \partial W/\partial F`.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

__all__ = ["Body"]


@runtime_checkable
class Body(Protocol):
    """Protocol of a discretized body (see module doc).

    Attributes
    ----------
    dim : int
        Spatial dimension (2 or 3).
    ndofs : int
        Number of displacement DOFs.
    linear : bool
        ``True`` when the internal force is linear in ``u`` (constant tangent):
        the condensed (Delassus) contact path applies.
    axisymmetric : bool
        ``True`` for a body of revolution in the r-z half-plane (:mod:`alcontact.fem._geometry`):
        forces are totals over the revolution and only the axial force is a global balance.
    axis_dofs : numpy.ndarray of int
        DOFs the body itself fixes to zero (:math:`u_r` on the axis of a body of revolution;
        empty otherwise): every solve adds them to the supports.
    """

    dim: int
    ndofs: int
    linear: bool
    axisymmetric: bool
    axis_dofs: np.ndarray

    def internal_force(self, u: np.ndarray) -> np.ndarray:
        """Internal force vector :math:`f_{int}(u)`, shape ``(ndofs,)``."""

    def tangent(self, u: np.ndarray) -> sp.csr_matrix:
        """Tangent stiffness :math:`\\partial f_{int}/\\partial u` (``ndofs x ndofs``, CSR)."""

    def energy(self, u: np.ndarray) -> float:
        """Stored energy :math:`\\Pi_{int}(u)` (``nan`` where the law has none)."""
