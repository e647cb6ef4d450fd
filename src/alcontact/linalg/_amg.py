r"""Smoothed-aggregation AMG hierarchy with a memory-lean first level.

:func:`pyamg.smoothed_aggregation_solver` builds each level with whole-matrix
temporaries: the strength matrix (a copy of the pattern and values of ``A``), the
scaled copy :math:`D^{-1} A` of the prolongator smoother, the product :math:`A T`,
the smoothed prolongator ``P`` and a separately stored restriction :math:`R = P^T`,
and the Galerkin product :math:`R (A P)` with the whole of ``A P`` alive. On the
first level, the one as large as the stiffness itself, that transient was the peak
of every large 3D contact solve (3D P1 Hertz: about 1,700 bytes per DOF above the
stiffness, against 415 for the stiffness).

:func:`smoothed_aggregation` builds the first level itself, with the same
algorithm and options as PyAMG's defaults (the hierarchy is the same to round-off):

* strength of connection ``'symmetric'`` with :math:`\theta = 0` keeps every entry
  of ``A`` and standard aggregation reads only the pattern, so the aggregation
  runs on the index arrays of ``A`` (no strength matrix is formed);
* the near-null space is improved by 4 symmetric Gauss-Seidel sweeps on
  :math:`A B = 0` and fitted per aggregate (PyAMG's ``fit_candidates``), giving the
  tentative prolongator ``T``;
* :math:`P = T - \frac{\omega}{\rho(D^{-1}A)} D^{-1} A T` (:math:`\omega = 4/3`,
  :math:`\rho` estimated by Arnoldi on the operator :math:`D^{-1}A`, no scaled copy)
  is computed by blocks of rows, in two passes (row lengths, then values into
  preallocated arrays), and stored once as CSR; the restriction is its transpose
  as a CSC *view* (:math:`R = P^T` shares the arrays of ``P``);
* the Galerkin product :math:`A_1 = \sum_b P_b^T (A_b P)` is summed over the same
  blocks of rows ``b``, so only one block of ``A P`` is alive at a time.

The coarser levels (a few per cent of the first) come from
:func:`pyamg.smoothed_aggregation_solver` on :math:`A_1`, with the same options
(no candidate improvement below the first level, as PyAMG's default).
"""

from __future__ import annotations

import contextlib

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator

__all__ = ["smoothed_aggregation", "AGGREGATIONS", "STRENGTH_THETA", "plain_aggregation", "updated_hierarchy",
           "reflected_hierarchy", "normal_reflections", "add_on_pattern", "entry_positions", "row_slice", "SMOOTHER",
           "ROW_BLOCK_NNZ"]

#: relaxation of every level: PyAMG's default for smoothed aggregation
SMOOTHER = ("block_gauss_seidel", {"sweep": "symmetric"})
#: relaxation of the rough hierarchy (:func:`plain_aggregation`): one forward block Gauss-Seidel sweep
#: before, one backward after (a symmetric V-cycle at half the sweeps of SMOOTHER: 3D Hertz under a body
#: force, CG to 0.1: P2 78k DOFs 19 iterations in 0.68 s CPU against 15 in 0.92 s, P1 39k 16 in 0.13 s
#: against 12 in 0.16 s, the same gap error, 0.003 and 0.015 h)
_ROUGH_PRE = ("block_gauss_seidel", {"sweep": "forward"})
_ROUGH_POST = ("block_gauss_seidel", {"sweep": "backward"})
#: candidate improvement on the first level: PyAMG's default
_IMPROVE = ("block_gauss_seidel", {"sweep": "symmetric", "iterations": 4})
#: Jacobi weight of the prolongator smoother: PyAMG's default
_OMEGA = 4.0 / 3.0
#: how the first aggregates are formed (:func:`smoothed_aggregation`): ``"pattern"`` every entry of ``A``
#: connects (strength threshold 0, Jacobi-smoothed prolongator, the memory-lean first level below);
#: ``"strength"`` only entries above :data:`STRENGTH_THETA` of the geometric mean of their diagonals
#: connect, with an energy-minimizing prolongator (PyAMG's ``smooth="energy"``)
AGGREGATIONS = ("pattern", "strength")
#: threshold of the symmetric strength of connection of ``aggregation="strength"``: on the graded 2D
#: Hertz meshes (elements up to 30 and 1,429 times longer than wide at 120k and 984k DOFs) threshold 0
#: aggregates across the thin direction of the slivers, and CG to 1e-10 on the stiffness took 101 and
#: 1,399 iterations; 0.1 with the energy-minimizing prolongator 17 and 15 (``docs/benchmarks/amg_paths.md``)
STRENGTH_THETA = 0.1
#: entries of ``A`` per block of rows in the prolongator smoothing and the Galerkin product
#: (the block of ``A P`` has about 3 times as many: ~25 MB of temporaries at 2**20)
ROW_BLOCK_NNZ = 1 << 20


