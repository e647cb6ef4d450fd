r"""The linear gaps of several contact pairs of which one or more joins two bodies, as one weighted gap.

A problem may stack a two-body (mortar) pair beside other pairs: three blocks stacked (two mortar
pairs), a block on a deformable base pressed by a rigid punch (a mortar pair and a rigid one). Its
contact points are stacked in the pairs' order (:meth:`~alcontact.contact.ContactProblem.slave_nodes`);
at small deformation each pair's block of rows is linear, :math:`g = g^0 + B u`:

- a pair with a deformable master: its mortar weighted gap (:func:`~alcontact.contact.kinematics._mortar.mortar_gap`,
  rows on the slave node and the master segment nodes, weights :math:`D_j`);
- a pair with a rigid master: the linearized gap (6.15), :math:`g^0_i = g(X_i)`, rows :math:`-\nu_i^T` on the
  DOFs of point :math:`i`, the tributary weights of its boundary (the rows a mortar gap has against a flat
  rigid master).

:func:`stacked_gap` stacks the blocks into one
:class:`~alcontact.contact.kinematics._mortar.MortarGap`, so every system takes the constant rows ``B``
of a non-pointwise kinematics as it does for one two-body pair (and the tangential rows of friction come
from the same ``B``, :mod:`alcontact.contact.kinematics._mortar_tangent`). :func:`pair_balance` gives the
contact force each pair puts on its slave side and on its master side.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
import scipy.sparse as sp

from ._mortar import MortarGap, mortar_gap


def stacked_gap(problem, element_size: Callable, gap_of: Callable | None = None,
                check: Callable | None = None) -> MortarGap:
    """The gaps of all pairs of ``problem`` (module doc) as one :class:`MortarGap`, rows in the stacked order.

    Parameters
    ----------
    problem : ContactProblem
        Several pairs, at least one with a :class:`~alcontact.contact.BodySurface` master.
    element_size : callable ``pair -> float``
        Contact-zone element size of the slave boundary of a pair with a rigid master.
    gap_of : callable ``pair -> MortarGap``, optional
        The gap operator of a pair whose master moves with the unknowns (default: its mortar weighted gap).
    check : callable ``(name, pair, gap) -> None``, optional
        Called with each two-body pair's own :class:`MortarGap` (warnings: no coverage, an overlap).
    """
    model = problem.model
    ndofs = int(model.ndofs)
    gap0, weights, normals, covered, hs, masters, blocks = [], [], [], [], [], [], []
    for pair in problem.pairs:
        name = problem.slave_name(pair)
        pts, dofs = model.node_dofs(name)
        m, d = dofs.shape
        if pair.rigid:
            g, nu = pair.master.evaluate(pts)
            rows = sp.csr_matrix((-np.asarray(nu, dtype=float).ravel(), (np.repeat(np.arange(m), d), dofs.ravel())),
                                 shape=(m, ndofs))
            rows.eliminate_zeros()
            gap0.append(np.asarray(g, dtype=float))
            normals.append(np.asarray(nu, dtype=float))
            weights.append(model.boundary_weights(name))
            covered.append(np.ones(m, dtype=bool))
            hs.append(element_size(pair))
        else:
            mg = gap_of(pair) if gap_of is not None else mortar_gap(model, pair.slave.body, pair.slave.name,
                                                                    pair.master)
            if check is not None:
                check(name, pair, mg)
            rows = mg.B
            gap0.append(mg.gap0)
            normals.append(mg.normals)
            weights.append(mg.weights)
            covered.append(mg.covered)
            hs.append(mg.h)
            masters.append(mg.master_dofs)
        blocks.append(rows)
    B = sp.vstack(blocks).tocsr()
    master_dofs = np.unique(np.vstack(masters), axis=0) if masters else np.empty((0, model.dim), dtype=np.int64)
    return MortarGap(gap0=np.concatenate(gap0), B=B, weights=np.concatenate(weights), normals=np.vstack(normals),
                     covered=np.concatenate(covered), h=float(min(hs)), master_dofs=master_dofs)


def pair_balance(problem, rows: sp.spmatrix, forces: np.ndarray, dofs: np.ndarray) -> dict:
    r"""The contact force of every pair on its slave side and on its master side, and their balance.

    Parameters
    ----------
    problem : ContactProblem
    rows : sparse matrix (m k, ndofs)
        The operator whose transpose carries the local nodal forces to the bodies, ``k`` rows per stacked
        point (point-major): ``B`` (``k = 1``) or the local rows of friction :math:`L` (``k = d``).
    forces : ndarray (m, k)
        The local nodal forces :math:`R` (the force on the bodies is :math:`-\mathrm{rows}^T R`).
    dofs : ndarray of int (m, d)
        The DOFs of the stacked points.

    Returns
    -------
    dict
        ``slave_contact_force`` / ``master_contact_force``: the resultants on the slave and the master sides,
        summed over the pairs with a deformable master; ``contact_force_balance``: the largest
        :math:`|F_s + F_m| / |F_s|` of those pairs (action = reaction; a rigid master's reaction is not in the
        model); ``pair_balance``: per pair ``{"slave_force", "master_force", "balance"}`` (``None`` for a
        rigid master).
    """
    model = problem.model
    m, d = dofs.shape
    R = np.asarray(forces, dtype=float).reshape(m, -1)
    k = R.shape[1]
    _, all_dofs = model.all_node_dofs()
    comp = np.empty(model.ndofs, dtype=np.int64)
    for a in range(d):
        comp[all_dofs[:, a]] = a
    W = (sp.diags(-R.ravel()) @ sp.csr_matrix(rows)).tocoo()  # row r: the force of local force r on every DOF
    point = W.row // k
    own = (dofs[point] == W.col[:, None]).any(axis=1)  # the entry is on its own slave point
    owner = problem.pair_of_points()[point]
    npairs = len(problem.pairs)
    total = np.zeros((npairs, d))
    slave = np.zeros((npairs, d))
    np.add.at(total, (owner, comp[W.col]), W.data)
    np.add.at(slave, (owner[own], comp[W.col[own]]), W.data[own])
    out_pairs, fs, fm, worst = [], np.zeros(d), np.zeros(d), 0.0
    for i, pair in enumerate(problem.pairs):
        if pair.rigid:
            out_pairs.append(None)
            continue
        master = total[i] - slave[i]
        norm = float(np.linalg.norm(slave[i]))
        bal = float(np.linalg.norm(total[i])) / norm if norm > 0 else 0.0
        out_pairs.append({"slave_force": slave[i].tolist(), "master_force": master.tolist(), "balance": bal})
        fs, fm, worst = fs + slave[i], fm + master, max(worst, bal)
    return {"slave_contact_force": fs.tolist(), "master_contact_force": fm.tolist(), "contact_force_balance": worst,
            "pair_balance": out_pairs}
