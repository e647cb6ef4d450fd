r"""Both sides of a pair between two bodies: the contact force on each body, the master-side pressure and gap.

For a mortar pair (:mod:`alcontact.contact.kinematics._mortar`) with the master weights
:math:`P_{jk}` (row ``j`` sums to 1 on a covered slave node), the slave nodal forces
:math:`r_j = w_j \lambda_j` are carried to the master nodes as :math:`\sum_j P_{jk} r_j`; the
master-side pressure is that force per master tributary length :math:`D^m_k = \int N^m_k\,ds`,

.. math::

    p^m_k = \frac{\sum_j P_{jk}\, w_j \lambda_j}{D^m_k}, \qquad
    g^m_k = \frac{\sum_j P_{jk}\, w_j\, g_j}{\sum_j P_{jk}\, w_j},

so that :math:`\sum_k D^m_k p^m_k = \sum_j w_j \lambda_j` (the same total force on both sides) and
the master-side gap is the slave gaps seen from the master node (``NaN`` where no slave node
sees it). :math:`P_{jk}` is read off the gap operator: :math:`B_{j, m(k)} = P_{jk} \nu_j^T`.
"""

from __future__ import annotations

import numpy as np


def master_side(mortar, master, nodal: np.ndarray, gaps: np.ndarray) -> dict:
    """``{"boundary", "points", "pressure", "gap"}`` on the master boundary nodes (module doc).

    Parameters
    ----------
    mortar : MortarGap
        The pair's gap operator (``master_dofs`` in the order of the master boundary's nodes).
    master : BodySurface
        The master (its body's boundary ``master.boundary``).
    nodal : ndarray (m,)
        Slave nodal normal forces :math:`w_j \\lambda_j`.
    gaps : ndarray (m,)
        Slave gaps of the state.
    """
    md = np.asarray(mortar.master_dofs)  # (k, d)
    d = md.shape[1]
    B = mortar.B.tocsc()
    nu = np.asarray(mortar.normals, dtype=float)
    P = sum(B[:, md[:, c]].multiply(nu[:, c][:, None]) for c in range(d)).tocsr()  # (m, k) = P_jk
    w = np.asarray(mortar.weights, dtype=float)
    force = np.asarray(P.T @ np.asarray(nodal, dtype=float)).ravel()
    seen = np.asarray(P.T @ np.where(mortar.covered, w, 0.0)).ravel()
    g = np.where(mortar.covered, np.asarray(gaps, dtype=float), 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        gap = np.where(np.abs(seen) > 1e-14 * max(float(w.max(initial=0.0)), 1e-300),
                       np.asarray(P.T @ (w * g)).ravel() / seen, np.nan)
    pts, _ = master.body.node_dofs(master.boundary)
    Dm = np.asarray(master.body.boundary_weights(master.boundary), dtype=float)
    return {"boundary": master.boundary, "points": pts, "pressure": force / Dm, "gap": gap}


def body_forces(model, dofs: np.ndarray, forces: np.ndarray) -> dict:
    """``{body name: contact force resultant}`` from the contact forces ``forces`` on the DOFs ``dofs`` (each
    body's displacement components; a rigid body's translation DOFs)."""
    n = int(model.ndofs)
    f = np.zeros(n)
    np.add.at(f, np.asarray(dofs, dtype=np.int64).ravel(), np.asarray(forces, dtype=float).ravel())
    out = {}
    for name, body, off in zip(model.names, model.bodies, model.offsets):
        _, bd = body.all_node_dofs()
        out[name] = [float(f[bd[:, c] + off].sum()) for c in range(bd.shape[1])]
    return out


def two_body_sides(problem, mortar, nodal: np.ndarray, gaps: np.ndarray) -> dict:
    """What ``solution.extra`` holds of both sides of a pair between two bodies: ``body_contact_forces``
    (:func:`body_forces`), ``contact_pairs`` (one entry per pair: its slave and master, the contact force on each
    side and ``contact_force_balance`` = |F_s + F_m| / |F_s|) and, for a body's surface as the master,
    ``master_side`` (:func:`master_side`)."""
    from ..masters._mortar import BodySurface

    model = problem.model
    cols = np.unique(mortar.B.indices).astype(np.int64)
    fc = mortar.contact_force(nodal)
    forces = body_forces(model, cols, fc[cols])
    pair = problem.pairs[0]
    slave = problem.contact_boundary
    master = pair.master
    m_name = model.names[next(i for i, b in enumerate(model.bodies) if b is master.body)]
    master_label = f"{m_name}/{master.boundary}" if isinstance(master, BodySurface) else m_name
    s_name = slave.split("/", 1)[0]
    fs, fm = np.asarray(forces[s_name]), np.asarray(forces[m_name])
    norm = float(np.linalg.norm(fs))
    out = {"body_contact_forces": forces,
           "contact_pairs": [{"slave": slave, "master": master_label, "slave_force": fs.tolist(),
                              "master_force": fm.tolist(),
                              "contact_force_balance": float(np.linalg.norm(fs + fm)) / norm if norm > 0 else 0.0}]}
    if isinstance(master, BodySurface):
        out["master_side"] = master_side(mortar, master, nodal, gaps)
    return out
