r"""Fixed sparse structures of the Newton matrices of :class:`~alcontact.contact.systems._full_space.FiniteContact`.

Every Newton matrix of the finite-deformation path is built on the CSR pattern of the
body's tangent (:attr:`Hyperelastic.tangent_pattern
<alcontact.fem.hyperelastic.Hyperelastic.tangent_pattern>`), which does not change
during a run:

- the free-DOF block :math:`K_{ff}` of :math:`K_T(u)`;
- the Newton matrix of subproblem (S), :math:`K_{ff} + B^T \operatorname{diag}(w D) B
  + \sum_i w_i t_i H_i`: the contact terms are :math:`d \times d` blocks on the DOFs of
  each point, :math:`w_i D_i \nu_i \nu_i^T + w_i t_i H_i`, which lie in the pattern of
  :math:`K_{ff}` (the DOFs of one node are coupled by the element matrices);
- the saddle-point matrix of the active-set reference,
  :math:`\begin{pmatrix} K_{ff} + \sum_{i\in A} r_i H_i & B_c^T \\ B_c & D \end{pmatrix}`
  with one constraint row per movable contact point.

:class:`NewtonLayout` computes once where every entry of these matrices comes from
(positions in the tangent's data, in the constraint rows, on the unit diagonal); a
Newton iteration then fills the values by one gather and a scatter of the point blocks
instead of slicing, adding and converting sparse matrices, and hands the linear solver
matrices that share one structure (read-only index arrays), so the solver keeps one
symbolic analysis per pattern (:class:`~alcontact.linalg.SequenceSolver`) and refactorizes
by a gather (:class:`~alcontact.linalg.PardisoSymmetricFactor`). The values are those of
the sparse-algebra construction to the last bit (the same products, added in the same
order); only the entries that cancel to an exact zero stay stored.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def _frozen(a: np.ndarray, dtype) -> np.ndarray:
    out = np.array(a, dtype=dtype)
    out.flags.writeable = False
    return out


def _gather_of(labelled: sp.csr_matrix) -> np.ndarray:
    """Source index of every stored entry of a matrix built from labels ``1, 2, ...`` (canonical order)."""
    labelled.sum_duplicates()  # sorts the column indices (labels move with them; no duplicates occur)
    return np.rint(labelled.data).astype(np.int64) - 1


class NewtonLayout:
    """Structures of the free-DOF tangent, the Newton matrix of (S) and the saddle-point matrix (module doc).

    Parameters
    ----------
    indptr, indices : ndarray
        Canonical CSR pattern of the body's tangent (all DOFs).
    free : ndarray of int
        Free DOFs (sorted).
    pos : ndarray of int, shape (m, d)
        Free index of every DOF of the contact points (-1 on a fixed DOF).
    movable : ndarray of int
        Contact points with a free DOF (the constraint rows of the saddle-point matrix, in order).

    Attributes
    ----------
    indptr, indices : ndarray
        CSR structure of the free block (read-only).
    complete : bool
        Whether every point block lies in the free block's pattern (else the caller keeps the
        sparse-algebra construction).
    """

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, free: np.ndarray, pos: np.ndarray,
                 movable: np.ndarray):
        self.source = (indptr, indices)
        n = indptr.size - 1
        nnz = int(indptr[-1])
        nf = free.size
        self.nf = nf
        labelled = sp.csr_matrix((np.arange(1, nnz + 1, dtype=float), indices, indptr), shape=(n, n))
        block = labelled[free][:, free].tocsr()
        self.sel = _gather_of(block)
        idx_t = np.int32 if self.sel.size < np.iinfo(np.int32).max else np.int64
        self.indptr = _frozen(block.indptr, idx_t)
        self.indices = _frozen(block.indices, idx_t)
        # position of entry (a, b) of every point's d x d block in the free block (-1: a fixed DOF)
        d = pos.shape[1]
        rows = np.repeat(pos, d, axis=1).astype(np.int64)  # (m, d*d), row-major (a, b) as _point_blocks
        cols = np.tile(pos, (1, d)).astype(np.int64)
        valid = (rows >= 0) & (cols >= 0)
        keys = np.repeat(np.arange(nf, dtype=np.int64), np.diff(self.indptr)) * nf + self.indices
        target = np.where(valid, rows * nf + cols, 0)
        at = np.minimum(np.searchsorted(keys, target), max(keys.size - 1, 0))
        found = keys.size > 0 and bool(np.all(keys[at][valid] == target[valid]))
        self.complete = bool(found) or not np.any(valid)
        self.block_pos = np.where(valid, at, -1)
        self.d = d
        self.pos = pos
        self.movable = movable
        self._saddle = None

    def matches(self, indptr: np.ndarray, indices: np.ndarray) -> bool:
        """Whether the tangent pattern ``(indptr, indices)`` is the one of this layout."""
        a, b = self.source
        return ((indptr is a or np.array_equal(indptr, a)) and (indices is b or np.array_equal(indices, b)))

    def built_here(self, M) -> bool:
        """Whether the sparse matrix ``M`` carries the free block's structure of this layout (:meth:`matrix`)."""
        ind = getattr(M, "indices", None)
        return (getattr(M, "indptr", None) is self.indptr and ind is not None
                and (ind is self.indices or ind.base is self.indices))

    # ------------------------------------------------------------------ values
    def free_block(self, kdata: np.ndarray) -> np.ndarray:
        """Values of the free block (a new array) from the tangent's values ``kdata``."""
        return kdata[self.sel]

    def add_blocks(self, data: np.ndarray, idx: np.ndarray, blocks: np.ndarray) -> None:
        """Add the ``d x d`` ``blocks`` of the points ``idx`` on their free DOFs to ``data`` in place."""
        loc = self.block_pos[idx].ravel()
        v = np.asarray(blocks, dtype=float).reshape(-1)
        keep = loc >= 0
        np.add.at(data, loc[keep], v[keep])

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        """The free-block CSR matrix with values ``data`` (shared read-only structure)."""
        M = sp.csr_matrix((data, self.indices, self.indptr), shape=(self.nf, self.nf))
        M.has_canonical_format = True
        return M

    # ------------------------------------------------------------------ saddle point
    def _saddle_layout(self):
        if self._saddle is None:
            nnz = self.sel.size
            pts = self.movable
            nc = pts.size
            d = self.d
            cols = self.pos[pts].ravel()
            rows = np.repeat(np.arange(nc), d)
            keep = cols >= 0
            nb = int(np.count_nonzero(keep))
            K = sp.csr_matrix((np.arange(1, nnz + 1, dtype=float), self.indices, self.indptr), shape=(self.nf, self.nf))
            Bc = sp.csr_matrix((np.arange(nnz + 1, nnz + nb + 1, dtype=float), (rows[keep], cols[keep])),
                               shape=(nc, self.nf))
            D = sp.csr_matrix((np.arange(nnz + nb + 1, nnz + nb + nc + 1, dtype=float), np.arange(nc),
                               np.arange(nc + 1)), shape=(nc, nc))
            S = sp.bmat([[K, Bc.T], [Bc, D]], format="csr")
            gather = _gather_of(S)
            idx_t = np.int32 if gather.size < np.iinfo(np.int32).max else np.int64
            self._saddle = (keep, gather, _frozen(S.indptr, idx_t), _frozen(S.indices, idx_t), S.shape)
        return self._saddle

    def saddle(self, kt_data: np.ndarray, nu: np.ndarray, on: np.ndarray) -> sp.csr_matrix:
        r"""Saddle-point matrix: free block ``kt_data``, constraint rows :math:`-\nu_j` of the movable points
        that are ``on`` (explicit zeros for the others) and the unit diagonal :math:`\Delta r_j = 0` of the others.

        ``nu`` (movable points, d) are the obstacle normals at the points.
        """
        keep, gather, indptr, indices, shape = self._saddle_layout()
        bvals = (-(nu * on[:, None])).ravel()[keep]
        vals = np.concatenate([kt_data, bvals, (~on).astype(float)])
        S = sp.csr_matrix((vals[gather], indices, indptr), shape=shape)
        S.has_canonical_format = True
        return S