def _row_blocks(A, nnz: int):
    """``(start, stop)`` ranges of rows of the CSR matrix ``A`` holding about ``nnz`` entries each."""
    n = A.shape[0]
    cuts = np.searchsorted(A.indptr, np.arange(0, int(A.indptr[-1]), max(int(nnz), 1)), side="right") - 1
    cuts = np.unique(np.concatenate([cuts, [n]]).clip(0, n))
    if cuts[0] != 0:
        cuts = np.concatenate([[0], cuts])
    return [(int(a), int(b)) for a, b in zip(cuts[:-1], cuts[1:]) if b > a]


def _rows(A, a: int, b: int) -> sp.csr_matrix:
    """Rows ``a:b`` of the CSR matrix ``A`` as a CSR matrix sharing its arrays (no copy)."""
    s, e = int(A.indptr[a]), int(A.indptr[b])
    out = sp.csr_matrix((A.data[s:e], A.indices[s:e], A.indptr[a : b + 1] - s), shape=(b - a, A.shape[1]))
    out.has_sorted_indices = A.has_sorted_indices
    return out


def _smoothed_prolongator(A, T, dinv: np.ndarray, scale: float, nnz_block: int) -> sp.csr_matrix:
    """:math:`P = T - scale\\,D^{-1} A T` as CSR, by blocks of rows in two passes (no ``A T`` alive)."""
    blocks = _row_blocks(A, nnz_block)

    def block(a, b):
        AT = _rows(A, a, b) @ T
        AT = sp.csr_matrix(AT)
        AT.data *= -scale * np.repeat(dinv[a:b], np.diff(AT.indptr))
        Pb = sp.csr_matrix(_rows(T, a, b) + AT)
        Pb.sort_indices()
        return Pb

    lens = np.zeros(A.shape[0], dtype=np.int64)
    for a, b in blocks:
        lens[a:b] = np.diff(block(a, b).indptr)
    indptr = np.zeros(A.shape[0] + 1, dtype=np.int64)
    np.cumsum(lens, out=indptr[1:])
    del lens
    idx_t = np.int32 if max(int(indptr[-1]), T.shape[1]) < np.iinfo(np.int32).max else np.int64
    data = np.empty(int(indptr[-1]))
    indices = np.empty(int(indptr[-1]), dtype=idx_t)
    for a, b in blocks:
        Pb = block(a, b)
        s, e = int(indptr[a]), int(indptr[b])
        data[s:e] = Pb.data
        indices[s:e] = Pb.indices
    P = sp.csr_matrix((data, indices, indptr.astype(idx_t)), shape=T.shape)
    P.has_sorted_indices = True
    return P


