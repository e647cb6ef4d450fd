r"""The gap of slave points against a rigid body whose pose is an unknown (small deformation).

Slave point ``i`` (reference position :math:`X_i`, displacement :math:`u_i`) against a
:class:`~alcontact.contact.masters._rigid_body.RigidBody` of shape gap :math:`\gamma` (at its
reference pose) and pose :math:`q = (c, \theta)` about the reference point :math:`X_0`: the
shape moved by :math:`q` has the gap :math:`\gamma(X_0 + R(\theta)^T (x - X_0 - c))`, which,
linearized at :math:`u = 0, q = 0` like (6.15), is

.. math::

    g_i = g^0_i - \nu_i \cdot u_i + \nu_i \cdot c + \theta \cdot (r_i \times \nu_i), \qquad
    r_i = X_i - X_0,

with :math:`g^0_i = \gamma(X_i)` and :math:`\nu_i = -\nabla\gamma(X_i)` the shape's normal
(:math:`r_i` may be taken at the slave point or at its projection: they differ by a multiple
of :math:`\nu_i`, whose cross product with :math:`\nu_i` vanishes). So :math:`g = g^0 + B u`
with the row of point ``i`` equal to :math:`-\nu_i^T` on its own DOFs (the node-to-surface row
of (6.15)) and :math:`(\nu_i^T, (r_i \times \nu_i)^T)` on the rigid body's DOFs. The contact
force :math:`-B^T r` (:math:`r = w \circ \lambda`) is :math:`r_i \nu_i` on slave point ``i``
and, on the rigid body, the force :math:`-\sum_i r_i \nu_i` and the moment
:math:`-\sum_i r_i\, r_i \times \nu_i` about :math:`X_0`: action = reaction exactly. The
operator has the shape of the mortar gap of two bodies
(:class:`~alcontact.contact.kinematics._mortar.MortarGap`), so the contact systems and every
algorithm treat the pair as a two-body pair: the rigid body's DOFs are :math:`d_r` more
unknowns (a Schur block of the condensed path), with no stiffness.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..masters._rigid_body import RigidBody, cross_rows
from ._mortar import MortarGap, _offset


def rigid_body_gap(model, slave_body, slave_name: str, master: RigidBody, h: float) -> MortarGap:
    """The linearized gap (module doc) of a slave boundary against a rigid body, as a :class:`MortarGap`.

    Parameters
    ----------
    model : alcontact.fem.MultiBody
        The bodies with the rigid body among them (DOF numbering of ``B``).
    slave_body, slave_name
        The slave boundary (its body and the body's own boundary name).
    master : RigidBody
    h : float
        Element size of the slave boundary near the shape (the length scale of the tolerances).

    Returns
    -------
    MortarGap
        ``weights`` the slave tributary lengths/areas, ``normals`` the shape's normals,
        every point ``covered``, ``master_dofs`` the rigid body's translation DOFs
        (``(1, d)``: the contact force on it sums there; its moment is on the rotation DOFs).
    """
    pts, dofs = slave_body.node_dofs(slave_name)
    off_s, off_m = _offset(model, slave_body), _offset(model, master)
    m, d = pts.shape
    gap0, nu = master.evaluate(pts)
    gap0, nu = np.asarray(gap0, dtype=float), np.asarray(nu, dtype=float)
    lever = cross_rows(pts - master.reference, nu).reshape(m, -1)  # (m, 1) in 2D, (m, 3) in 3D
    rigid = np.hstack([nu, lever])  # (m, d_r): d g / d q
    rows = np.concatenate([np.repeat(np.arange(m), d), np.repeat(np.arange(m), master.ndofs)])
    cols = np.concatenate([(dofs + off_s).ravel(), np.tile(np.arange(master.ndofs) + off_m, m)])
    vals = np.concatenate([(-nu).ravel(), rigid.ravel()])
    keep = vals != 0.0
    B = sp.csr_matrix((vals[keep], (rows[keep], cols[keep])), shape=(m, int(model.ndofs)))
    B.sum_duplicates()
    weights = np.asarray(slave_body.boundary_weights(slave_name), dtype=float)
    return MortarGap(gap0=gap0, B=B, weights=weights, normals=nu, covered=np.ones(m, dtype=bool),
                     h=float(h),
                     master_dofs=(master.translation_dofs + off_m)[None, :])

