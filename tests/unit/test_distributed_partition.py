"""Mesh partition helpers of alcontact.distributed (pure NumPy: no MPI needed)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from alcontact.distributed import dual_graph, owner_numbering, partition_elements
from alcontact.errors import InputError
from alcontact.fem import meshes


@pytest.mark.parametrize("mesh", [meshes.rectangle(0, 2, 0, 1, 6, 3), meshes.box(0, 1, 0, 1, 0, 1, 3, 2, 2)],
                         ids=["tri", "tet"])
def test_dual_graph_equals_the_facet_sharing_from_the_node_incidence(mesh):
    """Reference: elements sharing ``dim`` nodes, from the square of the element-node incidence."""
    t = mesh.t
    inc = sp.csr_matrix((np.ones(t.size), (np.repeat(np.arange(t.shape[1]), t.shape[0]), t.T.ravel())))
    ref = (inc @ inc.T).toarray() >= t.shape[0] - 1
    np.fill_diagonal(ref, False)
    assert np.array_equal(dual_graph(t).toarray() != 0, ref)


def test_owner_numbering_makes_each_ranks_nodes_contiguous():
    mesh = meshes.box(0, 1, 0, 1, 0, 1, 3, 3, 3)
    xc = mesh.p[0, mesh.t].mean(axis=0)
    parts = (xc > 0.5).astype(np.int64)
    owner, new = owner_numbering(mesh.t, parts, mesh.p.shape[1])
    assert np.array_equal(np.sort(new), np.arange(mesh.p.shape[1]))
    assert np.all(np.diff(owner[np.argsort(new)]) >= 0)  # rank 0's nodes first, then rank 1's
    shared = np.intersect1d(mesh.t[:, parts == 0], mesh.t[:, parts == 1])
    assert shared.size and np.all(owner[shared] == 0)  # a shared node belongs to the lowest rank


def test_too_few_elements_for_the_ranks():
    with pytest.raises(InputError, match="2 elements, fewer than the 3 MPI ranks"):
        partition_elements(meshes.rectangle(0, 1, 0, 1, 1, 1).t, 3)
