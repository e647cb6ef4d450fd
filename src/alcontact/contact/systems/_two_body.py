r"""The load-step predictor of a sliding two-body pair at finite deformation.

When the supports of the slave body move it by one translation :math:`\Delta c` along the
contact zone (a punch slid along a block: the driven top's prescribed displacements all change
by :math:`\Delta c`, nothing else changes), steady sliding carries the contact state with the
slave body: the slave body translates rigidly, the master body's displacement field is carried
along with the contact zone, and every slave node keeps its pressure,

.. math::

    u_{s,pred} = u_s + \Delta c, \qquad
    u_{m,pred}(X) = u_m(X - \Delta c), \qquad
    \lambda_{pred} = \lambda ,

the master's finite-element interpolant evaluated at the shifted nodes
(:meth:`~alcontact.fem.LinearElasticity.probe`; a node whose shifted position lies outside the
master body, or whose DOF is supported, keeps its value). It is the two-body counterpart of
:meth:`FiniteContact._slide <alcontact.contact.systems._full_space.FiniteContact>` (the rigid
obstacle carried by its path): without it a sliding step starts from the last state, where the
front of the contact zone penetrates and its back pulls, and the semi-smooth Newton reference
switched its active set back and forth until its budget ran out (two-body ironing, slide steps
of 0.7 slave elements).
"""

from __future__ import annotations

import numpy as np

from ...errors import InvertedElementError

#: the translation counts as sliding when its component along the mean normal of the pressed points is below
#: this fraction of its length (the rule of the rigid obstacle's slide predictor)
_TANGENTIAL = 0.5
#: relative spread of the slave body's support increments below which they are one translation
_UNIFORM_RTOL = 1e-10


def _translation(fc, fixed_values, load, slave: int):
    r"""The translation :math:`\Delta c` by which the step moves the slave body's supports, or ``None``.

    ``None`` unless every change of the step data is that of the slave body's supported DOFs and
    equal for every supported DOF of one component (the components not supported there must not
    change either), and the loads do not change.
    """
    fv_old, load_old, _ = fc._accepted
    if np.any(np.asarray(load) != np.asarray(load_old)):
        return None
    change = np.asarray(fixed_values, dtype=float) - np.asarray(fv_old, dtype=float)
    if not np.any(change):
        return None
    model = fc.model
    lo, hi = model.offsets[slave], model.offsets[slave + 1]
    mine = (fc.fixed >= lo) & (fc.fixed < hi)
    if np.any(change[~mine]):
        return None
    d = fc.dim
    body = model.bodies[slave]
    comp = np.zeros(body.ndofs, dtype=np.int64)
    comp[np.asarray(body.dof_map)] = np.arange(d)[None, :]
    c = comp[fc.fixed[mine] - lo]
    shift = np.zeros(d)
    for k in range(d):
        vals = change[mine][c == k]
        if vals.size == 0:
            continue
        scale = max(float(np.max(np.abs(vals))), 1e-300)
        if float(np.ptp(vals)) > _UNIFORM_RTOL * scale:
            return None
        shift[k] = float(vals.mean())
    return shift


def body_slide(fc, x: np.ndarray, fixed_values: np.ndarray, load: np.ndarray):
    """The slide prediction ``(x, pressures)`` of the module doc for the step data, or ``None``.

    ``fc`` is the :class:`~alcontact.contact.systems.FiniteContact` of a two-body pair (its
    kinematics the mortar gap at the current configuration) at the last accepted step; ``None``
    as well where the step does not translate the slave body along the contact zone, where no
    point is pressed, or where the prediction inverts an element.
    """
    kin = fc.kinematics
    if not hasattr(kin, "force_points") or len(fc.problem.pairs) != 1 or not np.any(fc.last_pressure > 0):
        return None
    pair = fc.problem.pairs[0]
    model = fc.model
    bodies = list(model.bodies)
    slave = next(i for i, b in enumerate(bodies) if b is pair.slave.body)
    master = next(i for i, b in enumerate(bodies) if b is pair.master.body)
    shift = _translation(fc, fixed_values, load, slave)
    if shift is None:
        return None
    pressed = fc.last_pressure > 0
    nbar = fc.normals[pressed].mean(axis=0)
    nn = float(np.linalg.norm(nbar))
    if nn == 0.0 or abs(float(nbar @ shift)) >= _TANGENTIAL * nn * float(np.linalg.norm(shift)):
        return None  # a pressing motion: the tangent predictor's
    u = fc.expand(x)
    u_new = u.copy()
    lo_s, hi_s = model.offsets[slave], model.offsets[slave + 1]
    body = bodies[slave]
    dof_map = np.asarray(body.dof_map)
    for k in range(fc.dim):
        u_new[lo_s + dof_map[:, k]] += shift[k]
    mbody = bodies[master]
    lo_m = model.offsets[master]
    X = np.asarray(mbody.scalar_doflocs, dtype=float)
    P, inside = mbody.probe((X - shift[:, None]).T)
    mmap = np.asarray(mbody.dof_map)
    for k in range(fc.dim):
        comp = u[lo_m + mmap[:, k]]
        comp[inside] = P @ comp
        u_new[lo_m + mmap[:, k]] = comp
    u_new[fc.fixed] = fixed_values  # supported DOFs keep their prescribed values
    trial = u_new[fc.free]
    try:
        fint = model.internal_force(u_new)
    except InvertedElementError:
        return None
    if not (np.all(np.isfinite(fint)) and np.all(np.isfinite(trial))):
        return None
    return trial, fc.last_pressure.copy()
