r"""The state of every rigid body of a solved problem: its pose, the contact force and moment on it, its reaction.

For a :class:`~alcontact.contact.RigidBody` with DOFs :math:`q = (c, \theta)` (translation of
its reference point :math:`X_0`, rotation about it) the solved state gives

- the pose :math:`q` (prescribed components: their values; the others: solved for);
- the contact force :math:`F^c` and moment :math:`M^c` (about :math:`X_0`) on it, the
  rigid-body block of :math:`-B^T r` (:mod:`alcontact.contact.kinematics._rigid_body`);
- the applied force and moment :math:`(F, M)` (:class:`~alcontact.contact.RigidLoad`);
- the reaction :math:`(R_F, R_M) = -(F^c + F, M^c + M)`: what the drive applies on the
  prescribed components (zero, to the equilibrium tolerance of the solve, on the free ones:
  there the body is in equilibrium).

The dictionary is what ``solution.extra["rigid_bodies"]`` holds, per body name of the
problem's :class:`~alcontact.fem.MultiBody`, JSON-ready.
"""

from __future__ import annotations

import numpy as np

from ..masters._rigid_body import RigidBody


def rigid_body_results(model, u: np.ndarray, contact_force: np.ndarray, load: np.ndarray,
                       fixed: np.ndarray) -> dict:
    """``{"rigid_bodies": {name: state}}`` for every rigid body of ``model`` (module doc); ``{}`` without one.

    Parameters
    ----------
    model : alcontact.fem.MultiBody
    u : ndarray (ndofs,)
        The solved displacement (the rigid bodies' poses included).
    contact_force : ndarray (ndofs,)
        The contact force on every DOF, :math:`-B^T r`.
    load : ndarray (ndofs,)
        The applied loads at the state's load level.
    fixed : array_like of int
        The prescribed DOFs.
    """
    bodies = getattr(model, "bodies", ())
    out = {}
    fixed = set(np.asarray(fixed, dtype=np.int64).ravel().tolist())
    for name, body, off in zip(getattr(model, "names", ()), bodies, getattr(model, "offsets", ())):
        if not isinstance(body, RigidBody):
            continue
        sl = slice(int(off), int(off) + body.ndofs)
        q, fc, f = np.asarray(u[sl], float), np.asarray(contact_force[sl], float), np.asarray(load[sl], float)
        held = np.array([int(off) + k in fixed for k in range(body.ndofs)])
        reaction = np.where(held, -(fc + f), 0.0) + 0.0  # (no negative zeros in the files)
        d = body.dim
        out[name] = {
            "reference": body.reference.tolist(),
            "displacement": q[:d].tolist(),
            "rotation": q[d:].tolist(),
            "prescribed": [n for n, h in zip(body.dof_names, held) if h],
            "contact_force": (fc[:d] + 0.0).tolist(), "contact_moment": (fc[d:] + 0.0).tolist(),
            "applied_force": f[:d].tolist(), "applied_moment": f[d:].tolist(),
            "reaction_force": reaction[:d].tolist(), "reaction_moment": reaction[d:].tolist(),
        }
    return {"rigid_bodies": out} if out else {}

