r"""Chunked, vectorized assembly of the small-strain stiffness on affine simplices (P1/P2).

The bilinear form of :mod:`alcontact.fem.elasticity`,

.. math::
    a(u, v) = \int_\Omega 2\mu\,\varepsilon(u):\varepsilon(v) + \lambda\,
    \operatorname{tr}\varepsilon(u)\,\operatorname{tr}\varepsilon(v)\,dx ,

gives, for the vector shape functions :math:`\phi_b e_l` (column) and :math:`\phi_a e_i` (row),
the ``d x d`` block of the scalar pair :math:`(a, b)`

.. math::
    K_{ai,bl} = \int_T \mu\,\delta_{il}\,\nabla\phi_a\cdot\nabla\phi_b
    + \mu\,\partial_l\phi_a\,\partial_i\phi_b + \lambda\,\partial_i\phi_a\,\partial_l\phi_b\,dx .

On affine simplices the gradients are the reference gradients times the inverse
Jacobian of the element map, and a quadrature of degree ``2 (order - 1)`` is exact.

Memory: scikit-fem's :func:`skfem.asm` evaluates every basis function of every
element at once (a :class:`skfem.Basis` holds ``nloc * (d + d^2)`` values per
element and quadrature point) and returns ``(d nloc)^2`` COO triplets per element
(values plus two int64 indices) before the conversion to CSR: about 15 kB per DOF
at peak for 3D P1 (measured at 232k DOFs). Here the matrix is assembled in its
final block form: the scalar sparsity pattern (one ``d x d`` block per pair of
scalar DOFs sharing an element) is computed once, the element blocks of a chunk of
elements are added into it with one :func:`numpy.bincount` on the range of pattern
positions that chunk touches, and the block matrix becomes the interleaved CSR
matrix (vector DOF ``d k + c``) at the end. Peak memory is the final matrix plus
one chunk (about 2 times the matrix).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import skfem
from skfem.quadrature import get_quadrature

from alcontact.fem.quality import is_curved

__all__ = ["elasticity_stiffness", "scalar_pattern", "scalar_doflocs", "default_intorder", "straight_mesh"]

#: element-matrix entries per chunk (float64: 16 MB of element blocks; with the temporaries of a
#: chunk about 100 MB, whatever the mesh size)
CHUNK_ENTRIES = 1 << 21


def scalar_pattern(sdofs: np.ndarray, ns: int) -> tuple[np.ndarray, np.ndarray]:
    """Sorted CSR structure of the scalar DOF graph (two DOFs adjacent if they share an element).

    Parameters
    ----------
    sdofs : ndarray of int, shape (nloc, nel)
        Scalar DOFs of each element (scikit-fem's ``element_dofs``).
    ns : int
        Number of scalar DOFs.

    Returns
    -------
    indptr : ndarray of int64, shape (ns + 1,)
    indices : ndarray of int32 (int64 above 2**31 entries)
    """
    nloc, nel = sdofs.shape
    # incidence (elements x scalar DOFs) in CSR form without sorting; A^T A has the pattern
    A = sp.csr_matrix((np.ones(nloc * nel, dtype=np.float32), np.ascontiguousarray(sdofs.T).ravel(),
                       np.arange(0, nloc * nel + 1, nloc, dtype=np.int64)), shape=(nel, ns))
    G = (A.T.tocsr() @ A).tocsr()
    del A
    G.sort_indices()
    return G.indptr.astype(np.int64), G.indices


def default_intorder(mesh, order: int) -> int:
    """Quadrature degree of the stiffness and of the hyperelastic forces.

    ``2 (order - 1)`` (at least 1) is exact for the linear stiffness on affine simplices.
    On a curved (isoparametric) mesh the integrand is rational in the reference
    coordinates and no degree is exact: there it is 4 on triangles (6 points) and 5 on
    tetrahedra (14 points), the lowest degrees above 2 whose rules have positive weights
    (scikit-fem's degree-3 rules and its degree-4 tetrahedron rule have a negative weight,
    which a hyperelastic energy must not see). Measured on the neo-Hookean half-cylinder
    (P2, delta/R = 0.4, n = 16) the force moves by 1.5e-3 from degree 2 to 6 (discretization
    error 7e-2), and on the hemisphere (n = 6, delta/R = 0.1) by 4e-4 from degree 2 to 5 (2e-2).
    """
    if is_curved(mesh):
        return 4 if mesh.dim() == 2 else 5
    return max(1, 2 * (int(order) - 1))


def straight_mesh(mesh):
    """The first-order mesh on the vertices of a curved ``mesh`` (same elements, facets and named sets)."""
    cls = skfem.MeshTri1 if mesh.dim() == 2 else skfem.MeshTet1
    return cls(np.asarray(mesh.doflocs[:, : mesh.nvertices], dtype=float), np.asarray(mesh.t),
               _boundaries=mesh._boundaries, _subdomains=mesh._subdomains)


def scalar_doflocs(mesh, order: int) -> np.ndarray:
    """Locations ``(dim, n_scalar)`` of the scalar P1/P2 DOFs: vertices, then edge (2D: facet) nodes.

    The numbering of :class:`skfem.assembly.Dofs` for the Lagrange elements of
    :mod:`alcontact.fem.elasticity` (checked against ``Basis.doflocs`` in the tests);
    computed from the mesh alone, without a quadrature. On a straight mesh the edge
    nodes are the midpoints; on a curved one (:func:`is_curved`) they are the mesh's
    own second-order nodes (on the true boundary curve/surface).
    """
    if is_curved(mesh):
        if order == 2:
            return np.asarray(mesh.doflocs, dtype=float)
        return np.asarray(mesh.doflocs[:, : mesh.nvertices], dtype=float)
    if order == 1:
        return np.asarray(mesh.p, dtype=float)
    # ElementTriP2 numbers its midpoint DOFs on the facets (= edges), ElementTetP2 on the edges
    edges = mesh.facets if mesh.dim() == 2 else mesh.edges
    return np.hstack([mesh.p, 0.5 * (mesh.p[:, edges[0]] + mesh.p[:, edges[1]])])


def _reference_gradients(element, intorder: int):
    """Quadrature points' reference gradients ``(nqp, nloc, dim)`` and weights ``(nqp,)``."""
    X, W = get_quadrature(element.refdom, intorder)
    nloc = element.doflocs.shape[0]
    G = np.stack([np.asarray(element.lbasis(X, j)[1]) for j in range(nloc)])  # (nloc, dim, nqp)
    return np.ascontiguousarray(G.transpose(2, 0, 1)), np.asarray(W, dtype=float)


def _affine_inverse(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Determinants and inverses of the element maps ``A (ne, d, d)`` by the adjugate formula.

    Entries that vanish by the structure of ``A`` (axis-aligned edges of tensor meshes)
    come out exactly zero, as with scikit-fem's affine mapping, so the matrix keeps the
    sparsity of :func:`skfem.asm` (an LU-based inverse leaves round-off there instead).
    """
    if A.shape[1] == 2:
        det = A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]
        adj = np.stack([np.stack([A[:, 1, 1], -A[:, 0, 1]], -1), np.stack([-A[:, 1, 0], A[:, 0, 0]], -1)], 1)
    else:
        c0, c1, c2 = A[:, :, 0], A[:, :, 1], A[:, :, 2]
        adj = np.stack([np.cross(c1, c2), np.cross(c2, c0), np.cross(c0, c1)], axis=1)  # rows of det * inv
        det = np.einsum("ei,ei->e", c0, adj[:, 0])
    return det, adj / det[:, None, None]


def _element_blocks(p: np.ndarray, t: np.ndarray, Gref: np.ndarray, W: np.ndarray, lam: float,
                    mu: float) -> np.ndarray:
    """Element blocks ``(ne, nloc, nloc, d, d)`` of the elements ``t`` (vertex indices ``(d+1, ne)``)."""
    d = p.shape[0]
    x0 = p[:, t[0]]
    Jm = np.stack([p[:, t[k + 1]] - x0 for k in range(d)], axis=-1)  # (d, ne, d): column k = x_k - x_0
    det, inv = _affine_inverse(np.ascontiguousarray(Jm.transpose(1, 0, 2)))  # grad phi = inv^T grad_ref phi
    g = np.einsum("eji,qaj->eqai", inv, Gref, optimize=True)  # (ne, nqp, nloc, d)
    dx = np.abs(det)[:, None] * W[None, :]  # (ne, nqp)
    gw = g * dx[:, :, None, None]
    S = np.einsum("eqai,eqbl->eabil", gw, g, optimize=True)  # int g_a[i] g_b[l]
    tr = np.einsum("eabii->eab", S)
    Ke = lam * S
    Ke += mu * S.transpose(0, 1, 2, 4, 3)
    for i in range(d):
        Ke[:, :, :, i, i] += mu * tr
    return Ke


#: entries below this times :math:`\sqrt{|K_{ii} K_{jj}|}` are round-off of couplings that vanish exactly
ROUNDOFF = 1e-14


def _drop_roundoff(blocks: np.ndarray, indptr: np.ndarray, indices: np.ndarray, ns: int) -> None:
    r"""Zero (in place) the block entries below :data:`ROUNDOFF` :math:`\sqrt{|K_{ii} K_{jj}|}`.

    Couplings that vanish exactly (e.g. between P2 DOFs of axis-aligned elements) come
    out of the quadrature sums as round-off, 1e-17 of the diagonal here, where scikit-fem's
    sums happened to give exact zeros for some and round-off for others: they carry no
    information, cost memory and matvec time, and (measured on the 2D P2 Hertz problem)
    perturbations of this size move the equilibrium residual of the pure penalty at
    :math:`\varepsilon_N \approx 10^{13}` between 6e-9 and 2e-8. The caller removes the zeros.
    """
    rows = np.repeat(np.arange(ns, dtype=np.int64), np.diff(indptr))
    diag_pos = np.flatnonzero(rows == indices)  # one per scalar row (the node block), in row order
    dg = np.sqrt(np.abs(np.einsum("kii->ki", blocks[diag_pos])))  # (ns, d)
    step = 1 << 18
    for s in range(0, blocks.shape[0], step):  # in chunks: the thresholds are as large as the blocks
        e = min(s + step, blocks.shape[0])
        thr = ROUNDOFF * dg[rows[s:e]][:, :, None] * dg[indices[s:e]][:, None, :]
        blk = blocks[s:e]
        blk[np.abs(blk) < thr] = 0.0


def elasticity_stiffness(mesh, element, sdofs: np.ndarray, ns: int, lam: float, mu: float, *,
                         intorder: int, chunk_entries: int = CHUNK_ENTRIES) -> sp.csr_matrix:
    r"""Stiffness of linear elasticity in the interleaved numbering ``dof = d k + c`` (symmetric CSR).

    Parameters
    ----------
    mesh : skfem.MeshTri1 or skfem.MeshTet1
        Affine simplex mesh.
    element : skfem.Element
        The scalar Lagrange element (P1 or P2); its local DOFs follow ``sdofs``.
    sdofs : ndarray of int, shape (nloc, nel)
        Scalar DOFs of each element.
    ns : int
        Number of scalar DOFs.
    lam, mu : float
        Lamé constants.
    intorder : int
        Quadrature degree (``2 (order - 1)``, at least 1, is exact on affine simplices).
    chunk_entries : int
        Element-matrix entries per chunk (bounds the temporary memory).

    Returns
    -------
    scipy.sparse.csr_matrix
        ``(d ns, d ns)``, sorted indices, exactly symmetric; entry ``(d k + i, d m + l)``
        is :math:`K_{ki,ml}` of the module doc summed over the elements.
    """
    p = np.asarray(mesh.p, dtype=float)
    t = np.asarray(mesh.t)
    d = p.shape[0]
    nloc, nel = sdofs.shape
    indptr, indices = scalar_pattern(sdofs, ns)
    nnz_s = int(indptr[-1])
    rows = np.repeat(np.arange(ns, dtype=np.int64), np.diff(indptr))
    keys = rows * ns + indices  # sorted: rows ascending, sorted columns within a row
    del rows
    Gref, W = _reference_gradients(element, intorder)
    dd = d * d
    blocks = np.zeros(nnz_s * dd)
    per = nloc * nloc * dd
    chunk = max(1, int(chunk_entries) // per)
    comp = np.arange(dd, dtype=np.int64)
    for s in range(0, nel, chunk):
        e = slice(s, min(s + chunk, nel))
        Ke = _element_blocks(p, t[:, e], Gref, W, lam, mu)  # (ne, a, b, i, l)
        sd = sdofs[:, e].astype(np.int64)
        ck = (sd[:, None, :] * ns + sd[None, :, :]).transpose(2, 0, 1)  # (ne, a, b)
        pos = np.searchsorted(keys, ck.ravel())
        del ck
        # the chunk's sums on the pattern positions it touches (a chunk's elements can span a
        # wide range of rows: a bincount over the whole range was as large as the matrix)
        u, inv = np.unique(pos, return_inverse=True)
        idx = (inv.reshape(-1)[:, None] * dd + comp[None, :]).ravel()
        blocks.reshape(-1, dd)[u] += np.bincount(idx, weights=Ke.ravel(), minlength=u.size * dd).reshape(-1, dd)
        del Ke, idx, pos, u, inv
    blocks = blocks.reshape(nnz_s, d, d)
    # exact symmetry: average each block with the transpose of its mirror block
    tpos = np.searchsorted(keys, indices.astype(np.int64) * ns + np.repeat(np.arange(ns, dtype=np.int64),
                                                                           np.diff(indptr)))
    del keys
    _symmetrize(blocks, tpos)
    del tpos
    _drop_roundoff(blocks, indptr, indices, ns)
    return _blocks_to_csr(blocks, indptr, indices, ns, d)


def _symmetrize(blocks: np.ndarray, tpos: np.ndarray, step: int = 1 << 18) -> None:
    """``blocks[i] = (blocks[i] + blocks[tpos[i]]^T) / 2`` for every block, in place, by chunks.

    Each pair is averaged once, from its upper block (``tpos[i] >= i``), and written to
    both: the same values as the whole-array expression (addition commutes), without its
    two copies of the blocks.
    """
    for s in range(0, blocks.shape[0], step):
        i = np.arange(s, min(s + step, blocks.shape[0]), dtype=np.int64)
        i = i[tpos[i] >= i]
        avg = 0.5 * (blocks[i] + blocks[tpos[i]].transpose(0, 2, 1))
        blocks[i] = avg
        blocks[tpos[i]] = avg.transpose(0, 2, 1)


def _blocks_to_csr(blocks: np.ndarray, indptr: np.ndarray, indices: np.ndarray, ns: int, d: int,
                   step: int = 1 << 14) -> sp.csr_matrix:
    """The block matrix as the interleaved CSR matrix (vector DOF ``d k + c``), reusing the block values' memory.

    The CSR rows ``d a .. d b`` hold exactly the entries of the block rows ``a .. b``, so
    the values are permuted within that range of the same array, by chunks of block rows;
    only the column indices are a new array (no BSR-to-CSR copy of the values). Chunks
    of about ``step`` blocks.
    """
    nnz_s = int(indptr[-1])
    dd = d * d
    idx_t = np.int32 if dd * nnz_s < np.iinfo(np.int32).max else np.int64
    flat = blocks.reshape(-1)
    cols = np.empty(nnz_s * dd, dtype=idx_t)
    lens = np.diff(indptr)
    cuts = np.unique(np.concatenate([np.searchsorted(indptr, np.arange(0, nnz_s, step), side="right") - 1, [ns]]))
    for a, b in zip(cuts[:-1], cuts[1:]):
        a, b = int(a), int(b)
        s, e = int(indptr[a]), int(indptr[b])
        if e == s:
            continue
        rl = lens[a:b]
        # entries of block row r: (block j of the row, i, l) -> CSR row d r + i, position d j + l
        blk = blocks[s:e]  # (nb, i, l)
        j = np.arange(e - s) - np.repeat(indptr[a:b] - s, rl)
        # CSR position within the chunk: d * (start of block row r) + i * (d * len_r) + d * j + l
        base = d * (np.repeat(indptr[a:b] - s, rl)) * d
        row_len = d * np.repeat(rl, rl)
        ii = np.arange(d)
        pos = (base[:, None, None] + ii[None, :, None] * row_len[:, None, None]
               + (d * j)[:, None, None] + ii[None, None, :])  # (nb, i, l)
        c = (d * indices[s:e].astype(np.int64))[:, None, None] + ii[None, None, :]
        flat[dd * s + pos.reshape(-1)] = blk.reshape(-1).copy()  # a copy: source and target overlap
        cols[dd * s + pos.reshape(-1)] = np.broadcast_to(c, pos.shape).reshape(-1)
    csr_ptr = np.zeros(d * ns + 1, dtype=np.int64)
    csr_ptr[1:] = np.repeat(d * lens, d)
    np.cumsum(csr_ptr, out=csr_ptr)
    K = sp.csr_matrix((flat, cols, csr_ptr.astype(idx_t)), shape=(d * ns, d * ns))
    K.has_sorted_indices = True
    return K
