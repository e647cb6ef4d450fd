"""Unit tests for rigid obstacles (signed gap, normal, projection, Hessian).

The generic checks are generated from the registry: every registered obstacle needs an
entry in ``EXAMPLES`` (parameters, points known to be inside the obstacle and points known
to be in free space), so a new obstacle is covered automatically.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from alcontact.contact import obstacles as obs
from alcontact.errors import InputError, NonFiniteError, UnknownNameError

SQRT2, SQRT3 = np.sqrt(2.0), np.sqrt(3.0)


def _user_sphere_gap(x):
    return 0.8 - np.linalg.norm(x - np.array([0.2, -0.1, 0.3]), axis=1)


_PENTAGON = [[0.0, 0.0], [1.2, -0.1], [1.6, 0.8], [0.7, 1.4], [-0.3, 0.9]]
# A cube cut by an oblique plane: faces, edges and vertices of several kinds.
_POLY_A = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1],
                    [1, 1, 1]], dtype=float)
_POLY_B = np.array([1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 2.2])

# name -> (params, points inside the obstacle (gap > 0), points in free space (gap < 0))
EXAMPLES: dict[str, tuple[dict, list, list]] = {
    "half-space": (dict(point=[0.1, 0.2, 0.3], normal=[0.3, -0.2, 1.0]),
                   [[0.1, 0.2, -1.0]], [[0.1, 0.2, 2.0]]),
    "sphere": (dict(center=[0.1, -0.2, 0.3], radius=0.7),
               [[0.1, -0.2, 0.5], [0.1, -0.2, 0.3]], [[2.0, 0.0, 0.0]]),
    "sphere-cavity": (dict(center=[0.1, -0.2, 0.3], radius=0.7),
                      [[2.0, 0.0, 0.0]], [[0.1, -0.2, 0.5], [0.1, -0.2, 0.3]]),
    "circle": (dict(center=[0.1, -0.2], radius=0.7), [[0.3, -0.2]], [[1.5, 1.0]]),
    "circle-cavity": (dict(center=[0.1, -0.2], radius=0.7), [[1.5, 1.0]], [[0.3, -0.2]]),
    "cylinder": (dict(center=[0.0, 0.1, 0.0], axis=[0.2, 0.1, 1.0], radius=0.5),
                 [[0.1, 0.1, 0.2], [1.0, 0.6, 5.0]], [[2.0, 0.0, 0.0]]),
    "cylinder-cavity": (dict(center=[0.0, 0.1, 0.0], axis=[0.2, 0.1, 1.0], radius=0.5),
                        [[2.0, 0.0, 0.0]], [[0.1, 0.1, 0.2], [1.0, 0.6, 5.0]]),
    "convex-polygon": (dict(vertices=_PENTAGON), [[0.6, 0.6]], [[3.0, 3.0], [0.6, -1.0]]),
    "convex-polyhedron": (dict(A=_POLY_A, b=_POLY_B), [[0.5, 0.5, 0.5]],
                          [[1.0, 1.0, 1.0], [2.0, -1.0, 0.5], [0.5, 0.5, -0.3]]),
    "convex-polygon-cavity": (dict(vertices=_PENTAGON), [[3.0, 3.0], [0.6, -1.0]], [[0.6, 0.6]]),
    "convex-polyhedron-cavity": (dict(A=_POLY_A, b=_POLY_B), [[1.0, 1.0, 1.0], [2.0, -1.0, 0.5], [0.5, 0.5, -0.3]],
                                 [[0.5, 0.5, 0.5]]),
    # a closed, non-convex L-shaped polygon, counter-clockwise: a solid obstacle, the body outside
    "surface": (dict(vertices=[[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]],
                     facets=[[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0]]),
                [[0.5, 0.5], [1.5, 0.5], [0.5, 1.5]], [[1.5, 1.5], [-1.0, 1.0], [3.0, 3.0]]),
    "user": (dict(gap=_user_sphere_gap, dim=3, length_scale=0.8),
             [[0.2, -0.1, 0.5]], [[2.0, 2.0, 2.0]]),
}


def _dim(ob, params):
    return ob.dim if ob.dim is not None else params.get("dim", 3)


def _sample(ob, name, m=300, seed=0):
    """Random points in a box around the example (both sides of the surface)."""
    params, inside, outside = EXAMPLES[name]
    rng = np.random.default_rng(seed)
    ref = np.array(inside + outside, dtype=float)
    mid = ref.mean(axis=0)
    half = max(1.0, float(np.max(np.ptp(ref, axis=0))))
    return mid + half * rng.uniform(-1.0, 1.0, size=(m, ref.shape[1]))


@pytest.fixture(params=obs.available())
def example(request):
    name = request.param
    if name not in EXAMPLES:
        pytest.fail(f"obstacle {name!r} is registered but has no entry in EXAMPLES")
    params, inside, outside = EXAMPLES[name]
    return name, obs.make(name, **params)


# --------------------------------------------------------------------------- generic


def test_every_example_is_registered():
    assert set(EXAMPLES) == set(obs.available())


def test_protocol_and_metadata(example):
    name, ob = example
    assert isinstance(ob, obs.Obstacle)
    assert ob.name == name
    assert isinstance(ob.describe(), str) and ob.describe()
    assert obs.docs()[name]


def test_sign_convention(example):
    name, ob = example
    _, inside, outside = EXAMPLES[name]
    assert np.all(ob.gap(np.array(inside, dtype=float)) > 0)
    assert np.all(ob.gap(np.array(outside, dtype=float)) < 0)


def test_shapes_and_finiteness(example):
    name, ob = example
    x = _sample(ob, name, m=40)
    m, d = x.shape
    g, n = ob.evaluate(x)
    assert g.shape == (m,) and n.shape == (m, d)
    assert ob.project(x).shape == (m, d)
    assert ob.gap_hessian(x).shape == (m, d, d)
    for arr in (g, n, ob.project(x), ob.gap_hessian(x)):
        assert np.all(np.isfinite(arr))
    np.testing.assert_array_equal(ob.gap(x), g)
    np.testing.assert_array_equal(ob.normal(x), n)


def test_empty_input(example):
    name, ob = example
    d = _dim(ob, EXAMPLES[name][0])
    x = np.zeros((0, d))
    assert ob.gap(x).shape == (0,)
    assert ob.normal(x).shape == (0, d)
    assert ob.project(x).shape == (0, d)
    assert ob.gap_hessian(x).shape == (0, d, d)


def test_normal_is_unit(example):
    name, ob = example
    x = _sample(ob, name)
    np.testing.assert_allclose(np.linalg.norm(ob.normal(x), axis=1), 1.0, atol=1e-7)


def test_normal_is_minus_gradient(example):
    """normal == -grad gap by central differences, skipping points within h of a kink."""
    name, ob = example
    x = _sample(ob, name)
    m, d = x.shape
    h = 1e-6
    g0 = ob.gap(x)
    fwd = np.empty((m, d))
    bwd = np.empty((m, d))
    for j in range(d):
        e = np.zeros(d)
        e[j] = h
        fwd[:, j] = (ob.gap(x + e) - g0) / h
        bwd[:, j] = (g0 - ob.gap(x - e)) / h
    smooth = np.max(np.abs(fwd - bwd), axis=1) < 1e-3
    assert smooth.mean() > 0.5, "gap is not smooth almost everywhere"
    grad = 0.5 * (fwd + bwd)
    np.testing.assert_allclose(ob.normal(x)[smooth], -grad[smooth], atol=2e-5)


def test_hessian_is_minus_jacobian_of_normal(example):
    name, ob = example
    x = _sample(ob, name, seed=1)
    m, d = x.shape
    h = 1e-5
    n0 = ob.normal(x)
    fwd = np.empty((m, d, d))
    bwd = np.empty((m, d, d))
    for j in range(d):
        e = np.zeros(d)
        e[j] = h
        fwd[:, :, j] = (ob.normal(x + e) - n0) / h
        bwd[:, :, j] = (n0 - ob.normal(x - e)) / h
    smooth = np.max(np.abs(fwd - bwd), axis=(1, 2)) < 1e-3
    assert smooth.mean() > 0.5
    jac = 0.5 * (fwd + bwd)
    hess = ob.gap_hessian(x)
    np.testing.assert_allclose(hess, np.swapaxes(hess, 1, 2), atol=1e-10)
    np.testing.assert_allclose(hess[smooth], -jac[smooth], atol=1e-4)


def test_projection_lies_on_surface_and_reconstructs(example):
    name, ob = example
    x = _sample(ob, name, seed=2)
    g, n = ob.evaluate(x)
    p = ob.project(x)
    np.testing.assert_allclose(ob.gap(p), 0.0, atol=1e-8)
    np.testing.assert_allclose(p - g[:, None] * n, x, atol=1e-8)
    np.testing.assert_allclose(ob.project(p), p, atol=1e-8)


def test_point_validation(example):
    name, ob = example
    d = _dim(ob, EXAMPLES[name][0])
    with pytest.raises(InputError, match=r"x must have shape"):
        ob.gap(np.zeros(d))
    bad = np.zeros((2, d))
    bad[1, 0] = np.nan
    with pytest.raises(InputError, match="finite"):
        ob.normal(bad)
    if ob.dim is not None:
        with pytest.raises(InputError, match=rf"\(m, {d}\)"):
            ob.gap(np.zeros((3, d + 1)))


def test_check_dim(example):
    name, ob = example
    if ob.dim is None:
        ob.check_dim(2)
        ob.check_dim(3)
        return
    ob.check_dim(ob.dim)
    with pytest.raises(InputError, match=f"{ob.dim}D"):
        ob.check_dim(5 - ob.dim)


# --------------------------------------------------------------------------- exact values


def test_square_exact_values():
    sq = obs.make("convex-polygon", vertices=[[0, 0], [1, 0], [1, 1], [0, 1]])
    x = np.array([[2.0, 2.0], [0.5, 2.0], [0.5, 0.6], [-1.0, -1.0], [1.0, 0.5]])
    np.testing.assert_allclose(sq.gap(x), [-SQRT2, -1.0, 0.4, -SQRT2, 0.0], atol=1e-14)
    n = sq.normal(x)
    np.testing.assert_allclose(n[0], [1 / SQRT2, 1 / SQRT2])
    np.testing.assert_allclose(n[1], [0.0, 1.0])
    np.testing.assert_allclose(n[2], [0.0, 1.0])
    np.testing.assert_allclose(n[3], [-1 / SQRT2, -1 / SQRT2])
    np.testing.assert_allclose(n[4], [1.0, 0.0])
    np.testing.assert_allclose(sq.project(x), [[1, 1], [0.5, 1], [0.5, 1], [0, 0], [1, 0.5]],
                               atol=1e-14)
    hess = sq.gap_hessian(x)
    e = np.array([1.0, 1.0]) / SQRT2
    np.testing.assert_allclose(hess[0], -(np.eye(2) - np.outer(e, e)) / SQRT2)
    np.testing.assert_allclose(hess[3], -(np.eye(2) - np.outer(e, e)) / SQRT2)  # corner (0, 0)
    np.testing.assert_allclose(hess[[1, 2, 4]], 0.0)  # edge region, inside, on the boundary


def test_square_from_halfspaces_equals_from_vertices():
    a = np.array([[2.0, 0.0], [0.0, 3.0], [-1.0, 0.0], [0.0, -1.0]])
    b = np.array([2.0, 3.0, 0.0, 0.0])
    sq1 = obs.make("convex-polygon", A=a, b=b)
    sq2 = obs.make("convex-polygon", vertices=[[0, 0], [1, 0], [1, 1], [0, 1]])
    x = np.random.default_rng(3).uniform(-2, 3, size=(200, 2))
    np.testing.assert_allclose(sq1.gap(x), sq2.gap(x), atol=1e-13)
    np.testing.assert_allclose(sq1.project(x), sq2.project(x), atol=1e-13)
    assert len(sq1.vertices) == 4


def test_cube_exact_values():
    cube = obs.make("convex-polyhedron",
                    vertices=np.array(list(itertools.product([0.0, 1.0], repeat=3))))
    assert cube.A.shape == (6, 3) and len(cube.vertices) == 8 and len(cube.edges) == 12
    x = np.array([[2, 2, 0.5], [2, 2, 2], [0.5, 0.5, 3], [0.5, 0.5, 0.6], [-1, 0.5, 0.5]])
    np.testing.assert_allclose(cube.gap(x), [-SQRT2, -SQRT3, -2.0, 0.4, -1.0], atol=1e-14)
    np.testing.assert_allclose(cube.project(x), [[1, 1, 0.5], [1, 1, 1], [0.5, 0.5, 1],
                                                 [0.5, 0.5, 1], [0, 0.5, 0.5]], atol=1e-14)
    np.testing.assert_allclose(cube.normal(x)[4], [-1, 0, 0])
    hess = cube.gap_hessian(x)
    n, t = np.array([1, 1, 0]) / SQRT2, np.array([0, 0, 1.0])
    np.testing.assert_allclose(hess[0], -(np.eye(3) - np.outer(n, n) - np.outer(t, t)) / SQRT2,
                               atol=1e-14)
    n = np.ones(3) / SQRT3
    np.testing.assert_allclose(hess[1], -(np.eye(3) - np.outer(n, n)) / SQRT3, atol=1e-14)
    np.testing.assert_allclose(hess[2:], 0.0)


def test_polyhedron_projection_certificate():
    """The projection onto conv(V) is characterised by (x - p).(v - p) <= 0 for all v."""
    rng = np.random.default_rng(4)
    pts = rng.normal(size=(12, 3))
    ob = obs.ConvexPolytope.from_vertices(pts)
    x = 3.0 * rng.normal(size=(400, 3))
    g, n = ob.evaluate(x)
    p = ob.project(x)
    out = g < 0
    assert out.sum() > 100
    # p is in the polytope ...
    assert np.all(p @ ob.A.T - ob.b <= 1e-10)
    # ... and is the nearest point of it: variational inequality over the vertices.
    vi = np.einsum("mj,mvj->mv", (x - p)[out], pts[None] - p[out][:, None, :])
    assert np.max(vi) <= 1e-10
    # inside: the ball of radius gap stays in the polytope and touches its boundary
    ins = ~out
    slack = ob.b - x[ins] @ ob.A.T
    np.testing.assert_allclose(slack.min(axis=1), g[ins], atol=1e-13)


def test_polygon_projection_certificate():
    ob = obs.make("convex-polygon", vertices=_PENTAGON)
    x = np.random.default_rng(5).uniform(-2.0, 3.0, size=(400, 2))
    g = ob.gap(x)
    p = ob.project(x)
    out = g < 0
    vi = np.einsum("mj,mvj->mv", (x - p)[out], np.array(_PENTAGON)[None] - p[out][:, None, :])
    assert np.max(vi) <= 1e-10
    np.testing.assert_allclose(np.linalg.norm(x - p, axis=1), np.abs(g), atol=1e-12)


def test_sphere_and_cavity_exact():
    x = np.array([[0.0, 0.0, 3.0], [0.0, 0.0, 0.5]])
    ind = obs.Sphere(center=[0, 0, 0], radius=1.0)
    cav = obs.make("sphere-cavity", center=[0, 0, 0], radius=1.0)
    np.testing.assert_allclose(ind.gap(x), [-2.0, 0.5])
    np.testing.assert_allclose(cav.gap(x), [2.0, -0.5])
    np.testing.assert_allclose(ind.normal(x), [[0, 0, 1], [0, 0, 1]])
    np.testing.assert_allclose(cav.normal(x), [[0, 0, -1], [0, 0, -1]])
    np.testing.assert_allclose(ind.project(x), [[0, 0, 1], [0, 0, 1]])
    np.testing.assert_allclose(cav.project(x), [[0, 0, 1], [0, 0, 1]])
    np.testing.assert_allclose(ind.gap_hessian(x)[0], -np.diag([1, 1, 0]) / 3.0)
    np.testing.assert_allclose(cav.gap_hessian(x)[1], np.diag([1, 1, 0]) / 0.5)


@pytest.mark.parametrize("name, params", [
    ("sphere", dict(center=[1, 2, 3], radius=0.5)),
    ("sphere-cavity", dict(center=[1, 2, 3], radius=0.5)),
    ("circle", dict(center=[1, 2], radius=0.5)),
    ("circle-cavity", dict(center=[1, 2], radius=0.5)),
    ("cylinder", dict(center=[1, 2, 3], axis=[0, 1, 1], radius=0.5)),
    ("cylinder-cavity", dict(center=[1, 2, 3], axis=[0, 1, 1], radius=0.5)),
])
def test_center_is_deterministic_and_finite(name, params):
    ob = obs.make(name, **params)
    c = np.array([params["center"]], dtype=float)
    g, n = ob.evaluate(c)
    sign = -1.0 if name.endswith("cavity") else 1.0
    np.testing.assert_allclose(g, [sign * 0.5])
    assert np.all(np.isfinite(n)) and np.isclose(np.linalg.norm(n), 1.0)
    np.testing.assert_array_equal(ob.normal(c), n)
    np.testing.assert_array_equal(ob.gap_hessian(c), 0.0)
    np.testing.assert_allclose(ob.gap(ob.project(c)), 0.0, atol=1e-14)
    if name.startswith("cylinder"):
        assert abs(n[0] @ ob.axis) < 1e-14


def test_cylinder_exact():
    cyl = obs.make("cylinder", center=[0, 0, 0], axis=[0, 0, 2], radius=1.0)
    x = np.array([[3.0, 0.0, 7.0], [0.0, 0.5, -4.0]])
    np.testing.assert_allclose(cyl.gap(x), [-2.0, 0.5])
    np.testing.assert_allclose(cyl.normal(x), [[1, 0, 0], [0, 1, 0]])
    np.testing.assert_allclose(cyl.project(x), [[1, 0, 7], [0, 1, -4]])
    np.testing.assert_allclose(cyl.gap_hessian(x)[0], -np.diag([0, 1, 0]) / 3.0)


def test_half_space_exact():
    hs = obs.make("half-space", point=[0, 1], normal=[0, 3])
    x = np.array([[5.0, 3.0], [-2.0, 0.0]])
    np.testing.assert_allclose(hs.gap(x), [-2.0, 1.0])
    np.testing.assert_allclose(hs.normal(x), [[0, 1], [0, 1]])
    np.testing.assert_allclose(hs.project(x), [[5, 1], [-2, 1]])
    np.testing.assert_array_equal(hs.gap_hessian(x), 0.0)


# --------------------------------------------------------------------------- user obstacle


def test_user_matches_sphere_with_and_without_derivatives():
    c, r = np.array([0.2, -0.1, 0.3]), 0.8
    ref = obs.Sphere(center=c, radius=r)
    x = np.random.default_rng(6).uniform(-1.5, 1.5, size=(50, 3))
    x = x[np.linalg.norm(x - c, axis=1) > 0.2]
    variants = [
        obs.UserObstacle(gap=ref.gap, dim=3, length_scale=r),
        obs.UserObstacle(gap=ref.gap, normal=ref.normal, dim=3),
        obs.UserObstacle(gap=ref.gap, normal=ref.normal, hessian=ref.gap_hessian, dim=3),
    ]
    for ob in variants:
        np.testing.assert_allclose(ob.gap(x), ref.gap(x))
        np.testing.assert_allclose(ob.normal(x), ref.normal(x), atol=1e-8)
        np.testing.assert_allclose(ob.project(x), ref.project(x), atol=1e-8)
        np.testing.assert_allclose(ob.gap_hessian(x), ref.gap_hessian(x), atol=1e-5)


def test_user_without_dim_accepts_any_dimension():
    ob = obs.UserObstacle(gap=lambda x: x[:, -1] - 1.0)
    assert ob.dim is None
    np.testing.assert_allclose(ob.normal(np.zeros((2, 2))), [[0, -1]] * 2, atol=1e-9)
    np.testing.assert_allclose(ob.normal(np.zeros((2, 3))), [[0, 0, -1]] * 2, atol=1e-9)


def test_user_callback_errors():
    with pytest.raises(InputError, match="shape"):
        obs.UserObstacle(gap=lambda x: x).gap(np.zeros((2, 2)))
    with pytest.raises(NonFiniteError):
        obs.UserObstacle(gap=lambda x: np.full(len(x), np.nan)).gap(np.zeros((2, 2)))
    with pytest.raises(InputError, match="normal"):
        obs.UserObstacle(gap=lambda x: x[:, 0], normal=lambda x: x[:, 0]).normal(np.zeros((2, 2)))
    with pytest.raises(InputError, match="callable"):
        obs.UserObstacle(gap=3.0)
    with pytest.raises(InputError, match="dim"):
        obs.UserObstacle(gap=lambda x: x[:, 0], dim=4)
    with pytest.raises(InputError, match="length_scale"):
        obs.UserObstacle(gap=lambda x: x[:, 0], length_scale=0.0)


# --------------------------------------------------------------------------- validation


@pytest.mark.parametrize("name, params, match", [
    ("sphere", dict(center=[0, 0, 0], radius=0.0), "radius"),
    ("sphere", dict(center=[0, 0, 0], radius=-1.0), "radius"),
    ("sphere", dict(center=[0, 0], radius=1.0), r"center must have shape \(3,\)"),
    ("circle", dict(center=[0, 0, 0], radius=1.0), r"center must have shape \(2,\)"),
    ("circle", dict(center=[0, np.nan], radius=1.0), "center must be finite"),
    ("circle", dict(center=[0, 0], radius=np.inf), "radius"),
    ("half-space", dict(point=[0, 0], normal=[0, 0]), "non-zero"),
    ("half-space", dict(point=[0, 0], normal=[0, 0, 1]), "normal must have shape"),
    ("half-space", dict(point=[0, 0, np.inf], normal=[0, 0, 1]), "point must be finite"),
    ("cylinder", dict(center=[0, 0, 0], axis=[0, 0, 0], radius=1.0), "axis"),
    ("cylinder", dict(center=[0, 0], axis=[0, 1], radius=1.0), "center"),
    ("convex-polygon", dict(vertices=[[0, 0], [0, 1], [1, 1], [1, 0]]), "clockwise"),
    ("convex-polygon", dict(vertices=[[0, 0], [2, 0], [1, 0.2], [1, 2]]), "convex"),
    ("convex-polygon", dict(vertices=[[0, 0], [1, 0], [1, 0], [0, 1]]), "coincide"),
    ("convex-polygon", dict(vertices=[[0, 0], [1, 0]]), r"shape \(n, 2\)"),
    ("convex-polygon", dict(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]]), r"\(n, 2\)"),
    ("convex-polygon", dict(), "either vertices or both A and b"),
    ("convex-polygon", dict(A=[[1, 0], [0, 1], [-1, -1]]), "either vertices or both A and b"),
    ("convex-polygon", dict(A=[[1, 0], [-1, 0], [0, 1], [0, -1]], b=[0, -1, 1, 1]), "empty"),
    ("convex-polygon", dict(A=[[1, 0], [-1, 0], [0, 1]], b=[1, 1, 1]), "unbounded"),
    ("convex-polygon", dict(A=[[1, 0], [-1, 0]], b=[1, 1]), "at least 3 faces"),
    ("convex-polygon", dict(A=[[1, 0], [0, 0], [0, 1]], b=[1, 1, 1]), "row 1 of A is zero"),
    ("convex-polygon", dict(A=[[1, 0], [-1, 0], [0, 1]], b=[1, 1]), r"b must have shape \(3,\)"),
    ("convex-polyhedron", dict(A=[[1, 0], [-1, 0], [0, 1]], b=[1, 1, 1]), r"\(k, 3\)"),
    ("convex-polyhedron", dict(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]),
     "no volume"),
    ("convex-polyhedron", dict(A=np.eye(3), b=[1, 1, np.nan]), "finite"),
])
def test_invalid_parameters(name, params, match):
    with pytest.raises(InputError, match=match):
        obs.make(name, **params)


def test_pentagram_rejected():
    star = [[np.cos(a), np.sin(a)] for a in np.pi / 2 + 4 * np.pi / 5 * np.arange(5)]
    with pytest.raises(InputError, match="convex"):
        obs.ConvexPolytope.from_vertices(star)


# --------------------------------------------------------------------------- registry


def test_unknown_name_suggests_close_match():
    with pytest.raises(UnknownNameError, match="Did you mean 'sphere'") as info:
        obs.make("spehre", center=[0, 0, 0], radius=1.0)
    assert info.value.kind == "obstacle" and "half-space" in info.value.known


def test_wrong_parameter_names_listed():
    with pytest.raises(InputError, match="accepted parameters: center, radius"):
        obs.make("sphere", center=[0, 0, 0], radus=1.0)


def test_register_custom_and_duplicate():
    def factory(height=0.0):
        return obs.HalfSpace(point=[0.0, height], normal=[0.0, 1.0])

    obs.register("test-floor", factory, doc="floor at a given height\nmore text")
    try:
        assert "test-floor" in obs.available()
        assert obs.docs()["test-floor"] == "floor at a given height"
        np.testing.assert_allclose(obs.make("test-floor", height=1.0).gap([[0.0, 0.0]]), [1.0])
        with pytest.raises(InputError, match="already registered"):
            obs.register("test-floor", factory)
        obs.register("test-floor", factory, doc="replaced", replace=True)
        assert obs.docs()["test-floor"] == "replaced"
    finally:
        obs._REGISTRY.pop("test-floor", None)
    with pytest.raises(InputError):
        obs.register("", factory)
    with pytest.raises(InputError):
        obs.register("x", 3)


@pytest.mark.parametrize("eps", [0.0, 1e-300, 1e-15, 1e-9])
def test_polytope_points_on_and_just_off_the_boundary(eps):
    """Vertices, edge midpoints and face centres, nudged by eps: normal stays unit."""
    cube = obs.make("convex-polyhedron", A=np.vstack([np.eye(3), -np.eye(3)]),
                    b=[1, 1, 1, 0, 0, 0])
    base = np.array(list(itertools.product([0.0, 0.5, 1.0], repeat=3)))
    base = base[np.any((base == 0.0) | (base == 1.0), axis=1)]  # boundary points only
    rng = np.random.default_rng(7)
    dirs = rng.normal(size=(len(base), 3))
    x = base + eps * dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    g, n = cube.evaluate(x)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-12)
    assert np.max(np.abs(g)) <= eps + 1e-15
    np.testing.assert_allclose(cube.project(x) - g[:, None] * n, x, atol=1e-14)
    assert np.all(np.isfinite(cube.gap_hessian(x)))


def test_obstacles_are_immutable(example):
    import dataclasses

    name, ob = example
    field = dataclasses.fields(ob)[0].name
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(ob, field, None)
    for value in vars(ob).values():
        if isinstance(value, np.ndarray):
            assert not value.flags.writeable
