"""``LinearElasticity.probe``: interpolation of nodal fields at points (the slide predictor of issue 18)."""

import numpy as np
import pytest

from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic


@pytest.mark.parametrize("dim,order", [(2, 1), (2, 2), (3, 1), (3, 2)])
def test_probe_reproduces_the_element_space_and_flags_outside_points(dim, order):
    """A polynomial of the element's degree is interpolated exactly (to round-off, 1e-12) at shifted
    nodes; shifted nodes beyond the box are reported outside and get no row."""
    mesh = meshes.rectangle(0, 2, 0, 1, 6, 3) if dim == 2 else meshes.box(0, 1, 0, 1, 0, 1, 3, 3, 3)
    body = Hyperelastic(mesh, Material(E=1.0, nu=0.3), order=order)
    X = body.scalar_doflocs

    def f(Y):
        v = 1.0 + Y[0] - 0.5 * Y[-1]
        return v + (Y[0] * Y[1] - Y[1] ** 2 if order == 2 else 0.0)

    shift = np.full(dim, 0.137)
    pts = X.T - shift
    P, inside = body.probe(pts)
    upper = np.ones(dim) if dim == 3 else np.array([2.0, 1.0])
    expect = np.all((pts >= -1e-12) & (pts <= upper + 1e-12), axis=1)
    np.testing.assert_array_equal(inside, expect)
    assert P.shape == (int(inside.sum()), X.shape[1])
    np.testing.assert_allclose(P @ f(X), f(pts[inside].T), atol=1e-12)
