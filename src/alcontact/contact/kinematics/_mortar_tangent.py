r"""The tangential mortar operator of a two-body pair (small deformation): the slip between the two surfaces.

The weighted gap of slave node ``j`` (:mod:`alcontact.contact.kinematics._mortar`) is
linear in the displacements, :math:`g_j = g^0_j + B_j u` with

.. math::

    B_j u = n_j \cdot \Big(u_j - \sum_k P_{jk}\, u_k\Big), \qquad
    P_{jk} = \frac{M_{jk}}{\sum_l M_{jl}}, \quad M_{jk} = \int_{\Gamma_s} \Phi_j\, N^m_k\circ\chi\, ds ,

the relative displacement of the slave node and its *mortar master point* (the master nodes
weighted by the dual shape function :math:`\Phi_j` of the node, the weights the normal
constraint uses) projected on the normal :math:`n_j = -\nu_j`. Friction measures the slip
between the two surfaces with the same relative displacement, projected on the tangent basis
:math:`T_j` (``d x (d-1)``, orthogonal to :math:`\nu_j`) of the slave node:

.. math::

    u_{T,j} = T_j^T \Big(u_j - \sum_k P_{jk}\, u_k\Big), \qquad
    \Delta u_{T,j} = u_{T,j}(u_{n+1}) - u_{T,j}(u_n),

the relative tangential displacement of the slave point and its projected master point over
a load step (the weighted relative slip of dual mortar friction, Gitterle, Popp, Gee & Wall,
*Int. J. Numer. Meth. Engng* 84 (2010) 543-571, at small deformation, normalized by :math:`D_j`
as the weighted gap is). A rigid translation of both bodies moves no :math:`u_{T,j}`, since the weights
:math:`P_{jk}` of every covered slave node sum to one. The local kinematics of node ``j`` is
then :math:`y_j = (g_j, u_{T,j}) = y^0_j + L_j u` with the rows

.. math::

    L_j = \begin{bmatrix} B_j \\ T_j^T \big(E_j - \sum_k P_{jk} E_k\big) \end{bmatrix}
        = [\,c_{jn}\, n_j^T;\ c_{jn}\, T_j^T\,]_{n} ,

:math:`E_n` the selection of the DOFs of node ``n`` and :math:`c_{jn} = B_{j,n}\cdot n_j` the
coefficient of node ``n`` in row ``j`` (1 on the slave node, :math:`-P_{jk}` on master node
``k``; their sum is zero). The local nodal forces :math:`R_j = w_j (t_{N,j}, t_{T,j})` act on
both bodies as :math:`-L^T R`, so the tangential forces balance exactly too (action = reaction).
:func:`mortar_local_rows` reads :math:`c_{jn}` from ``B`` itself, so it serves any
discretization of the weights (mortar, node-to-segment) whose rows have that structure.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

#: relative size of a part of a row of ``B`` that is not along the node's normal: beyond it the rows are not
#: those of a small-deformation weighted gap (a node block ``c n_j^T``) and have no tangential counterpart
STRUCTURE_TOL = 1e-10


def mortar_local_rows(B: sp.spmatrix, normals: np.ndarray, tangents: np.ndarray, node_dofs: np.ndarray) -> sp.csr_matrix:
    r"""The rows :math:`L` (module doc) of the local kinematics :math:`y = (g, u_T)` of a mortar pair.

    Parameters
    ----------
    B : sparse matrix (m, ndofs)
        Gap operator of the pair (:attr:`MortarGap.B <alcontact.contact.kinematics._mortar.MortarGap>`):
        row ``j`` is :math:`c_{jn} n_j^T` on the DOFs of every node ``n`` it touches.
    normals : ndarray (m, d)
        :math:`\nu_j = -n_j`, the master normal at each slave node (:attr:`MortarGap.normals`).
    tangents : ndarray (m, d, d-1)
        Orthonormal tangent bases :math:`T_j` (orthogonal to :math:`\nu_j`).
    node_dofs : ndarray of int (k, d)
        The DOFs of every node a row may touch (slave and master nodes, model numbering).

    Returns
    -------
    scipy.sparse.csr_matrix (m d, ndofs)
        Row ``j d`` is :math:`B_j`, rows ``j d + 1 ... j d + d - 1`` the tangential rows
        :math:`c_{jn} T_j^T` (point-major, the order of the local variables of the Coulomb law).

    Raises
    ------
    ValueError
        A row of ``B`` on a DOF of no node of ``node_dofs``, or a node block not along the row's
        normal (not the rows of a small-deformation weighted gap).
    """
    B = sp.coo_matrix(B)
    m, ndofs = B.shape
    nu = np.asarray(normals, dtype=float)
    T = np.asarray(tangents, dtype=float)
    d = nu.shape[1]
    nodes = np.unique(np.asarray(node_dofs, dtype=np.int64).reshape(-1, d), axis=0)
    node_of = -np.ones(ndofs, dtype=np.int64)
    comp_of = np.zeros(ndofs, dtype=np.int64)
    for k in range(d):
        node_of[nodes[:, k]] = np.arange(nodes.shape[0])
        comp_of[nodes[:, k]] = k
    where = node_of[B.col]
    if np.any(where < 0):
        raise ValueError("mortar_local_rows: a row of the gap operator touches a DOF of no slave or master node")
    n = -nu  # B_j = c_jn n_j^T on node n
    coef = sp.coo_matrix((B.data * n[B.row, comp_of[B.col]], (B.row, where)), shape=(m, nodes.shape[0])).tocsr()
    coef.sum_duplicates()
    cc = coef.tocoo()
    # the node blocks must be c n_j^T: B minus its normal part is zero (to round-off)
    normal_part = sp.coo_matrix(((cc.data[:, None] * n[cc.row]).ravel(),
                                 (np.repeat(cc.row, d), nodes[cc.col].ravel())), shape=(m, ndofs))
    defect = abs(B.tocsr() - normal_part.tocsr()).max() if B.nnz else 0.0
    if defect > STRUCTURE_TOL * max(abs(B).max() if B.nnz else 0.0, 1e-300):
        raise ValueError(f"mortar_local_rows: the gap operator is not a weighted small-deformation gap (a node block "
                         f"off the normal by {defect:.2e})")
    rows = [B.row * d]
    cols = [B.col]
    vals = [B.data]
    for k in range(d - 1):  # tangential row k of node j: c_jn T_j[:, k]^T on the DOFs of node n
        rows.append(np.repeat(cc.row * d + 1 + k, d))
        cols.append(nodes[cc.col].ravel())
        vals.append((cc.data[:, None] * T[cc.row, :, k]).ravel())
    L = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(m * d, ndofs))
    L.sum_duplicates()
    return L
