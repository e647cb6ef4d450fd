r"""Contact kinematics: the gap of the slave points against a master, its gradient and Hessian.

One interface (:class:`ContactKinematics`) for the two configurations of chapter 6 and for
any :class:`~alcontact.contact.Master`. At contact point ``i`` (a DOF location of the slave
boundary, reference position :math:`X_i`, displacement :math:`u_i`):

- :class:`LinearizedGap` (small deformation, ``configuration = "reference"``): the gap
  linearized at the reference configuration (6.15),

  .. math::

      g_i(u) = g^0_i - \nu_i \cdot u_i, \qquad
      \frac{\partial g_i}{\partial u_i} = -\nu_i, \qquad
      \frac{\partial^2 g_i}{\partial u_i^2} = 0,

  with :math:`g^0_i` the master's signed gap at :math:`X_i` and :math:`\nu_i` its normal
  there (evaluated once);
- :class:`CurrentGap` (finite deformation, ``configuration = "current"``): the gap at the
  current position :math:`x_i = X_i + u_i`,

  .. math::

      g_i(u) = \operatorname{gap}(X_i + u_i), \qquad
      \frac{\partial g_i}{\partial u_i} = -\nu_i(x_i), \qquad
      \frac{\partial^2 g_i}{\partial u_i^2} = H(x_i),

  :math:`\nu` the master's normal at the projection of :math:`x_i` and :math:`H` the
  Hessian of its signed distance (the curvature term of the consistent linearization of
  the contact force :math:`\sum_i w_i t_{N,i} \nabla g_i`; zero for a plane). The
  linearization of this gap at :math:`u = 0` is (6.15).

The derivatives are taken with respect to the *free* DOFs ``x`` of the body (the supported
ones hold prescribed values): the gradient :math:`G = \partial g / \partial x` is a sparse
matrix of one row per point, the *constraint rows* of the contact systems
(:mod:`alcontact.contact.systems`: the ``B`` of the condensed and Krylov strategies, the
:math:`B(u)` of the full-space Newton). Node-to-surface kinematics (both classes here)
have one block :math:`-\nu_i^T` per row, on the DOFs of point ``i`` alone, and a
:math:`d \times d` Hessian block per point: they declare ``pointwise = True``, which lets a
system fill those blocks into a fixed sparse structure. A kinematics whose gap couples
several points' DOFs (mortar: a weighted gap per slave node with dual shape functions, a
deformable master's DOFs) declares ``pointwise = False`` and gives its gradient and Hessian
only as sparse matrices (:meth:`GapEvaluation.gradient`, :meth:`GapEvaluation.curvature`),
which is all a system needs from it.

Sign convention: :math:`g \le 0` is feasible (no penetration).
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

from ..masters._stacked import StackedMaster


def _rows(normals: np.ndarray, pos: np.ndarray, nfree: int) -> sp.csr_matrix:
    """Rows :math:`-\\nu_i^T` on the free DOFs ``pos`` (``(k, d)``, -1 on supported DOFs) of ``k`` points."""
    k, d = pos.shape
    rows = np.repeat(np.arange(k), d)
    cols = pos.ravel()
    keep = cols >= 0
    return sp.csr_matrix(((-normals).ravel()[keep], (rows[keep], cols[keep])), shape=(k, nfree))


def point_blocks(pos: np.ndarray, blocks: np.ndarray, nfree: int) -> sp.csr_matrix:
    """Sparse sum of the ``d x d`` ``blocks`` (``(k, d, d)``) of ``k`` points on their free DOFs ``pos``."""
    k, d = pos.shape
    r = np.repeat(pos, d, axis=1).ravel()
    c = np.tile(pos, (1, d)).ravel()
    v = blocks.reshape(k, d * d).ravel()
    keep = (r >= 0) & (c >= 0) & (v != 0)
    return sp.csr_matrix((v[keep], (r[keep], c[keep])), shape=(nfree, nfree))


class GapEvaluation:
    r"""The gap of some contact points at one displacement, with its derivatives.

    What :meth:`ContactKinematics.evaluate` returns for the pointwise kinematics here; a
    kinematics whose gaps couple several points (mortar) returns an object with the same
    members (``idx``, ``g``, ``normals``, ``hessian``, :meth:`gradient`, :meth:`curvature`),
    whose gradient and curvature it assembles itself.

    Attributes
    ----------
    idx : ndarray of int (k,)
        The points (indices into the kinematics' points).
    g : ndarray (k,)
        Gaps :math:`g_i(u)` (:math:`\le 0` feasible).
    normals : ndarray (k, d)
        The master's unit normal at each point's projection (out of the master); the
        contact force on point ``i`` is :math:`w_i t_{N,i} \nu_i`.
    hessian : ndarray (k, d, d) or None
        :math:`\partial^2 g_i / \partial u_i^2` of a pointwise kinematics (asked with
        ``hessian=True``; zeros for the linearized gap (6.15)); ``None`` when not asked.
    """

    def __init__(self, idx, g, normals, hessian, pos, nfree, gradient=None):
        self.idx, self.g, self.normals, self.hessian = idx, g, normals, hessian
        self._pos, self._nfree, self._gradient = pos, nfree, gradient

    def gradient(self, mask: np.ndarray | None = None) -> sp.csr_matrix:
        r"""Constraint rows :math:`G = \partial g/\partial x`, shape ``(k, n_free)`` (CSR).

        Pointwise kinematics: the row of point ``i`` is :math:`-\nu_i^T` on its free DOFs.
        ``mask`` (bool ``(k,)``): the rows of the points where it is false are zero, stored as
        explicit zeros (the sparsity pattern does not depend on the mask).
        """
        if mask is not None:
            return _rows(self.normals * np.asarray(mask)[:, None], self._pos, self._nfree)
        if self._gradient is None:
            self._gradient = _rows(self.normals, self._pos, self._nfree)
        return self._gradient

    def curvature(self, c: np.ndarray) -> sp.csr_matrix:
        r""":math:`\sum_i c_i\, \partial^2 g_i / \partial x^2`, shape ``(n_free, n_free)`` (CSR).

        With :math:`c_i = w_i t_{N,i}` it is the geometric part of the tangent of the contact
        force :math:`G^T (w \circ t_N)`. Needs ``hessian=True`` in
        :meth:`ContactKinematics.evaluate`.
        """
        if self.hessian is None:
            raise ValueError("curvature needs the gap Hessian: evaluate(..., hessian=True)")
        c = np.asarray(c, dtype=float)
        return point_blocks(self._pos, c[:, None, None] * self.hessian, self._nfree)


@runtime_checkable
class ContactKinematics(Protocol):
    r"""The gap of the slave points against a master and its derivatives (module doc).

    Implemented by :class:`LinearizedGap` (6.15) and :class:`CurrentGap` (finite
    deformation); a contact system holds one and asks it for every gap, constraint row and
    curvature term it uses. A new kinematics (mortar, a deformable master) implements these
    members; the algorithms and systems do not change.

    Attributes
    ----------
    configuration : {"reference", "current"}
        Where the gap is measured: ``"reference"``, linearized at :math:`u = 0` (6.15), its
        gradient constant and its Hessian zero (the contact constraints are linear: a
        condensed or Krylov strategy may factorize or precondition once); ``"current"``, at
        :math:`x = X + u` (gradient and Hessian change with :math:`u`).
    pointwise : bool
        ``True`` when the row of point ``i`` of the gradient is :math:`-\nu_i^T` on the
        DOFs of point ``i`` alone and its Hessian one :math:`d \times d` block there
        (node-to-surface); ``False`` when a gap couples several points (mortar).
    points : ndarray (m, d)
        Reference positions :math:`X_i` of the slave points.
    dofs : ndarray of int (m, d)
        Their DOFs in the body's numbering.
    pos : ndarray of int (m, d)
        Their DOFs in the free numbering (-1 on supported DOFs).
    master : Master
        The master the gap is measured against (a system may move it between load
        steps; :class:`LinearizedGap` keeps the gap (6.15) of the master it was built with).
    """

    configuration: str
    pointwise: bool
    points: np.ndarray
    dofs: np.ndarray
    pos: np.ndarray
    master: Any

    def gaps(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        r"""Gaps :math:`g_i(u)` of the points ``idx`` (default all) for the full displacement ``u``."""

    def evaluate(self, u: np.ndarray, idx: np.ndarray | None = None, *, hessian: bool = False) -> GapEvaluation:
        r"""Gaps, normals, constraint rows and (``hessian``) curvature of the points ``idx`` (default all) at ``u``."""

    def current(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        r"""Current positions :math:`X_i + u_i` of the points ``idx`` (default all), shape ``(k, d)``."""

    def against(self, master: Any) -> "ContactKinematics":
        """The same points and configuration measured against another ``master`` (e.g. the position of a
        moving obstacle at the last load step, which the load-step predictor linearizes with)."""


class _PointKinematics:
    """Points, DOFs and free positions of a node-to-surface kinematics."""

    pointwise = True

    def __init__(self, points, dofs, pos, master, nfree: int):
        self.points = np.asarray(points, dtype=float)
        self.dofs = np.asarray(dofs, dtype=np.int64)
        self.pos = np.asarray(pos, dtype=np.int64)
        self.master = master
        self.nfree = int(nfree)

    def against(self, master):
        """The same points and configuration against another ``master`` (:class:`ContactKinematics`)."""
        return type(self)(self.points, self.dofs, self.pos, master, self.nfree)

    def current(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        """Current positions :math:`X_i + u_i` of the points ``idx`` (default all)."""
        if idx is None:
            return self.points + u[self.dofs]
        return self.points[idx] + u[self.dofs[idx]]

    def master_at(self, idx: np.ndarray | None = None):
        """The master of the points ``idx``: with several pairs, the stacked master restricted to those
        points (each against its own pair's master, :meth:`StackedMaster.take`); else the master."""
        if idx is not None and isinstance(self.master, StackedMaster):
            return self.master.take(idx)
        return self.master


class LinearizedGap(_PointKinematics):
    r"""The gap linearized at the reference configuration (6.15): :math:`g_i = g^0_i - \nu_i\cdot u_i`.

    Parameters
    ----------
    points, dofs, pos : ndarray
        Reference positions, DOFs and free positions of the slave points
        (:class:`ContactKinematics`).
    master : Master
        Evaluated once, at the reference positions: :attr:`gap0`, :attr:`normals`.
    nfree : int
        Number of free DOFs (columns of the constraint rows).

    Attributes
    ----------
    gap0 : ndarray (m,)
        Signed gaps :math:`g^0_i` of the reference positions.
    normals : ndarray (m, d)
        Master normals :math:`\nu_i` at their projections.
    rows : scipy.sparse.csr_matrix (m, n_free)
        The constant constraint rows :math:`-\nu_i^T` of all points.

    Examples
    --------
    >>> import numpy as np
    >>> from alcontact.contact import obstacles
    >>> plane = obstacles.make("half-space", point=[0.0, 0.0], normal=[0.0, 1.0])
    >>> kin = LinearizedGap([[0.0, 0.01]], [[0, 1]], [[0, 1]], plane, 2)
    >>> kin.gaps(np.array([0.0, -0.03]))  # moved 0.03 down: penetrates by 0.02
    array([0.02])
    """

    configuration = "reference"

    def __init__(self, points, dofs, pos, master, nfree: int):
        super().__init__(points, dofs, pos, master, nfree)
        self.gap0, self.normals = master.evaluate(self.points)
        self.rows = _rows(self.normals, self.pos, self.nfree)

    def gaps(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        if idx is None:
            return self.gap0 - np.einsum("ij,ij->i", self.normals, u[self.dofs])
        return self.gap0[idx] - np.einsum("ij,ij->i", self.normals[idx], u[self.dofs[idx]])

    def evaluate(self, u: np.ndarray, idx: np.ndarray | None = None, *, hessian: bool = False) -> GapEvaluation:
        if idx is None:
            idx = np.arange(self.points.shape[0])
        idx = np.asarray(idx, dtype=np.int64)
        H = np.zeros((idx.size, self.pos.shape[1], self.pos.shape[1])) if hessian else None
        return GapEvaluation(idx, self.gaps(u, idx), self.normals[idx], H, self.pos[idx], self.nfree,
                             gradient=self.rows[idx])


class CurrentGap(_PointKinematics):
    r"""The gap at the current configuration: :math:`g_i = \operatorname{gap}(X_i + u_i)` (module doc).

    Parameters are those of :class:`LinearizedGap`; :attr:`master` may be replaced between
    load steps (a moving obstacle).

    Examples
    --------
    >>> import numpy as np
    >>> from alcontact.contact import obstacles
    >>> ball = obstacles.make("circle", center=[0.0, 2.0], radius=1.0)
    >>> kin = CurrentGap([[0.0, 0.0]], [[0, 1]], [[0, 1]], ball, 2)
    >>> ev = kin.evaluate(np.array([0.0, 1.5]), np.array([0]), hessian=True)
    >>> ev.g, ev.gradient().toarray()  # 0.5 inside the disc; dg/du = -nu = (0, 1)
    (array([0.5]), array([[0., 1.]]))
    """

    configuration = "current"

    def gaps(self, u: np.ndarray, idx: np.ndarray | None = None) -> np.ndarray:
        return self.master_at(idx).gap(self.current(u, idx))

    def evaluate(self, u: np.ndarray, idx: np.ndarray | None = None, *, hessian: bool = False) -> GapEvaluation:
        xc = self.current(u, idx)
        master = self.master_at(idx)
        g, nu = master.evaluate(xc)
        H = master.gap_hessian(xc) if hessian else None
        if idx is None:
            return GapEvaluation(np.arange(self.points.shape[0]), g, nu, H, self.pos, self.nfree)
        idx = np.asarray(idx, dtype=np.int64)
        return GapEvaluation(idx, g, nu, H, self.pos[idx], self.nfree)
