"""AMG hierarchies are the same in every run (issue 21, run-to-run spread).

PyAMG estimates a spectral radius from a random start vector of NumPy's global generator, so two
setups of one matrix gave different prolongators and the Krylov and Newton counts of a contact
solve changed from run to run. The hierarchy builders seed the generator while they run and
restore the caller's state.
"""

import numpy as np
import scipy.sparse as sp

from alcontact.linalg._amg import plain_aggregation, smoothed_aggregation


def _laplacian(n=40):
    T = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    return (sp.kron(T, sp.eye(n)) + sp.kron(sp.eye(n), T)).tocsr()


def test_two_setups_give_the_same_hierarchy_and_leave_the_generator_alone():
    A = _laplacian()
    for build in (smoothed_aggregation, plain_aggregation):
        np.random.seed(123)
        before = np.random.get_state()[1].copy()
        one = build(A, max_coarse=50)
        assert np.array_equal(np.random.get_state()[1], before)  # the caller's state is restored
        np.random.rand(7)  # a different global state for the second setup
        two = build(A, max_coarse=50)
        assert len(one.levels) == len(two.levels) >= 2
        for a, b in zip(one.levels[:-1], two.levels[:-1]):
            assert (a.P != b.P).nnz == 0 and np.array_equal(a.P.data, b.P.data)
