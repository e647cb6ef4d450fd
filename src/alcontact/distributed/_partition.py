"""Element partition of a mesh (METIS through pymetis) and the node numbering it induces.

Why METIS through ``pymetis`` rather than PETSc's partitioner: Debian's PETSc has no
ParMETIS (non-free) and its PT-Scotch needs the graph as a distributed ``MatAdj``; the
mesh is read on rank 0 anyway (as by the serial path), and ``pymetis`` partitions its
element dual graph there in one call (k-way METIS, the partitioner the field uses), in a
small wheel that works with NumPy 1 and 2.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..errors import InputError

__all__ = ["dual_graph", "owner_numbering", "partition_elements"]


def _connectivity(where: str, t) -> np.ndarray:
    """``t`` as an integer array of shape ``(nodes_per_elem >= 2, n_elem)`` with node numbers >= 0, else an
    InputError naming the argument."""
    from .._options import show

    try:
        a = np.asarray(t)
    except (TypeError, ValueError, OverflowError):  # ragged nesting, huge integers
        a = None
    if a is None or a.dtype.kind not in "iu" or a.ndim != 2 or a.shape[0] < 2 or (a.size and a.min() < 0):
        raise InputError(f"{where}: t = {show(t)}: expected the element connectivity, an integer array of shape "
                         "(nodes_per_element, n_elements) with node numbers >= 0 (mesh.t).")
    return a


def partition_elements(t: np.ndarray, nparts: int, *, seed: int = 0) -> np.ndarray:
    """Part (``0 .. nparts-1``) of each element of the connectivity ``t`` (shape ``(nodes_per_elem, n_elem)``).

    Elements are neighbours when they share a facet (``dim`` nodes, the element dual graph).

    Raises
    ------
    InputError
        Fewer elements than parts, or pymetis missing (with the set-up command).
    """
    from .._options import is_integer, require

    t = _connectivity("partition_elements", t)
    n_el = t.shape[1]
    require("partition_elements", "nparts", nparts, is_integer(nparts) and nparts >= 1, "an integer >= 1")
    require("partition_elements", "seed", seed, is_integer(seed), "an integer")
    if n_el < nparts:
        raise InputError(f"the mesh has {n_el} elements, fewer than the {nparts} MPI ranks: it is too small to "
                         f"distribute; run it with fewer ranks (mpirun -n {max(1, n_el)}) or serially.")
    if nparts == 1:
        return np.zeros(n_el, dtype=np.int64)
    try:
        import pymetis
    except ImportError:
        from ..linalg import MPI_SETUP_HINT

        raise InputError(f"partitioning the mesh needs pymetis; {MPI_SETUP_HINT}.") from None
    dual = dual_graph(t)
    opts = pymetis.Options(seed=seed)
    _, parts = pymetis.part_graph(nparts, xadj=dual.indptr, adjncy=dual.indices, options=opts)
    parts = np.asarray(parts, dtype=np.int64)
    if np.unique(parts).size != nparts:
        raise InputError(f"METIS left a part empty ({np.unique(parts).size} of {nparts} parts used): the mesh is "
                         "too small for this many ranks; run with fewer ranks.")
    return parts


def dual_graph(t: np.ndarray) -> sp.csr_matrix:
    """Element dual graph (``n_elem x n_elem``, symmetric, no diagonal): elements sharing a facet.

    Built from the sorted facets of simplices (``dim`` of the ``dim + 1`` nodes), in
    ``O(n_elem log n_elem)`` time and ``O(n_elem)`` memory (not from the node incidence,
    whose square counts every element sharing a node: ~100 per tetrahedron).
    """
    t = _connectivity("dual_graph", t)
    k, n_el = t.shape
    facets = np.concatenate([np.sort(np.delete(t, i, axis=0), axis=0) for i in range(k)], axis=1).T  # (k n_el, k-1)
    owner = np.tile(np.arange(n_el), k)
    order = np.lexsort(facets.T[::-1])
    f, o = facets[order], owner[order]
    same = np.all(f[1:] == f[:-1], axis=1)
    a, b = o[:-1][same], o[1:][same]
    g = sp.csr_matrix((np.ones(2 * a.size, dtype=np.int8), (np.concatenate([a, b]), np.concatenate([b, a]))),
                      shape=(n_el, n_el))
    g.sort_indices()
    return g


def owner_numbering(t: np.ndarray, parts: np.ndarray, n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Owner rank of each node and a numbering in which each rank's nodes are contiguous.

    A node belongs to the lowest part among the elements that contain it.

    Returns
    -------
    owner : numpy.ndarray of int, shape (n_nodes,)
    new : numpy.ndarray of int, shape (n_nodes,)
        ``new[old]``: the node's number in the distributed numbering (rank 0's nodes
        first, in their original order, then rank 1's, ...).
    """
    from .._options import is_integer, require, show

    t = _connectivity("owner_numbering", t)
    top = int(t.max()) + 1 if t.size else 0
    require("owner_numbering", "n_nodes", n_nodes, is_integer(n_nodes) and n_nodes >= top,
            f"the number of nodes, at least the largest node number in t plus one ({top})")
    orphans = n_nodes > top  # nodes above every node number in t: checked before an array of n_nodes is made
    try:
        parts_ok = np.asarray(parts)
    except (TypeError, ValueError, OverflowError):
        parts_ok = None
    if parts_ok is None or parts_ok.dtype.kind not in "iu" or parts_ok.shape != (t.shape[1],):
        raise InputError(f"owner_numbering: parts = {show(parts)}: expected one part number per element, an "
                         f"integer array of shape ({t.shape[1]},) (partition_elements).")
    parts = parts_ok
    owner = np.full(top, np.iinfo(np.int64).max, dtype=np.int64)
    np.minimum.at(owner, t.ravel(), np.repeat(parts[None, :], t.shape[0], axis=0).ravel())
    if orphans or np.any(owner == np.iinfo(np.int64).max):
        raise InputError("the mesh has nodes that belong to no element; remove them before distributing it.")
    order = np.argsort(owner, kind="stable")
    new = np.empty(n_nodes, dtype=np.int64)
    new[order] = np.arange(n_nodes)
    return owner, new