def _coarse_pattern(A, P, k: int, blocks) -> sp.csr_matrix:
    """Block pattern ``(n_agg, n_agg)`` of :math:`P^T A P` for a prolongator with ``k`` columns per aggregate.

    Computed on the aggregates, by the blocks of rows of :func:`_galerkin`: the pattern of
    ``P`` with its columns collapsed to their aggregate (``float32`` ones: no
    cancellation), then the pattern products summed.
    """
    n = P.shape[0]
    Pg = sp.csr_matrix((np.ones(P.nnz, dtype=np.float32), P.indices // k, P.indptr.copy()), shape=(n, P.shape[1] // k))
    Pg.sum_duplicates()  # in place: hence the copy of indptr
    Pg.data[:] = 1.0
    G = None
    for a, b in blocks:
        Ab = _rows(A, a, b)
        Ab = sp.csr_matrix((np.ones(Ab.nnz, dtype=np.float32), Ab.indices, Ab.indptr), shape=Ab.shape)
        part = (_rows(Pg, a, b).T @ (Ab @ Pg)).tocsr()
        part.data[:] = 1.0
        G = part if G is None else (G + part).tocsr()
        G.data[:] = 1.0
    G.sort_indices()
    return G


def _add_into(flat: np.ndarray, keys: np.ndarray, ng: int, k: int, part, step: int = 1 << 18) -> bool:
    """Add the COO matrix ``part`` (no duplicates) into the ``(k, k)`` blocks ``flat`` of the block pattern ``keys``.

    In slices of ``step`` entries (the int64 index temporaries stay small). Returns
    False, having added nothing, when an entry lies outside the pattern.
    """
    where = []
    for s in range(0, part.nnz, step):
        r, c = part.row[s : s + step].astype(np.int64), part.col[s : s + step].astype(np.int64)
        q = (r // k) * ng + c // k
        pos = np.minimum(np.searchsorted(keys, q), keys.size - 1)
        if not np.array_equal(keys[pos], q):
            return False
        pos *= k * k
        pos += (r % k) * k + c % k
        where.append(pos)
    for s, pos in zip(range(0, part.nnz, step), where):
        flat[pos] += part.data[s : s + step]  # unique entries: no np.add.at needed
    return True


def _galerkin(A, P, k: int, nnz_block: int):
    r""":math:`P^T A P` summed over blocks of rows ``b``: :math:`\sum_b P_b^T (A_b P)`.

    With ``k`` columns of ``P`` per aggregate the result is a BSR matrix with ``(k, k)``
    blocks (PyAMG's format for the coarse levels) whose block pattern is computed first
    (:func:`_coarse_pattern`); each block's product is added into its values (no second
    copy of the coarse matrix). With ``k = 1`` (or a pattern that misses an entry) the
    block products are summed as sparse matrices.
    """
    blocks = _row_blocks(A, nnz_block)
    nc = P.shape[1]
    G = _coarse_pattern(A, P, k, blocks) if k > 1 and nc % k == 0 else None
    if G is not None:
        ng = G.shape[0]
        keys = np.repeat(np.arange(ng, dtype=np.int64), np.diff(G.indptr)) * ng + G.indices
        data = np.zeros((keys.size, k, k))
        flat = data.reshape(-1)
    Ac = None
    for a, b in blocks:
        part = sp.coo_matrix(_rows(P, a, b).T @ (_rows(A, a, b) @ P))
        if G is not None and _add_into(flat, keys, ng, k, part):
            continue
        part = part.tocsr()
        Ac = part if Ac is None else (Ac + part).tocsr()
    if G is None:
        return Ac
    # blocks that came out exactly zero (cancellations in the pattern) are left out, as scipy's
    # products drop exact zeros: PyAMG's coarse aggregation reads the block pattern
    keep = np.any(data != 0.0, axis=(1, 2))
    del flat, keys
    if not keep.all():
        counts = np.add.reduceat(keep, G.indptr[:-1].astype(np.int64))
        counts[np.diff(G.indptr) == 0] = 0
        indptr = np.zeros(G.shape[0] + 1, dtype=G.indptr.dtype)
        np.cumsum(counts, out=indptr[1:])
        indices = G.indices[keep]
        # compacted in place, by chunks (every kept block moves to a lower position), then shrunk
        dst = np.cumsum(keep) - 1
        step = 1 << 16
        for s in range(0, keep.size, step):
            sel = keep[s : s + step]
            data[dst[s : s + step][sel]] = data[s : s + step][sel]
        m = int(indptr[-1])
        del dst
        data.resize((m, k, k), refcheck=False)
    else:
        indptr, indices = G.indptr, G.indices
    del G
    out = sp.bsr_matrix((data, indices, indptr), shape=(nc, nc), blocksize=(k, k))
    return out if Ac is None else sp.bsr_matrix(out + Ac, blocksize=(k, k))


def _dinv_operator(A, dinv: np.ndarray) -> LinearOperator:
    """:math:`D^{-1} A` as an operator (for its spectral radius) without a scaled copy of ``A``."""

    def mv(v):
        v = np.asarray(v)
        return dinv.reshape((-1,) + (1,) * (v.ndim - 1)) * (A @ v)

    return LinearOperator(A.shape, matvec=mv, matmat=mv, dtype=A.dtype)


#: seed of NumPy's global generator while a hierarchy is built (:func:`_fixed_random_state`)
RANDOM_SEED = 0


@contextlib.contextmanager
def _fixed_random_state(seed: int = RANDOM_SEED):
    """NumPy's global generator seeded with ``seed`` inside the block, restored after it.

    PyAMG estimates the spectral radius of :math:`D^{-1}A` for the prolongator smoother
    (:func:`pyamg.util.linalg.approximate_spectral_radius`) from a random start vector of the
    global generator, so every setup built a slightly different hierarchy and the CG and
    Newton iterations of one problem changed from run to run (2D P1 Hertz, 10k DOFs,
    Algorithm 6.1 on the AMG path: 4 outer / 83 Newton, 5 / 79 and 5 / 76 in three runs of one
    process). A fixed seed makes the hierarchy, and every count after it, the same in every
    run; the caller's generator state is left as it was.
    """
    state = np.random.get_state()
    np.random.seed(seed)
    try:
        yield
    finally:
        np.random.set_state(state)


def smoothed_aggregation(A, B=None, *, max_coarse: int = 500, coarse_solver: str = "splu",
                         smoother=SMOOTHER, nnz_block: int = ROW_BLOCK_NNZ, aggregation: str = "pattern"):
    """PyAMG smoothed-aggregation hierarchy of the SPD CSR matrix ``A``.

    The same hierarchy in every run (:func:`_fixed_random_state`). ``aggregation``
    (:data:`AGGREGATIONS`): ``"pattern"`` builds the memory-lean first level of
    :func:`_smoothed_aggregation` (PyAMG's defaults); ``"strength"`` is
    ``pyamg.smoothed_aggregation_solver`` with the symmetric strength of connection at
    :data:`STRENGTH_THETA` and the energy-minimizing prolongator, for meshes of
    stretched elements (the graded 2D meshes), where the first aggregates must follow the
    strong couplings. Its operator complexity is higher (2.6 against 1.9 on the 2D 984k
    mesh), and on 3D meshes it is far higher (19 on the 3D P1 Hertz 105k stiffness) for no
    fewer iterations, which is why it is not the default there.
    """
    if aggregation not in AGGREGATIONS:
        raise ValueError(f"aggregation {aggregation!r}: expected one of {', '.join(AGGREGATIONS)}")
    with _fixed_random_state():
        if aggregation == "strength":
            return _strength_aggregation(A, B, max_coarse=max_coarse, coarse_solver=coarse_solver, smoother=smoother)
        return _smoothed_aggregation(A, B, max_coarse=max_coarse, coarse_solver=coarse_solver, smoother=smoother,
                                     nnz_block=nnz_block)


def _prepared(A, B):
    """``A`` as CSR with sorted indices, marked Hermitian for PyAMG, and the near-null space ``B`` as an
    ``(n, k)`` float array (constants when None)."""
    A = sp.csr_matrix(A)
    if not A.has_sorted_indices:
        A.sort_indices()
    A.symmetry = "hermitian"
    n = A.shape[0]
    B = np.ones((n, 1)) if B is None else np.asarray(B, dtype=float).reshape(n, -1)
    return A, B


def _strength_aggregation(A, B=None, *, max_coarse: int, coarse_solver: str, smoother):
    """``pyamg.smoothed_aggregation_solver`` with strength threshold :data:`STRENGTH_THETA` and energy smoothing."""
    import pyamg

    A, B = _prepared(A, B)
    return pyamg.smoothed_aggregation_solver(A, B=B, strength=("symmetric", {"theta": STRENGTH_THETA}),
                                             smooth="energy", max_coarse=max_coarse, coarse_solver=coarse_solver,
                                             presmoother=smoother, postsmoother=smoother)


def _smoothed_aggregation(A, B=None, *, max_coarse: int = 500, coarse_solver: str = "splu",
                          smoother=SMOOTHER, nnz_block: int = ROW_BLOCK_NNZ):
    """PyAMG smoothed-aggregation hierarchy of the SPD CSR matrix ``A`` with a memory-lean first level.

    Same method and options as ``pyamg.smoothed_aggregation_solver(A, B=B,
    max_coarse=max_coarse, coarse_solver=coarse_solver, presmoother=smoother,
    postsmoother=smoother)`` (module doc); only the first level is built here, by
    blocks of rows, and stores ``P`` once (``R`` is a transposed view of it).

    Parameters
    ----------
    A : scipy.sparse matrix (n, n)
        Symmetric positive definite (CSR; another format is converted).
    B : ndarray (n, k) or None
        Near-null space (the rigid-body modes for elasticity); None: constants.
    max_coarse : int
        Rows of the coarsest level (solved by ``coarse_solver``).
    coarse_solver : str
        PyAMG coarse solver name.
    smoother : tuple
        PyAMG relaxation descriptor of every level (pre and post).
    nnz_block : int
        Entries of ``A`` per block of rows of the first-level products (bounds their temporaries).

    Returns
    -------
    pyamg.multilevel.MultilevelSolver
    """
    import pyamg
    from pyamg.aggregation.aggregate import standard_aggregation
    from pyamg.aggregation.tentative import fit_candidates
    from pyamg.multilevel import MultilevelSolver
    from pyamg.relaxation.smoothing import change_smoothers
    from pyamg.relaxation.utils import relaxation_as_linear_operator
    from pyamg.util.linalg import approximate_spectral_radius

    A, B = _prepared(A, B)
    n = A.shape[0]
    opts = dict(max_coarse=max_coarse, coarse_solver=coarse_solver, presmoother=smoother, postsmoother=smoother)
    if n <= max_coarse:
        return pyamg.smoothed_aggregation_solver(A, B=B, **opts)
    # aggregation on the pattern of A (= the symmetric strength matrix at theta 0)
    AggOp, _ = standard_aggregation(sp.csr_matrix((A.data, A.indices, A.indptr), shape=A.shape, copy=False))
    B = relaxation_as_linear_operator(_IMPROVE, A, np.zeros((n, 1))) @ B
    T, Bc = fit_candidates(AggOp, B)
    del AggOp
    T = sp.csr_matrix(T)
    diag = A.diagonal()
    dinv = np.zeros(n)
    nz = diag != 0
    dinv[nz] = 1.0 / diag[nz]
    del diag, nz
    rho = approximate_spectral_radius(_dinv_operator(A, dinv))
    P = _smoothed_prolongator(A, T, dinv, _OMEGA / rho, nnz_block)
    del T, dinv
    # the coarse levels: PyAMG's block format of the Galerkin product of a (1, k)-block prolongator
    Ac = _galerkin(A, P, Bc.shape[1], nnz_block)
    first = MultilevelSolver.Level()
    first.A, first.B, first.P, first.R = A, B, P, P.T  # P.T: a CSC view on the arrays of P
    Ac.symmetry = "hermitian"
    rest = pyamg.smoothed_aggregation_solver(Ac, B=Bc, improve_candidates=None, max_levels=9, **opts)
    ml = MultilevelSolver([first, *rest.levels], coarse_solver=coarse_solver)
    change_smoothers(ml, smoother, smoother)
    return ml


def plain_aggregation(A, B=None, *, max_coarse: int = 500, coarse_solver: str = "splu"):
    """PyAMG aggregation hierarchy with unsmoothed (tentative) prolongators: a cheap preconditioner.

    ``pyamg.smoothed_aggregation_solver(A, B=B, smooth=None, improve_candidates=None, ...)``: the
    same standard aggregation and near-null space fit as :func:`smoothed_aggregation`, without the
    prolongator smoothing and the candidate improvement, whose products with ``A`` are most of the
    setup, and with one Gauss-Seidel sweep before and after (:data:`_ROUGH_PRE`). The V-cycle is a weaker preconditioner (more CG iterations per digit), so this hierarchy
    serves rough solves (:func:`alcontact.linalg.krylov.approximate_solve`), where its setup, a few
    per cent of a direct factorization of a 3D stiffness, is what counts.

    Parameters
    ----------
    A : scipy.sparse matrix (n, n)
        Symmetric positive definite.
    B : ndarray (n, k) or None
        Near-null space (the rigid-body modes for elasticity); None: constants.
    max_coarse, coarse_solver
        As :func:`smoothed_aggregation`.

    Returns
    -------
    pyamg.multilevel.MultilevelSolver
    """
    import pyamg

    A, B = _prepared(A, B)
    with _fixed_random_state():
        return pyamg.smoothed_aggregation_solver(A, B=B, smooth=None, improve_candidates=None, max_coarse=max_coarse,
                                                 coarse_solver=coarse_solver, presmoother=_ROUGH_PRE,
                                                 postsmoother=_ROUGH_POST)


# ---------------------------------------------------------------------- reuse for K + a contact term
def entry_positions(A, rows: np.ndarray, cols: np.ndarray) -> np.ndarray | None:
    """Positions of the entries ``(rows, cols)`` in the data of ``A`` (CSR or BSR, sorted indices).

    Returns ``(block, r, c)`` index arrays into ``A.data`` for BSR (``(pos,)`` for CSR),
    or ``None`` when an entry is not in the sparsity pattern of ``A``. Only the rows
    of ``A`` that hold entries are searched (a contact update touches few rows).
    """
    br, bc = A.blocksize if sp.issparse(A) and A.format == "bsr" else (1, 1)
    brow, bcol = rows // br, cols // bc
    ncol_b = A.shape[1] // bc
    ur, inv = np.unique(brow, return_inverse=True)
    starts = A.indptr[ur].astype(np.int64)
    lens = A.indptr[ur + 1].astype(np.int64) - starts
    if lens.sum() == 0:
        return None
    seg = np.repeat(np.arange(ur.size, dtype=np.int64), lens)
    pos = np.repeat(starts - np.concatenate([[0], np.cumsum(lens)[:-1]]), lens) + np.arange(lens.sum())
    keys = seg * ncol_b + A.indices[pos]  # sorted: segments ascending, sorted indices within each
    q = inv.astype(np.int64) * ncol_b + bcol
    k = np.minimum(np.searchsorted(keys, q), keys.size - 1)
    if not np.array_equal(keys[k], q):
        return None
    if br == 1 and bc == 1 and A.format != "bsr":
        return (pos[k],)
    return pos[k], rows % br, cols % bc


def add_on_pattern(A, D):
    """``A + D`` for a sparse ``D`` with few rows: a new data array on the index arrays of ``A``.

    Falls back to scipy's sum (in the format of ``A``) when ``D`` has an entry outside
    the pattern of ``A`` (e.g. an entry of a node block that assembled to exactly zero).
    """
    D = sp.coo_matrix(D)
    D.sum_duplicates()
    if D.nnz == 0:
        return A
    where = entry_positions(A, D.row.astype(np.int64), D.col.astype(np.int64))
    if where is None:
        out = (A + D).asformat(A.format, copy=False)
        if A.format == "bsr":
            out = sp.bsr_matrix(out, blocksize=A.blocksize)
        out.sort_indices()
        return out
    data = A.data.copy()
    np.add.at(data, where, D.data)
    kind = sp.bsr_matrix if A.format == "bsr" else sp.csr_matrix
    out = kind((data, A.indices, A.indptr), shape=A.shape)
    out.has_sorted_indices = True
    return out


def row_slice(P, rows: np.ndarray):
    """Rows ``rows`` (sorted, unique) of a CSR or BSR matrix as a CSR matrix ``(rows.size, ncols)``."""
    if P.format != "bsr":
        return sp.csr_matrix(P)[rows]
    br, bc = P.blocksize
    blk = rows // br
    starts = P.indptr[blk].astype(np.int64)
    lens = P.indptr[blk + 1].astype(np.int64) - starts
    seg = np.repeat(np.arange(rows.size, dtype=np.int64), lens)
    pos = np.repeat(starts - np.concatenate([[0], np.cumsum(lens)[:-1]]), lens) + np.arange(lens.sum())
    vals = P.data[pos, np.repeat(rows % br, lens), :]  # (nblocks, bc)
    cols = (P.indices[pos].astype(np.int64)[:, None] * bc + np.arange(bc)).ravel()
    return sp.csr_matrix((vals.ravel(), (np.repeat(seg, bc), cols)), shape=(rows.size, P.shape[1]))


def updated_hierarchy(ml_K, J, delta):
    r"""AMG hierarchy of :math:`J = K + \Delta` on the prolongators of the hierarchy ``ml_K`` of :math:`K`.

    The contact term :math:`\Delta = B_c^T \operatorname{diag}(k) B_c` is block diagonal on
    the few contact DOFs. Its Galerkin coarse versions :math:`\Delta_{l+1} = P_l^T \Delta_l P_l`
    touch only the coarse DOFs whose prolongator rows meet the contact DOFs, so the coarse
    operators :math:`A_l(K) + \Delta_l` of :math:`J` cost a copy of the coarse data plus a
    small product, instead of a new aggregation, prolongator smoothing and Galerkin product
    of the whole matrix (a fresh setup of :func:`smoothed_aggregation`, about 85 % of one linear solve on the
    3D Hertz problem). The smoothers are set up again on the new operators.
    """
    from pyamg.multilevel import MultilevelSolver
    from pyamg.relaxation.smoothing import change_smoothers

    levels = []
    D = sp.csr_matrix(delta)
    last = len(ml_K.levels) - 1
    for i, lk in enumerate(ml_K.levels):
        lvl = MultilevelSolver.Level()
        lvl.A = J if i == 0 else add_on_pattern(lk.A, D)
        lvl.A.symmetry = getattr(lk.A, "symmetry", "hermitian")
        lvl.B = lk.B
        if i < last:
            lvl.P, lvl.R = lk.P, lk.R
            D.eliminate_zeros()
            rows = np.unique(D.tocoo().row)
            if rows.size:
                Pc = row_slice(lk.P, rows)
                D = (Pc.T @ (D[rows][:, rows] @ Pc)).tocsr()
            else:
                D = sp.csr_matrix((lk.P.shape[1], lk.P.shape[1]))
        levels.append(lvl)
    ml = MultilevelSolver(levels, coarse_solver="splu")
    change_smoothers(ml, SMOOTHER, SMOOTHER)
    return ml


def normal_reflections(Bs, n: int):
    r"""Householder reflections :math:`H_i` that map a coordinate of each node onto its normal.

    ``Bs`` holds one row per point on disjoint DOFs (the rows :math:`-\nu_i^T` on the free
    DOFs of its node). :math:`H_i = I - 2 v v^T / v^T v`, :math:`v = u - s\,e_j` with
    :math:`u = B_i^T/|B_i|`, ``j`` its largest component and :math:`s` its sign, so that
    :math:`H_i u = s\,e_j`. Returns ``Q - I`` (``n x n``, symmetric; :math:`Q = Q^T = Q^{-1}`
    is block diagonal with :math:`H_i` on the DOFs of point ``i``) and the sorted DOFs it touches.
    """
    Bs = sp.csr_matrix(Bs)
    rows_out, cols_out, vals_out = [], [], []
    lens = np.diff(Bs.indptr)
    for d in np.unique(lens[lens > 0]):
        pts = np.flatnonzero(lens == d)
        pos = Bs.indptr[pts][:, None] + np.arange(d)
        dofs = Bs.indices[pos]  # (p, d)
        u = Bs.data[pos]
        u = u / np.linalg.norm(u, axis=1, keepdims=True)
        j = np.argmax(np.abs(u), axis=1)
        v = u.copy()
        v[np.arange(pts.size), j] -= np.sign(u[np.arange(pts.size), j])
        vv = np.einsum("pi,pi->p", v, v)
        ok = vv > 1e-30  # the normal is a coordinate already: H = I
        E = -2.0 * v[ok, :, None] * v[ok, None, :] / vv[ok, None, None]  # H - I, (p, d, d)
        dd = dofs[ok]
        rows_out.append(np.repeat(dd, d, axis=1).ravel())
        cols_out.append(np.tile(dd, (1, d)).ravel())
        vals_out.append(E.ravel())
    rows = np.concatenate(rows_out) if rows_out else np.zeros(0, dtype=np.int64)
    cols = np.concatenate(cols_out) if cols_out else np.zeros(0, dtype=np.int64)
    vals = np.concatenate(vals_out) if vals_out else np.zeros(0)
    E = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    return E, np.unique(rows)


def reflected_hierarchy(ml_K, J, delta, Bs, *, overwrite: bool = False):
    r"""Preconditioner of :math:`J = K + \Delta` whose first level sees each stiff spring on one coordinate.

    A spring much stiffer than its node (the default :math:`\varepsilon_N^0 = 100 E'/h` is
    about 20 times the node's normal stiffness on the 3D P2 Hertz mesh, the pure penalty
    raises it 1e5-fold) puts :math:`k_i \nu_i \nu_i^T` into the node block of
    :math:`J`. The first level of the hierarchy of ``K`` is a CSR matrix smoothed by pointwise
    Gauss-Seidel; on an oblique normal (the sphere away from its axis) the spring couples the
    node's DOFs, and pointwise relaxation barely moves the node's tangential motion: the CG
    iterations per Newton step grew with the penalty (3D P2 Hertz, 9k DOFs, a random
    right-hand side to 1e-8: 31, 206 and 748 iterations at 1e3, 1e5 and 1e7 :math:`E'/h`;
    keeping the stiff normals out of the coarse spaces, as for a support, did not help:
    182 and 715 at the last two; with the reflections: 30, 30, 31). With the reflections :math:`Q` of
    :func:`normal_reflections`, :math:`\hat J = Q J Q` carries each stiff spring on the
    diagonal of one DOF (no coupling left for the pointwise relaxation), and :math:`\hat P = Q P` keeps the
    coarse operators :math:`\hat P^T \hat J \hat P = P^T J P` of :func:`updated_hierarchy`.
    CG runs on :math:`\hat J y = Q r`, :math:`dx = Q y` (the AMG paths of :mod:`alcontact.contact`), i.e. with the
    preconditioner :math:`Q\,V(\hat J)\,Q` of :math:`J`, symmetric positive definite as the V-cycle is;
    :math:`Q - I` lives on the stiff points' DOFs, so :math:`\hat J` and :math:`\hat P` are
    corrections of a few rows and columns on the index arrays of :math:`J` and :math:`P`.

    With ``overwrite`` the data of ``J`` become those of :math:`\hat J` where its pattern
    allows (always, for the node blocks of a finite element matrix); the first level's
    matrix is :math:`\hat J` either way. Returns ``(hierarchy, Q - I)``; ``Q = I`` for a
    one-level hierarchy (a direct solve).
    """
    ml = updated_hierarchy(ml_K, J, delta)
    if len(ml.levels) == 1:  # one level: the coarse solver factorizes J, nothing to relax
        return ml, sp.csr_matrix(J.shape)
    E, r = normal_reflections(Bs, J.shape[0])
    Er = E[:, r]  # (n, |r|), nonzero rows only in r
    EJ = (Er @ sp.csr_matrix(J)[r]).tocsr()  # (Q - I) J
    EJE = (EJ[:, r] @ E[r]).tocsr()  # (Q - I) J (Q - I)
    corr = (EJ + EJ.T + EJE).tocoo()  # Q J Q - J, J symmetric
    corr.sum_duplicates()
    l0 = ml.levels[0]
    where = entry_positions(J, corr.row.astype(np.int64), corr.col.astype(np.int64)) if overwrite else None
    if where is not None:  # in the pattern of J (the node blocks): in place
        np.add.at(J.data, where, corr.data)
        Jh = J
    else:
        Jh = add_on_pattern(J, corr)
    Jh.symmetry = getattr(l0.A, "symmetry", "hermitian")
    P = l0.P
    Ph = add_on_pattern(P, (Er @ row_slice(P, r)).tocoo())  # Q P
    l0.A, l0.P = Jh, Ph
    l0.R = Ph.T.tocsr() if Ph.format != "bsr" else Ph.T
    from pyamg.relaxation.smoothing import change_smoothers

    change_smoothers(ml, SMOOTHER, SMOOTHER)
    return ml, E
